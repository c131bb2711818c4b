//! Right-hand side of the equations of motion (3.2.1) for SPHADS-1 with its 10 modes
//! (free flight, uniform gravity, and the full force set of the subsonic thesis scenario with
//! distributed fin loads). The RHS must not allocate: it runs on a workspace made once.

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

/// The RHS of the subsonic thesis scenario with every force block of its plan: gravity, body
/// aerodynamics and fin aerodynamics distributed over the fin nodes, with the thesis'
/// key-node fin model (the vehicle's) and with the lifting-surface model (issue 12: the
/// elastic increments from the per-Mach panel matrices). Target: the lifting-surface RHS no
/// slower than the key-node one.
fn bench_rhs_with_aero(c: &mut Criterion) {
    use flexflight::run::build_force_blocks;
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/thesis/section_6_5.vdl");
    for (sets, label) in [
        (
            vec![],
            "rhs sphads1 10 modes, gravity + body aero + distributed fin aero",
        ),
        (
            vec!["forces.fin_aero.model=lifting_surface".to_string()],
            "rhs sphads1 10 modes, gravity + body aero + lifting-surface fin aero",
        ),
    ] {
        let checked = check_files(std::slice::from_ref(&root), &sets, &DiskLoader);
        let sc = checked
            .program
            .scenario("subsonic_t06")
            .expect("scenario")
            .clone();
        let (compiled, _) = compile(&sc.vehicle).expect("compiles");
        let plan = flexflight::plan::build(&sc, &compiled).expect("plan");
        let forces = build_force_blocks(&plan, &compiled.reduced).expect("force blocks");
        let mut eom = Eom::new(&compiled.reduced, forces).expect("eom");
        let mut x = plan.initial_state.clone();
        // A slightly disturbed state so every block does real work.
        x[9] += 3.0;
        for k in 0..plan.n_modes {
            x[13 + k] = 1e-5 * (k as f64 + 1.0);
            x[13 + plan.n_modes + k] = 1e-3 * (k as f64 - 3.0);
        }
        // Two states 1 mm apart in altitude, taken in turn: as in a flight, where no two
        // stages share an altitude, the atmosphere is evaluated at every evaluation (once,
        // for both aerodynamic blocks: `aero::atmosphere::AirMemo`), never read from the
        // previous one.
        let mut x2 = x.clone();
        x2[2] -= 1e-3;
        let states = [x, x2];
        let mut turn = 0;
        let mut dx = vec![0.0; states[0].len()];
        c.bench_function(label, |b| {
            b.iter(|| {
                turn ^= 1;
                eom.rhs(0.0, black_box(&states[turn]), &mut dx)
                    .map(|_| dx[7])
            })
        });
    }
}

criterion_group!(aero_benches, bench_rhs_with_aero);

/// The RHS of the `hpr_k1000` flight (`examples/hpr_k1000`, scenario `k1000`: K1000T motor
/// burning, body and lifting-surface fin aerodynamics on three fins, gravity with its
/// altitude correction, the power-law wind, the energy works tracked) at the state of its
/// maximum dynamic pressure (t = 2.38 s, Mach 0.76, 39 kPa), taken from a run's rows: the
/// right-hand side a Monte Carlo sample of `k1000_flight` evaluates about 135,000 times
/// (issue 35). Two states 1 mm apart in altitude and 1 us apart in time, taken in turn, so
/// that neither the air, the wind nor the motor's propellant fraction is read from the
/// previous evaluation (as in a flight, where no two stages share a time or an altitude).
///
/// Where the time goes, block by block: the same state with the plan's force blocks
/// filtered (none, gravity, gravity and body, gravity and fins, all), burning (t at max q)
/// and burnt out (the same state at t + 3 s, as in the 20 s of coast that take most of the
/// ascent's steps: the motor's mass terms are constant there).
fn bench_rhs_k1000(c: &mut Criterion) {
    use flexflight::run::{build_force_blocks, build_propulsion, run};
    use flexflight::runtime::forces::{ForceBlock, ForceBlocks};
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/hpr_k1000/hpr_k1000.vdl");
    let checked = check_files(&[root], &["run.stop_time=2.5 s".to_string()], &DiskLoader);
    let sc = checked.program.scenario("k1000").expect("scenario").clone();
    let (compiled, _) = compile(&sc.vehicle).expect("compiles");
    let model = &compiled.reduced;
    let plan = flexflight::plan::build(&sc, &compiled).expect("plan");
    let out = run(&plan, model, &mut |_, _| {}).expect("runs");
    let col = |name: &str| {
        out.channels
            .iter()
            .position(|c| c == name)
            .expect("channel")
    };
    let q_col = col("dynamic_pressure");
    let row = out
        .rows
        .iter()
        .max_by(|a, b| a[q_col].total_cmp(&b[q_col]))
        .expect("rows");
    let n = plan.n_modes;
    let k = flexflight::plan::RIGID_CHANNELS.len();
    let t = row[0];
    eprintln!(
        "k1000 max-q state at t = {t} s, q = {:.0} Pa, {n} modes",
        row[q_col]
    );
    let all = build_force_blocks(&plan, model).expect("force blocks");
    let keep = |f: &dyn Fn(&ForceBlock) -> bool| {
        ForceBlocks::new(all.blocks.iter().filter(|b| f(b)).cloned().collect())
    };
    let is_gravity = |b: &ForceBlock| matches!(b, ForceBlock::Gravity(_));
    let sets: [(&str, ForceBlocks); 5] = [
        ("no force block", keep(&|_| false)),
        ("gravity", keep(&is_gravity)),
        (
            "gravity + body aero",
            keep(&|b| is_gravity(b) || matches!(b, ForceBlock::BodyAero(_))),
        ),
        (
            "gravity + fin aero",
            keep(&|b| is_gravity(b) || matches!(b, ForceBlock::FinAero(_))),
        ),
        ("every block", keep(&|_| true)),
    ];
    for (label, forces) in sets {
        let mut eom = Eom::new(model, forces).expect("eom").track_energy();
        if let Some(p) = build_propulsion(&plan, model).expect("propulsion") {
            eom = eom.with_propulsion(p).expect("motor");
        }
        let mut x = eom.layout().state(
            [
                row[col("p_inertial_x")],
                row[col("p_inertial_y")],
                row[col("p_inertial_z")],
            ],
            [
                row[col("q1")],
                row[col("q2")],
                row[col("q3")],
                row[col("q0")],
            ],
            [
                row[col("v_body_x")],
                row[col("v_body_y")],
                row[col("v_body_z")],
            ],
            [
                row[col("omega_body_x")],
                row[col("omega_body_y")],
                row[col("omega_body_z")],
            ],
            &row[k..k + n],
            &row[k + n..k + 2 * n],
        );
        x.resize(eom.dim(), 0.0);
        let mut x2 = x.clone();
        x2[2] -= 1e-3;
        let mut dx = vec![0.0; eom.dim()];
        for (phase, t0) in [("burning", t), ("burnt out", t + 3.0)] {
            let states = [(t0, x.clone()), (t0 + 1e-6, x2.clone())];
            let mut turn = 0;
            c.bench_function(&format!("rhs k1000 at max q, {phase}, {label}"), |b| {
                b.iter(|| {
                    turn ^= 1;
                    let (t, x) = &states[turn];
                    eom.rhs(*t, black_box(x), &mut dx).map(|_| dx[7])
                })
            });
        }
    }
}

criterion_group!(k1000_benches, bench_rhs_k1000);
criterion_main!(benches, aero_benches, k1000_benches);
