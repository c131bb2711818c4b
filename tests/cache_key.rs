//! The cache key and the sweep fingerprints are complete (issue 9, defect 1).
//!
//! Property: every leaf of the structural IR of a vehicle changes the cache key when it is
//! perturbed; no source position and no non-structural leaf (aerodynamics, force blocks,
//! anything of a scenario outside its vehicle) does. Source positions are told apart by
//! their TYPE (a `Span` serialises as the newtype struct `syntax::span::POSITION_TOKEN`),
//! never by a field name: the fin `span` (a length) and `fin_point(span = ...)` (a fraction)
//! are leaves like any other. The same for the sweep's variant and vehicle fingerprints.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use flexflight::check::ir::{Scenario, Vehicle};
use flexflight::check::{DiskLoader, check_files, check_scenario_files};
use flexflight::ops::compile::cache_key;
use flexflight::ops::sweep::case_fingerprints;
use serde_json::Value;

fn root(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

const TUBE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/fe-samples/tube21");

// ------------------------------------------------------------------ positions by type

/// A serialiser to `serde_json::Value` that mirrors serde_json's layout (externally tagged
/// enums, transparent newtype structs, `None` as null) but writes the marker string
/// `POSITION` wherever a value announces itself as a source position.
mod marked {
    use flexflight::syntax::span::POSITION_TOKEN;
    use serde::ser::{self, Serialize};
    use serde_json::{Map, Value};

    pub const POSITION: &str = "\u{0}position";

    #[derive(Debug)]
    pub struct E(String);
    impl std::fmt::Display for E {
        fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str(&self.0)
        }
    }
    impl std::error::Error for E {}
    impl ser::Error for E {
        fn custom<T: std::fmt::Display>(m: T) -> Self {
            E(m.to_string())
        }
    }

    pub fn to_value<T: Serialize + ?Sized>(v: &T) -> Value {
        v.serialize(S).unwrap()
    }

    pub struct S;
    pub struct Seq(Vec<Value>, Option<&'static str>);
    pub struct Obj(Map<String, Value>, Option<&'static str>, Option<String>);

    fn tagged(variant: Option<&'static str>, v: Value) -> Value {
        match variant {
            Some(t) => {
                let mut m = Map::new();
                m.insert(t.to_string(), v);
                Value::Object(m)
            }
            None => v,
        }
    }

    type R = Result<Value, E>;

    impl ser::Serializer for S {
        type Ok = Value;
        type Error = E;
        type SerializeSeq = Seq;
        type SerializeTuple = Seq;
        type SerializeTupleStruct = Seq;
        type SerializeTupleVariant = Seq;
        type SerializeMap = Obj;
        type SerializeStruct = Obj;
        type SerializeStructVariant = Obj;
        fn serialize_bool(self, v: bool) -> R {
            Ok(Value::Bool(v))
        }
        fn serialize_i8(self, v: i8) -> R {
            Ok(v.into())
        }
        fn serialize_i16(self, v: i16) -> R {
            Ok(v.into())
        }
        fn serialize_i32(self, v: i32) -> R {
            Ok(v.into())
        }
        fn serialize_i64(self, v: i64) -> R {
            Ok(v.into())
        }
        fn serialize_u8(self, v: u8) -> R {
            Ok(v.into())
        }
        fn serialize_u16(self, v: u16) -> R {
            Ok(v.into())
        }
        fn serialize_u32(self, v: u32) -> R {
            Ok(v.into())
        }
        fn serialize_u64(self, v: u64) -> R {
            Ok(v.into())
        }
        fn serialize_f32(self, v: f32) -> R {
            Ok(f64::from(v).into())
        }
        fn serialize_f64(self, v: f64) -> R {
            Ok(v.into())
        }
        fn serialize_char(self, v: char) -> R {
            Ok(Value::String(v.to_string()))
        }
        fn serialize_str(self, v: &str) -> R {
            Ok(Value::String(v.to_string()))
        }
        fn serialize_bytes(self, v: &[u8]) -> R {
            Ok(Value::Array(v.iter().map(|b| (*b).into()).collect()))
        }
        fn serialize_none(self) -> R {
            Ok(Value::Null)
        }
        fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> R {
            v.serialize(self)
        }
        fn serialize_unit(self) -> R {
            Ok(Value::Null)
        }
        fn serialize_unit_struct(self, _: &'static str) -> R {
            Ok(Value::Null)
        }
        fn serialize_unit_variant(self, _: &'static str, _: u32, v: &'static str) -> R {
            Ok(Value::String(v.to_string()))
        }
        fn serialize_newtype_struct<T: Serialize + ?Sized>(self, n: &'static str, v: &T) -> R {
            if n == POSITION_TOKEN {
                return Ok(Value::String(POSITION.into()));
            }
            v.serialize(self)
        }
        fn serialize_newtype_variant<T: Serialize + ?Sized>(
            self,
            _: &'static str,
            _: u32,
            t: &'static str,
            v: &T,
        ) -> R {
            Ok(tagged(Some(t), v.serialize(self)?))
        }
        fn serialize_seq(self, _: Option<usize>) -> Result<Seq, E> {
            Ok(Seq(Vec::new(), None))
        }
        fn serialize_tuple(self, _: usize) -> Result<Seq, E> {
            Ok(Seq(Vec::new(), None))
        }
        fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Seq, E> {
            Ok(Seq(Vec::new(), None))
        }
        fn serialize_tuple_variant(
            self,
            _: &'static str,
            _: u32,
            t: &'static str,
            _: usize,
        ) -> Result<Seq, E> {
            Ok(Seq(Vec::new(), Some(t)))
        }
        fn serialize_map(self, _: Option<usize>) -> Result<Obj, E> {
            Ok(Obj(Map::new(), None, None))
        }
        fn serialize_struct(self, _: &'static str, _: usize) -> Result<Obj, E> {
            Ok(Obj(Map::new(), None, None))
        }
        fn serialize_struct_variant(
            self,
            _: &'static str,
            _: u32,
            t: &'static str,
            _: usize,
        ) -> Result<Obj, E> {
            Ok(Obj(Map::new(), Some(t), None))
        }
    }

    macro_rules! seq_impl {
        ($tr:path, $m:ident) => {
            impl $tr for Seq {
                type Ok = Value;
                type Error = E;
                fn $m<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), E> {
                    self.0.push(v.serialize(S)?);
                    Ok(())
                }
                fn end(self) -> R {
                    Ok(tagged(self.1, Value::Array(self.0)))
                }
            }
        };
    }
    seq_impl!(ser::SerializeSeq, serialize_element);
    seq_impl!(ser::SerializeTuple, serialize_element);
    seq_impl!(ser::SerializeTupleStruct, serialize_field);
    seq_impl!(ser::SerializeTupleVariant, serialize_field);

    impl ser::SerializeMap for Obj {
        type Ok = Value;
        type Error = E;
        fn serialize_key<T: Serialize + ?Sized>(&mut self, k: &T) -> Result<(), E> {
            self.2 = Some(match k.serialize(S)? {
                Value::String(s) => s,
                other => other.to_string(),
            });
            Ok(())
        }
        fn serialize_value<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), E> {
            let k = self.2.take().unwrap_or_default();
            self.0.insert(k, v.serialize(S)?);
            Ok(())
        }
        fn end(self) -> R {
            Ok(Value::Object(self.0))
        }
    }
    macro_rules! struct_impl {
        ($tr:path) => {
            impl $tr for Obj {
                type Ok = Value;
                type Error = E;
                fn serialize_field<T: Serialize + ?Sized>(
                    &mut self,
                    k: &'static str,
                    v: &T,
                ) -> Result<(), E> {
                    self.0.insert(k.to_string(), v.serialize(S)?);
                    Ok(())
                }
                fn end(self) -> R {
                    Ok(tagged(self.1, Value::Object(self.0)))
                }
            }
        };
    }
    struct_impl!(ser::SerializeStruct);
    struct_impl!(ser::SerializeStructVariant);
}

