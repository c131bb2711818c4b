//! The motor's masses on the FE model: the casing (constant) and the propellant grain (which
//! burns), each a cylinder on the body axis attached to the body nodes.
//!
//! Discretisation: the motor's length is cut into [`SLICES`] equal slices; each slice is a
//! rigid body (mass `dm`, centroid on the axis, inertia about its centroid) attached by a
//! rigid link to the body node nearest its centroid, i.e. the 6x6 nodal block
//! `Aᵀ diag(dm 1, I_c) A` with `A = [[1, -d^×], [0, 1]]` for the offset `d` from the node
//! (the same rigid-offset block as the generator's point masses). A rigid link represents the
//! slice's rigid-body inertia exactly, and the slice inertias with the parallel-axis terms
//! add up to the cylinder's exactly (a uniform cylinder cut into slices of length `Δ`:
//! `Σ dm (x_s - x_c)² + Σ dm Δ²/12 = m L²/12`), so the mass, the first moment and the inertia
//! of the motor in the reduced model are those of the cylinders to rounding
//! (`tests/motor.rs` checks them); the elastic modes see the mass lumped at the nearest
//! nodes.
//!
//! - Propellant grain: a solid cylinder of the motor's diameter `D` (the bore and the casing
//!   wall are not modelled): slice `I_xx = dm D²/8`, `I_yy = I_zz = dm (D²/16 + Δ²/12)`.
//! - Casing (total minus propellant mass): a thin tube of diameter `D`: `I_xx = dm D²/4`,
//!   `I_yy = I_zz = dm (D²/8 + Δ²/12)`.

use faer::sparse::{SparseColMat, Triplet};
use nalgebra::{Matrix3, Matrix6, Vector3};

use super::fe_model::{Component, DOF_PER_NODE, FeModel};
use crate::check::ir::Motor;

/// Number of slices along the motor.
pub const SLICES: usize = 64;

/// Why the motor's masses cannot be placed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MotorMassError {
    #[error("the FE model has no body nodes to carry the motor")]
    NoBodyNodes,
    #[error("could not assemble the motor's mass matrix: {0}")]
    Assembly(String),
}

/// The rigid-offset 6x6 block of a body of mass `m`, inertia `ic` (about its centroid, body
/// axes, diagonal) at offset `d` from its node.
fn offset_block(m: f64, d: &Vector3<f64>, ic: [f64; 3]) -> Matrix6<f64> {
    let dx = Matrix3::new(0.0, -d.z, d.y, d.z, 0.0, -d.x, -d.y, d.x, 0.0);
    let i_c = Matrix3::from_diagonal(&Vector3::from(ic));
    let mut b = Matrix6::zeros();
    // Velocity of the centroid: u + θ × d = u - d^× θ.
    b.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&(Matrix3::identity() * m));
    b.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-m * dx));
    b.fixed_view_mut::<3, 3>(3, 0).copy_from(&(m * dx));
    b.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&(i_c - m * dx * dx));
    b
}

/// Blocks `(node, 6x6)` of one cylinder: `mass` spread uniformly over `[x_aft, x_aft + L]`,
/// with the slice inertia `inertia(dm, Δ)`.
fn cylinder_blocks(
    model: &FeModel,
    body: &[usize],
    x_aft: f64,
    length: f64,
    mass: f64,
    inertia: impl Fn(f64, f64) -> [f64; 3],
) -> Vec<(usize, Matrix6<f64>)> {
    let dl = length / SLICES as f64;
    let dm = mass / SLICES as f64;
    (0..SLICES)
        .map(|k| {
            let xs = x_aft + (k as f64 + 0.5) * dl;
            let c = Vector3::new(xs, 0.0, 0.0);
            // `body` is non-empty (checked by the caller).
            let node = body
                .iter()
                .copied()
                .min_by(|&a, &b| {
                    let da = (Vector3::from(model.nodes[a].position) - c).norm_squared();
                    let db = (Vector3::from(model.nodes[b].position) - c).norm_squared();
                    da.total_cmp(&db)
                })
                .unwrap_or_default();
            let d = c - Vector3::from(model.nodes[node].position);
            (node, offset_block(dm, &d, inertia(dm, dl)))
        })
        .collect()
}

