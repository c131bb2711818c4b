//! Constant coefficients of the reduced-order floating-frame equations (3.2.1).
//!
//! From an FE model (nodal 6x6 blocks of the mass matrix, eq. 2.5.2-2.5.3) and a set of shape
//! vectors `S` (one column per flexible coordinate `η_m`, eq. 3.1.3) this module computes
//! everything that (3.2.1) needs, so the runtime never touches the FE model again:
//!
//! - rigid `m`, `c`, `J` (eqs. 2.5.4, 2.5.6, 2.2.12; nodal form 2.5.25);
//! - `M̄ = S^T M S`, `K̄ = S^T K S` (eqs. 3.2.2, 3.2.20), and the modal damping that gives
//!   the free vehicle's elastic modes the requested ratios;
//! - `P̄` and `H̄` (eqs. 3.2.3, 3.2.5 from 2.5.23-2.5.24);
//! - `J̄'_ru,m` (eq. 3.2.13 from 2.5.11/2.5.14), `J̄''_uu,mp` (eq. 3.2.14 from 2.5.12 /
//!   Tables 2.1-2.4), `H̄'_m` (eq. 3.2.7 from 2.5.26 / Tables 2.5-2.6).
//!
//! Every coefficient is one entry of a single discretised kinetic energy (see
//! [`moments`] for the discretisation and [`ReducedModel::mass_matrix_into`] for `M_tot(η)`),
//! which is what makes (3.2.1) conserve energy (REFERENCE-NOTES, "Energy is conserved only
//! if..."). The thesis keeps `J''_uu` (second order in `η`); so do we, and `M_tot(η)` is then
//! the exact quadratic in `η` implied by the linear deformation `u = Φ η` (3.1.2).
//!
//! The mode fixity adjustment of thesis 3.3 is [`fix_modes_at_origin`].

mod fixity;
pub(crate) mod moments;
mod reduce;
mod reduced;

pub use fixity::fix_modes_at_origin;
pub use reduce::{RIGID_MASS_TOLERANCE, reduce};

/// What went wrong while computing the reduced coefficients.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CoefficientError {
    #[error("origin node index {origin} is out of range: the model has {n_nodes} nodes")]
    OriginOutOfRange { origin: usize, n_nodes: usize },
    #[error("{what} matrix is {rows}x{cols}, expected {expected}x{expected} (6 DOF per node)")]
    MatrixSize {
        what: &'static str,
        expected: usize,
        rows: usize,
        cols: usize,
    },
    #[error("{what} has length {found}, expected {expected}")]
    LengthMismatch {
        what: &'static str,
        expected: usize,
        found: usize,
    },
    #[error("{what} at row {row}, column {col} is not finite")]
    NonFinite {
        what: &'static str,
        row: usize,
        col: usize,
    },
    #[error("{what} number {index} is {value}, expected a finite value >= 0")]
    Negative {
        what: &'static str,
        index: usize,
        value: f64,
    },
    #[error("the total mass from the mass matrix is {mass}, expected > 0")]
    NonPositiveMass { mass: f64 },
    #[error(
        "the mass matrix does not describe a rigid mass distribution: {what} has relative \
         residual {residual:.3e} (tolerance {tolerance:.1e})"
    )]
    NonRigidMass {
        what: &'static str,
        residual: f64,
        tolerance: f64,
    },
    #[error(
        "the free-vehicle generalised mass of the selected shapes is not positive definite \
         (shape {index}: {value:e}): a selected shape has no elastic motion"
    )]
    ElasticMassNotPositive { index: usize, value: f64 },
    #[error("flexible coordinate index {index} is out of range ({n_modes} modes)")]
    ModeOutOfRange { index: usize, n_modes: usize },
}

/// Constant coefficients of the reduced-order equations of motion (3.2.1).
///
/// Plain data (archivable with rkyv). `n = n_modes`. Row-major layouts:
/// - `p_bar`, `h_bar`: 3 x n, entry `(i, m)` at `i * n + m`;
/// - `j_ru[m]`: `J̄'_ru,m` (3x3, `[row][col]`);
/// - `j_uu[m * n + p]`: `J̄''_uu,mp` (3x3), with `J̄''_pm = J̄''_mp^T`;
/// - `h_prime`: `H̄'_m` (3 x n each), entry `(m, i, p)` at `(m * 3 + i) * n + p`;
/// - `modal_mass`, `modal_stiffness`, `modal_damping`: n x n, entry `(m, p)` at `m * n + p`.
#[derive(
    Clone, Debug, PartialEq, rkyv::Archive, rkyv::Serialize, rkyv::Deserialize, serde::Serialize,
)]
pub struct ReducedModel {
    /// Index of the FE node that carries the body frame (thesis 2.5.2, 3.3).
    pub origin_node: u32,
    /// Number of flexible coordinates `n`.
    pub n_modes: u32,
    /// Total mass `m`, eq. (2.5.4).
    pub mass: f64,
    /// Rigid first moment `c = ∫ r dm`, eq. (2.5.6) (nodal form 2.5.25).
    pub first_moment: [f64; 3],
    /// Rigid second moment `J = -∫ r^× r^× dm` about the body-frame origin, eq. (2.2.12)
    /// (nodal form 2.5.25).
    pub inertia: [[f64; 3]; 3],
    /// `M̄ = S^T M S`, eq. (3.2.2).
    pub modal_mass: Vec<f64>,
    /// `K̄ = S^T K S`, eq. (3.2.20).
    pub modal_stiffness: Vec<f64>,
    /// Modal viscous damping `C̄` (n x n, symmetric; 2.5.32 allows viscous damping), built
    /// so that each elastic mode of the free vehicle has the damping ratio `ζ` asked for
    /// (derivation at `reduce::free_vehicle_damping`); `diag(2 ζ_m ω_m M_f,mm)` with `M_f`
    /// the free mode's generalised mass when the shapes are free-free eigenvectors.
    pub modal_damping: Vec<f64>,
    /// Squared natural frequencies `ω_m^2` the shapes came with, rad^2/s^2.
    pub omega2: Vec<f64>,
    /// Damping ratios `ζ_m` of the free vehicle's elastic modes, as given.
    pub damping_ratio: Vec<f64>,
    /// `P̄ = P S` (3 x n), eq. (3.2.3): column m is `∫ φ_m dm`.
    pub p_bar: Vec<f64>,
    /// `H̄ = H S` (3 x n), eq. (3.2.5): column m is `∫ r × φ_m dm`.
    pub h_bar: Vec<f64>,
    /// `J̄'_ru,m = -∫ r^× φ_m^× dm`, eq. (3.2.13) / (2.5.11).
    pub j_ru: Vec<[[f64; 3]; 3]>,
    /// `J̄''_uu,mp = -∫ φ_m^× φ_p^× dm`, eq. (3.2.14) / (2.5.12).
    pub j_uu: Vec<[[f64; 3]; 3]>,
    /// `H̄'_m` (3 x n each): column p is `∫ φ_m × φ_p dm`, eq. (3.2.7) / (2.5.26).
    pub h_prime: Vec<f64>,
    /// Largest relative departure of the mass matrix from a rigid mass distribution
    /// (non-isotropic `Σ A`, non-skew first moments); see [`RIGID_MASS_TOLERANCE`].
    pub rigid_mass_residual: f64,
}
