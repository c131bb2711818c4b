//! The linearised 3-D model (issue #5 item 3; beyond the thesis, which has only the planar
//! eigen-analyses of 6.1-6.2 and the time-domain runs of 6.3-6.5).
//!
//! # Reference condition (trim)
//! Ballistic flight (thrust blocks dropped, stimuli removed) at speed `V` and altitude `h`,
//! `α = β = 0`: `V_B = (V, 0, 0)`, `ω_B = 0`, attitude the scenario's initial one,
//! `η̇ = 0`. The elastic deflection `η*` is the static balance of the modal equations of
//! (3.2.1) at that condition: with `η̇ = 0`, `ω = 0` the modal rows of
//! `M_tot(η) v̇ = f(η) - [0; 0; K̄η]` (see [`crate::runtime::eom`]) read
//! `P̄ᵀ V̇ + H̄_totᵀ ω̇ + M̄ η̈ = Q(η) - K̄ η`; we solve `η̈(η) = 0` for `η` by Newton's method on
//! the full coupled right-hand side (finite-difference `n x n` Jacobian, backtracking),
//! which is `K̄ η = Q(η) - P̄ᵀ V̇ - H̄_totᵀ ω̇`: the aero and gravity loads minus the inertial
//! relief of the rigid accelerations they cause (under gravity alone `Q = P̄ᵀ g_B` and
//! `V̇ = g_B`, so a free-falling vehicle is not deformed). The rigid accelerations are
//! not zero (drag decelerates, gravity pulls): the linearisation is the frozen-time Jacobian
//! about this reference, as usual for ballistic stability.
//!
//! # Linear state
//! `δ = (δθ(3), δV_B(3), δω_B(3), δη(n), δη̇(n))`, `9 + 2n` entries. The inertial position is
//! dropped (the altitude is frozen: density and `g` stay at the reference values). The
//! attitude lives on the tangent space of the Euler parameters:
//! `q = δq ⊗ q0`, `δq ∝ (δθ/2, 1)` (Hughes' order `(ε, η)`), i.e.
//! `C_BI(q) = C_BI(δq) C_BI(q0)` and `C_BI(δq) = 1 - δθ^× + O(δθ²)` (eq. 4.4.9 with
//! `ε = δθ/2`, `η ≈ 1`). `δθ = 2 δε/δη` is twice the Gibbs vector of `δq`. Since `C_BI(q0)`
//! is constant, `δq` obeys the same kinematics (4.4.11)-(4.4.12) as `q`:
//! `δε̇ = ½(δε^× + δη) ω`, `δη̇ = -½ δεᵀω`, so
//! `δθ̇ = 2(δε̇ δη - δε δη̇)/δη² = ω + ½ δθ × ω + ¼ δθ (δθ·ω)` (derived here, exact).
//! Gravity's dependence on attitude is kept by default: `g_B = C_BI g_I` (eq. 5.1.3) is
//! evaluated at the perturbed `q`, so the `δθ` columns of the Jacobian carry
//! `∂g_B/∂δθ = (g_B)^×` into the force, moment and modal rows;
//! [`LineariseOptions::gravity_follows_attitude`] = `false` drops that path (gravity frozen
//! in body axes).
//!
//! # Jacobian
//! Central differences, column `j`: `A e_j = (f̃(δ + h_j e_j) - f̃(δ - h_j e_j)) / (2 h_j)`
//! with `h_j = ε^{1/3} max(|x_j|, s_j)` (`ε` the machine epsilon, the step that balances
//! truncation `O(h²)` and rounding `O(ε/h)`), where the floor scale `s_j` is 1 rad for
//! `δθ`, `max(|V_B|, 1 m/s)` for `δV`, 1 rad/s for `δω`, `s_m` for `δη_m` (the modal
//! amplitude that moves some node by 1 m: `1 / max_node |S_trans φ_m|`) and `ω_m s_m` for
//! `δη̇_m`.

// Index loops follow the block formulas above.
#![allow(clippy::needless_range_loop)]

use faer::Mat;
use faer::linalg::solvers::SolveCore;
use serde::Serialize;

use crate::runtime::eom::StateLayout;
use crate::runtime::integrate::{OdeSystem, RhsError};
use crate::runtime::kinematics::{cross, dot};

