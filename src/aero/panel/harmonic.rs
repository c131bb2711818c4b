//! Unsteady (harmonic) panel aerodynamics on the fin lattice of [`super`] (issue 13,
//! deliverable 1): a frequency-domain vortex-ring lattice with a convected harmonic wake
//! subsonic ([`vlm_map`], [`HarmonicVlm`]) and unsteady first-order piston theory supersonic
//! ([`piston_map`]), both as ONE complex linear map per Mach and reduced frequency: panel forces
//! from the normalwash angles, `F = q K(ν) α_e`.
//!
//! # Harmonic motion
//!
//! The surface moves as `z(x, y) e^{iωt}` (complex amplitude, fin coordinates of [`super`]);
//! every quantity below is the complex amplitude of an `e^{iωt}` oscillation. The normalwash
//! angle of [`super`] becomes `α_e = -∂z/∂x - iν z` (+ the rigid incidence), with the
//! dimensional reduced frequency
//!
//! `ν = ω / V` (1/m), so that the usual `k = ω b / V = ν b` for a semichord `b`.
//!
//! # Vortex rings on the lattice (Katz & Plotkin, *Low-Speed Aerodynamics*, 2nd ed., 12.3
//! "vortex ring elements", and 13.12 "unsteady motion of a thin lifting surface")
//!
//! Ring `i` of strip `j` (panel `p = j n_c + i`) has its leading segment on panel `i`'s
//! quarter-chord line (the bound vortex of [`super::Panel`]), its trailing segment on panel
//! `i + 1`'s, and the side segments on the strip edges `y = y_j`, `y = y_{j+1}`; the last
//! ring's trailing segment lies a quarter of the local panel chord behind the trailing edge
//! (K&P 12.3 and 13.12). The flow-tangency condition is imposed at the panel's
//! three-quarter-chord control point, as in [`super::vlm`]. Ring strengths `G_p` are the jump of
//! the perturbation potential `Δφ = φ_upper - φ_lower` over the ring (K&P 13.12: a vortex ring is
//! a constant-strength doublet panel); the bound vortex of panel `i` carries `G_i - G_{i-1}`.
//! Every ring is the closed polygon `LI -> LO -> TO -> TI -> LI` (leading-inner, leading-outer,
//! trailing-outer, trailing-inner) of straight segments, each of the Biot-Savart law of
//! [`super::vlm`] (K&P eq. (2.68)), with its wall image at `y = 0` (the polygon mirrored,
//! `LO' -> LI' -> TI' -> TO'`, so that the image bound vortex runs along `+y` with the same
//! strength as in [`super::vlm`]).
//!
//! # The harmonic wake (Kelvin's theorem)
//!
//! The wake carries no load, `Δp = ρ (V ∂/∂x + ∂/∂t) Δφ = 0` (the linearised form of K&P eq.
//! (13.37) below): the potential jump is convected with the free stream, `Δφ(x, t) = Δφ_TE(t -
//! ξ / V)`, `ξ` the distance behind the trailing edge, i.e. for harmonic motion
//!
//! `Γ_w(ξ) = Γ_TE e^{-iνξ}` (K&P 13.12: the latest wake ring takes the trailing-edge ring's
//! strength of the previous time step, `Γ_W(t) = Γ_TE(t - Δt)`, here in the limit of small
//! steps; Kelvin's theorem, K&P ch. 2: the shed spanwise vorticity `∂Γ_w/∂ξ` (along `+y`) is
//! what keeps the total circulation constant).
//!
//! Discretisation (derived here): behind strip `j` the wake continues the ring lattice with
//! rings of length `Δξ_j = r Δx_j` (`Δx_j` the strip's mid-strip panel chord, `r` =
//! [`WakeSettings::ring`]) whose spanwise segments are parallel to the last bound ring's trailing
//! segment. Ring `m = 0, 1, ...` spans `[m Δξ_j, (m + 1) Δξ_j]` behind that segment and has the
//! strength `G_w,m = G_TE e^{-iν (m + 1) Δξ_j}`, `G_TE` the strength of the strip's last bound
//! ring. With `r = 1` this is the lumped-vortex rule of the lattice carried into the wake: the
//! spanwise segment at the quarter point of the wake interval `[m Δξ, (m + 1) Δξ]` behind the
//! trailing edge then carries `G_w,m - G_w,m-1 = ∫ ∂Γ_w/∂ξ dξ` over that interval EXACTLY
//! (the potential jump at the interval ends), as the bound segments carry the bound vorticity
//! of their panels. The ringed wake ends after `N_j = ceil(L / Δξ_j)` rings, `L` =
//! [`WakeSettings::length`] times the root chord `c_r`, and is closed by a semi-infinite
//! horseshoe (legs along `+x` on the strip edges) of the last ring's strength: its bound segment cancels the
//! last ring's trailing segment, so the shed vorticity beyond `L` is dropped while the trailing
//! legs continue with constant strength. At `ν = 0` all wake rings carry `G_TE` and the wake is
//! exactly the pair of semi-infinite legs of [`super::vlm`]'s horseshoes: the model is then the
//! steady horseshoe lattice (ring `i` = `Σ_{k<=i} Γ_k`; tested to round-off).
//!
//! Truncation error (derived, two-dimensional worst case): the dropped shed sheet
//! `γ = -iνΓ_TE e^{-iνξ}` beyond `L` induces at the wing `(νΓ_TE/2π) |E_1(iνL)| ≈ Γ_TE / (2π
//! L)` in magnitude for `νL >> 1` (and vanishes as `ν ln ν` for `νL << 1`); against the bound vortex'
//! own normalwash `~ Γ / (π c)` this is a relative error `~ c / (2L)` on a wing of large aspect
//! ratio. On a low-aspect-ratio fin the trailing legs of neighbouring strips cancel and the far
//! shed segments (span `s`) induce only `~ Γ s / (4π L²)`, a relative error `~ c s / (4L²)`.
//! [`wake_truncation_estimate`] is the smaller of the two; [`check_resolution`] bounds it
//! (below). In the 2-D test the 200-chord wake (estimate 0.25 %) leaves 0.1-0.2 % at k = 0.05
//! after the lattice error is extrapolated away; on SPHADS-1's fin the measured change is 10x
//! below the estimate.
//!
//! # Flow tangency
//!
//! `Σ_q A_pq(ν) G_q + V α_e,p = 0` (K&P 13.12, the zero-normal-flow condition with the wake's
//! induced velocity on the right-hand side there, on the left here), `A(ν) = B + W(ν)`: `B` the (real)
//! influence of the bound rings and their images at the control points, and `W(ν)`, which
//! acts only on the columns of the strips' trailing-edge rings, `W_p,TE_j = Σ_m w_p,jm
//! e^{-iν(m + 1)Δξ_j}` (`w_p,jm` the real influence of wake ring `m` of strip `j`, the closing
//! horseshoe added to the last one). The geometry (`B` and `w`) does not depend on `ν`:
//! [`HarmonicVlm`] builds it once per Mach and [`HarmonicVlm::map`] only sums the phases,
//! inverts the complex `n x n` system and forms the loads ([`HarmonicVlm::forces`] solves it for
//! a few normalwash columns instead). Measured on SPHADS-1's fin, 8 x 12 panels, 1755 wake
//! rings, test profile on a loaded 2-core machine: geometry 53-57 ms per Mach, `map` 2.5-2.8 ms
//! and `forces` (11 columns) 1.4 ms per reduced frequency (docs/performance.md).
//!
//! # Loads: unsteady Bernoulli (K&P eq. (13.37), linearised)
//!
//! `Δp = p_lower - p_upper = ρ (V ∂Δφ/∂x + ∂Δφ/∂t)` (force along `+z`).
//!
//! K&P eq. (13.37) splits the panel force `ΔF = ρ [V (Γ_i - Γ_{i-1})/Δc + ∂Γ_i/∂t] ΔS` into
//! the two parts kept here, each where it acts:
//!
//! * the Kutta-Joukowski part on the bound segments, `ρ V (G_i - G_{i-1}) w_p` at the bound
//!   mid-point (the steady force of [`super::vlm`]);
//! * the `ρ ∂Δφ/∂t = ρ iω G_i` part on the ring's area ON THE WING, `ρ iω G_i A_i`, at that
//!   area's centroid: ring `i` covers the wing between bound lines `i` and `i + 1` (the last
//!   ring up to the trailing edge: behind it the wake carries no load). With the lumped
//!   (step) potential jump of the lattice this is the exact integral of `ρ iω Δφ` over the
//!   wing (the strip between the leading edge and the first bound vortex has `Δφ = 0`).
//!
//! With `G = V g` and `q = ρV²/2`: `F_KJ,p = q 2 w_p (g_i - g_{i-1})`, `F_t,p = q 2 iν A_i g_i`,
//! `A(ν) g = -α_e`, so `K = -D A(ν)⁻¹` with the `2n x n` load operator `D`. The map has `2n`
//! force points: rows `0..n` the Kutta-Joukowski forces at the bound mid-points, rows `n..2n`
//! the `∂Δφ/∂t` forces at the ring-area centroids (panel order both). At `ν = 0` the second
//! block is zero and the first is [`super::vlm::force_map`].
//!
//! In the two-dimensional limit this contains both parts of Theodorsen's airloads: the
//! circulatory lift with `C(k)` (from the wake) and the non-circulatory (apparent-mass) terms
//! (from `ρ ∂Δφ/∂t`, and from the `iν z` part of the normalwash); tested against Theodorsen.
//!
//! # Compressibility (a stated approximation)
//!
//! Göthert's stretch of [`super::vlm`]: the influence coefficients are those of the lattice and
//! wake stretched by `1/β` in `x`, the potential jumps `G` keep their values, the loads use the
//! physical strip widths and ring areas, and the wake phase is in PHYSICAL `x` (`Δξ_j` physical;
//! the convection at `V` is exact in linear compressible theory too). This is exact for steady
//! flow and wrong at order `k M²/β²` in unsteady flow: the linearised equation for `φ e^{iωt}`
//! is
//!
//! `β² φ_xx + φ_yy + φ_zz - 2iνM² φ_x + ν²M² φ = 0`
//!
//! (from `(∂_t + V∂_x)² φ / a² = ∇² φ`, derived), and after the stretch `x' = x/β` the two
//! last terms, which the Laplace kernel drops, are of relative size `2νM² c/β² = 4kM²/β²` and
//! `4k²M²/β²` (chord `c = 2b`) against the retained ones: the acoustic delay of the
//! compressible unsteady kernel. The doublet-lattice method (Albano & Rodden, AIAA J. 7(2),
//! 1969) integrates that kernel and is the exact-linear alternative: [`super::dlm`], on the
//! same lattice and with the same map type (`n` force points instead of `2n`). At `M = 0.5`,
//! `k = 0.1` the neglected term is `0.13` of the retained ones; at `M = 0.8`, `k = 0.5`,
//! `3.6`: use this model at low Mach or low `k` only. Measured against the DLM (test
//! `dlm_tests::compressible_departure_from_gothert`, 8 x 10 boxes on a swept trapezoid,
//! uniform `α_e`): the total lift differs by 1.4 % at `M = 0`, `k = 0.3` (the two
//! discretisations), and at `M = 0.5` by 0.45 % at `k = 0.02` and 5.1 % at `k = 0.3`, mostly
//! in the lag (imaginary) part, which Göthert's stretch over-predicts (0.374 against the DLM's
//! 0.253). On AGARD 445.6 this is the flutter frequency's Mach trend (docs/validation.md).
//!
//! # Resolution
//!
//! [`check_resolution`] applies the box-size rule of the MSC Nastran *Aeroelastic Analysis
//! User's Guide* (Rodden & Johnson, 1994, "aerodynamic modeling" guidelines for the
//! doublet-lattice method): the box chord `Δx < 0.08 V / f` for the highest frequency `f` (Hz)
//! of interest, i.e. `Δx < 0.08 · 2π / ν` (about 12.5 boxes per wavelength of the convected
//! wake). The `search` tool did not return the guide's text; the rule is quoted from the guide
//! as widely reproduced. The same limit applies to the wake rings (they carry the wake's
//! phase), and the ringed wake must be long enough that its [`wake_truncation_estimate`]
//! (above) is at most [`WAKE_ERROR`] = 1 %: `L >= min(c_r / (2 · 0.01), sqrt(c_r s / (4 ·
//! 0.01)))`, 3.1 root chords for SPHADS-1's fin, 50 chords for a wing of very large aspect
//! ratio. On SPHADS-1's fin (8 x 12 panels, M = 0.5, k = 0.05 .. 1) the total lift moves by
//! 1.8e-4 .. 4.5e-4 between a 5 and an 80 root-chord wake, 0.7e-4 .. 1.2e-4 at the default 10
//! (the estimates: 3.9e-3 and 9.8e-4), and falls close to `1/L²` (tested).
//!
//! # Supersonic: unsteady piston theory (Ashley & Zartarian 1956)
//!
//! First-order piston theory is local in space and time: `Δp = 2 ρ a w`, `w = V ∂z/∂x + ∂z/∂t`
//! (Ashley & Zartarian, J. Aeronaut. Sci. 23(12), 1956, the first-order term of their piston
//! pressure; [`super::piston`]); for harmonic motion `w = -V α_e` with the complex `α_e` above, so the unsteady map
//! is the quasi-steady one of [`super::piston::force_map`] applied to the complex normalwash,
//! independent of `ν` (with the same optional Ackeret factor).

