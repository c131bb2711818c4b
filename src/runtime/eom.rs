//! Equations of motion of the flexible vehicle, eq. (3.2.1), as a first-order system.
//!
//! # State
//! `x = (p_I, q, V_B, ω_B, η, η̇)`, length `13 + 2n` (see [`StateLayout`]): inertial position
//! of the body-frame origin (the nose node, z down), Euler parameters `q = (ε, η_q)` of
//! [`super::kinematics`] (eqs. 4.4.6-4.4.7), body-frame velocity of the origin, body
//! angular velocity, modal coordinates and their rates.
//!
//! # Derivation (the OCR of (2.5.1)/(3.2.1) cannot be trusted, REFERENCE-NOTES)
//! With `v = (V_B, ω_B, η̇)` the kinetic energy of the reduced model is
//! `T = ½ vᵀ M_tot(η) v` ([`ReducedModel::mass_matrix_into`]), with blocks
//! `M_tot = [[m 1, -c̄_tot^×, P̄], [c̄_tot^×, J̄_tot, H̄_tot], [P̄ᵀ, H̄_totᵀ, M̄]]`
//! (eqs. 3.2.2-3.2.12). `V_B`, `ω_B` are quasi-velocities, so Lagrange's equations take the
//! Boltzmann-Hamel form (Meirovitch, "Methods of Analytical Dynamics", 4.13; the thesis'
//! (2.4.1)-(2.4.2)):
//! ```text
//! d/dt(∂T/∂V) + ω × ∂T/∂V                 = F_B
//! d/dt(∂T/∂ω) + V × ∂T/∂V + ω × ∂T/∂ω     = G_B          (moment about the body origin)
//! d/dt(∂T/∂η̇) - ∂T/∂η + K̄ η + C̄ η̇        = Q
//! ```
//! With `p = (p_V, p_ω, p_η) = M_tot v`, `d/dt p = M_tot v̇ + Ṁ v`,
//! `Ṁ = Σ_m η̇_m ∂M_tot/∂η_m` and `∂T/∂η_m = ½ vᵀ (∂M_tot/∂η_m) v`, so
//! `M_tot(η) v̇ = f - Ṁ v + [0; 0; ∂T/∂η] - [ω×p_V; V×p_V + ω×p_ω; 0] - [0; 0; K̄η + C̄η̇]`.
//! Writing out the blocks with `ċ = P̄ η̇` (the rate of `c̄_tot = c + P̄η`, eq. 3.2.10),
//! `J̄̇_tot = Σ_m η̇_m ∂J̄_tot/∂η_m`, `H̄̇_tot = Σ_m η̇_m H̄'_m`:
//! ```text
//! p_V = m V + ω × c̄_tot + P̄ η̇
//! p_ω = c̄_tot × V + J̄_tot ω + H̄_tot η̇
//! (Ṁv)_V = ω × ċ,   (Ṁv)_ω = ċ × V + J̄̇_tot ω + H̄̇_tot η̇,   (Ṁv)_η = H̄̇_totᵀ ω
//! ∂T/∂η_m = P̄_m·(V × ω) + ½ ωᵀ (∂J̄_tot/∂η_m) ω + ωᵀ H̄'_m η̇
//! ```
//! Map onto the thesis' Coriolis matrix of (2.5.1)/(3.2.1) (right-hand side `-C_v v`):
//! - row 1: `-ω×ċ - ω×p_V = -[m ω^× V - ω^× c̄_tot^× ω + 2 ω^× P̄ η̇]`, i.e. entries
//!   `m ω_B^×`, `-ω_B^× c̄_tot^×` (the "ω_Δ" of the OCR is `ω_B`) and `2 P̄_ω` with
//!   `P̄_ω = ω_B^× P̄` (eq. 2.5.27);
//! - row 2: the Jacobi identity turns `V × (ω × c̄) + ω × (c̄ × V)` into `c̄_tot^× ω_B^× V`;
//!   `ω × J̄_tot ω` is the `ω_B^× J̄_tot` entry; the `ċ × V` and `V × P̄η̇` terms cancel; the
//!   remaining `J̄̇_tot ω + H̄̇_tot η̇ + ω × H̄_tot η̇` is the thesis' `2 H̄_ω,tot η̇`
//!   (eqs. 2.5.28-2.5.30), which it equals when `J̄'_ru` and `J̄''_uu` have the symmetry of
//!   their integrals; we keep the form implied by `T` so that energy is conserved exactly;
//! - row 3: `P̄_m·(V×ω) = (P̄_ωᵀ V)_m`, the `-P̄_ωᵀ` entry that (3.2.1) lost;
//!   `½ ωᵀ ∂J̄_tot/∂η_m ω` is `(H̄_ω,totᵀ ω)_m`; `ωᵀH̄'_m η̇ - (H̄̇_totᵀ ω)_m` is
//!   `2 (M̄_ω η̇)_m` (eq. 2.5.31) by the antisymmetry `H̄'_m e_p = -H̄'_p e_m`;
//! - `f_σ = K̄ η` (eq. 3.2.20) plus modal viscous damping `C̄ η̇`.
//!
//! The velocity-dependent part does no work: from the equations,
//! `vᵀ M v̇ = vᵀf - η̇ᵀ(K̄η + C̄η̇) - vᵀṀv + η̇ᵀ ∂T/∂η` (the `ω×p_V`, `V×p_V + ω×p_ω` terms give
//! `V·(ω×p_V) + ω·(V×p_V) = 0` and `ω·(ω×p_ω) = 0`), and `η̇ᵀ ∂T/∂η = ½ vᵀṀv`, so
//! `dT/dt = vᵀM v̇ + ½ vᵀṀv = vᵀf - η̇ᵀ(K̄η + C̄η̇)`: with no loads and no damping
//! `T + ½ ηᵀK̄η` is constant. The free-tumble test checks it (thesis 6.4).
//!
//! Kinematics: `ṗ_I = C_IB V_B`, `q̇` from eqs. (4.4.11)-(4.4.12), `d/dt η = η̇`.
//! `q` is renormalised after every accepted step ([`OdeSystem::project`]); because `q̇` is
//! linear in `q` and the rotation uses `q/|q|`, scaling the stored derivative's `q` part by
//! the same factor keeps the first-same-as-last derivative exact.
//!
//! # Variable mass: a burning motor ([`Propulsion`])
//! Sources: W. T. Thomson, "Introduction to Space Dynamics" (Dover 1986), ch. 7 ("Rocket
//! dynamics": the body-fixed control volume, Reynolds transport); Cornelisse, Schöyer and
//! Wakker, "Rocket Propulsion and Spaceflight Dynamics" (1979), ch. 8-9 (the equations of
//! motion of a variable-mass rocket: thrust, Coriolis and jet-damping terms);
//! H. Irschik, H. J. Holl, "Mechanics of variable-mass systems, Part 1", Appl. Mech. Rev.
//! 57 (2004), eq. (34) (Lagrange's equations of a control volume). The derivation below
//! puts them into the quasi-velocity form above.
//!
//! Control volume: the vehicle, fixed to the body frame, with the propellant inside it;
//! the only outflow crosses the nozzle exit at the deformed thrust point
//! `r_e = r_T + u_T + δ_T` ([`crate::runtime::forces::ThrustBlock`]). Assumption (Thomson's
//! "quasi-rigid" rocket): the gas inside the motor carries no momentum relative to the body
//! (the internal-flow Coriolis force and the unsteady internal flow are neglected; the
//! propellant's mass simply leaves the grain), and the propellant fraction `f(t)` scales the
//! propellant's mass matrix `M_p` ([`crate::runtime::motor`]): `M(t, η) = M_dry(η) +
//! f(t) M_p(η)`, so `T = ½ vᵀ M(t, η) v` with `v = (V_B, ω_B, η̇)`.
//!
//! For every quasi-velocity `v_k` with partial-velocity field `ψ_k(x)` (the fields `V`, `R`,
//! `U_m`, `φ_m` of [`crate::structure::coefficients`]), the generalised momentum of the
//! contents is `p_k = ∫_CV ψ_k·v dm = (M v)_k`. Reynolds' transport theorem for the
//! body-fixed control volume (Thomson eq. 7.1-3, Irschik-Holl eq. 34) adds to the balance
//! of the fixed-mass system (the Boltzmann-Hamel equations above) the flux of `ψ_k·v`
//! carried out through the exit, `-ṁ_e ψ_k(r_e)·v_abs,e`, where the exhaust's absolute
//! velocity is the exit point's velocity `v_e = Ψ_e v = V + ω × r_e + Φ_e η̇` plus the
//! exhaust velocity relative to the nozzle, `u_rel`. The part `-ṁ_e u_rel` (with the
//! pressure thrust) is the thrust `T(t)` of the curve, applied at `r_e` exactly as
//! [`crate::runtime::forces::ThrustBlock`] does (eqs. 5.2.1-5.2.6); what remains is
//! `-ṁ_e Ψ_eᵀ Ψ_e v` (`Ψ_e` the 3 x (6+n) partial-velocity matrix of the exit point:
//! `Ψ_eᵀ w = (w, r_e × w, Φ_eᵀ w)`). The time derivative of `p = M v` now has the explicit
//! part `Ṁ_t v = ḟ M_p v = -(ṁ_e/m_p) M_p v` (`ḟ = -ṁ_e/m_p`). So
//! ```text
//! M(t,η) v̇ = [right-hand side of the fixed-mass equations, with M(t,η)]
//!            + f_T + (ṁ_e/m_p) M_p(η) v - ṁ_e Ψ_eᵀ Ψ_e v
//! ```
//! - Translation row (ω = 0, η̇ = 0): `ṁ_e (V - V) = 0`, so `m(t) V̇ = F + T`: the rocket
//!   equation; with constant `T` and `ṁ_e = T/c` it integrates to Tsiolkovsky's
//!   `ΔV = c ln(m_0/m)` (tested to 1e-9 in `tests/motor.rs`).
//! - Rotation row (pitch rate ω, axis points `r_p` of the grain, `r_e` of the exit):
//!   `(ṁ_e/m_p) J_p ω - ṁ_e r_e × (ω × r_e)`: the rate of change of the propellant's inertia
//!   (the `-İω` term of Cornelisse et al.) and the jet damping moment
//!   `-ṁ_e r_e × (ω × r_e)`; on the axis they combine into `-ṁ_e (l_e² - l_p² - k_p²) ω`
//!   about the body origin (exit and grain arms `l`, grain radius of gyration `k_p`), with
//!   the force `ṁ_e ω × (r_p - r_e)` of the translation row (the mass centre moving forward
//!   as the grain burns).
//! - Modal rows: `(ṁ_e/m_p)(M_p v)_η - ṁ_e Φ_eᵀ v_e`, the same two effects on the elastic
//!   coordinates (the exhaust leaves with the nozzle's elastic velocity).
//!
//! Balances (the checks of `tests/motor.rs`): momentum
//! `d/dt p_I = F_I + T_I - ṁ_e C_IB v_e` (the exhaust takes away the momentum of the mass it
//! carries at the exit point's velocity; the thrust accounts for the relative velocity);
//! energy, from `dT/dt = vᵀM v̇ + ½ vᵀ(Ṁ_η + Ṁ_t)v` and the fixed-mass identities above,
//! ```text
//! d/dt (T + ½ηᵀK̄η) = vᵀ f_loads + vᵀ f_T + ṁ_e (½ vᵀ M_p v / m_p - |v_e|²) - η̇ᵀC̄η̇
//! ```
//! whose propulsive part for pure translation is `T·V - ½ ṁ_e V²`: the thrust's power less
//! the kinetic energy the burnt mass takes with it. [`Eom::track_energy`] integrates the three
//! works with the state so a run reports the balance's residual.

