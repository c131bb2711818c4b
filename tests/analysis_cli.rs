//! Issue 9, defects 4, 6 and 7: the NACA TN 4197 baseline in Martin's original form, the
//! 3-D stability verdict of a climbing flight (flight-path roots apart from the vehicle's),
//! and map ranges that carry units on the command line.

use std::path::{Path, PathBuf};
use std::process::Command;

use flexflight::analysis::linear::analyse;
use flexflight::analysis::linear_grid::StabilityClass;
use flexflight::analysis::linearise::LineariseOptions;
use flexflight::analysis::tn4197::Tn4197Fin;
use flexflight::ops::linear::load_variant;

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn cache() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("analysis-cli-test-cache")
}

fn stderr_of(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

// ---------------------------------------------------------------------------------------
// Defect 4: TN 4197.

/// Martin's form by hand (see `src/analysis/tn4197.rs` for the arithmetic): b = 0.1 m,
/// c_r = 0.2 m, c_t = 0.1 m, t = 2 mm, G = 26 GPa, p = 50 kPa: flutter Mach 1.527758. The
/// Peak of Flight 291 form gives 2.160362, sqrt(2) higher.
#[test]
fn tn4197_flutter_mach_is_martins_original_form() {
    let f = Tn4197Fin {
        shear_modulus: 26e9,
        span: 0.1,
        root_chord: 0.2,
        tip_chord: 0.1,
        thickness: 0.002,
        tip_le_offset: 0.1,
    };
    let m = f.flutter_mach(50_000.0);
    assert!((m - 1.527_758).abs() < 5e-7, "{m}: not Martin's TN 4197");
}

// ---------------------------------------------------------------------------------------
// Defect 6: a climbing flight.

/// SPHADS-1 at 200 m/s, 5 km, pitched up 60 deg (a climbing gravity turn), no stimuli.
const CLIMB: &str = r#"
import "VEHICLE"

scenario climb {
  vehicle = sphads1
  with {
    fins.thickness = 1.0 mm
  }
  initial {
    velocity = (200, 0, 0) m/s
    angular_velocity = (0, 0, 0) rad/s
    attitude = euler(0 deg, 60 deg, 0 deg)
    altitude = 5 km
  }
  run {
    stop_time = 1 s
    integrator = dopri5
    rtol = 1e-6
    atol = 1e-9
    output_interval = 1 ms
    stop_on_ground = true
  }
}

sweep climb_linear {
  scenario = climb
  analysis = linear3d
  grid {
    fins.thickness = [0.9 mm, 1.0 mm]
  }
}

sweep climb_linear_frozen {
  scenario = climb
  analysis = linear3d
  frozen_gravity = true
  grid {
    fins.thickness = [1.0 mm]
  }
}
"#;

fn climb_file(dir: &Path) -> PathBuf {
    let p = dir.join("climb.vdl");
    let text = CLIMB.replace(
        "VEHICLE",
        &repo("vehicles/sphads1.vdl").display().to_string(),
    );
    std::fs::write(&p, text).unwrap();
    p
}

/// With 1.0 mm fins SPHADS-1 is stable in level flight at 200 m/s, 5 km (the thesis' and
/// our 3-D boundary lies below 0.8 mm); pitched up 60 deg, the frozen reference adds the
/// gravity-turn root `g sin(gamma) / V = 9.79 x 0.866 / 200 = 0.042 1/s` of the trajectory,
/// which must not make the vehicle "divergent".
#[test]
fn a_climbing_flight_with_stiff_fins_is_not_divergent() {
    let dir = tempfile::tempdir().unwrap();
    let file = climb_file(dir.path());
    let v = load_variant(&file, "climb", &[], Some(&cache()), &mut |_| {}).unwrap();
    let r = analyse(&v, LineariseOptions::default()).unwrap();
    let slow: Vec<(f64, f64)> = r
        .eigen
        .roots
        .iter()
        .filter(|x| x.real.hypot(x.imag) < 1.0)
        .map(|x| (x.real, x.imag))
        .collect();
    eprintln!(
        "climb 60 deg, 1.0 mm: class {:?}, sigma_d {}, slow roots {slow:?}",
        r.eigen.class, r.eigen.sigma_d
    );
    assert_ne!(r.eigen.class, StabilityClass::Divergence);
    assert_eq!(r.eigen.class, StabilityClass::Stable);
}

/// The `linear3d` sweep over stiff thicknesses of the climb: no case divergent; with
/// `frozen_gravity = true` the same.
#[test]
fn a_linear3d_sweep_of_a_climb_is_not_divergent_at_stiff_thickness() {
    let dir = tempfile::tempdir().unwrap();
    let file = climb_file(dir.path());
    for sweep in ["climb_linear", "climb_linear_frozen"] {
        let out = dir.path().join(sweep);
        let o = bin()
            .arg("sweep")
            .arg(&file)
            .args(["--sweep", sweep, "--jobs", "1", "--out"])
            .arg(&out)
            .arg("--cache-dir")
            .arg(cache())
            .output()
            .unwrap();
        assert!(o.status.success(), "{sweep}: {}", stderr_of(&o));
        let table = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
        let mut lines = table.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let col = header.iter().position(|h| *h == "stability_class").unwrap();
        for l in lines {
            let class = l.split(',').nth(col).unwrap();
            assert_eq!(class, "stable", "{sweep}: {l}");
        }
    }
}

/// `analyze linear-map` of the climb at 1.0 mm: the cell is stable, not "1 unstable".
#[test]
fn a_linear_map_of_a_climb_is_not_divergent_at_stiff_thickness() {
    let dir = tempfile::tempdir().unwrap();
    let file = climb_file(dir.path());
    let out = dir.path().join("map");
    let o = bin()
        .args(["analyze", "linear-map"])
        .arg(&file)
        .args(["--scenario", "climb", "--thickness", "1.0mm:1.0mm:1"])
        .args(["--mach", "0.624:0.624:1", "--out"])
        .arg(&out)
        .arg("--cache-dir")
        .arg(cache())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr_of(&o));
    let text = std::fs::read_to_string(out.join("map.csv")).unwrap();
    let row: Vec<&str> = text.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(row[4], "stable", "{text}");
    assert!(stderr_of(&o).contains("(0 unstable"), "{}", stderr_of(&o));
}