fn add_blocks(
    n_dof: usize,
    base: Option<&SparseColMat<usize, f64>>,
    blocks: &[(usize, Matrix6<f64>)],
) -> Result<SparseColMat<usize, f64>, MotorMassError> {
    let mut t = Vec::new();
    if let Some(a) = base {
        let sym = a.symbolic();
        for j in 0..a.ncols() {
            for idx in sym.col_range(j) {
                t.push(Triplet::new(sym.row_idx()[idx], j, a.val()[idx]));
            }
        }
    }
    for (node, b) in blocks {
        for c in 0..6 {
            for r in 0..6 {
                let v = b[(r, c)];
                if v != 0.0 {
                    t.push(Triplet::new(
                        DOF_PER_NODE * node + r,
                        DOF_PER_NODE * node + c,
                        v,
                    ));
                }
            }
        }
    }
    SparseColMat::try_new_from_triplets(n_dof, n_dof, &t)
        .map_err(|e| MotorMassError::Assembly(format!("{e:?}")))
}

/// The FE model with the motor at ignition (casing and full grain added to `M`), and the
/// propellant grain's mass matrix alone (same DOFs).
pub fn with_motor(
    model: &FeModel,
    comps: &[Component],
    motor: &Motor,
) -> Result<(FeModel, SparseColMat<usize, f64>), MotorMassError> {
    let body: Vec<usize> = (0..model.nodes.len())
        .filter(|&i| comps.get(i).is_none_or(|c| *c == Component::Body))
        .collect();
    if body.is_empty() {
        return Err(MotorMassError::NoBodyNodes);
    }
    let (x_aft, length, dia) = (
        motor.position.value[0],
        motor.length.value,
        motor.diameter.value,
    );
    let m_p = motor.propellant_mass.value;
    let m_c = motor.total_mass.value - m_p;
    let grain = cylinder_blocks(model, &body, x_aft, length, m_p, |dm, dl| {
        let t = dm * (dia * dia / 16.0 + dl * dl / 12.0);
        [dm * dia * dia / 8.0, t, t]
    });
    let casing = cylinder_blocks(model, &body, x_aft, length, m_c, |dm, dl| {
        let t = dm * (dia * dia / 8.0 + dl * dl / 12.0);
        [dm * dia * dia / 4.0, t, t]
    });
    let n_dof = model.n_dof();
    let mut all = grain.clone();
    if m_c > 0.0 {
        all.extend(casing);
    }
    let mut full = model.clone();
    full.mass = add_blocks(n_dof, Some(&model.mass), &all)?;
    let prop = add_blocks(n_dof, None, &grain)?;
    Ok((full, prop))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_block_is_the_rigid_link_of_a_point_mass() {
        // Kinetic energy of the block for node velocity u, rotation rate θ: ½ m |u + θ×d|²
        // + ½ θᵀ I_c θ.
        let d = Vector3::new(0.3, -0.2, 0.1);
        let b = offset_block(2.0, &d, [0.1, 0.2, 0.3]);
        let u = Vector3::new(0.5, -1.0, 2.0);
        let th = Vector3::new(0.7, 0.2, -0.4);
        let mut v = nalgebra::Vector6::zeros();
        v.fixed_rows_mut::<3>(0).copy_from(&u);
        v.fixed_rows_mut::<3>(3).copy_from(&th);
        let e = 0.5 * (v.transpose() * b * v)[(0, 0)];
        let vc = u + th.cross(&d);
        let want = 0.5 * 2.0 * vc.norm_squared()
            + 0.5 * (0.1 * th.x * th.x + 0.2 * th.y * th.y + 0.3 * th.z * th.z);
        assert!((e - want).abs() < 1e-14, "{e} {want}");
    }
}
