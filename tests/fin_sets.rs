//! Issue 34, item 2: any number of fin sets. Further sets are named `fins` blocks
//! (`fins canards { ... }`) beside the unnamed one (the flexible, meshed set), checked by the
//! same code (`check::fin_sets`), rigid in the flight: their mass a rigid body on the body
//! (`structure::generate`), their aerodynamics in the built-in estimator's body table
//! (`aero::estimator`). Checked against hand values (planform area x thickness x density x
//! count; Barrowman's slope and centre of pressure).

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use flexflight::check::ir;
use flexflight::check::{DiskLoader, check_files};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Four trapezoidal canards of 2.5 mm aluminium, their root trailing edge 0.65 m aft of the
/// tip (0.2 m behind the nose's base), turned 45 deg from the main fins' first.
const CANARDS: &str = "  fins canards {
    count = 4
    span = 60 mm
    root_chord = 80 mm
    tip_chord = 40 mm
    leading_edge_sweep = 30 deg
    thickness = 2.5 mm
    root_trailing_edge = -0.65 m
    angles = [45 deg, 135 deg, 225 deg, 315 deg]
    material = aluminium_6061_t6
  }

";

/// Where the further blocks go: after the unnamed `fins` block of the HPR example.
const ANCHOR: &str = "  # AeroTech K1000T, 75 mm x 396 mm";

/// The HPR K1000 example (its motor files copied along) with `blocks` inserted after its
/// `fins` block, written to `dir/name.vdl`.
fn hpr_with(dir: &Path, name: &str, blocks: &str) -> PathBuf {
    let text = std::fs::read_to_string(repo("examples/hpr_k1000/hpr_k1000.vdl")).unwrap();
    for e in std::fs::read_dir(repo("examples/hpr_k1000")).unwrap() {
        let p = e.unwrap().path();
        if p.is_file() {
            std::fs::copy(&p, dir.join(p.file_name().unwrap())).unwrap();
        }
    }
    assert_eq!(text.matches(ANCHOR).count(), 1);
    let t = text.replacen(ANCHOR, &format!("{blocks}{ANCHOR}"), 1);
    let p = dir.join(format!("{name}.vdl"));
    std::fs::write(&p, t).unwrap();
    p
}

/// The 1-based line of the last occurrence of `needle` in the file `p`.
fn line_of(p: &Path, needle: &str) -> usize {
    let text = std::fs::read_to_string(p).unwrap();
    let at = text.rfind(needle).unwrap();
    text[..at].matches('\n').count() + 1
}

fn checked(p: &Path, sets: &[&str]) -> flexflight::check::Checked {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    check_files(&[p.to_path_buf()], &sets, &DiskLoader)
}

fn codes(c: &flexflight::check::Checked) -> Vec<(&'static str, String)> {
    c.diagnostics
        .iter()
        .map(|d| (d.code, d.message.clone()))
        .collect()
}

fn vehicle(c: &flexflight::check::Checked) -> &ir::Vehicle {
    assert!(!c.has_errors(), "{:?}", codes(c));
    &c.program.vehicles[0]
}

// ---- the language and check ------------------------------------------------------------------

/// A named `fins` block is a further set with the fields of `fins`, checked by the same code
/// (SI values, the default angles); the unnamed block stays the vehicle's flexible set; a
/// warning at `check` says the further set is rigid. On the old checker the second block was
/// read as nothing: no set, no warning.
#[test]
fn a_named_fins_block_is_a_further_rigid_set_with_the_fields_of_fins() {
    let dir = tempfile::tempdir().unwrap();
    let p = hpr_with(dir.path(), "canards", CANARDS);
    let c = checked(&p, &[]);
    let v = vehicle(&c);
    let primary = v.fins.as_ref().unwrap();
    assert_eq!(primary.count.value, 3);
    assert_eq!(v.fin_sets.len(), 1);
    let s = &v.fin_sets[0];
    assert_eq!(s.name.value, "canards");
    let f = &s.fins;
    assert_eq!(f.count.value, 4);
    assert!((f.span.value - 0.060).abs() < 1e-15);
    assert!((f.root_chord.value - 0.080).abs() < 1e-15);
    assert!((f.tip_chord.value - 0.040).abs() < 1e-15);
    assert!((f.thickness.value - 0.0025).abs() < 1e-15);
    assert!((f.leading_edge_sweep.value - 30f64.to_radians()).abs() < 1e-15);
    assert!((f.root_trailing_edge_x.value + 0.65).abs() < 1e-15);
    assert_eq!(f.material.name.value, "aluminium_6061_t6");
    assert!((f.angles[1].value - 135f64.to_radians()).abs() < 1e-15);
    let warn: Vec<_> = c
        .diagnostics
        .iter()
        .filter(|d| d.code == "vdl::fins::rigid_set")
        .collect();
    assert_eq!(warn.len(), 1, "{:?}", codes(&c));
    assert!(!warn[0].is_error());
    // The other outlines and fields of `fins` are the same code's: an elliptical, rounded
    // set with its own E.
    let ell = CANARDS
        .replacen("    tip_chord = 40 mm\n", "    planform = elliptical\n", 1)
        .replacen(
            "    leading_edge_sweep = 30 deg\n",
            "    cross_section = rounded\n    E = 69 GPa\n",
            1,
        );
    let p = hpr_with(dir.path(), "elliptical", &ell);
    let c = checked(&p, &[]);
    let f = &vehicle(&c).fin_sets[0].fins;
    assert!(!f.outline.is_trapezoidal());
    assert_eq!(f.cross_section.value, ir::FinSection::Rounded);
    assert!((f.material.youngs_modulus.value - 69e9).abs() < 1.0);
}

