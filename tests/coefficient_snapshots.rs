//! Snapshots of compiled coefficients: SPHADS-1, a two-element beam and a single plate
//! element with a point mass (models small enough to check by hand). Floats are printed to
//! 8 significant digits; entries below 1e-9 of the largest entry of their array are printed
//! as 0 (round-off, not physics); mode signs are normalised by the compiler (largest entry
//! positive) and repeated modes are ordered by the selection rules (fin 1, 2, ...).

use std::path::Path;

use flexflight::check::{DiskLoader, MemoryLoader, check_files, check_source};
use flexflight::structure::compile::{CompiledVehicle, compile};
use serde_json::Value;

fn sig(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    format!("{x:.7e}")
}

/// Format every number of a JSON tree; small entries relative to their array's max are 0.
fn fmt_value(v: &Value) -> Value {
    match v {
        Value::Array(a) => {
            let nums: Vec<f64> = flatten(v);
            let max = nums.iter().map(|x| x.abs()).fold(0.0, f64::max);
            Value::Array(a.iter().map(|x| fmt_scaled(x, max)).collect())
        }
        Value::Object(m) => {
            Value::Object(m.iter().map(|(k, x)| (k.clone(), fmt_value(x))).collect())
        }
        Value::Number(n) => Value::String(sig(n.as_f64().unwrap_or(f64::NAN))),
        other => other.clone(),
    }
}

fn fmt_scaled(v: &Value, max: f64) -> Value {
    match v {
        Value::Number(n) => {
            let x = n.as_f64().unwrap_or(f64::NAN);
            Value::String(if x.abs() < 1e-9 * max {
                "0".into()
            } else {
                sig(x)
            })
        }
        Value::Array(a) => Value::Array(a.iter().map(|x| fmt_scaled(x, max)).collect()),
        other => fmt_value(other),
    }
}

fn flatten(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(flatten).collect(),
        Value::Number(n) => vec![n.as_f64().unwrap_or(0.0)],
        _ => Vec::new(),
    }
}

fn snapshot_text(c: &CompiledVehicle) -> String {
    let modes: Vec<Value> = c
        .modes
        .iter()
        .map(|m| {
            serde_json::json!({
                "name": m.name, "class": m.class, "fin": m.fin,
                "frequency_hz": sig(m.frequency_hz), "generalised_mass": sig(m.generalised_mass),
            })
        })
        .collect();
    let reduced = fmt_value(&serde_json::to_value(&c.reduced).unwrap());
    let v = serde_json::json!({
        "nodes": c.node_positions.len(),
        "centre_of_mass": fmt_value(&serde_json::to_value(c.centre_of_mass).unwrap()),
        "modes": modes,
        "reduced": reduced,
    });
    serde_json::to_string_pretty(&v).unwrap()
}

fn compile_src(src: &str) -> CompiledVehicle {
    let loader = MemoryLoader::default();
    let checked = check_source("model.vdl", src, &loader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    compile(&checked.program.vehicles[0]).unwrap().0
}

#[test]
fn sphads1_coefficients() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("vehicles/sphads1.vdl");
    let checked = check_files(&[root], &[], &DiskLoader);
    let c = compile(&checked.program.vehicles[0]).unwrap().0;
    insta::assert_snapshot!(snapshot_text(&c));
}

/// A free-free tube of two Euler-Bernoulli elements (3 nodes, 18 DOF): its first two elastic
/// modes are the pair of first bending modes in the two planes.
#[test]
fn two_element_beam_coefficients() {
    let c = compile_src(
        r#"import "std/materials.vdl"
vehicle beam {
  material = aluminium_thesis
  origin = node(1)
  structure { generate { body { length = 1 m; diameter = 100 mm; wall = 5 mm; elements = 2 } } }
  key_nodes { body = node(2) }
  modes { body_bending = 2 }
  aero { source = builtin; reference_point = (-0.5, 0, 0) m }
  forces { gravity {} }
}
"#,
    );
    assert_eq!(c.node_positions.len(), 3);
    insta::assert_snapshot!(snapshot_text(&c));
}

/// One fin of one shell element on a one-element body, with a point mass: the smallest model
/// with a plate, a rigid root link and an offset mass.
#[test]
fn single_plate_with_point_mass_coefficients() {
    let c = compile_src(
        r#"import "std/materials.vdl"
vehicle plate {
  material = aluminium_thesis
  origin = node(1)
  structure {
    generate {
      body { length = 0.4 m; diameter = 100 mm; wall = 5 mm; elements = 1 }
      fin_mesh { span_elements = 1; chord_elements = 1 }
      point_mass tip { position = (-0.1, 0, 0) m; mass = 0.5 kg; inertia = (0.001, 0.002, 0.002) kg*m^2 }
    }
  }
  fins { count = 1; span = 100 mm; root_chord = 200 mm; tip_chord = 100 mm; trailing_edge_sweep = 0 deg; thickness = 2 mm }
  key_nodes { body = node(1); fins = fin_point(span = 1, chord = 0) }
  modes { indices = [1, 2, 3] }
  aero { source = builtin; reference_point = (-0.2, 0, 0) m }
  forces { gravity {} }
}
"#,
    );
    insta::assert_snapshot!(snapshot_text(&c));
}
