//! The clamped SPHADS-1 fin's flutter solution (issue 13): 10 modes, 20 reduced frequencies,
//! 40 speeds, at 200 m/s' Mach (0.624) at 5 km with the 0.875 mm fin (docs/validation.md's case):
//! the p-k solution alone on a prebuilt GAF table (target: under 1 s), and the GAF table
//! build alone, with the unsteady panels (harmonic vortex lattice, `analyze flutter`'s
//! default; as many chordwise panels as the box-size rule needs at the lowest speed) and the
//! quasi-steady ones. Also the flight margin's cached boundary read back (a warm run's cost).

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use flexflight::aero::atmosphere::{Atmosphere, Standard1976};
use flexflight::aero::estimator::ESTIMATOR_MACH;
use flexflight::analysis::flutter::fin::{
    FinAero, FinFlutterSettings, chordwise_for, clamped_fin_modes, fin_lattice, flutter_model,
    gaf_table,
};
use flexflight::analysis::flutter::pk::{PkSettings, pk_solve_cut};
use flexflight::artifact::Cache;
use flexflight::check::{DiskLoader, check_files};
use flexflight::ops::flutter::{cached_boundary, margin_spec};

fn bench_flutter(c: &mut Criterion) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/thesis/section_6_5.vdl");
    let sets = vec!["fins.thickness=0.875 mm".to_string()];
    let checked = check_files(&[root], &sets, &DiskLoader);
    assert!(!checked.has_errors());
    let sc = checked.program.scenario("subsonic_t06").expect("scenario");
    let v = &sc.vehicle;
    let modes = clamped_fin_modes(v, 10).expect("10 clamped modes");
    let air = Standard1976::new().at(5000.0).expect("5 km");
    let mach = 200.0 / air.speed_of_sound;
    let (lo, hi) = (0.3 * air.speed_of_sound, 3.0 * air.speed_of_sound);
    let speeds: Vec<f64> = (0..40).map(|i| lo + (hi - lo) * i as f64 / 39.0).collect();
    let w_max = modes.omega.iter().copied().fold(0.0, f64::max);
    let model = flutter_model(&modes, air.density);
    for aero in [FinAero::Unsteady, FinAero::QuasiSteady] {
        let mut s = FinFlutterSettings {
            aero,
            k_count: 20,
            ..FinFlutterSettings::default()
        };
        s.k_max = 1.2 * w_max * modes.b_ref() / lo;
        if aero == FinAero::Unsteady {
            s.chordwise = chordwise_for(&modes, s.k_max, s.chordwise);
        }
        let lattice = fin_lattice(&modes, &s).expect("lattice");
        let name = aero.name();
        eprintln!(
            "{name}: {} x {} panels, k up to {:.3}",
            s.chordwise, s.spanwise, s.k_max
        );
        c.bench_function(
            &format!("gaf table sphads1 clamped fin, 10 modes, 20 k, {name}"),
            |b| b.iter(|| gaf_table(&modes, &lattice, black_box(mach), &s).expect("gaf")),
        );
        let gaf = gaf_table(&modes, &lattice, mach, &s).expect("gaf");
        let (sol, cut) = pk_solve_cut(&model, &gaf, &speeds, PkSettings::default()).expect("p-k");
        eprintln!(
            "{name}: flutter {:?} m/s, cut {cut:?}",
            sol.critical().map(|f| f.speed)
        );
        c.bench_function(
            &format!("p-k sphads1 clamped fin, 10 modes, 20 k, 40 speeds, {name}"),
            |b| {
                b.iter(|| {
                    pk_solve_cut(&model, &gaf, black_box(&speeds), PkSettings::default())
                        .expect("p-k")
                })
            },
        );
    }
    // The flight margin's boundary read back from the cache (what a warm run pays).
    let dir = tempfile::tempdir().expect("tempdir");
    let cache = Cache::new(dir.path());
    let hpr = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/hpr_k1000/hpr_k1000.vdl");
    let checked = check_files(&[hpr], &[], &DiskLoader);
    let sc = checked.program.scenario("k1000").expect("scenario");
    let spec = margin_spec(sc, &ESTIMATOR_MACH).expect("spec");
    cached_boundary(&sc.vehicle, &spec, &cache).expect("cold boundary");
    c.bench_function("flight margin boundary, hpr_k1000, cache hit", |b| {
        b.iter(|| {
            let r = cached_boundary(&sc.vehicle, black_box(&spec), &cache).expect("boundary");
            assert!(r.outcome.is_hit());
            r
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench_flutter
}
criterion_main!(benches);
