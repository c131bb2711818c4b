//! The cache key of a vehicle's aerodynamics (issue 11, lever 1): it changes with every
//! vehicle input the estimated tables or the fin load weights depend on, and not with the
//! scenario (speed, stop time, stimuli), so cases of a sweep share one artifact.

use std::path::{Path, PathBuf};

fn thesis() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/thesis/section_6_5.vdl")
}

#[test]
fn the_aero_key_follows_the_vehicle_and_not_the_scenario() {
    let key = |sets: &[&str]| {
        let checked = flexflight::check::check_scenario_files(
            &[thesis()],
            &sets.iter().map(|s| s.to_string()).collect::<Vec<_>>(),
            "subsonic_t06",
            &flexflight::check::DiskLoader,
        );
        assert!(!checked.has_errors(), "{sets:?}: {:?}", checked.diagnostics);
        let sc = checked.program.scenario("subsonic_t06").unwrap().clone();
        let structural = flexflight::ops::compile::cache_key(&sc.vehicle).unwrap();
        flexflight::ops::compile::aero_cache_key(&sc.vehicle, &structural).unwrap()
    };
    let base = key(&[]);
    assert_eq!(base, key(&[]), "the key is deterministic");
    // Scenario inputs: the vehicle's aerodynamics do not depend on them.
    for s in [
        "initial.velocity=(150, 0, 0) m/s",
        "run.stop_time=1 s",
        "stimuli.first.start=2 s",
    ] {
        assert_eq!(key(&[s]), base, "{s} changed the aero key");
    }
    // Vehicle inputs the tables or the load weights depend on.
    for s in [
        "aero.reference_point=(-1.5, 0, 0) m",
        "aero.out_of_range=clamp",
        "aero.finish=smooth_paint",
        "aero.finish=20 um",
        "forces.fin_aero.distribution=uniform",
        "fins.root_chord=0.3 m",
        "structure.generate.body.diameter=130 mm",
    ] {
        assert_ne!(key(&[s]), base, "{s} did not change the aero key");
    }
}