/// `--set`, `with`, sweeps and dispersions all apply a dotted path to the syntax tree:
/// `fins.canards.thickness` (and `canards.thickness`) reach the named set, `fins.thickness`
/// the unnamed one even where a named block is written before it (the old override took the
/// first block of kind `fins`, whatever its name).
#[test]
fn overrides_reach_the_named_set_and_fins_still_means_the_unnamed_one() {
    let dir = tempfile::tempdir().unwrap();
    let p = hpr_with(dir.path(), "canards", CANARDS);
    let c = checked(&p, &["fins.canards.thickness=3 mm"]);
    let v = vehicle(&c);
    assert!((v.fin_sets[0].fins.thickness.value - 0.003).abs() < 1e-15);
    assert!((v.fins.as_ref().unwrap().thickness.value - 0.002).abs() < 1e-15);
    let c = checked(&p, &["canards.span=70 mm"]);
    assert!((vehicle(&c).fin_sets[0].fins.span.value - 0.070).abs() < 1e-15);
    // A named block written before the unnamed one.
    let text = std::fs::read_to_string(&p).unwrap();
    let moved = text.replacen(CANARDS, "", 1).replacen(
        "  fins {\n    count = 3",
        &format!("{CANARDS}  fins {{\n    count = 3"),
        1,
    );
    assert_ne!(moved, text);
    let q = dir.path().join("first.vdl");
    std::fs::write(&q, moved).unwrap();
    let c = checked(&q, &["fins.thickness=1.5 mm"]);
    let v = vehicle(&c);
    assert!((v.fins.as_ref().unwrap().thickness.value - 0.0015).abs() < 1e-15);
    assert!((v.fin_sets[0].fins.thickness.value - 0.0025).abs() < 1e-15);
    assert_eq!(v.fins.as_ref().unwrap().count.value, 3);
    // An unknown field of the named set is reported at the override.
    let c = checked(&p, &["fins.canards.thicknes=3 mm"]);
    assert!(c.has_errors());
    assert!(
        c.diagnostics.iter().any(|d| d.message.contains("thicknes")),
        "{:?}",
        codes(&c)
    );
}

/// Bad further sets are errors at `check` with the file, line and column and exit 1: two sets
/// that overlap (the same stations and an angle in common), a set on the nose, behind the
/// tail, a duplicate name; a set whose fins stand between the other set's at the same
/// stations is no overlap.
#[test]
fn bad_fin_sets_are_errors_at_check_with_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let p = hpr_with(dir.path(), "ok", CANARDS);
    let o = bin().arg("check").arg(&p).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("vdl::fins::rigid_set"),
        "{}",
        stderr(&o)
    );
    let cases: [(&str, String, &str, &str); 5] = [
        // At the main fins' stations, a fin at 0 deg like the main set's first.
        (
            "overlap",
            CANARDS
                .replacen(
                    "root_trailing_edge = -0.65 m",
                    "root_trailing_edge = -1.85 m",
                    1,
                )
                .replacen(
                    "angles = [45 deg, 135 deg, 225 deg, 315 deg]",
                    "angles = [0 deg, 90 deg, 180 deg, 270 deg]",
                    1,
                ),
            "vdl::fins::overlap",
            "root_trailing_edge = -1.85 m",
        ),
        (
            "nose",
            CANARDS.replacen(
                "root_trailing_edge = -0.65 m",
                "root_trailing_edge = -0.5 m",
                1,
            ),
            "vdl::fins::placement",
            "root_trailing_edge = -0.5 m",
        ),
        (
            "tail",
            CANARDS.replacen(
                "root_trailing_edge = -0.65 m",
                "root_trailing_edge = -1.95 m",
                1,
            ),
            "vdl::value::range",
            "root_trailing_edge = -1.95 m",
        ),
        (
            "duplicate",
            format!("{CANARDS}{CANARDS}"),
            "vdl::duplicate",
            "fins canards {",
        ),
        // Two named sets overlapping each other.
        (
            "pair",
            format!(
                "{CANARDS}{}",
                CANARDS
                    .replacen("fins canards", "fins strakes", 1)
                    .replacen(
                        "root_trailing_edge = -0.65 m",
                        "root_trailing_edge = -0.7 m",
                        1
                    )
                    .replacen(
                        "angles = [45 deg, 135 deg, 225 deg, 315 deg]",
                        "angles = [135 deg, 10 deg, 100 deg, 190 deg]",
                        1
                    )
            ),
            "vdl::fins::overlap",
            "root_trailing_edge = -0.7 m",
        ),
    ];
    for (name, blocks, code, at) in cases {
        let p = hpr_with(dir.path(), name, &blocks);
        let o = bin().arg("check").arg(&p).output().unwrap();
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{name}: {e}");
        assert!(e.contains(code), "{name}: {e}");
        // At the last occurrence (the duplicate: the second header).
        let line = line_of(&p, at);
        assert!(
            e.contains(&format!("{name}.vdl:{line}:")),
            "{name} at line {line}: {e}"
        );
    }
    // Between the main fins (0, 120, 240 deg) at their stations: no overlap.
    let between = CANARDS
        .replacen("count = 4", "count = 3", 1)
        .replacen(
            "root_trailing_edge = -0.65 m",
            "root_trailing_edge = -1.85 m",
            1,
        )
        .replacen(
            "angles = [45 deg, 135 deg, 225 deg, 315 deg]",
            "angles = [60 deg, 180 deg, 300 deg]",
            1,
        );
    let p = hpr_with(dir.path(), "between", &between);
    let o = bin().arg("check").arg(&p).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

