//! Nose-cone shapes of the generated body (`body { nose_length; nose_shape }`): the profiles,
//! their checking, and the integrals the structure generator and the built-in aerodynamics
//! take from the true profile.
//!
//! # Profiles
//!
//! r(s) for 0 <= s <= L (s aft of the tip, R the base radius, L the nose length), as the
//! OpenRocket technical documentation defines them (S. Niskanen, "Development of an Open
//! Source model rocket simulation software", M.Sc. thesis, Helsinki University of Technology,
//! 2009, sec. 3.1.1 and its fig. 3.3; OpenRocket's `Transition.Shape`,
//! core/src/main/java/info/openrocket/core/rocketcomponent/Transition.java, commit 8fa969d8):
//!
//! - `conical`: r = R s / L;
//! - `ogive` (tangent) and `ogive(k)`, 0 < k <= 1 (secant ogives; k -> 0 is the cone): the arc
//!   of the circle of radius rho = sqrt((L^2 + R^2)((2 - k)^2 L^2 + k^2 R^2) / (4 k^2 R^2))
//!   centred at (L/k, -y0), y0 = sqrt(rho^2 - (L/k)^2): r = sqrt(rho^2 - (L/k - s)^2) - y0
//!   (for L < R, s and L scaled by R/L first, as OpenRocket does);
//! - `elliptical`: the half-ellipsoid r = R sqrt(2 s/L - (s/L)^2);
//! - `parabolic(K)`, 0 <= K <= 1 (`parabolic` = K 1): r = R (2 s/L - K (s/L)^2) / (2 - K);
//! - `power(n)`, 0 < n <= 1: r = R (s/L)^n;
//! - `haack(C)`, 0 <= C <= 2/3 (`von_karman` = C 0, `lv_haack` = C 1/3): theta = acos(1 -
//!   2 s/L), r = R sqrt((theta - sin(2 theta)/2 + C sin^3 theta) / pi).
//!
//! The parameter ranges keep r(s) rising from 0 at the tip to R at the base (a nose, not a
//! bulb). Derivations: parabolic, dr/ds = R (2 - 2 K s/L)/((2 - K) L) >= 0 on [0, L] iff
//! K <= 1; power, n > 0 closes the tip and n <= 1 keeps it from being concave toward the
//! axis beyond a cone (n > 1 gives a cusp that OpenRocket does not offer either); Haack,
//! d(r^2)/dtheta is proportional to 1 - cos 2 theta + 3 C sin^2 theta cos theta = sin^2 theta
//! (2 + 3 C cos theta), non-negative on [0, pi] iff C <= 2/3 (at theta = pi, cos theta = -1);
//! ogive, k in (0, 1] are OpenRocket's secant ogives (k = 1 tangent).
//!
//! # Wall and integrals
//!
//! The nose is a shell of revolution of the body's wall t measured radially, as the
//! generator has always built the cone (`structure::generate::beam::section_at`): the section
//! at s is the annulus between r(s) and max(r(s) - t, 0), solid where r < t. Its mass,
//! moments and volume are integrals of polynomials in r(s) and s; [`NoseShape::integrate`]
//! computes them by Gauss-Legendre quadrature after the substitution s = L u^4 (which makes
//! r(s) = R (s/L)^n and the Haack profile's s^(3/4) tip smooth: the integrands become
//! polynomials times u^(4n + 3)), split at the station where r = t (the kink of the section).

use serde::{Deserialize, Serialize};

/// A nose profile (module doc). Parameters are the shapes' own (k, K, n, C).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NoseShape {
    Conical,
    Ogive { k: f64 },
    Elliptical,
    Parabolic { k: f64 },
    Power { n: f64 },
    Haack { c: f64 },
}

/// The named forms `nose_shape` takes without a parameter.
pub const NAMED: &[(&str, NoseShape)] = &[
    ("conical", NoseShape::Conical),
    ("ogive", NoseShape::Ogive { k: 1.0 }),
    ("elliptical", NoseShape::Elliptical),
    ("parabolic", NoseShape::Parabolic { k: 1.0 }),
    ("von_karman", NoseShape::Haack { c: 0.0 }),
    ("lv_haack", NoseShape::Haack { c: 1.0 / 3.0 }),
];

/// The parameterised forms: (name, the parameter's letter, its range).
pub const WITH_PARAMETER: &[(&str, &str, &str)] = &[
    ("ogive", "k", "0 < k <= 1"),
    ("parabolic", "K", "0 <= K <= 1"),
    ("power", "n", "0 < n <= 1"),
    ("haack", "C", "0 <= C <= 2/3"),
];

