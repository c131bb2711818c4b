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
//!   sloping of tapered regions mentioned at the end of A.2.6 is not modelled. A.2.6 takes the
//!   trailing edge unswept; [`supersonic_span_load`] generalises it to any trapezoid with a
//!   leading edge that is not swept forward (derivation there). A forward-swept leading edge
//!   is refused by the checker (`vdl::fins::forward_sweep`) for this model.

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
        "the supersonic load model needs a leading edge that is not swept forward (tan of the leading-edge sweep {tan_sweep}); the checker reports this as vdl::fins::forward_sweep"
    )]
    ForwardSweptLeadingEdge { tan_sweep: f64 },
    #[error("weights table: {0}")]
    Table(String),
}

/// Largest forward sweep of the leading edge, as tan Lambda_LE, still taken as unswept by
/// the supersonic load model (the checker refuses more, `vdl::fins::forward_sweep`). A
/// leading edge derived from a trailing-edge sweep and the taper carries rounding of this
/// order; within it the apex effect (which vanishes as Lambda_LE -> 0) is below 1e-9.
pub const FORWARD_SWEEP_TOL: f64 = 1e-9;

/// The four flow regimes of a swept, tapered fin in supersonic flow (App. A.2.6, Fig. A8),
/// classified for any trapezoid: omega is the semi-apex angle of the leading edge
/// ([`FinPlanform::tan_semi_apex`]) and the tip Mach line is the one from the tip leading
/// edge. The trailing edge's own regime is [`trailing_edge_is_subsonic`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SupersonicRegime {
    /// (a) Subsonic leading edge; the tip Mach line reaches the root (body) ahead of the
    /// trailing edge, beta s < c_r - x_t (= c_t for an unswept trailing edge, (A2.19)-(A2.21)).
    A,
    /// (b) Subsonic leading edge; the tip Mach line meets the trailing edge (A2.22)-(A2.23).
    B,
    /// (c) Supersonic leading edge; apex and tip Mach lines intersect on the fin (ahead of
    /// the trailing edge; beta < (c_r + c_t)/s for an unswept trailing edge, (A2.24)-(A2.25)).
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
    let chord = |theta: f64| p.trapezoid_chord_at(theta.cos());
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
///
/// The tip Mach line x = x_t + beta (s - y) meets the root at x_t + beta s, ahead of the root
/// trailing edge when beta s < c_r - x_t = c_t - s tan Lambda_TE. The apex Mach line
/// x = beta y meets it at y* = (x_t + beta s)/(2 beta), on the fin when
/// beta y* < c_r + y* tan Lambda_TE (for an unswept trailing edge: beta s < c_r + c_t).
pub fn supersonic_regime(p: &FinPlanform, mach: f64) -> Option<SupersonicRegime> {
    if mach < 1.0 {
        return None;
    }
    let beta = (mach * mach - 1.0).sqrt();
    let tan_omega = p.tan_semi_apex();
    let subsonic_le = beta * tan_omega < 1.0;
    let te = p.te_offset();
    let y_meet = (p.tip_le_offset + beta * p.span) / (2.0 * beta);
    Some(match (subsonic_le, beta * p.span < p.tip_chord - te) {
        (true, true) => SupersonicRegime::A,
        (true, false) => SupersonicRegime::B,
        (false, _) if beta * y_meet < p.root_chord + te * y_meet / p.span => SupersonicRegime::C,
        (false, _) => SupersonicRegime::D,
    })
}

