//! The flight's verdict when the vehicle leaves the model it integrates (issue 32).
//!
//! The equations of motion (3.2.1) are linear in the modal coordinates `η` (small elastic
//! deformation about the floating frame) and the aerodynamic blocks are linear in the local
//! incidence. A flight whose modes grow without bound (flutter, divergence) leaves both
//! models long before the integrator notices: in the linear model the deformation grows
//! exponentially to any size, the blow-up feeds absurd loads into the rigid body, and the run
//! would go on to "land". The run therefore stops, by default, at the first state outside
//! the model ([`crate::plan::ModelLimits`], checked after every accepted step and located by
//! bisection as every stop condition):
//!
//! - **Elastic displacement of any node beyond 10 % of the fin span** (of the body length
//!   without fins, 2 %). The bound is a small-rotation bound: a cantilever whose tip deflects
//!   by `δ` under a tip load has the tip slope `θ = 3δ / (2L)` (Euler-Bernoulli beam; e.g.
//!   Timoshenko & Gere, *Mechanics of Materials*, the cantilever's deflection and slope
//!   `PL³/3EI`, `PL²/2EI`), so `δ = 0.1 L` is `θ = 0.15 rad` (8.6 deg), where `sin θ` differs
//!   from `θ` by 0.4 % and `tan θ` by 0.75 %: beyond it neither the linear strain-displacement
//!   relations of the shell and beam elements nor the linear incidence of the fin's panels
//!   (both use `θ` for `sin θ`, `tan θ`) describe the fin. It is a bound of the model, not a
//!   strength: it says where the answer stops being an answer.
//! - **Fin root stress beyond the material's yield stress** (5.6; where the material states
//!   one and the user set no `fin_aero { stress_limit }`): the end of linear elasticity.
//!
//! At the verdict the run looks back over the accepted steps ([`ModalTrace`]) to say what
//! happened: per mode, the energy `E_m = ½ (K̄_mm η_m² + M̄_mm η̇_m²)` (the diagonal of the
//! modal strain and kinetic energies), its growth rate and its frequency:
//!
//! - window: from the last accepted step at which the total `Σ E_m` was below
//!   [`WINDOW_ENERGY_RATIO`] of its value at the verdict (the exponential part of the growth,
//!   not the forced response before it), else the whole trace;
//! - growth rate `σ_m`, 1/s, of the amplitude: half the least-squares slope of `ln E_m(t)`
//!   over the window (`E ∝ A²`);
//! - frequency: from the zero crossings of `η_m` in the window (each located by linear
//!   interpolation), `f = (N - 1) / (2 (t_N - t_1))`, when there are at least three (one full
//!   cycle);
//! - the growing modes: those with at least [`SHARE`] of the energy at the verdict and a
//!   positive growth rate, the total energy having grown at least [`GROWTH_RATIO`]-fold over
//!   the window;
//! - kind: **flutter** when the dominant growing mode oscillates, **divergence** when it
//!   grows without oscillating (a static aeroelastic instability), **model limit** when
//!   nothing grows (a bound crossed by a load, not an instability).

use super::eom::StateLayout;

/// The window starts where the total modal energy was below this fraction of its value at
/// the verdict (amplitude ratio about 32).
pub const WINDOW_ENERGY_RATIO: f64 = 1e-3;

/// A mode with less than this share of the modal energy at the verdict is not reported.
pub const SHARE: f64 = 0.05;

/// The total modal energy must grow at least this much over the window for growth.
pub const GROWTH_RATIO: f64 = 10.0;

/// Accepted steps kept for the verdict (a ring buffer; the oldest are overwritten).
pub const TRACE_CAPACITY: usize = 8192;

/// What a verdict says happened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VerdictKind {
    /// Oscillatory growth of the modes.
    Flutter,
    /// Non-oscillatory growth of the modes (static aeroelastic divergence).
    Divergence,
    /// A bound of the model was crossed without modal growth (a load).
    ModelLimit,
}

impl VerdictKind {
    /// The code in `summary.json` (`stop_reason` and `verdict.kind`).
    pub fn code(self) -> &'static str {
        match self {
            VerdictKind::Flutter => "flutter",
            VerdictKind::Divergence => "divergence",
            VerdictKind::ModelLimit => "model_limit",
        }
    }
}

/// One mode's growth at the verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct GrowingMode {
    /// The mode's index among the selected modes.
    pub mode: usize,
    /// Amplitude growth rate `σ`, 1/s (the energy grows as `e^{2σt}`).
    pub growth_rate: f64,
    /// Frequency from the zero crossings, Hz (None: fewer than three crossings).
    pub frequency_hz: Option<f64>,
    /// Share of the modal energy at the verdict.
    pub energy_share: f64,
}

