//! The doublet-lattice method (issue 13, deliverable 1): the subsonic unsteady lifting
//! surface of linear compressible potential theory on the fin lattice of [`super`], as ONE
//! complex linear map per Mach and reduced frequency (a [`HarmonicMap`], `F = q K(ν) α_e`),
//! interchangeable with [`super::harmonic::vlm_map`].
//!
//! # Sources
//!
//! - [AR69] E. Albano, W. P. Rodden, "A doublet-lattice method for calculating lift
//!   distributions on oscillating surfaces in subsonic flows", AIAA J. 7(2), 1969, 279-285:
//!   the method (boxes, doublet line on the quarter chord, downwash at the three-quarter chord,
//!   the steady part by horseshoe vortices, the parabolic approximation of the incremental
//!   kernel's numerator across each doublet line).
//! - [RTM98] W. P. Rodden, P. F. Taylor, S. C. McIntosh, "Further refinement of the subsonic
//!   doublet-lattice method", J. Aircraft 35(5), 1998, 720-727: the planar kernel in Landahl's
//!   form `K1`, the Laschka approximation of `I1` and the parabolic integral in the form used
//!   below (their eqs. for `K1`, `I1`, `A1, B1, C1` and `D1`), the `u1 < 0` continuation.
//! - [La67] M. T. Landahl, "Kernel function for nonplanar oscillating surfaces in a subsonic
//!   flow", AIAA J. 5(5), 1967, 1045-1046 (the kernel).
//! - [D82] R. N. Desmarais, "An accurate method for evaluating the kernel of the integral
//!   equation relating lift to downwash in unsteady potential flow", AIAA Paper 82-0687,
//!   1982 (the 12-term approximation used here; adopted by [RTM98]).
//! - [Ls63] B. Laschka, "Zur Theorie der harmonisch schwingenden tragenden Fläche bei
//!   Unterschallanströmung", ZFW 11(7), 1963, 265-292 (the exponential approximation,
//!   coefficients below).
//!
//! None of these texts was reachable here; the formulas were taken from the open
//! re-statements of DLMpro (Böhnisch & Bangel, TU Braunschweig, MATLAB, `Kernel.m`,
//! `LaschkaApproxCalc.m`, `LaschkaApprox.m`, `ParabolicApprox.m`, `LookUpTable.m`, which cite
//! [AR69] and [RTM98]) and checked against the derivations written here (every one of them is
//! re-derived below, and the closed forms are tested against quadrature).
//!
//! # The integral equation (planar)
//!
//! All boxes lie in `z = 0` (the lattice and its wall image are coplanar), so the nonplanar
//! part `K2 T2` of the kernel vanishes (`T2 ∝ z0`) and `T1 = cos(γ_r - γ_s) = 1`. For a
//! harmonic motion `e^{iωt}` ([`super::harmonic`]), `ν = ω/V`, the normalwash at `(x, y)` of a
//! pressure-jump distribution `Δc_p = (p_lower - p_upper)/q` is ([AR69] eq. (1), [RTM98])
//!
//! `w(x, y)/V = -(1/8π) ∬ Δc_p(ξ, η) K(x0, y0) dξ dη`, `x0 = x - ξ`, `y0 = y - η`,
//!
//! `K = K1 e^{-iν x0} / r1²`, `r1 = |y0|`,
//!
//! with the sign chosen so that `w` is the `+z` velocity of this crate: [AR69] and DLMpro's
//! `Kernel.m` carry the minus into the numerator (`P1 = -(K1 e^{-iνx0} - K10)`). The sign was
//! derived, not copied: far behind a doublet line of span `2e` carrying `Δc_p Δx = 2Γ/V`, `K1
//! -> -2`, and the finite-part integral `∫_{-e}^{e} dη/η² = -2/e` gives `w = -Γ/(π e)`, the
//! downwash of the two trailing vortices of a lifting horseshoe.
//!
//! Landahl's planar kernel ([La67]; [RTM98]):
//!
//! `K1 = -I1 - (M r1 / R) e^{-i k1 u1} / sqrt(1 + u1²)`,
//!
//! `R = sqrt(x0² + β² r1²)`, `β² = 1 - M²`, `u1 = (M R - x0)/(β² r1)`, `k1 = ν r1`,
//!
//! `I1(u1, k1) = ∫_{u1}^{∞} e^{-i k1 u} / (1 + u²)^{3/2} du`.
//!
//! Its steady value ([RTM98]) `K10 = -1 - x0/R` (derived: at `k1 = 0`, `I1 = 1 - u1/sqrt(1 +
//! u1²)`, and `sqrt(1 + u1²) = (R - M x0)/(β² r1)` since `β⁴ r1² + (M R - x0)² = (R - M x0)²`;
//! then `R(R + x0)(1 - M) + M β² r1² = (R + x0)(R - M x0)` gives `K1(k1 = 0) = -(1 + x0/R)`).
//! On the line `r1 -> 0` ([RTM98], as `Kernel.m`; derived: `u1 -> ∓∞` for `x0 ≷ 0`): `K1 ->
//! -2` downstream (`x0 > 0`) and `0` upstream.
//!
//! # I1 by an exponential approximation (Laschka [Ls63], Desmarais [D82]; [RTM98])
//!
//! `1 - u/sqrt(1 + u²) ≈ Σ_n a_n e^{-p_n u}` for `u >= 0` ([`I1Approx`]):
//!
//! - Laschka: 11 terms, `p_n = n c`, `c = 0.372`, `a_n` = 0.24186198, -2.7918027,
//!   24.991079, -111.59196, 271.43549, -305.75288, -41.183630, 545.98537, -644.78155,
//!   328.72755, -64.279511 (they sum to 1.00002, the left side at `u = 0`);
//! - Desmarais: 12 terms, `p_n = 2^n b`, `b = 0.009054814793`, `a_n` = 0.000319759140,
//!   -0.000055461471, 0.002726074362, 0.005749551566, 0.031455895072, 0.106031126212,
//!   0.406838011567, 0.798112357155, -0.417749229098, 0.077480713894, -0.012677284771,
//!   0.001787032960 (sum 1.0000185).
//!
//! (Coefficients as DLMpro's `LookUpTable.m` lists them.) Measured here on `u` in `[0, 20]`:
//! the largest error of Laschka's sum is 1.34e-3 (at `u ≈ 15`, where the function is 2.2e-3:
//! the exponentials cannot follow its `1/(2u²)` tail), of Desmarais' 2.5e-5. The first makes
//! the 2-D limit of the method 0.5-2.6 % off Theodorsen whatever the box count (test
//! `two_dimensional_limit_matches_theodorsen` prints both), so the method uses Desmarais'.
//!
//! Integrating `I1` by parts (`d/du [u/sqrt(1 + u²)] = (1 + u²)^{-3/2}`, derived):
//!
//! `I1(u1, k1) = e^{-i k1 u1} [1 - u1/sqrt(1 + u1²) - i k1 J(u1, k1)]` with
//! `e^{-i k1 u1} J = ∫_{u1}^{∞} (1 - u/sqrt(1 + u²)) e^{-i k1 u} du`,
//!
//! so that with the approximation `J ≈ Σ a_n e^{-p_n u1} (p_n - i k1) / (p_n² + k1²)`
//! ([RTM98]; `LaschkaApproxCalc.m`, `DesmaraisApproxCalc.m`). The first bracket term is exact; at `k1 = 0` the
//! approximation drops out and `K1 = K10` to round-off, which is why the method reproduces the
//! steady lattice at `ν = 0`. For `u1 < 0` ([RTM98]; derived by splitting the integral at 0 and
//! substituting `u -> -u` on `[u1, 0]`):
//!
//! `I1(u1, k1) = 2 Re I1(0, k1) - Re I1(-u1, k1) + i Im I1(-u1, k1)`.
//!
//! The approximation error is measured against quadrature in the tests (module `dlm_tests`).
//!
//! # Boxes, doublet lines, the parabolic integral ([AR69]; [RTM98] eq. for `D1`)
//!
//! Each panel of the [`Lattice`] is a box: its doublet line is the panel's quarter-chord line
//! (the VLM bound vortex, [`super::Panel::bound`]), mid-point `(x_c, y_c)`, half-width `e`,
//! sweep `tan λ` (`x = x_c + η tan λ`, `y = y_c + η`, `|η| <= e`); the normalwash point is the
//! panel's three-quarter-chord control point; `Δc_p` is uniform over the box, so the line
//! carries `Δc_p Δx` per unit span, `Δx` the box's mean chord (area / width). The box's
//! circulation `Γ = V Δc_p Δx / 2` (Kutta-Joukowski per unit span, `ρVΓ = q Δc_p Δx`) is the
//! unknown, as in [`super::vlm`]; in these variables the normalwash of box `s` at point `r` is
//!
//! `w_r / V = Σ_s [a_rs^VLM + d_rs(ν)] Γ_s / V`, `d_rs = -(1/4π) ∫_{-e}^{e} P(η) / (ȳ - η)² dη`,
//!
//! `P(η) = K1(x0, y0) e^{-iν x0} - K10(x0, y0)`, `x0 = x̄ - η tan λ`, `y0 = ȳ - η`, `(x̄, ȳ) =
//! (x_r - x_c, y_r - y_c)`:
//!
//! the steady kernel is integrated exactly by the horseshoe vortex of the same line ([AR69]:
//! the finite-part integral of `K10/r1²` along a doublet line is the horseshoe's normalwash;
//! [`super::vlm::influence_matrix`], whose Göthert stretch is exact for steady flow), and the
//! incremental numerator `P`, regular on the line, is the parabola through its values at
//! `η = -e, 0, e` ([AR69]):
//!
//! `P ≈ A η² + B η + C`, `A = (P(-e) - 2P(0) + P(e))/(2e²)`, `B = (P(e) - P(-e))/(2e)`,
//! `C = P(0)`,
//!
//! whose finite-part integral is (planar, `z̄ = 0`; [RTM98]'s `D1` with `z̄ = 0`; derived by
//! `η = ȳ - t`: `A η² + B η + C = (A ȳ² + B ȳ + C) - (2Aȳ + B) t + A t²`)
//!
//! `∫_{-e}^{e} P/(ȳ - η)² dη = (A ȳ² + B ȳ + C) 2e/(ȳ² - e²) + (ȳ A + B/2) ln[(ȳ - e)²/(ȳ +
//! e)²] + 2 e A`.
//!
//! The wall image ([`super`]) adds the mirrored box (mid-point `(x_c, -y_c)`, sweep `-tan λ`,
//! the same `Γ`), as [`super::vlm`] mirrors its horseshoes.
//!
//! # Loads and the map
//!
//! Flow tangency `Σ_s A_rs(ν) g_s = -α_e,r`, `A = a^VLM + d(ν)`, `g = Γ/V`. The box force is
//! `q Δc_p S_box = ρ V Γ w = q 2 w g` (`w` the strip width), the WHOLE unsteady load (the
//! acceleration-potential doublet carries the circulatory and the apparent-mass pressure
//! alike, so there is no separate `∂Δφ/∂t` block as in [`super::harmonic`]):
//!
//! `K(ν) = -2 diag(w) A(ν)⁻¹`, `n` force points.
//!
//! The force acts at the box's quarter-chord mid-point (the doublet line's mid-point, where
//! [AR69] lumps the box pressure, and the Kutta-Joukowski point of [`super::vlm`]): the
//! 1/4-3/4 rule is exact for the steady flat plate in 2-D only with the load on the quarter
//! chord (K&P 12.1), the centroid would shift every box's moment by a quarter box chord. So
//! `eval` = control points and `force` = bound mid-points, the points of
//! [`super::vlm::force_map`], and at `ν = 0` the map IS that one (tested to round-off).
//!
//! # Limits
//!
//! Linear subsonic theory: the kernel is exact for `M < 1`; it is accepted up to
//! [`MACH_LIMIT`] = 0.95 (beyond, `β² < 0.1` and the acoustic wavelength `2π β²/(ν M)` of the
//! kernel's phase `k1 u1 ∋ ν M R/β²` shrinks below the box-size rule's reach; no transonic
//! effect is modelled at any Mach). Box size: the MSC Nastran rule `Δx < 0.08 V/f` of
//! [`super::harmonic::check_resolution`] on the box chord, enforced. Box aspect ratio (width
//! over chord): the parabola must follow the numerator across the box, which varies on the
//! scale of the distance to the receiving point and of `1/ν`; the usual guideline is an aspect
//! ratio below about 3 (MSC Nastran Aeroelastic Analysis User's Guide, as widely quoted; not
//! read here), and [RTM98]'s quartic approximation was introduced for the wide boxes where the
//! parabola fails (W. P. Rodden, P. F. Taylor, S. C. McIntosh, "Improvements to the
//! doublet-lattice method in MSC/NASTRAN", whose abstract, read here, states that the number
//! of boxes needed "depends on aspect ratio and reduced frequency" and that the quartic
//! version "relaxes limitations of the previous version to permit higher box aspect ratios").
//! The quartic is not implemented; the flutter analyses refuse an explicit lattice whose boxes
//! exceed [`MAX_BOX_ASPECT`] (`analysis::flutter::fin`, [`check_boxes`]; the map itself does
//! not, so the 2-D test below can use wide far strips), and the automatic lattice of the
//! analyses ([`spanwise_for`]) adds strips until none does; measured: the 2-D test converges
//! (first order, Richardson 0.04 %) with aspect ratio 2 next to the receiving strip, and stalls
//! at 2.7 % when the strips are kept 1/8 chord wide while the boxes shrink to 1/64 chord
//! (aspect ratio 8).

