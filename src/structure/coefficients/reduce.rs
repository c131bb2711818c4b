//! `reduce`: every constant coefficient of (3.2.1) from the FE model and the shape vectors.
//!
//! With the bilinear form `E(f, g)` of [`super::moments`] (the nodal-block discretisation of
//! `∫ f · g dm`) and the fields, per node `a` (position `r_a`, mode `m` giving `u_m,a` and
//! `θ_m,a`; a field is written `(nodal vector, gradient)`):
//! - translation `V(x) = (x, 0)`,
//! - rigid rotation `R(x) = (x × r_a, x^×)`,
//! - rotation of the deformation `U_m(x) = (x × u_m,a, x^× θ_m,a^×)`,
//! - mode shape `φ_m = (u_m,a, θ_m,a^×)`,
//!
//! the inertial velocity field of (2.1.2), `V_B + ω × (r + u) + u̇` with `u = Σ η_m φ_m`, is
//! `V(V_B) + R(ω) + Σ_m η_m U_m(ω) + Σ_m η̇_m φ_m`, and `T = ½ E(v, v)` gives
//! ```text
//! x^T (m 1) y        = E(V(x), V(y))                  (2.5.4, 2.5.25)
//! x^T (-c^×) y       = E(V(x), R(y))                  (2.5.6, 2.5.25)
//! x^T J y            = E(R(x), R(y))                  (2.2.12, 2.5.25)
//! x^T (-(P̄ e_m)^×) y = E(V(x), U_m(y))                (2.5.8, 3.2.10: c_u = P̄ η)
//! P̄ e_m              = [E(V(e_i), φ_m)]_i             (2.5.23, 3.2.3)
//! H̄ e_m              = [E(R(e_i), φ_m)]_i             (2.5.23, 3.2.5)
//! x^T J̄'_ru,m y      = E(R(x), U_m(y))                (2.5.11: x^T(-r^× u^×)y = (x×r)·(y×u))
//! x^T J̄''_uu,mp y    = E(U_m(x), U_p(y))              (2.5.12, Tables 2.1-2.4)
//! H̄'_m e_p           = [E(U_m(e_i), φ_p)]_i           (2.5.26, Tables 2.5-2.6)
//! M̄_mp               = E(φ_m, φ_p) = s_m^T M s_p      (3.2.2)
//! ```
//! The thesis' reduced coefficients (3.2.13)-(3.2.14), (3.2.7) are S-weighted sums of the
//! full-order ones; here the fields are built directly from the columns of `S`, which is the
//! same sum done once. The `V`-`ω` block must have the form `-c_tot^×` of (3.2.1); this holds
//! when every node's column sums `Σ_a A_ab` are isotropic and `Σ_a B_ab` skew (true of any
//! mass matrix that represents rigid translation; beams and lumped masses satisfy it exactly).
//! The departure is measured and reported in [`ReducedModel::rigid_mass_residual`], and
//! `reduce` fails if it exceeds [`RIGID_MASS_TOLERANCE`].

use faer::MatRef;
use faer::sparse::SparseColMat;
use nalgebra::{Matrix3, Vector3};

use super::moments::{Dual, NodalBlocks, skew, vee_skew};
use super::{CoefficientError, ReducedModel};
use crate::structure::{DOF_PER_NODE, FeModel};

/// Largest relative departure from a rigid mass distribution that `reduce` accepts (allows
/// for the rounding of masses read from 8-character NASTRAN fields).
pub const RIGID_MASS_TOLERANCE: f64 = 1e-4;

fn to_array(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    [
        [m[(0, 0)], m[(0, 1)], m[(0, 2)]],
        [m[(1, 0)], m[(1, 1)], m[(1, 2)]],
        [m[(2, 0)], m[(2, 1)], m[(2, 2)]],
    ]
}

/// `S^T A S` for a sparse symmetric `A` (one sparse product per column of `S`).
fn project(a: &SparseColMat<usize, f64>, shapes: MatRef<'_, f64>) -> Vec<f64> {
    let n = shapes.ncols();
    let symbolic = a.symbolic();
    let row_idx = symbolic.row_idx();
    let val = a.val();
    let mut y = vec![0.0; shapes.nrows()];
    let mut out = vec![0.0; n * n];
    for p in 0..n {
        y.iter_mut().for_each(|v| *v = 0.0);
        for j in 0..shapes.nrows() {
            let sj = shapes[(j, p)];
            if sj == 0.0 {
                continue;
            }
            for idx in symbolic.col_range(j) {
                y[row_idx[idx]] += val[idx] * sj;
            }
        }
        for m in 0..n {
            out[m * n + p] = (0..shapes.nrows()).map(|i| shapes[(i, m)] * y[i]).sum();
        }
    }
    out
}

