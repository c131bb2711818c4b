//! The force blocks of chapter 5, each a [`ForceModel`], and their closed composition
//! [`ForceBlocks`] used by a run.
//!
//! - [`gravity`]: eqs. (5.1.1)-(5.1.6), with the altitude correction (5.1.2);
//! - [`thrust`]: eqs. (5.2.1)-(5.2.6), thrust curve, misalignment, nozzle flexibility;
//! - [`body_aero`]: fuselage aerodynamics through the key-node frames bn, ba, co (5.3);
//! - [`fin_aero`]: per-fin aerodynamics, nodal load distribution and leeward reduction (5.4);
//! - [`stress`]: the fin root bending stress approximation (5.6).
//!
//! Architecture invariant: `generalized_forces` never allocates, does IO or looks up names;
//! every table (thrust curve, nozzle shape rows) is resolved by the plan before the run.

pub mod body_aero;
pub mod fin_aero;
pub mod gravity;
pub mod stress;
pub mod thrust;

use super::eom::{ForceModel, StateView};

pub use body_aero::{AeroFault, AeroForceError, BodyAero, aero_tables};
pub use fin_aero::FinAero;
pub use gravity::GravityBlock;
pub use stress::FinRootStress;
pub use thrust::ThrustBlock;

/// One force block of a run (a closed set: the hot loop matches on it, no dynamic dispatch).
#[derive(Debug, Clone)]
pub enum ForceBlock {
    /// Gravity (5.1).
    Gravity(GravityBlock),
    /// Rocket thrust (5.2).
    Thrust(ThrustBlock),
    /// Body aerodynamics (5.3).
    BodyAero(Box<BodyAero>),
    /// Fin aerodynamics with distributed loads (5.4).
    FinAero(Box<FinAero>),
}

impl ForceModel for ForceBlock {
    fn generalized_forces(&mut self, t: f64, state: &StateView, out: &mut [f64]) {
        match self {
            ForceBlock::Gravity(b) => b.generalized_forces(t, state, out),
            ForceBlock::Thrust(b) => b.generalized_forces(t, state, out),
            ForceBlock::BodyAero(b) => b.generalized_forces(t, state, out),
            ForceBlock::FinAero(b) => b.generalized_forces(t, state, out),
        }
    }
}

/// The ordered force blocks of a run; their generalised forces add up.
#[derive(Debug, Clone, Default)]
pub struct ForceBlocks {
    /// In plan order.
    pub blocks: Vec<ForceBlock>,
}

impl ForceModel for ForceBlocks {
    fn generalized_forces(&mut self, t: f64, state: &StateView, out: &mut [f64]) {
        for b in &mut self.blocks {
            b.generalized_forces(t, state, out);
        }
    }
}
