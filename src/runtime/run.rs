//! The run driver: builds the force blocks of a [`Plan`], integrates the equations of
//! motion (3.2.1), checks the stop conditions after every accepted step and samples the
//! output channels at the output interval.
//!
//! Output sampling: the integrator's observer sees `(t, x, ẋ)` after every accepted step;
//! rows at the output times inside the step are interpolated by the cubic Hermite polynomial
//! through the two step ends and their derivatives (third-order accurate, no extra
//! right-hand side evaluations; the Euler parameters of a row are renormalised). When an
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

use super::atmosphere::{Atmosphere, Standard1976};
use super::deformation::NodeDeformation;
use super::eom::{EnergyLayout, Eom, EomError, FreeFlight, Propulsion, StateView};
use super::forces::{
    AeroFault, BodyAero, FinAero, ForceBlock, ForceBlocks, GravityBlock, ThrustBlock,
};
use super::integrate::OdeSystem;
use super::integrate::{
    AdaptiveOptions, Dop853, DormandPrince54, Integrator, Rk4, StepStats, StopReason,
};
use super::kinematics::{euler_angles, mat_vec, normalize_euler_parameters};
use super::motor::BurnSchedule;
use crate::check::ir;
use crate::plan::{ForcePlan, Plan};
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
        }
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
    probe.evaluate(0.0, &s)
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
    Ok(ForceBlocks { blocks })
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
    eval: Eom<'a, FreeFlight>,
    gravity: Option<GravityBlock>,
    atmosphere: Standard1976,
    /// A copy of the run's aerodynamic blocks, evaluated at accepted states for the stop
    /// conditions they raise (table range, fin stress) and for the aero channels; the RHS
    /// copies are never read from outside the integrator.
    aero: AeroProbe,
    /// What the stop condition saw (for the summary), set with the stop.
    stop_note: Option<String>,
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
    fn evaluate(&mut self, t: f64, s: &StateView) -> Option<(RunStop, String)> {
        use crate::runtime::eom::ForceModel;
        let mut hit = None;
        if let Some(b) = &mut self.body {
            b.clear_fault();
            self.buf.fill(0.0);
            b.generalized_forces(t, s, &mut self.buf);
            self.body_load = Self::load_about_cm(&self.cm, &self.buf);
            if let Some(f) = b.fault() {
                hit = hit.or_else(|| fault_stop(f, "body"));
            }
        }
        if let Some(b) = &mut self.fin {
            b.clear_fault();
            self.buf.fill(0.0);
            b.generalized_forces(t, s, &mut self.buf);
            self.fin_load = Self::load_about_cm(&self.cm, &self.buf);
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
        }
        hit
    }

    /// The aero channels of the last evaluation (column order of [`crate::plan::channel_names`]).
    fn channels(&self, r: &mut Vec<f64>) {
        if self.body.is_some() {
            r.extend_from_slice(&self.body_load);
        }
        if let Some(f) = &self.fin {
            r.extend_from_slice(&self.fin_load);
            for i in 0..f.n_fins() {
                let sample = f.last(i).unwrap_or_default();
                r.push(sample.alpha.to_degrees());
                r.push(sample.root_stress);
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
        if st.ground && s.position[2] >= 0.0 {
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
        if let Some((stop, note)) = self.aero.evaluate(t, &s) {
            self.stop_note = Some(note);
            return Some(stop);
        }
        None
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
        // Interpolated rows can overshoot the model range by a hair before the stop check
        // of the accepted step catches it: evaluate the air at the clamped altitude.
        let air = self
            .atmosphere
            .at(h.clamp(ATMOSPHERE_RANGE.0, ATMOSPHERE_RANGE.1))
            .ok();
        let (rho, a) = air.map_or((0.0, 0.0), |a| (a.density, a.speed_of_sound));
        r.push(if a > 0.0 { speed / a } else { 0.0 });
        r.push(0.5 * rho * speed * speed);
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
        // The aero channels at this state (a stop raised here is the step check's business).
        let _ = self.aero.evaluate(t, &s);
        self.aero.channels(&mut r);
        Ok(r)
    }
}

/// Cubic Hermite interpolation between `(t0, x0, d0)` and `(t1, x1, d1)` at `t`.
/// One end of an accepted step: time, state, derivative.
type StepEnd<'a> = (f64, &'a [f64], &'a [f64]);

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

/// Runs the plan on `model`. `progress(t, t_end)` is called after each accepted step.
pub fn run(
    plan: &Plan,
    model: &ReducedModel,
    progress: &mut dyn FnMut(f64, f64),
) -> Result<RunOutput, RunError> {
    let started = Instant::now();
    let probe = AeroProbe::of_plan(plan, model);
    let forces = build_force_blocks(plan, model)?;
    let mut eom = Eom::new(model, forces)?.track_energy();
    let mut eval = Eom::new(model, FreeFlight)?;
    if let Some(p) = build_propulsion(plan, model)? {
        eom = eom.with_propulsion(p.clone())?;
        eval = eval.with_propulsion(p)?;
    }
    let layout = eom.layout();
    if plan.initial_state.len() != layout.len() {
        return Err(RunError::InitialState {
            expected: layout.len(),
            found: plan.initial_state.len(),
        });
    }
    let energy0 = eval.invariants_at(0.0, &plan.initial_state)?.total_energy();
    let mut monitor = Monitor {
        plan,
        eval,
        gravity: plan
            .gravity()
            .map(|g| gravity_block(plan, model, g.altitude_correction)),
        atmosphere: Standard1976::new(),
        aero: probe,
        stop_note: None,
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
    let mut integrator: Box<dyn Integrator> = match plan.integrator.method {
        ir::Integrator::Dopri5 => Box::new(DormandPrince54::new(adaptive)),
        ir::Integrator::Dop853 => Box::new(Dop853::new(adaptive)),
        ir::Integrator::Rk4 => Box::new(Rk4::new(plan.integrator.step)),
    };

    let t_end = plan.stop.stop_time;
    let dt_out = plan.output_interval;
    // The state with the works of the energy balance appended (they start at zero).
    let dim = eom.dim();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut prev: Option<(f64, Vec<f64>, Vec<f64>)> = None;
    let mut next_k: u64 = 0;
    let mut last_row_t = f64::NEG_INFINITY;
    let mut stop_cond: Option<RunStop> = None;
    let mut stopped_at: Option<f64> = None;
    let mut row_error: Option<EomError> = None;
    let mut scratch = vec![0.0; dim];
    let mut x = plan.initial_state.clone();
    x.resize(dim, 0.0);
    let eps = 1e-9 * dt_out;

    let report = {
        let mut observer = |t: f64, xs: &[f64], dx: &[f64]| -> bool {
            let mut hit = monitor.stop_condition(t, xs);
            // A stop inside this step: locate the first state that meets a condition by
            // bisection on the step's Hermite interpolant (the step start met none).
            let mut t_stop = t;
            if let (Some(_), Some((tp, xp, dp))) = (hit, &prev) {
                let (mut lo, mut hi) = (*tp, t);
                for _ in 0..64 {
                    let mid = 0.5 * (lo + hi);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    hermite((*tp, xp, dp), (t, xs, dx), mid, &mut scratch);
                    match monitor.stop_condition(mid, &scratch) {
                        Some(reason) => {
                            hi = mid;
                            hit = Some(reason);
                        }
                        None => lo = mid,
                    }
                }
                t_stop = hi;
            }
            // Output times in (t_prev, t] (and t = 0 at the start) up to the stop time; when
            // a condition stops the run, the rows end with the stopping state itself (below).
            loop {
                let tk = next_k as f64 * dt_out;
                if tk > t + eps || tk > t_end + eps || (hit.is_some() && tk >= t_stop - eps) {
                    break;
                }
                let tk = if (tk - t).abs() <= eps { t } else { tk };
                match &prev {
                    Some((tp, xp, dp)) if tk > *tp && tk < t => {
                        hermite((*tp, xp, dp), (t, xs, dx), tk, &mut scratch)
                    }
                    _ => scratch.copy_from_slice(xs),
                }
                match monitor.row(tk, &mut scratch) {
                    Ok(r) if r.iter().all(|v| v.is_finite()) => {
                        rows.push(r);
                        last_row_t = tk;
                    }
                    Ok(_) => {
                        stop_cond = Some(RunStop::NonFinite);
                        return false;
                    }
                    Err(e) => {
                        row_error = Some(e);
                        return false;
                    }
                }
                next_k += 1;
            }
            if let Some(stop) = hit {
                match &prev {
                    Some((tp, xp, dp)) if t_stop < t => {
                        hermite((*tp, xp, dp), (t, xs, dx), t_stop, &mut scratch)
                    }
                    _ => scratch.copy_from_slice(xs),
                }
                if let Ok(r) = monitor.row(t_stop, &mut scratch) {
                    if r.iter().all(|v| v.is_finite()) {
                        rows.push(r);
                        last_row_t = t_stop;
                    }
                }
                stop_cond = Some(stop);
                stopped_at = Some(t_stop);
                return false;
            }
            match &mut prev {
                Some((tp, xp, dp)) => {
                    *tp = t;
                    xp.copy_from_slice(xs);
                    dp.copy_from_slice(dx);
                }
                None => prev = Some((t, xs.to_vec(), dx.to_vec())),
            }
            progress(t, t_end);
            true
        };
        integrator.integrate(&mut eom, 0.0, &mut x, t_end, &mut observer)
    };
    if let Some(e) = row_error {
        return Err(RunError::Eom(e));
    }
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
        if let Ok(r) = monitor.row(report.t, &mut x) {
            if r.iter().all(|v| v.is_finite()) {
                rows.push(r);
            }
        }
    }
    Ok(RunOutput {
        channels: plan.channels.clone(),
        rows,
        stop,
        stop_detail: detail,
        t_end: stopped_at.unwrap_or(report.t),
        stats: report.stats,
        wall_seconds: started.elapsed().as_secs_f64(),
    })
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
