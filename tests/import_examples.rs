//! More of OpenRocket's own bundled example designs (issue 34 item 6), imported, checked and
//! flown with the motor and conditions of each stored simulation whose status is up to date,
//! against the result the file stores (`tests/import_designs/`, provenance in its README;
//! the comparison and its explanations in docs/validation.md, "More of OpenRocket's
//! examples").
//!
//! Each flight's apogee is pinned to the figure measured when the test was written (to 1 mm,
//! so that any change to the import, the drag or the flight shows) and checked against the
//! issue's target, 5 % of OpenRocket's stored apogee. The motors not in the bundled
//! catalogue are OpenRocket's own database curves, the ones the designs name by digest
//! (`tests/import_designs/openrocket_motors/`). Examples the language cannot say are refused
//! by name, with the element's place, and nothing is written.

use std::path::{Path, PathBuf};
use std::process::Output;

mod import_support;
use import_support::{bin, design, flat, stderr};

fn cache() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("import-examples-cache")
}

/// `flexflight import DESIGN -o OUT --motor-dir openrocket_motors --material ...` (the
/// materials' stiffness: test inputs, the designs give only densities; it plays no part in
/// the apogee).
fn import(design_file: &str, out: &Path, materials: &[&str]) -> Output {
    let mut c = bin();
    c.arg("import")
        .arg(design(design_file))
        .arg("-o")
        .arg(out)
        .arg("--motor-dir")
        .arg(design("openrocket_motors"));
    for m in materials {
        c.arg("--material").arg(m);
    }
    c.output().unwrap()
}

fn import_and_check(design_file: &str, dir: &Path, materials: &[&str]) -> (PathBuf, String) {
    let out = dir.join("v.vdl");
    let o = import(design_file, &out, materials);
    assert!(o.status.success(), "import: {}", stderr(&o));
    let c = bin().arg("check").arg(&out).output().unwrap();
    assert!(c.status.success(), "check: {}", stderr(&c));
    (out, stderr(&o))
}

fn run(vdl: &Path, scenario: &str, sets: &[&str]) -> Output {
    let mut c = bin();
    c.arg("run")
        .arg(vdl)
        .args(["--scenario", scenario, "--no-flutter-margin", "--out"])
        .arg(vdl.with_file_name(format!("run_{scenario}")))
        .arg("--cache-dir")
        .arg(cache());
    for s in sets {
        c.arg("--set").arg(s);
    }
    c.output().unwrap()
}

/// The selected modes of the vehicle's compile (`--format json`): name, fin (1-based, 0 for
/// none) and frequency.
fn selected_modes(vdl: &Path) -> Vec<(String, u64, f64)> {
    let o = bin()
        .arg("compile")
        .arg(vdl)
        .args(["--format", "json", "--cache-dir"])
        .arg(cache())
        .output()
        .unwrap();
    assert!(o.status.success(), "compile: {}", stderr(&o));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    j["modes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| {
            (
                m["name"].as_str().unwrap().to_string(),
                m["fin"].as_u64().map_or(0, |f| f + 1),
                m["frequency_hz"].as_f64().unwrap(),
            )
        })
        .collect()
}

/// A flight's apogee, time to apogee and maximum speed (over the output rows).
struct Flown {
    apogee: f64,
    t_apogee: f64,
    v_max: f64,
}

fn fly(vdl: &Path, scenario: &str, sets: &[&str]) -> Flown {
    let r = run(vdl, scenario, sets);
    assert!(r.status.success(), "run {scenario}: {}", stderr(&r));
    let dir = vdl.with_file_name(format!("run_{scenario}"));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        s["stop_reason"], "ground",
        "{scenario}: {}",
        s["stop_reason"]
    );
    let history = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    let mut lines = history.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (vx, vy, vz) = (col("v_body_x"), col("v_body_y"), col("v_body_z"));
    let v_max = lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (v[vx] * v[vx] + v[vy] * v[vy] + v[vz] * v[vz]).sqrt()
        })
        .fold(0.0, f64::max);
    Flown {
        apogee: s["flight"]["apogee"]["altitude"].as_f64().unwrap(),
        t_apogee: s["flight"]["apogee"]["t"].as_f64().unwrap(),
        v_max,
    }
}

