//! The flight margin's cached flutter boundary (issue 13): its cache key covers every input,
//! a warm run reproduces a cold one bit for bit, a bad cache entry is rebuilt and never
//! trusted, and the boundary is the direct p-k solution at its nodes.

mod common;

use std::path::Path;
use std::process::Command;

use flexflight::aero::atmosphere::{Atmosphere, Standard1976};
use flexflight::aero::estimator::ESTIMATOR_MACH;
use flexflight::analysis::flutter::fin::{
    FinAero, clamped_fin_modes, fin_lattice, flutter_model, gaf_table,
};
use flexflight::analysis::flutter::margin::{
    BoundaryArtifact, BoundarySpec, MARGIN_CHORDWISE, solve_boundary, vehicle_spec,
};
use flexflight::analysis::flutter::pk::{PkSettings, pk_solve_cut};
use flexflight::artifact::{Cache, CacheOutcome, write_atomic};
use flexflight::check::{DiskLoader, check_files, ir};
use flexflight::ops::flutter::{boundary_key, cached_boundary, margin_spec};

fn hpr() -> ir::Scenario {
    let file = common::root().join("examples/hpr_k1000/hpr_k1000.vdl");
    let checked = check_files(&[file], &[], &DiskLoader);
    assert!(!checked.has_errors());
    checked.program.scenario("k1000").unwrap().clone()
}

/// A small quasi-steady spec on the vehicle's own layout (2 Mach x 2 altitude nodes), cheap
/// enough to solve in every test.
fn small_spec() -> BoundarySpec {
    let mut s = vehicle_spec(&ESTIMATOR_MACH, 0.0, true, 3, FinAero::QuasiSteady).unwrap();
    s.machs = vec![0.3, 0.6];
    s.speed_ranges.truncate(2);
    s.altitudes.truncate(2);
    s
}

/// Every leaf of the spec's serialisation, perturbed one at a time, changes the key: a
/// property over all its fields (a field added to `BoundarySpec` is covered without an edit
/// here). Fails if the key leaves out any field.
#[test]
fn every_field_of_the_boundary_spec_changes_the_key() {
    let sc = hpr();
    let spec = vehicle_spec(&ESTIMATOR_MACH, 0.0, true, 4, FinAero::Unsteady).unwrap();
    let base = boundary_key(&sc.vehicle, &spec).unwrap();
    let json = serde_json::to_value(&spec).unwrap();
    fn leaves(v: &serde_json::Value, path: Vec<String>, out: &mut Vec<Vec<String>>) {
        match v {
            serde_json::Value::Object(m) => {
                for (k, x) in m {
                    let mut p = path.clone();
                    p.push(k.clone());
                    leaves(x, p, out);
                }
            }
            serde_json::Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    let mut p = path.clone();
                    p.push(i.to_string());
                    leaves(x, p, out);
                }
            }
            _ => out.push(path),
        }
    }
    let mut paths = Vec::new();
    leaves(&json, Vec::new(), &mut paths);
    assert!(paths.len() > 40, "{}", paths.len());
    for path in &paths {
        let mut j = json.clone();
        let mut x = &mut j;
        for p in path {
            x = match x {
                serde_json::Value::Object(m) => m.get_mut(p).unwrap(),
                serde_json::Value::Array(a) => &mut a[p.parse::<usize>().unwrap()],
                _ => unreachable!(),
            };
        }
        *x = match x.clone() {
            serde_json::Value::Bool(b) => serde_json::Value::Bool(!b),
            serde_json::Value::Number(n) if n.is_u64() => (n.as_u64().unwrap() + 1).into(),
            serde_json::Value::Number(n) => (n.as_f64().unwrap() * 1.001 + 1e-3).into(),
            serde_json::Value::String(s) => serde_json::Value::String(
                if s == "unsteady" {
                    "quasi_steady"
                } else {
                    "unsteady"
                }
                .into(),
            ),
            other => panic!("unexpected leaf {other:?} at {path:?}"),
        };
        let changed: BoundarySpec = serde_json::from_value(j).unwrap();
        assert_ne!(changed, spec, "{path:?}");
        let k = boundary_key(&sc.vehicle, &changed).unwrap();
        assert_ne!(k, base, "the key ignores spec field {path:?}");
    }
}

