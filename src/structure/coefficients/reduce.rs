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
/// squared natural frequencies the shapes came with (stored, not used for the damping) and
/// `damping` the damping ratios `ζ_m` of the free vehicle's elastic modes (see
/// [`free_vehicle_damping`] for what that means and how `C̄` is built).
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
    let modal_damping = free_vehicle_damping(
        mass,
        &c,
        &inertia,
        &p_bar,
        &h_bar,
        &modal_mass,
        &modal_stiffness,
        damping,
    )?;
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

/// The modal damping matrix `C̄` that gives every elastic mode of the FREE vehicle the
/// damping ratio asked for.
///
/// **What `damping` means.** `ζ_m` is the damping ratio of the m-th elastic mode of the free
/// vehicle (no loads, linearised about rest): its roots are `λ = -ζ ω ± i ω √(1-ζ²)`. It is
/// not a ratio per coordinate `η_m` of the fixity-adjusted shapes: those coordinates are
/// coupled to the rigid body through the mass matrix, and the thesis' `C̄ = 2 ζ ω M̄_mm`
/// (2.5.32 with the modal mass of 3.2.2) then gives the free vehicle a different ratio
/// (`ζ M̄_mm / M_f,mm`: 0.27 instead of 0.01 for SPHADS-1's body bending, whose adjusted
/// shape carries 27 times the generalised mass of the free mode).
///
/// **Derivation.** Linearised about rest with no loads, (3.2.1) is
/// ```text
/// [ M_rr  B  ] [ v̇_r ]   [ 0    0 ] [ v_r ]   [ 0   0 ] [ q_r ]
/// [ B^T   M̄ ] [ η̈   ] + [ 0    C̄ ] [ η̇   ] + [ 0   K̄ ] [ η   ] = 0
/// ```
/// with `v_r = (V_B, ω_B)`, `M_rr = [[m 1, -c^×], [c^×, J]]` (2.5.25), `B = [P̄; H̄]`
/// (3.2.3, 3.2.5) and `M̄`, `K̄` of (3.2.2), (3.2.20): the `η = 0` block of `M_tot(η)` in
/// [`ReducedModel::mass_matrix_into`]. The rigid rows give `v̇_r = -M_rr⁻¹ B η̈`; substituted,
/// ```text
/// M_f η̈ + C̄ η̇ + K̄ η = 0,    M_f = M̄ - B^T M_rr⁻¹ B      (Schur complement)
/// ```
/// `M_f` is the generalised mass of the free-vehicle motion: writing the deformation of a
/// fixity-adjusted shape as `s = φ - R g` (free-free shape minus a rigid motion, 3.3.1),
/// `M_f = φ^T M φ` because the rigid part is exactly what the elimination removes (for
/// unadjusted free-free shapes `B = 0` and `M_f = M̄`). Let `M_f = L L^T` (Cholesky),
/// `L⁻¹ K̄ L⁻ᵀ = V Ω² V^T` (symmetric eigen-decomposition) and `Ψ = L⁻ᵀ V`, so that
/// `Ψ^T M_f Ψ = 1` and `Ψ^T K̄ Ψ = Ω²`. Choosing
/// ```text
/// C̄ = M_f Ψ diag(2 ζ_i ω_i) Ψ^T M_f = (L V) diag(2 ζ_i ω_i) (L V)^T
/// ```
/// makes `Ψ^T C̄ Ψ = diag(2 ζ_i ω_i)`, so in the coordinates `η = Ψ x` every free mode obeys
/// `ẍ_i + 2 ζ_i ω_i ẋ_i + ω_i² x_i = 0`: ratio exactly `ζ_i` at frequency `ω_i` (the
/// classical damping matrix built from modal ratios, Clough & Penzien, Dynamics of
/// Structures, ch. 12, applied here to the reduced free-vehicle pair `(M_f, K̄)`). When the selected shapes are free-free eigenvectors, `M_f` and `K̄` are
/// diagonal, `ω_i` are their frequencies and `C̄ = diag(2 ζ_m ω_m M_f,mm)`, the textbook
/// modal damping with the free mode's generalised mass.
///
/// **Which ζ for which root.** Root `i` takes `ζ_i = Σ_m V_mi² ζ_m`, the mean of the ratios of
/// the selected modes weighted by their share of it (the squares of the orthonormal `V`
/// sum to 1 over `m`): exactly `ζ_m` for a root that is one selected mode, and exactly the
/// common value when one ratio is given for all. All ratios zero gives `C̄ = 0` exactly.
///
/// `M_rr` is inverted by its symmetric eigen-decomposition, dropping eigenvalues below
/// `1e-12` of the largest (a direction with no rigid inertia, such as roll of a model with
/// all its mass on the axis, has no coupling either). Fails if `M_f` is not positive definite
/// (a selected shape with no elastic motion).
#[allow(clippy::too_many_arguments)]
fn free_vehicle_damping(
    mass: f64,
    c: &Vector3<f64>,
    inertia: &Matrix3<f64>,
    p_bar: &[f64],
    h_bar: &[f64],
    modal_mass: &[f64],
    modal_stiffness: &[f64],
    zeta: &[f64],
) -> Result<Vec<f64>, CoefficientError> {
    use nalgebra::{DMatrix, Matrix6, SymmetricEigen};
    let n = zeta.len();
    if zeta.iter().all(|z| *z == 0.0) {
        return Ok(vec![0.0; n * n]);
    }
    let cx = skew(c);
    let mut mrr = Matrix6::zeros();
    for i in 0..3 {
        for k in 0..3 {
            mrr[(i, k)] = if i == k { mass } else { 0.0 };
            mrr[(i, 3 + k)] = -cx[(i, k)];
            mrr[(3 + i, k)] = cx[(i, k)];
            mrr[(3 + i, 3 + k)] = inertia[(i, k)];
        }
    }
    let eig = SymmetricEigen::new(mrr);
    let top = eig.eigenvalues.iter().fold(0.0_f64, |a, &l| a.max(l.abs()));
    let mut mrr_pinv = Matrix6::zeros();
    for (j, &l) in eig.eigenvalues.iter().enumerate() {
        if l > 1e-12 * top {
            let q = eig.eigenvectors.column(j);
            mrr_pinv += q * q.transpose() / l;
        }
    }
    let b = DMatrix::from_fn(6, n, |i, m| {
        if i < 3 {
            p_bar[i * n + m]
        } else {
            h_bar[(i - 3) * n + m]
        }
    });
    let sym = |a: &[f64]| DMatrix::from_fn(n, n, |i, k| 0.5 * (a[i * n + k] + a[k * n + i]));
    let mut mf =
        sym(modal_mass) - b.transpose() * DMatrix::from_fn(6, 6, |i, k| mrr_pinv[(i, k)]) * &b;
    mf = 0.5 * (&mf + mf.transpose());
    let kbar = sym(modal_stiffness);
    let Some(chol) = mf.clone().cholesky() else {
        let index = (0..n)
            .min_by(|&i, &k| mf[(i, i)].total_cmp(&mf[(k, k)]))
            .unwrap_or(0);
        return Err(CoefficientError::ElasticMassNotPositive {
            index,
            value: mf[(index, index)],
        });
    };
    let l = chol.l();
    // A = L⁻¹ K̄ L⁻ᵀ.
    let linv_k =
        l.solve_lower_triangular(&kbar)
            .ok_or(CoefficientError::ElasticMassNotPositive {
                index: 0,
                value: 0.0,
            })?;
    let a = l.solve_lower_triangular(&linv_k.transpose()).ok_or(
        CoefficientError::ElasticMassNotPositive {
            index: 0,
            value: 0.0,
        },
    )?;
    let a = 0.5 * (&a + a.transpose());
    let e = SymmetricEigen::new(a);
    let lv = &l * &e.eigenvectors;
    let mut out = vec![0.0; n * n];
    for i in 0..n {
        let omega = e.eigenvalues[i].max(0.0).sqrt();
        let z: f64 = (0..n)
            .map(|m| e.eigenvectors[(m, i)].powi(2) * zeta[m])
            .sum();
        let d = 2.0 * z * omega;
        for r in 0..n {
            for k in 0..n {
                out[r * n + k] += lv[(r, i)] * d * lv[(k, i)];
            }
        }
    }
    // Exactly symmetric.
    for r in 0..n {
        for k in r + 1..n {
            let v = 0.5 * (out[r * n + k] + out[k * n + r]);
            out[r * n + k] = v;
            out[k * n + r] = v;
        }
    }
    Ok(out)
}
