//! Time-domain identification: fit `x(t) ≈ A e^(σ_d t) cos(ω_d t − φ) (+ c)` to a window of
//! a run's history, as the thesis does after each gust (eq. (6.30), Tables 6.1-6.2).
//!
//! Method, in two stages:
//! 1. **Matrix pencil** (Hua & Sarkar 1990; Sarkar & Pereira 1995). The window is sampled
//!    uniformly, `y_k = x(t_0 + k Δt)`, `k = 0..N`. A sum of `M` damped exponentials
//!    `y_k = Σ_m h_m z_m^k` makes the Hankel matrix `Y[i, j] = y_{i+j}` (`(N−L) × (L+1)`,
//!    pencil parameter `L = N/3`, at most [`MAX_PENCIL_COLUMNS`]) of rank `M`. With the
//!    SVD `Y = U Σ Vᵀ` (its `Σ` and `V` from the eigen-decomposition of the Gram matrix
//!    `YᵀY = V Σ² Vᵀ`, `hankel_right_singular`), the first `M` right singular vectors `V'`
//!    span the row space `span{(z_m^j)_j}`; deleting the last row
//!    (`V₁'`) or the first row (`V₂'`) gives `V₂' = V₁' T⁻¹ Z T` with `Z = diag(z_m)`
//!    (shifting `z^j` by one index multiplies it by `z`), so the poles are the eigenvalues of
//!    `V₁'⁺ V₂'`. The model order `M` is the number of singular values above
//!    `threshold · s_max`. Continuous poles follow from `z = e^{(σ + iω) Δt}`:
//!    `σ = ln|z| / Δt`, `ω = arg z / Δt`. Amplitudes are linear least squares on the real
//!    basis `e^{σt} cos ωt`, `e^{σt} sin ωt` (one column for a real pole) plus a constant.
//!    With an offset the pencil runs on the first difference `y_{k+1} − y_k`, which removes
//!    the constant (the pole `z = 1`) and keeps every other pole.
//! 2. **Nonlinear least squares** (variable projection, Golub & Pereyra 1973): the dominant
//!    pole of stage 1 starts a Levenberg-Marquardt iteration on its `(σ, ω)` alone, the other
//!    poles held; every linear amplitude, `(a, b)` of `e^{σt}(a cos ωt + b sin ωt)`, those
//!    of the other poles and `c`, is solved exactly at every trial point (holding the other
//!    poles keeps a second mode from biasing the dominant one): the residual is the data's
//!    part outside the span of all the columns, with the held columns' span removed once
//!    (`HeldProjection`). A pole of stage 1 that grows by more than `e^700` over the window
//!    is an error ([`IdentifyError::Unbounded`]: a step or spike, not a free response). Then `A = √(a² + b²)`,
//!    `φ = atan2(b, a)`, because `A cos(ωt − φ) = A cos φ cos ωt + A sin φ sin ωt`.
//!
//! The dominant mode is the pencil mode of largest energy over the window,
//! `Σ_k |contribution_k|²`; the least-damped mode (largest `σ` among the modes with at least
//! [`IdentifyOptions::energy_fraction`] of that energy) is reported beside it. Fit quality:
//! `nrmse = ‖r‖ / ‖y − ȳ‖` and `r_squared = 1 − nrmse²`.

use faer::Mat;
use serde::Serialize;

/// Settings of [`identify`].
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifyOptions {
    /// Fit a constant offset `c` as well.
    pub offset: bool,
    /// Singular values above `threshold · s_max` count towards the model order.
    pub threshold: f64,
    /// Upper bound of the model order (poles, counting a complex pair as two).
    pub max_order: usize,
    /// Modes with at least this fraction of the dominant mode's energy are candidates for
    /// [`Identification::least_damped`].
    pub energy_fraction: f64,
    /// Refine the dominant mode by nonlinear least squares.
    pub refine: bool,
}

impl Default for IdentifyOptions {
    fn default() -> Self {
        IdentifyOptions {
            offset: true,
            threshold: 1e-2,
            max_order: 12,
            energy_fraction: 0.1,
            refine: true,
        }
    }
}

/// Why a window could not be identified.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IdentifyError {
    #[error("the window has {found} samples; at least {needed} are needed")]
    TooShort { found: usize, needed: usize },
    #[error("times and values differ in length ({times} and {values})")]
    LengthMismatch { times: usize, values: usize },
    #[error("sample {index} is not finite or the times do not increase there")]
    BadSample { index: usize },
    #[error("the signal is constant over the window: nothing to identify")]
    Flat,
    #[error("the singular value decomposition or eigen-solve did not converge")]
    NoConvergence,
    #[error("no pole could be extracted from the window")]
    NoModes,
    #[error(
        "a pole of the window grows at sigma = {sigma:.4e} 1/s, beyond what a {span:.4} s window can hold (e^709): the window holds a step or a spike, not a free response"
    )]
    Unbounded { sigma: f64, span: f64 },
}

/// One pole of the pencil model with its least-squares amplitude.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PencilMode {
    /// Growth rate, 1/s.
    pub sigma: f64,
    /// Angular frequency, rad/s (0 for a real pole).
    pub omega: f64,
    /// Amplitude at the window start.
    pub amplitude: f64,
    /// Energy of the mode's contribution over the window, `Σ_k |x_m(t_k)|²`.
    pub energy: f64,
}