/// Why a linearisation could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LineariseError {
    /// The right-hand side failed at a perturbed state.
    #[error("right-hand side failed at the {what}: {error}")]
    Rhs { what: &'static str, error: RhsError },
    /// The reference state does not fit the model.
    #[error("reference state has {found} entries, the model needs {expected}")]
    StateLength { expected: usize, found: usize },
    /// The static balance of the modal equations has no solution found by Newton's method.
    #[error(
        "trim: the static elastic balance did not converge in {iterations} Newton iterations \
         (scaled residual {residual:.3e})"
    )]
    TrimNotConverged { iterations: usize, residual: f64 },
    /// A linear solve met a singular or non-finite matrix.
    #[error("{what}: singular or non-finite matrix")]
    Singular { what: &'static str },
    /// The eigen-decomposition failed.
    #[error("eigen-decomposition of the {dim} x {dim} state matrix did not converge")]
    Eigen { dim: usize },
}

/// Settings of the trim and the linearisation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LineariseOptions {
    /// Newton iterations of the trim.
    pub max_trim_iterations: usize,
    /// Trim convergence: largest `|Δη_m| / s_m` of a Newton step.
    pub trim_tolerance: f64,
    /// Roots with `|λ|` below this (rad/s) count as neutral rigid-body drift: the exact
    /// zeros (roll angle, heading, pitch attitude of a free body) and the slow roots that
    /// the frozen ballistic reference adds (gravity across the velocity turns a roll angle
    /// into a slow spiral-like sideslip departure, `|λ| ~ 5e-3` rad/s for SPHADS-1). They
    /// take no part in `sigma_d` and the classification (they are listed, and
    /// `max_real_all` includes them). Default `1e-2` rad/s: a time constant of 100 s, ten
    /// times the 10 s flights of thesis 6.5.
    pub neutral_tolerance: f64,
    /// Rotate gravity with the attitude perturbation (`true`, the complete linearisation)
    /// or keep `g_B` at its reference value (`false`): then the `δθ` columns of every row
    /// but `δθ̇` are zero, which removes the slow gravity-driven roots of the frozen
    /// ballistic reference (the flight path of the real trajectory curves under gravity, the
    /// frozen reference does not) and leaves three exact zero attitude roots.
    pub gravity_follows_attitude: bool,
}

impl Default for LineariseOptions {
    fn default() -> Self {
        Self {
            max_trim_iterations: 30,
            trim_tolerance: 1e-12,
            neutral_tolerance: 1e-2,
            gravity_follows_attitude: true,
        }
    }
}

/// Quaternion product in Hughes' order `(ε, η)`, defined so that
/// `C_BI(a ⊗ b) = C_BI(a) C_BI(b)` (eq. 4.4.9): `ε = η_b ε_a + η_a ε_b - ε_a × ε_b`,
/// `η = η_a η_b - ε_a·ε_b` (composition of eq. 4.4.9; checked against the matrix product in
/// the tests).
pub fn quaternion_product(a: &[f64; 4], b: &[f64; 4]) -> [f64; 4] {
    let ea = [a[0], a[1], a[2]];
    let eb = [b[0], b[1], b[2]];
    let x = cross(&ea, &eb);
    [
        b[3] * ea[0] + a[3] * eb[0] - x[0],
        b[3] * ea[1] + a[3] * eb[1] - x[1],
        b[3] * ea[2] + a[3] * eb[2] - x[2],
        a[3] * b[3] - dot(&ea, &eb),
    ]
}

/// The Euler parameters `q = δq ⊗ q0` of the tangent-space perturbation `δθ` about `q0`,
/// `δq = (δθ/2, 1) / |(δθ/2, 1)|` (module doc).
pub fn perturb_attitude(q0: &[f64; 4], dtheta: &[f64; 3]) -> [f64; 4] {
    let h = [0.5 * dtheta[0], 0.5 * dtheta[1], 0.5 * dtheta[2], 1.0];
    let s = 1.0 / h.iter().map(|v| v * v).sum::<f64>().sqrt();
    quaternion_product(&h.map(|v| v * s), q0)
}

/// The tangent coordinates `δθ = 2 δε / δη` of `q` about `q0` (`δq = q ⊗ q0⁻¹`, with
/// `q0⁻¹ = (-ε0, η0)` for unit `q0`); the inverse of [`perturb_attitude`].
pub fn attitude_perturbation(q0: &[f64; 4], q: &[f64; 4]) -> [f64; 3] {
    let inv = [-q0[0], -q0[1], -q0[2], q0[3]];
    let d = quaternion_product(q, &inv);
    [0, 1, 2].map(|i| 2.0 * d[i] / d[3])
}

