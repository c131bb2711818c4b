//! Time integrators for the equations of motion: adaptive Dormand-Prince 5(4) and fixed-step
//! classical Runge-Kutta 4, behind the small [`Integrator`] trait.
//!
//! Why not a crate: `differential-equations` 0.7 was the preferred candidate, but its
//! `ODE::diff(&self, ..)` takes the system by shared reference (our right-hand side owns a
//! mutable [`crate::runtime::eom::Workspace`] and `&mut` force blocks, which would need
//! `RefCell` in the hot path), and a state whose length is known only at run time
//! (`13 + 2n`) means `DVector`, whose stage arithmetic allocates on every step. Dormand-Prince
//! is forty lines with the published tableau, so it is written here with every buffer
//! allocated once per [`Integrator::integrate`] call and none inside the step loop.
//!
//! References: J. R. Dormand, P. J. Prince, "A family of embedded Runge-Kutta formulae",
//! J. Comput. Appl. Math. 6 (1980) 19-26 (tableau, FSAL); E. Hairer, S. P. Nørsett,
//! G. Wanner, "Solving Ordinary Differential Equations I", 2nd ed., II.4 (error norm
//! (4.11), step-size control (4.12)-(4.13), starting step size) and II.5 (DOPRI5).

// Stage loops index several buffers in step, as the Butcher tableau is written.
#![allow(clippy::needless_range_loop)]
// The DOP853 coefficients are copied digit for digit from dop853.f.
#![allow(clippy::excessive_precision)]

use thiserror::Error;

/// Why a right-hand side evaluation failed.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
pub enum RhsError {
    /// The mass matrix `M_tot(η)` is not positive definite at this state (its Cholesky
    /// factorisation met pivot `pivot` at row `row`).
    #[error("the mass matrix M_tot(eta) is not positive definite (pivot {pivot:e} at row {row})")]
    SingularMassMatrix { row: usize, pivot: f64 },
    /// The state or its derivative contains a NaN or an infinity.
    #[error("non-finite value in the state or its derivative at index {index}")]
    NonFinite { index: usize },
}

/// A first-order system `ẋ = f(t, x)` of fixed dimension.
pub trait OdeSystem {
    /// Length of the state vector.
    fn dim(&self) -> usize;
    /// Writes `f(t, x)` into `dx` (both of length [`Self::dim`]). Must not allocate.
    fn rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), RhsError>;
    /// How many leading entries of the state the adaptive error control weighs (the rest,
    /// e.g. quadratures integrated alongside for a balance, ride along). Default: all.
    fn error_dim(&self) -> usize {
        self.dim()
    }
    /// Called after every accepted step with the new state and its derivative; may project the
    /// state onto a constraint manifold (e.g. unit Euler parameters) provided it updates `dx`
    /// to the derivative at the projected state. Default: nothing.
    fn project(&mut self, _x: &mut [f64], _dx: &mut [f64]) {}
    /// The index range of the state whose dynamics are stiff and nearly linear (for the
    /// equations of motion: the modal coordinates and their rates), which an exponential
    /// integrator ([`crate::runtime::expint::Exponential`]) linearises and integrates
    /// exactly; `None` (the default) treats the whole state explicitly.
    fn linear_block(&self) -> Option<std::ops::Range<usize>> {
        None
    }
    /// Writes the Jacobian `∂f_B/∂x_B` of the [`Self::linear_block`] at `(t, x)` into `a`
    /// (row-major, `m x m`) and returns `true`, if the system has it in closed form; the
    /// default returns `false` and the integrator uses forward differences.
    fn linear_jacobian(&mut self, _t: f64, _x: &[f64], _a: &mut [f64]) -> bool {
        false
    }
}

/// The continuous extension of the last accepted step `[t_start, t_end]` of an integrator that
/// has one consistent with its method (the exponential integrator's, which stays accurate
/// where a step spans many periods of a fast mode and a cubic Hermite between the step ends
/// does not).
pub trait DenseOutput {
    /// Start of the step.
    fn t_start(&self) -> f64;
    /// Writes the interpolated state at `t` (in `[t_start, t_end]`) into `out` (the state's
    /// length). Must not allocate.
    fn eval(&self, t: f64, out: &mut [f64]);
}

/// Called as [`Observer`], with the step's continuous extension where the integrator has
/// one (`None` at the initial state and for integrators without one).
pub type DenseObserver<'o> = dyn FnMut(f64, &[f64], &[f64], Option<&dyn DenseOutput>) -> bool + 'o;

/// Work counters of one integration.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StepStats {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected steps (error too large or non-finite trial state).
    pub rejected: usize,
    /// Right-hand side evaluations.
    pub rhs_evaluations: usize,
}

/// Why the integration stopped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StopReason {
    /// Reached `t_end`.
    Completed,
    /// The step size fell below the resolution of `t` (or the minimum step).
    StepSizeUnderflow { t: f64, h: f64 },
    /// The state became non-finite (and shrinking the step did not help).
    NonFiniteState { t: f64 },
    /// The right-hand side failed.
    Rhs { t: f64, error: RhsError },
    /// The step budget ran out.
    MaxSteps { t: f64 },
    /// The observer asked to stop.
    ObserverStopped { t: f64 },
    /// The state slice does not have the system's dimension (nothing was integrated).
    StateLength { expected: usize, found: usize },
}

/// Result of [`Integrator::integrate`]: the state slice holds the state at `t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntegrationReport {
    /// Time reached (the state passed in holds the state at this time).
    pub t: f64,
    /// Work counters.
    pub stats: StepStats,
    /// Why it stopped.
    pub stop: StopReason,
}

impl IntegrationReport {
    /// `true` if `t_end` was reached.
    pub fn completed(&self) -> bool {
        self.stop == StopReason::Completed
    }
}

/// Called with `(t, x, ẋ)` at the start and after each accepted step; return `false` to stop.
pub type Observer<'o> = dyn FnMut(f64, &[f64], &[f64]) -> bool + 'o;

/// A time integrator.
pub trait Integrator {
    /// Integrates `sys` from `t0` to `t_end`, updating `x` in place. Never panics: failures
    /// come back as a [`StopReason`].
    fn integrate(
        &mut self,
        sys: &mut dyn OdeSystem,
        t0: f64,
        x: &mut [f64],
        t_end: f64,
        observer: &mut Observer<'_>,
    ) -> IntegrationReport;

    /// As [`Self::integrate`], the observer also given the step's continuous extension where
    /// the method has one. Default: [`Self::integrate`] with `None` (the same steps and bits).
    fn integrate_dense(
        &mut self,
        sys: &mut dyn OdeSystem,
        t0: f64,
        x: &mut [f64],
        t_end: f64,
        observer: &mut DenseObserver<'_>,
    ) -> IntegrationReport {
        self.integrate(sys, t0, x, t_end, &mut |t, x, dx| observer(t, x, dx, None))
    }
}

/// Settings of [`DormandPrince54`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveOptions {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// First step; `None` picks it by HNW II.4's starting-step algorithm.
    pub h_initial: Option<f64>,
    /// Largest step.
    pub h_max: f64,
    /// Smallest step before [`StopReason::StepSizeUnderflow`].
    pub h_min: f64,
    /// Step budget (accepted + rejected).
    pub max_steps: usize,
    /// Exponent `β` of the PI step-size controller ([`step_factor`]); `0` gives the standard
    /// (integral) controller of HNW (4.13).
    pub beta: f64,
}

