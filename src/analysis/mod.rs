//! Stage 7, analysis: stability analyses of thesis chapter 6 (issue #5) and beyond, built on
//! the compiled vehicle and the runtime's equations of motion, and what a run or a family of
//! runs says about stability:
//!
//! - [`planar`]: the planar pinned (6.1) and unpinned (6.2) eigen-stability models;
//! - [`flutter`]: p-k / k flutter analysis with unsteady aerodynamics (issue 13);
//! - [`tn4197`]: the NACA TN 4197 fin flutter boundary, a baseline printed next to ours;
//! - [`map`]: stability maps over fin thickness x Mach (Figs 6.3-6.8) and their CSV;
//! - [`linearise`], [`roots`], [`linear`], [`linear_grid`]: the linearised 3-D model (beyond
//!   the thesis), its roots with participation factors, and its thickness x Mach maps;
//! - [`identify`]: time-domain identification of a damped sinusoid (matrix pencil and
//!   nonlinear least squares), eq. (6.30);
//! - [`gust_response`]: that fit after each stimulus of a run (Tables 6.1-6.2);
//! - [`montecarlo`]: Monte Carlo dispersions: the random stream, drawing, running,
//!   statistics;
//! - [`sweep`]: variant sweeps: case expansion, parallel runs, tables, shards and merging.

pub mod flutter;
pub mod gust_response;
pub mod identify;
pub mod linear;
pub mod linear_grid;
pub mod linearise;
pub mod map;
pub mod montecarlo;
pub mod planar;
pub mod roots;
pub mod sweep;
pub mod tn4197;