// Index loops follow the block formulas above.
#![allow(clippy::needless_range_loop)]

use super::forces::ThrustBlock;
use super::integrate::{OdeSystem, RhsError};
use super::kinematics::{
    Mat3, c_bi_normalized, cross, euler_parameter_rates, mat_t_vec, mat_vec,
    normalize_euler_parameters,
};
use super::motor::{BurnSchedule, combine_into, dry_model};
use crate::structure::coefficients::ReducedModel;

/// Offsets of the blocks of the state vector `x = (p_I, q, V_B, ω_B, η, η̇)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StateLayout {
    /// Number of flexible coordinates `n`.
    pub n: usize,
}

impl StateLayout {
    /// Inertial position `p_I` (3).
    pub const POSITION: usize = 0;
    /// Euler parameters `(ε1, ε2, ε3, η)` (4).
    pub const ATTITUDE: usize = 3;
    /// Body velocity of the origin `V_B` (3).
    pub const VELOCITY: usize = 7;
    /// Body angular velocity `ω_B` (3).
    pub const ANGULAR_VELOCITY: usize = 10;
    /// Modal coordinates `η` (n).
    pub const ETA: usize = 13;

    /// Offset of `η̇`.
    pub fn eta_dot(&self) -> usize {
        13 + self.n
    }

    /// Length of the state vector, `13 + 2n`.
    pub fn len(&self) -> usize {
        13 + 2 * self.n
    }

    /// Never empty (13 rigid entries at least).
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Assembles a state vector from its parts (allocates; for initial conditions).
    pub fn state(
        &self,
        position: [f64; 3],
        attitude: [f64; 4],
        velocity: [f64; 3],
        angular_velocity: [f64; 3],
        eta: &[f64],
        eta_dot: &[f64],
    ) -> Vec<f64> {
        let mut x = vec![0.0; self.len()];
        x[0..3].copy_from_slice(&position);
        x[3..7].copy_from_slice(&attitude);
        x[7..10].copy_from_slice(&velocity);
        x[10..13].copy_from_slice(&angular_velocity);
        let n = self.n.min(eta.len());
        x[13..13 + n].copy_from_slice(&eta[..n]);
        let m = self.n.min(eta_dot.len());
        x[13 + self.n..13 + self.n + m].copy_from_slice(&eta_dot[..m]);
        x
    }
}

/// Read-only view of the state handed to force blocks.
#[derive(Debug, Clone, Copy)]
pub struct StateView<'a> {
    /// Inertial position of the body origin, m (z down).
    pub position: [f64; 3],
    /// Euler parameters `(ε1, ε2, ε3, η)` as integrated.
    pub attitude: [f64; 4],
    /// `C_BI` (inertial to body) of the normalised parameters, eq. (4.4.10).
    pub c_bi: Mat3,
    /// `V_B`, m/s.
    pub velocity: [f64; 3],
    /// `ω_B`, rad/s.
    pub angular_velocity: [f64; 3],
    /// `η`.
    pub eta: &'a [f64],
    /// `η̇`.
    pub eta_dot: &'a [f64],
}

impl<'a> StateView<'a> {
    /// The view of a state vector (no allocation).
    pub fn new(layout: StateLayout, x: &'a [f64]) -> Self {
        let q = [x[3], x[4], x[5], x[6]];
        let ed = layout.eta_dot();
        Self {
            position: [x[0], x[1], x[2]],
            attitude: q,
            c_bi: c_bi_normalized(&q),
            velocity: [x[7], x[8], x[9]],
            angular_velocity: [x[10], x[11], x[12]],
            eta: &x[13..ed],
            eta_dot: &x[ed..ed + layout.n],
        }
    }
}

/// A source of external generalised forces `(F_B, G_B, Q)` (length `6 + n`): body-frame
/// force, moment about the body origin, and modal forces `Q_m = ∫ φ_m · f dm`.
///
/// `out` arrives zeroed; implementations add their contribution. Called inside the
/// right-hand side: must not allocate, do IO or look up names.
pub trait ForceModel {
    /// Adds the generalised forces at `(t, state)` to `out`.
    fn generalized_forces(&mut self, t: f64, state: &StateView, out: &mut [f64]);
}

/// Free flight: no external loads (thesis 6.4).
#[derive(Debug, Clone, Copy, Default)]
pub struct FreeFlight;

impl ForceModel for FreeFlight {
    fn generalized_forces(&mut self, _t: f64, _state: &StateView, _out: &mut [f64]) {}
}

/// Uniform gravity `g_I` (no altitude correction), eqs. (5.1.1), (5.1.3)-(5.1.5), with the
/// modal part from virtual work: with `g_B = C_BI g_I` (eq. 5.1.3) and the position of a mass
/// element `r + u`, `δW = ∫ g_B·(δx + δθ × (r+u) + Φ δη) dm` gives
/// `F_B = m g_B` (5.1.4), `G_B = c̄_tot × g_B` (5.1.5, with the deformed first moment
/// `c̄_tot = c + P̄η` of eq. 3.2.10) and `Q = P̄ᵀ g_B` (P̄ columns `∫ φ_m dm`, eq. 3.2.3).
#[derive(Debug, Clone)]
pub struct UniformGravity {
    g_inertial: [f64; 3],
    mass: f64,
    first_moment: [f64; 3],
    p_bar: Vec<f64>,
    n: usize,
}

impl UniformGravity {
    /// Gravity `g_inertial` (m/s², z down: `(0, 0, 9.806)` in eq. 5.1.1) acting on `model`.
    pub fn new(model: &ReducedModel, g_inertial: [f64; 3]) -> Self {
        Self {
            g_inertial,
            mass: model.mass,
            first_moment: model.first_moment,
            p_bar: model.p_bar.clone(),
            n: model.n(),
        }
    }
}

impl UniformGravity {
    /// Replaces the mass properties `m`, `c`, `P̄` (a burning vehicle's, at the current
    /// propellant fraction); `p_bar` must have the length of the model's.
    pub fn set_mass_properties(&mut self, mass: f64, first_moment: [f64; 3], p_bar: &[f64]) {
        self.mass = mass;
        self.first_moment = first_moment;
        for (a, b) in self.p_bar.iter_mut().zip(p_bar) {
            *a = *b;
        }
    }

    /// Replaces `g_I` (m/s², inertial frame); lets a gravity block scale `g` with altitude
    /// (eq. 5.1.2) before each evaluation without copying the algebra.
    pub fn set_gravity(&mut self, g_inertial: [f64; 3]) {
        self.g_inertial = g_inertial;
    }

    /// The gravity currently applied, m/s², inertial frame.
    pub fn gravity(&self) -> [f64; 3] {
        self.g_inertial
    }

    /// Total mass `m`, kg.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// Deformed first moment `c̄_tot = c + P̄η` (eq. 3.2.10), body frame, kg m; the mass
    /// centre sits at `c̄_tot / m`. No allocation.
    pub fn first_moment_total(&self, eta: &[f64]) -> [f64; 3] {
        let n = self.n;
        let mut c = self.first_moment;
        for i in 0..3 {
            for m in 0..n.min(eta.len()) {
                c[i] += self.p_bar[i * n + m] * eta[m];
            }
        }
        c
    }
}

impl ForceModel for UniformGravity {
    fn generalized_forces(&mut self, _t: f64, s: &StateView, out: &mut [f64]) {
        let n = self.n;
        let g = mat_vec(&s.c_bi, &self.g_inertial);
        let c = self.first_moment_total(s.eta);
        let gm = cross(&c, &g);
        for i in 0..3 {
            out[i] += self.mass * g[i];
            out[3 + i] += gm[i];
        }
        for m in 0..n {
            out[6 + m] += (0..3).map(|i| self.p_bar[i * n + m] * g[i]).sum::<f64>();
        }
    }
}

/// Why an [`Eom`] could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EomError {
    /// A coefficient array of the reduced model has the wrong length.
    #[error("reduced model field {field} has length {found}, expected {expected} (n = {n})")]
    ModelShape {
        field: &'static str,
        expected: usize,
        found: usize,
        n: usize,
    },
    /// A state vector has the wrong length.
    #[error("state vector has length {found}, expected {expected}")]
    StateLength { expected: usize, found: usize },
}

/// Scratch space of the right-hand side, allocated once by [`Eom::new`]; the right-hand side
/// only writes into it.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// Right-hand side, then `v̇`.
    rhs: Vec<f64>,
    /// External generalised forces `(F_B, G_B, Q)`.
    forces: Vec<f64>,
    /// `H̄_tot(η)` (3 x n).
    h_tot: Vec<f64>,
    /// `∂T/∂η`.
    dt_deta: Vec<f64>,
    /// `G_m = ∂J̄_tot/∂η_m` (9 per mode, [`Precomputed`]).
    g: Vec<f64>,
    /// `H̄̇_tot = Σ_m η̇_m H̄'_m` (3 x n).
    h_dot: Vec<f64>,
    /// `W_H = L⁻¹ H̄_totᵀ` (n x 3) of the Schur complement solve.
    w_h: Vec<f64>,
    /// `L⁻¹ r_η`, then the back-substituted modal accelerations.
    z: Vec<f64>,
}

