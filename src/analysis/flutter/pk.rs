//! The p-k and k methods of flutter analysis on generalised coordinates.
//!
//! # Equations
//!
//! Generalised coordinates `η` (modal or physical), generalised mass `M`, stiffness `K`,
//! viscous damping `B`, structural (hysteretic) damping `g_s`, and the generalised
//! aerodynamic forces of harmonic motion `q Q(k) η` (`q = ρV²/2`, `k = ω b / V`, `b` the
//! reference semichord), `Q` tabulated or evaluated in `k` ([`Gaf`]):
//!
//! `M η̈ + B η̇ + (1 + i g_s) K η = q Q(k) η`.
//!
//! # The p-k method (Hassig, "An approximate true damping solution of the flutter equation by
//! determinant iteration", J. Aircraft 8(11), 1971, 885-889; Rodden & Johnson, *MSC/NASTRAN
//! Aeroelastic Analysis User's Guide*, 1994, §2.6, "PK method")
//!
//! The aerodynamic matrix is split into the part in phase with displacement and the part in
//! phase with velocity, `i Q^I η = (b / (k V)) Q^I η̇` for harmonic motion at `ω = k V / b`,
//! so that at a given `k` the equation is a real second-order system (Rodden & Johnson's
//! `[M p² + (B - ρ c̄ V Q^I / (4k)) p + (K - q Q^R)] u = 0` with `c̄ = 2b`; the hysteretic
//! term `i g_s K` is taken the same way, `g_s b/(kV) K η̇`):
//!
//! `M η̈ + [B + (g_s b/(kV)) K - (q b/(kV)) Q^I(k)] η̇ + [K - q Q^R(k)] η = 0`.
//!
//! faer 0.24 is used for the standard eigenproblem of its first-order form: the generalised
//! problem is reduced with `M⁻¹` (LU), `A = [[0, I], [-M⁻¹ K̃, -M⁻¹ B̃]]`, eigenvalues
//! `p = ω (γ ± i)`. For each mode the reduced frequency is iterated until the `k` of its root,
//! `k = Im(p) b / V`, matches the `k` at which `Q` was evaluated (Hassig's consistency
//! condition; fixed point, with a bracketing fallback, tolerance [`PkSettings::k_tolerance`]). The damping
//! is reported as `g = 2γ = 2 Re(p)/Im(p)` (Rodden & Johnson's convention), and the roots are
//! tracked from speed to speed by continuation: each mode starts from the linear prediction
//! of its converged roots at the two previous speeds (at the second speed from the root at
//! the first, at the first from `i ω_j` of the vacuum modes).
//!
//! # Flutter and divergence points
//!
//! A flutter point is where the damping of a mode crosses zero from below: bracketed between
//! two speeds of the sweep, it is located by Brent's method on `g(V)` (each evaluation is a
//! full p-k solution at `V`, started from the linear interpolation of the bracket's roots), not picked
//! from the grid. The coalescing partner is the other mode whose frequency is nearest at the
//! flutter speed. The divergence point is the zero-frequency root: `det(K - q Q^R(0)) = 0`,
//! `q_D = 1/λ_max`, `λ` the largest positive real eigenvalue of `K⁻¹ Q^R(0)`.
//!
//! # The k method (V-g method; Rodden & Johnson §2.6 "K method")
//!
//! Artificial structural damping `g` makes harmonic motion possible at every `k`:
//! `[-ω² M + (1 + i g) K - q Q(k)] η = 0` with `q = ρ ω² b² / (2 k²)`, i.e.
//! `K⁻¹ [M + (ρ b² / (2 k²)) Q(k)] η = ((1 + i g)/ω²) η`: an eigenvalue `μ` gives
//! `ω = 1/sqrt(Re μ)`, `g = Im μ / Re μ`, `V = ω b / k`. At `g = 0` the k and p-k methods solve
//! the same equation, so their flutter points coincide (tested).

use faer::linalg::solvers::Solve;
use faer::{Mat, c64};

/// A generalised aerodynamic force matrix as a function of reduced frequency: generalised
/// forces `q Q(k) η` for harmonic motion `η e^{iωt}`, `k = ω b / V`.
pub trait Gaf {
    /// Number of generalised coordinates.
    fn order(&self) -> usize;
    /// The reduced frequencies where `Q` is defined (inclusive).
    fn k_range(&self) -> (f64, f64);
    /// `Q(k)`, row-major `order x order`, written to `out`.
    fn eval(&self, k: f64, out: &mut [c64]);
}

/// A GAF evaluated by a function of `k` (analytic aerodynamics such as Theodorsen's).
pub struct GafFn<F: Fn(f64, &mut [c64])> {
    pub order: usize,
    pub k_max: f64,
    pub f: F,
}

impl<F: Fn(f64, &mut [c64])> Gaf for GafFn<F> {
    fn order(&self) -> usize {
        self.order
    }
    fn k_range(&self) -> (f64, f64) {
        (0.0, self.k_max)
    }
    fn eval(&self, k: f64, out: &mut [c64]) {
        (self.f)(k, out)
    }
}

/// `Q(k)` tabulated at increasing reduced frequencies and interpolated between them by a
/// natural cubic spline of each real and imaginary part (the MSC Nastran "surface spline"
/// option interpolates `Q` smoothly in `k` for the same reason: the p-k iteration needs `Q`
/// between the tabulated points).
#[derive(Clone, Debug, PartialEq)]
pub struct GafTable {
    order: usize,
    ks: Vec<f64>,
    /// `ks.len()` matrices, row-major.
    values: Vec<c64>,
    /// Second derivatives of the spline at the knots, same layout.
    second: Vec<c64>,
}

impl GafTable {
    /// A table from matrices `values[i]` (row-major `order x order`) at `ks[i]`; at least two
    /// strictly increasing, finite `k >= 0`.
    pub fn new(
        order: usize,
        ks: Vec<f64>,
        values: Vec<Vec<c64>>,
    ) -> Result<GafTable, FlutterError> {
        if ks.len() < 2 || ks.len() != values.len() {
            return Err(FlutterError::BadModel(format!(
                "a GAF table needs at least two reduced frequencies, one matrix each (got {} and {})",
                ks.len(),
                values.len()
            )));
        }
        if ks.iter().any(|k| !(k.is_finite() && *k >= 0.0)) || ks.windows(2).any(|w| w[1] <= w[0]) {
            return Err(FlutterError::BadModel(
                "GAF table reduced frequencies must be finite, >= 0 and strictly increasing".into(),
            ));
        }
        let nn = order * order;
        if values
            .iter()
            .any(|v| v.len() != nn || v.iter().any(|z| !(z.re.is_finite() && z.im.is_finite())))
        {
            return Err(FlutterError::BadModel(format!(
                "every GAF table matrix must be {order} x {order} and finite"
            )));
        }
        let m = ks.len();
        let flat: Vec<c64> = values.into_iter().flatten().collect();
        // Natural cubic spline per entry (tridiagonal solve, Thomas algorithm).
        let mut second = vec![c64::new(0.0, 0.0); m * nn];
        if m > 2 {
            let mut diag = vec![0.0; m];
            let mut upper = vec![0.0; m];
            let mut rhs = vec![c64::new(0.0, 0.0); m];
            for e in 0..nn {
                for i in 1..m - 1 {
                    let h0 = ks[i] - ks[i - 1];
                    let h1 = ks[i + 1] - ks[i];
                    diag[i] = 2.0 * (h0 + h1);
                    upper[i] = h1;
                    rhs[i] = (flat[(i + 1) * nn + e] - flat[i * nn + e]) * (6.0 / h1)
                        - (flat[i * nn + e] - flat[(i - 1) * nn + e]) * (6.0 / h0);
                }
                // Forward sweep on rows 1..m-1 (sub-diagonal h0 of row i).
                for i in 2..m - 1 {
                    let w = (ks[i] - ks[i - 1]) / diag[i - 1];
                    diag[i] -= w * upper[i - 1];
                    let r = rhs[i - 1];
                    rhs[i] -= r * w;
                }
                let mut s = vec![c64::new(0.0, 0.0); m];
                for i in (1..m - 1).rev() {
                    let next = if i + 1 < m - 1 {
                        s[i + 1]
                    } else {
                        c64::new(0.0, 0.0)
                    };
                    s[i] = (rhs[i] - next * upper[i]) / diag[i];
                }
                for i in 0..m {
                    second[i * nn + e] = s[i];
                }
            }
        }
        Ok(GafTable {
            order,
            ks,
            values: flat,
            second,
        })
    }

