//! Nodal-block discretisation of the mass integrals of thesis 2.2 and 2.5.
//!
//! Every inertia coefficient of (2.5.1)/(3.2.1) is an integral `∫ f · g dm` of two vector
//! fields over the vehicle: (2.2.7)-(2.2.19), (2.5.8)-(2.5.12). The thesis approximates
//! these integrals with the 6x6 nodal blocks of the FE mass matrix, (2.5.14)-(2.5.20) and
//! Tables 2.1-2.6, but the OCR of those tables is unusable. We therefore state the
//! discretisation once, here, and derive every coefficient from it (module `reduce`).
//!
//! **Affine nodal fields.** Near node `a` (undeformed position `r_a`, local offset `ρ`) a
//! field is written `f(r_a + ρ) = f_a + F_a ρ` with a nodal vector `f_a` and a 3x3 gradient
//! `F_a`. A rigid-per-node field (the FE interpolation of a shape vector: `u_a + θ_a × ρ`)
//! has a skew gradient `F_a = θ_a^×`; the fields `ω × u` of the floating-frame kinetic energy
//! have the non-skew gradient `ω^× θ_a^×`, which is why the thesis needs the "second moment"
//! quantities `Q̄_kl` of (2.5.19) in Tables 2.4 and 2.6.
//!
//! **Pair moments.** For the nodal block `M_ab = [[A, B], [C, D]]` (eq. 2.5.3; `A` = M_tt,
//! `B` = M_tr, `C` = M_rt = B_ba^T, `D` = M_rr) define, as if the block were a mass
//! distribution seen from nodes `a` and `b`,
//! - first moment on the `b` side `k_ab = -vee(skew B_ab)`, on the `a` side
//!   `k_ba = vee(skew C_ab)` (for a rigid body with mass centre offset `ρ_c`, `B = -m ρ_c^×`);
//! - second moment `Σ_ab = ½ tr(D_ab) 1 - D_ab^T` (the thesis' `Q̄_kl`, eq. 2.5.19: a rotary
//!   inertia `D = tr(Σ)1 - Σ^T` inverted).
//!
//! The bilinear form that replaces `∫ f · g dm` is
//! ```text
//! E(f, g) = Σ_ab [ f_a^T A_ab g_b + f_a^T G_b k_ab + g_b^T F_a k_ba + tr(G_b^T F_a Σ_ab)
//!                  + ½ f_a^T sym(B_ab) w(G_b) + ½ g_b^T sym(C_ab) w(F_a) ],
//! w(X) = vee(X - X^T).
//! ```
//! For skew gradients (`F_a = α_a^×`, `G_b = β_b^×`) it reduces exactly to
//! `Σ_ab [f_a; α_a]^T M_ab [g_b; β_b]`, i.e. to `s^T M s'` (so `M̄ = S^T M S`, eq. 3.2.2, and
//! the rigid quantities of (2.5.23)-(2.5.25) are unchanged); for a lumped model of rigid nodal
//! bodies (block-diagonal `M`) it is the exact integral for any affine field. It is symmetric
//! (`E(f, g) = E(g, f)`), so one kinetic energy `T = ½ E(V, V)` generates every coefficient.
//!
//! **Evaluation.** `E(f, g)` is computed in two passes: a pass over the stored blocks builds
//! the "dual" of `g` at every node, `(α_a, X_a)`, and a pass over the nodes contracts it with
//! `f`: `E = Σ_a f_a · α_a + tr(F_a X_a)`. With
//! `α_a = Σ_b A_ab g_b + G_b k_ab + ½ sym(B_ab) w(G_b)` and
//! `X_a = Σ_b k_ba g_b^T + Σ_ab G_b^T - (½ sym(C_ab) g_b)^×`
//! (using `w(F) · β = tr(F (-β^×))`).

use faer::sparse::SparseColMat;
use nalgebra::{Matrix3, Vector3};

use super::CoefficientError;
use crate::structure::DOF_PER_NODE;

/// Skew matrix `a^×` (REFERENCE-NOTES convention).
pub(crate) fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// `vee(skew part of m)`: the axial vector of `½ (m - m^T)`.
pub(crate) fn vee_skew(m: &Matrix3<f64>) -> Vector3<f64> {
    0.5 * Vector3::new(
        m[(2, 1)] - m[(1, 2)],
        m[(0, 2)] - m[(2, 0)],
        m[(1, 0)] - m[(0, 1)],
    )
}

/// `w(X) = vee(X - X^T)`.
fn w_of(x: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        x[(2, 1)] - x[(1, 2)],
        x[(0, 2)] - x[(2, 0)],
        x[(1, 0)] - x[(0, 1)],
    )
}

/// `τ(X)` with `tr(a^× X) = a · τ(X)`: `τ(X) = vee(X^T - X)`.
pub(crate) fn tau(x: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        x[(1, 2)] - x[(2, 1)],
        x[(2, 0)] - x[(0, 2)],
        x[(0, 1)] - x[(1, 0)],
    )
}

/// The moments of one stored nodal block `M_ab` (see the module documentation).
pub(crate) struct PairMoments {
    pub a: usize,
    pub b: usize,
    /// `A_ab`, translation-translation block.
    pub tt: Matrix3<f64>,
    /// `k_ab = -vee(skew B_ab)`.
    pub k_ab: Vector3<f64>,
    /// `k_ba = vee(skew C_ab)`.
    pub k_ba: Vector3<f64>,
    /// `½ sym(B_ab)`.
    pub half_b_sym: Matrix3<f64>,
    /// `½ sym(C_ab)`.
    pub half_c_sym: Matrix3<f64>,
    /// `Σ_ab = ½ tr(D_ab) 1 - D_ab^T`.
    pub sigma: Matrix3<f64>,
    /// Whether `B_ab` or `C_ab` has a symmetric part (false for beams and rigid bodies).
    pub has_sym: bool,
}

