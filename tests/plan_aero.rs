//! The plan resolves the aerodynamics (issue 9, defect 9): `flexflight plan` shows the
//! coefficient tables, the fin load weights and the key-node rows a run uses, and a warm
//! run reads the vehicle-only part (estimated tables, load weights) from the cache instead
//! of rebuilding it (issue 11, lever 1), flying the same bits.

use std::path::{Path, PathBuf};
use std::process::Command;

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn thesis() -> PathBuf {
    repo("examples/thesis/section_6_5.vdl")
}

fn flexflight(args: &[&str], cache: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .args(args)
        .arg("--cache-dir")
        .arg(cache)
        .output()
        .unwrap()
}

fn plan_json(scenario: &str, sets: &[&str], cache: &Path) -> serde_json::Value {
    let file = thesis();
    let mut args = vec![
        "plan",
        file.to_str().unwrap(),
        "--scenario",
        scenario,
        "--format",
        "json",
    ];
    for s in sets {
        args.extend(["--set", s]);
    }
    let o = flexflight(&args, cache);
    assert!(
        o.status.success(),
        "plan failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

fn run(scenario: &str, out: &Path, sets: &[&str], cache: &Path) -> serde_json::Value {
    let file = thesis();
    let mut args = vec![
        "run",
        file.to_str().unwrap(),
        "--scenario",
        scenario,
        "--out",
        out.to_str().unwrap(),
    ];
    for s in sets {
        args.extend(["--set", s]);
    }
    let o = flexflight(&args, cache);
    assert!(
        o.status.success(),
        "run failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

fn f64s(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// The compiled SPHADS-1 of a scenario, through the library (for the shape rows).
fn compiled(scenario: &str) -> flexflight::structure::compile::CompiledVehicle {
    // Compiled as the command line compiles (faer sequential, `ops::sequential_linear_algebra`):
    // the rows are compared bit for bit with the CLI's plan.
    flexflight::ops::sequential_linear_algebra();
    let checked = flexflight::check::check_files(&[thesis()], &[], &flexflight::check::DiskLoader);
    let sc = checked.program.scenario(scenario).unwrap().clone();
    flexflight::structure::compile::compile(&sc.vehicle)
        .unwrap()
        .0
}

#[test]
fn plan_json_holds_the_tables_load_weights_and_key_node_rows() {
    let cache = tempfile::tempdir().unwrap();
    let p = plan_json("subsonic_t06", &[], cache.path());
    let aero = &p["aero"];
    assert_eq!(aero["source"], "builtin", "{aero}");
    let n = p["n_modes"].as_u64().unwrap() as usize;

    // Both tables with their grids: the estimator's Mach, alpha and altitude axes.
    let tables = aero["tables"].as_array().unwrap();
    let kinds: Vec<&str> = tables.iter().map(|t| t["kind"].as_str().unwrap()).collect();
    assert_eq!(kinds, ["body", "fin"]);
    for t in tables {
        assert_eq!(
            f64s(&t["mach"]),
            flexflight::aero::estimator::ESTIMATOR_MACH.to_vec()
        );
        assert_eq!(
            f64s(&t["altitude_m"]),
            flexflight::aero::estimator::ESTIMATOR_ALTITUDE.to_vec()
        );
        let alpha = f64s(&t["alpha_deg"]);
        assert_eq!((alpha[0], *alpha.last().unwrap()), (-180.0, 180.0));
        // Coefficients at a few Machs inside the grid; a normal-force slope that is
        // positive (the body and each fin lift towards positive alpha).
        let samples = t["samples"].as_array().unwrap();
        assert!(samples.len() >= 3, "{t}");
        for s in samples {
            assert!(s["cn_alpha_per_rad"].as_f64().unwrap() > 0.0, "{s}");
        }
    }

    // The key-node rows are the compiled shapes at those nodes, bit for bit.
    let c = compiled("subsonic_t06");
    let rows_of = |node: usize| c.shapes[6 * node * n..6 * (node + 1) * n].to_vec();
    let body = &aero["body"];
    let k = body["key_node"].as_u64().unwrap() as usize;
    assert_eq!(k, c.key_body as usize);
    assert_eq!(f64s(&body["key_node_rows"]), rows_of(k));

    // One entry per fin: key node and its rows, and load weights at every grid Mach that
    // sum to 1 with a centre of pressure on the fin.
    let fins = aero["fins"].as_array().unwrap();
    assert_eq!(fins.len(), c.key_fins.len());
    for (i, f) in fins.iter().enumerate() {
        let k = f["key_node"].as_u64().unwrap() as usize;
        assert_eq!(k, c.key_fins[i] as usize);
        assert_eq!(f64s(&f["key_node_rows"]), rows_of(k));
        let weights = f["weights"].as_array().unwrap();
        assert_eq!(
            weights.len(),
            flexflight::aero::estimator::ESTIMATOR_MACH.len()
        );
        for w in weights {
            assert!((w["sum"].as_f64().unwrap() - 1.0).abs() < 1e-14, "{w}");
            let eta = w["eta_cp"].as_f64().unwrap();
            let xi = w["xi_cp"].as_f64().unwrap();
            assert!(eta > 0.0 && eta < 1.0 && xi > 0.0 && xi < 1.0, "{w}");
            // Body x of the centre of pressure between the root chord's leading and
            // trailing edges (SPHADS-1: root chord 0.32468 m ending at the body's tail).
            let x = f64s(&w["position_cp"])[0];
            assert!(x < -2.75 + 0.32468 && x > -2.75, "{w}");
        }
    }
}

#[test]
fn plan_text_shows_the_aerodynamics() {
    let cache = tempfile::tempdir().unwrap();
    let file = thesis();
    let o = flexflight(
        &["plan", file.to_str().unwrap(), "--scenario", "subsonic_t06"],
        cache.path(),
    );
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    for needle in [
        "aerodynamics   builtin coefficient tables",
        "body table",
        "fin  table",
        "body key node",
        "fin 1 key node",
        "fin 4 key node",
        "load weights over",
    ] {
        assert!(text.contains(needle), "no `{needle}` in\n{text}");
    }
}

#[test]
fn a_warm_run_reads_the_aerodynamics_from_the_cache_and_flies_the_same_bits() {
    let cache = tempfile::tempdir().unwrap();
    let dirs: Vec<tempfile::TempDir> = (0..2).map(|_| tempfile::tempdir().unwrap()).collect();
    let sets = ["run.stop_time=0.02 s"];
    let cold = run("subsonic_t06", dirs[0].path(), &sets, cache.path());
    let warm = run("subsonic_t06", dirs[1].path(), &sets, cache.path());
    assert_eq!(cold["aero_cache"], "miss");
    assert_eq!(warm["aero_cache"], "hit");
    assert_eq!(cold["aero_artifact_hash"], warm["aero_artifact_hash"]);
    // The artifact is a file of the cache, next to the structure's.
    let hash = warm["aero_artifact_hash"].as_str().unwrap();
    assert!(cache.path().join(format!("{hash}.ffa")).is_file());
    for f in [
        "history.csv",
        "aero_tables/body.csv",
        "aero_tables/fins.csv",
    ] {
        let a = std::fs::read(dirs[0].path().join(f)).unwrap();
        let b = std::fs::read(dirs[1].path().join(f)).unwrap();
        assert!(a == b, "{f} differs between the cold and the warm run");
    }
}

#[test]
fn a_corrupt_aero_artifact_is_rebuilt_not_used() {
    let cache = tempfile::tempdir().unwrap();
    let dirs: Vec<tempfile::TempDir> = (0..2).map(|_| tempfile::tempdir().unwrap()).collect();
    let sets = ["run.stop_time=0.01 s"];
    let cold = run("subsonic_t06", dirs[0].path(), &sets, cache.path());
    let hash = cold["aero_artifact_hash"].as_str().unwrap();
    let path = cache.path().join(format!("{hash}.ffa"));
    let mut bytes = std::fs::read(&path).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0x40;
    std::fs::write(&path, bytes).unwrap();
    let again = run("subsonic_t06", dirs[1].path(), &sets, cache.path());
    assert_eq!(again["aero_cache"], "rebuilt");
    let a = std::fs::read(dirs[0].path().join("history.csv")).unwrap();
    let b = std::fs::read(dirs[1].path().join("history.csv")).unwrap();
    assert!(a == b);
}

#[test]
fn a_sweep_shares_one_aero_artifact_per_vehicle() {
    // Three speeds of one vehicle share one set of tables and weights; two thicknesses are
    // two vehicles (two structures, two sets of load weights).
    let cache = tempfile::tempdir().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let src = format!(
        "import \"{}\"\n\nsweep speeds {{\n  scenario = subsonic_t06\n  analysis = run\n  grid {{\n    fins.thickness = [0.6 mm, 0.8 mm]\n    initial.velocity = [(150, 0, 0) m/s, (200, 0, 0) m/s, (250, 0, 0) m/s]\n  }}\n}}\n",
        thesis().display()
    );
    let file = dir.path().join("sweep.vdl");
    std::fs::write(&file, src).unwrap();
    let out = dir.path().join("out");
    let o = flexflight(
        &[
            "sweep",
            file.to_str().unwrap(),
            "--sweep",
            "speeds",
            "--set",
            "run.stop_time=0.005 s",
            "--out",
            out.to_str().unwrap(),
        ],
        cache.path(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut hashes = std::collections::BTreeMap::<String, Vec<String>>::new();
    for e in std::fs::read_dir(out.join("cases")).unwrap() {
        let s: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(e.unwrap().path().join("summary.json")).unwrap(),
        )
        .unwrap();
        let thickness = s["sweep_case"]["overrides"].to_string();
        let thickness = thickness.split("mm").next().unwrap().to_string();
        hashes
            .entry(s["aero_artifact_hash"].as_str().unwrap().to_string())
            .or_default()
            .push(thickness);
    }
    assert_eq!(hashes.len(), 2, "{hashes:?}");
    for cases in hashes.values() {
        assert_eq!(cases.len(), 3, "{hashes:?}");
        assert!(cases.iter().all(|c| c == &cases[0]), "{hashes:?}");
    }
}