    /// The number of generalised coordinates.
    pub fn order(&self) -> usize {
        self.order
    }

    /// The tabulated reduced frequencies.
    pub fn ks(&self) -> &[f64] {
        &self.ks
    }

    /// The matrix at knot `i`.
    pub fn at(&self, i: usize) -> &[c64] {
        let nn = self.order * self.order;
        &self.values[i * nn..(i + 1) * nn]
    }
}

impl Gaf for GafTable {
    fn order(&self) -> usize {
        self.order
    }
    fn k_range(&self) -> (f64, f64) {
        (self.ks[0], *self.ks.last().unwrap_or(&self.ks[0]))
    }
    fn eval(&self, k: f64, out: &mut [c64]) {
        let nn = self.order * self.order;
        let m = self.ks.len();
        // Interval i with ks[i] <= k <= ks[i+1] (clamped to the end intervals; the solver
        // checks the range before it asks).
        let i = match self.ks.iter().rposition(|&x| x <= k) {
            Some(i) => i.min(m - 2),
            None => 0,
        };
        let (x0, x1) = (self.ks[i], self.ks[i + 1]);
        let h = x1 - x0;
        let a = (x1 - k) / h;
        let b = (k - x0) / h;
        let ca = (a * a * a - a) * h * h / 6.0;
        let cb = (b * b * b - b) * h * h / 6.0;
        for (e, o) in out.iter_mut().enumerate().take(nn) {
            *o = self.values[i * nn + e] * a
                + self.values[(i + 1) * nn + e] * b
                + self.second[i * nn + e] * ca
                + self.second[(i + 1) * nn + e] * cb;
        }
    }
}

/// Why a flutter solution failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FlutterError {
    #[error("flutter model: {0}")]
    BadModel(String),
    #[error("the generalised mass matrix is singular")]
    SingularMass,
    #[error("the generalised stiffness matrix is singular (a free or mechanism mode): {0}")]
    SingularStiffness(&'static str),
    #[error("the eigenvalue solver failed at V = {speed:.3} m/s")]
    Eigen { speed: f64 },
    #[error(
        "mode {mode} at V = {speed:.3} m/s needs reduced frequency k = {k:.4}, outside the tabulated range {lo}..{hi}"
    )]
    KOutOfRange {
        mode: usize,
        speed: f64,
        k: f64,
        lo: f64,
        hi: f64,
    },
    #[error(
        "the p-k iteration of mode {mode} did not converge at V = {speed:.3} m/s (last k = {k:.4})"
    )]
    NoConvergence { mode: usize, speed: f64, k: f64 },
    #[error("speeds must be finite, positive and strictly increasing")]
    BadSpeeds,
}

/// The structural side of a flutter problem and the air it flies in.
#[derive(Clone, Debug, PartialEq)]
pub struct FlutterModel {
    /// Names of the generalised coordinates (e.g. "plunge", "pitch", "mode 3 (bending)").
    pub names: Vec<String>,
    /// Generalised mass, row-major `n x n`.
    pub mass: Vec<f64>,
    /// Generalised stiffness, row-major `n x n`.
    pub stiffness: Vec<f64>,
    /// Viscous generalised damping, row-major `n x n`.
    pub damping: Vec<f64>,
    /// Structural (hysteretic) damping `g_s` multiplying `K`.
    pub structural_g: f64,
    /// Reference semichord `b` of the reduced frequency `k = ω b / V`, m.
    pub b_ref: f64,
    /// Air density, kg/m³.
    pub density: f64,
}

impl FlutterModel {
    pub fn order(&self) -> usize {
        self.names.len()
    }

    fn validate(&self, gaf: &dyn Gaf) -> Result<(), FlutterError> {
        let n = self.order();
        if n == 0 {
            return Err(FlutterError::BadModel("no generalised coordinates".into()));
        }
        for (what, m) in [
            ("mass", &self.mass),
            ("stiffness", &self.stiffness),
            ("damping", &self.damping),
        ] {
            if m.len() != n * n || m.iter().any(|v| !v.is_finite()) {
                return Err(FlutterError::BadModel(format!(
                    "the {what} matrix must be {n} x {n} and finite"
                )));
            }
        }
        if gaf.order() != n {
            return Err(FlutterError::BadModel(format!(
                "the GAF has order {} but the structure {n}",
                gaf.order()
            )));
        }
        for (what, v) in [
            ("reference semichord", self.b_ref),
            ("density", self.density),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(FlutterError::BadModel(format!(
                    "{what} = {v} must be positive"
                )));
            }
        }
        if !(self.structural_g.is_finite() && self.structural_g >= 0.0) {
            return Err(FlutterError::BadModel(
                "structural damping g must be >= 0".into(),
            ));
        }
        Ok(())
    }

    /// Vacuum natural frequencies (rad/s, ascending) and, for each, the index of the
    /// coordinate with the largest share of the mode's kinetic energy (its name).
    pub fn vacuum_modes(&self) -> Result<Vec<(f64, usize)>, FlutterError> {
        let n = self.order();
        let minv = inverse(&self.mass, n).ok_or(FlutterError::SingularMass)?;
        let k = Mat::<f64>::from_fn(n, n, |i, j| self.stiffness[i * n + j]);
        let a = &minv * &k;
        let evd = a.eigen().map_err(|_| FlutterError::Eigen { speed: 0.0 })?;
        let (u, s) = (evd.U(), evd.S());
        let mut out: Vec<(f64, usize)> = (0..n)
            .map(|j| {
                let lam = s[j].re.max(0.0);
                let mut best = (0usize, -1.0);
                for i in 0..n {
                    let e = u[(i, j)].norm().powi(2) * self.mass[i * n + i];
                    if e > best.1 {
                        best = (i, e);
                    }
                }
                (lam.sqrt(), best.0)
            })
            .collect();
        out.sort_by(|x, y| x.0.total_cmp(&y.0));
        Ok(out)
    }
}

fn inverse(m: &[f64], n: usize) -> Option<Mat<f64>> {
    let a = Mat::<f64>::from_fn(n, n, |i, j| m[i * n + j]);
    let lu = a.partial_piv_lu();
    let inv = lu.solve(Mat::<f64>::identity(n, n));
    // Reject a singular or ill-conditioned matrix (the LU gives inf/NaN or huge entries).
    let scale = m.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    let inv_scale = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .fold(0.0_f64, |s, (i, j)| s.max(inv[(i, j)].abs()));
    if !(inv_scale.is_finite() && scale > 0.0 && inv_scale * scale < 1e14) {
        return None;
    }
    Some(inv)
}

/// Settings of the p-k iteration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PkSettings {
    /// Converged when `|k_new - k| <= k_tolerance * max(k, K_FLOOR)`.
    pub k_tolerance: f64,
}

impl Default for PkSettings {
    fn default() -> Self {
        PkSettings { k_tolerance: 1e-11 }
    }
}

/// The smallest reduced frequency at which `Q` is evaluated: a non-oscillatory root (a real
/// `p`) is solved with `Q(K_FLOOR)` (its `Q^I / k` is finite there).
pub const K_FLOOR: f64 = 1e-6;

