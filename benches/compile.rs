//! Structural compiler speed: SPHADS-1 from scratch (target < 2 s), a cache hit (< 20 ms),
//! and how compile time grows with the number of DOF (the sparse path at ~5k, ~25k, ~98k DOF;
//! target: 100,000 DOF in < 60 s and < 4 GB).

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use flexflight::artifact::Cache;
use flexflight::check::{DiskLoader, check_files};
use flexflight::ops::compile::cache_key;
use flexflight::structure::compile::{CompiledVehicle, compile};

fn sphads1(sets: &[String]) -> flexflight::check::ir::Vehicle {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("vehicles/sphads1.vdl");
    let checked = check_files(&[root], sets, &DiskLoader);
    assert!(!checked.has_errors());
    checked.program.vehicles[0].clone()
}

fn bench_compile(c: &mut Criterion) {
    let v = sphads1(&[]);
    let mut g = c.benchmark_group("compile");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    g.bench_function("sphads1 from scratch", |b| {
        b.iter(|| compile(black_box(&v)).map(|r| r.0.modes.len()))
    });
    let dir = tempfile::tempdir().expect("temp dir");
    let cache = Cache::new(dir.path().to_path_buf());
    let key = cache_key(&v).expect("key");
    cache
        .get_or_build(&key, || compile(&v).map(|r| r.0))
        .expect("first build");
    g.bench_function("sphads1 cache hit (key + load + validate)", |b| {
        b.iter(|| {
            let key = cache_key(black_box(&v)).expect("key");
            let (art, outcome) = cache
                .get_or_build::<CompiledVehicle, flexflight::structure::compile::StructureError>(
                    &key,
                    || unreachable!("the artifact is cached"),
                )
                .expect("hit");
            assert!(matches!(outcome, flexflight::artifact::CacheOutcome::Hit));
            art.get().modes.len()
        })
    });
    g.finish();

    let mut g = c.benchmark_group("compile scaling");
    g.sample_size(10).measurement_time(Duration::from_secs(30));
    for (span, chord) in [(10, 20), (25, 40), (50, 80)] {
        let v = sphads1(&[
            format!("structure.generate.fin_mesh.span_elements={span}"),
            format!("structure.generate.fin_mesh.chord_elements={chord}"),
        ]);
        let model = flexflight::structure::compile::build_model(&v).expect("model");
        let dof = model.n_dof();
        g.bench_with_input(BenchmarkId::new("sphads1 DOF", dof), &v, |b, v| {
            b.iter(|| compile(black_box(v)).map(|r| r.0.modes.len()))
        });
    }
    g.finish();
}

/// The fin panel matrices of SPHADS-1 (issue 12): 4 fins, 8 x 12 lattice, on the 17 Machs of
/// the built-in fin table (target < 1 s).
fn bench_panels(c: &mut Criterion) {
    use flexflight::aero::estimator::ESTIMATOR_MACH;
    use flexflight::aero::panel::fin_model::{self, PanelSettings};
    let v = sphads1(&[]);
    let compiled = compile(&v).expect("compiles").0;
    let mut g = c.benchmark_group("fin panels");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    g.bench_function("sphads1 panel matrices, 17 Machs", |b| {
        b.iter(|| {
            fin_model::compile(
                black_box(&compiled),
                &v,
                &ESTIMATOR_MACH,
                PanelSettings::default(),
            )
            .map(|m| m.fins.len())
        })
    });
    g.finish();
}

criterion_group!(benches, bench_panels, bench_compile);
criterion_main!(benches);