/// Is the trailing edge subsonic at Mach `mach` (the Mach component normal to it below 1,
/// |tan Lambda_TE| > beta)? Then [`supersonic_span_load`] is an approximation (see there).
pub fn trailing_edge_is_subsonic(p: &FinPlanform, mach: f64) -> bool {
    mach < 1.0 || (p.te_offset() / p.span).abs() > (mach * mach - 1.0).sqrt()
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
        if p.tip_le_offset < -FORWARD_SWEEP_TOL * p.span {
            return Err(FinLoadError::ForwardSweptLeadingEdge {
                tan_sweep: p.tip_le_offset / p.span,
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

/// Supersonic span load of a trapezoidal fin (A.2.6 generalised to a swept trailing edge),
/// alpha = 1.
///
/// Coordinates: x aft from the root leading edge, y out along the span (0..s), the root a
/// reflection plane (the fin and its mirror image form the wing, A.2.6). Leading edge
/// x_le(y) = y tan Lambda_LE = y cot omega (x_t = s cot omega at the tip), trailing edge
/// x_te(y) = c_r + y tan Lambda_TE with s tan Lambda_TE = x_t - (c_r - c_t)
/// ([`FinPlanform::te_offset`]; 0 in the thesis).
///
/// # Derivation
///
/// 1. *Base field.* In linearised supersonic flow a point feels only the planform inside its
///    forward Mach cone. Ahead of the tip's influence, that is the wedge of the leading edge
///    and its mirror image with apex at the root leading edge, whose lifting pressure is
///    conical, Delta p(x, y) = f(y/x) (Lagerstrom 1950, NACA TR 1060: conical flows; the
///    triangular wing's field of A.2.3-A.2.4). The section load between the leading edge and
///    a chordwise station X, F(X, y) = int_{x_le}^{X} f(y/x) dx, is then homogeneous of
///    degree 1: F(X, y) = X G(y/X). A.2.3-A.2.4 give it for X = c_r, the triangle's root
///    chord: (A2.6)-(A2.7) for a subsonic leading edge (beta tan omega < 1), where
///    4 c_r tan omega / E(m) sqrt(1 - (y/B)^2), B = c_r tan omega, m = 1 - beta^2 tan^2 omega,
///    is the integral of the conical pressure 4 tan omega / (E sqrt(1 - (y/(x tan omega))^2))
///    from x_le to c_r; (A2.8)-(A2.9) for a supersonic one. Hence the section load up to ANY
///    chordwise station X is the same formula with c_r replaced by X (and B by X tan omega);
///    for (A2.9), 4 (X - y cot omega)/sqrt(beta^2 - cot^2 omega) = 4 c(y)/sqrt(...), the
///    swept Ackeret load of the local chord.
/// 2. *Trailing edge.* Where the trailing edge is supersonic (|tan Lambda_TE| < beta) no
///    point of the fin has a trailing-edge or wake point in its forward Mach cone (a Mach
///    line from a point on the fin reaches the edge's station only aft of it), so the
///    pressure ahead of the edge is that of the uncut wedge and the section load is exactly
///    F(x_te(y), y): the formulas of step 1 with c_r -> x_te(y). For the unswept trailing
///    edge of A.2.6 this is the thesis' expression, operation for operation.
///    *Approximation:* a subsonic trailing edge (|tan Lambda_TE| > beta: heavily swept at
///    low supersonic Mach) imposes the Kutta condition and unloads the region ahead of it
///    (Evvard 1950, NACA TR 951, and Lagerstrom: "subsonic trailing edges"); that upstream
///    influence is neglected here: the load is still F(x_te, y). It tends continuously to
///    the exact result as the edge becomes sonic.
/// 3. *Tip.* The tip Mach cone from the tip leading edge (x_t, s) covers, at d = s - y, the
///    part of the chord aft of x_t + beta d; the chord reaching back from x_t to the local
///    trailing edge has length L(y) = x_te(y) - x_t = c_t - d tan Lambda_TE (c_t for the
///    thesis' fin). For a streamwise tip (side edge) on an unswept leading edge the tip-cone
///    pressure is (2/pi) asin(sqrt(beta d / x')) times the 2-D value, x' = x - x_t (A2.12;
///    Evvard 1950), and integrating it over x' in [beta d, L] gives the retained fraction
///    R(beta d / L) of [`tip_retained`] over the length L, so the section loses
///    L (1 - R(beta d / L)) of the base pressure. As in (A2.18)-(A2.21) this loss is applied
///    as the fraction f_tip = L / c(y) of the chord-averaged base load:
///    base (1 - (L/c) (1 - R(beta d / L))), only where beta d < L. This is exact for an
///    unswept leading edge with a supersonic trailing edge of any sweep (the off-planform
///    region y > s is then the only non-wing part of the forward cones, as for the
///    rectangular wing, because the wake of a supersonic trailing edge is never upstream of
///    a fin point); on a swept leading edge it is the thesis' approximation (the rectangular
///    tip correction on the triangular base). With c_t = 0 (a pointed tip) and a supersonic
///    trailing edge, L <= beta d everywhere and there is no tip loss, as linear theory has it.
///    The reflection of the tip Mach line at the root (regime (a)) is, as in the thesis,
///    covered by the same single equation (A2.21) over the whole span.
/// 4. *Rectangular leading edge.* tan omega -> infinity (x_t <= 1e-9 s, see
///    [`FORWARD_SWEEP_TOL`]): the mirror images join into a straight edge, no apex cone,
///    base 4 c(y) / beta (A2.11).
///
/// The result is continuous in the trailing-edge sweep (x_te and L are linear in it, and the
/// branches of steps 1 and 3 meet continuously), and reduces bit for bit to the thesis' A.2.6
/// expressions when the trailing edge is unswept (te_offset = 0: x_te = c_r, L = c_t).
fn supersonic_span_load(p: &FinPlanform, beta: f64, eta: f64) -> f64 {
    use std::f64::consts::PI;
    let s = p.span;
    let eta_c = eta.clamp(0.0, 1.0);
    let y = eta_c * s;
    let c = p.trapezoid_chord_at(eta);
    let tan_omega = p.tan_semi_apex();
    let te = p.te_offset();
    // Step 2: the section is cut at the local trailing edge x_te(y) (= c_r when unswept).
    let x_te = p.root_chord + eta_c * te;
    let base = if !tan_omega.is_finite() || tan_omega > 1e9 {
        4.0 * c / beta.max(1e-12)
    } else {
        let bt = beta * tan_omega;
        let big_b = x_te * tan_omega;
        if bt <= 1.0 + 1e-9 {
            let m = (1.0 - bt * bt).max(0.0);
            4.0 * x_te * tan_omega / elliptic_e(m) * (1.0 - (y / big_b).powi(2)).max(0.0).sqrt()
        } else if y >= x_te / beta {
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
    // Step 3: the tip-affected length of the local chord (= c_t when unswept).
    let l_tip = p.tip_chord - (1.0 - eta_c) * te;
    let t = beta * (s - y) / l_tip;
    if l_tip <= 0.0 || t >= 1.0 {
        base
    } else {
        base * (1.0 - l_tip / c * (1.0 - tip_retained(t)))
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