impl NoseShape {
    /// The shape `name(p)` with its parameter, or the range it must lie in.
    pub fn with_parameter(name: &str, p: f64) -> Result<NoseShape, &'static str> {
        let ok = |c: bool, s: NoseShape, range: &'static str| if c { Ok(s) } else { Err(range) };
        match name {
            "ogive" => ok(p > 0.0 && p <= 1.0, NoseShape::Ogive { k: p }, "0 < k <= 1"),
            "parabolic" => ok(
                (0.0..=1.0).contains(&p),
                NoseShape::Parabolic { k: p },
                "0 <= K <= 1",
            ),
            "power" => ok(p > 0.0 && p <= 1.0, NoseShape::Power { n: p }, "0 < n <= 1"),
            "haack" => ok(
                (0.0..=2.0 / 3.0).contains(&p),
                NoseShape::Haack { c: p },
                "0 <= C <= 2/3",
            ),
            _ => Err(""),
        }
    }

    /// Whether this is the cone, whose integrals are closed-form polynomials everywhere.
    pub fn is_conical(self) -> bool {
        matches!(self, NoseShape::Conical)
    }

    /// How the shape reads in messages.
    pub fn describe(self) -> String {
        match self {
            NoseShape::Conical => "conical".into(),
            NoseShape::Ogive { k: 1.0 } => "tangent ogive".into(),
            NoseShape::Ogive { k } => format!("secant ogive (k = {k})"),
            NoseShape::Elliptical => "elliptical".into(),
            NoseShape::Parabolic { k } => format!("parabolic series (K = {k})"),
            NoseShape::Power { n } => format!("power series (n = {n})"),
            NoseShape::Haack { c: 0.0 } => "von Karman (Haack, C = 0)".into(),
            NoseShape::Haack { c } if c == 1.0 / 3.0 => "LV-Haack (Haack, C = 1/3)".into(),
            NoseShape::Haack { c } => format!("Haack series (C = {c})"),
        }
    }

    /// The language's spelling (`ogive`, `power(0.5)`).
    pub fn source_text(self) -> String {
        match self {
            NoseShape::Conical => "conical".into(),
            NoseShape::Ogive { k: 1.0 } => "ogive".into(),
            NoseShape::Ogive { k } => format!("ogive({k})"),
            NoseShape::Elliptical => "elliptical".into(),
            NoseShape::Parabolic { k: 1.0 } => "parabolic".into(),
            NoseShape::Parabolic { k } => format!("parabolic({k})"),
            NoseShape::Power { n } => format!("power({n})"),
            NoseShape::Haack { c: 0.0 } => "von_karman".into(),
            NoseShape::Haack { c } if c == 1.0 / 3.0 => "lv_haack".into(),
            NoseShape::Haack { c } => format!("haack({c})"),
        }
    }

    /// Outer radius at `s` aft of the tip, base radius `r`, nose length `l` (module doc).
    pub fn radius(self, s: f64, r: f64, l: f64) -> f64 {
        let s = s.clamp(0.0, l);
        match self {
            NoseShape::Conical => r * s / l,
            // (k below 1e-6: the cone, its limit; the circle's radius overflows the formula.)
            NoseShape::Ogive { k } if k < 1e-6 => r * s / l,
            NoseShape::Ogive { k } => {
                let (s, l) = if l < r { (s * r / l, r) } else { (s, l) };
                let rho = ((l * l + r * r) * ((2.0 - k) * (2.0 - k) * l * l + k * k * r * r)
                    / (4.0 * k * k * r * r))
                    .sqrt();
                let lk = l / k;
                let y0 = (rho * rho - lk * lk).max(0.0).sqrt();
                ((rho * rho - (lk - s) * (lk - s)).max(0.0).sqrt() - y0).clamp(0.0, r)
            }
            NoseShape::Elliptical => {
                let u = s / l;
                r * (2.0 * u - u * u).max(0.0).sqrt()
            }
            NoseShape::Parabolic { k } => {
                let u = s / l;
                r * (2.0 * u - k * u * u) / (2.0 - k)
            }
            NoseShape::Power { n } => r * (s / l).powf(n),
            NoseShape::Haack { c } => {
                let th = (1.0 - 2.0 * s / l).clamp(-1.0, 1.0).acos();
                r * ((th - (2.0 * th).sin() / 2.0 + c * th.sin().powi(3)) / std::f64::consts::PI)
                    .max(0.0)
                    .sqrt()
            }
        }
    }

    /// The station s (aft of the tip) where the outer radius reaches `t` (the end of the solid
    /// tip of a wall `t`), by bisection on the monotone profile; `l` if it never does.
    pub fn solid_tip_end(self, t: f64, r: f64, l: f64) -> f64 {
        if self.is_conical() {
            return t * l / r;
        }
        if self.radius(l, r, l) <= t {
            return l;
        }
        let (mut a, mut b) = (0.0, l);
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            if self.radius(m, r, l) < t {
                a = m;
            } else {
                b = m;
            }
        }
        0.5 * (a + b)
    }

    /// `∫_{s0}^{s1} f(s, r(s)) ds` for f polynomial in r and s, by [`Self::rule`].
    pub fn integrate(
        self,
        r: f64,
        l: f64,
        s0: f64,
        s1: f64,
        panels: usize,
        f: impl Fn(f64, f64) -> f64,
    ) -> f64 {
        Self::rule(l, s0, s1, panels)
            .into_iter()
            .map(|(s, w)| w * f(s, self.radius(s, r, l)))
            .sum()
    }

    /// Quadrature points and weights `(s, w)` for `∫_{s0}^{s1} g(s) ds` over a nose of length
    /// `l` (0 <= s0 < s1 <= l): 5-point Gauss-Legendre on `panels` panels of u, with
    /// s = (l/2) u^4 on the fore half of the nose and s = l - (l/2) u^4 on the aft half, so
    /// that a profile's power-law behaviour at the tip (r ~ s^n, the Haack nose's s^(3/4)) and
    /// at the base (the Haack nose's r^2 ~ R^2 - c (l - s)^(3/2)) becomes smooth in u.
    pub fn rule(l: f64, s0: f64, s1: f64, panels: usize) -> Vec<(f64, f64)> {
        let half = 0.5 * l;
        let mut out = Vec::with_capacity(10 * panels);
        // Fore half: s = half u^4.
        let (a, b) = (s0.max(0.0), s1.min(half));
        if b > a {
            let (u0, u1) = ((a / half).powf(0.25), (b / half).powf(0.25));
            gauss(u0, u1, panels, |u, w| {
                out.push((half * u.powi(4), w * 4.0 * half * u.powi(3)));
            });
        }
        // Aft half: s = l - half u^4 (u decreasing as s grows; the weight's sign absorbed).
        let (a, b) = (s0.max(half), s1.min(l));
        if b > a {
            let (u0, u1) = (((l - b) / half).powf(0.25), ((l - a) / half).powf(0.25));
            gauss(u0, u1, panels, |u, w| {
                out.push((l - half * u.powi(4), w * 4.0 * half * u.powi(3)));
            });
        }
        out
    }

    /// Volume enclosed by the profile, `∫ pi r^2 ds` over the nose.
    pub fn volume(self, r: f64, l: f64) -> f64 {
        if self.is_conical() {
            return std::f64::consts::PI * r * r * l / 3.0;
        }
        self.integrate(r, l, 0.0, l, 64, |_, ro| std::f64::consts::PI * ro * ro)
    }

    /// Planform (side-view) area `∫ 2 r ds` and its centroid's distance aft of the tip.
    pub fn planform(self, r: f64, l: f64) -> (f64, f64) {
        if self.is_conical() {
            return (r * l, 2.0 / 3.0 * l);
        }
        let a = self.integrate(r, l, 0.0, l, 64, |_, ro| 2.0 * ro);
        let m = self.integrate(r, l, 0.0, l, 64, |s, ro| 2.0 * ro * s);
        (a, m / a)
    }

    /// Wetted (outer surface) area `∫ 2 pi r sqrt(1 + r'^2) ds`, r' by central differences
    /// of the profile (step 1e-6 L; the integrand is smooth after the substitution).
    pub fn wetted_area(self, r: f64, l: f64) -> f64 {
        if self.is_conical() {
            return std::f64::consts::PI * r * (r * r + l * l).sqrt();
        }
        let h = 1e-6 * l;
        self.integrate(r, l, 0.0, l, 64, |s, ro| {
            let (a, b) = ((s - h).max(0.0), (s + h).min(l));
            let slope = (self.radius(b, r, l) - self.radius(a, r, l)) / (b - a);
            2.0 * std::f64::consts::PI * ro * (1.0 + slope * slope).sqrt()
        })
    }
}