impl PairMoments {
    fn from_block(a: usize, b: usize, blk: &[[f64; 6]; 6]) -> Self {
        let sub = |r0: usize, c0: usize| Matrix3::from_fn(|i, j| blk[r0 + i][c0 + j]);
        let tt = sub(0, 0);
        let tr = sub(0, 3);
        let rt = sub(3, 0);
        let rr = sub(3, 3);
        let half_b_sym = 0.25 * (tr + tr.transpose());
        let half_c_sym = 0.25 * (rt + rt.transpose());
        Self {
            a,
            b,
            tt,
            k_ab: -vee_skew(&tr),
            k_ba: vee_skew(&rt),
            has_sym: half_b_sym
                .iter()
                .chain(half_c_sym.iter())
                .any(|v| *v != 0.0),
            half_b_sym,
            half_c_sym,
            sigma: Matrix3::identity() * (0.5 * rr.trace()) - rr.transpose(),
        }
    }
}

/// The stored nodal blocks of the mass matrix, each reduced to its pair moments.
pub(crate) struct NodalBlocks {
    pub pairs: Vec<PairMoments>,
}

impl NodalBlocks {
    /// Gather the 6x6 nodal blocks of `mass` (one pass over the nonzeros).
    pub fn from_mass(
        mass: &SparseColMat<usize, f64>,
        n_nodes: usize,
    ) -> Result<Self, CoefficientError> {
        let n = n_nodes * DOF_PER_NODE;
        if mass.nrows() != n || mass.ncols() != n {
            return Err(CoefficientError::MatrixSize {
                what: "mass",
                expected: n,
                rows: mass.nrows(),
                cols: mass.ncols(),
            });
        }
        let symbolic = mass.symbolic();
        let row_idx = symbolic.row_idx();
        let val = mass.val();
        let mut slot_of = vec![usize::MAX; n_nodes];
        let mut local: Vec<(usize, [[f64; 6]; 6])> = Vec::new();
        let mut pairs = Vec::new();
        for b in 0..n_nodes {
            for c in 0..DOF_PER_NODE {
                let j = b * DOF_PER_NODE + c;
                for idx in symbolic.col_range(j) {
                    let i = row_idx[idx];
                    let v = val[idx];
                    if !v.is_finite() {
                        return Err(CoefficientError::NonFinite {
                            what: "mass matrix entry",
                            row: i,
                            col: j,
                        });
                    }
                    let a = i / DOF_PER_NODE;
                    let slot = if slot_of[a] == usize::MAX {
                        slot_of[a] = local.len();
                        local.push((a, [[0.0; 6]; 6]));
                        local.len() - 1
                    } else {
                        slot_of[a]
                    };
                    local[slot].1[i % DOF_PER_NODE][c] += v;
                }
            }
            for (a, blk) in local.drain(..) {
                slot_of[a] = usize::MAX;
                pairs.push(PairMoments::from_block(a, b, &blk));
            }
        }
        Ok(Self { pairs })
    }

    /// Build the dual `(α_a, X_a)` of the affine field `(g_b, G_b)` (module documentation).
    pub fn dual_into(&self, g: &[Vector3<f64>], gm: &[Matrix3<f64>], dual: &mut Dual) {
        dual.alpha.iter_mut().for_each(|x| *x = Vector3::zeros());
        dual.x.iter_mut().for_each(|x| *x = Matrix3::zeros());
        for p in &self.pairs {
            let gb = &g[p.b];
            let gmb = &gm[p.b];
            dual.alpha[p.a] += p.tt * gb + gmb * p.k_ab;
            dual.x[p.a] += p.k_ba * gb.transpose() + p.sigma * gmb.transpose();
            if p.has_sym {
                dual.alpha[p.a] += p.half_b_sym * w_of(gmb);
                dual.x[p.a] -= skew(&(p.half_c_sym * gb));
            }
        }
    }
}

/// Per-node dual of a field: `E(f, g) = Σ_a f_a · α_a + tr(F_a X_a)`.
pub(crate) struct Dual {
    pub alpha: Vec<Vector3<f64>>,
    pub x: Vec<Matrix3<f64>>,
}

impl Dual {
    pub fn new(n_nodes: usize) -> Self {
        Self {
            alpha: vec![Vector3::zeros(); n_nodes],
            x: vec![Matrix3::zeros(); n_nodes],
        }
    }

    /// `E(V e_i, g)` for i = 1..3: the uniform translation field `f = e_i`, `F = 0`.
    pub fn contract_translation(&self) -> Vector3<f64> {
        self.alpha.iter().sum()
    }

    /// `E(e_i × p, g)` for i = 1..3, the field of a unit angular velocity acting on the points
    /// `p_a + ρ` with gradient `e_i^× L_a` (`L_a = 1` for the rigid positions, `L_a = θ_a^×`
    /// for a deformation `u_a + θ_a × ρ`): `(e_i × p_a)·α_a + tr(e_i^× L_a X_a)`
    /// `= e_i · [p_a × α_a + τ(L_a X_a)]`.
    pub fn contract_rotation(
        &self,
        p: impl Fn(usize) -> (Vector3<f64>, Option<Matrix3<f64>>),
    ) -> Vector3<f64> {
        let mut out = Vector3::zeros();
        for (a, (alpha, x)) in self.alpha.iter().zip(&self.x).enumerate() {
            let (pa, la) = p(a);
            out += pa.cross(alpha);
            out += match la {
                Some(l) => tau(&(l * x)),
                None => tau(x),
            };
        }
        out
    }
}
