//! Harmonic supersonic lifting surface: the Mach box method (issue 33), velocity-potential
//! form, for subsonic and supersonic leading, side and trailing edges alike. It gives the
//! complex panel forces of a fin oscillating harmonically at Mach `M > 1` for the flutter
//! solvers (`analysis::flutter::fin`), as [`super::harmonic`] does subsonic.
//!
//! # The harmonic supersonic source (derivation)
//!
//! The linearised potential `φ e^{iωt}` about a free stream `V` along `+x` obeys
//! `(iω + V∂_x)² φ / a² = ∇² φ`, i.e. with `ν = ω/V` and `β = sqrt(M² - 1)`
//!
//! `β² φ_xx - φ_yy - φ_zz + 2iνM² φ_x - ν²M² φ = 0`.
//!
//! Put `φ = e^{-iνM²x/β²} χ`: the first-derivative terms cancel and
//! `β² χ_xx - χ_yy - χ_zz + (ν²M²/β²) χ = 0`, a Klein-Gordon equation in the "time" `X = x/β`
//! with mass `κ = νM/β`. Its causal elementary solution in two space dimensions is
//! `cos(κ sqrt(X² - r²)) / sqrt(X² - r²)` inside the cone `X > r` (up to a constant), so the
//! harmonic supersonic source is
//!
//! `Φ_s = e^{-iνM² x_0/β²} cos(νM R/β²) / R`, `R = sqrt(x_0² - β²(y_0² + z²))`, `x_0 > β r`,
//!
//! the form of Garrick & Rubinow (NACA Rep. 846, 1946) and of the Mach box method (Pines,
//! Dugundji & Neuringer, J. Aeronaut. Sci. 22(10), 1955; Zartarian & Hsu, WADC TR 56-97;
//! Ashley & Landahl, *Aerodynamics of Wings and Bodies*, 1965, ch. 8). Near the source the
//! factor tends to 1, so its normalisation is the steady one: the potential on the upper side
//! `z = 0+` of a distribution of normal velocity `w(ξ, η)` (`φ_z(0+) = w`) is
//!
//! `φ(x, y) = -(1/π) ∬_{cone} w(ξ, η) e^{-iνM² x_0/β²} cos(νM R/β²)/R dξ dη`
//!
//! (steady 2-D check: `∫ dη / R = π/β` over the cone's width, `φ = -w x/β`,
//! `φ_x = -w/β`: Ackeret). The lower side carries `-φ`. With `w = -V α_e` (`α_e` the
//! normalwash angle of [`super`]) and `φ̂ = φ/V`:
//!
//! `φ̂(x, y) = (1/π) ∬ α_e e^{-iνM² x_0/β²} cos(νM R/β²)/R dξ dη`,
//! `Δp / q = (p_lower - p_upper)/q = 4 (φ̂_x + iν φ̂)` (linearised Bernoulli on both sides).
//!
//! *Two-dimensional limit (derived).* Integrating the source over `η` across the cone,
//! `∫ cos(νM R/β²)/R dη = (π/β) J_0(νM x_0/β²)` (with `βη = x_0 sin θ`,
//! `∫_{-π/2}^{π/2} cos(z cos θ) dθ = π J_0(z)`), so in 2-D
//! `φ̂(x) = (1/β) ∫_0^x α_e(ξ) e^{-iνM²(x-ξ)/β²} J_0(νM(x-ξ)/β²) dξ`, Garrick & Rubinow's
//! result; the tests compare the method with it.
//!
//! *Piston theory as a limit, and its criterion (derived from the 2-D kernel).* For `M >> 1`,
//! `β -> M`, `e^{-iνM² x_0/β²} -> e^{-iν x_0}` and `J_0 -> 1`, and
//! `φ̂_x + iνφ̂ -> α_e/M`: `Δp = 4 q α_e / M`, first-order piston theory (Ashley & Zartarian
//! 1956). The neglected terms are of relative size `1/β²` (the steady `M/β`, which the Ackeret
//! factor of [`super::piston`] removes) and, in the kernel, `ν x_0/β²` (the phase
//! `νM²x_0/β² - ν x_0`) and `(νM x_0/β²)²/4` (the Bessel function); for `νM c/β² >> 1` the
//! kernel oscillates fast, the potential becomes local again and piston theory returns (the
//! `k² M² >> 1` branch of Ashley & Zartarian). Piston theory also ignores every Mach cone:
//! a subsonic leading edge (`β < tan Λ_LE`) breaks it outright. [`piston_valid`] states the
//! criterion used for the flutter forces.
//!
//! # Boxes (the discretisation)
//!
//! The plane `z = 0` is cut into boxes `Δx` by `Δy = Δx/β` (the Mach lines through a box's
//! centre pass through the corners of the boxes diagonally ahead: Pines et al.'s grid) covering
//! the planform, the wake behind it and the off-wing "diaphragm" beside the tip and ahead of a
//! subsonic leading edge. A box is a wing box when its centre lies on the planform; `α_e` is
//! taken constant over it. The potential is evaluated at box centres:
//! `φ̂_P = Σ_Q σ_Q C(P - Q)` with the box integral
//!
//! `C(Δi, Δj) = (Δx/(πβ)) ∬_{box ∩ cone} e^{-iϖM² a} cos(ϖM sqrt(a² - b²)) / sqrt(a² - b²) da db`,
//!
//! in box units `a = x_0/Δx`, `b = β y_0/Δx`, `ϖ = νΔx/β²`, over the box
//! `[Δi - ½, Δi + ½] × [Δj - ½, Δj + ½]` within the cone `a > |b|`. The Mach-line singularity
//! is removed exactly by `b = a sin θ` (`da db / sqrt(a² - b²) = da dθ`); the `θ` limits
//! `asin(clamp(b_edge/a))` have square-root ends where `b_edge = ±a` (a box corner on the
//! Mach line), which the substitution `a = a_0 + L u²` makes smooth; 8-point Gauss-Legendre in
//! `u` and `θ`, with sub-panels enough that the phase turns by at most three radians per
//! sub-panel. At `ν = 0` these are the steady box integrals to rounding. The root is the
//! reflection plane of [`super`]: the image of box `(i, j)` is column `-1 - j` with the same
//! source.
//!
//! Sources: wing boxes carry `σ = α_e`. The diaphragm boxes' sources are unknown and fixed by
//! the conditions on the potential there: off the wing and its wake the potential is odd in
//! `z` and continuous, so `φ = 0` (beside the tip, ahead of a subsonic leading edge); in the
//! wake the pressure jump vanishes, `φ_x + iνφ = 0`, imposed between successive box centres
//! as `φ_i (1 + iνΔx/2) = φ_{i-1} (1 - iνΔx/2)` (the same difference as the pressure below,
//! so the wake carries exactly no load). A box's potential depends only on boxes in earlier
//! rows and on itself (boxes of the same row lie outside each other's cones), so the unknown
//! sources follow row by row, each from one equation ("marching"): no system is solved.
//!
//! Loads: the force `F/q = ∫ 4 (φ̂_x + iνφ̂) dA` of a wing box, at its centre, is
//! `4 Δy [φ̂_{i+½} - φ̂_{i-½} + iν Δx φ̂_i]` with the potential at its leading and trailing
//! interfaces: the mean of the two centres between wing boxes, 0 on the leading edge (the
//! potential is continuous and vanishes ahead of the wing), on the trailing edge the linear
//! extrapolation through the two last centres of the strip. Summed along a strip this
//! telescopes to `4 Δy [φ̂_TE + iν ∫ φ̂ dx]`, the exact strip lift, and it is exact for the
//! 2-D steady plate (`φ̂` linear) box by box (the wake's and the diaphragm's potentials enter
//! the loads only through the sources they carry). The last box of a strip extends to the
//! planform's trailing edge (the extrapolation reaches it), and the span is a whole number
//! of columns, so only the leading edge and the swept trailing edges are ragged. The
//! ragged planform edges (box inclusion by centre) are the method's classical first-order
//! error; the tests bound it against the steady constant-pressure panels
//! ([`super::supersonic`]) in the `ν -> 0` limit.

