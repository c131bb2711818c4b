//! Monte Carlo dispersion (issue 35): the same bits whatever `--jobs` or `--shard`, merged
//! shards equal to one run, resumption, check-time diagnostics of bad dispersions, and the
//! statistics' properties (binomial interval coverage, ellipse content, the written
//! correlation of correlated draws).
//!
//! The flights are the cheap 0.2 s free tumble of SPHADS-1 of tests/sweep.rs (no loads),
//! its altitude and turbulence intensity drawn: every sample shares one artifact.

use std::path::{Path, PathBuf};
use std::process::Command;

use flexflight::analysis::montecarlo::stats::{Z95, ellipses, spearman, wilson};
use flexflight::analysis::montecarlo::stream::{normal_quantile, uniform};
use flexflight::analysis::montecarlo::{draw, inverse_cdf};
use flexflight::analysis::sweep::Shard;
use flexflight::check::ir::{Correlation, Dispersion, DispersionEntry, DispersionLaw};
use flexflight::check::{DiskLoader, check_files};
use flexflight::ops::montecarlo::runner::{MonteCarloOptions, run_dispersion};
use flexflight::syntax::{Span, Spanned};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn cache() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("montecarlo-test-cache")
}

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
    turbulence air {
      model = dryden
      intensity = 1 m/s
      scale_length = 533 m
      seed = 3
      start = 0.05 s
      duration = 0.05 s
    }
  }
  run {
    stop_time = 0.1 s
    integrator = dopri5
    rtol = 1e-6
    atol = 1e-9
    output_interval = 1 ms
    stop_on_ground = false
  }
}

dispersion mc {
  scenario = tumble
  samples = 8
  seed = 2026
  vary {
    VARY
  }
  CORR
}
"#;

const GOOD_VARY: &str = "initial.altitude = normal(mean = 5 km, sd = 0.2 km)\n    stimuli.air.intensity = uniform(min = 0.5 m/s, max = 2 m/s)";
const GOOD_CORR: &str =
    "correlations = [correlate(\"initial.altitude\", \"stimuli.air.intensity\", 0.5)]";

fn write(dir: &Path, vary: &str, corr: &str) -> PathBuf {
    let vehicle = Path::new(env!("CARGO_MANIFEST_DIR")).join("vehicles/sphads1.vdl");
    let text = FILE
        .replace("VEHICLE", &vehicle.display().to_string())
        .replace("VARY", vary)
        .replace("CORR", corr);
    let path = dir.join("mc.vdl");
    std::fs::write(&path, text).unwrap();
    path
}

fn opts(jobs: usize, shard: Shard) -> MonteCarloOptions {
    MonteCarloOptions {
        samples: 8,
        jobs,
        shard,
        cache_dir: Some(cache()),
        sets: Vec::new(),
        progress: None,
        flutter_margin: None,
        full_summary: false,
        exact_boundaries: false,
    }
}

fn run_in(
    file: &Path,
    out: &Path,
    o: &MonteCarloOptions,
) -> flexflight::ops::montecarlo::runner::MonteCarloReport {
    let checked = check_files(&[file.to_path_buf()], &[], &DiskLoader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    let d = checked.program.dispersion("mc").unwrap();
    let scenario = &checked.program.scenarios[d.scenario].name.value;
    run_dispersion(file, d, scenario, out, o).unwrap()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap()
}

/// `samples.csv`, `statistics.json` and `statistics.txt` are byte-identical with 1 or 2
/// threads and for two shards merged by the binary's `merge`; every sample ran.
#[test]
fn same_bits_whatever_jobs_or_shards() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), GOOD_VARY, GOOD_CORR);
    let one = run_in(&file, &dir.path().join("j1"), &opts(1, Shard::ALL));
    let two = run_in(&file, &dir.path().join("j2"), &opts(2, Shard::ALL));
    assert_eq!((one.ran, one.failed, one.artifacts), (8, 0, 1));
    for f in ["samples.csv", "statistics.json", "statistics.txt"] {
        assert_eq!(
            read(&dir.path().join("j1").join(f)),
            read(&dir.path().join("j2").join(f)),
            "{f} differs between 1 and 2 threads"
        );
    }
    assert_eq!(two.rows, one.rows);
    let s0 = run_in(
        &file,
        &dir.path().join("s0"),
        &opts(1, Shard { index: 0, count: 2 }),
    );
    run_in(
        &file,
        &dir.path().join("s1"),
        &opts(2, Shard { index: 1, count: 2 }),
    );
    assert_eq!(s0.rows.len(), 4);
    let out = bin()
        .args(["merge", "--out"])
        .arg(dir.path().join("merged"))
        .arg(dir.path().join("s1"))
        .arg(dir.path().join("s0"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for f in ["samples.csv", "statistics.json", "statistics.txt"] {
        assert_eq!(
            read(&dir.path().join("merged").join(f)),
            read(&dir.path().join("j1").join(f)),
            "merged {f} differs from the unsharded run"
        );
    }
    // One shard alone: the merge writes what it has and says what is missing (exit 1).
    let out = bin()
        .args(["merge", "--out"])
        .arg(dir.path().join("m1"))
        .arg(dir.path().join("s0"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("4 sample(s) missing: 1, 3, 5, 7"));
    // The drawn inputs in the table are the stream's: column 2 of sample 3.
    let checked = check_files(std::slice::from_ref(&file), &[], &DiskLoader);
    let d = checked.program.dispersion("mc").unwrap();
    let x = draw(d, 3);
    assert_eq!(one.rows[3][2], format!("{}", x[0]));
    assert_eq!(one.rows[3][3], format!("{}", x[1]));
}

/// A re-run skips the finished samples and runs again only a missing one, with the same
/// table; `--set` that changes the variant runs them all again.
#[test]
fn a_rerun_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), GOOD_VARY, "");
    let out = dir.path().join("r");
    let first = run_in(&file, &out, &opts(2, Shard::ALL));
    let table = read(&out.join("samples.csv"));
    std::fs::remove_file(out.join("samples/sample_0005.json")).unwrap();
    let again = run_in(&file, &out, &opts(2, Shard::ALL));
    assert_eq!((again.ran, again.skipped), (1, 7));
    assert_eq!(read(&out.join("samples.csv")), table);
    assert_eq!(again.rows, first.rows);
    let mut changed = opts(2, Shard::ALL);
    changed.sets = vec!["run.stop_time=0.08 s".into()];
    let third = run_in(&file, &out, &changed);
    assert_eq!((third.ran, third.skipped), (8, 0));
}

