//! Stage 5, plan: everything a run needs, resolved from a checked [`Scenario`] and its
//! [`CompiledVehicle`] before the first step.
//!
//! The plan fixes the state layout and the initial state, the integrator settings, the stop
//! conditions, the ordered force blocks with their resolved parameters (thrust curve loaded,
//! nozzle node and its shape rows; the aerodynamic blocks with their coefficient tables,
//! fin load weights and key-node rows, [`aero`]), the planned stimuli and the output
//! channel names.
//!
//! Architecture invariant: every file read, name lookup and table resolution of a run
//! happens here; the runtime only indexes what the plan holds.

pub mod aero;
mod channels;

use std::path::PathBuf;

use serde::Serialize;

use crate::aero::atmosphere::{Atmosphere, AtmosphereError, Standard1976};
use crate::check::ir::{self, Attitude, InitialPosition, InitialVelocity, Scenario, Stimulus};
use crate::runtime::eom::StateLayout;
use crate::runtime::kinematics::euler_parameters_from_angles;
use crate::runtime::stimuli::{Stimuli, StimulusError};
use crate::runtime::thrust::{ThrustCurve, ThrustCurveError};
use crate::structure::compile::CompiledVehicle;
use crate::syntax::Span;

pub use channels::{AeroChannels, INVARIANT_CHANNELS, RIGID_CHANNELS, channel_names};

/// Why a plan could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// The thrust curve could not be read.
    #[error("thrust curve: {0}")]
    ThrustCurve(#[from] ThrustCurveError),
    /// Thrust is enabled but the vehicle has no nozzle key node.
    #[error("thrust is enabled but vehicle `{vehicle}` declares no nozzle key node")]
    NoNozzle { vehicle: String, span: Span },
    /// A stimulus has a bad parameter.
    #[error("stimulus: {0}")]
    Stimulus(#[from] StimulusError),
    /// The initial altitude is outside the atmosphere (Mach needs the speed of sound).
    #[error("initial state: {0}")]
    Atmosphere(#[from] AtmosphereError),
    /// The compiled vehicle's arrays disagree with its mode count.
    #[error("compiled vehicle `{vehicle}`: {what}")]
    Compiled { vehicle: String, what: String },
    /// A rail launch whose thrust never exceeds the weight component along the rail.
    #[error(
        "the vehicle cannot leave the rail: its largest thrust, {max_thrust:.1} N, never exceeds \
         its weight along the rail, m g sin(elevation) = {weight_along_rail:.1} N"
    )]
    NoLiftOff {
        span: Span,
        max_thrust: f64,
        weight_along_rail: f64,
    },
    /// The aerodynamic blocks could not be built (tables, fin geometry).
    #[error("aerodynamics: {error}")]
    Aero {
        error: crate::runtime::forces::AeroForceError,
        span: Span,
    },
}

impl PlanError {
    /// Where in the vehicle or scenario file the problem was written, if known.
    pub fn span(&self) -> Option<Span> {
        match self {
            PlanError::NoNozzle { span, .. }
            | PlanError::NoLiftOff { span, .. }
            | PlanError::Aero { span, .. } => Some(*span),
            PlanError::Stimulus(
                StimulusError::BadParameter { span, .. } | StimulusError::NoAirspeed { span, .. },
            ) => Some(*span),
            _ => None,
        }
    }

    /// The diagnostic code (docs/diagnostic-codes.md).
    pub fn code(&self) -> &'static str {
        match self {
            PlanError::NoLiftOff { .. } => "plan::no_liftoff",
            _ => "plan::invalid",
        }
    }
}

/// Which integrator and its settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct IntegratorPlan {
    /// Dormand-Prince 5(4) or RK4.
    pub method: ir::Integrator,
    pub rtol: f64,
    pub atol: f64,
    /// Fixed step (RK4) or first step (Dopri5), s.
    pub step: f64,
    /// Smallest step before the run stops with "step_underflow", s.
    pub min_step: f64,
}

/// When the run stops (besides step underflow and non-finite states, always on).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StopConditions {
    /// Final time, s.
    pub stop_time: f64,
    /// Stop when the body origin descends through the ground: inertial `z >= -ground_altitude`
    /// while `ż > 0` (descending).
    pub ground: bool,
    /// Altitude of the ground, m: the launch site's, else sea level (0).
    pub ground_altitude: f64,
    /// Stop when `|α|` exceeds this, rad.
    pub max_alpha: Option<f64>,
    /// Stop when the elastic displacement `|S_trans,i η|` at any node exceeds this, m.
    pub max_deformation: Option<f64>,
    /// The bounds of the model itself, always checked: a run that crosses one ends with a
    /// verdict (`runtime::verdict`).
    pub model_limits: ModelLimits,
}

