//! Dense path: Cholesky reduction of (K, M) and a full symmetric eigendecomposition.

use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, Par, Side};

use super::{ModalError, ModalOptions, Modes, finish};
use crate::structure::fe_model::FeModel;

/// Dense solve: M = L L^T, C = L^-1 K L^-T (symmetrised), C = U S U^T, Phi = L^-T U.
/// The columns of Phi are M-orthonormal because U is orthogonal:
/// Phi^T M Phi = U^T L^-1 L L^T L^-T U = I.
pub fn solve_dense_with(
    model: &FeModel,
    n_elastic_wanted: usize,
    opts: &ModalOptions,
) -> Result<Modes, ModalError> {
    let n = model.n_dof();
    if n == 0 {
        return Err(ModalError::EmptyModel("no DOF".into()));
    }
    let m = model.mass.to_dense();
    let k = model.stiffness.to_dense();
    let llt = m.llt(Side::Lower).map_err(|e| {
        ModalError::MassNotPositiveDefinite(format!(
            "dense Cholesky of M failed ({e:?}); a singular M (massless DOF) needs the sparse path or static condensation"
        ))
    })?;
    let l = llt.L();
    let par = Par::Seq;
    let mut x = k;
    solve_lower_triangular_in_place(l, x.as_mut(), par); // X = L^-1 K
    let mut c = x.transpose().to_owned();
    solve_lower_triangular_in_place(l, c.as_mut(), par); // C = L^-1 (L^-1 K)^T = L^-1 K L^-T
    // Symmetrise and scale to unit norm before the eigensolver. The scaling is a workaround:
    // with faer 0.24, `self_adjoint_eigen` of the unscaled C of a 1008-DOF grillage
    // (||C|| ~ 1e12, many repeated eigenvalues) returned ||C U - U S|| / ||C|| ~ 2.6e-4;
    // after scaling to ||C|| = 1 the residual is ~1e-14 (see tests/modal.rs).
    let c_norm = c.norm_l2();
    if !(c_norm.is_finite() && c_norm > 0.0) {
        return Err(ModalError::Eigensolver(format!(
            "L^-1 K L^-T has norm {c_norm}"
        )));
    }
    let c = Mat::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]) / c_norm);
    let evd = c
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| ModalError::Eigensolver(format!("{e:?}")))?;
    let lambda: Vec<f64> = (0..n).map(|i| evd.S()[i] * c_norm).collect();
    let mut phi = evd.U().to_owned();
    solve_upper_triangular_in_place(l.transpose(), phi.as_mut(), par); // Phi = L^-T U
    finish(model, lambda, phi, n_elastic_wanted, opts)
}