fn check_inputs(
    model: &FeModel,
    origin: usize,
    shapes: MatRef<'_, f64>,
    omega2: &[f64],
    damping: &[f64],
) -> Result<(), CoefficientError> {
    let n_nodes = model.nodes.len();
    if origin >= n_nodes {
        return Err(CoefficientError::OriginOutOfRange { origin, n_nodes });
    }
    let n_dof = model.n_dof();
    if shapes.nrows() != n_dof {
        return Err(CoefficientError::LengthMismatch {
            what: "shape vectors (rows)",
            expected: n_dof,
            found: shapes.nrows(),
        });
    }
    let n = shapes.ncols();
    for (what, list) in [("omega2", omega2), ("damping", damping)] {
        if list.len() != n {
            return Err(CoefficientError::LengthMismatch {
                what,
                expected: n,
                found: list.len(),
            });
        }
        if let Some((index, &value)) = list
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
        {
            return Err(CoefficientError::Negative { what, index, value });
        }
    }
    for col in 0..n {
        for row in 0..n_dof {
            if !shapes[(row, col)].is_finite() {
                return Err(CoefficientError::NonFinite {
                    what: "shape vector entry",
                    row,
                    col,
                });
            }
        }
    }
    let k = &model.stiffness;
    if k.nrows() != n_dof || k.ncols() != n_dof {
        return Err(CoefficientError::MatrixSize {
            what: "stiffness",
            expected: n_dof,
            rows: k.nrows(),
            cols: k.ncols(),
        });
    }
    for (n_pos, node) in model.nodes.iter().enumerate() {
        if node.position.iter().any(|x| !x.is_finite()) {
            return Err(CoefficientError::NonFinite {
                what: "node position",
                row: n_pos,
                col: 0,
            });
        }
    }
    Ok(())
}

