//! The burning motor (issue 10, "Variable mass"): the variable-mass equations of motion of
//! `runtime::eom` against Tsiolkovsky's rocket equation, the momentum balance with the
//! exhaust's share, the energy balance reported by a run, the mass properties of the motor
//! in the compiled vehicle, and the motor's diagnostics at `check`.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use flexflight::runtime::eom::{Eom, FreeFlight};
use flexflight::runtime::integrate::{
    AdaptiveOptions, DormandPrince54, Integrator, OdeSystem, RhsError,
};
use flexflight::runtime::kinematics::{c_bi_normalized, cross, mat_t_vec};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn cache() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("motor-test-cache")
}

/// A body-only vehicle (2 m aluminium tube, payload forward) with a motor at the tail and a
/// constant-thrust curve: 2000 N for 3 s, 3 kg of propellant (c = 2000 m/s).
fn vehicle_files(dir: &Path, extra_forces: &str, motor_extra: &str) -> PathBuf {
    std::fs::write(
        dir.join("constant.csv"),
        "time_s,thrust_N\n0,2000\n3,2000\n",
    )
    .unwrap();
    let vehicle = common::burner_vehicle(extra_forces, motor_extra);
    let text = format!(
        r#"{vehicle}
scenario climb {{
  vehicle = burner
  initial {{
    velocity = (10, 0, 0) m/s
    angular_velocity = (0, 0, 0) rad/s
    attitude = euler(0 deg, 90 deg, 0 deg)
    altitude = 1 km
  }}
  run {{
    stop_time = 3 s
    integrator = dopri5
    rtol = 1e-12
    atol = 1e-12
    output_interval = 250 ms
    stop_on_ground = false
  }}
}}
"#
    );
    let path = dir.join("burner.vdl");
    std::fs::write(&path, text).unwrap();
    path
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
        let rows = lines
            .map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect())
            .collect();
        History { columns, rows }
    }
    fn col(&self, name: &str) -> Vec<f64> {
        let i = self.columns.iter().position(|c| c == name).unwrap();
        self.rows.iter().map(|r| r[i]).collect()
    }
}

fn run(file: &Path, out: &Path, sets: &[&str]) -> std::process::Output {
    let mut c = bin();
    c.arg("run")
        .arg(file)
        .args(["--scenario", "climb", "--out"])
        .arg(out)
        .arg("--cache-dir")
        .arg(cache());
    for s in sets {
        c.args(["--set", s]);
    }
    c.output().unwrap()
}

