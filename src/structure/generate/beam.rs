//! 3-D two-node beam element (12 DOF) of the body tube, Euler-Bernoulli or Timoshenko.
//!
//! The body line is the body x axis, so the element frame is the body frame: DOF order per
//! node u, v, w, theta_x, theta_y, theta_z (fe_model.rs). Bending in the x-y plane uses
//! (v, theta_z) with theta_z = dv/dx; bending in the x-z plane uses (w, -theta_y) with
//! theta_y = -dw/dx; both use the same planar matrices.
//!
//! Shape functions: the "interdependent interpolation" of the Timoshenko beam (cubic v,
//! quadratic theta, exact homogeneous solutions for a uniform section; Friedman & Kosmatka,
//! Computers & Structures 47 (1993) 473-481; Reddy, Comput. Methods Appl. Mech. Engrg. 149
//! (1997) 113-132). With phi = 12 EI / (k G A l^2) they read, xi = s/l in [0, 1]:
//!
//! N_v = [1 - 3xi^2 + 2xi^3 + phi(1 - xi),  l(xi - 2xi^2 + xi^3 + phi/2 (xi - xi^2)),
//!        3xi^2 - 2xi^3 + phi xi,           l(-xi^2 + xi^3 - phi/2 (xi - xi^2))] / (1 + phi)
//! N_t = [6(xi^2 - xi)/l,  1 - 4xi + 3xi^2 + phi(1 - xi),  -6(xi^2 - xi)/l,  -2xi + 3xi^2 + phi xi]
//!       / (1 + phi)
//!
//! phi = 0 gives the Hermite cubics of Euler-Bernoulli theory (then N_t = N_v'). Both sets
//! reproduce rigid translation (v = 1, theta = 0) and rigid rotation (v = x, theta = 1)
//! exactly, for any phi.
//!
//! Element matrices are the energy integrals, evaluated with 5-point Gauss quadrature
//! (exact to degree 9):
//!   K = int EI N_t'^T N_t' + kGA (N_v' - N_t)^T (N_v' - N_t) dx   (shear term only for
//!       Timoshenko), axial int EA N'^T N', torsion int GJ N'^T N' (linear N);
//!   M = int (rho A + mu) N_v^T N_v + rho I N_t^T N_t dx (translation + rotary inertia),
//!       axial int (rho A + mu) N^T N, torsion int rho J_p N^T N with J_p = 2 I.
//! The section varies along the nose cone; the integrands of M are then polynomials of
//! degree <= 8 (A quadratic on the solid tip, linear on the hollow cone; I of degree 4), so
//! the quadrature is exact and the rigid-body projection of M equals the continuum's mass,
//! first moment and inertia tensor exactly (this is what `mass_properties` checks). The
//! thesis (2.5.9)-(2.5.12) takes the rigid-body inertia from these nodal blocks.
//! On a curved nose (ogive, elliptical, parabolic, power, Haack: `check::nose`) A(s) and I(s)
//! are no polynomials; each element there is integrated with `NoseShape::rule` (composite
//! Gauss after the substitution that makes the profile smooth at the tip and the base), so
//! the rigid-body projection equals the profile's integrals to rounding-level accuracy
//! rather than exactly (`tests/generator.rs` measures it).
//! A transition (`check::transition`) is a frustum or a shaped shell of revolution: on the
//! frustum the integrands are polynomials of the same degrees as on the hollow cone (exact);
//! on a shaped one each element is integrated with the transition's substituted rule, as on a
//! curved nose.
//! For Timoshenko elements phi uses the element means of EI and kGA (exact for uniform
//! elements, which is every element outside the nose).
//!
//! Shear coefficient: Cowper, "The shear coefficient in Timoshenko's beam theory", J. Appl.
//! Mech. 33 (1966) 335-340, hollow circle with m = r_i / r_o:
//! k = 6(1+nu)(1+m^2)^2 / ((7+6nu)(1+m^2)^2 + (20+12nu) m^2), which tends to
//! 2(1+nu)/(4+3nu) ~ 0.53 for a thin tube and to 6(1+nu)/(7+6nu) for a solid circle.

use nalgebra::{SMatrix, SVector};

use super::spec::{BeamTheory, BodySpec, MaterialProps};

/// 12 x 12 element matrix.
pub type Mat12 = SMatrix<f64, 12, 12>;

