//! Planar eigen-stability models of thesis chapter 6: the PINNED model (6.1, eqs.
//! (6.1)-(6.13)) and the UNPINNED model (6.2, eqs. (6.14)-(6.29)).
//!
//! - [`vehicle`]: mass properties, fin geometry, stiffness and the aerodynamic coefficients
//!   at a flight condition, from the compiled vehicle and the runtime's coefficient tables;
//! - [`matrices`]: the mass, damping and stiffness matrices (derived in its module doc where
//!   the OCR of (6.1), (6.8), (6.9), (6.28), (6.29) is unreadable) and the state matrix
//!   (6.12)-(6.13);
//! - this module: the parameters of one analysis, the eigenvalues (faer's real
//!   non-symmetric eigen solver), sigma_d = max Re(lambda), omega_d, the classification, and
//!   the unpinned equilibrium (6.2): the altitude at which the axial drag balances the weight.

pub mod matrices;
pub mod vehicle;

#[cfg(test)]
mod tests;

use faer::Mat;
use serde::Serialize;

pub use matrices::{SecondOrderSystem, pinned_system, state_matrix, unpinned_system};
pub use vehicle::{
    AeroDerivatives, FinGeometry, FlightCondition, PitchMassProperties, PlanarVehicle,
};

use crate::aero::atmosphere::{STANDARD_MAX_ALTITUDE, STANDARD_MIN_ALTITUDE};

/// Which planar model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PlanarKind {
    /// Pinned at the mass centre in a wind tunnel, free to pitch (6.1): x = (theta, delta).
    Pinned,
    /// Free flight straight down at terminal velocity (6.2): x = (x, y, theta, delta); the
    /// cyclic positions x, y are dropped from the state (see [`matrices`]).
    Unpinned,
}

impl PlanarKind {
    /// `pinned` or `unpinned`.
    pub fn name(self) -> &'static str {
        match self {
            PlanarKind::Pinned => "pinned",
            PlanarKind::Unpinned => "unpinned",
        }
    }
}

/// Why a planar analysis could not be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlanarError {
    #[error("vehicle `{vehicle}` has no fins: the planar models need a `fins` block")]
    NoFins { vehicle: String },
    #[error("fin thickness {thickness} m gives a non-physical vehicle (mass or inertia <= 0)")]
    BadThickness { thickness: f64 },
    #[error("aerodynamic coefficients: {0}")]
    Aero(String),
    #[error("coefficient table queried outside its `{axis}` axis: {value} not in [{min}, {max}]")]
    TableRange {
        axis: String,
        value: f64,
        min: f64,
        max: f64,
    },
    #[error("atmosphere: {0}")]
    Atmosphere(String),
    #[error("airspeed must be finite and positive, got {speed} m/s")]
    BadSpeed { speed: f64 },
    #[error(
        "no terminal-velocity equilibrium (Mach {mach:.4} at the lowest altitude) in the atmosphere's range ({min_m} m to {max_m} m): axial drag is {drag_low:.4e} N at the lowest altitude and {drag_high:.4e} N at the highest, weight {weight:.4e} N"
    )]
    NoEquilibrium {
        mach: f64,
        weight: f64,
        drag_low: f64,
        drag_high: f64,
        min_m: f64,
        max_m: f64,
    },
    #[error(
        "the mass matrix is not positive definite (J = {inertia} kg m^2, m_f d^2 = {fin_term} kg m^2)"
    )]
    MassMatrix { inertia: f64, fin_term: f64 },
    #[error("the eigen solver failed on the state matrix")]
    Eigen,
}