/// Vertical flight in vacuum with constant thrust and constant Isp: `V = V0 + c ln(m0/m)`
/// without gravity and `V = V0 + c ln(m0/m) - g t` with uniform gravity (Tsiolkovsky plus
/// the gravity loss), `m = m0 - ṁ t`, `ṁ = T / c`. The body bending modes are not excited by
/// an axial thrust on the axis, so `V_B,x` is the rocket's speed.
#[test]
fn vertical_burn_follows_tsiolkovsky_to_1e_9() {
    for (gravity, g) in [
        ("", 0.0),
        ("gravity { altitude_correction = false }", 9.806),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let file = vehicle_files(dir.path(), gravity, "");
        let out = dir.path().join("out");
        let o = run(&file, &out, &[]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let h = History::read(&out);
        let (t, v, m) = (h.col("t"), h.col("v_body_x"), h.col("mass"));
        let m0 = m[0];
        let (c, mdot) = (2000.0, 1.0);
        let mut worst_v: f64 = 0.0;
        let mut worst_m: f64 = 0.0;
        for k in 0..t.len() {
            let mk = m0 - mdot * t[k];
            let want = 10.0 + c * (m0 / mk).ln() - g * t[k];
            worst_v = worst_v.max(((v[k] - want) / want).abs());
            worst_m = worst_m.max(((m[k] - mk) / mk).abs());
        }
        assert_eq!(*t.last().unwrap(), 3.0);
        // Burnout: the vehicle has lost exactly its 3 kg of propellant.
        assert!(
            (m[m.len() - 1] - (m0 - 3.0)).abs() < 1e-12,
            "{}",
            m[m.len() - 1]
        );
        eprintln!("gravity {g}: worst relative speed error {worst_v:.3e}, mass {worst_m:.3e}");
        // The issue asks for 1e-9; 5e-14 is achieved (rtol 1e-12).
        assert!(worst_v < 1e-12, "speed error {worst_v:e}");
        assert!(worst_m < 1e-14, "mass error {worst_m:e}");
        // The mass centre moves forward as the aft grain burns.
        let cm = h.col("cm_body_x");
        assert!(
            cm[cm.len() - 1] > cm[0] + 0.05,
            "{} -> {}",
            cm[0],
            cm[cm.len() - 1]
        );
    }
}

fn compile_and_plan(
    file: &Path,
) -> (
    flexflight::structure::compile::CompiledVehicle,
    flexflight::plan::Plan,
) {
    let checked =
        flexflight::check::check_files(&[file.into()], &[], &flexflight::check::DiskLoader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    let scenario = checked.program.scenario("climb").unwrap().clone();
    let compiled = flexflight::structure::compile::compile(&scenario.vehicle)
        .unwrap()
        .0;
    let plan = flexflight::plan::build(&scenario, &compiled).unwrap();
    (compiled, plan)
}

/// The equations of motion with the momentum fluxes integrated alongside: `∫ (T_I - ṁ_e
/// v_e,I) dt` and its moment about the inertial origin.
struct WithFluxes<'m> {
    eom: Eom<'m, FreeFlight>,
}

impl OdeSystem for WithFluxes<'_> {
    fn dim(&self) -> usize {
        self.eom.dim() + 6
    }
    fn error_dim(&self) -> usize {
        self.eom.dim()
    }
    fn rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), RhsError> {
        let d = self.eom.dim();
        self.eom.rhs(t, &x[..d], &mut dx[..d])?;
        let s = self.eom.propulsion_sample().unwrap();
        let c_bi = c_bi_normalized(&[x[3], x[4], x[5], x[6]]);
        let f_b: [f64; 3] =
            [0, 1, 2].map(|i| s.thrust_force_body[i] - s.mass_flow * s.exit_velocity_body[i]);
        let rxv = cross(&s.exit_position_body, &s.exit_velocity_body);
        let g_b: [f64; 3] = [0, 1, 2].map(|i| s.thrust_moment_body[i] - s.mass_flow * rxv[i]);
        let f_i = mat_t_vec(&c_bi, &f_b);
        let pos = [x[0], x[1], x[2]];
        let pxf = cross(&pos, &f_i);
        let g_i = mat_t_vec(&c_bi, &g_b);
        for i in 0..3 {
            dx[d + i] = f_i[i];
            dx[d + 3 + i] = pxf[i] + g_i[i];
        }
        Ok(())
    }
    fn project(&mut self, x: &mut [f64], dx: &mut [f64]) {
        let d = self.eom.dim();
        self.eom.project(&mut x[..d], &mut dx[..d]);
    }
}