/// The bounds of the small-deformation, linear model a run integrates (derivation at
/// [`crate::runtime::verdict`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ModelLimits {
    /// Largest elastic nodal displacement, m: [`DEFLECTION_FRACTION_FIN`] of the fin span,
    /// or without fins [`DEFLECTION_FRACTION_BODY`] of the body length; None without
    /// elastic modes.
    pub deflection: Option<f64>,
    /// What `deflection` is a fraction of, for people.
    pub deflection_basis: &'static str,
    /// Stop at a fin root stress (5.6) beyond the material's yield stress, where the
    /// material states one and `fin_aero { stress_limit }` is not set.
    pub fin_yield: bool,
    /// Stop where the air reaches the vehicle from behind in free flight (total angle of
    /// attack beyond 90 deg) when its body coefficient table ends below 90 deg and the
    /// scenario has no recovery device (`run::Monitor::stop_condition`: a tumbling or
    /// tail-first fall).
    pub reversed_flow: bool,
}

/// The deflection bound as a fraction of the fin span (a tip slope of 0.15 rad).
pub const DEFLECTION_FRACTION_FIN: f64 = 0.1;

/// The deflection bound as a fraction of the body length, without fins.
pub const DEFLECTION_FRACTION_BODY: f64 = 0.02;

/// The model bounds of `vehicle` compiled as `compiled`, in a scenario with or without a
/// recovery device (see [`ModelLimits`]).
pub fn model_limits(
    vehicle: &crate::check::ir::Vehicle,
    compiled: &CompiledVehicle,
    recovery: bool,
) -> ModelLimits {
    let elastic = !compiled.modes.is_empty();
    let (deflection, deflection_basis) = match &vehicle.fins {
        Some(f) => (
            DEFLECTION_FRACTION_FIN * f.span.value,
            "10 % of the fin span",
        ),
        None => {
            let length = compiled
                .node_positions
                .iter()
                .map(|p| -p[0])
                .fold(0.0, f64::max);
            (DEFLECTION_FRACTION_BODY * length, "2 % of the body length")
        }
    };
    ModelLimits {
        deflection: (elastic && deflection > 0.0).then_some(deflection),
        deflection_basis,
        fin_yield: vehicle
            .forces
            .fin_aero
            .as_ref()
            .is_some_and(|f| f.stress_limit_fraction.is_none()),
        // A recovery device flies the descent (`run::Monitor::stop_condition`).
        reversed_flow: !recovery,
    }
}

/// Gravity block parameters (5.1).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GravityPlan {
    /// Apply (5.1.2).
    pub altitude_correction: bool,
}

/// Thrust block parameters (5.2), resolved.
#[derive(Debug, Clone, Serialize)]
pub struct ThrustPlan {
    /// The curve file.
    pub curve_file: PathBuf,
    /// Loaded curve (not serialised; see the summary fields).
    #[serde(skip)]
    pub curve: ThrustCurve,
    /// Total impulse, N s, and burn time, s, of the curve.
    pub total_impulse: f64,
    pub burn_time: f64,
    /// Index of the nozzle key node in the compiled node list.
    pub nozzle_node: usize,
    /// Its undeformed position `r_T`, m.
    pub nozzle_position: [f64; 3],
    /// Rows u, v, w of `S` at the nozzle (3 x n, row-major).
    pub s_translation: Vec<f64>,
    /// Rows θx, θy, θz of `S` at the nozzle (3 x n, row-major).
    pub s_rotation: Vec<f64>,
    /// `δ_T`, m.
    pub offset: [f64; 3],
    /// `α_T`, rad.
    pub misalignment: [f64; 3],
}

/// The vehicle's motor (issue 10, "Variable mass"), resolved: its curve and masses, where
/// its thrust acts, and the propellant's reduced coefficients on the vehicle's modal basis.
/// A vehicle with a motor burns it from `t = 0`: its thrust, variable mass and mass-flow
/// terms are part of the equations of motion ([`crate::runtime::eom::Propulsion`]), not a
/// force block.
#[derive(Debug, Clone, Serialize)]
pub struct MotorPlan {
    /// The `motor` block's name.
    pub name: String,
    /// Motor designation from the curve (RASP header, or the CSV file's stem).
    pub designation: String,
    /// Propellant mass at ignition and loaded motor mass, kg.
    pub propellant_mass: f64,
    pub total_mass: f64,
    /// Effective exhaust velocity `c = I_tot / m_p`, m/s (specific impulse `c / g0`).
    pub exhaust_velocity: f64,
    /// Vehicle mass at ignition and at burnout, kg.
    pub ignition_mass: f64,
    pub burnout_mass: f64,
    /// The thrust at the nozzle: curve, nozzle node and its shape rows, offset and
    /// misalignment (from the vehicle's `thrust` block if it has one).
    pub thrust: ThrustPlan,
    /// The propellant's coefficients at full load (not serialised).
    #[serde(skip)]
    pub propellant: crate::structure::coefficients::ReducedModel,
}