use faer::c64;

use super::harmonic::BOX_RULE;
use super::{Lattice, PanelError};
use crate::aero::FinPlanform;

/// Lowest Mach of the method: `Δy = Δx/β` grows without bound as `M -> 1` (at 1.1,
/// `Δy = 2.2 Δx`).
pub const MIN_MACH: f64 = 1.1;

/// Default number of boxes along the fin's streamwise extent (root leading edge to the
/// furthest trailing edge): the cost grows as its fourth power; at 32 the steady slope of the
/// tested planforms is within 2.3 % of the constant-pressure panels (48 boxes: 1.2 %).
pub const DEFAULT_BOXES: usize = 32;

/// Lowest Mach at which [`piston_valid`] accepts piston theory (`1/β² <= 0.19`; module doc).
pub const PISTON_MIN_MACH: f64 = 2.5;

/// The criterion for unsteady piston theory on `planform` at Mach `mach` (module doc):
/// `M >= PISTON_MIN_MACH` and a supersonic leading edge (`β > tan Λ_LE`, Λ_LE the
/// leading-edge sweep). Elsewhere the flutter forces use the Mach box.
pub fn piston_valid(planform: &FinPlanform, mach: f64) -> bool {
    if !(mach.is_finite() && mach >= PISTON_MIN_MACH) {
        return false;
    }
    let beta = (mach * mach - 1.0).sqrt();
    let tan_le = planform.tip_le_offset / planform.span;
    beta > tan_le.abs()
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// Index in the wing list.
    Wing(usize),
    Diaphragm,
    Wake,
}

