//! Fin planforms beyond the trapezoid (issue 34): the outline of one fin as its leading- and
//! trailing-edge curves over the span, shared by the checker (which validates a freeform
//! polygon), the structure generator (which meshes the fin with structured quads between the
//! two edges), and the aerodynamics (lattice, Mach box, the estimator's Barrowman values).
//!
//! # Coordinates
//!
//! `y` is the spanwise distance from the root (the body surface), `0 <= y <= s`; `x` is the
//! chordwise distance AFT of the root leading edge. A planform is described by its leading edge
//! `x_le(y)` and its chord `c(y) = x_te(y) - x_le(y) >= 0` (single-valued in chord per span
//! station: every line `y = const` cuts the fin in one chord).
//!
//! - **Trapezoidal:** `x_le(y) = x_t y / s`, `c(y) = c_r + (c_t - c_r) y / s` (`x_t` the tip's
//!   leading-edge offset, `s tan Λ_LE`).
//! - **Elliptical:** OpenRocket's elliptical fin (`EllipticalFinSet`: the half ellipse on the
//!   root chord with semi-axes `c_r / 2` and `s`, centred on the middle of the root chord):
//!   `x_le(y) = (c_r / 2)(1 - √(1 - (y/s)²))`, `c(y) = c_r √(1 - (y/s)²)`. Its area is
//!   `π c_r s / 4`; by the integrals below its mean aerodynamic chord is `8 c_r / (3π)` with
//!   its leading edge `c_r (1/2 - 4/(3π))` aft of the root leading edge, and the mid-chord line
//!   is unswept.
//! - **Freeform:** a polygon, as OpenRocket's `FreeformFinSet` stores it: from the root leading
//!   edge `(0, 0)` out to the tip and back to the root trailing edge `(c_r, 0)`. The checker
//!   splits it at its outermost points into a leading edge (y strictly increasing) and a
//!   trailing edge (y strictly decreasing), with at most one tip edge at `y = s` between them;
//!   both are piecewise linear in `y`.
//!
//! # The integrals (Niskanen 2009, sec. 3.2.2, "Barrowman's method for arbitrary planforms")
//!
//! OpenRocket's technical documentation (S. Niskanen, *Development of an Open Source model
//! rocket simulation software*, M.Sc. thesis, Helsinki University of Technology, 2009, sec.
//! 3.2.2) extends Barrowman's trapezoidal fin to any planform through the integrals over the
//! span of the local chord: the area `A = ∫ c dy`, the mean aerodynamic chord
//! `MAC = (1/A) ∫ c² dy`, its leading edge `x_MAC = (1/A) ∫ x_le c dy` and span station
//! `y_MAC = (1/A) ∫ y c dy`; the subsonic centre of pressure `x_MAC + MAC / 4`; the mid-chord
//! sweep in Diederich's slope as the span average of the cosine of the local mid-chord line's
//! sweep, `cos Γ_c = (1/s) ∫ cos Γ_c(y) dy` (OpenRocket's `FinSetCalc.calculateFinGeometry`
//! averages it over 48 strips). For a trapezoid every one of these reduces to Barrowman's
//! closed forms. Here the piecewise-linear edges are integrated exactly (each integrand is a
//! polynomial of degree <= 2 on every segment: Simpson's rule is exact), the ellipse
//! in closed form or, for `cos Γ_c` and `cos² Λ_LE`, by Gauss-Legendre quadrature in
//! `y = s sin θ` (which removes the square-root end point).

use serde::{Deserialize, Serialize};

/// The shape of a fin's outline (module doc).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum FinOutline {
    /// Straight leading and trailing edges from the root chord to the tip chord.
    #[default]
    Trapezoidal,
    /// The half ellipse on the root chord (module doc).
    Elliptical,
    /// Piecewise-linear edges: `leading` from the root leading edge `(0, 0)` to the tip,
    /// `trailing` from the root trailing edge `(0, c_r)` to the tip, both as `(y, x)` pairs
    /// with `y` strictly increasing, `x` aft of the root leading edge, m. Both end at `y = s`
    /// (the tip chord is `trailing.last - leading.last`, 0 for a pointed tip).
    Freeform {
        leading: Vec<[f64; 2]>,
        trailing: Vec<[f64; 2]>,
    },
}

impl FinOutline {
    pub fn is_trapezoidal(&self) -> bool {
        matches!(self, FinOutline::Trapezoidal)
    }