/// A rail launch, resolved (`launch { ... }`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LaunchPlan {
    /// Site altitude (the ground), m.
    pub site_altitude: f64,
    /// Distance travelled along the rail before the vehicle is free, m.
    pub rail_length: f64,
    /// Elevation and heading of the rail, rad.
    pub elevation: f64,
    pub heading: f64,
    /// Unit vector up the rail, inertial frame (x north, y east, z down):
    /// `(cos e cos psi, cos e sin psi, -sin e)`, the body x axis of the attitude
    /// `euler(0, e, psi)` (4.4.4).
    pub rail_direction: [f64; 3],
    /// Initial position of the body origin (nose tip): the aft end of the vehicle (its
    /// most aft node) at the foot of the rail, on the ground.
    pub start: [f64; 3],
}

/// A further, rigid fin set as planned (`fins NAME`): what the flight takes of it. Its mass
/// is a rigid body in the compiled structure, its aerodynamics (normal force, drag, pitch
/// damping, the roll of its cant and its roll damping) are in the body table.
#[derive(Debug, Clone, Serialize)]
pub struct FinSetPlan {
    pub name: String,
    pub count: usize,
    /// `trapezoidal`, `elliptical` or `freeform`.
    pub outline: &'static str,
    /// Body x of the root leading edge, m.
    pub root_leading_edge_x: f64,
    /// Span and root chord, m; planform area of one fin, m^2 (the true outline's).
    pub span: f64,
    pub root_chord: f64,
    pub area: f64,
    /// Thickness, m; material name; cant, rad.
    pub thickness: f64,
    pub material: String,
    pub cant: f64,
    /// Mass of the set's plates, kg (area x thickness x density x count; fillets apart).
    pub plate_mass: f64,
}

/// The further fin sets of `v` as [`FinSetPlan`]s (empty for an FE model from files, which
/// has none).
pub fn fin_set_plans(v: &ir::Vehicle) -> Vec<FinSetPlan> {
    let ir::Structure::Generate(g) = &v.structure else {
        return Vec::new();
    };
    v.fin_sets
        .iter()
        .map(|s| {
            let f = &s.fins;
            let area = crate::aero::estimator::planform(f, g.body.radius_under(f)).area();
            FinSetPlan {
                name: s.name.value.clone(),
                count: f.count.value,
                outline: f.outline.keyword(),
                root_leading_edge_x: f.root_trailing_edge_x.value + f.root_chord.value,
                span: f.span.value,
                root_chord: f.root_chord.value,
                area,
                thickness: f.thickness.value,
                material: f.material.name.value.clone(),
                cant: f.cant.value,
                plate_mass: area
                    * f.thickness.value
                    * f.material.density.value
                    * f.count.value as f64,
            }
        })
        .collect()
}

/// A recovery device, resolved.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParachutePlan {
    pub name: String,
    /// C_D S, m^2.
    pub cd_area: f64,
    pub trigger: ir::Trigger,
    /// Trigger-to-deployment delay, s.
    pub lag: f64,
}

/// One force block with its resolved parameters, in evaluation order.
#[derive(Debug, Clone, Serialize)]
#[serde(rename_all = "snake_case", tag = "block")]
pub enum ForcePlan {
    Gravity(GravityPlan),
    /// Boxed: the shape rows and the curve make it much larger than the others.
    Thrust(Box<ThrustPlan>),
    /// Body aerodynamics (5.3): its settings as checked.
    BodyAero {
        rate_terms: bool,
    },
    /// Fin aerodynamics (5.4): its settings as checked.
    FinAero {
        distribution: ir::Distribution,
        leeward_reduction: bool,
        stress_limit_fraction: Option<f64>,
    },
}

impl ForcePlan {
    /// The block's name as written in `forces { ... }`.
    pub fn name(&self) -> &'static str {
        match self {
            ForcePlan::Gravity(_) => "gravity",
            ForcePlan::Thrust(_) => "thrust",
            ForcePlan::BodyAero { .. } => "body_aero",
            ForcePlan::FinAero { .. } => "fin_aero",
        }
    }
}