/// `δθ̇ = ω + ½ δθ × ω + ¼ δθ (δθ·ω)`: the rate of the tangent coordinates (module doc).
pub fn tangent_rate(dtheta: &[f64; 3], omega: &[f64; 3]) -> [f64; 3] {
    let x = cross(dtheta, omega);
    let s = 0.25 * dot(dtheta, omega);
    [0, 1, 2].map(|i| omega[i] + 0.5 * x[i] + s * dtheta[i])
}

/// Central-difference Jacobian of `f: R^d -> R^d` at `x0` with steps `h` (row-major `d x d`).
pub fn central_jacobian<E>(
    x0: &[f64],
    h: &[f64],
    mut f: impl FnMut(&[f64], &mut [f64]) -> Result<(), E>,
) -> Result<Vec<f64>, E> {
    let d = x0.len();
    let mut a = vec![0.0; d * d];
    let mut x = x0.to_vec();
    let (mut fp, mut fm) = (vec![0.0; d], vec![0.0; d]);
    for j in 0..d {
        x[j] = x0[j] + h[j];
        f(&x, &mut fp)?;
        x[j] = x0[j] - h[j];
        f(&x, &mut fm)?;
        x[j] = x0[j];
        for i in 0..d {
            a[i * d + j] = (fp[i] - fm[i]) / (2.0 * h[j]);
        }
    }
    Ok(a)
}

/// The central-difference Jacobian `∂f/∂x` of any [`OdeSystem`] at `(t, x0)` with steps `h`.
pub fn system_jacobian<S: OdeSystem>(
    sys: &mut S,
    t: f64,
    x0: &[f64],
    h: &[f64],
) -> Result<Vec<f64>, RhsError> {
    central_jacobian(x0, h, |x, dx| sys.rhs(t, x, dx))
}

/// The central-difference step for an entry of size `x` with floor scale `s`.
pub fn step_size(x: f64, s: f64) -> f64 {
    f64::EPSILON.cbrt() * x.abs().max(s)
}

/// The trimmed reference state.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Trim {
    /// Full state `(p_I, q, V_B, ω_B, η, η̇)` of the reference.
    pub state: Vec<f64>,
    /// Static elastic deflection `η*`.
    pub eta: Vec<f64>,
    /// Newton iterations used.
    pub iterations: usize,
    /// Largest `|η̈_m| / (ω_m² s_m)` at `η*` (modal acceleration relative to the one a
    /// deflection `s_m` would give).
    pub residual: f64,
    /// Rigid accelerations `(V̇_B, ω̇_B)` at the reference (not zero in ballistic flight).
    pub rigid_acceleration: [f64; 6],
}

/// The linear state-space model `δ̇ = A δ`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinearModel {
    /// State names, in the order of `A`'s rows.
    pub state_names: Vec<String>,
    /// `A`, row-major `d x d`.
    pub a: Vec<f64>,
    /// Central-difference steps used per state.
    pub steps: Vec<f64>,
}

impl LinearModel {
    /// Dimension `d = 9 + 2n`.
    pub fn dim(&self) -> usize {
        self.state_names.len()
    }
}

/// Names of the linear states: `theta_x..z`, `v_body_x..z`, `omega_body_x..z`,
/// `eta_<mode>`, `eta_dot_<mode>`.
pub fn state_names(mode_names: &[String]) -> Vec<String> {
    let mut v: Vec<String> = ["theta_x", "theta_y", "theta_z"]
        .iter()
        .chain(&["v_body_x", "v_body_y", "v_body_z"])
        .chain(&["omega_body_x", "omega_body_y", "omega_body_z"])
        .map(|s| s.to_string())
        .collect();
    v.extend(mode_names.iter().map(|m| format!("eta_{m}")));
    v.extend(mode_names.iter().map(|m| format!("eta_dot_{m}")));
    v
}

/// The linearisation of one compiled vehicle with one set of force blocks: owns the
/// right-hand side and the modal scales.
#[derive(Debug)]
pub struct Linearizer<S> {
    sys: S,
    layout: StateLayout,
    /// `s_m`: modal amplitude that moves some node by 1 m.
    modal_scale: Vec<f64>,
    /// `ω_m`, rad/s.
    modal_frequency: Vec<f64>,
    mode_names: Vec<String>,
    options: LineariseOptions,
}

