//! The NACA TN 4197 fin flutter boundary: D. J. Martin, "Summary of Flutter Experiences as
//! a Guide to the Preliminary Design of Lifting Surfaces on Missiles", NACA TN 4197 (1958),
//! and the form popularised for rocket fins by J. Bennett's Apogee "Peak of Flight"
//! newsletter 291 (2011), used by RocketPy (`rocketpy/utilities.py`, `_flutter_mach_number`).
//! They differ by a factor of 2 under the root, i.e. sqrt(2) in speed; [`Tn4197Form`] has
//! both and the original is the default.
//!
//! **Martin (TN 4197)**, as every secondary source quotes it (we could not read the report
//! itself: no copy of its text is reachable here, so the equation below is the quoted one,
//! checked for self-consistency): with G in psi and p, p0 = 14.7 psi,
//!
//! ```text
//! V_f = a sqrt( G / ( 39.3 A^3 / ((t/c)^3 (A + 2)) * (lambda + 1)/2 * p/p0 ) )
//! ```
//!
//! The dimensional constant is `39.3 psi = 24 eps gamma p0 / pi` with `eps = 0.25` (the
//! elastic axis a quarter chord behind the aerodynamic centre), `gamma = 1.4` and
//! `p0 = 14.7 psi`: `24 x 0.25 x 1.4 x 14.7 / pi = 39.305 psi`. Dividing it by `p0` gives a
//! dimensionless form in any consistent units (here Pa):
//!
//! ```text
//! V_f / a = sqrt( G / X_M ),   X_M = (39.3/14.7) A^3 p (lambda + 1) / (2 (A + 2) (t/c)^3)
//! ```
//!
//! with `39.3 / 14.7 = 2.6735` (`24 eps gamma / pi = 2.6738`, the same to 1.2e-4).
//!
//! **Peak of Flight 291 / RocketPy**:
//!
//! ```text
//! V_f / a = sqrt( G / X_P ),   X_P = 1.337 A^3 p (lambda + 1) / (2 (A + 2) (t/c)^3)
//! ```
//!
//! `1.337 = 39.3 / (2 x 14.7)`: the constant was halved to absorb the 2 of `(lambda + 1)/2`,
//! and the 2 was then written in the denominator as well, so `X_P = X_M / 2` (to the rounding
//! of 1.337: `X_M / X_P = 1.99960`) and the PoF 291 speed is `sqrt(2)` times Martin's, i.e.
//! unconservative by 41 %. J. Cipolla (AeroRocket, "POF 291 Flutter Velocity Error Produces
//! Negative Margins of Safety Compared to NACA TN 4197", Technical Note 2021-2 V3, 2021,
//! summarised at aerorocket.com/finsim.html) reports the same factor, and his worked example
//! (aerorocket.com/FinSim_Supersonic_Flutter.html, Table 1) gives Mach 3.89 by TN 4197 and
//! 5.50 by PoF 291 for one fin: `5.50 / 3.89 = 1.414`.
//!
//! Symbols: `a` the speed of sound, `G` the shear modulus of the fin material, `p` the
//! ambient (static) pressure, `A = b^2 / S_fin` the aspect ratio of ONE fin panel (span b,
//! planform area S_fin), `lambda = c_t / c_r` the taper ratio and `t/c = t / c_r` the
//! thickness ratio at the root. The flutter Mach number is `V_f / a`.
//!
//! This is an empirical boundary for the torsion-dominated flutter of a cantilevered panel;
//! the planar models of chapter 6 instead predict the loss of pitch stability through fin
//! bending, so the two answer different questions and are printed side by side.

use serde::Serialize;

/// Which published form of the TN 4197 boundary (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Tn4197Form {
    /// Martin's original: `39.3 psi`, `(lambda + 1)/2`, `p/p0` (the default everywhere).
    Martin,
    /// Peak of Flight 291 / RocketPy: `1.337` and a further 2 in the denominator.
    PeakOfFlight291,
}

impl Tn4197Form {
    /// Both forms, the original first.
    pub const ALL: [Tn4197Form; 2] = [Tn4197Form::Martin, Tn4197Form::PeakOfFlight291];

    /// The coefficient `k` of `X = k A^3 p (lambda + 1) / (2 (A + 2) (t/c)^3)`.
    pub fn coefficient(self) -> f64 {
        match self {
            // 39.3 psi / p0 with p0 = 14.7 psi (module doc).
            Tn4197Form::Martin => 39.3 / 14.7,
            Tn4197Form::PeakOfFlight291 => 1.337,
        }
    }

