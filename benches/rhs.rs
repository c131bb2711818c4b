//! Right-hand side of the equations of motion (3.2.1) for SPHADS-1 with its 10 modes
//! (free flight and uniform gravity; the aerodynamic force blocks are benchmarked once they
//! are wired into the plan). The RHS must not allocate: it runs on a workspace made once.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use flexflight::check::{DiskLoader, check_files};
use flexflight::runtime::eom::{Eom, FreeFlight, UniformGravity};
use flexflight::runtime::integrate::OdeSystem;
use flexflight::structure::compile::compile;

fn bench_rhs(c: &mut Criterion) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("vehicles/sphads1.vdl");
    let checked = check_files(&[root], &[], &DiskLoader);
    let (compiled, _) = compile(&checked.program.vehicles[0]).expect("compiles");
    let model = &compiled.reduced;
    let eta: Vec<f64> = (0..model.n()).map(|k| 1e-4 * (k as f64 + 1.0)).collect();
    let eta_dot: Vec<f64> = (0..model.n()).map(|k| 1e-2 * (k as f64 - 3.0)).collect();

    let mut free = Eom::new(model, FreeFlight).expect("eom");
    let x = free.layout().state(
        [0.0, 0.0, -5000.0],
        [0.0, 0.0, 0.0, 1.0],
        [200.0, 1.0, 2.0],
        [0.1, 0.2, 0.3],
        &eta,
        &eta_dot,
    );
    let mut dx = vec![0.0; x.len()];
    c.bench_function("rhs sphads1 10 modes, free flight", |b| {
        b.iter(|| free.rhs(0.0, black_box(&x), &mut dx).map(|_| dx[7]))
    });
    let mut grav = Eom::new(model, UniformGravity::new(model, [0.0, 0.0, 9.806])).expect("eom");
    c.bench_function("rhs sphads1 10 modes, gravity", |b| {
        b.iter(|| grav.rhs(0.0, black_box(&x), &mut dx).map(|_| dx[7]))
    });
}

criterion_group!(benches, bench_rhs);
criterion_main!(benches);
