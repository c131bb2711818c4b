//! Fly a scenario: check, compile and plan through the cache ([`prepare`]), integrate with
//! the rows streamed to a sink ([`fly`]), and the run's documents: `history.csv`,
//! `summary.json` with the verdict, the flight summary, the energy balance and the warnings,
//! the flutter margin over the flight, the estimated coefficient tables ([`write_outputs`]).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::check::Checked;
use crate::check::ir::Scenario;
use crate::diagnostics::Diagnostic;
use crate::ops::OpsError;
use crate::ops::compile::{CachedAero, CompileOutcome, compile_cached, plan_cached};
use crate::ops::flutter::FlightMargin;
use crate::plan::{self, Plan, PlanError};
use crate::run::{self, RunOutput};
use crate::syntax::SourceMap;

/// A scenario ready to fly: its plan, the compiled vehicle, the checked scenario, how the
/// aerodynamics were obtained from the cache, and the check-time warnings (as
/// `summary.json` lists them).
pub struct Prepared {
    pub plan: Plan,
    pub compiled: CompileOutcome,
    pub scenario: Scenario,
    pub aero: Option<CachedAero>,
    pub check_warnings: Vec<serde_json::Value>,
}

/// Check-time work of a run: the scenario by name, compiled and planned with the structure
/// and the aerodynamics through the cache in `cache_dir`. Cache warnings go to `warn`;
/// errors are diagnostics on `checked.sources`.
pub fn prepare(
    checked: &mut Checked,
    scenario: &str,
    cache_dir: Option<&Path>,
    warn: &mut dyn FnMut(String),
) -> Result<Prepared, OpsError> {
    let Some(sc) = checked.program.scenario(scenario).cloned() else {
        return Err(super::unknown_scenario(&checked.program, scenario));
    };
    let outcome = compile_cached(checked, &sc.vehicle, cache_dir)?;
    if let crate::artifact::CacheOutcome::Rebuilt { .. } = &outcome.outcome {
        warn(outcome.outcome.to_string());
    }
    let cache = crate::artifact::Cache::resolve(cache_dir);
    match plan_cached(&sc, &outcome.compiled, &outcome.key, &cache, warn) {
        Ok((plan, aero)) => Ok(Prepared {
            plan,
            compiled: outcome,
            check_warnings: super::warnings::check_warnings(&checked.diagnostics, &checked.sources),
            scenario: sc,
            aero,
        }),
        Err(e) => Err(OpsError::Diagnostics(vec![plan_diagnostic(&e, &sc)])),
    }
}