// ------------------------------------------------------------------ leaves

#[derive(Clone, Debug, PartialEq)]
enum Seg {
    Key(String),
    Index(usize),
}

#[derive(Debug)]
struct Leaf {
    path: Vec<Seg>,
    /// Inside a value that serialised as a source position.
    position: bool,
}

/// Every number, string and bool of `plain` (serde_json's serialisation), with whether it
/// lies inside a source position according to `marked` (the same value, positions marked).
fn leaves(plain: &Value, marked: &Value, path: &mut Vec<Seg>, position: bool, out: &mut Vec<Leaf>) {
    let position = position || marked.as_str() == Some(marked::POSITION);
    match plain {
        Value::Object(map) => {
            for (k, v) in map {
                path.push(Seg::Key(k.clone()));
                let m = if position {
                    &Value::Null
                } else {
                    marked
                        .get(k)
                        .unwrap_or_else(|| panic!("{path:?} not marked"))
                };
                leaves(v, m, path, position, out);
                path.pop();
            }
        }
        Value::Array(items) => {
            for (i, v) in items.iter().enumerate() {
                path.push(Seg::Index(i));
                let m = if position {
                    &Value::Null
                } else {
                    marked
                        .get(i)
                        .unwrap_or_else(|| panic!("{path:?} not marked"))
                };
                leaves(v, m, path, position, out);
                path.pop();
            }
        }
        Value::Null => {}
        _ => {
            if !position {
                assert_eq!(plain, marked, "the two serialisations disagree at {path:?}");
            }
            out.push(Leaf {
                path: path.clone(),
                position,
            });
        }
    }
}

