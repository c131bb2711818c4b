//! flexflight: flight simulation and stability analysis of flexible rockets.
//!
//! A declarative model compiler, after K. Davidson (2005): a vehicle description file
//! (`.vdl`) declares an FE model, key nodes, mode selections, fins, aerodynamics and force
//! blocks; the compiler checks it, reduces the FE model to a few deformation modes with the
//! constant inertia coefficients of the floating-frame equations, and caches the result.
//!
//! Pipeline stages, one module each, bottom to top (see ARCHITECTURE.md; a stage imports only
//! the stages below it, `tests/layering.rs`):
//! - [`syntax`]: text to an untyped tree with spans, and the canonical printer;
//! - [`check`]: names, imports, units, ranges, overrides; produces the typed IR in SI;
//! - [`artifact`]: the cached, memory-mapped binary artifact of a compiled vehicle;
//! - [`structure`]: FE models (read or generated), modal analysis, reduced coefficients;
//! - [`aero`]: coefficient tables, the estimator, fin load weights, the steady and unsteady
//!   panel methods, the standard atmosphere, the static margin;
//! - [`runtime`]: equations of motion (3.2.1), integrators, force blocks, thrust curves,
//!   stimuli, the verdict;
//! - [`plan`]: a checked scenario and its compiled vehicle resolved into a run plan;
//! - [`run`]: the run driver (segments, events, stops, rows);
//! - [`analysis`]: stability analyses (planar and linearised 3-D models of ch. 6, stability
//!   maps, the TN 4197 baseline, flutter, time-domain identification, variant sweeps);
//! - [`report`]: figures and the report page;
//! - [`ops`]: the library API every front end calls (never prints or exits);
//! - [`cli`]: the command-line front end.
//!
//! Shared services: [`units`] (dimensions and unit table), [`diagnostics`] (the one place
//! spans become miette reports).

// Library code reports errors; it does not unwrap (tests, benches and the fuzzer may).
#![warn(clippy::unwrap_used, clippy::expect_used)]

pub mod aero;
pub mod analysis;
pub mod artifact;
pub mod check;
pub mod cli;
pub mod diagnostics;
pub mod import;
pub mod ops;
pub mod plan;
pub mod report;
pub mod run;
pub mod runtime;
pub mod structure;
pub mod syntax;
#[cfg(test)]
mod testutil;
pub mod units;

pub use check::ir::Program;
pub use diagnostics::Diagnostic;
