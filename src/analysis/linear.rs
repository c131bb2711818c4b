//! The linearised 3-D analysis of a planned scenario and its fin thickness x Mach map.
//!
//! The force blocks are those of the scenario's plan, built as a run builds them
//! ([`build_force_blocks`], the aerodynamic blocks copied from the plan), except that the reference is ballistic:
//! thrust blocks are dropped and the stimuli (gusts, turbulence) removed, so the
//! right-hand side does not depend on time. The reference altitude and attitude are the
//! scenario's initial ones; the speed is the scenario's initial speed or, in a map,
//! `Mach · a(h)` with `a` from the 1976 standard atmosphere (4.5.1).
//!
//! A map needs one compiled vehicle per fin thickness (the thickness changes the FE model,
//! so the modes and every reduced coefficient): the caller supplies them through a closure
//! (the CLI compiles through the artifact cache with a `--set fins.thickness=...`
//! override); its plan holds the aerodynamic blocks, and the equations of motion are
//! built once per thickness and reused for every Mach.

use serde::Serialize;

use super::linear_grid::{StabilityClass, StabilityMap};
use super::linearise::{LinearModel, LineariseError, LineariseOptions, Linearizer, Trim};
use super::roots::{EigenStructure, FlightPathScale, eigen_structure_separated};
use crate::aero::atmosphere::{Atmosphere, Standard1976};
use crate::check::ir::Scenario;
use crate::plan::{ForcePlan, Plan};
use crate::run::{RunError, build_force_blocks};
use crate::runtime::eom::Eom;
use crate::runtime::forces::ForceBlocks;
use crate::runtime::forces::gravity::gravity_at;
use crate::runtime::kinematics::{c_bi, mat_vec};
use crate::runtime::stimuli::Stimuli;
use crate::structure::compile::CompiledVehicle;

/// Why a linear analysis could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinearAnalysisError {
    /// The force blocks or the equations of motion could not be built.
    #[error("cannot build the equations of motion: {0}")]
    Build(String),
    /// The speed of sound at the reference altitude is unavailable.
    #[error("atmosphere at {altitude} m: {message}")]
    Atmosphere { altitude: f64, message: String },
    /// The trim, the Jacobian or the eigen-decomposition failed.
    #[error("{0}")]
    Linearise(#[from] LineariseError),
    /// A map variant could not be loaded or compiled.
    #[error("fin thickness {thickness} m: {message}")]
    Variant { thickness: f64, message: String },
    /// A map cell failed.
    #[error("fin thickness {thickness} m, Mach {mach}: {error}")]
    Cell {
        thickness: f64,
        mach: f64,
        error: Box<LinearAnalysisError>,
    },
}

impl From<RunError> for LinearAnalysisError {
    fn from(e: RunError) -> Self {
        LinearAnalysisError::Build(e.to_string())
    }
}

/// One structural variant of a scenario: its plan, the checked scenario and the compiled
/// vehicle.
#[derive(Debug, Clone)]
pub struct Variant {
    pub plan: Plan,
    pub scenario: Scenario,
    pub compiled: CompiledVehicle,
}

/// The flight condition of a linearisation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FlightCondition {
    /// Airspeed, m/s (`V_B = (speed, 0, 0)`, `α = β = 0`).
    pub speed: f64,
    /// Altitude, m.
    pub altitude: f64,
    /// `speed / a(h)`.
    pub mach: f64,
    /// Dynamic pressure `½ ρ V²`, Pa.
    pub dynamic_pressure: f64,
    /// Euler parameters `(ε, η)` of the reference attitude.
    pub attitude: [f64; 4],
}

/// Everything a linear analysis found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinearAnalysis {
    pub condition: FlightCondition,
    pub trim: Trim,
    /// `false` when the static elastic balance was not found: the model was then
    /// linearised about `η = 0` (see the roots for a static divergence).
    pub trim_converged: bool,
    /// The trim failure, if any.
    pub trim_message: Option<String>,
    pub model: LinearModel,
    pub eigen: EigenStructure,
}

