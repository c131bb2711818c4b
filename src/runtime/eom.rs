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

// Index loops follow the block formulas above.
#![allow(clippy::needless_range_loop)]

use super::integrate::{OdeSystem, RhsError};
use super::kinematics::{
    Mat3, c_bi_normalized, cross, euler_parameter_rates, mat_t_vec, mat_vec,
    normalize_euler_parameters,
};
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
    /// `M_tot(η)`, then its Cholesky factor (row-major, `(6+n)²`).
    mass_matrix: Vec<f64>,
    /// Right-hand side, then `v̇`.
    rhs: Vec<f64>,
    /// External generalised forces `(F_B, G_B, Q)`.
    forces: Vec<f64>,
    /// `H̄_tot(η)` (3 x n).
    h_tot: Vec<f64>,
    /// `∂T/∂η`.
    dt_deta: Vec<f64>,
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
}

impl Invariants {
    /// `T + ½ ηᵀK̄η`.
    pub fn total_energy(&self) -> f64 {
        self.kinetic_energy + self.strain_energy
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
                mass_matrix: vec![0.0; d * d],
                rhs: vec![0.0; d],
                forces: vec![0.0; d],
                h_tot: vec![0.0; 3 * n],
                dt_deta: vec![0.0; n],
            },
        })
    }

    /// The state layout.
    pub fn layout(&self) -> StateLayout {
        self.layout
    }

    /// `c̄_tot`, `J̄_tot`, `H̄_tot` (into the workspace) and `M_tot(η)` (into the workspace),
    /// eqs. (3.2.8)-(3.2.12); the same matrix as [`ReducedModel::mass_matrix_into`] without
    /// its allocation.
    fn assemble(&mut self, eta: &[f64]) -> Inertia {
        let md = self.model;
        let n = self.layout.n;
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
        let h = &mut self.ws.h_tot;
        // Lengths were checked in `Eom::new`; a failure here poisons the state with NaN so
        // the integrator stops with "non-finite state" instead of going on silently.
        if md.h_tot_into(eta, h).is_err() {
            h.fill(f64::NAN);
        }
        md.assemble_mass_matrix(c, &j, h, &mut self.ws.mass_matrix);
        Inertia { c_tot: c, j_tot: j }
    }

    /// Momenta `p_V = m V + ω × c̄_tot + P̄ η̇`, `p_ω = c̄_tot × V + J̄_tot ω + H̄_tot η̇`
    /// (rows of `M_tot v`); needs [`Self::assemble`] first.
    fn momenta(&self, inr: &Inertia, v: &[f64; 3], w: &[f64; 3], eta_dot: &[f64]) -> [[f64; 3]; 2] {
        let md = self.model;
        let n = self.layout.n;
        let wc = cross(w, &inr.c_tot);
        let cv = cross(&inr.c_tot, v);
        let jw = mat_vec(&inr.j_tot, w);
        let mut pv = [0.0; 3];
        let mut pw = [0.0; 3];
        for i in 0..3 {
            let (mut a, mut b) = (0.0, 0.0);
            for p in 0..n {
                a += md.p_bar[i * n + p] * eta_dot[p];
                b += self.ws.h_tot[i * n + p] * eta_dot[p];
            }
            pv[i] = md.mass * v[i] + wc[i] + a;
            pw[i] = cv[i] + jw[i] + b;
        }
        [pv, pw]
    }

    /// Energy and momentum of the state `x` (thesis 4.5.3); no allocation.
    pub fn invariants(&mut self, x: &[f64]) -> Result<Invariants, EomError> {
        let l = self.layout;
        if x.len() != l.len() {
            return Err(EomError::StateLength {
                expected: l.len(),
                found: x.len(),
            });
        }
        let n = l.n;
        let eta = &x[13..13 + n];
        let eta_dot = &x[13 + n..13 + 2 * n];
        let v = [x[7], x[8], x[9]];
        let w = [x[10], x[11], x[12]];
        let inr = self.assemble(eta);
        let [pv, pw] = self.momenta(&inr, &v, &w, eta_dot);
        let md = self.model;
        let mut pe = 0.0;
        let mut strain = 0.0;
        for m in 0..n {
            let mut row = 0.0;
            let mut k = 0.0;
            for i in 0..3 {
                row += md.p_bar[i * n + m] * v[i] + self.ws.h_tot[i * n + m] * w[i];
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
        })
    }
}

/// In-place Cholesky factorisation `A = L Lᵀ` of a row-major SPD matrix (lower triangle
/// overwritten by `L`) and solve of `A y = b` into `b`.
fn cholesky_solve(a: &mut [f64], d: usize, b: &mut [f64]) -> Result<(), RhsError> {
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
    Ok(())
}

