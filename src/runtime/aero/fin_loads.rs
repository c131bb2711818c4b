//! Distribution of a fin's normal force over its FE nodes (thesis 5.4.2-5.4.3, eqs.
//! (5.4.17)-(5.4.23), and App. A).
//!
//! A node is located by its non-dimensional span position eta (0 root .. 1 tip, (5.4.17)) and
//! chord position xi (0 leading edge .. 1 trailing edge of the local chord, (5.4.18)). The
//! load per unit area is taken as separable, Delta p = l(eta)/c(eta) g(xi): l is the span
//! load c c_l (per unit span) and g a chordwise profile with integral 1. In (eta, xi) the force
//! density is then s l(eta) g(xi), so the weights factor as w = a_i b_j (5.4.19)-(5.4.20),
//! K_t = K_b K_c.
//!
//! # Quadrature (our refinement of (5.4.22)-(5.4.23))
//!
//! The thesis lumps the load at the centre of each node's region of influence times its
//! length; that only approaches the continuous centre of pressure as the mesh is refined. Here
//! each node's share is the integral of the load against its linear "hat" function over the
//! two neighbouring intervals (its tributary region): for an interval [x_j, x_j+1] of length h
//! with I0 = int l and I1 = int x l, node j receives (x_j+1 I0 - I1)/h and node j+1 receives
//! (I1 - x_j I0)/h. Hats sum to 1 and reproduce x, so the weights sum to 1 and their first
//! moment equals the model's centre of pressure EXACTLY on any mesh (in eta, in xi, and,
//! because the leading edge and chord are linear in eta, in physical x too). Load outside the
//! first/last node (a mesh without root or tip nodes) goes wholly to that node. The span
//! integrals use composite 8-point Gauss-Legendre (32 panels per interval) in theta, eta =
//! cos(theta), which removes the sqrt(1 - eta) tip behaviour; the chordwise
//! integrals are exact (closed-form primitives).
//!
//! Nodes are grouped into rows of equal eta (tolerance 1e-9); each row gets its own chordwise
//! hats, so structured meshes with different chordwise spacing per row are handled. Nodes at
//! the same (eta, xi) share their weight equally.
//!
//! # Load models
//!
//! - Subsonic (M < 1): span load from Prandtl's lifting line by the Fourier sine series of
//!   A.1.1, (A1.1)-(A1.10), with the odd coefficients A1, A3, A5, A7 collocated at
//!   theta = pi/8, pi/4, 3pi/8, pi/2 (symmetric profile). Chordwise: the flat-plate thin-airfoil
//!   loading g = (2/pi) sqrt((1 - xi)/xi), whose centre of pressure is the quarter chord
//!   (A.1.1, "chordwise distribution").
//! - Supersonic (M >= 1): span load from linear wing theory, A.2 (A2.1)-(A2.26), in the four
//!   regimes of A.2.6 (see [`SupersonicRegime`]); chordwise uniform, the Ackeret flat-plate
//!   loading Delta p = 4 alpha / beta (A2.10), centre of pressure at half chord. The chordwise
//!   sloping of tapered regions mentioned at the end of A.2.6 is not modelled.

use crate::check::ir::Distribution;

use super::estimator::FinPlanform;

/// How a fin's load is spread: App. A theory, or uniform over the nodes.
pub type FinLoadModel = Distribution;

/// A fin FE node in non-dimensional fin coordinates (5.4.17)-(5.4.18).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FinNode {
    /// Span position, 0 at the root chord, 1 at the tip chord.
    pub eta: f64,
    /// Chord position, 0 at the local leading edge, 1 at the trailing edge.
    pub xi: f64,
}

/// Errors of the load distribution.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FinLoadError {
    #[error("fin node {index}: (eta, xi) = ({eta}, {xi}) is outside the fin [0, 1] x [0, 1]")]
    NodeOutside { index: usize, eta: f64, xi: f64 },
    #[error("fin load distribution needs at least one node")]
    NoNodes,
    #[error("Mach number {0} is not a finite non-negative number")]
    BadMach(f64),
    #[error("the subsonic Fourier system (A1.8) is singular")]
    SingularFourierSystem,
    #[error(
        "App. A.2.6 assumes an unswept trailing edge: tip leading-edge offset {offset} m differs from root minus tip chord {expected} m"
    )]
    SweptTrailingEdge { offset: f64, expected: f64 },
    #[error("weights table: {0}")]
    Table(String),
}