/// 5-point Gauss-Legendre on `panels` equal panels of [a, b]: calls `point(x, weight)`.
fn gauss(a: f64, b: f64, panels: usize, mut point: impl FnMut(f64, f64)) {
    const GAUSS5: [(f64, f64); 5] = [
        (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
        (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
        (0.0, 0.568_888_888_888_888_9),
        (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
        (0.906_179_845_938_664, 0.236_926_885_056_189_1),
    ];
    let h = (b - a) / panels as f64;
    for p in 0..panels {
        let mid = a + (p as f64 + 0.5) * h;
        for &(x, w) in &GAUSS5 {
            point(mid + 0.5 * h * x, 0.5 * h * w);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn all() -> Vec<NoseShape> {
        vec![
            NoseShape::Conical,
            NoseShape::Ogive { k: 1.0 },
            NoseShape::Ogive { k: 0.5 },
            NoseShape::Elliptical,
            NoseShape::Parabolic { k: 1.0 },
            NoseShape::Parabolic { k: 0.5 },
            NoseShape::Power { n: 0.5 },
            NoseShape::Power { n: 0.25 },
            NoseShape::Haack { c: 0.0 },
            NoseShape::Haack { c: 1.0 / 3.0 },
            NoseShape::Haack { c: 2.0 / 3.0 },
        ]
    }

    #[test]
    fn every_profile_rises_from_the_tip_to_the_base() {
        let (r, l) = (0.051, 0.4);
        for s in all() {
            assert_eq!(s.radius(0.0, r, l), 0.0, "{s:?} tip");
            assert!((s.radius(l, r, l) - r).abs() < 1e-15, "{s:?} base");
            let mut last = 0.0;
            for i in 1..=1000 {
                let y = s.radius(l * i as f64 / 1000.0, r, l);
                assert!(y >= last - 1e-15, "{s:?} rises");
                last = y;
            }
        }
    }

    /// Closed forms: the solid volumes of the cone (pi R^2 L/3), the half-ellipsoid
    /// (2 pi R^2 L/3), the full parabola K = 1 (8 pi R^2 L/15: r = R(2u - u^2), ∫(2u - u^2)^2
    /// du = 4/3 - 1 + 1/5), the power series (pi R^2 L/(2n + 1)) and the von Karman nose
    /// (pi R^2 L/2: ∫ (theta - sin 2theta/2) (sin theta/2) dtheta over [0, pi] / pi, = 1/2).
    #[test]
    fn volumes_match_their_closed_forms() {
        let (r, l) = (0.051, 0.4);
        let base = PI * r * r * l;
        for (s, v) in [
            (NoseShape::Elliptical, 2.0 / 3.0),
            (NoseShape::Parabolic { k: 1.0 }, 8.0 / 15.0),
            (NoseShape::Power { n: 0.5 }, 0.5),
            (NoseShape::Power { n: 0.25 }, 1.0 / 1.5),
            (NoseShape::Haack { c: 0.0 }, 0.5),
        ] {
            let got = s.volume(r, l) / base;
            assert!((got - v).abs() < 1e-12, "{s:?}: {got} vs {v}");
        }
        // The quadrature on the cone (a polynomial of degree 11 in u after the substitution,
        // so not exact for 5-point Gauss), against its closed form.
        let q = NoseShape::Conical.integrate(r, l, 0.0, l, 64, |_, ro| PI * ro * ro);
        assert!(
            (q / base - 1.0 / 3.0).abs() < 1e-14,
            "{}",
            q / base - 1.0 / 3.0
        );
    }

    #[test]
    fn the_solid_tip_ends_where_the_radius_is_the_wall() {
        let (r, l, t) = (0.051, 0.4, 0.002);
        for s in all() {
            let e = s.solid_tip_end(t, r, l);
            assert!((s.radius(e, r, l) - t).abs() < 1e-13, "{s:?}");
        }
    }

    #[test]
    fn parameters_out_of_range_are_refused() {
        for (name, p) in [
            ("power", 0.0),
            ("power", 1.5),
            ("haack", -0.1),
            ("haack", 0.7),
            ("ogive", 0.0),
            ("parabolic", 1.2),
        ] {
            assert!(NoseShape::with_parameter(name, p).is_err(), "{name}({p})");
        }
        assert!(NoseShape::with_parameter("haack", 2.0 / 3.0).is_ok());
    }
}