/// An edit of a vehicle.
type Edit = Box<dyn Fn(&mut ir::Vehicle)>;

/// The vehicle's structural and fin inputs change the key (each one the clamped modes depend
/// on); the scenario's flight does not enter it (the boundary is the vehicle's).
#[test]
fn the_fin_and_structure_inputs_change_the_key_and_the_flight_does_not() {
    let sc = hpr();
    let spec = small_spec();
    let base = boundary_key(&sc.vehicle, &spec).unwrap();
    let edits: Vec<(&str, Edit)> = vec![
        (
            "fin thickness",
            Box::new(|v| v.fins.as_mut().unwrap().thickness.value *= 1.01),
        ),
        (
            "fin span",
            Box::new(|v| v.fins.as_mut().unwrap().span.value *= 1.01),
        ),
        (
            "fin root chord",
            Box::new(|v| v.fins.as_mut().unwrap().root_chord.value *= 1.01),
        ),
        (
            "fin tip chord",
            Box::new(|v| v.fins.as_mut().unwrap().tip_chord.value *= 1.01),
        ),
        (
            "fin sweep",
            Box::new(|v| v.fins.as_mut().unwrap().leading_edge_sweep.value += 0.01),
        ),
        (
            "fin cant",
            Box::new(|v| v.fins.as_mut().unwrap().cant.value += 0.01),
        ),
        (
            "fin Young's modulus",
            Box::new(|v| v.fins.as_mut().unwrap().material.youngs_modulus.value *= 1.01),
        ),
        (
            "fin density",
            Box::new(|v| v.fins.as_mut().unwrap().material.density.value *= 1.01),
        ),
        (
            "fin Poisson ratio",
            Box::new(|v| v.fins.as_mut().unwrap().material.poisson.value *= 1.01),
        ),
        (
            "fin mesh",
            Box::new(|v| {
                if let ir::Structure::Generate(g) = &mut v.structure {
                    g.fin_chord_elements.value += 1;
                }
            }),
        ),
    ];
    for (what, edit) in &edits {
        let mut v = sc.vehicle.clone();
        edit(&mut v);
        assert_ne!(boundary_key(&v, &spec).unwrap(), base, "{what}");
    }
    // What the clamped fin does not see leaves the key alone (a motor or payload variant
    // shares the boundary), and indeed leaves the fin's modes unchanged.
    let unseen: Vec<(&str, Edit)> = vec![
        (
            "body material",
            Box::new(|v| v.material.density.value *= 1.5),
        ),
        (
            "body length and masses",
            Box::new(|v| {
                if let ir::Structure::Generate(g) = &mut v.structure {
                    g.body.length.value *= 1.1;
                    g.point_masses.clear();
                }
            }),
        ),
        ("motor", Box::new(|v| v.motor = None)),
    ];
    let modes = clamped_fin_modes(&sc.vehicle, 3).unwrap();
    for (what, edit) in &unseen {
        let mut v = sc.vehicle.clone();
        edit(&mut v);
        assert_ne!(v, sc.vehicle, "{what}");
        assert_eq!(boundary_key(&v, &spec).unwrap(), base, "{what}");
        let m = clamped_fin_modes(&v, 3).unwrap();
        assert_eq!(m.omega, modes.omega, "{what}");
        assert_eq!(m.normal_rows, modes.normal_rows, "{what}");
    }
    // The flight (rail elevation, wind, parachutes) is not an input; the site is.
    let mut sc2 = sc.clone();
    sc2.launch.as_mut().unwrap().elevation.value *= 0.9;
    sc2.wind = None;
    sc2.parachutes.clear();
    assert_eq!(boundary_key(&sc2.vehicle, &spec).unwrap(), base);
    let spec_of = |s: &ir::Scenario| margin_spec(s, &ESTIMATOR_MACH).unwrap();
    assert_eq!(spec_of(&sc2), spec_of(&sc));
    sc2.launch.as_mut().unwrap().site_altitude.value += 1000.0;
    assert_ne!(spec_of(&sc2), spec_of(&sc));
}

