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

use super::atmosphere::{Atmosphere, Standard1976};
use super::eom::{Eom, ForceModel, StateView};
use super::forces::{ForceBlock, ForceBlocks};
use super::integrate::{OdeSystem, RhsError};
use super::kinematics::{mat_t_vec, mat_vec};
use super::stimuli::Stimuli;

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
    mass: f64,
    forces: Vec<f64>,
    stimuli: Stimuli,
    atmosphere: Standard1976,
}

impl<'m> Flight<'m> {
    /// A flight starting in `phase`; `stimuli` give the wind the descent drag sees.
    pub fn new(eom: Eom<'m, ForceBlocks>, mass: f64, phase: Phase, stimuli: Stimuli) -> Self {
        let d = 6 + eom.layout().n;
        Flight {
            eom,
            phase,
            cd_area: 0.0,
            mass,
            forces: vec![0.0; d],
            stimuli,
            atmosphere: Standard1976::new(),
        }
    }

    /// Vehicle mass used by the rail and descent phases, kg.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// Rail phase: `m u̇ = F_x`, held at the foot while `u <= 0` and `F_x < 0`.
    fn rail_rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) {
        let l = self.eom.layout();
        let view = StateView::new(l, x);
        self.forces.fill(0.0);
        self.eom
            .forces
            .generalized_forces(t, &view, &mut self.forces);
        let mut a = self.forces[0] / self.mass;
        if view.velocity[0] <= 0.0 && a < 0.0 {
            a = 0.0;
        }
        dx.fill(0.0);
        let v = [view.velocity[0], 0.0, 0.0];
        dx[0..3].copy_from_slice(&mat_t_vec(&view.c_bi, &v));
        dx[7] = a;
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
        let m = self.mass;
        let f_i = mat_t_vec(
            &view.c_bi,
            &[self.forces[0], self.forces[1], self.forces[2]],
        );
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
}