/// The identified dominant mode of a window,
/// `A e^(σ_d (t − t_start)) cos(ω_d (t − t_start) − φ) + c`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Identification {
    /// `σ_d`, 1/s: negative is damped, positive grows.
    pub sigma_d: f64,
    /// `ω_d`, rad/s (0 for a real, non-oscillating pole).
    pub omega_d: f64,
    /// `ω_d / 2π`, Hz.
    pub frequency_hz: f64,
    /// `A`, at `t_start`, in the channel's unit.
    pub amplitude: f64,
    /// `φ`, rad.
    pub phase: f64,
    /// `c` (0 unless fitted).
    pub offset: f64,
    pub t_start: f64,
    pub t_end: f64,
    /// Uniform sample interval used, s.
    pub dt: f64,
    pub samples: usize,
    /// Model order chosen by the singular-value threshold.
    pub model_order: usize,
    /// The largest-`σ` pencil mode among those with at least
    /// [`IdentifyOptions::energy_fraction`] of the dominant mode's energy (the dominant
    /// mode itself when no other comes close).
    pub least_damped: Option<PencilMode>,
    /// Every pole of the pencil model (a complex pair once, `ω > 0`).
    pub modes: Vec<PencilMode>,
    /// `‖r‖ / ‖y − ȳ‖` of the full pencil model.
    pub pencil_nrmse: f64,
    /// `‖r‖ / ‖y − ȳ‖` of the final model (refined dominant pole and the other poles).
    pub nrmse: f64,
    /// `1 − nrmse²` of the final model.
    pub r_squared: f64,
    /// `1 − nrmse²` of the dominant damped sinusoid alone (amplitudes re-fitted): how much
    /// of the window the thesis' single-mode model explains.
    pub single_mode_r_squared: f64,
    /// Whether the nonlinear refinement ran and improved on the pencil estimate.
    pub refined: bool,
}

/// Upper bound of the pencil parameter `L`. `N/3 <= L <= N/2` filters noise best (Hua &
/// Sarkar), but any `L >= M` finds the poles; the bound keeps the SVD of a long window
/// (10 s at 1 ms) at `O(N L²)` instead of `O(N³)`.
pub const MAX_PENCIL_COLUMNS: usize = 200;

/// The largest `σ T` a window of length `T` admits (`e^709` is near the largest double).
const MAX_GROWTH_EXPONENT: f64 = 700.0;

/// The fewest samples [`identify`] accepts.
pub const MIN_SAMPLES: usize = 8;

/// Identify the dominant damped sinusoid of `x(t)`. The times must increase; they are
/// resampled onto a uniform grid of their median spacing (linear interpolation), so the
/// irregular last row of a history is harmless.
pub fn identify(
    t: &[f64],
    x: &[f64],
    opts: &IdentifyOptions,
) -> Result<Identification, IdentifyError> {
    if t.len() != x.len() {
        return Err(IdentifyError::LengthMismatch {
            times: t.len(),
            values: x.len(),
        });
    }
    if t.len() < MIN_SAMPLES {
        return Err(IdentifyError::TooShort {
            found: t.len(),
            needed: MIN_SAMPLES,
        });
    }
    for k in 0..t.len() {
        let increasing = k == 0 || t[k] > t[k - 1];
        if !(t[k].is_finite() && x[k].is_finite() && increasing) {
            return Err(IdentifyError::BadSample { index: k });
        }
    }
    let (dt, y) = resample(t, x);
    if y.len() < MIN_SAMPLES {
        return Err(IdentifyError::TooShort {
            found: y.len(),
            needed: MIN_SAMPLES,
        });
    }
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let spread = y.iter().map(|v| (v - mean).powi(2)).sum::<f64>().sqrt();
    let scale = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if spread <= 1e-13 * scale.max(f64::MIN_POSITIVE) || spread == 0.0 {
        return Err(IdentifyError::Flat);
    }

    // Stage 1: poles by the matrix pencil.
    let (poles, model_order) = pencil_poles(&y, dt, opts)?;
    // A pole whose envelope grows past the range of a double over the window (e^709) cannot
    // be a column of the fit: the window holds a step or a spike (at its end), not a free
    // response. Say so instead of letting the basis overflow into a failed factorisation.
    let span = dt * (y.len() - 1) as f64;
    if let Some(&(sigma, _)) = poles.iter().find(|p| p.0 * span > MAX_GROWTH_EXPONENT) {
        return Err(IdentifyError::Unbounded { sigma, span });
    }
    let cols = basis(&poles, y.len(), dt, opts.offset);
    let beta = lstsq(&cols, &y)?;
    let fitted = combine(&cols, &beta);
    let pencil_nrmse = norm_diff(&y, &fitted) / spread;
    let mut modes = Vec::with_capacity(poles.len());
    let mut col = 0;
    for &(sigma, omega) in &poles {
        let width = if oscillatory(omega, dt) { 2 } else { 1 };
        let part = combine(&cols[col..col + width], &beta[col..col + width]);
        let amplitude = beta[col..col + width]
            .iter()
            .map(|b| b * b)
            .sum::<f64>()
            .sqrt();
        modes.push(PencilMode {
            sigma,
            omega,
            amplitude,
            energy: part.iter().map(|v| v * v).sum(),
        });
        col += width;
    }
    let (di, dominant) = modes
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.energy.total_cmp(&b.1.energy))
        .ok_or(IdentifyError::NoModes)?;
    let least_damped = modes
        .iter()
        .filter(|m| m.energy >= opts.energy_fraction * dominant.energy)
        .max_by(|a, b| a.sigma.total_cmp(&b.sigma))
        .cloned();

    // Stage 2: refine the dominant pole with the other poles held (amplitudes of all free).
    let others: Vec<(f64, f64)> = poles
        .iter()
        .enumerate()
        .filter(|&(k, _)| k != di)
        .map(|(_, p)| *p)
        .collect();
    let start = (dominant.sigma, dominant.omega);
    let (sigma, omega, refined) = if opts.refine {
        let (p, improved) = refine(&y, dt, start, &others, opts.offset);
        (p.0, p.1, improved)
    } else {
        (start.0, start.1, false)
    };
    let mut all = vec![(sigma, omega)];
    all.extend_from_slice(&others);
    let full = basis(&all, y.len(), dt, opts.offset);
    let b = lstsq(&full, &y)?;
    let nrmse = norm_diff(&y, &combine(&full, &b)) / spread;
    let offset = if opts.offset { b[b.len() - 1] } else { 0.0 };
    let (amplitude, phase) = if oscillatory(omega, dt) {
        (b[0].hypot(b[1]), b[1].atan2(b[0]))
    } else {
        (
            b[0].abs(),
            if b[0] < 0.0 {
                std::f64::consts::PI
            } else {
                0.0
            },
        )
    };
    // The thesis' measure: how much of the window one damped sinusoid explains.
    let single = basis(&[(sigma, omega)], y.len(), dt, opts.offset);
    let bs = lstsq(&single, &y)?;
    let single_nrmse = norm_diff(&y, &combine(&single, &bs)) / spread;
    Ok(Identification {
        sigma_d: sigma,
        omega_d: omega,
        frequency_hz: omega / (2.0 * std::f64::consts::PI),
        amplitude,
        phase,
        offset,
        t_start: t[0],
        t_end: t[0] + dt * (y.len() - 1) as f64,
        dt,
        samples: y.len(),
        model_order,
        least_damped,
        modes,
        pencil_nrmse,
        nrmse,
        r_squared: 1.0 - nrmse * nrmse,
        single_mode_r_squared: 1.0 - single_nrmse * single_nrmse,
        refined,
    })
}

