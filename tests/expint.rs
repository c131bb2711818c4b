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

use flexflight::analysis::gust_response::{DEFAULT_CHANNELS, StimulusFit, identify_after_stimuli};
use flexflight::analysis::identify::IdentifyOptions;
use flexflight::check::{DiskLoader, check_files};
use flexflight::run::{RunOutput, RunStop, run};
use flexflight::structure::compile::compile;

fn fly(sets: &[&str]) -> (RunOutput, Vec<StimulusFit>) {
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
    let fits = identify_after_stimuli(
        &plan.stimuli,
        &out,
        DEFAULT_CHANNELS,
        &IdentifyOptions::default(),
    );
    (out, fits)
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
    ("fin incidence", |c| {
        c.starts_with("fin") && c.ends_with("_alpha")
    }),
    ("fin root stress", |c| c.ends_with("_root_stress")),
    ("energy", |c| {
        matches!(c, "energy_kinetic" | "energy_strain" | "energy_total")
    }),
    ("max deformation", |c| c == "max_deformation"),
];

/// The times at which the scenario's sharp-edged gusts switch on or off: a row there takes
/// the forcing from one side of the jump or the other depending on where the integrator's
/// steps end, so it is left out of the comparison.
const JUMPS: [f64; 4] = [1.0, 1.1, 5.0, 5.1];

/// Per group, the largest over its channels and rows of `|x - x_ref|`, divided by the
/// largest range (max - min over the reference flight) among the group's channels (the
/// lateral channels of this symmetric flight have ranges at round-off level and would
/// otherwise dominate with meaningless ratios).
fn group_errors(out: &RunOutput, reference: &RunOutput) -> Vec<(&'static str, f64)> {
    assert_eq!(out.channels, reference.channels);
    let rows = out.rows.len().min(reference.rows.len());
    assert!(rows > 9_000, "{rows}");
    // Row times agree (to the driver's snapping of an output time onto a step end 1e-12
    // away, which happens at the gust jumps).
    for k in 0..rows {
        let (a, b) = (out.rows[k][0], reference.rows[k][0]);
        assert!((a - b).abs() < 1e-9, "row {k}: {a} vs {b}");
    }
    let kept: Vec<usize> = (0..rows)
        .filter(|&k| {
            JUMPS
                .iter()
                .all(|t| (reference.rows[k][0] - t).abs() > 1e-9)
        })
        .collect();
    GROUPS
        .iter()
        .map(|(name, pick)| {
            let cols: Vec<usize> = (0..out.channels.len())
                .filter(|&j| pick(&out.channels[j]))
                .collect();
            assert!(!cols.is_empty(), "{name}");
            let range = cols
                .iter()
                .map(|&j| {
                    let (lo, hi) = reference.rows[..rows]
                        .iter()
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                            (lo.min(r[j]), hi.max(r[j]))
                        });
                    hi - lo
                })
                .fold(0.0f64, f64::max);
            let worst = cols
                .iter()
                .flat_map(|&j| kept.iter().map(move |&k| (j, k)))
                .map(|(j, k)| (out.rows[k][j] - reference.rows[k][j]).abs())
                .fold(0.0f64, f64::max);
            (*name, worst / range)
        })
        .collect()
}