/// The momentum balance of a burning, tumbling, vibrating vehicle in vacuum with a
/// misaligned, offset thrust: the vehicle's inertial momentum and angular momentum about the
/// inertial origin change by the thrust's impulse less what the exhaust takes away at the
/// nozzle's velocity, `d/dt p_I = T_I - ṁ_e v_e,I` and
/// `d/dt H_O = p_e × (T_I - ṁ_e v_e,I) + C_IB (G_T - ṁ_e r_e × v_e)`.
#[test]
fn burning_vehicle_balances_momentum_with_the_exhaust() {
    let dir = tempfile::tempdir().unwrap();
    let file = vehicle_files(
        dir.path(),
        "thrust {\n offset = (0, 3, -2) mm\n misalignment = (0, 0.5, 1) deg\n }",
        "",
    );
    let (compiled, plan) = compile_and_plan(&file);
    let model = &compiled.reduced;
    let p = flexflight::run::build_propulsion(&plan, model)
        .unwrap()
        .unwrap();
    let eom = Eom::new(model, FreeFlight)
        .unwrap()
        .with_propulsion(p.clone())
        .unwrap();
    let mut probe = Eom::new(model, FreeFlight)
        .unwrap()
        .with_propulsion(p)
        .unwrap();
    let mut sys = WithFluxes { eom };
    let mut x = plan.initial_state.clone();
    x[10..13].copy_from_slice(&[0.5, 1.0, -0.7]);
    let x0 = x.clone();
    x.resize(sys.dim(), 0.0);
    let inv0 = probe.invariants_at(0.0, &x0).unwrap();
    let h0 = |inv: &flexflight::runtime::eom::Invariants, x: &[f64]| {
        let c_bi = c_bi_normalized(&[x[3], x[4], x[5], x[6]]);
        let ho = mat_t_vec(&c_bi, &inv.angular_momentum_origin_body);
        let pxp = cross(&[x[0], x[1], x[2]], &inv.momentum_inertial);
        [0, 1, 2].map(|i| pxp[i] + ho[i])
    };
    let ang0 = h0(&inv0, &x0);
    let mut dp = DormandPrince54::new(AdaptiveOptions {
        rtol: 1e-11,
        atol: 1e-11,
        ..AdaptiveOptions::default()
    });
    let mut worst: (f64, f64) = (0.0, 0.0);
    let n = plan.layout().len();
    let mut observer = |t: f64, xs: &[f64], _dx: &[f64]| -> bool {
        let inv = probe.invariants_at(t, &xs[..n]).unwrap();
        let ang = h0(&inv, xs);
        let d = xs.len() - 6;
        for i in 0..3 {
            let lin = inv.momentum_inertial[i] - inv0.momentum_inertial[i] - xs[d + i];
            let rot = ang[i] - ang0[i] - xs[d + 3 + i];
            worst.0 = worst.0.max(lin.abs());
            worst.1 = worst.1.max(rot.abs());
        }
        true
    };
    let r = dp.integrate(&mut sys, 0.0, &mut x, 3.0, &mut observer);
    assert_eq!(
        r.stop,
        flexflight::runtime::integrate::StopReason::Completed
    );
    // Scales: the thrust's impulse (6000 N s) and its moment arm (~2 m).
    let (lin, rot) = (worst.0 / 6000.0, worst.1 / 12000.0);
    eprintln!("momentum balance: linear {lin:.3e}, angular {rot:.3e} (relative)");
    // Achieved: 1.2e-13 and 6.4e-11 (rtol 1e-11).
    assert!(lin < 1e-12 && rot < 5e-10, "{lin:e} {rot:e}");
    // The flight did rotate and vibrate: the balance is not the trivial one.
    let s = StateViewCheck::of(&x, plan.n_modes);
    assert!(s.eta_max > 1e-8, "modes not excited: {}", s.eta_max);
}

struct StateViewCheck {
    eta_max: f64,
}

impl StateViewCheck {
    fn of(x: &[f64], n: usize) -> Self {
        StateViewCheck {
            eta_max: x[13..13 + n].iter().fold(0.0, |a: f64, b| a.max(b.abs())),
        }
    }
}

/// The energy balance a run reports closes with thrust, mass flow, gravity, damping and
/// vibration: `Δ(T + U) - W_loads - W_propulsive + D` stays at the integration error.
#[test]
fn burning_flight_energy_balance_closes() {
    let dir = tempfile::tempdir().unwrap();
    let file = vehicle_files(
        dir.path(),
        "gravity { altitude_correction = true }\n thrust {\n offset = (0, 3, -2) mm\n misalignment = (0, 0.5, 1) deg\n }",
        "",
    );
    let out = dir.path().join("out");
    let o = run(
        &file,
        &out,
        &["initial.angular_velocity=(0.5, 1, -0.7) rad/s"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let b = &s["energy_balance"];
    let rel = b["max_relative_residual"].as_f64().unwrap();
    let wp = b["work_propulsive_j"].as_f64().unwrap();
    let wl = b["work_loads_j"].as_f64().unwrap();
    let diss = b["dissipated_j"].as_f64().unwrap();
    eprintln!("energy balance: {b}");
    assert!(wp > 1e5 && wl < 0.0 && diss > 0.0, "{b}");
    // Achieved: 2.5e-12 (rtol 1e-12) with the old modal damping; 2.55e-11 since `damping`
    // became the free vehicle's damping ratio (a full damping matrix on this vehicle).
    assert!(rel < 5e-11, "relative residual {rel:e}");
    assert_eq!(s["mass"]["motor"]["propellant_kg"].as_f64(), Some(3.0));
}

fn check(file: &Path) -> (bool, String) {
    let o = bin()
        .arg("check")
        .arg(file)
        .args(["--format", "json"])
        .output()
        .unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).to_string(),
    )
}