/// Bad dispersions fail `check` with a code, the file and a line and column.
#[test]
fn bad_dispersions_are_diagnosed_at_check() {
    let dir = tempfile::tempdir().unwrap();
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            "initial.altitud = normal(mean = 5 km, sd = 0.2 km)",
            "",
            "vdl::field::unknown",
            "did you mean `altitude`",
        ),
        (
            "initial.altitude = normal(mean = 5 km, sd = -0.2 km)",
            "",
            "vdl::dispersion::parameter",
            "spread must be positive",
        ),
        (
            "stimuli.air.intensity = uniform(min = 2 m/s, max = 0.5 m/s)",
            "",
            "vdl::dispersion::parameter",
            "inverted",
        ),
        (
            "initial.altitude = truncated_normal(mean = 5 km, sd = 0.1 km, min = 5.2 km, max = 4.8 km)",
            "",
            "vdl::dispersion::parameter",
            "inverted",
        ),
        (
            "initial.altitude = normal(mean = 5 km, sd = 200 m)",
            "",
            "vdl::dispersion::unit",
            "one unit",
        ),
        (
            "initial.altitude = gaussian(mean = 5 km, sd = 0.2 km)",
            "",
            "vdl::dispersion::distribution",
            "normal, uniform, truncated_normal, triangular",
        ),
        (
            "stimuli.air.intensity = uniform(min = -1 m/s, max = 2 m/s)",
            "",
            "vdl::value::range",
            "",
        ),
        (
            "initial.altitude = normal(mean = 5 km, sd = 0.2 km)\n    stimuli.air.intensity = uniform(min = 0.5 m/s, max = 2 m/s)\n    stimuli.air.scale_length = uniform(min = 400 m, max = 600 m)",
            "correlations = [correlate(\"initial.altitude\", \"stimuli.air.intensity\", 0.9), correlate(\"initial.altitude\", \"stimuli.air.scale_length\", 0.9), correlate(\"stimuli.air.intensity\", \"stimuli.air.scale_length\", -0.9)]",
            "vdl::dispersion::correlation",
            "not positive definite",
        ),
        (
            GOOD_VARY,
            "correlations = [correlate(\"initial.altitude\", \"stimuli.air.intensty\", 0.5)]",
            "vdl::dispersion::correlation",
            "did you mean `stimuli.air.intensity`",
        ),
        (
            GOOD_VARY,
            "correlations = [correlate(\"initial.altitude\", \"stimuli.air.intensity\", 1)]",
            "vdl::dispersion::correlation",
            "strictly between -1 and 1",
        ),
        (
            GOOD_VARY,
            "integrator = rk45",
            "vdl::value::keyword",
            "`rk45` is not one of `dop853`, `dopri5`, `exponential`, `rk4`, `scenario`",
        ),
    ];
    for (vary, corr, code, text) in cases {
        let file = write(dir.path(), vary, corr);
        let out = bin()
            .args(["check"])
            .arg(&file)
            .env("NO_COLOR", "1")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr).to_string()
            + &String::from_utf8_lossy(&out.stdout);
        assert_eq!(out.status.code(), Some(1), "{vary}: {err}");
        assert!(err.contains(code), "{vary}: expected {code}: {err}");
        assert!(err.contains(text), "{vary}: expected `{text}`: {err}");
        // file:line:column of the offending text (the dispersion is below line 40).
        assert!(
            err.lines().any(|l| l.contains("mc.vdl:") && {
                let tail = l.rsplit("mc.vdl:").next().unwrap_or("");
                let line: usize = tail
                    .split(':')
                    .next()
                    .and_then(|s| s.parse().ok())
                    .unwrap_or(0);
                line >= 40
            }),
            "{vary}: no file:line:column in the dispersion: {err}"
        );
    }
    // The good file checks clean, and an unknown dispersion name exits with 2.
    let file = write(dir.path(), GOOD_VARY, GOOD_CORR);
    let out = bin().args(["check"]).arg(&file).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = bin()
        .args(["montecarlo", "--dispersion", "nope", "--out"])
        .arg(dir.path().join("o"))
        .arg(&file)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    // A dispersion that names the vehicle instead of a scenario is told so (it was an
    // unknown scenario), as a sweep is.
    let text = std::fs::read_to_string(&file).unwrap().replace(
        "  scenario = tumble\n  samples",
        "  scenario = sphads1\n  samples",
    );
    std::fs::write(&file, text).unwrap();
    let out = bin()
        .args(["check"])
        .arg(&file)
        .env("NO_COLOR", "1")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("vdl::reference::kind")
            && err.contains("`sphads1` is a vehicle, not a scenario")
            && err.contains("a dispersion varies a scenario"),
        "{err}"
    );
}

