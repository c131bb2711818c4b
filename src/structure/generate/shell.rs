//! Flat four-node shell element of the fins: Q4 membrane + MITC4 plate bending + a small
//! Hughes-Brezzi drilling stiffness; consistent mass with thickness rotary inertia.
//!
//! Local frame: a, b in the plane, n = a x b the normal. Local DOF order per node
//! u_a, u_b, w, theta_a, theta_b, theta_n (rotation vector components, right-handed).
//! Mindlin kinematics: at height z the in-plane displacement is z (theta_b, -theta_a), so
//!   curvatures  k_aa = d theta_b/da, k_bb = -d theta_a/db, k_ab = d theta_b/db - d theta_a/da,
//!   shear       g_a = dw/da + theta_b, g_b = dw/db - theta_a.
//! Energies: bending 1/2 int k^T D_b k, D_b = E t^3/(12(1-nu^2)) [[1,nu,0],[nu,1,0],
//! [0,0,(1-nu)/2]]; shear 1/2 int k_s G t (g_a^2 + g_b^2), k_s = 5/6; membrane
//! 1/2 int e^T D_m e with D_m = E t/(1-nu^2) [...] (plane stress), 2 x 2 Gauss.
//!
//! MITC4 (Bathe & Dvorkin, Int. J. Numer. Meth. Engng 21 (1985) 367-383): the covariant
//! shear strains g_xi = a_xi g_a + b_xi g_b and g_eta = a_eta g_a + b_eta g_b are sampled
//! at the edge mid-points A (0, 1), C (0, -1) (g_xi) and B (1, 0), D (-1, 0) (g_eta) and
//! interpolated linearly, g_xi = (1+eta)/2 g_xi^A + (1-eta)/2 g_xi^C, etc.; then
//! (g_a, g_b) = J^-1 (g_xi, g_eta) at each Gauss point. This removes shear locking for the
//! thin fins (t/h ~ 0.1-0.3).
//!
//! Drilling (Hughes & Brezzi, Comput. Methods Appl. Mech. Engrg. 72 (1989) 105-121):
//! penalty 1/2 int gamma t (theta_n - omega)^2 with omega = (du_b/da - du_a/db)/2, 2 x 2
//! Gauss, gamma = G / 100 (`DRILLING_FACTOR`). A rigid rotation has theta_n = omega, so the
//! penalty does not disturb the rigid-body modes; it only removes the otherwise singular
//! drilling DOF. Flat fins: it couples to nothing but the in-plane field.
//!
//! Mass (consistent, 2 x 2 Gauss, exact because det J is linear on a straight-sided quad):
//! int N^T diag(rho t, rho t, rho t, rho t^3/12, rho t^3/12, 0) N dA. The rotary terms are
//! the plate's own inertia through its thickness (int rho z^2 dz = rho t^3/12 about the
//! in-plane axes); the drilling DOF has no mass (the rotation about n is carried by the
//! translations), so M is singular on theta_n: modal solvers must not factor M alone.

use nalgebra::{Matrix2, SMatrix, SVector};

use super::spec::MaterialProps;

/// 24 x 24 element matrix.
pub type Mat24 = SMatrix<f64, 24, 24>;
type Row24 = SVector<f64, 24>;

/// Drilling penalty gamma / G (module doc).
pub const DRILLING_FACTOR: f64 = 1e-2;
/// Mindlin shear correction factor.
const PLATE_SHEAR_FACTOR: f64 = 5.0 / 6.0;

const NODE_XI: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];

/// Bilinear shape functions and their natural derivatives at (xi, eta).
fn q4(xi: f64, eta: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let mut n = [0.0; 4];
    let mut dxi = [0.0; 4];
    let mut deta = [0.0; 4];
    for (i, &(xa, ea)) in NODE_XI.iter().enumerate() {
        n[i] = 0.25 * (1.0 + xa * xi) * (1.0 + ea * eta);
        dxi[i] = 0.25 * xa * (1.0 + ea * eta);
        deta[i] = 0.25 * ea * (1.0 + xa * xi);
    }
    (n, dxi, deta)
}

/// Jacobian [[a_xi, b_xi], [a_eta, b_eta]] at (xi, eta).
fn jacobian(ab: &[[f64; 2]; 4], dxi: &[f64; 4], deta: &[f64; 4]) -> Matrix2<f64> {
    let mut j = Matrix2::zeros();
    for i in 0..4 {
        j[(0, 0)] += dxi[i] * ab[i][0];
        j[(0, 1)] += dxi[i] * ab[i][1];
        j[(1, 0)] += deta[i] * ab[i][0];
        j[(1, 1)] += deta[i] * ab[i][1];
    }
    j
}

