//! flexflight: flight simulation and stability analysis of flexible rockets.

pub mod artifact;
pub mod structure;