fn entry(path: &str, distribution: DispersionLaw) -> DispersionEntry {
    DispersionEntry {
        path: path.into(),
        span: Span::default(),
        unit: String::new(),
        distribution,
    }
}

fn dispersion(entries: Vec<DispersionEntry>, corr: &[(usize, usize, f64)]) -> Dispersion {
    let n = entries.len();
    let mut r = vec![0.0; n * n];
    for i in 0..n {
        r[i * n + i] = 1.0;
    }
    for &(a, b, rho) in corr {
        r[a * n + b] = rho;
        r[b * n + a] = rho;
    }
    let cholesky = if corr.is_empty() {
        Vec::new()
    } else {
        flexflight::check::dispersion_cholesky(&r, n).unwrap()
    };
    Dispersion {
        name: Spanned::new("d".into(), Span::default()),
        span: Span::default(),
        scenario: 0,
        samples: 0,
        seed: 11,
        entries,
        correlations: corr
            .iter()
            .map(|&(a, b, rho)| Correlation {
                a,
                b,
                rho,
                span: Span::default(),
            })
            .collect(),
        cholesky,
        integrator: None,
    }
}

/// Two correlated normal entries have the written correlation (Pearson within 4 of its
/// standard errors, (1 - ρ²)/√n), an uncorrelated third keeps its own draws exactly, and
/// each has its mean and standard deviation.
#[test]
fn correlated_draws_have_the_written_correlation() {
    let n = 20_000;
    let rho = 0.6;
    let e = |m, s| DispersionLaw::Normal { mean: m, sd: s };
    let d = dispersion(
        vec![
            entry("a", e(10.0, 2.0)),
            entry("b", e(-3.0, 0.5)),
            entry("c", DispersionLaw::Uniform { min: 0.0, max: 1.0 }),
        ],
        &[(0, 1, rho)],
    );
    let free = dispersion(d.entries.clone(), &[]);
    let draws: Vec<Vec<f64>> = (0..n).map(|i| draw(&d, i)).collect();
    let col = |j: usize| draws.iter().map(|x| x[j]).collect::<Vec<f64>>();
    let (a, b) = (col(0), col(1));
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let sd = |v: &[f64]| {
        let m = mean(v);
        (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
    };
    let r = flexflight::analysis::montecarlo::stats::pearson(&a, &b);
    let se = (1.0 - rho * rho) / (n as f64).sqrt();
    assert!((r - rho).abs() < 4.0 * se, "r = {r}");
    assert!((mean(&a) - 10.0).abs() < 4.0 * 2.0 / (n as f64).sqrt());
    assert!((sd(&b) - 0.5).abs() < 4.0 * 0.5 / (2.0 * n as f64).sqrt());
    // Entry c is in no correlation: the same bits as without correlations.
    for i in 0..100 {
        assert_eq!(draw(&d, i)[2].to_bits(), draw(&free, i)[2].to_bits());
        assert_eq!(
            draw(&free, i)[0],
            inverse_cdf(&free.entries[0].distribution, uniform(11, i, 0))
        );
    }
    // A triangular entry correlated with a normal: Spearman close to (6/π) asin(ρ/2).
    let t = dispersion(
        vec![
            entry("a", e(0.0, 1.0)),
            entry(
                "t",
                DispersionLaw::Triangular {
                    min: 0.0,
                    mode: 1.0,
                    max: 4.0,
                },
            ),
        ],
        &[(0, 1, rho)],
    );
    let draws: Vec<Vec<f64>> = (0..n).map(|i| draw(&t, i)).collect();
    let x: Vec<f64> = draws.iter().map(|v| v[0]).collect();
    let y: Vec<f64> = draws.iter().map(|v| v[1]).collect();
    assert!(y.iter().all(|v| (0.0..=4.0).contains(v)));
    let rs = spearman(&x, &y).unwrap();
    let expected = 6.0 / std::f64::consts::PI * (rho / 2.0).asin();
    // The rank correlation's standard error is about (1 - r²)/√n as well.
    assert!(
        (rs - expected).abs() < 4.0 * (1.0 - expected * expected) / (n as f64).sqrt(),
        "{rs} vs {expected}"
    );
}

/// The Wilson 95 % interval covers the true proportion in about 95 % of experiments: over
/// 4 000 experiments of n = 200 at p = 0.1, 0.3 and 0.5, the coverage is within 3 binomial
/// standard errors (0.0034 each) of 0.95 minus the interval's known deviation at these n
/// and p (Brown, Cai & DasGupta 2001, Fig. 4: within ±0.01 of 0.95).
#[test]
fn the_wilson_interval_covers_at_its_level() {
    let experiments = 4000u64;
    let n = 200u64;
    for (s, p) in [(1u64, 0.1), (2, 0.3), (3, 0.5)] {
        let mut covered = 0;
        for e in 0..experiments {
            let k = (0..n).filter(|&t| uniform(100 + s, e, t) < p).count();
            let (lo, hi) = wilson(k, n as usize, Z95);
            if lo <= p && p <= hi {
                covered += 1;
            }
        }
        let c = covered as f64 / experiments as f64;
        assert!(
            (c - 0.95).abs() < 0.01 + 3.0 * 0.0034,
            "p = {p}: coverage {c}"
        );
    }
}

/// The k-sigma ellipses of a correlated Gaussian sample hold 1 - exp(-k²/2) of it (within 4
/// binomial standard errors), their axes are the covariance's (σ² = 9 and 1 rotated by
/// 30°), and their centre the mean.
#[test]
fn the_ellipses_hold_their_chi_square_share() {
    let n = 20_000u64;
    let (s1, s2, th) = (3.0f64, 1.0f64, 30f64.to_radians());
    let pts: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            let (a, b) = (
                s1 * normal_quantile(uniform(5, i, 0)),
                s2 * normal_quantile(uniform(5, i, 1)),
            );
            (
                100.0 + a * th.cos() - b * th.sin(),
                -50.0 + a * th.sin() + b * th.cos(),
            )
        })
        .collect();
    let e = ellipses(&pts).unwrap();
    for el in &e.ellipses {
        let p = 1.0 - (-0.5 * el.k * el.k).exp();
        assert_eq!(el.expected_share, p);
        let se = (p * (1.0 - p) / n as f64).sqrt();
        assert!(
            (el.observed_share - p).abs() < 4.0 * se,
            "k = {}: {}",
            el.k,
            el.observed_share
        );
        assert!((el.semi_major / el.k - s1).abs() < 0.05 * s1);
        assert!((el.semi_minor / el.k - s2).abs() < 0.05 * s2);
        assert!((el.angle - th).abs() < 0.02, "{}", el.angle);
    }
    assert!((e.mean[0] - 100.0).abs() < 4.0 * s1 / (n as f64).sqrt());
}

