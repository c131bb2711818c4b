//! Known answers of the planar models on hand-built parameters: decoupled and coupled
//! fin frequencies with the aerodynamics off, the rigid-fin limit, static divergence, the
//! determinant identity, and the unpinned axial mode.

use super::*;

/// Parameters with every aerodynamic and gravity term zero; the test sets what it needs.
fn quiet(kind: PlanarKind) -> PlanarParameters {
    let condition = FlightCondition {
        altitude: 0.0,
        speed: 100.0,
        mach: 0.3,
        density: 1.2,
        pressure: 101_325.0,
        temperature: 288.15,
        speed_of_sound: 340.0,
        dynamic_pressure: 0.0,
        gravity: 0.0,
    };
    PlanarParameters {
        kind,
        thickness: 1e-3,
        condition,
        mass_properties: PitchMassProperties {
            mass: 17.5,
            x_cg: -1.59,
            inertia: 11.6,
        },
        aero: AeroDerivatives {
            cn_alpha_body: 0.0,
            cm_alpha_body: 0.0,
            ca_body: 0.0,
            ca_mach_body: 0.0,
            ca_alpha_body: 0.0,
            cn_alpha_fin: 0.0,
            ca_fin: 0.0,
            ca_mach_fin: 0.0,
            ca_alpha_fin: 0.0,
            x_cp_fin: 0.0,
        },
        pitch_plane_fins: 2.0,
        fin_mass: 0.15,
        fin_stiffness: 9000.0,
        fin_bending_inertia: 0.0,
        x_cp_body: None,
        x_cp_fin: -2.6,
        a: None,
        d: 0.0,
        reference_area: 0.0127,
        fin_area: 0.028,
        reference_length: 0.127,
        body_lift: 0.0,
        fin_lift: 0.0,
        body_moment: 0.0,
        fin_axial_force: 0.0,
        axial_force: 0.0,
        weight: 0.0,
        axial_damping: 0.0,
        cn_alpha_dot: 0.0,
        cm_alpha_dot: 0.0,
        reference_x: -1.59,
    }
}

fn eig(p: &PlanarParameters) -> Vec<Eigenvalue> {
    analyse(p.clone()).unwrap().eigenvalues
}

/// The largest |Im| of the roots, and the smallest |lambda|.
fn max_im(ev: &[Eigenvalue]) -> f64 {
    ev.iter().map(|e| e.im.abs()).fold(0.0, f64::max)
}

#[test]
fn pinned_aero_off_decoupled_fin_is_sqrt_k_over_m() {
    // d = 0: M = diag(J, m_f), K = diag(0, k): lambda = +-i sqrt(k/m_f) and a double 0.
    let p = quiet(PlanarKind::Pinned);
    let ev = eig(&p);
    let w = (p.fin_stiffness / p.fin_mass).sqrt();
    assert!((max_im(&ev) - w).abs() < 1e-9 * w, "{ev:?}");
    assert!(ev.iter().all(|e| e.re.abs() < 1e-9 * w));
    let zeros = ev.iter().filter(|e| e.re.hypot(e.im) < 1e-6).count();
    assert_eq!(zeros, 2, "{ev:?}");
    assert_eq!(classify(&ev).class, Stability::Neutral);
}

#[test]
fn pinned_aero_off_coupled_fin_frequency() {
    // d != 0: the pitch inertia takes part. From det(K - w^2 M) = 0 with K = diag(0, k):
    // w^2 = k J / (m_f (J - m_f d^2)).
    let mut p = quiet(PlanarKind::Pinned);
    p.d = 1.0;
    let (j, mf, k) = (p.mass_properties.inertia, p.fin_mass, p.fin_stiffness);
    let w = (k * j / (mf * (j - mf))).sqrt();
    let ev = eig(&p);
    assert!((max_im(&ev) - w).abs() < 1e-9 * w, "{} vs {w}", max_im(&ev));
    // And it differs from the decoupled sqrt(k/m_f) by more than the tolerance.
    assert!((w - (k / mf).sqrt()).abs() > 1e-4 * w);
}

#[test]
fn unpinned_aero_off_coupled_fin_frequency_and_axial_mode() {
    // q = 0, g = 0: the delta row couples to v (m_f) and theta (-m_f d). With
    // v' = -m_f delta''/m and theta'' = m_f d delta''/J,
    // m_f (1 - m_f/m - m_f d^2/J) delta'' + k delta = 0.
    // The axial damping alone gives the real root -D_A/m.
    let mut p = quiet(PlanarKind::Unpinned);
    p.d = 0.9;
    p.axial_damping = 3.5;
    let (m, j, mf, k, d) = (
        p.mass_properties.mass,
        p.mass_properties.inertia,
        p.fin_mass,
        p.fin_stiffness,
        p.d,
    );
    let w = (k / (mf * (1.0 - mf / m - mf * d * d / j))).sqrt();
    let ev = eig(&p);
    assert_eq!(ev.len(), 6, "state (u, v, theta', delta', theta, delta)");
    assert!((max_im(&ev) - w).abs() < 1e-9 * w, "{} vs {w}", max_im(&ev));
    let axial = -p.axial_damping / m;
    assert!(
        ev.iter()
            .any(|e| (e.re - axial).abs() < 1e-9 && e.im == 0.0),
        "{ev:?}"
    );
}