// ---- mass ------------------------------------------------------------------------------------

/// The canards' hand values: one fin's area, its centroid's body x (root leading edge at
/// -0.57 m; the trapezoid's centroid `(x_t (c_r + 2 c_t) + c_r^2 + c_r c_t + c_t^2) / (3 (c_r +
/// c_t))` aft of it, x_t = s tan 30 deg), and `int c(y) (r + y)^2 dy` over the span (r the
/// body radius, c linear from c_r to c_t: a polynomial integrated exactly by Simpson's rule).
fn canard_hand() -> (f64, f64, f64) {
    let (s, cr, ct) = (0.060, 0.080, 0.040);
    let xt = s * 30f64.to_radians().tan();
    let area = 0.5 * (cr + ct) * s;
    let aft = (xt * (cr + 2.0 * ct) + cr * cr + cr * ct + ct * ct) / (3.0 * (cr + ct));
    let r = 0.049;
    let g = |y: f64| (cr + (ct - cr) * y / s) * (r + y).powi(2);
    let second = s / 6.0 * (g(0.0) + 4.0 * g(0.5 * s) + g(s));
    (area, -0.57 - aft, second)
}

/// A further set's exact mass (area x thickness x density x count), centre of mass and
/// inertia about the axis enter the compiled structure as a rigid body on the nearest body
/// node: the compiled FE model's rigid-body mass matrix (the flight's mass properties) rises
/// by the hand values, and it equals the closed-form `analytic_mass_properties` of the whole
/// vehicle. On the old code the set added no mass at all.
#[test]
fn a_further_set_adds_its_exact_mass_centre_and_inertia_to_the_compiled_structure() {
    use flexflight::structure::compile::{compile, generator_spec};
    use flexflight::structure::generate::{analytic_mass_properties, rigid_body_projection};
    let dir = tempfile::tempdir().unwrap();
    let with = checked(&hpr_with(dir.path(), "canards", CANARDS), &[]);
    let without = checked(&hpr_with(dir.path(), "plain", ""), &[]);
    let (vw, vo) = (vehicle(&with), vehicle(&without));
    let (cw, fw) = compile(vw).unwrap();
    let (co, fo) = compile(vo).unwrap();
    let (pw, po) = (rigid_body_projection(&fw), rigid_body_projection(&fo));
    let (area, x_c, second) = canard_hand();
    let (rho, t, n) = (2710.0, 0.0025, 4.0);
    assert_eq!(vw.fin_sets[0].fins.material.density.value, 2710.0);
    let m_set = n * rho * t * area;
    let dm = pw[0][0] - po[0][0];
    assert!((dm - m_set).abs() < 1e-12 * m_set, "{dm} vs {m_set}");
    // The first moment, from the compiled centres of mass.
    let (mw, mo) = (pw[0][0], po[0][0]);
    let first = mw * cw.centre_of_mass[0] - mo * co.centre_of_mass[0];
    assert!(
        (first - m_set * x_c).abs() < 1e-9 * (m_set * x_c).abs(),
        "{first} vs {}",
        m_set * x_c
    );
    // The centre stays on the axis (four fins at 90 deg steps).
    assert!(cw.centre_of_mass[1].abs() < 1e-12 && cw.centre_of_mass[2].abs() < 1e-12);
    // Roll inertia about the axis: sum over the fins of rho t (int c (r + y)^2 dy + t^2/12 A).
    let ixx = n * rho * t * (second + t * t / 12.0 * area);
    let d_ixx = pw[3][3] - po[3][3];
    assert!((d_ixx - ixx).abs() < 1e-9 * ixx, "{d_ixx} vs {ixx}");
    // The set's whole 6 x 6 (products of inertia included) against the closed form of the
    // generator's spec (the motor, added by `compile`, is in neither difference).
    let spec = |v: &ir::Vehicle| {
        let ir::Structure::Generate(g) = &v.structure else {
            panic!()
        };
        generator_spec(v, g)
    };
    let (sw, so) = (spec(vw), spec(vo));
    assert_eq!(sw.rigid_fins.len(), 1);
    let (ew, eo) = (
        analytic_mass_properties(&sw).rigid_mass_matrix(),
        analytic_mass_properties(&so).rigid_mass_matrix(),
    );
    for a in 0..6 {
        for b in 0..6 {
            let (fe, exact) = (pw[a][b] - po[a][b], ew[a][b] - eo[a][b]);
            let scale = (ew[a.min(b)][a.min(b)] - eo[a.min(b)][a.min(b)]).abs();
            assert!(
                (fe - exact).abs() <= 1e-9 * scale.max(exact.abs()),
                "({a},{b}) FE {fe} vs {exact}"
            );
        }
    }
    // Rigid: no node, mode or fin of the compiled model comes from the set.
    assert_eq!(cw.node_positions.len(), co.node_positions.len());
    assert_eq!(cw.modes.len(), co.modes.len());
}

// ---- aerodynamics ------------------------------------------------------------------------------

