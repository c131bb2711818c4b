//! Whole flights of the subsonic thesis scenario (200 m/s at 5 km, rtol 1e-6, every force
//! block of the plan, 1 ms output): with the scenario's 0.6 mm fins (our model flutters and
//! the run stops at the fin stress limit) and with 1.0 mm fins over the full 10 s. Its last
//! figures (25 November, before the right-hand-side and integrator work) are in the git
//! history of docs/performance.md, which today quotes the same flights as whole processes.

use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use flexflight::check::{DiskLoader, check_files};
use flexflight::run::run;
use flexflight::structure::compile::compile;

fn flight(c: &mut Criterion, label: &str, sets: &[String]) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/thesis/section_6_5.vdl");
    let checked = check_files(&[root], sets, &DiskLoader);
    let sc = checked
        .program
        .scenario("subsonic_t06")
        .expect("scenario")
        .clone();
    let (compiled, _) = compile(&sc.vehicle).expect("compiles");
    // The plan (with the aero blocks: estimated tables, fin load weights) is built once,
    // outside the timing.
    let plan = flexflight::plan::build(&sc, &compiled).expect("plan");
    let once = || run(&plan, &compiled.reduced, &mut |_, _| {}).expect("runs");
    let o = once();
    eprintln!(
        "{label}: stop {} at t = {:.4} s, {} steps, {} rejected, {} RHS evaluations",
        o.stop.code(),
        o.t_end,
        o.stats.accepted,
        o.stats.rejected,
        o.stats.rhs_evaluations
    );
    c.bench_function(label, |b| b.iter(once));
}

fn bench_flights(c: &mut Criterion) {
    flight(c, "subsonic_t06 as written (0.6 mm fins)", &[]);
    flight(
        c,
        "subsonic_t06 with 1.0 mm fins, 10 s",
        &["fins.thickness=1.0 mm".to_string()],
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench_flights
}
criterion_main!(benches);