// ---------------------------------------------------------------------------------------
// Defect 7: ranges with units.

/// A bare number where a length is needed is a diagnostic (exit 2, the code of a wrong
/// command line), pointing at the flag's text; nothing is written.
#[test]
fn a_bare_thickness_is_refused_by_both_maps() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        vec!["analyze", "map", "--planar", "--pinned"],
        vec!["analyze", "linear-map"],
    ] {
        let out = dir.path().join("never");
        let o = bin()
            .args(&args)
            .arg(repo("examples/thesis/section_6_5.vdl"))
            .args(["--scenario", "subsonic_t06", "--thickness", "0.4:0.4:1"])
            .args(["--mach", "0.6:0.6:1", "--out"])
            .arg(&out)
            .arg("--cache-dir")
            .arg(cache())
            .output()
            .unwrap();
        let err = stderr_of(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains("vdl::unit::missing"), "{args:?}: {err}");
        assert!(err.contains("<--thickness>"), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
}

/// `frozen_gravity` belongs to `analysis = linear3d`: with another analysis it is a
/// diagnostic at `check`, pointing at the field.
#[test]
fn frozen_gravity_with_another_analysis_is_refused_at_check() {
    let dir = tempfile::tempdir().unwrap();
    let file = climb_file(dir.path());
    let text = std::fs::read_to_string(&file).unwrap().replace(
        "analysis = linear3d\n  frozen_gravity = true",
        "analysis = planar_pinned\n  frozen_gravity = true",
    );
    std::fs::write(&file, text).unwrap();
    let o = bin().arg("check").arg(&file).output().unwrap();
    let err = stderr_of(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("vdl::sweep::option"), "{err}");
    assert!(err.contains("climb.vdl:36:20"), "{err}");
}
