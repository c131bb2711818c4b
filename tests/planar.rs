//! The planar stability models on SPHADS-1 (vehicles/sphads1.vdl, scenarios of
//! examples/thesis/section_6_5.vdl): mass properties of a thickness variant against a real
//! recompile, the terminal-velocity equilibrium, the sign trends the thesis states (thicker
//! fins more stable, pinned boundary falling with altitude), and the `analyze` command's
//! output and bad-input diagnostics.

use std::path::{Path, PathBuf};
use std::process::Command;

use flexflight::analysis::map::{CriticalThickness, planar_map};
use flexflight::analysis::planar::{self, Altitude, PlanarKind, PlanarVehicle, Speed, Stability};
use flexflight::check::{DiskLoader, check_files};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn cache() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("planar-test-cache")
}

/// The planar vehicle of a thesis scenario, compiled without the cache.
fn vehicle(scenario: &str) -> PlanarVehicle {
    let checked = check_files(&[repo("examples/thesis/section_6_5.vdl")], &[], &DiskLoader);
    assert!(!checked.has_errors());
    let sc = checked.program.scenario(scenario).unwrap();
    let (compiled, _) = flexflight::structure::compile::compile(&sc.vehicle).unwrap();
    PlanarVehicle::new(&sc.vehicle, &compiled).unwrap()
}

#[test]
fn thickness_variant_mass_properties_match_a_recompile() {
    // Predict the 1.0 mm vehicle from the 0.4 mm one (flat-plate fin mass at the planform
    // centroid) and compare with the FE model compiled at 1.0 mm.
    let thin = vehicle("subsonic_t04");
    let thick = vehicle("supersonic_t10");
    assert_eq!(thin.compiled, thin.mass_properties(0.4e-3).unwrap());
    let predicted = thin.mass_properties(1.0e-3).unwrap();
    let actual = thick.compiled;
    eprintln!("predicted {predicted:?}\nactual    {actual:?}");
    assert!((predicted.mass - actual.mass).abs() < 1e-6 * actual.mass);
    assert!((predicted.x_cg - actual.x_cg).abs() < 1e-4, "x_cg");
    // The neglected spread of the plate about its centroid: well under 1 %.
    assert!(
        (predicted.inertia - actual.inertia).abs() < 2e-3 * actual.inertia,
        "J"
    );
}

#[test]
fn unpinned_equilibrium_balances_drag_and_weight() {
    let v = vehicle("subsonic_t04");
    let m = v.mass_properties(0.5e-3).unwrap().mass;
    for mach in [0.8, 1.5, 2.5] {
        let h = planar::equilibrium_altitude(&v, m, Speed::Mach(mach)).unwrap();
        let c = v.condition_at_mach(h, mach).unwrap();
        let drag = v.axial_force(&c).unwrap();
        eprintln!("Mach {mach}: equilibrium altitude {h:.1} m");
        assert!(
            (drag - m * c.gravity).abs() < 1e-6 * drag,
            "{drag} vs {}",
            m * c.gravity
        );
    }
    // Subsonic enough that even sea-level air cannot hold the weight: a typed error.
    let e = planar::equilibrium_altitude(&v, m, Speed::Mach(0.3)).unwrap_err();
    assert!(
        matches!(e, planar::PlanarError::NoEquilibrium { .. }),
        "{e}"
    );
}

