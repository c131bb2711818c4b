//! Flights from the ground (issue 9 defect 5, issue 10 parts 2-7) through the binary: a
//! start on or below the ground is a diagnostic unless the vehicle can leave it, the ground
//! stop fires only on descent, a rail launch flies its rail and reports the exit, events
//! are located in time, parachutes bring the vehicle down, wind blows in the inertial frame.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn cache() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("launch-test-cache")
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

fn run(file: &Path, scenario: &str, out: &Path, sets: &[&str]) -> Output {
    let mut c = bin();
    c.arg("run")
        .arg(file)
        .args(["--scenario", scenario])
        .arg("--out")
        .arg(out)
        .arg("--cache-dir")
        .arg(cache());
    for s in sets {
        c.args(["--set", s]);
    }
    c.output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

const G0: f64 = 9.806;

/// SPHADS-1 with gravity only (uniform), from `altitude` at `speed` along the body axis
/// pitched `pitch` deg.
fn ground_scenario(dir: &Path, altitude: &str, speed: f64, pitch: f64) -> PathBuf {
    let text = format!(
        r#"import "{}"

scenario pad {{
  vehicle = sphads1
  with {{
    forces.body_aero.enabled = false
    forces.fin_aero.enabled = false
    forces.gravity.altitude_correction = false
  }}
  initial {{
    velocity = ({speed}, 0, 0) m/s
    attitude = euler(0 deg, {pitch} deg, 0 deg)
    altitude = {altitude}
  }}
  run {{
    stop_time = 10 s
    rtol = 1e-10
    atol = 1e-12
    output_interval = 10 ms
  }}
}}
"#,
        repo("vehicles/sphads1.vdl").display()
    );
    let file = dir.join("pad.vdl");
    std::fs::write(&file, text).unwrap();
    file
}

// ---------------------------------------------------------------------------------------
// Issue 9, defect 5: a start on or below the ground.

#[test]
fn a_start_at_rest_on_the_ground_is_a_diagnostic_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let file = ground_scenario(dir.path(), "0 m", 0.0, 0.0);
    let out = dir.path().join("out");
    let o = run(&file, "pad", &out, &[]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("run::on_ground"), "{e}");
    // A diagnostic with a span: the file and the line of the `initial` block.
    assert!(e.contains("pad.vdl:10:"), "{e}");
    assert!(!out.exists(), "a run that cannot start writes nothing");
}

#[test]
fn a_start_underground_is_a_diagnostic_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    for (speed, pitch) in [(0.0, 0.0), (50.0, -30.0)] {
        let file = ground_scenario(dir.path(), "-100 m", speed, pitch);
        let out = dir.path().join("out");
        let o = run(&file, "pad", &out, &[]);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert!(stderr(&o).contains("run::on_ground"), "{}", stderr(&o));
        assert!(!out.exists());
    }
}