    /// The keyword the language uses for it (`fins { planform = ... }`).
    pub fn keyword(&self) -> &'static str {
        match self {
            FinOutline::Trapezoidal => "trapezoidal",
            FinOutline::Elliptical => "elliptical",
            FinOutline::Freeform { .. } => "freeform",
        }
    }
}

/// Gauss-Legendre nodes and weights on [-1, 1], 16 points (Abramowitz & Stegun, Table 25.4).
const GL16: [(f64, f64); 8] = [
    (0.095_012_509_837_637_44, 0.189_450_610_455_068_5),
    (0.281_603_550_779_258_9, 0.182_603_415_044_923_6),
    (0.458_016_777_657_227_4, 0.169_156_519_395_002_5),
    (0.617_876_244_402_643_7, 0.149_595_988_816_576_7),
    (0.755_404_408_355_003, 0.124_628_971_255_533_9),
    (0.865_631_202_387_831_7, 0.095_158_511_682_492_78),
    (0.944_575_023_073_232_6, 0.062_253_523_938_647_89),
    (0.989_400_934_991_649_9, 0.027_152_459_411_754_09),
];

/// Panels of the composite Gauss-Legendre rule over `θ ∈ [0, π/2]` for the ellipse.
const ELLIPSE_PANELS: usize = 32;

/// A fin planform's edges: the outline with the trapezoid's dimensions (module doc).
#[derive(Clone, Copy, Debug)]
pub struct Edges<'a> {
    pub outline: &'a FinOutline,
    pub span: f64,
    pub root_chord: f64,
    pub tip_chord: f64,
    /// The trapezoid's tip leading-edge offset aft of the root's, m.
    pub tip_le_offset: f64,
}