fn at<'a>(v: &'a mut Value, path: &[Seg]) -> &'a mut Value {
    path.iter().fold(v, |v, s| match s {
        Seg::Key(k) => &mut v[k.as_str()],
        Seg::Index(i) => &mut v[*i],
    })
}

/// Every unit-variant name of the IR's enums (as serialised): the alternatives tried when a
/// string leaf is an enum tag.
const VARIANTS: &[&str] = &[
    "rounded",
    "euler_bernoulli",
    "timoshenko",
    "matrix_market",
    "op4",
    "dmig",
    "body_bending",
    "fin_flap",
    "fin_twist",
    "per_fin",
    "stop",
    "clamp",
    "theory",
    "uniform",
    "key_node",
    "load_weighted",
    "lifting_surface",
    "dopri5",
    "rk4",
    "dop853",
    "body",
    "inertial",
    "dryden",
    "von_karman",
    "run",
    "planar_pinned",
    "planar_unpinned",
    "linear3d",
    "grid",
    "zip",
];

/// Perturbed copies of a leaf, in order of preference. A path to an existing file becomes a
/// copy of it elsewhere (same bytes, other path), so a key that reads files can be computed.
fn perturbations(leaf: &Value, scratch: &Path) -> Vec<Value> {
    match leaf {
        Value::Bool(b) => vec![Value::Bool(!b)],
        Value::Number(n) => {
            if let Some(u) = n.as_u64() {
                vec![(u + 1).into(), u.saturating_sub(1).into()]
            } else {
                let x = n.as_f64().unwrap();
                vec![(x * 1.01 + 1e-3).into()]
            }
        }
        Value::String(s) => {
            let mut out = Vec::new();
            let p = Path::new(s);
            if p.is_file() {
                let copy = scratch.join(format!(
                    "copy-{}-{}",
                    std::fs::read_dir(scratch).unwrap().count(),
                    p.file_name().unwrap().to_string_lossy()
                ));
                std::fs::copy(p, &copy).unwrap();
                out.push(Value::String(copy.display().to_string()));
            } else {
                out.push(Value::String(format!("{s}x")));
            }
            out.extend(
                VARIANTS
                    .iter()
                    .filter(|v| **v != s)
                    .map(|v| Value::String(v.to_string())),
            );
            // Tags of enums whose other variants carry data.
            out.push(serde_json::json!({ "count": 1 }));
            out.push(serde_json::json!({ "PerFin": [] }));
            out.push(serde_json::json!({ "power": { "n": 0.5 } }));
            out
        }
        _ => unreachable!(),
    }
}

/// Walk every leaf of `value`, perturb it, rebuild the typed value and hand both the leaf
/// and the perturbed value to `check`. Fails if a leaf cannot be perturbed into a valid value.
fn walk<T: serde::Serialize + serde::de::DeserializeOwned>(
    value: &T,
    mut check: impl FnMut(&Leaf, &T),
) -> (usize, usize) {
    let scratch = tempfile::tempdir().unwrap();
    let plain = serde_json::to_value(value).unwrap();
    let marks = marked::to_value(value);
    let mut all = Vec::new();
    leaves(&plain, &marks, &mut Vec::new(), false, &mut all);
    let mut stuck = Vec::new();
    for leaf in &all {
        let mut done = false;
        for p in perturbations(at(&mut plain.clone(), &leaf.path), scratch.path()) {
            let mut j = plain.clone();
            *at(&mut j, &leaf.path) = p;
            if let Ok(t) = serde_json::from_value::<T>(j) {
                check(leaf, &t);
                done = true;
                break;
            }
        }
        if !done {
            stuck.push(leaf.path.clone());
        }
    }
    assert!(
        stuck.is_empty(),
        "leaves that could not be perturbed: {stuck:?}"
    );
    let positions = all.iter().filter(|l| l.position).count();
    (all.len() - positions, positions)
}