impl Default for AdaptiveOptions {
    fn default() -> Self {
        Self {
            rtol: 1e-8,
            atol: 1e-10,
            h_initial: None,
            h_max: f64::INFINITY,
            h_min: 0.0,
            max_steps: 10_000_000,
            beta: PI_BETA,
        }
    }
}

/// Default `β` of the PI step-size controller: Hairer's choice for DOPRI5 (dopri5.f,
/// `BETA = 0.04`; HNW I, II.4 "Stabilized step size control"; Hairer & Wanner, "Solving
/// Ordinary Differential Equations II", 2nd ed., IV.2, after K. Gustafsson, "Control
/// theoretic techniques for stepsize selection in explicit Runge-Kutta methods", ACM TOMS 17
/// (1991) 533-554).
pub const PI_BETA: f64 = 0.04;

/// The step-size factor `h_new / h` of a step with scaled error `err` whose predecessor had
/// `err_old` (HNW I, II.4, the PI ("Lund-stabilised") controller):
/// ```text
/// h_new = h · clamp(safety · err^(-α) · err_old^β, fac_min, fac_max),   α = 1/q - κ β
/// ```
/// with `q` the order of the error estimator's lower member plus one (`1/q` = `expo`; 5 for
/// DOPRI5, 8 for DOP853) and `κ` the factor of dopri5.f / dop853.f (0.75 and 0.2). `β = 0`
/// is the standard controller `h_new = h · 0.9 err^(-1/q)` (HNW (4.13)). After a rejection
/// the error history does not enter (`err_old = 1`) and the caller forbids growth.
pub(crate) fn step_factor(err: f64, err_old: f64, c: &Controller, beta: f64) -> f64 {
    if err == 0.0 {
        return c.fac_max;
    }
    let alpha = c.expo - c.kappa * beta;
    (c.safety * err.powf(-alpha) * err_old.powf(beta)).clamp(c.fac_min, c.fac_max)
}

/// The constants of a method's step-size controller.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Controller {
    pub(crate) expo: f64,
    pub(crate) kappa: f64,
    pub(crate) safety: f64,
    pub(crate) fac_min: f64,
    pub(crate) fac_max: f64,
}

/// DOPRI5's controller (dopri5.f: safety 0.9, factor in [0.2, 10]).
pub(crate) const DOPRI5_CONTROL: Controller = Controller {
    expo: 0.2,
    kappa: 0.75,
    safety: 0.9,
    fac_min: 0.2,
    fac_max: 10.0,
};

/// DOP853's controller (dop853.f: safety 0.9, factor in [1/3, 6]).
const DOP853_CONTROL: Controller = Controller {
    expo: 0.125,
    kappa: 0.2,
    safety: 0.9,
    fac_min: 0.333,
    fac_max: 6.0,
};

/// The smallest `err_old` the PI controller remembers (dopri5.f `FACOLD = MAX(ERR, 1.0D-4)`).
pub(crate) const ERR_OLD_MIN: f64 = 1e-4;

/// Adaptive explicit Runge-Kutta 5(4) of Dormand & Prince (1980), local extrapolation,
/// first-same-as-last, PI step control ([`step_factor`]: safety 0.9, factor in [0.2, 10],
/// `β` of [`AdaptiveOptions::beta`], no growth right after a rejection).
#[derive(Debug, Clone)]
pub struct DormandPrince54 {
    /// Settings.
    pub options: AdaptiveOptions,
    k: [Vec<f64>; 7],
    y_stage: Vec<f64>,
    y_new: Vec<f64>,
}

// Butcher tableau, Dormand & Prince (1980), Table 2 ("RK5(4)7M").
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
// e = b - b̂ (5th minus 4th order weights).
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;

impl DormandPrince54 {
    /// A new integrator; buffers grow to the system size on first use.
    pub fn new(options: AdaptiveOptions) -> Self {
        Self {
            options,
            k: Default::default(),
            y_stage: Vec::new(),
            y_new: Vec::new(),
        }
    }

    fn resize(&mut self, n: usize) {
        for k in &mut self.k {
            k.resize(n, 0.0);
        }
        self.y_stage.resize(n, 0.0);
        self.y_new.resize(n, 0.0);
    }

    /// Starting step size, HNW I, II.4 ("Starting Step Size", steps a-f), order 5.
    fn initial_step(
        &mut self,
        sys: &mut dyn OdeSystem,
        t0: f64,
        x: &[f64],
        span: f64,
    ) -> Result<f64, RhsError> {
        let [k0, k1, ..] = &mut self.k;
        initial_step(
            &self.options,
            5,
            sys,
            t0,
            x,
            span,
            k0,
            k1,
            &mut self.y_stage,
        )
    }
}

/// RMS norm of `v` weighted by `atol + rtol |y|`, HNW (4.11), over the first `ne` entries.
fn scaled_norm(o: &AdaptiveOptions, y: &[f64], v: &[f64], ne: usize) -> f64 {
    let (y, v) = (&y[..ne.min(y.len())], &v[..ne.min(v.len())]);
    let s: f64 = y
        .iter()
        .zip(v)
        .map(|(yi, vi)| {
            let sc = o.atol + o.rtol * yi.abs();
            (vi / sc) * (vi / sc)
        })
        .sum();
    (s / y.len().max(1) as f64).sqrt()
}

/// Starting step size of a method of order `order`, HNW I, II.4 ("Starting Step Size",
/// steps a-f); `k0 = f(t0, x)` on entry, `k1` and `y_stage` are scratch.
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step(
    o: &AdaptiveOptions,
    order: i32,
    sys: &mut dyn OdeSystem,
    t0: f64,
    x: &[f64],
    span: f64,
    k0: &mut [f64],
    k1: &mut [f64],
    y_stage: &mut [f64],
) -> Result<f64, RhsError> {
    {
        let ne = sys.error_dim().min(x.len());
        let d0 = scaled_norm(o, x, x, ne);
        let d1 = scaled_norm(o, x, k0, ne);
        let h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        }
        .min(span);
        for i in 0..x.len() {
            y_stage[i] = x[i] + h0 * k0[i];
        }
        sys.rhs(t0 + h0, y_stage, k1)?;
        let diff: f64 = {
            let s: f64 = (0..ne)
                .map(|i| {
                    let sc = o.atol + o.rtol * x[i].abs();
                    ((k1[i] - k0[i]) / sc).powi(2)
                })
                .sum();
            (s / ne.max(1) as f64).sqrt() / h0
        };
        let h1 = if d1.max(diff) <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / d1.max(diff)).powf(1.0 / order as f64)
        };
        Ok((100.0 * h0).min(h1).min(span).min(o.h_max))
    }
}

/// The state both methods accept: `n` entries, all finite.
pub(crate) fn check_state(n: usize, t: f64, x: &[f64]) -> Result<(), StopReason> {
    if x.len() != n {
        return Err(StopReason::StateLength {
            expected: n,
            found: x.len(),
        });
    }
    if x.iter().any(|v| !v.is_finite()) {
        return Err(StopReason::NonFiniteState { t });
    }
    Ok(())
}

/// `k0 = f(t0, x0)` and the observer at the initial state, as both methods start.
pub(crate) fn first_evaluation(
    sys: &mut dyn OdeSystem,
    t: f64,
    x: &[f64],
    k0: &mut [f64],
    stats: &mut StepStats,
    observer: &mut Observer<'_>,
) -> Result<(), StopReason> {
    stats.rhs_evaluations += 1;
    sys.rhs(t, x, k0)
        .map_err(|error| StopReason::Rhs { t, error })?;
    if !observer(t, x, k0) {
        return Err(StopReason::ObserverStopped { t });
    }
    Ok(())
}

