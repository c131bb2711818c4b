//! Minimal dense generalised eigen-solver for the generator's tests only (the real one is
//! `structure::modal`). Also included by tests/generator.rs through `#[path]`.
//!
//! K phi = omega^2 M phi is reduced with a shifted Cholesky factor, so that a singular K
//! (free-free) and a singular M (massless drilling DOFs) are both fine:
//! L L^T = K + sigma M,  C = L^-1 M L^-T,  C y = mu y,  omega^2 = 1/mu - sigma.
//! Modes with mu <= 1e-12 mu_max (infinite frequency, massless DOFs) are dropped.
#![allow(dead_code)] // used by tests/generator.rs through #[path]

use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::sparse::SparseColMat;
use faer::{Mat, Par, Side};

/// omega^2 in ascending order (rad^2/s^2).
pub fn generalized_eigenvalues(
    k: &SparseColMat<usize, f64>,
    m: &SparseColMat<usize, f64>,
    sigma: f64,
) -> Vec<f64> {
    let kd = k.to_dense();
    let md = m.to_dense();
    let n = kd.nrows();
    let a = Mat::<f64>::from_fn(n, n, |i, j| kd[(i, j)] + sigma * md[(i, j)]);
    let llt = a
        .llt(Side::Lower)
        .expect("K + sigma M must be positive definite");
    let l = llt.L();
    let mut x = md.clone();
    solve_lower_triangular_in_place(l, x.as_mut(), Par::Seq); // L^-1 M
    let mut c = x.transpose().to_owned(); // M L^-T
    solve_lower_triangular_in_place(l, c.as_mut(), Par::Seq); // L^-1 M L^-T
    let cs = Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    let mu = cs
        .self_adjoint_eigenvalues(Side::Lower)
        .expect("symmetric eigenvalues");
    let mu_max = mu.iter().cloned().fold(0.0, f64::max);
    let mut w2: Vec<f64> = mu
        .iter()
        .filter(|&&v| v > 1e-12 * mu_max)
        .map(|&v| 1.0 / v - sigma)
        .collect();
    w2.sort_by(f64::total_cmp);
    w2
}

/// Natural frequencies in Hz, ascending, with omega^2 clamped at 0.
pub fn frequencies_hz(
    k: &SparseColMat<usize, f64>,
    m: &SparseColMat<usize, f64>,
    sigma: f64,
) -> Vec<f64> {
    generalized_eigenvalues(k, m, sigma)
        .into_iter()
        .map(|w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect()
}
