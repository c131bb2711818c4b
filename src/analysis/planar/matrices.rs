//! Mass, damping and stiffness matrices of the planar models and the state matrix
//! (thesis eqs. (6.6)-(6.9), (6.12)-(6.13), (6.26)-(6.29)).
//!
//! Several entries of (6.1), (6.8), (6.9), (6.28), (6.29) are unreadable in the OCR, so the
//! matrices are derived here from the definitions (6.2)-(6.5) and (6.14)-(6.25).
//!
//! # Coordinates and kinematics (Figs 6.1, 6.6)
//! The model lies in the pitch plane of the fins (body x-z for the fins at roll 0 and 180
//! deg). As in the thesis, x points forward and y across; theta rotates x toward y; a body
//! point at distance x FORWARD of the mass centre moves across with `v + x theta'`. The
//! body centre of pressure is a distance `a` forward of the mass centre, the fin centre of
//! pressure a distance `d` aft; the fin centre of pressure deflects `delta` across (a flap,
//! which moves the fin but does not change its incidence). `V` (`V0`) is the airspeed.
//!
//! Local angles of attack, `alpha = -V_local/U` (6.24), with the cross velocities of
//! (6.15)-(6.16): `alpha_B = theta - (v + a theta')/V`,
//! `alpha_f = theta - (v - d theta' + delta')/V` (6.25); the pinned model has `v = 0` (6.4).
//! Normal forces, across (6.3), (6.20): `N_B = P_b alpha_B`, `N_f = P_f alpha_f` with
//! `P_b = q S C_Nalpha,B` and `P_f = q S C_Nalpha,f (S_f/S)`. The body's load about the mass
//! centre is `M_b alpha_B` with `M_b = q S b C_Malpha,cg = a P_b` (the body normal force at
//! its centre of pressure, (6.5) and the `a N_B` term of (6.17)); rate derivatives, when
//! given, add `q S b (b/2V) C_Malpha-dot theta'` to the moment and `q S (b/2V) C_Nalpha-dot
//! theta'` to the normal force (alpha-dot taken as theta', its part in v' neglected).
//!
//! # Kinetic energy and the mass matrix (6.7), (6.19), (6.27)
//! With the reference point at the undeformed mass centre (so the static moment `c_x` of
//! (6.19) vanishes) and the flapping fin mass `m_f` lumped at the fin centre of pressure,
//! `T = 1/2 m (u^2 + v^2) + 1/2 J theta'^2 + m_f v delta' - m_f d theta' delta' +
//! 1/2 m_f delta'^2`, where `J` is the total pitch inertia about the mass centre (the fins
//! included: `J = J_rest + m_f d^2`). Hence
//! `M_pinned = [[J, -m_f d], [-m_f d, m_f]]` (6.7) and
//! `M_unpinned = [[m,0,0,0],[0,m,0,m_f],[0,0,J,-m_f d],[0,m_f,-m_f d,m_f]]` (6.27, c_x = 0).
//! (u, v) are the velocity perturbations of (6.14): `U = V0 cos theta + u`,
//! `V = -V0 sin theta + v`; then `V' + theta' U = v'` to first order, so the body-frame
//! momentum equations carry no `m V0 theta'` term.
//!
//! # Generalised forces (6.17)-(6.18)
//! - u: `-(dA_B + dA_f)`, with `dA = q S/V0 (2 C_A + Mach C_A,Mach) u + q S C_A,alpha alpha`
//!   from (6.21)-(6.23) (`dq = 2 q0 u/V0`, `dMach = Mach u/V0`); the `C_A,alpha` terms of the
//!   thesis are kept, though a table symmetric in alpha makes them zero.
//! - v: `N_B + N_f - W theta` (weight's cross component in body axes).
//! - theta: `M_b alpha_B - d N_f + (A_f0 - m_f g) delta`: the moment of the fin axial force
//!   `A_f0` acting at the deflected fin (`A_f delta` of (6.17), (6.1)), and of the weight at
//!   the mass centre displaced `m_f delta/m` across (`-m_f g delta`; from the potential
//!   `-sum m_i g X_i`). The pinned model is in a wind tunnel: no gravity (thesis 6.1).
//! - delta: `N_f - k delta - m_f g theta` (the fin's own weight across the tilted fin;
//!   the thesis' (6.18) omits it; in the pinned model it is absent).
//!
//! # M x'' + C x' + K x = 0 (6.6), (6.26)
//! `C = -d(forces)/d(x')`, `K = -d(forces)/d(x)`. Pinned, x = (theta, delta):
//! `C = 1/V [[a M_b + d^2 P_f, -d P_f], [-d P_f, P_f]] - rate terms`,
//! `K = [[-M_b + d P_f, -A_f0], [-P_f, k]]` ((6.8)-(6.9): the same entries, with `a M_b =
//! a^2 P_b` where the thesis has its C_Malpha-dot, C_Nalpha-dot terms, and `k` not multiplied
//! by q S).
//! Unpinned, x = (x, y, theta, delta), `D_A = q S/V0 (2 C_A + Mach C_A,Mach)` (all surfaces),
//! `Q_B = q S C_A,alpha,B`, `Q_f = q S n_eff C_A,alpha,1`:
//! ```text
//! C = [[D_A, -(Q_B+Q_f)/V0,   -(a Q_B - d Q_f)/V0,     -Q_f/V0],
//!      [0,   (P_b+P_f)/V0,    (M_b - d P_f)/V0,         P_f/V0],
//!      [0,   (M_b - d P_f)/V0, (a M_b + d^2 P_f)/V0,   -d P_f/V0],
//!      [0,   P_f/V0,          -d P_f/V0,                P_f/V0]]   (- rate terms)
//! K = [[0, 0, Q_B + Q_f,           0],
//!      [0, 0, W - P_b - P_f,       0],
//!      [0, 0, d P_f - M_b,         m_f g - A_f0],
//!      [0, 0, m_f g - P_f,         k]]
//! ```
//! which is (6.28)-(6.29) with `C_Malpha c + C_Nalpha a` read as `M_b/(q S)`, plus the
//! gravity and fin-axial terms above.
//!
//! # State matrix (6.12)-(6.13)
//! `X = (x', x)`, `A = [[M, 0], [0, 1]]^-1 [[-C, -K], [1, 0]]`. In the unpinned model the
//! positions x, y are cyclic (their columns of K are zero): they add two zero eigenvalues
//! and would make sigma_d >= 0 everywhere, so their rows and columns are removed and the
//! state is `(u, v, theta', delta', theta, delta)`; the other eigenvalues are unchanged
//! (the removed block is upper triangular).