impl Integrator for DormandPrince54 {
    fn integrate(
        &mut self,
        sys: &mut dyn OdeSystem,
        t0: f64,
        x: &mut [f64],
        t_end: f64,
        observer: &mut Observer<'_>,
    ) -> IntegrationReport {
        let n = sys.dim();
        let mut stats = StepStats::default();
        let mut t = t0;
        let stop =
            |t: f64, stats: StepStats, stop: StopReason| IntegrationReport { t, stats, stop };
        if let Err(reason) = check_state(n, t, x) {
            return stop(t, stats, reason);
        }
        self.resize(n);
        let span = t_end - t0;
        if span <= 0.0 {
            return stop(t, stats, StopReason::Completed);
        }
        if let Err(reason) = first_evaluation(sys, t, x, &mut self.k[0], &mut stats, observer) {
            return stop(t, stats, reason);
        }
        let mut h = match self.options.h_initial {
            Some(h) => h.min(span),
            None => {
                stats.rhs_evaluations += 1;
                match self.initial_step(sys, t, x, span) {
                    Ok(h) => h,
                    Err(error) => return stop(t, stats, StopReason::Rhs { t, error }),
                }
            }
        };
        let mut last_rejected = false;
        let mut last_non_finite = false;
        let mut err_old = ERR_OLD_MIN;
        loop {
            if stats.accepted + stats.rejected >= self.options.max_steps {
                return stop(t, stats, StopReason::MaxSteps { t });
            }
            let remaining = t_end - t;
            let mut h_step = h.min(self.options.h_max);
            let lands = h_step >= remaining * (1.0 - 1e-12);
            if lands {
                h_step = remaining;
            }
            if !(h_step > self.options.h_min && t + h_step > t && h_step.is_finite()) {
                let reason = if last_non_finite {
                    StopReason::NonFiniteState { t }
                } else {
                    StopReason::StepSizeUnderflow { t, h: h_step }
                };
                return stop(t, stats, reason);
            }
            // Stages 2..7.
            let rows: [(f64, &[f64]); 6] = [
                (C2, &[A21]),
                (C3, &[A31, A32]),
                (C4, &[A41, A42, A43]),
                (C5, &[A51, A52, A53, A54]),
                (1.0, &[A61, A62, A63, A64, A65]),
                (1.0, &[B1, 0.0, B3, B4, B5, B6]),
            ];
            let mut failed = None;
            for (s, (c, a)) in rows.iter().enumerate() {
                let ys = if s == 5 {
                    &mut self.y_new
                } else {
                    &mut self.y_stage
                };
                let k = &self.k;
                match **a {
                    [a1] => stage_values(ys, x, k, [a1], h_step),
                    [a1, a2] => stage_values(ys, x, k, [a1, a2], h_step),
                    [a1, a2, a3] => stage_values(ys, x, k, [a1, a2, a3], h_step),
                    [a1, a2, a3, a4] => stage_values(ys, x, k, [a1, a2, a3, a4], h_step),
                    [a1, a2, a3, a4, a5] => stage_values(ys, x, k, [a1, a2, a3, a4, a5], h_step),
                    [a1, a2, a3, a4, a5, a6] => {
                        stage_values(ys, x, k, [a1, a2, a3, a4, a5, a6], h_step)
                    }
                    _ => unreachable!("DOPRI5 has six stages after the first"),
                }
                stats.rhs_evaluations += 1;
                let (_, rest) = self.k.split_at_mut(s + 1);
                let ys: &[f64] = if s == 5 { &self.y_new } else { &self.y_stage };
                if let Err(e) = sys.rhs(t + c * h_step, ys, &mut rest[0]) {
                    failed = Some(e);
                    break;
                }
            }
            let err = match failed {
                Some(RhsError::NonFinite { .. }) => f64::NAN,
                Some(error) => return stop(t, stats, StopReason::Rhs { t, error }),
                None => {
                    // Error estimate Σ e_j k_j, scaled by max(|y0|, |y1|) (HNW 4.11).
                    let o = self.options;
                    let mut s = 0.0;
                    let ne = sys.error_dim().min(n);
                    for i in 0..ne {
                        let e = h_step
                            * (E1 * self.k[0][i]
                                + E3 * self.k[2][i]
                                + E4 * self.k[3][i]
                                + E5 * self.k[4][i]
                                + E6 * self.k[5][i]
                                + E7 * self.k[6][i]);
                        let sc = o.atol + o.rtol * x[i].abs().max(self.y_new[i].abs());
                        s += (e / sc) * (e / sc);
                    }
                    (s / ne.max(1) as f64).sqrt()
                }
            };
            if !err.is_finite() || self.y_new.iter().any(|v| !v.is_finite()) {
                stats.rejected += 1;
                last_non_finite = true;
                last_rejected = true;
                h = 0.2 * h_step;
                continue;
            }
            last_non_finite = false;
            if err <= 1.0 {
                let fac = step_factor(err, err_old, &DOPRI5_CONTROL, self.options.beta);
                err_old = err.max(ERR_OLD_MIN);
                stats.accepted += 1;
                t = if lands { t_end } else { t + h_step };
                x.copy_from_slice(&self.y_new);
                // FSAL: k7 is f(t + h, y_new).
                self.k.swap(0, 6);
                sys.project(x, &mut self.k[0]);
                if !observer(t, x, &self.k[0]) {
                    return stop(t, stats, StopReason::ObserverStopped { t });
                }
                if lands {
                    return stop(t, stats, StopReason::Completed);
                }
                h = if last_rejected {
                    h_step * fac.min(1.0)
                } else {
                    h_step * fac
                };
                last_rejected = false;
            } else {
                stats.rejected += 1;
                last_rejected = true;
                h = h_step * step_factor(err, 1.0, &DOPRI5_CONTROL, self.options.beta).min(1.0);
            }
        }
    }
}

/// A stage's argument `y_i = x_i + h Σ_j a_j k_j,i` (the sum over `j` in order from `0.0`,
/// so the bits of the loop over `j` it replaces), with the `J` weights a constant-length
/// array and the slices cut to the state's length once: no bounds checks in the loop over
/// the state, which the compiler vectorises (its lanes are independent; Rust never fuses
/// `a * b + c`).
#[inline(always)]
fn stage_values<const J: usize>(ys: &mut [f64], x: &[f64], k: &[Vec<f64>; 7], a: [f64; J], h: f64) {
    let n = ys.len();
    let x = &x[..n];
    let ks: [&[f64]; J] = std::array::from_fn(|j| &k[j][..n]);
    for i in 0..n {
        let mut acc = 0.0;
        for j in 0..J {
            acc += a[j] * ks[j][i];
        }
        ys[i] = x[i] + h * acc;
    }
}

