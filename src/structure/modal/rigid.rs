//! Exact rigid-body vectors of a node set and M-orthonormalisation.

use faer::sparse::SparseColMat;
use faer::{Col, ColRef};

use crate::structure::fe_model::{DOF_PER_NODE, FeModel};

/// The 6 rigid-body vectors about the origin of the body frame: translations along x, y, z
/// and small rotations about x, y, z. A rotation theta about axis e moves the node at r by
/// theta (e x r) and rotates it by theta e (small-angle kinematics, C = 1 - theta^x of
/// REFERENCE-NOTES). Components in canonical order u v w theta_x theta_y theta_z.
pub fn rigid_body_vectors(model: &FeModel) -> Vec<Col<f64>> {
    let n = model.n_dof();
    let mut out = Vec::with_capacity(6);
    for axis in 0..3 {
        let mut t = Col::<f64>::zeros(n);
        for i in 0..model.nodes.len() {
            t[DOF_PER_NODE * i + axis] = 1.0;
        }
        out.push(t);
    }
    for axis in 0..3 {
        let mut e = [0.0; 3];
        e[axis] = 1.0;
        let mut v = Col::<f64>::zeros(n);
        for (i, node) in model.nodes.iter().enumerate() {
            let r = node.position;
            let exr = [
                e[1] * r[2] - e[2] * r[1],
                e[2] * r[0] - e[0] * r[2],
                e[0] * r[1] - e[1] * r[0],
            ];
            for k in 0..3 {
                v[DOF_PER_NODE * i + k] = exr[k];
                v[DOF_PER_NODE * i + 3 + k] = e[k];
            }
        }
        out.push(v);
    }
    out
}

/// `A x` for sparse A.
pub(crate) fn sparse_matvec(a: &SparseColMat<usize, f64>, x: ColRef<'_, f64>) -> Col<f64> {
    let mut y = Col::<f64>::zeros(a.nrows());
    for t in a.triplet_iter() {
        y[t.row] += t.val * x[t.col];
    }
    y
}

/// Modified Gram-Schmidt in the M inner product (twice, for stability). `None` if the
/// vectors are linearly dependent in that inner product.
pub(crate) fn m_orthonormal(
    m: &SparseColMat<usize, f64>,
    vectors: Vec<Col<f64>>,
) -> Option<Vec<Col<f64>>> {
    let mut basis: Vec<(Col<f64>, Col<f64>)> = Vec::with_capacity(vectors.len());
    for mut v in vectors {
        let norm0 = {
            let mv = sparse_matvec(m, v.as_ref());
            dot(&mv, &v).max(0.0).sqrt()
        };
        for _ in 0..2 {
            for (b, mb) in &basis {
                let c = dot(mb, &v);
                v -= c * b;
            }
        }
        let mv = sparse_matvec(m, v.as_ref());
        let norm = dot(&mv, &v).max(0.0).sqrt();
        if norm.is_nan() || norm <= 1e-10 * norm0 || norm == 0.0 {
            return None;
        }
        let s = faer::Scale(1.0 / norm);
        basis.push((&v * s, &mv * s));
    }
    Some(basis.into_iter().map(|(b, _)| b).collect())
}

fn dot(a: &Col<f64>, b: &Col<f64>) -> f64 {
    (0..a.nrows()).map(|i| a[i] * b[i]).sum()
}
