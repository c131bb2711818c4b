//! Gravity, thesis 5.1: eqs. (5.1.1)-(5.1.6).

use crate::runtime::eom::{ForceModel, StateView, UniformGravity};
use crate::runtime::kinematics::mat_t_vec;
use crate::runtime::motor::BurnSchedule;
use crate::structure::coefficients::ReducedModel;

/// Standard gravity at sea level, m/s², eq. (5.1.1).
pub const G0: f64 = 9.806;
/// Earth radius of the altitude correction, m, eq. (5.1.2).
pub const EARTH_RADIUS: f64 = 6_378_000.0;

/// Magnitude of gravity at altitude `h` (m above sea level): `g0` without the correction,
/// `g0 (R_E / (R_E + h))²` with it, eq. (5.1.2).
pub fn gravity_at(h: f64, altitude_correction: bool) -> f64 {
    if altitude_correction {
        let r = EARTH_RADIUS / (EARTH_RADIUS + h);
        G0 * r * r
    } else {
        G0
    }
}

/// Potential energy per unit mass of the gravity model at altitude `h`, zero at sea level:
/// `g0 h` for uniform gravity, and for the inverse-square field of (5.1.2)
/// `∫_0^h g0 R_E²/(R_E+s)² ds = g0 R_E h / (R_E + h)`, whose derivative is exactly
/// [`gravity_at`], so the energy check of a run stays exact with the correction on.
pub fn potential_per_mass(h: f64, altitude_correction: bool) -> f64 {
    if altitude_correction {
        G0 * EARTH_RADIUS * h / (EARTH_RADIUS + h)
    } else {
        G0 * h
    }
}

/// Gravity on the flexible vehicle, eqs. (5.1.1)-(5.1.6).
///
/// `g_I = (0, 0, g(h))` (inertial z down, eq. 5.1.1), `g_B = C_BI g_I` (5.1.3),
/// `F_B = m g_B` (5.1.4), `G_B = c̄_tot(η) × g_B` about the body origin (5.1.5), modal forces
/// `Q = P̄ᵀ g_B` (5.1.6): the algebra of [`UniformGravity`], which this block reuses with `g`
/// set before each evaluation.
///
/// The altitude `h` of (5.1.2) is that of the mass centre, `h = -(p_I + C_IB c̄_tot/m)_z`:
/// the field then derives from the potential `m Φ(h_cm)` of [`potential_per_mass`] (its
/// virtual work `m g·δr_cm` is exactly `F_B`, `G_B`, `Q` above), so energy is conserved
/// with the correction on. The variation of `g` over the vehicle length (~10⁻⁶ g) is
/// neglected, as in the thesis.
///
/// On a burning vehicle ([`Self::burning`]) `m`, `c` and `P̄` are those of the propellant
/// fraction `f(t)` of the burn schedule (`dry + f prop`, [`crate::runtime::motor`]), set
/// before each evaluation; gravity is then reported as external work in the energy balance
/// rather than as a potential (the burnt mass takes its potential energy with it).
#[derive(Debug, Clone)]
pub struct GravityBlock {
    uniform: UniformGravity,
    /// Apply (5.1.2).
    pub altitude_correction: bool,
    burn: Option<Box<GravityBurn>>,
}

/// The mass properties of a burning vehicle for gravity: dry and propellant `m`, `c`, `P̄`.
#[derive(Debug, Clone)]
struct GravityBurn {
    schedule: BurnSchedule,
    dry: (f64, [f64; 3], Vec<f64>),
    prop: (f64, [f64; 3], Vec<f64>),
    p_bar: Vec<f64>,
    fraction: f64,
}

impl GravityBlock {
    /// Gravity on `model`, with or without the altitude correction.
    pub fn new(model: &ReducedModel, altitude_correction: bool) -> Self {
        Self {
            uniform: UniformGravity::new(model, [0.0, 0.0, G0]),
            altitude_correction,
            burn: None,
        }
    }

    /// Gravity on the vehicle `full` (at ignition) whose propellant `prop` (same basis)
    /// burns by `schedule`.
    pub fn burning(
        full: &ReducedModel,
        prop: &ReducedModel,
        schedule: BurnSchedule,
        altitude_correction: bool,
    ) -> Self {
        let mut b = Self::new(full, altitude_correction);
        let dry_p: Vec<f64> = full
            .p_bar
            .iter()
            .zip(&prop.p_bar)
            .map(|(a, b)| a - b)
            .collect();
        let dry_c = [0, 1, 2].map(|i| full.first_moment[i] - prop.first_moment[i]);
        b.burn = Some(Box::new(GravityBurn {
            schedule,
            dry: (full.mass - prop.mass, dry_c, dry_p),
            prop: (prop.mass, prop.first_moment, prop.p_bar.clone()),
            p_bar: full.p_bar.clone(),
            fraction: 1.0,
        }));
        b
    }

    /// Sets the mass properties to the propellant fraction at `t` (no allocation).
    pub fn set_time(&mut self, t: f64) {
        if let Some(b) = &mut self.burn {
            let f = b.schedule.fraction(t);
            if f != b.fraction {
                b.fraction = f;
                let m = b.dry.0 + f * b.prop.0;
                let c = [0, 1, 2].map(|i| b.dry.1[i] + f * b.prop.1[i]);
                for ((o, d), p) in b.p_bar.iter_mut().zip(&b.dry.2).zip(&b.prop.2) {
                    *o = d + f * p;
                }
                self.uniform.set_mass_properties(m, c, &b.p_bar);
            }
        }
    }

