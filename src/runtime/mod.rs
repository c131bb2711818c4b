//! Runtime: the equations of motion of the reduced flexible vehicle and their integration.
//!
//! - [`eom`]: eq. (3.2.1) as a first-order system, force-model trait, energy and momentum;
//! - [`kinematics`]: Euler parameters and Euler angles (thesis 4.4);
//! - [`integrate`]: Dormand-Prince 5(4) and fixed-step RK4.
//!
//! Architecture invariant: the right-hand side never allocates, does IO or looks up names;
//! every buffer lives in a [`eom::Workspace`] created once per run.

pub mod eom;
pub mod integrate;
pub mod kinematics;