/// The coefficients of (3.2.1) rearranged once per model (again when a burning motor changes
/// the propellant fraction) so that the right-hand side evaluates the η-dependent inertia
/// as precomputed quadratic forms and solves `M_tot v̇ = r` on its 6 x 6 rigid block.
///
/// # The inertia sums
/// `J̄_tot(η) = J + Σ_m η_m A_m + Σ_mp η_m η_p J̄''_mp` (eqs. 3.2.9, 3.2.11, 3.2.12) with
/// `A_m = J̄'_ru,m + J̄'_ru,mᵀ`. Its gradient is `G_m = ∂J̄_tot/∂η_m = A_m + Σ_p η_p S_mp`
/// with `S_mp = J̄''_mp + J̄''_pm` (precomputed, laid out so that the sum over `p` is one
/// contiguous axpy of length 9n per mode). Since `J̄_tot` is quadratic in `η`,
/// `Σ_m η_m G_m = Σ_m η_m A_m + 2 Σ_mp η_m η_p J̄''_mp`, hence
/// `J̄_tot = J + ½ Σ_m η_m (A_m + G_m)`; and `J̄̇_tot = Σ_m η̇_m G_m`,
/// `½ ωᵀ(∂J̄_tot/∂η_m)ω = ½ ωᵀ G_m ω`. So the one contraction `G` (9n² multiply-adds)
/// replaces the three of the direct form (`J̄_tot`, `J̄̇_tot` and `∂T/∂η` each summed
/// `S_mp` over `m, p`).
///
/// `H̄_tot = H̄ + Σ_m η_m H̄'_m` and `H̄̇_tot = Σ_m η̇_m H̄'_m` (eqs. 3.2.4-3.2.6) come from
/// one pass over `H̄'`; then `(H̄̇_tot η̇)_i = Σ_p (H̄̇_tot)_ip η̇_p`,
/// `(H̄̇_totᵀ ω)_m = Σ_i ω_i (H̄̇_tot)_im`, and `ωᵀ H̄'_m η̇ = Σ_ip (ω_i η̇_p) (H̄'_m)_ip` is
/// one axpy per `(i, p)` over the transposed copy `H̄'ᵀ`.
///
/// # The solve (Schur complement on the rigid block)
/// `M_tot = [[A, B], [Bᵀ, M̄]]` with `A` the 6 x 6 rigid block `[[m 1, -c̄_tot^×],
/// [c̄_tot^×, J̄_tot]]`, `B = [P̄; H̄_tot]` (6 x n) and the constant modal mass `M̄ = L Lᵀ`
/// (Cholesky, once). Block elimination (Golub & Van Loan, "Matrix Computations", 4th ed.,
/// 3.2.10 and 4.2.6: the Schur complement of a symmetric positive definite matrix is
/// positive definite) with `W = L⁻¹ Bᵀ` (n x 6), `z = L⁻¹ r_η`:
/// ```text
/// (A - WᵀW) v̇_r = r_r - Wᵀ z,      v̇_η = L⁻ᵀ (z - W v̇_r)
/// ```
/// Only `W_H = L⁻¹ H̄_totᵀ` depends on `η`; `W_P = L⁻¹ P̄ᵀ` and the translational block
/// `S_vv = m 1 - W_Pᵀ W_P` are precomputed. The 6 x 6 Schur complement
/// `S = [[S_vv, S_ωvᵀ], [S_ωv, S_ωω]]` is factored by block Cholesky (Golub & Van Loan
/// 4.2.6 applied to the 2 x 2 block partition) on the constant factor `S_vv = L_vv L_vvᵀ`:
/// ```text
/// L_ωv = S_ωv L_vv⁻ᵀ,   S_ωω - L_ωv L_ωvᵀ = L_ωω L_ωωᵀ   (3 x 3 Cholesky),
/// forward   u_v = L_vv⁻¹ y_v,          u_ω = L_ωω⁻¹ (y_ω - L_ωv u_v),
/// backward  x_ω = L_ωω⁻ᵀ u_ω,          x_v = L_vv⁻ᵀ (u_v - L_ωvᵀ x_ω),
/// ```
/// so only three pivots (square roots, and one reciprocal each, multiplied in the
/// substitutions) are on the right-hand side's path instead of six and 27 divisions. A
/// failed pivot of `L_ωω` is the mass matrix's loss of positive definiteness (row
/// `3 + j`); `S_vv` is checked once. No allocation.
#[derive(Debug, Clone)]
struct Precomputed {
    n: usize,
    /// `A_m`, entry `(i, k)` at `m * 9 + 3 i + k`.
    a_lin: Vec<f64>,
    /// `S_mp`, entry `(i, k)` at `p * 9n + m * 9 + 3 i + k`.
    s_quad: Vec<f64>,
    /// `(H̄'_m)_ip` at `(i n + p) n + m`.
    h_prime_t: Vec<f64>,
    /// `L⁻¹` (lower triangular, row-major n x n) of `M̄ = L Lᵀ`.
    linv: Vec<f64>,
    /// `W_P = L⁻¹ P̄ᵀ`, entry `(p, i)` at `3 p + i`.
    w_p: Vec<f64>,
    /// `m 1 - W_Pᵀ W_P`.
    s_vv: Mat3,
    /// `L_vv⁻¹` (lower triangular) of the constant translational block `S_vv = L_vv L_vvᵀ`
    /// of the Schur complement ("The solve").
    s_vv_linv: Mat3,
    /// `S_vv` is not positive definite: every evaluation fails with this.
    rigid_error: Option<RhsError>,
    /// The modal stiffness and damping transposed, `K̄_mp` and `C̄_mp` at `p n + m`: the
    /// rows `r_m -= Σ_p (K̄_mp η_p + C̄_mp η̇_p)` as column sweeps over `m` (every `r_m`
    /// keeps its order of operations, so the bits of the row-by-row sums).
    k_t: Vec<f64>,
    c_t: Vec<f64>,
    /// The modal mass is not positive definite: every evaluation fails with this.
    modal_error: Option<RhsError>,
    /// Scratch of [`Self::rebuild`] (n x n).
    chol: Vec<f64>,
}

impl Precomputed {
    fn new(md: &ReducedModel) -> Self {
        let n = md.n();
        let mut p = Self {
            n,
            a_lin: vec![0.0; 9 * n],
            s_quad: vec![0.0; 9 * n * n],
            h_prime_t: vec![0.0; 3 * n * n],
            linv: vec![0.0; n * n],
            w_p: vec![0.0; 3 * n],
            s_vv: [[0.0; 3]; 3],
            s_vv_linv: [[0.0; 3]; 3],
            rigid_error: None,
            k_t: vec![0.0; n * n],
            c_t: vec![0.0; n * n],
            modal_error: None,
            chol: vec![0.0; n * n],
        };
        p.rebuild(md);
        p
    }

    /// Recomputes every array from `md` (same `n`; no allocation).
    fn rebuild(&mut self, md: &ReducedModel) {
        let n = self.n;
        for m in 0..n {
            for p in 0..n {
                self.k_t[p * n + m] = md.modal_stiffness[m * n + p];
                self.c_t[p * n + m] = md.modal_damping[m * n + p];
            }
        }
        self.rebuild_mass_terms(md);
    }

    /// Recomputes the arrays that depend on the mass distribution, all but `K̄ᵀ` and `C̄ᵀ`:
    /// what a burning motor's propellant fraction moves (`motor::combine_into` leaves the
    /// stiffness and damping of the compiled vehicle as they are), at every right-hand side
    /// of the burn. The same arithmetic as before the split, so the same bits.
    fn rebuild_mass_terms(&mut self, md: &ReducedModel) {
        let n = self.n;
        // Entry by entry as before (each a single addition or a copy), in the order of the
        // destination arrays, without the index arithmetic's bounds checks.
        for (a, jr) in self.a_lin.chunks_exact_mut(9).zip(&md.j_ru) {
            for i in 0..3 {
                for k in 0..3 {
                    a[3 * i + k] = jr[i][k] + jr[k][i];
                }
            }
        }
        if n > 0 {
            // S_mp at p 9n + m 9: block (p, m) is J̄''_mp + J̄''_pm, and J̄''_pm is
            // `j_uu[p n + m]`, the p-th row of blocks in order.
            for (p, (dst, row_p)) in self
                .s_quad
                .chunks_exact_mut(9 * n)
                .zip(md.j_uu.chunks_exact(n))
                .enumerate()
            {
                for (m, (s9, b)) in dst.chunks_exact_mut(9).zip(row_p).enumerate() {
                    let a = md.j_uu[m * n + p].as_flattened();
                    for ((o, x), y) in s9.iter_mut().zip(a).zip(b.as_flattened()) {
                        *o = x + y;
                    }
                }
            }
            // (H̄'_m)_ip at (i n + p) n + m from `h_prime[(m 3 + i) n + p]`: the transpose
            // of `h_prime` read as n rows of 3n.
            for (ip, dst) in self.h_prime_t.chunks_exact_mut(n).enumerate() {
                for (o, row) in dst.iter_mut().zip(md.h_prime.chunks_exact(3 * n)) {
                    *o = row[ip];
                }
            }
        }
        // M̄ = L Lᵀ, then L⁻¹ column by column (forward substitution on unit vectors).
        self.chol.copy_from_slice(&md.modal_mass);
        self.modal_error = cholesky_factor(&mut self.chol, n).err().map(|e| match e {
            RhsError::SingularMassMatrix { row, pivot } => RhsError::SingularMassMatrix {
                row: 6 + row,
                pivot,
            },
            other => other,
        });
        self.linv.fill(0.0);
        if self.modal_error.is_none() {
            let l = &self.chol;
            for j in 0..n {
                for i in j..n {
                    let mut s = if i == j { 1.0 } else { 0.0 };
                    for k in j..i {
                        s -= l[i * n + k] * self.linv[k * n + j];
                    }
                    self.linv[i * n + j] = s / l[i * n + i];
                }
            }
        }
        for p in 0..n {
            let l_row = &self.linv[p * n..p * n + p + 1];
            for i in 0..3 {
                self.w_p[3 * p + i] = l_row
                    .iter()
                    .zip(&md.p_bar[i * n..i * n + p + 1])
                    .map(|(l, b)| l * b)
                    .sum();
            }
        }
        for i in 0..3 {
            for k in 0..3 {
                let wtw: f64 = (0..n)
                    .map(|p| self.w_p[3 * p + i] * self.w_p[3 * p + k])
                    .sum();
                self.s_vv[i][k] = if i == k { md.mass } else { 0.0 } - wtw;
            }
        }
        // S_vv = L_vv L_vvᵀ and L_vv⁻¹ (forward substitution on unit vectors), once.
        let mut l = [0.0; 9];
        for i in 0..3 {
            l[3 * i..3 * i + 3].copy_from_slice(&self.s_vv[i]);
        }
        self.rigid_error = cholesky_factor(&mut l, 3).err();
        self.s_vv_linv = [[0.0; 3]; 3];
        if self.rigid_error.is_none() {
            for j in 0..3 {
                for i in j..3 {
                    let mut s = if i == j { 1.0 } else { 0.0 };
                    for k in j..i {
                        s -= l[3 * i + k] * self.s_vv_linv[k][j];
                    }
                    self.s_vv_linv[i][j] = s / l[3 * i + i];
                }
            }
        }
    }
}

