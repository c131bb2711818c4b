//! Eigen-structure of a linear model `δ̇ = A δ`: roots, damping, frequency, the stability
//! parameters `sigma_d`, `omega_d` of thesis (6.30) and the participation factors that say
//! which states drive each root.
//!
//! Participation factors (Pérez-Arriaga, Verghese, Schweppe, IEEE PAS-101 (1982) 3117):
//! with right eigenvectors `r_i` (columns of `R`) and left eigenvectors `l_i` (rows of
//! `L = R⁻¹`, so `l_i r_j = δ_ij`), `p_ki = |l_ki r_ki|`, normalised per root to sum 1. The
//! normalisation makes `p` independent of how `r_i` is scaled, and so of the units of the
//! states.
//!
//! # Flight-path roots
//! The reference of a linearisation is a frozen instant of a trajectory that is itself
//! turning and slowing under gravity and drag. Its slow drift shows as roots that belong to
//! the flight path, not to the vehicle's dynamics: perturbing the flight-path angle of a
//! climbing gravity turn grows (`γ̇ = -g cos γ / V` gives `∂γ̇/∂γ = g sin γ / V > 0` for
//! `γ > 0`: SPHADS-1 climbing at 60 deg at 200 m/s has a root near +0.04 1/s), and a
//! perturbed speed relaxes at `-2 D/(m V)`. Those roots are classified apart
//! ([`RootKind::FlightPath`]) and take no part in `sigma_d` and the vehicle's class.
//!
//! Criterion, from the point-mass flight-path equations (Etkin, *Dynamics of Atmospheric
//! Flight*, 1972, sec. 5.3 and 9.4; a point mass with drag `D` and no lift perturbation):
//! with `u = δV / V`,
//! `u̇ = -(2 a_D / V) u - (g cos γ / V) δγ` and `δγ̇ = (g cos γ / V) u + (g sin γ / V) δγ`
//! (`a_D = D / m`, `ρ` frozen, `C_D` constant; heading is neutral). Every root of this
//! system obeys `|λ| ≤ ‖J‖_∞ = max(2 a_D + g|cos γ|, g(|cos γ| + |sin γ|)) / V
//! ≤ Λ = (2 a_D + √2 g) / V`. A root of the full model is a flight-path root when
//! `|λ| ≤ Λ` AND at least half of its participation lies in the attitude states
//! (`theta_*`) and the axial speed (`v_body_x`): the point-mass motion turns attitude and
//! velocity together (angle of attack unchanged) and changes the speed, while the vehicle's
//! own rigid roots (short period, weathercock divergence) live in the angle of attack and
//! sideslip (`v_body_y`, `v_body_z`) and the body rates, and its elastic roots in the modal
//! states. SPHADS-1 at 200 m/s, 5 km, pitched up 60 deg, 1.0 mm fins: `Λ = 0.116 1/s`; the
//! flight-path roots are +0.0423 1/s (`theta_y`, `theta_z` 100 %: `g sin γ / V`) and
//! -0.048 1/s (`v_body_x` 100 %); the short period is -0.58 ± 8.7i (`omega_body` and
//! `v_body` 49 % each, `theta` below 1 %); elastic roots lie above 400 rad/s. A vehicle root
//! as slow as `Λ` (a static margin near zero) is kept a vehicle root by the participation
//! test as long as it lives in the angle of attack and rates.

use faer::Mat;
use faer::linalg::solvers::DenseSolveCore;
use serde::Serialize;

use super::linear_grid::StabilityClass;
use super::linearise::{LinearModel, LineariseError};

/// What a root belongs to (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RootKind {
    /// `|λ|` below the neutral tolerance: an exact rigid-body zero (roll angle, heading).
    Neutral,
    /// The slow drift of the trim's flight path (`|λ| ≤ Λ`, attitude and axial speed).
    FlightPath,
    /// A root of the vehicle's dynamics: these decide `sigma_d` and the class.
    Dynamic,
}

/// The flight-path rate scale `Λ = (2 a_D + √2 g) / V` of a reference (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FlightPathScale {
    /// Airspeed `V`, m/s.
    pub speed: f64,
    /// Gravity `g`, m/s² (0 without a gravity block).
    pub gravity: f64,
    /// `a_D`: magnitude of the non-gravitational (aerodynamic) acceleration at the trim,
    /// m/s².
    pub aero_acceleration: f64,
}

