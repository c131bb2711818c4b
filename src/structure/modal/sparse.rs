//! Sparse path: shift-invert Lanczos on B = L^-1 P M P^T L^-T with K - sigma M = P^T L L^T P
//! (see the module documentation of `modal` for the derivation).
//!
//! Two passes. Lanczos converges to the eigenvalues of B relative to the largest one, so
//! with a tiny shift the rigid modes (mu = 1/|sigma|) would dwarf the elastic ones and cost
//! accuracy. Pass 1 uses sigma_1 = -shift_rel * lambda_scale and 8 eigenpairs: it finds the
//! zero-frequency modes (up to 8, enough to detect mechanisms) and an estimate lambda_1 of
//! the first elastic eigenvalue. Pass 2 refactors with sigma_2 = -lambda_1 / 2 (if larger in
//! magnitude than sigma_1) and runs Lanczos on B deflated by the zero modes,
//! B_d = (I - Z Z^T) B (I - Z Z^T), Z an orthonormal basis of L^T P phi_r. For a rigid mode
//! phi_r, L^T P phi_r = L^-1 P (K - sigma_2 M) phi_r, computed with one triangular solve.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::matrix_free::LinOp;
use faer::matrix_free::eigen::{
    PartialEigenParams, partial_self_adjoint_eigen, partial_self_adjoint_eigen_scratch,
};
use faer::sparse::SparseColMat;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::supernodal::{SupernodalLltRef, SymbolicSupernodalCholesky};
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::{Conj, Mat, MatMut, MatRef, Par, Side};

use super::rigid::sparse_matvec;
use super::{ModalError, ModalOptions, Modes, finish, lambda_scale, quad};
use crate::structure::fe_io::sparse_axpy;
use crate::structure::fe_model::FeModel;

/// The operator B = L^-1 P M P^T L^-T, optionally deflated by the orthonormal columns of `z`.
struct ShiftInvert<'a> {
    symbolic: &'a SymbolicSupernodalCholesky<usize>,
    values: &'a [f64],
    /// fwd[i]: original index of permuted index i.
    fwd: &'a [usize],
    mass: &'a SparseColMat<usize, f64>,
    /// Deflation basis (Euclidean orthonormal columns), possibly empty.
    z: Mat<f64>,
}

impl std::fmt::Debug for ShiftInvert<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "ShiftInvert(n = {}, deflated {})",
            self.fwd.len(),
            self.z.ncols()
        )
    }
}

impl ShiftInvert<'_> {
    fn factor(&self) -> SupernodalLltRef<'_, usize, f64> {
        SupernodalLltRef::new(self.symbolic, self.values)
    }

    /// phi = P^T L^-T z for each column.
    fn back_transform(&self, z: MatRef<'_, f64>, stack: &mut MemStack) -> Mat<f64> {
        let n = self.fwd.len();
        let mut y = z.to_owned();
        self.factor()
            .l_transpose_solve_with_conj(Conj::No, y.as_mut(), Par::Seq, stack);
        let mut phi = Mat::<f64>::zeros(n, z.ncols());
        for j in 0..z.ncols() {
            for i in 0..n {
                phi[(self.fwd[i], j)] = y[(i, j)];
            }
        }
        phi
    }

    /// L^-1 P w for each column of `w` (original ordering in, permuted space out).
    fn forward_transform(&self, w: MatRef<'_, f64>, stack: &mut MemStack) -> Mat<f64> {
        let n = self.fwd.len();
        let mut out = Mat::<f64>::from_fn(n, w.ncols(), |i, j| w[(self.fwd[i], j)]);
        self.factor()
            .l_solve_with_conj(Conj::No, out.as_mut(), Par::Seq, stack);
        out
    }

    /// x <- (I - Z Z^T) x.
    fn project(&self, mut x: MatMut<'_, f64>) {
        if self.z.ncols() == 0 {
            return;
        }
        let c = self.z.transpose() * x.as_ref();
        x -= &self.z * c;
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
        let mut x = rhs.to_owned();
        self.project(x.as_mut());
        let phi = self.back_transform(x.as_ref(), stack);
        let mut mphi = Mat::<f64>::zeros(phi.nrows(), phi.ncols());
        for j in 0..phi.ncols() {
            for t in self.mass.triplet_iter() {
                mphi[(t.row, j)] += t.val * phi[(t.col, j)];
            }
        }
        let mut y = self.forward_transform(mphi.as_ref(), stack);
        self.project(y.as_mut());
        let mut out = out;
        out.copy_from(&y);
    }
    fn conj_apply(
        &self,
        out: MatMut<'_, f64>,
        rhs: MatRef<'_, f64>,
        par: Par,
        stack: &mut MemStack,
    ) {
        self.apply(out, rhs, par, stack);
    }
}

