//! A 50 x 50 planar stability map of SPHADS-1 (fin thickness 0.1-1.5 mm x Mach 0.5-3):
//! the pinned model at 5 km, and the unpinned model with its equilibrium altitude solved at
//! every point. Target (issue #5): under 100 ms per map.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use flexflight::analysis::map::{GridRange, planar_map};
use flexflight::analysis::planar::{Altitude, PlanarKind, PlanarVehicle};
use flexflight::check::{DiskLoader, check_files};
use flexflight::structure::compile::compile;

fn bench_planar(c: &mut Criterion) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/thesis/section_6_5.vdl");
    let checked = check_files(&[root], &[], &DiskLoader);
    let sc = checked.program.scenario("subsonic_t06").expect("scenario");
    let (compiled, _) = compile(&sc.vehicle).expect("compiles");
    let v = PlanarVehicle::new(&sc.vehicle, &compiled).expect("planar vehicle");
    let ts = GridRange {
        start: 0.1e-3,
        stop: 1.5e-3,
        count: 50,
    }
    .values();
    let ms = GridRange {
        start: 0.5,
        stop: 3.0,
        count: 50,
    }
    .values();
    c.bench_function("planar pinned map 50x50, 5 km", |b| {
        b.iter(|| {
            planar_map(
                &v,
                PlanarKind::Pinned,
                black_box(&ts),
                &ms,
                Altitude::Fixed(5000.0),
            )
        })
    });
    c.bench_function("planar unpinned map 50x50, equilibrium altitude", |b| {
        b.iter(|| {
            planar_map(
                &v,
                PlanarKind::Unpinned,
                black_box(&ts),
                &ms,
                Altitude::Equilibrium,
            )
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).without_plots();
    targets = bench_planar
}
criterion_main!(benches);