/// `motor_scale`: the scaled curve delivers `impulse` times the total impulse over
/// `burn_time` times the burn time (trapezoid rule, exact), the shape kept.
#[test]
fn a_scaled_motor_delivers_the_scaled_impulse_and_burn_time() {
    use flexflight::runtime::thrust::ThrustCurve;
    let c = ThrustCurve::from_points("t", &[(0.0, 0.0), (0.1, 1000.0), (2.0, 900.0), (2.5, 0.0)])
        .unwrap();
    for (a, b) in [(1.02, 0.97), (0.95, 1.1), (1.0, 1.0)] {
        let s = c.scaled(a, b);
        assert!((s.total_impulse() - a * c.total_impulse()).abs() < 1e-12 * c.total_impulse());
        assert!((s.burn_time() - b * c.burn_time()).abs() < 1e-15);
        assert!((s.thrust_at(1.0 * b) - a / b * c.thrust_at(1.0)).abs() < 1e-9);
    }
}

fn k1000_opts(samples: usize, jobs: usize) -> MonteCarloOptions {
    MonteCarloOptions {
        samples,
        jobs,
        shard: Shard::ALL,
        cache_dir: Some(cache()),
        sets: Vec::new(),
        progress: None,
        flutter_margin: None,
        full_summary: false,
        exact_boundaries: false,
    }
}