/// The Mach box grid of one fin at one Mach (module doc).
#[derive(Clone, Debug)]
pub struct MachBox {
    mach: f64,
    beta: f64,
    dx: f64,
    dy: f64,
    rows: usize,
    cols: usize,
    /// Columns on the span (the rest is the diaphragm beyond the tip).
    wing_cols: usize,
    kind: Vec<Kind>,
    /// Grid index `i * cols + j` of each wing box.
    wing: Vec<usize>,
    centres: Vec<[f64; 2]>,
    /// The trailing edge's `x` on each wing box's strip.
    te_x: Vec<f64>,
    planform_area: f64,
}

const GL8_X: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const GL8_W: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// The largest phase change (rad) of the box integrands over one 8-point Gauss-Legendre panel:
/// the rule's error for `exp(i ω t)` over a panel of phase `θ` is about `(θ/2)^16 / 16!`,
/// 3e-11 at 3 rad.
const PHASE_PER_PANEL: f64 = 3.0;

/// Composite 8-point Gauss-Legendre of `f` over `[lo, hi]` with `panels` panels.
fn gauss(lo: f64, hi: f64, panels: usize, mut f: impl FnMut(f64) -> c64) -> c64 {
    let h = (hi - lo) / panels as f64;
    let mut sum = c64::new(0.0, 0.0);
    for p in 0..panels {
        let mid = lo + (p as f64 + 0.5) * h;
        for (x, w) in GL8_X.iter().zip(GL8_W) {
            sum += (f(mid - 0.5 * h * x) + f(mid + 0.5 * h * x)) * w;
        }
    }
    sum * (0.5 * h)
}

