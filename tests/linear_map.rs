//! The fin thickness x Mach map of the linearised model: the thickness override reaches
//! the FE model (fin modes scale with thickness), the grid is complete, and repeated
//! thicknesses come from the artifact cache.

use std::path::PathBuf;

use flexflight::analysis::linear::linear_map;
use flexflight::analysis::linearise::LineariseOptions;
use flexflight::ops::linear::load_variant;

fn file() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/thesis/section_6_5.vdl")
}

#[test]
fn thickness_changes_the_fe_model_and_the_map_is_complete() {
    let cache = tempfile::tempdir().unwrap();
    let mut loads = Vec::new();
    let load = |t: f64| {
        loads.push(t);
        let sets = vec![format!("fins.thickness={} mm", t * 1e3)];
        load_variant(
            &file(),
            "subsonic_t06",
            &sets,
            Some(cache.path()),
            &mut |_| {},
        )
    };
    let ts = [0.4e-3, 0.8e-3];
    let ms = [0.5, 0.6, 0.7];
    let r = linear_map(&ts, &ms, load, LineariseOptions::default()).unwrap();
    assert_eq!(loads, ts.to_vec());
    assert_eq!(r.map.xs, ts.to_vec());
    assert_eq!(r.map.ys, ms.to_vec());
    assert_eq!(r.map.sigma.len(), 6);
    assert!(r.map.sigma.iter().all(|s| s.is_finite()));
    assert!((r.altitude - 5000.0).abs() < 1e-9);

    // A fin plate's flap frequency scales with its thickness (stiffness t³, mass t): the
    // override must reach the FE model, not only the aerodynamics.
    let flap = |t: f64| {
        let sets = vec![format!("fins.thickness={} mm", t * 1e3)];
        let v = load_variant(
            &file(),
            "subsonic_t06",
            &sets,
            Some(cache.path()),
            &mut |_| {},
        )
        .unwrap();
        v.compiled
            .modes
            .iter()
            .find(|m| m.class == "fin_flap")
            .unwrap()
            .frequency_hz
    };
    let (f4, f8) = (flap(0.4e-3), flap(0.8e-3));
    eprintln!(
        "fin flap: {f4} Hz at 0.4 mm, {f8} Hz at 0.8 mm, ratio {}",
        f8 / f4
    );
    assert!((f8 / f4 - 2.0).abs() < 0.1, "{}", f8 / f4);
    // Both thicknesses are in the cache now: a second map compiles nothing.
    let entries = std::fs::read_dir(cache.path()).unwrap().count();
    let r2 = linear_map(
        &ts,
        &ms,
        |t: f64| {
            let sets = vec![format!("fins.thickness={} mm", t * 1e3)];
            load_variant(
                &file(),
                "subsonic_t06",
                &sets,
                Some(cache.path()),
                &mut |_| {},
            )
        },
        LineariseOptions::default(),
    )
    .unwrap();
    assert_eq!(std::fs::read_dir(cache.path()).unwrap().count(), entries);
    assert_eq!(r2, r, "the map is deterministic");
}