/// Everything a run needs.
#[derive(Debug, Clone, Serialize)]
pub struct Plan {
    pub scenario: String,
    pub vehicle: String,
    /// The scenario's overrides as (path, value).
    pub overrides: Vec<(String, String)>,
    /// Number of modal coordinates `n` (state length `13 + 2n`).
    pub n_modes: usize,
    pub mode_names: Vec<String>,
    /// `x0 = (p_I, q, V_B, ω_B, η, η̇)` of [`StateLayout`].
    pub initial_state: Vec<f64>,
    pub integrator: IntegratorPlan,
    pub stop: StopConditions,
    /// Output interval, s.
    pub output_interval: f64,
    pub forces: Vec<ForcePlan>,
    /// The motor, if the vehicle has one.
    pub motor: Option<MotorPlan>,
    /// The stimuli as checked.
    pub stimuli: Vec<Stimulus>,
    /// Planned stimuli (turbulence series generated).
    #[serde(skip)]
    pub planned_stimuli: Stimuli,
    /// Columns of `history.csv`.
    pub channels: Vec<String>,
    /// Translation rows of `S` for every node (`3 n_nodes x n`, row-major), for the
    /// deformation stop and monitor.
    #[serde(skip)]
    pub node_translation_shapes: Vec<f64>,
    /// The rail launch, if the scenario has one.
    pub launch: Option<LaunchPlan>,
    /// Recovery devices in the order written.
    pub parachutes: Vec<ParachutePlan>,
    /// The further, rigid fin sets (`fins NAME`, `check::fin_sets`), in the order written.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub fin_sets: Vec<FinSetPlan>,
    /// The static margin model from the same tables as the aerodynamic blocks (both on).
    #[serde(skip)]
    pub static_margin: Option<crate::aero::static_margin::StaticMargin>,
    /// The aerodynamic blocks (with `body_aero` or `fin_aero`), built with the planned
    /// stimuli; a run copies them into its force blocks.
    #[serde(skip)]
    pub aero: Option<aero::PlanAero>,
    /// What `flexflight plan` shows of them.
    #[serde(rename = "aero")]
    pub aero_summary: Option<aero::AeroSummary>,
}

impl Plan {
    /// The state layout.
    pub fn layout(&self) -> StateLayout {
        StateLayout { n: self.n_modes }
    }

    /// Replaces the planned stimuli, in the plan and in the aerodynamic blocks that see them.
    pub fn set_stimuli(&mut self, stimuli: Stimuli) {
        if let Some(a) = &mut self.aero {
            a.set_stimuli(&stimuli);
        }
        self.planned_stimuli = stimuli;
    }

    /// The gravity block's settings, if gravity is on.
    pub fn gravity(&self) -> Option<&GravityPlan> {
        self.forces.iter().find_map(|f| match f {
            ForcePlan::Gravity(g) => Some(g),
            _ => None,
        })
    }
}

/// Builds the plan of `scenario` flown by `compiled` (its compiled vehicle).
pub fn build(scenario: &Scenario, compiled: &CompiledVehicle) -> Result<Plan, PlanError> {
    build_with_aero(scenario, compiled, None)
}