/// Quantities of eq. (3.2.1) that depend on `η` only.
struct Inertia {
    c_tot: [f64; 3],
    j_tot: Mat3,
}

/// Energy and momentum of a state (thesis 4.5.3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Invariants {
    /// Kinetic energy `T = ½ vᵀ M_tot(η) v`.
    pub kinetic_energy: f64,
    /// Strain energy `½ ηᵀ K̄ η`.
    pub strain_energy: f64,
    /// Translational momentum `p_B = ∂T/∂V_B` (body frame).
    pub momentum_body: [f64; 3],
    /// `p_I = C_IB p_B`.
    pub momentum_inertial: [f64; 3],
    /// Angular momentum about the body origin `h_o = ∂T/∂ω_B` (body frame).
    pub angular_momentum_origin_body: [f64; 3],
    /// Angular momentum about the mass centre, body frame:
    /// `h_cm = h_o - (c̄_tot / m) × p_B` (the mass centre sits at `c̄_tot/m`, eq. 3.2.10).
    pub angular_momentum_cm_body: [f64; 3],
    /// `C_IB h_cm`.
    pub angular_momentum_cm_inertial: [f64; 3],
    /// Mass `m` (with the propellant left at this time), kg.
    pub mass: f64,
    /// Mass centre `c̄_tot / m` (deformed), body frame, m.
    pub centre_of_mass_body: [f64; 3],
}

impl Invariants {
    /// `T + ½ ηᵀK̄η`.
    pub fn total_energy(&self) -> f64 {
        self.kinetic_energy + self.strain_energy
    }
}

/// The motor of a variable-mass vehicle inside the equations of motion (module doc,
/// "Variable mass"): the burn schedule, the thrust at the nozzle, the dry and propellant
/// coefficients and the working model at the current propellant fraction.
#[derive(Debug, Clone)]
pub struct Propulsion {
    schedule: BurnSchedule,
    thrust: ThrustBlock,
    /// Undeformed exit point `r_T + δ_T`, body frame, m.
    exit: [f64; 3],
    /// Rows u, v, w of `S` at the nozzle (3 x n).
    s_exit: Vec<f64>,
    dry: ReducedModel,
    prop: ReducedModel,
    current: ReducedModel,
    fraction: f64,
    /// `M_p(η)` (d x d) and its `H̄_tot` (3 x n); `M_p v`.
    mp_matrix: Vec<f64>,
    mp_h: Vec<f64>,
    mp_v: Vec<f64>,
    /// `v = (V_B, ω_B, η̇)`.
    mp_vel: Vec<f64>,
    /// Thrust generalised forces.
    thrust_forces: Vec<f64>,
    last: PropulsionSample,
}

/// What the motor did at the last right-hand side evaluation (for balances and tests).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PropulsionSample {
    /// Propellant fraction `f`.
    pub fraction: f64,
    /// Mass flow through the exit `ṁ_e`, kg/s.
    pub mass_flow: f64,
    /// Thrust force, body frame, N.
    pub thrust_force_body: [f64; 3],
    /// Thrust moment about the body origin, body frame, N m.
    pub thrust_moment_body: [f64; 3],
    /// Deformed exit point `r_e`, body frame, m.
    pub exit_position_body: [f64; 3],
    /// Velocity of the exit point `v_e = V + ω × r_e + Φ_e η̇`, body frame, m/s.
    pub exit_velocity_body: [f64; 3],
}

impl Propulsion {
    /// The motor of `full` (the compiled vehicle at ignition) whose propellant at full load
    /// contributes `prop` (same basis), burning by `schedule`, with its thrust block and the
    /// exit point `exit` (undeformed `r_T + δ_T`) with the nozzle's translation rows `s_exit`.
    pub fn new(
        full: &ReducedModel,
        prop: ReducedModel,
        schedule: BurnSchedule,
        thrust: ThrustBlock,
        exit: [f64; 3],
        s_exit: &[f64],
    ) -> Result<Self, EomError> {
        let n = full.n();
        let checks: [(&'static str, usize, usize); 8] = [
            ("propellant modal_mass", n * n, prop.modal_mass.len()),
            ("propellant p_bar", 3 * n, prop.p_bar.len()),
            ("propellant h_bar", 3 * n, prop.h_bar.len()),
            ("propellant j_ru", n, prop.j_ru.len()),
            ("propellant j_uu", n * n, prop.j_uu.len()),
            ("propellant h_prime", 3 * n * n, prop.h_prime.len()),
            ("propellant modes", n, prop.n()),
            ("nozzle shape rows", 3 * n, s_exit.len()),
        ];
        for (field, expected, found) in checks {
            if expected != found {
                return Err(EomError::ModelShape {
                    field,
                    expected,
                    found,
                    n,
                });
            }
        }
        let d = 6 + n;
        // M_p at η = 0: its constant entries stay, `refresh_eta_terms` rewrites the others.
        let (mut mp_h, mut mp_matrix) = (vec![0.0; 3 * n], vec![0.0; d * d]);
        assemble(&prop, &vec![0.0; n], &mut mp_h, &mut mp_matrix);
        Ok(Self {
            dry: dry_model(full, &prop),
            current: full.clone(),
            prop,
            schedule,
            thrust,
            exit,
            s_exit: s_exit.to_vec(),
            fraction: 1.0,
            mp_matrix,
            mp_h,
            mp_v: vec![0.0; d],
            mp_vel: vec![0.0; d],
            thrust_forces: vec![0.0; d],
            last: PropulsionSample::default(),
        })
    }

    /// The burn schedule.
    pub fn schedule(&self) -> &BurnSchedule {
        &self.schedule
    }

    /// Sets the working coefficients to the propellant fraction at `t` (a few axpy's on the
    /// coefficient arrays, only when `f` changed; no allocation).
    fn update(&mut self, t: f64) {
        let f = self.schedule.fraction(t);
        if f != self.fraction {
            combine_into(&self.dry, &self.prop, f, &mut self.current);
            self.fraction = f;
        }
    }
}

/// The equations of motion (3.2.1) of one reduced model with one force model.
#[derive(Debug, Clone)]
pub struct Eom<'m, F> {
    model: &'m ReducedModel,
    layout: StateLayout,
    /// External loads.
    pub forces: F,
    ws: Workspace,
    /// The coefficients rearranged for the right-hand side (of the current model).
    pre: Precomputed,
    /// The propellant fraction `pre` was built for (a motor's working model may have moved
    /// on through any caller of `Propulsion::update`; [`Self::sync_precomputed`]).
    pre_fraction: f64,
    /// The burning motor of a variable-mass vehicle.
    propulsion: Option<Box<Propulsion>>,
    /// Integrate the works of the energy balance after the state ([`Self::track_energy`]).
    track_energy: bool,
    /// The vector unit the right-hand side is compiled for, detected once.
    arch: pulp::Arch,
}

/// Entries appended to the state by [`Eom::track_energy`], after `13 + 2n`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EnergyLayout;

impl EnergyLayout {
    /// `∫ vᵀ f_loads dt`: work of the force blocks (gravity, aerodynamics, a thrust block
    /// without motor), J.
    pub const LOADS: usize = 0;
    /// `∫ (vᵀ f_T + ṁ_e (½ vᵀM_p v/m_p - |v_e|²)) dt`: propulsive work of the motor, J.
    pub const PROPULSIVE: usize = 1;
    /// `∫ η̇ᵀ C̄ η̇ dt`: energy dissipated by the modal damping, J.
    pub const DISSIPATED: usize = 2;
    /// Number of entries.
    pub const LEN: usize = 3;
}

