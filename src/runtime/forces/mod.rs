//! The force blocks of chapter 5, each a [`ForceModel`], and their closed composition
//! [`ForceBlocks`] used by a run.
//!
//! - [`gravity`]: eqs. (5.1.1)-(5.1.6), with the altitude correction (5.1.2);
//! - [`thrust`]: eqs. (5.2.1)-(5.2.6), thrust curve, misalignment, nozzle flexibility.
//!
//! The aerodynamic blocks (5.3 body, 5.4 fins) are added as further [`ForceBlock`] variants.
//!
//! Architecture invariant: `generalized_forces` never allocates, does IO or looks up names;
//! every table (thrust curve, nozzle shape rows) is resolved by the plan before the run.

pub mod gravity;
pub mod thrust;

use super::eom::{ForceModel, StateView};

pub use gravity::GravityBlock;
pub use thrust::ThrustBlock;

/// One force block of a run (a closed set: the hot loop matches on it, no dynamic dispatch).
#[derive(Debug, Clone)]
pub enum ForceBlock {
    /// Gravity (5.1).
    Gravity(GravityBlock),
    /// Rocket thrust (5.2).
    Thrust(ThrustBlock),
    // LEAD: add `BodyAero(body_aero::BodyAeroBlock)` and `FinAero(fin_aero::FinAeroBlock)`
    // here and in the match below; `runtime::run::build_force_blocks` builds them.
}

impl ForceModel for ForceBlock {
    fn generalized_forces(&mut self, t: f64, state: &StateView, out: &mut [f64]) {
        match self {
            ForceBlock::Gravity(b) => b.generalized_forces(t, state, out),
            ForceBlock::Thrust(b) => b.generalized_forces(t, state, out),
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
