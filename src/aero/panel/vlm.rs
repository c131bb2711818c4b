//! Subsonic lifting surface: horseshoe vortex lattice with Prandtl-Glauert compressibility.
//!
//! # Method (Katz & Plotkin, *Low-Speed Aerodynamics*, 2nd ed., 12.2-12.3; Bertin & Cummings,
//! *Aerodynamics for Engineers*, 7.x "vortex lattice method")
//!
//! Every panel carries a horseshoe vortex of strength `Γ_p`: a bound segment on the panel's
//! quarter-chord line (inner edge `A` to outer edge `B`, direction `+y`) and two trailing legs
//! parallel to the free stream (`+x`) to infinity; the flow-tangency condition is imposed at
//! the panel's three-quarter-chord point at mid-strip. (A horseshoe lattice with legs to
//! infinity is exactly a vortex-ring lattice with a steady flat wake: ring `i` of a strip carries
//! `Σ_{k<=i} Γ_k`.) The velocity of a straight segment `P1 -> P2` of unit strength at `P` is
//! the Biot-Savart law in the form of K&P eq. (2.68)/(10.115):
//!
//! `q = (1/4π) (r1 × r2)/|r1 × r2|² [r0 · (r1/|r1| - r2/|r2|)]`, `r0 = P2 - P1`, `r1 = P - P1`,
//! `r2 = P - P2`,
//!
//! and of a semi-infinite leg from `P1` along the unit vector `e` its limit `P2 = P1 + L e`,
//! `L -> ∞` (derived: `r1 × r2 -> L e × r1`, `r0 · (...) -> L (e·r1/|r1| + 1)`):
//!
//! `q = (1/4π) (e × r1)/|e × r1|² (1 + e · r1/|r1|)`.
//!
//! The horseshoe is `-leg(A) + seg(A, B) + leg(B)` (the first leg comes from downstream into
//! `A`). The wall at the root (see the module doc of [`super`]) adds the mirrored horseshoe
//! with bound segment from `B' = (x_B, -y_B)` to `A' = (x_A, -y_A)` (again `+y`, same `Γ`).
//! All points lie in `z = 0`, so only the `z` component `a_pq` (the influence coefficient) is
//! non-zero; a point on a segment's line (closer than 1e-10 of the segment scale) gets no
//! velocity from it, the usual cut-off.
//!
//! Flow tangency at control point `p`: `Σ_q a_pq Γ_q + V α_e,p = 0` (K&P (12.5)).
//!
//! Loads: Kutta-Joukowski on each bound segment, `F = ρ V × Γ l` with `l = B - A`: its `z`
//! component is `ρ V Γ (y_B - y_A)` whatever the sweep (`x̂ × (l_x, l_y, 0) = (0, 0, l_y)`),
//! acting at the bound mid-point. So `F_p = ρ V Γ_p w_p`, `w_p` the strip width, and
//!
//! `F = q K α_e`, `K = -2 diag(w) A⁻¹`.
//!
//! # Compressibility: Göthert's rule (Prandtl-Glauert)
//!
//! The linearised potential equation `β² φ_xx + φ_yy + φ_zz = 0`, `β = sqrt(1 - M²)`,
//! becomes Laplace's equation in `x' = x / β` (Göthert; Katz & Plotkin 12.x / Bertin &
//! Cummings 9.x "Göthert's rule"). The tangency condition `φ_z = V α_e` keeps its value at the
//! mapped points, and the pressure `C_p = -2 φ_x / V = -2 φ'_x' / (β V) = C_p' / β`. So the
//! compressible problem is the incompressible one on the planform stretched by `1/β` in `x`,
//! with the SAME normalwash, and its loads divided by `β`. Since the stretched panel chords
//! are the physical ones over `β`, `Δp = ρ V Γ'/(β Δx') = ρ V Γ'/Δx`: the Kutta-Joukowski
//! force with the physical strip width and the stretched-lattice circulation is already the
//! compressible load (no explicit `1/β`). The influence matrix is therefore built on the
//! stretched geometry (bound points, control points and legs along `x'`). For a flat
//! trapezoid this reproduces the Prandtl-Glauert scaling of the lift slope,
//! `C_Lα(M; A, Λ) = C_Lα(0; β A, atan(tan Λ / β)) / β`, which is how the Diederich/Helmbold
//! formula of DATCOM carries Mach.
//!
//! # Quasi-steady motion
//!
//! `α_e` contains the rates (`-ż/V`), so the same `K` gives the quasi-steady damping. This is
//! the circulatory quasi-steady theory (instantaneous normalwash, steady wake; Theodorsen's
//! `C(k) = 1`); the apparent-mass (non-circulatory, `ρ ∂Δφ/∂t`) pressures are NOT included.
//! In the two-dimensional limit it gives thin-airfoil theory applied to the instantaneous
//! normalwash: lift `2π q c ᾱ` with `ᾱ` the normalwash angle at three-quarter chord and a
//! moment about the quarter chord `-(π/8) q c³ θ̇ / V` from a pitch rate (tested).

use faer::Mat;
use faer::linalg::solvers::DenseSolveCore;
use faer::linalg::solvers::Solve;

use super::{Lattice, PanelError};

const FOUR_PI: f64 = 4.0 * std::f64::consts::PI;

