//! Modal analysis of a free-free FE model: K phi = omega^2 M phi.
//!
//! faer has no generalised symmetric eigensolver, so both paths reduce the pencil (K, M) to a
//! standard symmetric problem:
//!
//! * dense ([`solve_dense`]): M = L L^T, C = L^-1 K L^-T, C y = omega^2 y, phi = L^-T y.
//!   Needs M positive definite; a singular M (massless rotational DOF) is rejected with
//!   `modal::mass_not_positive_definite` (use the sparse path, or condense the massless DOFs
//!   statically before the solve).
//! * sparse ([`solve_sparse`]): shift-invert Lanczos. With sigma < 0 (the free-free K is
//!   singular) factor A = K - sigma M = P^T L L^T P (sparse supernodal Cholesky with a
//!   fill-reducing permutation P). Then K phi = lambda M phi is equivalent to
//!   B z = mu z with B = L^-1 P M P^T L^-T, z = L^T P phi and mu = 1 / (lambda - sigma):
//!   from M phi = mu A phi = mu P^T L L^T P phi, multiply by L^-1 P and substitute
//!   phi = P^T L^-T z. B is symmetric in the Euclidean inner product faer's Lanczos uses, its
//!   largest eigenvalues mu are the smallest lambda, and only A must be positive definite, so
//!   a singular (PSD) M is accepted. Eigenvalues are refined by the Rayleigh quotient
//!   phi^T K phi / phi^T M phi.
//!
//! Both paths then share the post-processing: rigid-body modes are the eigenvalues below
//! `rigid_rel_tol * lambda_scale`, with `lambda_scale = max_i K_ii / M_ii` over translational
//! DOFs (a Rayleigh quotient of a unit DOF vector, a cheap estimate of the top of the spectrum). More than 6 is an error
//! (mechanisms). When exactly 6 are found and the exact rigid-body vectors built from the node
//! positions (3 translations, 3 small rotations theta x r about the origin) lie in the null
//! space of K, the numerical rigid modes are replaced by an M-orthonormal basis of those exact
//! vectors (Gram-Schmidt in the M inner product, translations first). Elastic modes are
//! mass-normalised (phi^T M phi = 1), made M-orthogonal to the rigid modes, and sorted.

mod dense;
mod rigid;
mod sparse;

use faer::Mat;

pub use dense::solve_dense_with;
pub use rigid::rigid_body_vectors;
pub use sparse::solve_sparse_with;

use crate::structure::fe_model::FeModel;

/// Errors of the modal solve.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModalError {
    /// The model has no DOF or no mass.
    #[error("empty model: {0}")]
    EmptyModel(String),
    /// Cholesky of M failed (dense path).
    #[error("mass matrix not positive definite: {0}")]
    MassNotPositiveDefinite(String),
    /// Cholesky of K - sigma M failed for every shift tried (sparse path).
    #[error("K - sigma M is not positive definite for any shift tried: {0}")]
    ShiftedNotPositiveDefinite(String),
    /// More than 6 zero-frequency modes. `n_zero` is the number found: the dense path sees
    /// all of them; the sparse path looks at the 8 lowest eigenpairs, so it reports at most 8.
    /// `threshold_hz` is the frequency below which a mode counts as zero (1e-10 of the
    /// largest translational `K_ii / M_ii`): a model whose shortest elements raise the top
    /// of the spectrum far enough hides genuine elastic modes under it.
    #[error(
        "more than 6 zero-frequency modes: the model has mechanisms ({n_zero} zero-frequency modes found, below {threshold_hz:.4} Hz), or elements so short that the top of its spectrum hides its lowest elastic modes (a mode counts as zero below 1e-10 of the largest K_ii/M_ii)"
    )]
    Mechanisms { n_zero: usize, threshold_hz: f64 },
    /// The eigensolver failed or did not converge.
    #[error("eigensolver failed: {0}")]
    Eigensolver(String),
}

impl ModalError {
    /// Stable identifier, e.g. `"modal::mechanisms"`.
    pub fn code(&self) -> &'static str {
        match self {
            Self::EmptyModel(_) => "modal::empty_model",
            Self::MassNotPositiveDefinite(_) => "modal::mass_not_positive_definite",
            Self::ShiftedNotPositiveDefinite(_) => "modal::shifted_not_positive_definite",
            Self::Mechanisms { .. } => "modal::mechanisms",
            Self::Eigensolver(_) => "modal::eigensolver",
        }
    }
}

