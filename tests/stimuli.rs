//! Gust stimulus generator: deterministic pulses at hand-computed times, and the statistics
//! and determinism of seeded turbulence.

use flexflight::check::ir::{Frame, Stimulus, StimulusKind, TurbulenceModel};
use flexflight::runtime::stimuli::{Stimuli, StimulusError};
use flexflight::syntax::{Span, Spanned};

fn q(v: f64) -> Spanned<f64> {
    Spanned::new(v, Span::default())
}

fn stimulus(kind: StimulusKind) -> Stimulus {
    Stimulus {
        name: Spanned::new("s".to_string(), Span::default()),
        kind,
    }
}

fn v3(v: [f64; 3]) -> Spanned<[f64; 3]> {
    Spanned::new(v, Span::default())
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-12
}

#[test]
fn rectangular_gust_is_half_open() {
    let s = Stimuli::new(
        &[stimulus(StimulusKind::Gust {
            start: q(1.0),
            duration: q(0.1),
            velocity: v3([0.0, 0.0, 5.0]),
            frame: Frame::Body,
        })],
        100.0,
        10.0,
    )
    .unwrap();
    assert_eq!(s.wind(0.999_999).0, [0.0; 3]);
    assert_eq!(s.wind(1.0).0, [0.0, 0.0, 5.0]);
    assert_eq!(s.wind(1.05), ([0.0, 0.0, 5.0], [0.0; 3]));
    assert_eq!(s.wind(1.099_999).0, [0.0, 0.0, 5.0]);
    assert_eq!(s.wind(1.1 + 1e-12).0, [0.0; 3]);
    assert_eq!(s.wind(f64::NAN), ([0.0; 3], [0.0; 3]));
}

#[test]
fn one_minus_cosine_gust_values() {
    let s = Stimuli::new(
        &[stimulus(StimulusKind::OneMinusCosine {
            start: q(2.0),
            duration: q(0.4),
            velocity: v3([0.0, 4.0, 0.0]),
            frame: Frame::Inertial,
        })],
        0.0,
        10.0,
    )
    .unwrap();
    // v/2 (1 - cos(2 pi tau/T)): 0 at the edges, v/2 at T/4, v at T/2.
    let at = |t: f64| s.wind(t).1[1];
    assert!(close(at(2.0), 0.0));
    assert!(close(at(2.1), 2.0)); // 2 (1 - cos(pi/2))
    assert!(close(at(2.2), 4.0)); // 2 (1 - cos(pi))
    assert!(close(at(2.3), 2.0));
    assert!(close(
        at(2.05),
        2.0 * (1.0 - (std::f64::consts::PI / 4.0).cos())
    ));
    assert!(at(2.4).abs() < 1e-12);
    assert_eq!(at(1.9), 0.0);
    assert_eq!(at(2.5), 0.0);
    assert_eq!(s.wind(2.2).0, [0.0; 3]); // inertial frame only
}

#[test]
fn sine_wind_values() {
    let s = Stimuli::new(
        &[stimulus(StimulusKind::Sine {
            start: q(1.0),
            duration: q(2.0),
            amplitude: v3([3.0, 0.0, 0.0]),
            frequency: q(0.5),
            frame: Frame::Body,
        })],
        50.0,
        10.0,
    )
    .unwrap();
    let at = |t: f64| s.wind(t).0[0];
    // 3 sin(2 pi 0.5 (t - 1)) = 3 sin(pi (t - 1)).
    assert!(close(at(1.0), 0.0));
    assert!(close(at(1.5), 3.0));
    assert!(close(at(2.5), -3.0));
    assert!(close(at(1.25), 3.0 * (std::f64::consts::PI / 4.0).sin()));
    assert!(at(3.0).abs() < 1e-12);
    assert_eq!(at(0.99), 0.0);
    assert_eq!(at(3.01), 0.0);
}

#[test]
fn bad_parameters_are_errors() {
    let bad = Stimuli::new(
        &[stimulus(StimulusKind::Gust {
            start: q(1.0),
            duration: q(-0.1),
            velocity: v3([0.0, 0.0, 5.0]),
            frame: Frame::Body,
        })],
        100.0,
        10.0,
    );
    assert!(matches!(
        bad,
        Err(StimulusError::BadParameter {
            what: "duration",
            ..
        })
    ));
    let no_speed = Stimuli::new(&[turbulence(TurbulenceModel::Dryden, 1, 10.0)], 0.0, 10.0);
    assert!(matches!(no_speed, Err(StimulusError::NoAirspeed { .. })));
}

const SIGMA: f64 = 2.0;
const L: f64 = 300.0;
const V: f64 = 150.0;

fn turbulence(model: TurbulenceModel, seed: u64, duration: f64) -> Stimulus {
    stimulus(StimulusKind::Turbulence {
        model: Spanned::new(model, Span::default()),
        intensity: q(SIGMA),
        scale_length: q(L),
        seed: Spanned::new(seed, Span::default()),
        start: q(0.0),
        duration: q(duration),
    })
}

#[test]
fn turbulence_is_deterministic_per_seed() {
    let a = Stimuli::new(&[turbulence(TurbulenceModel::Dryden, 7, 20.0)], V, 20.0).unwrap();
    let b = Stimuli::new(&[turbulence(TurbulenceModel::Dryden, 7, 20.0)], V, 20.0).unwrap();
    let c = Stimuli::new(&[turbulence(TurbulenceModel::Dryden, 8, 20.0)], V, 20.0).unwrap();
    let (_, _, sa) = a.turbulence_series(0).unwrap();
    let (_, _, sb) = b.turbulence_series(0).unwrap();
    let (_, _, sc) = c.turbulence_series(0).unwrap();
    let bits = |s: &[[f64; 3]]| -> Vec<u64> { s.iter().flatten().map(|x| x.to_bits()).collect() };
    assert_eq!(bits(sa), bits(sb));
    assert_ne!(bits(sa), bits(sc));
    let t = 3.217;
    assert_eq!(a.wind(t).0.map(f64::to_bits), b.wind(t).0.map(f64::to_bits));
    assert_ne!(a.wind(t).0, c.wind(t).0);
    // Outside the window there is no wind; the window is cut at the stop time.
    assert_eq!(a.wind(20.5).0, [0.0; 3]);
    assert_eq!(a.wind(-0.1).0, [0.0; 3]);
}