fn k1000(
    out: &Path,
    o: &MonteCarloOptions,
) -> flexflight::ops::montecarlo::runner::MonteCarloReport {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hpr_k1000/hpr_k1000.vdl");
    let checked = check_files(std::slice::from_ref(&file), &[], &DiskLoader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    let d = checked.program.dispersion("k1000_flight").unwrap();
    let scenario = &checked.program.scenarios[d.scenario].name.value;
    run_dispersion(&file, d, scenario, out, o).unwrap()
}

/// Counts what the runner reports through `ops::Progress`.
#[derive(Default)]
struct Counting {
    total: std::sync::atomic::AtomicU64,
    done: std::sync::atomic::AtomicU64,
    finished: std::sync::atomic::AtomicU64,
}

impl flexflight::ops::Progress for Counting {
    fn start(&self, _: &str, total: u64) {
        self.total.store(total, std::sync::atomic::Ordering::SeqCst);
    }
    fn inc(&self, n: u64) {
        self.done.fetch_add(n, std::sync::atomic::Ordering::SeqCst);
    }
    fn finish(&self) {
        self.finished
            .fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    }
    fn warning(&self, _: &str) {}
}

/// The fast sample path (the flight summary's outputs and the margin's minimum, without
/// the rest of the run summary) gives the same bits as the outputs read from the complete
/// `summary.json` of the same flights, on the hpr_k1000 pad-to-landing flights with the
/// flutter margin; every output is there. Progress goes through `ops::Progress` (one
/// increment per sample run); the figures are written, the landing plot with one dot per
/// landing point.
#[test]
fn the_fast_path_gives_the_summary_bits() {
    use std::sync::atomic::Ordering::SeqCst;
    let dir = tempfile::tempdir().unwrap();
    let counting = std::sync::Arc::new(Counting::default());
    let mut fast = k1000_opts(3, 2);
    fast.progress = Some(counting.clone());
    let a = k1000(&dir.path().join("fast"), &fast);
    let mut full = k1000_opts(3, 2);
    full.full_summary = true;
    let b = k1000(&dir.path().join("full"), &full);
    assert_eq!((a.ran, a.failed), (3, 0), "{:?}", a.rows);
    assert_eq!(a.rows, b.rows);
    assert_eq!(
        read(&dir.path().join("fast/samples.csv")),
        read(&dir.path().join("full/samples.csv"))
    );
    let cols = &a.manifest.columns;
    for name in [
        "apogee_m",
        "max_mach",
        "max_q_pa",
        "off_rail_speed_m_s",
        "min_static_margin_cal",
        "landing_x_m",
        "landing_y_m",
        "flutter_margin_min",
    ] {
        let c = cols.iter().position(|h| h == name).unwrap();
        for r in &a.rows {
            assert!(
                r[c].parse::<f64>().is_ok_and(f64::is_finite),
                "{name}: {r:?}"
            );
        }
    }
    assert_eq!(
        (
            counting.total.load(SeqCst),
            counting.done.load(SeqCst),
            counting.finished.load(SeqCst)
        ),
        (3, 3, 1)
    );
    let figures = dir.path().join("fast/figures");
    for f in [
        "landing",
        "apogee",
        "flutter_margin",
        "sensitivity_flutter_margin",
        "sensitivity_apogee",
    ] {
        for ext in ["svg", "png"] {
            let p = figures.join(format!("{f}.{ext}"));
            assert!(
                p.metadata().is_ok_and(|m| m.len() > 1000),
                "{}",
                p.display()
            );
        }
    }
    // One dot per landing point, one for the legend.
    let svg = read(&figures.join("landing.svg"));
    assert_eq!(svg.matches("<circle").count(), 3 + 1, "{svg}");
}

/// A dispersion's samples fly the exponential integrator unless told otherwise (issue 35
/// item 4: the fastest accurate integrator; its statistics against a tight reference:
/// docs/montecarlo.md): the K1000T's scenario names no integrator, so its dispersion's
/// rows are those of the same samples flown with `--set run.integrator=exponential`, bit for
/// bit (and on one job as on two), not those with DOPRI5, the scenario's default; a `--set`
/// names another. A scenario that names its integrator (the tumble's `dopri5`) keeps it;
/// the dispersion's `integrator` field overrides it, `scenario` keeps it. The manifest and
/// `statistics.txt` say which integrator flew.
#[test]
fn a_dispersion_flies_the_exponential_integrator_unless_told_otherwise() {
    let dir = tempfile::tempdir().unwrap();
    let with_sets = |sets: &[&str], jobs: usize| {
        let mut o = k1000_opts(2, jobs);
        o.sets = sets.iter().map(|s| s.to_string()).collect();
        o
    };
    let plain = k1000(&dir.path().join("plain"), &with_sets(&[], 1));
    let exp = k1000(
        &dir.path().join("exp"),
        &with_sets(&["run.integrator=exponential"], 2),
    );
    let dopri = k1000(
        &dir.path().join("dopri5"),
        &with_sets(&["run.integrator=dopri5"], 1),
    );
    assert_eq!((plain.ran, plain.failed), (2, 0), "{:?}", plain.rows);
    assert_eq!(plain.rows, exp.rows);
    assert_ne!(plain.rows, dopri.rows);
    assert_eq!(
        plain.manifest.integrator.as_deref(),
        Some("exponential, rtol 1e-7, atol 1e-9")
    );
    assert_eq!(
        dopri.manifest.integrator.as_deref(),
        Some("dopri5, rtol 1e-7, atol 1e-9")
    );
    let json = read(&dir.path().join("plain/montecarlo.json"));
    assert!(
        json.contains("\"integrator\": \"exponential, rtol 1e-7, atol 1e-9\""),
        "{json}"
    );
    assert!(
        read(&dir.path().join("plain/statistics.txt"))
            .contains("\nintegrator: exponential, rtol 1e-7, atol 1e-9\n")
    );
    // Shards flown with different integrators are not one run.
    let merged = flexflight::ops::montecarlo::runner::merge(&[
        dir.path().join("plain"),
        dir.path().join("dopri5"),
    ]);
    assert!(merged.is_err_and(|e| e.contains("integrator")));

    // The tumble's scenario says `integrator = dopri5`.
    let integrator = |field: &str| {
        let d = tempfile::tempdir().unwrap();
        let f = write(d.path(), GOOD_VARY, field);
        let mut o = opts(1, Shard::ALL);
        o.samples = 2;
        run_in(&f, &d.path().join("out"), &o).manifest.integrator
    };
    let dopri5 = Some("dopri5, rtol 1e-6, atol 1e-9".to_string());
    assert_eq!(integrator(""), dopri5);
    assert_eq!(integrator("integrator = scenario"), dopri5);
    assert_eq!(
        integrator("integrator = exponential"),
        Some("exponential, rtol 1e-6, atol 1e-9".to_string())
    );
}

/// The run without rows under the canopies (`run::run_without_descent_rows`, the Monte
/// Carlo sample's flight) is the full run's flight: the same events, steps and rows up to
/// the first deployment, bit for bit; its Mach and q peaks over the skipped rows are the
/// first maxima of those channels over the full run's rows after the deployment, bit for
/// bit, and there are as many of them.
#[test]
fn a_run_without_descent_rows_is_the_same_flight() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hpr_k1000/hpr_k1000.vdl");
    let mut checked = check_files(std::slice::from_ref(&file), &[], &DiskLoader);
    let cache = cache();
    let prep =
        flexflight::ops::run::prepare(&mut checked, "k1000", Some(cache.as_path()), &mut |_| {})
            .unwrap_or_else(|_| panic!("k1000 does not prepare"));
    let model = &prep.compiled.compiled.reduced;
    let full = flexflight::run::run(&prep.plan, model, &mut |_, _| {}).unwrap();
    let (lean, peaks) = flexflight::run::run_without_descent_rows(&prep.plan, model).unwrap();
    assert_eq!(full.events, lean.events);
    assert_eq!(full.stop, lean.stop);
    assert_eq!(full.t_end.to_bits(), lean.t_end.to_bits());
    assert_eq!(full.stats, lean.stats);
    let t_canopy = full.events.deployments[0].2.t;
    let kept = full.rows.iter().filter(|r| r[0] <= t_canopy).count();
    assert_eq!(lean.rows.len(), kept);
    assert_eq!(&full.rows[..kept], &lean.rows[..]);
    assert_eq!(peaks.rows, full.rows.len() - kept);
    assert!(peaks.rows > 1000, "{}", peaks.rows);
    let first_max = |name: &str| {
        let c = full.channels.iter().position(|h| h == name).unwrap();
        full.rows[kept..]
            .iter()
            .map(|r| (r[c], r[0]))
            .reduce(|a, b| if b.0 > a.0 { b } else { a })
    };
    let bits = |p: Option<(f64, f64)>| p.map(|(v, t)| (v.to_bits(), t.to_bits()));
    assert_eq!(bits(peaks.mach), bits(first_max("mach")));
    assert_eq!(
        bits(peaks.dynamic_pressure),
        bits(first_max("dynamic_pressure"))
    );
}