fn top(leaf: &Leaf) -> &str {
    match leaf.path.first() {
        Some(Seg::Key(k)) => k,
        _ => "",
    }
}

fn path_text(leaf: &Leaf) -> String {
    leaf.path
        .iter()
        .map(|s| match s {
            Seg::Key(k) => k.clone(),
            Seg::Index(i) => i.to_string(),
        })
        .collect::<Vec<_>>()
        .join(".")
}

/// The property on one vehicle: structural leaves change the key, positions and the
/// aerodynamics and force blocks do not. Returns (structural, non-structural, positions).
fn key_property(v: &Vehicle) -> (usize, usize, usize) {
    let base = cache_key(v).unwrap();
    let (mut structural, mut other) = (0, 0);
    let mut wrong = Vec::new();
    let counts = walk(v, |leaf, t| {
        let changed = cache_key(t).unwrap() != base;
        let expect = !leaf.position && !matches!(top(leaf), "aero" | "forces");
        if !leaf.position {
            if expect {
                structural += 1;
            } else {
                other += 1;
            }
        }
        if changed != expect {
            wrong.push(format!(
                "{} ({}): key {}",
                path_text(leaf),
                if leaf.position { "position" } else { "value" },
                if changed { "changed" } else { "unchanged" }
            ));
        }
    });
    assert!(
        wrong.is_empty(),
        "{} wrong leaves:\n{}",
        wrong.len(),
        wrong.join("\n")
    );
    (structural, other, counts.1)
}

fn vehicle_of(file: &Path) -> Vehicle {
    let checked = check_files(&[file.to_path_buf()], &[], &DiskLoader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    checked.program.vehicles[0].clone()
}

#[test]
fn every_structural_leaf_of_sphads1_changes_the_cache_key_and_nothing_else_does() {
    let v = vehicle_of(&root("vehicles/sphads1.vdl"));
    let (s, o, p) = key_property(&v);
    eprintln!("sphads1: {s} structural leaves, {o} non-structural, {p} position leaves");
    // The fin span and the fin key node's span fraction are among the structural leaves.
    // 62, 12 and 27 today.
    assert!(s >= 60 && o >= 10 && p >= 25, "{s} {o} {p}");
}

/// tube21 read from the shared Matrix Market sample (files referenced by the vehicle).
const TUBE_VEHICLE: &str = r#"
import "std/materials.vdl"

vehicle tube21 {
  material = aluminium_thesis
  origin = node(1)
  structure {
    files {
      format = matrix_market
      mass = "TUBE/mass.mtx"
      stiffness = "TUBE/stiffness.mtx"
      nodes = "TUBE/nodes.csv"
      coordinates_unit = m
    }
  }
  key_nodes {
    body = node(11)
    nozzle = nearest((-2.75, 0, 0) m)
  }
  modes {
    body_bending = 4
    damping = [0.01, 0.02, 0.03, 0.04]
  }
  aero {
    source = builtin
    reference_area = 0.012668 m^2
    reference_length = 127 mm
    reference_point = (-1.375, 0, 0) m
  }
  forces {
    gravity {}
  }
}
"#;

#[test]
fn every_structural_leaf_of_an_imported_fe_vehicle_changes_the_cache_key() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("tube.vdl");
    std::fs::write(&file, TUBE_VEHICLE.replace("TUBE", TUBE)).unwrap();
    let v = vehicle_of(&file);
    let (s, o, p) = key_property(&v);
    eprintln!("tube21: {s} structural leaves, {o} non-structural, {p} position leaves");
    assert!(s > 10 && o > 3 && p > 10, "{s} {o} {p}");
    // The bytes of a referenced file are part of the key too.
    let copy = dir.path().join("k.mtx");
    let text = std::fs::read_to_string(Path::new(TUBE).join("stiffness.mtx")).unwrap();
    std::fs::write(&copy, text.replacen("E8", "E9", 1)).unwrap();
    let base = cache_key(&v).unwrap();
    let mut edited = v.clone();
    let flexflight::check::ir::Structure::Files(f) = &mut edited.structure else {
        panic!()
    };
    f.stiffness.value = copy.clone();
    let before = cache_key(&edited).unwrap();
    assert_ne!(base, before);
    std::fs::write(&copy, text).unwrap();
    assert_ne!(cache_key(&edited).unwrap(), before);
}