/// [`build`] with the vehicle-only aerodynamics (tables, fin load weights) taken from
/// `cached` (the [`aero::VehicleAero`] of the same vehicle, from the artifact cache or an
/// earlier plan) instead of being rebuilt. The plan is the same bits either way.
pub fn build_with_aero(
    scenario: &Scenario,
    compiled: &CompiledVehicle,
    cached: Option<&aero::VehicleAero>,
) -> Result<Plan, PlanError> {
    let vehicle = &scenario.vehicle;
    let n = compiled.modes.len();
    let n_nodes = compiled.node_positions.len();
    let bad = |what: String| PlanError::Compiled {
        vehicle: compiled.vehicle.clone(),
        what,
    };
    if compiled.reduced.n() != n {
        return Err(bad(format!(
            "{} reduced coordinates but {} modes",
            compiled.reduced.n(),
            n
        )));
    }
    if compiled.shapes.len() != 6 * n_nodes * n {
        return Err(bad(format!(
            "shape array has {} entries, expected 6 x {n_nodes} x {n}",
            compiled.shapes.len()
        )));
    }
    let rows = |node: usize, first_dof: usize| -> Vec<f64> {
        let mut v = Vec::with_capacity(3 * n);
        for d in 0..3 {
            let r = (6 * node + first_dof + d) * n;
            v.extend_from_slice(&compiled.shapes[r..r + n]);
        }
        v
    };

    // Initial state.
    let init = &scenario.initial;
    let launch = scenario.launch.as_ref().map(|l| {
        let (e, psi) = (l.elevation.value, l.heading.value);
        let d = [e.cos() * psi.cos(), e.cos() * psi.sin(), -e.sin()];
        // Most aft point of the vehicle (x <= 0 in the body frame).
        let x_aft = compiled
            .node_positions
            .iter()
            .map(|p| p[0])
            .fold(0.0_f64, f64::min);
        let h = l.site_altitude.value;
        LaunchPlan {
            site_altitude: h,
            rail_length: l.rail_length.value,
            elevation: e,
            heading: psi,
            rail_direction: d,
            start: [-x_aft * d[0], -x_aft * d[1], -h - x_aft * d[2]],
        }
    });
    let position = match (&launch, &init.position) {
        (Some(l), _) => l.start,
        (None, InitialPosition::Altitude(h)) => [0.0, 0.0, -h.value],
        (None, InitialPosition::Inertial(p)) => p.value,
    };
    let velocity = match &init.velocity {
        InitialVelocity::Body(v) => v.value,
        InitialVelocity::Mach(m) => {
            let a = Standard1976::new().at(-position[2])?.speed_of_sound;
            [m.value * a, 0.0, 0.0]
        }
    };
    // Runtime order is (ε1, ε2, ε3, η) with η the scalar part; `quaternion(q0, ...)` has
    // the scalar first (quaternion(1, 0, 0, 0) is the identity).
    let attitude = match &init.attitude {
        Attitude::Euler(a) => euler_parameters_from_angles(a.value[0], a.value[1], a.value[2]),
        Attitude::Quaternion(q) => [q.value[1], q.value[2], q.value[3], q.value[0]],
    };
    let layout = StateLayout { n };
    let zeros = vec![0.0; n];
    let initial_state = layout.state(
        position,
        attitude,
        velocity,
        init.angular_velocity.value,
        &zeros,
        &zeros,
    );

    // Force blocks, in evaluation order.
    let mut forces = Vec::new();
    if let Some(g) = &vehicle.forces.gravity {
        forces.push(ForcePlan::Gravity(GravityPlan {
            altitude_correction: g.altitude_correction,
        }));
    }
    let motor = match &vehicle.motor {
        Some(m) => {
            let node = usize::try_from(compiled.key_nozzle)
                .ok()
                .filter(|&k| k < n_nodes)
                .ok_or_else(|| PlanError::NoNozzle {
                    vehicle: vehicle.name.value.clone(),
                    span: m.header,
                })?;
            let propellant = compiled.propellant.clone().ok_or_else(|| {
                bad("the vehicle has a motor but the compiled vehicle no propellant".into())
            })?;
            if propellant.n() != n {
                return Err(bad(format!(
                    "propellant coefficients for {} modes, the vehicle has {n}",
                    propellant.n()
                )));
            }
            let curve = ThrustCurve::read(&m.curve.value)?;
            // The scenario's motor scatter (`motor_scale`): the same propellant delivers
            // a scaled impulse (its exhaust velocity below scales with it).
            let curve = match &scenario.motor_scale {
                Some(s) => curve.scaled(s.impulse.value, s.burn_time.value),
                None => curve,
            };
            let (offset, misalignment) = match &vehicle.forces.thrust {
                Some(t) => (t.offset.value, t.misalignment.value),
                None => ([0.0; 3], [0.0; 3]),
            };
            let total_impulse = curve.total_impulse();
            Some(MotorPlan {
                name: m.name.value.clone(),
                designation: curve.name.clone(),
                propellant_mass: m.propellant_mass.value,
                total_mass: m.total_mass.value,
                exhaust_velocity: total_impulse / m.propellant_mass.value,
                ignition_mass: compiled.reduced.mass,
                burnout_mass: compiled.reduced.mass - propellant.mass,
                thrust: ThrustPlan {
                    curve_file: m.curve.value.clone(),
                    total_impulse,
                    burn_time: curve.burn_time(),
                    curve,
                    nozzle_node: node,
                    nozzle_position: compiled.node_positions[node],
                    s_translation: rows(node, 0),
                    s_rotation: rows(node, 3),
                    offset,
                    misalignment,
                },
                propellant,
            })
        }
        None => None,
    };
    if let (Some(t), None) = (&vehicle.forces.thrust, &vehicle.motor) {
        let node = usize::try_from(compiled.key_nozzle)
            .ok()
            .filter(|&k| k < n_nodes)
            .ok_or_else(|| PlanError::NoNozzle {
                vehicle: vehicle.name.value.clone(),
                span: t.span,
            })?;
        let curve = ThrustCurve::read(&t.curve.value)?;
        forces.push(ForcePlan::Thrust(Box::new(ThrustPlan {
            curve_file: t.curve.value.clone(),
            total_impulse: curve.total_impulse(),
            burn_time: curve.burn_time(),
            curve,
            nozzle_node: node,
            nozzle_position: compiled.node_positions[node],
            s_translation: rows(node, 0),
            s_rotation: rows(node, 3),
            offset: t.offset.value,
            misalignment: t.misalignment.value,
        })));
    }
    if let Some(b) = &vehicle.forces.body_aero {
        forces.push(ForcePlan::BodyAero {
            rate_terms: b.rate_terms,
        });
    }
    if let Some(f) = &vehicle.forces.fin_aero {
        forces.push(ForcePlan::FinAero {
            distribution: f.distribution.value,
            leeward_reduction: f.leeward_reduction,
            stress_limit_fraction: f.stress_limit_fraction.as_ref().map(|q| q.value),
        });
    }

    // A rail launch needs a thrust that exceeds the weight along the rail at some time
    // (the rail's foot holds the vehicle until then). The mass is the initial one.
    if let (Some(l), Some(sl)) = (&launch, &scenario.launch) {
        let g = match &vehicle.forces.gravity {
            Some(g) => {
                crate::runtime::forces::gravity::gravity_at(l.site_altitude, g.altitude_correction)
            }
            None => 0.0,
        };
        let weight_along_rail = compiled.reduced.mass * g * l.elevation.sin();
        // With a motor the thrust is its curve and the mass its ignition mass (the
        // compiled vehicle's, which includes the propellant).
        let max_thrust = motor
            .as_ref()
            .map(|m| &m.thrust)
            .or_else(|| {
                forces.iter().find_map(|f| match f {
                    ForcePlan::Thrust(t) => Some(&**t),
                    _ => None,
                })
            })
            .map_or(0.0, |t| t.curve.points().map(|p| p.1).fold(0.0, f64::max));
        if max_thrust <= weight_along_rail {
            return Err(PlanError::NoLiftOff {
                span: sl.span,
                max_thrust,
                weight_along_rail,
            });
        }
    }

    let run = &scenario.run;
    let airspeed = velocity.iter().map(|v| v * v).sum::<f64>().sqrt();
    let mut planned_stimuli = Stimuli::new(&scenario.stimuli, airspeed, run.stop_time.value)?;
    let ground_altitude = launch.as_ref().map_or(0.0, |l| l.site_altitude);
    if let Some(w) = &scenario.wind {
        planned_stimuli.set_steady_wind(&w.profile, ground_altitude);
    }
    let aero = aero::resolve(vehicle, compiled, &planned_stimuli, cached).map_err(|error| {
        use crate::runtime::forces::AeroForceError as E;
        let fins_span = vehicle.fins.as_ref().map(|f| f.span_);
        let span = match &error {
            E::FinLoad(_)
            | E::NoFins { .. }
            | E::FinCount { .. }
            | E::EmptyFin { .. }
            | E::NodeOffPlanform { .. }
            | E::FinPanels(_) => fins_span
                .or(vehicle.forces.fin_aero.as_ref().map(|f| f.span))
                .unwrap_or(vehicle.aero.span),
            _ => vehicle.aero.span,
        };
        PlanError::Aero { error, span }
    })?;
    let aero_summary = aero.as_ref().map(aero::AeroSummary::new);
    let static_margin = aero
        .as_ref()
        .and_then(|a| crate::aero::static_margin::StaticMargin::new(vehicle, compiled, &a.tables));
    let mode_names: Vec<String> = compiled.modes.iter().map(|m| m.name.clone()).collect();
    let mut node_translation_shapes = Vec::with_capacity(3 * n_nodes * n);
    for node in 0..n_nodes {
        node_translation_shapes.extend(rows(node, 0));
    }
    Ok(Plan {
        scenario: scenario.name.value.clone(),
        vehicle: vehicle.name.value.clone(),
        overrides: scenario
            .overrides
            .iter()
            .map(|o| (o.path.clone(), o.value.clone()))
            .collect(),
        n_modes: n,
        channels: channel_names(
            &mode_names,
            AeroChannels {
                body: vehicle.forces.body_aero.is_some(),
                fins: if vehicle.forces.fin_aero.is_some() {
                    vehicle.fins.as_ref().map_or(0, |f| f.count.value)
                } else {
                    0
                },
            },
        ),
        mode_names,
        initial_state,
        integrator: IntegratorPlan {
            method: run.integrator.value,
            rtol: run.rtol.value,
            atol: run.atol.value,
            step: run.step.value,
            min_step: run.min_step.value,
        },
        stop: StopConditions {
            stop_time: run.stop_time.value,
            ground: run.stop_on_ground,
            ground_altitude,
            max_alpha: run.max_alpha.as_ref().map(|q| q.value),
            max_deformation: run.max_deformation.as_ref().map(|q| q.value),
            model_limits: if run.model_limits {
                model_limits(vehicle, compiled, !scenario.parachutes.is_empty())
            } else {
                ModelLimits {
                    deflection: None,
                    deflection_basis: "off (run { model_limits = false })",
                    fin_yield: false,
                    reversed_flow: false,
                }
            },
        },
        output_interval: run.output_interval.value,
        forces,
        motor,
        stimuli: scenario.stimuli.clone(),
        planned_stimuli,
        node_translation_shapes,
        launch,
        parachutes: scenario
            .parachutes
            .iter()
            .map(|p| ParachutePlan {
                name: p.name.value.clone(),
                cd_area: p.cd_area.value,
                trigger: p.trigger.value,
                lag: p.lag.value,
            })
            .collect(),
        fin_sets: fin_set_plans(vehicle),
        static_margin,
        aero,
        aero_summary,
    })
}

