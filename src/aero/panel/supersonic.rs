//! Steady supersonic lifting surface: constant-pressure panels with the finite-part kernel of
//! linearised supersonic flow (issue 33). Valid for subsonic and supersonic leading, trailing
//! and side edges alike, on the same trapezoidal panels as [`super::vlm`] and [`super::piston`].
//!
//! # The integral equation
//!
//! In linearised steady supersonic flow (`β = sqrt(M² - 1)`) a lifting-pressure distribution
//! `ΔC_p(ξ, η) = (p_lower - p_upper)/q` on the plane `z = 0` induces in that plane the
//! normalwash angle (the upward flow component over `V`, the `α_e` of [`super`]):
//!
//! `α_e(x, y) = -(1/4π) ⨎∬_τ ΔC_p(ξ, η) (x - ξ) / ((y - η)² R) dξ dη`,
//! `R = sqrt((x - ξ)² - β² (y - η)²)`,
//!
//! over the part `τ` of the planform inside the forward Mach cone of `(x, y)`
//! (`x - ξ > β |y - η|`), `⨎` Hadamard's finite part in `η`. This is the supersonic
//! lifting-surface equation in its acceleration-potential (pressure-doublet) form (Heaslet &
//! Lomax, "Supersonic and transonic small perturbation theory", in *General Theory of High
//! Speed Aerodynamics*, Princeton 1954, sec. D; Ashley & Landahl, *Aerodynamics of Wings and
//! Bodies*, 1965, ch. 8; it is the `k -> 0` limit of the harmonic kernel that the supersonic
//! doublet-lattice method ZONA51 discretises, Chen & Liu, AIAA J. 23(10), 1985). The sign and
//! the factor `1/4π` are fixed here by the two-dimensional limit, derived next, which must be
//! Ackeret's `ΔC_p = 4 α / β`.
//!
//! *2-D check (derivation).* A uniform `ΔC_p = C` from `ξ_0` to `x` on an infinite span: the
//! `ξ` integral gives `sqrt(X² - β² t²)` (`X = x - ξ_0`, `t = y - η`, `|t| < X/β`); with
//! `t = (X/β) sin θ` the `t` integrand becomes `β (1/sin²θ - 1) dθ` whose finite part over
//! `(-π/2, π/2)` is `β (0 - π)`. So `α_e = -(C/4π)(-π β) = C β / 4`, i.e. `C = 4 α_e / β`. ✓
//!
//! # Constant-pressure panels (derivation of the closed form)
//!
//! Each panel `r` carries a uniform `ΔC_p,r` (the discretisation of Woodward's supersonic
//! panel method, F. A. Woodward, NASA CR-2228, 1973, and of the steady part of ZONA51). A
//! panel is the strip `y_0 <= η <= y_1` between two straight edges `ξ = e_0 + e_1 η` (its
//! leading and trailing edges on lines of constant chord fraction). The `ξ` integral of the
//! kernel is exact, `∫ (x - ξ)/R dξ = -R`, so a panel contributes
//!
//! `α_e = -(ΔC_p / 4π) [G(leading edge) - G(trailing edge)]`,
//! `G(edge) = ⨎ ∫ S(t)/t² dt`, `S(t) = sqrt(Q(t))` where the edge point `(ξ_e(η), η)` is
//! inside the forward Mach cone, 0 elsewhere,
//!
//! with `t = y - η`, `X(t) = X_0 + e_1 t` the streamwise distance from the edge to the point
//! (`X_0 = x - e_0 - e_1 y`) and `Q = X² - β² t² = a + b t + c t²`, `a = X_0²`,
//! `b = 2 e_1 X_0`, `c = e_1² - β²` (discriminant `b² - 4ac = 4 β² X_0²`). The set where the
//! edge is in the cone, `X(t) > β |t|`, is one interval (`X(t) - β|t|` is concave); it is
//! intersected with the strip `[y - y_1, y - y_0]`. The primitive (Gradshteyn & Ryzhik
//! 2.267.1, 2.266 and 2.261 for `∫ sqrt(Q)/t²`, `∫ dt/(t sqrt Q)` with `a > 0`, `∫ dt/sqrt Q`):
//!
//! `F(t) = -sqrt(Q)/t + (b/2) J_1(t) + c J_2(t)`,
//! `J_1 = -(1/|X_0|) ln|(2a + b t + 2 |X_0| sqrt Q)/t|`,
//! `c J_2 = sqrt(-c) asin((2ct + b)/(2 β |X_0|))` for `c < 0` (a supersonic edge,
//! `|e_1| < β`), `sqrt(c) ln|2 sqrt(c Q) + 2ct + b|` for `c > 0` (subsonic edge), 0 for a sonic
//! edge. `F` has exactly the singular terms `-sqrt(a)/t` and `ln|t|` at `t = 0`, so the Hadamard
//! finite part over an interval containing 0 is `F(t_hi) - F(t_lo)` (the finite part drops the
//! pole, the principal value the logarithm). The normalwash of a panel is therefore finite
//! everywhere off its side edges, including on the Mach lines from its corners (where
//! `Q = 0`); the kernel of a supersonic horseshoe vortex is not (its downwash is infinite on
//! its Mach cone), which is why pressure panels are used here. When `X_0 = 0` (the point on
//! the edge's line; then the edge is in the cone only for `c > 0`, away from `t = 0`)
//! `S/t² = sqrt(c)/|t|` and `F = sqrt(c) sign(t) ln|t|`.
//!
//! # Collocation, reflection plane, loads
//!
//! The normalwash is imposed at one point per panel, at mid-strip and at the fraction
//! [`COLLOCATION_FRACTION`] of the panel's chord: 0.95, as the supersonic constant-pressure
//! box methods place it (the box's own upstream region is then almost all in the point's
//! Mach cone; the choice is tested by the convergence of the lift slope, see the tests). The
//! root is the reflection plane of [`super`]: each panel's mirror image `η -> -η` carries the
//! same `ΔC_p`. Panel forces `F_p = q A_p ΔC_p,p` act at the panel centroids. With the
//! influence matrix `D` (`α_e = D ΔC_p`):
//!
//! `F = q K α_e`, `K = diag(A) D⁻¹`,
//!
//! the same linear map as the other panel models. In two dimensions (`|t|` range inside the
//! strip) the influence of a panel on any point downstream of it vanishes and on its own
//! point is `β/4`: Ackeret exactly, on any lattice.

