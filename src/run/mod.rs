//! The run driver: builds the force blocks of a [`Plan`], integrates the equations of
//! motion (3.2.1), checks the stop conditions after every accepted step and samples the
//! output channels at the output interval.
//!
//! Output sampling: the integrator's observer sees `(t, x, ẋ)` after every accepted step,
//! and the step's continuous extension where the method has one
//! ([`Integrator::integrate_dense`]; the exponential integrator's, which stays accurate over
//! steps spanning many periods of a fin mode, and DOP853's order-7 `contd8`, three more
//! right-hand sides a step, so that its long steps at a tight tolerance keep their rows and
//! events as accurate as its steps); rows at the output times inside the step are
//! interpolated by it, else by the cubic Hermite polynomial through the two step ends and
//! their derivatives (third-order accurate, no extra right-hand side evaluations; DOPRI5
//! and RK4 keep it, bit for bit as before). The Euler parameters of a row are
//! renormalised. When an
//! accepted step meets a stop condition (ground, alpha, deformation, atmosphere range), the
//! first state meeting it is located by bisection on that interpolant and the history ends
//! with a row there; when the integrator gives up (step underflow, non-finite state) it ends
//! with a row at the last accepted state. So the history always reaches
//! the stop and never holds a non-finite value.
//!
//! Architecture invariant: the right-hand side (the [`Eom`] with its [`ForceBlocks`]) does
//! not allocate, do IO or look up names; channel evaluation happens in the observer, outside
//! it, with a second [`Eom`] used only for energies and momenta.

use std::time::Instant;

use crate::aero::atmosphere::{Atmosphere, Standard1976};
pub use crate::aero::static_margin::StaticMargin;
use crate::check::ir;
use crate::plan::{ForcePlan, Plan};
use crate::runtime::deformation::NodeDeformation;
use crate::runtime::eom::{EnergyLayout, Eom, EomError, FreeFlight, Propulsion, StateView};
use crate::runtime::expint::Exponential;
use crate::runtime::flight::{Flight, Phase};
use crate::runtime::forces::{
    AeroFault, BodyAero, FinAero, ForceBlock, ForceBlocks, GravityBlock, ThrustBlock,
};
use crate::runtime::integrate::{
    AdaptiveOptions, DenseOutput, Dop853, DormandPrince54, Integrator, OdeSystem, Rk4, StepStats,
    StopReason,
};
use crate::runtime::kinematics::{
    cross, euler_angles, mat_t_vec, mat_vec, normalize_euler_parameters,
};
use crate::runtime::motor::BurnSchedule;
use crate::runtime::verdict::{ModalTrace, TRACE_CAPACITY, Verdict, VerdictKind};
use crate::structure::coefficients::ReducedModel;

/// Lowest and highest altitude of the 1976 standard atmosphere, m (geometric).
const ATMOSPHERE_RANGE: (f64, f64) = (-500.0, 86_000.0);

/// Why a run could not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RunError {
    /// The plan has a force block whose parameters it does not hold (see
    /// [`crate::plan::aero`]).
    #[error("force block `{block}` was not built for this run")]
    ForceBlockUnavailable { block: &'static str },
    /// The reduced model is inconsistent.
    #[error("{0}")]
    Eom(#[from] EomError),
    /// The plan's initial state does not fit the model.
    #[error("initial state has {found} entries, the model needs {expected}")]
    InitialState { expected: usize, found: usize },
    /// The vehicle starts on or below the ground and cannot leave it.
    #[error(
        "the vehicle starts at altitude {altitude} m, on or below the ground ({ground} m), \
         with vertical speed {climb_rate:.6} m/s and vertical acceleration {climb_acceleration:.6} m/s^2: \
         it cannot leave the ground"
    )]
    CannotLeaveGround {
        altitude: f64,
        ground: f64,
        climb_rate: f64,
        climb_acceleration: f64,
    },
}

/// Why a run stopped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunStop {
    /// Reached the stop time.
    Completed,
    /// The body origin reached the ground (`z >= 0`).
    Ground,
    /// `|α|` exceeded the limit.
    MaxAlpha,
    /// The elastic displacement at some node exceeded the limit.
    MaxDeformation,
    /// The altitude left the range of the atmosphere model.
    AtmosphereRange,
    /// The step size fell below the minimum.
    StepUnderflow,
    /// The state became non-finite, or the mass matrix lost positive definiteness.
    NonFinite,
    /// The step budget ran out.
    MaxSteps,
    /// An aerodynamic coefficient table with the `stop` out-of-range policy was queried
    /// outside its range (Mach, angle of attack or altitude).
    AeroOutOfRange,
    /// A fin root stress (5.6) exceeded the fin_aero `stress_limit` fraction of yield.
    FinStress,
    /// The vehicle left its model (`plan::ModelLimits`) with the modes growing and
    /// oscillating: a flutter verdict ([`RunOutput::verdict`]).
    Flutter,
    /// The vehicle left its model with the modes growing without oscillation.
    Divergence,
    /// The vehicle left its model without modal growth (a load beyond a bound).
    ModelLimit,
}

impl RunStop {
    /// The snake_case code written to `summary.json`.
    pub fn code(&self) -> &'static str {
        match self {
            RunStop::Completed => "completed",
            RunStop::Ground => "ground",
            RunStop::MaxAlpha => "max_alpha",
            RunStop::MaxDeformation => "max_deformation",
            RunStop::AtmosphereRange => "atmosphere_range",
            RunStop::StepUnderflow => "step_underflow",
            RunStop::NonFinite => "non_finite",
            RunStop::MaxSteps => "max_steps",
            RunStop::AeroOutOfRange => "aero_out_of_range",
            RunStop::FinStress => "fin_stress",
            RunStop::Flutter => "flutter",
            RunStop::Divergence => "divergence",
            RunStop::ModelLimit => "model_limit",
        }
    }

    /// Whether the integration failed before the run reached any of its stops (the step
    /// size below `min_step`, a non-finite state, the step budget used up): the outputs are
    /// a flight cut short, not a flight to its end nor a verdict on it. The command line
    /// exits with `EXIT_INCOMPLETE` and a Monte Carlo sample is `incomplete`.
    pub fn is_incomplete(&self) -> bool {
        Self::is_incomplete_code(self.code())
    }

    /// [`RunStop::is_incomplete`] of a stop's code as `summary.json` writes it.
    pub fn is_incomplete_code(code: &str) -> bool {
        matches!(code, "step_underflow" | "non_finite" | "max_steps")
    }

    /// Whether the run ended with a verdict: the vehicle left its model.
    pub fn is_verdict(&self) -> bool {
        matches!(
            self,
            RunStop::Flutter | RunStop::Divergence | RunStop::ModelLimit
        )
    }
}

/// The result of a run.
#[derive(Debug, Clone)]
pub struct RunOutput {
    /// Column names (the plan's channels).
    pub channels: Vec<String>,
    /// Rows at the output times (and a last row at the stop), every value finite.
    pub rows: Vec<Vec<f64>>,
    pub stop: RunStop,
    /// What the integrator or the stop check said, for people.
    pub stop_detail: String,
    /// Time reached, s.
    pub t_end: f64,
    pub stats: StepStats,
    pub wall_seconds: f64,
    /// Flight events located in time (rail exit, burnout, apogee, deployments, landing).
    pub events: FlightEvents,
    /// What happened when the vehicle left its model (stop `flutter`, `divergence` or
    /// `model_limit`); the rows end at it.
    pub verdict: Option<Verdict>,
}

/// The state at a flight event.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EventPoint {
    /// Time, s.
    pub t: f64,
    /// Inertial position of the body origin, m (z down).
    pub position: [f64; 3],
    /// Inertial velocity of the body origin, m/s.
    pub velocity: [f64; 3],
}

impl EventPoint {
    fn of(layout: crate::runtime::eom::StateLayout, t: f64, x: &[f64]) -> Self {
        let s = StateView::new(layout, x);
        EventPoint {
            t,
            position: s.position,
            velocity: mat_t_vec(&s.c_bi, &s.velocity),
        }
    }