/// Adaptive explicit Runge-Kutta 8(5,3) of Dormand & Prince, "DOP853" (HNW I, II.10: the
/// 12-stage order-8 method with the combined 5th/3rd order error estimate; P. J. Prince,
/// J. R. Dormand, "High order embedded Runge-Kutta formulae", J. Comput. Appl. Math. 7
/// (1981) 67-75). Coefficients as in E. Hairer's dop853.f (version of 1996), first same
/// as last (the 13th evaluation `f(t + h, y_new)` is the next step's first stage, made
/// only for accepted steps).
///
/// Error estimate (dop853.f): with `sk_i = atol + rtol max(|y0_i|, |y1_i|)`,
/// `e5 = Σ_j E5_j k_j`, `e3 = Σ_j (b_j - b̂3_j) k_j`, `S5 = Σ (e5_i/sk_i)²`,
/// `S3 = Σ (e3_i/sk_i)²`: `err = |h| S5 / sqrt(N (S5 + 0.01 S3))` (behaves like the
/// 8th-order local error for small steps and like the 5th-order one for large ones).
/// Step control: [`step_factor`] with `α = 1/8 - 0.2 β`, factor in [1/3, 6].
///
/// Continuous extension ([`Integrator::integrate_dense`]; dop853.f `contd8`, HNW I II.6
/// and II.10): three more stages per accepted step (`c = 0.1, 0.2, 7/9`) give the
/// order-7 interpolant `y(t + θh) = y0 + θ(F0 + θ'(F1 + θ(F2 + θ'(F3 + θ(F4 + θ'(F5 +
/// θ F6))))))`, `θ' = 1 - θ`, with `F0 = Δy`, `F1 = h f0 - Δy`, `F2 = 2Δy - h(f1 + f0)`
/// and `F3..F6 = h Σ_j d_rj K_j` (coefficients of dop853.f, as transcribed in SciPy's
/// `dop853_coefficients.py`). The run driver takes its rows and locates its events on it:
/// DOP853's steps are long at a tight tolerance, and the cubic Hermite through the step
/// ends it used before is only third order (on the K1000T rail it put the rail exit
/// 6.5e-9 s early at rtol 1e-13, and the rows of a 10 s thesis flight 1.7e-6 of `η`'s
/// range off at rtol 1e-11, measured against DOPRI5 at rtol 1e-11 and 1e-12; so DOP853
/// was no tight reference between its steps). The plain [`Integrator::integrate`] does
/// not make the extra stages.
#[derive(Debug, Clone)]
pub struct Dop853 {
    /// Settings.
    pub options: AdaptiveOptions,
    k: [Vec<f64>; 12],
    y_stage: Vec<f64>,
    y_new: Vec<f64>,
    /// `f(t + h, y_new)` and the continuous extension's three extra stages (dense runs only).
    kx: [Vec<f64>; 4],
    /// The last accepted step's start state, `(t, h)` and the extension's `F_0..F_6`.
    dense_y0: Vec<f64>,
    dense_t: (f64, f64),
    dense_f: [Vec<f64>; 7],
}

/// DOP853 nodes `c_2..c_12` (dop853.f; `c_1 = 0`, `c_12 = 1`).
const D8_C: [f64; 12] = [
    0.0,
    0.526001519587677318785587544488e-01,
    0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    0.333333333333333333333333333333,
    0.25,
    0.307692307692307692307692307692,
    0.651282051282051282051282051282,
    0.6,
    0.857142857142857142857142857142,
    1.0,
];

/// DOP853 coupling coefficients `a_ij` (row `i` = stage `i + 1`, entries `j < i`), dop853.f.
const D8_A: [[f64; 11]; 12] = [
    [0.0; 11],
    [
        5.26001519587677318785587544488e-2,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
    ],
    [
        1.97250569845378994544595329183e-2,
        5.91751709536136983633785987549e-2,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
    ],
    [
        2.95875854768068491816892993775e-2,
        0.,
        8.87627564304205475450678981324e-2,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
    ],
    [
        2.41365134159266685502369798665e-1,
        0.,
        -8.84549479328286085344864962717e-1,
        9.24834003261792003115737966543e-1,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
    ],
    [
        3.7037037037037037037037037037e-2,
        0.,
        0.,
        1.70828608729473871279604482173e-1,
        1.25467687566822425016691814123e-1,
        0.,
        0.,
        0.,
        0.,
        0.,
        0.,
    ],
    [
        3.7109375e-2,
        0.,
        0.,
        1.70252211019544039314978060272e-1,
        6.02165389804559606850219397283e-2,
        -1.7578125e-2,
        0.,
        0.,
        0.,
        0.,
        0.,
    ],
    [
        3.70920001185047927108779319836e-2,
        0.,
        0.,
        1.70383925712239993810214054705e-1,
        1.07262030446373284651809199168e-1,
        -1.53194377486244017527936158236e-2,
        8.27378916381402288758473766002e-3,
        0.,
        0.,
        0.,
        0.,
    ],
    [
        6.24110958716075717114429577812e-1,
        0.,
        0.,
        -3.36089262944694129406857109825,
        -8.68219346841726006818189891453e-1,
        2.75920996994467083049415600797e1,
        2.01540675504778934086186788979e1,
        -4.34898841810699588477366255144e1,
        0.,
        0.,
        0.,
    ],
    [
        4.77662536438264365890433908527e-1,
        0.,
        0.,
        -2.48811461997166764192642586468,
        -5.90290826836842996371446475743e-1,
        2.12300514481811942347288949897e1,
        1.52792336328824235832596922938e1,
        -3.32882109689848629194453265587e1,
        -2.03312017085086261358222928593e-2,
        0.,
        0.,
    ],
    [
        -9.3714243008598732571704021658e-1,
        0.,
        0.,
        5.18637242884406370830023853209,
        1.09143734899672957818500254654,
        -8.14978701074692612513997267357,
        -1.85200656599969598641566180701e1,
        2.27394870993505042818970056734e1,
        2.49360555267965238987089396762,
        -3.0467644718982195003823669022,
        0.,
    ],
    [
        2.27331014751653820792359768449,
        0.,
        0.,
        -1.05344954667372501984066689879e1,
        -2.00087205822486249909675718444,
        -1.79589318631187989172765950534e1,
        2.79488845294199600508499808837e1,
        -2.85899827713502369474065508674,
        -8.87285693353062954433549289258,
        1.23605671757943030647266201528e1,
        6.43392746015763530355970484046e-1,
    ],
];

/// DOP853 weights `b_1..b_12` of the 8th-order solution (dop853.f).
const D8_B: [f64; 12] = [
    5.42937341165687622380535766363e-2,
    0.0,
    0.0,
    0.0,
    0.0,
    4.45031289275240888144113950566,
    1.89151789931450038304281599044,
    -5.8012039600105847814672114227,
    3.1116436695781989440891606237e-1,
    -1.52160949662516078556178806805e-1,
    2.01365400804030348374776537501e-1,
    4.47106157277725905176885569043e-2,
];

/// `b̂3` of the 3rd-order estimate, nonzero at stages 1, 9 and 12 (dop853.f `BHH1..3`).
const D8_BHH: [f64; 3] = [
    0.244094488188976377952755905512,
    0.733846688281611857341361741547,
    0.220588235294117647058823529412e-1,
];

/// `E5` of the 5th-order estimate (dop853.f `ER1, ER6..ER12`), stages 1..12.
const D8_E5: [f64; 12] = [
    0.1312004499419488073250102996e-1,
    0.0,
    0.0,
    0.0,
    0.0,
    -0.1225156446376204440720569753e1,
    -0.4957589496572501915214079952,
    0.1664377182454986536961530415e1,
    -0.3503288487499736816886487290,
    0.3341791187130174790297318841,
    0.8192320648511571246570742613e-1,
    -0.2235530786388629525884427845e-1,
];

