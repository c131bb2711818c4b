//! The flight knows when it has left its model (issue 32, findings 1-2 and deliverables 1-2):
//! a flight whose fins flutter ends with a flutter verdict at the first state outside the
//! model, its history and summary cover only the flight before it, its exit status is
//! `EXIT_VERDICT` (3), and its flutter margin can never say "criterion met".
//!
//! The rocket is `examples/m1670_4fin` (issue 32's: 4 G10 fins of 1.6 mm on a 102 mm
//! airframe, Cesaroni M1670). Before these deliverables its flight fluttered on the way up,
//! blew up (Mach 1.6e6 at the last row) and ended `step_underflow` with exit 0.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn cache() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("verdict-test-cache")
}

fn run(file: &Path, scenario: &str, out: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .arg("run")
        .arg(file)
        .args(["--scenario", scenario])
        .arg("--out")
        .arg(out)
        .arg("--cache-dir")
        .arg(cache())
        .args(extra)
        .output()
        .unwrap()
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// Column `name` of `history.csv`.
fn column(dir: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    let mut lines = text.lines();
    let i = lines
        .next()
        .unwrap()
        .split(',')
        .position(|c| c == name)
        .unwrap();
    lines
        .map(|l| l.split(',').nth(i).unwrap().parse().unwrap())
        .collect()
}

/// `examples/m1670_4fin` with its G10 modulus typed in MPa (17 MPa, meant 17 GPa), written
/// into `dir` with its motor file.
fn soft_copy(dir: &Path) -> PathBuf {
    let src = std::fs::read_to_string(repo("examples/m1670_4fin/m1670_4fin.vdl"))
        .unwrap()
        .replacen("E = 18 GPa\n  nu = 0.12", "E = 17 MPa\n  nu = 0.12", 1);
    assert!(src.contains("E = 17 MPa"));
    let file = dir.join("soft.vdl");
    std::fs::write(&file, src).unwrap();
    std::fs::copy(
        repo("examples/m1670_4fin/Cesaroni_M1670.eng"),
        dir.join("Cesaroni_M1670.eng"),
    )
    .unwrap();
    file
}

#[test]
fn a_flight_that_flutters_ends_with_a_flutter_verdict_and_covers_only_the_valid_flight() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let o = run(
        &repo("examples/m1670_4fin/m1670_4fin.vdl"),
        "flight",
        &out,
        &["--no-flutter-margin"],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(err.contains("FLUTTER at t = "), "{err}");
    let s = summary(&out);
    assert_eq!(s["stop_reason"], "flutter", "{s:#}");
    let v = &s["verdict"];
    assert_eq!(v["kind"], "flutter");
    let t = v["t"].as_f64().unwrap();
    // Every quantity of the verdict is the state of a flight still in its model: a subsonic
    // to low-supersonic launch, not the blown-up state.
    let mach = v["mach"].as_f64().unwrap();
    assert!(mach > 0.5 && mach < 1.5, "{v:#}");
    assert!(v["airspeed"].as_f64().unwrap() > 150.0);
    assert!(v["dynamic_pressure"].as_f64().unwrap() < 2e5);
    // Growing fin modes with a frequency: flutter, not a static overload.
    let modes = v["modes"].as_array().unwrap();
    assert!(!modes.is_empty());
    for m in modes {
        assert!(m["growth_rate"].as_f64().unwrap() > 0.0, "{m}");
        assert!(m["frequency_hz"].as_f64().is_some(), "{m}");
        assert!(m["name"].as_str().unwrap().starts_with("fin"), "{m}");
    }
    // The history ends at the verdict; no row is outside the model (10 % of the 102 mm
    // span), and no extremum or event comes from after it.
    let ts = column(&out, "t");
    assert_eq!(*ts.last().unwrap(), t);
    let deformation = column(&out, "max_deformation");
    assert!(deformation.iter().all(|d| *d <= 0.0102 * (1.0 + 1e-9)));
    let max_mach = s["flight"]["max_mach"]["value"].as_f64().unwrap();
    assert!(max_mach <= mach * (1.0 + 1e-12), "{max_mach}");
    assert!(s["flight"]["apogee"].is_null());
    assert_eq!(s["flight"]["deployments"].as_array().unwrap().len(), 0);
    assert!(s["flight"]["landing"].is_null());
}

#[test]
fn a_flight_with_a_verdict_never_meets_the_margin_criterion_and_tells_the_story() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let o = run(
        &repo("examples/m1670_4fin/m1670_4fin.vdl"),
        "flight",
        &out,
        &["--flutter-margin"],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{err}");
    let s = summary(&out);
    let m = &s["flutter_margin"];
    assert_eq!(m["meets_criterion"], false, "{m:#}");
    assert!(!err.contains(": met"), "{err}");
    // The first violation precedes the first time below 1; both precede the verdict.
    let t_v = s["verdict"]["t"].as_f64().unwrap();
    let t1 = m["first_violation"]["t"].as_f64().unwrap();
    let t2 = m["first_below_one"]["t"].as_f64().unwrap();
    assert!(t1 <= t2 && t2 < t_v, "{t1} {t2} {t_v}");
    let below = m["time_below_criterion_s"].as_f64().unwrap();
    let below_one = m["time_below_one_s"].as_f64().unwrap();
    assert!(below >= below_one && below_one > 0.0);
    // The spans add up to the times.
    for (key, total) in [
        ("spans_below_criterion", below),
        ("spans_below_one", below_one),
    ] {
        let sum: f64 = m[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s[1].as_f64().unwrap() - s[0].as_f64().unwrap())
            .sum();
        assert!((sum - total).abs() < 1e-9, "{key}");
    }
    let story = m["story"].as_str().unwrap();
    assert!(story.contains("left its model"), "{story}");
}

/// A modulus typed in MPa (meant: GPa): the fins are a hundred times too soft, the flight
/// used to blow up at 0.5 s and the margin said "criterion met". Now the flight ends with a
/// verdict just off the rail (divergence at about 40 m/s) and the margin is never met.
#[test]
fn a_unit_slip_in_the_modulus_never_gives_criterion_met() {
    let dir = tempfile::tempdir().unwrap();
    let file = soft_copy(dir.path());
    let out = dir.path().join("run");
    let o = run(&file, "flight", &out, &["--flutter-margin"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{err}");
    let s = summary(&out);
    assert!(s["verdict"].is_object(), "{s:#}");
    assert!(s["verdict"]["t"].as_f64().unwrap() < 1.0);
    assert_ne!(s["flutter_margin"]["meets_criterion"], true);
    assert!(!err.contains("criterion 1.15: met"), "{err}");
}

/// Finding 3: `analyze flutter --clamped --mach 0.5` on the 17 MPa fin started its sweep at
/// 0.3 a (100 m/s) and printed "flutter: V = 274.8 m/s" with no warning, while the fin is
/// unstable far below that. Now the leading-mode screen below the sweep finds the branch
/// unstable at its lowest speed, and the answer is a bound, never a higher crossing.
#[test]
fn a_clamped_sweep_never_reports_a_crossing_above_a_low_speed_instability() {
    let dir = tempfile::tempdir().unwrap();
    let file = soft_copy(dir.path());
    let out = dir.path().join("flutter");
    let o = Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .args(["analyze", "flutter", "--clamped"])
        .arg(&file)
        .args(["--scenario", "flight", "--mach", "0.5", "--out"])
        .arg(&out)
        .arg("--cache-dir")
        .arg(cache())
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        text.contains("flutter: unstable at the lowest speed solved, V_F < "),
        "{text}"
    );
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("flutter.json")).unwrap()).unwrap();
    let a = &j["answer"];
    assert_eq!(a["kind"], "below", "{j:#}");
    // Below the sweep's first speed (0.3 a), within reach of the quasi-steady 19.7 m/s the
    // issue found from 2 m/s.
    let v = a["speed_m_s"].as_f64().unwrap();
    assert!(v < 0.3 * 330.0 && v > 19.7, "{v}");
    assert!(j["screen"]["segments"].as_array().unwrap().len() >= 2);
}

