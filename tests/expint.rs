//! The exponential integrator (`run { integrator = exponential }`, `runtime::expint`) on the
//! real vehicle: the 10 s subsonic_t06 flight of `examples/thesis/section_6_5.vdl` with
//! 1.0 mm fins (the issue 11 benchmark), against a tight DOP853 reference (rtol 1e-10,
//! atol 1e-13), compared with DOPRI5 at the scenario's tolerances (rtol 1e-6, atol 1e-9).
//!
//! Error measure: for each output channel, the largest difference over the 1 ms rows from the
//! reference, divided by the channel's range over the reference flight (max - min); per
//! channel group, the largest of its channels. The rows are the integrators' interpolants
//! (DOPRI5: cubic Hermite between step ends; exponential: its own continuous extension), so
//! this checks the output between steps as well as the steps.

use std::path::PathBuf;

use flexflight::check::{DiskLoader, check_files};
use flexflight::runtime::run::{RunOutput, RunStop, run};
use flexflight::structure::compile::compile;

fn fly(sets: &[&str]) -> RunOutput {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/thesis/section_6_5.vdl");
    let mut all = vec!["fins.thickness=1.0 mm".to_string()];
    all.extend(sets.iter().map(|s| s.to_string()));
    let checked = check_files(&[root], &all, &DiskLoader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    let sc = checked
        .program
        .scenario("subsonic_t06")
        .expect("scenario")
        .clone();
    let (compiled, _) = compile(&sc.vehicle).expect("compiles");
    let plan = flexflight::plan::build(&sc, &compiled).expect("plan");
    let out = run(&plan, &compiled.reduced, &mut |_, _| {}).expect("runs");
    assert_eq!(out.stop, RunStop::Completed, "{}", out.stop_detail);
    out
}

/// Channel groups of the comparison: name and a predicate on the channel name.
type Group = (&'static str, fn(&str) -> bool);

const GROUPS: &[Group] = &[
    ("position", |c| c.starts_with("p_inertial_")),
    ("velocity", |c| c.starts_with("v_body_")),
    ("angular rate", |c| c.starts_with("omega_body_")),
    ("attitude", |c| matches!(c, "roll" | "pitch" | "yaw")),
    ("alpha, beta", |c| matches!(c, "alpha" | "beta")),
    ("modal eta", |c| {
        c.starts_with("eta_") && !c.starts_with("eta_dot_")
    }),
    ("modal rates", |c| c.starts_with("eta_dot_")),
    ("fin loads", |c| c.starts_with("fin")),
    ("energy", |c| c.starts_with("energy_")),
];

/// Per group, the largest over its channels of `max_rows |x - x_ref| / range(x_ref)`.
fn group_errors(out: &RunOutput, reference: &RunOutput) -> Vec<(&'static str, f64)> {
    assert_eq!(out.channels, reference.channels);
    let rows = out.rows.len().min(reference.rows.len());
    assert!(rows > 9_000, "{rows}");
    GROUPS
        .iter()
        .map(|(name, pick)| {
            let mut worst = 0.0f64;
            for (j, c) in out.channels.iter().enumerate() {
                if !pick(c) {
                    continue;
                }
                let (lo, hi) = reference.rows[..rows]
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                        (lo.min(r[j]), hi.max(r[j]))
                    });
                let range = hi - lo;
                if !(range > 0.0) {
                    continue;
                }
                for k in 0..rows {
                    assert_eq!(out.rows[k][0], reference.rows[k][0], "row times differ");
                    worst = worst.max((out.rows[k][j] - reference.rows[k][j]).abs() / range);
                }
            }
            (*name, worst)
        })
        .collect()
}

#[test]
fn exponential_matches_the_tight_reference_at_least_as_well_as_dopri5() {
    let reference = fly(&["run.integrator=dop853", "run.rtol=1e-10", "run.atol=1e-13"]);
    let dopri5 = fly(&["run.integrator=dopri5"]);
    let expo = fly(&["run.integrator=exponential"]);
    let e5 = group_errors(&dopri5, &reference);
    let ee = group_errors(&expo, &reference);
    eprintln!(
        "reference {:?}\ndopri5 {:?}\nexponential {:?}",
        reference.stats, dopri5.stats, expo.stats
    );
    for ((g, a), (_, b)) in e5.iter().zip(&ee) {
        eprintln!("{g:>14}: dopri5 {a:.2e}  exponential {b:.2e}");
    }
}
