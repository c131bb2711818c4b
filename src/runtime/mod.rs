//! The runtime's environment models (thesis chapters 4-5): the atmosphere (4.5.1), motor
//! thrust curves (5.2) and the gust / turbulence stimulus generator (4.5.2).
//!
//! Everything here is built before a run (reading files, generating turbulence series) and
//! evaluated during it without allocation.

pub mod atmosphere;
pub mod stimuli;
pub mod thrust;