/// A run whose integration failed (the step size below `min_step`, a non-finite state, or
/// the step budget used up) did not fly its scenario to its end: it is not a clean run.
/// Its exit status is `EXIT_INCOMPLETE` (4, not 0), its summary says `complete: false`
/// and the terminal says the flight is incomplete; a run that reached its stop exits 0
/// with `complete: true`. On the old code the same run (a `min_step` of 10 ms that the
/// tumble's first step cannot meet) ended `step_underflow at t = 0 s` with exit 0.
#[test]
fn a_run_whose_integration_fails_is_not_a_clean_run() {
    let dir = tempfile::tempdir().unwrap();
    let file = repo("examples/free_tumble.vdl");
    let out = dir.path().join("failed");
    let o = run(
        &file,
        "free_tumble",
        &out,
        &["--set", "run.min_step=10 ms", "--set", "run.rtol=1e-12"],
    );
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(4), "{err}");
    assert!(err.contains("INCOMPLETE"), "{err}");
    let s = summary(&out);
    assert_eq!(s["stop_reason"], "step_underflow");
    assert_eq!(s["complete"], false);
    let done = dir.path().join("done");
    let o = run(&file, "free_tumble", &done, &[]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let s = summary(&done);
    assert_eq!(s["stop_reason"], "completed");
    assert_eq!(s["complete"], true);
}

/// A rocket that falls tail first, exactly vertical and without wind (every windless
/// vertical flight after its apogee, until a parachute opens; NDRT 2020's README flight),
/// flies on: the built-in aerodynamics cover every flow direction, so at an angle of attack
/// of 180 deg the normal forces vanish instead of jumping between the +180 and -180 deg
/// sides with the sign of the round-off crossflow, and the axial force opposes the motion.
/// On the old code (tables from -20 to 20 deg, clamped beyond) the integrator chattered on
/// that jump and the run ended `max_steps` (exit 4) within a second of flight.
#[test]
fn a_rocket_falling_tail_first_flies_on_and_its_drag_opposes_the_fall() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("fall.vdl");
    let vehicle = repo("examples/hpr_k1000/hpr_k1000.vdl");
    std::fs::write(
        &file,
        format!(
            r#"import "{}"

scenario fall {{
  vehicle = hpr_k1000
  with {{
    forces.thrust.enabled = false
  }}
  initial {{
    velocity = (-30, 0, 0) m/s
    attitude = euler(0 deg, 90 deg, 0 deg)
    altitude = 1 km
  }}
  run {{
    stop_time = 3 s
    rtol = 1e-7
    atol = 1e-9
    output_interval = 10 ms
  }}
}}
"#,
            vehicle.display()
        ),
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = run(&file, "fall", &out, &["--no-flutter-margin"]);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(0), "{err}");
    let s = summary(&out);
    assert_eq!(s["stop_reason"], "completed", "{err}");
    // While it falls tail first (body x velocity negative), the axial aerodynamic force
    // pushes the body forward (+x), against the fall: a drag, not a thrust.
    let (vx, fx) = (
        column(&out, "v_body_x"),
        column(&out, "body_aero_force_body_x"),
    );
    let mut tail_first = 0;
    for (v, f) in vx.iter().zip(&fx) {
        if *v < -5.0 {
            tail_first += 1;
            assert!(*f > 0.0, "v_x {v} m/s, axial force {f} N");
        }
    }
    assert!(tail_first > 10, "{tail_first} rows tail first");
}