/// Damping changes below this are the eigensolver's round-off, not a crossing: `g =
/// 2 Re(p)/Im(p)` of an aerodynamically inert branch is `~1e-16` of either sign (faer's
/// eigenvalues are accurate to a few ulps of `|p|`); any physical crossing changes `g` by
/// many orders more between two speeds of a sweep.
pub const G_NOISE: f64 = 1e-10;

/// One converged root of one mode at one speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PkRoot {
    pub speed: f64,
    /// The eigenvalue `p` (1/s).
    pub p: c64,
    /// Reduced frequency `Im(p) b / V`.
    pub k: f64,
}

impl PkRoot {
    /// Frequency `Im(p)`, rad/s.
    pub fn omega(&self) -> f64 {
        self.p.im
    }
    /// Whether the root oscillates (`k` above the floor).
    pub fn oscillatory(&self) -> bool {
        self.k > 10.0 * K_FLOOR
    }
    /// Damping `g = 2 Re(p)/Im(p)` (Rodden & Johnson); `None` for a non-oscillatory root.
    pub fn g(&self) -> Option<f64> {
        self.oscillatory().then(|| 2.0 * self.p.re / self.p.im)
    }
}

/// A flutter point located by root finding.
#[derive(Clone, Debug, PartialEq)]
pub struct FlutterPoint {
    /// The mode (branch) whose damping crosses zero, and its name.
    pub mode: usize,
    pub name: String,
    /// The coalescing partner: the other branch nearest in frequency at the flutter speed.
    pub partner: Option<(usize, String)>,
    pub speed: f64,
    /// Frequency, rad/s.
    pub omega: f64,
    pub k: f64,
    /// Dynamic pressure `ρ V² / 2`, Pa.
    pub q: f64,
}

/// The divergence point (the zero-frequency root).
#[derive(Clone, Debug, PartialEq)]
pub struct Divergence {
    pub q: f64,
    pub speed: f64,
    /// The coordinate with the largest share of the divergence shape's strain energy.
    pub name: String,
}

/// A p-k sweep: for each branch (vacuum mode, ascending frequency) its roots at every speed.
#[derive(Clone, Debug, PartialEq)]
pub struct PkSolution {
    pub speeds: Vec<f64>,
    /// Branch names (the dominant coordinate of each vacuum mode).
    pub names: Vec<String>,
    /// `roots[j][i]`: branch `j` at `speeds[i]`.
    pub roots: Vec<Vec<PkRoot>>,
    /// Flutter points in increasing speed (all zero crossings from below).
    pub flutter: Vec<FlutterPoint>,
    /// Branches already unstable at the lowest speed.
    pub unstable_at_start: Vec<usize>,
    pub divergence: Option<Divergence>,
    /// The screen below the first speed ([`screen_below`]), when one was solved.
    pub screen: Option<LowSpeedScreen>,
}

/// What a sweep says about flutter, read as a user must read it (issue 32): a flutter
/// speed only where a stable speed brackets it from below; otherwise a bound.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FlutterAnswer<'a> {
    /// The lowest crossing of any branch, with every branch stable at the lowest speed
    /// solved.
    Flutter(&'a FlutterPoint),
    /// A branch is unstable at the lowest speed solved: the flutter speed is below it.
    Below(f64),
    /// No crossing up to the largest speed solved.
    Stable,
}

impl PkSolution {
    /// The lowest flutter point of the sweep proper (not the screen below it); see
    /// [`PkSolution::answer`] for the flutter speed.
    pub fn critical(&self) -> Option<&FlutterPoint> {
        self.flutter.first()
    }

    /// The lowest speed solved: the screen's, else the sweep's first.
    pub fn lowest_speed(&self) -> f64 {
        self.screen
            .as_ref()
            .map_or(self.speeds[0], |s| s.lowest_speed.min(self.speeds[0]))
    }

    /// The flutter answer over the screen and the sweep: unstable at the lowest speed solved
    /// gives [`FlutterAnswer::Below`]; else the lowest crossing of either, bracketed by a
    /// stable speed below it; a sweep unstable at its first speed with no crossing of the
    /// screen below it is a bound at that speed; never a crossing above an instability.
    pub fn answer(&self) -> FlutterAnswer<'_> {
        let (screen_unstable, screen_first) = match &self.screen {
            Some(s) => (!s.unstable_at_lowest.is_empty(), s.flutter.first()),
            None => (false, None),
        };
        if screen_unstable {
            return FlutterAnswer::Below(self.lowest_speed());
        }
        if let Some(f) = screen_first {
            return FlutterAnswer::Flutter(f);
        }
        if !self.unstable_at_start.is_empty() {
            return FlutterAnswer::Below(self.speeds[0]);
        }
        match self.flutter.first() {
            Some(f) => FlutterAnswer::Flutter(f),
            None => FlutterAnswer::Stable,
        }
    }
}

impl FlutterAnswer<'_> {
    /// The headline of an answer: `flutter: V = ...` or the bound or none, for people;
    /// `largest` is the sweep's largest speed, `extra` follows a flutter point's speed.
    pub fn headline(&self, largest: f64, extra: &str) -> String {
        match self {
            FlutterAnswer::Flutter(f) => format!(
                "flutter: V = {:.2} m/s{extra}, f = {:.2} Hz, q = {:.1} kPa, k = {:.4}, {} with {}",
                f.speed,
                f.omega / (2.0 * std::f64::consts::PI),
                f.q / 1e3,
                f.k,
                f.name,
                f.partner.as_ref().map_or("none", |p| p.1.as_str())
            ),
            FlutterAnswer::Below(v) => format!(
                "flutter: unstable at the lowest speed solved, V_F < {v:.2} m/s (no stable speed below it was found: lower the speeds, or fewer modes)"
            ),
            FlutterAnswer::Stable => {
                format!("flutter: none up to V = {largest:.1} m/s (the largest speed tried)")
            }
        }
    }

    /// The answer in JSON: `{"kind": "flutter" | "below" | "none", "speed_m_s": ...}`.
    pub fn json(&self) -> serde_json::Value {
        match self {
            FlutterAnswer::Flutter(f) => serde_json::json!({
                "kind": "flutter", "speed_m_s": f.speed, "mode": f.name,
                "frequency_hz": f.omega / (2.0 * std::f64::consts::PI),
            }),
            FlutterAnswer::Below(v) => serde_json::json!({"kind": "below", "speed_m_s": v}),
            FlutterAnswer::Stable => serde_json::json!({"kind": "none", "speed_m_s": null}),
        }
    }
}

impl LowSpeedScreen {
    /// The screen in JSON.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "segments": self.segments.iter().map(|(m, lo, hi)| serde_json::json!({
                "modes": m, "lowest_m_s": lo, "highest_m_s": hi
            })).collect::<Vec<_>>(),
            "lowest_speed_m_s": self.lowest_speed,
            "unstable_at_lowest": self.unstable_at_lowest,
            "flutter": self.flutter.iter().map(|f| serde_json::json!({
                "speed_m_s": f.speed, "mode": f.name,
                "frequency_hz": f.omega / (2.0 * std::f64::consts::PI),
            })).collect::<Vec<_>>(),
        })
    }

    /// One line for people.
    pub fn line(&self) -> String {
        let segs: Vec<String> = self
            .segments
            .iter()
            .map(|(m, lo, hi)| format!("{m} modes {lo:.1}-{hi:.1} m/s"))
            .collect();
        format!(
            "below the sweep, screened on the leading modes down to {:.2} m/s ({})",
            self.lowest_speed,
            segs.join(", ")
        )
    }
}