impl<'m, F: ForceModel> Eom<'m, F> {
    /// Checks the coefficient shapes once (so the right-hand side can index freely) and
    /// allocates the workspace.
    pub fn new(model: &'m ReducedModel, forces: F) -> Result<Self, EomError> {
        let n = model.n();
        let checks: [(&'static str, usize, usize); 8] = [
            ("modal_mass", n * n, model.modal_mass.len()),
            ("modal_stiffness", n * n, model.modal_stiffness.len()),
            ("modal_damping", n * n, model.modal_damping.len()),
            ("p_bar", 3 * n, model.p_bar.len()),
            ("h_bar", 3 * n, model.h_bar.len()),
            ("j_ru", n, model.j_ru.len()),
            ("j_uu", n * n, model.j_uu.len()),
            ("h_prime", 3 * n * n, model.h_prime.len()),
        ];
        for (field, expected, found) in checks {
            if expected != found {
                return Err(EomError::ModelShape {
                    field,
                    expected,
                    found,
                    n,
                });
            }
        }
        let d = 6 + n;
        Ok(Self {
            model,
            layout: StateLayout { n },
            forces,
            ws: Workspace {
                rhs: vec![0.0; d],
                forces: vec![0.0; d],
                h_tot: vec![0.0; 3 * n],
                dt_deta: vec![0.0; n],
                g: vec![0.0; 9 * n],
                h_dot: vec![0.0; 3 * n],
                w_h: vec![0.0; 3 * n],
                z: vec![0.0; n],
            },
            pre: Precomputed::new(model),
            pre_fraction: 1.0,
            propulsion: None,
            track_energy: false,
            arch: pulp::Arch::new(),
        })
    }

    /// Makes the vehicle burn: the motor's thrust, variable mass and mass-flow terms (module
    /// doc, "Variable mass"). The propulsion must be built on this model.
    pub fn with_propulsion(mut self, propulsion: Propulsion) -> Result<Self, EomError> {
        if propulsion.current.n() != self.layout.n {
            return Err(EomError::ModelShape {
                field: "propulsion modes",
                expected: self.layout.n,
                found: propulsion.current.n(),
                n: self.layout.n,
            });
        }
        self.pre.rebuild(&propulsion.current);
        self.pre_fraction = propulsion.fraction;
        self.propulsion = Some(Box::new(propulsion));
        Ok(self)
    }

    /// Appends the [`EnergyLayout`] works to the state (they start at zero): then
    /// `T + ½ηᵀK̄η - W_loads - W_propulsive + D` is constant, and its drift is the residual of
    /// the energy balance. The integrator's error control sees only the physical state
    /// ([`OdeSystem::error_dim`]), so tracking never changes a history.
    pub fn track_energy(mut self) -> Self {
        self.track_energy = true;
        self
    }

    /// The motor, if the vehicle burns.
    pub fn propulsion(&self) -> Option<&Propulsion> {
        self.propulsion.as_deref()
    }

    /// What the motor did at the last right-hand side evaluation.
    pub fn propulsion_sample(&self) -> Option<PropulsionSample> {
        self.propulsion.as_ref().map(|p| p.last)
    }

    /// Sets the mass properties to those at time `t` (the propellant fraction of the burn
    /// schedule); nothing without a motor.
    pub fn set_time(&mut self, t: f64) {
        if let Some(p) = &mut self.propulsion {
            p.update(t);
        }
        self.sync_precomputed();
    }

    /// Rebuilds the precomputed coefficients if the motor's propellant fraction moved since
    /// they were built (no allocation).
    fn sync_precomputed(&mut self) {
        if let Some(p) = &self.propulsion {
            if p.fraction != self.pre_fraction {
                self.pre.rebuild_mass_terms(&p.current);
                self.pre_fraction = p.fraction;
            }
        }
    }

    /// For the constrained phases of a flight (rail, point-mass descent; see
    /// [`crate::runtime::flight`]): sets the mass properties to time `t`, writes the motor's
    /// thrust generalised forces at `s` into `thrust` (zeros without a motor) and returns the
    /// mass and the exit mass flow `ṁ_e` (0 without a motor). No allocation.
    pub fn motor_at(&mut self, t: f64, s: &StateView, thrust: &mut [f64]) -> (f64, f64) {
        thrust.iter_mut().for_each(|x| *x = 0.0);
        match &mut self.propulsion {
            Some(p) => {
                p.update(t);
                p.thrust.generalized_forces(t, s, thrust);
                (p.current.mass, p.schedule.mass_flow(t))
            }
            None => (self.model.mass, 0.0),
        }
    }

    /// Mass and first moment `c̄_tot(η)` at the current propellant fraction.
    pub fn mass_properties(&self, eta: &[f64]) -> (f64, [f64; 3]) {
        let md = self.current_model();
        let n = self.layout.n;
        let mut c = md.first_moment;
        for i in 0..3 {
            for m in 0..n.min(eta.len()) {
                c[i] += md.p_bar[i * n + m] * eta[m];
            }
        }
        (md.mass, c)
    }

    /// The coefficients at the current propellant fraction.
    fn current_model(&self) -> &ReducedModel {
        match &self.propulsion {
            Some(p) => &p.current,
            None => self.model,
        }
    }

    /// The state layout.
    pub fn layout(&self) -> StateLayout {
        self.layout
    }

    /// Energy and momentum of the state `x` (thesis 4.5.3); no allocation.
    pub fn invariants(&mut self, x: &[f64]) -> Result<Invariants, EomError> {
        let l = self.layout;
        if x.len() != l.len() && x.len() != l.len() + EnergyLayout::LEN {
            return Err(EomError::StateLength {
                expected: l.len(),
                found: x.len(),
            });
        }
        self.sync_precomputed();
        let n = l.n;
        let eta = &x[13..13 + n];
        let eta_dot = &x[13 + n..13 + 2 * n];
        let v = [x[7], x[8], x[9]];
        let w = [x[10], x[11], x[12]];
        let md: &ReducedModel = match &self.propulsion {
            Some(p) => &p.current,
            None => self.model,
        };
        let ws = &mut self.ws;
        let inr = inertia(&self.pre, md, eta, &mut ws.g);
        if md.h_tot_into(eta, &mut ws.h_tot).is_err() {
            ws.h_tot.fill(f64::NAN);
        }
        let [pv, pw] = momenta(md, &ws.h_tot, &inr, &v, &w, eta_dot);
        let mut pe = 0.0;
        let mut strain = 0.0;
        for m in 0..n {
            let mut row = 0.0;
            let mut k = 0.0;
            for i in 0..3 {
                row += md.p_bar[i * n + m] * v[i] + ws.h_tot[i * n + m] * w[i];
            }
            for p in 0..n {
                row += md.modal_mass[m * n + p] * eta_dot[p];
                k += md.modal_stiffness[m * n + p] * eta[p];
            }
            pe += eta_dot[m] * row;
            strain += 0.5 * eta[m] * k;
        }
        let kinetic = 0.5
            * (v.iter().zip(&pv).map(|(a, b)| a * b).sum::<f64>()
                + w.iter().zip(&pw).map(|(a, b)| a * b).sum::<f64>()
                + pe);
        let c_bi = c_bi_normalized(&[x[3], x[4], x[5], x[6]]);
        let rc = inr.c_tot.map(|c| c / md.mass);
        let hc = cross(&rc, &pv);
        let h_cm = [pw[0] - hc[0], pw[1] - hc[1], pw[2] - hc[2]];
        Ok(Invariants {
            kinetic_energy: kinetic,
            strain_energy: strain,
            momentum_body: pv,
            momentum_inertial: mat_t_vec(&c_bi, &pv),
            angular_momentum_origin_body: pw,
            angular_momentum_cm_body: h_cm,
            angular_momentum_cm_inertial: mat_t_vec(&c_bi, &h_cm),
            mass: md.mass,
            centre_of_mass_body: rc,
        })
    }

    /// [`Self::invariants`] with the mass properties at time `t` ([`Self::set_time`]).
    pub fn invariants_at(&mut self, t: f64, x: &[f64]) -> Result<Invariants, EomError> {
        self.set_time(t);
        self.invariants(x)
    }
}

/// `c̄_tot(η)` and `J̄_tot(η)` of `md`, eqs. (3.2.8)-(3.2.9), in the one order of sums that
/// [`assemble`] and [`refresh_eta_terms`] share (so that their matrices have the same bits).
fn moments(md: &ReducedModel, eta: &[f64]) -> ([f64; 3], [[f64; 3]; 3]) {
    let n = md.n();
    let mut c = md.first_moment;
    for i in 0..3 {
        for m in 0..n {
            c[i] += md.p_bar[i * n + m] * eta[m];
        }
    }
    let mut j = md.inertia;
    for m in 0..n {
        let (jr, em) = (&md.j_ru[m], eta[m]);
        for i in 0..3 {
            for k in 0..3 {
                j[i][k] += em * (jr[i][k] + jr[k][i]);
            }
        }
        for p in 0..n {
            let (ju, w) = (&md.j_uu[m * n + p], em * eta[p]);
            for i in 0..3 {
                for k in 0..3 {
                    j[i][k] += w * ju[i][k];
                }
            }
        }
    }
    (c, j)
}

/// `c̄_tot`, `J̄_tot`, `H̄_tot` (into `h`) and `M_tot(η)` (into `mass_matrix`) of `md`,
/// eqs. (3.2.8)-(3.2.12); the same matrix as [`ReducedModel::mass_matrix_into`] without its
/// allocation.
fn assemble(md: &ReducedModel, eta: &[f64], h: &mut [f64], mass_matrix: &mut [f64]) -> Inertia {
    let (c, j) = moments(md, eta);
    // Lengths were checked in `Eom::new`; a failure here poisons the state with NaN so
    // the integrator stops with "non-finite state" instead of going on silently.
    if md.h_tot_into(eta, h).is_err() {
        h.fill(f64::NAN);
    }
    md.assemble_mass_matrix(c, &j, h, mass_matrix);
    Inertia { c_tot: c, j_tot: j }
}

/// [`assemble`] into a matrix that already holds `M_tot` of `md` at some `η` (built by
/// [`assemble`] once): `c̄_tot`, `J̄_tot` and `H̄_tot` by the same arithmetic, and only the
/// entries that depend on `η` rewritten (the `∓c̄_tot^×` and `J̄_tot` blocks, `H̄_tot` and
/// its transpose); the mass, `P̄` and `M̄` entries are constant. The same matrix, bit for
/// bit, as [`assemble`]'s.
fn refresh_eta_terms(md: &ReducedModel, eta: &[f64], h: &mut [f64], mass_matrix: &mut [f64]) {
    let n = md.n();
    let d = 6 + n;
    let (c, j) = moments(md, eta);
    if md.h_tot_into(eta, h).is_err() {
        h.fill(f64::NAN);
    }
    // `ReducedModel::assemble_mass_matrix`'s writes of these blocks.
    let x = [[0.0, -c[2], c[1]], [c[2], 0.0, -c[0]], [-c[1], c[0], 0.0]];
    for i in 0..3 {
        for k in 0..3 {
            mass_matrix[i * d + 3 + k] = -x[i][k];
            mass_matrix[(3 + i) * d + k] = x[i][k];
            mass_matrix[(3 + i) * d + 3 + k] = j[i][k];
        }
        for p in 0..n {
            mass_matrix[(3 + i) * d + 6 + p] = h[i * n + p];
            mass_matrix[(6 + p) * d + 3 + i] = h[i * n + p];
        }
    }
}

/// Momenta `p_V = m V + ω × c̄_tot + P̄ η̇`, `p_ω = c̄_tot × V + J̄_tot ω + H̄_tot η̇`
/// (rows of `M_tot v`) of `md`, with `inr` and `h_tot` from [`assemble`].
#[inline(always)]
fn momenta(
    md: &ReducedModel,
    h_tot: &[f64],
    inr: &Inertia,
    v: &[f64; 3],
    w: &[f64; 3],
    eta_dot: &[f64],
) -> [[f64; 3]; 2] {
    let n = md.n();
    let wc = cross(w, &inr.c_tot);
    let cv = cross(&inr.c_tot, v);
    let jw = mat_vec(&inr.j_tot, w);
    let mut pv = [0.0; 3];
    let mut pw = [0.0; 3];
    for i in 0..3 {
        let (mut a, mut b) = (0.0, 0.0);
        for p in 0..n {
            a += md.p_bar[i * n + p] * eta_dot[p];
            b += h_tot[i * n + p] * eta_dot[p];
        }
        pv[i] = md.mass * v[i] + wc[i] + a;
        pw[i] = cv[i] + jw[i] + b;
    }
    [pv, pw]
}

/// `vᵀ f` for generalised forces `f = (F_B, G_B, Q)` and `v = (V_B, ω_B, η̇)`: the power.
#[inline(always)]
fn generalized_power(f: &[f64], v: &[f64; 3], w: &[f64; 3], eta_dot: &[f64]) -> f64 {
    let mut s = 0.0;
    for i in 0..3 {
        s += f[i] * v[i] + f[3 + i] * w[i];
    }
    for (m, ed) in eta_dot.iter().enumerate() {
        s += f[6 + m] * ed;
    }
    s
}

/// Adds the motor's thrust and mass-flow terms `f_T + (ṁ_e/m_p) M_p(η) v - ṁ_e Ψ_eᵀ Ψ_e v`
/// (module doc, "Variable mass") to the right-hand side `r` (length `6 + n`) and returns the
/// propulsive power `vᵀ f_T + ṁ_e (½ vᵀ M_p v / m_p - |v_e|²)`. No allocation.
fn propulsion_terms(p: &mut Propulsion, t: f64, s: &StateView, r: &mut [f64]) -> f64 {
    let n = s.eta.len();
    let (v, w) = (s.velocity, s.angular_velocity);
    p.thrust_forces.iter_mut().for_each(|x| *x = 0.0);
    p.thrust.generalized_forces(t, s, &mut p.thrust_forces);
    let mut power = generalized_power(&p.thrust_forces, &v, &w, s.eta_dot);
    for (ri, fi) in r.iter_mut().zip(&p.thrust_forces) {
        *ri += fi;
    }
    // Deformed exit point and its velocity.
    let mut r_e = p.exit;
    let mut u_dot = [0.0; 3];
    for i in 0..3 {
        for m in 0..n {
            r_e[i] += p.s_exit[i * n + m] * s.eta[m];
            u_dot[i] += p.s_exit[i * n + m] * s.eta_dot[m];
        }
    }
    let wr = cross(&w, &r_e);
    let v_e = [0, 1, 2].map(|i| v[i] + wr[i] + u_dot[i]);
    let mdot = p.schedule.mass_flow(t);
    p.last = PropulsionSample {
        fraction: p.fraction,
        mass_flow: mdot,
        thrust_force_body: [p.thrust_forces[0], p.thrust_forces[1], p.thrust_forces[2]],
        thrust_moment_body: [p.thrust_forces[3], p.thrust_forces[4], p.thrust_forces[5]],
        exit_position_body: r_e,
        exit_velocity_body: v_e,
    };
    if mdot == 0.0 {
        return power;
    }
    // (ṁ_e/m_p) M_p(η) v: only the η-dependent entries of M_p are written (its constant
    // ones since `Propulsion::new`), the product summed over each row in column order.
    let d = 6 + n;
    refresh_eta_terms(&p.prop, s.eta, &mut p.mp_h, &mut p.mp_matrix);
    p.mp_vel[..3].copy_from_slice(&v);
    p.mp_vel[3..6].copy_from_slice(&w);
    p.mp_vel[6..].copy_from_slice(s.eta_dot);
    for (o, row) in p.mp_v.iter_mut().zip(p.mp_matrix.chunks_exact(d)) {
        *o = row.iter().zip(&p.mp_vel).map(|(m, x)| m * x).sum();
    }
    let k = mdot / p.schedule.propellant_mass();
    let mut vmv = 0.0;
    for ((ri, mv), x) in r.iter_mut().zip(&p.mp_v).zip(&p.mp_vel) {
        *ri += k * mv;
        vmv += x * mv;
    }
    // -ṁ_e Ψ_eᵀ v_e = -ṁ_e (v_e, r_e × v_e, Φ_eᵀ v_e).
    let rxv = cross(&r_e, &v_e);
    for i in 0..3 {
        r[i] -= mdot * v_e[i];
        r[3 + i] -= mdot * rxv[i];
    }
    for m in 0..n {
        let phi_v: f64 = (0..3).map(|i| p.s_exit[i * n + m] * v_e[i]).sum();
        r[6 + m] -= mdot * phi_v;
    }
    let ve2: f64 = v_e.iter().map(|x| x * x).sum();
    power += mdot * (0.5 * vmv / p.schedule.propellant_mass() - ve2);
    power
}

/// `Σ a_i b_i`.
#[inline(always)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// A row-major 3 x 3 matrix (9 entries) times a vector.
#[inline(always)]
fn mat9_vec(a: &[f64], x: &[f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| a[3 * i] * x[0] + a[3 * i + 1] * x[1] + a[3 * i + 2] * x[2])
}

/// `c̄_tot = c + P̄η` (eq. 3.2.10), `G_m = A_m + Σ_p η_p S_mp` into `g` and
/// `J̄_tot = J + ½ Σ_m η_m (A_m + G_m)` ([`Precomputed`]; eqs. 3.2.9, 3.2.11, 3.2.12).
#[inline(always)]
fn inertia(pre: &Precomputed, md: &ReducedModel, eta: &[f64], g: &mut [f64]) -> Inertia {
    let n = pre.n;
    let mut c = md.first_moment;
    for i in 0..3 {
        c[i] += dot(&md.p_bar[i * n..(i + 1) * n], eta);
    }
    g.copy_from_slice(&pre.a_lin);
    for (p, ep) in eta.iter().enumerate() {
        for (gi, si) in g.iter_mut().zip(&pre.s_quad[p * 9 * n..(p + 1) * 9 * n]) {
            *gi += ep * si;
        }
    }
    let mut j9 = [0.0; 9];
    for m in 0..n {
        let (a, gm) = (&pre.a_lin[m * 9..m * 9 + 9], &g[m * 9..m * 9 + 9]);
        for ik in 0..9 {
            j9[ik] += eta[m] * (a[ik] + gm[ik]);
        }
    }
    let mut j = md.inertia;
    for i in 0..3 {
        for k in 0..3 {
            j[i][k] += 0.5 * j9[3 * i + k];
        }
    }
    Inertia { c_tot: c, j_tot: j }
}

/// `H̄_tot = H̄ + Σ_m η_m H̄'_m` and `H̄̇_tot = Σ_m η̇_m H̄'_m` (3 x n each, eqs.
/// 3.2.4-3.2.6) in one pass over `H̄'`.
#[inline(always)]
fn h_tot_and_rate(md: &ReducedModel, eta: &[f64], eta_dot: &[f64], h: &mut [f64], hd: &mut [f64]) {
    let n = eta.len();
    h.copy_from_slice(&md.h_bar);
    hd.fill(0.0);
    for m in 0..n {
        let block = &md.h_prime[m * 3 * n..(m + 1) * 3 * n];
        let (e, ed) = (eta[m], eta_dot[m]);
        for ((hi, hdi), b) in h.iter_mut().zip(hd.iter_mut()).zip(block) {
            *hi += e * b;
            *hdi += ed * b;
        }
    }
}

/// Solves `M_tot(η) v̇ = r` in place by the Schur complement on the rigid block
/// ([`Precomputed`], "The solve"): `w_h` (3n) and `z` (n) are scratch. No allocation.
#[inline(always)]
fn schur_solve(
    pre: &Precomputed,
    inr: &Inertia,
    h_tot: &[f64],
    w_h: &mut [f64],
    z: &mut [f64],
    r: &mut [f64],
) -> Result<(), RhsError> {
    if let Some(e) = pre.modal_error.or(pre.rigid_error) {
        return Err(e);
    }
    let n = pre.n;
    let l = &pre.linv;
    // W_H = L⁻¹ H̄_totᵀ and z = L⁻¹ r_η.
    for p in 0..n {
        let row = &l[p * n..p * n + p + 1];
        let (mut a0, mut a1, mut a2, mut b) = (0.0, 0.0, 0.0, 0.0);
        for (q, lq) in row.iter().enumerate() {
            a0 += lq * h_tot[q];
            a1 += lq * h_tot[n + q];
            a2 += lq * h_tot[2 * n + q];
            b += lq * r[6 + q];
        }
        w_h[3 * p] = a0;
        w_h[3 * p + 1] = a1;
        w_h[3 * p + 2] = a2;
        z[p] = b;
    }
    // The blocks S_ωv, S_ωω (lower triangle) of S = A - WᵀW and the reduced right-hand
    // side y = r_r - Wᵀ z.
    let c = inr.c_tot;
    let mut s_wv = [[0.0, -c[2], c[1]], [c[2], 0.0, -c[0]], [-c[1], c[0], 0.0]];
    let mut s_ww = inr.j_tot;
    let mut y = [r[0], r[1], r[2], r[3], r[4], r[5]];
    for p in 0..n {
        let (wp, wh, zp) = (&pre.w_p[3 * p..3 * p + 3], &w_h[3 * p..3 * p + 3], z[p]);
        for i in 0..3 {
            y[i] -= wp[i] * zp;
            y[3 + i] -= wh[i] * zp;
            for k in 0..3 {
                s_wv[i][k] -= wh[i] * wp[k];
            }
            for k in 0..=i {
                s_ww[i][k] -= wh[i] * wh[k];
            }
        }
    }
    // L_ωv = S_ωv L_vv⁻ᵀ: (L_ωv)_ik = Σ_{j <= k} (S_ωv)_ij (L_vv⁻¹)_kj.
    let m = &pre.s_vv_linv;
    let mut l_wv = [[0.0; 3]; 3];
    for i in 0..3 {
        for k in 0..3 {
            l_wv[i][k] = (0..=k).map(|j| s_wv[i][j] * m[k][j]).sum();
        }
    }
    // S_ωω - L_ωv L_ωvᵀ = L_ωω L_ωωᵀ, with the reciprocal pivots.
    let mut lw = s_ww;
    let mut inv = [0.0; 3];
    for j in 0..3 {
        for i in j..3 {
            let mut s = lw[i][j];
            for k in 0..3 {
                s -= l_wv[i][k] * l_wv[j][k];
            }
            for k in 0..j {
                s -= lw[i][k] * lw[j][k];
            }
            if i == j {
                if !(s > 0.0 && s.is_finite()) {
                    return Err(RhsError::SingularMassMatrix {
                        row: 3 + j,
                        pivot: s,
                    });
                }
                let ljj = s.sqrt();
                lw[j][j] = ljj;
                inv[j] = 1.0 / ljj;
            } else {
                lw[i][j] = s * inv[j];
            }
        }
    }
    // Forward: u_v = L_vv⁻¹ y_v, u_ω = L_ωω⁻¹ (y_ω - L_ωv u_v).
    let u_v: [f64; 3] = std::array::from_fn(|i| (0..=i).map(|j| m[i][j] * y[j]).sum());
    let mut u_w = [0.0; 3];
    for i in 0..3 {
        let mut s = y[3 + i];
        for k in 0..3 {
            s -= l_wv[i][k] * u_v[k];
        }
        for k in 0..i {
            s -= lw[i][k] * u_w[k];
        }
        u_w[i] = s * inv[i];
    }
    // Backward: x_ω = L_ωω⁻ᵀ u_ω, x_v = L_vv⁻ᵀ (u_v - L_ωvᵀ x_ω).
    let mut x_w = [0.0; 3];
    for i in (0..3).rev() {
        let mut s = u_w[i];
        for k in i + 1..3 {
            s -= lw[k][i] * x_w[k];
        }
        x_w[i] = s * inv[i];
    }
    let t: [f64; 3] =
        std::array::from_fn(|j| u_v[j] - (0..3).map(|i| l_wv[i][j] * x_w[i]).sum::<f64>());
    let x_v: [f64; 3] = std::array::from_fn(|j| (j..3).map(|i| m[i][j] * t[i]).sum());
    let y = [x_v[0], x_v[1], x_v[2], x_w[0], x_w[1], x_w[2]];
    // v̇_η = L⁻ᵀ (z - W v̇_r).
    for p in 0..n {
        let (wp, wh) = (&pre.w_p[3 * p..3 * p + 3], &w_h[3 * p..3 * p + 3]);
        z[p] -=
            wp[0] * y[0] + wp[1] * y[1] + wp[2] * y[2] + wh[0] * y[3] + wh[1] * y[4] + wh[2] * y[5];
    }
    let re = &mut r[6..6 + n];
    re.fill(0.0);
    for p in 0..n {
        let zp = z[p];
        for (rq, lq) in re.iter_mut().zip(&l[p * n..p * n + p + 1]) {
            *rq += lq * zp;
        }
    }
    r[..6].copy_from_slice(&y);
    Ok(())
}

/// In-place Cholesky factorisation `A = L Lᵀ` of a row-major symmetric positive definite
/// matrix (only its lower triangle is read; it is overwritten by `L`).
fn cholesky_factor(a: &mut [f64], d: usize) -> Result<(), RhsError> {
    for j in 0..d {
        let mut s = a[j * d + j];
        for k in 0..j {
            s -= a[j * d + k] * a[j * d + k];
        }
        if !(s > 0.0 && s.is_finite()) {
            return Err(RhsError::SingularMassMatrix { row: j, pivot: s });
        }
        let ljj = s.sqrt();
        a[j * d + j] = ljj;
        for i in j + 1..d {
            let mut s = a[i * d + j];
            for k in 0..j {
                s -= a[i * d + k] * a[j * d + k];
            }
            a[i * d + j] = s / ljj;
        }
    }
    Ok(())
}

/// Solves `L Lᵀ y = b` into `b` with the factor of [`cholesky_factor`] (tests).
#[cfg(test)]
fn cholesky_substitute(a: &[f64], d: usize, b: &mut [f64]) {
    for i in 0..d {
        let mut s = b[i];
        for k in 0..i {
            s -= a[i * d + k] * b[k];
        }
        b[i] = s / a[i * d + i];
    }
    for i in (0..d).rev() {
        let mut s = b[i];
        for k in i + 1..d {
            s -= a[k * d + i] * b[k];
        }
        b[i] = s / a[i * d + i];
    }
}

/// Factorises and solves `A y = b` (tests; the right-hand side uses [`schur_solve`]).
#[cfg(test)]
fn cholesky_solve(a: &mut [f64], d: usize, b: &mut [f64]) -> Result<(), RhsError> {
    cholesky_factor(a, d)?;
    cholesky_substitute(a, d, b);
    Ok(())
}

/// [`OdeSystem::rhs`] of [`Eom`] as a [`pulp::WithSimd`] operation.
struct RhsOp<'e, 'm, F: ForceModel> {
    eom: &'e mut Eom<'m, F>,
    t: f64,
    x: &'e [f64],
    dx: &'e mut [f64],
}

impl<F: ForceModel> pulp::WithSimd for RhsOp<'_, '_, F> {
    type Output = Result<(), RhsError>;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        self.eom.rhs_body(self.t, self.x, self.dx)
    }
}

