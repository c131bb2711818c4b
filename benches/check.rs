//! Front-end speed: checking SPHADS-1 with its imports (target < 5 ms) and a generated
//! 10,000-line vehicle file (target < 100 ms).

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use flexflight::check::{DiskLoader, MemoryLoader, check_files, check_source};

const TRAILER: &str = "    }\n  }\n  key_nodes {\n    body = nearest((-1.59, 0, 0) m)\n  }\n  modes {\n    body_bending = 2\n  }\n  aero {\n    source = builtin\n    reference_point = (-1.59, 0, 0) m\n  }\n  forces {\n    gravity {}\n  }\n}\n";

/// A vehicle file of about `lines` lines: SPHADS-1's shape with many point masses.
pub fn generated_vehicle(lines: usize) -> String {
    let mut s = String::from(
        "import \"std/materials.vdl\"\n\nvehicle big {\n  material = aluminium_thesis\n  origin = node(1)\n  structure {\n    generate {\n      body {\n        length = 2.75 m\n        diameter = 127 mm\n        wall = 3 mm\n        elements = 40\n      }\n",
    );
    let mut k = 0;
    let mut count = s.lines().count() + TRAILER.lines().count();
    while count < lines {
        count += 5;
        let x = -0.1 - 2.5 * (k as f64 / 2000.0).fract();
        s.push_str(&format!(
            "      point_mass m{k} {{\n        position = ({x:.4}, 0, 0) m\n        mass = 0.001 kg\n        inertia = (0, 0, 0) kg*m^2 # each block is six lines\n      }}\n"
        ));
        k += 1;
    }
    s.push_str(TRAILER);
    s
}

fn bench_check(c: &mut Criterion) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("vehicles/sphads1.vdl");
    c.bench_function("check sphads1 with imports", |b| {
        b.iter(|| {
            let checked = check_files(black_box(std::slice::from_ref(&root)), &[], &DiskLoader);
            assert!(!checked.has_errors());
            checked
        })
    });
    let text = generated_vehicle(10_000);
    assert!(text.lines().count() >= 10_000);
    let loader = MemoryLoader::default();
    c.bench_function("check generated 10k-line vehicle", |b| {
        b.iter(|| {
            let checked = check_source("big.vdl", black_box(&text), &loader);
            assert!(!checked.has_errors(), "{:?}", checked.diagnostics.first());
            checked
        })
    });
}

criterion_group!(benches, bench_check);
criterion_main!(benches);
