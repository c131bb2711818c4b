//! Sweep throughput in cases per second with 1 and 2 worker threads: eight 0.2 s free-tumble
//! cases of SPHADS-1 (one structural variant, compiled into the cache before timing), each
//! writing its history, summary and identification. Every iteration writes into a fresh
//! directory, so nothing is resumed.

use std::path::PathBuf;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use flexflight::analysis::sweep::Shard;
use flexflight::check::{DiskLoader, check_files};
use flexflight::ops::sweep::{SweepOptions, run_sweep};

const FILE: &str = r#"
import "VEHICLE"

scenario tumble {
  vehicle = sphads1
  with {
    forces.gravity.enabled = false
    forces.body_aero.enabled = false
    forces.fin_aero.enabled = false
  }
  initial {
    velocity = (20, 10, 6) m/s
    angular_velocity = (6, 6, 6) rad/s
    attitude = euler(0 deg, 0 deg, 0 deg)
    altitude = 5 km
  }
  stimuli {
    gust first {
      start = 0.01 s
      duration = 0.01 s
      velocity = (0, 0, 5) m/s
      frame = body
    }
  }
  run {
    stop_time = 0.2 s
    integrator = dopri5
    rtol = 1e-6
    atol = 1e-9
    output_interval = 1 ms
    stop_on_ground = false
  }
}

sweep eight {
  scenario = tumble
  grid {
    initial.altitude = range(1 km, 8 km, count = 8)
  }
}
"#;

fn bench_sweep(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("tempdir");
    let vehicle = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("vehicles/sphads1.vdl");
    let file = dir.path().join("sweep.vdl");
    std::fs::write(
        &file,
        FILE.replace("VEHICLE", &vehicle.display().to_string()),
    )
    .expect("write");
    let checked = check_files(std::slice::from_ref(&file), &[], &DiskLoader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    let sweep = checked.program.sweep("eight").expect("sweep").clone();
    let opts = |jobs| SweepOptions {
        jobs,
        shard: Shard::ALL,
        cache_dir: Some(dir.path().join("cache")),
        sets: Vec::new(),
        progress: None,
    };
    // Warm the cache: the timed sweeps only load the artifact.
    run_sweep(&file, &sweep, "tumble", &dir.path().join("warm"), &opts(1)).expect("sweep");

    let mut group = c.benchmark_group("sweep");
    group.sample_size(10);
    group.throughput(Throughput::Elements(sweep.case_count() as u64));
    let mut k = 0;
    for jobs in [1, 2] {
        group.bench_function(format!("8 free-tumble cases, {jobs} thread(s)"), |b| {
            b.iter(|| {
                k += 1;
                let out = dir.path().join(format!("out{k}"));
                let r = run_sweep(&file, &sweep, "tumble", &out, &opts(jobs)).expect("sweep");
                assert_eq!((r.ran, r.failed), (8, 0));
            })
        });
    }
    group.finish();
}

// No plots: criterion's plotters backend finds no system font on a bare machine.
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = bench_sweep
}
criterion_main!(benches);