/// The largest box aspect ratio (width over chord) the flutter analyses accept for the
/// doublet lattice: the guideline of the module doc ("Limits") for the parabolic
/// approximation of the kernel's numerator across a box.
pub const MAX_BOX_ASPECT: f64 = 3.0;

/// The largest aspect ratio `width² / area` (strip width over mean box chord) of the
/// lattice's boxes.
pub fn max_box_aspect(lattice: &Lattice) -> f64 {
    lattice
        .panels
        .iter()
        .map(|p| p.width * p.width / p.area)
        .fold(0.0, f64::max)
}

/// The most spanwise strips [`spanwise_for`] lays out.
pub const MAX_AUTO_STRIPS: usize = 256;

/// The doublet lattice's box rules on a lattice: [`PanelError::WideBoxes`] when a box is
/// wider than [`MAX_BOX_ASPECT`] times its chord (the box-size rule in the chordwise
/// direction is checked per reduced frequency, [`Dlm::check_resolution`]).
pub fn check_boxes(lattice: &Lattice) -> Result<(), PanelError> {
    let ratio = max_box_aspect(lattice);
    if ratio > MAX_BOX_ASPECT {
        return Err(PanelError::WideBoxes {
            ratio,
            limit: MAX_BOX_ASPECT,
        });
    }
    Ok(())
}