/// The human summary printed by `flexflight plan`.
pub fn summary_text(p: &Plan) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let x = &p.initial_state;
    let _ = writeln!(s, "scenario       {}", p.scenario);
    let _ = writeln!(s, "vehicle        {}", p.vehicle);
    for (path, value) in &p.overrides {
        let _ = writeln!(s, "  with         {path} = {value}");
    }
    let _ = writeln!(
        s,
        "state          13 + 2 x {} = {} entries; modes: {}",
        p.n_modes,
        13 + 2 * p.n_modes,
        p.mode_names.join(", ")
    );
    let _ = writeln!(
        s,
        "p_I            ({:.6}, {:.6}, {:.6}) m (z down)",
        x[0], x[1], x[2]
    );
    let _ = writeln!(
        s,
        "q (eps, eta)   ({:.9}, {:.9}, {:.9}, {:.9})",
        x[3], x[4], x[5], x[6]
    );
    let _ = writeln!(
        s,
        "V_B            ({:.6}, {:.6}, {:.6}) m/s",
        x[7], x[8], x[9]
    );
    let _ = writeln!(
        s,
        "omega_B        ({:.6}, {:.6}, {:.6}) rad/s",
        x[10], x[11], x[12]
    );
    let i = &p.integrator;
    let _ = writeln!(
        s,
        "integrator     {:?}: rtol {:e}, atol {:e}, step {} s, min step {:e} s",
        i.method, i.rtol, i.atol, i.step, i.min_step
    );
    let st = &p.stop;
    let _ = writeln!(s, "stop           t = {} s", st.stop_time);
    if st.ground {
        let _ = writeln!(
            s,
            "               ground: body origin descending through altitude {} m",
            st.ground_altitude
        );
    }
    if let Some(l) = &p.launch {
        let _ = writeln!(
            s,
            "launch         rail {} m at elevation {:.3} deg, heading {:.3} deg, site altitude {} m",
            l.rail_length,
            l.elevation.to_degrees(),
            l.heading.to_degrees(),
            l.site_altitude
        );
    }
    for c in &p.parachutes {
        let _ = writeln!(
            s,
            "parachute      {}: cd_area {} m^2, trigger {:?}, lag {} s",
            c.name, c.cd_area, c.trigger, c.lag
        );
    }
    if let Some(a) = st.max_alpha {
        let _ = writeln!(s, "               |alpha| > {:.3} deg", a.to_degrees());
    }
    if let Some(d) = st.max_deformation {
        let _ = writeln!(s, "               max nodal deformation > {d} m");
    }
    let mut label = "model limits";
    if let Some(d) = st.model_limits.deflection {
        let _ = writeln!(
            s,
            "{label:<15}elastic displacement > {d} m ({}){}: a verdict (flutter, divergence or model limit)",
            st.model_limits.deflection_basis,
            if st.model_limits.fin_yield {
                ", fin root stress > yield"
            } else {
                ""
            }
        );
        label = "";
    }
    if st.model_limits.reversed_flow {
        let _ = writeln!(
            s,
            "{label:<15}air from behind in free flight (total alpha > 90 deg; no recovery device) with a body table ending below 90 deg: a verdict (model limit)"
        );
    }
    let _ = writeln!(s, "               step underflow, non-finite state");
    for f in &p.fin_sets {
        let _ = writeln!(
            s,
            "fin set        {}: {} {} fins, rigid; root LE at x = {:.4} m, span {:.4} m, root chord {:.4} m, {:.6} m^2 each, {:.2} mm {}, cant {:.3} deg; plates {:.4} kg; normal force, drag, pitch and roll in the body table",
            f.name,
            f.count,
            f.outline,
            f.root_leading_edge_x,
            f.span,
            f.root_chord,
            f.area,
            f.thickness * 1e3,
            f.material,
            f.cant.to_degrees(),
            f.plate_mass
        );
    }
    let _ = writeln!(s, "force blocks:");
    for f in &p.forces {
        let _ = match f {
            ForcePlan::Gravity(g) => writeln!(
                s,
                "  gravity      g0 = 9.806 m/s^2, altitude correction {}",
                if g.altitude_correction { "on" } else { "off" }
            ),
            ForcePlan::Thrust(t) => writeln!(
                s,
                "  thrust       {} ({:.3} N s over {:.3} s), nozzle node {} at ({:.4}, {:.4}, {:.4}) m, offset {:?} m, misalignment {:?} rad",
                t.curve_file.display(),
                t.total_impulse,
                t.burn_time,
                t.nozzle_node,
                t.nozzle_position[0],
                t.nozzle_position[1],
                t.nozzle_position[2],
                t.offset,
                t.misalignment
            ),
            ForcePlan::BodyAero { rate_terms } => {
                writeln!(
                    s,
                    "  body_aero    rate terms {}",
                    if *rate_terms { "on" } else { "off" }
                )
            }
            ForcePlan::FinAero {
                distribution,
                leeward_reduction,
                ..
            } => writeln!(
                s,
                "  fin_aero     distribution {distribution:?}, leeward reduction {}",
                if *leeward_reduction { "on" } else { "off" }
            ),
        };
    }
    if let Some(m) = &p.motor {
        let t = &m.thrust;
        let _ = writeln!(
            s,
            "  motor        {} ({}): {:.3} N s over {:.3} s, propellant {:.4} kg of {:.4} kg, c = {:.2} m/s, vehicle {:.4} kg -> {:.4} kg; nozzle node {} at ({:.4}, {:.4}, {:.4}) m, offset {:?} m, misalignment {:?} rad",
            m.name,
            m.designation,
            t.total_impulse,
            t.burn_time,
            m.propellant_mass,
            m.total_mass,
            m.exhaust_velocity,
            m.ignition_mass,
            m.burnout_mass,
            t.nozzle_node,
            t.nozzle_position[0],
            t.nozzle_position[1],
            t.nozzle_position[2],
            t.offset,
            t.misalignment
        );
    }
    if p.forces.is_empty() && p.motor.is_none() {
        let _ = writeln!(s, "  (none: free flight)");
    }
    if let Some(a) = &p.aero_summary {
        s.push_str(&a.text(p.n_modes));
    }
    let _ = writeln!(s, "stimuli        {}", p.stimuli.len());
    let _ = writeln!(
        s,
        "output         every {} s, {} channels",
        p.output_interval,
        p.channels.len()
    );
    s
}

