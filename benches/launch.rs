//! The launch of `examples/hpr_k1000` (K1000T motor component, 3 m rail at 85 deg, flexible
//! body and fins, built-in aerodynamics, wind) from the pad to t = 30 s (apogee at 21.7 s,
//! the drogue from 22.7 s): issue 10's performance target, "a 30 s launch-to-apogee flight
//! of the example with flexible fins well under a second". The figure is quoted in
//! docs/performance.md with its steps and right-hand-side evaluations.

use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use flexflight::check::{DiskLoader, check_files};
use flexflight::run::run;
use flexflight::structure::compile::compile;

fn bench_launch(c: &mut Criterion) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/hpr_k1000/hpr_k1000.vdl");
    let checked = check_files(&[root], &["run.stop_time=30 s".to_string()], &DiskLoader);
    let sc = checked.program.scenario("k1000").expect("scenario").clone();
    let (compiled, _) = compile(&sc.vehicle).expect("compiles");
    // The plan (aero tables, fin load weights) is built once, outside the timing.
    let plan = flexflight::plan::build(&sc, &compiled).expect("plan");
    let once = || run(&plan, &compiled.reduced, &mut |_, _| {}).expect("runs");
    let o = once();
    eprintln!(
        "k1000 launch to 30 s: stop {} at t = {:.4} s, {} steps, {} rejected, {} RHS evaluations",
        o.stop.code(),
        o.t_end,
        o.stats.accepted,
        o.stats.rejected,
        o.stats.rhs_evaluations
    );
    c.bench_function("k1000 launch, pad to 30 s", |b| b.iter(once));
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench_launch
}
criterion_main!(benches);
