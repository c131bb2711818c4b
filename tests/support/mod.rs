//! Hand-built FE models for the coefficient tests: consistent-mass beams, rigid point
//! bodies, random shapes.

#![allow(dead_code, clippy::unwrap_used)]

use faer::Mat;
use faer::sparse::{SparseColMat, Triplet};
use flexflight::structure::{Component, FeModel, Node};
use nalgebra::{DMatrix, Matrix3, Vector3};

// ---------------------------------------------------------------- helpers

pub struct Lcg(pub u64);
impl Lcg {
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
    }
    pub fn vec3(&mut self) -> Vector3<f64> {
        Vector3::new(self.next(), self.next(), self.next())
    }
}

pub fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

pub fn m3(a: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| a[i][j])
}

pub fn sparse(d: &DMatrix<f64>) -> SparseColMat<usize, f64> {
    let mut t = Vec::new();
    for j in 0..d.ncols() {
        for i in 0..d.nrows() {
            if d[(i, j)] != 0.0 {
                t.push(Triplet::new(i, j, d[(i, j)]));
            }
        }
    }
    SparseColMat::try_new_from_triplets(d.nrows(), d.ncols(), &t).unwrap()
}

pub fn model(positions: &[[f64; 3]], mass: &DMatrix<f64>, stiffness: &DMatrix<f64>) -> FeModel {
    FeModel {
        nodes: positions
            .iter()
            .enumerate()
            .map(|(i, p)| Node {
                id: i as u64 + 1,
                position: *p,
                component: Component::Body,
            })
            .collect(),
        mass: sparse(mass),
        stiffness: sparse(stiffness),
        elements: Vec::new(),
    }
}

pub fn rel_close(a: f64, b: f64, scale: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * scale
}

pub fn assert_m3(a: &Matrix3<f64>, b: &Matrix3<f64>, scale: f64, tol: f64, what: &str) {
    let err = (a - b).norm();
    assert!(
        err <= tol * scale,
        "{what}: |diff| = {err:e} > {:e}\n{a}\n{b}",
        tol * scale
    );
}

pub fn assert_v3(a: &Vector3<f64>, b: &Vector3<f64>, scale: f64, tol: f64, what: &str) {
    let err = (a - b).norm();
    assert!(
        err <= tol * scale,
        "{what}: |diff| = {err:e} > {:e}\n{a}\n{b}",
        tol * scale
    );
}

/// Rigid body of mass `mu` at offset `rho` from its node: `R^T mu R`, `R = [1, -rho^×]`
/// (block [[mu 1, -mu rho^×], [mu rho^×, -mu rho^× rho^×]]).
pub fn point_block(mu: f64, rho: &Vector3<f64>) -> [[f64; 6]; 6] {
    let rx = skew(rho);
    let b = -mu * rx;
    let d = -mu * rx * rx;
    let mut out = [[0.0; 6]; 6];
    for i in 0..3 {
        out[i][i] = mu;
        for j in 0..3 {
            out[i][3 + j] = b[(i, j)];
            out[3 + i][j] = b[(j, i)];
            out[3 + i][3 + j] = d[(i, j)];
        }
    }
    out
}

pub fn add_block(m: &mut DMatrix<f64>, a: usize, b: usize, blk: &[[f64; 6]; 6]) {
    for i in 0..6 {
        for j in 0..6 {
            m[(6 * a + i, 6 * b + j)] += blk[i][j];
        }
    }
}

/// 12-DOF consistent mass and stiffness of a Euler-Bernoulli beam in its local frame
/// (DOF u v w θx θy θz per node; θz = dv/dx, θy = -dw/dx).
pub fn beam_local(
    mass: f64,
    l: f64,
    rx2: f64,
    ea: f64,
    gj: f64,
    ei: f64,
) -> (DMatrix<f64>, DMatrix<f64>) {
    let mut m = DMatrix::zeros(12, 12);
    let mut k = DMatrix::zeros(12, 12);
    let pair = |mat: &mut DMatrix<f64>, i: usize, j: usize, a: f64, b: f64| {
        mat[(i, i)] += a;
        mat[(j, j)] += a;
        mat[(i, j)] += b;
        mat[(j, i)] += b;
    };
    pair(&mut m, 0, 6, mass / 3.0, mass / 6.0);
    pair(&mut m, 3, 9, mass * rx2 / 3.0, mass * rx2 / 6.0);
    pair(&mut k, 0, 6, ea / l, -ea / l);
    pair(&mut k, 3, 9, gj / l, -gj / l);
    let c = mass / 420.0;
    let e = ei / l.powi(3);
    for (idx, s) in [([1usize, 5, 7, 11], 1.0), ([2usize, 4, 8, 10], -1.0)] {
        let ls = s * l;
        let mb = [
            [156.0, 22.0 * ls, 54.0, -13.0 * ls],
            [22.0 * ls, 4.0 * l * l, 13.0 * ls, -3.0 * l * l],
            [54.0, 13.0 * ls, 156.0, -22.0 * ls],
            [-13.0 * ls, -3.0 * l * l, -22.0 * ls, 4.0 * l * l],
        ];
        let kb = [
            [12.0, 6.0 * ls, -12.0, 6.0 * ls],
            [6.0 * ls, 4.0 * l * l, -6.0 * ls, 2.0 * l * l],
            [-12.0, -6.0 * ls, 12.0, -6.0 * ls],
            [6.0 * ls, 2.0 * l * l, -6.0 * ls, 4.0 * l * l],
        ];
        for i in 0..4 {
            for j in 0..4 {
                m[(idx[i], idx[j])] += c * mb[i][j];
                k[(idx[i], idx[j])] += e * kb[i][j];
            }
        }
    }
    (m, k)
}