/// One stored simulation: its scenario, OpenRocket's stored apogee, maximum velocity and time
/// to apogee, and the apogee flexflight measured (release build, 7 December 2026).
struct Stored {
    scenario: &'static str,
    apogee: f64,
    v_max: f64,
    t_apogee: f64,
    measured: f64,
}

/// Flies `s` and holds it to its measured apogee (1 mm) and to 5 % of OpenRocket's.
fn compare(what: &str, vdl: &Path, s: &Stored, sets: &[&str]) {
    let f = fly(vdl, s.scenario, sets);
    let d = |a: f64, b: f64| 100.0 * (a / b - 1.0);
    eprintln!(
        "{what} {}: apogee {:.3} m ({:+.1} %), max speed {:.2} m/s ({:+.1} %), apogee at {:.3} s ({:+.1} %) against OpenRocket's {} m, {} m/s, {} s",
        s.scenario,
        f.apogee,
        d(f.apogee, s.apogee),
        f.v_max,
        d(f.v_max, s.v_max),
        f.t_apogee,
        d(f.t_apogee, s.t_apogee),
        s.apogee,
        s.v_max,
        s.t_apogee
    );
    assert!(
        (f.apogee - s.measured).abs() < 1e-3,
        "{what} {}: apogee {} m, measured {} m",
        s.scenario,
        f.apogee,
        s.measured
    );
    assert!(
        (f.apogee / s.apogee - 1.0).abs() < 0.05,
        "{what} {}: apogee {} m against OpenRocket's {} m",
        s.scenario,
        f.apogee,
        s.apogee
    );
}

/// OpenRocket's "3D printable nose cone and fins": an 18 mm Estes rocket with a PETG nose
/// and fin can on a paper tube, five stored simulations (Estes A8, B6 and three C6 delays).
/// The B6 is OpenRocket's own curve (not in the bundled catalogue); the A8 and C6 are the
/// bundled ones (OpenRocket's the same NAR data).
#[test]
fn the_3d_printable_rocket_flies_its_five_simulations_within_5_percent() {
    let dir = tempfile::tempdir().unwrap();
    let (vdl, warnings) = import_and_check(
        "printable_nose_cone_and_fins.ork",
        dir.path(),
        &[
            "Paper, spiral kraft glassine, Estes avg, bulk=3 GPa,0.3",
            "PETG - 100% infill=2 GPa,0.4",
        ],
    );
    let text = std::fs::read_to_string(&vdl).unwrap();
    // One finish per vehicle: the printed parts' `rough` (500 um) is taken for the paper
    // tube's `unfinished` (150 um) too; the C6 flights' shortfall (docs/validation.md).
    assert!(
        flat(&warnings).contains(
            "its surface finish `unfinished` (150 um) is taken as the vehicle's `rough` (500 um)"
        ),
        "{warnings}"
    );
    assert!(
        text.contains("finish = rough # 500 um; the design: rough on 4 of 5 components"),
        "{text}"
    );
    assert!(text.contains("curve = \"Estes_B6.eng\""), "{text}");
    assert_eq!(text.matches("\nscenario ").count(), 5, "{text}");
    for (s, sets) in [
        (
            Stored {
                scenario: "simulation_1",
                apogee: 38.733,
                v_max: 24.764,
                t_apogee: 3.085,
                measured: 38.7685,
            },
            &[][..],
        ),
        (
            Stored {
                scenario: "simulation_2",
                apogee: 112.011,
                v_max: 48.501,
                t_apogee: 4.912,
                measured: 110.2728,
            },
            &[][..],
        ),
        (
            Stored {
                scenario: "simulation_3_too_short_delay",
                apogee: 243.099,
                v_max: 83.142,
                t_apogee: 5.431,
                measured: 238.2156,
            },
            &[][..],
        ),
        (
            Stored {
                scenario: "simulation_4",
                apogee: 271.985,
                v_max: 83.16,
                t_apogee: 7.184,
                measured: 263.7792,
            },
            &[][..],
        ),
        (
            Stored {
                scenario: "simulation_5",
                apogee: 272.559,
                v_max: 83.143,
                t_apogee: 7.443,
                measured: 264.0656,
            },
            &[][..],
        ),
    ] {
        compare("3D printable", &vdl, &s, sets);
    }
}

