//! `flexflight run` end to end through the binary: the free tumble of thesis 6.4 conserves
//! energy, a gravity-only flight follows the analytic parabola, a ground impact stops the run
//! cleanly with complete files, and bad input writes nothing.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// One cache shared by the tests of this file (the artifact is written atomically).
fn cache() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("run-test-cache")
}

struct History {
    columns: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl History {
    fn read(dir: &Path) -> History {
        let text = std::fs::read_to_string(dir.join("history.csv")).unwrap();
        let mut lines = text.lines();
        let columns: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect())
            .collect();
        for r in &rows {
            assert_eq!(r.len(), columns.len());
            assert!(r.iter().all(|v| v.is_finite()), "non-finite row {r:?}");
        }
        History { columns, rows }
    }

    fn col(&self, name: &str) -> Vec<f64> {
        let i = self
            .columns
            .iter()
            .position(|c| c == name)
            .unwrap_or_else(|| panic!("{name}"));
        self.rows.iter().map(|r| r[i]).collect()
    }
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

fn run(file: &Path, scenario: &str, out: &Path, sets: &[&str]) -> std::process::Output {
    let mut c = bin();
    c.arg("run")
        .arg(file)
        .args(["--scenario", scenario])
        .arg("--out")
        .arg(out);
    c.arg("--cache-dir").arg(cache());
    for s in sets {
        c.args(["--set", s]);
    }
    c.output().unwrap()
}

#[test]
fn free_tumble_conserves_energy_for_one_second() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("tumble");
    let o = run(
        &repo("examples/free_tumble.vdl"),
        "free_tumble",
        &out,
        &["run.stop_time=1 s"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let h = History::read(&out);
    assert_eq!(h.rows.len(), 101, "0 to 1 s every 10 ms");
    let t = h.col("t");
    assert_eq!((t[0], t[100]), (0.0, 1.0));
    let e = h.col("energy_total");
    let drift = e.iter().map(|v| (v - e[0]).abs()).fold(0.0, f64::max) / e[0].abs();
    assert!(drift < 1e-6, "relative energy drift {drift:e}");
    // No gravity: the gravitational channel is zero and the vehicle really vibrates.
    assert!(h.col("energy_gravitational").iter().all(|v| *v == 0.0));
    assert!(h.col("energy_strain").iter().any(|v| *v > 0.0));
    // Momentum in the inertial frame is conserved too (no loads).
    for axis in ["x", "y", "z"] {
        let p = h.col(&format!("momentum_inertial_{axis}"));
        let scale = p.iter().map(|v| v.abs()).fold(1e-12, f64::max);
        let dp = p.iter().map(|v| (v - p[0]).abs()).fold(0.0, f64::max);
        assert!(dp / scale < 1e-6, "momentum {axis} drift {dp:e}");
    }
    let s = summary(&out);
    assert_eq!(s["stop_reason"], "completed");
    assert_eq!(s["scenario"], "free_tumble");
    assert_eq!(s["vehicle"], "sphads1");
    assert_eq!(s["overrides"].as_array().unwrap().len(), 3);
    assert!(s["accepted_steps"].as_u64().unwrap() > 0);
    assert!(s["rhs_evaluations"].as_u64().unwrap() >= 6 * s["accepted_steps"].as_u64().unwrap());
    assert_eq!(s["artifact_hash"].as_str().unwrap().len(), 64);
    assert!(s["extrema"]["energy_total"]["max"].as_f64().is_some());
    eprintln!("free tumble: relative energy drift {drift:e}");
}

/// A scenario of SPHADS-1 with gravity only (uniform, no altitude correction): launched at
/// 50 m/s along the body axis pitched 30° up, from 20 m.
fn gravity_scenario(dir: &Path) -> PathBuf {
    let vehicle = repo("vehicles/sphads1.vdl");
    let text = format!(
        r#"import "{}"

scenario drop {{
  vehicle = sphads1
  with {{
    forces.body_aero.enabled = false
    forces.fin_aero.enabled = false
    forces.gravity.altitude_correction = false
  }}
  initial {{
    velocity = (50, 0, 0) m/s
    angular_velocity = (0, 0, 0) rad/s
    attitude = euler(0 deg, 30 deg, 0 deg)
    altitude = 20 m
  }}
  run {{
    stop_time = 10 s
    integrator = dopri5
    rtol = 1e-10
    atol = 1e-12
    output_interval = 10 ms
    stop_on_ground = true
  }}
}}
"#,
        vehicle.display()
    );
    let file = dir.join("drop.vdl");
    std::fs::write(&file, text).unwrap();
    file
}

#[test]
fn gravity_only_flight_follows_the_parabola() {
    let dir = tempfile::tempdir().unwrap();
    let file = gravity_scenario(dir.path());
    let out = dir.path().join("out");
    let o = run(&file, "drop", &out, &["run.stop_time=3 s"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let h = History::read(&out);
    assert_eq!(summary(&out)["stop_reason"], "completed");
    let (s30, c30) = 30f64.to_radians().sin_cos();
    let (vx, vz, g) = (50.0 * c30, -50.0 * s30, 9.806);
    // No rotation and a uniform field: every point, the origin and the mass centre alike,
    // moves on r0 + v0 t + g t²/2.
    let (t, x, z) = (h.col("t"), h.col("p_inertial_x"), h.col("p_inertial_z"));
    let mut worst: f64 = 0.0;
    for k in 0..t.len() {
        let ex = vx * t[k];
        let ez = -20.0 + vz * t[k] + 0.5 * g * t[k] * t[k];
        worst = worst.max((x[k] - ex).abs()).max((z[k] - ez).abs());
    }
    assert!(
        worst < 1e-6,
        "largest departure from the parabola {worst:e} m"
    );
    // The mass centre's inertial momentum grows by m g t along z: m from p_B = m V_B at t = 0.
    let m = h.col("momentum_body_x")[0] / h.col("v_body_x")[0];
    assert!((m - 17.56).abs() < 0.01, "mass {m}");
    let pz = h.col("momentum_inertial_z");
    let k = t.len() - 1;
    assert!((pz[k] - pz[0] - m * g * t[k]).abs() < 1e-6 * m * g * t[k]);
    // Energy: kinetic + m g h is conserved.
    let e = h.col("energy_total");
    let drift = e.iter().map(|v| (v - e[0]).abs()).fold(0.0, f64::max) / e[0].abs();
    assert!(drift < 1e-8, "energy drift {drift:e}");
    // Attitude stays put.
    assert!(h.col("pitch").iter().all(|p| (p - 30.0).abs() < 1e-6));
    eprintln!("parabola: worst departure {worst:e} m, energy drift {drift:e}");
}

#[test]
fn ground_impact_stops_cleanly_with_complete_files() {
    let dir = tempfile::tempdir().unwrap();
    let file = gravity_scenario(dir.path());
    let out = dir.path().join("out");
    let o = run(&file, "drop", &out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&out);
    assert_eq!(s["stop_reason"], "ground");
    let h = History::read(&out);
    let (t, z) = (h.col("t"), h.col("p_inertial_z"));
    // Analytic impact: -20 - 25 t + g t²/2 = 0.
    let g = 9.806;
    let t_hit = (25.0 + (625.0 + 2.0 * g * 20.0_f64).sqrt()) / g;
    let last = t.len() - 1;
    assert_eq!(t[last], s["t_end"].as_f64().unwrap());
    // The stop is located on the step's interpolant: at the impact, to interpolation accuracy.
    assert!((t[last] - t_hit).abs() < 1e-6, "{} vs {t_hit}", t[last]);
    assert!(z[last] >= 0.0 && z[last] < 1e-6, "{}", z[last]);
    assert!(z[..last].iter().all(|v| *v < 0.0));
    // Rows every 10 ms up to the stop, then the stopping state.
    assert!(t.windows(2).all(|w| w[1] > w[0]));
    assert_eq!(last, (t_hit / 0.01).floor() as usize + 1);
}

#[test]
fn unknown_scenario_fails_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never");
    let o = run(
        &repo("examples/free_tumble.vdl"),
        "no_such_scenario",
        &out,
        &[],
    );
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("free_tumble"),
        "lists the declared ones"
    );
    assert!(!out.exists());
}

/// A thesis scenario with body and fin aerodynamics flies (first 50 ms, before its first
/// gust): the run completes, the fins are loaded (their flap coordinates move), and the
/// tables the built-in estimator produced are written beside the history.
#[test]
fn a_thesis_scenario_flies_with_body_and_fin_aerodynamics() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sub06");
    let o = run(
        &repo("examples/thesis/section_6_5.vdl"),
        "subsonic_t06",
        &out,
        &["run.stop_time=0.05 s"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&out);
    assert_eq!(s["stop_reason"], "completed");
    let flap = &s["extrema"]["eta_fin1_flap"];
    let moved = flap["max"]
        .as_f64()
        .unwrap()
        .abs()
        .max(flap["min"].as_f64().unwrap().abs());
    assert!(moved > 1e-7, "fin 1 flap did not move: {flap}");
    for t in ["body.csv", "fins.csv"] {
        let text = std::fs::read_to_string(out.join("aero_tables").join(t)).unwrap();
        assert!(text.lines().count() > 100, "{t} is too short");
    }
}

/// A run that flies but cannot write one of its files writes none of them: here
/// `summary.json` is a directory in the output directory, so it cannot be replaced. Before,
/// `history.csv` and `aero_tables/` were already written when the summary failed.
#[test]
fn a_run_that_cannot_write_every_output_writes_none() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sub06");
    std::fs::create_dir_all(out.join("summary.json").join("in_the_way")).unwrap();
    let o = run(
        &repo("examples/thesis/section_6_5.vdl"),
        "subsonic_t06",
        &out,
        &["run.stop_time=0.02 s"],
    );
    assert!(!o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("cannot write the run outputs"), "{stderr}");
    let mut left: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    left.sort();
    assert_eq!(left, vec!["summary.json".to_string()], "{left:?}");
    // With the obstacle gone, the same run writes everything.
    std::fs::remove_dir_all(out.join("summary.json")).unwrap();
    let o = run(
        &repo("examples/thesis/section_6_5.vdl"),
        "subsonic_t06",
        &out,
        &["run.stop_time=0.02 s"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in [
        "history.csv",
        "summary.json",
        "aero_tables/body.csv",
        "aero_tables/fins.csv",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
}

#[test]
fn plan_prints_json() {
    let o = bin()
        .arg("plan")
        .arg(repo("examples/free_tumble.vdl"))
        .args(["--scenario", "free_tumble", "--format", "json"])
        .arg("--cache-dir")
        .arg(cache())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let p: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(p["n_modes"], 10);
    assert_eq!(p["initial_state"].as_array().unwrap().len(), 33);
    assert_eq!(p["initial_state"][2], -5000.0);
    assert_eq!(p["forces"].as_array().unwrap().len(), 0);
    // + speed, acceleration, height (no aero blocks: no static margin).
    assert_eq!(
        p["channels"].as_array().unwrap().len(),
        24 + 2 * 10 + 25 + 3
    );
    assert!(p["motor"].is_null());
}

/// SPHADS-1 with a constant 100 N motor burning 1 s at the nozzle key node, written next to
/// a copy of the vehicle file; two scenarios: `burn` (level, gravity and aerodynamics off,
/// `misalignment` as given) and `mach_start` (for the plan of a Mach and quaternion start).
fn thrust_files(dir: &Path, misalignment: &str) -> PathBuf {
    let vehicle = std::fs::read_to_string(repo("vehicles/sphads1.vdl")).unwrap();
    let vehicle = vehicle.replacen(
        "  forces {\n",
        &format!(
            "  forces {{\n    thrust {{\n      curve = \"motor.csv\"\n      misalignment = {misalignment}\n    }}\n\n"
        ),
        1,
    );
    std::fs::write(dir.join("sphads1_motor.vdl"), vehicle).unwrap();
    std::fs::write(dir.join("motor.csv"), "time_s,thrust_N\n0,100\n1,100\n").unwrap();
    let text = r#"import "sphads1_motor.vdl"

scenario burn {
  vehicle = sphads1
  with {
    forces.gravity.enabled = false
    forces.body_aero.enabled = false
    forces.fin_aero.enabled = false
  }
  initial {
    velocity = (0, 0, 0) m/s
    angular_velocity = (0, 0, 0) rad/s
    attitude = euler(0 deg, 0 deg, 0 deg)
    altitude = 1 km
  }
  run {
    stop_time = 1.5 s
    integrator = dopri5
    rtol = 1e-10
    atol = 1e-12
    output_interval = 10 ms
    stop_on_ground = false
  }
}

scenario mach_start {
  vehicle = sphads1
  with {
    forces.body_aero.enabled = false
    forces.fin_aero.enabled = false
  }
  initial {
    mach = 0.5
    angular_velocity = (0, 0, 0) rad/s
    attitude = quaternion(0.8, 0, 0.6, 0)
    altitude = 5 km
  }
  run {
    stop_time = 1 s
  }
}
"#;
    let file = dir.join("burn.vdl");
    std::fs::write(&file, text).unwrap();
    file
}

#[test]
fn aligned_thrust_delivers_its_impulse() {
    let dir = tempfile::tempdir().unwrap();
    let file = thrust_files(dir.path(), "(0, 0, 0) rad");
    let out = dir.path().join("out");
    let o = run(&file, "burn", &out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let h = History::read(&out);
    assert_eq!(summary(&out)["stop_reason"], "completed");
    // Momentum theorem: the inertial momentum gains the total impulse, 100 N s along x.
    let last = h.rows.len() - 1;
    let px = h.col("momentum_inertial_x")[last];
    assert!((px - 100.0).abs() < 1e-6 * 100.0, "impulse {px}");
    // On the axis and aligned: no rotation, and V = I/m after the burn.
    let m = 17.56;
    let vx = h.col("v_body_x")[last];
    assert!((vx - 100.0 / m).abs() < 1e-3 * vx, "v {vx}");
    let w = h.col("omega_body_y");
    assert!(w.iter().all(|v| v.abs() < 1e-9), "{:e}", w[last]);
    eprintln!("aligned thrust: momentum {px}, v {vx}");
}

#[test]
fn misaligned_thrust_pitches_the_vehicle_by_the_hand_moment() {
    let dir = tempfile::tempdir().unwrap();
    let file = thrust_files(dir.path(), "(0, 0.01, 0) rad");
    let out = dir.path().join("out");
    let o = run(&file, "burn", &out, &["run.stop_time=0.2 s"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let h = History::read(&out);
    // T_alpha = (T, 0, -0.01 T) (5.2.2) at the nozzle, 2.75 m aft of the nose; the mass
    // centre is 1.5896 m aft: moment about it (-1.1604, 0, 0) x T_alpha = (0, -0.011604 T, 0).
    // dh_cm/dt equals it while the rotation stays small: h_cm_y(0.2 s) = -0.2321 N m s.
    let last = h.rows.len() - 1;
    let hy = h.col("h_cm_inertial_y")[last];
    let expect = -0.011604 * 100.0 * 0.2;
    assert!(
        (hy - expect).abs() < 0.01 * expect.abs(),
        "h_cm_y {hy} vs {expect}"
    );
    assert!(h.col("omega_body_y")[last] < 0.0);
}

#[test]
fn plan_resolves_mach_quaternion_altitude_and_thrust() {
    let dir = tempfile::tempdir().unwrap();
    let file = thrust_files(dir.path(), "(0, 0, 0.002) rad");
    let o = bin()
        .arg("plan")
        .arg(&file)
        .args(["--scenario", "mach_start", "--format", "json"])
        .arg("--cache-dir")
        .arg(cache())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let p: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let x: Vec<f64> = p["initial_state"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(x[2], -5000.0);
    // quaternion(q0 = 0.8, q1, q2 = 0.6, q3): the runtime stores (eps1, eps2, eps3, eta).
    assert_eq!(&x[3..7], &[0.0, 0.6, 0.0, 0.8]);
    // Mach 0.5 at 5 km: USSA76 T = 288.15 - 6.5 H (H geopotential km), a = sqrt(1.4 R T).
    let hgp: f64 = 6356.766 * 5.0 / (6356.766 + 5.0);
    let a = (1.4_f64 * 8314.32 / 28.9644 * (288.15 - 6.5 * hgp)).sqrt();
    assert!((x[7] - 0.5 * a).abs() < 1e-6, "{} vs {}", x[7], 0.5 * a);
    assert_eq!((x[8], x[9]), (0.0, 0.0));
    let forces = p["forces"].as_array().unwrap();
    let names: Vec<&str> = forces
        .iter()
        .map(|f| f["block"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["gravity", "thrust"]);
    assert_eq!(forces[0]["altitude_correction"], true);
    let t = &forces[1];
    assert!((t["total_impulse"].as_f64().unwrap() - 100.0).abs() < 1e-12);
    assert_eq!(t["misalignment"][2], 0.002);
    assert!((t["nozzle_position"][0].as_f64().unwrap() + 2.75).abs() < 0.05);
    assert_eq!(t["s_translation"].as_array().unwrap().len(), 3 * 10);
}

#[test]
fn deformation_and_alpha_limits_stop_the_run_at_the_first_state_beyond_them() {
    for (set, reason, column, limit) in [
        (
            "run.max_deformation=0.1 mm",
            "max_deformation",
            "max_deformation",
            1e-4,
        ),
        ("run.max_alpha=30 deg", "max_alpha", "alpha", 30.0),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let o = run(
            &repo("examples/free_tumble.vdl"),
            "free_tumble",
            &out,
            &[set],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let s = summary(&out);
        assert_eq!(s["stop_reason"], reason);
        let h = History::read(&out);
        let c = h.col(column);
        let last = c.len() - 1;
        assert!(c[last].abs() > limit, "{reason}: last {}", c[last]);
        assert!(c[..last].iter().all(|v| v.abs() <= limit), "{reason}");
        assert_eq!(h.col("t")[last], s["t_end"].as_f64().unwrap());
        assert!(s["t_end"].as_f64().unwrap() < 1.0);
    }
}

#[test]
fn the_same_run_twice_writes_the_same_history() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    for out in [&a, &b] {
        let o = run(
            &repo("examples/free_tumble.vdl"),
            "free_tumble",
            out,
            &["run.stop_time=0.2 s"],
        );
        assert!(o.status.success());
    }
    let read = |d: &Path| std::fs::read(d.join("history.csv")).unwrap();
    assert_eq!(read(&a), read(&b));
}

/// A tight tolerance through a gust's onset: the thesis' subsonic_t06 (1.0 mm fins) with
/// DOP853 at rtol 1e-10, atol 1e-13 and the default `min_step` (1e-12 s) to 1.2 s, past the
/// first rectangular gust's onset at 1 s. Before the run cut its segments at the gusts'
/// switch times, the steps shrank onto the wind's jump until they underflowed there
/// (`step_underflow at t = 0.9999999999995045 s`); now the run restarts at the switch, the
/// segment before ending on the wind's left-hand limit.
#[test]
fn a_tight_tolerance_flies_through_a_gusts_onset() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("tight");
    let o = run(
        &repo("examples/thesis/section_6_5.vdl"),
        "subsonic_t06",
        &out,
        &[
            "fins.thickness=1 mm",
            "run.stop_time=1.2 s",
            "run.integrator=dop853",
            "run.rtol=1e-10",
            "run.atol=1e-13",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = summary(&out);
    assert_eq!(s["stop_reason"], "completed", "{}", s["stop_detail"]);
}

/// `aero_tables/` is the text of the tables the built-in estimator makes for the vehicle,
/// byte for byte, now that the run's writer thread makes it while the flight runs (it
/// was made on the main thread after the flight before): both the body and the fin table,
/// each with its header line.
#[test]
fn the_written_coefficient_tables_are_the_estimators_text() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = run(
        &repo("examples/thesis/section_6_5.vdl"),
        "subsonic_t06",
        &out,
        &["run.stop_time=0.01 s"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let checked = flexflight::check::check_files(
        &[repo("vehicles/sphads1.vdl")],
        &[],
        &flexflight::check::DiskLoader,
    );
    let vehicle = &checked.program.vehicles[0];
    let tables = flexflight::runtime::forces::aero_tables(vehicle).unwrap();
    for (name, text) in tables.files() {
        let written = std::fs::read_to_string(out.join("aero_tables").join(name)).unwrap();
        assert!(
            written == text,
            "aero_tables/{name} is not the estimator's text ({} against {} bytes)",
            written.len(),
            text.len()
        );
    }
}