/// Covariant transverse shear (g_xi, g_eta) as rows over the 24 element DOFs at (xi, eta).
fn covariant_shear(ab: &[[f64; 2]; 4], xi: f64, eta: f64) -> (Row24, Row24) {
    let (n, dxi, deta) = q4(xi, eta);
    let j = jacobian(ab, &dxi, &deta);
    let (mut gx, mut ge) = (Row24::zeros(), Row24::zeros());
    for i in 0..4 {
        // g_xi = dw/dxi + theta_b a_xi - theta_a b_xi
        gx[6 * i + 2] += dxi[i];
        gx[6 * i + 4] += n[i] * j[(0, 0)];
        gx[6 * i + 3] -= n[i] * j[(0, 1)];
        ge[6 * i + 2] += deta[i];
        ge[6 * i + 4] += n[i] * j[(1, 0)];
        ge[6 * i + 3] -= n[i] * j[(1, 1)];
    }
    (gx, ge)
}

/// Area of the quad (for checks and the drilling scale).
#[cfg(test)]
pub fn quad_area(ab: &[[f64; 2]; 4]) -> f64 {
    let mut s = 0.0;
    for i in 0..4 {
        let (p, q) = (ab[i], ab[(i + 1) % 4]);
        s += p[0] * q[1] - q[0] * p[1];
    }
    0.5 * s
}

/// Stiffness and mass of one flat quad in its local frame. `ab` are the local in-plane
/// coordinates of the four corners, counter-clockwise about n.
pub fn shell_element(ab: &[[f64; 2]; 4], t: f64, mat: &MaterialProps) -> (Mat24, Mat24) {
    let (e, nu, rho) = (mat.youngs_modulus, mat.poisson, mat.density);
    let g = mat.shear_modulus();
    let dm = e * t / (1.0 - nu * nu);
    let db = e * t.powi(3) / (12.0 * (1.0 - nu * nu));
    let ks = PLATE_SHEAR_FACTOR * g * t;
    let gamma = DRILLING_FACTOR * g * t;
    let elastic = |c: f64| {
        SMatrix::<f64, 3, 3>::new(
            c,
            nu * c,
            0.0,
            nu * c,
            c,
            0.0,
            0.0,
            0.0,
            0.5 * (1.0 - nu) * c,
        )
    };
    let (d_m, d_b) = (elastic(dm), elastic(db));
    let inertia = [
        rho * t,
        rho * t,
        rho * t,
        rho * t.powi(3) / 12.0,
        rho * t.powi(3) / 12.0,
        0.0,
    ];
    shell_element_with(ab, &d_m, &d_b, ks, gamma, &inertia)
}

