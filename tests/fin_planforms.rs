//! Issue 34: fin planforms beyond the trapezoid. Elliptical and freeform (polygon) fins in
//! the language, the structure (the shell mesh follows the true edges, exact mass), the
//! aerodynamic lattice and the built-in tables (Barrowman for arbitrary planforms, Niskanen
//! 2009 sec. 3.2.2), against closed forms; a polygon equal to a trapezoid is the trapezoid.

#![allow(clippy::unwrap_used)]

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Command;

use flexflight::aero::estimator::{FinPlanform, planform};
use flexflight::aero::panel::fin_model::{self, PanelSettings};
use flexflight::check::ir::{self, FinOutline};
use flexflight::check::{DiskLoader, check_files};
use flexflight::structure::compile::{compile, generator_spec};
use flexflight::structure::generate::{
    BeamTheory, BodySpec, FinSpec, GeneratorSpec, MaterialProps, analytic_mass_properties,
    cantilever_fin_model, generate, rigid_body_projection,
};
use flexflight::structure::modal;

fn root(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// SPHADS-1's fins block (vehicles/sphads1.vdl).
const SPHADS_FINS: &str = "    span = 127.23 mm
    root_chord = 324.68 mm
    tip_chord = 122.67 mm
    trailing_edge_sweep = 0 deg # App. A.2.6";

/// vehicles/sphads1.vdl with its trapezoid's four fields replaced by `fins`, as a checked
/// vehicle (the file is written next to the target's temporary files; the standard library
/// is embedded).
fn sphads1_with(name: &str, fins: &str) -> ir::Vehicle {
    let text = std::fs::read_to_string(root("vehicles/sphads1.vdl")).unwrap();
    assert_eq!(text.matches(SPHADS_FINS).count(), 1);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fin_planforms");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(format!("{name}.vdl"));
    std::fs::write(&file, text.replacen(SPHADS_FINS, fins, 1)).unwrap();
    let checked = check_files(&[file], &[], &DiskLoader);
    assert!(
        checked.diagnostics.is_empty(),
        "{:?}",
        checked
            .diagnostics
            .iter()
            .map(|d| (d.code, d.message.clone()))
            .collect::<Vec<_>>()
    );
    checked.program.vehicles[0].clone()
}

/// The same trapezoid written as a freeform polygon: root leading edge, tip leading edge
/// (c_r - c_t aft, the trailing edge unswept), tip trailing edge, root trailing edge.
const SPHADS_POLYGON: &str = "    planform = freeform
    points = [(0, 0) mm, (202.01, 127.23) mm, (324.68, 127.23) mm, (324.68, 0) mm]";

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

fn aluminium() -> MaterialProps {
    MaterialProps {
        youngs_modulus: 70e9,
        poisson: 0.346,
        density: 2710.0,
    }
}

fn tube() -> BodySpec {
    BodySpec {
        length: 2.0,
        outer_diameter: 0.1,
        wall_thickness: 0.002,
        nose_length: 0.0,
        nose_shape: ir::NoseShape::Conical,
        transitions: Vec::new(),
        elements: 30,
        theory: BeamTheory::EulerBernoulli,
        material: aluminium(),
    }
}

/// A fin set of the generator with `outline` (root chord, span as given; the equivalent
/// trapezoid's tip chord and sweep are not used by the mesh of another outline).
fn fin(outline: FinOutline, root_chord: f64, span: f64, n_span: usize, n_chord: usize) -> FinSpec {
    FinSpec {
        count: 3,
        span,
        root_chord,
        tip_chord: 0.5 * root_chord,
        sweep: 0.3,
        thickness: 0.003,
        cant: 0.0,
        angles: vec![],
        root_trailing_edge_x: -2.0,
        span_elements: FinSpec::strips_for(&outline, n_span),
        chord_elements: n_chord,
        material: aluminium(),
        lamina: None,
        outline,
    }
}

/// A clipped, cranked freeform fin (not a trapezoid): (x aft, y out) from the root leading
/// edge; its area by the shoelace formula.
const POLYGON: [[f64; 2]; 6] = [
    [0.0, 0.0],
    [0.06, 0.04],
    [0.15, 0.11],
    [0.21, 0.11],
    [0.23, 0.05],
    [0.25, 0.0],
];

fn shoelace(p: &[[f64; 2]]) -> f64 {
    let mut a = 0.0;
    for k in 0..p.len() {
        let (u, v) = (p[k], p[(k + 1) % p.len()]);
        a += u[0] * v[1] - v[0] * u[1];
    }
    0.5 * a.abs()
}

fn polygon_outline() -> (FinOutline, f64, f64) {
    flexflight::check::fin_outline::freeform(&POLYGON).unwrap()
}

/// A freeform fin's shell mesh has a station at every corner, so its bilinear quads cover the
/// polygon exactly: the FE model's mass, first moment and inertia equal the closed forms (the
/// polygon's moments) to 1e-9, and the fins' mass is rho t A with A the shoelace area.
#[test]
fn freeform_fin_mesh_has_the_exact_mass_and_inertia() {
    let (outline, cr, s) = polygon_outline();
    let spec = GeneratorSpec {
        body: tube(),
        fins: Some(fin(outline, cr, s, 6, 8)),
        point_masses: vec![],
        distributed_masses: vec![],
        rigid_fins: vec![],
    };
    let model = generate(&spec).unwrap();
    let fe = rigid_body_projection(&model);
    let exact = analytic_mass_properties(&spec).rigid_mass_matrix();
    for a in 0..6 {
        for b in 0..6 {
            let scale = exact[a.min(b)][a.min(b)].abs().max(exact[a][b].abs());
            assert!(
                (fe[a][b] - exact[a][b]).abs() <= 1e-9 * scale.max(1e-12),
                "({a},{b}) FE {} vs {}",
                fe[a][b],
                exact[a][b]
            );
        }
    }
    let bare = GeneratorSpec {
        fins: None,
        ..spec.clone()
    };
    let fins_mass = analytic_mass_properties(&spec).mass - analytic_mass_properties(&bare).mass;
    let expected = 3.0 * 2710.0 * 0.003 * shoelace(&POLYGON);
    assert!(
        rel(fins_mass, expected) < 1e-12,
        "{fins_mass} vs {expected}"
    );
    assert!(
        rel(
            fe[0][0] - rigid_body_projection(&generate(&bare).unwrap())[0][0],
            expected
        ) < 1e-9
    );
}

/// The elliptical fin's mesh (stations s sin(pi j / 2n), the tip collapsed to one node)
/// converges to the ellipse's area pi/4 c_r s at second order; the closed-form mass of the
/// generator is exactly rho t pi/4 c_r s.
#[test]
fn elliptical_fin_area_is_pi_over_four_root_span_to_the_mesh_precision() {
    let (cr, s) = (0.2, 0.12);
    let exact = 0.25 * PI * cr * s;
    let bare = GeneratorSpec {
        body: tube(),
        fins: None,
        point_masses: vec![],
        distributed_masses: vec![],
        rigid_fins: vec![],
    };
    let bare_mass = rigid_body_projection(&generate(&bare).unwrap())[0][0];
    let mut errors = Vec::new();
    for n in [4, 8, 16, 32] {
        let spec = GeneratorSpec {
            fins: Some(fin(FinOutline::Elliptical, cr, s, n, 8)),
            ..bare.clone()
        };
        let fe = rigid_body_projection(&generate(&spec).unwrap())[0][0] - bare_mass;
        let area = fe / (3.0 * 2710.0 * 0.003);
        let closed = analytic_mass_properties(&spec).mass - analytic_mass_properties(&bare).mass;
        assert!(rel(closed, 3.0 * 2710.0 * 0.003 * exact) < 1e-14);
        errors.push(rel(area, exact));
        println!(
            "n = {n}: mesh area {area:.9e}, pi/4 c_r s {exact:.9e}, rel {:.3e}",
            rel(area, exact)
        );
    }
    // Inscribed: the mesh area is below the ellipse's, and the error falls as 1/n^2.
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(order > 1.9 && order < 2.1, "{errors:?}");
    }
    assert!(errors[3] < 4.5e-4, "{errors:?}");
}