impl<F: ForceModel> Eom<'_, F> {
    /// The body of [`OdeSystem::rhs`].
    #[inline(always)]
    fn rhs_body(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), RhsError> {
        let l = self.layout;
        let n = l.n;
        let d = 6 + n;
        let view = StateView::new(l, x);
        if let Some(p) = &mut self.propulsion {
            p.update(t);
        }
        self.sync_precomputed();
        self.ws.forces.iter_mut().for_each(|f| *f = 0.0);
        self.forces
            .generalized_forces(t, &view, &mut self.ws.forces);
        let (v, w) = (view.velocity, view.angular_velocity);
        let (eta, eta_dot) = (view.eta, view.eta_dot);
        let power_loads = if self.track_energy {
            generalized_power(&self.ws.forces, &v, &w, eta_dot)
        } else {
            0.0
        };
        let md: &ReducedModel = match &self.propulsion {
            Some(p) => &p.current,
            None => self.model,
        };
        let ws = &mut self.ws;
        let pre = &self.pre;
        let inr = inertia(pre, md, eta, &mut ws.g);
        h_tot_and_rate(md, eta, eta_dot, &mut ws.h_tot, &mut ws.h_dot);
        let [pv, pw] = momenta(md, &ws.h_tot, &inr, &v, &w, eta_dot);

        // ċ = P̄ η̇, J̄̇_tot ω = Σ_m η̇_m G_m ω, H̄̇_tot η̇ ([`Precomputed`]).
        let mut c_dot = [0.0; 3];
        for i in 0..3 {
            c_dot[i] = dot(&md.p_bar[i * n..(i + 1) * n], eta_dot);
        }
        let mut jdot = [0.0; 9];
        for (m, gm) in ws.g.chunks_exact(9).enumerate() {
            for (j, g) in jdot.iter_mut().zip(gm) {
                *j += eta_dot[m] * g;
            }
        }
        let jdot_w = mat9_vec(&jdot, &w);
        let hdot_etadot = [0, 1, 2].map(|i| dot(&ws.h_dot[i * n..(i + 1) * n], eta_dot));
        // ∂T/∂η_m - (H̄̇_totᵀ ω)_m with ∂T/∂η_m = P̄_m·(V×ω) + ½ ωᵀ G_m ω + ωᵀ H̄'_m η̇.
        ws.dt_deta.fill(0.0);
        for i in 0..3 {
            for p in 0..n {
                let c = w[i] * eta_dot[p];
                let col = &pre.h_prime_t[(i * n + p) * n..(i * n + p + 1) * n];
                for (d, h) in ws.dt_deta.iter_mut().zip(col) {
                    *d += c * h;
                }
            }
        }
        let vxw = cross(&v, &w);
        for (m, gm) in ws.g.chunks_exact(9).enumerate() {
            let mut s = 0.0;
            for i in 0..3 {
                s += md.p_bar[i * n + m] * vxw[i];
            }
            let gw = mat9_vec(gm, &w);
            s += 0.5 * (w[0] * gw[0] + w[1] * gw[1] + w[2] * gw[2]);
            let hdot_t_w = w[0] * ws.h_dot[m] + w[1] * ws.h_dot[n + m] + w[2] * ws.h_dot[2 * n + m];
            ws.dt_deta[m] += s - hdot_t_w;
        }

        let wxc = cross(&w, &c_dot);
        let wxpv = cross(&w, &pv);
        let cdxv = cross(&c_dot, &v);
        let vxpv = cross(&v, &pv);
        let wxpw = cross(&w, &pw);
        let r = &mut ws.rhs;
        let f = &ws.forces;
        for i in 0..3 {
            r[i] = f[i] - wxc[i] - wxpv[i];
            r[3 + i] = f[3 + i] - cdxv[i] - jdot_w[i] - hdot_etadot[i] - vxpv[i] - wxpw[i];
        }
        // r_m = Q_m + ∂T/∂η_m - Σ_p (K̄_mp η_p + C̄_mp η̇_p), column by column ([`Precomputed`]).
        let rm = &mut r[6..6 + n];
        for ((o, fm), dm) in rm.iter_mut().zip(&f[6..6 + n]).zip(&ws.dt_deta) {
            *o = fm + dm;
        }
        // A rigid body (n = 0) has no columns; `chunks_exact(0)` would panic.
        if n > 0 {
            for (p, (kc, cc)) in pre
                .k_t
                .chunks_exact(n)
                .zip(pre.c_t.chunks_exact(n))
                .enumerate()
            {
                let (e, ed) = (eta[p], eta_dot[p]);
                for ((o, k), c) in rm.iter_mut().zip(kc).zip(cc) {
                    *o -= k * e + c * ed;
                }
            }
        }
        let mut dissipation = 0.0;
        if self.track_energy {
            for m in 0..n {
                for p in 0..n {
                    dissipation += eta_dot[m] * md.modal_damping[m * n + p] * eta_dot[p];
                }
            }
        }
        let power_propulsive = match &mut self.propulsion {
            Some(p) => propulsion_terms(p, t, &view, r),
            None => 0.0,
        };
        schur_solve(pre, &inr, &ws.h_tot, &mut ws.w_h, &mut ws.z, r)?;

        let c_ib_v = mat_t_vec(&view.c_bi, &v);
        let qd = euler_parameter_rates(&view.attitude, &w);
        dx[0..3].copy_from_slice(&c_ib_v);
        dx[3..7].copy_from_slice(&qd);
        dx[7..13].copy_from_slice(&r[0..6]);
        dx[13..13 + n].copy_from_slice(eta_dot);
        dx[13 + n..13 + 2 * n].copy_from_slice(&r[6..d]);
        if self.track_energy {
            let e = l.len();
            dx[e + EnergyLayout::LOADS] = power_loads;
            dx[e + EnergyLayout::PROPULSIVE] = power_propulsive;
            dx[e + EnergyLayout::DISSIPATED] = dissipation;
        }
        if let Some(index) = dx.iter().position(|v| !v.is_finite()) {
            return Err(RhsError::NonFinite { index });
        }
        Ok(())
    }
}