use faer::Mat;
use faer::linalg::solvers::Solve;

use super::{PlanarError, PlanarParameters};

/// `M x'' + C x' + K x = 0` with names; `cyclic` lists coordinates whose position is
/// dropped from the state (zero stiffness column).
#[derive(Clone, Debug)]
pub struct SecondOrderSystem {
    pub coordinates: Vec<&'static str>,
    pub state: Vec<&'static str>,
    pub mass: Mat<f64>,
    pub damping: Mat<f64>,
    pub stiffness: Mat<f64>,
    pub cyclic: Vec<usize>,
}

/// Lever `a` times the body moment: `a M_b = a^2 P_b` (0 when the body load is a couple).
fn body_rate_moment(p: &PlanarParameters) -> f64 {
    p.a.map_or(0.0, |a| a * p.body_moment)
}

/// Rate-derivative damping of the body: (normal force, moment about the mass centre) per
/// unit theta', from C_Nalpha-dot and C_Malpha-dot on b/(2V) (5.3.7)-(5.3.8).
fn rate_terms(p: &PlanarParameters) -> (f64, f64) {
    let q = p.condition.dynamic_pressure;
    let (s, b, v) = (p.reference_area, p.reference_length, p.condition.speed);
    let k = b / (2.0 * v);
    let n = q * s * k * p.cn_alpha_dot;
    // The rate normal force acts at the reference point (where the runtime's body block
    // applies it, and about which the derivatives are given): its moment about the mass
    // centre adds to the C_Malpha-dot couple.
    let m = q * s * b * k * p.cm_alpha_dot + n * (p.reference_x - p.mass_properties.x_cg);
    (n, m)
}

/// The pinned model (6.6)-(6.9); see the module doc.
pub fn pinned_system(p: &PlanarParameters) -> SecondOrderSystem {
    let v = p.condition.speed;
    let (pf, d, mf) = (p.fin_lift, p.d, p.fin_mass);
    let (_, m_rate) = rate_terms(p);
    let j = p.mass_properties.inertia;
    let mass = mat(&[&[j, -mf * d], &[-mf * d, mf]]);
    let damping = mat(&[
        &[(body_rate_moment(p) + d * d * pf) / v - m_rate, -d * pf / v],
        &[-d * pf / v, pf / v],
    ]);
    let stiffness = mat(&[
        &[-p.body_moment + d * pf, -p.fin_axial_force],
        &[-pf, p.fin_stiffness],
    ]);
    SecondOrderSystem {
        coordinates: vec!["theta", "delta"],
        state: vec!["theta_dot", "delta_dot", "theta", "delta"],
        mass,
        damping,
        stiffness,
        cyclic: Vec::new(),
    }
}

