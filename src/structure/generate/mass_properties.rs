//! Closed-form mass properties of the generated vehicle, computed from the geometry alone
//! (an independent code path from the element matrices), and the rigid-body projection of
//! an assembled mass matrix to compare with.
//!
//! The rigid-body mass matrix about the origin is
//!   R^T M R = [[m I, -(m c)^x], [(m c)^x, J_O]],  J_O = int rho (|r|^2 I - r r^T) dV,
//! where R stacks, for every node at r, the block [[I, -r^x], [0, I]] (u = V + omega x r).
//! This is the rigid part of the thesis's mass matrix (2.5.1): P (mass), c (first moment)
//! and J (inertia about the body origin), cf. (2.2.16)-(2.2.19).

use faer::sparse::SparseColMat;
use nalgebra::{Matrix3, Vector3};

use super::assembly::skew;
use super::mesh::fin_frame;
use super::spec::{BodySpec, FinSpec, GeneratorSpec};
use crate::structure::fe_model::FeModel;

/// Mass, first moment and inertia tensor about the body-frame origin (the nose tip).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Total mass m, kg.
    pub mass: f64,
    /// First moment m * r_cm, kg m.
    pub first_moment: [f64; 3],
    /// J_O = int rho (|r|^2 I - r r^T) dV, kg m^2.
    pub inertia_about_origin: [[f64; 3]; 3],
}

impl MassProperties {
    fn zero() -> Self {
        Self {
            mass: 0.0,
            first_moment: [0.0; 3],
            inertia_about_origin: [[0.0; 3]; 3],
        }
    }

    /// Add a body given its mass, first moment and second moment tensor
    /// S = int rho r r^T dV (then J = tr(S) I - S).
    fn add_second_moment(&mut self, m: f64, first: Vector3<f64>, s: Matrix3<f64>) {
        self.mass += m;
        let j = Matrix3::identity() * s.trace() - s;
        for a in 0..3 {
            self.first_moment[a] += first[a];
            for b in 0..3 {
                self.inertia_about_origin[a][b] += j[(a, b)];
            }
        }
    }

    /// The 6 x 6 rigid-body mass matrix [[m I, -(m c)^x], [(m c)^x, J_O]].
    pub fn rigid_mass_matrix(&self) -> [[f64; 6]; 6] {
        let sx = skew(&self.first_moment);
        let mut out = [[0.0; 6]; 6];
        for a in 0..3 {
            out[a][a] = self.mass;
            for b in 0..3 {
                out[a][3 + b] = -sx[(a, b)];
                out[3 + a][b] = sx[(a, b)];
                out[3 + a][3 + b] = self.inertia_about_origin[a][b];
            }
        }
        out
    }
}

/// Polynomial in s with coefficients c[k] s^k.
#[derive(Clone, Debug)]
struct Poly(Vec<f64>);

impl Poly {
    fn mul(&self, o: &Poly) -> Poly {
        let mut c = vec![0.0; self.0.len() + o.0.len() - 1];
        for (i, a) in self.0.iter().enumerate() {
            for (j, b) in o.0.iter().enumerate() {
                c[i + j] += a * b;
            }
        }
        Poly(c)
    }
    fn sub(&self, o: &Poly) -> Poly {
        let n = self.0.len().max(o.0.len());
        Poly(
            (0..n)
                .map(|k| self.0.get(k).unwrap_or(&0.0) - o.0.get(k).unwrap_or(&0.0))
                .collect(),
        )
    }
    fn scale(&self, f: f64) -> Poly {
        Poly(self.0.iter().map(|c| c * f).collect())
    }
    fn pow(&self, n: usize) -> Poly {
        (0..n).fold(Poly(vec![1.0]), |acc, _| acc.mul(self))
    }
    /// int_a^b p(s) ds via the antiderivative.
    fn integrate(&self, a: f64, b: f64) -> f64 {
        self.0
            .iter()
            .enumerate()
            .map(|(k, c)| c * (b.powi(k as i32 + 1) - a.powi(k as i32 + 1)) / (k as f64 + 1.0))
            .sum()
    }
}

