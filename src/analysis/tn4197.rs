//! The NACA TN 4197 fin flutter boundary (D. J. Martin, "Summary of Flutter Experiences as
//! a Guide to the Preliminary Design of Lifting Surfaces on Missiles", NACA TN 4197, 1958),
//! in the form popularised for rocket fins by J. Bennett / Apogee "Peak of Flight" newsletter
//! 291 (2011) and used by RocketPy's fin flutter analysis:
//!
//! ```text
//! V_f = a sqrt( G / X ),   X = 1.337 AR^3 p (lambda + 1) / (2 (AR + 2) (t/c)^3)
//! ```
//!
//! with `a` the speed of sound, `G` the shear modulus of the fin material, `p` the ambient
//! (static) pressure, `AR = b^2 / S_fin` the aspect ratio of ONE fin panel (span b, planform
//! area S_fin), `lambda = c_t / c_r` the taper ratio and `t/c = t / c_r` the thickness ratio
//! at the root. The constant `1.337 = 24 eps gamma / (2 pi)` with `eps = 0.25` (elastic axis
//! a quarter chord behind the aerodynamic centre) and `gamma = 1.4` is dimensionless (Martin's
//! form writes `39.3 = 1.337 x 2 x 14.7 psi` with `p / p0`), so `G / p` may be given in any
//! consistent units; here both are Pa. The flutter Mach number is `V_f / a = sqrt(G / X)`.
//!
//! This is an empirical boundary for the torsion-dominated flutter of a cantilevered panel;
//! the planar models of chapter 6 instead predict the loss of pitch stability through fin
//! bending, so the two answer different questions and are printed side by side.

use serde::Serialize;

/// What the formula needs of one fin panel.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Tn4197Fin {
    /// Shear modulus G, Pa.
    pub shear_modulus: f64,
    /// Span b, m.
    pub span: f64,
    pub root_chord: f64,
    pub tip_chord: f64,
    /// Thickness t, m.
    pub thickness: f64,
}

impl Tn4197Fin {
    /// Aspect ratio of one panel `b^2 / S_fin`.
    pub fn aspect_ratio(&self) -> f64 {
        let area = 0.5 * (self.root_chord + self.tip_chord) * self.span;
        self.span * self.span / area
    }

    /// The flutter Mach number `sqrt(G / X)` at ambient pressure `pressure` (Pa); see the
    /// module doc. Non-finite when the inputs are not positive.
    pub fn flutter_mach(&self, pressure: f64) -> f64 {
        let ar = self.aspect_ratio();
        let taper = self.tip_chord / self.root_chord;
        let tc = self.thickness / self.root_chord;
        let x = 1.337 * ar.powi(3) * pressure * (taper + 1.0) / (2.0 * (ar + 2.0) * tc.powi(3));
        (self.shear_modulus / x).sqrt()
    }

    /// The flutter speed `V_f = a sqrt(G / X)`, m/s.
    pub fn flutter_speed(&self, pressure: f64, speed_of_sound: f64) -> f64 {
        speed_of_sound * self.flutter_mach(pressure)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand calculation: b = 0.1 m, c_r = 0.2 m, c_t = 0.1 m, t = 2 mm, G = 26 GPa,
    /// p = 50 kPa, a = 320 m/s. S_fin = 0.015 m^2, AR = 0.01/0.015 = 0.666667, lambda = 0.5,
    /// t/c = 0.01; X = 1.337 * 0.296296 * 50000 * 1.5 / (2 * 2.666667 * 1e-6)
    /// = 29711.1 / 5.333333e-6 = 5.570833e9; G/X = 4.667165; sqrt = 2.160362;
    /// V_f = 320 * 2.160362 = 691.316 m/s.
    #[test]
    fn matches_hand_calculation() {
        let f = Tn4197Fin {
            shear_modulus: 26e9,
            span: 0.1,
            root_chord: 0.2,
            tip_chord: 0.1,
            thickness: 0.002,
        };
        assert!((f.aspect_ratio() - 0.666_666_7).abs() < 1e-6);
        assert!((f.flutter_mach(50_000.0) - 2.160_362).abs() < 1e-6);
        assert!((f.flutter_speed(50_000.0, 320.0) - 691.316).abs() < 1e-3);
    }

    /// Scaling laws read off the formula: V_f ~ t^(3/2) and ~ p^(-1/2).
    #[test]
    fn scales_with_thickness_and_pressure() {
        let f = |t: f64| Tn4197Fin {
            shear_modulus: 26e9,
            span: 0.127,
            root_chord: 0.325,
            tip_chord: 0.123,
            thickness: t,
        };
        let r = f(2e-3).flutter_mach(30_000.0) / f(1e-3).flutter_mach(30_000.0);
        assert!((r - 2f64.powf(1.5)).abs() < 1e-12);
        let r = f(1e-3).flutter_mach(10_000.0) / f(1e-3).flutter_mach(40_000.0);
        assert!((r - 2.0).abs() < 1e-12);
    }
}