#[test]
fn thicker_fins_are_more_stable_and_the_pinned_boundary_falls_with_altitude() {
    let v = vehicle("subsonic_t04");
    let sigma = |t: f64, h: f64, mach: f64| {
        let c = planar::condition_at(&v, t, mach, Altitude::Fixed(h)).unwrap();
        planar::verdict(&planar::parameters(&v, PlanarKind::Pinned, t, c).unwrap()).unwrap()
    };
    let thin = sigma(0.2e-3, 0.0, 0.8);
    let thick = sigma(1.2e-3, 0.0, 0.8);
    eprintln!("pinned, sea level, Mach 0.8: 0.2 mm {thin:?}; 1.2 mm {thick:?}");
    assert!(thin.sigma_d > 0.0 && thick.sigma_d < 0.0);
    assert_eq!(thick.class, Stability::Stable);
    // Critical thickness at Mach 0.8 at 0, 10, 20 km (thesis 6.1.1: lower at altitude).
    let ts: Vec<f64> = (1..=30).map(|k| 0.05e-3 * k as f64).collect();
    let crit: Vec<f64> = [0.0, 10_000.0, 20_000.0]
        .iter()
        .map(|&h| {
            let m = planar_map(&v, PlanarKind::Pinned, &ts, &[0.8], Altitude::Fixed(h));
            match m.mach_boundaries()[0].model {
                CriticalThickness::Crossing(t) => t,
                other => panic!("no boundary at {h} m: {other:?}"),
            }
        })
        .collect();
    eprintln!("pinned critical thickness at Mach 0.8, 0/10/20 km: {crit:?}");
    assert!(crit[0] > crit[1] && crit[1] > crit[2], "{crit:?}");
}

#[test]
fn analyze_planar_prints_matrices_and_eigenvalues_as_json() {
    for (flag, n_state) in [("--pinned", 4), ("--unpinned", 6)] {
        let o = bin()
            .args(["analyze", "planar", flag])
            .arg(repo("examples/thesis/section_6_5.vdl"))
            .args([
                "--scenario",
                "supersonic_t10",
                "--format",
                "json",
                "--cache-dir",
            ])
            .arg(cache())
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let a = &j["analysis"];
        assert_eq!(a["eigenvalues"].as_array().unwrap().len(), n_state);
        assert_eq!(a["state_matrix"].as_array().unwrap().len(), n_state);
        assert!(a["parameters"]["fin_stiffness"].as_f64().unwrap() > 0.0);
        // The printed analysis is the library's at the scenario's initial condition, to
        // the bit (serde_json writes f64 round-trip exact), and its verdict is the
        // classification of the printed roots.
        let kind = if flag == "--pinned" {
            PlanarKind::Pinned
        } else {
            PlanarKind::Unpinned
        };
        let checked = check_files(&[repo("examples/thesis/section_6_5.vdl")], &[], &DiskLoader);
        let sc = checked.program.scenario("supersonic_t10").unwrap();
        let want = flexflight::ops::planar::analyse_at_initial_condition(
            sc,
            &vehicle("supersonic_t10"),
            kind,
        )
        .unwrap();
        let roots: Vec<planar::Eigenvalue> = a["eigenvalues"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| planar::Eigenvalue {
                re: e["re"].as_f64().unwrap(),
                im: e["im"].as_f64().unwrap(),
            })
            .collect();
        assert_eq!(roots, want.eigenvalues, "{flag}");
        let v = planar::classify(&roots);
        assert_eq!(
            a["verdict"]["class"].as_str(),
            Some(want.verdict.class.name())
        );
        assert_eq!(v.class, want.verdict.class);
        assert_eq!(a["verdict"]["sigma_d"].as_f64(), Some(v.sigma_d));
        // Thesis 6.5 for 1.0 mm fins at 700 m/s, 10 km: stable.
        assert_eq!(want.verdict.class, Stability::Stable, "{flag}: {v:?}");
    }
}

