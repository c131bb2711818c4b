//! Helpers shared by the integration tests (each test file uses a subset).
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use serde_json::Value;

/// Keys that hold source locations in the IR's serialisation.
const SPAN_KEYS: &[&str] = &["span", "span_", "header"];

/// Is this the serialisation of a `Span`, `[file, start, end]`?
fn is_span(v: &Value) -> bool {
    v.as_array()
        .is_some_and(|a| a.len() == 3 && a.iter().all(Value::is_u64))
}

/// Remove every span-valued key, recursively. Only keys whose value is a serialised `Span`
/// go: the fin `span` (a length) and `fin_point(span = ...)` (a fraction) stay.
pub fn strip_spans(v: &mut Value) {
    match v {
        Value::Object(map) => {
            map.retain(|k, x| !(SPAN_KEYS.contains(&k.as_str()) && is_span(x)));
            for x in map.values_mut() {
                strip_spans(x);
            }
        }
        Value::Array(items) => items.iter_mut().for_each(strip_spans),
        _ => {}
    }
}

/// Replace every number by a string of 8 significant digits (so snapshots do not depend on
/// the last bits of a unit conversion).
pub fn round_numbers(v: &mut Value) {
    match v {
        Value::Number(n) => {
            let x = n.as_f64().unwrap_or(f64::NAN);
            *v = Value::String(sig8(x));
        }
        Value::Object(map) => map.values_mut().for_each(round_numbers),
        Value::Array(items) => items.iter_mut().for_each(round_numbers),
        _ => {}
    }
}

/// `x` with 8 significant digits, in exponent form when that is shorter to read.
pub fn sig8(x: f64) -> String {
    if x == 0.0 {
        return "0".to_string();
    }
    if x.fract() == 0.0 && x.abs() < 1e8 {
        return format!("{x:.0}");
    }
    let e = x.abs().log10().floor() as i32;
    if (-4..8).contains(&e) {
        let decimals = (7 - e).max(0) as usize;
        let s = format!("{x:.decimals$}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        format!("{x:.7e}")
    }
}

/// Replace a directory prefix in every string (resolved file paths differ per checkout).
pub fn replace_paths(v: &mut Value, dir: &Path, by: &str) {
    let d = dir.display().to_string();
    match v {
        Value::String(s) if s.contains(&d) => *s = s.replace(&d, by),
        Value::Object(map) => map.values_mut().for_each(|x| replace_paths(x, dir, by)),
        Value::Array(items) => items.iter_mut().for_each(|x| replace_paths(x, dir, by)),
        _ => {}
    }
}

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every `.vdl` file under the shipped directories, sorted.
pub fn shipped_vdl_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(rd) = std::fs::read_dir(dir) else {
            return;
        };
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "vdl") {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    for d in ["vehicles", "stdlib", "examples"] {
        walk(&root().join(d), &mut out);
    }
    out.sort();
    out
}

/// The checked program as JSON (`Program` itself is not `Serialize`; its parts are).
pub fn program_json(p: &flexflight::Program) -> Value {
    serde_json::json!({
        "materials": p.materials,
        "vehicles": p.vehicles,
        "scenarios": p.scenarios,
        "sweeps": p.sweeps,
        "fixtures": p.fixtures,
        "tunnel_tests": p.tunnel_tests,
    })
}

/// The body-only vehicle `burner` of the motor and launch tests (2 m aluminium tube, 3 kg
/// payload forward, a motor component `grain` at the tail on `constant.csv`: 3 kg of
/// propellant in a 4.5 kg motor), as `.vdl` text after the materials import; `forces` and
/// `motor_extra` go into its `forces` and `motor` blocks.
pub fn burner_vehicle(forces: &str, motor_extra: &str) -> String {
    format!(
        r#"import "std/materials.vdl"

vehicle burner {{
  material = aluminium_6061_t6
  origin = node(1)
  structure {{
    generate {{
      body {{
        length = 2 m
        diameter = 100 mm
        wall = 2 mm
        elements = 20
      }}
      point_mass payload {{
        position = (-0.5, 0, 0) m
        mass = 3 kg
        inertia = (0.002, 0.03, 0.03) kg*m^2
      }}
    }}
  }}
  motor grain {{
    curve = "constant.csv"
    position = (-2, 0, 0) m
    length = 600 mm
    diameter = 75 mm
    propellant_mass = 3 kg
    total_mass = 4.5 kg
    {motor_extra}
  }}
  key_nodes {{
    body = nearest((-1, 0, 0) m)
  }}
  modes {{
    body_bending = 2
    fixity = origin
    damping = 0.02
  }}
  aero {{
    source = builtin
    reference_length = 100 mm
    reference_point = (-1, 0, 0) m
  }}
  forces {{
    {forces}
  }}
}}
"#
    )
}