/// Add a body-of-revolution segment s in [s0, s1] (x = -s) with outer and inner radius
/// polynomials in s: mass int rho A, first moment -int rho A s e_x, second moments
/// S_xx = int rho A s^2, S_yy = S_zz = int rho I (I = pi/4 (r_o^4 - r_i^4)).
fn add_revolution(out: &mut MassProperties, rho: f64, ro: &Poly, ri: &Poly, s0: f64, s1: f64) {
    let pi = std::f64::consts::PI;
    let area = ro.pow(2).sub(&ri.pow(2)).scale(pi);
    let inertia = ro.pow(4).sub(&ri.pow(4)).scale(0.25 * pi);
    let s = Poly(vec![0.0, 1.0]);
    let m = rho * area.integrate(s0, s1);
    let sx = -rho * area.mul(&s).integrate(s0, s1);
    let sxx = rho * area.mul(&s.pow(2)).integrate(s0, s1);
    let syy = rho * inertia.integrate(s0, s1);
    out.add_second_moment(
        m,
        Vector3::new(sx, 0.0, 0.0),
        Matrix3::from_diagonal(&Vector3::new(sxx, syy, syy)),
    );
}

fn add_body(out: &mut MassProperties, b: &BodySpec) {
    let rho = b.material.density;
    let r = 0.5 * b.outer_diameter;
    let t = b.wall_thickness;
    let ln = b.nose_length;
    if ln > 0.0 && !b.nose_shape.is_conical() {
        add_curved_nose(out, b);
    } else if ln > 0.0 {
        let kappa = r / ln;
        let s_solid = t / kappa; // r_o = t here; t < r so s_solid < l_n
        add_revolution(
            out,
            rho,
            &Poly(vec![0.0, kappa]),
            &Poly(vec![0.0]),
            0.0,
            s_solid,
        );
        add_revolution(
            out,
            rho,
            &Poly(vec![0.0, kappa]),
            &Poly(vec![-t, kappa]),
            s_solid,
            ln,
        );
    }
    // The tube behind the nose: sections of one diameter between the transitions, and the
    // transitions (frustum: linear radius polynomials; shaped: the profile's quadrature).
    let mut from = ln;
    let mut rs = r;
    for tr in &b.transitions {
        add_revolution(
            out,
            rho,
            &Poly(vec![rs]),
            &Poly(vec![rs - t]),
            from,
            tr.start,
        );
        if tr.shape.is_conical() {
            let k = (tr.r_aft - tr.r_fore) / tr.length;
            let ro = Poly(vec![tr.r_fore - k * tr.start, k]);
            let ri = Poly(vec![tr.r_fore - k * tr.start - t, k]);
            add_revolution(out, rho, &ro, &ri, tr.start, tr.end());
        } else {
            add_shaped_transition(out, rho, t, tr);
        }
        from = tr.end();
        rs = tr.r_aft;
    }
    add_revolution(
        out,
        rho,
        &Poly(vec![rs]),
        &Poly(vec![rs - t]),
        from,
        b.length,
    );
}

/// A shaped transition (`check::transition`): the integrals of [`add_revolution`] of the
/// annulus between r(s) and r(s) - t by the transition's quadrature.
fn add_shaped_transition(
    out: &mut MassProperties,
    rho: f64,
    t: f64,
    tr: &crate::check::transition::TransitionGeom,
) {
    let pi = std::f64::consts::PI;
    let area = |ro: f64| pi * (ro * ro - (ro - t) * (ro - t));
    let inertia = |ro: f64| 0.25 * pi * (ro.powi(4) - (ro - t).powi(4));
    let (a, b) = (tr.start, tr.end());
    let m = rho * tr.integrate(a, b, |_, ro| area(ro));
    let sx = -rho * tr.integrate(a, b, |s, ro| area(ro) * s);
    let sxx = rho * tr.integrate(a, b, |s, ro| area(ro) * s * s);
    let syy = rho * tr.integrate(a, b, |_, ro| inertia(ro));
    out.add_second_moment(
        m,
        Vector3::new(sx, 0.0, 0.0),
        Matrix3::from_diagonal(&Vector3::new(sxx, syy, syy)),
    );
}