#[test]
fn analyze_map_writes_the_grid() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("map");
    let o = bin()
        .args(["analyze", "map", "--planar", "--pinned"])
        .arg(repo("examples/thesis/section_6_5.vdl"))
        .args([
            "--scenario",
            "subsonic_t04",
            "--thickness",
            "0.2mm:3.0mm:5",
            "--mach",
            "0.5:2.5:4",
            "--altitude",
            "5km",
            "--out",
        ])
        .arg(&out)
        .arg("--cache-dir")
        .arg(cache())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("map.csv")).unwrap();
    let mut lines = text.lines();
    assert!(
        lines
            .next()
            .unwrap()
            .starts_with("thickness_m,mach,altitude_m")
    );
    // Every cell is the library's verdict at that thickness, Mach and altitude, to the bit
    // (Rust writes f64 round-trip exact), in thickness-major order over the requested grid.
    let v = vehicle("subsonic_t04");
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    assert_eq!(rows.len(), 20);
    let num = |s: &str| s.parse::<f64>().unwrap();
    let mut classes = std::collections::BTreeSet::new();
    for (k, r) in rows.iter().enumerate() {
        let (t, mach) = (num(&r[0]), num(&r[1]));
        let t_want = 0.2e-3 + (k / 4) as f64 * (3.0e-3 - 0.2e-3) / 4.0;
        let mach_want = 0.5 + (k % 4) as f64 * 2.0 / 3.0;
        assert!(
            (t - t_want).abs() < 1e-18 && (mach - mach_want).abs() < 1e-15,
            "{r:?}"
        );
        let c = planar::condition_at(&v, t, mach, Altitude::Fixed(5000.0)).unwrap();
        assert_eq!(num(&r[2]), 5000.0);
        assert_eq!(num(&r[3]), c.speed);
        let want =
            planar::verdict(&planar::parameters(&v, PlanarKind::Pinned, t, c).unwrap()).unwrap();
        assert_eq!(
            (num(&r[4]), num(&r[5])),
            (want.sigma_d, want.omega_d),
            "{r:?}"
        );
        assert_eq!(r[6], want.class.name(), "{r:?}");
        classes.insert(r[6].clone());
    }
    // The grid spans the boundary: the thinnest fins are unstable somewhere, the thickest
    // stable somewhere.
    assert!(
        classes.contains("stable") && classes.len() > 1,
        "{classes:?}"
    );
    assert!(out.join("boundary.csv").is_file());
    assert!(out.join("critical_thickness.csv").is_file());
    // The TN 4197 curve (Martin's form: Mach 0.43 at 1.2 mm, 1.70 at 3 mm here), in the
    // map's axes, where it lies inside the Mach range; it must agree with boundary.csv's
    // TN 4197 column.
    let overlay = std::fs::read_to_string(out.join("overlay_TN_4197.csv")).unwrap();
    let boundary = std::fs::read_to_string(out.join("boundary.csv")).unwrap();
    let mut expected = Vec::new();
    for l in boundary.lines().skip(1) {
        let f: Vec<&str> = l.split(',').collect();
        if f[4] == "crossing" {
            expected.push(format!("{},{}", f[0], f[3]));
        }
    }
    let got: Vec<String> = overlay.lines().skip(1).map(String::from).collect();
    assert_eq!(overlay.lines().next(), Some("thickness_m,mach"));
    assert_eq!(got, expected);
    assert!(
        !got.is_empty(),
        "TN 4197 should cross Mach 0.5..2.5 for some thickness"
    );
}

