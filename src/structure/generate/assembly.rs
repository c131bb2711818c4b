//! Sparse assembly from triplets, with rigid-link elimination of the fin root nodes.
//!
//! Every element node maps to a global node in one of three ways (`NodeMap`): it is a
//! global node, it is a slave rigidly linked to a master node, or it is fixed (clamped).
//! A slave at offset d = r_s - r_m from its master moves as
//!   u_s = u_m + theta_m x d = u_m - d^x theta_m,   theta_s = theta_m,
//! i.e. q_s = A q_m with A = [[I, -d^x], [0, I]], so an element block K_ab between element
//! nodes a and b contributes A_a^T K_ab A_b to the global block of their masters. The slave
//! DOFs never appear in the model. (The same A appears in the thesis's nodal-block
//! approximations (2.5.14)-(2.5.20), where a node's rigid motion is V_B + omega_B x r.)

use faer::sparse::{SparseColMat, Triplet};
use nalgebra::{Matrix3, Matrix6, Vector3};

use super::GenerateError;
use crate::structure::fe_model::DOF_PER_NODE;

/// Assembled sparse matrix type of `FeModel`.
pub type SparseMatrix = SparseColMat<usize, f64>;

/// How an element node enters the global system.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NodeMap {
    /// A global node (index into `FeModel::nodes`).
    Node(usize),
    /// Rigidly linked to global node `master`, at offset `offset` = r_slave - r_master.
    Slave { master: usize, offset: [f64; 3] },
    /// Clamped: all six DOFs zero.
    Fixed,
}

/// Skew matrix a^x = [[0, -a3, a2], [a3, 0, -a1], [-a2, a1, 0]] (REFERENCE-NOTES).
pub fn skew(a: &[f64; 3]) -> Matrix3<f64> {
    Matrix3::new(0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0)
}

/// Rigid-link transformation A = [[I, -d^x], [0, I]] (module doc).
pub fn rigid_link(d: &[f64; 3]) -> Matrix6<f64> {
    let mut a = Matrix6::identity();
    a.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-skew(d)));
    a
}

/// 6 x 6 mass block of a rigid body of mass m, centre at offset d from a node, principal
/// inertia `inertia` (about its own centre, node axes): kinetic energy
/// 1/2 m |u - d^x theta|^2 + 1/2 theta^T I_c theta gives
/// [[m I, -m d^x], [m d^x, I_c - m d^x d^x]].
pub fn offset_mass_block(m: f64, d: &[f64; 3], inertia: &[f64; 3]) -> Matrix6<f64> {
    let dx = skew(d);
    let mut b = Matrix6::zeros();
    b.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(Matrix3::identity() * m));
    b.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-m * dx));
    b.fixed_view_mut::<3, 3>(3, 0).copy_from(&(m * dx));
    let ic = Matrix3::from_diagonal(&Vector3::new(inertia[0], inertia[1], inertia[2]));
    b.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&(ic - m * dx * dx));
    b
}

/// Triplet lists of K and M for `n_nodes` global nodes.
pub struct Assembler {
    n_dof: usize,
    k: Vec<Triplet<usize, usize, f64>>,
    m: Vec<Triplet<usize, usize, f64>>,
}

impl Assembler {
    /// An empty assembler for `n_nodes` nodes of six DOFs.
    pub fn new(n_nodes: usize) -> Self {
        Self {
            n_dof: n_nodes * DOF_PER_NODE,
            k: Vec::new(),
            m: Vec::new(),
        }
    }

    /// Reserve room for `n` more 6 x 6 blocks in each matrix.
    pub fn reserve_blocks(&mut self, n: usize) {
        self.k.reserve(36 * n);
        self.m.reserve(36 * n);
    }

