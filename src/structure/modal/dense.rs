//! Dense path: Cholesky reduction of (K, M) and a full symmetric eigendecomposition.

use faer::linalg::solvers::Solve;
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
    let m_full = model.mass.to_dense();
    let k_full = model.stiffness.to_dense();
    // Static condensation of massless DOFs (exact: with no inertia they are in static
    // equilibrium at every instant): K_ss x_s + K_sm x_m = 0, so x_s = T x_m with
    // T = -K_ss^-1 K_sm, and the eigenproblem on the massive set is
    // (K_mm + K_ms T) x_m = omega^2 M_mm x_m. Shell drilling rotations are the usual case.
    let m_max = (0..n).map(|i| m_full[(i, i)].abs()).fold(0.0, f64::max);
    let massless: Vec<bool> = (0..n)
        .map(|i| (0..n).all(|j| m_full[(i, j)].abs() <= 1e-14 * m_max))
        .collect();
    let keep: Vec<usize> = (0..n).filter(|&i| !massless[i]).collect();
    let drop: Vec<usize> = (0..n).filter(|&i| massless[i]).collect();
    let (m, k, t) = if drop.is_empty() {
        (m_full, k_full, None)
    } else {
        let (nm, ns) = (keep.len(), drop.len());
        let kss = Mat::from_fn(ns, ns, |a, b| k_full[(drop[a], drop[b])]);
        let ksm = Mat::from_fn(ns, nm, |a, b| k_full[(drop[a], keep[b])]);
        let kss_llt = kss.llt(Side::Lower).map_err(|e| {
            ModalError::MassNotPositiveDefinite(format!(
                "{ns} massless DOF could not be condensed: their stiffness block is not positive definite ({e:?})"
            ))
        })?;
        let t = -kss_llt.solve(&ksm); // ns x nm
        let k_red = Mat::from_fn(nm, nm, |a, b| {
            let mut v = k_full[(keep[a], keep[b])];
            for c in 0..ns {
                v += k_full[(keep[a], drop[c])] * t[(c, b)];
            }
            v
        });
        let k_red = Mat::from_fn(nm, nm, |a, b| 0.5 * (k_red[(a, b)] + k_red[(b, a)]));
        let m_red = Mat::from_fn(nm, nm, |a, b| m_full[(keep[a], keep[b])]);
        (m_red, k_red, Some(t))
    };
    let n_full = n;
    let n = m.nrows();
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
    let phi = match t {
        None => phi,
        Some(t) => {
            // Expand: massive DOFs from Phi, massless ones x_s = T x_m.
            let xs = &t * &phi;
            let mut full = Mat::<f64>::zeros(n_full, phi.ncols());
            for (a, &i) in keep.iter().enumerate() {
                for j in 0..phi.ncols() {
                    full[(i, j)] = phi[(a, j)];
                }
            }
            for (c, &i) in drop.iter().enumerate() {
                for j in 0..phi.ncols() {
                    full[(i, j)] = xs[(c, j)];
                }
            }
            full
        }
    };
    finish(model, lambda, phi, n_elastic_wanted, opts)
}
