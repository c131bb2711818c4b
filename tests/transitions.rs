//! Issue 34: transitions, boat tails and a body of more than one diameter
//! (`body { transition { ... } }`, `check::transition`): the generated structure's exact mass
//! and its nodes at the section ends, Barrowman's normal force and centre of pressure of a
//! boat tail in the built-in aerodynamics, and bad input refused at `check` with file, line
//! and column.

#![allow(clippy::unwrap_used)]

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use flexflight::aero::estimator::{BodyShape, NoseShape as EstNose, body_coefficients};
use flexflight::check::ir::NoseShape;
use flexflight::check::transition::TransitionGeom;
use flexflight::structure::Component;
use flexflight::structure::generate::{
    BeamTheory, BodySpec, GeneratorSpec, MaterialProps, analytic_mass_properties, generate,
    rigid_body_projection,
};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn body(transitions: Vec<TransitionGeom>) -> BodySpec {
    BodySpec {
        length: 2.0,
        outer_diameter: 0.102,
        wall_thickness: 0.002,
        nose_length: 0.4,
        nose_shape: NoseShape::Ogive { k: 1.0 },
        transitions,
        elements: 40,
        theory: BeamTheory::EulerBernoulli,
        material: MaterialProps {
            youngs_modulus: 70e9,
            poisson: 0.33,
            density: 2710.0,
        },
    }
}

/// A reducer (frustum) to 80 mm, a von Kármán widening back to 102 mm, and a conical boat tail
/// to 76 mm at the tail.
fn three_transitions() -> Vec<TransitionGeom> {
    vec![
        TransitionGeom {
            start: 0.8,
            length: 0.1,
            r_fore: 0.051,
            r_aft: 0.040,
            shape: NoseShape::Conical,
        },
        TransitionGeom {
            start: 1.2,
            length: 0.15,
            r_fore: 0.040,
            r_aft: 0.051,
            shape: NoseShape::Haack { c: 0.0 },
        },
        TransitionGeom {
            start: 1.9,
            length: 0.1,
            r_fore: 0.051,
            r_aft: 0.038,
            shape: NoseShape::Conical,
        },
    ]
}

/// The outer radius of the test body at s aft of the tip, written out here independently of
/// the library's `section_radius` (the profiles' definitions: `check::nose` for the nose and
/// the shaped transition's offset profile, a straight line on the frustums).
fn radius(s: f64) -> f64 {
    let ogive = NoseShape::Ogive { k: 1.0 };
    let haack = NoseShape::Haack { c: 0.0 };
    match s {
        s if s < 0.4 => ogive.radius(s, 0.051, 0.4),
        s if s < 0.8 => 0.051,
        s if s < 0.9 => 0.051 + (0.040 - 0.051) * (s - 0.8) / 0.1,
        s if s < 1.2 => 0.040,
        s if s < 1.35 => 0.040 + haack.radius(s - 1.2, 0.011, 0.15),
        s if s < 1.9 => 0.051,
        s => 0.051 + (0.038 - 0.051) * (s - 1.9) / 0.1,
    }
}

/// Mass, first moment and axial second moment about the tip of the shell between r(s) and
/// max(r(s) - t, 0), composite Simpson on each segment (400,000 panels each).
fn simpson_mass(t: f64, rho: f64) -> (f64, f64, f64) {
    let cuts = [0.0, 0.4, 0.8, 0.9, 1.2, 1.35, 1.9, 2.0];
    let (mut m, mut mx, mut mxx) = (0.0, 0.0, 0.0);
    for w in cuts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let n = 400_000;
        let h = (b - a) / n as f64;
        for i in 0..=n {
            // Inside the segment (its ends' one-sided limits).
            let s = (a + i as f64 * h).clamp(a + 1e-13, b - 1e-13);
            let ro = radius(s);
            let ri = (ro - t).max(0.0);
            let area = rho * PI * (ro * ro - ri * ri);
            let k = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            m += k * area * h / 3.0;
            mx += k * area * s * h / 3.0;
            mxx += k * area * s * s * h / 3.0;
        }
    }
    (m, mx, mxx)
}

