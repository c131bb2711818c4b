//! Stage 6, runtime: the equations of motion of the reduced flexible vehicle, their
//! integration, and the environment models the force blocks use.
//!
//! - [`eom`]: eq. (3.2.1) as a first-order system, force-model trait, energy and momentum;
//! - [`kinematics`]: Euler parameters and Euler angles (thesis 4.4);
//! - [`integrate`]: Dormand-Prince 5(4), DOP853 and fixed-step RK4;
//! - [`deformation`]: the largest nodal elastic displacement (stop condition, channel);
//! - [`forces`]: the force blocks of chapter 5 (gravity, thrust; aerodynamics plugged in);
//! - [`run`]: the run driver: stop conditions and output channels;
//! - [`aero`]: coefficient tables, the built-in estimator, fin load distributions (5.4, App. A)
//!   and the leeward reduction (5.4.24-5.4.31);
//! - [`atmosphere`]: U.S. Standard Atmosphere 1976 and user tables (4.5.1);
//! - [`thrust`]: RASP `.eng` and CSV thrust curves (5.2);
//! - [`catalogue`]: the bundled thrust curves and motors by designation;
//! - [`stimuli`]: gusts, sinusoids and seeded turbulence (4.5.2).
//!
//! Architecture invariant: the right-hand side never allocates, does IO or looks up names;
//! every buffer lives in a [`eom::Workspace`] created once per run, and everything the
//! environment models need (files, turbulence series) is prepared before the run.

pub mod catalogue;
pub mod deformation;
pub mod eom;
pub mod expint;
pub mod flight;
pub mod forces;
pub mod integrate;
pub mod kinematics;
pub mod motor;
pub mod stimuli;
pub mod thrust;
pub mod verdict;