fn boundary_file(cache: &Cache, sc: &ir::Scenario, spec: &BoundarySpec) -> std::path::PathBuf {
    cache.path_for(&boundary_key(&sc.vehicle, spec).unwrap())
}

/// Miss, then hit with the same values bit for bit; a corrupt file (one payload byte flipped:
/// the checksum fails) and a valid container whose contents do not fit the spec are both
/// rebuilt, never used, and the call succeeds. Fails if a bad entry were trusted or fatal.
#[test]
fn a_bad_cache_entry_is_rebuilt_not_trusted_and_not_fatal() {
    let sc = hpr();
    let spec = small_spec();
    let dir = tempfile::tempdir().unwrap();
    let cache = Cache::new(dir.path());
    let cold = cached_boundary(&sc.vehicle, &spec, &cache).unwrap();
    assert!(
        matches!(cold.outcome, CacheOutcome::Miss),
        "{}",
        cold.outcome
    );
    let warm = cached_boundary(&sc.vehicle, &spec, &cache).unwrap();
    assert!(warm.outcome.is_hit(), "{}", warm.outcome);
    let bits = |b: &flexflight::analysis::flutter::margin::Boundary| {
        b.speeds.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    };
    assert_eq!(bits(&warm.boundary), bits(&cold.boundary));
    assert_eq!(warm.boundary, cold.boundary);
    assert_eq!(warm.fin, cold.fin);

    // A flipped payload byte.
    let path = boundary_file(&cache, &sc, &spec);
    let mut bytes = std::fs::read(&path).unwrap();
    let last = bytes.len() - 9;
    bytes[last] ^= 0x55;
    std::fs::write(&path, &bytes).unwrap();
    let again = cached_boundary(&sc.vehicle, &spec, &cache).unwrap();
    assert!(
        matches!(again.outcome, CacheOutcome::Rebuilt { .. }),
        "{}",
        again.outcome
    );
    assert_eq!(bits(&again.boundary), bits(&cold.boundary));
    assert!(
        cached_boundary(&sc.vehicle, &spec, &cache)
            .unwrap()
            .outcome
            .is_hit()
    );

    // A valid container with a value that is not a flutter speed.
    let key = boundary_key(&sc.vehicle, &spec).unwrap();
    let mut art = BoundaryArtifact::new(&cold.boundary, &cold.fin);
    art.speeds[0] = f64::NAN;
    write_atomic(dir.path(), &key, &art).unwrap();
    let again = cached_boundary(&sc.vehicle, &spec, &cache).unwrap();
    assert!(
        matches!(again.outcome, CacheOutcome::Rebuilt { .. }),
        "{}",
        again.outcome
    );
    assert_eq!(bits(&again.boundary), bits(&cold.boundary));

    // Truncated to its header.
    std::fs::write(&path, &std::fs::read(&path).unwrap()[..100]).unwrap();
    let again = cached_boundary(&sc.vehicle, &spec, &cache).unwrap();
    assert!(matches!(again.outcome, CacheOutcome::Rebuilt { .. }));
    assert_eq!(bits(&again.boundary), bits(&cold.boundary));
}