/// All constant coefficients of (3.2.1), computed from the 6x6 nodal blocks of `M` (never
/// forming dense N x N x (3x3) arrays); derivation in the module documentation.
///
/// `origin` is the node that carries the body frame; `shapes` (6N x n) should already have
/// zero motion at that node ([`super::fix_modes_at_origin`], thesis 3.3). `omega2` are the
/// squared natural frequencies and `damping` the modal damping ratios `ζ_m` of the shapes.
/// Positions `r_a` are the node positions in the body frame.
///
/// Cost: `(4 n + 6)` passes over the stored nodal blocks and `O(n^2)` passes over the nodes.
pub fn reduce(
    model: &FeModel,
    origin: usize,
    shapes: MatRef<'_, f64>,
    omega2: &[f64],
    damping: &[f64],
) -> Result<ReducedModel, CoefficientError> {
    check_inputs(model, origin, shapes, omega2, damping)?;
    let n_nodes = model.nodes.len();
    let n = shapes.ncols();
    let blocks = NodalBlocks::from_mass(&model.mass, n_nodes)?;
    let r: Vec<Vector3<f64>> = model
        .nodes
        .iter()
        .map(|nd| Vector3::from(nd.position))
        .collect();
    let node_vec = |m: usize, a: usize, k0: usize| {
        let i = a * DOF_PER_NODE + k0;
        Vector3::new(shapes[(i, m)], shapes[(i + 1, m)], shapes[(i + 2, m)])
    };
    let u: Vec<Vec<Vector3<f64>>> = (0..n)
        .map(|m| (0..n_nodes).map(|a| node_vec(m, a, 0)).collect())
        .collect();
    let theta: Vec<Vec<Vector3<f64>>> = (0..n)
        .map(|m| (0..n_nodes).map(|a| node_vec(m, a, 3)).collect())
        .collect();
    let theta_x: Vec<Vec<Matrix3<f64>>> =
        theta.iter().map(|t| t.iter().map(skew).collect()).collect();

    let mut dual = Dual::new(n_nodes);
    let mut g = vec![Vector3::zeros(); n_nodes];
    let mut gm = vec![Matrix3::zeros(); n_nodes];
    let unit = |j: usize| Vector3::from_fn(|i, _| if i == j { 1.0 } else { 0.0 });

    // Rigid 6x6 of (2.5.25): E(V, V), E(V, R), E(R, R).
    let (mut tm, mut tc, mut jr) = (Matrix3::zeros(), Matrix3::zeros(), Matrix3::zeros());
    for j in 0..3 {
        let e = unit(j);
        g.iter_mut().for_each(|x| *x = e);
        gm.iter_mut().for_each(|x| *x = Matrix3::zeros());
        blocks.dual_into(&g, &gm, &mut dual);
        tm.set_column(j, &dual.contract_translation());
        for a in 0..n_nodes {
            g[a] = e.cross(&r[a]);
            gm[a] = skew(&e);
        }
        blocks.dual_into(&g, &gm, &mut dual);
        tc.set_column(j, &dual.contract_translation());
        jr.set_column(j, &dual.contract_rotation(|a| (r[a], None)));
    }
    let mass = tm.trace() / 3.0;
    if !(mass > 0.0 && mass.is_finite()) {
        return Err(CoefficientError::NonPositiveMass { mass });
    }
    let length = r
        .iter()
        .map(|x| x.norm())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let c = -vee_skew(&tc);
    let mut residual = (tm - Matrix3::identity() * mass).norm() / mass;
    residual = residual.max((tc + skew(&c)).norm() / (mass * length));
    let inertia = 0.5 * (jr + jr.transpose());

    let mut p_bar = vec![0.0; 3 * n];
    let mut h_bar = vec![0.0; 3 * n];
    let mut h_prime = vec![0.0; 3 * n * n];
    let mut j_ru = vec![[[0.0; 3]; 3]; n];
    let mut j_uu = vec![[[0.0; 3]; 3]; n * n];
    for p in 0..n {
        // Mode field φ_p: P̄, H̄, H̄'.
        g.copy_from_slice(&u[p]);
        gm.copy_from_slice(&theta_x[p]);
        blocks.dual_into(&g, &gm, &mut dual);
        let pp = dual.contract_translation();
        let hp = dual.contract_rotation(|a| (r[a], None));
        for i in 0..3 {
            p_bar[i * n + p] = pp[i];
            h_bar[i * n + p] = hp[i];
        }
        for m in 0..n {
            let hm = dual.contract_rotation(|a| (u[m][a], Some(theta_x[m][a])));
            for i in 0..3 {
                h_prime[(m * 3 + i) * n + p] = hm[i];
            }
        }
        // Rotated deformation U_p(e_j): J̄', J̄'' and the c_u check.
        let mut jp = Matrix3::zeros();
        let mut cu = Matrix3::zeros();
        let mut jpp = vec![Matrix3::zeros(); n];
        for j in 0..3 {
            let ex = skew(&unit(j));
            for a in 0..n_nodes {
                g[a] = unit(j).cross(&u[p][a]);
                gm[a] = ex * theta_x[p][a];
            }
            blocks.dual_into(&g, &gm, &mut dual);
            jp.set_column(j, &dual.contract_rotation(|a| (r[a], None)));
            cu.set_column(j, &dual.contract_translation());
            for (m, jmp) in jpp.iter_mut().enumerate() {
                jmp.set_column(
                    j,
                    &dual.contract_rotation(|a| (u[m][a], Some(theta_x[m][a]))),
                );
            }
        }
        j_ru[p] = to_array(&jp);
        for (m, jmp) in jpp.iter().enumerate() {
            j_uu[m * n + p] = to_array(jmp);
        }
        let shape_scale = mass
            * (u[p].iter().map(|x| x.norm()).fold(0.0, f64::max)
                + length * theta[p].iter().map(|x| x.norm()).fold(0.0, f64::max));
        if shape_scale > 0.0 {
            residual = residual.max((cu + skew(&pp)).norm() / shape_scale);
        }
    }
    if residual > RIGID_MASS_TOLERANCE {
        return Err(CoefficientError::NonRigidMass {
            what: "translational column sums (isotropy) or first moments (skewness)",
            residual,
            tolerance: RIGID_MASS_TOLERANCE,
        });
    }

    let modal_mass = project(&model.mass, shapes);
    let modal_stiffness = project(&model.stiffness, shapes);
    let mut modal_damping = vec![0.0; n * n];
    for m in 0..n {
        modal_damping[m * n + m] = 2.0 * damping[m] * omega2[m].sqrt() * modal_mass[m * n + m];
    }
    Ok(ReducedModel {
        origin_node: origin as u32,
        n_modes: n as u32,
        mass,
        first_moment: [c.x, c.y, c.z],
        inertia: to_array(&inertia),
        modal_mass,
        modal_stiffness,
        modal_damping,
        omega2: omega2.to_vec(),
        damping_ratio: damping.to_vec(),
        p_bar,
        h_bar,
        j_ru,
        j_uu,
        h_prime,
        rigid_mass_residual: residual,
    })
}