use faer::linalg::solvers::{DenseSolveCore, Solve};
use faer::{Mat, c64};

use super::piston::{self, Correction};
use super::vlm::{self, leg_w, segment_w};
use super::{Lattice, PanelError, SUBSONIC_LIMIT, SUPERSONIC_LIMIT, polygon_centroid};

/// Cut-off of the Biot-Savart law for points on a segment's line, as [`super::vlm`].
const CUTOFF: f64 = 1e-10;

/// The MSC Nastran box-size rule: box chord `< BOX_RULE · V / f` (module doc).
pub const BOX_RULE: f64 = 0.08;

/// The largest estimated wake-truncation error [`check_resolution`] accepts (module doc,
/// [`wake_truncation_estimate`]).
pub const WAKE_ERROR: f64 = 0.01;

/// The estimated relative error of truncating the ringed wake at `length` (m) behind a fin of
/// root chord `c_r` and span `s` (module doc, "truncation error"): `min(c_r / (2L), c_r s /
/// (4L²))`, the two-dimensional and the low-aspect-ratio bound.
pub fn wake_truncation_estimate(root_chord: f64, span: f64, length: f64) -> f64 {
    (root_chord / (2.0 * length)).min(root_chord * span / (4.0 * length * length))
}

/// The shortest ringed wake (m) whose [`wake_truncation_estimate`] is [`WAKE_ERROR`].
pub fn min_wake_length(root_chord: f64, span: f64) -> f64 {
    (root_chord / (2.0 * WAKE_ERROR)).min((root_chord * span / (4.0 * WAKE_ERROR)).sqrt())
}

