//! Aerodynamic data of the runtime force block: built-in estimator figures for the SPHADS-1
//! fin planform against hand calculations, and the estimator's tables written to CSV and read
//! back through the table reader.

use flexflight::aero::fin_loads::{centre_of_pressure, supersonic_regime};
use flexflight::aero::{
    BodyShape, CoefficientTable, EstimatedTables, FinNode, FinPlanform, NoseShape,
    SupersonicRegime, TableKind, nodal_weights,
};
use flexflight::check::ir::{Distribution, OutOfRange};

fn sphads_fin() -> FinPlanform {
    FinPlanform::unswept_trailing_edge(0.12723, 0.32468, 0.12267, 0.127 / 2.0)
}

fn sphads_body() -> BodyShape {
    // Length and diameter from Table 4.1; the nose length is our assumption (not stated).
    BodyShape {
        length: 2.75,
        diameter: 0.127,
        nose: NoseShape::Cone { length: 0.4 },
        reference_x: -1.59,
        transitions: vec![],
        roughness: flexflight::aero::estimator::DEFAULT_ROUGHNESS,
        guides: vec![],
        fin_sets: vec![],
    }
}

/// Cone wave drag of the SPHADS body (0.4 m nose) at M 2, computed by hand (see the test).
const WAVE_M2: f64 = 0.0900;

const S_REF: f64 = std::f64::consts::PI * 0.0635 * 0.0635;

#[test]
fn sphads_fin_normal_force_slope_hand_values() {
    // Hand calculation: A_f = (0.32468 + 0.12267)/2 * 0.12723 = 0.0284582 m^2,
    // S = pi 0.0635^2 = 0.0126677 m^2, A = 2 s^2/A_f = 1.137633,
    // Lambda_c = atan(((c_r - c_t) + c_t/2 - c_r/2)/s) = 38.4453 deg.
    // M = 0.5: beta = 0.866025, beta A / cos Lambda_c = 1.257893,
    //   C_Nalpha = 2 pi 1.137633 * 2.246518 / (2 + sqrt(4 + 1.582295)) = 3.68074 /rad.
    // K_T(B) = 1 + 0.0635/(0.12723 + 0.0635) = 1.332931.
    let f = sphads_fin();
    assert!(
        (f.cn_alpha(0.5, S_REF) - 3.680_74).abs() < 1e-5,
        "{}",
        f.cn_alpha(0.5, S_REF)
    );
    assert!((f.interference() - 1.332_931).abs() < 1e-6);
    // M = 2: the supersonic lifting surface (validated in panel::supersonic_tests), below
    // 2-D Ackeret, 4/sqrt(3) * 2.246518 = 5.18811 /rad, by the fin's Mach cones.
    let (slope, _) = f.supersonic_lifting_surface(2.0);
    let sup = f.cn_alpha(2.0, S_REF);
    assert!((sup - slope * 2.246_518).abs() < 1e-5 * sup, "{sup}");
    assert!(sup < 0.8 * 5.188_11, "{sup}");
    // Transonic blend: M = 1.0 is half way between the 0.9 and 1.1 values.
    let mid = 0.5 * (f.cn_alpha(0.9, S_REF) + f.cn_alpha(1.1, S_REF));
    assert!((f.cn_alpha(1.0, S_REF) - mid).abs() < 1e-12);
}

#[test]
fn sphads_fin_centre_of_pressure_hand_values() {
    // Barrowman x_f = x_t/3 (c_r + 2c_t)/(c_r + c_t) + (c_r + c_t - c_r c_t/(c_r + c_t))/6
    //  = 0.067337*1.274221 + 0.358318/6 = 0.085801 + 0.059720 = 0.145521 m;
    // supersonic: the lifting surface's, between the quarter and the half MAC
    // (MAC LE 0.085801, MAC = 0.238879: 0.145521 .. 0.205241 m).
    let f = sphads_fin();
    assert!((f.x_cp(0.5) - 0.145_521).abs() < 1e-6, "{}", f.x_cp(0.5));
    let x2 = f.x_cp(2.0);
    assert!(x2 > 0.145_521 && x2 < 0.205_241, "{x2}");
}