/// `z` velocity at `p` of a unit-strength straight segment `p1 -> p2` (all in `z = 0`; see the
/// module doc). Zero when `p` is on the segment's line.
pub(super) fn segment_w(p: [f64; 2], p1: [f64; 2], p2: [f64; 2], cutoff: f64) -> f64 {
    let r1 = [p[0] - p1[0], p[1] - p1[1]];
    let r2 = [p[0] - p2[0], p[1] - p2[1]];
    let r0 = [p2[0] - p1[0], p2[1] - p1[1]];
    // r1 × r2 has only a z component for vectors in the plane.
    let cz = r1[0] * r2[1] - r1[1] * r2[0];
    let n1 = r1[0].hypot(r1[1]);
    let n2 = r2[0].hypot(r2[1]);
    let scale = r0[0].hypot(r0[1]);
    if cz.abs() <= cutoff * scale * scale || n1 == 0.0 || n2 == 0.0 {
        return 0.0;
    }
    let dot = r0[0] * (r1[0] / n1 - r2[0] / n2) + r0[1] * (r1[1] / n1 - r2[1] / n2);
    cz / (cz * cz) * dot / FOUR_PI
}

/// `z` velocity at `p` of a unit-strength semi-infinite leg from `p1` along `+x`.
pub(super) fn leg_w(p: [f64; 2], p1: [f64; 2], cutoff: f64, scale: f64) -> f64 {
    let r1 = [p[0] - p1[0], p[1] - p1[1]];
    // e × r1 with e = x̂: z component r1_y.
    let cz = r1[1];
    if cz.abs() <= cutoff * scale {
        return 0.0;
    }
    let n1 = r1[0].hypot(r1[1]);
    (1.0 + r1[0] / n1) / cz / FOUR_PI
}

/// `z` velocity at `p` of a unit horseshoe with bound segment `a -> b` (legs along `+x`).
pub(super) fn horseshoe_w(p: [f64; 2], a: [f64; 2], b: [f64; 2], cutoff: f64) -> f64 {
    let scale = (b[0] - a[0]).hypot(b[1] - a[1]);
    -leg_w(p, a, cutoff, scale) + segment_w(p, a, b, cutoff) + leg_w(p, b, cutoff, scale)
}

/// Prandtl-Glauert factor `β = sqrt(1 - M²)` for `0 <= M < 1`.
pub fn beta(mach: f64) -> Result<f64, PanelError> {
    if !(mach.is_finite() && (0.0..1.0).contains(&mach)) {
        return Err(PanelError::BadMach(mach));
    }
    Ok((1.0 - mach * mach).sqrt())
}

/// The aerodynamic influence matrix `A` (row-major, `n x n`, 1/m) at Mach `mach`: `A[p][q]`
/// is the normal velocity at control point `p` per unit circulation of horseshoe `q` and its
/// wall image, on the Göthert-stretched lattice.
pub fn influence_matrix(lattice: &Lattice, mach: f64) -> Result<Vec<f64>, PanelError> {
    let b = beta(mach)?;
    let n = lattice.len();
    let stretch = |p: [f64; 2]| [p[0] / b, p[1]];
    const CUTOFF: f64 = 1e-10;
    let mut a = vec![0.0; n * n];
    for (q, pq) in lattice.panels.iter().enumerate() {
        let (ba, bb) = (stretch(pq.bound[0]), stretch(pq.bound[1]));
        let (ia, ib) = ([bb[0], -bb[1]], [ba[0], -ba[1]]);
        for (p, pp) in lattice.panels.iter().enumerate() {
            let c = stretch(pp.control);
            a[p * n + q] = horseshoe_w(c, ba, bb, CUTOFF) + horseshoe_w(c, ia, ib, CUTOFF);
        }
    }
    Ok(a)
}

/// The subsonic force map `K` (row-major `n x n`, m²) at Mach `mach`: panel normal forces
/// `F_p = q Σ_r K[p][r] α_e,r` (N), `α_e` at the control points, forces at the bound
/// mid-points. See the module doc.
pub fn force_map(lattice: &Lattice, mach: f64) -> Result<Vec<f64>, PanelError> {
    let n = lattice.len();
    let a = influence_matrix(lattice, mach)?;
    let m = Mat::<f64>::from_fn(n, n, |i, j| a[i * n + j]);
    let inv = m.partial_piv_lu().inverse();
    let mut k = vec![0.0; n * n];
    for p in 0..n {
        let w = lattice.panels[p].width;
        for r in 0..n {
            k[p * n + r] = -2.0 * w * inv[(p, r)];
        }
    }
    if k.iter().any(|v| !v.is_finite()) {
        return Err(PanelError::Singular(mach));
    }
    Ok(k)
}

/// Circulations `Γ` (m²/s) for normalwash angles `alpha_e` at the control points and airspeed
/// `v`: the solution of `A Γ = -V α_e`.
pub fn circulation(
    lattice: &Lattice,
    mach: f64,
    v: f64,
    alpha_e: &[f64],
) -> Result<Vec<f64>, PanelError> {
    let n = lattice.len();
    let a = influence_matrix(lattice, mach)?;
    let m = Mat::<f64>::from_fn(n, n, |i, j| a[i * n + j]);
    let mut rhs = Mat::<f64>::from_fn(n, 1, |i, _| -v * alpha_e[i]);
    m.partial_piv_lu().solve_in_place(rhs.as_mut());
    let g: Vec<f64> = (0..n).map(|i| rhs[(i, 0)]).collect();
    if g.iter().any(|v| !v.is_finite()) {
        return Err(PanelError::Singular(mach));
    }
    Ok(g)
}