/// Assemble a beam element between nodes `a` and `b` into global matrices.
#[allow(clippy::too_many_arguments)]
pub fn add_beam(
    m: &mut DMatrix<f64>,
    k: &mut DMatrix<f64>,
    pos: &[[f64; 3]],
    a: usize,
    b: usize,
    mass_per_length: f64,
    rx2: f64,
    stiff: (f64, f64, f64),
) {
    let pa = Vector3::from(pos[a]);
    let pb = Vector3::from(pos[b]);
    let l = (pb - pa).norm();
    let lx = (pb - pa) / l;
    let reference = if lx.z.abs() < 0.9 {
        Vector3::z()
    } else {
        Vector3::y()
    };
    let ly = reference.cross(&lx).normalize();
    let lz = lx.cross(&ly);
    let mut t = DMatrix::zeros(12, 12);
    for blk in 0..4 {
        for j in 0..3 {
            t[(3 * blk, 3 * blk + j)] = lx[j];
            t[(3 * blk + 1, 3 * blk + j)] = ly[j];
            t[(3 * blk + 2, 3 * blk + j)] = lz[j];
        }
    }
    let (ml, kl) = beam_local(mass_per_length * l, l, rx2, stiff.0, stiff.1, stiff.2);
    let mg = t.transpose() * ml * &t;
    let kg = t.transpose() * kl * &t;
    let dofs: Vec<usize> = (0..6)
        .map(|i| 6 * a + i)
        .chain((0..6).map(|i| 6 * b + i))
        .collect();
    for i in 0..12 {
        for j in 0..12 {
            m[(dofs[i], dofs[j])] += mg[(i, j)];
            k[(dofs[i], dofs[j])] += kg[(i, j)];
        }
    }
}

/// A small 3-D rocket-like model: a body beam chain along -x from the nose (node 0 at the
/// origin), two fins (one along +y, one along -z) and an offset point mass with rotary inertia.
pub fn beam_model() -> (FeModel, DMatrix<f64>) {
    let pos = vec![
        [0.0, 0.0, 0.0],
        [-0.5, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [-1.5, 0.0, 0.0],
        [-2.0, 0.0, 0.0],
        [-1.9, 0.06, 0.0],
        [-1.95, 0.12, 0.0],
        [-1.9, 0.0, -0.06],
        [-1.95, 0.0, -0.12],
    ];
    let n = pos.len() * 6;
    let mut m = DMatrix::zeros(n, n);
    let mut k = DMatrix::zeros(n, n);
    let body = (5.5e7, 1.2e4, 1.6e4);
    for e in 0..4 {
        add_beam(&mut m, &mut k, &pos, e, e + 1, 2.1, 4.0e-3, body);
    }
    let fin = (2.0e6, 5.0e1, 8.0e1);
    for (a, b) in [(4, 5), (5, 6), (4, 7), (7, 8)] {
        add_beam(&mut m, &mut k, &pos, a, b, 0.4, 1.0e-4, fin);
    }
    // Payload: 1.5 kg at an offset from node 2, with its own inertia about its centre.
    let mut blk = point_block(1.5, &Vector3::new(0.02, 0.01, -0.03));
    for (i, v) in [0.003, 0.004, 0.005].iter().enumerate() {
        blk[3 + i][3 + i] += v;
    }
    add_block(&mut m, 2, 2, &blk);
    add_block(&mut m, 4, 4, &point_block(0.8, &Vector3::zeros()));
    (model(&pos, &m, &k), m)
}

/// The beam model with a symmetric translation-rotation coupling `S` added to `M_23` and
/// removed from `M_33` (shell-like mass coupling): column sums unchanged, so (3.2.1) keeps its
/// `c_tot^×` form, but the `sym(B)`/`sym(C)` terms of the discretisation are exercised.
pub fn beam_model_with_symmetric_coupling() -> (FeModel, DMatrix<f64>) {
    let (fe, mut m) = beam_model();
    let s = Matrix3::new(0.01, 0.002, 0.0, 0.002, -0.005, 0.001, 0.0, 0.001, 0.003);
    for i in 0..3 {
        for j in 0..3 {
            m[(12 + i, 18 + 3 + j)] += s[(i, j)];
            m[(18 + 3 + j, 12 + i)] += s[(i, j)];
            m[(18 + i, 18 + 3 + j)] -= s[(i, j)];
            m[(18 + 3 + j, 18 + i)] -= s[(i, j)];
        }
    }
    let pos: Vec<[f64; 3]> = fe.nodes.iter().map(|n| n.position).collect();
    let k = DMatrix::identity(m.nrows(), m.ncols());
    (model(&pos, &m, &k), m)
}

pub fn random_shapes(rng: &mut Lcg, rows: usize, n: usize, scale: f64) -> Mat<f64> {
    Mat::from_fn(rows, n, |_, _| scale * rng.next())
}

pub fn shape_at(s: &Mat<f64>, m: usize, a: usize) -> (Vector3<f64>, Vector3<f64>) {
    let v = |o: usize| {
        Vector3::new(
            s[(6 * a + o, m)],
            s[(6 * a + o + 1, m)],
            s[(6 * a + o + 2, m)],
        )
    };
    (v(0), v(3))
}