/// The automatic lattice of the doublet lattice (issue 33): with `chordwise` boxes along
/// every chord (the consumer's count from the box-size rule `Δx < 0.08 V/f` at its highest
/// reduced frequency, module doc "Limits"), the fewest spanwise strips, at least
/// `min_spanwise` and at most [`MAX_AUTO_STRIPS`], with which no box of the lattice on
/// `planform` with `spacing` is wider than [`MAX_BOX_ASPECT`] times its mean chord.
///
/// The count is searched upward one strip at a time (the largest aspect ratio is not
/// monotone in the count for every outline, and the lattice is cheap to lay out), so the
/// answer is the smallest that meets the rule. Which box binds: uniform strips of width `s /
/// n_s` bind at the tip (the shortest chord), `n_s >= s n_c / (3 c_tip)`; the cosine strips
/// of [`Spacing::Cosine`] are widest at the root, `s sin(π/(2 n_s)) ≈ π s / (2 n_s)`, so
/// `n_s >= π s n_c / (6 c_r)` there, and at a rounded tip (elliptical outline, chord
/// `∝ sqrt(1 - η²)`) the last strip's aspect ratio falls like `π s n_c / (2 n_s c_r)` too.
/// An outline ending in a point along a straight edge (a zero tip chord reached linearly)
/// has a last strip whose aspect ratio is `2 s n_c / c_r` whatever the count (its width and
/// its chord shrink together); there, and whenever [`MAX_AUTO_STRIPS`] strips do not
/// suffice, [`PanelError::WideBoxes`] says so and the vortex lattice remains
/// (`--aero vortex-lattice`).
pub fn spanwise_for(
    planform: &crate::aero::estimator::FinPlanform,
    chordwise: usize,
    min_spanwise: usize,
    spacing: super::Spacing,
) -> Result<usize, PanelError> {
    let mut ratio = f64::INFINITY;
    for ns in min_spanwise.max(1)..=MAX_AUTO_STRIPS.max(min_spanwise) {
        let l = Lattice::new(planform, chordwise, ns, spacing)?;
        ratio = max_box_aspect(&l);
        if ratio <= MAX_BOX_ASPECT {
            return Ok(ns);
        }
    }
    Err(PanelError::WideBoxes {
        ratio,
        limit: MAX_BOX_ASPECT,
    })
}

