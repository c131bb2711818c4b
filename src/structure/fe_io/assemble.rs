//! Shared checks and assembly: raw matrix entries with their source lines become the
//! full-storage symmetric `SparseColMat` of an [`FeModel`], in canonical DOF order.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use faer::sparse::{SparseColMat, Triplet};

use super::error::{FeReadError, SourceLocation};
use crate::structure::fe_model::{DOF_PER_NODE, Element, FeModel, Node};

/// Per-node order of the 6 components in a file.
///
/// `order[k]` is the canonical component (0 = u, 1 = v, 2 = w, 3 = theta_x, 4 = theta_y,
/// 5 = theta_z) of the k-th DOF of each node in the file. The canonical order is the identity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DofOrder([usize; DOF_PER_NODE]);

impl DofOrder {
    /// u v w theta_x theta_y theta_z.
    pub const CANONICAL: Self = Self([0, 1, 2, 3, 4, 5]);

    /// A file order; rejects anything that is not a permutation of 0..6.
    pub fn new(order: [usize; DOF_PER_NODE]) -> Result<Self, FeReadError> {
        let mut seen = [false; DOF_PER_NODE];
        for &c in &order {
            if c >= DOF_PER_NODE || seen[c] {
                return Err(FeReadError::BadDofOrder(
                    SourceLocation::line(Path::new("<options>"), 0),
                    format!("{order:?}"),
                ));
            }
            seen[c] = true;
        }
        Ok(Self(order))
    }

    /// Canonical component of the file's component `k` (0-based).
    pub fn canonical(&self, k: usize) -> usize {
        self.0[k]
    }

    /// Canonical global DOF of file index `i` (0-based, node-major, 6 per node).
    pub fn canonical_dof(&self, i: usize) -> usize {
        (i / DOF_PER_NODE) * DOF_PER_NODE + self.0[i % DOF_PER_NODE]
    }
}

impl Default for DofOrder {
    fn default() -> Self {
        Self::CANONICAL
    }
}

/// Options common to all readers.
#[derive(Clone, Debug)]
pub struct ReadOptions {
    /// Per-node component order of the files.
    pub dof_order: DofOrder,
    /// Relative tolerance of the symmetry check: |a_ij - a_ji| <= tol * max|a|.
    pub symmetry_rel_tol: f64,
    /// Name of the mass matrix in OP4 / DMIG files.
    pub mass_name: String,
    /// Name of the stiffness matrix in OP4 / DMIG files.
    pub stiffness_name: String,
}

impl Default for ReadOptions {
    fn default() -> Self {
        Self {
            dof_order: DofOrder::CANONICAL,
            symmetry_rel_tol: 1e-9,
            mass_name: "MAA".into(),
            stiffness_name: "KAA".into(),
        }
    }
}

/// How a file stores a matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Storage {
    /// One triangle (or both, then they must agree); the other is mirrored.
    Symmetric,
    /// Every entry given; the matrix must be symmetric within tolerance.
    General,
}

/// A matrix as read, before checks: 0-based file indices, with the line of each entry.
#[derive(Clone, Debug)]
pub struct RawMatrix {
    pub path: PathBuf,
    /// Line of the header that declared the size (for size errors).
    pub header_line: usize,
    pub nrows: usize,
    pub ncols: usize,
    pub storage: Storage,
    /// (row, col, value, line)
    pub entries: Vec<(usize, usize, f64, usize)>,
}