/// The four flow regimes of a swept, tapered fin in supersonic flow (App. A.2.6, Fig. A8).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SupersonicRegime {
    /// (a) Subsonic leading edge; the tip Mach line reaches the root (body) ahead of the
    /// trailing edge, beta s < c_t (A2.19)-(A2.21).
    A,
    /// (b) Subsonic leading edge; the tip Mach line meets the trailing edge (A2.22)-(A2.23).
    B,
    /// (c) Supersonic leading edge; apex and tip Mach lines intersect on the fin,
    /// beta < (c_r + c_t)/s (A2.24)-(A2.25).
    C,
    /// (d) Supersonic leading edge; no intersection on the fin (A2.26).
    D,
}

/// Section lift-curve slope used in mu of (A1.5): thin-airfoil 2 pi per rad. (The OCR writes
/// mu = c a_inf/(8 s) = c C_Nalpha/(8 s); Glauert's lifting-line equation (A1.3) uses the
/// SECTION slope a_inf, so we take a_inf = 2 pi.)
const SECTION_LIFT_SLOPE: f64 = 2.0 * std::f64::consts::PI;

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

/// Composite 8-point Gauss-Legendre of f over [a, b] with `panels` panels.
fn gauss(a: f64, b: f64, panels: usize, f: &mut impl FnMut(f64) -> f64) -> f64 {
    let h = (b - a) / panels as f64;
    let mut sum = 0.0;
    for p in 0..panels {
        let mid = a + (p as f64 + 0.5) * h;
        for (x, w) in GL8_X.iter().zip(GL8_W) {
            sum += w * (f(mid - 0.5 * h * x) + f(mid + 0.5 * h * x));
        }
    }
    sum * 0.5 * h
}

/// int_lo^hi f(eta) d eta with eta = cos(theta): the span loads behave like sqrt(1 - eta) at
/// the tip (Fourier series (A1.1), tip cone (A2.14)), which is smooth in theta.
fn span_integral(lo: f64, hi: f64, panels: usize, f: &mut impl FnMut(f64) -> f64) -> f64 {
    let (t_lo, t_hi) = (hi.clamp(0.0, 1.0).acos(), lo.clamp(0.0, 1.0).acos());
    gauss(t_lo, t_hi, panels, &mut |t: f64| f(t.cos()) * t.sin())
}

/// Complete elliptic integral of the second kind E(m) = int_0^{pi/2} sqrt(1 - m sin^2) (A2.5),
/// 0 <= m <= 1 (smooth integrand: Gauss-Legendre to ~1e-14).
pub fn elliptic_e(m: f64) -> f64 {
    gauss(0.0, std::f64::consts::FRAC_PI_2, 16, &mut |t: f64| {
        (1.0 - m * t.sin().powi(2)).max(0.0).sqrt()
    })
}

/// Odd Fourier coefficients [A1, A3, A5, A7] of the span load for alpha = 1 rad, eqs.
/// (A1.4)-(A1.10): mu alpha sin(theta) = sum A_n sin(n theta) (sin(theta) + n mu) at
/// theta = pi/8, pi/4, 3pi/8, pi/2, with mu = c(theta) a_inf / (8 s) (A1.5).
///
/// The span station is eta = cos(theta) (from z = -s cos theta (A1.6) on the mirrored half:
/// theta = pi/2 at the root, 0 at the tip). The chord is the linear taper
/// c = c_r (1 - (1 - lambda) cos theta), lambda = c_t/c_r; the OCR's "c_r (1 - lambda) cos
/// theta + c_r" has a sign slip (it would make the tip chord larger than the root).
pub fn subsonic_fourier_coefficients(p: &FinPlanform) -> Result<[f64; 4], FinLoadError> {
    let chord = |theta: f64| p.chord_at(theta.cos());
    fourier_coefficients(p.span, &chord)
}