use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, c64};

use super::harmonic::{BOX_RULE, HarmonicMap, finite_or_singular, solve_normalwash};
use super::{Lattice, PanelError, vlm};

/// The highest Mach number the doublet-lattice map accepts (module doc, "limits").
pub const MACH_LIMIT: f64 = 0.95;

/// Laschka's exponent `c` (module doc).
const LASCHKA_C: f64 = 0.372;
/// Laschka's coefficients `a_1 .. a_11` (module doc).
const LASCHKA_A: [f64; 11] = [
    0.24186198, -2.7918027, 24.991079, -111.59196, 271.43549, -305.75288, -41.183630, 545.98537,
    -644.78155, 328.72755, -64.279511,
];

/// `1 - u/sqrt(1 + u²)` for `u >= 0`, without cancellation.
fn one_minus(u: f64) -> f64 {
    let s = (1.0 + u * u).sqrt();
    1.0 / (s * (s + u))
}

/// Desmarais' exponent base `b` (module doc): the exponents are `2^n b`.
const DESMARAIS_B: f64 = 0.009054814793;
/// Desmarais' coefficients `a_1 .. a_12` (module doc).
const DESMARAIS_A: [f64; 12] = [
    0.000319759140,
    -0.000055461471,
    0.002726074362,
    0.005749551566,
    0.031455895072,
    0.106031126212,
    0.406838011567,
    0.798112357155,
    -0.417749229098,
    0.077480713894,
    -0.012677284771,
    0.001787032960,
];

/// The exponential approximation of `1 - u/sqrt(1 + u²) ≈ Σ a_n e^{-p_n u}` (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum I1Approx {
    /// Laschka's 11 terms, `p_n = 0.372 n`.
    Laschka,
    /// Desmarais' 12 terms, `p_n = 2^n b` (the default: 50 times more accurate).
    Desmarais,
}

/// `I1(u1, k1)` for `u1 >= 0` by the exponential approximation (module doc).
fn i1_nonneg(u1: f64, k1: f64, approx: I1Approx) -> c64 {
    let mut j = c64::new(0.0, 0.0);
    match approx {
        I1Approx::Laschka => {
            for (n, a) in LASCHKA_A.iter().enumerate() {
                let p = (n + 1) as f64 * LASCHKA_C;
                j += c64::new(p, -k1) * (a * (-p * u1).exp() / (p * p + k1 * k1));
            }
        }
        I1Approx::Desmarais => {
            // e^{-2^n b u1} by repeated squaring of e^{-2 b u1} (one exponential).
            let mut p = 2.0 * DESMARAIS_B;
            let mut q = (-p * u1).exp();
            for a in DESMARAIS_A {
                j += c64::new(p, -k1) * (a * q / (p * p + k1 * k1));
                p *= 2.0;
                q *= q;
            }
        }
    }
    let (s, c) = (k1 * u1).sin_cos();
    let phase = c64::new(c, -s);
    phase * (c64::new(one_minus(u1), 0.0) - c64::new(0.0, k1) * j)
}

/// `I1(u1, k1) = ∫_{u1}^{∞} e^{-i k1 u} (1 + u²)^{-3/2} du` by the exponential approximation
/// `approx`, any `u1` (module doc).
pub fn i1_with(u1: f64, k1: f64, approx: I1Approx) -> c64 {
    if u1 >= 0.0 {
        i1_nonneg(u1, k1, approx)
    } else {
        let i0 = i1_nonneg(0.0, k1, approx);
        let im = i1_nonneg(-u1, k1, approx);
        c64::new(2.0 * i0.re - im.re, im.im)
    }
}

/// `I1` by Desmarais' approximation, the one the method uses.
pub fn i1(u1: f64, k1: f64) -> c64 {
    i1_with(u1, k1, I1Approx::Desmarais)
}

