//! Flutter analysis (issue 13): the p-k and k methods on generalised coordinates with
//! tabulated unsteady generalised aerodynamic forces `Q(k)`, and the published cases it is
//! validated on.
//!
//! - [`pk`]: the solver (p-k after Hassig 1971 and Rodden & Johnson's MSC Nastran Aeroelastic
//!   User's Guide, the k method, flutter points by root finding, divergence);
//! - [`bessel`], [`theodorsen`]: Theodorsen's function and the typical-section airloads;
//! - [`fin`]: the fin clamped at its root with the fin panels' generalised forces (the fin
//!   designer's case);
//! - [`vehicle`]: the free flexible vehicle (its reduced model's modes and rigid-body
//!   motions) with every fin's panel generalised forces and the body's quasi-steady loads;
//! - [`wing`]: a lifting surface clamped at its root (the language's `fixture`), its plate
//!   model and flutter problems (AGARD 445.6 is `examples/agard445/agard445.vdl`).

pub mod bessel;
pub mod fin;
pub mod margin;
pub mod pk;
pub mod theodorsen;
pub mod thickness;
pub mod vehicle;
pub mod wing;

pub use pk::{
    Divergence, FlutterError, FlutterModel, FlutterPoint, Gaf, GafFn, GafTable, KSolution, PkRoot,
    PkSettings, PkSolution, k_method, pk_solve,
};