/// Body-frame corners of fin `i` (m): root trailing edge, root leading edge, tip leading
/// edge, tip trailing edge, laid out as the structure generator lays out the fin
/// (`structure::generate::mesh::fin_grid`): the planform in the plane of body x and the
/// span direction `e_s = (0, cos delta_i, sin delta_i)`, its root at `root_radius` from the
/// axis, the chord turned by the cant about the span axis through the middle of the root
/// chord toward the fin normal `(0, -sin delta_i, cos delta_i)`. The leading edge at the tip
/// lies `span tan(leading_edge_sweep)` aft of the root's (docs/language.md, "Angles").
pub fn fin_corners(f: &ir::Fins, i: usize, root_radius: f64) -> [[f64; 3]; 4] {
    let delta = f.angles.get(i).map_or(0.0, |a| a.value);
    let (sd, cd) = delta.sin_cos();
    let (sc, cc) = f.cant.value.sin_cos();
    let es = [0.0, cd, sd];
    let ea = [cc, -sc * sd, sc * cd];
    let (cr, ct, b) = (f.root_chord.value, f.tip_chord.value, f.span.value);
    let x_te = f.root_trailing_edge_x.value;
    let pivot = x_te + 0.5 * cr;
    let x_le_tip = x_te + cr - b * f.leading_edge_sweep.value.tan();
    let planform = [
        (x_te, 0.0),
        (x_te + cr, 0.0),
        (x_le_tip, b),
        (x_le_tip - ct, b),
    ];
    planform.map(|(x, eta)| {
        let a = x - pivot;
        let r = root_radius + eta;
        [
            pivot + a * ea[0],
            r * es[1] + a * ea[1],
            r * es[2] + a * ea[2],
        ]
    })
}