/// The p-k screen below a sweep's first speed (see [`screen_below`]).
#[derive(Clone, Debug, PartialEq)]
pub struct LowSpeedScreen {
    /// Each segment: the number of leading modes kept, its lowest and highest speed, m/s;
    /// from the fullest model down.
    pub segments: Vec<(usize, f64, f64)>,
    /// The lowest speed solved, m/s.
    pub lowest_speed: f64,
    /// Branches (coordinates of the full model) unstable at the lowest speed solved.
    pub unstable_at_lowest: Vec<usize>,
    /// Crossings found in the segments, by increasing speed (branch indices are the full
    /// model's coordinates).
    pub flutter: Vec<FlutterPoint>,
}

/// The leading coordinates `keep` of a GAF (the sub-block of `Q(k)`).
struct LeadingGaf<'a> {
    gaf: &'a dyn Gaf,
    keep: Vec<usize>,
    buf: std::cell::RefCell<Vec<c64>>,
}

impl Gaf for LeadingGaf<'_> {
    fn order(&self) -> usize {
        self.keep.len()
    }
    fn k_range(&self) -> (f64, f64) {
        self.gaf.k_range()
    }
    fn eval(&self, k: f64, out: &mut [c64]) {
        let n = self.gaf.order();
        let mut buf = self.buf.borrow_mut();
        self.gaf.eval(k, &mut buf);
        let m = self.keep.len();
        for (a, &i) in self.keep.iter().enumerate() {
            for (b, &j) in self.keep.iter().enumerate() {
                out[a * m + b] = buf[i * n + j];
            }
        }
    }
}

/// Speeds per segment of [`screen_below`].
pub const SCREEN_SPEEDS: usize = 12;

/// The screen below a sweep's first speed `v_first` (issue 32: no sweep may miss a low
/// flutter speed).
///
/// A sweep cannot start near zero airspeed with all its modes: the reduced frequency of the
/// highest branch, `k = ω b / V`, grows without bound as `V` falls, and a panel lattice
/// resolves it only up to the table's `k_max` (the box-size rule fixed the sweep's first
/// speed). The lower branches need much smaller `k`. So below `v_first` the p-k equation is
/// solved on the leading (lowest-frequency) modes alone, a modal truncation like the one that
/// chose the sweep's modes: with the `m` lowest modes the table holds every branch's `k`
/// (with the 20 % margin of the sweep, for roots stiffened above their vacuum frequency)
/// down to `V_m = 1.2 ω_m b / k_max`. The segments run from `m = n - 1` (from `v_first`
/// down to `V_{n-1}`) to `m = 2` (the two lowest modes, which a bending-torsion flutter
/// needs), each over [`SCREEN_SPEEDS`] speeds and overlapping the next at its end. The
/// coordinates must be uncoupled structurally (diagonal mass and stiffness, the modal
/// coordinates of a fin or a fixture); otherwise, or with fewer than three coordinates, no
/// screen is solved (`None`). A segment whose p-k iteration fails is cut like a sweep
/// ([`pk_solve_cut`]); the screen ends at the lowest speed solved.
pub fn screen_below(
    model: &FlutterModel,
    gaf: &dyn Gaf,
    v_first: f64,
    settings: PkSettings,
) -> Result<Option<LowSpeedScreen>, FlutterError> {
    let n = model.order();
    let diagonal = |m: &[f64]| (0..n).all(|i| (0..n).all(|j| i == j || m[i * n + j] == 0.0));
    if n < 3 || !diagonal(&model.mass) || !diagonal(&model.stiffness) {
        return Ok(None);
    }
    let mut order: Vec<(f64, usize)> = (0..n)
        .map(|i| {
            let w2 = model.stiffness[i * n + i] / model.mass[i * n + i];
            (w2.max(0.0).sqrt(), i)
        })
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (_, k_hi) = gaf.k_range();
    let mut top = v_first;
    let mut segments = Vec::new();
    let mut flutter = Vec::new();
    let mut unstable_at_lowest = Vec::new();
    let mut lowest = v_first;
    for m in (2..n).rev() {
        let v_m = 1.2 * order[m - 1].0 * model.b_ref / k_hi;
        if !(v_m.is_finite() && v_m > 0.0 && v_m < top * (1.0 - 1e-9)) {
            continue;
        }
        let mut keep: Vec<usize> = order[..m].iter().map(|o| o.1).collect();
        keep.sort_unstable();
        let sub = |a: &[f64]| -> Vec<f64> {
            keep.iter()
                .flat_map(|&i| keep.iter().map(move |&j| a[i * n + j]))
                .collect()
        };
        let part = FlutterModel {
            names: keep.iter().map(|&i| model.names[i].clone()).collect(),
            mass: sub(&model.mass),
            stiffness: sub(&model.stiffness),
            damping: sub(&model.damping),
            structural_g: model.structural_g,
            b_ref: model.b_ref,
            density: model.density,
        };
        let leading = LeadingGaf {
            gaf,
            keep: keep.clone(),
            buf: std::cell::RefCell::new(vec![c64::new(0.0, 0.0); n * n]),
        };
        let speeds: Vec<f64> = (0..SCREEN_SPEEDS)
            .map(|i| v_m + (top - v_m) * i as f64 / (SCREEN_SPEEDS - 1) as f64)
            .collect();
        let sol = match cut_sweep(&part, &leading, &speeds, settings, None) {
            Ok((s, _)) => s,
            // Not even the two lowest speeds converge: the screen ends above.
            Err(FlutterError::NoConvergence { .. }) => break,
            Err(e) => return Err(e),
        };
        // Branch `j` of the part is its j-th vacuum mode; map it to the full model's
        // coordinate by its name's coordinate.
        let coord = |name: &str| keep[part.names.iter().position(|x| x == name).unwrap_or(0)];
        for f in &sol.flutter {
            let mut f = f.clone();
            f.mode = coord(&f.name);
            if let Some(p) = f.partner.as_mut() {
                p.0 = coord(&p.1);
            }
            flutter.push(f);
        }
        unstable_at_lowest = sol
            .unstable_at_start
            .iter()
            .map(|&j| coord(&sol.names[j]))
            .collect();
        lowest = sol.speeds[0];
        segments.push((m, lowest, top));
        top = lowest;
    }
    if segments.is_empty() {
        return Ok(None);
    }
    flutter.sort_by(|x, y| x.speed.total_cmp(&y.speed));
    Ok(Some(LowSpeedScreen {
        segments,
        lowest_speed: lowest,
        unstable_at_lowest,
        flutter,
    }))
}

/// [`pk_solve_cut`] with the [`screen_below`] its first speed, in [`PkSolution::screen`].
pub fn pk_solve_screened(
    model: &FlutterModel,
    gaf: &dyn Gaf,
    speeds: &[f64],
    settings: PkSettings,
) -> Result<(PkSolution, Option<(f64, usize)>), FlutterError> {
    let (mut sol, cut) = cut_sweep(model, gaf, speeds, settings, None)?;
    sol.screen = screen_below(model, gaf, sol.speeds[0], settings)?;
    Ok((sol, cut))
}

/// Workspace of the p-k eigenproblem.
struct PkProblem<'a> {
    model: &'a FlutterModel,
    gaf: &'a dyn Gaf,
    minv: Mat<f64>,
    q_buf: Vec<c64>,
    settings: PkSettings,
}

impl<'a> PkProblem<'a> {
    fn new(
        model: &'a FlutterModel,
        gaf: &'a dyn Gaf,
        settings: PkSettings,
    ) -> Result<Self, FlutterError> {
        model.validate(gaf)?;
        let n = model.order();
        let minv = inverse(&model.mass, n).ok_or(FlutterError::SingularMass)?;
        Ok(PkProblem {
            model,
            gaf,
            minv,
            q_buf: vec![c64::new(0.0, 0.0); n * n],
            settings,
        })
    }