/// OpenRocket's "Chute release": a 64 mm rocket with a drogue at apogee and a main at 152 m
/// (500 ft), two stored simulations, AeroTech G40W and G80T, both OpenRocket's own curves.
#[test]
fn chute_release_flies_its_two_simulations_within_5_percent() {
    let dir = tempfile::tempdir().unwrap();
    let (vdl, warnings) = import_and_check(
        "chute_release.ork",
        dir.path(),
        &[
            "Paper, spiral kraft glassine, Estes avg, bulk=3 GPa,0.3",
            "Plywood (birch)=8 GPa,0.3",
        ],
    );
    let text = std::fs::read_to_string(&vdl).unwrap();
    // The fins' tabs (3 x 119.6 x 17.7 mm of 4.76 mm birch plywood inside the body): no
    // structure, but their 19.0 g are the fin set's, as OpenRocket counts them (the importer
    // dropped them before: +2.5 % and +1.5 % of apogee).
    assert!(
        flat(&warnings).contains("the fin tab (inside the body) is not represented as structure; its mass (19.0 g) is kept"),
        "{warnings}"
    );
    assert!(
        text.contains("distributed_mass trapezoidal_fin_set_tabs {\n        from = -0.9059418 m\n        to = -1.025525 m\n        mass = 0.019029 kg\n"),
        "{text}"
    );
    // The default configuration's G80T is the vehicle's motor, the G40W simulation's a `with`.
    assert!(
        text.contains("  motor g80t {\n    curve = \"AeroTech_G80T.eng\""),
        "{text}"
    );
    assert!(
        text.contains("motor.curve = \"AeroTech_G40W.eng\""),
        "{text}"
    );
    // The importer's `fin_flap = per_fin` and `fin_twist = per_fin` are met by a mode of
    // each class on each fin, at one frequency (a symmetric set): the flap and twist roll
    // combinations, which twist the paper tube, complete their clusters
    // (`selection::complete_fin_cluster`). On the old classifier the flap selection was
    // unmet and, flown with `fin_flap = 3`, the twist roll combination (516.9 Hz, 26 %
    // below its pair) was no member of a cluster: each fin took the first twist mode it
    // dominated (516.9, 695.7 and 1648.7 Hz).
    let modes = selected_modes(&vdl);
    for (class, hz) in [("flap", 356.504), ("twist", 641.660)] {
        let of: Vec<&(String, u64, f64)> = modes
            .iter()
            .filter(|m| m.0.ends_with(&format!("_{class}")))
            .collect();
        assert_eq!(of.len(), 3, "{modes:?}");
        for (k, m) in of.iter().enumerate() {
            assert_eq!(m.0, format!("fin{}_{class}", k + 1), "{modes:?}");
            assert_eq!(m.1, k as u64 + 1, "{modes:?}");
            assert!((m.2 - hz).abs() < 1e-3, "{class}: {modes:?}");
        }
    }
    compare(
        "Chute release",
        &vdl,
        &Stored {
            scenario: "simulation_2",
            apogee: 307.726,
            v_max: 72.071,
            t_apogee: 8.424,
            measured: 306.7810,
        },
        &[],
    );
    let s3 = Stored {
        scenario: "simulation_3",
        apogee: 487.936,
        v_max: 106.285,
        t_apogee: 9.962,
        measured: 485.7448,
    };
    compare("Chute release", &vdl, &s3, &[]);
    // The mode selection plays no part in the apogee: two flap modes instead of one localised
    // on each fin give the same apogee to 1 mm.
    compare("Chute release", &vdl, &s3, &["modes.fin_flap=2"]);
}