    /// Add an element whose matrices are in global directions, 6 DOFs per element node.
    /// `k_e(a, b)` and `m_e(a, b)` return the 6 x 6 blocks between element nodes a and b.
    pub fn add_element(
        &mut self,
        maps: &[NodeMap],
        k_e: impl Fn(usize, usize) -> Matrix6<f64>,
        m_e: impl Fn(usize, usize) -> Matrix6<f64>,
    ) {
        let resolve = |map: &NodeMap| -> Option<(usize, Option<Matrix6<f64>>)> {
            match map {
                NodeMap::Node(i) => Some((*i, None)),
                NodeMap::Slave { master, offset } => Some((*master, Some(rigid_link(offset)))),
                NodeMap::Fixed => None,
            }
        };
        let resolved: Vec<_> = maps.iter().map(resolve).collect();
        for (a, ra) in resolved.iter().enumerate() {
            let Some((ga, ta)) = ra else { continue };
            for (b, rb) in resolved.iter().enumerate() {
                let Some((gb, tb)) = rb else { continue };
                let mut kb = k_e(a, b);
                let mut mb = m_e(a, b);
                if let Some(t) = ta {
                    kb = t.transpose() * kb;
                    mb = t.transpose() * mb;
                }
                if let Some(t) = tb {
                    kb *= t;
                    mb *= t;
                }
                Self::push_block(&mut self.k, *ga, *gb, &kb);
                Self::push_block(&mut self.m, *ga, *gb, &mb);
            }
        }
    }

    /// Add a 6 x 6 mass block at one global node.
    pub fn add_nodal_mass(&mut self, node: usize, block: &Matrix6<f64>) {
        Self::push_block(&mut self.m, node, node, block);
    }

    fn push_block(
        list: &mut Vec<Triplet<usize, usize, f64>>,
        ga: usize,
        gb: usize,
        b: &Matrix6<f64>,
    ) {
        for c in 0..6 {
            for r in 0..6 {
                let v = b[(r, c)];
                if v != 0.0 {
                    list.push(Triplet::new(6 * ga + r, 6 * gb + c, v));
                }
            }
        }
    }

    /// Build (mass, stiffness); duplicates are summed.
    pub fn finish(self) -> Result<(SparseMatrix, SparseMatrix), GenerateError> {
        let build = |t: &[Triplet<usize, usize, f64>]| {
            SparseColMat::try_new_from_triplets(self.n_dof, self.n_dof, t)
                .map_err(|e| GenerateError::Assembly(format!("{e:?}")))
        };
        Ok((build(&self.m)?, build(&self.k)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The offset mass block equals A^T diag(m, m, m, I_c) A with A the rigid link, i.e. the
    /// signs of the coupling and of the parallel-axis term are those of a rigid offset.
    #[test]
    fn offset_mass_is_rigid_link_of_point_mass() {
        let d = [0.3, -0.2, 0.1];
        let (m, ic) = (2.5, [0.1, 0.2, 0.3]);
        let a = rigid_link(&d);
        let mut diag = Matrix6::zeros();
        for i in 0..3 {
            diag[(i, i)] = m;
            diag[(i + 3, i + 3)] = ic[i];
        }
        let want = a.transpose() * diag * a;
        let got = offset_mass_block(m, &d, &ic);
        assert!((want - got).abs().max() < 1e-14);
        // Rotational block about the node: I_c + m (|d|^2 I - d d^T).
        let dd = Vector3::from(d);
        let par = m * (dd.norm_squared() * Matrix3::identity() - dd * dd.transpose());
        let rot = got.fixed_view::<3, 3>(3, 3).into_owned();
        assert!(
            (rot - par - Matrix3::from_diagonal(&Vector3::from(ic)))
                .abs()
                .max()
                < 1e-14
        );
        // A unit rotation about z moves the mass by theta x d = (-d_y, d_x, 0).
        let mut q = nalgebra::Vector6::zeros();
        q[5] = 1.0;
        let u = a * q;
        assert!((u[0] - 0.2).abs() < 1e-15 && (u[1] - 0.3).abs() < 1e-15 && u[2] == 0.0);
    }
}