/// The nodes of the continuous extension's three extra stages (dop853.f `c14..c16`).
const D8_C_EXTRA: [f64; 3] = [0.1, 0.2, 0.777777777777777777777777777778];

/// The extra stages' couplings (dop853.f `a141..a1615`), over `k_1..k_12`, then
/// `f(t + h, y_new)`, `k_14`, `k_15`.
const D8_A_EXTRA: [[f64; 15]; 3] = [
    [
        5.61675022830479523392909219681e-2,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        2.53500210216624811088794765333e-1,
        -2.46239037470802489917441475441e-1,
        -1.24191423263816360469010140626e-1,
        1.5329179827876569731206322685e-1,
        8.20105229563468988491666602057e-3,
        7.56789766054569976138603589584e-3,
        -8.298e-3,
        0.0,
        0.0,
    ],
    [
        3.18346481635021405060768473261e-2,
        0.0,
        0.0,
        0.0,
        0.0,
        2.83009096723667755288322961402e-2,
        5.35419883074385676223797384372e-2,
        -5.49237485713909884646569340306e-2,
        0.0,
        0.0,
        -1.08347328697249322858509316994e-4,
        3.82571090835658412954920192323e-4,
        -3.40465008687404560802977114492e-4,
        1.41312443674632500278074618366e-1,
        0.0,
    ],
    [
        -4.28896301583791923408573538692e-1,
        0.0,
        0.0,
        0.0,
        0.0,
        -4.69762141536116384314449447206,
        7.68342119606259904184240953878,
        4.06898981839711007970213554331,
        3.56727187455281109270669543021e-1,
        0.0,
        0.0,
        0.0,
        -1.39902416515901462129418009734e-3,
        2.9475147891527723389556272149,
        -9.15095847217987001081870187138,
    ],
];

/// The extension's `d41..d716` (dop853.f): `F_{3+r} = h Σ_j D8_D[r][j] K_j` over the 12
/// stages, `f(t + h, y_new)` and the three extra stages.
const D8_D: [[f64; 16]; 4] = [
    [
        -0.84289382761090128651353491142e1,
        0.0,
        0.0,
        0.0,
        0.0,
        0.56671495351937776962531783590,
        -0.30689499459498916912797304727e1,
        0.23846676565120698287728149680e1,
        0.21170345824450282767155149946e1,
        -0.87139158377797299206789907490,
        0.22404374302607882758541771650e1,
        0.63157877876946881815570249290,
        -0.88990336451333310820698117400e-1,
        0.18148505520854727256656404962e2,
        -0.91946323924783554000451984436e1,
        -0.44360363875948939664310572000e1,
    ],
    [
        0.10427508642579134603413151009e2,
        0.0,
        0.0,
        0.0,
        0.0,
        0.24228349177525818288430175319e3,
        0.16520045171727028198505394887e3,
        -0.37454675472269020279518312152e3,
        -0.22113666853125306036270938578e2,
        0.77334326684722638389603898808e1,
        -0.30674084731089398182061213626e2,
        -0.93321305264302278729567221706e1,
        0.15697238121770843886131091075e2,
        -0.31139403219565177677282850411e2,
        -0.93529243588444783865713862664e1,
        0.35816841486394083752465898540e2,
    ],
    [
        0.19985053242002433820987653617e2,
        0.0,
        0.0,
        0.0,
        0.0,
        -0.38703730874935176555105901742e3,
        -0.18917813819516756882830838328e3,
        0.52780815920542364900561016686e3,
        -0.11573902539959630126141871134e2,
        0.68812326946963000169666922661e1,
        -0.10006050966910838403183860980e1,
        0.77771377980534432092869265740,
        -0.27782057523535084065932004339e1,
        -0.60196695231264120758267380846e2,
        0.84320405506677161018159903784e2,
        0.11992291136182789328035130030e2,
    ],
    [
        -0.25693933462703749003312586129e2,
        0.0,
        0.0,
        0.0,
        0.0,
        -0.15418974869023643374053993627e3,
        -0.23152937917604549567536039109e3,
        0.35763911791061412378285349910e3,
        0.93405324183624310003907691704e2,
        -0.37458323136451633156875139351e2,
        0.10409964950896230045147246184e3,
        0.29840293426660503123344363579e2,
        -0.43533456590011143754432175058e2,
        0.96324553959188282948394950600e2,
        -0.39177261675615439165231486172e2,
        -0.14972683625798562581422125276e3,
    ],
];

impl Dop853 {
    /// A new integrator; buffers grow to the system size on first use.
    pub fn new(options: AdaptiveOptions) -> Self {
        Self {
            options,
            k: Default::default(),
            y_stage: Vec::new(),
            y_new: Vec::new(),
            kx: Default::default(),
            dense_y0: Vec::new(),
            dense_t: (0.0, 0.0),
            dense_f: Default::default(),
        }
    }

    /// The continuous extension of the step `(t, t + h)` from `x` just accepted (`k` its
    /// stages, `kx[0] = f(t + h, y_new)`): the three extra stages, then `F_0..F_6` of
    /// dop853.f's `contd8` (module doc of [`Dop853`]). False if an extra stage could not be
    /// evaluated (the step then has no extension; the driver falls back to its cubic).
    fn extend(
        &mut self,
        sys: &mut dyn OdeSystem,
        t: f64,
        h: f64,
        x: &[f64],
        stats: &mut StepStats,
    ) -> bool {
        let n = x.len();
        for s in 0..3 {
            let a = &D8_A_EXTRA[s];
            for i in 0..n {
                let mut acc = 0.0;
                for j in 0..12 {
                    acc += a[j] * self.k[j][i];
                }
                for j in 0..=s {
                    acc += a[12 + j] * self.kx[j][i];
                }
                self.y_stage[i] = x[i] + h * acc;
            }
            stats.rhs_evaluations += 1;
            let (_, rest) = self.kx.split_at_mut(s + 1);
            if sys
                .rhs(t + D8_C_EXTRA[s] * h, &self.y_stage, &mut rest[0])
                .is_err()
                || rest[0].iter().any(|v| !v.is_finite())
            {
                return false;
            }
        }
        for i in 0..n {
            let dy = self.y_new[i] - x[i];
            let (f0, f1) = (self.k[0][i], self.kx[0][i]);
            self.dense_f[0][i] = dy;
            self.dense_f[1][i] = h * f0 - dy;
            self.dense_f[2][i] = 2.0 * dy - h * (f1 + f0);
            for r in 0..4 {
                let d = &D8_D[r];
                let mut acc = 0.0;
                for j in 0..12 {
                    acc += d[j] * self.k[j][i];
                }
                for j in 0..4 {
                    acc += d[12 + j] * self.kx[j][i];
                }
                self.dense_f[3 + r][i] = h * acc;
            }
        }
        self.dense_y0.copy_from_slice(x);
        self.dense_t = (t, h);
        true
    }
}

/// DOP853's continuous extension of the last accepted step (dop853.f `contd8`):
/// `y(t + θh) = y0 + θ(F0 + θ'(F1 + θ(F2 + θ'(F3 + θ(F4 + θ'(F5 + θ F6))))))`, `θ' = 1 - θ`.
struct D8Dense<'a> {
    it: &'a Dop853,
}