/// Plane-stress stiffness `Q̄` (3 x 3, Voigt order `(aa, bb, ab)` with the engineering shear
/// strain, as the element's membrane strain and curvature vectors) of an orthotropic
/// lamina whose principal direction 1 makes the angle `theta` (rad, counter-clockwise about
/// n) with the local `a` axis.
///
/// Principal axes (Jones, *Mechanics of Composite Materials*, 2nd ed., 1999, eq. (2.61)):
/// `Q11 = E1/(1 - ν12 ν21)`, `Q22 = E2/(1 - ν12 ν21)`, `Q12 = ν12 E2/(1 - ν12 ν21)`,
/// `Q66 = G12`, `ν21 = ν12 E2/E1`. Rotated (Jones eq. (2.84)), `m = cos θ`, `n = sin θ`:
/// `Q̄11 = Q11 m⁴ + 2(Q12 + 2Q66) n²m² + Q22 n⁴`,
/// `Q̄12 = (Q11 + Q22 - 4Q66) n²m² + Q12 (n⁴ + m⁴)`,
/// `Q̄22 = Q11 n⁴ + 2(Q12 + 2Q66) n²m² + Q22 m⁴`,
/// `Q̄16 = (Q11 - Q12 - 2Q66) n m³ + (Q12 - Q22 + 2Q66) n³ m`,
/// `Q̄26 = (Q11 - Q12 - 2Q66) n³ m + (Q12 - Q22 + 2Q66) n m³`,
/// `Q̄66 = (Q11 + Q22 - 2Q12 - 2Q66) n²m² + Q66 (n⁴ + m⁴)`.
/// With `E1 = E2 = E`, `G12 = E/(2(1+ν))` it is the isotropic matrix of [`shell_element`]
/// for every `θ` (tested).
pub fn orthotropic_plane_stress(
    e1: f64,
    e2: f64,
    nu12: f64,
    g12: f64,
    theta: f64,
) -> SMatrix<f64, 3, 3> {
    let nu21 = nu12 * e2 / e1;
    let den = 1.0 - nu12 * nu21;
    let (q11, q22, q12, q66) = (e1 / den, e2 / den, nu12 * e2 / den, g12);
    let (m, n) = (theta.cos(), theta.sin());
    let (m2, n2) = (m * m, n * n);
    let b11 = q11 * m2 * m2 + 2.0 * (q12 + 2.0 * q66) * n2 * m2 + q22 * n2 * n2;
    let b12 = (q11 + q22 - 4.0 * q66) * n2 * m2 + q12 * (n2 * n2 + m2 * m2);
    let b22 = q11 * n2 * n2 + 2.0 * (q12 + 2.0 * q66) * n2 * m2 + q22 * m2 * m2;
    let b16 = (q11 - q12 - 2.0 * q66) * n * m2 * m + (q12 - q22 + 2.0 * q66) * n2 * n * m;
    let b26 = (q11 - q12 - 2.0 * q66) * n2 * n * m + (q12 - q22 + 2.0 * q66) * n * m2 * m;
    let b66 = (q11 + q22 - 2.0 * q12 - 2.0 * q66) * n2 * m2 + q66 * (n2 * n2 + m2 * m2);
    SMatrix::<f64, 3, 3>::new(b11, b12, b16, b12, b22, b26, b16, b26, b66)
}

/// The element of a homogeneous lamina of thickness `t` with plane-stress stiffness `q`
/// ([`orthotropic_plane_stress`]), transverse shear modulus `g_transverse` (the same in both
/// transverse planes; `k_s = 5/6` as in [`shell_element`]) and density `rho`: `D_m = q t`,
/// `D_b = q t³/12`, drilling penalty `DRILLING_FACTOR g_transverse t`, the mass of
/// [`shell_element`].
pub fn shell_element_lamina(
    ab: &[[f64; 2]; 4],
    t: f64,
    q: &SMatrix<f64, 3, 3>,
    g_transverse: f64,
    rho: f64,
) -> (Mat24, Mat24) {
    let ks = PLATE_SHEAR_FACTOR * g_transverse * t;
    let gamma = DRILLING_FACTOR * g_transverse * t;
    let inertia = [
        rho * t,
        rho * t,
        rho * t,
        rho * t.powi(3) / 12.0,
        rho * t.powi(3) / 12.0,
        0.0,
    ];
    shell_element_with(ab, &(q * t), &(q * (t.powi(3) / 12.0)), ks, gamma, &inertia)
}