impl Edges<'_> {
    /// Leading edge `x_le(y)`, m aft of the root leading edge.
    pub fn le(&self, y: f64) -> f64 {
        match self.outline {
            FinOutline::Trapezoidal => self.tip_le_offset * (y / self.span),
            FinOutline::Elliptical => 0.5 * self.root_chord * (1.0 - root_term(y / self.span)),
            FinOutline::Freeform { leading, .. } => polyline(leading, y),
        }
    }

    /// Local chord `c(y)`, m.
    pub fn chord(&self, y: f64) -> f64 {
        match self.outline {
            FinOutline::Trapezoidal => {
                self.root_chord + (self.tip_chord - self.root_chord) * (y / self.span)
            }
            FinOutline::Elliptical => self.root_chord * root_term(y / self.span),
            FinOutline::Freeform { leading, trailing } => {
                (polyline(trailing, y) - polyline(leading, y)).max(0.0)
            }
        }
    }

    /// Whether the tip chord is zero (the structured mesh collapses its tip row to one node).
    pub fn pointed_tip(&self) -> bool {
        self.chord(self.span) <= 1e-12 * self.root_chord
    }

    /// The span stations where an edge has a corner (0 and `s` included, ascending): a
    /// structured mesh or lattice with these among its stations represents the polygon
    /// exactly. Only the root and the tip for the trapezoid and the ellipse.
    pub fn breakpoints(&self) -> Vec<f64> {
        match self.outline {
            FinOutline::Trapezoidal | FinOutline::Elliptical => vec![0.0, self.span],
            FinOutline::Freeform { leading, trailing } => {
                let mut ys: Vec<f64> = leading.iter().chain(trailing).map(|p| p[0]).collect();
                ys.sort_by(f64::total_cmp);
                ys.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * self.span);
                ys
            }
        }
    }

    /// `n` spanwise strips (`n + 1` stations from 0 to `s`): uniform for the trapezoid
    /// (`s j / n`, as the generator always laid them out); `s sin(π j / (2n))` for the ellipse
    /// (dense at the tip, where the chord changes fastest); for a polygon, every corner is a
    /// station and the strips are shared among the segments in proportion to their length
    /// (at least one each, so more than `n` when the polygon has more than `n` segments).
    pub fn stations(&self, n: usize) -> Vec<f64> {
        let n = n.max(1);
        match self.outline {
            FinOutline::Trapezoidal => (0..=n).map(|j| self.span * j as f64 / n as f64).collect(),
            FinOutline::Elliptical => (0..=n)
                .map(|j| {
                    if j == n {
                        self.span
                    } else {
                        self.span * (std::f64::consts::FRAC_PI_2 * j as f64 / n as f64).sin()
                    }
                })
                .collect(),
            FinOutline::Freeform { .. } => {
                let b = self.breakpoints();
                let segs = b.len() - 1;
                // One strip per segment, then each further strip to the segment with the
                // longest strips (the first on a tie), up to max(n, segments) in all.
                let len: Vec<f64> = b.windows(2).map(|w| w[1] - w[0]).collect();
                let mut counts = vec![1usize; segs];
                for _ in segs..n.max(segs) {
                    let mut best = 0;
                    for k in 1..segs {
                        if len[k] / counts[k] as f64 > len[best] / counts[best] as f64 {
                            best = k;
                        }
                    }
                    counts[best] += 1;
                }
                let mut out = vec![0.0];
                for (w, &c) in b.windows(2).zip(&counts) {
                    for k in 1..=c {
                        out.push(if k == c {
                            w[1]
                        } else {
                            w[0] + (w[1] - w[0]) * k as f64 / c as f64
                        });
                    }
                }
                out
            }
        }
    }

    /// The integrals of the module doc: `[∫ c dy, ∫ c² dy, ∫ x_le c dy, ∫ y c dy]`.
    pub fn moments(&self) -> [f64; 4] {
        match self.outline {
            FinOutline::Trapezoidal | FinOutline::Freeform { .. } => {
                // Piecewise linear: Simpson's rule on each segment is exact (degree <= 2).
                let mut m = [0.0; 4];
                for w in self.breakpoints().windows(2) {
                    let (y0, y1) = (w[0], w[1]);
                    let ym = 0.5 * (y0 + y1);
                    let h = (y1 - y0) / 6.0;
                    for (y, wt) in [(y0, h), (ym, 4.0 * h), (y1, h)] {
                        let (c, x) = (self.chord_on(y, y0, y1), self.le_on(y, y0, y1));
                        m[0] += wt * c;
                        m[1] += wt * c * c;
                        m[2] += wt * x * c;
                        m[3] += wt * y * c;
                    }
                }
                m
            }
            FinOutline::Elliptical => {
                let (c, s) = (self.root_chord, self.span);
                let pi = std::f64::consts::PI;
                // ∫ c dy = π c s/4; ∫ c² dy = 2 c² s/3; ∫ x_le c dy = (c² s/2)(π/4 - 2/3);
                // ∫ y c dy = c s²/3.
                [
                    0.25 * pi * c * s,
                    2.0 / 3.0 * c * c * s,
                    0.5 * c * c * s * (0.25 * pi - 2.0 / 3.0),
                    c * s * s / 3.0,
                ]
            }
        }
    }

    /// The leading edge on the segment `[y0, y1]` (its one-sided value at a corner).
    fn le_on(&self, y: f64, y0: f64, y1: f64) -> f64 {
        match self.outline {
            FinOutline::Freeform { leading, .. } => polyline_on(leading, y, y0, y1),
            _ => self.le(y),
        }
    }

    /// The chord on the segment `[y0, y1]` (its one-sided value at a corner).
    fn chord_on(&self, y: f64, y0: f64, y1: f64) -> f64 {
        match self.outline {
            FinOutline::Freeform { leading, trailing } => {
                (polyline_on(trailing, y, y0, y1) - polyline_on(leading, y, y0, y1)).max(0.0)
            }
            _ => self.chord(y),
        }
    }

    /// Planform area of one fin, m².
    pub fn area(&self) -> f64 {
        self.moments()[0]
    }

    /// Mean aerodynamic chord and its leading edge aft of the root leading edge (module doc).
    pub fn mean_aerodynamic_chord(&self) -> (f64, f64) {
        let [a, c2, xc, _] = self.moments();
        (c2 / a, xc / a)
    }

    /// Span average of a function of the local slopes `(dx_le/dy, dx_mid/dy)`:
    /// `(1/s) ∫ g dy`, exact for the polygon (the slopes are constant per segment), by
    /// Gauss-Legendre in `y = s sin θ` for the ellipse.
    fn span_average(&self, g: impl Fn(f64, f64) -> f64) -> f64 {
        match self.outline {
            FinOutline::Trapezoidal | FinOutline::Freeform { .. } => {
                let b = self.breakpoints();
                let mut sum = 0.0;
                for w in b.windows(2) {
                    let (y0, y1) = (w[0], w[1]);
                    let dy = y1 - y0;
                    let dle = (self.le_on(y1, y0, y1) - self.le_on(y0, y0, y1)) / dy;
                    let dte = (self.le_on(y1, y0, y1) + self.chord_on(y1, y0, y1)
                        - self.le_on(y0, y0, y1)
                        - self.chord_on(y0, y0, y1))
                        / dy;
                    sum += dy * g(dle, 0.5 * (dle + dte));
                }
                sum / self.span
            }
            FinOutline::Elliptical => {
                // x_le = (c/2)(1 - cos θ) with y = s sin θ: dx_le/dy = (c/2s) tan θ; the
                // mid-chord line x = c/2 is unswept. dy = s cos θ dθ.
                let h = std::f64::consts::FRAC_PI_2 / ELLIPSE_PANELS as f64;
                let mut sum = 0.0;
                for k in 0..ELLIPSE_PANELS {
                    let mid = (k as f64 + 0.5) * h;
                    for &(x, w) in &GL16 {
                        for t in [mid - 0.5 * h * x, mid + 0.5 * h * x] {
                            let slope = 0.5 * self.root_chord / self.span * t.tan();
                            sum += 0.5 * h * w * t.cos() * g(slope, 0.0);
                        }
                    }
                }
                sum
            }
        }
    }

    /// `cos Γ_c`, the span average of the cosine of the mid-chord sweep (module doc).
    pub fn cos_mid_chord_sweep(&self) -> f64 {
        self.span_average(|_, dm| 1.0 / dm.hypot(1.0))
    }

    /// `(1/s) ∫ cos² Λ_LE dy`: the leading edge's pressure drag on its frontal area `t s`
    /// scales with the square of the cosine of its local sweep.
    pub fn mean_cos2_leading_edge(&self) -> f64 {
        self.span_average(|dl, _| 1.0 / (1.0 + dl * dl))
    }

    /// The streamwise extent `(x_min, x_max)` of the planform aft of the root leading edge.
    pub fn x_extent(&self) -> (f64, f64) {
        match self.outline {
            FinOutline::Trapezoidal => (
                self.tip_le_offset.min(0.0),
                self.root_chord.max(self.tip_le_offset + self.tip_chord),
            ),
            FinOutline::Elliptical => (0.0, self.root_chord),
            FinOutline::Freeform { leading, trailing } => (
                leading.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
                trailing
                    .iter()
                    .map(|p| p[1])
                    .fold(f64::NEG_INFINITY, f64::max),
            ),
        }
    }
}