/// Numeric Cholesky of K + shift M; retries with shift x 10 (at most 8 times) on failure.
fn factorize(
    model: &FeModel,
    symbolic: &SymbolicCholesky<usize>,
    values: &mut [f64],
    mut shift: f64,
) -> Result<f64, ModalError> {
    let mut last_err = String::new();
    for _ in 0..9 {
        let a = sparse_axpy(&model.stiffness, shift, &model.mass)
            .ok_or_else(|| ModalError::Eigensolver("cannot form K - sigma M".into()))?;
        let mut mem = MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        match symbolic.factorize_numeric_llt(
            values,
            a.as_ref(),
            Side::Lower,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut mem),
            Default::default(),
        ) {
            Ok(_) => return Ok(shift),
            Err(e) => {
                last_err = format!("sigma = {:.3e}: {e:?}", -shift);
                shift *= 10.0;
            }
        }
    }
    Err(ModalError::ShiftedNotPositiveDefinite(last_err))
}

/// Runs Lanczos for the `n_ev` largest eigenvalues of `op`; returns (lambda, phi) with lambda
/// the Rayleigh quotients phi^T K phi / phi^T M phi.
fn lanczos(
    model: &FeModel,
    op: &ShiftInvert<'_>,
    n_ev: usize,
    opts: &ModalOptions,
) -> Result<(Vec<f64>, Mat<f64>), ModalError> {
    let n = model.n_dof();
    let mut eigvecs = Mat::<f64>::zeros(n, n_ev);
    let mut eigvals = vec![0.0; n_ev];
    let mut v0 = Mat::<f64>::from_fn(n, 1, |i, _| 1.0 + 0.5 * (0.7 * i as f64).sin());
    op.project(v0.as_mut());
    let params = PartialEigenParams {
        max_restarts: 2000,
        ..Default::default()
    };
    let req = partial_self_adjoint_eigen_scratch(op, n_ev, Par::Seq, params);
    let mut mem = MemBuffer::new(req.or(op.apply_scratch(n_ev.max(8), Par::Seq)));
    // faer 0.24's partial eigensolver ends in a bare `panic!()` when it runs out of restarts
    // without converging (operator/self_adjoint_eigen/mod.rs). A library must not panic on
    // input, so that one case is caught here and reported as an eigensolver error.
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        partial_self_adjoint_eigen(
            eigvecs.as_mut(),
            &mut eigvals,
            op,
            v0.col(0),
            opts.lanczos_tol,
            Par::Seq,
            MemStack::new(&mut mem),
            params,
        )
    }));
    let Ok(info) = run else {
        return Err(ModalError::Eigensolver(format!(
            "the Lanczos iteration for {n_ev} eigenpairs did not converge within {} restarts",
            params.max_restarts
        )));
    };
    if info.n_converged_eigen < n_ev {
        return Err(ModalError::Eigensolver(format!(
            "Lanczos converged {} of {n_ev} eigenpairs",
            info.n_converged_eigen
        )));
    }
    let phi = op.back_transform(eigvecs.as_ref(), MemStack::new(&mut mem));
    let lambda = (0..n_ev)
        .map(|j| {
            let c = phi.col(j);
            let mm = quad(&model.mass, c, c);
            if mm > 0.0 {
                quad(&model.stiffness, c, c) / mm
            } else {
                f64::INFINITY
            }
        })
        .collect();
    Ok((lambda, phi))
}