/// The element from its section constants: membrane `d_m` and bending `d_b` (3 x 3), shear
/// `ks` (= k_s G t), drilling penalty `gamma`, and the mass per unit area of the six local
/// DOFs `inertia` (module doc).
fn shell_element_with(
    ab: &[[f64; 2]; 4],
    d_m: &SMatrix<f64, 3, 3>,
    d_b: &SMatrix<f64, 3, 3>,
    ks: f64,
    gamma: f64,
    inertia: &[f64; 6],
) -> (Mat24, Mat24) {
    // MITC4 tying points.
    let (gx_a, _) = covariant_shear(ab, 0.0, 1.0);
    let (gx_c, _) = covariant_shear(ab, 0.0, -1.0);
    let (_, ge_b) = covariant_shear(ab, 1.0, 0.0);
    let (_, ge_d) = covariant_shear(ab, -1.0, 0.0);

    let gp = 1.0 / 3f64.sqrt();
    let mut k = Mat24::zeros();
    let mut m = Mat24::zeros();
    for &(xi, eta) in &[(-gp, -gp), (gp, -gp), (gp, gp), (-gp, gp)] {
        let (n, dxi, deta) = q4(xi, eta);
        let j = jacobian(ab, &dxi, &deta);
        let det = j.determinant();
        let jinv = match j.try_inverse() {
            Some(ji) => ji,
            None => continue, // degenerate quad: validated away by the mesher
        };
        // Physical derivatives: [d/da; d/db] = J^-1 [d/dxi; d/deta].
        let mut da = [0.0; 4];
        let mut dbv = [0.0; 4];
        for i in 0..4 {
            da[i] = jinv[(0, 0)] * dxi[i] + jinv[(0, 1)] * deta[i];
            dbv[i] = jinv[(1, 0)] * dxi[i] + jinv[(1, 1)] * deta[i];
        }
        let mut bm = SMatrix::<f64, 3, 24>::zeros();
        let mut bb = SMatrix::<f64, 3, 24>::zeros();
        let mut drill = Row24::zeros();
        for i in 0..4 {
            let c = 6 * i;
            bm[(0, c)] = da[i];
            bm[(1, c + 1)] = dbv[i];
            bm[(2, c)] = dbv[i];
            bm[(2, c + 1)] = da[i];
            bb[(0, c + 4)] = da[i];
            bb[(1, c + 3)] = -dbv[i];
            bb[(2, c + 4)] = dbv[i];
            bb[(2, c + 3)] = -da[i];
            drill[c + 5] = n[i];
            drill[c + 1] -= 0.5 * da[i];
            drill[c] += 0.5 * dbv[i];
        }
        // Assumed covariant shear, then Cartesian.
        let gx = 0.5 * (1.0 + eta) * gx_a + 0.5 * (1.0 - eta) * gx_c;
        let ge = 0.5 * (1.0 + xi) * ge_b + 0.5 * (1.0 - xi) * ge_d;
        let ga = jinv[(0, 0)] * gx + jinv[(0, 1)] * ge;
        let gb = jinv[(1, 0)] * gx + jinv[(1, 1)] * ge;

        k += det * (bm.transpose() * d_m * bm + bb.transpose() * d_b * bb);
        k += det * ks * (ga * ga.transpose() + gb * gb.transpose());
        k += det * gamma * drill * drill.transpose();

        for a in 0..4 {
            for b in 0..4 {
                let nn = det * n[a] * n[b];
                for (d, &mu) in inertia.iter().enumerate() {
                    m[(6 * a + d, 6 * b + d)] += nn * mu;
                }
            }
        }
    }
    (k, m)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn alu() -> MaterialProps {
        MaterialProps {
            youngs_modulus: 70e9,
            poisson: 0.3,
            density: 2700.0,
        }
    }

    /// The element is a polynomial in the thickness, `K(t) = t K1 + t^3 K3` and
    /// `M(t) = t M1 + t^3 M3` (membrane, transverse shear and drilling stiffness and the
    /// translational mass go with `t`, bending stiffness and rotary inertia with `t^3`;
    /// module doc), exactly: `K1, K3` (and `M1, M3`) solved from 1.0 and 3.0 mm reproduce
    /// the element at 0.6, 1.6, 2.2 and 4 mm to rounding (achieved 4.2e-16 of the largest
    /// entry at most), for the isotropic and the lamina element. This is what lets a fin
    /// thickness drawn per sample be a parametric family of one mesh (docs/performance.md,
    /// Monte Carlo): a shear or drilling term in another power of `t`, or a thickness
    /// offset of the mid-plane, breaks it.
    #[test]
    fn the_element_is_t_k1_plus_t_cubed_k3() {
        let m = alu();
        let g = m.shear_modulus();
        let ab = [[0.0, 0.0], [0.05, 0.01], [0.045, 0.06], [-0.01, 0.05]];
        let q = orthotropic_plane_stress(60e9, 20e9, 0.25, 5e9, 0.4);
        let elements: [&dyn Fn(f64) -> (Mat24, Mat24); 2] =
            [&|t| shell_element(&ab, t, &m), &|t| {
                shell_element_lamina(&ab, t, &q, g, m.density)
            }];
        for element in elements {
            let (ta, tb) = (1.0e-3, 3.0e-3);
            let ((ka, ma), (kb, mb)) = (element(ta), element(tb));
            let split = |a: &Mat24, b: &Mat24| {
                let c3 = (b / tb - a / ta) / (tb * tb - ta * ta);
                let c1 = a / ta - c3 * (ta * ta);
                (c1, c3)
            };
            let (k1, k3) = split(&ka, &kb);
            let (m1, m3) = split(&ma, &mb);
            for t in [0.6e-3, 1.6e-3, 2.2e-3, 4.0e-3] {
                let (k, mm) = element(t);
                let ek = (k - (k1 * t + k3 * t.powi(3))).abs().max() / k.abs().max();
                let em = (mm - (m1 * t + m3 * t.powi(3))).abs().max() / mm.abs().max();
                assert!(ek < 1e-14 && em < 1e-14, "t {t}: K {ek:e}, M {em:e}");
            }
            // Both parts are there (the law is not t alone nor t^3 alone).
            assert!(k1.abs().max() > 0.0 && k3.abs().max() > 0.0);
            assert!(m1.abs().max() > 0.0 && m3.abs().max() > 0.0);
        }
    }

    /// `Q̄` of an isotropic lamina is the isotropic plane-stress matrix at every angle, and
    /// the lamina element equals [`shell_element`] (to rounding: achieved 1e-16 relative).
    #[test]
    fn isotropic_lamina_is_the_isotropic_element() {
        let m = alu();
        let g = m.shear_modulus();
        let ab = [[0.0, 0.0], [0.05, 0.01], [0.045, 0.06], [-0.01, 0.05]];
        let (k0, m0) = shell_element(&ab, 0.002, &m);
        for theta in [0.0, 0.3, 1.0, 2.5] {
            let q = orthotropic_plane_stress(m.youngs_modulus, m.youngs_modulus, 0.3, g, theta);
            let c = m.youngs_modulus / (1.0 - 0.09);
            let want = SMatrix::<f64, 3, 3>::new(c, 0.3 * c, 0.0, 0.3 * c, c, 0.0, 0.0, 0.0, g);
            assert!((q - want).abs().max() < 1e-12 * c, "theta {theta}: {q}");
            let (k1, m1) = shell_element_lamina(&ab, 0.002, &q, g, m.density);
            assert!((k1 - k0).abs().max() < 1e-12 * k0.abs().max());
            assert!((m1 - m0).abs().max() < 1e-12 * m0.abs().max());
        }
    }

    /// Turning the lamina by 90 degrees swaps the two directions (Q̄11 <-> Q̄22, no
    /// coupling terms), and by 45 degrees it couples shear and extension with Q̄16 = Q̄26
    /// only when E1 = E2 (it is not).
    #[test]
    fn orthotropic_rotation_swaps_directions() {
        let (e1, e2, nu, g) = (3.151e9, 0.4162e9, 0.31, 0.4392e9);
        let q0 = orthotropic_plane_stress(e1, e2, nu, g, 0.0);
        let q90 = orthotropic_plane_stress(e1, e2, nu, g, std::f64::consts::FRAC_PI_2);
        let tol = 1e-9 * q0[(0, 0)];
        assert!((q0[(0, 0)] - q90[(1, 1)]).abs() < tol);
        assert!((q0[(1, 1)] - q90[(0, 0)]).abs() < tol);
        assert!((q0[(0, 1)] - q90[(0, 1)]).abs() < tol);
        assert!(q90[(0, 2)].abs() < tol && q90[(1, 2)].abs() < tol);
        let q45 = orthotropic_plane_stress(e1, e2, nu, g, std::f64::consts::FRAC_PI_4);
        assert!(q45[(0, 2)] > 0.0 && q45[(1, 2)] > 0.0);
        assert!((q45[(0, 0)] - q45[(1, 1)]).abs() < tol);
        assert!((q45 - q45.transpose()).abs().max() < tol);
    }

    /// The six rigid-body motions of a skewed quad produce no strain energy.
    #[test]
    fn rigid_modes_have_zero_energy() {
        let ab = [[0.0, 0.0], [0.05, 0.01], [0.045, 0.06], [-0.01, 0.05]];
        let (k, m) = shell_element(&ab, 0.002, &alu());
        let norm = k.abs().max();
        for mode in 0..6 {
            let mut r = Row24::zeros();
            for i in 0..4 {
                let (a, b) = (ab[i][0], ab[i][1]);
                // u = U + Theta x (a, b, 0)
                let mut u = [0.0; 6];
                match mode {
                    0..=2 => u[mode] = 1.0,
                    3 => {
                        u[2] = b;
                        u[3] = 1.0;
                    }
                    4 => {
                        u[2] = -a;
                        u[4] = 1.0;
                    }
                    _ => {
                        u[0] = -b;
                        u[1] = a;
                        u[5] = 1.0;
                    }
                }
                for d in 0..6 {
                    r[6 * i + d] = u[d];
                }
            }
            let kr = k * r;
            assert!(
                kr.abs().max() < 1e-10 * norm,
                "mode {mode}: {}",
                kr.abs().max()
            );
            if mode < 3 {
                // total mass rho t A
                let mass = (r.transpose() * m * r)[(0, 0)];
                let want = 2700.0 * 0.002 * quad_area(&ab);
                assert!((mass - want).abs() < 1e-12 * want);
            }
        }
    }
}
