//! Fin root bending stress approximation (thesis 5.6, eqs. (5.6.1)-(5.6.2)).
//!
//! The fin is taken as a cantilevered Euler-Bernoulli beam of rectangular section (average
//! chord c̄ by thickness t): `σ = M z_c / I` (5.6.1) with `I = c̄ t³ / 12` and `z_c = t/2`, so
//! `σ = 6 M / (c̄ t²)`. The thesis writes `M = N_f y_cp` and, for the critical load (5.6.2),
//! places the centre of pressure at mid-span. We use the root bending moment of the
//! distributed nodal normal loads instead, `M = Σ_k f_k (y_k - y_root)`, which equals
//! `N_f y_cp` with the centre of pressure of the actual distribution (the spanwise moment
//! the fin load weights carry exactly, see [`crate::aero::fin_loads`]). The
//! critical normal force of (5.6.2) is also given, for reports.

/// The stress model of one fin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FinRootStress {
    /// Fin thickness t, m.
    pub thickness: f64,
    /// Average chord c̄ = (c_r + c_t)/2, m.
    pub mean_chord: f64,
    /// Fin span b, m.
    pub span: f64,
    /// Material yield stress σ_y, Pa (None when the material does not state it).
    pub yield_stress: Option<f64>,
}

impl FinRootStress {
    /// Section second moment `I = c̄ t³ / 12` (5.6).
    pub fn second_moment(&self) -> f64 {
        self.mean_chord * self.thickness.powi(3) / 12.0
    }

    /// Bending stress magnitude `|M| z_c / I` (5.6.1) of the root bending moment `moment` (N m).
    pub fn stress(&self, moment: f64) -> f64 {
        moment.abs() * 0.5 * self.thickness / self.second_moment()
    }

    /// Critical normal force `(N_f)_cr = 2 σ_y I / (b z_c)` (5.6.2) (centre of pressure at
    /// mid-span), or None without a yield stress.
    pub fn critical_normal_force(&self) -> Option<f64> {
        self.yield_stress
            .map(|sy| 2.0 * sy * self.second_moment() / (self.span * 0.5 * self.thickness))
    }

    /// `σ / σ_y` of a stress, or None without a yield stress.
    pub fn yield_fraction(&self, stress: f64) -> Option<f64> {
        self.yield_stress.map(|sy| stress / sy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flexure_formula_and_critical_force_agree() {
        let s = FinRootStress {
            thickness: 1e-3,
            mean_chord: 0.2,
            span: 0.12,
            yield_stress: Some(275e6),
        };
        // I = 0.2 * 1e-9 / 12; sigma = 6 M / (c t^2) for M = 1 N m: 6 / (0.2e-6) = 30 MPa.
        assert!((s.stress(1.0) - 30e6).abs() < 1e-3);
        // At the critical force with the load at mid-span the stress is the yield stress.
        let n = s.critical_normal_force().unwrap();
        assert!((s.stress(n * 0.06) - 275e6).abs() < 1e-3 * 275e6);
        assert!((s.yield_fraction(s.stress(n * 0.06)).unwrap() - 1.0).abs() < 1e-12);
    }
}
