//! Eigen-structure of a linear model `δ̇ = A δ`: roots, damping, frequency, the stability
//! parameters `sigma_d`, `omega_d` of thesis (6.30) and the participation factors that say
//! which states drive each root.
//!
//! Participation factors (Pérez-Arriaga, Verghese, Schweppe, IEEE PAS-101 (1982) 3117):
//! with right eigenvectors `r_i` (columns of `R`) and left eigenvectors `l_i` (rows of
//! `L = R⁻¹`, so `l_i r_j = δ_ij`), `p_ki = |l_ki r_ki|`, normalised per root to sum 1. The
//! normalisation makes `p` independent of how `r_i` is scaled, and so of the units of the
//! states.

use faer::Mat;
use faer::linalg::solvers::DenseSolveCore;
use serde::Serialize;

use super::linear_grid::StabilityClass;
use super::linearise::{LinearModel, LineariseError};

/// One root of `A`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Root {
    /// `Re λ`, 1/s.
    pub real: f64,
    /// `Im λ`, rad/s.
    pub imag: f64,
    /// `ζ = -Re λ / |λ|` (0 for `λ = 0`).
    pub damping_ratio: f64,
    /// Undamped natural frequency `|λ| / 2π`, Hz.
    pub natural_frequency_hz: f64,
    /// Damped frequency `|Im λ| / 2π`, Hz.
    pub frequency_hz: f64,
    /// `|λ|` below [`super::linearise::LineariseOptions::neutral_tolerance`]: a neutral
    /// rigid-body root.
    pub neutral: bool,
    /// Normalised participation factor of every state (order of the model's state names).
    pub participation: Vec<f64>,
}

impl Root {
    /// The `k` states that participate most, largest first, as (index, factor).
    pub fn top_states(&self, k: usize) -> Vec<(usize, f64)> {
        let mut idx: Vec<(usize, f64)> = self.participation.iter().copied().enumerate().collect();
        idx.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        idx.truncate(k);
        idx
    }
}

/// All roots of a model and the stability summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EigenStructure {
    /// Roots sorted by decreasing real part (then decreasing imaginary part).
    pub roots: Vec<Root>,
    /// `sigma_d = max Re λ` over the roots that are not neutral, 1/s.
    pub sigma_d: f64,
    /// `|Im λ|` of that least-stable root, rad/s.
    pub omega_d: f64,
    /// `max Re λ` over all roots, neutral ones included (their numerical noise shows here).
    pub max_real_all: f64,
    /// Stable if `sigma_d <= 0`, else flutter (complex least-stable root) or divergence
    /// (real).
    pub class: StabilityClass,
}

/// Eigenvalues, eigenvectors and participation factors of `model.a`; roots with
/// `|λ| < neutral_tolerance` are marked neutral.
pub fn eigen_structure(
    model: &LinearModel,
    neutral_tolerance: f64,
) -> Result<EigenStructure, LineariseError> {
    let d = model.dim();
    let a = Mat::<f64>::from_fn(d, d, |i, j| model.a[i * d + j]);
    if model.a.iter().any(|v| !v.is_finite()) {
        return Err(LineariseError::Singular {
            what: "state matrix A",
        });
    }
    let evd = a.eigen().map_err(|_| LineariseError::Eigen { dim: d })?;
    let r = evd.U();
    let s = evd.S();
    // L = R⁻¹ (rows are the left eigenvectors with l_i r_i = 1).
    let l = r.partial_piv_lu().inverse();
    let mut roots = Vec::with_capacity(d);
    for i in 0..d {
        let lam = s[i];
        let (re, im) = (lam.re, lam.im);
        let modulus = re.hypot(im);
        let mut p: Vec<f64> = (0..d).map(|k| (l[(i, k)] * r[(k, i)]).norm()).collect();
        let total: f64 = p.iter().sum();
        if total > 0.0 && total.is_finite() {
            p.iter_mut().for_each(|v| *v /= total);
        } else {
            // R nearly singular (a Jordan block): fall back to |r_ki|² normalised.
            let t: f64 = (0..d).map(|k| r[(k, i)].norm().powi(2)).sum();
            p = (0..d)
                .map(|k| r[(k, i)].norm().powi(2) / t.max(f64::MIN_POSITIVE))
                .collect();
        }
        roots.push(Root {
            real: re,
            imag: im,
            damping_ratio: if modulus > 0.0 { -re / modulus } else { 0.0 },
            natural_frequency_hz: modulus / std::f64::consts::TAU,
            frequency_hz: im.abs() / std::f64::consts::TAU,
            neutral: modulus < neutral_tolerance,
            participation: p,
        });
    }
    roots.sort_by(|a, b| b.real.total_cmp(&a.real).then(b.imag.total_cmp(&a.imag)));
    let max_real_all = roots
        .iter()
        .map(|r| r.real)
        .fold(f64::NEG_INFINITY, f64::max);
    let least = roots.iter().find(|r| !r.neutral);
    let (sigma_d, omega_d, complex) = match least {
        Some(r) => (r.real, r.imag.abs(), r.imag != 0.0),
        None => (0.0, 0.0, false),
    };
    let class = if sigma_d <= 0.0 {
        StabilityClass::Stable
    } else if complex {
        StabilityClass::Flutter
    } else {
        StabilityClass::Divergence
    };
    Ok(EigenStructure {
        roots,
        sigma_d,
        omega_d,
        max_real_all,
        class,
    })
}