impl<F: ForceModel> OdeSystem for Eom<'_, F> {
    fn dim(&self) -> usize {
        self.layout.len()
            + if self.track_energy {
                EnergyLayout::LEN
            } else {
                0
            }
    }

    fn error_dim(&self) -> usize {
        self.layout.len()
    }

    /// `ẋ` of the module-level derivation. No allocation: every buffer is in the workspace.
    /// Compiled for the widest vector unit found at run time (pulp's dispatch, detected once
    /// in [`Eom::new`]): Rust never reassociates floating-point sums nor fuses `a * b + c`, so
    /// the vectorised loops give the same bits as the baseline code.
    fn rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), RhsError> {
        self.arch.dispatch(RhsOp {
            eom: self,
            t,
            x,
            dx,
        })
    }

    /// The stiff, nearly linear part of the equations for the exponential integrator: the
    /// modal coordinates and their rates `η, η̇` (the fin modes) *and* the body velocities
    /// `V_B, ω_B`, which the floating frame couples to them through the inertia (the modes
    /// are fixed at the origin, not mean axes, so the fast eigenvectors of the Jacobian have
    /// components in `V_B, ω_B`; measured on subsonic_t06 with 1.0 mm fins over 3 s: 4,613
    /// steps with `η, η̇` alone, 3,589 with `ω_B` added, 1,000 with `V_B, ω_B`, 1,153 with the
    /// attitude too; over 10 s with the attitude, or the position too, 44,564: the
    /// decomposition of the Jacobian with the Euler parameters' rows fails or is refused and
    /// the block falls back to explicit; with the three work quadratures appended to the
    /// block 2,900 instead of 2,827; these with refreshes every 200 steps). None without modes.
    fn linear_block(&self) -> Option<std::ops::Range<usize>> {
        (self.layout.n > 0).then_some(StateLayout::VELOCITY..self.layout.len())
    }

    /// Renormalises the Euler parameters (constraint 4.4.8) and scales their stored rate by
    /// the same factor (`q̇` is linear in `q`; nothing else depends on `|q|`).
    fn project(&mut self, x: &mut [f64], dx: &mut [f64]) {
        if let Some(s) = normalize_euler_parameters(&mut x[3..7]) {
            dx[3..7].iter_mut().for_each(|v| *v *= s);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_solves_a_small_spd_system() {
        let mut a = vec![4.0, 2.0, 0.4, 2.0, 5.0, 1.0, 0.4, 1.0, 3.0];
        let a0 = a.clone();
        let mut b = vec![1.0, -2.0, 0.5];
        let b0 = b.clone();
        cholesky_solve(&mut a, 3, &mut b).unwrap();
        for i in 0..3 {
            let r: f64 = (0..3).map(|k| a0[i * 3 + k] * b[k]).sum();
            assert!((r - b0[i]).abs() < 1e-14);
        }
        let mut bad = vec![1.0, 2.0, 2.0, 1.0];
        assert!(cholesky_solve(&mut bad, 2, &mut [1.0, 1.0]).is_err());
    }
}

#[cfg(test)]
mod schur_tests {
    use super::*;

    use crate::runtime::stimuli::NormalSource;

    /// A uniform deviate in `[-1, 1)` from the crate's SplitMix64.
    fn uniform(state: &mut NormalSource) -> f64 {
        (state.next_u64() >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    fn skew(a: &[f64; 3]) -> Mat3 {
        [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]]
    }

    fn mul(a: &Mat3, b: &Mat3) -> Mat3 {
        std::array::from_fn(|i| std::array::from_fn(|k| (0..3).map(|j| a[i][j] * b[j][k]).sum()))
    }

    /// The coefficients (3.2.2)-(3.2.14) of point masses `m_k` at `r_k` with random mode
    /// shapes `φ_m,k` (no FE model): `M_tot(η)` is then the mass matrix of the points at
    /// `r_k + Σ_m η_m φ_m,k`, symmetric positive definite for enough points.
    fn point_mass_model(n: usize, points: usize, seed: u64) -> ReducedModel {
        let mut s = NormalSource::new(seed);
        let mass: Vec<f64> = (0..points).map(|_| 1.5 + uniform(&mut s)).collect();
        let r: Vec<[f64; 3]> = (0..points)
            .map(|_| {
                [
                    3.0 * uniform(&mut s),
                    0.3 * uniform(&mut s),
                    0.3 * uniform(&mut s),
                ]
            })
            .collect();
        let phi: Vec<Vec<[f64; 3]>> = (0..n)
            .map(|_| {
                (0..points)
                    .map(|_| [0.0; 3].map(|_: f64| uniform(&mut s)))
                    .collect()
            })
            .collect();
        let mut md = ReducedModel {
            origin_node: 0,
            n_modes: n as u32,
            mass: mass.iter().sum(),
            first_moment: [0.0; 3],
            inertia: [[0.0; 3]; 3],
            modal_mass: vec![0.0; n * n],
            modal_stiffness: vec![0.0; n * n],
            modal_damping: vec![0.0; n * n],
            omega2: vec![0.0; n],
            damping_ratio: vec![0.0; n],
            p_bar: vec![0.0; 3 * n],
            h_bar: vec![0.0; 3 * n],
            j_ru: vec![[[0.0; 3]; 3]; n],
            j_uu: vec![[[0.0; 3]; 3]; n * n],
            h_prime: vec![0.0; 3 * n * n],
            rigid_mass_residual: 0.0,
        };
        for k in 0..points {
            let (mk, rk) = (mass[k], &r[k]);
            let rx = skew(rk);
            let rr = mul(&rx, &rx);
            for i in 0..3 {
                md.first_moment[i] += mk * rk[i];
                for j in 0..3 {
                    md.inertia[i][j] -= mk * rr[i][j];
                }
            }
            for m in 0..n {
                let fm = &phi[m][k];
                let rf = cross(rk, fm);
                let jr = mul(&rx, &skew(fm));
                for i in 0..3 {
                    md.p_bar[i * n + m] += mk * fm[i];
                    md.h_bar[i * n + m] += mk * rf[i];
                    for j in 0..3 {
                        md.j_ru[m][i][j] -= mk * jr[i][j];
                    }
                }
                for p in 0..n {
                    let fp = &phi[p][k];
                    md.modal_mass[m * n + p] += mk * (0..3).map(|i| fm[i] * fp[i]).sum::<f64>();
                    let ju = mul(&skew(fm), &skew(fp));
                    let fxf = cross(fm, fp);
                    for i in 0..3 {
                        md.h_prime[(m * 3 + i) * n + p] += mk * fxf[i];
                        for j in 0..3 {
                            md.j_uu[m * n + p][i][j] -= mk * ju[i][j];
                        }
                    }
                }
            }
        }
        md
    }

    /// The loops of [`Precomputed::rebuild_mass_terms`] before they were rewritten without
    /// the index arithmetic (issue 35): `a_lin`, `s_quad`, `h_prime_t`, `w_p` by index.
    fn rebuild_by_index(md: &ReducedModel) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
        let n = md.n();
        let (mut a_lin, mut s_quad, mut h_prime_t) =
            (vec![0.0; 9 * n], vec![0.0; 9 * n * n], vec![0.0; 3 * n * n]);
        for m in 0..n {
            for i in 0..3 {
                for k in 0..3 {
                    a_lin[m * 9 + 3 * i + k] = md.j_ru[m][i][k] + md.j_ru[m][k][i];
                }
            }
            for p in 0..n {
                let (a, b) = (&md.j_uu[m * n + p], &md.j_uu[p * n + m]);
                for i in 0..3 {
                    for k in 0..3 {
                        s_quad[p * 9 * n + m * 9 + 3 * i + k] = a[i][k] + b[i][k];
                    }
                }
            }
            for i in 0..3 {
                for p in 0..n {
                    h_prime_t[(i * n + p) * n + m] = md.h_prime[(m * 3 + i) * n + p];
                }
            }
        }
        let pre = Precomputed::new(md);
        let mut w_p = vec![0.0; 3 * n];
        for p in 0..n {
            for i in 0..3 {
                w_p[3 * p + i] = (0..=p)
                    .map(|q| pre.linv[p * n + q] * md.p_bar[i * n + q])
                    .sum();
            }
        }
        (a_lin, s_quad, h_prime_t, w_p)
    }

    fn same_bits(a: &[f64], b: &[f64], what: &str) {
        assert_eq!(a.len(), b.len(), "{what}");
        for (k, (x, y)) in a.iter().zip(b).enumerate() {
            assert_eq!(x.to_bits(), y.to_bits(), "{what}[{k}]: {x} {y}");
        }
    }

    /// The burn's per-evaluation work in its cheaper forms has the bits of the forms it
    /// replaced: the precomputed arrays of a model (rebuilt at every right-hand side of a
    /// burn) and the propellant's mass matrix `M_p(η)` refreshed in its `η`-dependent
    /// entries only, against [`assemble`] from zero, over a sequence of deflections.
    #[test]
    fn the_burns_cheaper_forms_have_the_bits_of_the_old_ones() {
        for (case, &n) in [1usize, 3, 8, 10, 16].iter().enumerate() {
            let md = point_mass_model(n, 4 * n + 6, 31 + case as u64);
            let pre = Precomputed::new(&md);
            let (a_lin, s_quad, h_prime_t, w_p) = rebuild_by_index(&md);
            same_bits(&pre.a_lin, &a_lin, "a_lin");
            same_bits(&pre.s_quad, &s_quad, "s_quad");
            same_bits(&pre.h_prime_t, &h_prime_t, "h_prime_t");
            same_bits(&pre.w_p, &w_p, "w_p");
            let d = 6 + n;
            let (mut h0, mut m0) = (vec![0.0; 3 * n], vec![0.0; d * d]);
            assemble(&md, &vec![0.0; n], &mut h0, &mut m0);
            let mut s = NormalSource::new(77 + case as u64);
            for _ in 0..10 {
                let eta: Vec<f64> = (0..n).map(|_| 0.2 * uniform(&mut s)).collect();
                let (mut h1, mut m1) = (vec![0.0; 3 * n], vec![0.0; d * d]);
                assemble(&md, &eta, &mut h1, &mut m1);
                refresh_eta_terms(&md, &eta, &mut h0, &mut m0);
                same_bits(&m0, &m1, "M_p");
                same_bits(&h0, &h1, "H_tot");
            }
        }
    }

    /// The block-Cholesky Schur solve ([`Precomputed`], "The solve") against the dense
    /// mass matrix of [`assemble`]: `M_tot(η) v̇ = r` to round-off for a few random models,
    /// deflections and right-hand sides.
    #[test]
    fn the_schur_solve_inverts_the_assembled_mass_matrix() {
        let mut worst: f64 = 0.0;
        for (case, &n) in [1usize, 3, 10, 16].iter().enumerate() {
            let md = point_mass_model(n, 4 * n + 6, 17 + case as u64);
            let pre = Precomputed::new(&md);
            assert!(pre.modal_error.is_none() && pre.rigid_error.is_none());
            let mut s = NormalSource::new(1000 + case as u64);
            for _ in 0..20 {
                let eta: Vec<f64> = (0..n).map(|_| 0.2 * uniform(&mut s)).collect();
                let b: Vec<f64> = (0..6 + n).map(|_| uniform(&mut s)).collect();
                let (mut g, mut h, mut hd) = (vec![0.0; 9 * n], vec![0.0; 3 * n], vec![0.0; 3 * n]);
                let inr = inertia(&pre, &md, &eta, &mut g);
                h_tot_and_rate(&md, &eta, &eta, &mut h, &mut hd);
                let (mut w_h, mut z, mut x) = (vec![0.0; 3 * n], vec![0.0; n], b.clone());
                schur_solve(&pre, &inr, &h, &mut w_h, &mut z, &mut x).unwrap();
                let d = 6 + n;
                let mut mm = vec![0.0; d * d];
                assemble(&md, &eta, &mut h, &mut mm);
                let norm_m = mm.iter().map(|v| v.abs()).fold(0.0, f64::max);
                let norm_x = x.iter().map(|v| v.abs()).fold(0.0, f64::max);
                for i in 0..d {
                    let ri: f64 = (0..d).map(|k| mm[i * d + k] * x[k]).sum::<f64>() - b[i];
                    worst = worst.max(ri.abs() / (norm_m * norm_x));
                }
            }
        }
        eprintln!("worst relative residual {worst:.2e}");
        assert!(worst < 2e-15, "relative residual {worst:.2e}");
    }
}