fn stderr_of(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn bad_input_gives_diagnostics_and_nonzero_exit() {
    let dir = tempfile::tempdir().unwrap();
    // A vehicle without fins (the imported NASTRAN tube) in a scenario.
    let file = dir.path().join("tube.vdl");
    std::fs::write(
        &file,
        format!(
            "import \"{}\"\n\nscenario tube_flight {{\n  vehicle = tube21\n\n  initial {{\n    velocity = (200, 0, 0) m/s\n    altitude = 1 km\n  }}\n\n  run {{\n    stop_time = 1 s\n  }}\n}}\n",
            repo("examples/tube_from_nastran.vdl").display()
        ),
    )
    .unwrap();
    let o = bin()
        .args(["analyze", "planar", "--pinned"])
        .arg(&file)
        .args(["--scenario", "tube_flight", "--cache-dir"])
        .arg(cache())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", stderr_of(&o));
    assert!(
        stderr_of(&o).contains("analysis::planar::no_fins"),
        "{}",
        stderr_of(&o)
    );

    // An empty thickness range (COUNT = 0), checked like a vehicle-file count.
    let o = bin()
        .args(["analyze", "map", "--planar", "--pinned"])
        .arg(repo("examples/thesis/section_6_5.vdl"))
        .args(["--scenario", "subsonic_t04", "--thickness", "1mm:2mm:0"])
        .args(["--mach", "0.5:1:3", "--out"])
        .arg(dir.path().join("never"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr_of(&o).contains("vdl::value::range"),
        "{}",
        stderr_of(&o)
    );
    assert!(!dir.path().join("never").exists());

    // 200 m/s: drag cannot balance SPHADS-1's weight anywhere in the atmosphere.
    let o = bin()
        .args(["analyze", "planar", "--unpinned"])
        .arg(repo("examples/thesis/section_6_5.vdl"))
        .args(["--scenario", "subsonic_t04", "--cache-dir"])
        .arg(cache())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr_of(&o).contains("analysis::planar::no_equilibrium"),
        "{}",
        stderr_of(&o)
    );
}

/// `analyze planar` prints the NACA TN 4197 flutter Mach in both published forms (the
/// README claims it); the numbers are checked against the formula evaluated here by hand
/// for SPHADS-1's fins (aluminium, E 70 GPa, nu 0.346; span 127.23 mm, chords 324.68 and
/// 122.67 mm; 0.6 mm thick) at the scenario's 5 km pressure.
#[test]
fn analyze_planar_prints_the_tn4197_flutter_mach_in_both_forms() {
    let run = |format: &str| {
        let o = bin()
            .args(["analyze", "planar", "--pinned"])
            .arg(repo("examples/thesis/section_6_5.vdl"))
            .args([
                "--scenario",
                "subsonic_t06",
                "--format",
                format,
                "--cache-dir",
            ])
            .arg(cache())
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr_of(&o));
        String::from_utf8(o.stdout).unwrap()
    };
    let j: serde_json::Value = serde_json::from_str(&run("json")).unwrap();
    let tn = &j["tn4197"];
    let p = tn["pressure_pa"].as_f64().unwrap();
    // 1976 standard atmosphere at 5 km geometric altitude: 54048 Pa (NOAA-S/T 76-1562,
    // Table I).
    assert!((p - 54_048.3).abs() < 0.5, "{p}");
    let g = 70e9 / (2.0 * 1.346);
    let (b, cr, ct, t): (f64, f64, f64, f64) = (0.127_23, 0.324_68, 0.122_67, 0.6e-3);
    let area = 0.5 * (cr + ct) * b;
    let a = b * b / area;
    let x = |k: f64| k * a.powi(3) * p * (ct / cr + 1.0) / (2.0 * (a + 2.0) * (t / cr).powi(3));
    let martin = (g / x(39.3 / 14.7)).sqrt();
    let pof = (g / x(1.337)).sqrt();
    let got_m = tn["martin"]["flutter_mach"].as_f64().unwrap();
    let got_p = tn["peak_of_flight_291"]["flutter_mach"].as_f64().unwrap();
    eprintln!("SPHADS-1 fin at 5 km: TN 4197 Martin M {got_m}, PoF 291 M {got_p}");
    assert!(
        (got_m - martin).abs() < 1e-12 * martin,
        "{got_m} vs {martin}"
    );
    assert!((got_p - pof).abs() < 1e-12 * pof, "{got_p} vs {pof}");
    assert!((got_p / got_m - 2f64.sqrt()).abs() < 2e-4);
    let text = run("human");
    let line = |name: &str| {
        text.lines()
            .find(|l| l.contains(name))
            .unwrap_or_else(|| panic!("no `{name}` line in\n{text}"))
            .to_string()
    };
    assert!(line("TN 4197 (Martin 1958)").contains(&format!("flutter Mach {martin:.5}")));
    assert!(line("Peak of Flight 291").contains(&format!("flutter Mach {pof:.5}")));
}