/// The incremental numerator `P = K1 e^{-iν x0} - K10` of the planar kernel at `(x0, y0)`
/// (module doc); `scale` sets the `r1 -> 0` threshold.
pub fn increment_numerator(
    x0: f64,
    y0: f64,
    nu: f64,
    mach: f64,
    scale: f64,
    approx: I1Approx,
) -> c64 {
    let r1 = y0.abs();
    let b2 = 1.0 - mach * mach;
    let (s, c) = (nu * x0).sin_cos();
    let wave = c64::new(c, -s);
    if r1 <= 1e-12 * scale {
        return if x0 > 0.0 {
            c64::new(2.0, 0.0) - wave * 2.0
        } else {
            c64::new(0.0, 0.0)
        };
    }
    let r = (x0 * x0 + b2 * r1 * r1).sqrt();
    let u1 = (mach * r - x0) / (b2 * r1);
    let k1 = nu * r1;
    // sqrt(1 + u1²) = (R - M x0)/(β² r1) (module doc), and K10 = -(R + x0)/R written without
    // cancellation upstream: R + x0 = β² r1² / (R - x0).
    let root = (r - mach * x0) / (b2 * r1);
    let (su, cu) = (k1 * u1).sin_cos();
    let k1v = -i1_with(u1, k1, approx) - c64::new(cu, -su) * (mach * r1 / (r * root));
    let k10 = if x0 >= 0.0 {
        -(r + x0) / r
    } else {
        -(b2 * r1 * r1) / (r * (r - x0))
    };
    k1v * wave - c64::new(k10, 0.0)
}

/// A doublet line: mid-point, half-width `e` and sweep `tan λ` (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Line {
    mid: [f64; 2],
    half: f64,
    tan_sweep: f64,
}

impl Line {
    fn from_ends(a: [f64; 2], b: [f64; 2]) -> Line {
        let half = 0.5 * (b[1] - a[1]);
        Line {
            mid: [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])],
            half,
            tan_sweep: (b[0] - a[0]) / (2.0 * half),
        }
    }

    /// The wall image (module doc).
    fn image(&self) -> Line {
        Line {
            mid: [self.mid[0], -self.mid[1]],
            half: self.half,
            tan_sweep: -self.tan_sweep,
        }
    }
}

/// The incremental normalwash `d` (`+z` velocity per unit `Γ`, 1/m) at `p` of the doublet line
/// from `a` to `b` (`y_b > y_a`), WITHOUT its wall image: the parabolic integral of the module
/// doc, `I1` by `approx`.
pub fn increment(
    p: [f64; 2],
    a: [f64; 2],
    b: [f64; 2],
    nu: f64,
    mach: f64,
    approx: I1Approx,
) -> c64 {
    line_increment(p, &Line::from_ends(a, b), nu, mach, approx)
}

fn line_increment(p: [f64; 2], l: &Line, nu: f64, mach: f64, approx: I1Approx) -> c64 {
    let e = l.half;
    let (xb, yb) = (p[0] - l.mid[0], p[1] - l.mid[1]);
    let at = |eta: f64| increment_numerator(xb - eta * l.tan_sweep, yb - eta, nu, mach, e, approx);
    let (pm, p0, pp) = (at(-e), at(0.0), at(e));
    let a = (pm - p0 * 2.0 + pp) / (2.0 * e * e);
    let b = (pp - pm) / (2.0 * e);
    let c = p0;
    let f = 2.0 * e / (yb * yb - e * e);
    let log = ((yb - e) * (yb - e) / ((yb + e) * (yb + e))).ln();
    let integral = (a * (yb * yb) + b * yb + c) * f + (a * yb + b * 0.5) * log + a * (2.0 * e);
    -integral / (4.0 * std::f64::consts::PI)
}

/// The doublet lattice of one fin at one Mach: the steady (VLM) influence, the doublet lines
/// and the points, from which [`Self::map`] forms the map at any reduced frequency.
#[derive(Clone, Debug)]
pub struct Dlm {
    n: usize,
    mach: f64,
    steady: Vec<f64>,
    lines: Vec<Line>,
    widths: Vec<f64>,
    eval: Vec<[f64; 2]>,
    force: Vec<[f64; 2]>,
    max_box_chord: f64,
    /// The frequency-independent part of the kernel ([`Self::influence`], "Cost").
    geometry: Geometry,
}

/// The kernel's sampling points and every frequency-independent quantity of the numerator
/// `P` and of the parabolic integral, computed once per Mach ([`Dlm::influence`], "Cost").
#[derive(Clone, Debug)]
struct Geometry {
    /// The distinct sampling points `η = -e, 0, e` of the doublet lines and of their images.
    points: Vec<[f64; 2]>,
    /// Per line, the indices into `points` of `P(-e), P(0), P(e)`: the line, then its image.
    taps: Vec<[[usize; 3]; 2]>,
    /// Per receiving point `r` and line `s` (row-major `n x n`), the weights of `P(-e),
    /// P(0), P(e)` in `d_rs`, line then image, `-1/(4π)` included.
    weights: Vec<[[f64; 3]; 2]>,
    /// Per receiving point and sampling point (row-major `n x points`), the pair's geometry.
    pairs: Vec<PairGeo>,
    /// The distinct spanwise coordinates of the sampling points, and each point's index in it.
    ys: Vec<f64>,
    point_y: Vec<usize>,
}