/// A curved nose (`check::nose`): the same integrals as [`add_revolution`] of the annulus
/// between r(s) and max(r(s) - t, 0), by the profile's quadrature on the solid tip and on the
/// hollow shell separately (the section has a kink where r = t), 64 panels each.
fn add_curved_nose(out: &mut MassProperties, b: &BodySpec) {
    let pi = std::f64::consts::PI;
    let (rho, r, t, ln) = (
        b.material.density,
        0.5 * b.outer_diameter,
        b.wall_thickness,
        b.nose_length,
    );
    let shape = b.nose_shape;
    let s_solid = shape.solid_tip_end(t, r, ln);
    let area = |ro: f64| {
        let ri = (ro - t).max(0.0);
        pi * (ro * ro - ri * ri)
    };
    let inertia = |ro: f64| {
        let ri = (ro - t).max(0.0);
        0.25 * pi * (ro.powi(4) - ri.powi(4))
    };
    let mut m = 0.0;
    let mut sx = 0.0;
    let mut sxx = 0.0;
    let mut syy = 0.0;
    for (s0, s1) in [(0.0, s_solid), (s_solid, ln)] {
        m += rho * shape.integrate(r, ln, s0, s1, 64, |_, ro| area(ro));
        sx -= rho * shape.integrate(r, ln, s0, s1, 64, |s, ro| area(ro) * s);
        sxx += rho * shape.integrate(r, ln, s0, s1, 64, |s, ro| area(ro) * s * s);
        syy += rho * shape.integrate(r, ln, s0, s1, 64, |_, ro| inertia(ro));
    }
    out.add_second_moment(
        m,
        Vector3::new(sx, 0.0, 0.0),
        Matrix3::from_diagonal(&Vector3::new(sxx, syy, syy)),
    );
}

/// Polygon area integrals (Green's theorem, counter-clockwise vertices):
/// [A, int a, int b, int a^2, int b^2, int a b].
fn polygon_moments(v: &[[f64; 2]]) -> [f64; 6] {
    let mut m = [0.0; 6];
    for i in 0..v.len() {
        let (p, q) = (v[i], v[(i + 1) % v.len()]);
        let cr = p[0] * q[1] - q[0] * p[1];
        m[0] += cr / 2.0;
        m[1] += cr * (p[0] + q[0]) / 6.0;
        m[2] += cr * (p[1] + q[1]) / 6.0;
        m[3] += cr * (p[0] * p[0] + p[0] * q[0] + q[0] * q[0]) / 12.0;
        m[4] += cr * (p[1] * p[1] + p[1] * q[1] + q[1] * q[1]) / 12.0;
        m[5] += cr * (2.0 * p[0] * p[1] + p[0] * q[1] + q[0] * p[1] + 2.0 * q[0] * q[1]) / 24.0;
    }
    m
}