/// A corrupt `.eng` line is a diagnostic on that line of the curve file at `check` (not
/// only at `run`), and nonsense motors are diagnostics with spans.
#[test]
fn bad_motors_are_diagnostics_at_check() {
    let dir = tempfile::tempdir().unwrap();
    let file = vehicle_files(dir.path(), "", "");
    let (ok, text) = check(&file);
    assert!(ok, "{text}");

    // A corrupt line 4 of a RASP file.
    std::fs::write(
        dir.path().join("bad.eng"),
        "; test\nK1000T-P 75 396 P 1.182 2.575 AT\n0.004 895.1\n0.015 11x9.7\n0.5 0\n",
    )
    .unwrap();
    let text = std::fs::read_to_string(&file)
        .unwrap()
        .replace("curve = \"constant.csv\"", "curve = \"bad.eng\"")
        .replace("propellant_mass = 3 kg", "")
        .replace("total_mass = 4.5 kg", "");
    std::fs::write(&file, text).unwrap();
    let (ok, out) = check(&file);
    assert!(!ok);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap_or_else(|_| panic!("{out}"));
    let d = if v.is_array() {
        &v[0]
    } else {
        &v["diagnostics"][0]
    };
    assert_eq!(d["code"], "vdl::motor::curve", "{out}");
    let labels = d["labels"].as_array().unwrap();
    assert!(
        labels
            .iter()
            .any(|l| l["file"].as_str().unwrap_or("").ends_with("bad.eng") && l["line"] == 4),
        "{out}"
    );

    // Propellant heavier than the loaded motor; a motor wider than the bore; a thrust
    // curve next to the motor's.
    for (from, to, code) in [
        (
            "total_mass = 4.5 kg",
            "total_mass = 2.5 kg",
            "vdl::motor::mass",
        ),
        (
            "diameter = 75 mm",
            "diameter = 98 mm",
            "vdl::motor::geometry",
        ),
        // A motor heavier than it can be (4.5 t for 4.5 kg), and just above the bound: a
        // 75 mm x 600 mm cylinder of solid steel (7850 kg/m^3) is 20.81 kg.
        (
            "total_mass = 4.5 kg",
            "total_mass = 4500 kg",
            "vdl::motor::heavy",
        ),
        (
            "total_mass = 4.5 kg",
            "total_mass = 20.9 kg",
            "vdl::motor::heavy",
        ),
        (
            "position = (-2, 0, 0) m",
            "position = (-2.3, 0, 0) m",
            "vdl::motor::geometry",
        ),
    ] {
        let file = vehicle_files(dir.path(), "", "");
        let text = std::fs::read_to_string(&file).unwrap().replace(from, to);
        std::fs::write(&file, text).unwrap();
        let (ok, out) = check(&file);
        assert!(!ok, "{from} -> {to}");
        assert!(out.contains(code), "{code}: {out}");
        assert!(out.contains("\"line\""), "no span: {out}");
    }
    // Just below the bound the same motor is accepted.
    let file = vehicle_files(dir.path(), "", "");
    let text = std::fs::read_to_string(&file)
        .unwrap()
        .replace("total_mass = 4.5 kg", "total_mass = 20.7 kg");
    std::fs::write(&file, text).unwrap();
    let (ok, out) = check(&file);
    assert!(
        ok,
        "a 20.7 kg motor of 75 mm x 600 mm is below solid steel: {out}"
    );
    let file = vehicle_files(dir.path(), "thrust { curve = \"constant.csv\" }", "");
    let (ok, out) = check(&file);
    assert!(!ok && out.contains("vdl::motor::thrust_curve"), "{out}");
}

/// The motor in the compiled vehicle: the casing and the grain add exactly their cylinders'
/// mass, first moment and inertia (about the nose), and the propellant's coefficients are
/// the grain's alone.
#[test]
fn compiled_motor_adds_its_cylinders_mass_properties() {
    let dir = tempfile::tempdir().unwrap();
    let with = vehicle_files(dir.path(), "", "");
    let text = std::fs::read_to_string(&with).unwrap();
    let start = text.find("  motor grain {").unwrap();
    let end = start + text[start..].find("  }\n").unwrap() + 4;
    let without = dir.path().join("dry.vdl");
    std::fs::write(&without, format!("{}{}", &text[..start], &text[end..])).unwrap();
    let (a, _) = compile_and_plan(&with);
    let (b, _) = compile_and_plan(&without);
    let (m_p, m_c, l, d, x_c) = (3.0, 1.5, 0.6, 0.075, -1.7);
    let (ra, rb, p) = (&a.reduced, &b.reduced, a.propellant.as_ref().unwrap());
    let rel = |x: f64, y: f64| ((x - y) / y).abs();
    assert!(
        rel(ra.mass - rb.mass, m_p + m_c) < 1e-12,
        "{}",
        ra.mass - rb.mass
    );
    assert!(rel(p.mass, m_p) < 1e-13);
    assert!(rel(ra.first_moment[0] - rb.first_moment[0], (m_p + m_c) * x_c) < 1e-12);
    assert!(rel(p.first_moment[0], m_p * x_c) < 1e-13);
    // J about the nose: axial m D²/8 (grain) + m D²/4 (casing); transverse
    // m (D²/16 + L²/12) + m x_c² (grain), m (D²/8 + L²/12) + m x_c² (casing).
    let jxx = m_p * d * d / 8.0 + m_c * d * d / 4.0;
    let jyy = m_p * (d * d / 16.0 + l * l / 12.0)
        + m_c * (d * d / 8.0 + l * l / 12.0)
        + (m_p + m_c) * x_c * x_c;
    let djxx = ra.inertia[0][0] - rb.inertia[0][0];
    let djyy = ra.inertia[1][1] - rb.inertia[1][1];
    eprintln!("ΔJxx {djxx} vs {jxx}, ΔJyy {djyy} vs {jyy}");
    assert!(rel(djxx, jxx) < 1e-10 && rel(djyy, jyy) < 1e-10);
    assert!(
        rel(
            p.inertia[2][2],
            m_p * (d * d / 16.0 + l * l / 12.0 + x_c * x_c)
        ) < 1e-12
    );
}

