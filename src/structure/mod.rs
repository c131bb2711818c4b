//! Stage 3, structure: FE models (read or generated), modal analysis, mode selection and
//! the reduced-order coefficients of the floating-frame equations.

pub mod coefficients;
pub mod compile;
pub mod fe_io;
pub mod fe_model;
pub mod generate;
pub mod modal;
pub mod motor;
pub mod selection;

pub use fe_model::{Component, DOF_PER_NODE, Element, ElementKind, FeModel, Node};
