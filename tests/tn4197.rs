//! Issue 38, item 1: the third published form of NACA TN 4197, J. K. Bennett's revised method
//! (Peak of Flight 615/617: Martin's planform term `eps` from the fin's centroid), checked by
//! hand on SPHADS-1's fin and printed beside Martin's and the Peak of Flight 291 form by
//! `analyze planar`, `analyze map` and `analyze flutter`.

use std::path::{Path, PathBuf};
use std::process::Command;

use flexflight::aero::atmosphere::{Atmosphere, Standard1976};
use flexflight::analysis::tn4197::{Tn4197Fin, Tn4197Form};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn cache() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("tn4197-test-cache")
}

/// SPHADS-1's fin (vehicles/sphads1.vdl): span 127.23 mm, chords 324.68 / 122.67 mm, unswept
/// trailing edge, aluminium_thesis (E 70 GPa, nu 0.346).
fn sphads1_fin(thickness: f64) -> Tn4197Fin {
    Tn4197Fin {
        shear_modulus: 70e9 / (2.0 * 1.346),
        span: 0.127_23,
        root_chord: 0.324_68,
        tip_chord: 0.122_67,
        thickness,
        tip_le_offset: 0.324_68 - 0.122_67,
    }
}

/// By hand, SPHADS-1's fin at 200 m/s, 5 km.
///
/// Planform: the tip's leading edge lies `m = c_r - c_t = 0.20201 m` aft of the root's (the
/// trailing edge is unswept), i.e. a leading edge swept `atan(0.20201 / 0.12723) = 57.80 deg`.
/// Centroid `x_c = (c_r^2 + c_r c_t + c_t^2 + m (c_r + 2 c_t)) / (3 (c_r + c_t))`
/// `= (0.1054171 + 0.0398285 + 0.0150479 + 0.20201 x 0.57002) / (3 x 0.44735)`
/// `= (0.1602935 + 0.1151497) / 1.34205 = 0.2754433 / 1.34205 = 0.2052407 m`;
/// `x_c / c_r = 0.632132`, `eps = 0.382132` (Martin fixes 0.25).
///
/// Coefficients `k` of `X = k A^3 p (lambda + 1) / (2 (A + 2) (t/c_r)^3)`: Martin
/// `39.3 / 14.7 = 2.673469`; PoF 291 `1.337`; Bennett `24 x 0.382132 x 1.4 / pi
/// = 12.83964 / 3.141593 = 4.086985`. Bennett's speed over Martin's:
/// `sqrt(2.673469 / 4.086985) = sqrt(0.654141) = 0.808790`, 19.1 % lower.
///
/// Air, US Standard Atmosphere 1976 at 5 km geometric (geopotential 4996.07 m'):
/// `T = 288.15 - 6.5 x 4.99607 = 255.6755 K`, `a = sqrt(1.4 x 287.0531 x 255.6755)
/// = 320.546 m/s`, `p = 54048.3 Pa` (NOAA-S/T 76-1562, Table I: 54048 Pa).
///
/// Critical thickness (`V_f = 200 m/s`): `(t/c_r)^3 = k A^3 p (lambda + 1) (V/a)^2 /
/// (2 (A + 2) G)` with `S = 0.5 x 0.44735 x 0.12723 = 0.02845817 m^2`, `A = 0.0161875 /
/// 0.02845817 = 0.568816`, `A^3 = 0.184042`, `lambda = 0.377818`, `G = 70e9 / 2.692
/// = 26.00297 GPa`, `(V/a)^2 = (0.623938)^2 = 0.389299`:
/// `A^3 p (lambda + 1) (V/a)^2 = 0.184042 x 54048.3 x 1.377818 x 0.389299 = 5335.51 Pa`,
/// `2 (A + 2) G = 2 x 2.568816 x 26.00297e9 = 1.335945e11 Pa`, ratio `3.99381e-8`.
/// Martin: `x 2.673469 = 1.06773e-7`, cube root `4.74410e-3`, `t = 1.5403 mm`.
/// PoF 291: `x 1.337 = 5.33972e-8`, `3.76564e-3`, `t = 1.2226 mm`.
/// Bennett: `x 4.086985 = 1.63227e-7`, `5.46507e-3`, `t = 1.7744 mm`.
#[test]
fn bennett_form_on_sphads1_by_hand() {
    let f = sphads1_fin(1e-3);
    assert!((f.tip_le_offset / f.span).atan().to_degrees() - 57.80 < 0.005);
    assert!(
        (f.centroid_x() - 0.205_240_7).abs() < 2e-7,
        "{}",
        f.centroid_x()
    );
    assert!((f.epsilon() - 0.382_132).abs() < 1e-6, "{}", f.epsilon());
    assert!((f.coefficient_in(Tn4197Form::PeakOfFlight615) - 4.086_985).abs() < 2e-6);
    let air = Standard1976::new().at(5_000.0).unwrap();
    assert!((air.pressure - 54_048.3).abs() < 0.05, "{}", air.pressure);
    assert!(
        (air.speed_of_sound - 320.546).abs() < 1e-3,
        "{}",
        air.speed_of_sound
    );
    let ratio = f.flutter_speed_in(
        Tn4197Form::PeakOfFlight615,
        air.pressure,
        air.speed_of_sound,
    ) / f.flutter_speed_in(Tn4197Form::Martin, air.pressure, air.speed_of_sound);
    assert!((ratio - 0.808_790).abs() < 1e-6, "{ratio}");
    let t = |form| f.critical_thickness_in(form, air.pressure, air.speed_of_sound, 200.0) * 1e3;
    let (tm, tp, tb) = (
        t(Tn4197Form::Martin),
        t(Tn4197Form::PeakOfFlight291),
        t(Tn4197Form::PeakOfFlight615),
    );
    eprintln!("SPHADS-1 at 200 m/s, 5 km: t_crit Martin {tm} mm, PoF 291 {tp} mm, PoF 615 {tb} mm");
    assert!((tm - 1.5403).abs() < 1e-4, "{tm}");
    assert!((tp - 1.2226).abs() < 1e-4, "{tp}");
    assert!((tb - 1.7744).abs() < 1e-4, "{tb}");
    // And that thickness flutters at 200 m/s in Bennett's form.
    let at = sphads1_fin(tb * 1e-3);
    let v = at.flutter_speed_in(
        Tn4197Form::PeakOfFlight615,
        air.pressure,
        air.speed_of_sound,
    );
    assert!((v - 200.0).abs() < 1e-9, "{v}");
}

