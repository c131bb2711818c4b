//! Panel <-> FE-node interpolation: the infinite-plate surface spline.
//!
//! # The spline (Harder & Desmarais, "Interpolation using surface splines", J. Aircraft 9(2),
//! 1972, 189-191; the `SPLINE1` of MSC Nastran's aeroelastic module)
//!
//! The normal displacement `z` of the fin plane is interpolated from its values `z_k` at the
//! fin's FE nodes `(x_k, y_k)` (fin coordinates of [`super`]) as the deflection of an infinite
//! thin plate loaded by point forces `P_k` at the nodes, plus a rigid plane:
//!
//! `z(x, y) = a_0 + a_1 x + a_2 y + Σ_k P_k K(r_k)`, `K(r) = r² ln r²`, `r_k = |(x, y) - (x_k, y_k)|`.
//!
//! Derivation: the plate equation `D ∇⁴ z = Σ P_k δ(r - r_k)` has the fundamental solution
//! `r² ln r / (8 π D)`; `r² ln r² = 2 r² ln r`, the constant `1/(16 π D)` is absorbed in `P_k`.
//! The plate must be in equilibrium under its point loads (no net force or moment, else the
//! deflection would grow like `r² ln r` at infinity with no balancing support):
//!
//! `Σ P_k = 0`, `Σ P_k x_k = 0`, `Σ P_k y_k = 0`,
//!
//! and it passes through the nodal values, `z(x_k, y_k) = z_k`. With `R_kl = K(r_kl)`
//! (`K(0) = 0`) and `C = [1 x_k y_k]` (`N x 3`) this is the symmetric system
//!
//! `[[R, C], [Cᵀ, 0]] [P; a] = [z; 0]`,
//!
//! regular whenever the nodes are not collinear (Harder & Desmarais). At a point `p` the value
//! is `[k(p)ᵀ, 1, x_p, y_p] S⁻¹ [z; 0]`, so the interpolation matrix `G` (points x nodes) is the
//! first `N` columns of `B S⁻¹`, `B` the rows `[k(p)ᵀ, 1, x_p, y_p]`. The chordwise slope uses
//! the derivative of the same function, `∂K/∂x = 2 (x - x_k)(1 + ln r²)` (0 at `r = 0`) and
//! `∂/∂x (a_0 + a_1 x + a_2 y) = a_1`. The spline reproduces any plane exactly (rigid motions
//! of the fin: plunge, pitch, roll about the root) and is smooth (`C¹`, with a continuous
//! slope), which is why the slopes at the panel points come from it rather than from the
//! shell's own shape functions.
//!
//! # Consistent forces
//!
//! With `z_p = Σ_k G_pk z_k` the virtual work of panel forces `F_p` is
//! `Σ_p F_p δz_p = Σ_k (Σ_p G_pk F_p) δz_k`: the nodal forces are `f = Gᵀ F` (the same matrix
//! transposed; they have the same total and the same first moments as `F`, because `G`
//! reproduces `1`, `x` and `y`: `Σ_k G_pk = 1`, `Σ_k G_pk x_k = x_p`, `Σ_k G_pk y_k = y_p`).
//!
//! Coincident nodes (an imported mesh with duplicate grid points, or a node and the virtual
//! root node over it) would make `S` singular: nodes closer than 1e-9 of the fin's root chord
//! are merged into one spline point and share its column equally.

use faer::Mat;
use faer::linalg::solvers::DenseSolveCore;

/// Errors of the spline.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SplineError {
    #[error("surface spline needs at least three non-collinear nodes (got {0} distinct)")]
    TooFewNodes(usize),
    #[error("surface spline system is singular (nodes collinear?)")]
    Singular,
    #[error("node or point coordinate is not finite")]
    NotFinite,
}

fn kernel(d2: f64) -> f64 {
    if d2 > 0.0 { d2 * d2.ln() } else { 0.0 }
}