/// The burner vehicle with its `motor` block's body replaced by `motor_body`, checked from
/// memory: (the checked program's motor if any, its diagnostics as (code, is error, message,
/// the text under the first label)).
#[allow(clippy::type_complexity)]
fn check_motor_body(
    motor_body: &str,
) -> (
    Option<flexflight::check::ir::Motor>,
    Vec<(&'static str, bool, String, String)>,
) {
    use flexflight::check::{MemoryLoader, check_source};
    let v = common::burner_vehicle("", "");
    let start = v.find("  motor grain {").unwrap();
    let end = start + v[start..].find("  }\n").unwrap() + 4;
    let text = format!(
        "{}  motor grain {{\n{motor_body}\n  }}\n{}",
        &v[..start],
        &v[end..]
    );
    let c = check_source("m.vdl", &text, &MemoryLoader::default());
    let diags = c
        .diagnostics
        .iter()
        .map(|d| {
            let under = d
                .labels
                .first()
                .map(|l| text[l.span.start as usize..l.span.end as usize].to_string())
                .unwrap_or_default();
            (d.code, d.is_error(), d.message.clone(), under)
        })
        .collect();
    let motor = c.program.vehicles.first().and_then(|v| v.motor.clone());
    (motor, diags)
}

/// `motor { designation = ... }` (issue 34): the bundled curve is found however the
/// rocketeer writes the name, and the header's dimensions and masses are the motor's.
#[test]
fn a_motor_by_designation_takes_the_catalogue_headers_dimensions_and_masses() {
    for name in ["Cesaroni M1670", "CTI M1670", "M1670", "cesaroni m1670-bs"] {
        let (m, d) = check_motor_body(&format!(
            "    designation = \"{name}\"\n    position = (-2, 0, 0) m"
        ));
        assert!(d.is_empty(), "{name}: {d:?}");
        let m = m.unwrap_or_else(|| panic!("{name}: no motor"));
        // The RASP header of motors/Cesaroni_M1670.eng: `M1670-BS 75 757 0 3.101 5.231 CTI`.
        assert_eq!(m.length.value, 0.757, "{name}");
        assert_eq!(m.diameter.value, 0.075, "{name}");
        assert_eq!(m.propellant_mass.value, 3.101, "{name}");
        assert_eq!(m.total_mass.value, 5.231, "{name}");
        assert!(
            m.curve
                .value
                .to_string_lossy()
                .ends_with("Cesaroni_M1670.eng"),
            "{:?}",
            m.curve.value
        );
        // The curve the plan reads is the bundled one.
        let curve = flexflight::runtime::thrust::ThrustCurve::read(&m.curve.value).unwrap();
        assert_eq!(curve.name, "M1670-BS");
    }
}

/// The file form keeps working and now also takes its dimensions from the header.
#[test]
fn a_motor_curve_file_without_dimensions_takes_the_headers() {
    let eng = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("motors/AeroTech_K1000T.eng"),
    )
    .unwrap();
    let v = common::burner_vehicle("", "")
        .replace("curve = \"constant.csv\"", "curve = \"k.eng\"")
        .replace("length = 600 mm", "")
        .replace("diameter = 75 mm", "")
        .replace("propellant_mass = 3 kg", "")
        .replace("total_mass = 4.5 kg", "");
    let mut loader = flexflight::check::MemoryLoader::default();
    loader.files.insert(PathBuf::from("k.eng"), eng);
    let c = flexflight::check::check_source("m.vdl", &v, &loader);
    assert!(c.diagnostics.is_empty(), "{:?}", c.diagnostics);
    let m = c.program.vehicles[0].motor.clone().unwrap();
    // `K1000T-P 75 396 P 1.182 2.575 AT`.
    assert_eq!((m.length.value, m.diameter.value), (0.396, 0.075));
    // A CSV curve has no header: its dimensions are still required.
    let v = common::burner_vehicle("", "").replace("length = 600 mm", "");
    let mut loader = flexflight::check::MemoryLoader::default();
    loader.files.insert(
        PathBuf::from("constant.csv"),
        "time_s,thrust_N\n0,2000\n3,2000\n".into(),
    );
    let c = flexflight::check::check_source("m.vdl", &v, &loader);
    assert!(
        c.diagnostics
            .iter()
            .any(|d| d.code == "vdl::field::missing" && d.message.contains("length")),
        "{:?}",
        c.diagnostics
    );
}