    /// `|V_I|`, m/s.
    pub fn speed(&self) -> f64 {
        self.velocity.iter().map(|v| v * v).sum::<f64>().sqrt()
    }

    /// Altitude above sea level, m.
    pub fn altitude(&self) -> f64 {
        -self.position[2]
    }
}

/// The events of a flight, each located on the interpolant of the step that crossed it
/// (bisection to the double-precision resolution of the step, as the stop conditions).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FlightEvents {
    /// The vehicle has travelled the rail length (a rail launch only).
    pub rail_exit: Option<EventPoint>,
    /// The thrust curve's last point.
    pub burnout: Option<EventPoint>,
    /// The vertical velocity changes sign from climbing to descending.
    pub apogee: Option<EventPoint>,
    /// Each recovery device that deployed: its name, the trigger and the deployment.
    pub deployments: Vec<(String, EventPoint, EventPoint)>,
    /// The body origin descended through the ground.
    pub landing: Option<EventPoint>,
}

/// The stop condition the aerodynamic blocks raise at the plan's initial state, if any: an
/// initial condition outside a coefficient table with the `stop` policy, or a fin already
/// beyond its stress limit. Callers report it as a diagnostic before anything runs.
pub fn check_initial_state(plan: &Plan, model: &ReducedModel) -> Option<(RunStop, String)> {
    if plan.initial_state.len() != plan.layout().len() {
        return None; // `run` reports the shape error itself
    }
    let mut probe = AeroProbe::of_plan(plan, model);
    let s = StateView::new(plan.layout(), &plan.initial_state);
    probe.evaluate(0.0, &s, plan.stop.model_limits.fin_yield)
}

/// The force blocks of the plan, in plan order (the aerodynamic ones copied from the plan).
pub fn build_force_blocks(plan: &Plan, model: &ReducedModel) -> Result<ForceBlocks, RunError> {
    let aero = plan.aero.as_ref();
    let mut blocks = Vec::new();
    for f in &plan.forces {
        match f {
            ForcePlan::Gravity(g) => blocks.push(ForceBlock::Gravity(gravity_block(
                plan,
                model,
                g.altitude_correction,
            ))),
            ForcePlan::Thrust(t) => blocks.push(ForceBlock::Thrust(ThrustBlock::new(
                t.curve.clone(),
                t.nozzle_position,
                t.offset,
                t.misalignment,
                &t.s_translation,
                &t.s_rotation,
                plan.n_modes,
            ))),
            ForcePlan::BodyAero { .. } => match aero.and_then(|a| a.body.clone()) {
                Some(b) => blocks.push(ForceBlock::BodyAero(Box::new(b))),
                None => return Err(RunError::ForceBlockUnavailable { block: f.name() }),
            },
            ForcePlan::FinAero { .. } => match aero.and_then(|a| a.fin.clone()) {
                Some(b) => blocks.push(ForceBlock::FinAero(Box::new(b))),
                None => return Err(RunError::ForceBlockUnavailable { block: f.name() }),
            },
        }
    }
    Ok(ForceBlocks::new(blocks))
}

/// The gravity block of `plan`: with a motor, on the burning vehicle's mass properties.
fn gravity_block(plan: &Plan, model: &ReducedModel, altitude_correction: bool) -> GravityBlock {
    match &plan.motor {
        Some(m) => GravityBlock::burning(
            model,
            &m.propellant,
            BurnSchedule::new(m.thrust.curve.clone(), m.propellant_mass),
            altitude_correction,
        ),
        None => GravityBlock::new(model, altitude_correction),
    }
}

/// The motor of `plan` inside the equations of motion (thrust at the nozzle, variable mass,
/// mass-flow terms), if the vehicle has one.
pub fn build_propulsion(plan: &Plan, model: &ReducedModel) -> Result<Option<Propulsion>, RunError> {
    let Some(m) = &plan.motor else {
        return Ok(None);
    };
    let t = &m.thrust;
    let thrust = ThrustBlock::new(
        t.curve.clone(),
        t.nozzle_position,
        t.offset,
        t.misalignment,
        &t.s_translation,
        &t.s_rotation,
        plan.n_modes,
    );
    let exit = [0, 1, 2].map(|i| t.nozzle_position[i] + t.offset[i]);
    Ok(Some(Propulsion::new(
        model,
        m.propellant.clone(),
        BurnSchedule::new(t.curve.clone(), m.propellant_mass),
        thrust,
        exit,
        &t.s_translation,
    )?))
}

/// Evaluates the output channels of a state and the stop conditions (outside the RHS).
struct Monitor<'a> {
    plan: &'a Plan,
    /// The phase the run is in (kept equal to the integrated system's).
    phase: Phase,
    /// A copy of the run's right-hand side, for the acceleration channel at output rows.
    accel: Flight<'a>,
    accel_buf: Vec<f64>,
    static_margin: Option<StaticMargin>,
    eval: Eom<'a, FreeFlight>,
    gravity: Option<GravityBlock>,
    atmosphere: Standard1976,
    /// A copy of the run's aerodynamic blocks, evaluated at accepted states for the stop
    /// conditions they raise (table range, fin stress) and for the aero channels; the RHS
    /// copies are never read from outside the integrator.
    aero: AeroProbe,
    /// What the stop condition saw (for the summary), set with the stop.
    stop_note: Option<String>,
    /// The last angle of attack, degrees, of the body coefficient table when it ends below
    /// 90 deg and the scenario has no recovery device: in free flight, air from behind the
    /// vehicle is then a bound of the model ([`Monitor::stop_condition`]).
    reversed_flow_table_end: Option<f64>,
    /// The stop was the reversed-flow bound: a model limit that no modal growth explains.
    reversed_flow: bool,
    /// `T + ½ηᵀK̄η` at `t = 0` (the energy balance's reference).
    energy0: f64,
    /// The node shapes for the largest elastic displacement.
    deformation: NodeDeformation,
}

/// The aerodynamic blocks of a run outside its right-hand side, and what they gave at the
/// last evaluated state.
struct AeroProbe {
    body: Option<BodyAero>,
    fin: Option<FinAero>,
    /// Undeformed centre of mass, body frame (moment reference of the aero channels).
    cm: [f64; 3],
    buf: Vec<f64>,
    /// Body aero force and moment about `cm`, body axes.
    body_load: [f64; 6],
    /// Fin aero force and moment about `cm` (all fins), body axes.
    fin_load: [f64; 6],
}

impl AeroProbe {
    /// A copy of the plan's aerodynamic blocks.
    fn of_plan(plan: &Plan, model: &ReducedModel) -> Self {
        let aero = plan.aero.as_ref();
        Self::new(
            aero.and_then(|a| a.body.clone()),
            aero.and_then(|a| a.fin.clone()),
            model,
        )
    }

    fn new(body: Option<BodyAero>, fin: Option<FinAero>, model: &ReducedModel) -> Self {
        let m = model.mass.max(f64::MIN_POSITIVE);
        AeroProbe {
            body,
            fin,
            cm: model.first_moment.map(|c| c / m),
            buf: vec![0.0; 6 + model.n()],
            body_load: [0.0; 6],
            fin_load: [0.0; 6],
        }
    }

    /// Force and moment about `cm` from the first six generalised forces (force, moment
    /// about the body origin): `M_cm = M_o - r_cm × F`.
    fn load_about_cm(cm: &[f64; 3], q: &[f64]) -> [f64; 6] {
        let f = [q[0], q[1], q[2]];
        let rf = crate::runtime::kinematics::cross(cm, &f);
        [f[0], f[1], f[2], q[3] - rf[0], q[4] - rf[1], q[5] - rf[2]]
    }

    /// Evaluates the blocks at `(t, state)`; returns a stop condition they raise, with a note.
    fn evaluate(&mut self, t: f64, s: &StateView, yield_limit: bool) -> Option<(RunStop, String)> {
        self.evaluate_with::<true>(t, s, yield_limit)
    }

