//! The phases of a flight from the pad to the ground: the equations of motion of each phase
//! around the free-flight equations (3.2.1) of [`Eom`].
//!
//! # Rail (launch rail, 1-DOF)
//! On the rail the vehicle is held to translation along the rail direction `d` (its body x
//! axis): the rail's reactions keep `ω_B = 0`, `V_B = (u, 0, 0)`, and the elastic coordinates
//! are held at `η = η̇ = 0` (the rail and the pad support the vehicle; the elastic response
//! during the first metres, at dynamic pressures below 1 kPa, is left out). Then the
//! kinetic energy is `T = ½ m u²` (the `M_tot` entry `m 1` of (3.2.2) with `ω = η̇ = 0`) and
//! the generalised force along the one coordinate is the body-x component `F_x` of the
//! external loads (gravity, thrust, aerodynamics; the rail is frictionless and its normal
//! reactions do no work along it), so Lagrange's equation is
//! ```text
//! m u̇ = F_x,   ṗ_I = C_IB V_B = u d,   q̇ = 0,   ω̇ = 0,   η̇ = η̈ = 0
//! ```
//! The foot of the rail (the launch lug stop) holds the vehicle at rest: while `u <= 0` a
//! negative `F_x` gives `u̇ = 0` (the vehicle waits on the pad until the thrust exceeds the
//! weight component along the rail, `m g sin(elevation)`).
//!
//! With a burning motor (`eom.rs`, "Variable mass") `m = m(t)` is the burning vehicle's mass
//! and `F_x` includes the thrust `T_x(t)`. The mass-flow terms of (3.2.1) with propulsion,
//! `(ṁ_e/m_p) M_p(η) v - ṁ_e Ψ_eᵀΨ_e v`, vanish in the translation rows for a pure
//! translation `v = (u, 0, 0)`, `ω = η̇ = 0`: the propellant's translation block of `M_p` is
//! `m_p 1` and `Ψ_e`'s is `1`, so they give `ṁ_e u - ṁ_e u = 0`. Hence `m(t) u̇ = F_x + T_x`.
//!
//! # Energy balance in the constrained phases
//! The works of [`Eom::track_energy`] are integrated here too, so the balance residual of a
//! run stays meaningful from the pad to the ground. With `T = ½ m u²`,
//! `Ṫ = m u u̇ + ½ ṁ u² = (F_x + T_x) u - ½ ṁ_e u²` (`ṁ = -ṁ_e`), which is the sum of the
//! loads' power `F_x u` and the propulsive power of `eom.rs`, `vᵀ f_T + ṁ_e (½ vᵀ M_p v / m_p
//! - |v_e|²) = T_x u + ṁ_e (½ u² - u²)` (`v_e = u` on the rail). The descent is the same with
//! `u` replaced by the body velocity `V_B` (`ω = 0`, frozen modes): loads' power
//! `f_B·V_B + D·V_I` (the drag's work counted with the loads), propulsive power
//! `f_T·V_B - ½ ṁ_e |V_B|²`. The foot of the rail does no work (`u = 0` while it holds).
//!
//! # Free flight
//! [`Eom`] unchanged.
//!
//! # Descent under a recovery device
//! From the first deployment on the vehicle is frozen to a rigid body at its attitude of
//! that instant (`ω_B = 0`, `η = η̇ = 0` set at deployment, the elastic energy then is left
//! out) and moves as a point mass under gravity, any remaining thrust and the drag of the
//! deployed devices, `D = -½ ρ |V_a| V_a Σ (C_D S)_k` along the air-relative velocity
//! `V_a = V_I - W_I` (the standard drag law of a parachute, e.g. Knacke, "Parachute Recovery
//! Systems Design Manual", NWC TP 6575, 1991, eq. 5-1). The vehicle's own body and fin
//! aerodynamics are switched off under the canopy, as RocketPy does in its descent phase.
//! With `ω = 0`, `V̇_B = C_BI a_I`, `a_I = C_IB F_B / m + D / m`.
//!
//! Architecture invariant: `rhs` never allocates, does IO or looks up names (the buffers are
//! made in [`Flight::new`]).

use super::eom::{EnergyLayout, Eom, ForceModel, StateView};
use super::forces::{ForceBlock, ForceBlocks};
use super::integrate::{OdeSystem, RhsError};
use super::kinematics::{mat_t_vec, mat_vec};
use super::stimuli::Stimuli;
use crate::aero::atmosphere::{Atmosphere, Standard1976};

/// Which equations of motion hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Sliding along the launch rail (1-DOF).
    Rail,
    /// Free flight, eq. (3.2.1).
    Free,
    /// Rigid point-mass descent under recovery devices.
    Descent,
}

/// The right-hand side of a flight: the free-flight [`Eom`] with the rail and descent
/// phases around it.
#[derive(Debug, Clone)]
pub struct Flight<'m> {
    /// The free-flight equations; their force blocks serve every phase.
    pub eom: Eom<'m, ForceBlocks>,
    /// The current phase (changed by the run driver between integrations).
    pub phase: Phase,
    /// Total drag area of the deployed devices, m².
    pub cd_area: f64,
    forces: Vec<f64>,
    thrust: Vec<f64>,
    stimuli: Stimuli,
    atmosphere: Standard1976,
}

