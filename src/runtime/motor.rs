//! The burning motor at run time: the propellant fraction `f(t)` and the mass flow, and the
//! reduced coefficients of the vehicle at `f` as the affine combination of the dry and the
//! propellant coefficients.
//!
//! # Burn law
//! The propellant burns in proportion to the delivered impulse (OpenRocket
//! `ThrustCurveMotor.getCGx`/`getTotalMass`, RocketPy `Motor.mass_flow_rate` with
//! `exhaust_velocity = total_impulse / propellant_initial_mass`): with the impulse delivered
//! so far `I(t) = ∫_0^t T dτ` and the total impulse `I_tot`,
//! ```text
//! f(t) = 1 - I(t) / I_tot,      m_prop(t) = f(t) m_p,      ṁ_e(t) = m_p T(t) / I_tot = T(t) / c,
//! ```
//! with `c = I_tot / m_p` the effective exhaust velocity (constant specific impulse
//! `c / g0`; the pressure thrust is folded into `c`, so `T = ṁ_e c` exactly). For the
//! piecewise-linear curve of [`ThrustCurve`] `I(t)` is the exact piecewise-quadratic integral
//! (trapezoid at the points plus the partial segment).
//!
//! # Coefficients
//! Every mass-dependent coefficient of [`ReducedModel`] is a linear function of the mass
//! matrix (one bilinear form `E(f, g)`, [`crate::structure::coefficients`]), so on one modal
//! basis `S` the model of the vehicle with propellant fraction `f` is
//! `coef(M_dry + f M_p) = coef(M_dry) + f coef(M_p)` exactly. The compiled vehicle holds the
//! full vehicle at ignition (`reduced`, on the ignition eigenmodes) and the propellant's
//! contribution at full load (`propellant`); the dry coefficients are their difference,
//! formed once. The stiffness `K̄` and the modal damping `C̄` do not depend on the
//! propellant and are those of the compiled vehicle.

use crate::runtime::thrust::ThrustCurve;
use crate::structure::coefficients::ReducedModel;

/// `f(t)` and `ṁ_e(t)` of one thrust curve and propellant mass (module doc).
#[derive(Debug, Clone)]
pub struct BurnSchedule {
    curve: ThrustCurve,
    times: Vec<f64>,
    thrust: Vec<f64>,
    /// `I` at `times`, N s.
    cumulative: Vec<f64>,
    total_impulse: f64,
    propellant_mass: f64,
}

impl BurnSchedule {
    /// The schedule of `curve` burning `propellant_mass` kg. A curve with no impulse burns
    /// nothing (`f = 1` throughout).
    pub fn new(curve: ThrustCurve, propellant_mass: f64) -> Self {
        let (times, thrust): (Vec<f64>, Vec<f64>) = curve.points().unzip();
        let mut cumulative = Vec::with_capacity(times.len());
        let mut acc = 0.0;
        for i in 0..times.len() {
            if i > 0 {
                acc += 0.5 * (thrust[i - 1] + thrust[i]) * (times[i] - times[i - 1]);
            }
            cumulative.push(acc);
        }
        Self {
            curve,
            times,
            thrust,
            cumulative,
            total_impulse: acc,
            propellant_mass,
        }
    }

    /// The thrust curve.
    pub fn curve(&self) -> &ThrustCurve {
        &self.curve
    }

    /// Total impulse `I_tot`, N s.
    pub fn total_impulse(&self) -> f64 {
        self.total_impulse
    }

    /// Propellant mass at ignition `m_p`, kg.
    pub fn propellant_mass(&self) -> f64 {
        self.propellant_mass
    }

    /// Effective exhaust velocity `c = I_tot / m_p`, m/s.
    pub fn exhaust_velocity(&self) -> f64 {
        self.total_impulse / self.propellant_mass
    }

    /// Impulse delivered up to `t`, `I(t)`, N s (exact for the piecewise-linear curve).
    pub fn impulse(&self, t: f64) -> f64 {
        let n = self.times.len();
        if n == 0 || t.is_nan() || t <= self.times[0] {
            return 0.0;
        }
        if t >= self.times[n - 1] {
            return self.total_impulse;
        }
        let i = self.times.partition_point(|&x| x <= t).clamp(1, n - 1) - 1;
        let (t0, t1) = (self.times[i], self.times[i + 1]);
        let tau = t - t0;
        let slope = (self.thrust[i + 1] - self.thrust[i]) / (t1 - t0);
        self.cumulative[i] + self.thrust[i] * tau + 0.5 * slope * tau * tau
    }