    /// Eigenvalues of the first-order system at speed `v` with `Q(k)`.
    fn eigenvalues(&mut self, v: f64, k: f64) -> Result<Vec<c64>, FlutterError> {
        let m = self.model;
        let n = m.order();
        let ke = k.max(K_FLOOR);
        self.gaf.eval(ke, &mut self.q_buf);
        let q = 0.5 * m.density * v * v;
        let rate = m.b_ref / (ke * v);
        let kt = Mat::<f64>::from_fn(n, n, |i, j| {
            m.stiffness[i * n + j] - q * self.q_buf[i * n + j].re
        });
        let bt = Mat::<f64>::from_fn(n, n, |i, j| {
            m.damping[i * n + j] + m.structural_g * rate * m.stiffness[i * n + j]
                - q * rate * self.q_buf[i * n + j].im
        });
        let mk = &self.minv * &kt;
        let mb = &self.minv * &bt;
        // The first-order form in the scaled state `z = [s η, η̇]` (a diagonal similarity,
        // the same eigenvalues): `A = [[0, s I], [-M⁻¹K̃ / s, -M⁻¹B̃]]` with `s` the square
        // root of the largest `|M⁻¹K̃|` entry, about the highest modal frequency. Unscaled,
        // the lower-left block is of order `ω_max²` against the identity above it, and the
        // eigenvalues carry an absolute error of order `ε ω_max²`: on a 4.85 kHz fin torsion
        // mode (examples/valetudo) `Im p` moved by 1e-7 relative between evaluations, so the
        // consistency residual never met the 1e-11 tolerance (the iteration did not
        // converge) and an inert branch's damping came out at ±1.8e-11. Scaled, both blocks
        // are of order `ω_max` and the error is of order `ε ω_max`.
        let s = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, j)| mk[(i, j)].abs())
            .fold(0.0, f64::max)
            .sqrt();
        let s = if s.is_finite() && s > 0.0 { s } else { 1.0 };
        let a = Mat::<f64>::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
            (true, true) => 0.0,
            (true, false) => {
                if j - n == i {
                    s
                } else {
                    0.0
                }
            }
            (false, true) => -mk[(i - n, j)] / s,
            (false, false) => -mb[(i - n, j - n)],
        });
        if (0..2 * n).any(|i| (0..2 * n).any(|j| !a[(i, j)].is_finite())) {
            return Err(FlutterError::Eigen { speed: v });
        }
        let ev = a
            .eigenvalues()
            .map_err(|_| FlutterError::Eigen { speed: v })?;
        Ok(ev)
    }

    /// The root of `A(v, k)` continuing the branch: nearest (Im >= 0) to `p0`.
    fn select(&mut self, v: f64, k: f64, p0: c64) -> Result<c64, FlutterError> {
        let ev = self.eigenvalues(v, k)?;
        let scale = p0.norm().max(1e-12);
        ev.iter()
            .filter(|z| z.im >= -1e-12 * scale)
            .min_by(|x, y| (**x - p0).norm().total_cmp(&(**y - p0).norm()))
            .copied()
            .ok_or(FlutterError::Eigen { speed: v })
    }

    /// The converged root of the branch started at `p0`, at speed `v`: a zero of the residual
    /// `r(k) = Im(p(k)) b / V - k` (Hassig's consistency condition), `p(k)` the root of
    /// `A(v, k)` that continues the branch (nearest to the previous iterate's root).
    ///
    /// The first step is the classical fixed-point step `k <- k + r`; while `r` keeps its sign
    /// the step is doubled (the fixed-point map of a heavily damped root has a slope near 1 and
    /// would crawl); once `r` changes sign the zero is bracketed and found by Brent's method. A
    /// branch whose root turns real (no oscillatory consistent root: `r < 0` down to the point
    /// where `p` leaves the imaginary half-plane) is reported as non-oscillatory, `k = K_FLOOR`.
    fn solve_mode(&mut self, mode: usize, v: f64, p0: c64) -> Result<PkRoot, FlutterError> {
        let b = self.model.b_ref;
        let (lo, hi) = self.gaf.k_range();
        let check = |k: f64| -> Result<(), FlutterError> {
            if k > hi * (1.0 + 1e-12) || (lo > 0.0 && k < lo * (1.0 - 1e-12) && k > 10.0 * K_FLOOR)
            {
                return Err(FlutterError::KOutOfRange {
                    mode,
                    speed: v,
                    k,
                    lo,
                    hi,
                });
            }
            Ok(())
        };
        let tol = self.settings.k_tolerance;
        // A root whose reduced frequency is below the floor is non-oscillatory whatever its
        // phase: the exact zeros of a free vehicle's rigid coordinates come out of the
        // eigensolver as round-off of either phase (`|p| ~ 1e-12`).
        let is_real = |p: c64| p.im <= 1e-9 * p.norm() || p.im * b / v < K_FLOOR;
        let mut k = (p0.im.max(0.0) * b / v).max(10.0 * K_FLOOR);
        let mut p = p0;
        let mut last: Option<(f64, f64, c64)> = None;
        let mut gamma = 1.0_f64;
        for _ in 0..200 {
            check(k)?;
            p = self.select(v, k, p)?;
            if is_real(p) {
                return Ok(PkRoot {
                    speed: v,
                    p: c64::new(p.re, 0.0),
                    k: K_FLOOR,
                });
            }
            let r = p.im * b / v - k;
            if r.abs() <= tol * k {
                return Ok(PkRoot {
                    speed: v,
                    p,
                    k: k + r,
                });
            }
            if let Some((kl, rl, pl)) = last {
                if rl.signum() != r.signum() {
                    let mut f = |kk: f64| -> Result<f64, FlutterError> {
                        check(kk)?;
                        let q = self.select(v, kk, pl)?;
                        Ok(if is_real(q) { -kk } else { q.im * b / v - kk })
                    };
                    let ks = brent(&mut f, kl, k, rl, r)?;
                    let q = self.select(v, ks, pl)?;
                    if is_real(q) {
                        return Ok(PkRoot {
                            speed: v,
                            p: c64::new(q.re, 0.0),
                            k: K_FLOOR,
                        });
                    }
                    let kn = q.im * b / v;
                    if (kn - ks).abs() > 1e3 * tol * ks {
                        // The selected root jumps inside the bracket: no continuous zero.
                        return Err(FlutterError::NoConvergence {
                            mode,
                            speed: v,
                            k: ks,
                        });
                    }
                    return Ok(PkRoot {
                        speed: v,
                        p: q,
                        k: kn,
                    });
                }
                gamma = (2.0 * gamma).min(1e6);
            }
            last = Some((k, r, p));
            k = (k + gamma * r).clamp(10.0 * K_FLOOR, hi);
        }
        Err(FlutterError::NoConvergence { mode, speed: v, k })
    }
}

/// The p-k solution over `speeds` (m/s, increasing): V-g and V-f of every branch, the flutter
/// points by root finding and the divergence point.
pub fn pk_solve(
    model: &FlutterModel,
    gaf: &dyn Gaf,
    speeds: &[f64],
    settings: PkSettings,
) -> Result<PkSolution, FlutterError> {
    sweep(model, gaf, speeds, settings, None)
}

/// [`pk_solve`] with the branches started at the lowest speed from `starts` (one root per
/// vacuum mode, in the ascending order of [`FlutterModel::vacuum_modes`]) instead of `i ω_j`,
/// for a model with rigid-body (zero-frequency) coordinates: their vacuum roots coincide at
/// 0, so continuation from `i ω_j = 0` would start every rigid branch on the same root.
/// The divergence is not solved (`None`): with free coordinates the stiffness is singular,
/// and the caller solves its restrained problem. Otherwise as [`pk_solve`].
pub fn pk_solve_started(
    model: &FlutterModel,
    gaf: &dyn Gaf,
    speeds: &[f64],
    settings: PkSettings,
    starts: &[c64],
) -> Result<PkSolution, FlutterError> {
    if starts.len() != model.order() {
        return Err(FlutterError::BadModel(format!(
            "{} start roots for {} branches",
            starts.len(),
            model.order()
        )));
    }
    sweep(model, gaf, speeds, settings, Some(starts))
}