impl<F: ForceModel> OdeSystem for Eom<'_, F> {
    fn dim(&self) -> usize {
        self.layout.len()
    }

    /// `ẋ` of the module-level derivation. No allocation: every buffer is in the workspace.
    fn rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), RhsError> {
        let l = self.layout;
        let n = l.n;
        let d = 6 + n;
        let view = StateView::new(l, x);
        self.ws.forces.iter_mut().for_each(|f| *f = 0.0);
        self.forces
            .generalized_forces(t, &view, &mut self.ws.forces);
        let (v, w) = (view.velocity, view.angular_velocity);
        let (eta, eta_dot) = (view.eta, view.eta_dot);
        let inr = self.assemble(eta);
        let [pv, pw] = self.momenta(&inr, &v, &w, eta_dot);
        let md = self.model;

        // ċ = P̄ η̇, J̄̇_tot ω, H̄̇_tot η̇.
        let mut c_dot = [0.0; 3];
        let mut hdot_etadot = [0.0; 3];
        let mut jdot: Mat3 = [[0.0; 3]; 3];
        for m in 0..n {
            let ed = eta_dot[m];
            for i in 0..3 {
                c_dot[i] += md.p_bar[i * n + m] * ed;
                for p in 0..n {
                    hdot_etadot[i] += ed * md.h_prime[(m * 3 + i) * n + p] * eta_dot[p];
                }
                for k in 0..3 {
                    jdot[i][k] += ed * (md.j_ru[m][i][k] + md.j_ru[m][k][i]);
                }
            }
            for p in 0..n {
                // ∂/∂η_m of Σ η_a η_b J''_ab = Σ_p η_p (J''_mp + J''_pm).
                let wgt = ed * eta[p];
                let (a, b) = (&md.j_uu[m * n + p], &md.j_uu[p * n + m]);
                for i in 0..3 {
                    for k in 0..3 {
                        jdot[i][k] += wgt * (a[i][k] + b[i][k]);
                    }
                }
            }
        }
        let jdot_w = mat_vec(&jdot, &w);
        let vxw = cross(&v, &w);
        // ∂T/∂η_m = P̄_m·(V×ω) + ½ ωᵀ(∂J̄_tot/∂η_m)ω + ωᵀ H̄'_m η̇, and (H̄̇_totᵀ ω)_m.
        for m in 0..n {
            let mut s = 0.0;
            for i in 0..3 {
                s += md.p_bar[i * n + m] * vxw[i];
            }
            let mut jd: Mat3 = [[0.0; 3]; 3];
            for i in 0..3 {
                for k in 0..3 {
                    jd[i][k] = md.j_ru[m][i][k] + md.j_ru[m][k][i];
                }
            }
            for p in 0..n {
                let (a, b) = (&md.j_uu[m * n + p], &md.j_uu[p * n + m]);
                for i in 0..3 {
                    for k in 0..3 {
                        jd[i][k] += eta[p] * (a[i][k] + b[i][k]);
                    }
                }
            }
            let jdw = mat_vec(&jd, &w);
            s += 0.5 * (0..3).map(|i| w[i] * jdw[i]).sum::<f64>();
            let mut hdot_t_w = 0.0;
            for i in 0..3 {
                for p in 0..n {
                    s += w[i] * md.h_prime[(m * 3 + i) * n + p] * eta_dot[p];
                    hdot_t_w += eta_dot[p] * md.h_prime[(p * 3 + i) * n + m] * w[i];
                }
            }
            self.ws.dt_deta[m] = s - hdot_t_w;
        }

        let wxc = cross(&w, &c_dot);
        let wxpv = cross(&w, &pv);
        let cdxv = cross(&c_dot, &v);
        let vxpv = cross(&v, &pv);
        let wxpw = cross(&w, &pw);
        let r = &mut self.ws.rhs;
        let f = &self.ws.forces;
        for i in 0..3 {
            r[i] = f[i] - wxc[i] - wxpv[i];
            r[3 + i] = f[3 + i] - cdxv[i] - jdot_w[i] - hdot_etadot[i] - vxpv[i] - wxpw[i];
        }
        for m in 0..n {
            let mut s = f[6 + m] + self.ws.dt_deta[m];
            for p in 0..n {
                s -= md.modal_stiffness[m * n + p] * eta[p]
                    + md.modal_damping[m * n + p] * eta_dot[p];
            }
            r[6 + m] = s;
        }
        cholesky_solve(&mut self.ws.mass_matrix, d, r)?;

        let c_ib_v = mat_t_vec(&view.c_bi, &v);
        let qd = euler_parameter_rates(&view.attitude, &w);
        dx[0..3].copy_from_slice(&c_ib_v);
        dx[3..7].copy_from_slice(&qd);
        dx[7..13].copy_from_slice(&r[0..6]);
        dx[13..13 + n].copy_from_slice(eta_dot);
        dx[13 + n..13 + 2 * n].copy_from_slice(&r[6..d]);
        if let Some(index) = dx.iter().position(|v| !v.is_finite()) {
            return Err(RhsError::NonFinite { index });
        }
        Ok(())
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
