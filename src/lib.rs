//! flexflight: flight simulation and stability analysis of flexible rockets.

pub mod check;
pub mod cli;
pub mod diagnostics;
pub mod structure;
pub mod syntax;
pub mod units;