    /// Short name for tables and CSV headers.
    pub fn name(self) -> &'static str {
        match self {
            Tn4197Form::Martin => "TN 4197 (Martin 1958)",
            Tn4197Form::PeakOfFlight291 => "TN 4197 as in Peak of Flight 291 / RocketPy",
        }
    }
}

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

    /// The flutter Mach number of Martin's original form at ambient pressure `pressure`
    /// (Pa); see the module doc. Non-finite when the inputs are not positive.
    pub fn flutter_mach(&self, pressure: f64) -> f64 {
        self.flutter_mach_in(Tn4197Form::Martin, pressure)
    }

    /// The flutter Mach number `sqrt(G / X)` of `form` at ambient pressure `pressure` (Pa).
    pub fn flutter_mach_in(&self, form: Tn4197Form, pressure: f64) -> f64 {
        let ar = self.aspect_ratio();
        let taper = self.tip_chord / self.root_chord;
        let tc = self.thickness / self.root_chord;
        let x = form.coefficient() * ar.powi(3) * pressure * (taper + 1.0)
            / (2.0 * (ar + 2.0) * tc.powi(3));
        (self.shear_modulus / x).sqrt()
    }

    /// The flutter speed `V_f = a sqrt(G / X)` of `form`, m/s.
    pub fn flutter_speed_in(&self, form: Tn4197Form, pressure: f64, speed_of_sound: f64) -> f64 {
        speed_of_sound * self.flutter_mach_in(form, pressure)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hand_fin() -> Tn4197Fin {
        Tn4197Fin {
            shear_modulus: 26e9,
            span: 0.1,
            root_chord: 0.2,
            tip_chord: 0.1,
            thickness: 0.002,
        }
    }

    /// Hand calculation in Martin's own units and layout, converted: b = 0.1 m,
    /// c_r = 0.2 m, c_t = 0.1 m, t = 2 mm, G = 26 GPa, p = 50 kPa, a = 320 m/s.
    /// S_fin = 0.015 m^2, A = 0.01/0.015 = 2/3, A^3 = 8/27, lambda = 0.5, t/c = 0.01.
    /// G = 26e9 / 6894.757293168 = 3_770_981.4 psi, p/p0 = 50000 / (14.7 x 6894.757293168)
    /// = 0.493331; 39.3 A^3 / ((t/c)^3 (A + 2)) = 39.3 x 0.296296 / (1e-6 x 2.666667)
    /// = 4_366_666.7 psi; x (lambda + 1)/2 = 0.75 -> 3_275_000.0; x p/p0 -> 1_615_659.0 psi;
    /// G / that = 2.334046, sqrt = 1.527758; V_f = 320 x 1.527758 = 488.883 m/s.
    #[test]
    fn martin_matches_a_hand_calculation_in_psi() {
        let f = hand_fin();
        assert!((f.aspect_ratio() - 2.0 / 3.0).abs() < 1e-15);
        let m = f.flutter_mach(50_000.0);
        assert!((m - 1.527_758).abs() < 5e-7, "{m}");
        let v = f.flutter_speed_in(Tn4197Form::Martin, 50_000.0, 320.0);
        assert!((v - 488.883).abs() < 5e-4, "{v}");
        // The same with the formula evaluated literally in psi (the report's units).
        let psi = 6_894.757_293_168;
        let (g_psi, p_psi) = (26e9 / psi, 50_000.0 / psi);
        let (a, tc) = (2.0f64 / 3.0, 0.01f64);
        let x = 39.3 * a.powi(3) / (tc.powi(3) * (a + 2.0)) * (1.5 / 2.0) * (p_psi / 14.7);
        assert!(((g_psi / x).sqrt() - m).abs() < 1e-14);
    }

    /// Hand calculation of the PoF 291 form with the same fin: X = 1.337 x 0.296296 x 50000
    /// x 1.5 / (2 x 2.666667 x 1e-6) = 29711.1 / 5.333333e-6 = 5.570833e9; G/X = 4.667165;
    /// sqrt = 2.160362; V_f = 320 x 2.160362 = 691.316 m/s; and the ratio to Martin's is
    /// sqrt((39.3/14.7) / 1.337) = 1.414073, sqrt(2) to the rounding of 1.337.
    #[test]
    fn peak_of_flight_form_is_sqrt_two_faster() {
        let f = hand_fin();
        let m = f.flutter_mach_in(Tn4197Form::PeakOfFlight291, 50_000.0);
        assert!((m - 2.160_362).abs() < 5e-7, "{m}");
        let v = f.flutter_speed_in(Tn4197Form::PeakOfFlight291, 50_000.0, 320.0);
        assert!((v - 691.316).abs() < 5e-4, "{v}");
        let ratio = m / f.flutter_mach(50_000.0);
        assert!((ratio - 1.414_073_241_456_3).abs() < 1e-12, "{ratio}");
        assert!((ratio - 2f64.sqrt()).abs() < 2e-4);
    }

    /// The constants: 39.3 psi = 24 eps gamma p0 / pi with eps = 0.25, gamma = 1.4,
    /// p0 = 14.7 psi (to the 3 digits printed), and 1.337 = 39.3 / (2 x 14.7).
    #[test]
    fn constants_are_consistent() {
        let derived = 24.0 * 0.25 * 1.4 * 14.7 / std::f64::consts::PI;
        assert!((derived - 39.3).abs() < 0.01, "{derived}");
        assert!((39.3f64 / (2.0 * 14.7) - 1.337).abs() < 5e-4);
        assert_eq!(Tn4197Form::Martin.coefficient(), 39.3 / 14.7);
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
        for form in Tn4197Form::ALL {
            let r =
                f(2e-3).flutter_mach_in(form, 30_000.0) / f(1e-3).flutter_mach_in(form, 30_000.0);
            assert!((r - 2f64.powf(1.5)).abs() < 1e-14);
            let r =
                f(1e-3).flutter_mach_in(form, 10_000.0) / f(1e-3).flutter_mach_in(form, 40_000.0);
            assert!((r - 2.0).abs() < 1e-14);
        }
    }
}