/// d/dalpha (per rad) of the body table's C_N and C_M at Mach `m`, sea level, by the difference
/// over +-2 deg (the estimator's grid; both coefficients of a further set are linear in alpha).
fn body_slopes(t: &flexflight::aero::EstimatedTables, m: f64) -> (f64, f64, f64) {
    let p = t.body.lookup(m, 2.0, 0.0).unwrap();
    let n = t.body.lookup(m, -2.0, 0.0).unwrap();
    let a0 = t.body.lookup(m, 0.0, 0.0).unwrap();
    let da = 4f64.to_radians();
    ((p[0] - n[0]) / da, (p[2] - n[2]) / da, a0[1])
}

/// The canards in the built-in estimator, against Barrowman by hand (Mach 0.3): the body
/// table's normal-force slope rises by (N/2) K_T(B) C_Nalpha,1 (Diederich's slope on the fin's
/// area, K_T(B) = 1 + r/(s + r)), its centre of pressure moves forward to the slope-weighted
/// mean with the set's at the quarter point of its mean aerodynamic chord (Barrowman's x_f),
/// its axial coefficient rises by N times one fin's axial coefficient, and the rate
/// derivatives by the set's pitch damping. The fin table (the flexible set's) is unchanged.
/// On the old code the body table did not move.
#[test]
fn canards_move_the_centre_of_pressure_forward_by_barrowmans_amount_and_add_their_drag() {
    use flexflight::aero::estimator::{FinProfile, fin_axial, planform};
    use flexflight::runtime::forces::aero_tables;
    let dir = tempfile::tempdir().unwrap();
    let with = checked(&hpr_with(dir.path(), "canards", CANARDS), &[]);
    let without = checked(&hpr_with(dir.path(), "plain", ""), &[]);
    let (vw, vo) = (vehicle(&with), vehicle(&without));
    let (tw, to) = (aero_tables(vw).unwrap(), aero_tables(vo).unwrap());
    let m = 0.3;
    let (cn_w, cm_w, ca_w) = body_slopes(&tw, m);
    let (cn_o, cm_o, ca_o) = body_slopes(&to, m);
    // Barrowman by hand.
    let pi = std::f64::consts::PI;
    let (s, cr, ct, r, n) = (0.060, 0.080, 0.040, 0.049, 4.0);
    let xt = s * 30f64.to_radians().tan();
    let area = 0.5 * (cr + ct) * s;
    let aspect = 2.0 * s * s / area;
    let tan_mid = (xt + 0.5 * ct - 0.5 * cr) / s;
    let cos_mid = 1.0 / (1.0 + tan_mid * tan_mid).sqrt();
    let beta = (1.0 - m * m).sqrt();
    let k = beta * aspect / cos_mid;
    let slope = 2.0 * pi * aspect / (2.0 + (4.0 + k * k).sqrt());
    let s_ref = pi * 0.098 * 0.098 / 4.0;
    let k_tb = 1.0 + r / (s + r);
    let d_cn = n / 2.0 * k_tb * slope * area / s_ref;
    let x_f = xt / 3.0 * (cr + 2.0 * ct) / (cr + ct) + (cr + ct - cr * ct / (cr + ct)) / 6.0;
    let x_set = -0.57 - x_f;
    let (x_ref, d) = (-1.25, 0.098);
    assert!(
        ((cn_w - cn_o) - d_cn).abs() < 1e-9 * d_cn,
        "{} vs {d_cn}",
        cn_w - cn_o
    );
    let d_cm = d_cn * (x_set - x_ref) / d;
    assert!(((cm_w - cm_o) - d_cm).abs() < 1e-9 * d_cm.abs());
    // The body table's centre of pressure is the slope-weighted mean of the body's and the
    // set's; the vehicle's (with the three main fins of the fin table, (N/2) their slope at
    // their own centre of pressure, as `aero::static_margin` sums them) moves forward.
    let (x_o, x_w) = (x_ref + d * cm_o / cn_o, x_ref + d * cm_w / cn_w);
    let x_hand = (cn_o * x_o + d_cn * x_set) / (cn_o + d_cn);
    assert!((x_w - x_hand).abs() < 1e-9, "{x_w} vs {x_hand}");
    let fp = to.fin.lookup(m, 2.0, 0.0).unwrap();
    let fm = to.fin.lookup(m, -2.0, 0.0).unwrap();
    let cn_f = 1.5 * (fp[0] - fm[0]) / 4f64.to_radians();
    let x_fins = -1.65 - 0.5 * (fp[2] + fm[2]);
    let vehicle_cp = |cn_b: f64, x_b: f64| (cn_b * x_b + cn_f * x_fins) / (cn_b + cn_f);
    let (cp_o, cp_w) = (vehicle_cp(cn_o, x_o), vehicle_cp(cn_w, x_w));
    let cp_hand = (cn_o * x_o + d_cn * x_set + cn_f * x_fins) / (cn_o + d_cn + cn_f);
    assert!((cp_w - cp_hand).abs() < 1e-9, "{cp_w} vs {cp_hand}");
    assert!(cp_w > cp_o + 0.05, "forward: {cp_w} vs {cp_o}");
    println!(
        "body C_Nalpha {cn_o:.4} -> {cn_w:.4} /rad, vehicle x_cp {cp_o:.4} -> {cp_w:.4} m (Mach {m})"
    );
    // Drag: N times one canard's axial coefficient, the unnamed set's function.
    let f = &vw.fin_sets[0].fins;
    let per_fin = fin_axial(
        &planform(f, r),
        Some(FinProfile {
            thickness: 0.0025,
            section: ir::FinSection::Square,
        }),
        flexflight::aero::estimator::DEFAULT_ROUGHNESS,
        1.9,
        s_ref,
        m,
        0.0,
    );
    assert!(
        ((ca_w - ca_o) - n * per_fin).abs() < 1e-12,
        "{} vs {}",
        ca_w - ca_o,
        n * per_fin
    );
    println!("C_A {ca_o:.5} -> {ca_w:.5} at Mach {m}");
    // The flexible set's fin table is untouched.
    assert_eq!(tw.fin, to.fin);
}