/// Normalised autocorrelation of one axis at integer lags.
fn autocorrelation(samples: &[[f64; 3]], axis: usize, lag: usize) -> f64 {
    let n = samples.len() - lag;
    let mean = samples.iter().map(|s| s[axis]).sum::<f64>() / samples.len() as f64;
    let var = samples
        .iter()
        .map(|s| (s[axis] - mean).powi(2))
        .sum::<f64>()
        / samples.len() as f64;
    let cov = (0..n)
        .map(|k| (samples[k][axis] - mean) * (samples[k + lag][axis] - mean))
        .sum::<f64>()
        / n as f64;
    cov / var
}

fn std_dev(samples: &[[f64; 3]], axis: usize) -> f64 {
    let n = samples.len() as f64;
    let mean = samples.iter().map(|s| s[axis]).sum::<f64>() / n;
    (samples
        .iter()
        .map(|s| (s[axis] - mean).powi(2))
        .sum::<f64>()
        / (n - 1.0))
        .sqrt()
}

/// Check of the length scale: Dryden's correlation functions (MIL-F-8785C) are
/// R_u(xi) = sigma^2 exp(-xi/L) and R_v(xi) = R_w = sigma^2 (1 - xi/(2L)) exp(-xi/L) with
/// xi = V dt (frozen turbulence), so at the time lag L/V the normalised autocorrelation is
/// e^-1 = 0.368 for u and e^-1/2 = 0.184 for v and w. A series of 4000 L/V gives these to
/// about +-0.03 (standard error ~ sqrt(2 T_I / T) ~ 0.02).
#[test]
fn dryden_statistics_match_intensity_and_length_scale() {
    let duration = 4000.0 * L / V;
    let s = Stimuli::new(
        &[turbulence(TurbulenceModel::Dryden, 42, duration)],
        V,
        duration,
    )
    .unwrap();
    let (_, step, samples) = s.turbulence_series(0).unwrap();
    let lag = ((L / V) / step).round() as usize;
    assert!(
        ((lag as f64) * step - L / V).abs() < 1e-9,
        "grid holds the lag L/V"
    );
    for axis in 0..3 {
        let sd = std_dev(samples, axis);
        eprintln!("Dryden axis {axis}: std {sd:.4} (sigma {SIGMA})");
        assert!((sd - SIGMA).abs() < 0.1 * SIGMA, "axis {axis}: {sd}");
    }
    let ru = autocorrelation(samples, 0, lag);
    let rv = autocorrelation(samples, 1, lag);
    let rw = autocorrelation(samples, 2, lag);
    let e = (-1.0f64).exp();
    eprintln!(
        "Dryden rho(L/V): u {ru:.4} (e^-1 = {e:.4}), v {rv:.4}, w {rw:.4} ({:.4})",
        e / 2.0
    );
    assert!((ru - e).abs() < 0.03, "{ru}");
    assert!((rv - e / 2.0).abs() < 0.03, "{rv}");
    assert!((rw - e / 2.0).abs() < 0.03, "{rw}");
    // Axes are independent.
    let cross = samples.iter().map(|x| x[0] * x[2]).sum::<f64>() / samples.len() as f64;
    assert!(cross.abs() < 0.05 * SIGMA * SIGMA, "{cross}");
}

/// von Karman: intensity within 10 %, and the integral time scale of u,
/// T_I = integral of rho_u(t) dt, equals L/V for the von Karman spectrum
/// (Phi_u(0) = sigma^2 2L/pi); for the rational approximation it is
/// 1/(2 var(H)) = 1.032 L/V (var(H) = (b1^2 a0 + b0^2 a2)/(2 a0 a1 a2) = 0.4844 for
/// H = (1 + 0.25 s)/(1 + 1.357 s + 0.1987 s^2)). The sum runs to 5 L/V; expected within 10 %.
#[test]
fn von_karman_statistics_match_intensity_and_length_scale() {
    let duration = 4000.0 * L / V;
    let s = Stimuli::new(
        &[turbulence(TurbulenceModel::VonKarman, 3, duration)],
        V,
        duration,
    )
    .unwrap();
    let (_, step, samples) = s.turbulence_series(0).unwrap();
    for axis in 0..3 {
        let sd = std_dev(samples, axis);
        eprintln!("von Karman axis {axis}: std {sd:.4}");
        assert!((sd - SIGMA).abs() < 0.1 * SIGMA, "axis {axis}: {sd}");
    }
    let max_lag = ((5.0 * L / V) / step).round() as usize;
    // Trapezoidal integral of the normalised autocorrelation, lag stride 2 for speed.
    let mut integral = 0.0;
    let mut previous = 1.0;
    for lag in (2..=max_lag).step_by(2) {
        let r = autocorrelation(samples, 0, lag);
        integral += 0.5 * (previous + r) * 2.0 * step;
        previous = r;
    }
    eprintln!(
        "von Karman u integral scale {integral:.4} s vs L/V = {} s",
        L / V
    );
    assert!((integral - 1.032 * L / V).abs() < 0.1 * L / V, "{integral}");
}