impl<'m> Flight<'m> {
    /// A flight starting in `phase`; `stimuli` give the wind the descent drag sees.
    pub fn new(eom: Eom<'m, ForceBlocks>, phase: Phase, stimuli: Stimuli) -> Self {
        let d = 6 + eom.layout().n;
        Flight {
            eom,
            phase,
            cd_area: 0.0,
            forces: vec![0.0; d],
            thrust: vec![0.0; d],
            stimuli,
            atmosphere: Standard1976::new(),
        }
    }

    /// [`Stimuli::set_left_of`] on every copy of the stimuli the right-hand side reads (the
    /// descent's and the aerodynamic blocks').
    pub fn set_wind_left_of(&mut self, t: Option<f64>) {
        use crate::runtime::forces::ForceBlock;
        self.stimuli.set_left_of(t);
        for b in &mut self.eom.forces.blocks {
            match b {
                ForceBlock::BodyAero(a) => a.set_wind_left_of(t),
                ForceBlock::FinAero(a) => a.set_wind_left_of(t),
                ForceBlock::Gravity(_) | ForceBlock::Thrust(_) => {}
            }
        }
    }

    /// Writes the works of the energy balance (module doc) into `dx`, if the state has them.
    fn works(&self, dx: &mut [f64], power_loads: f64, power_propulsive: f64) {
        let e = self.eom.layout().len();
        if let Some(w) = dx.get_mut(e..e + EnergyLayout::LEN) {
            w[EnergyLayout::LOADS] = power_loads;
            w[EnergyLayout::PROPULSIVE] = power_propulsive;
            w[EnergyLayout::DISSIPATED] = 0.0;
        }
    }

    /// Rail phase: `m u̇ = F_x`, held at the foot while `u <= 0` and `F_x < 0`.
    fn rail_rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) {
        let l = self.eom.layout();
        let view = StateView::new(l, x);
        self.forces.fill(0.0);
        self.eom
            .forces
            .generalized_forces(t, &view, &mut self.forces);
        let (mass, mass_flow) = self.eom.motor_at(t, &view, &mut self.thrust);
        let mut a = (self.forces[0] + self.thrust[0]) / mass;
        if view.velocity[0] <= 0.0 && a < 0.0 {
            a = 0.0;
        }
        dx.fill(0.0);
        let u = view.velocity[0];
        let v = [u, 0.0, 0.0];
        dx[0..3].copy_from_slice(&mat_t_vec(&view.c_bi, &v));
        dx[7] = a;
        self.works(
            dx,
            self.forces[0] * u,
            self.thrust[0] * u - 0.5 * mass_flow * u * u,
        );
    }

    /// Descent phase: rigid point mass, gravity and thrust blocks plus the device drag.
    fn descent_rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) {
        let l = self.eom.layout();
        let view = StateView::new(l, x);
        self.forces.fill(0.0);
        for b in &mut self.eom.forces.blocks {
            if matches!(b, ForceBlock::Gravity(_) | ForceBlock::Thrust(_)) {
                b.generalized_forces(t, &view, &mut self.forces);
            }
        }
        let (m, mass_flow) = self.eom.motor_at(t, &view, &mut self.thrust);
        let f_b = [0, 1, 2].map(|k| self.forces[k] + self.thrust[k]);
        let f_i = mat_t_vec(&view.c_bi, &f_b);
        let v_i = mat_t_vec(&view.c_bi, &view.velocity);
        let altitude = -view.position[2];
        let (wb, wi) = self.stimuli.wind_at(t, altitude);
        let wb_i = mat_t_vec(&view.c_bi, &wb);
        let va = [0, 1, 2].map(|k| v_i[k] - wi[k] - wb_i[k]);
        let speed = (va[0] * va[0] + va[1] * va[1] + va[2] * va[2]).sqrt();
        let rho = self
            .atmosphere
            .at(altitude.clamp(-500.0, 86_000.0))
            .map_or(0.0, |a| a.density);
        let k = -0.5 * rho * speed * self.cd_area;
        let a_i = [0, 1, 2].map(|i| (f_i[i] + k * va[i]) / m);
        dx.fill(0.0);
        dx[0..3].copy_from_slice(&v_i);
        dx[7..10].copy_from_slice(&mat_vec(&view.c_bi, &a_i));
        let vb = view.velocity;
        let dot = |a: &[f64], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let drag_power = k * (va[0] * v_i[0] + va[1] * v_i[1] + va[2] * v_i[2]);
        self.works(
            dx,
            dot(&self.forces[0..3], &vb) + drag_power,
            dot(&self.thrust[0..3], &vb) - 0.5 * mass_flow * dot(&vb, &vb),
        );
    }
}

impl OdeSystem for Flight<'_> {
    fn dim(&self) -> usize {
        self.eom.dim()
    }

    fn rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), RhsError> {
        match self.phase {
            Phase::Free => return self.eom.rhs(t, x, dx),
            Phase::Rail => self.rail_rhs(t, x, dx),
            Phase::Descent => self.descent_rhs(t, x, dx),
        }
        if let Some(index) = dx.iter().position(|v| !v.is_finite()) {
            return Err(RhsError::NonFinite { index });
        }
        Ok(())
    }

    fn project(&mut self, x: &mut [f64], dx: &mut [f64]) {
        self.eom.project(x, dx)
    }

    /// The modal block in free flight; on the rail and under a canopy the modes are frozen
    /// (their derivatives are zero), so there is nothing stiff.
    fn linear_block(&self) -> Option<std::ops::Range<usize>> {
        match self.phase {
            Phase::Free => self.eom.linear_block(),
            Phase::Rail | Phase::Descent => None,
        }
    }
}
