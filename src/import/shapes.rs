//! Nose-cone profiles as OpenRocket defines them, and the mass of a shell of revolution.
//!
//! The profiles r(x) for 0 <= x <= L (x from the tip, R the aft radius, k the shape
//! parameter) are those of the OpenRocket technical documentation (S. Niskanen, 2009,
//! section 3.1.1 "Nose cones") as implemented in OpenRocket's `Transition.Shape`
//! (core/src/main/java/info/openrocket/core/rocketcomponent/Transition.java, read at commit
//! 8fa969d8):
//!
//! - conical: r = R x / L;
//! - ogive (k in [0, 1]; k = 1 tangent, k -> 0 a cone, between: secant ogives): the arc of
//!   the circle of radius rho = sqrt((L^2 + R^2)((2 - k)^2 L^2 + k^2 R^2) / (4 k^2 R^2))
//!   centred at (L/k, -y0), y0 = sqrt(rho^2 - (L/k)^2): r = sqrt(rho^2 - (L/k - x)^2) - y0
//!   (for L < R, x and L are scaled by R/L first, as OpenRocket does);
//! - ellipsoid: with x' = x R / L, r = sqrt(2 R x' - x'^2);
//! - power series: r = R (x/L)^k;
//! - parabolic series: r = R (2 x/L - k (x/L)^2) / (2 - k);
//! - Haack series: theta = acos(1 - 2x/L), r = R sqrt((theta - sin(2 theta)/2 + k sin^3
//!   theta) / pi) (k = 0 von Karman, k = 1/3 LV-Haack).
//!
//! The mass of a nose shell uses the wall the structure generator gives the conical nose
//! (`structure::generate::beam::section_at`): a solid of revolution between r(x) and
//! max(r(x) - t, 0), so that the imported mass correction (true shape minus the generated
//! cone) compares like with like.

use std::f64::consts::PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NoseShape {
    Conical,
    Ogive(f64),
    Ellipsoid,
    Power(f64),
    Parabolic(f64),
    Haack(f64),
}

impl NoseShape {
    /// From OpenRocket's `<shape>` and `<shapeparameter>`; `None` for an unknown shape.
    pub fn from_ork(shape: &str, k: f64) -> Option<NoseShape> {
        Some(match shape.trim().to_ascii_lowercase().as_str() {
            "conical" => NoseShape::Conical,
            "ogive" => NoseShape::Ogive(k.clamp(0.0, 1.0)),
            "ellipsoid" => NoseShape::Ellipsoid,
            "power" => NoseShape::Power(k.clamp(0.0, 1.0)),
            "parabolic" => NoseShape::Parabolic(k.clamp(0.0, 1.0)),
            "haack" => NoseShape::Haack(k.clamp(0.0, 2.0)),
            _ => return None,
        })
    }

    /// The language's `nose_shape` for this profile (`check::nose`, the same formulas), if it
    /// has one: OpenRocket's power series with k = 0 (a blunt cylinder) and Haack parameters
    /// above 2/3 (a bulging profile) have none.
    pub fn to_language(self) -> Option<crate::check::ir::NoseShape> {
        use crate::check::ir::NoseShape as L;
        Some(match self {
            NoseShape::Conical => L::Conical,
            NoseShape::Ogive(k) if k < 1e-6 => L::Conical,
            NoseShape::Ogive(k) => L::Ogive { k },
            NoseShape::Ellipsoid => L::Elliptical,
            NoseShape::Power(k) if k > 0.0 => L::Power { n: k },
            NoseShape::Power(_) => return None,
            NoseShape::Parabolic(k) => L::Parabolic { k },
            NoseShape::Haack(k) if k <= 2.0 / 3.0 => L::Haack { c: k },
            NoseShape::Haack(_) => return None,
        })
    }

    pub fn describe(self) -> String {
        match self {
            NoseShape::Conical => "conical".into(),
            NoseShape::Ogive(k) if (k - 1.0).abs() < 1e-9 => "tangent ogive".into(),
            NoseShape::Ogive(k) => format!("secant ogive (k = {k})"),
            NoseShape::Ellipsoid => "ellipsoid".into(),
            NoseShape::Power(k) => format!("power series (k = {k})"),
            NoseShape::Parabolic(k) => format!("parabolic series (k = {k})"),
            NoseShape::Haack(k) if k.abs() < 1e-9 => "von Karman (Haack, k = 0)".into(),
            NoseShape::Haack(k) if (k - 1.0 / 3.0).abs() < 1e-6 => {
                "LV-Haack (Haack, k = 1/3)".into()
            }
            NoseShape::Haack(k) => format!("Haack series (k = {k})"),
        }
    }

