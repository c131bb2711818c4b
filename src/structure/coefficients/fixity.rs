//! Mode fixity adjustment about the origin node, thesis 3.3.

use faer::{Mat, MatRef};
use nalgebra::Vector3;

use super::CoefficientError;
use crate::structure::{DOF_PER_NODE, FeModel};

/// Mode fixity adjustment about the origin node, thesis 3.3 eqs. (3.3.1)-(3.3.2): every shape
/// vector gets zero translation and rotation at the origin node.
///
/// For each column, the rigid-body motion the shape gives the origin node (translation `u_0`,
/// rotation `θ_0`) is subtracted from every node `k`:
/// `u_k ← u_k - u_0 - θ_0 × (r_k - r_0)`, `θ_k ← θ_k - θ_0`, i.e. `s = q_k - R_k q_0` with
/// `R_k = [[1, -(r_k - r_0)^×], [0, 1]]` (eq. 2.5.24). As in (3.3.2) the small-angle factor
/// `(1 - θ_0^×)` of (3.3.1) is dropped (it is second order in the shape amplitude). Positions
/// are measured from the origin node, so the adjustment is correct even if that node is not
/// at the body-frame origin. A rigid-body vector becomes zero.
///
/// Fails (never panics) if `origin` is not a node or `shapes` does not have 6N rows.
pub fn fix_modes_at_origin(
    model: &FeModel,
    origin: usize,
    shapes: MatRef<'_, f64>,
) -> Result<Mat<f64>, CoefficientError> {
    let n_nodes = model.nodes.len();
    if origin >= n_nodes {
        return Err(CoefficientError::OriginOutOfRange { origin, n_nodes });
    }
    if shapes.nrows() != model.n_dof() {
        return Err(CoefficientError::LengthMismatch {
            what: "shape vectors (rows)",
            expected: model.n_dof(),
            found: shapes.nrows(),
        });
    }
    let r0 = Vector3::from(model.nodes[origin].position);
    let mut out = shapes.to_owned();
    let o = origin * DOF_PER_NODE;
    for col in 0..shapes.ncols() {
        let u0 = Vector3::new(shapes[(o, col)], shapes[(o + 1, col)], shapes[(o + 2, col)]);
        let t0 = Vector3::new(
            shapes[(o + 3, col)],
            shapes[(o + 4, col)],
            shapes[(o + 5, col)],
        );
        for (k, node) in model.nodes.iter().enumerate() {
            let rigid = u0 + t0.cross(&(Vector3::from(node.position) - r0));
            let i = k * DOF_PER_NODE;
            for d in 0..3 {
                out[(i + d, col)] -= rigid[d];
                out[(i + 3 + d, col)] -= t0[d];
            }
        }
    }
    Ok(out)
}