    /// The stop check of an accepted state: the stop condition [`Self::evaluate`] would
    /// return, from the blocks' check-only evaluations (`BodyAero::check_with`,
    /// `FinAero::check_with`: the faults and the fin root stresses with the same bits, no
    /// loads). The loads and fin samples are not updated: a row reads them after its own
    /// evaluation ([`Monitor::row`]).
    fn check(&mut self, t: f64, s: &StateView, yield_limit: bool) -> Option<(RunStop, String)> {
        self.evaluate_with::<false>(t, s, yield_limit)
    }

    fn evaluate_with<const LOADS: bool>(
        &mut self,
        t: f64,
        s: &StateView,
        yield_limit: bool,
    ) -> Option<(RunStop, String)> {
        use crate::runtime::eom::ForceModel;
        let mut hit = None;
        // One memo for both blocks of a check (the air at one altitude, the same values).
        let mut memo = crate::aero::atmosphere::AirMemo::default();
        if let Some(b) = &mut self.body {
            b.clear_fault();
            if LOADS {
                self.buf.fill(0.0);
                b.generalized_forces(t, s, &mut self.buf);
                self.body_load = Self::load_about_cm(&self.cm, &self.buf);
            } else {
                b.check_with(t, s, &mut memo);
            }
            if let Some(f) = b.fault() {
                hit = hit.or_else(|| fault_stop(f, "body"));
            }
        }
        if let Some(b) = &mut self.fin {
            b.clear_fault();
            if LOADS {
                self.buf.fill(0.0);
                b.generalized_forces(t, s, &mut self.buf);
                self.fin_load = Self::load_about_cm(&self.cm, &self.buf);
            } else {
                b.check_with(t, s, &mut memo);
            }
            if let Some(f) = b.fault() {
                hit = hit.or_else(|| fault_stop(f, "fin"));
            }
            if let Some(i) = b.stress_limit_exceeded() {
                let fraction = b
                    .stress_model(i)
                    .and_then(|m| m.yield_fraction(b.root_stress(i)))
                    .unwrap_or(f64::NAN);
                hit = hit.or_else(|| {
                    Some((
                        RunStop::FinStress,
                        format!(
                            "fin {} root stress {:.4e} Pa = {:.3} of yield",
                            i + 1,
                            b.root_stress(i),
                            fraction
                        ),
                    ))
                });
            }
            if yield_limit {
                if let Some(i) = b.yield_exceeded() {
                    hit = hit.or_else(|| {
                        Some((
                            RunStop::ModelLimit,
                            format!(
                                "fin {} root stress {:.4e} Pa beyond the material's yield stress, the end of linear elasticity",
                                i + 1,
                                b.root_stress(i)
                            ),
                        ))
                    });
                }
            }
        }
        hit
    }

    /// Takes the body and fin loads of an output row from the row's own right-hand side
    /// (its force blocks kept apart, [`ForceBlocks::keep_each`]) instead of evaluating the
    /// blocks again: the same blocks (copies of the plan's) at the same `(t, x)`, each
    /// computed from zero as [`Self::evaluate`] does, so the loads have the same bits.
    /// Returns the fin block whose samples the channels read (`Some(None)` without fins),
    /// or `None` when the flight's blocks lack one of the probe's (a plan whose `forces`
    /// leave an aerodynamic block out: then [`Self::evaluate`] is the way).
    fn loads_from<'b>(&mut self, blocks: &'b ForceBlocks) -> Option<Option<&'b FinAero>> {
        let (mut body, mut fin) = (None, None);
        for (i, b) in blocks.blocks.iter().enumerate() {
            match b {
                ForceBlock::BodyAero(_) => body = body.or(blocks.kept(i)),
                ForceBlock::FinAero(f) => fin = fin.or(blocks.kept(i).map(|q| (q, &**f))),
                _ => {}
            }
        }
        if self.body.is_some() != body.is_some() || self.fin.is_some() != fin.is_some() {
            return None;
        }
        if let Some(q) = body {
            self.body_load = Self::load_about_cm(&self.cm, q);
        }
        if let Some((q, _)) = fin {
            self.fin_load = Self::load_about_cm(&self.cm, q);
        }
        Some(fin.map(|(_, f)| f))
    }

    /// The aero channels of the last evaluation (column order of [`crate::plan::channel_names`]),
    /// the fin samples from `fin` if given, else from the probe's own fin block; the root
    /// stresses zero when the loads are off (`loaded` false: under a canopy).
    fn channels(&self, r: &mut Vec<f64>, fin: Option<&FinAero>, loaded: bool) {
        if self.body.is_some() {
            r.extend_from_slice(&self.body_load);
        }
        if let Some(f) = fin.or(self.fin.as_ref()) {
            r.extend_from_slice(&self.fin_load);
            for i in 0..f.n_fins() {
                let sample = f.last(i).unwrap_or_default();
                r.push(sample.alpha.to_degrees());
                r.push(if loaded { sample.root_stress } else { 0.0 });
            }
        }
    }
}

/// The stop condition of an aerodynamic fault, with a note naming the block.
fn fault_stop(f: AeroFault, block: &str) -> Option<(RunStop, String)> {
    match f {
        AeroFault::TableOutOfRange { axis, value } => Some((
            RunStop::AeroOutOfRange,
            format!(
                "{block} coefficient table queried at {axis:?} = {value} outside its range (policy stop)"
            ),
        )),
        AeroFault::NonFinite => Some((
            RunStop::NonFinite,
            format!("non-finite state in the {block} aerodynamics"),
        )),
        // The altitude range is its own stop condition, checked before.
        AeroFault::Atmosphere { .. } => None,
    }
}