/// The structure follows the true radius: the FE model's rigid-body projection (mass, first
/// moment, axial second moment) equals the profile's integrals, computed here independently;
/// the library's own closed forms (`analytic_mass_properties`) agree; a body node lies at each
/// end of every transition.
#[test]
fn a_body_with_transitions_has_the_mass_of_its_profile_and_nodes_at_the_section_ends() {
    let spec = GeneratorSpec {
        body: body(three_transitions()),
        fins: None,
        point_masses: vec![],
        distributed_masses: vec![],
        rigid_fins: vec![],
    };
    let model = generate(&spec).unwrap();
    let fe = rigid_body_projection(&model);
    let analytic = analytic_mass_properties(&spec);
    let (m, mx, mxx) = simpson_mass(0.002, 2710.0);
    let e_mass = (fe[0][0] - m).abs() / m;
    let e_first = (fe[4][2].abs() - mx).abs() / mx;
    // I_yy about the tip = int rho A s^2 + int rho I (the section's own): the first dominates.
    let e_analytic = (analytic.mass - m).abs() / m;
    eprintln!(
        "transitions: FE mass {e_mass:e}, first moment {e_first:e}, closed form {e_analytic:e}"
    );
    assert!(e_mass < 1e-9, "FE mass {} vs {m}: {e_mass:e}", fe[0][0]);
    assert!(e_first < 1e-9, "first moment: {e_first:e}");
    assert!(e_analytic < 1e-9, "closed form {} vs {m}", analytic.mass);
    assert!(fe[4][4] > mxx, "I_yy about the tip exceeds int rho A s^2");
    // Without the transitions the mass is the plain tube's: they change it.
    let plain = GeneratorSpec {
        body: body(vec![]),
        ..spec.clone()
    };
    let fe0 = rigid_body_projection(&generate(&plain).unwrap());
    assert!((fe0[0][0] - fe[0][0]).abs() > 1e-3 * m);
    // Nodes at both ends of every transition.
    let xs: Vec<f64> = model
        .nodes
        .iter()
        .filter(|n| n.component == Component::Body)
        .map(|n| n.position[0])
        .collect();
    for t in three_transitions() {
        for s in [t.start, t.end()] {
            assert!(
                xs.iter().any(|x| (x + s).abs() < 1e-12),
                "no body node at x = {}",
                -s
            );
        }
    }
}

fn est_body(transitions: Vec<TransitionGeom>) -> BodyShape {
    BodyShape {
        length: 2.0,
        diameter: 0.102,
        nose: EstNose::Cone { length: 0.4 },
        reference_x: -1.2,
        transitions,
        roughness: flexflight::aero::estimator::DEFAULT_ROUGHNESS,
        guides: vec![],
        fin_sets: vec![],
    }
}

/// (C_N_alpha per rad, centre of pressure body x) of the body at a vanishing angle of attack
/// (1e-7 deg: the crossflow term, quadratic in alpha, is 1e-8 of the potential one there).
fn slope_and_cp(b: &BodyShape) -> (f64, f64) {
    let a = 1e-7;
    let [cn, _, cm] = body_coefficients(b, 0.3, a, 0.0);
    let slope = cn / f64::to_radians(a);
    (slope, b.reference_x + b.reference_diameter() * cm / cn)
}

/// A boat tail's potential normal force is Barrowman's 2 (A_aft - A_fore)/A_ref per rad at his
/// frustum centre of pressure l/3 (1 + (1 - rho)/(1 - rho^2)) aft of its fore end, rho =
/// d_fore/d_aft (Barrowman 1967, sec. 3); the body's centre of pressure moves forward by the
/// slope-weighted amount; the reference diameter stays the largest.
#[test]
fn a_boat_tail_moves_the_centre_of_pressure_forward_by_barrowmans_amount() {
    let plain = est_body(vec![]);
    let tail = TransitionGeom {
        start: 1.85,
        length: 0.15,
        r_fore: 0.051,
        r_aft: 0.035,
        shape: NoseShape::Conical,
    };
    let tailed = est_body(vec![tail]);
    assert_eq!(tailed.reference_diameter(), 0.102);
    let s_ref = PI * 0.102f64.powi(2) / 4.0;
    let (k0, x0) = slope_and_cp(&plain);
    let (k1, x1) = slope_and_cp(&tailed);
    let k_t = 2.0 * PI * (0.035f64.powi(2) - 0.051f64.powi(2)) / s_ref;
    let rho = 0.051 / 0.035;
    let x_t = -(1.85 + 0.15 / 3.0 * (1.0 + (1.0 - rho) / (1.0 - rho * rho)));
    assert!((k0 - 2.0).abs() < 1e-6, "nose slope {k0}");
    assert!(((k1 - k0) - k_t).abs() < 1e-6, "{} vs {k_t}", k1 - k0);
    let expected = (k0 * x0 + k_t * x_t) / (k0 + k_t);
    assert!(
        (x1 - expected).abs() < 1e-6,
        "centre of pressure {x1} m, Barrowman {expected} m"
    );
    assert!(x1 > x0, "a boat tail moves the centre of pressure forward");
    eprintln!(
        "boat tail: C_N_alpha {k0:.4} -> {k1:.4} /rad, x_cp {x0:.4} -> {x1:.4} m (Barrowman {expected:.4})"
    );
}

