//! Thrust curves: the real RASP curves in shared/motors, the (0, 0) and end conventions,
//! and every reader error on small files.

use std::path::{Path, PathBuf};

use flexflight::runtime::thrust::{ThrustCurve, ThrustCurveError};

fn motor(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/motors/")).join(name)
}

#[test]
fn aerotech_k1000t_is_a_k_motor_of_about_1000_n() {
    let curve = ThrustCurve::read(&motor("AeroTech_K1000T.eng")).unwrap();
    assert_eq!(curve.name, "K1000T-P");
    assert_eq!(curve.maker.as_deref(), Some("AT"));
    assert_eq!(curve.propellant_mass, Some(1.182));
    assert_eq!(curve.total_mass, Some(2.575));
    assert_eq!(curve.diameter, Some(0.075));
    let impulse = curve.total_impulse();
    eprintln!(
        "K1000T: I = {impulse:.1} N s, t_b = {} s, mean {:.1} N",
        curve.burn_time(),
        curve.average_thrust()
    );
    // K class: 1280.01-2560 N s (NAR/TRA impulse classes).
    assert!((1280.0..=2560.0).contains(&impulse), "{impulse}");
    // The designation's number is the average thrust in N.
    assert!((curve.average_thrust() - 1000.0).abs() < 0.01 * 1000.0);
    assert_eq!(curve.burn_time(), 2.5);
    // The file starts at 0.004 s: linear ramp from (0, 0) to (0.004, 895.149).
    assert_eq!(curve.thrust_at(0.0), 0.0);
    assert!((curve.thrust_at(0.002) - 0.5 * 895.149).abs() < 1e-9);
    // Between points: linear.
    assert!((curve.thrust_at(0.25) - 0.5 * (1109.853 + 1116.459)).abs() < 1e-9);
    // After the last point and before ignition: zero.
    assert_eq!(curve.thrust_at(2.6), 0.0);
    assert_eq!(curve.thrust_at(-1.0), 0.0);
    assert_eq!(curve.thrust_at(f64::NAN), 0.0);
}

#[test]
fn cesaroni_m1670_matches_its_rated_impulse() {
    let curve = ThrustCurve::read(&motor("Cesaroni_M1670.eng")).unwrap();
    assert_eq!(curve.name, "M1670-BS");
    assert_eq!(curve.maker.as_deref(), Some("CTI"));
    let impulse = curve.total_impulse();
    eprintln!(
        "M1670: I = {impulse:.1} N s, t_b = {} s, mean {:.1} N",
        curve.burn_time(),
        curve.average_thrust()
    );
    // M class: 5120.01-10240 N s. Rated total impulse about 6023 N s (the figure given for
    // the Pro75 M1670; the file itself carries no rating): within 0.5 %.
    assert!((5120.0..=10240.0).contains(&impulse));
    assert!((impulse - 6023.0).abs() < 0.005 * 6023.0, "{impulse}");
    // The file starts at t = 0 with zero thrust: no point is added.
    assert_eq!(curve.points().next(), Some((0.0, 0.0)));
    assert_eq!(curve.points().count(), 16);
    assert!((curve.thrust_at(0.0735) - 800.0).abs() < 1e-9);
}

#[test]
fn impulse_of_a_triangle_and_the_end_step() {
    // A last point with thrust ends in a step to zero.
    let c = ThrustCurve::from_points("tri", &[(1.0, 100.0), (2.0, 100.0)]).unwrap();
    // Ramp 0-1 s to 100 N (50 N s) then 100 N for 1 s (100 N s).
    assert!((c.total_impulse() - 150.0).abs() < 1e-12);
    assert_eq!(c.thrust_at(2.0), 100.0);
    assert_eq!(c.thrust_at(2.0 + 1e-12), 0.0);
    assert_eq!(c.burn_time(), 2.0);
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn eng_error(text: &str) -> ThrustCurveError {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "bad.eng", text);
    let e = ThrustCurve::read(&path).unwrap_err();
    assert!(e.to_string().contains("bad.eng"), "{e}");
    e
}

const HEADER: &str = "; test motor\nX100 29 100 0 0.1 0.2 XX\n";