impl Monitor<'_> {
    /// Largest elastic displacement `|S_trans,i η|` over the nodes, m.
    fn max_deformation(&mut self, eta: &[f64]) -> f64 {
        self.deformation.max_displacement(eta)
    }

    /// Airspeed vector relative to the air, body frame (wind from the stimuli).
    fn air_velocity(&self, t: f64, s: &StateView) -> [f64; 3] {
        let (wb, wi) = self.plan.planned_stimuli.wind(t);
        let wi_b = mat_vec(&s.c_bi, &wi);
        [0, 1, 2].map(|i| s.velocity[i] - wb[i] - wi_b[i])
    }

    /// The stop condition met by the accepted state `x`, if any (its note in `stop_note`).
    fn stop_condition(&mut self, t: f64, x: &[f64]) -> Option<RunStop> {
        let s = StateView::new(self.plan.layout(), x);
        let st = &self.plan.stop;
        // The ground stops a run only when the vehicle descends through it: a start on the
        // pad (checked before the run to be able to leave it) is not an impact.
        if st.ground
            && s.position[2] >= -st.ground_altitude
            && mat_t_vec(&s.c_bi, &s.velocity)[2] > 0.0
        {
            return Some(RunStop::Ground);
        }
        let h = -s.position[2];
        if !(ATMOSPHERE_RANGE.0..=ATMOSPHERE_RANGE.1).contains(&h) {
            return Some(RunStop::AtmosphereRange);
        }
        if let Some(limit) = st.max_alpha {
            let v = self.air_velocity(t, &s);
            if v[2].atan2(v[0]).abs() > limit {
                return Some(RunStop::MaxAlpha);
            }
        }
        if let Some(limit) = st.max_deformation {
            if self.deformation.exceeds(s.eta, limit) {
                return Some(RunStop::MaxDeformation);
            }
        }
        if let Some(limit) = st.model_limits.deflection {
            if self.deformation.exceeds(s.eta, limit) {
                self.stop_note = Some(format!(
                    "elastic displacement beyond {limit} m ({}), the small-rotation bound of the linear model",
                    st.model_limits.deflection_basis
                ));
                return Some(RunStop::ModelLimit);
            }
        }
        // Air from behind (total angle of attack beyond 90 deg, the axial airspeed reversed)
        // in free flight, with a body table that ends below 90 deg (a user's or Missile
        // DATCOM's; the built-in tables span every flow direction since AERO_REVISION 8,
        // `aero::estimator::estimator_alpha`) and no recovery device:
        // the table's axial coefficient, a drag along -x for flow from ahead, would push
        // along the flow (a drag doing positive work), and its normal force, clamped at the
        // table's last angle, keeps its size while its direction follows the vanishing
        // crossflow as the flow passes exactly tail first, where by axial symmetry it must
        // be zero (the direction flips and the step size collapses: RockSim's FooBar Test
        // stalled at `max_steps` 0.06 s after apogee). The whole fall is outside the model:
        // a verdict, not a flight on clamped coefficients. With a recovery device the flow
        // that turns near apogee at almost no dynamic pressure (hpr_k1000 passes 160 deg
        // 0.55 s after apogee, before its drogue's 1 s lag) is flown on the clamped
        // coefficients until the device deploys, as before (the plan's `reversed_flow` is
        // off). On the rail the vehicle is held (a tailwind at rest is not flight).
        if let (Phase::Free, Some(end)) = (self.phase, self.reversed_flow_table_end) {
            let v = self.air_velocity(t, &s);
            if v[0] < 0.0 {
                let cross = (v[1] * v[1] + v[2] * v[2]).sqrt();
                let alpha = cross.atan2(v[0]).to_degrees();
                self.stop_note = Some(format!(
                    "air from behind the vehicle (total angle of attack {alpha:.1} deg, through 90 deg) at {h:.1} m with no recovery device: the body coefficient table ends at {end} deg, and a tumbling or tail-first fall is outside the aerodynamic model (a recovery device flies the descent as a point mass)"
                ));
                self.reversed_flow = true;
                return Some(RunStop::ModelLimit);
            }
        }
        // Under a canopy the vehicle's own aerodynamics are off (crate::runtime::flight).
        if self.phase != Phase::Descent {
            if let Some((stop, note)) = self.aero.check(t, &s, st.model_limits.fin_yield) {
                self.stop_note = Some(note);
                return Some(stop);
            }
        }
        None
    }

    /// Density and speed of sound at altitude `h` (zero outside the model). Interpolated
    /// rows can overshoot the model range by a hair before the stop check of the accepted
    /// step catches it: the air is evaluated at the clamped altitude.
    fn air_at(&self, h: f64) -> (f64, f64) {
        let air = self
            .atmosphere
            .at(h.clamp(ATMOSPHERE_RANGE.0, ATMOSPHERE_RANGE.1))
            .ok();
        air.map_or((0.0, 0.0), |a| (a.density, a.speed_of_sound))
    }

    /// The `mach` and `dynamic_pressure` channels of the row at `(t, x)`, by the same
    /// arithmetic as [`Self::row`] (so the same bits), without the rest of the row.
    fn peak_channels(&self, t: f64, x: &mut [f64]) -> (f64, f64) {
        normalize_euler_parameters(&mut x[3..7]);
        let s = StateView::new(self.plan.layout(), x);
        let v = self.air_velocity(t, &s);
        let speed = v.iter().map(|c| c * c).sum::<f64>().sqrt();
        let (rho, a) = self.air_at(-s.position[2]);
        mach_and_q(speed, rho, a)
    }

    /// One row of channels (column order of [`crate::plan::channel_names`]).
    fn row(&mut self, t: f64, x: &mut [f64]) -> Result<Vec<f64>, EomError> {
        normalize_euler_parameters(&mut x[3..7]);
        let layout = self.plan.layout();
        let inv = self.eval.invariants_at(t, x)?;
        if let Some(g) = &mut self.gravity {
            g.set_time(t);
        }
        let s = StateView::new(layout, x);
        let mut r = Vec::with_capacity(self.plan.channels.len());
        r.push(t);
        r.extend_from_slice(&s.position);
        r.extend_from_slice(&s.velocity);
        r.extend_from_slice(&s.angular_velocity);
        r.extend(euler_angles(&s.c_bi).map(f64::to_degrees));
        let q = s.attitude;
        r.extend_from_slice(&[q[3], q[0], q[1], q[2]]);
        let v = self.air_velocity(t, &s);
        let speed = v.iter().map(|c| c * c).sum::<f64>().sqrt();
        let (alpha, beta) = if speed > 0.0 {
            (v[2].atan2(v[0]), (v[1] / speed).clamp(-1.0, 1.0).asin())
        } else {
            (0.0, 0.0)
        };
        r.push(alpha.to_degrees());
        r.push(beta.to_degrees());
        let h = -s.position[2];
        let (rho, a) = self.air_at(h);
        let (mach, q) = mach_and_q(speed, rho, a);
        r.push(mach);
        r.push(q);
        r.push(h);
        r.push(rho);
        r.push(a);
        r.extend_from_slice(s.eta);
        r.extend_from_slice(s.eta_dot);
        r.push(self.max_deformation(s.eta));
        let gravitational = self
            .gravity
            .as_ref()
            .map_or(0.0, |g| g.potential_energy(&s));
        r.push(inv.kinetic_energy);
        r.push(inv.strain_energy);
        r.push(gravitational);
        r.push(inv.total_energy() + gravitational);
        r.extend_from_slice(&inv.momentum_body);
        r.extend_from_slice(&inv.momentum_inertial);
        r.extend_from_slice(&inv.angular_momentum_cm_body);
        r.extend_from_slice(&inv.angular_momentum_cm_inertial);
        r.push(inv.mass);
        r.extend_from_slice(&inv.centre_of_mass_body);
        // The works integrated with the state (`Eom::track_energy`) and the balance's
        // residual `Δ(T + ½ηᵀK̄η) - W_loads - W_propulsive + D`.
        let e = layout.len();
        let (w_loads, w_prop, diss) = match x.get(e..e + EnergyLayout::LEN) {
            Some(w) => (
                w[EnergyLayout::LOADS],
                w[EnergyLayout::PROPULSIVE],
                w[EnergyLayout::DISSIPATED],
            ),
            None => (f64::NAN, f64::NAN, f64::NAN),
        };
        r.push(w_loads);
        r.push(w_prop);
        r.push(diss);
        r.push(inv.total_energy() - self.energy0 - w_loads - w_prop + diss);
        // The row's right-hand side (for the acceleration below); its force blocks are kept
        // apart, so the aero channels read their loads from it.
        let rhs = self.accel.rhs(t, x, &mut self.accel_buf);
        // The aero channels at this state (a stop raised here is the step check's business).
        if self.phase == Phase::Descent {
            // Under a canopy the vehicle's aerodynamics are off: no loads, no root stress;
            // the fin angles of attack are those of the current air-relative velocity.
            let _ = self.aero.evaluate(t, &s, false);
            self.aero.body_load = [0.0; 6];
            self.aero.fin_load = [0.0; 6];
            self.aero.channels(&mut r, None, false);
        } else {
            match self.aero.loads_from(&self.accel.eom.forces) {
                Some(fin) => self.aero.channels(&mut r, fin, true),
                None => {
                    let _ = self.aero.evaluate(t, &s, false);
                    self.aero.channels(&mut r, None, true);
                }
            }
        }
        // Flight channels: inertial speed and acceleration of the origin,
        // d/dt (C_IB V_B) = C_IB (V̇_B + ω_B × V_B), from the run's own right-hand side.
        let v_i = mat_t_vec(&s.c_bi, &s.velocity);
        r.push(v_i.iter().map(|c| c * c).sum::<f64>().sqrt());
        let acc = match rhs {
            Ok(()) => {
                let vd = [self.accel_buf[7], self.accel_buf[8], self.accel_buf[9]];
                let wv = cross(&s.angular_velocity, &s.velocity);
                let a_b = [0, 1, 2].map(|k| vd[k] + wv[k]);
                a_b.iter().map(|c| c * c).sum::<f64>().sqrt()
            }
            Err(_) => f64::NAN,
        };
        r.push(acc);
        r.push(h - self.plan.stop.ground_altitude);
        if let Some(sm) = &self.static_margin {
            let m = if a > 0.0 { speed / a } else { 0.0 };
            // The undeformed centre of mass at this time (`invariants_at` set the fraction).
            let (mass, c) = self.eval.mass_properties(&[]);
            r.push(sm.calibres(m, h, c[0] / mass).unwrap_or(f64::NAN));
        }
        Ok(r)
    }
}

/// The Mach number and dynamic pressure of an airspeed `speed` in air of density `rho` and
/// speed of sound `a` (Mach 0 outside the atmosphere model, where `a` is 0).
fn mach_and_q(speed: f64, rho: f64, a: f64) -> (f64, f64) {
    (
        if a > 0.0 { speed / a } else { 0.0 },
        0.5 * rho * speed * speed,
    )
}

