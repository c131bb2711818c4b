//! Stability analyses of thesis chapter 6 (issue #5).
//!
//! - [`planar`]: the planar pinned (6.1) and unpinned (6.2) eigen-stability models;
//! - [`tn4197`]: the NACA TN 4197 fin flutter boundary, a baseline printed next to ours;
//! - [`map`]: stability maps over fin thickness x Mach (Figs 6.3-6.8) and their CSV.

pub mod map;
pub mod planar;
pub mod tn4197;