/// Observed (release, 3 December 2026 evening, the run cut at the gusts' switch times and
/// the reference with it), error per group relative to its range, DOPRI5 / exponential:
/// position 9.9e-12 / 2.4e-9, velocity 3.0e-7 / 1.3e-8, angular rate 2.4e-5 / 1.1e-6,
/// attitude 2.4e-8 / 7.3e-8, alpha and beta 6.3e-7 / 2.7e-8, eta 1.7e-5 / 4.5e-6, eta rates
/// 3.8e-5 / 1.4e-5, fin incidence 2.9e-6 / 2.0e-6, fin root stress 5.1e-6 / 3.3e-6, energies
/// 6.4e-11 / 4.5e-9, largest deformation 7.1e-6 / 1.02e-5; steps 14,069 / 2,204, evaluations
/// 94,319 / 15,372. So the exponential integrator is as accurate or better on the modal
/// coordinates, the fin loads and the rigid rates, and less accurate (but far inside the
/// scenario's tolerance, rtol 1e-6) on the position, attitude and energies, which it
/// integrates explicitly through a velocity that carries the fin modes' oscillation, and on
/// the largest deformation (x1.44): its error peaks on the rows 4-12 ms after a gust's end
/// (4.7e-8 m against DOPRI5's 3.2e-8 m at t = 1.112 s, on `η` errors of 3e-9 for both, the
/// atol), where the node shapes amplify it. (Before the cuts, on 2 December, the largest
/// deformation read 1.08e-5 / 1.11e-5 and `η` 1.7e-5 / 5.7e-6 against a reference that
/// crossed the gusts' jumps itself and differed from today's by 4.7e-6 of `η`'s range.)
/// After issue 34's fin drag by cross-section (6 December 2026; the default `square` fins
/// carry leading- and trailing-edge pressure drag, so the flight is not the same), debug
/// build, DOPRI5 / exponential: position 1.2e-11 / 1.15e-8, velocity 2.8e-7 / 4.5e-8,
/// angular rate 2.4e-5 / 1.0e-6, attitude 2.40e-8 / 1.12e-7, alpha and beta 6.4e-7 / 2.6e-8,
/// eta 1.7e-5 / 4.5e-6, eta rates 3.8e-5 / 1.4e-5, fin incidence 2.8e-6 / 1.9e-6, fin root
/// stress 5.1e-6 / 3.3e-6, energies 1.3e-10 / 1.9e-8, largest deformation 7.1e-6 / 1.02e-5.
/// With the edge drag removed by a temporary patch the test passes as before, so the change
/// is the flight's, not the integrators'; but the exponential integrator's attitude error
/// (7.3e-8 before) now exceeds the 1e-7 floor, and the floor was raised to 1.5e-7 with the
/// same headroom over the achieved value as before (1e-7 over 7.3e-8). The exponential
/// integrator is 4.7x DOPRI5's error on the attitude of this flight, an argument against
/// making it the default that the next change to the integrator must answer.
/// Since 6 December 2026 the reference's rows come from DOP853's own order-7 continuous
/// extension (before, from a cubic Hermite across its long steps, which put the reference
/// itself about 1.7e-6 of `η`'s range off between its steps: the `η`, fin and deformation
/// errors quoted above were mostly the reference's). Against the sound reference (dev
/// profile, DOPRI5 / exponential): position 1.18e-11 / 1.15e-8, velocity 2.78e-7 / 4.54e-8,
/// angular rate 2.37e-5 / 2.39e-8, attitude 2.41e-8 / 1.12e-7, alpha and beta 6.36e-7 /
/// 5.36e-9, eta 1.71e-5 / 1.76e-8, eta rates 3.78e-5 / 5.86e-8, fin incidence 2.89e-6 /
/// 1.02e-8, fin root stress 5.17e-6 / 1.53e-8, energies 1.32e-10 / 1.94e-8, largest
/// deformation 6.43e-6 / 2.19e-8; steps 14,065 / 2,232. So the exponential integrator is
/// 300 to 1,000 times more accurate on the modes, the fin loads and the deformation, and
/// behind on the position, attitude and energies (the slow states, which DOPRI5 over-resolves
/// at the stability bound of the fin modes; docs/performance.md, work-precision).
/// The test pins: each group no worse than DOPRI5's error (5 % margin) or below 1.5e-7 of
/// its range; the modal, fin and deformation groups below 1 % of DOPRI5's (achieved 0.1 %
/// to 0.35 %); fewer than a quarter of DOPRI5's evaluations; the gust-response
/// identification of `summary.json` (the same call as `flexflight run`): the least-damped
/// root's damping and frequency within 2e-7 of DOPRI5's, every fitted root's frequency
/// within 2e-5 and growth rate within 1 % (the lightly damped 90 Hz root seen in `alpha` is
/// the loosest).
#[test]
fn exponential_matches_the_tight_reference_at_least_as_well_as_dopri5() {
    let (reference, _) = fly(&[
        "run.integrator=dop853",
        "run.rtol=1e-10",
        "run.atol=1e-13",
        "run.min_step=1e-15 s",
    ]);
    let (dopri5, fits5) = fly(&["run.integrator=dopri5"]);
    let (expo, fitse) = fly(&["run.integrator=exponential"]);
    let e5 = group_errors(&dopri5, &reference);
    let ee = group_errors(&expo, &reference);
    eprintln!(
        "reference {:?}\ndopri5 {:?}\nexponential {:?}",
        reference.stats, dopri5.stats, expo.stats
    );
    for ((g, a), (_, b)) in e5.iter().zip(&ee) {
        eprintln!("{g:>16}: dopri5 {a:.2e}  exponential {b:.2e}");
    }
    for ((g, a), (_, b)) in e5.iter().zip(&ee) {
        assert!(
            *b <= (1.05 * a).max(1.5e-7),
            "{g}: dopri5 {a:e}, exponential {b:e}"
        );
        if g.starts_with("modal") || g.starts_with("fin") || *g == "max deformation" {
            assert!(*b <= 0.01 * a, "{g}: dopri5 {a:e}, exponential {b:e}");
        }
    }
    assert!(
        4 * expo.stats.rhs_evaluations < dopri5.stats.rhs_evaluations,
        "{:?} {:?}",
        expo.stats,
        dopri5.stats
    );
    // The gust-response identification of summary.json: the same roots.
    assert_eq!(fits5.len(), fitse.len());
    for (a, b) in fits5.iter().zip(&fitse) {
        assert_eq!((&a.channel, &a.stimulus), (&b.channel, &b.stimulus));
        let (Some(fa), Some(fb)) = (&a.fit, &b.fit) else {
            panic!("{} {}: a fit failed", a.channel, a.stimulus);
        };
        let rel = |x: f64, y: f64| (x - y).abs() / y.abs();
        eprintln!(
            "{} / {}: sigma_d {} vs {}, f {} vs {} Hz",
            a.channel, a.stimulus, fb.sigma_d, fa.sigma_d, fb.frequency_hz, fa.frequency_hz
        );
        assert!(
            rel(fb.sigma_d, fa.sigma_d) < 2e-7,
            "{} {}",
            fb.sigma_d,
            fa.sigma_d
        );
        assert!(rel(fb.frequency_hz, fa.frequency_hz) < 2e-7);
        assert_eq!(fa.modes.len(), fb.modes.len());
        for (ma, mb) in fa.modes.iter().zip(&fb.modes) {
            eprintln!(
                "   root ({}, {}) vs ({}, {})",
                mb.sigma, mb.omega, ma.sigma, ma.omega
            );
            assert!(rel(mb.omega, ma.omega) < 2e-5, "{ma:?} {mb:?}");
            assert!(rel(mb.sigma, ma.sigma) < 1e-2, "{ma:?} {mb:?}");
        }
    }
}