#[test]
fn eng_errors_carry_file_and_line() {
    let e = eng_error(&format!("{HEADER}0.1 10\n0.1 20\n"));
    assert!(
        matches!(e, ThrustCurveError::TimeNotIncreasing { line: 4, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("bad.eng:4:"), "{e}");
    let e = eng_error(&format!("{HEADER}0.1 10\n0.05 20\n"));
    assert!(
        matches!(e, ThrustCurveError::TimeNotIncreasing { line: 4, .. }),
        "{e}"
    );
    let e = eng_error(&format!("{HEADER}0.1 -10\n"));
    assert!(
        matches!(e, ThrustCurveError::NegativeThrust { line: 3, .. }),
        "{e}"
    );
    let e = eng_error(&format!("{HEADER}0.1 10\n0.2 inf\n"));
    assert!(
        matches!(e, ThrustCurveError::NotFinite { line: 4, .. }),
        "{e}"
    );
    let e = eng_error(&format!("{HEADER}0.1 NaN\n"));
    assert!(
        matches!(e, ThrustCurveError::NotFinite { line: 3, .. }),
        "{e}"
    );
    let e = eng_error(&format!("{HEADER}0.1 10\n0.2\n"));
    assert!(
        matches!(
            e,
            ThrustCurveError::MissingField {
                line: 4,
                what: "thrust",
                ..
            }
        ),
        "{e}"
    );
    let e = eng_error(&format!("{HEADER}0.1 10 5\n"));
    assert!(
        matches!(e, ThrustCurveError::ExtraField { line: 3, .. }),
        "{e}"
    );
    let e = eng_error(HEADER);
    assert!(matches!(e, ThrustCurveError::EmptyCurve { .. }), "{e}");
    let e = eng_error("; only comments\n");
    assert!(matches!(e, ThrustCurveError::EmptyCurve { .. }), "{e}");
    let e = eng_error("X100 29 100 0 0.1\n0.1 10\n");
    assert!(
        matches!(e, ThrustCurveError::MissingField { line: 1, .. }),
        "{e}"
    );
    let e = eng_error("X100 29 100 0 0.3 0.2 XX\n0.1 10\n");
    assert!(
        matches!(e, ThrustCurveError::PropellantExceedsTotal { line: 1, .. }),
        "{e}"
    );
    let e = eng_error("X100 29 100 0 -0.1 0.2 XX\n0.1 10\n");
    assert!(
        matches!(e, ThrustCurveError::NonPositive { line: 1, .. }),
        "{e}"
    );
    let e = eng_error(&format!("{HEADER}-0.1 10\n"));
    assert!(
        matches!(e, ThrustCurveError::NegativeTime { line: 3, .. }),
        "{e}"
    );
    let e = ThrustCurve::read(Path::new("/nonexistent/m.eng")).unwrap_err();
    assert!(matches!(e, ThrustCurveError::Io { .. }));
}

#[test]
fn csv_curves_and_their_errors() {
    let dir = tempfile::tempdir().unwrap();
    let good = write(
        dir.path(),
        "hybrid.csv",
        "# static test\ntime_s,thrust_N\n0,0\n0.5,200\n1.5,200\n2,0\n",
    );
    let c = ThrustCurve::read(&good).unwrap();
    assert_eq!(c.name, "hybrid");
    assert_eq!(c.total_mass, None);
    assert!((c.total_impulse() - 300.0).abs() < 1e-12);
    assert!((c.thrust_at(0.25) - 100.0).abs() < 1e-12);

    type Case = (&'static str, fn(&ThrustCurveError) -> bool);
    let cases: [Case; 7] = [
        ("time_s,thrust_N\n0,0\n1,5\n1,6\n", |e| {
            matches!(e, ThrustCurveError::TimeNotIncreasing { line: 4, .. })
        }),
        ("time_s,thrust_N\n0,0\n1,-5\n", |e| {
            matches!(e, ThrustCurveError::NegativeThrust { line: 3, .. })
        }),
        ("time_s,thrust_N\n0,0\n1,abc\n", |e| {
            matches!(e, ThrustCurveError::NotFinite { line: 3, .. })
        }),
        ("time_s,thrust_N\n0,0\n1,\n", |e| {
            matches!(e, ThrustCurveError::MissingField { line: 3, .. })
        }),
        ("time_s,thrust_N\n0,0\n1\n", |e| {
            matches!(e, ThrustCurveError::MissingField { line: 3, .. })
        }),
        ("time_s,thrust_N\n", |e| {
            matches!(e, ThrustCurveError::EmptyCurve { .. })
        }),
        ("t,F\n0,0\n", |e| {
            matches!(e, ThrustCurveError::BadHeader { line: 1, .. })
        }),
    ];
    for (i, (text, check)) in cases.iter().enumerate() {
        let path = write(dir.path(), &format!("bad{i}.csv"), text);
        let e = ThrustCurve::read(&path).unwrap_err();
        assert!(check(&e), "case {i}: {e}");
        assert!(e.to_string().contains(&format!("bad{i}.csv")), "{e}");
    }
}