/// The planform's moments `[A, ∫a, ∫b, ∫a², ∫b², ∫ab]` in the fin's (a = x - pivot, b =
/// spanwise) coordinates, exact for each outline: the polygon's by [`polygon_moments`]; the
/// half ellipse on the root chord (semi-axes `A = c_r/2` along a, `B = s` along b, centred on
/// the pivot, the middle of the root chord) in closed form: area `π A B/2`, `∫a = 0`,
/// `∫b = 2 A B²/3`, `∫a² = π A³ B/8`, `∫b² = π A B³/8`, `∫ab = 0` (the half-disc integrals
/// scaled by the axes).
fn outline_moments(f: &FinSpec) -> [f64; 6] {
    use crate::check::ir::FinOutline;
    match &f.outline {
        FinOutline::Trapezoidal => {
            let corners = f.planform_corners().map(|(x, eta)| [x - f.pivot_x(), eta]);
            polygon_moments(&corners)
        }
        FinOutline::Elliptical => {
            let (a, b) = (0.5 * f.root_chord, f.span);
            let pi = std::f64::consts::PI;
            [
                0.5 * pi * a * b,
                0.0,
                2.0 / 3.0 * a * b * b,
                pi * a.powi(3) * b / 8.0,
                pi * a * b.powi(3) / 8.0,
                0.0,
            ]
        }
        FinOutline::Freeform { leading, trailing } => {
            // Counter-clockwise in (a, b) as the trapezoid's corners: root trailing edge, the
            // leading edge out to the tip, the trailing edge back in (a = root LE x - x_aft -
            // pivot).
            let a0 = f.root_leading_edge_x() - f.pivot_x();
            let mut v: Vec<[f64; 2]> = vec![[a0 - trailing[0][1], 0.0]];
            v.extend(leading.iter().map(|p| [a0 - p[1], p[0]]));
            v.extend(trailing.iter().rev().map(|p| [a0 - p[1], p[0]]));
            v.dedup();
            if v.first() == v.last() {
                v.pop();
            }
            polygon_moments(&v)
        }
    }
}

/// One flat fin: r = p0 + a e_a + b e_b + z n over the planform, |z| <= t/2.
fn add_fin(out: &mut MassProperties, f: &FinSpec, delta: f64, root_radius: f64) {
    let frame = fin_frame(delta, f.cant);
    let (ea, eb, n) = (
        frame.row(0).transpose(),
        frame.row(1).transpose(),
        frame.row(2).transpose(),
    );
    let p0 = Vector3::new(f.pivot_x(), 0.0, 0.0) + root_radius * eb;
    let [area, sa, sb, saa, sbb, sab] = outline_moments(f);
    let rt = f.material.density * f.thickness;
    let first_local = sa * ea + sb * eb;
    let mut s = area * p0 * p0.transpose()
        + p0 * first_local.transpose()
        + first_local * p0.transpose()
        + saa * ea * ea.transpose()
        + sbb * eb * eb.transpose()
        + sab * (ea * eb.transpose() + eb * ea.transpose());
    s *= rt;
    s += f.material.density * f.thickness.powi(3) / 12.0 * area * n * n.transpose();
    out.add_second_moment(rt * area, rt * (area * p0 + first_local), s);
}

/// The mass properties of a further, rigid fin set `f` on `body` (all its plates, as
/// [`analytic_mass_properties`] adds the meshed set's) about the point `(about_x, 0, 0)`:
/// the set moved by `-about_x` along the axis, its root radius that of its own station. About
/// a body node this is the 6 x 6 nodal mass block of the set rigidly attached there
/// ([`MassProperties::rigid_mass_matrix`]: `[[m I, -(m c)^x], [(m c)^x, J]]`, the rigid
/// body's mass matrix in the node's translations and rotations).
pub fn rigid_fin_set(body: &BodySpec, f: &FinSpec, about_x: f64) -> MassProperties {
    let root_radius = super::mesh::fin_root_radius(body, f.pivot_x());
    let mut moved = f.clone();
    moved.root_trailing_edge_x -= about_x;
    let mut out = MassProperties::zero();
    for delta in moved.fin_angles() {
        add_fin(&mut out, &moved, delta, root_radius);
    }
    out
}