/// The unpinned model (6.26)-(6.29); see the module doc.
pub fn unpinned_system(p: &PlanarParameters) -> SecondOrderSystem {
    let v = p.condition.speed;
    let q = p.condition.dynamic_pressure;
    let g = p.condition.gravity;
    let (pb, pf, mb, d, mf) = (p.body_lift, p.fin_lift, p.body_moment, p.d, p.fin_mass);
    let a = p.a.unwrap_or(0.0);
    let qb = q * p.reference_area * p.aero.ca_alpha_body;
    let qf = q * p.reference_area * p.pitch_plane_fins * p.aero.ca_alpha_fin;
    let (n_rate, m_rate) = rate_terms(p);
    let (m, j) = (p.mass_properties.mass, p.mass_properties.inertia);
    let mass = mat(&[
        &[m, 0.0, 0.0, 0.0],
        &[0.0, m, 0.0, mf],
        &[0.0, 0.0, j, -mf * d],
        &[0.0, mf, -mf * d, mf],
    ]);
    let damping = mat(&[
        &[
            p.axial_damping,
            -(qb + qf) / v,
            -(a * qb - d * qf) / v,
            -qf / v,
        ],
        &[0.0, (pb + pf) / v, (mb - d * pf) / v - n_rate, pf / v],
        &[
            0.0,
            (mb - d * pf) / v,
            (body_rate_moment(p) + d * d * pf) / v - m_rate,
            -d * pf / v,
        ],
        &[0.0, pf / v, -d * pf / v, pf / v],
    ]);
    let stiffness = mat(&[
        &[0.0, 0.0, qb + qf, 0.0],
        &[0.0, 0.0, p.weight - pb - pf, 0.0],
        &[0.0, 0.0, d * pf - mb, mf * g - p.fin_axial_force],
        &[0.0, 0.0, mf * g - pf, p.fin_stiffness],
    ]);
    SecondOrderSystem {
        coordinates: vec!["x", "y", "theta", "delta"],
        state: vec!["u", "v", "theta_dot", "delta_dot", "theta", "delta"],
        mass,
        damping,
        stiffness,
        cyclic: vec![0, 1],
    }
}

/// The state matrix (6.12)-(6.13) with the cyclic positions removed (module doc).
pub fn state_matrix(
    sys: &SecondOrderSystem,
    p: &PlanarParameters,
) -> Result<Mat<f64>, PlanarError> {
    let n = sys.mass.nrows();
    let mass_error = || PlanarError::MassMatrix {
        inertia: p.mass_properties.inertia,
        fin_term: p.fin_mass * p.d * p.d,
    };
    let llt = sys.mass.llt(faer::Side::Lower).map_err(|_| mass_error())?;
    // A singular M can factor in floating point: demand every pivot L_ii^2 above
    // round-off relative to the largest diagonal entry of M.
    let scale = (0..n).map(|i| sys.mass[(i, i)].abs()).fold(0.0, f64::max);
    let l = llt.L();
    if (0..n).any(|i| {
        (l[(i, i)] * l[(i, i)]).partial_cmp(&(1e-12 * scale)) != Some(std::cmp::Ordering::Greater)
    }) {
        return Err(mass_error());
    }
    // [-C, -K] solved by M.
    let mut rhs = Mat::<f64>::zeros(n, 2 * n);
    for i in 0..n {
        for j in 0..n {
            rhs[(i, j)] = -sys.damping[(i, j)];
            rhs[(i, n + j)] = -sys.stiffness[(i, j)];
        }
    }
    let top = llt.solve(&rhs);
    let keep: Vec<usize> = (0..2 * n)
        .filter(|k| !(*k >= n && sys.cyclic.contains(&(k - n))))
        .collect();
    let dim = keep.len();
    let mut a = Mat::<f64>::zeros(dim, dim);
    for (r, &kr) in keep.iter().enumerate() {
        for (c, &kc) in keep.iter().enumerate() {
            a[(r, c)] = if kr < n {
                top[(kr, kc)]
            } else if kc == kr - n {
                1.0
            } else {
                0.0
            };
        }
    }
    if (0..dim).any(|i| (0..dim).any(|j| !a[(i, j)].is_finite())) {
        return Err(mass_error());
    }
    Ok(a)
}

fn mat(rows: &[&[f64]]) -> Mat<f64> {
    Mat::from_fn(rows.len(), rows[0].len(), |i, j| rows[i][j])
}
