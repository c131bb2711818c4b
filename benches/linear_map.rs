//! The linearised 3-D stability map of issue #5 (target: 20 x 20 points where fin
//! thickness changes the FE model, under 60 s on a 2-core machine).
//!
//! Four figures: one linear analysis (trim, Jacobian, eigen-structure with participation
//! factors) of SPHADS-1 at the subsonic thesis condition, with and without building the
//! force blocks (the aerodynamic tables are estimated then); the full 20 x 20 map with every
//! thickness already in the artifact cache (check + cache load per thickness, 400
//! linearisations); and a 4 x 20 map with a fresh, empty cache on every iteration (4
//! structural compilations). A cold 20 x 20 map costs about the warm 20 x 20 figure plus
//! five times the compile part of the cold 4 x 20 figure (thicknesses compile
//! independently, one after the other).

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use flexflight::analysis::linear::{analyse, analyse_with, linear_map, linearizer, plan_gravity};
use flexflight::analysis::linearise::LineariseOptions;
use flexflight::ops::linear::load_variant;

fn thicknesses(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| 0.3e-3 + 0.7e-3 * k as f64 / (n - 1) as f64)
        .collect()
}

fn machs(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| 0.3 + 2.0 * k as f64 / (n - 1) as f64)
        .collect()
}

fn bench_linear_map(c: &mut Criterion) {
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/thesis/section_6_5.vdl");
    let warm = tempfile::tempdir().expect("tempdir");
    let load = |dir: PathBuf| {
        let file = file.clone();
        move |t: f64| {
            let sets = vec![format!("fins.thickness={} mm", t * 1e3)];
            load_variant(&file, "subsonic_t06", &sets, Some(&dir), &mut |_| {})
        }
    };
    let options = LineariseOptions::default();

    let variant = load(warm.path().to_path_buf())(0.6e-3).expect("variant");
    c.bench_function(
        "linear analysis sphads1 subsonic_t06, with force-block setup",
        |b| b.iter(|| analyse(black_box(&variant), options).map(|r| r.eigen.sigma_d)),
    );
    let mut lin = linearizer(&variant, options).expect("linearizer");
    let q0 = [0.0, 0.0, 0.0, 1.0];
    let g = plan_gravity(&variant.plan, 5000.0);
    c.bench_function(
        "linear analysis sphads1 at 200 m/s, 5 km (trim, Jacobian, eigen)",
        |b| {
            b.iter(|| {
                analyse_with(&mut lin, black_box(200.0), 5000.0, q0, g, options)
                    .map(|r| r.eigen.sigma_d)
            })
        },
    );

    let (ts, ms) = (thicknesses(20), machs(20));
    // Fill the cache once.
    linear_map(&ts, &ms, load(warm.path().to_path_buf()), options).expect("map");
    let mut group = c.benchmark_group("linear map");
    group.sample_size(10);
    group.bench_function("20 x 20, thicknesses cached", |b| {
        b.iter(|| {
            linear_map(&ts, &ms, load(warm.path().to_path_buf()), options)
                .map(|m| m.map.sigma.len())
        })
    });
    let ts4 = thicknesses(4);
    group.bench_function("4 x 20, empty cache (4 compilations)", |b| {
        b.iter(|| {
            let cold = tempfile::tempdir().expect("tempdir");
            linear_map(&ts4, &ms, load(cold.path().to_path_buf()), options)
                .map(|m| m.map.sigma.len())
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    // No plots: the plotters backend needs system fonts, absent on a bare machine.
    config = Criterion::default().without_plots();
    targets = bench_linear_map
}
criterion_main!(benches);