/// Gauss-Legendre points and weights on [0, 1], 5 points.
#[allow(clippy::excessive_precision)]
pub(crate) const GAUSS5: [(f64, f64); 5] = [
    (0.046_910_077_030_668_0, 0.118_463_442_528_094_55),
    (0.230_765_344_947_158_45, 0.239_314_335_249_683_25),
    (0.5, 0.284_444_444_444_444_44),
    (0.769_234_655_052_841_55, 0.239_314_335_249_683_25),
    (0.953_089_922_969_332_0, 0.118_463_442_528_094_55),
];

/// Panels of [`crate::check::ir::NoseShape::rule`] per beam element of a curved nose (20
/// points per element, 40 where it crosses the nose's mid-length).
pub const NOSE_PANELS: usize = 4;

/// Tube cross-section at one station.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TubeSection {
    pub outer_radius: f64,
    pub inner_radius: f64,
}

impl TubeSection {
    /// Area A = pi (r_o^2 - r_i^2).
    pub fn area(&self) -> f64 {
        std::f64::consts::PI * (self.outer_radius.powi(2) - self.inner_radius.powi(2))
    }
    /// Second moment I_y = I_z = pi/4 (r_o^4 - r_i^4).
    pub fn second_moment(&self) -> f64 {
        0.25 * std::f64::consts::PI * (self.outer_radius.powi(4) - self.inner_radius.powi(4))
    }
    /// Cowper's shear coefficient of a hollow circle (module doc).
    pub fn shear_coefficient(&self, nu: f64) -> f64 {
        if self.outer_radius <= 0.0 {
            return 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu);
        }
        let m2 = (self.inner_radius / self.outer_radius).powi(2);
        let q = (1.0 + m2).powi(2);
        6.0 * (1.0 + nu) * q / ((7.0 + 6.0 * nu) * q + (20.0 + 12.0 * nu) * m2)
    }
}

/// Section of the body at station x (x <= 0): the nose profile r_o(s) on the nose (s = -x;
/// the cone r_o = R s / l_n, or `check::nose`'s profile), inner radius max(r_o - t, 0) (same
/// wall, solid where r_o < t); the tube beyond.
pub fn section_at(body: &BodySpec, x: f64) -> TubeSection {
    let r = 0.5 * body.outer_diameter;
    let s = -x;
    let outer = if body.nose_length > 0.0 && s < body.nose_length {
        if body.nose_shape.is_conical() {
            r * s.max(0.0) / body.nose_length
        } else {
            body.nose_shape.radius(s, r, body.nose_length)
        }
    } else {
        crate::check::transition::section_radius(r, &body.transitions, s)
    };
    TubeSection {
        outer_radius: outer,
        inner_radius: (outer - body.wall_thickness).max(0.0),
    }
}

/// The nose's solid-tip end s_solid (r_o = t, `NoseShape::solid_tip_end`) when it lies
/// strictly inside the element [s_fore, s_aft] (distances aft of the tip), where the section's
/// formula changes from the solid circle to the tube.
fn solid_tip_split(body: &BodySpec, s_fore: f64, s_aft: f64) -> Option<f64> {
    if body.nose_length <= 0.0 || s_fore >= body.nose_length {
        return None;
    }
    let s = body.nose_shape.solid_tip_end(
        body.wall_thickness,
        0.5 * body.outer_diameter,
        body.nose_length,
    );
    let tol = 1e-12 * (s_aft - s_fore);
    (s > s_fore + tol && s < s_aft - tol).then_some(s)
}