/// The discretised harmonic wake (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WakeSettings {
    /// Length of the ringed wake behind the trailing edge, in root chords; beyond it a
    /// semi-infinite horseshoe closes the wake.
    pub length: f64,
    /// Length of a wake ring as a fraction of the strip's mid-strip panel chord.
    pub ring: f64,
}

impl Default for WakeSettings {
    /// 10 root chords of rings as long as the panels: on SPHADS-1's fin the lift is within
    /// 1.2e-4 of an 80-chord wake; it also passes [`min_wake_length`] for the Goland wing (9.1
    /// chords) and AGARD 445.6 (5.8 root chords), not for rectangular wings of aspect ratio
    /// `2s/c` above 8.
    fn default() -> Self {
        WakeSettings {
            length: 10.0,
            ring: 1.0,
        }
    }
}

/// A complex force map (module doc). From [`vlm_map`]: `eval` the `n` control points, `force`
/// `2n` points (the `n` bound mid-points for the Kutta-Joukowski forces, then the `n`
/// ring-area centroids for the `ρ ∂Δφ/∂t` forces); from [`piston_map`]: the `n` centroids for
/// both.
#[derive(Clone, Debug, PartialEq)]
pub struct HarmonicMap {
    /// Points where the normalwash alpha_e is imposed (fin coordinates, m).
    pub eval: Vec<[f64; 2]>,
    /// Points where the forces act.
    pub force: Vec<[f64; 2]>,
    /// Complex force map, row-major force.len() x eval.len(): panel force amplitudes
    /// F = q K alpha_e (N per unit q).
    pub k: Vec<c64>,
}