/// Every scalar one planar analysis used (printed by `flexflight analyze planar`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlanarParameters {
    pub kind: PlanarKind,
    /// Fin thickness t, m.
    pub thickness: f64,
    pub condition: FlightCondition,
    pub mass_properties: PitchMassProperties,
    pub aero: AeroDerivatives,
    /// Fins acting in the pitch plane, `n_eff = sum cos^2 delta_i`.
    pub pitch_plane_fins: f64,
    /// Flapping fin mass m_f = n_eff rho A_f t, kg.
    pub fin_mass: f64,
    /// Fin stiffness k = n_eff 24 E I / L^3, N/m (6.10).
    pub fin_stiffness: f64,
    /// Bending inertia I = c t^3/12 of one fin, m^4 (6.11).
    pub fin_bending_inertia: f64,
    /// Body x of the body and fin centres of pressure, m.
    pub x_cp_body: Option<f64>,
    pub x_cp_fin: f64,
    /// a: distance from the mass centre FORWARD to the body centre of pressure, m (None when
    /// the body normal-force slope is zero: the body load is then a pure couple).
    pub a: Option<f64>,
    /// d: distance from the mass centre AFT to the fin centre of pressure, m.
    pub d: f64,
    /// S and S_f (one fin's planform area), m^2; b, m.
    pub reference_area: f64,
    pub fin_area: f64,
    pub reference_length: f64,
    /// `P_b = q S C_Nalpha,B` and `P_f = q S n_eff C_Nalpha,1`, N/rad.
    pub body_lift: f64,
    pub fin_lift: f64,
    /// Body pitching moment about the mass centre per radian, `q S b C_Malpha,cg`, N m/rad.
    pub body_moment: f64,
    /// Axial force of the flapping fins A_f0 = q S n_eff C_A,1, N.
    pub fin_axial_force: f64,
    /// Total axial force (body + all fins) A_0, N.
    pub axial_force: f64,
    /// Weight W = m g, N.
    pub weight: f64,
    /// Axial-force damping `q S / V (2 C_A + Mach dC_A/dMach)` (body + all fins), N s/m
    /// (eqs. (6.21)-(6.23)).
    pub axial_damping: f64,
    /// Rate derivatives used: the body table's `cn_q` = C_Nq + C_Nalpha-dot and `cm_q` =
    /// C_mq + C_malpha-dot (about the reference point, per rad of theta' b/(2V)), zero
    /// without `rate_terms`; the same numbers the runtime's body block applies.
    pub cn_alpha_dot: f64,
    pub cm_alpha_dot: f64,
    /// Body x of the coefficient reference point (where the rate normal force acts), m.
    pub reference_x: f64,
}

/// What kind of motion the least stable root is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stability {
    /// Every root has Re < 0.
    Stable,
    /// The least stable root has Re = 0 (to round-off): marginal.
    Neutral,
    /// An oscillatory root with Re > 0 (thesis: "flutter").
    Flutter,
    /// A real root with Re > 0 (thesis: "divergence").
    Divergence,
}

impl Stability {
    /// Snake-case name used in CSV and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Stability::Stable => "stable",
            Stability::Neutral => "neutral",
            Stability::Flutter => "flutter",
            Stability::Divergence => "divergence",
        }
    }
}

/// A complex eigenvalue.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Eigenvalue {
    pub re: f64,
    pub im: f64,
}

/// sigma_d, omega_d and the class of a set of eigenvalues.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StabilityVerdict {
    /// sigma_d = max Re(lambda), 1/s.
    pub sigma_d: f64,
    /// |Im| of the root with the largest real part, rad/s.
    pub omega_d: f64,
    pub class: Stability,
}

/// One complete planar analysis.
#[derive(Clone, Debug, Serialize)]
pub struct PlanarAnalysis {
    pub parameters: PlanarParameters,
    /// Names of the second-order coordinates and of the state.
    pub coordinates: Vec<&'static str>,
    pub state: Vec<&'static str>,
    pub mass: Vec<Vec<f64>>,
    pub damping: Vec<Vec<f64>>,
    pub stiffness: Vec<Vec<f64>>,
    pub state_matrix: Vec<Vec<f64>>,
    pub eigenvalues: Vec<Eigenvalue>,
    pub verdict: StabilityVerdict,
}

/// Relative size below which a real part counts as zero and an imaginary part as absent.
const ROUND_OFF: f64 = 1e-9;

/// sigma_d, omega_d and the classification of `eigenvalues`; the root with the largest real
/// part decides (thesis 6.1.1: flutter = oscillating unstable growth, divergence =
/// non-oscillating). A conjugate pair counts as oscillatory when |Im| exceeds round-off.
pub fn classify(eigenvalues: &[Eigenvalue]) -> StabilityVerdict {
    let scale = eigenvalues
        .iter()
        .map(|e| e.re.hypot(e.im))
        .fold(1.0, f64::max);
    let mut best = Eigenvalue {
        re: f64::NEG_INFINITY,
        im: 0.0,
    };
    for e in eigenvalues {
        // Ties on Re: prefer the oscillatory root (it decides the class of a pair).
        if e.re > best.re || (e.re == best.re && e.im.abs() > best.im.abs()) {
            best = *e;
        }
    }
    let tol = ROUND_OFF * scale;
    let class = if best.re < -tol {
        Stability::Stable
    } else if best.re <= tol {
        Stability::Neutral
    } else if best.im.abs() > tol {
        Stability::Flutter
    } else {
        Stability::Divergence
    };
    StabilityVerdict {
        sigma_d: best.re,
        omega_d: best.im.abs(),
        class,
    }
}