    /// Propellant fraction `f(t) = 1 - I(t)/I_tot` in `[0, 1]`.
    pub fn fraction(&self, t: f64) -> f64 {
        if self.total_impulse > 0.0 {
            (1.0 - self.impulse(t) / self.total_impulse).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    /// Mass flow leaving through the nozzle `ṁ_e = m_p T(t) / I_tot >= 0`, kg/s.
    pub fn mass_flow(&self, t: f64) -> f64 {
        if self.total_impulse > 0.0 {
            self.propellant_mass * self.curve.thrust_at(t) / self.total_impulse
        } else {
            0.0
        }
    }

    /// Thrust `T(t)`, N.
    pub fn thrust(&self, t: f64) -> f64 {
        self.curve.thrust_at(t)
    }
}

/// The mass-dependent coefficients of a reduced model at propellant fraction `f`: `dry + f
/// prop` into `out` (the fields `K̄`, `C̄`, `ω²`, `ζ` of `out` are left as they are). No
/// allocation: `out` already has the shapes of `dry`.
pub fn combine_into(dry: &ReducedModel, prop: &ReducedModel, f: f64, out: &mut ReducedModel) {
    out.mass = dry.mass + f * prop.mass;
    for i in 0..3 {
        out.first_moment[i] = dry.first_moment[i] + f * prop.first_moment[i];
        for k in 0..3 {
            out.inertia[i][k] = dry.inertia[i][k] + f * prop.inertia[i][k];
        }
    }
    axpy(&dry.modal_mass, &prop.modal_mass, f, &mut out.modal_mass);
    axpy(&dry.p_bar, &prop.p_bar, f, &mut out.p_bar);
    axpy(&dry.h_bar, &prop.h_bar, f, &mut out.h_bar);
    axpy(&dry.h_prime, &prop.h_prime, f, &mut out.h_prime);
    axpy3(&dry.j_ru, &prop.j_ru, f, &mut out.j_ru);
    axpy3(&dry.j_uu, &prop.j_uu, f, &mut out.j_uu);
}

/// The dry coefficients `full - prop` (the compiled vehicle at ignition minus its
/// propellant); stiffness, damping and frequencies are those of `full`.
pub fn dry_model(full: &ReducedModel, prop: &ReducedModel) -> ReducedModel {
    let mut dry = full.clone();
    combine_into(full, prop, -1.0, &mut dry);
    dry
}

fn axpy(a: &[f64], b: &[f64], f: f64, out: &mut [f64]) {
    for ((o, x), y) in out.iter_mut().zip(a).zip(b) {
        *o = x + f * y;
    }
}

fn axpy3(a: &[[[f64; 3]; 3]], b: &[[[f64; 3]; 3]], f: f64, out: &mut [[[f64; 3]; 3]]) {
    for ((o, x), y) in out.iter_mut().zip(a).zip(b) {
        for i in 0..3 {
            for k in 0..3 {
                o[i][k] = x[i][k] + f * y[i][k];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn impulse_is_the_exact_integral_of_the_piecewise_linear_curve() {
        let curve =
            ThrustCurve::from_points("t", &[(0.5, 100.0), (1.5, 300.0), (2.0, 0.0)]).unwrap();
        // Points (0,0), (0.5,100), (1.5,300), (2,0): I_tot = 25 + 200 + 75 = 300.
        let s = BurnSchedule::new(curve, 2.0);
        assert_eq!(s.total_impulse(), 300.0);
        // On (0.5, 1.5): T = 100 + 200 (t - 0.5); I(1) = 25 + 100·0.5 + 100·0.25 = 100.
        assert!((s.impulse(1.0) - 100.0).abs() < 1e-13);
        assert!((s.fraction(1.0) - (1.0 - 100.0 / 300.0)).abs() < 1e-15);
        assert_eq!(s.fraction(-1.0), 1.0);
        assert_eq!(s.fraction(5.0), 0.0);
        // ṁ_e = m_p T / I_tot, and f' = -ṁ_e / m_p by central differences.
        let h = 1e-6;
        let df = (s.fraction(1.0 + h) - s.fraction(1.0 - h)) / (2.0 * h);
        assert!((df + s.mass_flow(1.0) / 2.0).abs() < 1e-8, "{df}");
        assert!((s.exhaust_velocity() - 150.0).abs() < 1e-13);
    }
}