/// Uniform resampling at the median spacing, from `t[0]` to the last time it reaches.
fn resample(t: &[f64], x: &[f64]) -> (f64, Vec<f64>) {
    let mut gaps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    gaps.sort_by(f64::total_cmp);
    let dt = gaps[gaps.len() / 2];
    let span = t[t.len() - 1] - t[0];
    let n = (span / dt * (1.0 + 1e-9)).floor() as usize + 1;
    let mut y = Vec::with_capacity(n);
    let mut j = 0;
    for k in 0..n {
        let tk = t[0] + dt * k as f64;
        while j + 2 < t.len() && t[j + 1] <= tk {
            j += 1;
        }
        let f = ((tk - t[j]) / (t[j + 1] - t[j])).clamp(0.0, 1.0);
        y.push(x[j] + f * (x[j + 1] - x[j]));
    }
    (dt, y)
}

/// Poles `(σ, ω)` with `ω ≥ 0` (a complex pair once) and the model order.
fn pencil_poles(
    y: &[f64],
    dt: f64,
    opts: &IdentifyOptions,
) -> Result<(Vec<(f64, f64)>, usize), IdentifyError> {
    let d: Vec<f64>;
    let s: &[f64] = if opts.offset {
        d = y.windows(2).map(|w| w[1] - w[0]).collect();
        &d
    } else {
        y
    };
    let n = s.len();
    let l = (n / 3).clamp(2, MAX_PENCIL_COLUMNS);
    let rows = n - l;
    let (sv, v) = hankel_right_singular(s, rows, l + 1)?;
    let s_max = sv[0];
    if s_max <= 0.0 {
        return Err(IdentifyError::Flat);
    }
    let rank = sv.iter().filter(|&&si| si > opts.threshold * s_max).count();
    let m = rank.clamp(1, opts.max_order.max(1).min(l));
    let v1: Vec<Vec<f64>> = (0..m)
        .map(|c| (0..l).map(|r| v[(r, c)]).collect())
        .collect();
    let v2 = Mat::<f64>::from_fn(l, m, |r, c| v[(r + 1, c)]);
    // Pencil matrix V1'⁺ V2' (m × m), column by column.
    let mut pencil = Mat::<f64>::zeros(m, m);
    for c in 0..m {
        let rhs: Vec<f64> = (0..l).map(|r| v2[(r, c)]).collect();
        let sol = lstsq(&v1, &rhs)?;
        for r in 0..m {
            pencil[(r, c)] = sol[r];
        }
    }
    let z = pencil
        .eigenvalues()
        .map_err(|_| IdentifyError::NoConvergence)?;
    let mut poles = Vec::new();
    for zi in z {
        let r = zi.re.hypot(zi.im);
        if !(r > 1e-12 && r.is_finite()) {
            continue;
        }
        let angle = zi.im.atan2(zi.re);
        // Conjugates appear twice; keep ω ≥ 0. A real negative z has angle π: the Nyquist
        // oscillation, kept as a real-basis column with ω = π/Δt (one column: sin vanishes).
        if angle < -1e-9 {
            continue;
        }
        let omega = if angle.abs() <= 1e-9 { 0.0 } else { angle / dt };
        poles.push((r.ln() / dt, omega));
    }
    if poles.is_empty() {
        return Err(IdentifyError::NoModes);
    }
    poles.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.total_cmp(&b.1)));
    Ok((poles, m))
}

