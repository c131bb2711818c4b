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
use crate::aero::atmosphere::AirMemo;

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
        self.forces_with(t, state, &mut AirMemo::default(), out);
    }
}

impl ForceBlock {
    /// The block's generalised forces, the aerodynamic blocks reading the air through
    /// `memo` (one evaluation of the atmosphere for every block of a right-hand side).
    fn forces_with(&mut self, t: f64, state: &StateView, memo: &mut AirMemo, out: &mut [f64]) {
        match self {
            ForceBlock::Gravity(b) => b.generalized_forces(t, state, out),
            ForceBlock::Thrust(b) => b.generalized_forces(t, state, out),
            ForceBlock::BodyAero(b) => b.forces_with(t, state, memo, out),
            ForceBlock::FinAero(b) => b.forces_with(t, state, memo, out),
        }
    }
}

/// The ordered force blocks of a run; their generalised forces add up.
#[derive(Debug, Clone, Default)]
pub struct ForceBlocks {
    /// In plan order.
    pub blocks: Vec<ForceBlock>,
    /// Empty, or one buffer per block (see [`Self::keep_each`]).
    each: Vec<Vec<f64>>,
    /// The air at the last altitude, shared by the aerodynamic blocks ([`AirMemo`]).
    air: AirMemo,
}

impl ForceBlocks {
    pub fn new(blocks: Vec<ForceBlock>) -> Self {
        ForceBlocks {
            blocks,
            each: Vec::new(),
            air: AirMemo::default(),
        }
    }

    /// From here on every block's generalised forces (`d` values) are computed into a
    /// buffer of their own, from zero, and then added to the total, so that an output row
    /// can read a block's loads from the same evaluation as the accelerations
    /// ([`Self::kept`]). A block's buffer then has the bits of a separate evaluation of
    /// that block; the total is summed block by block, which can differ from the plain
    /// accumulation in the last bits. Used by the output rows' copy of the right-hand
    /// side only, never by the integrated one.
    pub fn keep_each(&mut self, d: usize) {
        self.each = vec![vec![0.0; d]; self.blocks.len()];
    }

    /// The generalised forces of block `i` at the last evaluation, if [`Self::keep_each`]
    /// is on.
    pub fn kept(&self, i: usize) -> Option<&[f64]> {
        self.each.get(i).map(Vec::as_slice)
    }
}

impl ForceModel for ForceBlocks {
    fn generalized_forces(&mut self, t: f64, state: &StateView, out: &mut [f64]) {
        let memo = &mut self.air;
        if self.each.is_empty() {
            for b in &mut self.blocks {
                b.forces_with(t, state, memo, out);
            }
            return;
        }
        for (b, buf) in self.blocks.iter_mut().zip(&mut self.each) {
            buf.fill(0.0);
            b.forces_with(t, state, memo, buf);
            for (o, v) in out.iter_mut().zip(buf.iter()) {
                *o += v;
            }
        }
    }
}