impl HarmonicMap {
    /// The force amplitudes `F / q` for normalwash amplitudes `alpha_e` at [`Self::eval`].
    pub fn apply(&self, alpha_e: &[c64]) -> Vec<c64> {
        let n = self.eval.len();
        (0..self.force.len())
            .map(|f| {
                self.k[f * n..(f + 1) * n]
                    .iter()
                    .zip(alpha_e)
                    .map(|(k, a)| k * a)
                    .sum()
            })
            .collect()
    }
}

/// The `z` velocity at `p` of a unit closed polygon `c[0] -> c[1] -> c[2] -> c[3] -> c[0]`
/// and of its wall image (module doc).
fn ring_w(p: [f64; 2], c: &[[f64; 2]; 4]) -> f64 {
    let m = |q: [f64; 2]| [q[0], -q[1]];
    let img = [m(c[1]), m(c[0]), m(c[3]), m(c[2])];
    let mut w = 0.0;
    for r in [c, &img] {
        for k in 0..4 {
            w += segment_w(p, r[k], r[(k + 1) % 4], CUTOFF);
        }
    }
    w
}

fn shoelace_area(c: &[[f64; 2]; 4]) -> f64 {
    let mut a = 0.0;
    for k in 0..4 {
        let (p, q) = (c[k], c[(k + 1) % 4]);
        a += p[0] * q[1] - q[0] * p[1];
    }
    0.5 * a.abs()
}

