//! `fin_aero { model = key_node | lifting_surface }` (issue 12, deliverables 4-6): the key-node
//! model's histories are those of before the panel model existed; the lifting-surface model
//! does not depend on `key_nodes.fins` (flight and linearised roots); both agree in the
//! rigid-fin limit.

use std::path::{Path, PathBuf};

use flexflight::analysis::linear::Variant;

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// The checked scenario `scenario` of the thesis 6.5 file with `sets`, compiled and planned.
fn variant(scenario: &str, sets: &[&str]) -> Variant {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let checked = flexflight::check::check_files(
        &[repo("examples/thesis/section_6_5.vdl")],
        &sets,
        &flexflight::check::DiskLoader,
    );
    assert!(
        checked.diagnostics.is_empty(),
        "{:?}",
        checked.diagnostics
    );
    let scenario = checked
        .program
        .scenario(scenario)
        .cloned()
        .expect("scenario");
    let compiled = flexflight::structure::compile::compile(&scenario.vehicle)
        .unwrap()
        .0;
    let plan = flexflight::plan::build(&scenario, &compiled).unwrap();
    Variant {
        plan,
        scenario,
        compiled,
    }
}

/// The history rows of a run of `v`.
fn history(v: &Variant) -> Vec<Vec<f64>> {
    flexflight::runtime::run::run(&v.plan, &v.compiled.reduced, &mut |_, _| {})
        .unwrap()
        .rows
}

/// blake3 of the rows' bits.
fn digest(rows: &[Vec<f64>]) -> String {
    let mut h = blake3::Hasher::new();
    for r in rows {
        for x in r {
            h.update(&x.to_bits().to_le_bytes());
        }
    }
    h.finalize().to_hex().to_string()
}

/// The thesis' key-node model flies bit for bit as it did before the lifting-surface model
/// existed: the digest was recorded on commit f68d3e8 (before `fin_aero.model`), 0.6 mm fins
/// through the first gust (1.2 s), with the vehicle's key-node settings.
#[test]
fn key_node_history_is_unchanged() {
    let v = variant("subsonic_t06", &["run.stop_time=1.2s"]);
    let rows = history(&v);
    let d = digest(&rows);
    eprintln!("rows {} digest {d}", rows.len());
    assert_eq!(d, "dfea711f61c8c1881a4ffce892ce9afe4da48c1247ec33424ec952e4eb144b10");
}