/// (A1.8)-(A1.10) for any chord law `chord(theta)`; used by tests with elliptic chords.
fn fourier_coefficients(span: f64, chord: &dyn Fn(f64) -> f64) -> Result<[f64; 4], FinLoadError> {
    use std::f64::consts::PI;
    let thetas = [PI / 8.0, PI / 4.0, 3.0 * PI / 8.0, PI / 2.0];
    let mut a = [[0.0f64; 5]; 4];
    for (row, &th) in thetas.iter().enumerate() {
        let mu = chord(th) * SECTION_LIFT_SLOPE / (8.0 * span);
        for (col, n) in [1.0, 3.0, 5.0, 7.0].iter().enumerate() {
            a[row][col] = (n * th).sin() * (th.sin() + n * mu);
        }
        a[row][4] = mu * th.sin();
    }
    // Gaussian elimination with partial pivoting on the augmented 4x5 matrix.
    for k in 0..4 {
        let piv = (k..4)
            .max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))
            .unwrap_or(k);
        if a[piv][k].abs() < 1e-14 {
            return Err(FinLoadError::SingularFourierSystem);
        }
        a.swap(k, piv);
        let pivot_row = a[k];
        for row in a.iter_mut().skip(k + 1) {
            let f = row[k] / pivot_row[k];
            for (x, p) in row.iter_mut().zip(pivot_row).skip(k) {
                *x -= f * p;
            }
        }
    }
    let mut x = [0.0; 4];
    for k in (0..4).rev() {
        let s: f64 = (k + 1..4).map(|j| a[k][j] * x[j]).sum();
        x[k] = (a[k][4] - s) / a[k][k];
    }
    Ok(x)
}

/// The supersonic regime of A.2.6 at Mach `mach` > 1 (None when subsonic).
pub fn supersonic_regime(p: &FinPlanform, mach: f64) -> Option<SupersonicRegime> {
    if mach < 1.0 {
        return None;
    }
    let beta = (mach * mach - 1.0).sqrt();
    let tan_omega = p.tan_semi_apex();
    let subsonic_le = beta * tan_omega < 1.0;
    Some(match (subsonic_le, beta * p.span < p.tip_chord) {
        (true, true) => SupersonicRegime::A,
        (true, false) => SupersonicRegime::B,
        (false, _) if beta * p.span < p.root_chord + p.tip_chord => SupersonicRegime::C,
        (false, _) => SupersonicRegime::D,
    })
}

/// Span-load shape at Mach `mach` and span fraction `eta`, for alpha = 1 (arbitrary scale).
pub struct SpanLoad {
    kind: SpanLoadKind,
}

enum SpanLoadKind {
    Subsonic([f64; 4]),
    Supersonic { p: FinPlanform, beta: f64 },
}

impl SpanLoad {
    /// Prepares the span-load model for a planform and Mach number.
    pub fn new(p: &FinPlanform, mach: f64) -> Result<Self, FinLoadError> {
        if !(mach.is_finite() && mach >= 0.0) {
            return Err(FinLoadError::BadMach(mach));
        }
        if mach < 1.0 {
            return Ok(SpanLoad {
                kind: SpanLoadKind::Subsonic(subsonic_fourier_coefficients(p)?),
            });
        }
        let expected = p.root_chord - p.tip_chord;
        if (p.tip_le_offset - expected).abs() > 1e-6 * p.root_chord {
            return Err(FinLoadError::SweptTrailingEdge {
                offset: p.tip_le_offset,
                expected,
            });
        }
        Ok(SpanLoad {
            kind: SpanLoadKind::Supersonic {
                p: p.clone(),
                beta: (mach * mach - 1.0).sqrt(),
            },
        })
    }

    /// The span load l(eta) (c c_l per unit alpha, arbitrary common scale).
    pub fn at(&self, eta: f64) -> f64 {
        match &self.kind {
            // Gamma = 4 s V sum A_n sin(n theta) (A1.1), theta = acos(eta).
            SpanLoadKind::Subsonic(a) => {
                let th = eta.clamp(0.0, 1.0).acos();
                a[0] * th.sin()
                    + a[1] * (3.0 * th).sin()
                    + a[2] * (5.0 * th).sin()
                    + a[3] * (7.0 * th).sin()
            }
            SpanLoadKind::Supersonic { p, beta } => supersonic_span_load(p, *beta, eta),
        }
    }
}

/// Retained fraction of the 2-D section load in the tip Mach cone of a rectangular wing,
/// (A2.14): R(t) = (1/pi) acos(1 - 2t) + (2/pi) sqrt(t - t^2), t = beta (s - y)/c.
/// (The OCR of (A2.21)-(A2.26) prints "+ (2/pi) sqrt" inside the LOST bracket 1 - [...];
/// consistency with (A2.14), which we re-derived by integrating the tip-cone pressure
/// (2/pi) asin(sqrt(beta d/x)) (A2.12) over the chord, gives the lost part 1 - R(t).)
fn tip_retained(t: f64) -> f64 {
    use std::f64::consts::PI;
    let t = t.clamp(0.0, 1.0);
    (1.0 - 2.0 * t).acos() / PI + 2.0 / PI * (t - t * t).max(0.0).sqrt()
}