/// At its nodes the vehicle's (unsteady) boundary is the flutter speed of a p-k solution
/// made directly (fin lattice, GAF table and sweep built here, not through `solve_boundary`);
/// between two altitude nodes the interpolated `V_F` is within the stated error of a direct
/// solution at the mid altitude.
#[test]
fn the_boundary_matches_a_direct_p_k_at_its_nodes_and_between_them() {
    let sc = hpr();
    let mut spec = vehicle_spec(&ESTIMATOR_MACH, 0.0, true, 4, FinAero::Unsteady).unwrap();
    // Mach 0.6 and 2.0 (the harmonic lattice and the Mach box), two altitude nodes.
    let keep = [2usize, 10];
    spec.machs = keep.iter().map(|&i| spec.machs[i]).collect();
    spec.speed_ranges = keep.iter().map(|&i| spec.speed_ranges[i]).collect();
    spec.altitudes.truncate(2);
    assert_eq!(spec.machs, [0.6, 2.0]);
    let modes = clamped_fin_modes(&sc.vehicle, 4).unwrap();
    let b = solve_boundary(&modes, &spec).unwrap();
    let atm = Standard1976::new();
    let s = spec.fin_settings();
    assert_eq!(s.chordwise, MARGIN_CHORDWISE);
    let lattice = fin_lattice(&modes, &s).unwrap();
    let w_max = modes.omega.iter().copied().fold(0.0, f64::max);
    let direct = |i: usize, h: f64| -> f64 {
        let [lo, hi] = b.speed_ranges[i];
        let speeds: Vec<f64> = (0..40).map(|k| lo + (hi - lo) * k as f64 / 39.0).collect();
        let mut s2 = s;
        s2.k_max = 1.2 * w_max * modes.b_ref() / lo;
        let gaf = gaf_table(&modes, &lattice, spec.machs[i], &s2).unwrap();
        let rho = atm.at(h).unwrap().density;
        let (sol, _) = pk_solve_cut(
            &flutter_model(&modes, rho),
            &gaf,
            &speeds,
            PkSettings::default(),
        )
        .unwrap();
        sol.critical().expect("a flutter point in the sweep").speed
    };
    for (i, &m) in spec.machs.iter().enumerate() {
        for (j, &h) in spec.altitudes.iter().enumerate() {
            let p = b.at(m, h);
            assert!(p.in_grid && p.trusted && !p.lower_bound && !p.upper_bound);
            assert_eq!(p.flutter_speed, b.speeds[i * 2 + j]);
            let vf = direct(i, h);
            assert_eq!(p.flutter_speed, vf, "Mach {m}, {h} m");
        }
        // Mid-way (1200 m of the 2600 m interval): V_F sqrt(rho) interpolated. Achieved:
        // 8.9e-5 at Mach 0.6, 1.25e-4 at Mach 2.0 (linear interpolation of V_F itself would
        // be 3.0e-3 at both).
        let h = 0.5 * (spec.altitudes[0] + spec.altitudes[1]);
        let (vi, vd) = (b.at(m, h).flutter_speed, direct(i, h));
        assert!((vi / vd - 1.0).abs() < 2e-4, "Mach {m}: {vi} vs {vd}");
    }
    // Outside the grid: flagged, evaluated at the edge.
    let top = b.at(2.5, 100.0);
    assert!(!top.in_grid);
    assert_eq!(top.flutter_speed, b.at(2.0, 100.0).flutter_speed);
    assert!(!b.at(0.6, 3000.0).in_grid);
}

fn flexflight() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn run(out: &Path, cache: &Path) -> (String, serde_json::Value) {
    let o = flexflight()
        .arg("run")
        .arg(common::root().join("examples/hpr_k1000/hpr_k1000.vdl"))
        .args(["--scenario", "k1000", "--set", "run.stop_time=3 s", "--out"])
        .arg(out)
        .arg("--cache-dir")
        .arg(cache)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    (String::from_utf8_lossy(&o.stderr).to_string(), s)
}

/// A warm run reads the boundary from the cache (no eigen-solve, no p-k: the cache says hit)
/// and writes the cold run's `flutter_margin.csv` byte for byte; a corrupted entry is rebuilt
/// with a warning, and the run still succeeds with the same margin.
#[test]
fn a_warm_run_writes_the_cold_runs_margin_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let (_, cold) = run(&dir.path().join("cold"), &cache);
    let fm = &cold["flutter_margin"];
    assert_eq!(fm["boundary_cache"], "miss");
    // The doublet lattice since issue 33 (its own 0.95 node floored by the box rule: before
    // that fix this K1000 margin was not computed).
    assert_eq!(fm["aero"], "doublet_lattice");
    let (_, warm) = run(&dir.path().join("warm"), &cache);
    assert_eq!(warm["flutter_margin"]["boundary_cache"], "hit");
    assert_eq!(warm["flutter_margin"]["boundary_hash"], fm["boundary_hash"]);
    let csv =
        |d: &str| std::fs::read_to_string(dir.path().join(d).join("flutter_margin.csv")).unwrap();
    assert!(
        csv("warm") == csv("cold"),
        "the warm margin differs from the cold one"
    );
    // Corrupt the cached boundary: rebuilt, not fatal, the same margin.
    let file = cache.join(format!("{}.ffa", fm["boundary_hash"].as_str().unwrap()));
    let mut bytes = std::fs::read(&file).unwrap();
    let i = bytes.len() / 2;
    bytes[i] ^= 0xff;
    std::fs::write(&file, &bytes).unwrap();
    let (stderr, bad) = run(&dir.path().join("bad"), &cache);
    assert_eq!(bad["flutter_margin"]["boundary_cache"], "rebuilt");
    assert!(
        stderr.contains("warning: flutter boundary: rebuilt"),
        "{stderr}"
    );
    assert!(
        csv("bad") == csv("cold"),
        "the rebuilt margin differs from the cold one"
    );
    inspect_shows_the_cached_boundary_and_panel_matrices(&cache, &cold);
}