/// `∬_{box ∩ cone} e^{-iϖM²a} cos(ϖM sqrt(a²-b²)) / sqrt(a²-b²) da db` over the box
/// `[di - ½, di + ½] × [dj - ½, dj + ½]` (module doc), `dj <= di`.
fn box_integral(di: usize, dj: usize, varpi: f64, mach: f64) -> c64 {
    let (di, dj) = (di as f64, dj as f64);
    let (b_lo, b_hi) = (dj - 0.5, dj + 0.5);
    let (a_lo, a_hi) = ((di - 0.5).max(0.0), di + 0.5);
    // Breakpoints where a box edge meets the Mach line b = ±a.
    let mut cuts = vec![a_lo];
    for c in [b_lo.abs(), b_hi.abs()] {
        if c > a_lo && c < a_hi {
            cuts.push(c);
        }
    }
    cuts.push(a_hi);
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let m2 = mach * mach;
    let mut total = c64::new(0.0, 0.0);
    for w in cuts.windows(2) {
        let (lo, len) = (w[0], w[1] - w[0]);
        if len <= 0.0 {
            continue;
        }
        // Phase turns of the a-integrand over the segment: ϖ M (M + 1) per unit a at most;
        // at most PHASE_PER_PANEL radians per 8-point panel.
        let na = 1 + (varpi * mach * (mach + 1.0) * len / PHASE_PER_PANEL).ceil() as usize;
        // a = lo + len u², da = 2 len u du, u in [0, 1].
        total += gauss(0.0, 1.0, na, |u| {
            let a = lo + len * u * u;
            if a <= 0.0 {
                return c64::new(0.0, 0.0);
            }
            let t_lo = (b_lo / a).clamp(-1.0, 1.0).asin();
            let t_hi = (b_hi / a).clamp(-1.0, 1.0).asin();
            if t_hi <= t_lo {
                return c64::new(0.0, 0.0);
            }
            let z = varpi * mach * a;
            let nt = 1 + (z * (t_hi - t_lo) / PHASE_PER_PANEL).ceil() as usize;
            let inner = if varpi == 0.0 {
                c64::new(t_hi - t_lo, 0.0)
            } else {
                gauss(t_lo, t_hi, nt, |t| c64::new((z * t.cos()).cos(), 0.0))
            };
            let (s, c) = (varpi * m2 * a).sin_cos();
            inner * c64::new(c, -s) * (2.0 * len * u)
        });
    }
    total
}

impl MachBox {
    /// The grid on `planform` at Mach `mach >= MIN_MACH` with about `boxes` boxes along the
    /// fin's streamwise extent (the span a whole number `round(s β boxes / extent)` of
    /// columns, at least one).
    pub fn new(planform: &FinPlanform, mach: f64, boxes: usize) -> Result<MachBox, PanelError> {
        if !(mach.is_finite() && mach >= MIN_MACH) {
            return Err(PanelError::BadMach(mach));
        }
        Self::at_any_supersonic_mach(planform, mach, boxes)
    }

    /// [`Self::new`] at any `M > 1` (the tests measure the method's error below
    /// [`MIN_MACH`]).
    pub(super) fn at_any_supersonic_mach(
        planform: &FinPlanform,
        mach: f64,
        boxes: usize,
    ) -> Result<MachBox, PanelError> {
        if !(mach.is_finite() && mach > 1.0) {
            return Err(PanelError::BadMach(mach));
        }
        // Validates the planform.
        Lattice::new(planform, 1, 1, super::Spacing::Uniform)?;
        if boxes == 0 {
            return Err(PanelError::EmptyLattice {
                chordwise: 0,
                spanwise: 0,
            });
        }
        let beta = (mach * mach - 1.0).sqrt();
        let p = planform;
        let (x_lo, x_hi) = p.edges().x_extent();
        // The span is a whole number of columns (no ragged tip); Δx follows from Δy = Δx/β
        // as near the requested count along the streamwise extent as that allows.
        let wing_cols = ((p.span * beta * boxes as f64 / (x_hi - x_lo)).round() as usize).max(1);
        let dy = p.span / wing_cols as f64;
        let dx = dy * beta;
        let boxes = ((x_hi - x_lo) / dx).ceil() as usize;
        // Diaphragm columns beyond the tip that can both receive from and act on the wing.
        let cols = wing_cols + boxes / 2 + 2;
        let rows = boxes + 1;
        let mut kind = Vec::with_capacity(rows * cols);
        let (mut wing, mut centres, mut te_x) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..rows {
            for j in 0..cols {
                let c = [x_lo + (i as f64 + 0.5) * dx, (j as f64 + 0.5) * dy];
                let k = if c[1] < p.span {
                    let eta = c[1] / p.span;
                    let le = p.le_at(eta);
                    let te = le + p.chord_at(eta);
                    if c[0] > le && c[0] < te {
                        wing.push(i * cols + j);
                        centres.push(c);
                        te_x.push(te);
                        Kind::Wing(wing.len() - 1)
                    } else if c[0] >= te {
                        Kind::Wake
                    } else {
                        Kind::Diaphragm
                    }
                } else {
                    Kind::Diaphragm
                };
                kind.push(k);
            }
        }
        if wing.is_empty() {
            return Err(PanelError::EmptyLattice {
                chordwise: boxes,
                spanwise: wing_cols,
            });
        }
        // Rows behind the last wing box act on no wing box: dropped.
        let rows = wing.iter().map(|g| g / cols).max().unwrap_or(0) + 1;
        kind.truncate(rows * cols);
        Ok(MachBox {
            mach,
            beta,
            dx,
            dy,
            rows,
            cols,
            wing_cols,
            kind,
            wing,
            centres,
            te_x,
            planform_area: p.area(),
        })
    }