/// The flight changes accordingly: canards forward of the centre of mass lower the static
/// margin at the rail exit and, with their drag and mass, the apogee; the check's rigid-set
/// warning is in `summary.json`; the canards get their own clamped-fin flutter margin
/// (`flutter_margin.sets`) and the minimum is over both sets. On the old code the two
/// flights were the same.
#[test]
fn canards_lower_the_static_margin_and_the_apogee_of_the_flight() {
    let dir = tempfile::tempdir().unwrap();
    let fly = |name: &str, blocks: &str| -> serde_json::Value {
        let p = hpr_with(dir.path(), name, blocks);
        let out = dir.path().join(format!("out-{name}"));
        let o = bin()
            .arg("run")
            .arg(&p)
            .args(["--scenario", "k1000", "--out"])
            .arg(&out)
            .arg("--cache-dir")
            .arg(dir.path().join("cache"))
            .output()
            .unwrap();
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
    };
    let plain = fly("plain", "");
    let canards = fly("canards", CANARDS);
    let margin = |s: &serde_json::Value| {
        s["flight"]["static_margin_calibres"]["at_rail_exit"]
            .as_f64()
            .unwrap()
    };
    let apogee = |s: &serde_json::Value| s["flight"]["apogee"]["altitude"].as_f64().unwrap();
    println!(
        "margin at rail exit {:.3} -> {:.3} cal, apogee {:.1} -> {:.1} m",
        margin(&plain),
        margin(&canards),
        apogee(&plain),
        apogee(&canards)
    );
    assert!(margin(&canards) < margin(&plain) - 0.1);
    assert!(apogee(&canards) < apogee(&plain) - 1.0);
    // Each set's flutter margin: the unnamed set's at the top level, the canards' in
    // `sets`, and the minimum over both.
    let fm = &canards["flutter_margin"];
    let speed = |j: &serde_json::Value| j["minimum"]["speed_margin"].as_f64().unwrap();
    let sets = fm["sets"].as_array().unwrap();
    assert_eq!(sets.len(), 1);
    assert_eq!(sets[0]["name"], "canards");
    assert_eq!(sets[0]["computed"], true);
    let (main, can) = (speed(fm), speed(&sets[0]));
    let lowest = fm["minimum_over_sets"]["speed_margin"].as_f64().unwrap();
    assert_eq!(lowest, main.min(can));
    assert_eq!(
        fm["minimum_over_sets"]["set"],
        if can < main { "canards" } else { "fins" }
    );
    assert_eq!(
        fm["meets_criterion_all_sets"].as_bool().unwrap(),
        fm["meets_criterion"].as_bool().unwrap() && sets[0]["meets_criterion"].as_bool().unwrap()
    );
    // The canards' boundary is their own (another fin: another boundary).
    assert_ne!(sets[0]["boundary_hash"], fm["boundary_hash"]);
    println!("flutter margin: fins {main:.3}, canards {can:.3}");
    let warned = canards["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .any(|w| w["code"] == "vdl::fins::rigid_set");
    assert!(warned, "{}", canards["warnings"]);
}

/// Both cache keys see a further set: the structural key (its mass is in the model) and the
/// aerodynamic key (its coefficients are in the tables) change with its thickness; a vehicle
/// without sets keeps the keys it had (the field is not serialised when empty).
#[test]
fn the_cache_keys_include_the_further_sets() {
    use flexflight::ops::compile::{aero_cache_key, cache_key};
    let dir = tempfile::tempdir().unwrap();
    let p = hpr_with(dir.path(), "canards", CANARDS);
    let a = checked(&p, &[]);
    let b = checked(&p, &["fins.canards.thickness=3 mm"]);
    let (va, vb) = (vehicle(&a), vehicle(&b));
    let (ka, kb) = (cache_key(va).unwrap(), cache_key(vb).unwrap());
    assert_ne!(ka, kb);
    assert_ne!(
        aero_cache_key(va, &ka).unwrap(),
        aero_cache_key(vb, &kb).unwrap()
    );
    // Without sets the vehicle serialises as before: no `fin_sets` key at all.
    let plain = checked(&hpr_with(dir.path(), "plain", ""), &[]);
    let json = serde_json::to_value(vehicle(&plain)).unwrap();
    assert!(json.get("fin_sets").is_none());
    assert!(serde_json::to_value(va).unwrap().get("fin_sets").is_some());
}

// ---- import ------------------------------------------------------------------------------------

/// OpenRocket's own "Simulation scripting" example (tests/import_designs/README.md: two
/// canards `CONTROL` on the forward tube and three main fins written as three one-fin sets,
/// one stage; its hybrid motor replaced by a catalogue AeroTech L1150) imports: the three
/// one-fin sets merged into one three-fin set at their angles, the aft-most, as the unnamed
/// `fins` block; the canards a named set; it checks (the rigid-set warning), compiles and
/// flies. The old importer refused it ("the language has one fin set for now"); the main
/// fins' 1 deg cant then stopped the flight (their tip nodes found off the planform).
#[test]
fn a_design_with_canards_and_three_one_fin_sets_imports_checks_and_flies() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("rc.vdl");
    let o = bin()
        .arg("import")
        .arg(repo("tests/import_designs/roll_control_canards.ork"))
        .arg("-o")
        .arg(&out)
        .args(["--material", "Cardboard=3 GPa,0.3"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains("merged into one set of their 3 fins"),
        "{text}"
    );
    let c = checked(&out, &[]);
    let v = vehicle(&c);
    let main = v.fins.as_ref().unwrap();
    assert_eq!(main.count.value, 3);
    let deg: Vec<f64> = main.angles.iter().map(|a| a.value.to_degrees()).collect();
    for (a, b) in deg.iter().zip([-150.0, -30.0, 90.0]) {
        assert!((a - b).abs() < 1e-9, "{deg:?}");
    }
    assert!((main.root_chord.value - 0.495).abs() < 1e-12);
    assert_eq!(v.fin_sets.len(), 1);
    let canards = &v.fin_sets[0];
    assert_eq!(canards.name.value, "control");
    assert_eq!(canards.fins.count.value, 2);
    assert!((canards.fins.span.value - 0.100).abs() < 1e-12);
    // The canards' root leading edge: the forward tube's top (the 0.53 m nose) + 0.28 m.
    assert!((canards.fins.root_trailing_edge_x.value + 0.86).abs() < 1e-9);
    assert!(
        c.diagnostics
            .iter()
            .any(|d| d.code == "vdl::fins::rigid_set")
    );
    let run = dir.path().join("run");
    let o = bin()
        .arg("run")
        .arg(&out)
        .args(["--scenario", "no_controlling", "--out"])
        .arg(&run)
        .arg("--cache-dir")
        .arg(dir.path().join("cache"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("summary.json")).unwrap()).unwrap();
    let apogee = s["flight"]["apogee"]["altitude"].as_f64().unwrap();
    println!(
        "{}",
        String::from_utf8_lossy(&o.stdout)
            .lines()
            .find(|l| l.contains("apogee"))
            .unwrap_or("")
    );
    assert!(apogee > 100.0, "{apogee}");
}

/// A Monte Carlo sample's minimum flutter margin is the minimum over every fin set where the
/// vehicle has further sets (`flutter_margin.minimum_over_sets`), the unnamed set's otherwise.
#[test]
fn the_monte_carlo_minimum_flutter_margin_is_over_all_sets() {
    use flexflight::analysis::montecarlo::SampleOutputs;
    let one = serde_json::json!({"flutter_margin": {"minimum": {"speed_margin": 2.0}}});
    assert_eq!(
        SampleOutputs::from_summary(&one).flutter_margin_min,
        Some(2.0)
    );
    let sets = serde_json::json!({"flutter_margin": {
        "minimum": {"speed_margin": 2.0},
        "sets": [{"name": "canards", "minimum": {"speed_margin": 1.4}}],
        "minimum_over_sets": {"speed_margin": 1.4, "set": "canards"},
    }});
    assert_eq!(
        SampleOutputs::from_summary(&sets).flutter_margin_min,
        Some(1.4)
    );
}

// ---- roll ------------------------------------------------------------------------------------

/// A further set's roll in the built-in estimator (`aero::estimator::fin_set_roll`), by hand
/// at Mach 0.3: the body table's roll columns hold Niskanen's (2009, eqs. (3.69), (3.71))
/// forcing `cl_0 = N (y_MAC + r_t) (C_Nalpha)_1 delta / d` and damping
/// `cl_p = -2 N slope I_2 / (S d^2)` with the fin's own slope (Diederich's, by hand as in the
/// test above) and `I_2 = ∫ c (r_t + y)^2 dy` by hand; their zero, the equilibrium roll rate,
/// is `V delta (y_MAC + r_t) A_f / I_2` at every Mach of the table; the cant's sign is the
/// forcing's; a vehicle without further sets keeps its eight-column table. On the old code
/// the body table had no roll columns.
#[test]
fn a_canted_further_set_has_niskanens_roll_forcing_and_damping_in_the_body_table() {
    use flexflight::runtime::forces::aero_tables;
    let dir = tempfile::tempdir().unwrap();
    let canted = CANARDS.replacen(
        "    thickness = 2.5 mm\n",
        "    thickness = 2.5 mm\n    cant = 2 deg\n",
        1,
    );
    let p = hpr_with(dir.path(), "canted", &canted);
    let t = aero_tables(vehicle(&checked(&p, &[]))).unwrap();
    let m: f64 = 0.3;
    let pi = std::f64::consts::PI;
    let (s, cr, ct, r, n): (f64, f64, f64, f64, f64) = (0.060, 0.080, 0.040, 0.049, 4.0);
    let (area, _, i2) = canard_hand();
    let xt = s * 30f64.to_radians().tan();
    let aspect = 2.0 * s * s / area;
    let tan_mid = (xt + 0.5 * ct - 0.5 * cr) / s;
    let cos_mid = 1.0 / (1.0 + tan_mid * tan_mid).sqrt();
    let k = (1.0 - m * m).sqrt() * aspect / cos_mid;
    let slope = 2.0 * pi * aspect / (2.0 + (4.0 + k * k).sqrt());
    let (d, s_ref) = (0.098, pi * 0.098 * 0.098 / 4.0);
    let y_mac = s / 3.0 * (cr + 2.0 * ct) / (cr + ct);
    let delta = 2f64.to_radians();
    let cl_0 = n * (y_mac + r) * slope * area / s_ref * delta / d;
    let cl_p = -2.0 * n * slope * i2 / (s_ref * d * d);
    for alpha in [-4.0, 0.0, 6.0] {
        let got = t.body.body_roll(m, alpha, 0.0).unwrap().unwrap();
        println!(
            "Mach {m}, alpha {alpha}: cl_0 {} (hand {cl_0}), cl_p {} (hand {cl_p})",
            got.cl_0, got.cl_p
        );
        assert!((got.cl_0 - cl_0).abs() < 1e-12 * cl_0, "{got:?}");
        assert!((got.cl_p - cl_p).abs() < 1e-12 * cl_p.abs(), "{got:?}");
    }
    // The equilibrium roll rate per unit speed, p_eq / V = -2 cl_0 / (cl_p d), is the
    // planform's alone at every Mach (the same slope in forcing and damping).
    let p_eq = delta * (y_mac + r) * area / i2;
    for mach in [0.1, 0.5, 0.95, 1.05, 1.5, 2.5] {
        let got = t.body.body_roll(mach, 0.0, 0.0).unwrap().unwrap();
        let ratio = -2.0 * got.cl_0 / (got.cl_p * d);
        assert!(
            (ratio - p_eq).abs() < 1e-12 * p_eq,
            "Mach {mach}: {ratio} vs {p_eq}"
        );
    }
    println!(
        "p_eq / V = {p_eq:.5} rad/m: {:.2} rev/s at 100 m/s",
        100.0 * p_eq / (2.0 * pi)
    );
    // The opposite cant, the opposite forcing and the same damping.
    let p = hpr_with(
        dir.path(),
        "minus",
        &canted.replacen("cant = 2 deg", "cant = -2 deg", 1),
    );
    let minus = aero_tables(vehicle(&checked(&p, &[]))).unwrap();
    let (a, b) = (
        t.body.body_roll(m, 2.0, 0.0).unwrap().unwrap(),
        minus.body.body_roll(m, 2.0, 0.0).unwrap().unwrap(),
    );
    assert!(a.cl_0 == -b.cl_0 && a.cl_p == b.cl_p);
    // No further set, no roll columns.
    let plain = aero_tables(vehicle(&checked(&hpr_with(dir.path(), "plain", ""), &[]))).unwrap();
    assert!(plain.body.has_rates() && !plain.body.has_roll());
}

/// The flight rolls: canards canted +0.5 deg roll the vehicle the way the flexible main fins
/// canted +0.5 deg do (the same sign convention in the fin block and the body table), and no
/// faster than the canards' own equilibrium roll rate at the flight's speed (the main fins
/// add their damping). On the old code the canted canards rolled it no more than straight
/// ones.
#[test]
fn canted_canards_roll_the_flight_the_way_canted_main_fins_do() {
    let dir = tempfile::tempdir().unwrap();
    let fly_file = |p: &Path, name: &str, set: &[&str]| -> Vec<(f64, f64, f64)> {
        let out = dir.path().join(format!("out-{name}"));
        let mut c = bin();
        c.arg("run")
            .arg(p)
            .args(["--scenario", "k1000", "--out"])
            .arg(&out)
            .arg("--cache-dir")
            .arg(dir.path().join("cache"));
        for s in set {
            c.args(["--set", s]);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
        let mut lines = text.lines().filter(|l| !l.starts_with('#'));
        let head: Vec<&str> = lines.next().unwrap().split(',').collect();
        let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
        let (ct, cp, cu) = (col("t"), col("omega_body_x"), col("v_body_x"));
        lines
            .map(|l| {
                let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
                (v[ct], v[cp], v[cu])
            })
            .collect()
    };
    let fly = |name: &str, blocks: &str, set: &[&str]| {
        fly_file(&hpr_with(dir.path(), name, blocks), name, set)
    };
    let at = |h: &[(f64, f64, f64)], t: f64| *h.iter().find(|r| r.0 >= t).unwrap();
    let canted = CANARDS.replacen(
        "    thickness = 2.5 mm\n",
        "    thickness = 2.5 mm\n    cant = 0.5 deg\n",
        1,
    );
    let canards = fly("canards", &canted, &[]);
    let main = fly("main", "", &["fins.cant=0.5 deg"]);
    let straight = fly("straight", CANARDS, &[]);
    let (area, _, i2) = canard_hand();
    let (s, cr, ct, r) = (0.060, 0.080, 0.040, 0.049);
    let rate_per_speed =
        0.5f64.to_radians() * (s / 3.0 * (cr + 2.0 * ct) / (cr + ct) + r) * area / i2;
    for t in [1.0, 2.0, 3.0] {
        let (c, m, z) = (at(&canards, t), at(&main, t), at(&straight, t));
        println!(
            "t {t}: roll rate canted canards {:.4}, canted main fins {:.4}, straight canards {:.2e} rad/s; canards' own p_eq {:.4} rad/s at {:.1} m/s",
            c.1,
            m.1,
            z.1,
            rate_per_speed * c.2,
            c.2
        );
        assert!(
            c.1.signum() == m.1.signum() && c.1.abs() > 0.1,
            "{c:?} vs {m:?}"
        );
        assert!(c.1.abs() < rate_per_speed * c.2, "{c:?}");
        // The uncanted vehicle's own small roll (its three main fins' leeward reduction at
        // an angle of attack is not symmetric in roll): 1.3 % of the canted canards' at 1 s.
        assert!(z.1.abs() < 0.03 * c.1.abs(), "{z:?}");
    }
    // The main fins themselves as a rigid set (`fins aft`, no flexible set): the roll rate
    // follows the set's own equilibrium `p_eq = V delta (y_MAC + r_t) A_f / I_2`, the check of
    // the body block's roll moment (its sign, `q S d`, `p d/(2V)`); the flexible main fins'
    // fin block, another model of the same roll, is beside it (printed).
    let text = std::fs::read_to_string(repo("examples/hpr_k1000/hpr_k1000.vdl")).unwrap();
    let rigid = text
        .replacen("  fins {\n    count = 3", "  fins aft {\n    count = 3", 1)
        .replacen("    cant = 0 deg\n", "    cant = 0.5 deg\n", 1)
        .replacen("    fins = fin_point(span = 0.5, chord = 0.25)\n", "", 1)
        .replacen("    fin_flap = per_fin\n    fin_twist = per_fin\n", "", 1)
        .replacen(
            "    fin_aero {\n      distribution = theory\n      leeward_reduction = true\n    }\n",
            "",
            1,
        );
    assert!(!rigid.contains("fin_point") && rigid.contains("fins aft {"));
    let p = dir.path().join("rigid_main.vdl");
    std::fs::write(&p, rigid).unwrap();
    let rigid = fly_file(&p, "rigid_main", &[]);
    let (s, cr, ct, r) = (0.120, 0.250, 0.100, 0.049);
    let y_mac = s / 3.0 * (cr + 2.0 * ct) / (cr + ct);
    let g = |y: f64| (cr + (ct - cr) * y / s) * (r + y).powi(2);
    let i2 = s / 6.0 * (g(0.0) + 4.0 * g(0.5 * s) + g(s));
    let per_speed = 0.5f64.to_radians() * (y_mac + r) * 0.5 * (cr + ct) * s / i2;
    let (rg, fl) = (at(&rigid, 3.0), at(&main, 3.0));
    let p_eq = per_speed * rg.2;
    println!(
        "t 3: main fins canted 0.5 deg, rigid set {:.3} rad/s (its p_eq {p_eq:.3} at {:.1} m/s), flexible {:.3} rad/s",
        rg.1, rg.2, fl.1
    );
    assert!((rg.1 - p_eq).abs() < 0.015 * p_eq, "{rg:?} vs {p_eq}");
}

/// `plan` lists each further set (human: a `fin set` line with its planform, mass and where
/// its aerodynamics are, and its fins' corners under `set NAME`; JSON: `fin_sets`), and the
/// vehicle without sets prints and serialises none. On the old code `plan` did not name the
/// canards anywhere.
#[test]
fn plan_lists_the_further_sets_with_their_corners() {
    let dir = tempfile::tempdir().unwrap();
    let plan = |name: &str, blocks: &str, json: bool| -> String {
        let p = hpr_with(dir.path(), name, blocks);
        let mut c = bin();
        c.arg("plan")
            .arg(&p)
            .args(["--scenario", "k1000", "--cache-dir"])
            .arg(dir.path().join("cache"));
        if json {
            c.args(["--format", "json"]);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let text = plan("canards", CANARDS, false);
    let line = text
        .lines()
        .find(|l| l.starts_with("fin set        canards:"))
        .unwrap_or_else(|| panic!("{text}"));
    let (area, _, _) = canard_hand();
    let mass = area * 0.0025 * 2710.0 * 4.0;
    println!("{line}");
    assert!(
        line.contains("4 trapezoidal fins, rigid; root LE at x = -0.5700 m"),
        "{line}"
    );
    assert!(line.contains(&format!("{area:.6} m^2 each")), "{line}");
    assert!(line.contains(&format!("plates {mass:.4} kg")), "{line}");
    // The corners: the canards' four under their heading, the first at 45 deg with its root
    // trailing edge at -0.65 m on the 49 mm body radius (turned 45 deg about x).
    let after: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("  set canards (rigid):"))
        .skip(1)
        .take_while(|l| l.starts_with("  fin "))
        .collect();
    assert_eq!(after.len(), 4, "{text}");
    let r = 0.049 / 2f64.sqrt();
    assert!(
        after[0].contains(&format!("at 45.000 deg: (-0.65000, {r:.5}, {r:.5})")),
        "{}",
        after[0]
    );
    let json: serde_json::Value = serde_json::from_str(&plan("canards", CANARDS, true)).unwrap();
    let sets = json["fin_sets"].as_array().unwrap();
    assert_eq!(sets.len(), 1);
    assert_eq!(sets[0]["name"], "canards");
    assert!((sets[0]["plate_mass"].as_f64().unwrap() - mass).abs() < 1e-12);
    // Without sets: no line, no key.
    assert!(!plan("plain", "", false).contains("fin set "));
    let json: serde_json::Value = serde_json::from_str(&plan("plain", "", true)).unwrap();
    assert!(json.get("fin_sets").is_none());
}