/// The subsonic harmonic vortex lattice of one fin at one Mach: the `ν`-independent geometry
/// (bound-ring and wake-ring influence coefficients), from which [`Self::map`] forms the map at
/// any reduced frequency (module doc).
#[derive(Clone, Debug)]
pub struct HarmonicVlm {
    n: usize,
    chordwise: usize,
    spanwise: usize,
    mach: f64,
    /// Bound-ring influence `B` (row-major `n x n`, 1/m).
    bound: Vec<f64>,
    /// Wake-ring influence `w` (row-major `n x n_wake`, 1/m); strip `j`'s rings are the columns
    /// `wake_start[j]..wake_start[j + 1]`.
    wake: Vec<f64>,
    wake_start: Vec<usize>,
    /// Phase distance `(m + 1) Δξ_j` (m, physical) of every wake column.
    wake_xi: Vec<f64>,
    /// Strip widths `w_p` and on-wing ring areas `A_p` (m, m²).
    widths: Vec<f64>,
    ring_areas: Vec<f64>,
    eval: Vec<[f64; 2]>,
    force: Vec<[f64; 2]>,
    /// Resolution data: the largest chordwise panel length, the longest wake ring, the ringed
    /// wake length and the smallest allowed (m).
    max_panel_chord: f64,
    max_wake_ring: f64,
    wake_length: f64,
    min_wake_length: f64,
}

impl HarmonicVlm {
    /// The geometry of `lattice` at Mach `mach` (`0 <= M <= 0.9`) with the wake `wake`.
    pub fn new(
        lattice: &Lattice,
        mach: f64,
        wake: &WakeSettings,
    ) -> Result<HarmonicVlm, PanelError> {
        if !(mach.is_finite() && mach >= 0.0) {
            return Err(PanelError::BadMach(mach));
        }
        if mach > SUBSONIC_LIMIT {
            return Err(PanelError::Untrusted(mach, "harmonic vortex lattice"));
        }
        for (what, value) in [("length", wake.length), ("ring", wake.ring)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(PanelError::BadWake { what, value });
            }
        }
        let b = vlm::beta(mach)?;
        let (nc, ns) = (lattice.chordwise, lattice.spanwise);
        let n = lattice.len();
        let pl = &lattice.planform;
        let reference = pl.root_chord;
        let wake_length = wake.length * reference;
        let st = |p: [f64; 2]| [p[0] / b, p[1]];
        let stq = |c: [[f64; 2]; 4]| [st(c[0]), st(c[1]), st(c[2]), st(c[3])];
        let controls: Vec<[f64; 2]> = lattice.panels.iter().map(|p| st(p.control)).collect();

        // Bound rings (physical corners LI, LO, TO, TI) and their on-wing parts.
        let mut rings = Vec::with_capacity(n);
        let mut ring_areas = Vec::with_capacity(n);
        let mut ring_centroids = Vec::with_capacity(n);
        let mut max_panel_chord: f64 = 0.0;
        for j in 0..ns {
            for i in 0..nc {
                let p = &lattice.panels[j * nc + i];
                for (a, b) in [(0, 3), (1, 2)] {
                    max_panel_chord = max_panel_chord.max(p.corners[b][0] - p.corners[a][0]);
                }
                let (t_in, t_out, wing) = if i + 1 < nc {
                    let q = &lattice.panels[j * nc + i + 1];
                    (q.bound[0], q.bound[1], [q.bound[0], q.bound[1]])
                } else {
                    let l_in = p.corners[3][0] - p.corners[0][0];
                    let l_out = p.corners[2][0] - p.corners[1][0];
                    (
                        [p.corners[3][0] + 0.25 * l_in, p.corners[3][1]],
                        [p.corners[2][0] + 0.25 * l_out, p.corners[2][1]],
                        [p.corners[3], p.corners[2]],
                    )
                };
                rings.push([p.bound[0], p.bound[1], t_out, t_in]);
                let on_wing = [p.bound[0], p.bound[1], wing[1], wing[0]];
                ring_areas.push(shoelace_area(&on_wing));
                ring_centroids.push(polygon_centroid(&on_wing));
            }
        }
        let mut bound = vec![0.0; n * n];
        for (q, r) in rings.iter().enumerate() {
            let r = stq(*r);
            for (p, c) in controls.iter().enumerate() {
                bound[p * n + q] = ring_w(*c, &r);
            }
        }