/// The roots `p` of the p-k eigenproblem at speed `v` with `Q(k)` (all `2n`, any order): the
/// first-order system of the module doc, for choosing start roots.
pub fn pk_roots(
    model: &FlutterModel,
    gaf: &dyn Gaf,
    v: f64,
    k: f64,
) -> Result<Vec<c64>, FlutterError> {
    let mut prob = PkProblem::new(model, gaf, PkSettings::default())?;
    prob.eigenvalues(v, k)
}

fn sweep(
    model: &FlutterModel,
    gaf: &dyn Gaf,
    speeds: &[f64],
    settings: PkSettings,
    starts: Option<&[c64]>,
) -> Result<PkSolution, FlutterError> {
    if speeds.is_empty()
        || speeds.iter().any(|v| !(v.is_finite() && *v > 0.0))
        || speeds.windows(2).any(|w| w[1] <= w[0])
    {
        return Err(FlutterError::BadSpeeds);
    }
    let mut prob = PkProblem::new(model, gaf, settings)?;
    let vac = model.vacuum_modes()?;
    let n = model.order();
    let names: Vec<String> = vac.iter().map(|&(_, i)| model.names[i].clone()).collect();
    let mut roots: Vec<Vec<PkRoot>> = vec![Vec::with_capacity(speeds.len()); n];
    for (i, &v) in speeds.iter().enumerate() {
        for j in 0..n {
            let p0 = match i {
                0 => starts.map_or(c64::new(0.0, vac[j].0), |s| s[j]),
                1 => roots[j][0].p,
                // Linear predictor from the two previous speeds: nearest-root continuation
                // from the previous root alone jumps to a neighbouring root where branches
                // cross in frequency (a free vehicle's fin twist falling through its body
                // bending), losing the branch.
                _ => {
                    let (a, b) = (roots[j][i - 2], roots[j][i - 1]);
                    let t = (v - b.speed) / (b.speed - a.speed);
                    let p = b.p + (b.p - a.p) * t;
                    c64::new(p.re, p.im.max(0.0))
                }
            };
            let r = prob.solve_mode(j, v, p0)?;
            roots[j].push(r);
        }
    }
    let mut unstable_at_start = Vec::new();
    let mut flutter = Vec::new();
    for j in 0..n {
        // Above the round-off of an inert branch (`G_NOISE`, below), as the crossings are.
        if roots[j][0].g().is_some_and(|g| g > G_NOISE) {
            unstable_at_start.push(j);
        }
        for i in 0..speeds.len().saturating_sub(1) {
            let (a, b) = (roots[j][i], roots[j][i + 1]);
            let (Some(ga), Some(gb)) = (a.g(), b.g()) else {
                continue;
            };
            // A branch the air does not act on has round-off damping (|g| ~ 1e-16, either
            // sign): its sign changes are noise, not flutter.
            if !(ga < 0.0 && gb >= 0.0) || gb - ga <= G_NOISE {
                continue;
            }
            // Each evaluation starts from the linear interpolation of the bracket's roots
            // (starting every one from the lower root can land on a neighbouring branch
            // near a frequency crossing and make g(V) jump).
            let start = |v: f64| a.p + (b.p - a.p) * ((v - a.speed) / (b.speed - a.speed));
            let mut f = |v: f64| -> Result<f64, FlutterError> {
                let r = prob.solve_mode(j, v, start(v))?;
                Ok(r.g().unwrap_or(f64::NAN))
            };
            let vf = brent(&mut f, a.speed, b.speed, ga, gb)?;
            let r = prob.solve_mode(j, vf, start(vf))?;
            // Partner: the other branch nearest in frequency at the flutter speed.
            let mut partner: Option<(usize, f64)> = None;
            for jj in (0..n).filter(|&jj| jj != j) {
                let rr = prob.solve_mode(jj, vf, roots[jj][i].p)?;
                if !rr.oscillatory() {
                    continue;
                }
                let d = (rr.omega() - r.omega()).abs();
                if partner.is_none_or(|(_, best)| d < best) {
                    partner = Some((jj, d));
                }
            }
            flutter.push(FlutterPoint {
                mode: j,
                name: names[j].clone(),
                partner: partner.map(|(jj, _)| (jj, names[jj].clone())),
                speed: vf,
                omega: r.omega(),
                k: r.k,
                q: 0.5 * model.density * vf * vf,
            });
        }
    }
    flutter.sort_by(|x, y| x.speed.total_cmp(&y.speed));
    let divergence = match starts {
        Some(_) => None,
        None => divergence(model, gaf)?,
    };
    Ok(PkSolution {
        speeds: speeds.to_vec(),
        names,
        roots,
        flutter,
        unstable_at_start,
        divergence,
        screen: None,
    })
}

/// [`pk_solve`], but a branch whose p-k iteration does not converge at some speed (typically
/// near zero frequency at high speed, where an unsteady `Q^I/k` varies fastest) ends the
/// sweep there: the solution is re-run on the speeds below it, and the speed and branch of
/// the cut are returned with it (`None` when the whole sweep was solved). Fails as
/// [`pk_solve`] when fewer than two speeds would remain.
pub fn pk_solve_cut(
    model: &FlutterModel,
    gaf: &dyn Gaf,
    speeds: &[f64],
    settings: PkSettings,
) -> Result<(PkSolution, Option<(f64, usize)>), FlutterError> {
    cut_sweep(model, gaf, speeds, settings, None)
}

/// [`pk_solve_cut`] with start roots ([`pk_solve_started`]).
pub fn pk_solve_cut_started(
    model: &FlutterModel,
    gaf: &dyn Gaf,
    speeds: &[f64],
    settings: PkSettings,
    starts: &[c64],
) -> Result<(PkSolution, Option<(f64, usize)>), FlutterError> {
    if starts.len() != model.order() {
        return Err(FlutterError::BadModel(format!(
            "{} start roots for {} branches",
            starts.len(),
            model.order()
        )));
    }
    cut_sweep(model, gaf, speeds, settings, Some(starts))
}

fn cut_sweep(
    model: &FlutterModel,
    gaf: &dyn Gaf,
    speeds: &[f64],
    settings: PkSettings,
    starts: Option<&[c64]>,
) -> Result<(PkSolution, Option<(f64, usize)>), FlutterError> {
    let mut sp = speeds.to_vec();
    let mut cut = None;
    loop {
        match sweep(model, gaf, &sp, settings, starts) {
            Err(FlutterError::NoConvergence { speed, mode, .. })
                if sp.iter().filter(|v| **v < speed).count() >= 2 =>
            {
                cut = Some((speed, mode));
                sp.retain(|v| *v < speed);
            }
            other => return other.map(|s| (s, cut)),
        }
    }
}

