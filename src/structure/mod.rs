//! Stage 3, structure: FE models (read or generated), modal analysis, mode selection and
//! the reduced-order coefficients of the floating-frame equations.

pub mod fe_model;

pub use fe_model::{Component, Element, ElementKind, FeModel, Node, DOF_PER_NODE};
pub mod fe_io;
pub mod modal;