/// An override that contradicts the header is a warning at the value (the issue: `length`
/// silently overrode the header); a value that agrees with it, or `expect_unusual`, is quiet.
#[test]
fn an_override_contradicting_the_header_is_a_warning() {
    let base = "    designation = \"Cesaroni M1670\"\n    position = (-2, 0, 0) m\n";
    for (field, value) in [
        ("length", "600 mm"),
        ("diameter", "54 mm"),
        ("propellant_mass", "2.9 kg"),
        ("total_mass", "5.4 kg"),
    ] {
        let (m, d) = check_motor_body(&format!("{base}    {field} = {value}"));
        assert!(m.is_some(), "a warning only: {d:?}");
        assert_eq!(d.len(), 1, "{field}: {d:?}");
        assert_eq!(d[0].0, "vdl::motor::header");
        assert!(!d[0].1, "a warning");
        assert!(d[0].2.contains(field), "{d:?}");
        assert_eq!(d[0].3, value, "labelled at the value");
        let (_, d) = check_motor_body(&format!(
            "{base}    {field} = {value}\n    expect_unusual = true"
        ));
        assert!(d.is_empty(), "{d:?}");
    }
    // The header's own values, written out (3.10 kg is 3.101 to three figures).
    let (_, d) = check_motor_body(&format!(
        "{base}    length = 757 mm\n    diameter = 75 mm\n    propellant_mass = 3.10 kg\n    total_mass = 5231 g"
    ));
    assert!(d.is_empty(), "{d:?}");
}

/// Unknown, ambiguous and contradictory motors are errors at `check`, at the string, listing
/// the nearest curves or the candidates.
#[test]
fn unknown_and_ambiguous_designations_are_errors_at_the_string() {
    let one = |body: &str| {
        let (m, d) = check_motor_body(body);
        assert!(m.is_none(), "{body}");
        assert_eq!(d.len(), 1, "{body}: {d:?}");
        assert!(d[0].1, "an error: {d:?}");
        d.into_iter().next().unwrap()
    };
    let at = "\n    position = (-2, 0, 0) m";
    let d = one(&format!("    designation = \"Cesaroni M1600\"{at}"));
    assert_eq!(d.0, "vdl::motor::designation");
    assert_eq!(d.3, "\"Cesaroni M1600\"");
    assert!(
        d.2.contains("the nearest: `Cesaroni M1670-BS`, `Cesaroni M1400`"),
        "{}",
        d.2
    );
    let d = one(&format!("    designation = \"AeroTech H125W\"{at}"));
    assert_eq!(d.0, "vdl::motor::ambiguous");
    assert_eq!(d.3, "\"AeroTech H125W\"");
    assert!(
        d.2.contains("`AeroTech H125W-29mm`") && d.2.contains("`AeroTech H125W-38mm`"),
        "{}",
        d.2
    );
    let d = one(&format!("    designation = \"Acme M1670\"{at}"));
    assert_eq!(d.0, "vdl::motor::designation");
    assert!(d.2.contains("`Acme`"), "{}", d.2);
    let d = one(&format!(
        "    designation = \"M1670\"\n    curve = \"constant.csv\"{at}"
    ));
    assert_eq!(d.0, "vdl::motor::source");
    let d = one(&format!("    length = 757 mm{at}"));
    assert_eq!(d.0, "vdl::motor::source");
}