/// Singular values (descending) and right singular vectors (columns, same order) of the
/// `rows x cols` Hankel matrix `Y[i, j] = s[i + j]`, from the eigen-decomposition of its Gram
/// matrix `G = Yᵀ Y` (`cols x cols`): `G = V Σ² Vᵀ`. The Hankel structure gives `G` in
/// `O(rows · cols + cols²)` instead of the `O(rows · cols²)` of a product or an SVD:
/// `G[0, j] = Σ_r s[r] s[r + j]` directly, then along each diagonal
/// `G[i + 1, j + 1] = G[i, j] + s[rows + i] s[rows + j] - s[i] s[j]` (the window of row sums
/// slides by one sample; derived from the definition). The signal is scaled to unit maximum
/// first (the eigensolver's unit-norm scaling; `V` is unchanged and `Σ` scales back).
///
/// Accuracy: forming `G` squares the condition number, so singular values below about
/// `sqrt(ε) σ_max ≈ 1e-8 σ_max` are lost in round-off, and a subspace of singular values
/// above the pencil threshold (`1e-2 σ_max` by default) is perturbed by about
/// `cols · ε (σ_max/σ_m)²` over its relative gap (1e-10 at the threshold) instead of the
/// SVD's `ε σ_max/σ_m`: far below the fit error of any real window, and the thin SVD of the
/// `3,700 x 201` Hankel matrix of a 4 s window at 1 ms cost 25 ms against 2 ms here.
fn hankel_right_singular(
    s: &[f64],
    rows: usize,
    cols: usize,
) -> Result<(Vec<f64>, Mat<f64>), IdentifyError> {
    let scale = s.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if !(scale > 0.0 && scale.is_finite()) {
        return Err(IdentifyError::Flat);
    }
    let u: Vec<f64> = s[..rows + cols - 1].iter().map(|v| v / scale).collect();
    let mut g = Mat::<f64>::zeros(cols, cols);
    for j in 0..cols {
        let g0j = (0..rows).map(|r| u[r] * u[r + j]).sum::<f64>();
        g[(0, j)] = g0j;
        g[(j, 0)] = g0j;
        let mut acc = g0j;
        for i in 0..cols - 1 - j {
            // (i, i + j) -> (i + 1, i + j + 1)
            acc += u[rows + i] * u[rows + i + j] - u[i] * u[i + j];
            g[(i + 1, i + j + 1)] = acc;
            g[(i + j + 1, i + 1)] = acc;
        }
    }
    let eig = g
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|_| IdentifyError::NoConvergence)?;
    let (lambda, vecs) = (eig.S().column_vector(), eig.U());
    // Ascending from the solver; descending here.
    let order: Vec<usize> = (0..cols).rev().collect();
    let sv: Vec<f64> = order
        .iter()
        .map(|&k| scale * lambda[k].max(0.0).sqrt())
        .collect();
    let v = Mat::<f64>::from_fn(cols, cols, |r, c| vecs[(r, order[c])]);
    Ok((sv, v))
}

/// Real basis columns for the poles (`e^{σt}cos ωt`, `e^{σt}sin ωt`, or `e^{σt}` when
/// `ω = 0` or at the Nyquist frequency), then a constant column if `offset`.
fn basis(poles: &[(f64, f64)], n: usize, dt: f64, offset: bool) -> Vec<Vec<f64>> {
    let mut cols = Vec::new();
    for &(sigma, omega) in poles {
        let (c, s) = damped_phasor(sigma, omega, dt, n);
        cols.push(c);
        if oscillatory(omega, dt) {
            cols.push(s);
        }
    }
    if offset {
        cols.push(vec![1.0; n]);
    }
    cols
}

/// Samples between two direct evaluations in [`damped_phasor`].
const PHASOR_RESTART: usize = 32;

/// `e^{σ t_k} cos ω t_k` and `e^{σ t_k} sin ω t_k` at `t_k = k Δt`, `k = 0..n`: the powers
/// `z^k` of `z = e^{(σ + iω) Δt}` by complex products, restarted every [`PHASOR_RESTART`]
/// samples from the direct `e^{σ t_k} (cos ω t_k, sin ω t_k)`. Each product adds a relative
/// error of at most `√5 ε` to `|z^k|` (Higham, *Accuracy and Stability of Numerical
/// Algorithms*, 2nd ed., Lemma 3.5), so the samples between restarts are within about
/// `31 √5 ε ≈ 1.5e-14` of `e^{σ t_k}` relative to the restart value; the direct form itself
/// carries a phase error of up to `ε ω t_k / 2` from rounding its argument (1.7e-12 rad
/// at the Nyquist frequency of 1 ms samples after 10 s), so the products cost no accuracy
/// the direct form had, and replace an `exp`, a `sin` and a `cos` per sample by four
/// multiplications (tested against both).
fn damped_phasor(sigma: f64, omega: f64, dt: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut c, mut s) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let env = (sigma * dt).exp();
    let (sin1, cos1) = (omega * dt).sin_cos();
    let (zr, zi) = (env * cos1, env * sin1);
    let (mut wr, mut wi) = (1.0, 0.0);
    for k in 0..n {
        if k % PHASOR_RESTART == 0 {
            let e = (sigma * dt * k as f64).exp();
            let (sk, ck) = (omega * dt * k as f64).sin_cos();
            (wr, wi) = (e * ck, e * sk);
        } else {
            (wr, wi) = (wr * zr - wi * zi, wr * zi + wi * zr);
        }
        c.push(wr);
        s.push(wi);
    }
    (c, s)
}

