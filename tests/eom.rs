#![allow(clippy::type_complexity, clippy::needless_range_loop)]
//! Equations of motion (3.2.1) and their integration: conservation in free tumble (thesis
//! 6.4), the rigid parabola under uniform gravity, the torque-free asymmetric top against
//! Jacobi's elliptic functions, the constrained modal frequency, and determinism.

use std::sync::OnceLock;

use flexflight::runtime::eom::{Eom, FreeFlight, Invariants, StateLayout, UniformGravity};
use flexflight::runtime::integrate::{
    AdaptiveOptions, DormandPrince54, IntegrationReport, Integrator, OdeSystem,
};
use flexflight::runtime::kinematics::{c_bi, mat_t_vec};
use flexflight::structure::coefficients::ReducedModel;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;
const IDENTITY: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

fn sphads1() -> &'static ReducedModel {
    static MODEL: OnceLock<ReducedModel> = OnceLock::new();
    MODEL.get_or_init(|| {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/vehicles/sphads1.vdl");
        let checked =
            flexflight::check::check_files(&[path.into()], &[], &flexflight::check::DiskLoader);
        let v = &checked.program.vehicles[0];
        let (c, _) = flexflight::structure::compile::compile(v).unwrap();
        c.reduced.clone()
    })
}

/// The rigid 6x6 part of a model (n = 0).
fn rigid_part(m: &ReducedModel) -> ReducedModel {
    ReducedModel {
        n_modes: 0,
        modal_mass: vec![],
        modal_stiffness: vec![],
        modal_damping: vec![],
        omega2: vec![],
        damping_ratio: vec![],
        p_bar: vec![],
        h_bar: vec![],
        j_ru: vec![],
        j_uu: vec![],
        h_prime: vec![],
        ..m.clone()
    }
}

/// The model restricted to the flexible coordinates `keep`.
fn select_modes(m: &ReducedModel, keep: &[usize]) -> ReducedModel {
    let n = m.n();
    let k = keep.len();
    let sq = |a: &[f64]| -> Vec<f64> {
        keep.iter()
            .flat_map(|&r| keep.iter().map(move |&c| a[r * n + c]))
            .collect()
    };
    let rows3 = |a: &[f64]| -> Vec<f64> {
        (0..3)
            .flat_map(|i| keep.iter().map(move |&c| a[i * n + c]))
            .collect()
    };
    ReducedModel {
        n_modes: k as u32,
        modal_mass: sq(&m.modal_mass),
        modal_stiffness: sq(&m.modal_stiffness),
        modal_damping: sq(&m.modal_damping),
        omega2: keep.iter().map(|&r| m.omega2[r]).collect(),
        damping_ratio: keep.iter().map(|&r| m.damping_ratio[r]).collect(),
        p_bar: rows3(&m.p_bar),
        h_bar: rows3(&m.h_bar),
        j_ru: keep.iter().map(|&r| m.j_ru[r]).collect(),
        j_uu: keep
            .iter()
            .flat_map(|&r| keep.iter().map(move |&c| m.j_uu[r * n + c]))
            .collect(),
        h_prime: keep
            .iter()
            .flat_map(|&a| {
                (0..3).flat_map(move |i| keep.iter().map(move |&p| m.h_prime[(a * 3 + i) * n + p]))
            })
            .collect(),
        ..m.clone()
    }
}

fn undamped(m: &ReducedModel) -> ReducedModel {
    ReducedModel {
        modal_damping: vec![0.0; m.modal_damping.len()],
        damping_ratio: vec![0.0; m.damping_ratio.len()],
        ..m.clone()
    }
}

fn tight(rtol: f64, atol: f64) -> DormandPrince54 {
    DormandPrince54::new(AdaptiveOptions {
        rtol,
        atol,
        ..Default::default()
    })
}

fn run(
    sys: &mut dyn OdeSystem,
    integrator: &mut dyn Integrator,
    x: &mut [f64],
    t_end: f64,
    observer: &mut dyn FnMut(f64, &[f64], &[f64]) -> bool,
) -> IntegrationReport {
    let r = integrator.integrate(sys, 0.0, x, t_end, observer);
    assert!(r.completed(), "{r:?}");
    r
}