const SCENARIO: &str = r#"
import "VEHICLE"

scenario s {
  vehicle = sphads1
  with {
    forces.gravity.enabled = false
    fins.thickness = 0.7 mm
  }
  initial {
    velocity = (20, 10, 6) m/s
    angular_velocity = (6, 6, 6) rad/s
    attitude = euler(1 deg, 2 deg, 3 deg)
    altitude = 5 km
  }
  stimuli {
    gust first {
      start = 0.01 s
      duration = 0.01 s
      velocity = (0, 0, 5) m/s
      frame = body
    }
  }
  run {
    stop_time = 0.2 s
    stop_on_ground = false
  }
}
"#;

fn scenario_file(dir: &Path) -> PathBuf {
    let file = dir.join("s.vdl");
    let vehicle = root("vehicles/sphads1.vdl");
    std::fs::write(
        &file,
        SCENARIO.replace("VEHICLE", &vehicle.display().to_string()),
    )
    .unwrap();
    file
}

fn scenario(file: &Path, sets: &[String]) -> Scenario {
    let checked = check_scenario_files(&[file.to_path_buf()], sets, "s", &DiskLoader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    checked.program.scenario("s").unwrap().clone()
}

/// The sweep's fingerprints: the variant changes with every leaf of the scenario, the
/// vehicle fingerprint with every leaf of its vehicle, the key with every structural leaf;
/// no position changes any of them.
#[test]
fn sweep_fingerprints_change_with_exactly_what_they_cover() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scenario(&scenario_file(dir.path()), &[]);
    let (key, variant, vehicle) = case_fingerprints(&sc).unwrap();
    let mut wrong = Vec::new();
    let (values, positions) = walk(&sc, |leaf, t| {
        let (k, va, ve) = case_fingerprints(t).unwrap();
        let in_vehicle = top(leaf) == "vehicle";
        let structural = in_vehicle
            && !matches!(
                leaf.path.get(1),
                Some(Seg::Key(k)) if k == "aero" || k == "forces"
            );
        let p = !leaf.position;
        let got = (k != key, va != variant, ve != vehicle);
        let want = (p && structural, p, p && in_vehicle);
        if got != want {
            wrong.push(format!("{}: {got:?}, expected {want:?}", path_text(leaf)));
        }
    });
    eprintln!("scenario: {values} value leaves, {positions} position leaves");
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    // 103 and 39 today.
    assert!(values >= 100 && positions >= 35, "{values} {positions}");
}

/// A sweep over the fin span: every case is its own structural variant, variant and vehicle.
#[test]
fn a_sweep_over_fin_span_gives_distinct_variants() {
    let dir = tempfile::tempdir().unwrap();
    let file = scenario_file(dir.path());
    let mut seen = Vec::new();
    for span in ["120 mm", "240 mm", "12 m"] {
        let sc = scenario(&file, &[format!("fins.span={span}")]);
        let f = case_fingerprints(&sc).unwrap();
        for other in &seen {
            let (k, va, ve): &(_, String, String) = other;
            assert!(*k != f.0 && *va != f.1 && *ve != f.2, "span {span}");
        }
        seen.push(f);
    }
    // And the fin key node's span fraction.
    let a = case_fingerprints(&scenario(&file, &[])).unwrap();
    let b = case_fingerprints(&scenario(
        &file,
        &["key_nodes.fins=fin_point(span = 0.75, chord = 0.25)".into()],
    ))
    .unwrap();
    assert_ne!(a.0, b.0);
}

/// Moving text around (a comment line before everything) moves every position and changes
/// no fingerprint.
#[test]
fn moved_text_keeps_every_fingerprint() {
    let dir = tempfile::tempdir().unwrap();
    let file = scenario_file(dir.path());
    let sa = scenario(&file, &[]);
    let a = case_fingerprints(&sa).unwrap();
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(&file, format!("# moved\n\n{text}")).unwrap();
    let sb = scenario(&file, &[]);
    let b = case_fingerprints(&sb).unwrap();
    assert_eq!(a, b);
    // The aerodynamic cache key (structural key + whole vehicle, with the scenario's `with`
    // overrides, whose positions moved) too; it changes with a value outside the structure.
    let aero = |sc: &Scenario| flexflight::ops::compile::aero_cache_key(&sc.vehicle, &a.0).unwrap();
    assert_eq!(aero(&sa), aero(&sb));
    let other = scenario(&file, &["aero.reference_length=128 mm".into()]);
    assert_ne!(aero(&sa), aero(&other));
}
