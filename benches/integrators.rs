//! The integrators on the 10 s subsonic_t06 flight with 1.0 mm fins (every force block of
//! the plan, no output, no stop checks): steps, rejections, right-hand-side evaluations and
//! wall time of DOPRI5 with the standard and the PI step-size controller and of DOP853, at
//! several tolerances, each with its error at t = 10 s against a tight-tolerance reference
//! (DOP853 at rtol 1e-10, atol 1e-13; its own error estimated against rtol 1e-11; at rtol 1e-12 the step underflows at the gust onset, t = 5 s).
//!
//! Error measure: the weighted RMS norm of the state difference in the scale of the
//! scenario's tolerances, `sqrt(mean(((x - x_ref) / (1e-9 + 1e-6 |x_ref|))²))` over the
//! 13 + 2n state entries (1 = an error of the size the default tolerances ask per step), and
//! the largest modal coordinate error relative to `max |η_ref|`.
//!
//! `cargo bench --bench integrators` prints one line per configuration (not criterion: one
//! timed run each after a warm-up run, median of 3).

use std::path::PathBuf;
use std::time::Instant;

use flexflight::check::{DiskLoader, check_files};
use flexflight::run::build_force_blocks;
use flexflight::runtime::eom::Eom;
use flexflight::runtime::expint::Exponential;
use flexflight::runtime::integrate::{
    AdaptiveOptions, Dop853, DormandPrince54, Integrator, PI_BETA, StepStats,
};
use flexflight::structure::compile::compile;

#[derive(Clone, Copy)]
enum Method {
    Dopri5,
    Dop853,
    Exponential,
}

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/thesis/section_6_5.vdl");
    let sets = ["fins.thickness=1.0 mm".to_string()];
    let checked = check_files(&[root], &sets, &DiskLoader);
    let sc = checked
        .program
        .scenario("subsonic_t06")
        .expect("scenario")
        .clone();
    let (compiled, _) = compile(&sc.vehicle).expect("compiles");
    let plan = flexflight::plan::build(&sc, &compiled).expect("plan");
    let model = &compiled.reduced;
    let n = plan.n_modes;
    let t_end = 10.0;
    let fly = |method: Method, rtol: f64, atol: f64, beta: f64| -> (Vec<f64>, StepStats, f64) {
        let opts = AdaptiveOptions {
            rtol,
            atol,
            h_initial: Some(plan.integrator.step),
            beta,
            max_steps: 20_000_000,
            ..AdaptiveOptions::default()
        };
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..4 {
            let forces = build_force_blocks(&plan, model).expect("force blocks");
            let mut eom = Eom::new(model, forces).expect("eom");
            let mut x = plan.initial_state.clone();
            let mut integ: Box<dyn Integrator> = match method {
                Method::Dopri5 => Box::new(DormandPrince54::new(opts)),
                Method::Dop853 => Box::new(Dop853::new(opts)),
                Method::Exponential => Box::new(Exponential::new(opts)),
            };
            let t0 = Instant::now();
            let r = integ.integrate(&mut eom, 0.0, &mut x, t_end, &mut |_, _, _| true);
            times.push(t0.elapsed().as_secs_f64());
            assert!(r.completed(), "{:?}", r.stop);
            last = Some((x, r.stats));
            if rtol < 1e-10 {
                break; // the references: one run
            }
        }
        let wall = if times.len() > 1 {
            let mut t = times[1..].to_vec();
            t.sort_by(f64::total_cmp);
            t[t.len() / 2]
        } else {
            times[0]
        };
        let (x, stats) = last.expect("ran");
        (x, stats, wall)
    };
    let (x_ref, s_ref, w_ref) = fly(Method::Dop853, 1e-10, 1e-13, 0.0);
    let (x_ref2, ..) = fly(Method::Dop853, 1e-11, 1e-14, 0.0);
    let eta_max = x_ref[13..13 + n].iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let error = |x: &[f64], r: &[f64]| -> (f64, f64) {
        let s: f64 = x
            .iter()
            .zip(r)
            .map(|(a, b)| ((a - b) / (1e-9 + 1e-6 * b.abs())).powi(2))
            .sum();
        let eta = (13..13 + n)
            .map(|i| (x[i] - r[i]).abs())
            .fold(0.0f64, f64::max)
            / eta_max;
        ((s / x.len() as f64).sqrt(), eta)
    };
    let (e_ref, eta_ref) = error(&x_ref, &x_ref2);
    println!(
        "reference DOP853 rtol 1e-10: {} steps ({} rejected), {} RHS, {:.3} s; vs rtol 1e-11: weighted {:.2e}, eta {:.2e}",
        s_ref.accepted, s_ref.rejected, s_ref.rhs_evaluations, w_ref, e_ref, eta_ref
    );
    println!(
        "method | controller | rtol | atol | steps | rejected | RHS | wall s | weighted error | eta error"
    );
    let cases: &[(Method, &str, f64, f64, f64)] = &[
        (Method::Dopri5, "standard", 1e-6, 1e-9, 0.0),
        (Method::Dopri5, "PI 0.04", 1e-6, 1e-9, PI_BETA),
        (Method::Dopri5, "PI 0.08", 1e-6, 1e-9, 0.08),
        (Method::Dop853, "standard", 1e-6, 1e-9, 0.0),
        (Method::Dop853, "PI 0.04", 1e-6, 1e-9, PI_BETA),
        (Method::Dop853, "PI 0.04", 1e-5, 1e-8, PI_BETA),
        (Method::Dop853, "PI 0.04", 1e-7, 1e-10, PI_BETA),
        (Method::Dopri5, "PI 0.04", 1e-7, 1e-10, PI_BETA),
        (Method::Dopri5, "PI 0.04", 1e-8, 1e-11, PI_BETA),
        (Method::Dop853, "PI 0.04", 1e-8, 1e-11, PI_BETA),
        (Method::Exponential, "PI 0.04", 1e-6, 1e-9, PI_BETA),
        (Method::Exponential, "PI 0.04", 1e-7, 1e-10, PI_BETA),
        (Method::Exponential, "PI 0.04", 1e-8, 1e-11, PI_BETA),
    ];
    for &(m, ctl, rtol, atol, beta) in cases {
        let (x, st, wall) = fly(m, rtol, atol, beta);
        let (e, eta) = error(&x, &x_ref);
        let name = match m {
            Method::Dopri5 => "DOPRI5",
            Method::Dop853 => "DOP853",
            Method::Exponential => "ETD3(5)",
        };
        println!(
            "{name} | {ctl} | {rtol:e} | {atol:e} | {} | {} | {} | {wall:.3} | {e:.2e} | {eta:.2e}",
            st.accepted, st.rejected, st.rhs_evaluations
        );
    }
}