        // Wake rings behind each strip: (origin inner, origin outer, Δξ, ring count).
        let mut wake_start = vec![0];
        let mut wake_xi = Vec::new();
        let mut strips = Vec::with_capacity(ns);
        let mut max_wake_ring: f64 = 0.0;
        for j in 0..ns {
            let te = &rings[j * nc + nc - 1];
            let p = &lattice.panels[j * nc + nc - 1];
            let l_mid =
                0.5 * ((p.corners[3][0] - p.corners[0][0]) + (p.corners[2][0] - p.corners[1][0]));
            let dxi = wake.ring * l_mid;
            max_wake_ring = max_wake_ring.max(dxi);
            let count = ((wake_length / dxi).ceil() as usize).max(1);
            wake_xi.extend((1..=count).map(|m| m as f64 * dxi));
            wake_start.push(wake_xi.len());
            strips.push((te[3], te[2], dxi, count));
        }
        let nw = wake_xi.len();
        let mut wake_w = vec![0.0; n * nw];
        // Adjacent wake rings share their spanwise segments: ring m is `S_m - S_{m+1}` plus its
        // two sides, `S_k` the segment (and image) on line k, inner to outer; the closing
        // horseshoe's bound segment cancels `-S_N`, leaving its two legs (and images).
        let seg2 = |c: [f64; 2], p1: [f64; 2], p2: [f64; 2]| {
            segment_w(c, p1, p2, CUTOFF) + segment_w(c, [p2[0], -p2[1]], [p1[0], -p1[1]], CUTOFF)
        };
        for (j, &(o_in, o_out, dxi, count)) in strips.iter().enumerate() {
            let at = |o: [f64; 2], m: usize| st([o[0] + m as f64 * dxi, o[1]]);
            for (p, &c) in controls.iter().enumerate() {
                let row = &mut wake_w[p * nw + wake_start[j]..p * nw + wake_start[j + 1]];
                let mut lead = seg2(c, at(o_in, 0), at(o_out, 0));
                for (m, w) in row.iter_mut().enumerate() {
                    let sides = seg2(c, at(o_out, m), at(o_out, m + 1))
                        + seg2(c, at(o_in, m + 1), at(o_in, m));
                    if m + 1 < count {
                        let trail = seg2(c, at(o_in, m + 1), at(o_out, m + 1));
                        *w = lead - trail + sides;
                        lead = trail;
                    } else {
                        let (a, b) = (at(o_in, count), at(o_out, count));
                        let scale = (b[0] - a[0]).hypot(b[1] - a[1]);
                        let (ai, bi) = ([b[0], -b[1]], [a[0], -a[1]]);
                        let legs = -leg_w(c, a, CUTOFF, scale) + leg_w(c, b, CUTOFF, scale)
                            - leg_w(c, ai, CUTOFF, scale)
                            + leg_w(c, bi, CUTOFF, scale);
                        *w = lead + sides + legs;
                    }
                }
            }
        }