    /// Radius at `x` from the tip (module doc).
    pub fn radius(self, x: f64, r: f64, l: f64) -> f64 {
        let x = x.clamp(0.0, l);
        match self {
            NoseShape::Conical => r * x / l,
            NoseShape::Ogive(k) => {
                if k < 1e-6 {
                    return r * x / l;
                }
                let (x, l) = if l < r { (x * r / l, r) } else { (x, l) };
                let rho = ((l * l + r * r) * ((2.0 - k) * (2.0 - k) * l * l + k * k * r * r)
                    / (4.0 * k * k * r * r))
                    .sqrt();
                let lk = l / k;
                let y0 = (rho * rho - lk * lk).max(0.0).sqrt();
                ((rho * rho - (lk - x) * (lk - x)).max(0.0)).sqrt() - y0
            }
            NoseShape::Ellipsoid => {
                let x = x * r / l;
                (2.0 * r * x - x * x).max(0.0).sqrt()
            }
            NoseShape::Power(k) => {
                if k <= 1e-5 {
                    if x <= 1e-5 { 0.0 } else { r }
                } else {
                    r * (x / l).powf(k)
                }
            }
            NoseShape::Parabolic(k) => r * ((2.0 * x / l - k * (x / l).powi(2)) / (2.0 - k)),
            NoseShape::Haack(k) => {
                let th = (1.0 - 2.0 * x / l).clamp(-1.0, 1.0).acos();
                r * ((th - (2.0 * th).sin() / 2.0 + k * th.sin().powi(3)) / PI)
                    .max(0.0)
                    .sqrt()
            }
        }
    }

    /// Mass and centroid (distance from the tip) of the shell of wall `t`, density `rho`
    /// (module doc), by composite Simpson's rule on 2000 panels.
    pub fn shell_mass(self, r: f64, l: f64, t: f64, rho: f64, filled: bool) -> (f64, f64) {
        let n = 2000;
        let h = l / n as f64;
        let (mut m, mut mx) = (0.0, 0.0);
        for i in 0..=n {
            let x = i as f64 * h;
            let ro = self.radius(x, r, l);
            let ri = if filled { 0.0 } else { (ro - t).max(0.0) };
            let a = PI * (ro * ro - ri * ri);
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            m += w * a;
            mx += w * a * x;
        }
        let m = rho * m * h / 3.0;
        let mx = rho * mx * h / 3.0;
        (m, if m > 0.0 { mx / m } else { 0.0 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_profile_runs_from_the_tip_to_the_base() {
        let (r, l) = (0.05, 0.3);
        for s in [
            NoseShape::Conical,
            NoseShape::Ogive(1.0),
            NoseShape::Ogive(0.5),
            NoseShape::Ellipsoid,
            NoseShape::Power(0.5),
            NoseShape::Parabolic(0.75),
            NoseShape::Haack(0.0),
            NoseShape::Haack(1.0 / 3.0),
        ] {
            assert!(s.radius(0.0, r, l).abs() < 1e-12, "{s:?} tip");
            assert!((s.radius(l, r, l) - r).abs() < 1e-9, "{s:?} base");
            let mut last = 0.0;
            for i in 1..=100 {
                let y = s.radius(l * i as f64 / 100.0, r, l);
                assert!(y + 1e-12 >= last, "{s:?} grows monotonically");
                last = y;
            }
        }
    }

    /// Every OpenRocket shape the language can say maps to the same profile (the importer
    /// writes `nose_shape` instead of a cone): the two radius functions agree everywhere; the
    /// two it cannot say (power k = 0, Haack above 2/3) map to none.
    #[test]
    fn openrocket_shapes_map_to_the_languages_same_profiles() {
        let (r, l) = (0.0508, 0.4);
        for (shape, k) in [
            ("conical", 0.0),
            ("ogive", 1.0),
            ("ogive", 0.5),
            ("ogive", 0.0),
            ("ellipsoid", 0.0),
            ("power", 0.5),
            ("power", 1.0),
            ("parabolic", 0.75),
            ("parabolic", 1.0),
            ("haack", 0.0),
            ("haack", 1.0 / 3.0),
        ] {
            let or = NoseShape::from_ork(shape, k).unwrap();
            let lang = or.to_language().unwrap_or_else(|| panic!("{shape} {k}"));
            for i in 0..=400 {
                let x = l * i as f64 / 400.0;
                let (a, b) = (or.radius(x, r, l), lang.radius(x, r, l));
                assert!((a - b).abs() <= 1e-15, "{shape}({k}) at {x}: {a} vs {b}");
            }
        }
        assert!(NoseShape::Power(0.0).to_language().is_none());
        assert!(NoseShape::Haack(1.0).to_language().is_none());
    }

    #[test]
    fn tangent_ogive_meets_the_body_tangentially() {
        let (r, l) = (0.05, 0.3);
        let s = NoseShape::Ogive(1.0);
        let h = 1e-6;
        let slope = (s.radius(l, r, l) - s.radius(l - h, r, l)) / h;
        assert!(slope.abs() < 1e-3, "slope at the base {slope}");
    }

    #[test]
    fn filled_cone_mass_is_one_third_of_the_cylinder() {
        // V = pi R^2 L / 3, centroid 3L/4 from the tip.
        let (r, l, rho) = (0.05, 0.3, 1000.0);
        let (m, xc) = NoseShape::Conical.shell_mass(r, l, 0.0, rho, true);
        let exact = rho * PI * r * r * l / 3.0;
        assert!((m - exact).abs() / exact < 1e-9, "{m} vs {exact}");
        assert!((xc - 0.75 * l).abs() < 1e-9);
    }
}
