//! A lifting surface clamped at its root as a model in the language (issue 13, deliverable
//! 3): the `fixture` of `examples/agard445/agard445.vdl` is the library's AGARD 445.6 wing,
//! `analyze flutter` of its wind-tunnel scenario reproduces the published flutter point, and
//! the checker refuses what the fixture cannot mean.

mod common;

// The published cases the p-k solver is validated on, built in code (test fixtures, not
// library code: issue 36): Goland's uniform cantilever (strip theory), Hodges & Pierce's
// typical section and the AGARD 445.6 weakened wing this file compares the language's
// fixture with.
// Public items of the library version that this file does not call stay as they were.
#[allow(dead_code, unused_imports)]
#[path = "validation/agard445.rs"]
mod agard445;
#[path = "validation/goland.rs"]
mod goland;
#[path = "validation/typical_section.rs"]
mod typical_section;

use std::path::PathBuf;
use std::process::Command;

use agard445::{FLUTTER_TESTS, ModelSpec, wing_mass};
use flexflight::analysis::flutter::wing::{WingDensity, WingMaterial, WingThickness};
use flexflight::check::{DiskLoader, MemoryLoader, check_files, check_source, ir};
use flexflight::ops::tunnel::wing_spec;

fn example() -> PathBuf {
    common::root().join("examples/agard445/agard445.vdl")
}

fn tunnel(name: &str) -> ir::TunnelTest {
    let checked = check_files(&[example()], &[], &DiskLoader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    checked.program.tunnel_test(name).unwrap().clone()
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

/// The fixture written in the language is the library's model: the same planform (feet
/// converted, the leading-edge sweep derived from the quarter-chord sweep to 2e-16), the same
/// section, lamina, grain and mesh, and the wing mass of the report's table rounded as
/// written (1.866 kg against the table's mean).
#[test]
fn the_fixture_is_the_library_wing() {
    let t = tunnel("m0499");
    let ours = wing_spec(&t.fixture);
    let lib = agard445::wing_spec(&ModelSpec::default());
    assert_eq!(ours.span, lib.span);
    assert_eq!(ours.root_chord, lib.root_chord);
    assert_eq!(ours.tip_chord, lib.tip_chord);
    assert!(
        close(ours.leading_edge_sweep, lib.leading_edge_sweep, 4e-16),
        "{} vs {}",
        ours.leading_edge_sweep,
        lib.leading_edge_sweep
    );
    assert_eq!(ours.thickness, lib.thickness);
    assert!(matches!(ours.thickness, WingThickness::Section(ref h) if h.len() == 11));
    assert_eq!(ours.material, lib.material);
    assert!(matches!(ours.material, WingMaterial::Orthotropic { .. }));
    assert_eq!(
        (ours.chord_elements, ours.span_elements),
        (lib.chord_elements, lib.span_elements)
    );
    let (WingDensity::Mass(m), WingDensity::Mass(m_lib)) = (ours.density, lib.density) else {
        panic!("{:?} {:?}", ours.density, lib.density);
    };
    assert_eq!(m, 1.866);
    assert_eq!(m_lib, wing_mass());
    assert!(close(m, m_lib, 1.3e-5), "{m} vs {m_lib}");
    // The tunnel: Yates' density in slug/ft^3, converted exactly.
    let test = &FLUTTER_TESTS[0];
    assert_eq!(t.mach.value, test.mach);
    assert!(close(t.density.value, test.density, 1e-12));
    assert_eq!(t.speeds.value.len(), 69);
    assert_eq!(t.speeds.value[0], 60.0);
    assert_eq!(
        t.fixture.reference_frequency.unwrap().value,
        agard445::OMEGA_ALPHA
    );
}

/// `analyze flutter` of the M 0.499 wind-tunnel scenario with the default aerodynamics, the
/// doublet lattice since issue 33: first torsion and first bending coalesce at a flutter
/// speed index 1.6 % above Yates' 0.4459 (0.4529) and a frequency ratio 9.3 % above his
/// 0.5353 (0.5851); tolerances near those (2 % and 10 %). Fails on the old code, whose
/// default (the vortex lattice, +14.9 % in frequency ratio) is outside the 10 %. Outputs
/// all or nothing in `--out`.
#[test]
fn analyze_flutter_of_the_tunnel_scenario_gives_the_published_point() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m0499");
    let o = Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .args(["analyze", "flutter"])
        .arg(example())
        .args(["--scenario", "m0499", "--format", "json", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["case"], "fixture");
    assert_eq!(j["aero"], "doublet_lattice");
    assert_eq!(j["aero_method"], "doublet lattice");
    assert_eq!(j["panels"], serde_json::json!([13, 12]));
    let f = &j["flutter"][0];
    let test = &FLUTTER_TESTS[0];
    let fsi = f["speed_index"].as_f64().unwrap();
    let ratio = f["frequency_ratio"].as_f64().unwrap();
    println!("FSI {fsi:.4} vs {}, ratio {ratio:.4}", test.speed_index);
    assert!(close(fsi, test.speed_index, 0.02), "{fsi}");
    assert!(close(ratio, test.frequency_ratio(), 0.10), "{ratio}");
    let pair = [f["mode"].as_str().unwrap(), f["partner"].as_str().unwrap()];
    assert!(
        pair.iter().any(|m| m.contains("torsion")) && pair.iter().any(|m| m.contains("bending")),
        "{f}"
    );
    // Yates' mass ratio from the fixture's mass and the tunnel's density.
    let mu = j["mass_ratio"].as_f64().unwrap();
    assert!(
        close(mu, test.mass_ratio, 1e-4),
        "{mu} vs {}",
        test.mass_ratio
    );
    let vg = std::fs::read_to_string(out.join("vg.csv")).unwrap();
    assert_eq!(vg.lines().count(), 1 + 4 * 69);
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("flutter.json")).unwrap()).unwrap();
    assert_eq!(saved, j);
}

