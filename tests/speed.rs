//! Same bits from the cheaper forms of the default path (issue 35, item 2): what a speed
//! change claims to keep is checked here against the code it replaces.
//!
//! - The stop check of a run's accepted states evaluates the aerodynamic blocks without
//!   their loads (`FinAero::check_with`, `BodyAero::check_with`): every fin's root stress
//!   (the yield and stress-limit stops) and every fault must have the bits of the full
//!   evaluation (`forces_with`), on the K1000T's lifting-surface fins and on the thesis'
//!   key-node fins, at states spread over the Mach grid (between grid Machs and on them),
//!   the incidences (leeward fins included), the deformations and the altitudes, and at
//!   states that fault.

use std::path::{Path, PathBuf};

use flexflight::aero::atmosphere::AirMemo;
use flexflight::check::{DiskLoader, check_files};
use flexflight::plan::Plan;
use flexflight::runtime::eom::{StateLayout, StateView};
use flexflight::structure::compile::compile;

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn plan(file: &str, scenario: &str, sets: &[&str]) -> Plan {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let checked = check_files(&[repo(file)], &sets, &DiskLoader);
    let sc = checked
        .program
        .scenario(scenario)
        .expect("scenario")
        .clone();
    let (compiled, _) = compile(&sc.vehicle).expect("compiles");
    flexflight::plan::build(&sc, &compiled).expect("plan")
}

/// A deterministic stream in [-1, 1).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// States around the plan's initial one: speeds over the fin table's range (Mach 0.05 to
/// beyond its end), every direction of the airspeed in the body's cross plane (windward and
/// leeward fins), rates, deformations and altitudes; the attitude normalised.
fn states(plan: &Plan, count: usize, seed: u64) -> Vec<Vec<f64>> {
    let n = plan.n_modes;
    let mut r = Lcg(seed);
    (0..count)
        .map(|k| {
            let mut x = plan.initial_state.clone();
            x[2] = -(10.0 + 6000.0 * (0.5 + 0.5 * r.next()));
            let q = [r.next(), r.next(), r.next(), 1.0 + r.next().abs()];
            let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
            for i in 0..4 {
                x[3 + i] = q[i] / norm;
            }
            // Every 7th state sits exactly on a table node speed-wise only by chance; the
            // spread covers Mach 0.05-1.5 at sea level.
            let speed = 17.0 + 500.0 * (k as f64 / count as f64);
            let incidence = 0.3 * r.next();
            let roll = std::f64::consts::PI * r.next();
            x[7] = speed * incidence.cos();
            x[8] = speed * incidence.sin() * roll.cos();
            x[9] = speed * incidence.sin() * roll.sin();
            for w in &mut x[10..13] {
                *w = 2.0 * r.next();
            }
            for m in 0..n {
                x[13 + m] = 3e-4 * r.next();
                x[13 + n + m] = 5e-2 * r.next();
            }
            x
        })
        .collect()
}

/// `check_with` against `forces_with` on copies of the plan's blocks at `states`: the root
/// stress, angle of attack, Mach, dynamic pressure and leeward factor of every fin, and the
/// faults, bit for bit. Returns how many fin samples had a non-zero root stress.
fn compare(plan: &Plan, states: &[Vec<f64>]) -> usize {
    let aero = plan.aero.as_ref().expect("aerodynamics");
    let layout = StateLayout { n: plan.n_modes };
    let d = 6 + plan.n_modes;
    let mut loaded = 0;
    for (k, x) in states.iter().enumerate() {
        let s = StateView::new(layout, x);
        let t = 0.01 * k as f64;
        if let Some(fin) = &aero.fin {
            let (mut full, mut check) = (fin.clone(), fin.clone());
            let mut out = vec![0.0; d];
            full.forces_with(t, &s, &mut AirMemo::default(), &mut out);
            check.check_with(t, &s, &mut AirMemo::default());
            assert_eq!(full.fault(), check.fault(), "state {k}: fin fault");
            for i in 0..full.n_fins() {
                let (a, b) = (full.last(i).unwrap(), check.last(i).unwrap());
                for (what, p, q) in [
                    ("root stress", a.root_stress, b.root_stress),
                    ("root moment", a.root_moment, b.root_moment),
                    ("alpha", a.alpha, b.alpha),
                    ("mach", a.mach, b.mach),
                    ("q", a.dynamic_pressure, b.dynamic_pressure),
                    ("leeward", a.leeward_factor, b.leeward_factor),
                ] {
                    assert_eq!(
                        p.to_bits(),
                        q.to_bits(),
                        "state {k}, fin {i}: {what} {p} {q}"
                    );
                }
                assert_eq!(full.yield_exceeded(), check.yield_exceeded());
                assert_eq!(full.stress_limit_exceeded(), check.stress_limit_exceeded());
                loaded += usize::from(a.root_stress != 0.0);
            }
        }
        if let Some(body) = &aero.body {
            let (mut full, mut check) = (body.clone(), body.clone());
            let mut out = vec![0.0; d];
            full.forces_with(t, &s, &mut AirMemo::default(), &mut out);
            check.check_with(t, &s, &mut AirMemo::default());
            assert_eq!(full.fault(), check.fault(), "state {k}: body fault");
        }
    }
    loaded
}

#[test]
fn the_stop_checks_fin_stresses_and_faults_have_the_bits_of_the_full_evaluation() {
    for (file, scenario, sets) in [
        // Lifting-surface fins (panel matrices, between and on grid Machs), three fins.
        ("examples/hpr_k1000/hpr_k1000.vdl", "k1000", &[][..]),
        // The thesis' key-node fins, four fins; SPHADS-1's tables stop out of range
        // (`out_of_range = stop`), so the check raises table faults too.
        ("examples/thesis/section_6_5.vdl", "subsonic_t06", &[][..]),
    ] {
        let p = plan(file, scenario, sets);
        let mut xs = states(&p, 400, 7);
        // Faulting states: beyond the atmosphere, a non-finite airspeed, a huge Mach.
        let mut high = xs[0].clone();
        high[2] = -200_000.0;
        let mut nan = xs[1].clone();
        nan[8] = f64::NAN;
        let mut fast = xs[2].clone();
        fast[7] = 5_000.0;
        xs.extend([high, nan, fast]);
        let loaded = compare(&p, &xs);
        assert!(
            loaded > 300,
            "{file} {scenario}: {loaded} loaded fin samples"
        );
    }
}