use faer::Mat;
use faer::linalg::solvers::DenseSolveCore;

use super::{Lattice, PanelError};

/// Chordwise position of the collocation point within its panel (module doc).
pub const COLLOCATION_FRACTION: f64 = 0.95;

/// `β = sqrt(M² - 1)` for `M > 1`.
pub fn beta(mach: f64) -> Result<f64, PanelError> {
    if !(mach.is_finite() && mach > 1.0) {
        return Err(PanelError::BadMach(mach));
    }
    Ok((mach * mach - 1.0).sqrt())
}

/// The `u >= 0` where `x0 > k u` (a half-line, an interval from 0, or empty).
fn half(x0: f64, k: f64) -> Option<(f64, f64)> {
    if k > 0.0 {
        (x0 > 0.0).then(|| (0.0, x0 / k))
    } else if x0 > 0.0 {
        Some((0.0, f64::INFINITY))
    } else if k < 0.0 {
        Some((x0 / k, f64::INFINITY))
    } else {
        None
    }
}

/// Primitive `F(t)` of `sqrt(Q)/t²` (module doc), `t != 0`.
fn primitive(x0: f64, e1: f64, beta: f64, t: f64) -> f64 {
    let c = e1 * e1 - beta * beta;
    let xt = x0 + e1 * t;
    let q = (xt * xt - beta * beta * t * t).max(0.0);
    let sq = q.sqrt();
    let ax = x0.abs();
    if ax <= 1e-12 * t.abs() {
        // X_0 = 0: S/t² = sqrt(c)/|t| (only c > 0 reaches here with a non-empty interval).
        return c.max(0.0).sqrt() * t.signum() * t.abs().ln();
    }
    let a = x0 * x0;
    let b = 2.0 * e1 * x0;
    let j1 = -((2.0 * a + b * t + 2.0 * ax * sq) / t).abs().ln() / ax;
    let cj2 = if c < 0.0 {
        // asin((2ct + b) / (2 β |X_0|)) written as an arctangent: with Q = a + b t + c t²
        // and b² - 4ac = 4 β² X_0², (2ct + b)² = 4cQ + 4β²X_0², so the cosine of that angle
        // is sqrt(-cQ) / (β |X_0|) and asin(z) = atan2(2ct + b, 2 sqrt(-cQ)). The asin form
        // loses half the digits where its argument is near ±1 (the edge of the Mach cone,
        // Q -> 0: 3e-9 relative on a 2-D strip); this one is exact there.
        (-c).sqrt() * (2.0 * c * t + b).atan2(2.0 * (-c * q).sqrt())
    } else if c > 0.0 {
        c.sqrt() * (2.0 * (c * q).sqrt() + 2.0 * c * t + b).abs().ln()
    } else {
        0.0
    };
    -sq / t + 0.5 * b * j1 + cj2
}

/// `G = ⨎ ∫ S(t)/t² dt` of one edge `ξ = e0 + e1 η` over the strip `y0 <= η <= y1`, at the
/// point `(x, y)` (module doc).
fn edge_integral(x: f64, y: f64, e0: f64, e1: f64, y0: f64, y1: f64, beta: f64) -> f64 {
    let x0 = x - e0 - e1 * y;
    // The interval of t where the edge is inside the forward Mach cone.
    let right = half(x0, beta - e1);
    let left = half(x0, beta + e1).map(|(lo, hi)| (-hi, -lo));
    let (lo, hi) = match (left, right) {
        (Some(l), Some(r)) => (l.0.min(r.0), l.1.max(r.1)),
        (Some(l), None) => l,
        (None, Some(r)) => r,
        (None, None) => return 0.0,
    };
    let (lo, hi) = (lo.max(y - y1), hi.min(y - y0));
    if hi <= lo {
        return 0.0;
    }
    primitive(x0, e1, beta, hi) - primitive(x0, e1, beta, lo)
}