/// Supersonic span load of a swept, tapered fin with unswept trailing edge (A.2.6), alpha = 1.
///
/// The fin is the generating triangle (apex at the root leading edge, semi-apex angle omega
/// with tan omega = s/(c_r - c_t), semispan B = c_r tan omega) cut at the tip chord. Its base
/// section load is
/// - subsonic leading edge (beta tan omega < 1): (A2.6)-(A2.7),
///   4 c_r tan omega / E(m) sqrt(1 - (y/B)^2) with m = 1 - beta^2 tan^2 omega (on the trailing
///   edge tan v / tan omega = y/B);
/// - supersonic leading edge: (A2.8) for y <= c_r/beta and (A2.9) beyond. In (A2.6)-(A2.9) "b"
///   is the triangle semispan B (then (A2.9) is 4 c(y)/sqrt(beta^2 - cot^2 omega), and (A2.8)
///   meets (A2.9) continuously at y = c_r/beta; a tested identity).
///
/// Tip effect, (A2.21)-(A2.26): for y >= s - c_t/beta the base is multiplied by
/// 1 - f_tip (1 - R(t)), t = beta (s - y)/c_t, f_tip = c_t / c(y) (A2.18) (the tip-affected
/// length of the local chord equals that of a rectangular fin of chord c_t because the trailing
/// edge is unswept). In regime (a) the reflected tip Mach line is, as in the thesis, covered by
/// the same single equation (A2.21) over the whole span. A rectangular fin (c_r = c_t) is the
/// limit tan omega -> infinity: base 4 c/beta (A2.11).
fn supersonic_span_load(p: &FinPlanform, beta: f64, eta: f64) -> f64 {
    use std::f64::consts::PI;
    let s = p.span;
    let y = eta.clamp(0.0, 1.0) * s;
    let c = p.chord_at(eta);
    let tan_omega = p.tan_semi_apex();
    let base = if !tan_omega.is_finite() || tan_omega > 1e9 {
        4.0 * c / beta.max(1e-12)
    } else {
        let bt = beta * tan_omega;
        let big_b = p.root_chord * tan_omega;
        if bt <= 1.0 + 1e-9 {
            let m = (1.0 - bt * bt).max(0.0);
            4.0 * p.root_chord * tan_omega / elliptic_e(m)
                * (1.0 - (y / big_b).powi(2)).max(0.0).sqrt()
        } else if y >= p.root_chord / beta {
            // (A2.9): 4 (B - y) cot(omega) / sqrt(beta^2 - cot^2 omega)
            let cot = 1.0 / tan_omega;
            4.0 * (big_b - y) * cot / (beta * beta - cot * cot).sqrt()
        } else {
            // (A2.8)
            let b2 = beta * beta * tan_omega * tan_omega;
            let a1 = ((y * b2 - big_b) / ((big_b - y) * bt))
                .clamp(-1.0, 1.0)
                .asin();
            let a2 = ((y * b2 + big_b) / ((big_b + y) * bt))
                .clamp(-1.0, 1.0)
                .asin();
            4.0 / (b2 - 1.0).sqrt() * (big_b + (big_b - y) / PI * a1 - (big_b + y) / PI * a2)
        }
    };
    let t = beta * (s - y) / p.tip_chord;
    if t >= 1.0 {
        base
    } else {
        base * (1.0 - p.tip_chord / c * (1.0 - tip_retained(t)))
    }
}

/// Chordwise primitives (P0, P1) = (int_0^xi g, int_0^xi x g) of the chordwise profile.
fn chord_primitives(supersonic: bool, xi: f64) -> (f64, f64) {
    use std::f64::consts::PI;
    let xi = xi.clamp(0.0, 1.0);
    if supersonic {
        (xi, 0.5 * xi * xi)
    } else {
        // g = (2/pi) sqrt((1-xi)/xi); with xi = (1 - cos phi)/2, g dxi = (1 + cos phi) dphi/pi
        // and xi g dxi = sin^2(phi) dphi / (2 pi).
        let phi = (1.0 - 2.0 * xi).acos();
        (
            (phi + phi.sin()) / PI,
            (phi / 2.0 - (2.0 * phi).sin() / 4.0) / (2.0 * PI),
        )
    }
}