/// Interpolation matrices of a surface spline through `nodes` (fin coordinates, m), at
/// `points`: `(G, G_x)`, both row-major `points.len() x nodes.len()`, values and chordwise
/// slopes (`z_p = Σ_k G[p][k] z_k`, `(∂z/∂x)_p = Σ_k G_x[p][k] z_k`). `scale` (m, e.g. the
/// root chord) normalises the coordinates for conditioning.
pub fn surface_spline(
    nodes: &[[f64; 2]],
    points: &[[f64; 2]],
    scale: f64,
) -> Result<(Vec<f64>, Vec<f64>), SplineError> {
    if nodes
        .iter()
        .chain(points)
        .any(|p| !(p[0].is_finite() && p[1].is_finite()))
        || !(scale.is_finite() && scale > 0.0)
    {
        return Err(SplineError::NotFinite);
    }
    // Merge coincident nodes: `owner[k]` = spline point of node k.
    let tol = 1e-9 * scale;
    let mut unique: Vec<[f64; 2]> = Vec::new();
    let mut owner = Vec::with_capacity(nodes.len());
    for nd in nodes {
        let found = unique
            .iter()
            .position(|u| (u[0] - nd[0]).hypot(u[1] - nd[1]) <= tol);
        owner.push(match found {
            Some(i) => i,
            None => {
                unique.push(*nd);
                unique.len() - 1
            }
        });
    }
    let m = unique.len();
    if m < 3 {
        return Err(SplineError::TooFewNodes(m));
    }
    let u: Vec<[f64; 2]> = unique
        .iter()
        .map(|p| [p[0] / scale, p[1] / scale])
        .collect();
    let dim = m + 3;
    let s = Mat::<f64>::from_fn(dim, dim, |i, j| match (i < m, j < m) {
        (true, true) => {
            let (dx, dy) = (u[i][0] - u[j][0], u[i][1] - u[j][1]);
            kernel(dx * dx + dy * dy)
        }
        (true, false) => [1.0, u[i][0], u[i][1]][j - m],
        (false, true) => [1.0, u[j][0], u[j][1]][i - m],
        (false, false) => 0.0,
    });
    let inv = s.partial_piv_lu().inverse();
    if (0..dim).any(|i| (0..dim).any(|j| !inv[(i, j)].is_finite())) {
        return Err(SplineError::Singular);
    }
    // Collinear nodes leave S singular in exact arithmetic; LU then returns huge entries.
    // Check the interpolation property on the nodes themselves.
    let np = points.len();
    let nn = nodes.len();
    let mut g = vec![0.0; np * nn];
    let mut gx = vec![0.0; np * nn];
    let mut row = vec![0.0; dim];
    let mut row_x = vec![0.0; dim];
    let share: Vec<f64> = (0..m)
        .map(|i| 1.0 / owner.iter().filter(|&&o| o == i).count() as f64)
        .collect();
    for (p, pt) in points.iter().enumerate() {
        let (x, y) = (pt[0] / scale, pt[1] / scale);
        for (i, ui) in u.iter().enumerate() {
            let (dx, dy) = (x - ui[0], y - ui[1]);
            let d2 = dx * dx + dy * dy;
            row[i] = kernel(d2);
            row_x[i] = if d2 > 0.0 {
                2.0 * dx * (1.0 + d2.ln())
            } else {
                0.0
            };
        }
        row[m..].copy_from_slice(&[1.0, x, y]);
        row_x[m..].copy_from_slice(&[0.0, 1.0, 0.0]);
        for i in 0..m {
            let (mut a, mut b) = (0.0, 0.0);
            for j in 0..dim {
                a += row[j] * inv[(j, i)];
                b += row_x[j] * inv[(j, i)];
            }
            // Slope in physical units: d/dx = (1/scale) d/d(x/scale).
            for (k, &o) in owner.iter().enumerate() {
                if o == i {
                    g[p * nn + k] = a * share[i];
                    gx[p * nn + k] = b * share[i] / scale;
                }
            }
        }
    }
    // Plane reproduction is the spline's defining property; its failure means S was singular.
    for p in 0..np {
        let sum: f64 = g[p * nn..(p + 1) * nn].iter().sum();
        if !sum.is_finite() || (sum - 1.0).abs() > 1e-6 {
            return Err(SplineError::Singular);
        }
    }
    Ok((g, gx))
}