impl DenseOutput for D8Dense<'_> {
    fn t_start(&self) -> f64 {
        self.it.dense_t.0
    }

    fn eval(&self, t: f64, out: &mut [f64]) {
        let (t0, h) = self.it.dense_t;
        let th = if h > 0.0 {
            ((t - t0) / h).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let th1 = 1.0 - th;
        let f = &self.it.dense_f;
        for (i, o) in out.iter_mut().enumerate().take(self.it.dense_y0.len()) {
            let mut y = f[6][i] * th;
            y = (y + f[5][i]) * th1;
            y = (y + f[4][i]) * th;
            y = (y + f[3][i]) * th1;
            y = (y + f[2][i]) * th;
            y = (y + f[1][i]) * th1;
            y = (y + f[0][i]) * th;
            *o = self.it.dense_y0[i] + y;
        }
    }
}

impl Integrator for Dop853 {
    fn integrate(
        &mut self,
        sys: &mut dyn OdeSystem,
        t0: f64,
        x: &mut [f64],
        t_end: f64,
        observer: &mut Observer<'_>,
    ) -> IntegrationReport {
        self.steps(
            sys,
            t0,
            x,
            t_end,
            &mut |t, x, dx, _| observer(t, x, dx),
            false,
        )
    }

    /// With the method's own 7th-order continuous extension (three more right-hand sides
    /// per accepted step; the steps and their bits are those of [`Self::integrate`]).
    fn integrate_dense(
        &mut self,
        sys: &mut dyn OdeSystem,
        t0: f64,
        x: &mut [f64],
        t_end: f64,
        observer: &mut DenseObserver<'_>,
    ) -> IntegrationReport {
        self.steps(sys, t0, x, t_end, observer, true)
    }
}

impl Dop853 {
    fn steps(
        &mut self,
        sys: &mut dyn OdeSystem,
        t0: f64,
        x: &mut [f64],
        t_end: f64,
        observer: &mut DenseObserver<'_>,
        dense: bool,
    ) -> IntegrationReport {
        let n = sys.dim();
        let mut stats = StepStats::default();
        let mut t = t0;
        let stop =
            |t: f64, stats: StepStats, stop: StopReason| IntegrationReport { t, stats, stop };
        if let Err(reason) = check_state(n, t, x) {
            return stop(t, stats, reason);
        }
        for k in self
            .k
            .iter_mut()
            .chain(&mut self.kx)
            .chain(&mut self.dense_f)
        {
            k.resize(n, 0.0);
        }
        self.y_stage.resize(n, 0.0);
        self.y_new.resize(n, 0.0);
        self.dense_y0.resize(n, 0.0);
        let span = t_end - t0;
        if span <= 0.0 {
            return stop(t, stats, StopReason::Completed);
        }
        if let Err(reason) =
            first_evaluation(sys, t, x, &mut self.k[0], &mut stats, &mut |t, x, dx| {
                observer(t, x, dx, None)
            })
        {
            return stop(t, stats, reason);
        }
        let o = self.options;
        let mut h = match o.h_initial {
            Some(h) => h.min(span),
            None => {
                stats.rhs_evaluations += 1;
                let [k0, k1, ..] = &mut self.k;
                match initial_step(&o, 8, sys, t, x, span, k0, k1, &mut self.y_stage) {
                    Ok(h) => h,
                    Err(error) => return stop(t, stats, StopReason::Rhs { t, error }),
                }
            }
        };
        let ne = sys.error_dim().min(n);
        let mut last_rejected = false;
        let mut last_non_finite = false;
        let mut err_old = ERR_OLD_MIN;
        loop {
            if stats.accepted + stats.rejected >= o.max_steps {
                return stop(t, stats, StopReason::MaxSteps { t });
            }
            let remaining = t_end - t;
            let mut h_step = h.min(o.h_max);
            let lands = h_step >= remaining * (1.0 - 1e-12);
            if lands {
                h_step = remaining;
            }
            if !(h_step > o.h_min && t + h_step > t && h_step.is_finite()) {
                let reason = if last_non_finite {
                    StopReason::NonFiniteState { t }
                } else {
                    StopReason::StepSizeUnderflow { t, h: h_step }
                };
                return stop(t, stats, reason);
            }
            // Stages 2..12.
            let mut failed = None;
            for s in 1..12 {
                let a = &D8_A[s];
                for i in 0..n {
                    let mut acc = 0.0;
                    for j in 0..s {
                        acc += a[j] * self.k[j][i];
                    }
                    self.y_stage[i] = x[i] + h_step * acc;
                }
                stats.rhs_evaluations += 1;
                let (_, rest) = self.k.split_at_mut(s);
                if let Err(e) = sys.rhs(t + D8_C[s] * h_step, &self.y_stage, &mut rest[0]) {
                    failed = Some(e);
                    break;
                }
            }
            let err = match failed {
                Some(RhsError::NonFinite { .. }) => f64::NAN,
                Some(error) => return stop(t, stats, StopReason::Rhs { t, error }),
                None => {
                    let (mut s5, mut s3) = (0.0, 0.0);
                    for i in 0..n {
                        let mut inc = 0.0;
                        let mut e5 = 0.0;
                        for j in 0..12 {
                            inc += D8_B[j] * self.k[j][i];
                            e5 += D8_E5[j] * self.k[j][i];
                        }
                        self.y_new[i] = x[i] + h_step * inc;
                        if i < ne {
                            let e3 = inc
                                - D8_BHH[0] * self.k[0][i]
                                - D8_BHH[1] * self.k[8][i]
                                - D8_BHH[2] * self.k[11][i];
                            let sk = o.atol + o.rtol * x[i].abs().max(self.y_new[i].abs());
                            s5 += (e5 / sk) * (e5 / sk);
                            s3 += (e3 / sk) * (e3 / sk);
                        }
                    }
                    let deno = s5 + 0.01 * s3;
                    let deno = if deno > 0.0 { deno } else { 1.0 };
                    h_step * s5 / (ne.max(1) as f64 * deno).sqrt()
                }
            };
            if !err.is_finite() || self.y_new.iter().any(|v| !v.is_finite()) {
                stats.rejected += 1;
                last_non_finite = true;
                last_rejected = true;
                h = 0.2 * h_step;
                continue;
            }
            last_non_finite = false;
            if err <= 1.0 {
                // FSAL: the 13th evaluation f(t + h, y_new) starts the next step.
                let t_new = if lands { t_end } else { t + h_step };
                stats.rhs_evaluations += 1;
                let k_last = if dense {
                    &mut self.kx[0]
                } else {
                    &mut self.k[11]
                };
                match sys.rhs(t_new, &self.y_new, k_last) {
                    Ok(()) => {}
                    Err(RhsError::NonFinite { .. }) => {
                        stats.rejected += 1;
                        last_non_finite = true;
                        last_rejected = true;
                        h = 0.2 * h_step;
                        continue;
                    }
                    Err(error) => return stop(t, stats, StopReason::Rhs { t, error }),
                }
                // The extension needs stage 12 and `f(t + h, y_new)` both (the latter
                // then takes stage 12's place as in the plain run: the same bits).
                let extended = dense && {
                    let ok = self.extend(sys, t, t_new - t, x, &mut stats);
                    let [.., k12] = &mut self.k;
                    k12.copy_from_slice(&self.kx[0]);
                    ok
                };
                let fac = step_factor(err, err_old, &DOP853_CONTROL, o.beta);
                err_old = err.max(ERR_OLD_MIN);
                stats.accepted += 1;
                t = t_new;
                x.copy_from_slice(&self.y_new);
                self.k.swap(0, 11);
                sys.project(x, &mut self.k[0]);
                let ext = D8Dense { it: self };
                let d: Option<&dyn DenseOutput> = if extended { Some(&ext) } else { None };
                if !observer(t, x, &self.k[0], d) {
                    return stop(t, stats, StopReason::ObserverStopped { t });
                }
                if lands {
                    return stop(t, stats, StopReason::Completed);
                }
                h = if last_rejected {
                    h_step * fac.min(1.0)
                } else {
                    h_step * fac
                };
                last_rejected = false;
            } else {
                stats.rejected += 1;
                last_rejected = true;
                h = h_step * step_factor(err, 1.0, &DOP853_CONTROL, o.beta).min(1.0);
            }
        }
    }
}