/// Hat-function shares of the load with interval integrals `integrals(a, b) = (I0, I1)` for
/// sorted distinct nodes `x` on [0, 1]; written into `out`.
fn hat_shares(x: &[f64], integrals: &mut impl FnMut(f64, f64) -> (f64, f64), out: &mut [f64]) {
    out.iter_mut().for_each(|v| *v = 0.0);
    let n = x.len();
    if n == 1 {
        out[0] = integrals(0.0, 1.0).0;
        return;
    }
    if x[0] > 0.0 {
        out[0] += integrals(0.0, x[0]).0;
    }
    for j in 0..n - 1 {
        let (i0, i1) = integrals(x[j], x[j + 1]);
        let h = x[j + 1] - x[j];
        out[j] += (x[j + 1] * i0 - i1) / h;
        out[j + 1] += (i1 - x[j] * i0) / h;
    }
    if x[n - 1] < 1.0 {
        out[n - 1] += integrals(x[n - 1], 1.0).0;
    }
}

/// Distinct sorted values (tolerance `tol`) and, for each input, its group index.
fn group(values: &[f64], tol: f64) -> (Vec<f64>, Vec<usize>) {
    let mut sorted: Vec<f64> = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let mut distinct: Vec<f64> = Vec::new();
    for v in sorted {
        if distinct.last().is_none_or(|&d| v - d > tol) {
            distinct.push(v);
        }
    }
    let idx = values
        .iter()
        .map(|&v| {
            distinct
                .partition_point(|&d| d < v - tol)
                .min(distinct.len() - 1)
        })
        .collect();
    (distinct, idx)
}

const GROUP_TOL: f64 = 1e-9;

/// Nodal weights w_k (sum 1) so that a fin normal force F acts as F w_k on node k
/// (5.4.19)-(5.4.23); see the module doc for the models and the quadrature.
pub fn nodal_weights(
    p: &FinPlanform,
    nodes: &[FinNode],
    mach: f64,
    model: FinLoadModel,
) -> Result<Vec<f64>, FinLoadError> {
    if nodes.is_empty() {
        return Err(FinLoadError::NoNodes);
    }
    for (index, n) in nodes.iter().enumerate() {
        let ok = |v: f64| v.is_finite() && (-GROUP_TOL..=1.0 + GROUP_TOL).contains(&v);
        if !ok(n.eta) || !ok(n.xi) {
            return Err(FinLoadError::NodeOutside {
                index,
                eta: n.eta,
                xi: n.xi,
            });
        }
    }
    if model == Distribution::Uniform {
        return Ok(vec![1.0 / nodes.len() as f64; nodes.len()]);
    }
    let load = SpanLoad::new(p, mach)?;
    let supersonic = mach >= 1.0;
    let etas: Vec<f64> = nodes.iter().map(|n| n.eta.clamp(0.0, 1.0)).collect();
    let (rows, row_of) = group(&etas, GROUP_TOL);
    let mut a = vec![0.0; rows.len()];
    hat_shares(
        &rows,
        &mut |lo, hi| {
            let i0 = span_integral(lo, hi, 32, &mut |e| load.at(e));
            let i1 = span_integral(lo, hi, 32, &mut |e| e * load.at(e));
            (i0, i1)
        },
        &mut a,
    );
    let mut w = vec![0.0; nodes.len()];
    for (r, _) in rows.iter().enumerate() {
        let members: Vec<usize> = (0..nodes.len()).filter(|&k| row_of[k] == r).collect();
        let xis: Vec<f64> = members
            .iter()
            .map(|&k| nodes[k].xi.clamp(0.0, 1.0))
            .collect();
        let (cols, col_of) = group(&xis, GROUP_TOL);
        let mut b = vec![0.0; cols.len()];
        hat_shares(
            &cols,
            &mut |lo, hi| {
                let (p0a, p1a) = chord_primitives(supersonic, lo);
                let (p0b, p1b) = chord_primitives(supersonic, hi);
                (p0b - p0a, p1b - p1a)
            },
            &mut b,
        );
        let mut multiplicity = vec![0usize; cols.len()];
        col_of.iter().for_each(|&c| multiplicity[c] += 1);
        for (m, &k) in members.iter().enumerate() {
            let c = col_of[m];
            w[k] = a[r] * b[c] / multiplicity[c] as f64;
        }
    }
    let total: f64 = w.iter().sum();
    Ok(w.into_iter().map(|v| v / total).collect())
}