/// The plan of a ballistic reference: thrust blocks dropped, stimuli removed.
pub fn ballistic_plan(plan: &Plan) -> Plan {
    let mut p = plan.clone();
    p.forces.retain(|f| !matches!(f, ForcePlan::Thrust(_)));
    p.stimuli.clear();
    p.set_stimuli(Stimuli::default());
    p
}

/// The equations of motion with the ballistic force blocks of `variant`.
pub fn ballistic_eom(variant: &Variant) -> Result<Eom<'_, ForceBlocks>, LinearAnalysisError> {
    let plan = ballistic_plan(&variant.plan);
    let forces = build_force_blocks(&plan, &variant.compiled.reduced)?;
    Eom::new(&variant.compiled.reduced, forces)
        .map_err(|e| LinearAnalysisError::Build(e.to_string()))
}

/// The linearizer of `variant` (ballistic force blocks, modal scales from its shapes).
pub fn linearizer(
    variant: &Variant,
    options: LineariseOptions,
) -> Result<Linearizer<Eom<'_, ForceBlocks>>, LinearAnalysisError> {
    let eom = ballistic_eom(variant)?;
    Ok(Linearizer::new(
        eom,
        &variant.plan.node_translation_shapes,
        &variant.compiled.reduced.omega2,
        &variant.plan.mode_names,
        options,
    ))
}

/// Reference altitude (m) and attitude of the scenario's initial state.
fn reference_of(plan: &Plan) -> (f64, [f64; 4], f64) {
    let x = &plan.initial_state;
    let speed = x
        .get(7..10)
        .map_or(0.0, |v| v.iter().map(|c| c * c).sum::<f64>().sqrt());
    match (x.get(2), x.get(3..7)) {
        (Some(z), Some(q)) => (-z, [q[0], q[1], q[2], q[3]], speed),
        _ => (0.0, [0.0, 0.0, 0.0, 1.0], speed),
    }
}

/// Air at `altitude`: (speed of sound, density).
fn air(altitude: f64) -> Result<(f64, f64), LinearAnalysisError> {
    Standard1976::new()
        .at(altitude)
        .map(|a| (a.speed_of_sound, a.density))
        .map_err(|e| LinearAnalysisError::Atmosphere {
            altitude,
            message: e.to_string(),
        })
}

/// Gravity at `altitude` as the plan's gravity block applies it (0 without one), m/s².
pub fn plan_gravity(plan: &Plan, altitude: f64) -> f64 {
    plan.gravity()
        .map_or(0.0, |g| gravity_at(altitude, g.altitude_correction))
}

/// The flight-path scale of a trim (see [`super::roots`]): `a_D = |V̇_B - g_B|` with
/// `g_B = C_BI(q0) (0, 0, g)` (eq. 5.1.3; `ω_B = 0` at the trim, so `V̇_B` is the specific
/// force plus gravity).
pub fn flight_path_scale(
    trim: &Trim,
    speed: f64,
    gravity: f64,
    attitude: [f64; 4],
) -> FlightPathScale {
    let g_b = mat_vec(&c_bi(&attitude), &[0.0, 0.0, gravity]);
    let a = &trim.rigid_acceleration;
    let aero = ((a[0] - g_b[0]).powi(2) + (a[1] - g_b[1]).powi(2) + (a[2] - g_b[2]).powi(2)).sqrt();
    FlightPathScale {
        speed,
        gravity,
        aero_acceleration: aero,
    }
}