#[test]
fn a_climbing_start_on_the_ground_flies_until_it_descends_through_it() {
    let dir = tempfile::tempdir().unwrap();
    let file = ground_scenario(dir.path(), "0 m", 50.0, 30.0);
    let out = dir.path().join("out");
    let o = run(&file, "pad", &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = summary(&out);
    assert_eq!(s["stop_reason"], "ground");
    // Ballistic: back on the ground after 2 v sin(30 deg) / g.
    let t_hit = 2.0 * 25.0 / G0;
    let t_end = s["t_end"].as_f64().unwrap();
    assert!((t_end - t_hit).abs() < 1e-7, "{t_end} vs {t_hit}");
    let h = History::read(&out);
    assert!(h.rows.len() > 500, "{} rows", h.rows.len());
    // The apogee is located in time: v^2 sin^2 / 2g at v sin / g.
    let ap = &s["flight"]["apogee"];
    assert!((ap["t"].as_f64().unwrap() - 25.0 / G0).abs() < 1e-7, "{ap}");
    assert!((ap["altitude"].as_f64().unwrap() - 625.0 / (2.0 * G0)).abs() < 1e-7);
    let landing = &s["flight"]["landing"];
    assert!((landing["t"].as_f64().unwrap() - t_hit).abs() < 1e-7);
    assert!((landing["speed"].as_f64().unwrap() - 50.0).abs() < 1e-6);
}

// ---------------------------------------------------------------------------------------
// Issue 10: the rail, Mach 0, events, parachutes, wind.

/// SPHADS-1 with a constant `thrust` N motor burning `burn` s, launched from a rail;
/// `extra` goes into the scenario (parachutes, wind), `aero` switches both aero blocks.
fn rail_scenario(dir: &Path, thrust: f64, burn: f64, aero: bool, extra: &str) -> PathBuf {
    let vehicle = std::fs::read_to_string(repo("vehicles/sphads1.vdl")).unwrap();
    let vehicle = vehicle.replacen(
        "  forces {\n",
        "  forces {\n    thrust {\n      curve = \"motor.csv\"\n    }\n\n",
        1,
    );
    std::fs::write(dir.join("sphads1_motor.vdl"), vehicle).unwrap();
    std::fs::write(
        dir.join("motor.csv"),
        format!("time_s,thrust_N\n0,{thrust}\n{burn},{thrust}\n"),
    )
    .unwrap();
    let aero_off = if aero {
        ""
    } else {
        "    forces.body_aero.enabled = false\n    forces.fin_aero.enabled = false\n"
    };
    let text = format!(
        r#"import "sphads1_motor.vdl"

scenario pad {{
  vehicle = sphads1
  with {{
{aero_off}    forces.gravity.altitude_correction = false
  }}
  launch {{
    site_altitude = 100 m
    rail_length = 3 m
    elevation = 80 deg
    heading = 30 deg
  }}
{extra}
  run {{
    stop_time = 300 s
    rtol = 1e-10
    atol = 1e-12
    output_interval = 10 ms
  }}
}}
"#
    );
    let file = dir.join("pad.vdl");
    std::fs::write(&file, text).unwrap();
    file
}

/// The vehicle mass from the history: `p_B = m V_B` on the rail (no rotation, modes held),
/// at t = 0.05 s.
fn mass_of(h: &History) -> f64 {
    let (p, v) = (h.col("momentum_body_x"), h.col("v_body_x"));
    p[5] / v[5]
}

#[test]
fn a_rail_launch_slides_along_the_rail_and_leaves_it_at_the_analytic_speed() {
    let dir = tempfile::tempdir().unwrap();
    let file = rail_scenario(dir.path(), 1000.0, 2.0, false, "");
    let out = dir.path().join("out");
    let o = run(&file, "pad", &out, &["run.stop_time=1 s"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let h = History::read(&out);
    let s = summary(&out);
    let m = 17.56;
    let m_hist = mass_of(&h);
    assert!((m_hist - m).abs() < 0.01, "mass {m_hist}");
    // On the rail: u' = T/m - g sin(e), so the exit after L = 3 m is at
    // t = sqrt(2 L / a) with speed sqrt(2 a L).
    let a = 1000.0 / m_hist - G0 * 80f64.to_radians().sin();
    let (t_exit, v_exit) = ((6.0 / a).sqrt(), (6.0 * a).sqrt());
    let exit = &s["flight"]["rail_exit"];
    let t = exit["t"].as_f64().unwrap();
    let v = s["flight"]["off_rail_speed"].as_f64().unwrap();
    assert!((t - t_exit).abs() < 1e-9 * t_exit, "{t} vs {t_exit}");
    assert!((v - v_exit).abs() < 1e-9 * v_exit, "{v} vs {v_exit}");
    // The rail holds the attitude and the modes: no rotation, no deformation before the
    // exit; the aft end starts at the foot of the rail on the ground (100 m).
    let (tt, wy, pitch, yaw) = (
        h.col("t"),
        h.col("omega_body_y"),
        h.col("pitch"),
        h.col("yaw"),
    );
    for k in 0..tt.len() {
        if tt[k] <= t_exit {
            assert_eq!(wy[k], 0.0);
            assert!((pitch[k] - 80.0).abs() < 1e-9 && (yaw[k] - 30.0).abs() < 1e-9);
            assert_eq!(h.col("max_deformation")[k], 0.0);
        }
    }
    let alt0 = h.col("altitude")[0];
    assert!(
        (alt0 - (100.0 + 2.75 * 80f64.to_radians().sin())).abs() < 1e-9,
        "{alt0}"
    );
    // The event's position lies on the rail 3 m up from the start.
    let p = exit["position"].as_array().unwrap();
    let p: Vec<f64> = p.iter().map(|v| v.as_f64().unwrap()).collect();
    let p0 = [
        h.col("p_inertial_x")[0],
        h.col("p_inertial_y")[0],
        h.col("p_inertial_z")[0],
    ];
    let d = ((p[0] - p0[0]).powi(2) + (p[1] - p0[1]).powi(2) + (p[2] - p0[2]).powi(2)).sqrt();
    assert!((d - 3.0).abs() < 1e-9, "{d}");
}

#[test]
fn a_vehicle_whose_thrust_cannot_lift_it_off_the_rail_is_a_diagnostic() {
    let dir = tempfile::tempdir().unwrap();
    // 17.56 kg x 9.806 x sin 80 deg = 169.6 N > 150 N.
    let file = rail_scenario(dir.path(), 150.0, 2.0, false, "");
    let out = dir.path().join("out");
    let o = run(&file, "pad", &out, &[]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("plan::no_liftoff"), "{e}");
    assert!(
        e.contains("pad.vdl:10:"),
        "labelled at the launch block: {e}"
    );
    assert!(!out.exists());
}

fn check(file: &Path) -> Output {
    bin().arg("check").arg(file).output().unwrap()
}

#[test]
fn bad_launch_wind_and_parachute_input_is_reported_with_spans_at_check() {
    let dir = tempfile::tempdir().unwrap();
    let file = rail_scenario(dir.path(), 1000.0, 2.0, false, "");
    let text = std::fs::read_to_string(&file).unwrap();
    let cases = [
        (
            "rail_length = 3 m",
            "rail_length = -1 m",
            "rail_length = -1 m",
        ),
        (
            "site_altitude = 100 m",
            "site_altitude = 90 km",
            "site_altitude = 90 km",
        ),
        // Below the atmosphere's lower end (-500 m, where the 1976 tables start).
        (
            "site_altitude = 100 m",
            "site_altitude = -1 km",
            "site_altitude = -1 km",
        ),
        (
            "elevation = 80 deg",
            "elevation = 95 deg",
            "elevation = 95 deg",
        ),
    ];
    for (from, to, needle) in cases {
        std::fs::write(&file, text.replace(from, to)).unwrap();
        let o = check(&file);
        assert_eq!(o.status.code(), Some(1), "{to}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains("vdl::value::range") && e.contains(needle),
            "{to}: {e}"
        );
    }
    // A parachute with no trigger; a wind table with heights out of order.
    for (extra, code) in [
        (
            "  parachute main {\n    cd_area = 2 m^2\n  }\n",
            "vdl::field::missing",
        ),
        (
            "  wind {\n    profile = [at(100 m, 5 m/s, 270 deg), at(50 m, 6 m/s, 270 deg)]\n  }\n",
            "vdl::wind::profile",
        ),
        (
            "  parachute main {\n    cd_area = 2 m^2\n    trigger = never\n  }\n",
            "vdl::type::mismatch",
        ),
    ] {
        let f = rail_scenario(dir.path(), 1000.0, 2.0, false, extra);
        let o = check(&f);
        assert_eq!(o.status.code(), Some(1), "{extra}: {}", stderr(&o));
        assert!(stderr(&o).contains(code), "{extra}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("pad.vdl:"),
            "with a span: {}",
            stderr(&o)
        );
    }
    // `launch` and `initial` together.
    let f = rail_scenario(
        dir.path(),
        1000.0,
        2.0,
        false,
        "  initial {\n    velocity = (0, 0, 0) m/s\n    altitude = 0 m\n  }\n",
    );
    let o = check(&f);
    assert!(
        stderr(&o).contains("vdl::launch::initial"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_launch_with_stop_policy_tables_flies_from_mach_0_without_stopping() {
    // SPHADS-1's built-in tables have `out_of_range = stop`: before Mach 0 was in the grid
    // the launch stopped at t = 0 on `aero_out_of_range`.
    let dir = tempfile::tempdir().unwrap();
    let file = rail_scenario(dir.path(), 1000.0, 2.0, true, "");
    let out = dir.path().join("out");
    let o = run(
        &file,
        "pad",
        &out,
        &["run.stop_time=3 s", "run.rtol=1e-7", "run.atol=1e-9"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s = summary(&out);
    assert_eq!(s["stop_reason"], "completed", "{}", s["stop_detail"]);
    let h = History::read(&out);
    let mach = h.col("mach");
    assert_eq!(mach[0], 0.0);
    assert!(mach.iter().all(|m| m.is_finite()));
    assert!(h.col("alpha").iter().all(|a| a.is_finite()));
    assert!(s["flight"]["off_rail_speed"].as_f64().unwrap() > 10.0);
    let sm = s["flight"]["static_margin_calibres"]["at_rail_exit"]
        .as_f64()
        .unwrap();
    assert!(sm.is_finite() && sm > 0.0, "static margin {sm}");
}

#[test]
fn parachutes_deploy_after_their_trigger_and_descend_at_terminal_speed() {
    let dir = tempfile::tempdir().unwrap();
    let chutes = "  parachute drogue {\n    cd_area = 0.5 m^2\n    trigger = apogee\n    lag = 1.5 s\n  }\n  parachute main {\n    cd_area = 8 m^2\n    trigger = altitude(400 m)\n  }\n";
    let file = rail_scenario(dir.path(), 1000.0, 2.0, false, chutes);
    let out = dir.path().join("out");
    let o = run(&file, "pad", &out, &["run.rtol=1e-9", "run.atol=1e-11"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = summary(&out);
    assert_eq!(s["stop_reason"], "ground", "{}", s["stop_detail"]);
    let f = &s["flight"];
    // Burnout at the curve's last point.
    assert!((f["burnout"]["t"].as_f64().unwrap() - 2.0).abs() < 1e-12);
    // Apogee: vertical speed zero there.
    let ap = &f["apogee"];
    assert!(ap["velocity"][2].as_f64().unwrap().abs() < 1e-9, "{ap}");
    let t_ap = ap["t"].as_f64().unwrap();
    let deps = f["deployments"].as_array().unwrap();
    assert_eq!(deps.len(), 2, "{deps:?}");
    assert_eq!(deps[0]["name"], "drogue");
    let (trig, dep) = (&deps[0]["trigger"], &deps[0]["deployment"]);
    assert!((trig["t"].as_f64().unwrap() - t_ap).abs() < 1e-12);
    assert!((dep["t"].as_f64().unwrap() - t_ap - 1.5).abs() < 1e-9);
    // The main at 400 m above the ground (100 m), on descent, no lag.
    let main = &deps[1];
    assert!((main["trigger"]["height"].as_f64().unwrap() - 400.0).abs() < 1e-6);
    assert!(
        (main["deployment"]["t"].as_f64().unwrap() - main["trigger"]["t"].as_f64().unwrap()).abs()
            < 1e-12
    );
    // Landing at the terminal speed of the point mass under both canopies:
    // v_t = sqrt(2 m g / (rho cd_area)), rho of the 1976 atmosphere at 100 m (1.2133 kg/m^3).
    let h = History::read(&out);
    let m = mass_of(&h);
    let rho = *h.col("air_density").last().unwrap();
    let v_t = (2.0 * m * G0 / (rho * 8.5)).sqrt();
    let v = f["landing"]["speed"].as_f64().unwrap();
    assert!(
        (v - v_t).abs() < 1e-3 * v_t,
        "landing {v} vs terminal {v_t}"
    );
    assert!((f["landing"]["height"].as_f64().unwrap()).abs() < 1e-6);
    // Under the canopy the vehicle is rigid and does not rotate.
    let t = h.col("t");
    let td = dep["t"].as_f64().unwrap();
    let wy = h.col("omega_body_y");
    assert!(
        t.iter()
            .zip(&wy)
            .filter(|(t, _)| **t > td)
            .all(|(_, w)| *w == 0.0)
    );
}

/// Under a canopy the vehicle's own aerodynamics are off: the aerodynamic load channels and
/// the fin root stresses are zero from the deployment on, and the fin angles of attack follow
/// the air-relative velocity. Before the fix the fin channels kept, for the whole descent,
/// the values of the last evaluation before the deployment (hpr_k1000: a root stress of
/// 0.42 MPa and -114 deg frozen for 150 s under the parachutes).
#[test]
fn under_a_canopy_the_fin_channels_show_no_load_and_the_current_angle_of_attack() {
    let dir = tempfile::tempdir().unwrap();
    let chute = "  parachute drogue {\n    cd_area = 2 m^2\n    trigger = time(3 s)\n  }\n";
    let file = rail_scenario(dir.path(), 1000.0, 2.0, true, chute);
    let out = dir.path().join("out");
    let o = run(
        &file,
        "pad",
        &out,
        &["run.stop_time=6 s", "run.rtol=1e-7", "run.atol=1e-9"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let h = History::read(&out);
    let t = h.col("t");
    let td = 3.0;
    let fins: Vec<String> = h
        .columns
        .iter()
        .filter(|c| c.starts_with("fin") && c.ends_with("_root_stress"))
        .cloned()
        .collect();
    assert!(!fins.is_empty(), "{:?}", h.columns);
    let loads: Vec<String> = h
        .columns
        .iter()
        .filter(|c| c.contains("_aero_force_") || c.contains("_aero_moment_"))
        .cloned()
        .collect();
    assert_eq!(loads.len(), 12, "{:?}", h.columns);
    for c in fins.iter().chain(&loads) {
        let v = h.col(c);
        // Loaded before the deployment...
        assert!(
            t.iter().zip(&v).any(|(t, v)| *t < td && *v != 0.0),
            "{c} zero in flight"
        );
        // ...and not under the canopy.
        let under: Vec<f64> = t
            .iter()
            .zip(&v)
            .filter(|(t, _)| **t > td)
            .map(|(_, v)| *v)
            .collect();
        assert!(under.len() > 200, "{}", under.len());
        assert!(
            under.iter().all(|v| *v == 0.0),
            "{c} under the canopy: {:?}",
            &under[..5]
        );
    }
    // The air-relative velocity turns from along the body axis towards the vertical while
    // the frozen vehicle keeps its attitude: the fin angles of attack change with it.
    for i in 1..=fins.len() {
        let a = h.col(&format!("fin{i}_alpha"));
        let under: Vec<f64> = t
            .iter()
            .zip(&a)
            .filter(|(t, _)| **t > td)
            .map(|(_, a)| *a)
            .collect();
        let (lo, hi) = under
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), a| {
                (l.min(*a), h.max(*a))
            });
        assert!(
            hi - lo > 1.0,
            "fin{i}_alpha under the canopy {lo}..{hi} deg"
        );
    }
}

#[test]
fn a_steady_wind_carries_the_descent_downwind_at_the_wind_speed() {
    let dir = tempfile::tempdir().unwrap();
    let extra = "  wind {\n    speed = 6 m/s\n    direction = 270 deg\n  }\n  parachute main {\n    cd_area = 8 m^2\n    trigger = apogee\n  }\n";
    let file = rail_scenario(dir.path(), 1000.0, 2.0, false, extra);
    let out = dir.path().join("out");
    let o = run(&file, "pad", &out, &["run.rtol=1e-9", "run.atol=1e-11"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = summary(&out);
    let v = &s["flight"]["landing"]["velocity"];
    // A wind from the west blows toward the east (+y): the canopy drifts with it.
    assert!((v[1].as_f64().unwrap() - 6.0).abs() < 1e-3, "{v}");
    assert!(v[0].as_f64().unwrap().abs() < 1e-3, "{v}");
    // Without wind the same flight lands elsewhere: the drift is east of it.
    let still = dir.path().join("still");
    let file = rail_scenario(
        dir.path(),
        1000.0,
        2.0,
        false,
        "  parachute main {\n    cd_area = 8 m^2\n    trigger = apogee\n  }\n",
    );
    let o = run(&file, "pad", &still, &["run.rtol=1e-9", "run.atol=1e-11"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let y_wind = s["flight"]["landing"]["position"][1].as_f64().unwrap();
    let y_still = summary(&still)["flight"]["landing"]["position"][1]
        .as_f64()
        .unwrap();
    assert!(y_wind > y_still + 100.0, "{y_wind} vs {y_still}");
}

// ---------------------------------------------------------------------------------------
// Issue 10: the rail and the descent with a burning motor (variable mass).

/// A body-only vehicle (2 m aluminium tube, 3 kg payload) with a motor component at the
/// tail: `thrust` N for 3 s, 3 kg of propellant in a 4.5 kg motor; gravity only (uniform), from
/// a 3 m rail at 80 deg; `extra` goes into the scenario.
fn burner_pad(dir: &Path, thrust: f64, extra: &str) -> PathBuf {
    std::fs::write(
        dir.join("constant.csv"),
        format!("time_s,thrust_N\n0,{thrust}\n3,{thrust}\n"),
    )
    .unwrap();
    let vehicle = common::burner_vehicle("gravity {\n      altitude_correction = false\n    }", "");
    let text = format!(
        r#"{vehicle}
scenario pad {{
  vehicle = burner
  launch {{
    site_altitude = 100 m
    rail_length = 3 m
    elevation = 80 deg
    heading = 30 deg
  }}
{extra}
  run {{
    stop_time = 3000 s
    rtol = 1e-10
    atol = 1e-12
    output_interval = 10 ms
  }}
}}
"#
    );
    let path = dir.join("burner.vdl");
    std::fs::write(&path, text).unwrap();
    path
}

/// On the rail a burning vehicle obeys `m(t) u' = T - m(t) g sin(e)` with
/// `m(t) = m0 - mdot t`, `mdot = m_p / t_b` (the propellant burns with the impulse; constant
/// thrust): `u = c ln(m0/m) - g sin(e) t` and
/// `s = (c / mdot) (m0 - m - m ln(m0/m)) - g sin(e) t^2 / 2`, `c = T / mdot`. The rail exit
/// (s = 3 m), the off-rail speed and the mass history follow that to the integrator's
/// tolerance.
#[test]
fn a_burning_vehicle_leaves_the_rail_at_the_variable_mass_speed() {
    let dir = tempfile::tempdir().unwrap();
    let file = burner_pad(dir.path(), 2000.0, "");
    let out = dir.path().join("out");
    let o = run(&file, "pad", &out, &["run.stop_time=1 s"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let h = History::read(&out);
    let s = summary(&out);
    let m0 = h.col("mass")[0];
    let (thrust, mdot) = (2000.0, 1.0);
    let c = thrust / mdot;
    let gs = G0 * 80f64.to_radians().sin();
    let mass = |t: f64| m0 - mdot * t;
    let dist = |t: f64| {
        let m = mass(t);
        c / mdot * (m0 - m - m * (m0 / m).ln()) - 0.5 * gs * t * t
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if dist(mid) >= 3.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let t_exit = hi;
    let v_exit = c * (m0 / mass(t_exit)).ln() - gs * t_exit;
    let t = s["flight"]["rail_exit"]["t"].as_f64().unwrap();
    let v = s["flight"]["off_rail_speed"].as_f64().unwrap();
    // The event is located on the step's cubic Hermite interpolant (third order): exact
    // for the constant-mass rail (a quadratic), here `ln` leaves an interpolation error of
    // a few 1e-8 (5.4e-8 in t measured) for steps of some 50 ms.
    eprintln!("rail exit t {t} vs {t_exit}, speed {v} vs {v_exit}");
    assert!((t - t_exit).abs() < 1e-7 * t_exit, "{t} vs {t_exit}");
    assert!((v - v_exit).abs() < 1e-7 * v_exit, "{v} vs {v_exit}");
    // The mass channel burns linearly from the first row.
    let (tt, mm) = (h.col("t"), h.col("mass"));
    for k in 0..tt.len() {
        assert!(
            (mm[k] - mass(tt[k])).abs() < 1e-12 * m0,
            "t {}: {}",
            tt[k],
            mm[k]
        );
    }
    // On the rail the momentum is m(t) u (no rotation, modes held).
    let (p, u) = (h.col("momentum_body_x"), h.col("v_body_x"));
    for k in 0..tt.len() {
        if tt[k] < t_exit && u[k] > 0.0 {
            assert!((p[k] / u[k] - mass(tt[k])).abs() < 1e-9 * m0);
        }
    }
}

/// The energy balance closes over a whole flight from the pad: the rail, the burning free
/// flight, apogee, the freeze at deployment (its removed energy booked as dissipated) and
/// the descent under the canopy to the ground.
#[test]
fn the_energy_balance_closes_from_the_pad_to_the_ground() {
    let dir = tempfile::tempdir().unwrap();
    let file = burner_pad(
        dir.path(),
        300.0,
        "  parachute main {\n    cd_area = 2 m^2\n    trigger = apogee\n    lag = 1 s\n  }\n",
    );
    let out = dir.path().join("out");
    let o = run(&file, "pad", &out, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = summary(&out);
    assert_eq!(s["stop_reason"], "ground", "{}", s["stop_detail"]);
    let eb = &s["energy_balance"];
    // Output rows between step ends are cubic Hermite interpolants of the state (the
    // works included): their residual is the interpolation error, 7.2e-9 of the largest
    // work measured (1.9e-4 J); the last row (the ground, located on the interpolant too)
    // 3.5e-12 with the standard step controller, 2.1e-11 with the PI controller.
    let r = eb["max_relative_residual"].as_f64().unwrap();
    assert!(r < 2e-8, "{eb}");
    let scale = eb["work_loads_j"].as_f64().unwrap().abs();
    let last = eb["residual_j"].as_f64().unwrap().abs();
    assert!(last < 5e-11 * scale, "{eb}");
    assert!(eb["work_propulsive_j"].as_f64().unwrap() > 0.0);
    // The freeze at deployment keeps the momentum and removes energy (>= 0).
    assert!(eb["dissipated_j"].as_f64().unwrap() >= 0.0, "{eb}");
    let m = &s["mass"];
    assert!(
        (m["final_kg"].as_f64().unwrap() - (m["initial_kg"].as_f64().unwrap() - 3.0)).abs() < 1e-12
    );
}

/// A body table that starts at alpha = 0 (the body block only ever queries `alpha_b >= 0`,
/// `runtime::forces::body_aero` step 3) is a complete body table: the static margin must not
/// query it at -2 deg. Before the fix the margin was NaN from t = 0 and the first output row
/// stopped the run as `non_finite at t = 0 s` (examples/calisto, whose RocketPy-derived body
/// table has alpha 0..180 deg). Property: cutting the negative angles out of the built-in
/// (odd in alpha) body table changes neither the flight nor the static margin.
#[test]
fn a_body_table_from_alpha_zero_gives_the_same_static_margin_and_flight() {
    let dir = tempfile::tempdir().unwrap();
    let file = rail_scenario(dir.path(), 1000.0, 2.0, true, "");
    let out_builtin = dir.path().join("builtin");
    let sets = ["run.stop_time=1.5 s", "run.rtol=1e-8", "run.atol=1e-10"];
    let o = run(&file, "pad", &out_builtin, &sets);
    assert!(o.status.success(), "{}", stderr(&o));
    // The estimated tables, the body one without its negative angles of attack.
    let body = std::fs::read_to_string(out_builtin.join("aero_tables/body.csv")).unwrap();
    let mut kept = 0;
    let mut cut = 0;
    let body: String = body
        .lines()
        .filter(|l| {
            let neg = l
                .split(',')
                .nth(1)
                .and_then(|a| a.trim().parse::<f64>().ok())
                .is_some_and(|a| a < 0.0);
            if neg {
                cut += 1;
            } else {
                kept += 1;
            }
            !neg
        })
        .map(|l| format!("{l}\n"))
        .collect();
    assert!(cut > 0 && kept > cut, "{cut} rows cut, {kept} kept");
    std::fs::write(dir.path().join("body.csv"), body).unwrap();
    std::fs::copy(
        out_builtin.join("aero_tables/fins.csv"),
        dir.path().join("fins.csv"),
    )
    .unwrap();
    let vdl = dir.path().join("sphads1_motor.vdl");
    let text = std::fs::read_to_string(&vdl).unwrap().replacen(
        "    source = builtin\n",
        "    source = tables\n    body_table = \"body.csv\"\n    fin_table = \"fins.csv\"\n",
        1,
    );
    assert!(text.contains("body_table"));
    std::fs::write(&vdl, text).unwrap();
    let out_tables = dir.path().join("tables");
    let o = run(&file, "pad", &out_tables, &sets);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = summary(&out_tables);
    assert_eq!(s["stop_reason"], "completed", "{}", s["stop_detail"]);
    let (a, b) = (History::read(&out_builtin), History::read(&out_tables));
    for name in ["static_margin", "altitude", "mach", "alpha"] {
        let (x, y) = (a.col(name), b.col(name));
        assert_eq!(x.len(), y.len(), "{name}");
        let worst = x
            .iter()
            .zip(&y)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0f64, f64::max);
        assert!(worst < 1e-9, "{name}: largest difference {worst:e}");
    }
    assert!(a.col("static_margin").iter().all(|m| m.is_finite()));
}

/// The static margin follows the burning vehicle's centre of mass: `(x_cg(t) - x_cp) / d`
/// with `x_cg(t)` the history's `cm_body_x`. Before the fix it used the ignition centre of
/// mass for the whole flight (examples/calisto: 2.77 cal at maximum q at burnout instead of
/// 3.68, the centre of mass having moved 0.116 m = 0.91 cal forward). Below the tables'
/// lowest Mach (0.01, held) the centre of pressure is constant, so on the first part of the
/// rail `d sm(t) - cm_body_x(t)` is constant while the propellant burns.
#[test]
fn the_static_margin_follows_the_centre_of_mass_of_a_burning_vehicle() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = run(
        &repo("examples/calisto/calisto.vdl"),
        "calisto",
        &out,
        &["run.stop_time=0.2 s"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let h = History::read(&out);
    let (mach, sm, cm) = (h.col("mach"), h.col("static_margin"), h.col("cm_body_x"));
    let d = 0.127;
    let held: Vec<usize> = (0..mach.len()).filter(|&k| mach[k] < 0.01).collect();
    assert!(held.len() > 5, "{} rows below Mach 0.01", held.len());
    let (first, last) = (held[0], *held.last().unwrap());
    assert!(
        (cm[last] - cm[first]).abs() > 1e-4,
        "the centre of mass must move: {} -> {}",
        cm[first],
        cm[last]
    );
    let x_cp = cm[first] - d * sm[first];
    for &k in &held {
        let got = cm[k] - d * sm[k];
        assert!(
            (got - x_cp).abs() < 1e-12,
            "t {}: x_cp {got} vs {x_cp}",
            h.col("t")[k]
        );
    }
}

/// The exponential integrator against a tight reference on the M1670 boost and coast
/// (`examples/hpr_k1000`, scenario `m1670`, to 15 s, its own tolerances rtol 1e-7, atol
/// 1e-9; reference DOP853 rtol 1e-10, atol 1e-13). The eigenbasis of the flight's linear
/// block is ill-conditioned (`‖V‖‖V⁻¹‖` 6e5 to 1.5e7: the `ω × V` coupling at up to
/// 470 m/s); transforming the state itself put `ε cond(V) |V_B|`, about 1e-6 rad/s, into the
/// roll rate at a few refreshes (1.51e-6 rad/s off the reference, at every tolerance down to
/// 1e-9); in the increment form (`runtime::expint`, "Increment form") 1.66e-7, and 1.75e-7
/// since the runs restart at the thrust curve's points (DOPRI5: 3.43e-7 before that
/// restart, 1.64e-7 with it; so the bound is absolute, not DOPRI5's figure). `η`: 5.4e-11
/// (DOPRI5 8.2e-11). Against the reference with DOP853's continuous extension (6 December
/// 2026; its rows were a cubic Hermite before, part of those figures): body rates 8.19e-8
/// rad/s (DOPRI5 1.78e-7), `η` 2.59e-11 (5.85e-11); the bound 3e-7 -> 1.5e-7.
///
/// Since the built-in tables span every flow direction (aerodynamics revision 8, 7 December
/// 2026) the axial coefficients vary with the angle of attack (Niskanen's scaling), and on
/// the rail in the scenario's crosswind the fins' angle of attack sweeps from -95 to -5 deg
/// in the first 0.2 s across the tables' rows, each a kink of the piecewise-linear
/// interpolation: body rates 7.01e-8 rad/s (DOPRI5 1.71e-7), `η` 8.81e-11 (DOPRI5 5.99e-11),
/// so the exponential integrator's modes are no longer closer than DOPRI5's on this boost.
/// With the fins' scaling held at its 20-degree value beyond 20 deg (a temporary patch, a
/// new cache revision) `η` was 2.38e-11 against 5.97e-11: the rows beyond the stall are the
/// cause. Asserted: the modes within 1.5 times DOPRI5's error (measured 1.47).
#[test]
fn the_exponential_integrators_body_rates_on_a_boost_stay_near_the_reference() {
    let dir = tempfile::tempdir().unwrap();
    let file = repo("examples/hpr_k1000/hpr_k1000.vdl");
    let fly = |name: &str, sets: &[&str]| -> History {
        let out = dir.path().join(name);
        let mut c = bin();
        c.arg("run")
            .arg(&file)
            .args(["--scenario", "m1670", "--no-flutter-margin", "--out"])
            .arg(&out)
            .arg("--cache-dir")
            .arg(cache())
            .args(["--set", "run.stop_time=15 s"]);
        for s in sets {
            c.args(["--set", s]);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        History::read(&out)
    };
    let reference = fly(
        "reference",
        &[
            "run.integrator=dop853",
            "run.rtol=1e-10",
            "run.atol=1e-13",
            "run.min_step=1e-15 s",
        ],
    );
    let dopri5 = fly("dopri5", &["run.integrator=dopri5"]);
    let exponential = fly("exponential", &["run.integrator=exponential"]);
    let worst = |h: &History, prefix: &str| -> f64 {
        let mut e = 0.0f64;
        for (i, c) in reference.columns.iter().enumerate() {
            if c.starts_with(prefix) && !(prefix == "eta_" && c.starts_with("eta_dot")) {
                assert_eq!(h.columns[i], *c);
                for (r, x) in reference.rows.iter().zip(&h.rows) {
                    e = e.max((r[i] - x[i]).abs());
                }
            }
        }
        e
    };
    assert_eq!(reference.rows.len(), exponential.rows.len());
    let (w_d, w_e) = (
        worst(&dopri5, "omega_body"),
        worst(&exponential, "omega_body"),
    );
    let (eta_d, eta_e) = (worst(&dopri5, "eta_"), worst(&exponential, "eta_"));
    eprintln!("omega: dopri5 {w_d:.3e}, exponential {w_e:.3e}; eta: {eta_d:.3e}, {eta_e:.3e}");
    assert!(w_e < 1.5e-7, "omega: exponential {w_e:e} (dopri5 {w_d:e})");
    assert!(
        eta_e <= 1.5 * eta_d,
        "eta: exponential {eta_e:e} vs dopri5 {eta_d:e}"
    );
}

/// The M1670's boost through its thrust curve's first points (0.055, 0.092, 0.1, 0.15, 0.2,
/// 0.5 s: kinks of the piecewise-linear curve) with DOPRI5 (rtol 1e-7): a tighter atol
/// flies no further from the reference than the rtol's floor, and a tighter rtol flies closer
/// (DOP853 rtol 1e-10, atol 1e-13). A step across a
/// kink has a local error of order `h² Δf'` that the embedded estimate can miss;
/// integrating across the points, atol 1e-11 ended 3.06e-4 m/s off the reference against
/// 1.0e-5 at atol 1e-9. The run now restarts the integrator at every thrust-curve point:
/// measured 9.95e-6 and 1.01e-5 m/s (both the rtol's share of 100 m/s: the atol no longer
/// matters here, as it should not). Those figures and the later 3.46e-6 / 3.23e-6 (8dd9b78)
/// were mostly the reference's own error: DOP853's rows were a cubic Hermite across its
/// long steps. With its continuous extension (6 December 2026) the same runs are 1.60e-6
/// (atol 1e-9) and 1.73e-6 m/s (atol 1e-11): both DOPRI5's rtol share, their order decided
/// by round-off. So the test asserts that floor (the atol moves the error by less than a
/// tenth, measured 8 %; across the kinks it made it 30 times worse; both under 2e-6) and
/// compares levels off it: rtol 1e-9 (atol 1e-11) is 1.76e-7 m/s off, 9.1 times closer
/// than rtol 1e-7, asserted at 8 (the reference is not the floor there: DOP853 at rtol
/// 1e-12 is 1.8e-9 from it). Tolerance proportionality (Hairer, Nørsett & Wanner, vol. I,
/// II.4: DOPRI5's global error roughly proportional to the tolerance) would give 100; this
/// boost does not reach it (rtol 1e-5: 9.3e-6, 1e-6: 5.0e-6, 1e-7: 1.6e-6 m/s), measured
/// 6 December 2026 and not explained here: the assertion is the measured factor.
///
/// Re-measured 7 December 2026 for the built-in tables over every flow direction
/// (aerodynamics revision 8: the axial coefficients vary with the angle of attack, and the
/// fins sweep -95 to -5 deg on the rail in the crosswind, across the tables' rows, each a
/// kink of the interpolation): 3.35e-6 (atol 1e-9) and 3.30e-6 m/s (atol 1e-11), the atol
/// still immaterial (1.5 %); rtol 1e-9 5.27e-7 m/s, 6.4 times closer. With the fins'
/// scaling held at its 20-degree value beyond 20 deg (a temporary patch): 2.81e-6, 2.75e-6
/// and 2.67e-7 m/s; the rest of the rise from 1.6e-6 is the scaling's rows within 20 deg.
/// Asserted: the floor below 3.5e-6 and the factor 6.
#[test]
fn a_tighter_tolerance_flies_the_boost_closer_to_the_reference() {
    let dir = tempfile::tempdir().unwrap();
    let file = repo("examples/hpr_k1000/hpr_k1000.vdl");
    let fly = |name: &str, sets: &[&str]| -> History {
        let out = dir.path().join(name);
        let mut c = bin();
        c.arg("run")
            .arg(&file)
            .args(["--scenario", "m1670", "--no-flutter-margin", "--out"])
            .arg(&out)
            .arg("--cache-dir")
            .arg(cache())
            .args([
                "--set",
                "run.stop_time=1 s",
                "--set",
                "run.integrator=dopri5",
            ]);
        for s in sets {
            c.args(["--set", s]);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        History::read(&out)
    };
    let reference = fly(
        "reference",
        &[
            "run.integrator=dop853",
            "run.rtol=1e-10",
            "run.atol=1e-13",
            "run.min_step=1e-15 s",
        ],
    );
    let worst = |h: &History| -> f64 {
        let (r, x) = (reference.col("v_body_x"), h.col("v_body_x"));
        assert_eq!(r.len(), x.len());
        r.iter()
            .zip(&x)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let e9 = worst(&fly("atol9", &["run.atol=1e-9"]));
    let e11 = worst(&fly("atol11", &["run.atol=1e-11"]));
    let tight = worst(&fly("rtol9", &["run.rtol=1e-9", "run.atol=1e-11"]));
    eprintln!(
        "v_body_x off the reference: rtol 1e-7 atol 1e-9 {e9:.3e} m/s, atol 1e-11 {e11:.3e} m/s; rtol 1e-9 atol 1e-11 {tight:.3e} m/s"
    );
    // At rtol 1e-7 the atol is not what limits: the floor is the rtol's share, and the atol
    // moves the error by less than a tenth either way (measured 8 %).
    assert!(
        (e11 / e9 - 1.0).abs() < 0.1,
        "atol 1e-11: {e11:e} m/s, atol 1e-9: {e9:e} m/s"
    );
    assert!(e9.max(e11) < 3.5e-6, "{e9:e} {e11:e}");
    // A tighter rtol, off that floor, flies closer: 100x in tolerance, measured 6.4x.
    assert!(
        tight * 6.0 <= e9,
        "rtol 1e-9: {tight:e} m/s, rtol 1e-7: {e9:e} m/s"
    );
}

/// A team's flight with a measured apogee (issue 34 item 6): Valetudo (Projeto Jupiter,
/// 2019; RocketPy's docs/examples/valetudo_flight_sim.ipynb records 860 m above the ground,
/// the flight recordings lost), flown with flexflight's own aerodynamics (`examples/valetudo`:
/// Barrowman normal force and the built-in drag build-up, not the team's RASAero curve).
/// The issue's target is 10 % of the measured apogee: 913.3 m, +6.2 %, measured. The rail
/// phase is set up like RocketPy's (`tools/rocketpy/valetudo.py`: the travel until the upper
/// button leaves the rail): off-rail speed 22.61 m/s against RocketPy 1.13.0's 22.597 m/s.
#[test]
fn valetudo_reaches_its_measured_apogee_within_ten_percent() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = bin()
        .arg("run")
        .arg(repo("examples/valetudo/valetudo.vdl"))
        .args(["--scenario", "valetudo", "--no-flutter-margin", "--out"])
        .arg(&out)
        .arg("--cache-dir")
        .arg(cache())
        .args(["--set", "run.stop_time=20 s"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let s = summary(&out);
    let apogee = s["flight"]["apogee"]["height"].as_f64().unwrap();
    let off_rail = s["flight"]["off_rail_speed"].as_f64().unwrap();
    eprintln!("apogee {apogee} m, off the rail at {off_rail} m/s");
    assert!((apogee / 860.0 - 1.0).abs() < 0.10, "apogee {apogee} m");
    assert!(
        (off_rail / 22.597 - 1.0).abs() < 2e-3,
        "off rail {off_rail} m/s"
    );
}

/// Flies `examples/ndrt2020` (the Notre Dame Rocket Team's 2020 rocket, RocketPy's
/// docs/examples/ndrt_2020_flight_sim.ipynb) to just past its apogee and returns the apogee
/// height and the off-rail speed. The runs stop there: the flight is exactly vertical and
/// windless, and past apogee the rocket falls tail first at an angle of attack of exactly
/// 180 deg, where the integrator stalls (max_steps about 0.5 s after apogee; README there).
fn ndrt2020(scenario: &str, stop_time: &str) -> (f64, f64) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = bin()
        .arg("run")
        .arg(repo("examples/ndrt2020/ndrt2020.vdl"))
        .args(["--scenario", scenario, "--no-flutter-margin", "--out"])
        .arg(&out)
        .arg("--cache-dir")
        .arg(cache())
        .args(["--set", &format!("run.stop_time={stop_time}")])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let s = summary(&out);
    let apogee = s["flight"]["apogee"]["height"].as_f64().unwrap();
    let apogee_t = s["flight"]["apogee"]["t"].as_f64().unwrap();
    let off_rail = s["flight"]["off_rail_speed"].as_f64().unwrap();
    eprintln!("{scenario}: apogee {apogee} m at {apogee_t} s, off the rail at {off_rail} m/s");
    // RocketPy 1.13.0 (tools/rocketpy/ndrt2020.py) on the same effective rail, 1.462 m.
    assert!(
        (off_rail / 13.0454 - 1.0).abs() < 2e-3,
        "off rail {off_rail} m/s"
    );
    (apogee, apogee_t)
}

/// The second team flight with a measured apogee (issue 34 item 6): the Notre Dame Rocket
/// Team's 2020 rocket, 4,320 ft = 1316.736 m measured, flown with flexflight's own
/// aerodynamics (built-in normal force and drag build-up, zero-lift C_D 0.36 at Mach 0.3
/// against the team's 0.44): 1413.5 m, +7.3 %, measured (release build, 7 December 2026).
/// The assertion is that figure to 0.1 %, and the issue's 10 % of the measurement.
#[test]
fn ndrt2020_reaches_its_measured_apogee_within_ten_percent() {
    let (apogee, t) = ndrt2020("ndrt2020", "17.7 s");
    assert!(t < 17.7, "apogee not reached: {t} s");
    assert!((apogee / 1413.5 - 1.0).abs() < 1e-3, "apogee {apogee} m");
    assert!((apogee / 1316.736 - 1.0).abs() < 0.10, "apogee {apogee} m");
}

/// The same vehicle with the team's drag (the notebook's constant C_D 0.44 in place of the
/// drag build-up, the built-in normal force kept; `tools/constant_drag_tables.py`): 1334.8 m
/// measured, against RocketPy 1.13.0's 1331.25 m with the same C_D, atmosphere and rail
/// (+0.27 %; `tools/rocketpy/ndrt2020.py`).
#[test]
fn ndrt2020_with_the_teams_drag_flies_as_rocketpy() {
    let (apogee, t) = ndrt2020("ndrt2020_cd044", "17.1 s");
    assert!(t < 17.1, "apogee not reached: {t} s");
    assert!((apogee / 1334.8 - 1.0).abs() < 1e-3, "apogee {apogee} m");
    assert!((apogee / 1331.25 - 1.0).abs() < 5e-3, "apogee {apogee} m");
}