/// The collapsed tip is sound: the clamped elliptical fin has no spurious zero-energy mode
/// (its stiffness is positive definite) and its first frequencies converge with the mesh.
#[test]
fn elliptical_cantilever_fin_has_no_spurious_modes_and_converges() {
    let mut first = Vec::new();
    for n in [8, 16, 32] {
        let f = fin(FinOutline::Elliptical, 0.2, 0.12, n, 2 * n.min(12));
        let model = cantilever_fin_model(&f).unwrap();
        let modes = modal::solve(&model, 4).unwrap();
        let hz: Vec<f64> = modes
            .omega2
            .iter()
            .map(|w| w.max(0.0).sqrt() / (2.0 * PI))
            .collect();
        println!("n = {n}: {hz:?}");
        assert!(hz[0] > 1.0, "spurious low mode: {hz:?}");
        first.push(hz[0]);
    }
    assert!(rel(first[1], first[2]) < 0.01, "{first:?}");
    assert!(
        rel(first[0], first[2]) > rel(first[1], first[2]),
        "{first:?}"
    );
}

/// Barrowman for arbitrary planforms (Niskanen 2009, sec. 3.2.2) on the half ellipse, in
/// closed form: A = pi c_r s / 4, MAC = 8 c_r / (3 pi), MAC leading edge c_r (1/2 - 4/(3 pi)),
/// so the subsonic centre of pressure x_MAC + MAC/4 = c_r (1/2 - 2/(3 pi)) aft of the root
/// leading edge; the mid-chord line is unswept, so Diederich's slope on A is
/// 2 pi AR / (2 + sqrt(4 + (beta AR)^2)) with AR = 2 s^2 / A.
#[test]
fn elliptical_fin_tables_are_barrowmans_closed_forms() {
    let v = sphads1_with(
        "elliptical",
        "    planform = elliptical\n    span = 127.23 mm\n    root_chord = 324.68 mm",
    );
    let f = v.fins.as_ref().unwrap();
    let p: FinPlanform = planform(f, 0.0635);
    let (cr, s) = (0.32468, 0.12723);
    let area = 0.25 * PI * cr * s;
    assert!(rel(p.area(), area) < 1e-15);
    let (mac, x_mac) = p.mean_aerodynamic_chord();
    assert!(rel(mac, 8.0 * cr / (3.0 * PI)) < 1e-15);
    assert!(rel(x_mac, cr * (0.5 - 4.0 / (3.0 * PI))) < 1e-14);
    for mach in [0.0f64, 0.3, 0.6, 0.8] {
        let beta = (1.0 - mach * mach).sqrt();
        let ar = 2.0 * s * s / area;
        let slope = 2.0 * PI * ar / (2.0 + (4.0 + (beta * ar).powi(2)).sqrt());
        let s_ref = 0.0127;
        assert!(
            rel(p.cn_alpha(mach, s_ref), slope * area / s_ref) < 1e-13,
            "{mach}"
        );
        assert!(
            rel(p.x_cp(mach), cr * (0.5 - 2.0 / (3.0 * PI))) < 1e-14,
            "{mach}"
        );
    }
    // The equivalent trapezoid of the analyses that take one: the same area and MAC leading
    // edge.
    let ct = f.tip_chord.value;
    assert!(rel(0.5 * (cr + ct) * s, area) < 1e-15);
}