        let mut force: Vec<[f64; 2]> = lattice.panels.iter().map(|p| p.bound_mid()).collect();
        force.extend(ring_centroids);
        Ok(HarmonicVlm {
            n,
            chordwise: nc,
            spanwise: ns,
            mach,
            bound,
            wake: wake_w,
            wake_start,
            wake_xi,
            widths: lattice.panels.iter().map(|p| p.width).collect(),
            ring_areas,
            eval: lattice.panels.iter().map(|p| p.control).collect(),
            force,
            max_panel_chord,
            max_wake_ring,
            wake_length,
            min_wake_length: min_wake_length(pl.root_chord, pl.span),
        })
    }

    /// Mach number of this lattice.
    pub fn mach(&self) -> f64 {
        self.mach
    }

    /// Number of wake rings (all strips).
    pub fn wake_rings(&self) -> usize {
        self.wake_xi.len()
    }

    /// The resolution check of [`check_resolution`] for this lattice and wake.
    pub fn check_resolution(&self, nu: f64) -> Result<(), PanelError> {
        resolution(
            nu,
            self.max_panel_chord,
            self.max_wake_ring,
            self.wake_length,
            self.min_wake_length,
        )
    }

    /// The complex tangency matrix `A(ν) = B + W(ν)` (module doc, "flow tangency").
    fn tangency(&self, nu: f64) -> Mat<c64> {
        let n = self.n;
        let nc = self.chordwise;
        let nw = self.wake_xi.len();
        let (cos, sin): (Vec<f64>, Vec<f64>) = self
            .wake_xi
            .iter()
            .map(|xi| {
                let (s, c) = (nu * xi).sin_cos();
                (c, -s)
            })
            .unzip();
        let mut a = Mat::<c64>::from_fn(n, n, |p, q| c64::new(self.bound[p * n + q], 0.0));
        for j in 0..self.spanwise {
            let (s, e) = (self.wake_start[j], self.wake_start[j + 1]);
            let te = j * nc + nc - 1;
            for p in 0..n {
                let row = &self.wake[p * nw + s..p * nw + e];
                let (mut re, mut im) = (0.0, 0.0);
                for ((w, c), sn) in row.iter().zip(&cos[s..e]).zip(&sin[s..e]) {
                    re += w * c;
                    im += w * sn;
                }
                a[(p, te)] += c64::new(re, im);
            }
        }
        a
    }

    /// The force amplitudes `F / q` (row-major `2n x m`, rows as [`HarmonicMap::force`]) for `m`
    /// normalwash columns `alpha_e` (row-major `n x m`, at [`HarmonicMap::eval`]): the same as
    /// [`Self::map`] then [`HarmonicMap::apply`] per column, by one LU solve instead of the
    /// inverse (for a projection on a few modes).
    pub fn forces(&self, nu: f64, alpha_e: &[c64], m: usize) -> Result<Vec<c64>, PanelError> {
        self.check_resolution(nu)?;
        let n = self.n;
        let g = solve_normalwash(n, alpha_e, m, || self.tangency(nu))?;
        let nc = self.chordwise;
        let mut f = vec![c64::new(0.0, 0.0); 2 * n * m];
        for p in 0..n {
            let w2 = 2.0 * self.widths[p];
            let t = c64::new(0.0, 2.0 * nu * self.ring_areas[p]);
            for c in 0..m {
                let prev = if p % nc == 0 {
                    c64::new(0.0, 0.0)
                } else {
                    g[(p - 1, c)]
                };
                f[p * m + c] = (g[(p, c)] - prev) * w2;
                f[(n + p) * m + c] = t * g[(p, c)];
            }
        }
        finite_or_singular(f, self.mach)
    }

    /// The complex force map at reduced frequency `nu = ω / V` (1/m), module doc.
    pub fn map(&self, nu: f64) -> Result<HarmonicMap, PanelError> {
        self.check_resolution(nu)?;
        let n = self.n;
        let nc = self.chordwise;
        let a = self.tangency(nu);
        let inv = a.partial_piv_lu().inverse();
        let mut k = vec![c64::new(0.0, 0.0); 2 * n * n];
        for p in 0..n {
            let w2 = 2.0 * self.widths[p];
            let first = p % nc == 0;
            let t = c64::new(0.0, 2.0 * nu * self.ring_areas[p]);
            for r in 0..n {
                let g = inv[(p, r)];
                let prev = if first {
                    c64::new(0.0, 0.0)
                } else {
                    inv[(p - 1, r)]
                };
                k[p * n + r] = -(g - prev) * w2;
                k[(n + p) * n + r] = -t * g;
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
}

/// The singularity strengths `g` (row-major `n x m` as a matrix) of `A g = -α_e` for the `m`
/// normalwash columns `alpha_e` (row-major `n x m`), `A` the `n x n` influence matrix built by
/// `influence` (only once the shape is checked), by one LU solve: the common step of the
/// harmonic vortex lattice's and the doublet lattice's `forces`.
pub(super) fn solve_normalwash(
    n: usize,
    alpha_e: &[c64],
    m: usize,
    influence: impl FnOnce() -> Mat<c64>,
) -> Result<Mat<c64>, PanelError> {
    if alpha_e.len() != n * m {
        return Err(PanelError::Shape {
            expected: n * m,
            got: alpha_e.len(),
        });
    }
    let mut g = Mat::<c64>::from_fn(n, m, |p, c| -alpha_e[p * m + c]);
    influence().partial_piv_lu().solve_in_place(g.as_mut());
    Ok(g)
}

/// `f`, or [`PanelError::Singular`] when an entry is not finite (a singular influence matrix).
pub(super) fn finite_or_singular(f: Vec<c64>, mach: f64) -> Result<Vec<c64>, PanelError> {
    if f.iter().any(|v| !(v.re.is_finite() && v.im.is_finite())) {
        return Err(PanelError::Singular(mach));
    }
    Ok(f)
}

fn resolution(
    nu: f64,
    max_panel_chord: f64,
    max_wake_ring: f64,
    wake_length: f64,
    min_wake_length: f64,
) -> Result<(), PanelError> {
    if !(nu.is_finite() && nu >= 0.0) {
        return Err(PanelError::BadFrequency(nu));
    }
    const RULE: &str = "box chord < 0.08 V/f (MSC Nastran Aeroelastic User's Guide)";
    let limit = BOX_RULE * std::f64::consts::TAU / nu; // +inf at nu = 0
    for (what, value) in [
        ("chordwise panel length", max_panel_chord),
        ("wake ring length", max_wake_ring),
    ] {
        if value > limit {
            return Err(PanelError::TooCoarse {
                what,
                value,
                limit,
                nu,
                rule: RULE,
            });
        }
    }
    if wake_length < min_wake_length {
        return Err(PanelError::TooCoarse {
            what: "wake length",
            value: wake_length,
            limit: min_wake_length,
            nu,
            rule: "estimated wake truncation error min(c_r/2L, c_r s/4L^2) above WAKE_ERROR = 1 %",
        });
    }
    Ok(())
}

/// The subsonic harmonic force map of `lattice` at Mach `mach` and reduced frequency `nu = ω/V`
/// (1/m): [`HarmonicVlm::new`] then [`HarmonicVlm::map`] (build the [`HarmonicVlm`] once to
/// evaluate many frequencies).
pub fn vlm_map(
    lattice: &Lattice,
    mach: f64,
    nu: f64,
    wake: &WakeSettings,
) -> Result<HarmonicMap, PanelError> {
    check_resolution(lattice, nu, wake)?;
    HarmonicVlm::new(lattice, mach, wake)?.map(nu)
}

/// Supersonic: first-order piston theory is local and its unsteady form is the quasi-steady one
/// applied to the complex alpha_e (Ashley & Zartarian 1956); same Ackeret option as piston.rs.
/// `M >= 1.2` ([`super::SUPERSONIC_LIMIT`]); evaluation and force points at the centroids.
pub fn piston_map(
    lattice: &Lattice,
    mach: f64,
    correction: Correction,
) -> Result<HarmonicMap, PanelError> {
    if !(mach.is_finite() && mach >= 0.0) {
        return Err(PanelError::BadMach(mach));
    }
    if mach < SUPERSONIC_LIMIT {
        return Err(PanelError::Untrusted(mach, "piston theory"));
    }
    let k = piston::force_map(lattice, mach, correction)?;
    let centroids: Vec<[f64; 2]> = lattice.panels.iter().map(|p| p.centroid).collect();
    Ok(HarmonicMap {
        eval: centroids.clone(),
        force: centroids,
        k: k.into_iter().map(|v| c64::new(v, 0.0)).collect(),
    })
}

/// Reduced-frequency resolution check: Err(PanelError::TooCoarse{..}) when the lattice's
/// chordwise panel length (or a wake ring) exceeds the MSC Nastran box-size rule `0.08 V/f =
/// 0.08 · 2π/ν` for the wavelength `2π/ν`, or when the wake is shorter than
/// [`min_wake_length`] (module doc); `BadFrequency` for a negative or non-finite `nu`,
/// `BadWake` for bad settings.
pub fn check_resolution(lattice: &Lattice, nu: f64, wake: &WakeSettings) -> Result<(), PanelError> {
    for (what, value) in [("length", wake.length), ("ring", wake.ring)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(PanelError::BadWake { what, value });
        }
    }
    let nc = lattice.chordwise;
    let mut max_panel_chord: f64 = 0.0;
    let mut max_wake_ring: f64 = 0.0;
    for (idx, p) in lattice.panels.iter().enumerate() {
        let (l_in, l_out) = (
            p.corners[3][0] - p.corners[0][0],
            p.corners[2][0] - p.corners[1][0],
        );
        max_panel_chord = max_panel_chord.max(l_in).max(l_out);
        if idx % nc == nc - 1 {
            max_wake_ring = max_wake_ring.max(wake.ring * 0.5 * (l_in + l_out));
        }
    }
    let pl = &lattice.planform;
    let reference = pl.root_chord;
    resolution(
        nu,
        max_panel_chord,
        max_wake_ring,
        wake.length * reference,
        min_wake_length(pl.root_chord, pl.span),
    )
}