/// The fins' material constants are override paths (`fins.E`, `fins.nu`, `fins.rho`: the
/// fins' own constants over their `material`'s), so a dispersion can draw them, checked at
/// `check` like any override, and they reach the structure: the clamped fin's frequencies
/// scale as sqrt(E / rho) (achieved to 5e-12). Fails on the code before them: `fins.E` was
/// an unknown field.
#[test]
fn the_fins_material_constants_are_dispersable() {
    let k1000 = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hpr_k1000/hpr_k1000.vdl");
    let fins = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let checked = check_files(std::slice::from_ref(&k1000), &sets, &DiskLoader);
        (
            checked
                .program
                .scenario("k1000")
                .and_then(|s| s.vehicle.fins.clone()),
            checked.diagnostics,
        )
    };
    let (nominal, d) = fins(&[]);
    assert!(d.iter().all(|d| d.code != "vdl::field::unknown"), "{d:?}");
    let nominal = nominal.expect("fins").material;
    let (over, d) = fins(&["fins.E=60 GPa", "fins.nu=0.31", "fins.rho=2500 kg/m^3"]);
    assert!(
        !d.iter()
            .any(|d| d.severity == flexflight::diagnostics::Severity::Error),
        "{d:?}"
    );
    let over = over.expect("fins").material;
    assert_eq!(over.youngs_modulus.value, 60e9);
    assert_eq!(over.poisson.value, 0.31);
    assert_eq!(over.density.value, 2500.0);
    assert_eq!(over.name, nominal.name);
    assert_eq!(over.yield_stress, nominal.yield_stress);
    assert_ne!(nominal.youngs_modulus.value, 60e9);
    // The constants reach the structure: the clamped fin's stiffness is linear in E and
    // its mass in rho (nu fixed), so every natural frequency scales as sqrt(E / rho).
    let modes = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let checked = check_files(std::slice::from_ref(&k1000), &sets, &DiskLoader);
        let v = &checked.program.scenario("k1000").expect("k1000").vehicle;
        flexflight::analysis::flutter::fin::clamped_fin_modes(v, 4)
            .expect("modes")
            .omega
    };
    let e0 = nominal.youngs_modulus.value;
    let rho0 = nominal.density.value;
    let w0 = modes(&[]);
    let w1 = modes(&[&format!("fins.E={} Pa", 1.21 * e0)]);
    let w2 = modes(&[&format!("fins.rho={} kg/m^3", 1.44 * rho0)]);
    for k in 0..4 {
        let (r1, r2) = (w1[k] / w0[k], w2[k] / w0[k]);
        eprintln!(
            "mode {k}: {:.2} Hz, x{r1:.12} (E x1.21), x{r2:.12} (rho x1.44)",
            w0[k] / std::f64::consts::TAU
        );
        assert!((r1 - 1.1).abs() < 5e-11, "mode {k}: {r1}");
        assert!((r2 - 1.0 / 1.2).abs() < 5e-11, "mode {k}: {r2}");
    }
    // Out of range: diagnosed at check with the override's own code.
    for (set, code) in [
        ("fins.nu=0.6", "vdl::value::range"),
        ("fins.E=-3 GPa", "vdl::value::range"),
        ("fins.E=3 m", "vdl::unit::mismatch"),
    ] {
        let (_, d) = fins(&[set]);
        assert!(
            d.iter()
                .any(|d| d.code == code && d.severity == flexflight::diagnostics::Severity::Error),
            "{set}: {d:?}"
        );
    }
    // A unit slip (MPa for GPa) is questioned as a material's would be.
    let (_, d) = fins(&["fins.E=69 MPa"]);
    assert!(
        d.iter().any(|d| d.code == "vdl::material::unit_slip"),
        "{d:?}"
    );
    // In a dispersion.
    let dir = tempfile::tempdir().unwrap();
    let disp = dir.path().join("d.vdl");
    std::fs::write(
        &disp,
        format!(
            "import \"{}\"\ndispersion fin_modulus {{\n  scenario = k1000\n  samples = 4\n  seed = 1\n  vary {{\n    fins.E = normal(mean = 68.9 GPa, rel = 0.03)\n    fins.nu = uniform(min = 0.32, max = 0.34)\n  }}\n}}\n",
            k1000.display()
        ),
    )
    .unwrap();
    let checked = check_files(std::slice::from_ref(&disp), &[], &DiskLoader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    assert!(checked.program.dispersion("fin_modulus").is_some());
    std::fs::write(
        &disp,
        format!(
            "import \"{}\"\ndispersion fin_modulus {{\n  scenario = k1000\n  samples = 4\n  seed = 1\n  vary {{\n    fins.nu = uniform(min = 0.3, max = 0.6)\n  }}\n}}\n",
            k1000.display()
        ),
    )
    .unwrap();
    let checked = check_files(&[disp], &[], &DiskLoader);
    assert!(checked.has_errors(), "{:?}", checked.diagnostics);
}

