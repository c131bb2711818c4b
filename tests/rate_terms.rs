//! `body_aero { rate_terms = true }` (thesis 5.3.5-5.3.9, 5.3.22-5.3.25): the option changes
//! the flight, and the pitch damping it adds is the one flight-mechanics theory predicts for
//! the body's C_mq + C_mα̇.

use std::path::{Path, PathBuf};
use std::process::Command;

use flexflight::analysis::linear::{Variant, analyse};
use flexflight::analysis::linearise::LineariseOptions;

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn run(out: &Path, sets: &[&str]) -> std::process::Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_flexflight"));
    c.arg("run")
        .arg(repo("examples/thesis/section_6_5.vdl"))
        .args(["--scenario", "subsonic_t06"])
        .arg("--out")
        .arg(out)
        .arg("--cache-dir")
        .arg(Path::new(env!("CARGO_TARGET_TMPDIR")).join("rate-terms-cache"));
    for s in sets {
        c.args(["--set", s]);
    }
    c.output().unwrap()
}

/// Column `name` of `history.csv`.
fn column(dir: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let i = header
        .iter()
        .position(|c| *c == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    lines
        .map(|l| l.split(',').nth(i).unwrap().parse().unwrap())
        .collect()
}

#[test]
fn rate_terms_change_the_history() {
    // SPHADS-1 with 3 mm fins (0.6 mm flutters before the gust in our model, see the README)
    // at 200 m/s, 5 km, the body-z gust at 1 s; 3 s of flight with the option on (the
    // vehicle file) and off.
    let dir = tempfile::tempdir().unwrap();
    let (on, off) = (dir.path().join("on"), dir.path().join("off"));
    let sets = ["run.stop_time=3s", "fins.thickness=3mm"];
    let o = run(&on, &sets);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = run(
        &off,
        &[sets[0], sets[1], "forces.body_aero.rate_terms=false"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (a, b) = (column(&on, "omega_body_y"), column(&off, "omega_body_y"));
    assert_eq!(a.len(), b.len());
    let t = column(&on, "t");
    assert!(
        *t.last().unwrap() >= 3.0 - 1e-9,
        "the run stopped at {}",
        t.last().unwrap()
    );
    // The same start (no rate at t = 0); the gravity turn before the gust already gives a
    // small pitch rate, so the histories part from the start, and after the gust the pitch
    // rate differs by a visible fraction of its peak.
    assert_eq!(a[0], b[0]);
    let on_text = std::fs::read(on.join("history.csv")).unwrap();
    assert_ne!(on_text, std::fs::read(off.join("history.csv")).unwrap());
    let peak = b.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let diff = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(
        peak > 0.0 && diff > 0.02 * peak,
        "peak {peak}, largest difference {diff}"
    );
    // And the oscillation dies faster with the option on: the pitch-rate amplitude over the
    // last half second is smaller.
    let tail = t.iter().position(|&t| t >= 2.5).unwrap();
    let amp = |x: &[f64]| x[tail..].iter().map(|x| x.abs()).fold(0.0, f64::max);
    eprintln!("tail amplitude on {} off {}", amp(&a), amp(&b));
    assert!(amp(&a) < amp(&b), "on {} off {}", amp(&a), amp(&b));
}

/// The checked scenario `subsonic_t06` with `sets`, compiled and planned.
fn variant(sets: &[&str]) -> Variant {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let checked = flexflight::check::check_files(
        &[repo("examples/thesis/section_6_5.vdl")],
        &sets,
        &flexflight::check::DiskLoader,
    );
    let scenario = checked
        .program
        .scenario("subsonic_t06")
        .cloned()
        .expect("scenario");
    let compiled = flexflight::structure::compile::compile(&scenario.vehicle)
        .unwrap()
        .0;
    let plan = flexflight::plan::build(&scenario, &compiled).unwrap();
    Variant {
        plan,
        scenario,
        compiled,
    }
}

/// The roots `(Re, Im)` with `Im > 0` below 20 Hz: the rigid pitch and yaw oscillations.
fn slow_oscillations(v: &Variant) -> Vec<(f64, f64)> {
    let r = analyse(v, LineariseOptions::default()).unwrap();
    let mut out: Vec<(f64, f64)> = r
        .eigen
        .roots
        .iter()
        .filter(|r| !r.neutral && r.imag > 0.0 && r.frequency_hz < 20.0)
        .map(|r| (r.real, r.imag))
        .collect();
    out.sort_by(|a, b| a.1.total_cmp(&b.1));
    out
}

/// The pitch damping `rate_terms` adds, against the short-period approximation.
///
/// The body block adds, about the reference point, the moment
/// `q∞ S d (d/(2V)) cm_q q` and the normal force `q∞ S (d/(2V)) cn_q q` (at the reference
/// point, `x_ref - x_cg` ahead of the mass centre), so the pitch-rate derivative of the
/// moment about the mass centre grows by
/// `ΔM_q = q∞ S d/(2V) (d cm_q + (x_ref - x_cg) cn_q)` (N m s). In the short-period
/// approximation (Nelson, "Flight Stability and Automatic Control", 2nd ed., 1998, §4.4;
/// Etkin & Reid, "Dynamics of Flight", 3rd ed., 1996, §6.4) the roots solve
/// `λ² - (M_q/I_yy + M_α̇/I_yy + Z_α/(m V)) λ + (Z_α M_q/(m V I_yy) - M_α/I_yy) = 0`; the sum of
/// the two roots is the trace, so a change of M_q moves the real part of the pair by
/// `Δσ = ΔM_q/(2 I_yy)`, whatever Z_q (the rate normal force) does to the frequency. The
/// linearised 3-D model has the elastic modes, the rigid translations and gravity too;
/// with 3 mm fins (fin flap near 180 Hz, far from the 1.6 Hz pitch oscillation) they
/// couple little, and the two degenerate pairs (pitch and yaw: the body block's rate loads
/// are the same in both planes) each move by the predicted amount. Measured: σ -0.66190 ->
/// -0.75263 1/s, a change of -0.090727 1/s against -0.089786 1/s predicted (+1.05 %); the
/// frequency moves from 9.8263 to 9.8168 rad/s.
#[test]
fn rate_terms_add_the_predicted_short_period_damping() {
    let stiff = "fins.thickness=3mm";
    let on = variant(&[stiff]);
    let off = variant(&[stiff, "forces.body_aero.rate_terms=false"]);
    let (r_on, r_off) = (slow_oscillations(&on), slow_oscillations(&off));
    assert_eq!(r_on.len(), 2, "{r_on:?}");
    assert_eq!(r_off.len(), 2, "{r_off:?}");
    // The prediction from the body table's rate columns at the flight condition.
    let lin = analyse(&on, LineariseOptions::default()).unwrap();
    let c = lin.condition;
    let v = &on.scenario.vehicle;
    let tables = flexflight::runtime::forces::aero_tables(v).unwrap();
    let rates = tables
        .body
        .body_rates(c.mach, 0.0, c.altitude)
        .unwrap()
        .unwrap();
    let (s, d) = (v.aero.reference_area.value, v.aero.reference_length.value);
    let arm = v.aero.reference_point.value[0] - on.compiled.centre_of_mass[0];
    let dm_q = c.dynamic_pressure * s * d / (2.0 * c.speed) * (d * rates.cm_q + arm * rates.cn_q);
    let predicted = dm_q / (2.0 * on.compiled.inertia_cm[1][1]);
    for (a, b) in r_on.iter().zip(&r_off) {
        let measured = a.0 - b.0;
        eprintln!(
            "sigma off {} on {}: change {measured} 1/s, predicted {predicted} 1/s ({} %); omega {} -> {} rad/s",
            b.0,
            a.0,
            100.0 * (measured / predicted - 1.0),
            b.1,
            a.1
        );
        assert!(
            (measured / predicted - 1.0).abs() < 0.02,
            "measured {measured}, predicted {predicted}"
        );
    }
    // The planar models apply the same derivatives (the body table's rate columns).
    let planar = flexflight::analysis::planar::PlanarVehicle::new(v, &on.compiled).unwrap();
    let pc = planar.condition_at_speed(c.altitude, c.speed).unwrap();
    let p = flexflight::analysis::planar::parameters(
        &planar,
        flexflight::analysis::planar::PlanarKind::Unpinned,
        3e-3,
        pc,
    )
    .unwrap();
    assert_eq!((p.cn_alpha_dot, p.cm_alpha_dot), (rates.cn_q, rates.cm_q));
    let planar_off =
        flexflight::analysis::planar::PlanarVehicle::new(&off.scenario.vehicle, &off.compiled)
            .unwrap();
    let p_off = flexflight::analysis::planar::parameters(
        &planar_off,
        flexflight::analysis::planar::PlanarKind::Unpinned,
        3e-3,
        pc,
    )
    .unwrap();
    assert_eq!((p_off.cn_alpha_dot, p_off.cm_alpha_dot), (0.0, 0.0));
}