/// Boat-tail drag (Niskanen 2009, sec. 3.4.3): the base drag shrinks with the base area and the
/// boat tail takes a share of the base drag on its frontal area, all of it up to a fineness
/// l/(d_f - d_a) of 1, (3 - fineness)/2 between, none from 3 on; the friction follows the
/// smaller wetted area. Checked at Mach 0.5 against the blunt tube, the friction coefficient
/// recomputed here from the atmosphere and the friction law (`skin_friction`, with the body's
/// fineness correction).
#[test]
fn boat_tail_drag_follows_the_base_drag_and_its_fineness() {
    use flexflight::aero::atmosphere::{Atmosphere, Standard1976};
    let ca = |t: Vec<TransitionGeom>| body_coefficients(&est_body(t), 0.5, 0.0, 0.0)[1];
    let blunt = ca(vec![]);
    let base_cd = 0.12 + 0.13 * 0.25;
    let air = Standard1976::new().at(0.0).unwrap();
    let re = air.density * 0.5 * air.speed_of_sound * 2.0 / air.viscosity;
    use flexflight::aero::estimator::{DEFAULT_ROUGHNESS, body_friction_correction, skin_friction};
    let cf = skin_friction(re, 0.5, DEFAULT_ROUGHNESS / 2.0) * body_friction_correction(2.0, 0.102);
    let s_ref = PI * 0.102f64.powi(2) / 4.0;
    let (rf, ra) = (0.051, 0.035);
    let removed = PI * (rf * rf - ra * ra) / s_ref;
    for (fineness, share) in [(0.5, 1.0), (1.0, 1.0), (2.0, 0.5), (3.0, 0.0), (4.0, 0.0)] {
        let l: f64 = fineness * 2.0 * (rf - ra);
        let tail = TransitionGeom {
            start: 2.0 - l,
            length: l,
            r_fore: rf,
            r_aft: ra,
            shape: NoseShape::Conical,
        };
        let wet_tube = 2.0 * PI * rf * l;
        let wet_tail = PI * (rf + ra) * ((rf - ra).powi(2) + l * l).sqrt();
        let expected =
            -base_cd * removed + base_cd * removed * share + cf * (wet_tail - wet_tube) / s_ref;
        let got = ca(vec![tail]) - blunt;
        assert!(
            (got - expected).abs() < 1e-12,
            "fineness {fineness}: {got} vs {expected}"
        );
    }
}

// ---- check ---------------------------------------------------------------------------------

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The HPR example with a 2.0 m body ending in a boat tail behind the fins, its block
/// replaced by `block`.
fn hpr_with(dir: &Path, block: &str) -> PathBuf {
    let text = std::fs::read_to_string(repo("examples/hpr_k1000/hpr_k1000.vdl")).unwrap();
    for e in std::fs::read_dir(repo("examples/hpr_k1000")).unwrap() {
        let p = e.unwrap().path();
        if p.is_file() {
            std::fs::copy(&p, dir.join(p.file_name().unwrap())).unwrap();
        }
    }
    let t = text
        .replacen("        length = 1.9 m\n", "        length = 2.0 m\n", 1)
        .replacen(
            "        theory = euler_bernoulli\n",
            &format!("        theory = euler_bernoulli\n{block}"),
            1,
        );
    assert_ne!(t, text);
    let p = dir.join("tail.vdl");
    std::fs::write(&p, t).unwrap();
    p
}

const BOAT_TAIL: &str = "        transition {
          fore_station = -1.9 m
          length = 100 mm
          fore_diameter = 98 mm
          aft_diameter = 80 mm
        }
";