/// The verdict of a run that left its model.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    pub kind: VerdictKind,
    /// Time, s (the located first state outside the model).
    pub t: f64,
    /// The bound crossed, for people.
    pub criterion: String,
    /// The modes with a share of the energy, largest share first.
    pub modes: Vec<GrowingMode>,
    /// Length of the window the growth was measured over, s.
    pub window: f64,
    /// The bound crossed was the flow's (air from behind the vehicle, beyond its body
    /// table: `run::Monitor::stop_condition`), not the structure's: it says nothing of the
    /// modes, and the flutter margin up to it stands.
    pub flow: bool,
}

/// The modal coordinates and rates at the last accepted steps, in a ring buffer allocated
/// once (no allocation per step).
#[derive(Debug, Clone)]
pub struct ModalTrace {
    n: usize,
    cap: usize,
    /// `cap` records of `1 + 2n` values: t, η, η̇.
    data: Vec<f64>,
    /// Records written so far (the newest at `(len - 1) % cap`).
    len: usize,
    last_t: f64,
}

impl ModalTrace {
    pub fn new(n: usize, capacity: usize) -> Self {
        let cap = if n == 0 { 0 } else { capacity.max(2) };
        ModalTrace {
            n,
            cap,
            data: vec![0.0; cap * (1 + 2 * n)],
            len: 0,
            last_t: f64::NEG_INFINITY,
        }
    }

    /// Records the state `x` at `t` (a time not after the last one is ignored).
    pub fn push(&mut self, layout: StateLayout, t: f64, x: &[f64]) {
        if self.cap == 0 || t <= self.last_t {
            return;
        }
        let w = 1 + 2 * self.n;
        let i = self.len % self.cap;
        let rec = &mut self.data[i * w..(i + 1) * w];
        rec[0] = t;
        let e = StateLayout::ETA;
        rec[1..].copy_from_slice(&x[e..e + 2 * self.n]);
        debug_assert_eq!(layout.n, self.n);
        self.len += 1;
        self.last_t = t;
    }

    /// The records in time order.
    fn records(&self) -> impl Iterator<Item = &[f64]> {
        let w = 1 + 2 * self.n;
        let count = self.len.min(self.cap);
        let start = if self.len > self.cap {
            self.len % self.cap
        } else {
            0
        };
        (0..count).map(move |k| {
            let i = (start + k) % self.cap;
            &self.data[i * w..(i + 1) * w]
        })
    }