/// The frequency-independent part of `P` at one (receiving, sampling) pair (module doc):
/// `|u1|`, `1 - |u1|/sqrt(1 + u1²)`, `e^{-2 b |u1|}` (Desmarais' base), `M r1 / (R
/// sqrt(1 + u1²))`, `K10`, whether `u1 < 0`, and whether the point lies on the doublet's
/// line (`r1 -> 0`: then `K1 = k10`, -2 downstream and 0 upstream).
#[derive(Clone, Copy, Debug)]
struct PairGeo {
    au: f64,
    om: f64,
    q: f64,
    amp: f64,
    k10: f64,
    negative: bool,
    on_line: bool,
}

impl PairGeo {
    fn new(x0: f64, y0: f64, mach: f64, scale: f64) -> PairGeo {
        let r1 = y0.abs();
        let b2 = 1.0 - mach * mach;
        if r1 <= 1e-12 * scale {
            let k = if x0 > 0.0 { -2.0 } else { 0.0 };
            return PairGeo {
                au: 0.0,
                om: 0.0,
                q: 0.0,
                amp: 0.0,
                k10: k,
                negative: false,
                on_line: true,
            };
        }
        // As `increment_numerator`, term by term.
        let r = (x0 * x0 + b2 * r1 * r1).sqrt();
        let u1 = (mach * r - x0) / (b2 * r1);
        let root = (r - mach * x0) / (b2 * r1);
        let k10 = if x0 >= 0.0 {
            -(r + x0) / r
        } else {
            -(b2 * r1 * r1) / (r * (r - x0))
        };
        let au = u1.abs();
        PairGeo {
            au,
            om: one_minus(au),
            q: (-2.0 * DESMARAIS_B * au).exp(),
            amp: mach * r1 / (r * root),
            k10,
            negative: u1 < 0.0,
            on_line: false,
        }
    }

    /// `K1 e^{-iν x0} - K10` given `wave = e^{-iν x0}` and the quantities of its spanwise
    /// distance `r1` ([`Station`]) (module doc; `I1` by Desmarais').
    #[inline]
    fn numerator(&self, wave: c64, st: &Station) -> c64 {
        if self.on_line {
            return wave * self.k10 - c64::new(self.k10, 0.0);
        }
        let k1 = st.k1;
        let (s, c) = (k1 * self.au).sin_cos();
        // e^{-i k1 |u1|}.
        let phase = c64::new(c, -s);
        // Desmarais' J at |u1| (module doc; as `i1_nonneg`), q = e^{-2^n b |u1|}.
        let (mut jr, mut ji) = (0.0, 0.0);
        let mut q = self.q;
        for (n, a) in DESMARAIS_A.iter().enumerate() {
            let w = a * q * st.inv[n];
            jr += st.p[n] * w;
            ji -= k1 * w;
            q *= q;
        }
        // I1(|u1|, k1) = phase [om - i k1 J].
        let inner = c64::new(self.om + k1 * ji, -k1 * jr);
        let i_abs = phase * inner;
        let (i1, e_u1) = if self.negative {
            let i0 = st.i0;
            (c64::new(2.0 * i0.re - i_abs.re, i_abs.im), c64::new(c, s))
        } else {
            (i_abs, phase)
        };
        let k1v = -i1 - e_u1 * self.amp;
        k1v * wave - c64::new(self.k10, 0.0)
    }
}

/// What every sampling point at one spanwise distance `r1` from a receiving point shares at
/// one frequency: `k1 = ν r1`, Desmarais' `p_n` and `1/(p_n² + k1²)`, and `I1(0, k1)` (the
/// `u1 < 0` continuation, module doc).
#[derive(Clone, Copy, Debug)]
struct Station {
    k1: f64,
    p: [f64; 12],
    inv: [f64; 12],
    i0: c64,
}

impl Station {
    fn new(k1: f64) -> Station {
        let mut p = [0.0; 12];
        let mut inv = [0.0; 12];
        let mut pn = 2.0 * DESMARAIS_B;
        let (mut jr, mut ji) = (0.0, 0.0);
        for n in 0..12 {
            p[n] = pn;
            inv[n] = 1.0 / (pn * pn + k1 * k1);
            // J(0, k1) = Σ a_n (p_n - i k1)/(p_n² + k1²).
            let w = DESMARAIS_A[n] * inv[n];
            jr += pn * w;
            ji -= k1 * w;
            pn *= 2.0;
        }
        // I1(0, k1) = 1 - i k1 J(0, k1).
        Station {
            k1,
            p,
            inv,
            i0: c64::new(1.0 + k1 * ji, -k1 * jr),
        }
    }
}

