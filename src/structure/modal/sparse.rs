//! Sparse path: shift-invert Lanczos on B = L^-1 P M P^T L^-T with K - sigma M = P^T L L^T P
//! (see the module documentation of `modal` for the derivation).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::matrix_free::LinOp;
use faer::matrix_free::eigen::{PartialEigenParams, partial_self_adjoint_eigen, partial_self_adjoint_eigen_scratch};
use faer::sparse::SparseColMat;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::supernodal::{SupernodalLltRef, SymbolicSupernodalCholesky};
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholeskyRaw, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::{Col, Conj, Mat, MatMut, MatRef, Par, Side};

use super::{ModalError, ModalOptions, Modes, finish, lambda_scale};
use crate::structure::fe_io::sparse_axpy;
use crate::structure::fe_model::FeModel;

/// The operator B = L^-1 P M P^T L^-T.
struct ShiftInvert<'a> {
    symbolic: &'a SymbolicSupernodalCholesky<usize>,
    values: &'a [f64],
    /// fwd[i]: original index of permuted index i.
    fwd: &'a [usize],
    mass: &'a SparseColMat<usize, f64>,
}

impl std::fmt::Debug for ShiftInvert<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ShiftInvert(n = {})", self.fwd.len())
    }
}

impl ShiftInvert<'_> {
    /// phi = P^T L^-T z for each column of `z` (in place on a copy).
    fn back_transform(&self, z: MatRef<'_, f64>, stack: &mut MemStack) -> Mat<f64> {
        let n = self.fwd.len();
        let mut y = z.to_owned();
        let l = SupernodalLltRef::new(self.symbolic, self.values);
        l.l_transpose_solve_with_conj(Conj::No, y.as_mut(), Par::Seq, stack);
        let mut phi = Mat::<f64>::zeros(n, z.ncols());
        for j in 0..z.ncols() {
            for i in 0..n {
                phi[(self.fwd[i], j)] = y[(i, j)];
            }
        }
        phi
    }
}

impl LinOp<f64> for ShiftInvert<'_> {
    fn apply_scratch(&self, rhs_ncols: usize, par: Par) -> StackReq {
        self.symbolic.solve_in_place_scratch::<f64>(rhs_ncols, par)
    }
    fn nrows(&self) -> usize {
        self.fwd.len()
    }
    fn ncols(&self) -> usize {
        self.fwd.len()
    }
    fn apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _par: Par, stack: &mut MemStack) {
        let n = self.fwd.len();
        let phi = self.back_transform(rhs, stack);
        let mut out = out;
        let mut mphi = Mat::<f64>::zeros(n, rhs.ncols());
        for j in 0..rhs.ncols() {
            for t in self.mass.triplet_iter() {
                mphi[(t.row, j)] += t.val * phi[(t.col, j)];
            }
            for i in 0..n {
                out[(i, j)] = mphi[(self.fwd[i], j)];
            }
        }
        let l = SupernodalLltRef::new(self.symbolic, self.values);
        l.l_solve_with_conj(Conj::No, out.as_mut(), Par::Seq, stack);
    }
    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, stack: &mut MemStack) {
        self.apply(out, rhs, par, stack);
    }
}

/// Sparse solve by shift-invert Lanczos (faer `partial_self_adjoint_eigen`).
///
/// sigma starts at `-opts.shift_rel * lambda_scale` and is multiplied by 10 (at most 8
/// times) while the Cholesky factorisation of K - sigma M fails.
pub fn solve_sparse_with(model: &FeModel, n_elastic_wanted: usize, opts: &ModalOptions) -> Result<Modes, ModalError> {
    let n = model.n_dof();
    let scale = lambda_scale(model)?;
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    };
    let mut shift = opts.shift_rel * scale;
    // K - sigma M (sigma = -shift). The pattern of the sum does not depend on the shift: the
    // triplet assembly keeps every position of K and M.
    let shifted = |shift: f64| {
        sparse_axpy(&model.stiffness, shift, &model.mass)
            .ok_or_else(|| ModalError::Eigensolver("cannot form K - sigma M".into()))
    };
    let a0 = shifted(shift)?;
    let symbolic = factorize_symbolic_cholesky(a0.symbolic(), Side::Lower, SymmetricOrdering::Amd, params)
        .map_err(|e| ModalError::Eigensolver(format!("symbolic Cholesky: {e:?}")))?;
    let SymbolicCholeskyRaw::Supernodal(sym_super) = symbolic.raw() else {
        return Err(ModalError::Eigensolver("expected a supernodal factorisation".into()));
    };
    let fwd: Vec<usize> = match symbolic.perm() {
        Some(p) => p.arrays().0.to_vec(),
        None => (0..n).collect(),
    };
    let mut values = vec![0.0; symbolic.len_val()];
    let mut last_err = String::new();
    let mut factored = false;
    for _ in 0..9 {
        let a = shifted(shift)?;
        let mut mem = MemBuffer::new(symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()));
        match symbolic.factorize_numeric_llt(
            &mut values,
            a.as_ref(),
            Side::Lower,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut mem),
            Default::default(),
        ) {
            Ok(_) => {
                factored = true;
                break;
            }
            Err(e) => {
                last_err = format!("sigma = {:.3e}: {e:?}", -shift);
                shift *= 10.0;
            }
        }
    }
    if !factored {
        return Err(ModalError::ShiftedNotPositiveDefinite(last_err));
    }
    let op = ShiftInvert { symbolic: sym_super, values: &values, fwd: &fwd, mass: &model.mass };
    let n_ev = (n_elastic_wanted + 7).min(n);
    let mut eigvecs = Mat::<f64>::zeros(n, n_ev);
    let mut eigvals = vec![0.0; n_ev];
    let v0 = Col::<f64>::from_fn(n, |i| 1.0 + 0.5 * (0.7 * i as f64).sin());
    let params = PartialEigenParams { max_restarts: 2000, ..Default::default() };
    let req = partial_self_adjoint_eigen_scratch(&op, n_ev, Par::Seq, params);
    let mut mem = MemBuffer::new(req.or(op.apply_scratch(n_ev, Par::Seq)));
    let info = partial_self_adjoint_eigen(
        eigvecs.as_mut(),
        &mut eigvals,
        &op,
        v0.as_ref(),
        opts.lanczos_tol,
        Par::Seq,
        MemStack::new(&mut mem),
        params,
    );
    if info.n_converged_eigen < n_ev {
        return Err(ModalError::Eigensolver(format!(
            "Lanczos converged {} of {n_ev} eigenpairs",
            info.n_converged_eigen
        )));
    }
    let phi = op.back_transform(eigvecs.as_ref(), MemStack::new(&mut mem));
    // Rayleigh quotients: lambda = phi^T K phi / phi^T M phi (sigma + 1/mu as fallback order key).
    let lambda: Vec<f64> = (0..n_ev)
        .map(|j| {
            let c = phi.col(j);
            let km = super::quad(&model.stiffness, c, c);
            let mm = super::quad(&model.mass, c, c);
            if mm > 0.0 { km / mm } else { f64::INFINITY }
        })
        .collect();
    finish(model, lambda, phi, n_elastic_wanted, opts)
}