    /// The verdict at `t` for the bound `criterion`, from the recorded steps, with the modal
    /// mass and stiffness matrices (`n x n`, row-major).
    pub fn verdict(
        &self,
        t: f64,
        criterion: String,
        modal_mass: &[f64],
        modal_stiffness: &[f64],
    ) -> Verdict {
        let n = self.n;
        let recs: Vec<&[f64]> = self.records().collect();
        let energy = |r: &[f64], m: usize| {
            0.5 * (modal_stiffness[m * n + m] * r[1 + m] * r[1 + m]
                + modal_mass[m * n + m] * r[1 + n + m] * r[1 + n + m])
        };
        let total = |r: &[f64]| (0..n).map(|m| energy(r, m)).sum::<f64>();
        let none = Verdict {
            kind: VerdictKind::ModelLimit,
            t,
            criterion: criterion.clone(),
            modes: Vec::new(),
            window: 0.0,
            flow: false,
        };
        let Some(last) = recs.last() else {
            return none;
        };
        let e_final = total(last);
        if !(e_final > 0.0 && e_final.is_finite()) {
            return none;
        }
        let i0 = recs
            .iter()
            .rposition(|r| total(r) <= WINDOW_ENERGY_RATIO * e_final)
            .unwrap_or(0);
        let win = &recs[i0..];
        if win.len() < 3 {
            return none;
        }
        let (t0, t1) = (win[0][0], win[win.len() - 1][0]);
        let grew = e_final >= GROWTH_RATIO * total(win[0]);
        let mut modes = Vec::new();
        for m in 0..n {
            let share = energy(last, m) / e_final;
            if share < SHARE {
                continue;
            }
            // Least-squares slope of ln E_m(t).
            let floor = 1e-300_f64;
            let pts: Vec<(f64, f64)> = win
                .iter()
                .map(|r| (r[0], energy(r, m).max(floor).ln()))
                .collect();
            let np = pts.len() as f64;
            let tm = pts.iter().map(|p| p.0).sum::<f64>() / np;
            let lm = pts.iter().map(|p| p.1).sum::<f64>() / np;
            let sxx = pts.iter().map(|p| (p.0 - tm) * (p.0 - tm)).sum::<f64>();
            let sxy = pts.iter().map(|p| (p.0 - tm) * (p.1 - lm)).sum::<f64>();
            let sigma = if sxx > 0.0 { 0.5 * sxy / sxx } else { 0.0 };
            // Zero crossings of η_m.
            let mut crossings = Vec::new();
            for w in win.windows(2) {
                let (a, b) = (w[0][1 + m], w[1][1 + m]);
                if a == 0.0 || a.signum() != b.signum() && b != 0.0 {
                    let tc = if a == b {
                        w[0][0]
                    } else {
                        w[0][0] + (w[1][0] - w[0][0]) * a / (a - b)
                    };
                    crossings.push(tc);
                }
            }
            let frequency_hz = (crossings.len() >= 3).then(|| {
                let span = crossings[crossings.len() - 1] - crossings[0];
                (crossings.len() - 1) as f64 / (2.0 * span)
            });
            modes.push(GrowingMode {
                mode: m,
                growth_rate: sigma,
                frequency_hz,
                energy_share: share,
            });
        }
        modes.sort_by(|a, b| b.energy_share.total_cmp(&a.energy_share));
        let kind = match modes.first() {
            Some(d) if grew && d.growth_rate > 0.0 => {
                if d.frequency_hz.is_some() {
                    VerdictKind::Flutter
                } else {
                    VerdictKind::Divergence
                }
            }
            _ => VerdictKind::ModelLimit,
        };
        Verdict {
            kind,
            t,
            criterion,
            modes,
            window: t1 - t0,
            flow: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A layout of `n` modes with no motor or energy states.
    fn trace_of(n: usize, f: impl Fn(f64) -> Vec<f64>, ts: &[f64]) -> ModalTrace {
        let layout = StateLayout { n };
        let mut tr = ModalTrace::new(n, TRACE_CAPACITY);
        let mut x = vec![0.0; layout.len()];
        for &t in ts {
            let v = f(t);
            x[StateLayout::ETA..StateLayout::ETA + 2 * n].copy_from_slice(&v);
            tr.push(layout, t, &x);
        }
        tr
    }

    fn times(t_end: f64, dt: f64) -> Vec<f64> {
        (0..=((t_end / dt).round() as usize))
            .map(|i| i as f64 * dt)
            .collect()
    }

    #[test]
    fn a_growing_oscillation_is_flutter_with_its_growth_rate_and_frequency() {
        // η = e^{σt} sin(ωt) of a unit-mass mode with stiffness ω²: over whole cycles the
        // energy is ½ ω² e^{2σt} (plus O(σ/ω) ripple).
        for (sigma, hz) in [(5.0, 90.0), (20.0, 35.0), (2.0, 12.0)] {
            let w = 2.0 * std::f64::consts::PI * hz;
            let tr = trace_of(
                1,
                |t| {
                    let e = (sigma * t).exp();
                    vec![
                        e * (w * t).sin(),
                        e * (sigma * (w * t).sin() + w * (w * t).cos()),
                    ]
                },
                &times(3.0, 1e-4),
            );
            let v = tr.verdict(3.0, "bound".into(), &[1.0], &[w * w]);
            assert_eq!(v.kind, VerdictKind::Flutter);
            let m = &v.modes[0];
            assert!(
                (m.growth_rate - sigma).abs() < 0.02 * sigma,
                "{sigma} {m:?}"
            );
            assert!(
                (m.frequency_hz.unwrap() - hz).abs() < 1e-3 * hz,
                "{hz} {m:?}"
            );
        }
    }

    #[test]
    fn monotone_growth_is_divergence_and_no_growth_is_a_model_limit() {
        let tr = trace_of(
            1,
            |t| vec![(8.0 * t).exp(), 8.0 * (8.0 * t).exp()],
            &times(2.0, 1e-3),
        );
        let v = tr.verdict(2.0, "bound".into(), &[1.0], &[100.0]);
        assert_eq!(v.kind, VerdictKind::Divergence);
        assert!((v.modes[0].growth_rate - 8.0).abs() < 0.05, "{v:?}");
        // A steady oscillation (a load, no growth).
        let w = 2.0 * std::f64::consts::PI * 20.0;
        let tr = trace_of(
            1,
            |t| vec![(w * t).sin(), w * (w * t).cos()],
            &times(2.0, 1e-4),
        );
        let v = tr.verdict(2.0, "bound".into(), &[1.0], &[w * w]);
        assert_eq!(v.kind, VerdictKind::ModelLimit);
    }

    #[test]
    fn the_ring_buffer_keeps_the_newest_steps_in_order() {
        let layout = StateLayout { n: 1 };
        let mut tr = ModalTrace::new(1, 4);
        let mut x = vec![0.0; layout.len()];
        for i in 0..10 {
            x[StateLayout::ETA] = i as f64;
            tr.push(layout, i as f64, &x);
        }
        let ts: Vec<f64> = tr.records().map(|r| r[0]).collect();
        assert_eq!(ts, vec![6.0, 7.0, 8.0, 9.0]);
        let etas: Vec<f64> = tr.records().map(|r| r[1]).collect();
        assert_eq!(etas, ts);
    }
}