/// Planar shape functions (N_v, N_t) and their x-derivatives at xi for length l, shear
/// parameter phi (module doc).
fn planar_shapes(xi: f64, l: f64, phi: f64) -> [[f64; 4]; 4] {
    let d = 1.0 + phi;
    let (x2, x3) = (xi * xi, xi * xi * xi);
    let nv = [
        (1.0 - 3.0 * x2 + 2.0 * x3 + phi * (1.0 - xi)) / d,
        l * (xi - 2.0 * x2 + x3 + 0.5 * phi * (xi - x2)) / d,
        (3.0 * x2 - 2.0 * x3 + phi * xi) / d,
        l * (-x2 + x3 - 0.5 * phi * (xi - x2)) / d,
    ];
    // d/dx = (1/l) d/dxi
    let dnv = [
        (-6.0 * xi + 6.0 * x2 - phi) / (d * l),
        (1.0 - 4.0 * xi + 3.0 * x2 + 0.5 * phi * (1.0 - 2.0 * xi)) / d,
        (6.0 * xi - 6.0 * x2 + phi) / (d * l),
        (-2.0 * xi + 3.0 * x2 - 0.5 * phi * (1.0 - 2.0 * xi)) / d,
    ];
    let nt = [
        6.0 * (x2 - xi) / (l * d),
        (1.0 - 4.0 * xi + 3.0 * x2 + phi * (1.0 - xi)) / d,
        -6.0 * (x2 - xi) / (l * d),
        (-2.0 * xi + 3.0 * x2 + phi * xi) / d,
    ];
    let dnt = [
        6.0 * (2.0 * xi - 1.0) / (l * l * d),
        (-4.0 + 6.0 * xi - phi) / (l * d),
        -6.0 * (2.0 * xi - 1.0) / (l * l * d),
        (-2.0 + 6.0 * xi + phi) / (l * d),
    ];
    [nv, dnv, nt, dnt]
}