    /// Does the mass change (then gravity is work, not a potential, in the energy balance)?
    pub fn is_burning(&self) -> bool {
        self.burn.is_some()
    }

    /// Altitude of the mass centre, m (the `h` of eq. 5.1.2). No allocation.
    pub fn centre_of_mass_altitude(&self, s: &StateView) -> f64 {
        let c = self.uniform.first_moment_total(s.eta);
        let m = self.uniform.mass();
        let offset = mat_t_vec(&s.c_bi, &c.map(|x| x / m));
        -(s.position[2] + offset[2])
    }

    /// Gravitational potential energy `m Φ(h_cm)` (zero at sea level), J.
    pub fn potential_energy(&self, s: &StateView) -> f64 {
        let h = self.centre_of_mass_altitude(s);
        self.uniform.mass() * potential_per_mass(h, self.altitude_correction)
    }
}

impl ForceModel for GravityBlock {
    fn generalized_forces(&mut self, t: f64, s: &StateView, out: &mut [f64]) {
        self.set_time(t);
        let g = if self.altitude_correction {
            gravity_at(self.centre_of_mass_altitude(s), true)
        } else {
            G0
        };
        self.uniform.set_gravity([0.0, 0.0, g]);
        self.uniform.generalized_forces(t, s, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runtime::eom::StateLayout;
    use crate::runtime::kinematics::euler_parameters_from_angles;

    /// A one-mode model with hand-chosen m, c, P̄ (the other coefficients do not enter).
    pub(crate) fn model() -> ReducedModel {
        ReducedModel {
            origin_node: 0,
            n_modes: 1,
            mass: 2.0,
            first_moment: [-3.0, 0.4, 0.0],
            inertia: [[1.0, 0.0, 0.0], [0.0, 5.0, 0.0], [0.0, 0.0, 5.0]],
            modal_mass: vec![1.0],
            modal_stiffness: vec![1.0],
            modal_damping: vec![0.0],
            omega2: vec![1.0],
            damping_ratio: vec![0.0],
            p_bar: vec![0.0, 0.5, 0.2],
            h_bar: vec![0.0; 3],
            j_ru: vec![[[0.0; 3]; 3]],
            j_uu: vec![[[0.0; 3]; 3]],
            h_prime: vec![0.0; 3],
            rigid_mass_residual: 0.0,
        }
    }

    #[test]
    fn level_vehicle_gets_weight_moment_and_modal_force() {
        let md = model();
        let layout = StateLayout { n: 1 };
        let x = layout.state(
            [0.0, 0.0, -1000.0],
            [0.0, 0.0, 0.0, 1.0],
            [0.0; 3],
            [0.0; 3],
            &[0.1],
            &[0.0],
        );
        let s = StateView::new(layout, &x);
        let mut b = GravityBlock::new(&md, false);
        let mut out = vec![0.0; 7];
        b.generalized_forces(0.0, &s, &mut out);
        // g_B = (0, 0, 9.806); c_tot = (-3, 0.4 + 0.05, 0.02).
        let g = 9.806;
        assert!((out[2] - 2.0 * g).abs() < 1e-12);
        // c × g = (c_y g, -c_x g, 0) = (0.45 g, 3 g, 0).
        assert!((out[3] - 0.45 * g).abs() < 1e-12);
        assert!((out[4] - 3.0 * g).abs() < 1e-12);
        assert!(out[5].abs() < 1e-12);
        // Q = P̄ᵀ g_B = 0.2 g.
        assert!((out[6] - 0.2 * g).abs() < 1e-12);
    }

    #[test]
    fn pitched_vehicle_and_altitude_correction() {
        let md = model();
        let layout = StateLayout { n: 1 };
        // Pitch 90° nose up: body x points to -z inertial, g_B = C_BI (0,0,g) = (-g, 0, 0).
        let q = euler_parameters_from_angles(0.0, std::f64::consts::FRAC_PI_2, 0.0);
        let x = layout.state([0.0, 0.0, -10_000.0], q, [0.0; 3], [0.0; 3], &[0.0], &[0.0]);
        let s = StateView::new(layout, &x);
        let mut b = GravityBlock::new(&md, true);
        // Mass centre at c/m = (-1.5, 0.2, 0) body: 1.5 m below the nose when pointing up.
        let h = b.centre_of_mass_altitude(&s);
        assert!((h - (10_000.0 - 1.5)).abs() < 1e-9, "{h}");
        let g = 9.806 * (6_378_000.0_f64 / (6_378_000.0 + h)).powi(2);
        let mut out = vec![0.0; 7];
        b.generalized_forces(0.0, &s, &mut out);
        assert!((out[0] + 2.0 * g).abs() < 1e-9, "{}", out[0]);
        assert!(out[1].abs() < 1e-9 && out[2].abs() < 1e-9);
        // c × (-g, 0, 0) = (0, c_z (-g) ... ) = (0, -g c_z, g c_y) with c = (-3, 0.4, 0).
        assert!((out[5] - 0.4 * g).abs() < 1e-9);
        // Energy: m g0 R h/(R+h), and its altitude derivative is m g(h).
        let e = b.potential_energy(&s);
        assert!((e - 2.0 * 9.806 * 6_378_000.0 * h / (6_378_000.0 + h)).abs() < 1e-6);
        let dh = 1.0;
        let d = (potential_per_mass(h + dh, true) - potential_per_mass(h - dh, true)) / (2.0 * dh);
        assert!((d - gravity_at(h, true)).abs() < 1e-9);
    }
}