/// Eigenvalues of a real (non-symmetric) matrix with faer's general eigen solver.
pub fn eigenvalues(a: &Mat<f64>) -> Result<Vec<Eigenvalue>, PlanarError> {
    let ev = a.eigenvalues().map_err(|_| PlanarError::Eigen)?;
    let out: Vec<Eigenvalue> = ev
        .iter()
        .map(|z| Eigenvalue { re: z.re, im: z.im })
        .collect();
    if out.iter().any(|e| !(e.re.is_finite() && e.im.is_finite())) {
        return Err(PlanarError::Eigen);
    }
    Ok(out)
}

/// Where the analysis is made: an explicit condition, or (unpinned model, Fig 6.8) the
/// terminal-velocity equilibrium altitude at a Mach number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Altitude {
    /// Geometric altitude, m.
    Fixed(f64),
    /// The altitude at which the axial drag equals the weight at the given Mach (6.2).
    Equilibrium,
}

/// The speed an equilibrium is sought at.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Speed {
    /// A Mach number (the map axis): the airspeed follows the speed of sound at each altitude.
    Mach(f64),
    /// An airspeed, m/s (a scenario's initial speed).
    Airspeed(f64),
}

/// The geometric altitude at which the zero-incidence axial drag at `speed` equals the
/// weight `m g(h)` (the equilibrium of 6.2: sum A_0 = W), by bisection over the 1976
/// atmosphere's range. The drag `q S C_A` falls monotonically with altitude at a fixed Mach
/// (`q = gamma p Mach^2 / 2` and p falls) and at a fixed airspeed (rho falls; C_A changes
/// only through the Reynolds number and, at a fixed airspeed, the Mach number), so a sign
/// change of drag - weight between the range ends brackets the root.
pub fn equilibrium_altitude(
    vehicle: &PlanarVehicle,
    mass: f64,
    speed: Speed,
) -> Result<f64, PlanarError> {
    let (Speed::Mach(x) | Speed::Airspeed(x)) = speed;
    if !(x.is_finite() && x > 0.0) {
        return Err(PlanarError::BadSpeed { speed: x });
    }
    let at = |h: f64| match speed {
        Speed::Mach(m) => vehicle.condition_at_mach(h, m),
        Speed::Airspeed(v) => vehicle.condition_at_speed(h, v),
    };
    let excess = |h: f64| -> Result<(f64, f64, f64), PlanarError> {
        let c = at(h)?;
        let drag = vehicle.axial_force(&c)?;
        Ok((drag - mass * c.gravity, drag, c.mach))
    };
    // The atmosphere's range, narrowed to the coefficient tables' altitudes when they stop
    // outside them.
    let (mut lo, mut hi) = vehicle.altitude_range(STANDARD_MIN_ALTITUDE, STANDARD_MAX_ALTITUDE);
    let (f_lo, drag_low, mach) = excess(lo)?;
    let (f_hi, drag_high, _) = excess(hi)?;
    if f_lo < 0.0 || f_hi > 0.0 {
        return Err(PlanarError::NoEquilibrium {
            mach,
            weight: mass * at(lo)?.gravity,
            drag_low,
            drag_high,
            min_m: lo,
            max_m: hi,
        });
    }
    // 40 halvings of at most 86.5 km: below 0.1 mm.
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if excess(mid)?.0 > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// Parameters of a planar analysis of `vehicle` with fins of thickness `thickness` at the
/// flight condition `condition`.
pub fn parameters(
    vehicle: &PlanarVehicle,
    kind: PlanarKind,
    thickness: f64,
    condition: FlightCondition,
) -> Result<PlanarParameters, PlanarError> {
    if !(condition.speed.is_finite() && condition.speed > 0.0) {
        return Err(PlanarError::BadSpeed {
            speed: condition.speed,
        });
    }
    let mp = vehicle.mass_properties(thickness)?;
    let aero = vehicle.aero(&condition)?;
    let f = &vehicle.fins;
    let n_eff = f.pitch_plane_fins;
    let q = condition.dynamic_pressure;
    let s = vehicle.reference_area;
    let b = vehicle.reference_length;
    let v = condition.speed;
    let x_cp_fin = f.root_leading_edge_x - aero.x_cp_fin;
    // Moment slope about the mass centre: C_M,cg = C_M,ref + C_N (x_ref - x_cg)/b (a normal
    // force ahead of the mass centre pitches the nose up, as the estimator's (5.3.3) sign).
    let cm_cg = aero.cm_alpha_body + aero.cn_alpha_body * (vehicle.reference_x - mp.x_cg) / b;
    let (a, x_cp_body) = if aero.cn_alpha_body.abs() > 1e-12 {
        let a = b * cm_cg / aero.cn_alpha_body;
        (Some(a), Some(mp.x_cg + a))
    } else {
        (None, None)
    };
    let fin_i = f.mean_chord * thickness.powi(3) / 12.0;
    let mach = condition.mach;
    let ca_total = aero.ca_body + f.count as f64 * aero.ca_fin;
    let ca_mach_total = aero.ca_mach_body + f.count as f64 * aero.ca_mach_fin;
    let (cn_q, cm_q) = vehicle.rate_derivatives(&condition)?;
    Ok(PlanarParameters {
        kind,
        thickness,
        condition,
        mass_properties: mp,
        aero,
        pitch_plane_fins: n_eff,
        fin_mass: n_eff * f.mass_one(thickness),
        fin_stiffness: n_eff * f.stiffness_one(thickness),
        fin_bending_inertia: fin_i,
        x_cp_body,
        x_cp_fin,
        a,
        d: mp.x_cg - x_cp_fin,
        reference_area: s,
        fin_area: f.area,
        reference_length: b,
        body_lift: q * s * aero.cn_alpha_body,
        fin_lift: q * s * n_eff * aero.cn_alpha_fin,
        body_moment: q * s * b * cm_cg,
        fin_axial_force: q * s * n_eff * aero.ca_fin,
        axial_force: q * s * ca_total,
        weight: mp.mass * condition.gravity,
        axial_damping: q * s / v * (2.0 * ca_total + mach * ca_mach_total),
        cn_alpha_dot: cn_q,
        cm_alpha_dot: cm_q,
        reference_x: vehicle.reference_x,
    })
}

/// The complete analysis from parameters: M, C, K, A, eigenvalues, verdict.
pub fn analyse(p: PlanarParameters) -> Result<PlanarAnalysis, PlanarError> {
    let sys = match p.kind {
        PlanarKind::Pinned => pinned_system(&p),
        PlanarKind::Unpinned => unpinned_system(&p),
    };
    let a = state_matrix(&sys, &p)?;
    let ev = eigenvalues(&a)?;
    let verdict = classify(&ev);
    let rows = |m: &Mat<f64>| -> Vec<Vec<f64>> {
        (0..m.nrows())
            .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
            .collect()
    };
    Ok(PlanarAnalysis {
        coordinates: sys.coordinates.clone(),
        state: sys.state.clone(),
        mass: rows(&sys.mass),
        damping: rows(&sys.damping),
        stiffness: rows(&sys.stiffness),
        state_matrix: rows(&a),
        eigenvalues: ev,
        verdict,
        parameters: p,
    })
}

/// sigma_d, omega_d and class only (the map's inner loop: no copies of the matrices).
pub fn verdict(p: &PlanarParameters) -> Result<StabilityVerdict, PlanarError> {
    let sys = match p.kind {
        PlanarKind::Pinned => pinned_system(p),
        PlanarKind::Unpinned => unpinned_system(p),
    };
    let a = state_matrix(&sys, p)?;
    Ok(classify(&eigenvalues(&a)?))
}

/// The flight condition of an analysis at Mach `mach`: at a fixed altitude, or at the
/// equilibrium altitude for the vehicle with fins of thickness `thickness`.
pub fn condition_at(
    vehicle: &PlanarVehicle,
    thickness: f64,
    mach: f64,
    altitude: Altitude,
) -> Result<FlightCondition, PlanarError> {
    let h = match altitude {
        Altitude::Fixed(h) => h,
        Altitude::Equilibrium => {
            let mp = vehicle.mass_properties(thickness)?;
            equilibrium_altitude(vehicle, mp.mass, Speed::Mach(mach))?
        }
    };
    vehicle.condition_at_mach(h, mach)
}