/// `inspect` of the run's two vehicle artifacts besides the structure (issue 12, item 4;
/// issue 13): the flutter boundary prints the speeds the run used, bit for bit, and the
/// aerodynamics artifact prints every fin's panel matrices, equal bit for bit to the panel
/// model compiled directly for the same vehicle. Before, `inspect` knew only the compiled
/// structure and refused both with `artifact::schema`.
fn inspect_shows_the_cached_boundary_and_panel_matrices(cache: &Path, cold: &serde_json::Value) {
    use flexflight::aero::panel::fin_model::{PanelSettings, compile as panels};
    use flexflight::structure::compile::compile;
    let inspect = |hash: &str, json: bool| -> String {
        let mut c = flexflight();
        c.arg("inspect").arg(cache.join(format!("{hash}.ffa")));
        if json {
            c.args(["--format", "json"]);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stdout).unwrap()
    };
    let fm = &cold["flutter_margin"];
    let b: serde_json::Value =
        serde_json::from_str(&inspect(fm["boundary_hash"].as_str().unwrap(), true)).unwrap();
    assert_eq!(b["artifact"], "flutter boundary");
    let flat: Vec<f64> = b["flutter_speeds_by_mach"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
        .collect();
    let used: Vec<f64> = fm["boundary"]["flutter_speeds"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(flat, used);
    let hash = cold["aero_artifact_hash"].as_str().unwrap();
    let a: serde_json::Value = serde_json::from_str(&inspect(hash, true)).unwrap();
    assert_eq!(a["artifact"], "aerodynamics");
    let p = &a["fin_panels"];
    let machs: Vec<f64> = p["machs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    // The command line runs faer sequentially (`ops::sequential_linear_algebra`): the
    // matrices rebuilt here must be too, or their last bits follow this process's threads.
    flexflight::ops::sequential_linear_algebra();
    let sc = hpr();
    let (c, _) = compile(&sc.vehicle).unwrap();
    let model = panels(&c, &sc.vehicle, &machs, PanelSettings::default()).unwrap();
    let fins = p["fins"].as_array().unwrap();
    assert_eq!(fins.len(), model.fins.len());
    for (f, (shown, built)) in fins.iter().zip(&model.fins).enumerate() {
        for (g, at) in shown.as_array().unwrap().iter().enumerate() {
            let rows: Vec<f64> = at["transfer"]
                .as_array()
                .unwrap()
                .iter()
                .flat_map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
                .collect();
            assert!(rows == built.at(g), "fin {f}, grid Mach {g}");
        }
    }
    let text = inspect(hash, false);
    assert!(text.contains("fin_panels:") && text.contains("fin_load_weights:"));
}

/// Rows outside the boundary's grid (here the fin table stops at Mach 0.8, so the grid's last
/// Mach node is 0.9) are flagged `in_grid = 0`, counted, and kept out of the minimum that
/// decides the criterion, even when their (edge-evaluated) margin is the smallest. Fails if
/// such a row were silently extrapolated into the minimum.
#[test]
fn rows_outside_the_grid_are_flagged_and_kept_out_of_the_minimum() {
    use flexflight::run::{RunOutput, RunStop};
    let sc = hpr();
    // (t, Mach, altitude): in the grid; in the grid, the fastest; above the last Mach node.
    let rows: Vec<Vec<f64>> = [(0.0, 0.3, 1000.0), (1.0, 0.85, 1000.0), (2.0, 1.5, 1000.0)]
        .iter()
        .map(|&(t, m, h)| vec![t, m, h])
        .collect();
    let o = RunOutput {
        channels: vec!["t".into(), "mach".into(), "altitude".into()],
        rows,
        stop: RunStop::Completed,
        stop_detail: String::new(),
        t_end: 2.0,
        stats: Default::default(),
        wall_seconds: 0.0,
        events: Default::default(),
        verdict: None,
    };
    let dir = tempfile::tempdir().unwrap();
    let m =
        flexflight::ops::flutter::flight_margin(&sc, &o, &[0.0, 0.4, 0.8], &Cache::new(dir.path()));
    let j = &m.json;
    assert_eq!(
        j["boundary"]["machs"],
        serde_json::json!([0.0, 0.3, 0.6, 0.9])
    );
    assert_eq!(j["outside_grid_rows"], 1);
    assert_eq!(j["minimum"]["t"], 1.0);
    assert_eq!(j["minimum"]["in_grid"], true);
    assert_eq!(j["minimum_including_transonic"]["t"], 2.0);
    assert_eq!(j["minimum_including_transonic"]["in_grid"], false);
    let lines: Vec<&str> = m.csv.lines().collect();
    assert!(lines[0].ends_with(",in_grid,uncertainty"), "{}", lines[0]);
    let flags: Vec<&str> = lines[1..]
        .iter()
        .map(|l| l.rsplit(',').nth(1).unwrap())
        .collect();
    assert_eq!(flags, ["1", "1", "0"]);
    // A subsonic grid carries no stated uncertainty.
    assert!(lines[1..].iter().all(|l| l.ends_with(",0")), "{lines:?}");
    // The outside row is evaluated at the grid's edge (Mach 0.9), not extrapolated.
    let edge: f64 = lines[3].split(',').nth(4).unwrap().parse().unwrap();
    let spec = margin_spec(&sc, &[0.0, 0.4, 0.8]).unwrap();
    let b = cached_boundary(&sc.vehicle, &spec, &Cache::new(dir.path())).unwrap();
    assert!(b.outcome.is_hit());
    assert_eq!(edge, b.boundary.at(0.9, 1000.0).flutter_speed);
    assert!(
        m.line.contains("1 rows outside the boundary's grid"),
        "{}",
        m.line
    );
}

fn calisto() -> ir::Scenario {
    let file = common::root().join("examples/calisto/calisto.vdl");
    let checked = check_files(&[file], &[], &DiskLoader);
    assert!(!checked.has_errors());
    checked.program.scenario("calisto").unwrap().clone()
}

/// The margin's Mach grid follows the two theories' ranges, not the fin table's resolution:
/// a table tabulated every 0.01 in Mach (RocketPy's curves, examples/calisto) gets the
/// built-in estimator's supersonic ladder, cut at the table's last node. Fails on a grid that
/// takes every table node above 1.2 (Calisto: 81 supersonic nodes, 729 p-k sweeps, 30 s of
/// every run with an empty cache).
#[test]
fn the_mach_grid_does_not_grow_with_the_tables_resolution() {
    use flexflight::analysis::flutter::margin::vehicle_mach_nodes;
    let sub = [0.0, 0.3, 0.6, 0.9];
    // Issue 33: the transonic band's nodes and the Mach box's first Mach come with any table
    // past 0.9.
    let band = [0.95, 1.0, 1.05, 1.1];
    let with = |above: &[f64]| [&sub[..], &band[..], above].concat();
    // The estimator's own axis: the grid it always had.
    assert_eq!(
        vehicle_mach_nodes(&ESTIMATOR_MACH),
        with(&[1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0])
    );
    let dense = |top: usize| (0..=top).map(|i| i as f64 / 100.0).collect::<Vec<_>>();
    assert_eq!(vehicle_mach_nodes(&dense(200)), with(&[1.2, 1.5, 2.0]));
    assert_eq!(vehicle_mach_nodes(&dense(173)), with(&[1.2, 1.5, 1.73]));
    assert_eq!(vehicle_mach_nodes(&dense(130)), with(&[1.2, 1.3]));
    assert_eq!(vehicle_mach_nodes(&dense(110)), with(&[1.2]));
    assert_eq!(vehicle_mach_nodes(&dense(86)), sub);
    assert_eq!(
        vehicle_mach_nodes(&[0.0, 1.0, 7.0]),
        with(&[1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 7.0])
    );
}

/// A node whose p-k iteration does not converge at the lowest speed of its sweep (Calisto's
/// fin at Mach 1.73 and 15 km: the fourth mode at 174 m/s, k = 4.26, piston theory) is solved
/// from the lowest speed that converges, and the screen below that speed covers the rest.
/// Before, the whole boundary failed and the run wrote "flutter margin: not computed".
#[test]
fn a_node_whose_lowest_speed_does_not_converge_starts_at_the_next_speed() {
    let sc = calisto();
    let mut spec = margin_spec(&sc, &[0.0, 2.0]).unwrap();
    // a_ref from the Mach 0 node's range (3 max(M, 1) a_ref).
    let a_ref = spec.speed_ranges[0][1] / 3.0;
    let hi = 3.0 * 1.73 * a_ref;
    spec.machs = vec![1.73];
    spec.speed_ranges = vec![[0.1 * hi, hi]];
    spec.altitudes = vec![15_000.0];
    let modes = clamped_fin_modes(&sc.vehicle, spec.modes).unwrap();
    let b = solve_boundary(&modes, &spec).unwrap();
    assert_eq!(b.node_lowest_speeds.len(), 1);
    // Since issue 32 the leading-mode screen (pk::screen_below) solves below the raised
    // start, down to where the table holds the two lowest modes' reduced frequencies: the
    // node's lowest speed solved is below the sweep's nominal start and the node is not
    // flagged as raised.
    let lo = b.node_lowest_speeds[0];
    assert!(lo < 0.1 * hi, "{lo} from {}", 0.1 * hi);
    assert!(!b.raised_start(0, 0));
    assert!(b.speeds[0].is_finite() && b.speeds[0] >= lo);
    // The sweep proper still starts at the next speed that converges (the screen is solved
    // from there): without the screen's segments the node would carry that start.
}

/// Under a canopy the vehicle is a frozen rigid body: the margin covers the flight up to the
/// first deployment (issue 32: the margin's warnings counted descent rows). The same three
/// rows as above with a deployment at t = 1.5 s: the row after it (the one outside the grid)
/// is neither written nor counted. Fails on the old code (3 rows, 1 outside the grid).
#[test]
fn margin_rows_end_at_the_first_deployment() {
    use flexflight::run::{EventPoint, FlightEvents, RunOutput, RunStop};
    let sc = hpr();
    let rows: Vec<Vec<f64>> = [(0.0, 0.3, 1000.0), (1.0, 0.85, 1000.0), (2.0, 1.5, 1000.0)]
        .iter()
        .map(|&(t, m, h)| vec![t, m, h])
        .collect();
    let at = |t: f64| EventPoint {
        t,
        ..Default::default()
    };
    let o = RunOutput {
        channels: vec!["t".into(), "mach".into(), "altitude".into()],
        rows,
        stop: RunStop::Completed,
        stop_detail: String::new(),
        t_end: 2.0,
        stats: Default::default(),
        wall_seconds: 0.0,
        events: FlightEvents {
            deployments: vec![("drogue".into(), at(1.4), at(1.5))],
            ..Default::default()
        },
        verdict: None,
    };
    let dir = tempfile::tempdir().unwrap();
    let m =
        flexflight::ops::flutter::flight_margin(&sc, &o, &[0.0, 0.4, 0.8], &Cache::new(dir.path()));
    assert_eq!(m.json["rows_until"], 1.5);
    assert_eq!(m.json["outside_grid_rows"], 0);
    assert_eq!(m.csv.lines().count(), 1 + 2, "{}", m.csv);
}