/// `analyze planar` reports the three forms (JSON and text), with `eps`, and states that the
/// thickness ratio is taken on the root chord.
#[test]
fn analyze_planar_prints_the_three_forms() {
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
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stdout).unwrap()
    };
    let j: serde_json::Value = serde_json::from_str(&run("json")).unwrap();
    let tn = &j["tn4197"];
    let p = tn["pressure_pa"].as_f64().unwrap();
    let f = sphads1_fin(0.6e-3);
    assert!((tn["epsilon"].as_f64().unwrap() - f.epsilon()).abs() < 1e-9);
    assert_eq!(tn["thickness_ratio_chord"], "root");
    let want = f.flutter_mach_in(Tn4197Form::PeakOfFlight615, p);
    let got = tn["peak_of_flight_615"]["flutter_mach"].as_f64().unwrap();
    assert!((got - want).abs() < 1e-9 * want, "{got} vs {want}");
    let m = tn["martin"]["flutter_mach"].as_f64().unwrap();
    assert!((got / m - 0.808_790).abs() < 1e-5, "{}", got / m);
    let text = run("human");
    let line = text
        .lines()
        .find(|l| l.contains("Peak of Flight 615 (Bennett)"))
        .unwrap_or_else(|| panic!("no Bennett line in\n{text}"));
    assert!(line.contains(&format!("flutter Mach {want:.5}")), "{line}");
    assert!(text.contains("(root chord), eps 0.38213"), "{text}");
}

/// `analyze map` writes Bennett's boundary next to Martin's: `map.csv` column, the
/// `tn4197_pof615` columns of `boundary.csv` and `critical_thickness.csv`, and its overlay.
/// At a fixed altitude the critical thickness of a form scales with `k^(1/3)`, so Bennett's
/// over Martin's is `(4.086985 / 2.673469)^(1/3) = 1.15195` at every Mach (to the linear
/// interpolation of the grid between thicknesses).
#[test]
fn analyze_map_writes_the_bennett_boundary() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("map");
    let o = bin()
        .args(["analyze", "map", "--planar", "--pinned"])
        .arg(repo("examples/thesis/section_6_5.vdl"))
        .args([
            "--scenario",
            "subsonic_t06",
            "--thickness",
            "0.5mm:3mm:251",
            "--mach",
            "0.4:0.8:3",
            "--altitude",
            "5km",
            "--cache-dir",
        ])
        .arg(cache())
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let map = std::fs::read_to_string(out.join("map.csv")).unwrap();
    assert!(
        map.lines()
            .next()
            .unwrap()
            .ends_with(",tn4197_pof615_flutter_mach")
    );
    let ct = std::fs::read_to_string(out.join("critical_thickness.csv")).unwrap();
    let mut lines = ct.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let mut n = 0;
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        assert_eq!(f[col("tn4197_status")], "crossing", "{l}");
        assert_eq!(f[col("tn4197_pof615_status")], "crossing", "{l}");
        let tm: f64 = f[col("tn4197_critical_thickness_m")].parse().unwrap();
        let tb: f64 = f[col("tn4197_pof615_critical_thickness_m")]
            .parse()
            .unwrap();
        assert!((tb / tm - 1.151_95).abs() < 2e-3, "{l}: {}", tb / tm);
        n += 1;
    }
    assert_eq!(n, 3);
    let overlay = std::fs::read_to_string(out.join("overlay_TN_4197_PoF_615.csv")).unwrap();
    assert!(overlay.lines().count() > 10, "{overlay}");
}

/// `analyze flutter --clamped` prints and writes the three forms.
#[test]
fn analyze_flutter_prints_the_three_forms() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fl");
    let o = bin()
        .args(["analyze", "flutter"])
        .arg(repo("examples/thesis/section_6_5.vdl"))
        .args(["--scenario", "subsonic_t06", "--clamped", "--modes", "2"])
        .args(["--speeds", "100m/s:400m/s:8", "--cache-dir"])
        .arg(cache())
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains(
            "NACA TN 4197 (TN 4197 as revised in Peak of Flight 615 (Bennett)): flutter speed"
        ),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = std::fs::read_to_string(out.join("flutter.json")).unwrap();
    let j: serde_json::Value = serde_json::from_str(&text).unwrap();
    let tn = &j["tn4197"];
    assert_eq!(tn["thickness_ratio_chord"], "root");
    assert!((tn["epsilon"].as_f64().unwrap() - 0.382_132).abs() < 1e-6);
    let r = tn["peak_of_flight_615"]["flutter_speed_m_s"]
        .as_f64()
        .unwrap()
        / tn["martin"]["flutter_speed_m_s"].as_f64().unwrap();
    assert!((r - 0.808_790).abs() < 1e-5, "{r}");
}