/// A freeform polygon equal to SPHADS-1's trapezoid is the trapezoid: the same estimated
/// tables, structural modes and panel transfer matrices to round-off.
#[test]
fn freeform_polygon_equal_to_the_trapezoid_gives_the_same_tables_modes_and_panels() {
    let trap = sphads1_with("trapezoid", SPHADS_FINS);
    let poly = sphads1_with("polygon", SPHADS_POLYGON);
    let (ft, fp) = (trap.fins.as_ref().unwrap(), poly.fins.as_ref().unwrap());
    assert!(rel(fp.tip_chord.value, ft.tip_chord.value) < 1e-14);
    assert!((fp.leading_edge_sweep.value - ft.leading_edge_sweep.value).abs() < 1e-14);
    // Tables.
    let tt = flexflight::runtime::forces::aero_tables(&trap)
        .unwrap()
        .files();
    let tp = flexflight::runtime::forces::aero_tables(&poly)
        .unwrap()
        .files();
    let mut worst = 0.0f64;
    for ((_, a), (_, b)) in tt.iter().zip(&tp) {
        let na: Vec<f64> = a
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter_map(|w| w.parse().ok())
            .collect();
        let nb: Vec<f64> = b
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter_map(|w| w.parse().ok())
            .collect();
        assert_eq!(na.len(), nb.len());
        for (x, y) in na.iter().zip(&nb) {
            worst = worst.max((x - y).abs() / x.abs().max(1e-300));
        }
    }
    println!("tables: worst relative difference {worst:e}");
    assert!(worst < 1e-12, "{worst:e}");
    // Modes and mass.
    let ct = compile(&trap).unwrap().0;
    let cp = compile(&poly).unwrap().0;
    assert_eq!(ct.node_positions.len(), cp.node_positions.len());
    assert!(rel(cp.reduced.mass, ct.reduced.mass) < 1e-13);
    for (a, b) in ct.modes.iter().zip(&cp.modes) {
        assert!(
            rel(b.frequency_hz, a.frequency_hz) < 1e-9,
            "{} Hz vs {} Hz",
            b.frequency_hz,
            a.frequency_hz
        );
    }
    // Panel transfer matrices of fin 1 at subsonic and supersonic Mach numbers.
    let machs = [0.5, 2.0];
    let mt = fin_model::compile(&ct, &trap, &machs, PanelSettings::default()).unwrap();
    let mp = fin_model::compile(&cp, &poly, &machs, PanelSettings::default()).unwrap();
    for (g, mach) in machs.iter().enumerate() {
        let (a, b) = (mt.fins[0].at(g), mp.fins[0].at(g));
        let scale = a.iter().map(|x| x.abs()).fold(0.0, f64::max);
        let diff = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        println!("panels at Mach {mach}: max difference {diff:e} of {scale:e}");
        assert!(diff < 1e-10 * scale, "{diff:e} of {scale:e}");
    }
    // The generator sees the same geometry.
    let (ir::Structure::Generate(gt), ir::Structure::Generate(gp)) =
        (&trap.structure, &poly.structure)
    else {
        panic!()
    };
    let at = analytic_mass_properties(&generator_spec(&trap, gt));
    let ap = analytic_mass_properties(&generator_spec(&poly, gp));
    assert!(rel(ap.mass, at.mass) < 1e-14);
}

