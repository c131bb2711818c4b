//! The finite-element model handed to the structural compiler.
//!
//! Every source of a model (the NASTRAN/Matrix Market readers in `fe_io`, the built-in
//! generator in `generate`) produces this one type. Conventions (REFERENCE-NOTES.md):
//! body frame with origin at the nose tip, x forward through the nose (so every point of the
//! vehicle has x <= 0), z nominally down; 6 DOF per node in the canonical order
//! u, v, w, theta_x, theta_y, theta_z; DOF `6*i + k` belongs to `nodes[i]`.

use faer::sparse::SparseColMat;

/// Degrees of freedom per node: u, v, w, theta_x, theta_y, theta_z.
pub const DOF_PER_NODE: usize = 6;

/// Which part of the vehicle a node belongs to (used by the mode classifier).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
pub enum Component {
    /// Fuselage, nose and everything rigidly attached to the body line.
    Body,
    /// Fin number `i` (0-based), fin i at angle delta_i = 2 pi i / n about body x.
    Fin(u16),
    /// Not known (for example a model read from a file with no component information).
    Unknown,
}

/// One FE node.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// The id the source file gave the node (GRID id, CSV id, or 1-based generator index).
    pub id: u64,
    /// Undeformed position in the body frame, metres.
    pub position: [f64; 3],
    pub component: Component,
}

/// Element topology, kept only for plotting deformed shapes and for reports.
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    pub id: u64,
    pub kind: ElementKind,
    /// Indices into `FeModel::nodes` (not ids).
    pub nodes: Vec<usize>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum ElementKind {
    Beam,
    Shell,
    /// A rigid link or any other connection shown as a line.
    Link,
}

/// A finite-element model: nodes, and the global mass and stiffness matrices.
///
/// Invariants: `mass` and `stiffness` are square of size `6 * nodes.len()`, stored with
/// both triangles (full symmetric storage), rows sorted within each column, no duplicates.
#[derive(Clone, Debug)]
pub struct FeModel {
    pub nodes: Vec<Node>,
    pub mass: SparseColMat<usize, f64>,
    pub stiffness: SparseColMat<usize, f64>,
    pub elements: Vec<Element>,
}

impl FeModel {
    /// Number of degrees of freedom, `6 * nodes.len()`.
    pub fn n_dof(&self) -> usize {
        self.nodes.len() * DOF_PER_NODE
    }

    /// Index of the node with the given source id.
    pub fn node_index(&self, id: u64) -> Option<usize> {
        self.nodes.iter().position(|n| n.id == id)
    }
}