/// A wind-tunnel scenario is not flown, and the flags that set the air of a flight do not
/// apply to it: both refused before any work, with the way to do it.
#[test]
fn tunnel_scenarios_refuse_flight_commands_and_flags() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let o = Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .arg("run")
        .arg(example())
        .args(["--scenario", "m0499", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("wind tunnel") && err.contains("analyze flutter"),
        "{err}"
    );
    assert!(!out.exists());
    let o = Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .args(["analyze", "flutter"])
        .arg(example())
        .args(["--scenario", "m0499", "--altitude", "5 km", "--match-point"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--altitude, --match-point"), "{err}");
}

const FIXTURE: &str = r#"import "std/materials.vdl"
material ply { E = 10 GPa; E2 = 1 GPa; G12 = 0.7 GPa; nu = 0.3; rho = 600 kg/m^3 }
fixture wing {
  material = MAT
  surface { span = 0.5 m; root_chord = 0.3 m; tip_chord = 0.2 m; SWEEP; THICKNESS; GRAIN }
}
scenario t { fixture = wing; tunnel { mach = 0.3; density = 1.2 kg/m^3; speeds = range(10 m/s, 100 m/s, count = 10) } }
"#;

fn check_fixture(material: &str, sweep: &str, thickness: &str, grain: &str) -> Vec<String> {
    let src = FIXTURE
        .replace("MAT", material)
        .replace("SWEEP", sweep)
        .replace("THICKNESS", thickness)
        .replace("GRAIN", grain);
    let checked = check_source("case.vdl", &src, &MemoryLoader::default());
    checked
        .diagnostics
        .iter()
        .map(|d| d.code.to_string())
        .collect()
}

/// Every field of the surface is checked: a complete one passes; each defect gives its own
/// code (a missing sweep, two sweeps, two thicknesses, a grain on an isotropic material, a
/// one-station section).
#[test]
fn the_checker_refuses_what_a_fixture_cannot_mean() {
    let ok = check_fixture(
        "ply",
        "leading_edge_sweep = 30 deg",
        "thickness = 2 mm",
        "grain = swept(30 deg)",
    );
    assert!(ok.is_empty(), "{ok:?}");
    let ok = check_fixture(
        "aluminium_6061_t6",
        "trailing_edge_sweep = 0 deg",
        "half_thickness = [0, 0.02, 0]",
        "mass = 0.5 kg",
    );
    assert!(ok.is_empty(), "{ok:?}");
    for (case, codes) in [
        (
            check_fixture(
                "ply",
                "mass = 1 kg",
                "thickness = 2 mm",
                "grain = grid_lines",
            ),
            "vdl::field::missing",
        ),
        (
            check_fixture(
                "ply",
                "leading_edge_sweep = 30 deg; quarter_chord_sweep = 20 deg",
                "thickness = 2 mm",
                "grain = grid_lines",
            ),
            "vdl::fins::sweep",
        ),
        (
            check_fixture(
                "ply",
                "leading_edge_sweep = 30 deg",
                "thickness = 2 mm; half_thickness = [0, 0.02, 0]",
                "grain = grid_lines",
            ),
            "vdl::fixture::thickness",
        ),
        (
            check_fixture(
                "aluminium_6061_t6",
                "leading_edge_sweep = 30 deg",
                "thickness = 2 mm",
                "grain = grid_lines",
            ),
            "vdl::material::orthotropic",
        ),
        (
            check_fixture(
                "ply",
                "leading_edge_sweep = 30 deg",
                "half_thickness = [0.02]",
                "grain = grid_lines",
            ),
            "vdl::fixture::thickness",
        ),
    ] {
        assert!(
            case.iter().any(|c| c == codes),
            "expected {codes}: {case:?}"
        );
    }
}

/// The tunnel block: speeds must increase, and a flown scenario's vehicle cannot be a
/// fixture's surface (a vehicle name in `fixture =` is named as a vehicle).
#[test]
fn the_tunnel_block_is_checked() {
    let bad = FIXTURE
        .replace("MAT", "ply")
        .replace("SWEEP", "leading_edge_sweep = 0 deg")
        .replace("THICKNESS", "thickness = 2 mm")
        .replace("GRAIN", "grain = grid_lines")
        .replace("range(10 m/s, 100 m/s, count = 10)", "[50 m/s, 40 m/s]");
    let checked = check_source("case.vdl", &bad, &MemoryLoader::default());
    let codes: Vec<&str> = checked.diagnostics.iter().map(|d| d.code).collect();
    assert!(codes.contains(&"vdl::fixture::speeds"), "{codes:?}");
}

/// An orthotropic material is refused where a vehicle would use it (the generated body and
/// fins are isotropic shells and beams), at the line that uses it.
#[test]
fn a_vehicle_refuses_an_orthotropic_material() {
    let file = common::root().join("vehicles/sphads1.vdl");
    let text = std::fs::read_to_string(&file).unwrap();
    let patched = text.replace(
        "import \"std/materials.vdl\"",
        "import \"std/materials.vdl\"\nmaterial ply { E = 10 GPa; E2 = 1 GPa; G12 = 0.7 GPa; nu = 0.3; rho = 600 kg/m^3 }",
    );
    let patched = patched.replacen("material = aluminium_thesis", "material = ply", 1);
    let checked = check_source("sphads1.vdl", &patched, &MemoryLoader::default());
    let d = checked
        .diagnostics
        .iter()
        .find(|d| d.code == "vdl::material::orthotropic")
        .unwrap_or_else(|| panic!("{:?}", checked.diagnostics));
    let at = patched.find("material = ply").unwrap();
    assert!(
        d.labels
            .iter()
            .any(|l| l.span.start as usize == at + "material = ".len()),
        "{d:?}"
    );
}

/// Issue 33, AGARD 445.6 at Yates' transonic point M 0.954 (`m0954`, the doublet lattice):
/// answered on the transonic bridge (the doublet lattice's 0.95 and the Mach box's 1.1, weight
/// 0.027, stated uncertainty +-0.5 %), bending with torsion at a flutter speed index 0.3394
/// against the published 0.3059 (+10.9 %: linear theory has no transonic dip) and a frequency
/// ratio 0.3842 against 0.3807 (+0.9 %). The computed values are pinned at the printed
/// digits. Fails on the old code (the band was refused: the Mach box was not wired for
/// fixtures and the doublet lattice stopped at 0.95).
#[test]
fn agard_transonic_point_is_answered_on_the_bridge() {
    let o = Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .args(["analyze", "flutter"])
        .arg(example())
        .args([
            "--scenario",
            "m0954",
            "--aero",
            "doublet-lattice",
            "--format",
            "json",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let method = j["aero_method"].as_str().unwrap();
    assert!(method.starts_with("transonic bridge (+-0.5 %)"), "{method}");
    assert_eq!(j["transonic_bridge"]["low_mach"], 0.95);
    assert_eq!(j["transonic_bridge"]["high_mach"], 1.1);
    let f = &j["flutter"][0];
    let fsi = f["speed_index"].as_f64().unwrap();
    let ratio = f["frequency_ratio"].as_f64().unwrap();
    println!("M 0.954: FSI {fsi:.5}, ratio {ratio:.5}");
    assert!((fsi - 0.33940).abs() < 5e-5, "{fsi}");
    assert!((ratio - 0.38420).abs() < 5e-5, "{ratio}");
    let published = &FLUTTER_TESTS[3];
    assert_eq!(published.mach, 0.954);
    assert!(
        fsi > published.speed_index,
        "no transonic dip in linear theory"
    );
}

/// The line of `docs/validation.md` that contains `key` (the first one).
fn validation_line(key: &str) -> String {
    std::fs::read_to_string(common::root().join("docs/validation.md"))
        .unwrap()
        .lines()
        .find(|l| l.contains(key))
        .unwrap_or_else(|| panic!("no line with `{key}` in docs/validation.md"))
        .to_string()
}

/// Issue 38, item 2: the Goland comparison is against the published 450 ft/s (137.16 m/s),
/// not the rounded 137 m/s; the deviation printed is the solver's, to the two decimals shown.
#[test]
fn validation_goland_deviation_is_against_450_ft_s() {
    use flexflight::analysis::flutter::pk::{PkSettings, pk_solve};
    use goland::UniformWing;
    let w = UniformWing::goland();
    let (model, gaf, _) = w.flutter_problem(20, 4).unwrap();
    let speeds: Vec<f64> = (1..=60).map(|i| 5.0 * i as f64).collect();
    let sol = pk_solve(&model, &gaf, &speeds, PkSettings::default()).unwrap();
    let v = sol.critical().unwrap().speed;
    let rel = 100.0 * (v / (450.0 * 0.3048) - 1.0);
    let row = validation_line("| Goland wing (20 beam elements, 4 modes");
    assert!(row.contains("450 ft/s = 137.16 m/s"), "{row}");
    assert!(row.contains(&format!("{v:.3} m/s")), "{v}: {row}");
    assert!(row.contains(&format!("{rel:+.2} %")), "{rel}: {row}");
}

/// The doublet lattice refuses a lattice whose boxes are too wide for its parabolic kernel
/// approximation on a fixture too, as on the clamped fin: AGARD 445.6 on one strip (boxes
/// about 20 times wider than long) is `WideBoxes`, with the diagnostic code of the clamped
/// fin's refusal; the vortex lattice takes the same lattice. Fails on the old code, where the
/// fixture's doublet lattice computed on any boxes.
#[test]
fn a_fixture_lattice_with_wide_boxes_is_refused_by_the_doublet_lattice() {
    use flexflight::aero::panel::PanelError;
    use flexflight::analysis::flutter::wing::{
        UnsteadyAero, UnsteadySettings, WingError, unsteady_problem,
    };
    let t = tunnel("m0499");
    let modes = wing_spec(&t.fixture).modes(2).unwrap();
    let settings = UnsteadySettings {
        aero: UnsteadyAero::DoubletLattice,
        k_max: 0.3,
        k_count: 3,
        spanwise: 1,
        min_chordwise: 0,
    };
    match unsteady_problem(&modes, 0.499, t.density.value, &settings) {
        Err(e @ WingError::Panel(PanelError::WideBoxes { ratio, limit })) => {
            println!("{e}");
            assert!(ratio > limit && limit == 3.0, "{ratio}");
            assert_eq!(
                flexflight::ops::tunnel::tunnel_code(&e),
                "analysis::flutter::wide_boxes"
            );
        }
        Err(other) => panic!("{other}"),
        Ok(_) => panic!("accepted boxes much wider than long"),
    }
    let vortex = UnsteadySettings {
        aero: UnsteadyAero::VortexLattice,
        ..settings
    };
    assert!(unsteady_problem(&modes, 0.499, t.density.value, &vortex).is_ok());
}

/// `--aero vortex-lattice` (the name of `--aero unsteady` since the doublet lattice became the
/// default, issue 33) is the old default: the M 0.499 point's flutter speed index and
/// frequency ratio as recorded before the switch (README, examples/agard445: 0.4512, 0.6153).
#[test]
fn the_vortex_lattice_keeps_its_figures_behind_its_flag() {
    for name in ["vortex-lattice", "unsteady"] {
        let o = Command::new(env!("CARGO_BIN_EXE_flexflight"))
            .args(["analyze", "flutter"])
            .arg(example())
            .args(["--scenario", "m0499", "--aero", name, "--format", "json"])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(j["aero"], "unsteady");
        assert_eq!(j["aero_method"], "harmonic vortex lattice (Goethert)");
        let f = &j["flutter"][0];
        let fsi = f["speed_index"].as_f64().unwrap();
        let ratio = f["frequency_ratio"].as_f64().unwrap();
        println!("--aero {name}: FSI {fsi:.5}, ratio {ratio:.5}");
        assert!((fsi - 0.4512).abs() < 5e-5, "{fsi}");
        assert!((ratio - 0.6153).abs() < 5e-5, "{ratio}");
    }
}

/// NASA TN D-1824's 15-degree swept plate wing (model A, `examples/tnd1824/tnd1824.vdl`) at
/// Mach 0.45 with the default aerodynamics (the doublet lattice): against the flutter point
/// COSMIC NASTRAN's demonstration problem D10-02-1A takes from the TN (5980 in/s = 151.9
/// m/s, 121 Hz, k = 0.1314) the flutter speed is 2.9 % low and the frequency 5.2 % low
/// (docs/validation.md); the computed figures are pinned at the printed digits, the
/// published differences held within 3.5 % and 6 %.
#[test]
fn tnd1824_subsonic_point_against_the_nastran_demonstration() {
    let file = common::root().join("examples/tnd1824/tnd1824.vdl");
    let o = Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .args(["analyze", "flutter"])
        .arg(&file)
        .args(["--scenario", "m045", "--format", "json"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["aero_method"], "doublet lattice");
    let f = &j["flutter"][0];
    let v = f["speed_m_s"].as_f64().unwrap();
    let hz = f["frequency_hz"].as_f64().unwrap();
    println!("TN D-1824 M 0.45: V {v:.2} m/s, f {hz:.2} Hz ({f})");
    let published_v = 5980.0 * 0.0254;
    assert!(close(v, published_v, 0.035), "{v}");
    assert!(close(hz, 121.0, 0.06), "{hz}");
    assert!((v - 147.49).abs() < 0.01, "{v}");
    assert!((hz - 114.66).abs() < 0.01, "{hz}");
}