/// Issue 33: the fin of the M1670 4-fin rocket (span 102 mm, root 203, tip 76, leading edge
/// 38.8 deg, body 102 mm) had a per-fin slope of 2.2 times its Mach 0.9 value at Mach 1.2
/// (Ackeret's 2-D factor on a fin with a subsonic leading edge and beta A = 0.85). With the
/// lifting surface it stays within 30 % of the subsonic value (linear theory's slope peaks
/// near beta A = 1, here Mach 1.2) and falls with Mach above that.
#[test]
fn issue33_fin_slope_is_sensible_at_low_supersonic_mach() {
    let s = 0.102;
    let f = FinPlanform {
        span: s,
        root_chord: 0.203,
        tip_chord: 0.076,
        tip_le_offset: s * 38.8f64.to_radians().tan(),
        body_radius: 0.051,
        outline: flexflight::check::ir::FinOutline::Trapezoidal,
    };
    let s_ref = std::f64::consts::PI * 0.051 * 0.051;
    let at = |m: f64| f.interference() * f.cn_alpha(m, s_ref);
    let machs = [0.9, 1.1, 1.2, 1.5, 2.0, 3.0];
    let v: Vec<f64> = machs.iter().map(|&m| at(m)).collect();
    eprintln!("issue-33 fin C_Nalpha K_T(B) on S over {machs:?}: {v:?}");
    assert!(v[2] / v[0] < 1.3 && v[1] / v[0] > 0.9, "{v:?}");
    assert!(v.windows(2).skip(2).all(|w| w[1] < w[0]), "{v:?}");
}

#[test]
fn sphads_fin_load_distribution_figures() {
    let f = sphads_fin();
    let (eta_sub, xi_sub) = centre_of_pressure(&f, 0.5).unwrap();
    let (eta_sup, xi_sup) = centre_of_pressure(&f, 2.0).unwrap();
    println!("SPHADS-1 span cp: M 0.5 eta {eta_sub:.5}, M 2 eta {eta_sup:.5}");
    assert_eq!((xi_sub, xi_sup), (0.25, 0.5));
    // A tapered fin loads its root: the span cp lies inboard of the elliptic 4/(3 pi).
    assert!(
        eta_sub > 0.3 && eta_sub < 4.0 / (3.0 * std::f64::consts::PI),
        "{eta_sub}"
    );
    assert!(eta_sup > 0.3 && eta_sup < 0.5, "{eta_sup}");
    assert_eq!(supersonic_regime(&f, 2.0), Some(SupersonicRegime::C));
    // A 6 x 4 element mesh reproduces the model cp.
    let nodes: Vec<FinNode> = (0..=6)
        .flat_map(|i| {
            (0..=4).map(move |j| FinNode {
                eta: i as f64 / 6.0,
                xi: j as f64 / 4.0,
            })
        })
        .collect();
    for (m, eta_cp) in [(0.5, eta_sub), (2.0, eta_sup)] {
        let w = nodal_weights(&f, &nodes, m, Distribution::Theory).unwrap();
        let e: f64 = nodes.iter().zip(&w).map(|(n, w)| n.eta * w).sum();
        assert!((e - eta_cp).abs() < 1e-6, "M {m}: {e} vs {eta_cp}");
    }
}