/// The divergence point from `det(K - q Q^R(k_0)) = 0` at the table's lowest `k_0` (module doc);
/// `None` when no positive real root exists (or `k_0 > 0`: no steady aerodynamics).
pub fn divergence(model: &FlutterModel, gaf: &dyn Gaf) -> Result<Option<Divergence>, FlutterError> {
    model.validate(gaf)?;
    let n = model.order();
    let (lo, _) = gaf.k_range();
    if lo > 0.0 {
        return Ok(None);
    }
    let kinv = inverse(&model.stiffness, n).ok_or(FlutterError::SingularStiffness("divergence"))?;
    let mut q0 = vec![c64::new(0.0, 0.0); n * n];
    gaf.eval(0.0, &mut q0);
    let qr = Mat::<f64>::from_fn(n, n, |i, j| q0[i * n + j].re);
    let a = &kinv * &qr;
    let evd = a.eigen().map_err(|_| FlutterError::Eigen { speed: 0.0 })?;
    let (u, s) = (evd.U(), evd.S());
    let mut best: Option<(f64, usize)> = None;
    for j in 0..n {
        let l = s[j];
        if l.re > 0.0 && l.im.abs() <= 1e-9 * l.norm() && best.is_none_or(|(b, _)| l.re > b) {
            best = Some((l.re, j));
        }
    }
    Ok(best.map(|(lam, j)| {
        let q = 1.0 / lam;
        // The coordinate with the largest share of the divergence shape's strain energy.
        let energy = |x: usize| u[(x, j)].norm().powi(2) * model.stiffness[x * n + x];
        let dominant = (0..n)
            .max_by(|&x, &y| energy(x).total_cmp(&energy(y)))
            .unwrap_or(0);
        Divergence {
            q,
            speed: (2.0 * q / model.density).sqrt(),
            name: model.names[dominant].clone(),
        }
    }))
}

/// Brent's method (Brent, *Algorithms for Minimization without Derivatives*, 1973, ch. 4) on
/// `[a, b]` with `f(a) = fa`, `f(b) = fb` of opposite signs (or `fb = 0`).
fn brent<F>(f: &mut F, a: f64, b: f64, fa: f64, fb: f64) -> Result<f64, FlutterError>
where
    F: FnMut(f64) -> Result<f64, FlutterError>,
{
    let (mut a, mut b, mut fa, mut fb) = (a, b, fa, fb);
    if fb == 0.0 {
        return Ok(b);
    }
    let (mut c, mut fc) = (a, fa);
    let (mut d, mut e) = (b - a, b - a);
    for _ in 0..200 {
        if fb.signum() == fc.signum() {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 1e-13 * b.abs();
        let m = 0.5 * (c - b);
        if m.abs() <= tol || fb == 0.0 {
            return Ok(b);
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol * m.signum() };
        fb = f(b)?;
        if !fb.is_finite() {
            return Err(FlutterError::NoConvergence {
                mode: usize::MAX,
                speed: b,
                k: f64::NAN,
            });
        }
    }
    Ok(b)
}

/// One eigenvalue of the k method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KRoot {
    pub k: f64,
    pub speed: f64,
    pub omega: f64,
    /// Required structural damping `g`.
    pub g: f64,
}

/// A k-method (V-g) sweep over decreasing `k` (increasing speed).
#[derive(Clone, Debug, PartialEq)]
pub struct KSolution {
    pub ks: Vec<f64>,
    /// `roots[j][i]`: branch `j` at `ks[i]` (tracked by nearest eigenvalue).
    pub roots: Vec<Vec<KRoot>>,
    /// Flutter points (g crossing zero from below as speed increases), by root finding on `k`.
    pub flutter: Vec<KRoot>,
}

fn k_method_eigs(
    model: &FlutterModel,
    gaf: &dyn Gaf,
    kinv: &Mat<c64>,
    k: f64,
    buf: &mut [c64],
) -> Result<Vec<c64>, FlutterError> {
    let n = model.order();
    gaf.eval(k, buf);
    let f = 0.5 * model.density * model.b_ref * model.b_ref / (k * k);
    let a = Mat::<c64>::from_fn(n, n, |i, j| {
        c64::new(model.mass[i * n + j], 0.0) + buf[i * n + j] * f
    });
    let z = kinv * &a;
    z.eigenvalues()
        .map_err(|_| FlutterError::Eigen { speed: f64::NAN })
}

fn k_root(k: f64, b: f64, mu: c64) -> Option<KRoot> {
    if mu.re.is_nan() || mu.re <= 0.0 {
        return None;
    }
    let omega = 1.0 / mu.re.sqrt();
    Some(KRoot {
        k,
        speed: omega * b / k,
        omega,
        g: mu.im / mu.re,
    })
}

/// The k method over `ks` (any order; sorted descending internally). Requires `B = 0` and
/// `g_s = 0` (the method's damping is the artificial `g`).
pub fn k_method(
    model: &FlutterModel,
    gaf: &dyn Gaf,
    ks: &[f64],
) -> Result<KSolution, FlutterError> {
    model.validate(gaf)?;
    if model.damping.iter().any(|v| *v != 0.0) || model.structural_g != 0.0 {
        return Err(FlutterError::BadModel(
            "the k method takes no structural damping (its g is the unknown)".into(),
        ));
    }
    let n = model.order();
    let (lo, hi) = gaf.k_range();
    let mut ks: Vec<f64> = ks.to_vec();
    if ks
        .iter()
        .any(|k| !(k.is_finite() && *k > 0.0 && *k >= lo && *k <= hi))
        || ks.len() < 2
    {
        return Err(FlutterError::BadModel(format!(
            "k-method reduced frequencies must be > 0 and within {lo}..{hi}"
        )));
    }
    ks.sort_by(|a, b| b.total_cmp(a));
    ks.dedup();
    let kinv_r = inverse(&model.stiffness, n).ok_or(FlutterError::SingularStiffness("k method"))?;
    let kinv = Mat::<c64>::from_fn(n, n, |i, j| c64::new(kinv_r[(i, j)], 0.0));
    let mut buf = vec![c64::new(0.0, 0.0); n * n];
    let mut mus: Vec<Vec<c64>> = Vec::with_capacity(ks.len());
    for (i, &k) in ks.iter().enumerate() {
        let mut ev = k_method_eigs(model, gaf, &kinv, k, &mut buf)?;
        if i == 0 {
            // Branch order: descending Re μ (ascending frequency).
            ev.sort_by(|a, b| b.re.total_cmp(&a.re));
        } else {
            // Greedy nearest assignment to the previous μ of each branch.
            let prev = &mus[i - 1];
            let mut taken = vec![false; n];
            let mut ordered = vec![c64::new(0.0, 0.0); n];
            for j in 0..n {
                let best = (0..n)
                    .filter(|&t| !taken[t])
                    .min_by(|&x, &y| {
                        (ev[x] - prev[j])
                            .norm()
                            .total_cmp(&(ev[y] - prev[j]).norm())
                    })
                    .unwrap_or(0);
                taken[best] = true;
                ordered[j] = ev[best];
            }
            ev = ordered;
        }
        mus.push(ev);
    }
    let b = model.b_ref;
    let mut roots = vec![Vec::new(); n];
    for (i, &k) in ks.iter().enumerate() {
        for j in 0..n {
            roots[j].push(k_root(k, b, mus[i][j]).unwrap_or(KRoot {
                k,
                speed: f64::NAN,
                omega: f64::NAN,
                g: f64::NAN,
            }));
        }
    }
    let mut flutter = Vec::new();
    for j in 0..n {
        for i in 0..ks.len() - 1 {
            let (ra, rb) = (roots[j][i], roots[j][i + 1]);
            if !(ra.g < 0.0 && rb.g >= 0.0) {
                continue;
            }
            let target = mus[i][j];
            let mut f = |k: f64| -> Result<f64, FlutterError> {
                let ev = k_method_eigs(model, gaf, &kinv, k, &mut buf)?;
                let mu = ev
                    .iter()
                    .min_by(|x, y| (**x - target).norm().total_cmp(&(**y - target).norm()))
                    .copied()
                    .unwrap_or(c64::new(f64::NAN, f64::NAN));
                Ok(mu.im / mu.re)
            };
            let kf = brent(&mut f, ra.k, rb.k, ra.g, rb.g)?;
            let ev = k_method_eigs(model, gaf, &kinv, kf, &mut buf)?;
            let mu = ev
                .iter()
                .min_by(|x, y| (**x - target).norm().total_cmp(&(**y - target).norm()))
                .copied()
                .unwrap_or(c64::new(f64::NAN, f64::NAN));
            if let Some(r) = k_root(kf, b, mu) {
                flutter.push(r);
            }
        }
    }
    flutter.sort_by(|x, y| x.speed.total_cmp(&y.speed));
    Ok(KSolution { ks, roots, flutter })
}

