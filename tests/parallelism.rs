//! Determinism whatever the linear algebra's thread setting (issue 37): faer's dense kernels
//! (LU, Cholesky, eigen, products) read a process-wide parallelism whose default is "all of
//! rayon's threads", and their parallel blocking changes the last bits of a result, so the
//! same flutter analysis gave different bits on machines with different core counts, and in
//! one process before and after a flight (which set it sequential). The operations now run
//! faer sequentially whatever the caller set. One test in its own binary: it changes the
//! process-wide setting.

use std::path::{Path, PathBuf};

use faer::Par;
use flexflight::ops::Project;
use flexflight::ops::flutter::{AeroChoice, FlutterRequest, solve_request, summary_json};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn clamped_flutter() -> String {
    let cache = Path::new(env!("CARGO_TARGET_TMPDIR")).join("parallelism-cache");
    let mut p = Project::open(
        &[repo("examples/hpr_k1000/hpr_k1000.vdl")],
        &[],
        Some(&cache),
    )
    .map_err(|(e, _)| e)
    .unwrap();
    let req = FlutterRequest {
        clamped: true,
        altitude: Some(1000.0),
        mach: Some(0.5),
        speeds: Some((0..36).map(|i| 200.0 + 20.0 * i as f64).collect()),
        modes: None,
        aero: AeroChoice::Unsteady,
    };
    let r = solve_request(&mut p.checked, "k1000", &req, Some(&cache), &mut |_| {}).unwrap();
    let mut j = summary_json(&r);
    j.as_object_mut().unwrap().remove("gaf_cache");
    // Every number with all its bits: serde_json prints the shortest round-trip form.
    j.to_string()
}

#[test]
fn a_flutter_analysis_has_the_same_bits_whatever_faers_parallelism() {
    faer::set_global_parallelism(Par::rayon(2));
    let parallel = clamped_flutter();
    faer::set_global_parallelism(Par::Seq);
    let sequential = clamped_flutter();
    assert_eq!(parallel, sequential);
}