/// Element stiffness and mass of the body segment [x_aft, x_fore] (x_aft < x_fore <= 0),
/// with non-structural line mass `line_mass` (kg/m, translation only) over the element.
/// Node 0 of the element is the aft node (x_aft), node 1 the fore node.
pub fn beam_element(body: &BodySpec, x_aft: f64, x_fore: f64, line_mass: f64) -> (Mat12, Mat12) {
    let l = x_fore - x_aft;
    let MaterialProps {
        youngs_modulus: e,
        poisson: nu,
        density: rho,
    } = body.material;
    let g = body.material.shear_modulus();

    // The quadrature rule on [0, 1]: 5-point Gauss, exact for the cone and the tube (module
    // doc); on an element of a curved nose, `NoseShape::rule`'s substituted composite Gauss
    // on the element (its integrands are not polynomials there).
    let curved = body.nose_length > 0.0
        && !body.nose_shape.is_conical()
        && x_aft >= -body.nose_length * (1.0 + 1e-12);
    // A shaped transition's element likewise (the mesh puts nodes at its ends, so an element
    // lies on one transition or none); a frustum's integrands are polynomials (A linear and
    // I quartic in x, as on the hollow cone), for which 5-point Gauss is exact.
    let shaped = body.transitions.iter().find(|t| {
        !t.shape.is_conical()
            && -x_fore >= t.start * (1.0 - 1e-12)
            && -x_aft <= t.end() * (1.0 + 1e-12)
    });
    // An element across the nose's solid-tip end s_solid (where r_o = t; the mesh leaves no
    // node there when it lies within 0.3 of a division of the tip: `mesh::body_stations`)
    // is integrated as its two parts, on each of which the section is one formula (solid,
    // or hollow), so the rule keeps its exactness (cone) or its rounding-level accuracy
    // (curved nose).
    let split = solid_tip_split(body, -x_fore, -x_aft);
    let rule: Vec<(f64, f64)> = if curved {
        let ln = body.nose_length;
        let (s_fore, s_aft) = (-x_fore, -x_aft);
        let parts = match split {
            Some(s) => vec![(s_fore, s), (s, s_aft)],
            None => vec![(s_fore, s_aft)],
        };
        parts
            .into_iter()
            .flat_map(|(a, b)| crate::check::ir::NoseShape::rule(ln, a, b, NOSE_PANELS))
            .map(|(s, w)| ((-s - x_aft) / l, w / l))
            .collect()
    } else if let Some(s) = split {
        // The cone: 5-point Gauss on each part (exact on each, module doc).
        let xi_s = (-s - x_aft) / l; // the split in the element's xi (0 aft, 1 fore)
        [(0.0, xi_s), (xi_s, 1.0)]
            .into_iter()
            .flat_map(|(a, b)| {
                GAUSS5
                    .iter()
                    .map(move |&(x, w)| (a + (b - a) * x, (b - a) * w))
            })
            .collect()
    } else if let Some(t) = shaped {
        t.rule((-x_fore).max(t.start), (-x_aft).min(t.end()), NOSE_PANELS)
            .into_iter()
            .map(|(s, w)| ((-s - x_aft) / l, w / l))
            .collect()
    } else {
        GAUSS5.to_vec()
    };
    // Element means for the Timoshenko shear parameter.
    let (mut ei_mean, mut kga_mean) = (0.0, 0.0);
    for &(xi, wq) in &rule {
        let sec = section_at(body, x_aft + xi * l);
        ei_mean += wq * e * sec.second_moment();
        kga_mean += wq * sec.shear_coefficient(nu) * g * sec.area();
    }
    let phi = match body.theory {
        BeamTheory::EulerBernoulli => 0.0,
        BeamTheory::Timoshenko => 12.0 * ei_mean / (kga_mean * l * l),
    };

    let mut kb = SMatrix::<f64, 4, 4>::zeros(); // planar bending stiffness
    let mut mb = SMatrix::<f64, 4, 4>::zeros(); // planar bending mass
    let (mut ea, mut gj, mut mu_ax, mut rho_jp) = ([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
    for &(xi, wq) in &rule {
        let sec = section_at(body, x_aft + xi * l);
        let (a, i) = (sec.area(), sec.second_moment());
        let w = wq * l;
        let [nv, dnv, nt, dnt] = planar_shapes(xi, l, phi);
        let (nv, dnv, nt, dnt) = (
            SVector::<f64, 4>::from(nv),
            SVector::<f64, 4>::from(dnv),
            SVector::<f64, 4>::from(nt),
            SVector::<f64, 4>::from(dnt),
        );
        kb += w * e * i * dnt * dnt.transpose();
        if body.theory == BeamTheory::Timoshenko {
            let gam = dnv - nt;
            kb += w * sec.shear_coefficient(nu) * g * a * gam * gam.transpose();
        }
        mb += w * ((rho * a + line_mass) * nv * nv.transpose() + rho * i * nt * nt.transpose());
        // Linear shape functions for axial and torsion: N = (1 - xi, xi).
        let n = [1.0 - xi, xi];
        let lin = [n[0] * n[0], n[0] * n[1], n[1] * n[1]];
        for k in 0..3 {
            mu_ax[k] += w * (rho * a + line_mass) * lin[k];
            rho_jp[k] += w * rho * 2.0 * i * lin[k];
        }
        let dd = w / (l * l); // N' N'^T = [[1, -1], [-1, 1]] / l^2
        ea[0] += dd * e * a;
        gj[0] += dd * g * 2.0 * i;
    }
    ea = [ea[0], -ea[0], ea[0]];
    gj = [gj[0], -gj[0], gj[0]];

    let mut k = Mat12::zeros();
    let mut m = Mat12::zeros();
    // Axial (u: 0, 6) and torsion (theta_x: 3, 9), 2 x 2 from [a11, a12, a22].
    for (idx, kv, mv) in [(0usize, ea, mu_ax), (3usize, gj, rho_jp)] {
        let d = [idx, idx + 6];
        let pick = |v: [f64; 3], r: usize, c: usize| if r == c { v[2 * r] } else { v[1] };
        for r in 0..2 {
            for c in 0..2 {
                k[(d[r], d[c])] += pick(kv, r, c);
                m[(d[r], d[c])] += pick(mv, r, c);
            }
        }
    }
    // Bending x-y: (v, theta_z) = (1, 5, 7, 11), signs +; x-z: (w, -theta_y) = (2, 4, 8, 10).
    for (d, s) in [
        ([1usize, 5, 7, 11], [1.0, 1.0, 1.0, 1.0]),
        ([2usize, 4, 8, 10], [1.0, -1.0, 1.0, -1.0]),
    ] {
        for r in 0..4 {
            for c in 0..4 {
                k[(d[r], d[c])] += s[r] * s[c] * kb[(r, c)];
                m[(d[r], d[c])] += s[r] * s[c] * mb[(r, c)];
            }
        }
    }
    (k, m)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tube(theory: BeamTheory) -> BodySpec {
        BodySpec {
            length: 2.0,
            outer_diameter: 0.127,
            wall_thickness: 0.003,
            nose_length: 0.0,
            nose_shape: crate::check::ir::NoseShape::Conical,
            transitions: Vec::new(),
            elements: 10,
            theory,
            material: MaterialProps {
                youngs_modulus: 70e9,
                poisson: 0.346,
                density: 2710.0,
            },
        }
    }

    /// A uniform element reproduces the closed-form Timoshenko stiffness
    /// EI/((1+phi) l^3) [[12, 6l, -12, 6l], [6l, (4+phi)l^2, -6l, (2-phi)l^2], ...]
    /// (Przemieniecki, Theory of Matrix Structural Analysis, 1968, sec. 5.6).
    #[test]
    fn uniform_timoshenko_matches_closed_form() {
        for theory in [BeamTheory::EulerBernoulli, BeamTheory::Timoshenko] {
            let b = tube(theory);
            let (x0, x1) = (-0.3, -0.25);
            let l = x1 - x0;
            let (k, _) = beam_element(&b, x0, x1, 0.0);
            let sec = section_at(&b, -1.0);
            let ei = 70e9 * sec.second_moment();
            let phi = match theory {
                BeamTheory::EulerBernoulli => 0.0,
                BeamTheory::Timoshenko => {
                    12.0 * ei
                        / (sec.shear_coefficient(0.346)
                            * b.material.shear_modulus()
                            * sec.area()
                            * l
                            * l)
                }
            };
            let c = ei / ((1.0 + phi) * l * l * l);
            let expect = [
                [12.0, 6.0 * l, -12.0, 6.0 * l],
                [6.0 * l, (4.0 + phi) * l * l, -6.0 * l, (2.0 - phi) * l * l],
                [-12.0, -6.0 * l, 12.0, -6.0 * l],
                [6.0 * l, (2.0 - phi) * l * l, -6.0 * l, (4.0 + phi) * l * l],
            ];
            let d = [1, 5, 7, 11];
            for r in 0..4 {
                for q in 0..4 {
                    let want = c * expect[r][q];
                    let got = k[(d[r], d[q])];
                    assert!(
                        (got - want).abs() <= 1e-9 * c * 12.0,
                        "{theory:?} ({r},{q}): {got} vs {want}"
                    );
                }
            }
        }
    }

    /// Euler-Bernoulli consistent translational mass of a uniform element without rotary
    /// inertia is rho A l / 420 [[156, 22l, 54, -13l], ...] (Przemieniecki 11.3); the rotary
    /// part adds rho I / (30 l) [[36, 3l, -36, 3l], ...].
    #[test]
    fn uniform_euler_bernoulli_mass_matches_closed_form() {
        let b = tube(BeamTheory::EulerBernoulli);
        let (x0, x1) = (-1.0, -0.8);
        let l = x1 - x0;
        let (_, m) = beam_element(&b, x0, x1, 0.0);
        let sec = section_at(&b, -1.0);
        let (ra, ri) = (2710.0 * sec.area(), 2710.0 * sec.second_moment());
        let t = [
            [156.0, 22.0 * l, 54.0, -13.0 * l],
            [22.0 * l, 4.0 * l * l, 13.0 * l, -3.0 * l * l],
            [54.0, 13.0 * l, 156.0, -22.0 * l],
            [-13.0 * l, -3.0 * l * l, -22.0 * l, 4.0 * l * l],
        ];
        let r = [
            [36.0, 3.0 * l, -36.0, 3.0 * l],
            [3.0 * l, 4.0 * l * l, -3.0 * l, -l * l],
            [-36.0, -3.0 * l, 36.0, -3.0 * l],
            [3.0 * l, -l * l, -3.0 * l, 4.0 * l * l],
        ];
        let d = [1, 5, 7, 11];
        for p in 0..4 {
            for q in 0..4 {
                let want = ra * l / 420.0 * t[p][q] + ri / (30.0 * l) * r[p][q];
                let got = m[(d[p], d[q])];
                assert!(
                    (got - want).abs() <= 1e-12 * ra * l,
                    "({p},{q}): {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn cowper_limits() {
        let thin = TubeSection {
            outer_radius: 1.0,
            inner_radius: 0.999_999,
        };
        let nu = 0.3;
        assert!((thin.shear_coefficient(nu) - 2.0 * 1.3 / (4.0 + 0.9)).abs() < 1e-5);
        let solid = TubeSection {
            outer_radius: 1.0,
            inner_radius: 0.0,
        };
        assert!((solid.shear_coefficient(nu) - 6.0 * 1.3 / (7.0 + 1.8)).abs() < 1e-12);
    }
}