fn norm(a: &[f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

#[test]
fn the_eom_mass_matrix_is_the_coefficient_mass_matrix() {
    // M_tot v̇ = r: with zero velocities and forces e_k, v̇ = M_tot⁻¹ e_k; compare M_tot v̇.
    let model = undamped(sphads1());
    let n = model.n();
    let d = 6 + n;
    let eta: Vec<f64> = (0..n).map(|m| 1e-3 * (m as f64 + 1.0).sin()).collect();
    let mm = model.mass_matrix(&eta).unwrap();
    struct Unit(usize);
    impl flexflight::runtime::eom::ForceModel for Unit {
        fn generalized_forces(
            &mut self,
            _t: f64,
            _s: &flexflight::runtime::eom::StateView,
            out: &mut [f64],
        ) {
            out[self.0] = 1.0;
        }
    }
    let zero_k = ReducedModel {
        modal_stiffness: vec![0.0; n * n],
        ..model.clone()
    };
    let l = StateLayout { n };
    for k in [0, 4, 6, d - 1] {
        let mut eom = Eom::new(&zero_k, Unit(k)).unwrap();
        let x = l.state([0.0; 3], IDENTITY, [0.0; 3], [0.0; 3], &eta, &vec![0.0; n]);
        let mut dx = vec![0.0; l.len()];
        eom.rhs(0.0, &x, &mut dx).unwrap();
        let mut a = vec![0.0; d];
        a[..6].copy_from_slice(&dx[7..13]);
        a[6..].copy_from_slice(&dx[13 + n..]);
        for i in 0..d {
            let r: f64 = (0..d).map(|j| mm[i * d + j] * a[j]).sum();
            let e = if i == k { 1.0 } else { 0.0 };
            assert!((r - e).abs() < 1e-9, "k {k} row {i}: {r}");
        }
    }
}

/// The whole right-hand side against the Boltzmann-Hamel equations written directly from
/// the mass matrix and its η-derivatives (module doc of `runtime::eom`):
/// `M_tot v̇ = f - Ṁ v + ∂T/∂η - [ω×p_V; V×p_V + ω×p_ω; K̄η + C̄η̇]`, with
/// `Ṁ = Σ_m η̇_m ∂M/∂η_m`, `∂T/∂η_m = ½ vᵀ(∂M/∂η_m)v`, `p = M v`, every matrix from
/// `ReducedModel::mass_matrix` / `mass_matrix_derivative_into` (dense, allocating). The
/// model has a full (non-diagonal, non-unit) modal mass and damping so that the Schur
/// complement solve and the precomputed quadratic forms are exercised in general.
#[test]
fn rhs_matches_the_boltzmann_hamel_equations_from_the_mass_matrix_derivatives() {
    let base = sphads1();
    let n = base.n();
    let d = 6 + n;
    let mut model = base.clone();
    for m in 0..n {
        for p in 0..n {
            let mm = model.modal_mass[m * n + p];
            model.modal_mass[m * n + p] = if m == p {
                mm * (1.0 + 0.3 * m as f64)
            } else {
                0.02 * mm.abs().max(1.0) * ((m + p) as f64).cos() + mm
            };
            model.modal_damping[m * n + p] += if m == p { 0.5 } else { 0.01 };
        }
    }
    let l = StateLayout { n };
    let mut eom = Eom::new(&model, FreeFlight).unwrap();
    for trial in 0..4 {
        let tr = trial as f64;
        let eta: Vec<f64> = (0..n).map(|m| 2e-3 * (m as f64 + 1.0 + tr).sin()).collect();
        let eta_dot: Vec<f64> = (0..n).map(|m| 0.3 * (2.0 * m as f64 - tr).cos()).collect();
        let v = [180.0 + tr, -3.0, 7.0 - tr];
        let w = [2.0, -1.0 + 0.5 * tr, 0.7];
        let x = l.state([0.0, 0.0, -1000.0], IDENTITY, v, w, &eta, &eta_dot);
        let mut dx = vec![0.0; l.len()];
        eom.rhs(0.0, &x, &mut dx).unwrap();
        let mut vd = vec![0.0; d];
        vd[..6].copy_from_slice(&dx[7..13]);
        vd[6..].copy_from_slice(&dx[13 + n..]);
        let mut vel = vec![0.0; d];
        vel[..3].copy_from_slice(&v);
        vel[3..6].copy_from_slice(&w);
        vel[6..].copy_from_slice(&eta_dot);
        let mm = model.mass_matrix(&eta).unwrap();
        let mv = |a: &[f64], x: &[f64]| -> Vec<f64> {
            (0..d)
                .map(|i| (0..d).map(|j| a[i * d + j] * x[j]).sum())
                .collect()
        };
        let p = mv(&mm, &vel);
        let mut r = vec![0.0; d];
        let mut dm = vec![0.0; d * d];
        for m in 0..n {
            model.mass_matrix_derivative_into(&eta, m, &mut dm).unwrap();
            let dmv = mv(&dm, &vel);
            for i in 0..d {
                r[i] -= eta_dot[m] * dmv[i];
            }
            r[6 + m] += 0.5 * (0..d).map(|i| vel[i] * dmv[i]).sum::<f64>();
        }
        let cr = |a: &[f64], b: &[f64]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let (pv, pw) = (&p[0..3], &p[3..6]);
        let (wxpv, vxpv, wxpw) = (cr(&w, pv), cr(&v, pv), cr(&w, pw));
        for i in 0..3 {
            r[i] -= wxpv[i];
            r[3 + i] -= vxpv[i] + wxpw[i];
        }
        for m in 0..n {
            for q in 0..n {
                r[6 + m] -= model.modal_stiffness[m * n + q] * eta[q]
                    + model.modal_damping[m * n + q] * eta_dot[q];
            }
        }
        let lhs = mv(&mm, &vd);
        let scale = r.iter().chain(&lhs).fold(0.0f64, |a, b| a.max(b.abs()));
        for i in 0..d {
            assert!(
                (lhs[i] - r[i]).abs() <= 1e-12 * scale,
                "trial {trial} row {i}: {} vs {} (scale {scale:e})",
                lhs[i],
                r[i]
            );
        }
    }
}

/// Largest relative drifts of (energy, |p_I|, p_I components, |h_cm|, h_I components).
#[derive(Debug, Default, Clone, Copy)]
struct Drift {
    energy: f64,
    p_norm: f64,
    p_comp: f64,
    h_norm: f64,
    h_comp: f64,
}

fn drift_of(i0: &Invariants, i: &Invariants, acc: &mut Drift) {
    let rel = |a: f64, b: f64, s: f64| (a - b).abs() / s;
    let (p0, p) = (i0.momentum_inertial, i.momentum_inertial);
    let (h0, h) = (
        i0.angular_momentum_cm_inertial,
        i.angular_momentum_cm_inertial,
    );
    let (pn, hn) = (norm(&p0), norm(&h0));
    acc.energy = acc
        .energy
        .max(rel(i.total_energy(), i0.total_energy(), i0.total_energy()));
    acc.p_norm = acc.p_norm.max(rel(norm(&i.momentum_body), pn, pn));
    acc.h_norm = acc
        .h_norm
        .max(rel(norm(&i.angular_momentum_cm_body), hn, hn));
    for k in 0..3 {
        acc.p_comp = acc.p_comp.max(rel(p[k], p0[k], pn));
        acc.h_comp = acc.h_comp.max(rel(h[k], h0[k], hn));
    }
}

#[test]
fn free_tumble_conserves_energy_and_momenta() {
    // Thesis 6.4: no loads, V_B0 = (20, 10, 2π) m/s, ω_B0 = (2π, 2π, 2π) rad/s, 10 s.
    let model = undamped(sphads1());
    let n = model.n();
    assert_eq!(n, 10);
    let l = StateLayout { n };
    let mut x = l.state(
        [0.0; 3],
        IDENTITY,
        [20.0, 10.0, TWO_PI],
        [TWO_PI; 3],
        &vec![0.0; n],
        &vec![0.0; n],
    );
    let mut eom = Eom::new(&model, FreeFlight).unwrap();
    let mut probe = Eom::new(&model, FreeFlight).unwrap();
    let i0 = probe.invariants(&x).unwrap();
    let mut drift = Drift::default();
    let mut max_eta = 0.0f64;
    let r = run(
        &mut eom,
        &mut tight(1e-11, 1e-13),
        &mut x,
        10.0,
        &mut |_, x, _| {
            drift_of(&i0, &probe.invariants(x).unwrap(), &mut drift);
            max_eta = x[13..13 + n].iter().fold(max_eta, |a, e| a.max(e.abs()));
            true
        },
    );
    eprintln!(
        "free tumble: {:?}; drift {drift:?}; max |eta| {max_eta:e}",
        r.stats
    );
    assert!(max_eta > 0.0, "the tumble must excite the modes");
    for (what, v) in [
        ("energy", drift.energy),
        ("|p|", drift.p_norm),
        ("p_I", drift.p_comp),
        ("|h_cm|", drift.h_norm),
        ("h_I", drift.h_comp),
    ] {
        assert!(v < 1e-6, "{what} drift {v:e}");
    }
}

#[test]
fn damping_dissipates_energy_in_free_tumble_but_keeps_momenta() {
    // 2 % modal damping, C̄ = diag(2 ζ ω_m M̄_mm).
    let base = sphads1();
    let n = base.n();
    let mut model = base.clone();
    for m in 0..n {
        model.modal_damping[m * n + m] =
            2.0 * 0.02 * base.omega2[m].sqrt() * base.modal_mass[m * n + m];
    }
    let model = &model;
    let l = StateLayout { n };
    let eta0: Vec<f64> = (0..n).map(|m| 1e-4 * (1.0 + m as f64).cos()).collect();
    let mut x = l.state(
        [0.0; 3],
        IDENTITY,
        [20.0, 10.0, TWO_PI],
        [TWO_PI; 3],
        &eta0,
        &vec![0.0; n],
    );
    let mut eom = Eom::new(model, FreeFlight).unwrap();
    let mut probe = Eom::new(model, FreeFlight).unwrap();
    let i0 = probe.invariants(&x).unwrap();
    let mut drift = Drift::default();
    let mut e_prev = i0.total_energy();
    let mut increases = 0;
    run(
        &mut eom,
        &mut tight(1e-10, 1e-12),
        &mut x,
        1.0,
        &mut |_, x, _| {
            let i = probe.invariants(x).unwrap();
            if i.total_energy() > e_prev * (1.0 + 1e-12) {
                increases += 1;
            }
            e_prev = i.total_energy();
            drift_of(&i0, &i, &mut drift);
            true
        },
    );
    assert_eq!(increases, 0);
    assert!(e_prev < i0.total_energy());
    assert!(drift.p_comp < 1e-6 && drift.h_comp < 1e-6, "{drift:?}");
}

#[test]
fn rigid_body_mass_centre_follows_the_parabola_under_uniform_gravity() {
    let model = rigid_part(sphads1());
    let l = StateLayout { n: 0 };
    let g = [0.0, 0.0, 9.806];
    let m = model.mass;
    let c = model.first_moment;
    for omega0 in [[0.0; 3], [0.3, -2.0, 1.5]] {
        let q0 = flexflight::runtime::kinematics::euler_parameters_from_angles(0.2, 0.4, -0.3);
        let v0 = [150.0, -4.0, 12.0];
        let mut x = l.state([1.0, 2.0, -300.0], q0, v0, omega0, &[], &[]);
        let cm = |x: &[f64]| -> [f64; 3] {
            let r = mat_t_vec(&c_bi(&[x[3], x[4], x[5], x[6]]), &c.map(|ci| ci / m));
            [x[0] + r[0], x[1] + r[1], x[2] + r[2]]
        };
        let p_cm0 = cm(&x);
        // Mass-centre velocity V + ω × c/m, in inertial axes.
        let w = omega0;
        let rc = c.map(|ci| ci / m);
        let vb = [
            v0[0] + w[1] * rc[2] - w[2] * rc[1],
            v0[1] + w[2] * rc[0] - w[0] * rc[2],
            v0[2] + w[0] * rc[1] - w[1] * rc[0],
        ];
        let v_cm0 = mat_t_vec(&c_bi(&q0), &vb);
        let mut eom = Eom::new(&model, UniformGravity::new(&model, g)).unwrap();
        let mut worst = 0.0f64;
        let r = run(
            &mut eom,
            &mut tight(1e-13, 1e-13),
            &mut x,
            3.0,
            &mut |t, x, _| {
                let p = cm(x);
                for k in 0..3 {
                    let exact = p_cm0[k] + v_cm0[k] * t + 0.5 * g[k] * t * t;
                    worst = worst.max((p[k] - exact).abs());
                }
                true
            },
        );
        eprintln!(
            "parabola omega0 {omega0:?}: max error {worst:e} m, {:?}",
            r.stats
        );
        assert!(worst < 1e-9, "{worst:e}");
    }
}

/// `(sn, cn, dn)(u | m)` by the arithmetic-geometric mean, Abramowitz & Stegun 16.4
/// (descending Landen transformation): `a_0 = 1, b_0 = √(1-m), c_0 = √m`, AGM to `c_N ≈ 0`,
/// `φ_N = 2^N a_N u`, `sin(2φ_{k-1} - φ_k) = (c_k/a_k) sin φ_k`, then `sn = sin φ_0`,
/// `cn = cos φ_0`, `dn = cos φ_0 / cos(φ_1 - φ_0)`.
fn jacobi_sn_cn_dn(u: f64, m: f64) -> (f64, f64, f64) {
    let mut a = [0.0f64; 16];
    let mut c = [0.0f64; 16];
    a[0] = 1.0;
    let mut b = (1.0 - m).sqrt();
    c[0] = m.sqrt();
    let mut n = 0;
    while c[n].abs() > 1e-16 && n < 15 {
        let an = 0.5 * (a[n] + b);
        c[n + 1] = 0.5 * (a[n] - b);
        b = (a[n] * b).sqrt();
        a[n + 1] = an;
        n += 1;
    }
    if n == 0 {
        // m = 0: sn = sin, cn = cos, dn = 1 (A&S 16.6.1-16.6.3 with m = 0).
        return (u.sin(), u.cos(), 1.0);
    }
    let mut phi = 2f64.powi(n as i32) * a[n] * u;
    let mut phi_prev = phi;
    for k in (1..=n).rev() {
        phi_prev = phi;
        phi = 0.5 * (phi + (c[k] / a[k] * phi.sin()).asin());
    }
    (phi.sin(), phi.cos(), phi.cos() / (phi_prev - phi).cos())
}

#[test]
fn jacobi_functions_match_tabulated_values() {
    // m = 0 and m = 1 limits, and sn²+cn² = 1, dn² + m sn² = 1 (A&S 16.9.1).
    let (s, c, d) = jacobi_sn_cn_dn(0.7, 0.0);
    assert!((s - 0.7f64.sin()).abs() < 1e-15 && (c - 0.7f64.cos()).abs() < 1e-15 && d == 1.0);
    // m → 1: sn → tanh, dn → sech (A&S 16.6.1, 16.6.3); the correction is O(1 - m).
    let (s, _, d) = jacobi_sn_cn_dn(0.7, 1.0 - 1e-12);
    assert!((s - 0.7f64.tanh()).abs() < 1e-11 && (d - 0.7f64.cosh().recip()).abs() < 1e-11);
    let (s, c, d) = jacobi_sn_cn_dn(1.3, 0.4);
    assert!((s * s + c * c - 1.0).abs() < 1e-15 && (d * d + 0.4 * s * s - 1.0).abs() < 1e-15);
    // d sn/du = cn dn by central difference.
    let h = 1e-5;
    let ds = (jacobi_sn_cn_dn(1.3 + h, 0.4).0 - jacobi_sn_cn_dn(1.3 - h, 0.4).0) / (2.0 * h);
    assert!((ds - c * d).abs() < 1e-9);
}

#[test]
fn torque_free_asymmetric_body_follows_jacobi_elliptic_solution() {
    // Principal inertias about the mass centre I1 < I2 < I3, mass centre off the origin.
    let (i1, i2, i3) = (1.0, 2.0, 3.0);
    let mass = 3.0;
    let c = [-4.5, 0.3, 0.0]; // first moment: mass centre at c/m
    let c2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    let mut inertia = [[0.0; 3]; 3];
    for i in 0..3 {
        for k in 0..3 {
            let jcm = if i == k { [i1, i2, i3][i] } else { 0.0 };
            // Parallel axis: J_o = J_cm + (|c|² 1 - c cᵀ)/m.
            inertia[i][k] = jcm + ((if i == k { c2 } else { 0.0 }) - c[i] * c[k]) / mass;
        }
    }
    let model = ReducedModel {
        mass,
        first_moment: c,
        inertia,
        ..rigid_part(sphads1())
    };
    let (w10, w30) = (2.0, 1.5);
    // Origin velocity chosen so the mass centre moves: V = v_cm - ω × c/m.
    let l = StateLayout { n: 0 };
    let mut x = l.state(
        [0.0; 3],
        IDENTITY,
        [5.0, -1.0, 2.0],
        [w10, 0.0, w30],
        &[],
        &[],
    );
    // Energy and momentum about the mass centre: 2E = Σ I ω², M² = Σ I² ω².
    let e2 = i1 * w10 * w10 + i3 * w30 * w30;
    let mm = (i1 * w10).powi(2) + (i3 * w30).powi(2);
    assert!(
        mm > e2 * i2,
        "this branch of the solution needs M² > 2 E I2"
    );
    let a1 = ((e2 * i3 - mm) / (i1 * (i3 - i1))).sqrt();
    let a2 = ((e2 * i3 - mm) / (i2 * (i3 - i2))).sqrt();
    let a3 = ((mm - e2 * i1) / (i3 * (i3 - i1))).sqrt();
    let rate = ((i3 - i2) * (mm - e2 * i1) / (i1 * i2 * i3)).sqrt();
    let k2 = (i2 - i1) * (e2 * i3 - mm) / ((i3 - i2) * (mm - e2 * i1));
    let mut eom = Eom::new(&model, FreeFlight).unwrap();
    let mut worst = 0.0f64;
    let r = run(
        &mut eom,
        &mut tight(1e-12, 1e-14),
        &mut x,
        10.0,
        &mut |t, x, _| {
            let (sn, cn, dn) = jacobi_sn_cn_dn(rate * t, k2);
            let exact = [a1 * cn, a2 * sn, a3 * dn];
            for k in 0..3 {
                worst = worst.max((x[10 + k] - exact[k]).abs());
            }
            true
        },
    );
    eprintln!(
        "Jacobi top: max |omega - exact| {worst:e} rad/s, {:?}",
        r.stats
    );
    assert!(worst < 1e-8, "{worst:e}");
}

#[test]
fn single_mode_oscillates_at_the_constrained_frequency() {
    let full = undamped(sphads1());
    // The mode with the strongest coupling to the rigid motion.
    let n = full.n();
    let coupling = |m: usize| -> f64 {
        (0..3)
            .map(|i| full.p_bar[i * n + m].powi(2) + full.h_bar[i * n + m].powi(2))
            .sum::<f64>()
            / full.modal_mass[m * n + m]
    };
    let mode = (0..n)
        .max_by(|a, b| coupling(*a).total_cmp(&coupling(*b)))
        .unwrap();
    let model = select_modes(&full, &[mode]);
    // Analytic: zero momentum ⇒ M_rr a_r + M_re η̈ = 0 ⇒ (M_ee - M_er M_rr⁻¹ M_re) η̈ = -K η.
    let mm = model.mass_matrix(&[0.0]).unwrap();
    let d = 7;
    let mut a = [[0.0f64; 7]; 6];
    for i in 0..6 {
        for k in 0..6 {
            a[i][k] = mm[i * d + k];
        }
        a[i][6] = mm[i * d + 6];
    }
    // Gaussian elimination of M_rr y = M_re.
    for p in 0..6 {
        for r in p + 1..6 {
            let f = a[r][p] / a[p][p];
            for k in p..7 {
                a[r][k] -= f * a[p][k];
            }
        }
    }
    let mut y = [0.0; 6];
    for p in (0..6).rev() {
        y[p] = (a[p][6] - (p + 1..6).map(|k| a[p][k] * y[k]).sum::<f64>()) / a[p][p];
    }
    let m_eff = mm[6 * d + 6] - (0..6).map(|i| mm[6 * d + i] * y[i]).sum::<f64>();
    let omega_exact = (model.modal_stiffness[0] / m_eff).sqrt();
    let omega_unconstrained = (model.modal_stiffness[0] / model.modal_mass[0]).sqrt();
    assert!(
        (omega_exact / omega_unconstrained - 1.0).abs() > 1e-4,
        "the rigid coupling must matter for this test to mean something"
    );
    let period = TWO_PI / omega_exact;
    let l = StateLayout { n: 1 };
    let eta0 = 1e-6 * model.modal_mass[0].sqrt().recip();
    let mut x = l.state([0.0; 3], IDENTITY, [0.0; 3], [0.0; 3], &[eta0], &[0.0]);
    let mut eom = Eom::new(&model, FreeFlight).unwrap();
    let mut dp = DormandPrince54::new(AdaptiveOptions {
        rtol: 1e-11,
        atol: 1e-11 * eta0,
        h_max: period / 40.0,
        ..Default::default()
    });
    // Downward zero crossings of η by cubic Hermite interpolation (η̇ is the slope).
    let mut prev: Option<(f64, f64, f64)> = None;
    let mut crossings = Vec::new();
    run(&mut eom, &mut dp, &mut x, 30.25 * period, &mut |t, x, _| {
        let (e, ed) = (x[13], x[14]);
        if let Some((t0, e0, ed0)) = prev {
            if e0 > 0.0 && e <= 0.0 {
                let h = t - t0;
                let p = |s: f64| {
                    let (s2, s3) = (s * s, s * s * s);
                    (2.0 * s3 - 3.0 * s2 + 1.0) * e0
                        + (s3 - 2.0 * s2 + s) * h * ed0
                        + (-2.0 * s3 + 3.0 * s2) * e
                        + (s3 - s2) * h * ed
                };
                let (mut lo, mut hi) = (0.0, 1.0);
                for _ in 0..80 {
                    let mid = 0.5 * (lo + hi);
                    if p(mid) > 0.0 { lo = mid } else { hi = mid }
                }
                crossings.push(t0 + 0.5 * (lo + hi) * h);
            }
        }
        prev = Some((t, e, ed));
        true
    });
    assert!(crossings.len() >= 30);
    let measured = (crossings.last().unwrap() - crossings[0]) / (crossings.len() - 1) as f64;
    let omega = TWO_PI / measured;
    let rel = (omega / omega_exact - 1.0).abs();
    eprintln!(
        "mode {mode}: omega exact {omega_exact} rad/s (unconstrained {omega_unconstrained}), \
         measured {omega}, relative error {rel:e}"
    );
    assert!(rel < 1e-6, "{rel:e}");
}

#[test]
fn two_runs_give_identical_bits() {
    let model = sphads1();
    let n = model.n();
    let l = StateLayout { n };
    let go = || {
        let mut x = l.state(
            [0.0; 3],
            IDENTITY,
            [20.0, 10.0, TWO_PI],
            [TWO_PI; 3],
            &vec![1e-4; n],
            &vec![0.0; n],
        );
        let mut eom = Eom::new(model, UniformGravity::new(model, [0.0, 0.0, 9.806])).unwrap();
        let r = run(
            &mut eom,
            &mut tight(1e-9, 1e-11),
            &mut x,
            0.5,
            &mut |_, _, _| true,
        );
        (x, r)
    };
    let (x1, r1) = go();
    let (x2, r2) = go();
    assert_eq!(r1, r2);
    assert!(x1.iter().zip(&x2).all(|(a, b)| a.to_bits() == b.to_bits()));
}

#[test]
#[ignore = "timing; run with --release -- --ignored --nocapture"]
fn rhs_cost_for_sphads1() {
    let model = sphads1();
    let n = model.n();
    let l = StateLayout { n };
    let x = l.state(
        [0.0; 3],
        IDENTITY,
        [20.0, 10.0, TWO_PI],
        [TWO_PI; 3],
        &vec![1e-4; n],
        &vec![1e-3; n],
    );
    let mut dx = vec![0.0; l.len()];
    let mut eom = Eom::new(model, UniformGravity::new(model, [0.0, 0.0, 9.806])).unwrap();
    let reps = 200_000;
    let t0 = std::time::Instant::now();
    for i in 0..reps {
        eom.rhs(i as f64 * 1e-9, &x, &mut dx).unwrap();
    }
    let per = t0.elapsed().as_secs_f64() / reps as f64;
    eprintln!(
        "RHS for sphads1 (n = {n}): {:.3} us per evaluation ({})",
        per * 1e6,
        dx[20]
    );
}