/// Classical fixed-step Runge-Kutta 4 (Kutta 1901), the last step shortened to land on
/// `t_end`.
#[derive(Debug, Clone)]
pub struct Rk4 {
    /// Step size.
    pub h: f64,
    k: [Vec<f64>; 4],
    y_stage: Vec<f64>,
}

impl Rk4 {
    /// A new integrator with step `h`.
    pub fn new(h: f64) -> Self {
        Self {
            h,
            k: Default::default(),
            y_stage: Vec::new(),
        }
    }
}

impl Integrator for Rk4 {
    fn integrate(
        &mut self,
        sys: &mut dyn OdeSystem,
        t0: f64,
        x: &mut [f64],
        t_end: f64,
        observer: &mut Observer<'_>,
    ) -> IntegrationReport {
        let n = sys.dim();
        let mut stats = StepStats::default();
        let mut t = t0;
        let report =
            |t: f64, stats: StepStats, stop: StopReason| IntegrationReport { t, stats, stop };
        if let Err(reason) = check_state(n, t, x) {
            return report(t, stats, reason);
        }
        if !(self.h > 0.0 && self.h.is_finite()) {
            return report(t, stats, StopReason::StepSizeUnderflow { t, h: self.h });
        }
        for k in &mut self.k {
            k.resize(n, 0.0);
        }
        self.y_stage.resize(n, 0.0);
        if let Err(reason) = first_evaluation(sys, t, x, &mut self.k[0], &mut stats, observer) {
            return report(t, stats, reason);
        }
        let steps = ((t_end - t0) / self.h).ceil().max(0.0) as usize;
        for step in 0..steps {
            let t_next = if step + 1 == steps {
                t_end
            } else {
                t0 + (step + 1) as f64 * self.h
            };
            let h = t_next - t;
            for (s, (c, a)) in [(0.5, 0.5), (0.5, 0.5), (1.0, 1.0)].iter().enumerate() {
                for i in 0..n {
                    self.y_stage[i] = x[i] + h * a * self.k[s][i];
                }
                stats.rhs_evaluations += 1;
                let (_, rest) = self.k.split_at_mut(s + 1);
                if let Err(error) = sys.rhs(t + c * h, &self.y_stage, &mut rest[0]) {
                    return report(t, stats, StopReason::Rhs { t, error });
                }
            }
            for i in 0..n {
                x[i] += h / 6.0
                    * (self.k[0][i] + 2.0 * self.k[1][i] + 2.0 * self.k[2][i] + self.k[3][i]);
            }
            t = t_next;
            stats.accepted += 1;
            if x.iter().any(|v| !v.is_finite()) {
                return report(t, stats, StopReason::NonFiniteState { t });
            }
            stats.rhs_evaluations += 1;
            if let Err(error) = sys.rhs(t, x, &mut self.k[0]) {
                return report(t, stats, StopReason::Rhs { t, error });
            }
            sys.project(x, &mut self.k[0]);
            if !observer(t, x, &self.k[0]) {
                return report(t, stats, StopReason::ObserverStopped { t });
            }
        }
        report(t, stats, StopReason::Completed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Harmonic oscillator `ẍ = -x`.
    struct Oscillator;
    impl OdeSystem for Oscillator {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), RhsError> {
            dx[0] = x[1];
            dx[1] = -x[0];
            Ok(())
        }
    }

    #[test]
    fn dormand_prince_matches_cosine_and_converges_at_order_five() {
        let mut errs = Vec::new();
        for rtol in [1e-6, 1e-9, 1e-12] {
            let mut dp = DormandPrince54::new(AdaptiveOptions {
                rtol,
                atol: rtol,
                ..Default::default()
            });
            let mut x = [1.0, 0.0];
            let r = dp.integrate(&mut Oscillator, 0.0, &mut x, 10.0, &mut |_, _, _| true);
            assert!(r.completed());
            let e = (x[0] - 10f64.cos()).abs() + (x[1] + 10f64.sin()).abs();
            errs.push((e, r.stats));
        }
        assert!(errs[2].0 < 1e-10, "{errs:?}");
        assert!(errs[0].0 > errs[1].0 && errs[1].0 > errs[2].0, "{errs:?}");
    }

    /// Order 8: on a fixed step sequence (`h_initial`, tolerances so loose every step is
    /// accepted and `h_max` caps the growth) halving the step divides the error by 2^8
    /// (a wrong coefficient drops the order to 5 or less).
    #[test]
    fn dop853_converges_at_order_eight() {
        let e = |h: f64| {
            let mut dp = Dop853::new(AdaptiveOptions {
                rtol: 0.9,
                atol: 0.9,
                h_initial: Some(h),
                h_max: h,
                ..Default::default()
            });
            let mut x = [1.0, 0.0];
            let r = dp.integrate(&mut Oscillator, 0.0, &mut x, 8.0, &mut |_, _, _| true);
            assert!(r.completed() && r.stats.rejected == 0, "{r:?}");
            (x[0] - 8f64.cos()).abs() + (x[1] + 8f64.sin()).abs()
        };
        // Observed orders log2(e(h)/e(h/2)) of 8.21 and 7.91 (below h = 0.2 round-off
        // takes over: e(0.1) ~ 1e-14).
        for (a, b) in [(0.8, 0.4), (0.4, 0.2)] {
            let order = (e(a) / e(b)).log2();
            assert!((order - 8.0).abs() < 0.3, "h {a}: order {order}");
        }
    }

    /// The largest error of the rows at `θ = ¼, ½, ¾` of every step of a dense run of the
    /// oscillator over `[0, 20]`, taken as the run driver takes them: from the step's
    /// continuous extension if it has one, else from the cubic Hermite through the step's
    /// ends and derivatives.
    fn dense_row_error(it: &mut dyn Integrator) -> (f64, StepStats) {
        let mut prev: Option<(f64, [f64; 2], [f64; 2])> = None;
        let mut worst = 0.0f64;
        let mut x = [1.0, 0.0];
        let r = it.integrate_dense(
            &mut Oscillator,
            0.0,
            &mut x,
            20.0,
            &mut |t, x, dx, dense| {
                if let Some((tp, xp, dp)) = prev {
                    let h = t - tp;
                    for th in [0.25, 0.5, 0.75] {
                        let tau = tp + th * h;
                        let mut y = [0.0; 2];
                        match dense {
                            Some(d) => d.eval(tau, &mut y),
                            None => {
                                let (h00, h10) = (
                                    (1.0 + 2.0 * th) * (1.0 - th) * (1.0 - th),
                                    th * (1.0 - th) * (1.0 - th),
                                );
                                let (h01, h11) = (th * th * (3.0 - 2.0 * th), th * th * (th - 1.0));
                                for i in 0..2 {
                                    y[i] = h00 * xp[i]
                                        + h * h10 * dp[i]
                                        + h01 * x[i]
                                        + h * h11 * dx[i];
                                }
                            }
                        }
                        let e = (y[0] - tau.cos()).abs().max((y[1] + tau.sin()).abs());
                        worst = worst.max(e);
                    }
                }
                prev = Some((t, [x[0], x[1]], [dx[0], dx[1]]));
                true
            },
        );
        assert!(r.completed(), "{r:?}");
        (worst, r.stats)
    }

    /// DOP853's rows between its (long) steps come from its own 7th-order continuous
    /// extension (dop853.f `contd8`), so a tight-tolerance run is a tight reference between
    /// the steps too. With the cubic Hermite the run driver used before, the rows of this
    /// run (rtol = atol = 1e-11, 82 steps of about 0.24) were 1.0e-5 off the solution,
    /// 10^6 times the tolerance; with the extension 2.3e-11 (measured). The steps, and so the state at the
    /// step ends, keep their bits.
    #[test]
    fn dop853_rows_between_long_steps_follow_the_solution() {
        let opts = AdaptiveOptions {
            rtol: 1e-11,
            atol: 1e-11,
            ..Default::default()
        };
        let (e, stats) = dense_row_error(&mut Dop853::new(opts));
        eprintln!("dop853 rows: {e:.2e} ({stats:?})");
        assert!(e < 1e-9, "{e:e}");
        // The same steps and end state as the plain run.
        let mut a = [1.0, 0.0];
        let mut b = [1.0, 0.0];
        let ra =
            Dop853::new(opts).integrate(&mut Oscillator, 0.0, &mut a, 20.0, &mut |_, _, _| true);
        let rb = Dop853::new(opts).integrate_dense(
            &mut Oscillator,
            0.0,
            &mut b,
            20.0,
            &mut |_, _, _, _| true,
        );
        assert_eq!(ra.stats.accepted, rb.stats.accepted);
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
    }

    /// The continuous extension is of order 7: on one fixed step from the oscillator's
    /// start, its error at `θ = 0.37` falls by about 2^8 when the step halves (local error
    /// `O(h^8)`); a wrong `D8_D` or extra-stage coefficient drops it to 4 or less.
    #[test]
    fn dop853_continuous_extension_is_of_order_seven() {
        let e = |h: f64| {
            let mut dp = Dop853::new(AdaptiveOptions {
                rtol: 0.9,
                atol: 0.9,
                h_initial: Some(h),
                h_max: h,
                ..Default::default()
            });
            let mut x = [1.0, 0.0];
            let mut err = f64::NAN;
            let tau = 0.37 * h;
            let r = dp.integrate_dense(&mut Oscillator, 0.0, &mut x, h, &mut |_, _, _, d| {
                if let Some(d) = d {
                    let mut y = [0.0; 2];
                    d.eval(tau, &mut y);
                    err = (y[0] - tau.cos()).abs() + (y[1] + tau.sin()).abs();
                }
                true
            });
            assert!(r.completed(), "{r:?}");
            err
        };
        for (a, b) in [(1.6, 0.8), (0.8, 0.4)] {
            let order = (e(a) / e(b)).log2();
            eprintln!("h {a}: {:.3e} -> {:.3e}, log2 ratio {order:.2}", e(a), e(b));
            assert!(order > 7.5, "h {a}: log2 ratio {order}");
        }
    }

    /// Tolerance proportionality: at rtol 1e-6 .. 1e-12 the global error tracks the
    /// tolerance, and DOP853 needs fewer evaluations than DOPRI5 at the tight end.
    #[test]
    fn dop853_matches_cosine_with_fewer_evaluations_than_dopri5_at_tight_tolerance() {
        for rtol in [1e-6, 1e-9, 1e-12] {
            let opts = AdaptiveOptions {
                rtol,
                atol: rtol,
                ..Default::default()
            };
            let mut x8 = [1.0, 0.0];
            let r8 =
                Dop853::new(opts)
                    .integrate(&mut Oscillator, 0.0, &mut x8, 10.0, &mut |_, _, _| true);
            let mut x5 = [1.0, 0.0];
            let r5 = DormandPrince54::new(opts).integrate(
                &mut Oscillator,
                0.0,
                &mut x5,
                10.0,
                &mut |_, _, _| true,
            );
            assert!(r8.completed() && r5.completed());
            let e8 = (x8[0] - 10f64.cos()).abs() + (x8[1] + 10f64.sin()).abs();
            assert!(e8 < 100.0 * rtol, "rtol {rtol}: {e8}");
            if rtol <= 1e-9 {
                assert!(
                    r8.stats.rhs_evaluations < r5.stats.rhs_evaluations,
                    "{r8:?} {r5:?}"
                );
            }
        }
    }

    /// The PI controller (β = 0.04) against the standard one (β = 0) on a problem with
    /// frequent step-size changes (a stiff-ish oscillator in the accuracy regime): fewer
    /// rejected steps, the same accuracy class.
    #[test]
    fn pi_controller_rejects_fewer_steps_than_the_standard_one() {
        let run = |beta: f64| {
            let mut dp = DormandPrince54::new(AdaptiveOptions {
                rtol: 1e-6,
                atol: 1e-9,
                beta,
                ..Default::default()
            });
            let mut x = [1.0, 0.0, 0.0, 1.0];
            let r = dp.integrate(&mut TwoScale, 0.0, &mut x, 20.0, &mut |_, _, _| true);
            assert!(r.completed());
            r.stats
        };
        let (std, pi) = (run(0.0), run(PI_BETA));
        assert!(pi.rejected < std.rejected, "standard {std:?}, PI {pi:?}");
    }

    /// A slow oscillator driving a fast lightly damped one (the fin modes on the rigid
    /// motion, in miniature).
    struct TwoScale;
    impl OdeSystem for TwoScale {
        fn dim(&self) -> usize {
            4
        }
        fn rhs(&mut self, _t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), RhsError> {
            dx[0] = x[1];
            dx[1] = -x[0];
            dx[2] = x[3];
            dx[3] = -400.0 * x[2] - 0.2 * x[3] + 50.0 * x[0] * x[0];
            Ok(())
        }
    }

    #[test]
    fn rk4_error_falls_by_sixteen_when_step_halves() {
        let e = |h: f64| {
            let mut x = [1.0, 0.0];
            let r = Rk4::new(h).integrate(&mut Oscillator, 0.0, &mut x, 5.0, &mut |_, _, _| true);
            assert!(r.completed());
            (x[0] - 5f64.cos()).abs()
        };
        let ratio = e(0.02) / e(0.01);
        assert!((ratio - 16.0).abs() < 0.5, "{ratio}");
    }

    struct Blowup;
    impl OdeSystem for Blowup {
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&mut self, _t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), RhsError> {
            dx[0] = x[0] * x[0];
            Ok(())
        }
    }

    #[test]
    fn finite_time_blowup_stops_without_panic() {
        let mut dp = DormandPrince54::new(AdaptiveOptions::default());
        let mut x = [1.0];
        let r = dp.integrate(&mut Blowup, 0.0, &mut x, 2.0, &mut |_, _, _| true);
        assert!(!r.completed());
        assert!((r.t - 1.0).abs() < 1e-2, "{r:?}");
        assert!(matches!(
            r.stop,
            StopReason::StepSizeUnderflow { .. } | StopReason::NonFiniteState { .. }
        ));
    }
}