/// What a run gives: the integrator's output, the text of `history.csv`, `summary.json`,
/// the flutter margin when computed, and the estimated coefficient tables' files.
pub struct Flown {
    pub output: RunOutput,
    pub history: String,
    pub summary: serde_json::Value,
    pub margin: Option<FlightMargin>,
    pub tables: Option<[(&'static str, String); 2]>,
}

/// Flies a prepared scenario. `progress(t, t_end)` is called from the integration (cheap,
/// at every accepted step); `sink` sees every output row as it is made (the rows are also
/// in the result). `flutter_margin`: `None` computes the margin for a launch from a rail
/// only. `sources` are the checked sources (the flight's warnings point into them).
pub fn fly(
    prep: &Prepared,
    sources: &SourceMap,
    flutter_margin: Option<bool>,
    cache_dir: Option<&Path>,
    progress: &mut dyn FnMut(f64, f64),
    sink: &mut dyn FnMut(&[f64]),
) -> Result<Flown, OpsError> {
    let (p, sc) = (&prep.plan, &prep.scenario);
    // Initial conditions outside a coefficient table (policy `stop`) or a fin already past
    // its stress limit: a diagnostic before anything runs or is written.
    if let Some((stop, note)) = run::check_initial_state(p, &prep.compiled.compiled.reduced) {
        let d = Diagnostic::error(
            "run::initial_state",
            format!(
                "the initial state of scenario `{}` already meets a stop condition ({}): {note}",
                sc.name.value,
                stop.code()
            ),
        )
        .label(sc.initial.span, "this initial condition")
        .with_help(
            "start inside the coefficient tables' Mach, alpha and altitude range, or write \
             `out_of_range = clamp` in the vehicle's `aero` block",
        );
        return Err(OpsError::Diagnostics(vec![d]));
    }
    // history.csv's text (a pure function of the rows) is formatted on a second thread as
    // the flight appends the rows: the same bytes as formatting them afterwards
    // ([`history_csv`]; test `streamed_history_text_is_the_history_csv` in tests/fin_models.rs),
    // while the flight is still running.
    let rows_hint = ((p.stop.stop_time / p.output_interval).max(0.0) as usize).saturating_add(2);
    let (result, streamed, tables) = std::thread::scope(|scope| {
        let (tx, rx) = std::sync::mpsc::channel::<Vec<f64>>();
        let channels = &p.channels;
        let width = channels.len().max(1);
        let aero = p.aero.as_ref();
        let writer = scope.spawn(move || {
            // The estimated coefficient tables' text first (it depends on the vehicle
            // only), while the flight starts: off the main thread's path.
            let tables = estimated_table_files(aero);
            let mut h = HistoryText::new(channels, rows_hint);
            for batch in rx {
                for row in batch.chunks_exact(width) {
                    h.push_row(row);
                }
            }
            (h, tables)
        });
        // Rows go over in batches of `BATCH` (one message, so one wake-up of the writer,
        // per batch: a message per row cost more than the formatting it moved).
        const BATCH: usize = 256;
        let mut batch = Vec::with_capacity(BATCH * width);
        // Rows are `width` wide; one that is not (never seen) leaves the text to be
        // formatted from the rows afterwards.
        let mut widths_ok = true;
        let result = run::run_with_rows(p, &prep.compiled.compiled.reduced, progress, &mut |row| {
            sink(row);
            widths_ok &= row.len() == width;
            batch.extend_from_slice(row);
            if batch.len() >= BATCH * width {
                // A send fails only if the writer has gone (it panicked): the text
                // is then formatted from the rows afterwards (below).
                let _ = tx.send(std::mem::replace(
                    &mut batch,
                    Vec::with_capacity(BATCH * width),
                ));
            }
        });
        if !batch.is_empty() {
            let _ = tx.send(batch);
        }
        drop(tx);
        let (streamed, tables) = match writer.join() {
            Ok((h, tables)) => (Some(h).filter(|_| widths_ok), Some(tables)),
            Err(_) => (None, None),
        };
        (result, streamed, tables)
    });
    let output = match result {
        Ok(o) => o,
        Err(e @ run::RunError::CannotLeaveGround { .. }) => {
            let d = Diagnostic::error("run::on_ground", e.to_string())
                .label(sc.initial.span, "this initial condition")
                .with_help(
                    "start above the ground, climbing, or fly from a rail with a \
                     `launch { site_altitude, rail_length, elevation, heading }` block",
                );
            return Err(OpsError::Diagnostics(vec![d]));
        }
        Err(e) => {
            return Err(OpsError::Coded {
                code: "run::cannot_start",
                message: e.to_string(),
                input: true,
            });
        }
    };
    // The post-processing is small dense algebra (the identification's 201 x 201
    // eigen-solves, the margin's p-k solutions): faer's own threads only cost their start-up
    // and spinning here, and sequential kernels give the same bits whatever the machine.
    crate::ops::sequential_linear_algebra();
    let history = match streamed {
        Some(h) if h.rows() == output.rows.len() => h.finish(),
        _ => history_csv(&output),
    };
    let (mut summary, margin) = post_process(
        p,
        sc,
        &prep.compiled,
        &output,
        prep.aero.as_ref(),
        flutter_margin,
        cache_dir,
    );
    super::warnings::add_to_summary(&mut summary, prep.check_warnings.clone());
    let flight_warnings =
        super::warnings::flight_warnings(sc, &output, p.stop.ground_altitude, sources);
    super::warnings::add_to_summary(&mut summary, flight_warnings);
    // Made on the writer thread during the flight; here only if that thread failed.
    let tables = tables.unwrap_or_else(|| estimated_table_files(p.aero.as_ref()));
    Ok(Flown {
        output,
        history,
        summary,
        margin,
        tables,
    })
}

/// Writes a run's files into `out`: `history.csv`, `summary.json`, `flutter_margin.csv`
/// (when computed) and `aero_tables/` (the coefficient tables the built-in estimator made,
/// for users to inspect or replace with `aero { source = tables ... }`). Every file at once
/// ([`super::files::write_all_atomic`]): a run that cannot write all of them writes none
/// and leaves the directory as it was.
pub fn write_outputs(out: &Path, f: &Flown) -> std::io::Result<()> {
    let summary_text = serde_json::to_string_pretty(&f.summary).unwrap_or_default() + "\n";
    let mut files: Vec<(PathBuf, &str)> = vec![
        (out.join("history.csv"), f.history.as_str()),
        (out.join("summary.json"), summary_text.as_str()),
    ];
    if let Some(m) = f.margin.as_ref().filter(|m| !m.csv.is_empty()) {
        files.push((out.join("flutter_margin.csv"), m.csv.as_str()));
    }
    let tables_dir = out.join("aero_tables");
    let mut dirs = vec![out];
    if let Some(t) = &f.tables {
        dirs.push(&tables_dir);
        for (name, text) in t {
            files.push((tables_dir.join(name), text.as_str()));
        }
    }
    super::files::write_all_atomic(&dirs, &files)
}

/// Channels whose extrema go into `summary.json` (when present).
const SUMMARY_CHANNELS: &[&str] = &[
    "altitude",
    "mach",
    "alpha",
    "beta",
    "dynamic_pressure",
    "omega_body_x",
    "omega_body_y",
    "omega_body_z",
    "max_deformation",
    "energy_total",
    "mass",
    "cm_body_x",
    "energy_balance_residual",
];

pub fn plan_diagnostic(e: &PlanError, sc: &Scenario) -> Diagnostic {
    let d = Diagnostic::error(e.code(), e.to_string());
    match e.span() {
        Some(span) => d.label(span, "here"),
        None => d.label(sc.name.span, "while planning this scenario"),
    }
}

/// The fin panel matrices (issue 12) on the fin table's Mach grid, for `plan` of a vehicle
/// whose run does not use them (`model = key_node`); a line saying why when they cannot be
/// built.
pub fn fin_panels_text(sc: &Scenario, c: &crate::structure::compile::CompiledVehicle) -> String {
    use crate::aero::panel::fin_model::{self, PanelSettings};
    use crate::aero::tables::Axis;
    let v = &sc.vehicle;
    let Some(f) = v.fins.as_ref() else {
        return String::new();
    };
    let machs = match crate::runtime::forces::body_aero::aero_tables(v) {
        Ok(t) => t.fin.axis(Axis::Mach).to_vec(),
        Err(e) => return format!("fin panels: not built ({e})\n"),
    };
    match fin_model::compile(c, v, &machs, PanelSettings::default()) {
        Ok(m) => {
            let area = 0.5 * (f.root_chord.value + f.tip_chord.value) * f.span.value;
            m.summary_text(c, area)
        }
        Err(e) => format!("fin panels: not built ({e})\n"),
    }
}

/// `summary.json` (with the aero cache's note) and, when asked or by default for a launch,
/// the flutter margin over the flight (which adds itself to the summary).
/// The files of `aero_tables/` (name, text) when the run's tables were estimated.
pub fn estimated_table_files(
    aero: Option<&plan::aero::PlanAero>,
) -> Option<[(&'static str, String); 2]> {
    aero.filter(|a| a.estimated).map(|a| a.tables.files())
}

pub fn post_process(
    p: &Plan,
    sc: &Scenario,
    compiled: &CompileOutcome,
    output: &RunOutput,
    aero_cache: Option<&CachedAero>,
    flutter_margin: Option<bool>,
    cache_dir: Option<&Path>,
) -> (serde_json::Value, Option<FlightMargin>) {
    let mut summary = with_aero_cache(summary_json(p, compiled, output), aero_cache);
    let margin = if flutter_margin.unwrap_or(sc.launch.is_some()) {
        // The boundary's Mach grid reaches the fin table's last Mach (the built-in
        // estimator's grid without aerodynamics).
        let table_machs = p.aero.as_ref().map_or_else(
            || crate::aero::estimator::ESTIMATOR_MACH.to_vec(),
            |a| a.tables.fin.axis(crate::aero::tables::Axis::Mach).to_vec(),
        );
        let cache = crate::artifact::Cache::resolve(cache_dir);
        let m = super::flutter::flight_margin(sc, output, &table_machs, &cache);
        if let Some(map) = summary.as_object_mut() {
            map.insert("flutter_margin".into(), m.json.clone());
        }
        Some(m)
    } else {
        None
    };
    (summary, margin)
}

/// `history.csv`: a header of channel names, one row per output time. Floats are written
/// in the shortest round-trip form ([`super::floatfmt`]), so reading them back gives the
/// same numbers.
pub fn history_csv(o: &RunOutput) -> String {
    let mut h = HistoryText::new(&o.channels, o.rows.len());
    for row in &o.rows {
        h.push_row(row);
    }
    h.finish()
}

/// The text of `history.csv` built row by row ([`history_csv`] is its rows pushed in
/// order), so that `flexflight run` can format the rows on a second thread as the flight
/// appends them (`run::run_with_rows`) instead of after it.
pub struct HistoryText {
    s: String,
    buf: zmij::Buffer,
    rows: usize,
}

impl HistoryText {
    /// The header of `channels`; room reserved for about `rows_hint` rows.
    pub fn new(channels: &[String], rows_hint: usize) -> Self {
        let mut s = channels.join(",");
        s.push('\n');
        // About 20 bytes a value, at most 64 MiB ahead (a longer history grows as usual).
        s.reserve(
            rows_hint
                .saturating_mul(channels.len())
                .saturating_mul(20)
                .min(64 << 20),
        );
        HistoryText {
            s,
            buf: zmij::Buffer::new(),
            rows: 0,
        }
    }

    /// Appends one row: shortest round-trip form, exponent notation for very small or
    /// large values (`floatfmt`: the bytes of `{}` / `{:e}`, several times faster).
    pub fn push_row(&mut self, row: &[f64]) {
        for (i, v) in row.iter().enumerate() {
            if i > 0 {
                self.s.push(',');
            }
            super::floatfmt::push_shortest(&mut self.s, *v, &mut self.buf);
        }
        self.s.push('\n');
        self.rows += 1;
    }

    /// The number of rows pushed.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// The text.
    pub fn finish(self) -> String {
        self.s
    }
}

/// `summary.json` of a run.
pub fn summary_json(p: &Plan, c: &CompileOutcome, o: &RunOutput) -> serde_json::Value {
    let mut extrema = serde_json::Map::new();
    let mut wanted: Vec<String> = SUMMARY_CHANNELS.iter().map(|s| s.to_string()).collect();
    wanted.extend(p.mode_names.iter().map(|m| format!("eta_{m}")));
    for name in &wanted {
        let Some(col) = o.channels.iter().position(|c| c == name) else {
            continue;
        };
        let mut lo = (f64::INFINITY, 0.0);
        let mut hi = (f64::NEG_INFINITY, 0.0);
        for r in &o.rows {
            if r[col] < lo.0 {
                lo = (r[col], r[0]);
            }
            if r[col] > hi.0 {
                hi = (r[col], r[0]);
            }
        }
        if o.rows.is_empty() {
            continue;
        }
        extrema.insert(
            name.clone(),
            serde_json::json!({ "min": lo.0, "t_min": lo.1, "max": hi.0, "t_max": hi.1 }),
        );
    }
    let energy_balance = energy_balance_json(o);
    let mass = mass_json(p, o);
    serde_json::json!({
        "scenario": p.scenario,
        "vehicle": p.vehicle,
        "overrides": p.overrides.iter().map(|(k, v)| serde_json::json!({"path": k, "value": v})).collect::<Vec<_>>(),
        "artifact": c.path,
        "artifact_hash": c.key.to_hex(),
        "stop_reason": o.stop.code(),
        "complete": !o.stop.is_incomplete(),
        "stop_detail": o.stop_detail,
        "t_end": o.t_end,
        "stop_time": p.stop.stop_time,
        "wall_time_s": o.wall_seconds,
        "accepted_steps": o.stats.accepted,
        "rejected_steps": o.stats.rejected,
        "rhs_evaluations": o.stats.rhs_evaluations,
        "rows": o.rows.len(),
        "output_interval": p.output_interval,
        "energy_balance": energy_balance,
        "mass": mass,
        "verdict": verdict_json(p, o),
        "flight": flight_summary(p, o),
        "extrema": extrema,
        "identification": crate::analysis::gust_response::identify_after_stimuli(
            &p.stimuli,
            o,
            crate::analysis::gust_response::DEFAULT_CHANNELS,
            &crate::analysis::identify::IdentifyOptions::default(),
        ),
    })
}

/// The verdict of a run that left its model (`null` otherwise): the kind, the state at it
/// (from the history's last row, which is at the verdict), the bound crossed and the modes
/// with their growth rates and frequencies (`runtime::verdict`).
pub fn verdict_json(p: &Plan, o: &RunOutput) -> serde_json::Value {
    let Some(v) = &o.verdict else {
        return serde_json::Value::Null;
    };
    let at = |name: &str| last_value(o, name);
    let mach = at("mach");
    let airspeed = mach.zip(at("speed_of_sound")).map(|(m, a)| m * a);
    let modes: Vec<serde_json::Value> = v
        .modes
        .iter()
        .map(|m| {
            serde_json::json!({
                "name": p.mode_names.get(m.mode),
                "growth_rate": m.growth_rate,
                "frequency_hz": m.frequency_hz,
                "energy_share": m.energy_share,
            })
        })
        .collect();
    serde_json::json!({
        "kind": v.kind.code(),
        "t": v.t,
        "mach": mach,
        "altitude": at("altitude"),
        "airspeed": airspeed,
        "dynamic_pressure": at("dynamic_pressure"),
        "criterion": v.criterion,
        "modes": modes,
        "growth_window_s": v.window,
        "bound": if v.flow { "flow" } else { "structure" },
        "message": verdict_line(p, o),
    })
}

/// Channel `name` at the history's last row (at a verdict, the verdict's state).
fn last_value(o: &RunOutput, name: &str) -> Option<f64> {
    let c = o.channels.iter().position(|c| c == name)?;
    o.rows.last().map(|r| r[c])
}

/// The terminal line of a verdict (None without one).
pub fn verdict_line(p: &Plan, o: &RunOutput) -> Option<String> {
    let v = o.verdict.as_ref()?;
    let at = |name: &str| last_value(o, name);
    let what = match v.kind {
        crate::runtime::verdict::VerdictKind::Flutter => "FLUTTER",
        crate::runtime::verdict::VerdictKind::Divergence => "DIVERGENCE",
        crate::runtime::verdict::VerdictKind::ModelLimit => "MODEL LIMIT",
    };
    let mut s = format!("{what} at t = {:.3} s", v.t);
    if let (Some(m), Some(a), Some(h), Some(q)) = (
        at("mach"),
        at("speed_of_sound"),
        at("altitude"),
        at("dynamic_pressure"),
    ) {
        let _ = write!(
            s,
            ", Mach {m:.3}, {:.1} m/s, altitude {h:.0} m, q {:.1} kPa",
            m * a,
            q / 1e3
        );
    }
    let growing: Vec<String> = v
        .modes
        .iter()
        .filter(|m| m.growth_rate > 0.0)
        .map(|m| {
            let name = p.mode_names.get(m.mode).map_or("?", String::as_str);
            match m.frequency_hz {
                Some(f) => format!("{name} {f:.1} Hz, growth {:.1} 1/s", m.growth_rate),
                None => format!("{name} non-oscillatory, growth {:.1} 1/s", m.growth_rate),
            }
        })
        .collect();
    if !growing.is_empty() {
        let more = growing.len().saturating_sub(4);
        let _ = write!(
            s,
            "; growing: {}",
            growing[..growing.len() - more].join("; ")
        );
        if more > 0 {
            let _ = write!(s, "; {more} more in summary.json");
        }
    }
    let _ = write!(
        s,
        " ({}); the history ends there: the flight after it is outside the model",
        v.criterion
    );
    Some(s)
}

/// The energy balance of a run (replaces the old `energy_total_max_relative_drift`, which
/// meant nothing with thrust on): `Δ(T + ½ηᵀK̄η) - W_loads - W_propulsive + D`, the works
/// integrated with the state (`runtime::eom::Eom::track_energy`). Its residual is zero for
/// exact integration whatever the loads (gravity, aerodynamics, thrust, mass flow); without
/// loads and damping it is the drift of the conserved energy.
fn energy_balance_json(o: &RunOutput) -> serde_json::Value {
    let col = |name: &str| o.channels.iter().position(|c| c == name);
    let (Some(ke), Some(se), Some(wl), Some(wp), Some(di), Some(res)) = (
        col("energy_kinetic"),
        col("energy_strain"),
        col("work_loads"),
        col("work_propulsive"),
        col("energy_dissipated"),
        col("energy_balance_residual"),
    ) else {
        return serde_json::Value::Null;
    };
    let (Some(first), Some(last)) = (o.rows.first(), o.rows.last()) else {
        return serde_json::Value::Null;
    };
    let e = |r: &Vec<f64>| r[ke] + r[se];
    let max_abs_residual = o.rows.iter().map(|r| r[res].abs()).fold(0.0, f64::max);
    // Scale: the largest energy or work magnitude seen (so a flight that starts at rest is
    // measured against what the loads did to it).
    let scale = o
        .rows
        .iter()
        .flat_map(|r| [e(r).abs(), r[wl].abs(), r[wp].abs(), r[di].abs()])
        .fold(0.0, f64::max);
    serde_json::json!({
        "definition": "residual = (T + U)(t) - (T + U)(0) - work_loads - work_propulsive + dissipated",
        "energy_change_j": e(last) - e(first),
        "work_loads_j": last[wl],
        "work_propulsive_j": last[wp],
        "dissipated_j": last[di],
        "residual_j": last[res],
        "max_abs_residual_j": max_abs_residual,
        "max_relative_residual": if scale > 0.0 { max_abs_residual / scale } else { max_abs_residual },
    })
}

/// Mass and centre of mass at the start and the end, and the motor's numbers.
fn mass_json(p: &Plan, o: &RunOutput) -> serde_json::Value {
    let col = |name: &str| o.channels.iter().position(|c| c == name);
    let (Some(m), Some(cx)) = (col("mass"), col("cm_body_x")) else {
        return serde_json::Value::Null;
    };
    let (Some(first), Some(last)) = (o.rows.first(), o.rows.last()) else {
        return serde_json::Value::Null;
    };
    serde_json::json!({
        "initial_kg": first[m],
        "final_kg": last[m],
        "initial_cm_body_x_m": first[cx],
        "final_cm_body_x_m": last[cx],
        "motor": p.motor.as_ref().map(|mo| serde_json::json!({
            "name": mo.name,
            "designation": mo.designation,
            "propellant_kg": mo.propellant_mass,
            "total_kg": mo.total_mass,
            "total_impulse_ns": mo.thrust.total_impulse,
            "burn_time_s": mo.thrust.burn_time,
            "exhaust_velocity_m_s": mo.exhaust_velocity,
            "ignition_mass_kg": mo.ignition_mass,
            "burnout_mass_kg": mo.burnout_mass,
        })),
    })
}

/// The figures a rocketry engineer reads first (`summary.json`'s `flight`): events located
/// in time by the run, maxima over the output rows (and the event rows), and the static
/// margin at rail exit, at maximum dynamic pressure and its minimum from the start (or the
/// rail exit) to apogee (or the first deployment, whichever comes first).
pub fn flight_summary(p: &Plan, o: &RunOutput) -> serde_json::Value {
    use serde_json::json;
    let col = |name: &str| o.channels.iter().position(|c| c == name);
    let ev = &o.events;
    let point = |e: &run::EventPoint| {
        json!({
            "t": e.t,
            "altitude": e.altitude(),
            "height": e.altitude() - p.stop.ground_altitude,
            "position": e.position,
            "velocity": e.velocity,
            "speed": e.speed(),
        })
    };
    let max_of = |name: &str| -> Option<(f64, f64)> {
        let c = col(name)?;
        o.rows
            .iter()
            .map(|r| (r[c], r[0]))
            .fold(None, |acc: Option<(f64, f64)>, x| match acc {
                Some(a) if a.0 >= x.0 => Some(a),
                _ => Some(x),
            })
    };
    let value_at = |name: &str, t: f64| -> Option<f64> {
        let c = col(name)?;
        o.rows
            .iter()
            .min_by(|a, b| (a[0] - t).abs().total_cmp(&(b[0] - t).abs()))
            .map(|r| r[c])
    };
    let max_q = max_of("dynamic_pressure");
    let t_from = ev.rail_exit.map_or(0.0, |e| e.t);
    let t_to = [
        ev.apogee.map(|a| a.t),
        ev.deployments.first().map(|d| d.2.t),
    ]
    .into_iter()
    .flatten()
    .reduce(f64::min)
    .unwrap_or(o.t_end);
    let margin_min = col("static_margin").and_then(|c| {
        o.rows
            .iter()
            .filter(|r| r[0] >= t_from && r[0] <= t_to)
            .map(|r| (r[c], r[0]))
            .reduce(|a, b| if b.0 < a.0 { b } else { a })
    });
    let landing = ev.landing.map(|l| {
        let mut v = point(&l);
        v["ground_range"] = json!((l.position[0].powi(2) + l.position[1].powi(2)).sqrt());
        v
    });
    json!({
        "apogee": ev.apogee.map(|a| point(&a)),
        "max_mach": max_of("mach").map(|(m, t)| json!({"value": m, "t": t})),
        "max_dynamic_pressure": max_q.map(|(q, t)| json!({"value": q, "t": t})),
        "max_acceleration": max_of("acceleration").map(|(a, t)| json!({"value": a, "t": t})),
        "rail_exit": ev.rail_exit.map(|e| point(&e)),
        "off_rail_speed": ev.rail_exit.map(|e| e.speed()),
        "burnout": ev.burnout.map(|b| point(&b)),
        "deployments": ev.deployments.iter().map(|(name, trig, dep)| json!({
            "name": name, "trigger": point(trig), "deployment": point(dep)
        })).collect::<Vec<_>>(),
        "landing": landing,
        "static_margin_calibres": {
            "at_rail_exit": ev.rail_exit.and_then(|e| value_at("static_margin", e.t)),
            "at_max_q": max_q.and_then(|(_, t)| value_at("static_margin", t)),
            "min": margin_min.map(|(m, t)| json!({"value": m, "t": t})),
        },
        "maxima_sampled_at": "output rows and event rows",
    })
}

/// The one-line flight summary printed after a run, when the flight has an apogee.
pub fn flight_line(f: &serde_json::Value) -> Option<String> {
    let num = |v: &serde_json::Value| v.as_f64();
    let ap = &f["apogee"];
    let mut s = format!(
        "  apogee {:.1} m at {:.2} s",
        num(&ap["height"])?,
        num(&ap["t"])?
    );
    if let Some(m) = num(&f["max_mach"]["value"]) {
        let _ = write!(s, ", max Mach {m:.3}");
    }
    if let (Some(q), Some(t)) = (
        num(&f["max_dynamic_pressure"]["value"]),
        num(&f["max_dynamic_pressure"]["t"]),
    ) {
        let _ = write!(s, ", max q {:.1} kPa at {t:.2} s", q / 1e3);
    }
    if let Some(a) = num(&f["max_acceleration"]["value"]) {
        let _ = write!(s, ", max accel {:.1} g", a / 9.806);
    }
    if let Some(v) = num(&f["off_rail_speed"]) {
        let _ = write!(s, ", off rail {v:.2} m/s");
    }
    if let (Some(t), Some(v)) = (num(&f["burnout"]["t"]), num(&f["burnout"]["speed"])) {
        let _ = write!(s, ", burnout {t:.3} s at {v:.1} m/s");
    }
    let sm = &f["static_margin_calibres"];
    if let Some(m) = num(&sm["at_rail_exit"]) {
        let _ = write!(s, ", margin {m:.2} cal off rail");
    }
    if let Some(m) = num(&sm["at_max_q"]) {
        let _ = write!(s, ", {m:.2} at max q");
    }
    if let Some(m) = num(&sm["min"]["value"]) {
        let _ = write!(s, ", min {m:.2}");
    }
    if let Some(l) = f["landing"].as_object() {
        let _ = write!(
            s,
            ", landing {:.1} m from the pad at {:.2} m/s ({:.1} s)",
            l.get("ground_range")
                .and_then(|v| v.as_f64())
                .unwrap_or(f64::NAN),
            l.get("speed").and_then(|v| v.as_f64()).unwrap_or(f64::NAN),
            l.get("t").and_then(|v| v.as_f64()).unwrap_or(f64::NAN),
        );
    }
    Some(s)
}

/// `summary` with the aerodynamics' cache key and whether the cache held them
/// (`aero_artifact_hash`, `aero_cache`: `hit`, `miss` or `rebuilt`; null without
/// aerodynamics).
pub fn with_aero_cache(
    mut summary: serde_json::Value,
    aero: Option<&CachedAero>,
) -> serde_json::Value {
    if let Some(map) = summary.as_object_mut() {
        map.insert(
            "aero_artifact_hash".into(),
            aero.map(|a| a.key.to_hex()).into(),
        );
        map.insert(
            "aero_cache".into(),
            aero.map(|a| match a.outcome {
                crate::artifact::CacheOutcome::Hit => "hit",
                crate::artifact::CacheOutcome::Miss => "miss",
                crate::artifact::CacheOutcome::Rebuilt { .. } => "rebuilt",
            })
            .into(),
        );
    }
    summary
}

/// The vehicle's zero-lift drag curve `(Mach, C_D)` on the coefficient tables' Mach grid
/// (the body table's), at altitude `altitude_m`: at zero angle of attack the drag is the
/// axial force, so `C_D(M) = C_A,body(M, 0, h) + n C_A,fin(M, 0, h)` with `n` the number of
/// fins (the fin table holds ONE fin's coefficients at its own angle of attack, on the same
/// reference area: module doc of [`crate::aero::tables`]); every fin is at `alpha_f = 0`
/// (fin cant, which gives each fin an angle of attack of its own, is not in the curve). This
/// is the drag curve RocketPy takes (`power_off_drag`, a CSV of Mach and C_D on the
/// reference area `pi r^2`). `None` for a plan without coefficient tables; `Err` when a
/// table lookup fails (the altitude outside a `stop` table).
pub fn drag_curve(
    p: &Plan,
    n_fins: usize,
    altitude_m: f64,
) -> Option<Result<Vec<(f64, f64)>, String>> {
    use crate::aero::tables::Axis;
    let t = &p.aero.as_ref()?.tables;
    let curve = t
        .body
        .axis(Axis::Mach)
        .iter()
        .map(|&m| {
            let body = t
                .body
                .lookup(m, 0.0, altitude_m)
                .map_err(|e| e.to_string())?;
            let fin = t
                .fin
                .lookup(m, 0.0, altitude_m)
                .map_err(|e| e.to_string())?;
            Ok((m, body[1] + n_fins as f64 * fin[1]))
        })
        .collect();
    Some(curve)
}