impl<S: OdeSystem> Linearizer<S> {
    /// `sys` is the right-hand side of (3.2.1) (an [`crate::runtime::eom::Eom`]),
    /// `node_translation_shapes` the translation rows of `S` for every node
    /// (`3 n_nodes x n`, as in [`crate::plan::Plan`]), `omega2` the modal `ω_m²`.
    pub fn new(
        sys: S,
        node_translation_shapes: &[f64],
        omega2: &[f64],
        mode_names: &[String],
        options: LineariseOptions,
    ) -> Self {
        let n = mode_names.len();
        let layout = StateLayout { n };
        let mut modal_scale = vec![1.0; n];
        if n > 0 {
            for (m, s) in modal_scale.iter_mut().enumerate() {
                let worst = node_translation_shapes
                    .chunks_exact(3 * n)
                    .map(|node| (0..3).map(|i| node[i * n + m].powi(2)).sum::<f64>().sqrt())
                    .fold(0.0, f64::max);
                if worst > 0.0 && worst.is_finite() {
                    *s = 1.0 / worst;
                }
            }
        }
        let modal_frequency = (0..n)
            .map(|m| omega2.get(m).map_or(1.0, |w| w.max(0.0).sqrt().max(1.0)))
            .collect();
        Self {
            sys,
            layout,
            modal_scale,
            modal_frequency,
            mode_names: mode_names.to_vec(),
            options,
        }
    }

    /// The floor scales `s_j` of the linear states (module doc).
    fn floor_scales(&self, reference: &[f64]) -> Vec<f64> {
        let n = self.layout.n;
        let speed = reference[7..10].iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut s = vec![1.0; 9 + 2 * n];
        for i in 3..6 {
            s[i] = speed.max(1.0);
        }
        for m in 0..n {
            s[9 + m] = self.modal_scale[m];
            s[9 + n + m] = self.modal_frequency[m] * self.modal_scale[m];
        }
        s
    }

    /// Trim at `speed` (m/s) and `altitude` (m) with attitude `q0`, `α = 0` (module doc).
    pub fn trim(
        &mut self,
        speed: f64,
        altitude: f64,
        q0: [f64; 4],
    ) -> Result<Trim, LineariseError> {
        self.trim_iterated(speed, altitude, q0, self.options.max_trim_iterations, true)
    }

    /// The reference with `η = 0` (no static balance): the fallback when [`Self::trim`]
    /// fails, and the exact trim of a model without loads.
    pub fn trim_at_zero(
        &mut self,
        speed: f64,
        altitude: f64,
        q0: [f64; 4],
    ) -> Result<Trim, LineariseError> {
        self.trim_iterated(speed, altitude, q0, 0, false)
    }