#[test]
fn sphads_body_hand_values() {
    let b = sphads_body();
    let est = EstimatedTables::estimate(&b, &sphads_fin(), OutOfRange::Stop).unwrap();
    // alpha = 2 deg: potential C_N = sin 4deg cos 1deg = 0.069756*0.999848 = 0.069745;
    // crossflow 1.2 (A_p/S) sin^2 2deg with A_p = 0.127*(2.75 - 0.4) + 0.5*0.127*0.4 = 0.323850,
    // A_p/S = 25.5651: 1.2*25.5651*0.00121797 = 0.037365. Total 0.107110.
    let c = est.body.body(0.5, 2.0, 0.0).unwrap();
    assert!((c.cn - 0.107_110).abs() < 2e-6, "{}", c.cn);
    // Nose force ahead of the c.g. (x = -0.26667 vs -1.59) pitches nose up.
    assert!(c.cm > 0.0);
    // Base drag at M 0.5: 0.12 + 0.13*0.25 = 0.1525; the rest is skin friction (positive).
    assert!(c.ca > 0.1525 && c.ca < 0.6, "{}", c.ca);
    // M 2: base 0.25/2 = 0.125 plus cone wave drag (1.59 + 1.83/4) atan(0.5/3.149606)^1.69
    // = 2.0475 * 0.157436^1.69 = 0.0900 (hand), plus positive skin friction.
    let ca2 = est.body.body(2.0, 0.0, 5000.0).unwrap().ca;
    assert!(
        ca2 > 0.125 + WAVE_M2 && ca2 < 0.125 + WAVE_M2 + 0.3,
        "{ca2}"
    );
    // Fin table: C_N = K_T C_Nalpha alpha at M 2, alpha 4 deg (K_T = 1.332931, C_Nalpha of
    // the lifting surface, checked in sphads_fin_normal_force_slope_hand_values).
    let f = sphads_fin();
    let fin = est.fin.fin(2.0, 4.0, 0.0).unwrap();
    let want = 1.332_931 * f.cn_alpha(2.0, S_REF) * 4f64.to_radians();
    assert!((fin.cn - want).abs() < 1e-5, "{} vs {want}", fin.cn);
    assert!((fin.x_cp_m - f.x_cp(2.0)).abs() < 1e-12);
}

#[test]
fn estimator_tables_write_and_read_back() {
    let est = EstimatedTables::estimate(&sphads_body(), &sphads_fin(), OutOfRange::Clamp).unwrap();
    let dir = tempfile::tempdir().unwrap();
    est.write(dir.path()).unwrap();
    let body = CoefficientTable::read_csv(
        TableKind::Body,
        &dir.path().join("body.csv"),
        OutOfRange::Clamp,
    )
    .unwrap();
    let fin = CoefficientTable::read_csv(
        TableKind::Fin,
        &dir.path().join("fins.csv"),
        OutOfRange::Clamp,
    )
    .unwrap();
    for (m, a, h) in [
        (0.5, 3.0, 1000.0),
        (2.2, -7.5, 12_000.0),
        (0.95, 19.0, 25_000.0),
    ] {
        assert_eq!(
            body.lookup(m, a, h).unwrap(),
            est.body.lookup(m, a, h).unwrap()
        );
        assert_eq!(
            fin.lookup(m, a, h).unwrap(),
            est.fin.lookup(m, a, h).unwrap()
        );
    }
    let text = std::fs::read_to_string(dir.path().join("body.csv")).unwrap();
    assert!(text.lines().nth(1) == Some("mach,alpha_deg,altitude_m,cn,ca,cm,cn_q,cm_q"));
    assert_eq!(
        body.body_rates(0.95, 19.0, 25_000.0).unwrap(),
        est.body.body_rates(0.95, 19.0, 25_000.0).unwrap()
    );
}

/// The SPHADS-1 body of `vehicles/sphads1.vdl` (0.45 m cone nose).
fn sphads1_vdl_body() -> BodyShape {
    BodyShape {
        length: 2.75,
        diameter: 0.127,
        nose: NoseShape::Cone { length: 0.45 },
        reference_x: -1.59,
        transitions: vec![],
        roughness: flexflight::aero::estimator::DEFAULT_ROUGHNESS,
        guides: vec![],
        fin_sets: vec![],
    }
}