    /// Mach number of the grid.
    pub fn mach(&self) -> f64 {
        self.mach
    }

    /// Number of wing boxes.
    pub fn len(&self) -> usize {
        self.wing.len()
    }

    /// Whether there are no wing boxes (never, once built).
    pub fn is_empty(&self) -> bool {
        self.wing.is_empty()
    }

    /// Box length `Δx` (m).
    pub fn box_length(&self) -> f64 {
        self.dx
    }

    /// The wing boxes' centres: where `α_e` is taken and the forces act.
    pub fn centres(&self) -> &[[f64; 2]] {
        &self.centres
    }

    /// The box influence coefficients `C(Δi, Δj)`, `Δj <= Δi` (module doc), row-major
    /// `rows x rows`, at reduced frequency `nu`.
    fn coefficients(&self, nu: f64) -> Vec<c64> {
        let n = self.rows;
        let varpi = nu * self.dx / (self.beta * self.beta);
        let scale = self.dx / (std::f64::consts::PI * self.beta);
        let mut c = vec![c64::new(0.0, 0.0); n * n];
        for di in 0..n {
            for dj in 0..=di {
                c[di * n + dj] = box_integral(di, dj, varpi, self.mach) * scale;
            }
        }
        c
    }

    /// The force amplitudes `F / q` (row-major `len x m`, at [`Self::centres`]) for `m`
    /// normalwash columns `alpha_e` (row-major `len x m`, at the same points), reduced
    /// frequency `nu = ω/V` (1/m). `TooCoarse` when `Δx` breaks the box rule
    /// `Δx < 0.08 · 2π/ν` of [`super::harmonic`].
    pub fn forces(&self, nu: f64, alpha_e: &[c64], m: usize) -> Result<Vec<c64>, PanelError> {
        if !(nu.is_finite() && nu >= 0.0) {
            return Err(PanelError::BadFrequency(nu));
        }
        let limit = BOX_RULE * std::f64::consts::TAU / nu;
        if self.dx > limit {
            return Err(PanelError::TooCoarse {
                what: "Mach box length",
                value: self.dx,
                limit,
                nu,
                rule: "box chord < 0.08 V/f (MSC Nastran Aeroelastic User's Guide)",
            });
        }
        let nw = self.wing.len();
        if alpha_e.len() != nw * m {
            return Err(PanelError::Shape {
                expected: nw * m,
                got: alpha_e.len(),
            });
        }
        let (rows, cols) = (self.rows, self.cols);
        let coef = self.coefficients(nu);
        let zero = c64::new(0.0, 0.0);
        let mut sigma = vec![zero; rows * cols * m];
        let mut phi = vec![zero; rows * cols * m];
        let lag = c64::new(1.0, -0.5 * nu * self.dx) / c64::new(1.0, 0.5 * nu * self.dx);
        let c00 = coef[0];
        let mut acc = vec![zero; m];
        let last = rows - 1;
        for i in 0..rows {
            for j in 0..cols {
                // A diaphragm box `d` columns beyond the tip carries a source only if a wing
                // box is in its cone (`d <= i`) and matters only if it is in a wing box's
                // cone (`d <= last - i`), directly or through other such boxes (each column
                // outward costs a row either way): otherwise its source stays 0.
                if j >= self.wing_cols {
                    let d = j + 1 - self.wing_cols;
                    if d > i.min(last - i) {
                        continue;
                    }
                }
                acc.iter_mut().for_each(|a| *a = zero);
                // Every source box in the forward cone except the box itself.
                for ip in 0..=i {
                    let di = i - ip;
                    let crow = &coef[di * rows..(di + 1) * rows];
                    let base = ip * cols;
                    let (j_lo, j_hi) = (j.saturating_sub(di), (j + di).min(cols - 1));
                    for jp in j_lo..=j_hi {
                        if di == 0 && jp == j {
                            continue;
                        }
                        let cf = crow[j.abs_diff(jp)];
                        let s = &sigma[(base + jp) * m..(base + jp + 1) * m];
                        for (a, sv) in acc.iter_mut().zip(s) {
                            *a += cf * sv;
                        }
                    }
                    // Images: column -1 - jp at distance j + jp + 1 <= di.
                    if di > j {
                        for jp in 0..(di - j).min(cols) {
                            let cf = crow[j + jp + 1];
                            let s = &sigma[(base + jp) * m..(base + jp + 1) * m];
                            for (a, sv) in acc.iter_mut().zip(s) {
                                *a += cf * sv;
                            }
                        }
                    }
                }
                let g = i * cols + j;
                // The box's own image lies at distance 2j + 1 > 0 = di: outside its cone.
                for c in 0..m {
                    let s = match self.kind[g] {
                        Kind::Wing(w) => alpha_e[w * m + c],
                        Kind::Diaphragm => -acc[c] / c00,
                        Kind::Wake => {
                            let prev = if i == 0 {
                                zero
                            } else {
                                phi[((i - 1) * cols + j) * m + c]
                            };
                            (prev * lag - acc[c]) / c00
                        }
                    };
                    sigma[g * m + c] = s;
                    phi[g * m + c] = acc[c] + c00 * s;
                }
            }
        }
        // Loads (module doc): 4 Δy [φ̂_{i+½} - φ̂_{i-½} + iν Δx φ̂_i] per wing box.
        let is_wing = |g: usize| matches!(self.kind[g], Kind::Wing(_));
        let inu_dx = c64::new(0.0, nu * self.dx);
        let mut f = vec![zero; nw * m];
        for (w, &g) in self.wing.iter().enumerate() {
            let i = g / cols;
            let ahead = (i > 0 && is_wing(g - cols)).then(|| g - cols);
            let behind = (i + 1 < rows && is_wing(g + cols)).then_some(g + cols);
            for c in 0..m {
                let here = phi[g * m + c];
                let prev = ahead.map_or(zero, |a| phi[a * m + c]);
                // Leading interface: the mean of the two centres, 0 on the leading edge.
                let front = if ahead.is_some() {
                    (prev + here) * 0.5
                } else {
                    zero
                };
                // Trailing interface: the mean; the last box of a strip reaches the trailing
                // edge, where the potential is the linear extrapolation through the box ahead
                // (or through 0 on the leading edge).
                let (back, length) = match behind {
                    Some(b) => ((here + phi[b * m + c]) * 0.5, inu_dx),
                    None => {
                        let reach = self.te_x[w] - self.centres[w][0];
                        let slope = if ahead.is_some() {
                            (here - prev) * (1.0 / self.dx)
                        } else {
                            here * (2.0 / self.dx)
                        };
                        (
                            here + slope * reach,
                            c64::new(0.0, nu * (reach + 0.5 * self.dx)),
                        )
                    }
                };
                f[w * m + c] = (back - front + length * here) * (4.0 * self.dy);
            }
        }
        if f.iter().any(|v| !(v.re.is_finite() && v.im.is_finite())) {
            return Err(PanelError::Singular(self.mach));
        }
        Ok(f)
    }

    /// Steady normal-force slope per radian on the planform area and centre of pressure (m
    /// aft of the root leading edge) for a uniform incidence (the `ν -> 0` limit).
    pub fn slope_and_centre(&self) -> Result<(f64, f64), PanelError> {
        let n = self.len();
        let f = self.forces(0.0, &vec![c64::new(1.0, 0.0); n], 1)?;
        let (mut force, mut moment) = (0.0, 0.0);
        for (v, c) in f.iter().zip(&self.centres) {
            force += v.re;
            moment += v.re * c[0];
        }
        if force == 0.0 {
            return Err(PanelError::Singular(self.mach));
        }
        Ok((force / self.planform_area, moment / force))
    }
}