    fn trim_iterated(
        &mut self,
        speed: f64,
        altitude: f64,
        q0: [f64; 4],
        max_iterations: usize,
        require_convergence: bool,
    ) -> Result<Trim, LineariseError> {
        let n = self.layout.n;
        let ed = self.layout.eta_dot();
        let mut x = self.layout.state(
            [0.0, 0.0, -altitude],
            q0,
            [speed, 0.0, 0.0],
            [0.0; 3],
            &vec![0.0; n],
            &vec![0.0; n],
        );
        let mut dx = vec![0.0; x.len()];
        let scale: Vec<f64> = (0..n)
            .map(|m| self.modal_frequency[m].powi(2) * self.modal_scale[m])
            .collect();
        let residual = |dx: &[f64]| -> f64 {
            (0..n)
                .map(|m| (dx[ed + m] / scale[m]).abs())
                .fold(0.0, f64::max)
        };
        let eval = |sys: &mut S, x: &[f64], dx: &mut [f64], what| {
            sys.rhs(0.0, x, dx)
                .map_err(|error| LineariseError::Rhs { what, error })
        };
        eval(&mut self.sys, &x, &mut dx, "trim state")?;
        let mut r = residual(&dx);
        let mut iterations = 0;
        let mut converged = n == 0 || r < self.options.trim_tolerance;
        while !converged && iterations < max_iterations {
            iterations += 1;
            // Newton: J Δη = -η̈(η), J = ∂η̈/∂η by central differences.
            let mut jac = Mat::<f64>::zeros(n, n);
            let mut xp = x.clone();
            let mut dp = vec![0.0; x.len()];
            let mut dm = vec![0.0; x.len()];
            for p in 0..n {
                let h = step_size(x[13 + p], self.modal_scale[p]);
                xp[13 + p] = x[13 + p] + h;
                eval(&mut self.sys, &xp, &mut dp, "trim Jacobian")?;
                xp[13 + p] = x[13 + p] - h;
                eval(&mut self.sys, &xp, &mut dm, "trim Jacobian")?;
                xp[13 + p] = x[13 + p];
                for m in 0..n {
                    jac[(m, p)] = (dp[ed + m] - dm[ed + m]) / (2.0 * h);
                }
            }
            let mut rhs = Mat::<f64>::from_fn(n, 1, |m, _| -dx[ed + m]);
            let lu = jac.partial_piv_lu();
            lu.solve_in_place_with_conj(faer::Conj::No, rhs.as_mut());
            let delta: Vec<f64> = (0..n).map(|m| rhs[(m, 0)]).collect();
            if delta.iter().any(|d| !d.is_finite()) {
                return Err(LineariseError::Singular {
                    what: "trim Newton step",
                });
            }
            // Backtracking: halve the step until the residual falls.
            let mut lambda = 1.0;
            let mut accepted = false;
            for _ in 0..12 {
                for m in 0..n {
                    xp[13 + m] = x[13 + m] + lambda * delta[m];
                }
                if eval(&mut self.sys, &xp, &mut dp, "trim step").is_ok() {
                    let r_new = residual(&dp);
                    if r_new < r || r_new < self.options.trim_tolerance {
                        x.copy_from_slice(&xp);
                        dx.copy_from_slice(&dp);
                        r = r_new;
                        accepted = true;
                        break;
                    }
                }
                lambda *= 0.5;
            }
            let step = (0..n)
                .map(|m| (lambda * delta[m] / self.modal_scale[m]).abs())
                .fold(0.0, f64::max);
            if !accepted {
                break;
            }
            converged = step < self.options.trim_tolerance || r < self.options.trim_tolerance;
        }
        if require_convergence && !converged {
            return Err(LineariseError::TrimNotConverged {
                iterations,
                residual: r,
            });
        }
        let mut rigid_acceleration = [0.0; 6];
        rigid_acceleration.copy_from_slice(&dx[7..13]);
        Ok(Trim {
            eta: x[13..13 + n].to_vec(),
            state: x,
            iterations,
            residual: r,
            rigid_acceleration,
        })
    }

    /// `A` about the full reference state `reference` (module doc).
    pub fn linearise(&mut self, reference: &[f64]) -> Result<LinearModel, LineariseError> {
        let l = self.layout;
        if reference.len() != l.len() {
            return Err(LineariseError::StateLength {
                expected: l.len(),
                found: reference.len(),
            });
        }
        let n = l.n;
        let d = 9 + 2 * n;
        let q0 = [reference[3], reference[4], reference[5], reference[6]];
        let floor = self.floor_scales(reference);
        // Magnitudes of the linear states at the reference (δθ is measured from q0: 0).
        let magnitude: Vec<f64> = (0..d)
            .map(|j| if j < 3 { 0.0 } else { reference[4 + j] })
            .collect();
        let steps: Vec<f64> = (0..d).map(|j| step_size(magnitude[j], floor[j])).collect();
        let mut x = reference.to_vec();
        let mut dx = vec![0.0; l.len()];
        let sys = &mut self.sys;
        let f = |delta: &[f64], out: &mut [f64]| -> Result<(), LineariseError> {
            let dth = [delta[0], delta[1], delta[2]];
            x[3..7].copy_from_slice(&perturb_attitude(&q0, &dth));
            for j in 3..d {
                x[4 + j] = reference[4 + j] + delta[j];
            }
            sys.rhs(0.0, &x, &mut dx)
                .map_err(|error| LineariseError::Rhs {
                    what: "perturbed state",
                    error,
                })?;
            let w = [x[10], x[11], x[12]];
            out[0..3].copy_from_slice(&tangent_rate(&dth, &w));
            out[3..d].copy_from_slice(&dx[7..13 + 2 * n]);
            Ok(())
        };
        let mut a = central_jacobian(&vec![0.0; d], &steps, f)?;
        if !self.options.gravity_follows_attitude {
            // Attitude reaches the loads only through g_B = C_BI g_I (no inertial wind in a
            // ballistic reference, altitude frozen): drop that path.
            for i in 3..d {
                for j in 0..3 {
                    a[i * d + j] = 0.0;
                }
            }
        }
        Ok(LinearModel {
            state_names: state_names(&self.mode_names),
            a,
            steps,
        })
    }
}