/// A boat tail checks; each bad transition is an error at `check` with the file, line and
/// column of the offending value and a non-zero exit: fore diameter not meeting the section
/// ahead, a negative length, overlapping the nose, the fins or past the tail, equal
/// diameters (no transition), an unknown shape.
#[test]
fn transitions_check_and_bad_ones_are_errors_at_the_value() {
    let dir = tempfile::tempdir().unwrap();
    let p = hpr_with(dir.path(), BOAT_TAIL);
    let o = bin().arg("check").arg(&p).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // The transition block starts on line 40 of the file; its fields on 41-44.
    for (from, to, code, line) in [
        (
            "fore_diameter = 98 mm",
            "fore_diameter = 90 mm",
            "vdl::transition::mismatch",
            43,
        ),
        (
            "length = 100 mm",
            "length = -100 mm",
            "vdl::value::range",
            42,
        ),
        (
            "fore_station = -1.9 m",
            "fore_station = -0.3 m",
            "vdl::transition::overlap",
            41,
        ),
        (
            "fore_station = -1.9 m",
            "fore_station = -1.8 m",
            "vdl::transition::overlap",
            41,
        ),
        (
            "length = 100 mm",
            "length = 200 mm",
            "vdl::transition::overlap",
            42,
        ),
        (
            "aft_diameter = 80 mm",
            "aft_diameter = 98 mm",
            "vdl::transition::no_op",
            44,
        ),
        (
            "aft_diameter = 80 mm",
            "aft_diameter = 80 mm\n          shape = ogiv",
            "vdl::value::keyword",
            45,
        ),
    ] {
        let p = hpr_with(dir.path(), &BOAT_TAIL.replacen(from, to, 1));
        let o = bin().arg("check").arg(&p).output().unwrap();
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{to}: {e}");
        assert!(e.contains(code), "{to}: {e}");
        assert!(
            e.contains(&format!("tail.vdl:{line}:")),
            "{to} at line {line}: {e}"
        );
    }
}

/// A body of three diameters (docs/language.md: `transition {...}` "any number, fore to
/// aft"): a payload section widened ahead of the fins and a boat tail behind them, two
/// unnamed `transition` blocks, checks and compiles; the check refused the second as a
/// duplicate block (`vdl::duplicate`) after the launch lugs' repeatable blocks came in.
#[test]
fn a_body_of_two_transitions_checks_and_compiles() {
    let dir = tempfile::tempdir().unwrap();
    let blocks = "        transition {
          fore_station = -0.6 m
          length = 50 mm
          fore_diameter = 98 mm
          aft_diameter = 110 mm
        }
        transition {
          fore_station = -1.0 m
          length = 50 mm
          fore_diameter = 110 mm
          aft_diameter = 98 mm
        }
";
    let p = hpr_with(dir.path(), blocks);
    let o = bin().arg("check").arg(&p).output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let o = bin()
        .arg("compile")
        .arg(&p)
        .arg("--cache-dir")
        .arg(dir.path().join("cache"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// A transition that starts at the nose's base as written in another unit (`nose_length =
/// 396.875 mm` is 0.39687500000000003 m, `fore_station = -0.396875 m` is 0.396875 m) is
/// behind the nose for the generator as it is for the checker (both within 1e-12 of the
/// station): RockSim's "FooBar Test", imported, passed `check` and was refused at `compile`
/// (`generate::bad_geometry`, "a transition must start ... behind the nose"), which this
/// reproduces on the old generator.
#[test]
fn a_transition_at_the_nose_base_in_another_unit_is_behind_the_nose() {
    let nose = 396.875 * 1e-3;
    let start = 0.396875;
    assert!(start < nose, "the two spellings differ in the last bit");
    let mut b = body(vec![TransitionGeom {
        start,
        length: 0.05,
        r_fore: 0.051,
        r_aft: 0.045,
        shape: NoseShape::Conical,
    }]);
    b.nose_length = nose;
    let spec = GeneratorSpec {
        body: b,
        fins: None,
        point_masses: vec![],
        distributed_masses: vec![],
        rigid_fins: vec![],
    };
    let model = generate(&spec).unwrap();
    // One body node at the nose's base (the two stations are one).
    let at_base = model
        .nodes
        .iter()
        .filter(|n| n.component == Component::Body && (n.position[0] + nose).abs() < 1e-9)
        .count();
    assert_eq!(at_base, 1);
}