/// Closed-form mass properties of the vehicle `spec` describes (see the `generate` module
/// doc for the geometry): tapered tube, trapezoidal plates, line masses, point masses.
pub fn analytic_mass_properties(spec: &GeneratorSpec) -> MassProperties {
    let mut out = MassProperties::zero();
    add_body(&mut out, &spec.body);
    if let Some(f) = &spec.fins {
        for delta in f.fin_angles() {
            add_fin(
                &mut out,
                f,
                delta,
                super::mesh::fin_root_radius(&spec.body, f.pivot_x()),
            );
        }
    }
    for f in &spec.rigid_fins {
        let p = rigid_fin_set(&spec.body, f, 0.0);
        out.mass += p.mass;
        for a in 0..3 {
            out.first_moment[a] += p.first_moment[a];
            for b in 0..3 {
                out.inertia_about_origin[a][b] += p.inertia_about_origin[a][b];
            }
        }
    }
    for d in &spec.distributed_masses {
        let (a, b) = (d.x_from.min(d.x_to), d.x_from.max(d.x_to));
        let mu = d.mass / (b - a);
        let sxx = mu * (b.powi(3) - a.powi(3)) / 3.0;
        out.add_second_moment(
            d.mass,
            Vector3::new(d.mass * 0.5 * (a + b), 0.0, 0.0),
            Matrix3::from_diagonal(&Vector3::new(sxx, 0.0, 0.0)),
        );
    }
    for p in &spec.point_masses {
        let r = Vector3::from(p.position);
        // S = m r r^T + S_c, with S_c chosen so that tr(S_c) I - S_c = diag(I_c):
        // S_c = tr(I_c)/2 I - diag(I_c).
        let ic = Vector3::from(p.inertia);
        let sc = Matrix3::identity() * (0.5 * ic.sum()) - Matrix3::from_diagonal(&ic);
        out.add_second_moment(p.mass, p.mass * r, p.mass * r * r.transpose() + sc);
    }
    out
}

/// R^T M R for the six rigid-body vectors about the body origin (module doc), 6 x 6.
pub fn rigid_body_projection(model: &FeModel) -> [[f64; 6]; 6] {
    let r = rigid_body_vectors(model);
    let m: &SparseColMat<usize, f64> = &model.mass;
    let mut out = [[0.0; 6]; 6];
    for t in m.triplet_iter() {
        let (row, col, v) = (t.row, t.col, *t.val);
        for a in 0..6 {
            let ra = r[row][a];
            if ra == 0.0 {
                continue;
            }
            for b in 0..6 {
                out[a][b] += ra * v * r[col][b];
            }
        }
    }
    out
}

/// The six rigid-body vectors about the origin, one row of 6 per DOF.
pub fn rigid_body_vectors(model: &FeModel) -> Vec<[f64; 6]> {
    let mut r = vec![[0.0; 6]; model.n_dof()];
    for (i, node) in model.nodes.iter().enumerate() {
        let px = skew(&node.position);
        for d in 0..3 {
            r[6 * i + d][d] = 1.0;
            r[6 * i + 3 + d][3 + d] = 1.0;
            for b in 0..3 {
                r[6 * i + d][3 + b] = -px[(d, b)];
            }
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polygon_moments_of_unit_square() {
        let m = polygon_moments(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        let want = [1.0, 0.5, 0.5, 1.0 / 3.0, 1.0 / 3.0, 0.25];
        for k in 0..6 {
            assert!((m[k] - want[k]).abs() < 1e-15, "{k}: {}", m[k]);
        }
    }

    /// A thin tube of length L about its end: I_yy = m L^2 / 3 + m (r_o^2 + r_i^2) / 4.
    #[test]
    fn tube_inertia_closed_form() {
        let mut out = MassProperties::zero();
        let (ro, ri, l, rho) = (0.06, 0.05, 2.0, 1000.0);
        add_revolution(&mut out, rho, &Poly(vec![ro]), &Poly(vec![ri]), 0.0, l);
        let m = rho * std::f64::consts::PI * (ro * ro - ri * ri) * l;
        assert!((out.mass - m).abs() < 1e-12 * m);
        assert!((out.first_moment[0] + m * l / 2.0).abs() < 1e-12 * m);
        let iyy = m * l * l / 3.0 + m * (ro * ro + ri * ri) / 4.0;
        assert!((out.inertia_about_origin[1][1] - iyy).abs() < 1e-12 * iyy);
        let ixx = m * (ro * ro + ri * ri) / 2.0;
        assert!((out.inertia_about_origin[0][0] - ixx).abs() < 1e-12 * ixx);
    }
}
