//! The structural compiler end to end: SPHADS-1 and its tri-fin variant compile to the
//! mode sets the vehicle files ask for, with mass properties equal to the analytic ones of
//! the generated geometry, and bad structural inputs give diagnostics without touching the
//! cache.

use std::path::{Path, PathBuf};

use flexflight::check::{DiskLoader, MemoryLoader, check_files, check_source};
use flexflight::structure::compile::{CompiledVehicle, compile, generator_spec};
use flexflight::structure::generate::analytic_mass_properties;

fn root(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn compile_file(p: &str, sets: &[String]) -> CompiledVehicle {
    let checked = check_files(&[root(p)], sets, &DiskLoader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    let v = &checked.program.vehicles[0];
    compile(v).expect("compiles").0
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

#[test]
fn sphads1_has_two_bending_four_flap_four_twist_modes() {
    let c = compile_file("vehicles/sphads1.vdl", &[]);
    let classes: Vec<(&str, i32)> = c.modes.iter().map(|m| (m.class.as_str(), m.fin)).collect();
    assert_eq!(
        classes,
        vec![
            ("body_bending", -1),
            ("body_bending", -1),
            ("fin_flap", 0),
            ("fin_flap", 1),
            ("fin_flap", 2),
            ("fin_flap", 3),
            ("fin_twist", 0),
            ("fin_twist", 1),
            ("fin_twist", 2),
            ("fin_twist", 3),
        ]
    );
    // The stated design targets of the vehicle file (thesis 5.5 and 6.5.6).
    assert!(
        (c.centre_of_mass[0] + 1.59).abs() < 0.005,
        "c.g. at {}",
        c.centre_of_mass[0]
    );
    let f_bend = c.modes[0].frequency_hz;
    assert!((85.0..95.0).contains(&f_bend), "first bending {f_bend} Hz");
    // Localised fin modes are single-fin: almost no energy on the other fins.
    for m in &c.modes[2..] {
        assert!(m.body_fraction < 0.5, "{m:?}");
    }
    // Repeated modes: the four flap frequencies agree (cruciform symmetry).
    for m in &c.modes[3..6] {
        assert!(rel(m.frequency_hz, c.modes[2].frequency_hz) < 1e-3);
    }
}

#[test]
fn tri_fin_variant_yields_one_mode_per_fin() {
    let c = compile_file("vehicles/sphads1a.vdl", &[]);
    let flap: Vec<i32> = c
        .modes
        .iter()
        .filter(|m| m.class == "fin_flap")
        .map(|m| m.fin)
        .collect();
    let twist: Vec<i32> = c
        .modes
        .iter()
        .filter(|m| m.class == "fin_twist")
        .map(|m| m.fin)
        .collect();
    assert_eq!(flap, vec![0, 1, 2]);
    assert_eq!(twist, vec![0, 1, 2]);
    assert_eq!(c.modes.len(), 8);
}

/// (2.5.25): the rigid properties of the compiled model equal the analytic mass, centre of
/// mass and inertia of the generated geometry (tube, conical nose, fins, point and
/// distributed masses) to 1e-9 relative.
#[test]
fn rigid_properties_equal_the_analytic_ones() {
    let checked = check_files(&[root("vehicles/sphads1.vdl")], &[], &DiskLoader);
    let v = &checked.program.vehicles[0];
    let flexflight::check::ir::Structure::Generate(g) = &v.structure else {
        panic!()
    };
    let analytic = analytic_mass_properties(&generator_spec(v, g));
    let c = compile(v).unwrap().0;
    let r = &c.reduced;
    assert!(
        rel(r.mass, analytic.mass) < 1e-9,
        "{} vs {}",
        r.mass,
        analytic.mass
    );
    let scale_c = analytic
        .first_moment
        .iter()
        .map(|x| x.abs())
        .fold(0.0, f64::max);
    for k in 0..3 {
        assert!((r.first_moment[k] - analytic.first_moment[k]).abs() < 1e-9 * scale_c);
    }
    let scale_j = analytic
        .inertia_about_origin
        .iter()
        .flatten()
        .map(|x| x.abs())
        .fold(0.0, f64::max);
    for a in 0..3 {
        for b in 0..3 {
            let d = (r.inertia[a][b] - analytic.inertia_about_origin[a][b]).abs();
            assert!(
                d < 1e-9 * scale_j,
                "J[{a}][{b}]: {} vs {}",
                r.inertia[a][b],
                analytic.inertia_about_origin[a][b]
            );
        }
    }
}

/// Fin thickness enters the structure: thicker fins, stiffer fins.
#[test]
fn fin_thickness_override_changes_the_fin_frequencies() {
    let thin = compile_file("vehicles/sphads1.vdl", &["fins.thickness=0.4 mm".into()]);
    let thick = compile_file("vehicles/sphads1.vdl", &["fins.thickness=0.8 mm".into()]);
    // Plate bending: f ~ t (D ~ t^3, mass ~ t), so doubling t doubles the flap frequency of
    // a fin clamped rigidly at its root. The fin root sits on the flexible, massive body shell,
    // which does not scale with t: measured 2.0119 (48.860 / 24.286 Hz), 0.6 % above.
    let ratio = thick.modes[2].frequency_hz / thin.modes[2].frequency_hz;
    assert!((ratio - 2.0).abs() < 0.015, "flap ratio {ratio}");
}

/// With 1.0 mm fins the flap combinations that roll or bend the body sit 5.7 % above the
/// others (eigenfrequencies 60.27, 60.32, 60.32, 63.74 Hz); all four are still one cluster,
/// localised one per fin, and no fin takes a second flap mode (263 Hz) instead. A localised
/// mode is a combination of the cluster's eigenvectors, so its frequency (the Rayleigh
/// quotient, the modal stiffness over the modal mass) is the cluster's RMS, 61.18 Hz, the
/// same for the four fins (they are identical): to 2e-11 measured.
#[test]
fn thick_fins_keep_one_first_flap_mode_per_fin() {
    let c = compile_file("vehicles/sphads1.vdl", &["fins.thickness=1.0 mm".into()]);
    let flap: Vec<f64> = c
        .modes
        .iter()
        .filter(|m| m.class == "fin_flap")
        .map(|m| m.frequency_hz)
        .collect();
    assert_eq!(flap.len(), 4);
    for f in &flap {
        assert!((60.0..64.0).contains(f), "flap {f} Hz: {flap:?}");
        assert!(rel(*f, flap[0]) < 1e-9, "{flap:?}");
    }
}

fn structure_error(src: &str) -> String {
    let mut loader = MemoryLoader::default();
    loader.files.insert("v.vdl".into(), src.into());
    let checked = check_source("v.vdl", src, &loader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    match compile(&checked.program.vehicles[0]) {
        Ok(_) => panic!("expected a structure error"),
        Err(e) => format!("{}: {e}", e.code()),
    }
}

const BASE: &str = r#"
import "std/materials.vdl"
vehicle v {
  material = aluminium_thesis
  origin = ORIGIN
  structure { generate { body { length = 1 m; diameter = 100 mm; wall = 2 mm; elements = 10 } } }
  key_nodes { body = BODY }
  modes { MODES }
  aero { source = builtin; reference_point = (-0.5, 0, 0) m }
  forces { gravity {} }
}
"#;

fn vehicle(origin: &str, body: &str, modes: &str) -> String {
    BASE.replace("ORIGIN", origin)
        .replace("BODY", body)
        .replace("MODES", modes)
}

#[test]
fn a_key_node_that_does_not_exist_is_reported() {
    let e = structure_error(&vehicle("node(1)", "node(999)", "body_bending = 2"));
    assert!(e.starts_with("structure::key_node"), "{e}");
    assert!(e.contains("999"), "{e}");
}

#[test]
fn an_impossible_selection_names_what_was_found() {
    let e = structure_error(&vehicle("node(1)", "node(2)", "band = [100 kHz, 200 kHz]"));
    assert!(e.starts_with("structure::modes::unmet"), "{e}");
    assert!(e.contains("Hz"), "{e}");
    let e = structure_error(&vehicle("node(1)", "node(2)", "body_bending = 500"));
    assert!(e.starts_with("structure::modes::unmet"), "{e}");
    assert!(e.contains("body_bending"), "{e}");
}

/// A failed compilation writes nothing into the cache.
#[test]
fn a_failed_compile_leaves_the_cache_empty() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("v.vdl");
    std::fs::write(&file, vehicle("node(1)", "node(999)", "body_bending = 2")).unwrap();
    let cache = dir.path().join("cache");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .args([
            "compile",
            file.to_str().unwrap(),
            "--cache-dir",
            cache.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("structure::key_node"));
    assert!(!cache.exists() || std::fs::read_dir(&cache).unwrap().next().is_none());
}

/// compile twice: the second run is a cache hit and prints the same summary; a corrupted
/// artifact is detected, reported and rebuilt.
#[test]
fn the_cli_caches_and_rebuilds_corrupt_artifacts() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let run = || {
        std::process::Command::new(env!("CARGO_BIN_EXE_flexflight"))
            .args([
                "compile",
                root("vehicles/sphads1.vdl").to_str().unwrap(),
                "--format",
                "json",
                "--cache-dir",
            ])
            .arg(&cache)
            .output()
            .unwrap()
    };
    let first = run();
    assert!(
        first.status.success(),
        "{}",
        String::from_utf8_lossy(&first.stderr)
    );
    let j1: serde_json::Value = serde_json::from_slice(&first.stdout).unwrap();
    assert_eq!(j1["cache"], "miss");
    let second = run();
    let j2: serde_json::Value = serde_json::from_slice(&second.stdout).unwrap();
    assert_eq!(j2["cache"], "hit");
    assert_eq!(j1["modes"], j2["modes"]);
    assert_eq!(j1["hash"], j2["hash"]);
    // Flip one payload byte.
    let path = PathBuf::from(j1["artifact"].as_str().unwrap());
    let mut bytes = std::fs::read(&path).unwrap();
    let k = bytes.len() - 100;
    bytes[k] ^= 0x55;
    std::fs::write(&path, bytes).unwrap();
    let third = run();
    assert!(third.status.success());
    let j3: serde_json::Value = serde_json::from_slice(&third.stdout).unwrap();
    assert_eq!(j3["cache"], "rebuilt");
    assert!(String::from_utf8_lossy(&third.stderr).contains("artifact::checksum"));
    assert_eq!(j3["modes"], j1["modes"]);
}

/// A structure read from NASTRAN OUTPUT4 + GRID bulk data compiles through the same
/// pipeline and reproduces the sample's reference frequencies (scipy eigh) to 1e-8.
#[test]
fn nastran_example_reproduces_reference_frequencies() {
    let c = compile_file("examples/tube_from_nastran.vdl", &[]);
    let reference: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root("examples/fe/tube21/reference.json")).unwrap(),
    )
    .unwrap();
    let f_ref: Vec<f64> = reference["fe_frequencies_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let got: Vec<f64> = c.modes.iter().map(|m| m.frequency_hz).collect();
    // Bending pairs: reference modes 1-2 and 3-4 (5 is the first torsion/axial).
    for (g, r) in got.iter().zip([f_ref[0], f_ref[1], f_ref[2], f_ref[3]]) {
        assert!(rel(*g, r) < 1e-8, "{g} vs {r}");
    }
}

/// A reader that goes away (`flexflight inspect X | head`) ends the command quietly with
/// exit status 141 (128 + SIGPIPE, what a shell reports for a tool killed by the signal),
/// not with the panic of `println!` on a broken pipe (exit 101 and a backtrace).
#[test]
fn a_closed_standard_output_ends_the_command_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let bin = env!("CARGO_BIN_EXE_flexflight");
    let o = std::process::Command::new(bin)
        .arg("compile")
        .arg(root("examples/thesis/section_6_5.vdl"))
        .arg("--cache-dir")
        .arg(dir.path())
        .args(["--format", "json"])
        .output()
        .unwrap();
    assert!(o.status.success());
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let artifact = json["artifact"].as_str().unwrap();
    // Its JSON is about 0.7 MB, ten pipe buffers: the writes cannot all land before the read
    // end is closed.
    let mut child = std::process::Command::new(bin)
        .args(["inspect", artifact, "--format", "json"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(o.status.code(), Some(141), "{stderr}");
}