impl RawMatrix {
    /// Checks the raw entries and builds the full-storage symmetric matrix in canonical order.
    ///
    /// Checks: square, finite values, indices in range, no duplicates, symmetry within
    /// `opts.symmetry_rel_tol` (general storage, or both triangles given), non-negative
    /// diagonal. Exact zeros are dropped.
    pub fn into_symmetric(
        self,
        opts: &ReadOptions,
    ) -> Result<SparseColMat<usize, f64>, FeReadError> {
        let hdr = SourceLocation::line(&self.path, self.header_line);
        if self.nrows != self.ncols {
            return Err(FeReadError::NotSquare(
                hdr,
                format!("{} rows x {} columns", self.nrows, self.ncols),
            ));
        }
        let n = self.nrows;
        let mut map: HashMap<(usize, usize), (f64, usize)> =
            HashMap::with_capacity(self.entries.len());
        let mut max_abs = 0.0_f64;
        for &(i, j, v, line) in &self.entries {
            let loc = SourceLocation::line(&self.path, line);
            if !v.is_finite() {
                return Err(FeReadError::NonFinite(
                    loc,
                    format!("entry ({}, {}) = {v}", i + 1, j + 1),
                ));
            }
            if i >= n || j >= n {
                return Err(FeReadError::IndexOutOfRange(
                    loc,
                    format!("entry ({}, {}) outside a {n} x {n} matrix", i + 1, j + 1),
                ));
            }
            if map.insert((i, j), (v, line)).is_some() {
                return Err(FeReadError::DuplicateEntry(
                    loc,
                    format!("entry ({}, {})", i + 1, j + 1),
                ));
            }
            max_abs = max_abs.max(v.abs());
        }
        let tol = opts.symmetry_rel_tol * max_abs;
        let mut triplets = Vec::with_capacity(2 * map.len());
        for (&(i, j), &(v, line)) in &map {
            let loc = SourceLocation::line(&self.path, line);
            if i == j {
                if v < 0.0 {
                    return Err(FeReadError::NegativeDiagonal(
                        loc,
                        format!("entry ({0}, {0}) = {v:e}", i + 1),
                    ));
                }
            } else {
                match (map.get(&(j, i)), self.storage) {
                    (Some(&(w, _)), _) => {
                        if (v - w).abs() > tol {
                            return Err(FeReadError::Asymmetric(
                                loc,
                                format!(
                                    "entry ({}, {}) = {v:e} but ({}, {}) = {w:e}; tolerance {tol:e}",
                                    i + 1,
                                    j + 1,
                                    j + 1,
                                    i + 1
                                ),
                            ));
                        }
                    }
                    (None, Storage::General) => {
                        if v.abs() > tol {
                            return Err(FeReadError::Asymmetric(
                                loc,
                                format!(
                                    "entry ({}, {}) = {v:e} has no transposed entry; tolerance {tol:e}",
                                    i + 1,
                                    j + 1
                                ),
                            ));
                        }
                    }
                    (None, Storage::Symmetric) => {}
                }
            }
            if v == 0.0 {
                continue;
            }
            let (ci, cj) = (
                opts.dof_order.canonical_dof(i),
                opts.dof_order.canonical_dof(j),
            );
            if i == j || map.contains_key(&(j, i)) {
                // Both triangles present (or diagonal): take the mean of the pair once per entry.
                let w = map.get(&(j, i)).map_or(v, |p| p.0);
                triplets.push(Triplet::new(ci, cj, 0.5 * (v + w)));
            } else {
                triplets.push(Triplet::new(ci, cj, v));
                triplets.push(Triplet::new(cj, ci, v));
            }
        }
        SparseColMat::try_new_from_triplets(n, n, &triplets)
            .map_err(|e| FeReadError::BadRecord(hdr, format!("cannot build sparse matrix: {e:?}")))
    }
}

/// Builds the model after the size checks shared by all readers: M and K of equal size, and
/// size `6 * nodes.len()`. Then runs [`super::validate`] with `mass_path` as the location.
pub fn build_model(
    nodes: Vec<Node>,
    elements: Vec<Element>,
    mass: RawMatrix,
    stiffness: RawMatrix,
    opts: &ReadOptions,
) -> Result<FeModel, FeReadError> {
    if mass.nrows != stiffness.nrows || mass.ncols != stiffness.ncols {
        return Err(FeReadError::SizeMismatch(
            SourceLocation::line(&stiffness.path, stiffness.header_line),
            format!(
                "mass is {} x {} ({}), stiffness is {} x {}",
                mass.nrows,
                mass.ncols,
                mass.path.display(),
                stiffness.nrows,
                stiffness.ncols
            ),
        ));
    }
    for m in [&mass, &stiffness] {
        if m.nrows != DOF_PER_NODE * nodes.len() || m.ncols != m.nrows {
            return Err(FeReadError::SizeNotSixPerNode(
                SourceLocation::line(&m.path, m.header_line),
                format!(
                    "{} x {} matrix but {} nodes need {}",
                    m.nrows,
                    m.ncols,
                    nodes.len(),
                    DOF_PER_NODE * nodes.len()
                ),
            ));
        }
    }
    let mass_path = mass.path.clone();
    let model = FeModel {
        nodes,
        mass: mass.into_symmetric(opts)?,
        stiffness: stiffness.into_symmetric(opts)?,
        elements,
    };
    super::validate(&model).map_err(|e| match e {
        FeReadError::MassNotPositiveSemiDefinite { message, .. } => {
            FeReadError::MassNotPositiveSemiDefinite(SourceLocation::line(&mass_path, 0), message)
        }
        other => other,
    })?;
    Ok(model)
}

/// Checks a node list for duplicate ids. `lines[i]` is the source line of `nodes[i]`.
pub fn check_unique_ids(nodes: &[Node], lines: &[usize], path: &Path) -> Result<(), FeReadError> {
    let mut seen: HashMap<u64, usize> = HashMap::with_capacity(nodes.len());
    for (node, &line) in nodes.iter().zip(lines) {
        if let Some(first) = seen.insert(node.id, line) {
            return Err(FeReadError::DuplicateNode(
                SourceLocation::line(path, line),
                format!("node {} already defined on line {first}", node.id),
            ));
        }
    }
    Ok(())
}
