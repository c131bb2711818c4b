//! Supersonic panels: piston theory.
//!
//! # Piston theory (Lighthill 1953; Ashley & Zartarian, "Piston theory - a new aerodynamic
//! tool for the aeroelastician", J. Aeronaut. Sci. 23(12), 1956, 1109-1118)
//!
//! At high Mach numbers each surface element acts as a piston in a one-dimensional tube: the
//! local pressure follows from the normal velocity `w` of the surface INTO the gas by the
//! isentropic simple-wave relation `p/p∞ = (1 + (γ - 1)/2 · w/a)^(2γ/(γ - 1))` (`a` the free
//! stream speed of sound). Its expansion to third order in `ε = w/a` (derived here: take the
//! logarithm, `(2γ/(γ-1)) ln(1 + (γ-1)ε/2) = γε - γ(γ-1)ε²/4 + γ(γ-1)²ε³/12 + O(ε⁴)`,
//! exponentiate, collect) is Ashley & Zartarian's third-order piston theory:
//!
//! `p/p∞ = 1 + γ ε + γ(γ+1)/4 ε² + γ(γ+1)/12 ε³`.
//!
//! On a thin plate the lower surface moves into the gas with `w = V α_e` and the upper one
//! away from it with `-V α_e` (`α_e` the normalwash angle of [`super`], `w = V α_e` includes
//! `-V ∂z/∂x - ∂z/∂t`). The even terms cancel in the difference, and with `γ p∞ = ρ a²`:
//!
//! `Δp = p_lower - p_upper = 2 ρ a V α_e [1 + (γ+1)/12 M² α_e²]` (third order),
//! `Δp = 2 ρ a V α_e = (4 q / M) α_e` (first order).
//!
//! The panel models here are linear maps, `F = q K α_e` (about the flat undeformed fin the
//! third-order term has zero slope, so the linear matrices of both orders coincide; the
//! third-order pressure is provided for the pointwise law, [`delta_p_third_order`]).
//!
//! # Low supersonic Mach numbers: the Ackeret factor
//!
//! First-order piston theory is the `M >> 1` limit of linear supersonic theory: for a flat
//! plate at `α` Ackeret's result is `Δp = 4 q α / sqrt(M² - 1)` (Ackeret 1925; Anderson,
//! *Modern Compressible Flow*, eq. (4.51)), and piston theory under-predicts it by the factor
//! `sqrt(M² - 1)/M` (0.866 at M = 2, 0.943 at M = 3). [`Correction::Ackeret`] replaces
//! `4 q / M` by `4 q / sqrt(M² - 1)` (i.e. `2 q / sqrt(M² - 1)` per surface) for BOTH the slope
//! and the rate parts of `α_e`: exact for the steady flat plate in 2-D, and it keeps the
//! damping-to-stiffness ratio of piston theory `1/V` (the proper low-supersonic 2-D
//! quasi-steady damping differs; neither form is trusted near M = 1). Piston theory is used
//! for `M >= 1.2` ([`super::SUPERSONIC_LIMIT`]); it is accurate when `M² >> 1` and, being
//! local, ignores the tip and root Mach cones (their share of the fin shrinks as `1/β`).

use super::{Lattice, PanelError};

/// Ratio of specific heats of air.
pub const GAMMA: f64 = 1.4;

/// The low-supersonic factor applied to first-order piston theory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Correction {
    /// Classical first-order piston theory, `Δp = (4 q / M) α_e`.
    None,
    /// `Δp = (4 q / sqrt(M² - 1)) α_e` (Ackeret's flat-plate factor).
    Ackeret,
}

/// The coefficient `c` in `Δp = c q α_e` at Mach `mach > 1`.
pub fn pressure_coefficient_slope(mach: f64, correction: Correction) -> Result<f64, PanelError> {
    if !(mach.is_finite() && mach > 1.0) {
        return Err(PanelError::BadMach(mach));
    }
    Ok(match correction {
        Correction::None => 4.0 / mach,
        Correction::Ackeret => 4.0 / (mach * mach - 1.0).sqrt(),
    })
}

/// Third-order piston theory pressure on one surface, `p/p∞` for `ε = w/a` (module doc).
pub fn pressure_ratio_third_order(eps: f64) -> f64 {
    let g = GAMMA;
    1.0 + g * eps + g * (g + 1.0) / 4.0 * eps * eps + g * (g + 1.0) / 12.0 * eps * eps * eps
}

/// The exact isentropic simple-wave pressure `p/p∞ = (1 + (γ-1)/2 ε)^(2γ/(γ-1))`.
pub fn pressure_ratio_simple_wave(eps: f64) -> f64 {
    let g = GAMMA;
    (1.0 + 0.5 * (g - 1.0) * eps).powf(2.0 * g / (g - 1.0))
}

/// Pressure jump `Δp` (Pa) of third-order piston theory on a thin plate: free-stream static
/// pressure `p_inf`, Mach `mach`, normalwash angle `alpha_e` (module doc).
pub fn delta_p_third_order(p_inf: f64, mach: f64, alpha_e: f64) -> f64 {
    let eps = mach * alpha_e;
    p_inf * (pressure_ratio_third_order(eps) - pressure_ratio_third_order(-eps))
}

/// The supersonic force map `K` (row-major `n x n`, diagonal, m²): `F_p = q K[p][p] α_e,p`,
/// `α_e` and the force at the panel centroids.
pub fn force_map(
    lattice: &Lattice,
    mach: f64,
    correction: Correction,
) -> Result<Vec<f64>, PanelError> {
    let c = pressure_coefficient_slope(mach, correction)?;
    let n = lattice.len();
    let mut k = vec![0.0; n * n];
    for (p, panel) in lattice.panels.iter().enumerate() {
        k[p * n + p] = c * panel.area;
    }
    Ok(k)
}