impl Geometry {
    /// `bounds`: each line's end points as the lattice lays them out (neighbours share them
    /// bit for bit), `lines` the lines made from them.
    fn new(bounds: &[[[f64; 2]; 2]], lines: &[Line], eval: &[[f64; 2]], mach: f64) -> Geometry {
        let mut points: Vec<[f64; 2]> = Vec::new();
        let mut index = std::collections::BTreeMap::<(u64, u64), usize>::new();
        let mut tap = |p: [f64; 2]| -> usize {
            // -0.0 and 0.0 are one point.
            let p = [p[0] + 0.0, p[1] + 0.0];
            *index
                .entry((p[0].to_bits(), p[1].to_bits()))
                .or_insert_with(|| {
                    points.push(p);
                    points.len() - 1
                })
        };
        let mut taps = Vec::with_capacity(lines.len());
        for (l, [a, b]) in lines.iter().zip(bounds) {
            // The line runs from `a` (η = -e) to `b` (η = e); its image from the image of `b`
            // (η = -e) to that of `a`.
            let mirror = |p: [f64; 2]| [p[0], -p[1]];
            taps.push([
                [tap(*a), tap(l.mid), tap(*b)],
                [tap(mirror(*b)), tap(mirror(l.mid)), tap(mirror(*a))],
            ]);
        }
        let scale = lines.iter().map(|l| l.half).fold(f64::INFINITY, f64::min);
        let n = eval.len();
        let np = points.len();
        let mut pairs = Vec::with_capacity(n * np);
        for p in eval {
            for q in &points {
                pairs.push(PairGeo::new(p[0] - q[0], p[1] - q[1], mach, scale));
            }
        }
        let mut weights = Vec::with_capacity(n * lines.len());
        let c = -1.0 / (4.0 * std::f64::consts::PI);
        for p in eval {
            for l in lines {
                let w = |l: &Line| -> [f64; 3] {
                    let e = l.half;
                    let yb = p[1] - l.mid[1];
                    let f = 2.0 * e / (yb * yb - e * e);
                    let log = ((yb - e) * (yb - e) / ((yb + e) * (yb + e))).ln();
                    // ∫ = A α + B β + C γ with A, B, C the parabola's (module doc).
                    let alpha = yb * yb * f + yb * log + 2.0 * e;
                    let beta = yb * f + 0.5 * log;
                    let gamma = f;
                    let a2 = alpha / (2.0 * e * e);
                    let b2 = beta / (2.0 * e);
                    [c * (a2 - b2), c * (gamma - 2.0 * a2), c * (a2 + b2)]
                };
                weights.push([w(l), w(&l.image())]);
            }
        }
        let mut ys: Vec<f64> = Vec::new();
        let mut y_index = std::collections::BTreeMap::<u64, usize>::new();
        let point_y = points
            .iter()
            .map(|p| {
                *y_index.entry(p[1].to_bits()).or_insert_with(|| {
                    ys.push(p[1]);
                    ys.len() - 1
                })
            })
            .collect();
        Geometry {
            points,
            taps,
            weights,
            pairs,
            ys,
            point_y,
        }
    }
}

impl Dlm {
    /// The doublet lattice of `lattice` at Mach `mach` (`0 <= M <= `[`MACH_LIMIT`]).
    pub fn new(lattice: &Lattice, mach: f64) -> Result<Dlm, PanelError> {
        if !(mach.is_finite() && mach >= 0.0) {
            return Err(PanelError::BadMach(mach));
        }
        if mach > MACH_LIMIT {
            return Err(PanelError::Untrusted(mach, "doublet lattice"));
        }
        let steady = vlm::influence_matrix(lattice, mach)?;
        let lines: Vec<Line> = lattice
            .panels
            .iter()
            .map(|p| Line::from_ends(p.bound[0], p.bound[1]))
            .collect();
        let eval: Vec<[f64; 2]> = lattice.panels.iter().map(|p| p.control).collect();
        let bounds: Vec<[[f64; 2]; 2]> = lattice.panels.iter().map(|p| p.bound).collect();
        let geometry = Geometry::new(&bounds, &lines, &eval, mach);
        let mut max_box_chord: f64 = 0.0;
        for p in &lattice.panels {
            for (a, b) in [(0, 3), (1, 2)] {
                max_box_chord = max_box_chord.max(p.corners[b][0] - p.corners[a][0]);
            }
        }
        Ok(Dlm {
            n: lattice.len(),
            mach,
            steady,
            lines,
            widths: lattice.panels.iter().map(|p| p.width).collect(),
            eval,
            force: lattice.panels.iter().map(|p| p.bound_mid()).collect(),
            max_box_chord,
            geometry,
        })
    }

    /// Mach number of this lattice.
    pub fn mach(&self) -> f64 {
        self.mach
    }

    /// The box-size rule `Δx < 0.08 · 2π/ν` (module doc); `BadFrequency` for a negative or
    /// non-finite `nu`.
    pub fn check_resolution(&self, nu: f64) -> Result<(), PanelError> {
        if !(nu.is_finite() && nu >= 0.0) {
            return Err(PanelError::BadFrequency(nu));
        }
        let limit = BOX_RULE * std::f64::consts::TAU / nu;
        if self.max_box_chord > limit {
            return Err(PanelError::TooCoarse {
                what: "box chord",
                value: self.max_box_chord,
                limit,
                nu,
                rule: "box chord < 0.08 V/f (MSC Nastran Aeroelastic User's Guide)",
            });
        }
        Ok(())
    }