/// A dispersion of the K1000T's fin thickness alone (`k1000`, pad to landing with the
/// flutter margin), its samples drawn from `k1000_mc`'s truncated normal.
const THICKNESS_FILE: &str = r#"
import "K1000"

dispersion k1000_t {
  scenario = k1000
  samples = 3
  seed = 2026
  vary {
    fins.thickness = truncated_normal(mean = 2 mm, sd = 0.05 mm, min = 1.85 mm, max = 2.15 mm)
  }
}
"#;

fn thickness_run(
    file: &Path,
    out: &Path,
    jobs: usize,
    shard: Shard,
    exact: bool,
) -> flexflight::ops::montecarlo::runner::MonteCarloReport {
    let checked = check_files(&[file.to_path_buf()], &[], &DiskLoader);
    assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
    let d = checked.program.dispersion("k1000_t").unwrap();
    let mut o = k1000_opts(3, jobs);
    o.shard = shard;
    o.exact_boundaries = exact;
    run_dispersion(file, d, "k1000", out, &o).unwrap()
}

/// The flutter boundary of a fin-thickness dispersion interpolated between compiled
/// thicknesses (`ops::montecarlo::family`): the nodes cover the drawn range at the stated
/// spacing; every sample's minimum flutter margin agrees with its exact per-sample boundary
/// (`exact_boundaries`) within 5e-6 relative (measured 2.4e-6 on the interior sample, the
/// other two being the nodes; the stated bound, docs/montecarlo.md, is the boundary cells'
/// 3.1e-5), and an interior sample's is not the exact one's bits (the interpolation ran);
/// every other output is the exact run's bit for bit. A sample outside the nodes would have
/// no margin (the parse fails); an interpolation linear in `t` instead of `ln t` errs by
/// about `p (p - 1) h² / 8 ≈ 2e-4` here. `samples.csv` and the statistics are the same bits with 1 and 2 jobs and
/// with 2 shards merged.
#[test]
fn the_thickness_family_gives_the_exact_margin_within_its_bound() {
    let dir = tempfile::tempdir().unwrap();
    let k1000 = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hpr_k1000/hpr_k1000.vdl");
    let file = dir.path().join("t.vdl");
    std::fs::write(
        &file,
        THICKNESS_FILE.replace("K1000", &k1000.display().to_string()),
    )
    .unwrap();
    let exact = thickness_run(&file, &dir.path().join("exact"), 2, Shard::ALL, true);
    let one = thickness_run(&file, &dir.path().join("j1"), 1, Shard::ALL, false);
    let two = thickness_run(&file, &dir.path().join("j2"), 2, Shard::ALL, false);
    assert_eq!((one.ran, one.failed), (3, 0), "{:?}", one.rows);
    assert_eq!(exact.manifest.boundary_nodes, None);
    let nodes = one.manifest.boundary_nodes.clone().expect("the family ran");
    let cols = &one.manifest.columns;
    let c = |name: &str| cols.iter().position(|h| h == name).unwrap();
    let (ct, cm) = (c("fins.thickness [mm]"), c("flutter_margin_min"));
    let ts: Vec<f64> = one.rows.iter().map(|r| r[ct].parse().unwrap()).collect();
    let lo = ts.iter().copied().fold(f64::INFINITY, f64::min) * 1e-3;
    let hi = ts.iter().copied().fold(0.0, f64::max) * 1e-3;
    assert!(
        (nodes[0] / lo - 1.0).abs() < 1e-12 && (nodes[nodes.len() - 1] / hi - 1.0).abs() < 1e-12
    );
    for w in nodes.windows(2) {
        assert!(w[1] > w[0] && (w[1] / w[0]).ln() <= 0.078 * (1.0 + 1e-12));
    }
    let mut worst = 0.0f64;
    for (a, e) in one.rows.iter().zip(&exact.rows) {
        let (x, y): (f64, f64) = (a[cm].parse().unwrap(), e[cm].parse().unwrap());
        worst = worst.max((x / y - 1.0).abs());
        let interior = nodes
            .iter()
            .all(|n| (n * 1e3 - a[ct].parse::<f64>().unwrap()).abs() > 1e-9);
        if interior {
            assert_ne!(
                x.to_bits(),
                y.to_bits(),
                "sample {} was not interpolated",
                a[0]
            );
        }
        for k in 0..a.len() {
            if k != cm {
                assert_eq!(a[k], e[k], "column {}", cols[k]);
            }
        }
    }
    eprintln!(
        "nodes {nodes:?} m, thicknesses {ts:?} mm, largest relative margin error {worst:.2e}"
    );
    assert!(worst <= 5e-6, "{worst:e}");
    for f in ["samples.csv", "statistics.json", "statistics.txt"] {
        assert_eq!(
            read(&dir.path().join("j1").join(f)),
            read(&dir.path().join("j2").join(f)),
            "{f} differs between 1 and 2 threads"
        );
    }
    assert_eq!(two.rows, one.rows);
    thickness_run(
        &file,
        &dir.path().join("s0"),
        1,
        Shard { index: 0, count: 2 },
        false,
    );
    thickness_run(
        &file,
        &dir.path().join("s1"),
        1,
        Shard { index: 1, count: 2 },
        false,
    );
    let out = bin()
        .args(["merge", "--out"])
        .arg(dir.path().join("merged"))
        .arg(dir.path().join("s0"))
        .arg(dir.path().join("s1"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for f in ["samples.csv", "statistics.json", "statistics.txt"] {
        assert_eq!(
            read(&dir.path().join("merged").join(f)),
            read(&dir.path().join("j1").join(f)),
            "merged {f} differs from the unsharded run"
        );
    }
}

/// A sample whose integration failed (here every sample: a `min_step` of 10 ms that the
/// tumble's first step cannot meet, `step_underflow` at t = 0) did not fly its scenario:
/// it is `incomplete` in `samples.csv`, out of the statistics (its outputs are a flight cut
/// short), counted and listed apart from the samples that succeeded and those that
/// failed to run. On the old code such a sample was `ok` and its cut-short outputs were in
/// the statistics ("8 succeeded, 0 failed").
#[test]
fn a_sample_whose_integration_fails_is_incomplete_not_a_success() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), GOOD_VARY, "");
    let out = dir.path().join("r");
    let mut o = opts(2, Shard::ALL);
    o.sets = vec!["run.min_step=10 ms".into(), "run.rtol=1e-12".into()];
    let r = run_in(&file, &out, &o);
    assert_eq!((r.ran, r.failed, r.incomplete), (8, 0, 8), "{:?}", r.rows);
    let table = read(&out.join("samples.csv"));
    let rows: Vec<&str> = table.lines().skip(1).collect();
    assert_eq!(rows.len(), 8);
    assert!(
        rows.iter()
            .all(|l| l.contains(",incomplete,step_underflow,")),
        "{table}"
    );
    let s: serde_json::Value = serde_json::from_str(&read(&out.join("statistics.json"))).unwrap();
    assert_eq!(s["succeeded"], 0);
    assert_eq!(s["failed"], 0);
    assert_eq!(s["incomplete"], 8);
    assert_eq!(s["incomplete_samples"].as_array().unwrap().len(), 8);
    assert!(read(&out.join("statistics.txt")).contains("0 succeeded, 0 failed, 8 incomplete"));
    // A re-run resumes them (their result is the same bits), not flies them again.
    let again = run_in(&file, &out, &o);
    assert_eq!((again.ran, again.skipped, again.incomplete), (0, 8, 8));
    assert_eq!(read(&out.join("samples.csv")), table);
}
