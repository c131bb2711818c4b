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
}

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
        }
    }
}

/// Adaptive explicit Runge-Kutta 5(4) of Dormand & Prince (1980), local extrapolation,
/// first-same-as-last, standard step control (HNW I, II.4 (4.11)-(4.13): safety 0.9,
/// factor in [0.2, 10], no growth right after a rejection).
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

    /// RMS norm of `v` weighted by `atol + rtol |y|`, HNW (4.11).
    fn scaled_norm(&self, y: &[f64], v: &[f64], ne: usize) -> f64 {
        let o = &self.options;
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

    /// Starting step size, HNW I, II.4 ("Starting Step Size", steps a-f), order 5.
    fn initial_step(
        &mut self,
        sys: &mut dyn OdeSystem,
        t0: f64,
        x: &[f64],
        span: f64,
    ) -> Result<f64, RhsError> {
        let ne = sys.error_dim().min(x.len());
        let d0 = self.scaled_norm(x, x, ne);
        let d1 = self.scaled_norm(x, &self.k[0], ne);
        let h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        }
        .min(span);
        for i in 0..x.len() {
            self.y_stage[i] = x[i] + h0 * self.k[0][i];
        }
        let [k0, k1, ..] = &mut self.k;
        sys.rhs(t0 + h0, &self.y_stage, k1)?;
        let diff: f64 = {
            let o = &self.options;
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
            (0.01 / d1.max(diff)).powf(1.0 / 5.0)
        };
        Ok((100.0 * h0).min(h1).min(span).min(self.options.h_max))
    }
}

/// The state both methods accept: `n` entries, all finite.
fn check_state(n: usize, t: f64, x: &[f64]) -> Result<(), StopReason> {
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
fn first_evaluation(
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
                for i in 0..n {
                    let mut acc = 0.0;
                    for (j, aj) in a.iter().enumerate() {
                        acc += aj * self.k[j][i];
                    }
                    ys[i] = x[i] + h_step * acc;
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
            // HNW (4.13): h_new = h · min(facmax, max(facmin, 0.9 err^(-1/5))).
            let fac = if err == 0.0 {
                10.0
            } else {
                (0.9 * err.powf(-0.2)).clamp(0.2, 10.0)
            };
            if err <= 1.0 {
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
                h = h_step * fac.min(1.0);
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