    /// The complex influence matrix `A(ν) = a^VLM + d(ν)` (module doc), images included.
    ///
    /// # Cost
    ///
    /// The sum of the module doc evaluated as written needs `6 n²` kernel numerators per
    /// frequency. Three identities make it cheaper without changing the formulas (the
    /// results agree with [`Self::influence_direct`] to round-off, test
    /// `fast_influence_is_the_direct_sum`):
    ///
    /// - neighbouring boxes of a chordwise row share the end points of their doublet lines
    ///   (the lattice's strip edges), so `P` is evaluated once per distinct point: `2 n_s + 1`
    ///   per row instead of `3 n_s`, for the lines and for their images;
    /// - everything in `P` but the frequency is geometry (`R`, `u1`, `K10`, `sqrt(1 + u1²)`,
    ///   Desmarais' `e^{-p_n |u1|}`), and the parabolic integral is linear in the three
    ///   samples, `∫ = A α + B β + C γ` with `α = ȳ² f + ȳ L + 2e`, `β = ȳ f + L/2`, `γ = f`,
    ///   `f = 2e/(ȳ² - e²)`, `L = ln[(ȳ - e)²/(ȳ + e)²]` (rearranging the module doc's
    ///   closed form), so those and the three weights are computed once per Mach;
    /// - `e^{-iν x0} = e^{-iν x_r} e^{iν ξ}` factors into one phase per receiving point and
    ///   one per sampling point.
    pub fn influence(&self, nu: f64) -> Mat<c64> {
        let n = self.n;
        let g = &self.geometry;
        let np = g.points.len();
        let phase = |x: f64, sign: f64| {
            let (s, c) = (nu * x).sin_cos();
            c64::new(c, sign * s)
        };
        let er: Vec<c64> = self.eval.iter().map(|p| phase(p[0], -1.0)).collect();
        let es: Vec<c64> = g.points.iter().map(|p| phase(p[0], 1.0)).collect();
        let mut a = Mat::<c64>::from_fn(n, n, |r, s| c64::new(self.steady[r * n + s], 0.0));
        let mut num = vec![c64::new(0.0, 0.0); np];
        let mut stations: Vec<Station> = Vec::with_capacity(g.ys.len());
        for r in 0..n {
            let yr = self.eval[r][1];
            stations.clear();
            stations.extend(g.ys.iter().map(|&y| Station::new(nu * (yr - y).abs())));
            let pairs = &g.pairs[r * np..(r + 1) * np];
            for (((v, pair), e), &yi) in num.iter_mut().zip(pairs).zip(&es).zip(&g.point_y) {
                *v = pair.numerator(er[r] * *e, &stations[yi]);
            }
            for s in 0..n {
                let w = &g.weights[r * n + s];
                let t = &g.taps[s];
                let mut d = c64::new(0.0, 0.0);
                for side in 0..2 {
                    for i in 0..3 {
                        d += num[t[side][i]] * w[side][i];
                    }
                }
                a[(r, s)] += d;
            }
        }
        a
    }

    /// [`Self::influence`] by the module doc's sum as written (the reference of the test
    /// `fast_influence_is_the_direct_sum`).
    pub fn influence_direct(&self, nu: f64) -> Mat<c64> {
        let n = self.n;
        let mut a = Mat::<c64>::from_fn(n, n, |r, s| c64::new(self.steady[r * n + s], 0.0));
        for (s, line) in self.lines.iter().enumerate() {
            let image = line.image();
            for (r, &p) in self.eval.iter().enumerate() {
                a[(r, s)] += line_increment(p, line, nu, self.mach, I1Approx::Desmarais)
                    + line_increment(p, &image, nu, self.mach, I1Approx::Desmarais);
            }
        }
        a
    }

    /// The complex force map at reduced frequency `nu = ω/V` (1/m): `eval` the control points,
    /// `force` the box quarter-chord mid-points (module doc).
    pub fn map(&self, nu: f64) -> Result<HarmonicMap, PanelError> {
        self.check_resolution(nu)?;
        let n = self.n;
        let inv = self.influence(nu).partial_piv_lu().inverse();
        let mut k = vec![c64::new(0.0, 0.0); n * n];
        for p in 0..n {
            let w2 = 2.0 * self.widths[p];
            for r in 0..n {
                k[p * n + r] = -inv[(p, r)] * w2;
            }
        }
        if k.iter().any(|v| !(v.re.is_finite() && v.im.is_finite())) {
            return Err(PanelError::Singular(self.mach));
        }
        Ok(HarmonicMap {
            eval: self.eval.clone(),
            force: self.force.clone(),
            k,
        })
    }

    /// The force amplitudes `F / q` (row-major `n x m`) for `m` normalwash columns `alpha_e`
    /// (row-major `n x m`, at the control points), by one LU solve.
    pub fn forces(&self, nu: f64, alpha_e: &[c64], m: usize) -> Result<Vec<c64>, PanelError> {
        self.check_resolution(nu)?;
        let n = self.n;
        let g = solve_normalwash(n, alpha_e, m, || self.influence(nu))?;
        let mut f = vec![c64::new(0.0, 0.0); n * m];
        for p in 0..n {
            let w2 = 2.0 * self.widths[p];
            for c in 0..m {
                f[p * m + c] = g[(p, c)] * w2;
            }
        }
        finite_or_singular(f, self.mach)
    }
}

/// The doublet-lattice force map of `lattice` at Mach `mach` and `nu = ω/V` (1/m):
/// [`Dlm::new`] then [`Dlm::map`].
pub fn dlm_map(lattice: &Lattice, mach: f64, nu: f64) -> Result<HarmonicMap, PanelError> {
    Dlm::new(lattice, mach)?.map(nu)
}