/// Edges of a panel as (e0, e1) of `ξ = e0 + e1 η` (leading, trailing) and its strip.
fn panel_edges(c: &[[f64; 2]; 4]) -> ([f64; 2], [f64; 2], f64, f64) {
    // Corners: leading-inner, leading-outer, trailing-outer, trailing-inner.
    let (y0, y1) = (c[0][1], c[1][1]);
    let line = |p: [f64; 2], q: [f64; 2]| {
        let e1 = (q[0] - p[0]) / (q[1] - p[1]);
        [p[0] - e1 * p[1], e1]
    };
    (line(c[0], c[1]), line(c[3], c[2]), y0, y1)
}

/// The collocation point of a panel: mid-strip, at [`COLLOCATION_FRACTION`] of its chord.
pub fn collocation_point(corners: &[[f64; 2]; 4]) -> [f64; 2] {
    let ym = 0.5 * (corners[0][1] + corners[1][1]);
    let le = 0.5 * (corners[0][0] + corners[1][0]);
    let te = 0.5 * (corners[3][0] + corners[2][0]);
    [le + COLLOCATION_FRACTION * (te - le), ym]
}

/// Normalwash angle at `(x, y)` per unit `ΔC_p` on the panel with `corners` and on its wall
/// image.
pub fn panel_normalwash(p: [f64; 2], corners: &[[f64; 2]; 4], beta: f64) -> f64 {
    let (le, te, y0, y1) = panel_edges(corners);
    let g = |e: [f64; 2]| {
        edge_integral(p[0], p[1], e[0], e[1], y0, y1, beta)
            // Image: ξ = e0 - e1 η on -y1 <= η <= -y0.
            + edge_integral(p[0], p[1], e[0], -e[1], -y1, -y0, beta)
    };
    -(g(le) - g(te)) / (4.0 * std::f64::consts::PI)
}

/// The influence matrix `D` (row-major, `n x n`): `α_e,p = Σ_r D[p][r] ΔC_p,r`, `α_e` at the
/// collocation points.
pub fn influence_matrix(lattice: &Lattice, mach: f64) -> Result<Vec<f64>, PanelError> {
    let b = beta(mach)?;
    let n = lattice.len();
    let points: Vec<[f64; 2]> = lattice
        .panels
        .iter()
        .map(|p| collocation_point(&p.corners))
        .collect();
    let mut d = vec![0.0; n * n];
    for (r, pr) in lattice.panels.iter().enumerate() {
        for (p, x) in points.iter().enumerate() {
            d[p * n + r] = panel_normalwash(*x, &pr.corners, b);
        }
    }
    Ok(d)
}

/// The steady supersonic force map `K` (row-major `n x n`, m²): panel normal forces
/// `F_p = q Σ_r K[p][r] α_e,r` (N), `α_e` at the collocation points, forces at the panel
/// centroids. See the module doc.
pub fn force_map(lattice: &Lattice, mach: f64) -> Result<Vec<f64>, PanelError> {
    let n = lattice.len();
    let d = influence_matrix(lattice, mach)?;
    let m = Mat::<f64>::from_fn(n, n, |i, j| d[i * n + j]);
    let inv = m.partial_piv_lu().inverse();
    let mut k = vec![0.0; n * n];
    for p in 0..n {
        let a = lattice.panels[p].area;
        for r in 0..n {
            k[p * n + r] = a * inv[(p, r)];
        }
    }
    if k.iter().any(|v| !v.is_finite()) {
        return Err(PanelError::Singular(mach));
    }
    Ok(k)
}

/// Normal-force slope of the fin per radian on its own area `A_f` and the centre of pressure
/// (m aft of the root leading edge) for a uniform incidence, steady, at Mach `mach > 1`.
pub fn slope_and_centre(lattice: &Lattice, mach: f64) -> Result<(f64, f64), PanelError> {
    let n = lattice.len();
    let d = influence_matrix(lattice, mach)?;
    let m = Mat::<f64>::from_fn(n, n, |i, j| d[i * n + j]);
    let rhs = Mat::<f64>::from_fn(n, 1, |_, _| 1.0);
    use faer::linalg::solvers::Solve;
    let cp = m.partial_piv_lu().solve(rhs);
    let (mut force, mut moment) = (0.0, 0.0);
    for (p, panel) in lattice.panels.iter().enumerate() {
        let f = cp[(p, 0)] * panel.area;
        force += f;
        moment += f * panel.centroid[0];
    }
    let slope = force / lattice.planform.area();
    if !(slope.is_finite() && moment.is_finite()) || force == 0.0 {
        return Err(PanelError::Singular(mach));
    }
    Ok((slope, moment / force))
}
