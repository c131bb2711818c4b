//! Snapshots of the checked IR: SPHADS-1 as declared, and the thesis scenario subsonic_t04
//! (SPHADS-1 with 0.4 mm fins). JSON, spans removed, numbers to 8 significant digits.

mod common;

use flexflight::check::{DiskLoader, check_files};
use flexflight::diagnostics::{RenderOptions, render};

fn checked_json(rel: &str) -> serde_json::Value {
    let path = common::root().join(rel);
    let checked = check_files(&[path], &[], &DiskLoader);
    assert!(
        checked.diagnostics.is_empty(),
        "{rel}:\n{}",
        render(
            &checked.diagnostics,
            &checked.sources,
            RenderOptions::plain(100)
        )
    );
    let mut v = common::program_json(&checked.program);
    common::strip_spans(&mut v);
    common::replace_paths(&mut v, &common::root(), "$ROOT");
    common::round_numbers(&mut v);
    v
}

#[test]
fn sig8_formatting() {
    assert_eq!(common::sig8(0.0), "0");
    assert_eq!(common::sig8(2710.0), "2710");
    assert_eq!(common::sig8(0.346), "0.346");
    assert_eq!(common::sig8(0.1 + 0.2), "0.3");
    assert_eq!(common::sig8(7.0e10), "7.0000000e10");
    assert_eq!(common::sig8(-1.59), "-1.59");
    assert_eq!(common::sig8(std::f64::consts::PI), "3.1415927");
    assert_eq!(common::sig8(1.2345678912e-6), "1.2345679e-6");
}

#[test]
fn sphads1_ir() {
    let v = checked_json("vehicles/sphads1.vdl");
    let vehicles = v["vehicles"].as_array().expect("vehicles");
    assert_eq!(vehicles.len(), 1);
    // Spot checks independent of the snapshot: SI units.
    let fins = &vehicles[0]["fins"];
    assert_eq!(fins["thickness"], "0.0006");
    assert_eq!(fins["count"], "4");
    assert_eq!(fins["span"], "0.12723");
    assert_eq!(vehicles[0]["key_nodes"]["fins"]["Fraction"]["span"], "0.5");
    // No span survived: no `[file, start, end]` triple under a span key.
    assert!(
        !serde_json::to_string(&v)
            .expect("json")
            .contains("\"header\"")
    );
    insta::assert_snapshot!(
        "sphads1",
        serde_json::to_string_pretty(&vehicles[0]).expect("json")
    );
}

#[test]
fn subsonic_t04_ir() {
    let v = checked_json("examples/thesis/section_6_5.vdl");
    let scenario = v["scenarios"]
        .as_array()
        .expect("scenarios")
        .iter()
        .find(|s| s["name"] == "subsonic_t04")
        .expect("subsonic_t04")
        .clone();
    // The `with` override reached the vehicle variant, in SI.
    assert_eq!(scenario["vehicle"]["fins"]["thickness"], "0.0004");
    insta::assert_snapshot!(
        "subsonic_t04",
        serde_json::to_string_pretty(&scenario).expect("json")
    );
}