/// `√(1 - η²)`, 0 beyond the tip.
fn root_term(eta: f64) -> f64 {
    (1.0 - eta * eta).max(0.0).sqrt()
}

/// Linear interpolation of `(y, x)` points at `y` (held beyond the ends).
fn polyline(p: &[[f64; 2]], y: f64) -> f64 {
    let Some(first) = p.first() else {
        return 0.0;
    };
    if y <= first[0] {
        return first[1];
    }
    for w in p.windows(2) {
        if y <= w[1][0] {
            let t = (y - w[0][0]) / (w[1][0] - w[0][0]);
            return w[0][1] + t * (w[1][1] - w[0][1]);
        }
    }
    p[p.len() - 1][1]
}

/// The polyline on the segment of it that covers `[y0, y1]` (a sub-interval of one of its
/// segments), evaluated at `y`: the one-sided value at a corner.
fn polyline_on(p: &[[f64; 2]], y: f64, y0: f64, y1: f64) -> f64 {
    let mid = 0.5 * (y0 + y1);
    for w in p.windows(2) {
        if mid >= w[0][0] && mid <= w[1][0] {
            let t = (y - w[0][0]) / (w[1][0] - w[0][0]);
            return w[0][1] + t * (w[1][1] - w[0][1]);
        }
    }
    polyline(p, y)
}

/// Why a freeform outline is refused (the checker reports it at the offending point).
#[derive(Clone, Debug, PartialEq)]
pub enum OutlineError {
    /// Fewer than three points.
    TooFew,
    /// The first or the last point is not on the root (`y = 0`): index of the point.
    RootNotOnBody(usize),
    /// A point between the first and the last lies on or below the root line.
    BelowRoot(usize),
    /// The chord is not single-valued per span station: the outline turns back in `y` at
    /// this point (it goes out, in and out again), or a horizontal edge lies below the tip.
    NotSingleValued(usize),
    /// The leading edge meets or passes the trailing edge at the point of this index: the
    /// outline crosses itself.
    Crosses(usize),
    /// The root chord (between the first and the last point) is zero or negative.
    RootChord,
}

