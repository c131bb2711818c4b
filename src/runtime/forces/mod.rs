//! Force blocks of the runtime (thesis chapter 5): each implements
//! [`super::eom::ForceModel`], precomputes everything at construction and never allocates in
//! the right-hand side.
//!
//! - [`body_aero`]: fuselage aerodynamics through the key-node frames bn, ba, co (5.3);
//! - [`fin_aero`]: per-fin aerodynamics, nodal load distribution and leeward reduction (5.4);
//! - [`stress`]: the fin root bending stress approximation (5.6).

pub mod body_aero;
pub mod fin_aero;
pub mod stress;

pub use body_aero::{AeroFault, AeroForceError, BodyAero, RateDerivatives, aero_tables};
pub use fin_aero::FinAero;
pub use stress::FinRootStress;