/// Sparse solve by shift-invert Lanczos (faer `partial_self_adjoint_eigen`), two passes as
/// described in the module documentation.
pub fn solve_sparse_with(
    model: &FeModel,
    n_elastic_wanted: usize,
    opts: &ModalOptions,
) -> Result<Modes, ModalError> {
    let n = model.n_dof();
    let scale = lambda_scale(model)?;
    let tol = opts.rigid_rel_tol * scale;
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
        ..Default::default()
    };
    // The pattern of K + s M does not depend on s (the triplet sum keeps every position).
    let a0 = sparse_axpy(&model.stiffness, 1.0, &model.mass)
        .ok_or_else(|| ModalError::Eigensolver("cannot form K - sigma M".into()))?;
    let symbolic =
        factorize_symbolic_cholesky(a0.symbolic(), Side::Lower, SymmetricOrdering::Amd, params)
            .map_err(|e| ModalError::Eigensolver(format!("symbolic Cholesky: {e:?}")))?;
    let SymbolicCholeskyRaw::Supernodal(sym_super) = symbolic.raw() else {
        return Err(ModalError::Eigensolver(
            "expected a supernodal factorisation".into(),
        ));
    };
    let fwd: Vec<usize> = match symbolic.perm() {
        Some(p) => p.arrays().0.to_vec(),
        None => (0..n).collect(),
    };
    let mut values = vec![0.0; symbolic.len_val()];

    // Pass 1: zero modes and an estimate of the first elastic eigenvalue.
    let shift1 = factorize(model, &symbolic, &mut values, opts.shift_rel * scale)?;
    let op1 = ShiftInvert {
        symbolic: sym_super,
        values: &values,
        fwd: &fwd,
        mass: &model.mass,
        z: Mat::zeros(n, 0),
    };
    let (lambda1, phi1) = lanczos(model, &op1, 8.min(n), opts)?;
    let zero: Vec<usize> = (0..lambda1.len()).filter(|&j| lambda1[j] < tol).collect();
    if zero.len() > 6 {
        return Err(ModalError::Mechanisms {
            n_zero: zero.len(),
            threshold_hz: tol.max(0.0).sqrt() / (2.0 * std::f64::consts::PI),
        });
    }
    let first_elastic = lambda1
        .iter()
        .copied()
        .filter(|&l| l >= tol)
        .fold(f64::INFINITY, f64::min);
    let rigid_phi = Mat::<f64>::from_fn(n, zero.len(), |i, k| phi1[(i, zero[k])]);
    let n_el = n_elastic_wanted.min(n - zero.len());
    if n_el == 0 {
        return finish(
            model,
            zero.iter().map(|&j| lambda1[j]).collect(),
            rigid_phi,
            0,
            opts,
        );
    }

    // Pass 2: shift near the first elastic eigenvalue, deflate the zero modes.
    let shift2 = if first_elastic.is_finite() {
        (0.5 * first_elastic).max(shift1)
    } else {
        shift1
    };
    let shift2 = factorize(model, &symbolic, &mut values, shift2)?;
    let mut op2 = ShiftInvert {
        symbolic: sym_super,
        values: &values,
        fwd: &fwd,
        mass: &model.mass,
        z: Mat::zeros(n, 0),
    };
    if !zero.is_empty() {
        // L^T P phi = L^-1 P (K + shift2 M) phi.
        let mut w = Mat::<f64>::zeros(n, zero.len());
        for k in 0..zero.len() {
            let c = rigid_phi.col(k);
            let kc = sparse_matvec(&model.stiffness, c);
            let mc = sparse_matvec(&model.mass, c);
            for i in 0..n {
                w[(i, k)] = kc[i] + shift2 * mc[i];
            }
        }
        let mut mem = MemBuffer::new(op2.apply_scratch(zero.len(), Par::Seq));
        let z = op2.forward_transform(w.as_ref(), MemStack::new(&mut mem));
        let qr = z.qr();
        op2.z = qr.compute_thin_Q();
    }
    let (lambda2, phi2) = lanczos(model, &op2, n_el, opts)?;
    let mut lambda: Vec<f64> = zero.iter().map(|&j| lambda1[j]).collect();
    lambda.extend(lambda2);
    let vecs = faer::concat![[rigid_phi, phi2]];
    finish(model, lambda, vecs, n_elastic_wanted, opts)
}