/// What a run without its rows under canopies ([`run_without_descent_rows`]) keeps of the
/// rows it did not compute: the first maximum `(value, t)` over them of the `mach` and
/// `dynamic_pressure` channels, the same bits as those channels of the rows a full run
/// writes there.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DescentPeaks {
    /// Rows skipped.
    pub rows: usize,
    pub mach: Option<(f64, f64)>,
    pub dynamic_pressure: Option<(f64, f64)>,
}

impl DescentPeaks {
    fn add(&mut self, t: f64, (mach, q): (f64, f64)) {
        self.rows += 1;
        if self.mach.is_none_or(|(m, _)| mach > m) {
            self.mach = Some((mach, t));
        }
        if self.dynamic_pressure.is_none_or(|(p, _)| q > p) {
            self.dynamic_pressure = Some((q, t));
        }
    }
}

/// Cubic Hermite interpolation between `(t0, x0, d0)` and `(t1, x1, d1)` at `t`.
/// One end of an accepted step: time, state, derivative.
type StepEnd<'a> = (f64, &'a [f64], &'a [f64]);

/// The accepted step the observer is looking at: its end `(t, x, ẋ)` and the integrator's
/// continuous extension over it, if the method has one (else the cubic Hermite of the step
/// ends from the driver's previous state).
type Step<'a, 'd> = (f64, &'a [f64], &'a [f64], Option<&'d dyn DenseOutput>);

fn hermite((t0, x0, d0): StepEnd, (t1, x1, d1): StepEnd, t: f64, out: &mut [f64]) {
    let h = t1 - t0;
    let s = if h > 0.0 { (t - t0) / h } else { 1.0 };
    let (s2, s3) = (s * s, s * s * s);
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = -2.0 * s3 + 3.0 * s2;
    let h11 = s3 - s2;
    for i in 0..out.len() {
        out[i] = h00 * x0[i] + h10 * h * d0[i] + h01 * x1[i] + h11 * h * d1[i];
    }
}

/// Upward vertical speed `-ż` of the origin (z down), m/s.
fn climb_rate(layout: crate::runtime::eom::StateLayout, x: &[f64]) -> f64 {
    let s = StateView::new(layout, x);
    -mat_t_vec(&s.c_bi, &s.velocity)[2]
}

/// Bisection for the first time in `(lo, hi]` where `pred` holds, given it fails at `lo`
/// and holds at `hi` (64 halvings: the double-precision resolution of the interval).
fn bisect(mut lo: f64, mut hi: f64, mut pred: impl FnMut(f64) -> bool) -> f64 {
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if pred(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// What ends an integration segment before the stop: the equations of motion change.
#[derive(Debug, Clone, PartialEq)]
enum SegmentEnd {
    /// The vehicle leaves the rail: free flight from here.
    RailExit,
    /// These recovery devices deploy: the point-mass descent from here.
    Deploy(Vec<usize>),
}

/// The observer's state across the accepted steps and segments of a run.
struct Driver<'a, 'p> {
    plan: &'p Plan,
    monitor: Monitor<'a>,
    layout: crate::runtime::eom::StateLayout,
    rows: Vec<Vec<f64>>,
    prev: Option<(f64, Vec<f64>, Vec<f64>)>,
    next_k: u64,
    last_row_t: f64,
    stop_cond: Option<RunStop>,
    stopped_at: Option<f64>,
    row_error: Option<EomError>,
    scratch: Vec<f64>,
    eps: f64,
    t_end: f64,
    dt_out: f64,
    /// Burnout time (the thrust curve's last point), if the vehicle has thrust.
    burn_time: Option<f64>,
    apogee_armed: bool,
    events: FlightEvents,
    /// Per recovery device: its trigger point and deployment time, once triggered.
    triggered: Vec<Option<(EventPoint, f64)>>,
    deployed: Vec<bool>,
    /// The segment end met in the last step, its time and state.
    segment: Option<(SegmentEnd, f64, Vec<f64>)>,
    progress: &'a mut dyn FnMut(f64, f64),
    /// Called with every history row as it is appended (see [`run_with_rows`]).
    on_row: &'a mut dyn FnMut(&[f64]),
    /// The modal state at the last accepted steps, for a verdict's growth rates.
    trace: ModalTrace,
    /// `Some`: rows under a canopy are not computed, only their Mach and q peaks kept.
    descent_peaks: Option<DescentPeaks>,
}

impl Driver<'_, '_> {
    fn interp(&mut self, step: Step, tau: f64) {
        let (t, xs, dx, dense) = step;
        match (&self.prev, dense) {
            (_, Some(d)) if tau < t && tau >= d.t_start() => d.eval(tau, &mut self.scratch),
            (Some((tp, xp, dp)), None) if tau < t => {
                hermite((*tp, xp, dp), (t, xs, dx), tau, &mut self.scratch)
            }
            _ => self.scratch.copy_from_slice(xs),
        }
    }

    /// First time in `(tp, t]` where `pred(τ, x(τ))` holds on the step's interpolant, if it
    /// holds at `t`.
    fn locate(
        &mut self,
        step: Step,
        mut pred: impl FnMut(&Self, f64, &[f64]) -> bool,
    ) -> Option<f64> {
        let (t, xs, dx, dense) = step;
        if self.prev.is_none() || !pred(self, t, xs) {
            return None;
        }
        let (tp, xp, dp) = self.prev.take()?;
        let mut buf = std::mem::take(&mut self.scratch);
        let hit = bisect(tp, t, |tau| {
            match dense {
                Some(d) => d.eval(tau, &mut buf),
                None => hermite((tp, &xp, &dp), (t, xs, dx), tau, &mut buf),
            }
            pred(self, tau, &buf)
        });
        self.scratch = buf;
        self.prev = Some((tp, xp, dp));
        Some(hit)
    }

    fn rail_distance(&self, x: &[f64]) -> f64 {
        match &self.plan.launch {
            Some(l) => (0..3)
                .map(|k| (x[k] - l.start[k]) * l.rail_direction[k])
                .sum(),
            None => 0.0,
        }
    }

    fn event_point(&mut self, step: Step, tau: f64) -> EventPoint {
        self.interp(step, tau);
        EventPoint::of(self.layout, tau, &self.scratch)
    }

    /// The observer: stops, segment ends and events located in the accepted step
    /// `(t_prev, t]`, then the output rows up to the first of them.
    fn observe(&mut self, t: f64, xs: &[f64], dx: &[f64], dense: Option<&dyn DenseOutput>) -> bool {
        let step: Step = (t, xs, dx, dense);
        let mut hit = self.monitor.stop_condition(t, xs);
        // A stop inside this step: locate the first state that meets a condition by
        // bisection on the step's interpolant (the step start met none).
        let mut t_stop = t;
        if let (Some(_), Some((tp, xp, dp))) = (hit, &self.prev) {
            let (mut lo, mut hi) = (*tp, t);
            for _ in 0..64 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                match dense {
                    Some(d) => d.eval(mid, &mut self.scratch),
                    None => hermite((*tp, xp, dp), (t, xs, dx), mid, &mut self.scratch),
                }
                match self.monitor.stop_condition(mid, &self.scratch) {
                    Some(reason) => {
                        hi = mid;
                        hit = Some(reason);
                    }
                    None => lo = mid,
                }
            }
            t_stop = hi;
        }
        let mut t_lim = if hit.is_some() { t_stop } else { t };
        let mut segment: Option<(SegmentEnd, f64)> = None;
        // Rail exit.
        if self.monitor.phase == Phase::Rail {
            let length = self.plan.launch.as_ref().map_or(0.0, |l| l.rail_length);
            if let Some(te) = self.locate(step, |d, _, x| d.rail_distance(x) >= length) {
                if te < t_lim || (hit.is_none() && te <= t_lim) {
                    t_lim = te;
                    segment = Some((SegmentEnd::RailExit, te));
                    hit = None;
                }
            }
        }
        // Events that only get recorded (burnout, apogee, triggers), in (t_prev, t_lim].
        let tp = self.prev.as_ref().map(|p| p.0);
        let mut burnout = None;
        let mut apogee = None;
        let mut triggers: Vec<(usize, EventPoint, f64)> = Vec::new();
        if let Some(tp) = tp {
            if let Some(tb) = self.burn_time {
                if self.events.burnout.is_none() && tb > tp && tb <= t_lim {
                    burnout = Some(self.event_point(step, tb));
                }
            }
            if self.apogee_armed
                && self.events.apogee.is_none()
                && self.monitor.phase != Phase::Rail
            {
                let layout = self.layout;
                if let Some(ta) = self.locate(step, |_, _, x| climb_rate(layout, x) <= 0.0) {
                    if ta <= t_lim {
                        apogee = Some(self.event_point(step, ta));
                    }
                }
            }
            let t_apogee = self.events.apogee.or(apogee).map(|a| a.t);
            for i in 0..self.plan.parachutes.len() {
                if self.triggered[i].is_some() {
                    continue;
                }
                let c = &self.plan.parachutes[i];
                let (trigger, lag) = (c.trigger, c.lag);
                let at = match trigger {
                    crate::check::ir::Trigger::Apogee => apogee.map(|a| a.t),
                    crate::check::ir::Trigger::Time(tt) => (tt <= t_lim).then_some(tt.max(tp)),
                    crate::check::ir::Trigger::Altitude(h) => match t_apogee {
                        Some(ta) => {
                            let g = self.plan.stop.ground_altitude;
                            self.locate(step, |_, tau, x| tau >= ta && -x[2] - g <= h)
                        }
                        None => None,
                    },
                };
                if let Some(at) = at.filter(|&a| a <= t_lim) {
                    let p = self.event_point(step, at);
                    triggers.push((i, p, at + lag));
                }
            }
        }
        // Deployments due in this step (already triggered, or just now).
        let mut due: Vec<(usize, f64)> = Vec::new();
        if let Some(tp) = tp {
            for (i, tr) in self.triggered.iter().enumerate() {
                if let Some((_, td)) = tr {
                    if !self.deployed[i] && *td <= t_lim {
                        due.push((i, td.max(tp)));
                    }
                }
            }
        }
        for (i, _, td) in &triggers {
            if *td <= t_lim {
                due.push((*i, *td));
            }
        }
        if let Some(td) = due.iter().map(|d| d.1).reduce(f64::min) {
            if td < t_lim || (hit.is_none() && td <= t_lim) {
                t_lim = td;
                hit = None;
                let ids = due.iter().filter(|d| d.1 <= td).map(|d| d.0).collect();
                segment = Some((SegmentEnd::Deploy(ids), td));
            }
        }
        if hit.is_some() {
            t_stop = t_lim;
        }
        // Commit the recorded events up to the end of this step's flight.
        if let Some(b) = burnout.filter(|b| b.t <= t_lim) {
            self.events.burnout = Some(b);
        }
        if let Some(a) = apogee.filter(|a| a.t <= t_lim) {
            self.events.apogee = Some(a);
        }
        for (i, p, td) in triggers {
            if p.t <= t_lim {
                self.triggered[i] = Some((p, td));
            }
        }
        if climb_rate(self.layout, xs) > 0.0 && segment.is_none() && hit.is_none() {
            self.apogee_armed = true;
        }
        let cut = hit.is_some() || segment.is_some();
        // Output times in (t_prev, t] (and t = 0 at the start) up to the stop time; when
        // a condition or a segment end cuts the step, the rows end with that state (below).
        loop {
            let tk = self.next_k as f64 * self.dt_out;
            if tk > t + self.eps || tk > self.t_end + self.eps || (cut && tk >= t_lim - self.eps) {
                break;
            }
            if tk <= self.last_row_t + self.eps {
                self.next_k += 1;
                continue;
            }
            let tk = if (tk - t).abs() <= self.eps { t } else { tk };
            self.interp(step, tk);
            let mut row_state = std::mem::take(&mut self.scratch);
            if let (Some(peaks), Phase::Descent) = (&mut self.descent_peaks, self.monitor.phase) {
                peaks.add(tk, self.monitor.peak_channels(tk, &mut row_state));
                self.scratch = row_state;
                self.last_row_t = tk;
                self.next_k += 1;
                continue;
            }
            let r = self.monitor.row(tk, &mut row_state);
            self.scratch = row_state;
            match r {
                Ok(r) if r.iter().all(|v| v.is_finite()) => {
                    (self.on_row)(&r);
                    self.rows.push(r);
                    self.last_row_t = tk;
                }
                Ok(_) => {
                    self.stop_cond = Some(RunStop::NonFinite);
                    return false;
                }
                Err(e) => {
                    self.row_error = Some(e);
                    return false;
                }
            }
            self.next_k += 1;
        }
        if cut {
            self.interp(step, t_lim);
            let mut row_state = std::mem::take(&mut self.scratch);
            let lean = self.descent_peaks.is_some() && self.monitor.phase == Phase::Descent;
            if lean {
                // The same normalisation of the state as `row` (the landing point and a
                // segment's state are read from it).
                let channels = self.monitor.peak_channels(t_lim, &mut row_state);
                let fresh = t_lim > self.last_row_t + self.eps;
                if let (true, Some(peaks)) = (fresh, &mut self.descent_peaks) {
                    peaks.add(t_lim, channels);
                    self.last_row_t = t_lim;
                }
            } else if let Ok(r) = self.monitor.row(t_lim, &mut row_state) {
                if r.iter().all(|v| v.is_finite()) && t_lim > self.last_row_t + self.eps {
                    (self.on_row)(&r);
                    self.rows.push(r);
                    self.last_row_t = t_lim;
                }
            }
            if let Some(stop) = hit {
                if stop == RunStop::ModelLimit {
                    self.trace.push(self.layout, t_lim, &row_state);
                }
                if stop == RunStop::Ground {
                    self.events.landing = Some(EventPoint::of(self.layout, t_lim, &row_state));
                }
                self.stop_cond = Some(stop);
                self.stopped_at = Some(t_stop);
            } else if let Some((kind, te)) = segment {
                self.segment = Some((kind, te, row_state.clone()));
            }
            self.scratch = row_state;
            return false;
        }
        if self.monitor.phase != Phase::Descent {
            self.trace.push(self.layout, t, xs);
        }
        match &mut self.prev {
            Some((tp, xp, dp)) => {
                *tp = t;
                xp.copy_from_slice(xs);
                dp.copy_from_slice(dx);
            }
            None => self.prev = Some((t, xs.to_vec(), dx.to_vec())),
        }
        (self.progress)(t, self.t_end);
        true
    }
}

/// The upward speed and acceleration of the origin at the plan's initial state, m/s and
/// m/s^2, from the run's own right-hand side in its first phase.
fn initial_climb(flight: &mut Flight, x: &[f64]) -> Result<(f64, f64), RunError> {
    let layout = flight.eom.layout();
    let mut dx = vec![0.0; x.len()];
    flight
        .rhs(0.0, x, &mut dx)
        .map_err(|_| RunError::InitialState {
            expected: layout.len(),
            found: x.len(),
        })?;
    let s = StateView::new(layout, x);
    let vd = [dx[7], dx[8], dx[9]];
    let wv = cross(&s.angular_velocity, &s.velocity);
    let a_i = mat_t_vec(&s.c_bi, &[vd[0] + wv[0], vd[1] + wv[1], vd[2] + wv[2]]);
    Ok((climb_rate(layout, x), -a_i[2]))
}

/// Runs the plan on `model`. `progress(t, t_end)` is called after each accepted step.
///
/// The run is integrated in segments: a rail launch first integrates the rail phase until
/// the rail exit, then free flight; the first deployment of a recovery device switches to
/// the descent (crate::runtime::flight). Each segment restarts the integrator at the event,
/// so no step straddles a change of the equations of motion.
pub fn run(
    plan: &Plan,
    model: &ReducedModel,
    progress: &mut dyn FnMut(f64, f64),
) -> Result<RunOutput, RunError> {
    run_with_rows(plan, model, progress, &mut |_| {})
}

/// [`run`], with `on_row(row)` called for every row of the history as it is appended, in
/// order: the rows it sees are exactly `RunOutput::rows` (rows are only ever appended), so a
/// caller can format or analyse them on another thread while the flight goes on
/// (`flexflight run` writes `history.csv`'s text that way).
pub fn run_with_rows(
    plan: &Plan,
    model: &ReducedModel,
    progress: &mut dyn FnMut(f64, f64),
    on_row: &mut dyn FnMut(&[f64]),
) -> Result<RunOutput, RunError> {
    run_inner(plan, model, progress, on_row, false).map(|(o, _)| o)
}

/// [`run`] without the rows under a canopy (after the first deployment), for a caller that
/// reads only the flight's events and the rows before it (a Monte Carlo sample:
/// `ops::montecarlo`): the integration, the events and the rows up to the deployment are
/// the same bits as [`run`]'s; of the rows not computed the Mach number's and the dynamic
/// pressure's first maxima are returned ([`DescentPeaks`]). A row is most of the cost of a
/// step under a canopy (its right-hand side, invariants, aero and static margin channels),
/// and 10 ms rows over a 150 s descent are thousands. What is lost: the skipped rows'
/// other channels and the check that they are finite (a full run stops `non_finite` at a
/// non-finite row; the integrator's own check of the state still stops this one).
pub fn run_without_descent_rows(
    plan: &Plan,
    model: &ReducedModel,
) -> Result<(RunOutput, DescentPeaks), RunError> {
    run_inner(plan, model, &mut |_, _| {}, &mut |_| {}, true)
        .map(|(o, p)| (o, p.unwrap_or_default()))
}

fn run_inner(
    plan: &Plan,
    model: &ReducedModel,
    progress: &mut dyn FnMut(f64, f64),
    on_row: &mut dyn FnMut(&[f64]),
    lean_descent: bool,
) -> Result<(RunOutput, Option<DescentPeaks>), RunError> {
    let started = Instant::now();
    let probe = AeroProbe::of_plan(plan, model);
    let static_margin = plan.static_margin.clone();
    let forces = build_force_blocks(plan, model)?;
    let mut eom = Eom::new(model, forces)?.track_energy();
    let mut eval = Eom::new(model, FreeFlight)?;
    if let Some(p) = build_propulsion(plan, model)? {
        eom = eom.with_propulsion(p.clone())?;
        eval = eval.with_propulsion(p)?;
    }
    let layout = eom.layout();
    // The state with the works of the energy balance appended (they start at zero).
    let dim = eom.dim();
    if plan.initial_state.len() != layout.len() {
        return Err(RunError::InitialState {
            expected: layout.len(),
            found: plan.initial_state.len(),
        });
    }
    let first_phase = match &plan.launch {
        Some(l) if l.rail_length > 0.0 => Phase::Rail,
        _ => Phase::Free,
    };
    let mut flight = Flight::new(eom, first_phase, plan.planned_stimuli.clone());
    // A start on or below the ground must be able to leave it: climbing, or at rest with
    // an upward acceleration (a rail launch waits on the rail's foot instead, and the plan
    // has checked its thrust can lift it).
    let mut x = plan.initial_state.clone();
    x.resize(dim, 0.0);
    let energy0 = eval.invariants_at(0.0, &plan.initial_state)?.total_energy();
    let h0 = -plan.initial_state[2];
    if plan.stop.ground && h0 <= plan.stop.ground_altitude && first_phase != Phase::Rail {
        let (climb, climb_acc) = initial_climb(&mut flight, &x)?;
        if !(climb > 0.0 || (climb == 0.0 && climb_acc > 0.0)) {
            return Err(RunError::CannotLeaveGround {
                altitude: h0,
                ground: plan.stop.ground_altitude,
                climb_rate: climb,
                climb_acceleration: climb_acc,
            });
        }
    }
    let monitor = Monitor {
        plan,
        phase: first_phase,
        accel: {
            let mut a = flight.clone();
            let d = 6 + a.eom.layout().n;
            a.eom.forces.keep_each(d);
            a
        },
        accel_buf: vec![0.0; dim],
        static_margin,
        eval,
        gravity: plan
            .gravity()
            .map(|g| gravity_block(plan, model, g.altitude_correction)),
        atmosphere: Standard1976::new(),
        reversed_flow_table_end: probe
            .body
            .as_ref()
            .filter(|_| plan.stop.model_limits.reversed_flow)
            .and_then(|b| {
                let a = b.table().axis(crate::aero::tables::Axis::AlphaDeg);
                a.last().copied().filter(|&end| end < 90.0)
            }),
        aero: probe,
        stop_note: None,
        reversed_flow: false,
        energy0,
        deformation: NodeDeformation::new(&plan.node_translation_shapes, plan.n_modes),
    };
    let adaptive = AdaptiveOptions {
        rtol: plan.integrator.rtol,
        atol: plan.integrator.atol,
        h_initial: (plan.integrator.step > 0.0).then_some(plan.integrator.step),
        h_min: plan.integrator.min_step,
        // A run that needs more steps than this has gone stiff or unstable: stop it with
        // `max_steps` rather than let it grind for many minutes.
        max_steps: 2_000_000,
        ..AdaptiveOptions::default()
    };
    let make_integrator = || -> Box<dyn Integrator> {
        match plan.integrator.method {
            ir::Integrator::Dopri5 => Box::new(DormandPrince54::new(adaptive)),
            ir::Integrator::Dop853 => Box::new(Dop853::new(adaptive)),
            ir::Integrator::Rk4 => Box::new(Rk4::new(plan.integrator.step)),
            ir::Integrator::Exponential => Box::new(Exponential::new(adaptive)),
        }
    };

    let t_end = plan.stop.stop_time;
    let dt_out = plan.output_interval;
    let burn_time = plan
        .motor
        .as_ref()
        .map(|m| m.thrust.burn_time)
        .or_else(|| {
            plan.forces.iter().find_map(|f| match f {
                ForcePlan::Thrust(t) => Some(t.burn_time),
                _ => None,
            })
        })
        .filter(|&t| t > 0.0);
    let mut driver = Driver {
        plan,
        monitor,
        layout,
        rows: Vec::new(),
        prev: None,
        next_k: 0,
        last_row_t: f64::NEG_INFINITY,
        stop_cond: None,
        stopped_at: None,
        row_error: None,
        scratch: vec![0.0; dim],
        eps: 1e-9 * dt_out,
        t_end,
        dt_out,
        burn_time,
        apogee_armed: climb_rate(layout, &plan.initial_state) > 0.0,
        events: FlightEvents::default(),
        triggered: vec![None; plan.parachutes.len()],
        deployed: vec![false; plan.parachutes.len()],
        segment: None,
        progress,
        on_row,
        trace: ModalTrace::new(layout.n, TRACE_CAPACITY),
        descent_peaks: lean_descent.then(DescentPeaks::default),
    };
    // The thrust curve's points: the right-hand side is only continuous there (a kink of
    // the piecewise-linear curve) or jumps (ignition, burnout). A step across such a point
    // has a local error of the order of `h² Δf'` that the embedded estimates of the
    // Runge-Kutta pairs can miss (measured: DOPRI5 at atol 1e-11 was 3e-4 m/s off the
    // reference after the M1670's points at 0.15 and 0.2 s, thirty times its error at
    // 1e-9), so each segment is also cut at every point and the integrator restarted
    // there, as at the events. The same for the gusts' switch times (a rectangular pulse
    // jumps at both ends: DOP853 at rtol 1e-10 underflowed its step at the first onset).
    let gust_switches: Vec<f64> = {
        let mut g: Vec<f64> = plan
            .planned_stimuli
            .switch_times()
            .filter(|&t| t > 0.0 && t < t_end)
            .collect();
        g.sort_by(f64::total_cmp);
        g.dedup();
        g
    };
    let breakpoints: Vec<f64> = {
        let mut b: Vec<f64> = plan
            .motor
            .as_ref()
            .map(|m| &m.thrust.curve)
            .into_iter()
            .chain(plan.forces.iter().filter_map(|f| match f {
                ForcePlan::Thrust(t) => Some(&t.curve),
                _ => None,
            }))
            .flat_map(|c| c.times().iter().copied())
            .filter(|&t| t > 0.0 && t < t_end)
            .chain(gust_switches.iter().copied())
            .collect();
        b.sort_by(f64::total_cmp);
        b.dedup();
        b
    };
    let mut t0 = 0.0;
    let mut stats = StepStats::default();
    let report = loop {
        let mut integrator = make_integrator();
        let t_seg = breakpoints
            .iter()
            .copied()
            .find(|&b| b > t0)
            .unwrap_or(t_end);
        // At a gust's switch time the segment's end takes the wind's left-hand limit.
        flight.set_wind_left_of(
            gust_switches
                .binary_search_by(|g| g.total_cmp(&t_seg))
                .is_ok()
                .then_some(t_seg),
        );
        let report = {
            let mut observer = |t: f64, xs: &[f64], dx: &[f64], dense: Option<&dyn DenseOutput>| {
                driver.observe(t, xs, dx, dense)
            };
            integrator.integrate_dense(&mut flight, t0, &mut x, t_seg, &mut observer)
        };
        stats.accepted += report.stats.accepted;
        stats.rejected += report.stats.rejected;
        stats.rhs_evaluations += report.stats.rhs_evaluations;
        let Some((kind, te, xe)) = driver.segment.take() else {
            if t_seg < t_end && matches!(report.stop, StopReason::Completed) {
                // At a thrust-curve point or a gust's switch time (`x` is the state
                // there): the same equations from here, a fresh integrator. The next
                // segment starts one ulp later, so that its first evaluation takes the
                // right-hand limit where the forcing jumps (a curve ending at a non-zero
                // thrust: `thrust_at` of the last point is the left value, which the
                // segment before ends on; a sine pulse's end); the shift moves the state by
                // `ulp(t) |ẋ|`, below its own round-off.
                driver.prev = None;
                t0 = f64::from_bits(t_seg.to_bits() + 1);
                continue;
            }
            break report;
        };
        x.copy_from_slice(&xe);
        match kind {
            SegmentEnd::RailExit => {
                driver.events.rail_exit = Some(EventPoint::of(layout, te, &x));
                flight.phase = Phase::Free;
            }
            SegmentEnd::Deploy(ids) => {
                for i in ids {
                    driver.deployed[i] = true;
                    flight.cd_area += plan.parachutes[i].cd_area;
                    let trigger = driver.triggered[i].map_or_else(EventPoint::default, |p| p.0);
                    driver.events.deployments.push((
                        plan.parachutes[i].name.clone(),
                        trigger,
                        EventPoint::of(layout, te, &x),
                    ));
                }
                // Frozen to a rigid body at its attitude of this instant, keeping its linear
                // momentum: every point then moves with the mass centre's velocity
                // `p_B / m` (which includes the elastic and rotational contributions). The
                // kinetic energy of the motion relative to the mass centre and the strain
                // energy this removes (>= 0, Koenig's theorem) are booked as dissipated
                // (absorbed by the opening), so the energy balance stays closed.
                let n = layout.n;
                let inv = driver.monitor.eval.invariants_at(te, &x)?;
                let before = inv.total_energy();
                for k in 0..3 {
                    x[7 + k] = inv.momentum_body[k] / inv.mass;
                }
                x[10..13].fill(0.0);
                x[13..13 + 2 * n].fill(0.0);
                let after = driver.monitor.eval.invariants_at(te, &x)?.total_energy();
                if let Some(d) = x.get_mut(layout.len() + EnergyLayout::DISSIPATED) {
                    *d += before - after;
                }
                flight.phase = Phase::Descent;
            }
        }
        driver.monitor.phase = flight.phase;
        driver.monitor.accel.phase = flight.phase;
        driver.monitor.accel.cd_area = flight.cd_area;
        driver.prev = None;
        driver.apogee_armed |= climb_rate(layout, &x) > 0.0;
        t0 = te;
    };
    let Driver {
        mut monitor,
        mut rows,
        last_row_t,
        stop_cond,
        stopped_at,
        row_error,
        eps,
        events,
        on_row,
        trace,
        mut descent_peaks,
        ..
    } = driver;
    if let Some(e) = row_error {
        return Err(RunError::Eom(e));
    }
    // A bound of the model crossed: what the modes did on the way there.
    let verdict = match (stop_cond, stopped_at) {
        // The reversed-flow bound is the flow's, not the structure's: no modal analysis.
        (Some(RunStop::ModelLimit), Some(t)) if monitor.reversed_flow => Some(Verdict {
            kind: VerdictKind::ModelLimit,
            t,
            criterion: monitor.stop_note.clone().unwrap_or_default(),
            modes: Vec::new(),
            window: 0.0,
            flow: true,
        }),
        (Some(RunStop::ModelLimit), Some(t)) => Some(trace.verdict(
            t,
            monitor.stop_note.clone().unwrap_or_default(),
            &model.modal_mass,
            &model.modal_stiffness,
        )),
        _ => None,
    };
    let stop_cond = match &verdict {
        Some(v) => Some(match v.kind {
            VerdictKind::Flutter => RunStop::Flutter,
            VerdictKind::Divergence => RunStop::Divergence,
            VerdictKind::ModelLimit => RunStop::ModelLimit,
        }),
        None => stop_cond,
    };
    let (stop, detail) = match (stop_cond, report.stop) {
        (Some(s), _) => (
            s,
            match &monitor.stop_note {
                Some(note) => format!(
                    "{} at t = {} s: {note}",
                    s.code(),
                    stopped_at.unwrap_or(report.t)
                ),
                None => format!("{} at t = {} s", s.code(), stopped_at.unwrap_or(report.t)),
            },
        ),
        (None, StopReason::Completed) => (RunStop::Completed, "reached the stop time".into()),
        (None, StopReason::StepSizeUnderflow { t, h }) => (
            RunStop::StepUnderflow,
            format!("step size {h:e} s below the minimum at t = {t} s"),
        ),
        (None, StopReason::NonFiniteState { t }) => {
            (RunStop::NonFinite, format!("non-finite state at t = {t} s"))
        }
        (None, StopReason::Rhs { t, error }) => {
            (RunStop::NonFinite, format!("at t = {t} s: {error}"))
        }
        (None, StopReason::MaxSteps { t }) => (
            RunStop::MaxSteps,
            format!("step budget used up at t = {t} s"),
        ),
        (None, other) => (RunStop::NonFinite, format!("{other:?}")),
    };
    // The integrator leaves `x` at the last accepted state (the stop time, or where an
    // underflow or non-finite trial stopped it): close the history there.
    if stopped_at.is_none() && last_row_t < report.t - eps && x.iter().all(|v| v.is_finite()) {
        if let (Some(peaks), Phase::Descent) = (&mut descent_peaks, monitor.phase) {
            peaks.add(report.t, monitor.peak_channels(report.t, &mut x));
        } else if let Ok(r) = monitor.row(report.t, &mut x) {
            if r.iter().all(|v| v.is_finite()) {
                on_row(&r);
                rows.push(r);
            }
        }
    }
    Ok((
        RunOutput {
            channels: plan.channels.clone(),
            rows,
            stop,
            stop_detail: detail,
            t_end: stopped_at.unwrap_or(report.t),
            stats,
            wall_seconds: started.elapsed().as_secs_f64(),
            events,
            verdict,
        },
        descent_peaks,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hermite_reproduces_a_cubic_exactly() {
        let f = |t: f64| 2.0 * t * t * t - t * t + 3.0 * t - 1.0;
        let df = |t: f64| 6.0 * t * t - 2.0 * t + 3.0;
        let (t0, t1) = (0.3, 1.1);
        let mut out = [0.0];
        for t in [0.3, 0.5, 0.77, 1.1] {
            hermite(
                (t0, &[f(t0)], &[df(t0)]),
                (t1, &[f(t1)], &[df(t1)]),
                t,
                &mut out,
            );
            assert!((out[0] - f(t)).abs() < 1e-13, "{t}");
        }
    }
}