#[test]
fn pinned_rigid_fin_limit_is_the_rigid_pitch_oscillator() {
    // k -> infinity: delta -> 0 and the pitch motion is J theta'' + c theta' + k_t theta = 0
    // with c = (a M_b + d^2 P_f)/V and k_t = d P_f - M_b.
    let mut p = quiet(PlanarKind::Pinned);
    p.d = 1.0;
    p.a = Some(0.9);
    p.fin_lift = 1800.0;
    p.body_lift = 570.0;
    p.body_moment = 0.9 * 570.0;
    p.fin_stiffness = 1e11;
    let v = p.condition.speed;
    let j = p.mass_properties.inertia;
    let c = (0.9 * p.body_moment + p.fin_lift) / v;
    let kt = p.fin_lift - p.body_moment;
    let re = -c / (2.0 * j);
    let im = (kt / j - re * re).sqrt();
    let ev = eig(&p);
    let slow = ev
        .iter()
        .min_by(|a, b| a.re.hypot(a.im).total_cmp(&b.re.hypot(b.im)))
        .unwrap();
    assert!((slow.re - re).abs() < 1e-4 * im, "{slow:?} vs {re} {im}");
    assert!(
        (slow.im.abs() - im).abs() < 1e-4 * im,
        "{slow:?} vs {re} {im}"
    );
    assert_eq!(classify(&ev).class, Stability::Stable);
}

#[test]
fn product_of_pinned_eigenvalues_is_det_k_over_det_m() {
    // For A of (6.13), det(A) = det(K)/det(M) (block determinant with [[M,0],[0,1]]).
    let mut p = quiet(PlanarKind::Pinned);
    p.d = 0.98;
    p.a = Some(0.87);
    p.fin_lift = 1860.0;
    p.body_lift = 570.0;
    p.body_moment = 0.87 * 570.0;
    p.fin_axial_force = 6.3;
    p.fin_stiffness = 1946.0;
    p.fin_mass = 0.0617;
    let r = analyse(p).unwrap();
    let det2 = |m: &Vec<Vec<f64>>| m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let expected = det2(&r.stiffness) / det2(&r.mass);
    // Product of complex eigenvalues (real for a real matrix).
    let (mut pr, mut pi) = (1.0, 0.0);
    for e in &r.eigenvalues {
        (pr, pi) = (pr * e.re - pi * e.im, pr * e.im + pi * e.re);
    }
    assert!(
        (pr - expected).abs() < 1e-9 * expected.abs(),
        "{pr} vs {expected}"
    );
    assert!(pi.abs() < 1e-9 * expected.abs());
}

#[test]
fn body_ahead_of_fins_without_fin_lift_diverges() {
    // A statically unstable pinned vehicle (body moment larger than the fin restoring
    // moment) has a real positive root: divergence.
    let mut p = quiet(PlanarKind::Pinned);
    p.d = 1.0;
    p.a = Some(0.9);
    p.body_lift = 570.0;
    p.body_moment = 0.9 * 570.0;
    p.fin_lift = 100.0;
    let ev = eig(&p);
    let v = classify(&ev);
    assert_eq!(v.class, Stability::Divergence, "{ev:?}");
    assert!(v.sigma_d > 0.0 && v.omega_d == 0.0);
}

#[test]
fn classification_rules() {
    let e = |re, im| Eigenvalue { re, im };
    assert_eq!(
        classify(&[e(-1.0, 2.0), e(-1.0, -2.0)]).class,
        Stability::Stable
    );
    let v = classify(&[e(-1.0, 0.0), e(0.5, 3.0), e(0.5, -3.0)]);
    assert_eq!(
        (v.class, v.sigma_d, v.omega_d),
        (Stability::Flutter, 0.5, 3.0)
    );
    let v = classify(&[e(2.0, 0.0), e(0.5, 3.0), e(0.5, -3.0)]);
    assert_eq!(
        (v.class, v.sigma_d, v.omega_d),
        (Stability::Divergence, 2.0, 0.0)
    );
}

#[test]
fn singular_mass_matrix_is_an_error() {
    // J = m_f d^2: the rest of the vehicle has no inertia; M is singular.
    let mut p = quiet(PlanarKind::Pinned);
    p.d = 2.0;
    p.mass_properties.inertia = p.fin_mass * 4.0;
    assert!(matches!(analyse(p), Err(PlanarError::MassMatrix { .. })));
}