impl FlightPathScale {
    /// `Λ`, 1/s.
    pub fn rate(&self) -> f64 {
        (2.0 * self.aero_acceleration + std::f64::consts::SQRT_2 * self.gravity)
            / self.speed.max(f64::MIN_POSITIVE)
    }
}

/// Participation share of the attitude states and the axial speed (`δθ`, `δV_x`: the first
/// four linear states, [`super::linearise::state_names`]) above which a slow root counts as
/// a flight-path root.
pub const FLIGHT_PATH_PARTICIPATION: f64 = 0.5;

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
    /// Neutral, flight path or the vehicle's own (module doc).
    pub kind: RootKind,
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
    /// `sigma_d = max Re λ` over the vehicle's dynamic roots (not neutral, not flight
    /// path), 1/s.
    pub sigma_d: f64,
    /// `|Im λ|` of that least-stable root, rad/s.
    pub omega_d: f64,
    /// `max Re λ` over all roots, neutral ones included (their numerical noise shows here).
    pub max_real_all: f64,
    /// Stable if `sigma_d <= 0`, else flutter (complex least-stable root) or divergence
    /// (real).
    pub class: StabilityClass,
    /// The scale the flight-path roots were separated with (`None`: not separated).
    pub flight_path_scale: Option<FlightPathScale>,
    /// `Λ`, 1/s (`None`: not separated).
    pub flight_path_rate: Option<f64>,
    /// `max Re λ` over the flight-path roots (`None`: there are none).
    pub flight_path_sigma: Option<f64>,
}

/// Eigenvalues, eigenvectors and participation factors of `model.a`; roots with
/// `|λ| < neutral_tolerance` are marked neutral, every other root is the vehicle's (no
/// flight-path separation: see [`eigen_structure_separated`]).
pub fn eigen_structure(
    model: &LinearModel,
    neutral_tolerance: f64,
) -> Result<EigenStructure, LineariseError> {
    eigen_structure_with(model, neutral_tolerance, None)
}

/// [`eigen_structure`] with the flight-path roots of `scale` separated from the vehicle's
/// dynamic roots (module doc).
pub fn eigen_structure_separated(
    model: &LinearModel,
    neutral_tolerance: f64,
    scale: FlightPathScale,
) -> Result<EigenStructure, LineariseError> {
    eigen_structure_with(model, neutral_tolerance, Some(scale))
}

fn eigen_structure_with(
    model: &LinearModel,
    neutral_tolerance: f64,
    scale: Option<FlightPathScale>,
) -> Result<EigenStructure, LineariseError> {
    let flight_path_rate = scale.map(|s| s.rate());
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
        let neutral = modulus < neutral_tolerance;
        let attitude_velocity: f64 = p.iter().take(4).sum();
        let kind = match flight_path_rate {
            _ if neutral => RootKind::Neutral,
            Some(rate) if modulus <= rate && attitude_velocity >= FLIGHT_PATH_PARTICIPATION => {
                RootKind::FlightPath
            }
            _ => RootKind::Dynamic,
        };
        roots.push(Root {
            real: re,
            imag: im,
            damping_ratio: if modulus > 0.0 { -re / modulus } else { 0.0 },
            natural_frequency_hz: modulus / std::f64::consts::TAU,
            frequency_hz: im.abs() / std::f64::consts::TAU,
            neutral,
            kind,
            participation: p,
        });
    }
    roots.sort_by(|a, b| b.real.total_cmp(&a.real).then(b.imag.total_cmp(&a.imag)));
    let max_real_all = roots
        .iter()
        .map(|r| r.real)
        .fold(f64::NEG_INFINITY, f64::max);
    let least = roots.iter().find(|r| r.kind == RootKind::Dynamic);
    let flight_path_sigma = roots
        .iter()
        .filter(|r| r.kind == RootKind::FlightPath)
        .map(|r| r.real)
        .reduce(f64::max);
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
        flight_path_scale: scale,
        flight_path_rate,
        flight_path_sigma,
    })
}