/// The hpr_k1000 example copied into a temporary directory with its trapezoid's four fields
/// replaced by `fins`: the directory and the vehicle file.
fn hpr_k1000_with_fins(fins: &str) -> (tempfile::TempDir, PathBuf) {
    let src = root("examples/hpr_k1000");
    let dir = tempfile::tempdir().unwrap();
    for e in std::fs::read_dir(&src).unwrap() {
        let p = e.unwrap().path();
        if p.is_file() {
            std::fs::copy(&p, dir.path().join(p.file_name().unwrap())).unwrap();
        }
    }
    let file = dir.path().join("hpr_k1000.vdl");
    let text = std::fs::read_to_string(&file).unwrap();
    let old = "    span = 120 mm\n    root_chord = 250 mm\n    tip_chord = 100 mm\n    trailing_edge_sweep = 0 deg\n";
    assert_eq!(text.matches(old).count(), 1);
    std::fs::write(&file, text.replacen(old, fins, 1)).unwrap();
    (dir, file)
}

/// An elliptical-finned vehicle checks, compiles and flies (the built-in tables, the fin
/// panel model and the structure on the true planform): the hpr_k1000 example with its fins
/// made a half ellipse on the same root chord and span.
#[test]
fn an_elliptical_finned_rocket_checks_compiles_and_flies() {
    let (dir, file) = hpr_k1000_with_fins(
        "    planform = elliptical\n    span = 120 mm\n    root_chord = 250 mm\n",
    );
    let out = dir.path().join("out");
    let cache = dir.path().join("cache");
    let o = Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .arg("run")
        .arg(&file)
        .args(["--scenario", "k1000", "--out"])
        .arg(&out)
        .arg("--cache-dir")
        .arg(&cache)
        .args(["--set", "run.stop_time = 6 s"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert!(summary.is_object());
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let mut lines = history.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let mach = header.iter().position(|h| *h == "mach").unwrap();
    let mut max_mach = 0.0f64;
    let mut rows = 0;
    for l in lines {
        let cells: Vec<f64> = l.split(',').map(|c| c.parse().unwrap()).collect();
        assert!(cells.iter().all(|c| c.is_finite()), "{l}");
        max_mach = max_mach.max(cells[mach]);
        rows += 1;
    }
    println!("{rows} rows, max Mach {max_mach:.3}");
    assert!(
        rows > 100 && max_mach > 0.3,
        "{rows} rows, max Mach {max_mach}"
    );
    // The flutter margin over the flight, from the clamped elliptical fin's boundary.
    let margin = std::fs::read_to_string(out.join("flutter_margin.csv")).unwrap();
    assert!(margin.lines().count() > 10);
}

/// A pointed freeform fin (a clipped delta ending in a point at the tip): its mesh collapses
/// the tip row, its lattice's outer panels are triangles, and the vehicle compiles with
/// finite tables and panel matrices.
#[test]
fn a_pointed_freeform_fin_compiles_with_finite_tables_and_panels() {
    let v = sphads1_with(
        "delta",
        "    planform = freeform\n    points = [(0, 0) mm, (250, 127.23) mm, (324.68, 0) mm]",
    );
    let f = v.fins.as_ref().unwrap();
    assert!(f.tip_chord.value.abs() < 1e-12 * f.root_chord.value);
    let t = flexflight::runtime::forces::aero_tables(&v)
        .unwrap()
        .files();
    for (_, csv) in &t {
        assert!(!csv.contains("NaN") && !csv.contains("inf"), "{csv}");
    }
    let c = compile(&v).unwrap().0;
    assert!(c.modes.iter().all(|m| m.frequency_hz > 1.0));
    let m = fin_model::compile(&c, &v, &[0.5, 2.0], PanelSettings::default()).unwrap();
    for g in 0..2 {
        assert!(m.fins[0].at(g).iter().all(|x| x.is_finite()));
    }
    // The triangle's area, by the polygon: c_r s / 2.
    let p = planform(f, 0.0635);
    assert!(rel(p.area(), 0.5 * 0.32468 * 0.12723) < 1e-14);
}

/// A rocket whose freeform fins end in a point along straight edges: the doublet lattice's
/// automatic strips cannot meet its box rule there (`dlm::spanwise_for`: the last strip's
/// aspect ratio is `2 s n_c / c_r` whatever the strip count), so the flight's flutter margin
/// falls back to the vortex lattice and says so, instead of "not computed". The hpr_k1000
/// example with its fins made a clipped delta ending in a point on the same root chord and
/// span.
#[test]
fn a_pointed_fins_flight_margin_falls_back_to_the_vortex_lattice_and_says_so() {
    let (dir, file) = hpr_k1000_with_fins(
        "    planform = freeform\n    points = [(0, 0) mm, (200, 120) mm, (250, 0) mm]\n",
    );
    // The premise: no strip count meets the doublet lattice's box rule on this fin.
    let checked = check_files(std::slice::from_ref(&file), &[], &DiskLoader);
    assert!(checked.diagnostics.is_empty());
    let f = checked.program.vehicles[0].fins.clone().unwrap();
    let pf = planform(&f, 0.0);
    assert!(matches!(
        flexflight::aero::panel::dlm::spanwise_for(
            &pf,
            flexflight::analysis::flutter::margin::MARGIN_CHORDWISE,
            1,
            flexflight::aero::panel::Spacing::Cosine
        ),
        Err(flexflight::aero::panel::PanelError::WideBoxes { .. })
    ));
    let out = dir.path().join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .arg("run")
        .arg(&file)
        .args(["--scenario", "k1000", "--out"])
        .arg(&out)
        .arg("--cache-dir")
        .arg(dir.path().join("cache"))
        .args(["--set", "run.stop_time = 6 s"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let m = &summary["flutter_margin"];
    assert_eq!(m["computed"], serde_json::json!(true), "{m}");
    assert_eq!(m["aero"], serde_json::json!("unsteady"), "{m}");
    assert!(
        m["aero_fallback"]
            .as_str()
            .is_some_and(|s| s.contains("box rule")),
        "{m}"
    );
    assert!(m["minimum"]["speed_margin"].as_f64().unwrap() > 0.0, "{m}");
    assert!(
        stdout.contains("vortex lattice") || err.contains("vortex lattice"),
        "{stdout}\n{err}"
    );
    let margin = std::fs::read_to_string(out.join("flutter_margin.csv")).unwrap();
    assert!(margin.lines().count() > 10);
}
