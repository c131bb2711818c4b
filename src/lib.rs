//! flexflight: flight simulation and stability analysis of flexible rockets.

pub mod structure;
pub mod syntax;
pub mod units;