/// `plan`'s lines with each fin's four corner points (body frame, m), the unnamed set's and
/// each further set's, or a line saying why there are none. An elliptical or freeform fin's
/// corners are those of its equivalent trapezoid (same span, root chord, area and leading
/// edge of the mean aerodynamic chord: `check::ir::Fins::outline`), and the line says so.
pub fn fin_corners_text(v: &ir::Vehicle) -> String {
    use std::fmt::Write as _;
    let Some(f) = v.fins.as_ref() else {
        return String::new();
    };
    let body = match &v.structure {
        ir::Structure::Generate(g) => &g.body,
        ir::Structure::Files(_) => {
            return "fin corners    not drawn: the structure is read from files (its nodes place the fins)\n".to_string();
        }
    };
    let mut s = String::from(
        "fin corners    body frame, m: root TE, root LE, tip LE, tip TE (x forward from the nose tip)\n",
    );
    let sets = std::iter::once((None, f)).chain(
        v.fin_sets
            .iter()
            .map(|fs| (Some(fs.name.value.as_str()), &fs.fins)),
    );
    for (name, f) in sets {
        if let Some(n) = name {
            let _ = writeln!(s, "  set {n} (rigid):");
        }
        if !f.outline.is_trapezoidal() {
            let _ = writeln!(
                s,
                "  ({} outline: the corners of its equivalent trapezoid)",
                f.outline.keyword()
            );
        }
        let radius = body.radius_under(f);
        for i in 0..f.count.value {
            let c = fin_corners(f, i, radius);
            let _ = write!(
                s,
                "  fin {} at {:.3} deg:",
                i + 1,
                f.angles.get(i).map_or(0.0, |a| a.value.to_degrees())
            );
            for p in c {
                let _ = write!(s, " ({:.5}, {:.5}, {:.5})", p[0], p[1], p[2]);
            }
            s.push('\n');
        }
    }
    s
}