/// Trim, linearise and decompose at `speed` with an existing linearizer; `gravity` (m/s²)
/// sets the flight-path scale that separates the trajectory's slow roots from the
/// vehicle's ([`super::roots`]).
pub fn analyse_with<S: crate::runtime::integrate::OdeSystem>(
    lin: &mut Linearizer<S>,
    speed: f64,
    altitude: f64,
    attitude: [f64; 4],
    gravity: f64,
    options: LineariseOptions,
) -> Result<LinearAnalysis, LinearAnalysisError> {
    let (a, rho) = air(altitude)?;
    let condition = FlightCondition {
        speed,
        altitude,
        mach: speed / a,
        dynamic_pressure: 0.5 * rho * speed * speed,
        attitude,
    };
    let (trim, converged, message) = match lin.trim(speed, altitude, attitude) {
        Ok(t) => (t, true, None),
        Err(e @ LineariseError::TrimNotConverged { .. })
        | Err(e @ LineariseError::Singular { .. }) => {
            let t = lin.trim_at_zero(speed, altitude, attitude)?;
            (t, false, Some(e.to_string()))
        }
        Err(e) => return Err(e.into()),
    };
    let model = lin.linearise(&trim.state)?;
    let scale = flight_path_scale(&trim, speed, gravity, attitude);
    let eigen = eigen_structure_separated(&model, options.neutral_tolerance, scale)?;
    Ok(LinearAnalysis {
        condition,
        trim,
        trim_converged: converged,
        trim_message: message,
        model,
        eigen,
    })
}

/// The linear analysis of a scenario at its initial speed, altitude and attitude.
pub fn analyse(
    variant: &Variant,
    options: LineariseOptions,
) -> Result<LinearAnalysis, LinearAnalysisError> {
    let (altitude, attitude, speed) = reference_of(&variant.plan);
    let gravity = plan_gravity(&variant.plan, altitude);
    let mut lin = linearizer(variant, options)?;
    analyse_with(&mut lin, speed, altitude, attitude, gravity, options)
}

/// A fin thickness x Mach map of the linearised model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinearMap {
    /// `xs` fin thickness (m), `ys` Mach.
    pub map: StabilityMap,
    /// Cells (same index as the map) whose trim did not converge (linearised about `η = 0`).
    pub trim_failures: Vec<usize>,
    /// Reference altitude, m.
    pub altitude: f64,
}

/// Sweeps `thicknesses` (m) x `machs`: `load(t)` gives the variant with fin thickness `t`;
/// each Mach is flown at `Mach · a(h)` at the scenario's altitude and attitude.
pub fn linear_map(
    thicknesses: &[f64],
    machs: &[f64],
    mut load: impl FnMut(f64) -> Result<Variant, String>,
    options: LineariseOptions,
) -> Result<LinearMap, LinearAnalysisError> {
    let nx = thicknesses.len();
    let cells = nx * machs.len();
    let mut map = StabilityMap {
        xs: thicknesses.to_vec(),
        ys: machs.to_vec(),
        sigma: vec![0.0; cells],
        omega: vec![0.0; cells],
        class: vec![StabilityClass::Stable; cells],
        flight_path_sigma: vec![f64::NAN; cells],
    };
    let mut trim_failures = Vec::new();
    let mut altitude = 0.0;
    for (i, &t) in thicknesses.iter().enumerate() {
        let variant = load(t).map_err(|message| LinearAnalysisError::Variant {
            thickness: t,
            message,
        })?;
        let (h, attitude, _) = reference_of(&variant.plan);
        altitude = h;
        let (a, _) = air(h)?;
        let gravity = plan_gravity(&variant.plan, h);
        let mut lin = linearizer(&variant, options)?;
        for (j, &mach) in machs.iter().enumerate() {
            let cell = |e: LinearAnalysisError| LinearAnalysisError::Cell {
                thickness: t,
                mach,
                error: Box::new(e),
            };
            let r =
                analyse_with(&mut lin, mach * a, h, attitude, gravity, options).map_err(cell)?;
            let k = map.index(i, j);
            map.sigma[k] = r.eigen.sigma_d;
            map.omega[k] = r.eigen.omega_d;
            map.class[k] = r.eigen.class;
            map.flight_path_sigma[k] = r.eigen.flight_path_sigma.unwrap_or(f64::NAN);
            if !r.trim_converged {
                trim_failures.push(k);
            }
        }
    }
    Ok(LinearMap {
        map,
        trim_failures,
        altitude,
    })
}