/// A freeform outline from its points `(x, y)` (x aft, y outward; listed from the root leading
/// edge out to the tip and back to the root trailing edge, or the reverse). Returns the
/// outline in the root leading edge's frame (x aft of the first root point), the root chord
/// and the span, or why it cannot be a fin.
pub fn freeform(points: &[[f64; 2]]) -> Result<(FinOutline, f64, f64), OutlineError> {
    let n = points.len();
    if n < 3 {
        return Err(OutlineError::TooFew);
    }
    for k in [0, n - 1] {
        if points[k][1] != 0.0 {
            return Err(OutlineError::RootNotOnBody(k));
        }
    }
    if let Some(k) = (1..n - 1).find(|&k| points[k][1] <= 0.0) {
        return Err(OutlineError::BelowRoot(k));
    }
    // Index in the caller's order of the point at position k of the oriented list.
    let reversed = points[0][0] > points[n - 1][0];
    let idx = |k: usize| if reversed { n - 1 - k } else { k };
    let p: Vec<[f64; 2]> = if reversed {
        points.iter().rev().copied().collect()
    } else {
        points.to_vec()
    };
    let x0 = p[0][0];
    let root = p[n - 1][0] - x0;
    if root <= 0.0 {
        return Err(OutlineError::RootChord);
    }
    // Up (y strictly increasing), at most one tip edge at the maximum, down (strictly
    // decreasing).
    let span = p.iter().map(|q| q[1]).fold(0.0, f64::max);
    let top = (0..n).find(|&k| p[k][1] == span).unwrap_or(0);
    for k in 0..top {
        if p[k + 1][1] <= p[k][1] {
            return Err(OutlineError::NotSingleValued(idx(k + 1)));
        }
    }
    let mut tip_end = top;
    if top + 1 < n && p[top + 1][1] == span {
        tip_end = top + 1;
    }
    for k in tip_end..n - 1 {
        if p[k + 1][1] >= p[k][1] {
            return Err(OutlineError::NotSingleValued(idx(k + 1)));
        }
    }
    let leading: Vec<[f64; 2]> = p[..=top].iter().map(|q| [q[1], q[0] - x0]).collect();
    let trailing: Vec<[f64; 2]> = p[tip_end..]
        .iter()
        .rev()
        .map(|q| [q[1], q[0] - x0])
        .collect();
    // Simple (not self-crossing) iff the leading edge stays forward of the trailing edge
    // at every station below the tip: the difference is piecewise linear, so checking the
    // corners of both edges suffices.
    for (k, q) in p.iter().enumerate().take(n - 1).skip(1) {
        let y = q[1];
        if y >= span {
            continue;
        }
        if polyline(&trailing, y) - polyline(&leading, y) <= 0.0 {
            return Err(OutlineError::Crosses(idx(k)));
        }
    }
    if polyline(&trailing, span) < polyline(&leading, span) {
        return Err(OutlineError::Crosses(idx(top)));
    }
    Ok((FinOutline::Freeform { leading, trailing }, root, span))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edges(o: &FinOutline, s: f64, cr: f64) -> Edges<'_> {
        Edges {
            outline: o,
            span: s,
            root_chord: cr,
            tip_chord: 0.0,
            tip_le_offset: 0.0,
        }
    }

    #[test]
    fn ellipse_closed_forms_match_quadrature_of_its_edges() {
        let o = FinOutline::Elliptical;
        let e = edges(&o, 0.11, 0.17);
        // Brute-force midpoint integration in theta of the edge functions.
        let n = 200_000;
        let mut m = [0.0; 4];
        for k in 0..n {
            let t = (k as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
            let y = e.span * t.sin();
            let dy = e.span * t.cos() * std::f64::consts::FRAC_PI_2 / n as f64;
            let (c, x) = (e.chord(y), e.le(y));
            m[0] += c * dy;
            m[1] += c * c * dy;
            m[2] += x * c * dy;
            m[3] += y * c * dy;
        }
        for (a, b) in m.iter().zip(e.moments()) {
            assert!((a - b).abs() < 1e-9 * b.abs(), "{a} vs {b}");
        }
        let (mac, x) = e.mean_aerodynamic_chord();
        let pi = std::f64::consts::PI;
        assert!((mac - 8.0 * 0.17 / (3.0 * pi)).abs() < 1e-15);
        assert!((x - 0.17 * (0.5 - 4.0 / (3.0 * pi))).abs() < 1e-15);
        assert!((e.cos_mid_chord_sweep() - 1.0).abs() < 1e-14);
    }

    #[test]
    fn ellipse_leading_edge_sweep_average_matches_brute_force() {
        let o = FinOutline::Elliptical;
        let e = edges(&o, 0.11, 0.17);
        // (1/s) ∫ 1/(1 + x_le'(y)²) dy by the midpoint rule in θ (y = s sin θ).
        let n = 400_000;
        let mut sum = 0.0;
        for k in 0..n {
            let t = (k as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
            let slope = 0.5 * 0.17 / 0.11 * t.tan();
            sum += t.cos() / (1.0 + slope * slope) * std::f64::consts::FRAC_PI_2 / n as f64;
        }
        let q = e.mean_cos2_leading_edge();
        assert!((q - sum).abs() < 1e-10, "{q} vs {sum}");
        assert!(q > 0.0 && q < 1.0);
    }

    #[test]
    fn polygon_equal_to_a_trapezoid_has_its_integrals() {
        let (s, cr, ct, xt) = (0.12, 0.3, 0.1, 0.15);
        let t = Edges {
            outline: &FinOutline::Trapezoidal,
            span: s,
            root_chord: cr,
            tip_chord: ct,
            tip_le_offset: xt,
        };
        let (o, root, span) = freeform(&[[0.0, 0.0], [xt, s], [xt + ct, s], [cr, 0.0]]).unwrap();
        assert_eq!((root, span), (cr, s));
        let f = edges(&o, span, root);
        for (a, b) in t.moments().iter().zip(f.moments()) {
            assert!((a - b).abs() < 1e-16, "{a} vs {b}");
        }
        let area = 0.5 * (cr + ct) * s;
        assert!((t.area() - area).abs() < 1e-17);
        // Barrowman's closed forms.
        let mac = 2.0 / 3.0 * (cr + ct - cr * ct / (cr + ct));
        let xm = xt * (cr + 2.0 * ct) / (3.0 * (cr + ct));
        let (m, x) = f.mean_aerodynamic_chord();
        assert!((m - mac).abs() < 1e-15 && (x - xm).abs() < 1e-15);
        let gc = ((xt + 0.5 * ct - 0.5 * cr) / s).atan().cos();
        assert!((f.cos_mid_chord_sweep() - gc).abs() < 1e-15);
    }

    #[test]
    fn bad_outlines_are_refused_at_the_offending_point() {
        // Crosses itself: the trailing edge passes forward of the leading edge.
        let bow = [
            [0.0, 0.0],
            [0.2, 0.1],
            [0.0, 0.12],
            [0.05, 0.05],
            [0.3, 0.0],
        ];
        assert!(matches!(
            freeform(&bow),
            Err(OutlineError::NotSingleValued(_)) | Err(OutlineError::Crosses(_))
        ));
        let cross = [[0.0, 0.0], [0.3, 0.1], [0.1, 0.1], [0.05, 0.0]];
        assert_eq!(freeform(&cross), Err(OutlineError::Crosses(1)));
        let lifted = [[0.0, 0.01], [0.1, 0.1], [0.2, 0.0]];
        assert_eq!(freeform(&lifted), Err(OutlineError::RootNotOnBody(0)));
        let wavy = [
            [0.0, 0.0],
            [0.05, 0.1],
            [0.06, 0.05],
            [0.1, 0.12],
            [0.2, 0.0],
        ];
        assert_eq!(freeform(&wavy), Err(OutlineError::NotSingleValued(2)));
        let dip = [[0.0, 0.0], [0.05, 0.1], [0.1, 0.0], [0.2, 0.0]];
        assert_eq!(freeform(&dip), Err(OutlineError::BelowRoot(2)));
    }

    #[test]
    fn polygon_stations_include_every_corner() {
        let (o, root, span) = freeform(&[
            [0.0, 0.0],
            [0.05, 0.03],
            [0.1, 0.1],
            [0.2, 0.1],
            [0.25, 0.0],
        ])
        .unwrap();
        let e = edges(&o, span, root);
        let st = e.stations(6);
        assert_eq!(st.len(), 7);
        for b in e.breakpoints() {
            assert!(st.contains(&b), "{b} in {st:?}");
        }
        assert!(st.windows(2).all(|w| w[1] > w[0]));
    }
}