#[cfg(test)]
mod tests {
    /// The answer is never a crossing above an instability: whatever the crossings, a
    /// branch unstable at the lowest speed solved (of the screen, else of the sweep) gives a
    /// bound at that speed; a screen crossing below the sweep is the answer even when the
    /// sweep is unstable at its start; otherwise the lowest crossing.
    #[test]
    fn the_answer_is_never_a_crossing_above_an_instability() {
        let point = |v: f64| FlutterPoint {
            mode: 0,
            name: "m".into(),
            partner: None,
            speed: v,
            omega: 1.0,
            k: 0.1,
            q: 1.0,
        };
        let base = PkSolution {
            speeds: vec![100.0, 200.0, 300.0],
            names: vec!["m".into()],
            roots: vec![],
            flutter: vec![point(250.0)],
            unstable_at_start: vec![],
            divergence: None,
            screen: None,
        };
        let screen = |unstable: bool, crossing: Option<f64>| LowSpeedScreen {
            segments: vec![(2, 20.0, 100.0)],
            lowest_speed: 20.0,
            unstable_at_lowest: if unstable { vec![0] } else { vec![] },
            flutter: crossing.into_iter().map(point).collect(),
        };
        let speed = |s: &PkSolution| match s.answer() {
            FlutterAnswer::Flutter(f) => ("flutter", f.speed),
            FlutterAnswer::Below(v) => ("below", v),
            FlutterAnswer::Stable => ("none", 0.0),
        };
        assert_eq!(speed(&base), ("flutter", 250.0));
        let mut s = base.clone();
        s.unstable_at_start = vec![0];
        assert_eq!(speed(&s), ("below", 100.0));
        s.screen = Some(screen(false, Some(60.0)));
        assert_eq!(speed(&s), ("flutter", 60.0));
        s.screen = Some(screen(true, Some(60.0)));
        assert_eq!(speed(&s), ("below", 20.0));
        let mut s = base.clone();
        s.screen = Some(screen(false, None));
        assert_eq!(speed(&s), ("flutter", 250.0));
        s.flutter.clear();
        assert_eq!(speed(&s), ("none", 0.0));
    }

    use super::*;

    /// Two uncoupled modes, `M = I`, `b = 1`, `ρ = 2` (so `q = V²`): mode B at 80 rad/s
    /// with light damping; mode A at 100 rad/s softened by the air, `ω_A² = 100² - 1.44 V²`
    /// (it falls through B's frequency at V = 50), with structural damping 31 and
    /// aerodynamic damping `-V c₁`, `c₁ = 0.5`, so that its damping vanishes exactly at
    /// V = 62 (`Q_I = c₁ k`, quasi-steady: the p-k roots are those of the constant-coefficient
    /// system). On a 10 m/s grid, continuation from the previous root alone jumps from A to
    /// B at V = 60 (B's root is nearer A's root at 50 than A's own root at 60) and the flutter
    /// is lost (the old `pk_solve` found none); the linear predictor keeps the branch.
    #[test]
    fn a_branch_falling_through_another_keeps_its_root_and_flutters() {
        let model = FlutterModel {
            names: vec!["B".into(), "A".into()],
            mass: vec![1.0, 0.0, 0.0, 1.0],
            stiffness: vec![6400.0, 0.0, 0.0, 10000.0],
            damping: vec![0.5, 0.0, 0.0, 31.0],
            structural_g: 0.0,
            b_ref: 1.0,
            density: 2.0,
        };
        let gaf = GafFn {
            order: 2,
            k_max: 10.0,
            f: |k: f64, out: &mut [c64]| {
                out.fill(c64::new(0.0, 0.0));
                out[3] = c64::new(1.44, 0.5 * k);
            },
        };
        let speeds: Vec<f64> = (1..=10).map(|i| 10.0 * i as f64).collect();
        let sol = pk_solve(&model, &gaf, &speeds, PkSettings::default()).unwrap();
        let f = sol.critical().expect("mode A flutters at 62 m/s");
        assert_eq!(f.name, "A");
        assert!((f.speed - 62.0).abs() < 1e-9, "{}", f.speed);
        // ω_A at 62 m/s: sqrt(100² - 1.44 · 62²).
        let w = (10000.0 - 1.44 * 62.0 * 62.0_f64).sqrt();
        assert!((f.omega - w).abs() < 1e-8 * w, "{} vs {w}", f.omega);
        // Each branch stays on its own root at every speed (B stays at 80 rad/s).
        for r in &sol.roots[0] {
            let want = (6400.0 - 0.0625_f64).sqrt();
            assert!((r.p.im - want).abs() < 1e-9 * want, "{:?}", r.p);
        }
    }

    /// A branch the air does not act on (a zero row and column of `Q`, as a fin's in-plane
    /// modes) keeps its vacuum root at every speed and is never flagged: examples/valetudo's
    /// clamped fin has one at 4.85 kHz above two coupled ones. Before the first-order form
    /// was scaled, its `Im p` came out 9.1e-8 relative off `ω` and its damping at +1.8e-11, so
    /// the sweep called it unstable at its lowest speed (`g > 0`: round-off of either sign)
    /// and answered `V_F < 154.5 m/s` for a fin stable over the whole sweep. Measured now:
    /// `Im p / ω - 1` at most 4.4e-16 (bound 1e-14), `|g|` at most 1.8e-16 (bound 2e-15).
    #[test]
    fn an_inert_high_frequency_branch_keeps_its_vacuum_root_and_is_not_unstable() {
        let w = [2309.0, 11400.0, 30488.0];
        let n = 3;
        let mut model = FlutterModel {
            names: (0..n).map(|j| format!("mode {j}")).collect(),
            mass: vec![0.0; n * n],
            stiffness: vec![0.0; n * n],
            damping: vec![0.0; n * n],
            structural_g: 0.0,
            b_ref: 0.029,
            density: 1.15,
        };
        for (j, wj) in w.iter().enumerate() {
            model.mass[j * n + j] = 1.0;
            model.stiffness[j * n + j] = wj * wj;
        }
        // Quasi-steady coupling of the first two (aerodynamic damping -q b Q1 / V, Q1
        // negative definite: stable); nothing on the third.
        let q0 = [[-3.0, 8.0], [2.0, -5.0]];
        let q1 = [[-11.0, 3.0], [4.0, -9.0]];
        let gaf = GafFn {
            order: n,
            k_max: 10.0,
            f: move |k: f64, out: &mut [c64]| {
                out.fill(c64::new(0.0, 0.0));
                for i in 0..2 {
                    for j in 0..2 {
                        out[i * n + j] = c64::new(q0[i][j], k * q1[i][j]);
                    }
                }
            },
        };
        let speeds: Vec<f64> = (0..40)
            .map(|i| 154.548 + (1013.0 - 154.548) * i as f64 / 39.0)
            .collect();
        let (sol, cut) = pk_solve_cut(&model, &gaf, &speeds, PkSettings::default()).unwrap();
        assert_eq!(cut, None);
        assert!(
            sol.unstable_at_start.is_empty(),
            "{:?}",
            sol.unstable_at_start
        );
        assert_eq!(sol.answer(), FlutterAnswer::Stable);
        let (mut im, mut g) = (0.0f64, 0.0f64);
        for r in &sol.roots[2] {
            im = im.max((r.p.im / w[2] - 1.0).abs());
            g = g.max(r.g().unwrap().abs());
        }
        eprintln!("inert branch: Im p / w - 1 at most {im:e}, |g| at most {g:e}");
        assert!(im < 1e-14 && g < 2e-15, "{im:e} {g:e}");
    }
}