#[test]
fn body_rate_derivatives_hand_values() {
    use flexflight::aero::estimator::body_rate_derivatives;
    // Hand calculation, d = 0.127 m, l = 2.75 m, L_n = 0.45 m, s_r = 1.59 m (reference point
    // aft of the nose), S = pi d^2/4 = 0.01266768698 m^2, A_b = S.
    // Vol/S = L_n/3 + (l - L_n) = 0.15 + 2.30 = 2.45 m; l - s_r = 1.16 m.
    // Potential (slender body):
    //   C_Nq + C_Nadot = 4 (1.16 + 2.45)/0.127 = 14.44/0.127 = 113.7007874,
    //   C_mq + C_madot = -4 (1.16/0.127)^2 = -4 * 1.3456/0.016129 = -333.7094674.
    // Crossflow at alpha = 10 deg: |sin a| cos a = 0.1736482 * 0.9848078 = 0.1710101,
    //   k = 4 * 1.2 * 0.1710101 = 0.8208483;
    //   I_1 = d (L_n^2/3 - s_r L_n/2) + d ((l - s_r)^2 - (L_n - s_r)^2)/2
    //       = 0.127 (0.0675 - 0.35775) + 0.127 (1.3456 - 1.2996)/2 = -0.03686175 + 0.002921
    //       = -0.03394075 m^2,
    //   I_2 = d (L_n^3/4 - 2 s_r L_n^2/3 + s_r^2 L_n/2) + d ((l - s_r)^3 - (L_n - s_r)^3)/3
    //       = 0.127 (0.02278125 - 0.21465 + 0.5688225) + 0.127 (1.560896 + 1.481544)/3
    //       = 0.04787313 + 0.12879663 = 0.17666975 m^3;
    //   S d = 0.001608796, S d^2 = 0.0002043171:
    //   C_Nq = 113.7007874 + 0.8208483 (-0.03394075)/0.001608806 = 113.7007874 - 17.3174251
    //        = 96.3833623,
    //   C_mq = -333.7094674 - 0.8208483 * 0.17666975/0.0002043184 = -333.7094674 - 709.7744516
    //        = -1043.4839190.
    let b = sphads1_vdl_body();
    let [cn0, cm0] = body_rate_derivatives(&b, 0.0);
    assert!((cn0 / 113.7007874 - 1.0).abs() < 1e-9, "{cn0}");
    assert!((cm0 / -333.7094674 - 1.0).abs() < 1e-9, "{cm0}");
    let [cn10, cm10] = body_rate_derivatives(&b, 10.0);
    assert!((cn10 / 96.3833623 - 1.0).abs() < 1e-9, "{cn10}");
    assert!((cm10 / -1043.4839190 - 1.0).abs() < 1e-9, "{cm10}");
    // Even in alpha (the body block queries the total angle of attack, >= 0).
    assert_eq!(body_rate_derivatives(&b, -10.0), [cn10, cm10]);
    // The estimator's body table carries them as its rate columns (exact at grid points).
    let tables = EstimatedTables::estimate(&b, &sphads_fin(), OutOfRange::Clamp).unwrap();
    let r = tables.body.body_rates(0.7, 10.0, 5000.0).unwrap().unwrap();
    assert_eq!([r.cn_q, r.cm_q], [cn10, cm10]);
    assert!(tables.fin.body_rates(0.7, 10.0, 5000.0).unwrap().is_none());
}

#[test]
fn fin_rate_derivatives_hand_values() {
    use flexflight::aero::estimator::fin_rate_derivatives;
    // SPHADS-1 fins at Mach 0.6 (root leading edge at x = -2.75 + 0.32468 = -2.42532 m):
    // beta = 0.8, A = 1.137633, Lambda_c = 38.4453 deg (cos = 0.783180),
    //   beta A / cos Lambda_c = 1.162053, C_Nalpha,1 = 2 pi 1.137633 * 2.246518
    //   / (2 + sqrt(4 + 1.350367)) = 16.057959/4.313052 = 3.723099 /rad;
    // K_T(B) = 1.332931; x_cp = x_le(MAC) + MAC/4 = 0.0830049 + 0.2501645/4 = 0.1455210 m aft
    // of the root leading edge, at x = -2.5708410 m: arm l_f = 0.9808410 m, l_f/d = 7.723158;
    // two fins in the pitch plane (n_eff = 2): slope = 2 * 1.332931 * 3.723099 = 9.925207;
    // C_Nq = 2 * 9.925207 * 7.723158 = 153.30885, C_mq = -2 * 9.925207 * 7.723158^2
    // = -1184.0285.
    let f = sphads_fin();
    let [cn, cm] = fin_rate_derivatives(&f, S_REF, 0.127, -2.42532, -1.59, 2.0, 0.6);
    assert!((cn / 153.30885 - 1.0).abs() < 1e-7, "{cn}");
    assert!((cm / -1184.0285 - 1.0).abs() < 1e-7, "{cm}");
}