/// Does a pole of angular frequency `omega` take a cosine and a sine column? Not at zero
/// and not at the Nyquist frequency `π/Δt`, where the sine vanishes at every sample.
fn oscillatory(omega: f64, dt: f64) -> bool {
    omega > 0.0 && omega < std::f64::consts::PI / dt * (1.0 - 1e-9)
}

fn combine<C: AsRef<[f64]>>(cols: &[C], beta: &[f64]) -> Vec<f64> {
    let n = cols.first().map_or(0, |c| c.as_ref().len());
    (0..n)
        .map(|k| cols.iter().zip(beta).map(|(c, b)| c.as_ref()[k] * b).sum())
        .collect()
}

fn norm_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Least squares `min ‖C β − y‖` by a truncated SVD (singular values below `1e-12 s_max`
/// dropped), so collinear columns give the minimum-norm solution instead of a blow-up.
fn lstsq<C: AsRef<[f64]>>(cols: &[C], y: &[f64]) -> Result<Vec<f64>, IdentifyError> {
    let n = y.len();
    let p = cols.len();
    if p == 0 {
        return Ok(Vec::new());
    }
    // Column scaling keeps growing exponentials from dominating the rank decision.
    let norms: Vec<f64> = cols
        .iter()
        .map(|c| {
            c.as_ref()
                .iter()
                .map(|v| v * v)
                .sum::<f64>()
                .sqrt()
                .max(f64::MIN_POSITIVE)
        })
        .collect();
    let a = Mat::<f64>::from_fn(n, p, |i, j| cols[j].as_ref()[i] / norms[j]);
    let svd = a.thin_svd().map_err(|_| IdentifyError::NoConvergence)?;
    let (u, s, v) = (svd.U(), svd.S().column_vector(), svd.V());
    let s_max = s[0];
    let mut beta = vec![0.0; p];
    for i in 0..s.nrows() {
        let significant = s[i] > 1e-12 * s_max;
        if !significant {
            continue;
        }
        let coef = (0..n).map(|r| u[(r, i)] * y[r]).sum::<f64>() / s[i];
        for (j, b) in beta.iter_mut().enumerate() {
            *b += v[(j, i)] * coef;
        }
    }
    for (b, nrm) in beta.iter_mut().zip(&norms) {
        *b /= nrm;
    }
    Ok(beta)
}

/// An orthonormal basis of the held columns (the other poles and the constant) and the
/// data with their span removed, built once per refinement: every trial pole then only has
/// its own one or two columns to project ([`projected_cost`]).
struct HeldProjection {
    /// Orthonormal columns spanning the held basis columns.
    q: Vec<Vec<f64>>,
    /// `y - Q Qᵀ y`.
    residual: Vec<f64>,
}

/// Relative size below which a column adds nothing to the span it is projected against
/// (the `1e-12` truncation of [`lstsq`]'s singular values, for one column at a time).
const SPAN_TOLERANCE: f64 = 1e-12;

/// Remove the span of the orthonormal columns of `q` and then `more` from `v` by classical
/// Gram-Schmidt applied twice ("twice is enough": Giraud, Langou & Rozložník, Comput. Math.
/// Appl. 50 (2005); the re-orthogonalised CGS2 keeps `Qᵀ v` at round-off), in place.
fn project_out(q: &[Vec<f64>], more: &[Vec<f64>], v: &mut [f64]) {
    for _ in 0..2 {
        for qk in q.iter().chain(more) {
            let c: f64 = qk.iter().zip(v.iter()).map(|(a, b)| a * b).sum();
            for (vi, qi) in v.iter_mut().zip(qk) {
                *vi -= c * qi;
            }
        }
    }
}

/// The part of `col` outside the span of `q` and `more`, normalised, or `None` below
/// [`SPAN_TOLERANCE`] of the column (collinear: the span does not grow).
fn orthogonal_part(q: &[Vec<f64>], more: &[Vec<f64>], col: &[f64]) -> Option<Vec<f64>> {
    let norm0 = col.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !(norm0 > 0.0 && norm0.is_finite()) {
        return None;
    }
    let mut v: Vec<f64> = col.iter().map(|c| c / norm0).collect();
    project_out(q, more, &mut v);
    let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    (norm > SPAN_TOLERANCE).then(|| {
        v.iter_mut().for_each(|x| *x /= norm);
        v
    })
}

impl HeldProjection {
    fn new(y: &[f64], held: &[Vec<f64>]) -> Self {
        let mut q: Vec<Vec<f64>> = Vec::with_capacity(held.len());
        for col in held {
            if let Some(v) = orthogonal_part(&q, &[], col) {
                q.push(v);
            }
        }
        let mut residual = y.to_vec();
        project_out(&q, &[], &mut residual);
        HeldProjection { q, residual }
    }
}

/// Residual of the model with the pole `(σ, ω)` and the held poles (and the constant, if
/// any) of `held`, every amplitude projected out: `r = (I - P) y` with `P` the orthogonal
/// projector on the span of all the columns. It is the residual of the least-squares fit
/// [`lstsq`] gives (the same projection, and unique even where columns are collinear), built
/// as `y` minus its held part (once) minus its part along the pole's own columns after the
/// held span is removed from them (Gram-Schmidt; variable projection, Golub & Pereyra 1973):
/// a few passes over the window instead of a `n x p` SVD per trial point.
fn projected_cost(y: &[f64], dt: f64, p: (f64, f64), held: &HeldProjection) -> Option<Vec<f64>> {
    let mut own: Vec<Vec<f64>> = Vec::with_capacity(2);
    for col in basis(&[p], y.len(), dt, false) {
        if let Some(v) = orthogonal_part(&held.q, &own, &col) {
            own.push(v);
        }
    }
    // `held.residual` is already orthogonal to the held span, and so is each `own` column.
    let mut r = held.residual.clone();
    for qk in &own {
        let c: f64 = qk.iter().zip(&r).map(|(a, b)| a * b).sum();
        for (ri, qi) in r.iter_mut().zip(qk) {
            *ri -= c * qi;
        }
    }
    r.iter().all(|v| v.is_finite()).then_some(r)
}

/// Levenberg-Marquardt on `(σ, ω)` (only `σ` for a real pole) of the variable-projection
/// residual, with central-difference Jacobians. Returns the parameters and whether the cost
/// went down.
fn refine(
    y: &[f64],
    dt: f64,
    start: (f64, f64),
    others: &[(f64, f64)],
    offset: bool,
) -> ((f64, f64), bool) {
    let real = start.1 == 0.0;
    let span = dt * (y.len() - 1) as f64;
    let held = HeldProjection::new(y, &basis(others, y.len(), dt, offset));
    let cost = |p: (f64, f64)| {
        projected_cost(y, dt, p, &held).map(|r| (r.iter().map(|v| v * v).sum::<f64>(), r))
    };
    let Some((mut c0, mut r0)) = cost(start) else {
        return (start, false);
    };
    let first = c0;
    let mut p = start;
    let mut lambda = 1e-3;
    let nyquist = std::f64::consts::PI / dt;
    for _ in 0..60 {
        let h = [
            1e-6 * p.0.abs().max(1.0 / span),
            1e-6 * p.1.abs().max(1.0 / span),
        ];
        let mut jac: Vec<Vec<f64>> = Vec::new();
        for (axis, &hk) in h.iter().enumerate().take(if real { 1 } else { 2 }) {
            let shift = |s: f64| {
                if axis == 0 {
                    (p.0 + s, p.1)
                } else {
                    (p.0, p.1 + s)
                }
            };
            let (Some(rp), Some(rm)) = (
                projected_cost(y, dt, shift(hk), &held),
                projected_cost(y, dt, shift(-hk), &held),
            ) else {
                return (p, c0 < first);
            };
            jac.push(
                rp.iter()
                    .zip(&rm)
                    .map(|(a, b)| (a - b) / (2.0 * hk))
                    .collect(),
            );
        }
        let dim = jac.len();
        let mut jtj = [[0.0; 2]; 2];
        let mut jtr = [0.0; 2];
        for a in 0..dim {
            jtr[a] = jac[a].iter().zip(&r0).map(|(j, r)| j * r).sum();
            for b in 0..dim {
                jtj[a][b] = jac[a].iter().zip(&jac[b]).map(|(x, z)| x * z).sum();
            }
        }
        let mut accepted = false;
        for _ in 0..12 {
            let m = [
                [jtj[0][0] * (1.0 + lambda), jtj[0][1]],
                [jtj[1][0], jtj[1][1] * (1.0 + lambda)],
            ];
            let step = if dim == 1 {
                [-jtr[0] / m[0][0], 0.0]
            } else {
                let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
                [
                    -(m[1][1] * jtr[0] - m[0][1] * jtr[1]) / det,
                    -(m[0][0] * jtr[1] - m[1][0] * jtr[0]) / det,
                ]
            };
            if !(step[0].is_finite() && step[1].is_finite()) {
                lambda *= 10.0;
                continue;
            }
            let trial = (p.0 + step[0], (p.1 + step[1]).clamp(0.0, nyquist));
            if let Some((c1, r1)) = cost(trial) {
                if c1 < c0 {
                    let small = (c0 - c1) <= 1e-14 * c0;
                    p = trial;
                    c0 = c1;
                    r0 = r1;
                    lambda = (lambda / 10.0).max(1e-12);
                    accepted = true;
                    if small {
                        return (p, c0 < first);
                    }
                    break;
                }
            }
            lambda *= 10.0;
        }
        if !accepted {
            break;
        }
    }
    (p, c0 < first)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seeded Gaussian noise: splitmix64 and Box-Muller.
    fn noise(seed: u64, n: usize) -> Vec<f64> {
        let mut s = seed;
        let mut next = || {
            s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| {
                let (u1, u2) = (next().max(1e-300), next());
                (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
            })
            .collect()
    }

    fn signal(sigma: f64, omega: f64, phi: f64, c: f64, dt: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..n).map(|k| 1.0 + dt * k as f64).collect();
        let x = t
            .iter()
            .map(|&tk| {
                let s = tk - 1.0;
                2.0 * (sigma * s).exp() * (omega * s - phi).cos() + c
            })
            .collect();
        (t, x)
    }

    /// The phasor products equal the direct `e^{σt}(cos ωt, sin ωt)` at every restart and
    /// stay, relative to the envelope, within `31 √5 ε` of the restart value times the
    /// directly evaluated `z^j` (`j` samples after it: a small argument, accurate to a few
    /// `ε`) over long windows of decaying, growing, slow, fast and Nyquist poles; and
    /// within that plus the argument rounding `ε ω t` of the direct form at every sample.
    #[test]
    fn damped_phasors_by_products_match_the_direct_form() {
        let dt = 1e-3;
        let n = 10_001;
        let (mut worst, mut worst_direct) = (0.0f64, 0.0f64);
        let bound = 31.0 * 5f64.sqrt() * f64::EPSILON;
        for (sigma, omega) in [
            (-0.8, 2.0 * std::f64::consts::PI * 2.2),
            (0.4, 2.0 * std::f64::consts::PI * 130.0),
            (-25.0, 600.0),
            (0.0, 0.0),
            (-3.0, std::f64::consts::PI / dt),
            (1.0, 1e-3),
        ] {
            let (c, s) = damped_phasor(sigma, omega, dt, n);
            for k in 0..n {
                let e = (sigma * dt * k as f64).exp();
                let (sk, ck) = (omega * dt * k as f64).sin_cos();
                let direct = ((c[k] - e * ck).abs()).max((s[k] - e * sk).abs()) / e;
                let r = k - k % PHASOR_RESTART;
                let j = (k - r) as f64;
                let (ej, (sj, cj)) = ((sigma * dt * j).exp(), (omega * dt * j).sin_cos());
                let (zr, zi) = (ej * cj, ej * sj);
                let (ref_c, ref_s) = (c[r] * zr - s[r] * zi, c[r] * zi + s[r] * zr);
                let err = ((c[k] - ref_c).abs()).max((s[k] - ref_s).abs()) / e;
                if k == r {
                    assert_eq!(direct, 0.0, "restart {k}, pole ({sigma}, {omega})");
                }
                assert!(
                    direct <= bound + 2.0 * f64::EPSILON * omega * dt * k as f64,
                    "sample {k}, pole ({sigma}, {omega}): {direct:e} from the direct form"
                );
                worst = worst.max(err);
                worst_direct = worst_direct.max(direct);
            }
        }
        eprintln!(
            "phasor error {worst:e} (bound {bound:e}), against the direct form {worst_direct:e}"
        );
        assert!(worst < bound, "worst {worst:e} against {bound:e}");
        assert!(worst > 0.0);
    }

    #[test]
    fn damped_sinusoid_without_noise_is_recovered_exactly() {
        let (t, x) = signal(-0.8, 2.0 * std::f64::consts::PI * 2.2, 0.7, 0.3, 0.01, 400);
        let id = identify(&t, &x, &IdentifyOptions::default()).unwrap();
        assert!((id.sigma_d + 0.8).abs() < 1e-6, "{id:?}");
        assert!((id.frequency_hz - 2.2).abs() < 1e-6, "{id:?}");
        assert!((id.amplitude - 2.0).abs() < 1e-6 && (id.phase - 0.7).abs() < 1e-6);
        assert!((id.offset - 0.3).abs() < 1e-6);
        assert!(id.r_squared > 1.0 - 1e-10 && id.pencil_nrmse < 1e-6);
        assert!((id.t_start - 1.0).abs() < 1e-12);
    }

    #[test]
    fn growing_sinusoid_with_noise_is_recovered_to_one_percent() {
        let omega = 2.0 * std::f64::consts::PI * 1.27;
        let (t, mut x) = signal(0.12, omega, -1.0, 0.0, 0.01, 900);
        let peak = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (v, e) in x.iter_mut().zip(noise(7, 900)) {
            *v += 0.02 * peak * e;
        }
        let id = identify(&t, &x, &IdentifyOptions::default()).unwrap();
        assert!((id.sigma_d - 0.12).abs() < 0.01, "{id:?}");
        assert!((id.omega_d - omega).abs() < 0.01 * omega, "{id:?}");
        assert!(id.r_squared > 0.99 && id.r_squared < 1.0, "{id:?}");
    }

    #[test]
    fn damped_sinusoid_with_noise_and_a_second_weak_mode() {
        let omega = 2.0 * std::f64::consts::PI * 2.15;
        let (t, mut x) = signal(-0.33, omega, 0.2, 0.05, 0.01, 800);
        let nz = noise(42, 800);
        for (k, v) in x.iter_mut().enumerate() {
            let s = 0.01 * k as f64;
            // A fast, strongly damped mode (-6 1/s, 9 Hz) and 1 % noise.
            *v += 0.3 * (-6.0 * s).exp() * (2.0 * std::f64::consts::PI * 9.0 * s).cos()
                + 0.02 * nz[k];
        }
        let id = identify(&t, &x, &IdentifyOptions::default()).unwrap();
        assert!((id.sigma_d + 0.33).abs() < 0.02, "{id:?}");
        assert!((id.omega_d - omega).abs() < 0.005 * omega, "{id:?}");
        assert!(id.model_order >= 3, "{id:?}");
    }

    #[test]
    fn a_weaker_growing_mode_is_reported_as_least_damped() {
        let (t, x): (Vec<f64>, Vec<f64>) = (0..600)
            .map(|k| {
                let s = 0.005 * k as f64;
                let main = (-s).exp() * (2.0 * std::f64::consts::PI * 3.0 * s).cos();
                let grow = 0.1 * (0.5 * s).exp() * (2.0 * std::f64::consts::PI * 7.0 * s).sin();
                (s, main + grow)
            })
            .unzip();
        let id = identify(&t, &x, &IdentifyOptions::default()).unwrap();
        assert!((id.sigma_d + 1.0).abs() < 1e-5, "{id:?}");
        assert!((id.frequency_hz - 3.0).abs() < 1e-5, "{id:?}");
        let ld = id.least_damped.unwrap();
        assert!(
            (ld.sigma - 0.5).abs() < 1e-5 && (ld.omega - 14.0 * std::f64::consts::PI).abs() < 1e-4
        );
    }

    #[test]
    fn pure_exponential_divergence_has_zero_frequency() {
        let t: Vec<f64> = (0..120).map(|k| 0.01 * k as f64).collect();
        let x: Vec<f64> = t.iter().map(|s| 0.01 * (4.26 * s).exp() - 0.002).collect();
        let id = identify(&t, &x, &IdentifyOptions::default()).unwrap();
        assert_eq!(id.omega_d, 0.0, "{id:?}");
        assert!((id.sigma_d - 4.26).abs() < 1e-6, "{id:?}");
        assert!((id.offset + 0.002).abs() < 1e-8 && id.phase == 0.0);
    }

    #[test]
    fn refinement_improves_a_noisy_pencil_estimate() {
        let omega = 2.0 * std::f64::consts::PI * 3.4;
        let (t, mut x) = signal(-0.25, omega, 0.0, 0.0, 0.02, 300);
        for (v, e) in x.iter_mut().zip(noise(3, 300)) {
            *v += 0.2 * e;
        }
        let coarse = IdentifyOptions {
            refine: false,
            ..IdentifyOptions::default()
        };
        let a = identify(&t, &x, &coarse).unwrap();
        let b = identify(&t, &x, &IdentifyOptions::default()).unwrap();
        assert!(b.refined && !a.refined && b.nrmse < a.nrmse, "{a:?} {b:?}");
        assert!((b.sigma_d + 0.25).abs() < 0.05 && (b.omega_d - omega).abs() < 0.01 * omega);
    }

    #[test]
    fn a_long_window_is_identified_quickly() {
        // 10 s at 1 ms, as a thesis run's output: the pencil parameter is capped.
        let omega = 2.0 * std::f64::consts::PI * 4.4;
        let (t, mut x) = signal(-0.29, omega, 1.2, 0.0, 0.001, 10_000);
        for (v, e) in x.iter_mut().zip(noise(11, 10_000)) {
            *v += 0.01 * e;
        }
        let started = std::time::Instant::now();
        let id = identify(&t, &x, &IdentifyOptions::default()).unwrap();
        assert!((id.sigma_d + 0.29).abs() < 0.005 && (id.omega_d - omega).abs() < 1e-3 * omega);
        assert!(
            started.elapsed().as_secs_f64() < 10.0,
            "{:?}",
            started.elapsed()
        );
    }

    #[test]
    fn irregular_last_sample_is_resampled() {
        let (mut t, mut x) = signal(-0.5, 10.0, 0.0, 0.0, 0.01, 200);
        let tl = t[199] + 0.0037;
        t.push(tl);
        x.push(2.0 * (-0.5 * (tl - 1.0)).exp() * (10.0 * (tl - 1.0)).cos());
        let id = identify(&t, &x, &IdentifyOptions::default()).unwrap();
        assert_eq!(id.samples, 200);
        assert!((id.sigma_d + 0.5).abs() < 1e-6 && (id.omega_d - 10.0).abs() < 1e-6);
    }

    /// A step at the window's last sample (a sharp-edged gust starting there, as in
    /// subsonic_t06's alpha before the windows were made half-open) makes the pencil see a
    /// pole growing at thousands per second; the fit says so instead of overflowing its basis
    /// into a failed factorisation ("did not converge").
    #[test]
    fn a_step_at_the_window_end_is_reported_as_such() {
        let dt = 1e-3;
        let (t, mut x) = signal(-0.7, 8.4, 0.3, 0.0, dt, 3901);
        *x.last_mut().unwrap() += 50.0 * x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        match identify(&t, &x, &IdentifyOptions::default()) {
            Err(IdentifyError::Unbounded { sigma, span }) => {
                assert!(sigma * span > MAX_GROWTH_EXPONENT, "{sigma} {span}");
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn bad_windows_are_errors() {
        let opts = IdentifyOptions::default();
        assert_eq!(
            identify(&[0.0, 1.0], &[1.0, 2.0], &opts),
            Err(IdentifyError::TooShort {
                found: 2,
                needed: MIN_SAMPLES
            })
        );
        let t: Vec<f64> = (0..20).map(f64::from).collect();
        assert_eq!(identify(&t, &[3.0; 20], &opts), Err(IdentifyError::Flat));
        let mut x = vec![0.0; 20];
        x[5] = f64::NAN;
        assert_eq!(
            identify(&t, &x, &opts),
            Err(IdentifyError::BadSample { index: 5 })
        );
        assert!(matches!(
            identify(&t, &x[..19], &opts),
            Err(IdentifyError::LengthMismatch { .. })
        ));
    }
}
