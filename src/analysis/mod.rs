//! Stability analyses of thesis chapter 6 (issue #5), built on the compiled vehicle and the
//! runtime's equations of motion:
//!
//! - [`planar`]: the planar pinned (6.1) and unpinned (6.2) eigen-stability models;
//! - [`tn4197`]: the NACA TN 4197 fin flutter boundary, a baseline printed next to ours;
//! - [`map`]: stability maps over fin thickness x Mach (Figs 6.3-6.8) and their CSV;
//! - [`linearise`], [`roots`], [`linear`], [`linear_grid`]: the linearised 3-D model (beyond
//!   the thesis), its roots with participation factors, and its thickness x Mach maps.

pub mod linear;
pub mod linear_grid;
pub mod linearise;
pub mod map;
pub mod planar;
pub mod roots;
pub mod tn4197;
