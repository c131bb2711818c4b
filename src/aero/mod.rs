//! Aerodynamic data of the force block (thesis 5.3-5.5 and App. A).
//!
//! - [`tables`]: coefficient tables over Mach, angle of attack (deg) and altitude (m), read
//!   from CSV (the thesis tabulated Missile DATCOM output, 5.5), with multilinear
//!   interpolation and a per-table out-of-range policy.
//! - [`estimator`]: the built-in estimator used when no tables are given (slender body,
//!   Jorgensen crossflow, skin friction, base and wave drag; Barrowman/Diederich fins,
//!   linear supersonic theory). It writes the tables it produced in the same CSV format.
//! - [`fin_loads`]: nodal weights that distribute a fin's normal force over its FE nodes
//!   (5.4.17-5.4.23, App. A: Fourier sine series subsonic, linear wing theory supersonic).
//! - [`leeward`]: the leeward load reduction factor f_LW (5.4.24-5.4.31).
//!
//! Angles in the tables and in the leeward formula are degrees (as in the thesis); every
//! other quantity is SI.

pub mod atmosphere;
pub mod datcom;
pub mod estimator;
pub mod fin_loads;
pub mod leeward;
pub mod panel;
pub mod static_margin;
pub mod tables;

pub use estimator::{BodyShape, EstimatedTables, FinPlanform, NoseShape};
pub use fin_loads::{
    FinLoadError, FinLoadModel, FinLoadTable, FinNode, SupersonicRegime, nodal_weights,
};
pub use leeward::f_lw;
pub use tables::{
    Axis, BodyCoefficients, BodyRateCoefficients, CoefficientTable, FinCoefficients, TableError,
    TableKind,
};