/// OpenRocket's "Simulation extensions" (Sampo Niskanen's HyperLOC 1600-based design): a
/// 140 mm cardboard rocket on a HyperTEK L540 hybrid (OpenRocket's own curve), canards and
/// three canted one-fin sets (merged into one set of three). Its first simulation, "No
/// controlling", has no extension and is compared; the other two fly OpenRocket's
/// roll-control and air-start extensions, which the import now says it does not carry, and
/// are not compared.
///
/// The design overrides its three body tubes' masses below what their material and wall
/// give (366, 670 and 1268 g against 739, 885 and 1558 g). A negative mass cannot be added:
/// the importer used to leave the vehicle 878 g (7.3 %) heavier than OpenRocket's, its
/// apogee 3.8 % lower (2369.01 m); the generated body's density is now lowered to keep the
/// lightest tube's override and the other parts' masses are restored (docs/validation.md).
#[test]
fn simulation_extensions_flies_its_plain_simulation_within_5_percent() {
    let dir = tempfile::tempdir().unwrap();
    let (vdl, warnings) = import_and_check(
        "simulation_extensions.ork",
        dir.path(),
        &["Cardboard=3 GPa,0.3"],
    );
    let w = flat(&warnings);
    // The tubes' overrides are kept: the generated body's density is lowered to the lightest
    // tube's ratio, 366 g against the 738.914 g its wall gives (the import used to warn
    // that the generated structure was heavier there, by 878 g in all).
    assert_eq!(
        w.matches("the generated structure is").count(),
        0,
        "{warnings}"
    );
    for needle in [
        "simulation `Active roll control`: its extension `RollControl` (info.openrocket.core.simulation.extension.example.RollControl) is not imported",
        "simulation `Roll control + air-start`: its extension `AirStart`",
    ] {
        assert!(w.contains(needle), "{needle}: {warnings}");
    }
    assert_eq!(
        w.matches("is not imported: the scenario flies without it")
            .count(),
        3
    );
    let text = std::fs::read_to_string(&vdl).unwrap();
    assert!(
        text.contains(
            "# the generated body's density is 341.7717 kg/m^3, 0.495321 of the design's 690 kg/m^3"
        ),
        "{text}"
    );
    assert!(
        text.contains(
            "# Approximation: simulation `Roll control + air-start`: its extension `RollControl`"
        ),
        "{text}"
    );
    assert!(
        text.contains("curve = \"Hypertek_2800CC172L-L540.eng\""),
        "{text}"
    );
    compare(
        "Simulation extensions",
        &vdl,
        &Stored {
            scenario: "no_controlling",
            apogee: 2462.535,
            v_max: 240.707,
            t_apogee: 22.461,
            measured: 2453.2584,
        },
        &[],
    );
}

/// The examples the language cannot say yet: each import fails with its diagnostic at the
/// element, and writes nothing.
#[test]
fn examples_that_cannot_be_said_are_refused_by_name() {
    for (file, code, needles) in [
        (
            "dual_parachute_deployment.ork",
            "import::override",
            &[
                "`Sustainer` overrides the mass of the whole stage: an assembly mass cannot be spread over the generated structure",
            ][..],
        ),
        (
            "clustered_motors.ork",
            "import::unsupported",
            &[
                "innertube `Clustered Inner Tube` (in `Body tube`): a motor cluster (`4-ring`) cannot be represented: one motor on the axis can",
            ][..],
        ),
        (
            "airstart_timing.ork",
            "import::unsupported",
            &[
                "innertube `38mm airstart` (in `Body tube`): a motor cluster (`3-ring`) cannot be represented",
            ][..],
        ),
        (
            "base_drag_hack.ork",
            "import::unsupported",
            &[
                "freeformfinset `Freeform Fiin Set (4)` (in `Body Tube`): this freeform fin cannot be represented: it is not single-valued in chord per span station",
                "its drag override is not representable",
            ][..],
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("v.vdl");
        let o = import(file, &out, &[]);
        assert_eq!(o.status.code(), Some(1), "{file}: {}", stderr(&o));
        let e = flat(&stderr(&o));
        assert!(e.contains(code), "{file}: {e}");
        assert!(e.contains(&format!("{file}:")), "{file}: no place: {e}");
        for n in needles {
            assert!(e.contains(n), "{file}: {n}: {e}");
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "{file}");
    }
}