/// FNV-1a of a text (a stable digest without dependencies).
fn fnv1a(text: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The built-in tables of SPHADS-1 (a conical nose) are those the estimator gave before
/// nose shapes and fin profiles existed (issue 34; but for the friction law, below), bit for
/// bit: the body table as the vehicle flies it, and the fin table of the flat plate (`EstimatedTables::estimate`, no
/// profile), against the FNV-1a digests of `aero_tables/body.csv` and `fins.csv` written by
/// the debug binary of main at commit cbf2126 (`flexflight run examples/thesis/section_6_5.vdl
/// --scenario subsonic_t04 --set run.stop_time=0.002s`). So the conical nose needs no
/// aerodynamics cache revision; the fin table with the fin's thickness does (revision 4).
/// Re-recorded for the skin friction by Reynolds number and roughness (revision 6): with
/// `skin_friction` set back to Prandtl-Schlichting and `body_friction_correction` to 1 by a
/// temporary patch (the fins' friction then still on their chord's Reynolds number), both
/// old digests (0xa296_01bf_40f6_9590, 0x0568_29ce_1d50_91c7) returned, so the friction law
/// is the only change in these tables; the fin table's digest moved once more when the fins'
/// friction took the rocket's Reynolds number (the body table's did not). Re-recorded for
/// the tables over every flow direction (revision 8): with `axial_scaling` returning 1,
/// `fin_incidence` the angle itself and `estimator_alpha` the old -20..20 deg grid (a
/// temporary patch), both digests above returned, and `fin_models::key_node_history_is_unchanged`
/// passed unchanged: those three are the only changes in these tables.
#[test]
fn conical_nose_tables_are_bit_identical_to_before_nose_shapes() {
    use flexflight::check::{DiskLoader, check_files};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("vehicles/sphads1.vdl");
    let c = check_files(&[path], &[], &DiskLoader);
    assert!(!c.has_errors());
    let v = &c.program.vehicles[0];
    let flown = flexflight::runtime::forces::aero_tables(v).unwrap();
    let [(_, body), _] = flown.files();
    assert_eq!(
        fnv1a(&body),
        0xdd4a_33e7_4872_c712,
        "the conical body table changed"
    );
    // The same planform as a flat plate: the old fin table.
    let r = 0.5 * 0.127;
    let plate = EstimatedTables::estimate(
        &BodyShape {
            length: 2.75,
            diameter: 0.127,
            nose: NoseShape::Cone { length: 0.45 },
            reference_x: -1.59,
            transitions: vec![],
            roughness: flexflight::aero::estimator::DEFAULT_ROUGHNESS,
            guides: vec![],
            fin_sets: vec![],
        },
        &flexflight::aero::estimator::planform(v.fins.as_ref().unwrap(), r),
        OutOfRange::Clamp,
    )
    .unwrap();
    let [(_, body2), (_, fins)] = plate.files();
    assert_eq!(body2, body);
    assert_eq!(
        fnv1a(&fins),
        0xa503_87ea_2670_ed85,
        "the flat-plate fin table changed"
    );
    // With the fin's 0.6 mm square edges the fin table is another (more drag).
    let [_, (_, fins_flown)] = flown.files();
    assert_ne!(fins_flown, fins);
}

/// Barrowman's nose centre of pressure x_cp = L - V/A_base (Niskanen 2009, sec. 3.2.1) for the
/// nose shapes whose volume has a closed form (derived in `check::nose`'s tests): the cone
/// 2L/3, the half-ellipsoid L/3 (V = 2/3 pi R^2 L), the full parabola 7L/15 (V = 8/15 pi R^2
/// L), the power series 2nL/(2n + 1) (V = pi R^2 L/(2n + 1)), the von Karman nose L/2
/// (V = pi R^2 L/2). The normal-force slope is 2 /rad for each (the potential term does not
/// depend on the shape: checked on the tables at Mach 0.5, where the tables of two shapes
/// differ in C_N only by the crossflow term of their side views).
#[test]
fn nose_centre_of_pressure_follows_the_volume() {
    use flexflight::aero::estimator::nose_centre_of_pressure;
    use flexflight::check::ir::NoseShape as Shape;
    let (l, d) = (0.4, 0.102);
    for (shape, xcp) in [
        (Shape::Conical, 2.0 / 3.0),
        (Shape::Elliptical, 1.0 / 3.0),
        (Shape::Parabolic { k: 1.0 }, 7.0 / 15.0),
        (Shape::Power { n: 0.5 }, 0.5),
        (Shape::Power { n: 0.75 }, 0.6),
        (Shape::Haack { c: 0.0 }, 0.5),
    ] {
        let (len, x) = nose_centre_of_pressure(NoseShape::Profile { length: l, shape }, d);
        assert_eq!(len, l);
        assert!(
            (-x / l - xcp).abs() < 1e-12,
            "{shape:?}: {} L against {xcp} L",
            -x / l
        );
    }
    // The profile path agrees with the cone's own.
    let (_, cone) = nose_centre_of_pressure(NoseShape::Cone { length: l }, d);
    assert!((cone + 2.0 / 3.0 * l).abs() < 1e-15);
}

/// Fin drag sees thickness (issue 34): the 3.2 mm fin has more axial force than the 1.6 mm
/// fin of the same planform at every Mach of the grid, for every cross-section; square edges
/// more than rounded, rounded more than an airfoil's up to Mach 1; and without a profile the
/// estimator's flat plate of the old tables.
#[test]
fn the_thicker_fin_has_more_axial_force() {
    use flexflight::aero::estimator::{ESTIMATOR_MACH, FinProfile, fin_axial};
    use flexflight::check::ir::FinSection;
    let f = sphads_fin();
    let p = |t: f64, section| {
        Some(FinProfile {
            thickness: t,
            section,
        })
    };
    for &m in &ESTIMATOR_MACH {
        for section in [FinSection::Square, FinSection::Rounded, FinSection::Airfoil] {
            let thin = fin_axial(&f, p(1.6e-3, section), 60e-6, 2.75, S_REF, m, 1000.0);
            let thick = fin_axial(&f, p(3.2e-3, section), 60e-6, 2.75, S_REF, m, 1000.0);
            assert!(thick > thin, "M {m} {section:?}: {thick} vs {thin}");
            let flat = fin_axial(&f, None, 60e-6, 2.75, S_REF, m, 1000.0);
            assert!(thin > flat, "M {m} {section:?}");
        }
        let sq = fin_axial(
            &f,
            p(3.2e-3, FinSection::Square),
            60e-6,
            2.75,
            S_REF,
            m,
            1000.0,
        );
        let ro = fin_axial(
            &f,
            p(3.2e-3, FinSection::Rounded),
            60e-6,
            2.75,
            S_REF,
            m,
            1000.0,
        );
        let af = fin_axial(
            &f,
            p(3.2e-3, FinSection::Airfoil),
            60e-6,
            2.75,
            S_REF,
            m,
            1000.0,
        );
        assert!(sq > ro, "M {m}: {sq} {ro}");
        // The airfoil differs from the rounded section by its trailing edge (none against
        // half the base drag) and, above Mach 1, its thickness wave drag on the planform
        // (`thickness_wave_drag`, tests/drag.rs), which can outweigh the rounded edge's.
        let (mac, _) = f.mean_aerodynamic_chord();
        let wave = flexflight::aero::estimator::thickness_wave_drag(
            FinSection::Airfoil,
            3.2e-3 / mac,
            f.mid_chord_sweep(),
            m,
        );
        let te = flexflight::aero::estimator::trailing_edge_drag(FinSection::Rounded, m);
        let want = (wave * f.area() - te * 3.2e-3 * f.span) / S_REF;
        assert!(((af - ro) - want).abs() < 1e-15, "M {m}: {af} {ro} {want}");
        if m <= 1.0 {
            assert!(ro >= af && wave == 0.0, "M {m}: {ro} {af} {wave}");
        }
    }
}

/// The edge drags against the formulas of Niskanen 2009 (sec. 3.4.4, App. B.1, eq. 3.94),
/// evaluated by hand: the square leading edge 0.85 q_stag/q, 0.85 at rest and 0.85 * 1.275
/// = 1.08375 at Mach 1- (1 + 1/4 + 1/40); at Mach 2, q_stag/q = 1.84 - 0.19 + 0.010375 +
/// 0.000546875 = 1.660921875. Barrowman's rounded edge: 0 at rest, (0.75)^-0.417 - 1 =
/// 0.127456 at Mach 0.5, continuous at Mach 0.9 (0.998 and 1) and at Mach 1 (0.8215 from
/// both sides: 1 - 0.1785, 1.214 - 0.502 + 0.1095). The base drag 0.12 at rest, 0.25 at
/// Mach 1 from both sides. One fin's pressure term on S is (LE cos^2 Gamma + TE) t s / S.
#[test]
fn fin_edge_drags_follow_the_cited_formulas() {
    use flexflight::aero::estimator::{
        FinProfile, base_drag, fin_axial, leading_edge_drag, stagnation_pressure_ratio,
        trailing_edge_drag,
    };
    use flexflight::check::ir::FinSection::{Airfoil, Rounded, Square};
    assert_eq!(leading_edge_drag(Square, 0.0), 0.85);
    assert!((leading_edge_drag(Square, 0.999_999_999) - 1.083_75).abs() < 1e-8);
    assert!((stagnation_pressure_ratio(2.0) - 1.660_921_875).abs() < 1e-15);
    assert_eq!(leading_edge_drag(Rounded, 0.0), 0.0);
    assert!((leading_edge_drag(Rounded, 0.5) - 0.127_456).abs() < 1e-6);
    assert!((leading_edge_drag(Rounded, 0.899_999_999) - 0.998_8).abs() < 1e-3);
    assert!((leading_edge_drag(Rounded, 0.9) - 1.0).abs() < 1e-15);
    let below = leading_edge_drag(Rounded, 1.0 - 1e-12);
    let above = leading_edge_drag(Airfoil, 1.0);
    assert!((below - 0.8215).abs() < 1e-9 && (above - 0.8215).abs() < 1e-12);
    assert_eq!(base_drag(0.0), 0.12);
    assert!((base_drag(1.0 - 1e-12) - 0.25).abs() < 1e-9 && base_drag(1.0) == 0.25);
    assert_eq!(trailing_edge_drag(Rounded, 0.0), 0.06);
    assert_eq!(trailing_edge_drag(Airfoil, 2.0), 0.0);
    // The pressure term of a square 3.2 mm SPHADS fin at Mach 2 on S, by hand: Gamma_L =
    // atan(x_t/s) with x_t = c_r - c_t = 0.20201 m, s = 0.12723 m: cos^2 = s^2/(s^2 + x_t^2)
    // = 0.0161875/(0.0161875 + 0.0408080) = 0.284013; (0.85 * 1.660921875 * 0.284013 +
    // 0.125) * 0.0032 * 0.12723 / 0.0126677 = 0.0169044.
    let f = sphads_fin();
    let p = |t| {
        Some(FinProfile {
            thickness: t,
            section: Square,
        })
    };
    // The friction part scales with (1 + 2t/c_mac); remove it with the zero-thickness profile.
    let with = fin_axial(&f, p(3.2e-3), 60e-6, 2.75, S_REF, 2.0, 1000.0);
    let (mac, _) = f.mean_aerodynamic_chord();
    let friction0 = fin_axial(&f, None, 60e-6, 2.75, S_REF, 2.0, 1000.0);
    let pressure = with - friction0 * (1.0 + 2.0 * 3.2e-3 / mac);
    assert!((pressure - 0.016_904_4).abs() < 1e-7, "{pressure}");
}

/// The built-in tables answer every flow direction (a tumbling or tail-first fall), and there
/// the axial force opposes the flow: `C_A cos(alpha) > 0` away from 90 deg, for the body and
/// for a fin at its own angle of attack; Niskanen's scaling mirrored, `C_A(180 - a) =
/// -C_A(a)`; the fin's normal force that of the mirrored angle for air from its trailing
/// edge, `C_N(180 - a) = C_N(a)`; and both normal forces vanish with the crossflow at
/// +-180 deg. On the old code the tables ended at 20 deg (with `stop`, 30 deg was refused).
#[test]
fn builtin_tables_cover_every_flow_direction_with_the_axial_force_against_the_flow() {
    let est = EstimatedTables::estimate(&sphads_body(), &sphads_fin(), OutOfRange::Stop).unwrap();
    for m in [0.1, 0.5, 0.95, 1.5, 3.0] {
        for h in [0.0, 12_000.0] {
            for k in -72..=72 {
                let a = 2.5 * f64::from(k);
                let b = est.body.body(m, a, h).unwrap();
                let f = est.fin.fin(m, a, h).unwrap();
                let c = a.to_radians().cos();
                if c.abs() > 1e-6 {
                    assert!(b.ca * c > 0.0, "body M {m} alpha {a}: ca {}", b.ca);
                    assert!(f.ca * c > 0.0, "fin M {m} alpha {a}: ca {}", f.ca);
                } else {
                    assert!(b.ca.abs() < 1e-15 && f.ca.abs() < 1e-15, "alpha {a}");
                }
            }
            // Grid angles whose mirror 180 - a is a grid angle too.
            for a in [0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0] {
                for s in [1.0, -1.0] {
                    let (b1, b2) = (
                        est.body.body(m, s * a, h).unwrap(),
                        est.body.body(m, s * (180.0 - a), h).unwrap(),
                    );
                    assert!((b1.ca + b2.ca).abs() < 1e-12 * b1.ca.abs().max(1.0), "{a}");
                    let (f1, f2) = (
                        est.fin.fin(m, s * a, h).unwrap(),
                        est.fin.fin(m, s * (180.0 - a), h).unwrap(),
                    );
                    assert!((f1.ca + f2.ca).abs() < 1e-12, "fin ca at {a}");
                    assert!((f1.cn - f2.cn).abs() < 1e-12, "fin cn at {a}");
                }
            }
            for a in [180.0, -180.0] {
                assert!(est.body.body(m, a, h).unwrap().cn.abs() < 1e-12);
                assert!(est.fin.fin(m, a, h).unwrap().cn.abs() < 1e-12);
            }
            // Past the stall the fin's normal force is held at its 20-degree value.
            let stall = est.fin.fin(m, 20.0, h).unwrap().cn;
            for a in [30.0, 60.0, 90.0, 120.0, 160.0] {
                assert_eq!(est.fin.fin(m, a, h).unwrap().cn, stall, "{a}");
            }
        }
    }
}

/// Niskanen's axial scaling as the technical documentation states its conditions: 1 at 0,
/// 1.3 at 17 deg and 0 at 90 deg, with a zero slope at all three (one-sided differences of
/// 1e-5 deg on each side: their error, h |f''| / 2, is below 3.2e-8 per deg), continuous at
/// 17 deg, odd about 90 deg and even in alpha.
#[test]
fn the_axial_scaling_meets_the_published_conditions() {
    use flexflight::aero::estimator::axial_scaling as f;
    assert_eq!(f(0.0), 1.0);
    assert!((f(17.0) - 1.3).abs() < 1e-15);
    assert_eq!(f(90.0), 0.0);
    let h = 1e-5;
    for a in [0.0, 17.0, 90.0] {
        for slope in [(f(a + h) - f(a)) / h, (f(a) - f(a - h)) / h] {
            assert!(slope.abs() < 3.2e-8, "slope {slope} at {a} deg");
        }
    }
    assert!((f(17.0 - 1e-9) - f(17.0 + 1e-9)).abs() < 1e-9);
    for k in 0..=180 {
        let a = f64::from(k);
        assert_eq!(f(-a), f(a));
        assert!((f(180.0 - a) + f(a)).abs() < 1e-15, "{a}");
        if a < 90.0 {
            assert!(f(a) > 0.0 && f(a) <= 1.3 + 1e-15, "{a}");
        }
    }
}