/// Result of a modal solve.
#[derive(Clone, Debug)]
pub struct Modes {
    /// Eigenvalues omega^2 (rad^2/s^2): `n_rigid` rigid-body modes first, then elastic modes
    /// in increasing order.
    pub omega2: Vec<f64>,
    /// Mode shapes, `n_dof x omega2.len()`, columns M-orthonormal (phi^T M phi = I).
    pub shapes: Mat<f64>,
    /// Number of rigid-body (zero-frequency) modes at the start.
    pub n_rigid: usize,
}

impl Modes {
    /// Natural frequencies f = sqrt(omega^2) / (2 pi) in Hz (negative round-off clamps to 0).
    pub fn frequencies_hz(&self) -> Vec<f64> {
        self.omega2
            .iter()
            .map(|&w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect()
    }

    /// Frequencies of the elastic modes only, in Hz.
    pub fn elastic_frequencies_hz(&self) -> Vec<f64> {
        self.frequencies_hz().split_off(self.n_rigid)
    }
}

/// Tuning of the modal solve.
#[derive(Clone, Debug)]
pub struct ModalOptions {
    /// Eigenvalues below `rigid_rel_tol * lambda_scale` are rigid-body modes.
    pub rigid_rel_tol: f64,
    /// Models with more DOF than this use the sparse path in [`solve`].
    pub dense_max_dof: usize,
    /// Initial shift sigma = -shift_rel * lambda_scale of the sparse path (multiplied by 10
    /// while the factorisation of K - sigma M fails).
    pub shift_rel: f64,
    /// Convergence tolerance passed to the Lanczos solver.
    pub lanczos_tol: f64,
}

impl Default for ModalOptions {
    fn default() -> Self {
        Self {
            rigid_rel_tol: 1e-10,
            dense_max_dof: 2000,
            shift_rel: 1e-9,
            lanczos_tol: 1e-13,
        }
    }
}

/// Modal solve with the default options: dense up to 2000 DOF, sparse above. Returns the rigid
/// modes and the `n_elastic_wanted` lowest elastic modes (fewer if the model has fewer).
/// The dense path condenses massless DOFs (e.g. shell drilling rotations) statically; if M
/// is singular in another way, the sparse path (which only needs K - sigma M positive
/// definite) is tried.
pub fn solve(model: &FeModel, n_elastic_wanted: usize) -> Result<Modes, ModalError> {
    let opts = ModalOptions::default();
    if model.n_dof() <= opts.dense_max_dof {
        match solve_dense_with(model, n_elastic_wanted, &opts) {
            Err(ModalError::MassNotPositiveDefinite(_)) => {
                solve_sparse_with(model, n_elastic_wanted, &opts)
            }
            other => other,
        }
    } else {
        solve_sparse_with(model, n_elastic_wanted, &opts)
    }
}

/// Dense path with default options.
pub fn solve_dense(model: &FeModel, n_elastic_wanted: usize) -> Result<Modes, ModalError> {
    solve_dense_with(model, n_elastic_wanted, &ModalOptions::default())
}

/// Sparse (shift-invert Lanczos) path with default options.
pub fn solve_sparse(model: &FeModel, n_elastic_wanted: usize) -> Result<Modes, ModalError> {
    solve_sparse_with(model, n_elastic_wanted, &ModalOptions::default())
}

/// `lambda_scale = max_i K_ii / M_ii` over the translational DOFs with M_ii > 0.
///
/// Rotational DOFs are left out: for thin shells their rotary mass (rho t^3 / 12) is so small
/// that K_ii / M_ii there exceeds the physical top of the spectrum by many orders, which made
/// genuine low fin modes (0.6 mm SPHADS-1 fins, about 30 Hz) fall under the rigid-mode
/// threshold and be reported as mechanisms.
pub(crate) fn lambda_scale(model: &FeModel) -> Result<f64, ModalError> {
    let n = model.n_dof();
    let mut km = vec![(0.0, 0.0); n];
    for t in model.stiffness.triplet_iter().filter(|t| t.row == t.col) {
        km[t.row].0 = *t.val;
    }
    for t in model.mass.triplet_iter().filter(|t| t.row == t.col) {
        km[t.row].1 = *t.val;
    }
    let s = km
        .iter()
        .enumerate()
        .filter(|(i, (_, m))| i % crate::structure::DOF_PER_NODE < 3 && *m > 0.0)
        .map(|(_, km)| km)
        .map(|(k, m)| k / m)
        .fold(0.0_f64, f64::max);
    if n == 0 || s <= 0.0 || !s.is_finite() {
        return Err(ModalError::EmptyModel(format!(
            "{n} DOF, K_ii/M_ii scale {s}"
        )));
    }
    Ok(s)
}

/// `x^T A y` for a sparse symmetric A.
pub(crate) fn quad(
    a: &faer::sparse::SparseColMat<usize, f64>,
    x: faer::ColRef<'_, f64>,
    y: faer::ColRef<'_, f64>,
) -> f64 {
    a.triplet_iter().map(|t| x[t.row] * t.val * y[t.col]).sum()
}

/// Shared post-processing: rigid-mode count and replacement, mass normalisation, sorting,
/// truncation to `n_rigid + n_elastic_wanted`. `lambda` and the columns of `vecs` are the
/// computed eigenpairs (any order, any scaling).
pub(crate) fn finish(
    model: &FeModel,
    lambda: Vec<f64>,
    vecs: Mat<f64>,
    n_elastic_wanted: usize,
    opts: &ModalOptions,
) -> Result<Modes, ModalError> {
    let scale = lambda_scale(model)?;
    let tol = opts.rigid_rel_tol * scale;
    let mut order: Vec<usize> = (0..lambda.len()).collect();
    order.sort_by(|&a, &b| lambda[a].total_cmp(&lambda[b]));
    let n_zero = order.iter().filter(|&&i| lambda[i] < tol).count();
    if n_zero > 6 {
        return Err(ModalError::Mechanisms {
            n_zero,
            threshold_hz: tol.max(0.0).sqrt() / (2.0 * std::f64::consts::PI),
        });
    }
    let n = model.n_dof();
    let mut rigid: Vec<faer::Col<f64>> = Vec::new();
    if n_zero == 6 {
        if let Some(basis) = rigid::m_orthonormal(&model.mass, rigid::rigid_body_vectors(model)) {
            if basis
                .iter()
                .all(|r| quad(&model.stiffness, r.as_ref(), r.as_ref()) < tol)
            {
                rigid = basis;
            }
        }
    }
    if rigid.is_empty() {
        let numerical: Vec<faer::Col<f64>> = order[..n_zero]
            .iter()
            .map(|&i| vecs.col(i).to_owned())
            .collect();
        rigid = rigid::m_orthonormal(&model.mass, numerical).ok_or_else(|| {
            ModalError::Eigensolver("rigid-body modes are linearly dependent".into())
        })?;
    }
    let n_el = n_elastic_wanted.min(order.len() - n_zero);
    let mut mr: Vec<faer::Col<f64>> = Vec::new();
    for r in &rigid {
        mr.push(rigid::sparse_matvec(&model.mass, r.as_ref()));
    }
    let mut elastic: Vec<(f64, faer::Col<f64>)> = Vec::with_capacity(n_el);
    for (k, &i) in order[n_zero..n_zero + n_el].iter().enumerate() {
        let mut phi = vecs.col(i).to_owned();
        for (r, m_r) in rigid.iter().zip(&mr) {
            let c: f64 = (0..n).map(|d| m_r[d] * phi[d]).sum();
            phi -= c * r;
        }
        let mass = quad(&model.mass, phi.as_ref(), phi.as_ref());
        if mass <= 0.0 || !mass.is_finite() {
            return Err(ModalError::Eigensolver(format!(
                "elastic mode {k} has modal mass {mass}"
            )));
        }
        phi *= faer::Scale(1.0 / mass.sqrt());
        elastic.push((quad(&model.stiffness, phi.as_ref(), phi.as_ref()), phi));
    }
    // Sort by the refined eigenvalue (degenerate pairs may swap at round-off level).
    elastic.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut shapes = Mat::<f64>::zeros(n, n_zero + n_el);
    let mut omega2 = Vec::with_capacity(n_zero + n_el);
    for (k, r) in rigid.iter().enumerate() {
        shapes.col_mut(k).copy_from(r);
        omega2.push(quad(&model.stiffness, r.as_ref(), r.as_ref()).max(0.0));
    }
    for (k, (w2, phi)) in elastic.into_iter().enumerate() {
        omega2.push(w2);
        shapes.col_mut(n_zero + k).copy_from(&phi);
    }
    Ok(Modes {
        omega2,
        shapes,
        n_rigid: n_zero,
    })
}