/// The model's centre of pressure (eta_cp, xi_cp) at Mach `mach`: eta_cp = int eta l / int l
/// (2000 Gauss panels), xi_cp = 1/4 subsonic (thin airfoil) and 1/2 supersonic (Ackeret).
pub fn centre_of_pressure(p: &FinPlanform, mach: f64) -> Result<(f64, f64), FinLoadError> {
    let load = SpanLoad::new(p, mach)?;
    let i0 = span_integral(0.0, 1.0, 2000, &mut |e| load.at(e));
    let i1 = span_integral(0.0, 1.0, 2000, &mut |e| e * load.at(e));
    Ok((i1 / i0, if mach >= 1.0 { 0.5 } else { 0.25 }))
}

/// Nodal weights precomputed on a Mach grid; [`Self::weights_at`] interpolates linearly in
/// Mach (clamped to the grid) into a caller buffer, without allocating. Linear interpolation
/// keeps the sum 1 and moves the centre of pressure linearly between grid Machs.
#[derive(Clone, Debug, PartialEq)]
pub struct FinLoadTable {
    machs: Vec<f64>,
    n_nodes: usize,
    /// Row-major: weights of Mach i at [i * n_nodes ..].
    weights: Vec<f64>,
}

impl FinLoadTable {
    /// Computes the weights at every Mach of `machs` (strictly increasing).
    pub fn new(
        p: &FinPlanform,
        nodes: &[FinNode],
        machs: &[f64],
        model: FinLoadModel,
    ) -> Result<Self, FinLoadError> {
        if machs.is_empty()
            || machs
                .windows(2)
                .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
        {
            return Err(FinLoadError::Table(
                "Mach grid must be non-empty and strictly increasing".into(),
            ));
        }
        let mut weights = Vec::with_capacity(machs.len() * nodes.len());
        for &m in machs {
            weights.extend(nodal_weights(p, nodes, m, model)?);
        }
        Ok(FinLoadTable {
            machs: machs.to_vec(),
            n_nodes: nodes.len(),
            weights,
        })
    }

    /// A table from weights computed before (the cache): `weights[i * n_nodes + k]` is node
    /// k's weight at `machs[i]`. Checks the shape and the grid, not the values.
    pub fn from_weights(
        machs: Vec<f64>,
        n_nodes: usize,
        weights: Vec<f64>,
    ) -> Result<Self, FinLoadError> {
        if machs.is_empty()
            || machs
                .windows(2)
                .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
            || weights.len() != machs.len() * n_nodes
            || n_nodes == 0
        {
            return Err(FinLoadError::Table(format!(
                "{} weights for {} Machs x {n_nodes} nodes, or a Mach grid that is not strictly increasing",
                weights.len(),
                machs.len()
            )));
        }
        Ok(FinLoadTable {
            machs,
            n_nodes,
            weights,
        })
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.n_nodes
    }

    /// All weights, row-major by Mach.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The Mach grid of the table.
    pub fn machs(&self) -> &[f64] {
        &self.machs
    }

    /// The weights at grid Mach `i` (empty past the grid).
    pub fn grid_weights(&self, i: usize) -> &[f64] {
        self.weights
            .get(i * self.n_nodes..(i + 1) * self.n_nodes)
            .unwrap_or(&[])
    }

    /// Interpolation bracket at `mach` (clamped to the grid): the weights there are
    /// `(1 - t) w_i + t w_(i+1)` (`t = 0` on a one-point grid).
    pub fn bracket(&self, mach: f64) -> Result<(usize, f64), FinLoadError> {
        if !mach.is_finite() {
            return Err(FinLoadError::BadMach(mach));
        }
        let m = mach.clamp(self.machs[0], self.machs[self.machs.len() - 1]);
        if self.machs.len() == 1 {
            return Ok((0, 0.0));
        }
        let upper = self
            .machs
            .partition_point(|&x| x <= m)
            .clamp(1, self.machs.len() - 1);
        let i = upper - 1;
        Ok((i, (m - self.machs[i]) / (self.machs[i + 1] - self.machs[i])))
    }

    /// Weights at `mach` into `out` (length = number of nodes).
    pub fn weights_at(&self, mach: f64, out: &mut [f64]) -> Result<(), FinLoadError> {
        if out.len() != self.n_nodes {
            return Err(FinLoadError::Table(format!(
                "buffer of {} for {} nodes",
                out.len(),
                self.n_nodes
            )));
        }
        let (i, t) = self.bracket(mach)?;
        let n = self.n_nodes;
        for (k, o) in out.iter_mut().enumerate() {
            let lo = self.weights[i * n + k];
            *o = if t == 0.0 {
                lo
            } else {
                (1.0 - t) * lo + t * self.weights[(i + 1) * n + k]
            };
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "fin_loads_tests.rs"]
mod tests;
