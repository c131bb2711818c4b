//! `flexflight analyze flutter`: parse the options, call the flutter operations
//! ([`crate::ops::flutter`]) and render their results.

use std::path::PathBuf;

use clap::Args;

use crate::aero::atmosphere::{Atmosphere, Standard1976};
use crate::analysis::flutter::fin::FinFlutterError;
use crate::analysis::flutter::pk::FlutterAnswer;
use crate::analysis::linear::Variant;
use crate::artifact::Cache;
use crate::check::cli_values;
use crate::check::ir;
use crate::diagnostics::Diagnostic;
use crate::ops::flutter::{
    AeroChoice, CLAMPED_MODES, Condition, FinFlutter, MATCH_MAX, MatchError, critical_thickness,
    flutter_code, flutter_diagnostic, flutter_speed_of, match_point, report_text,
    scenario_altitude, scenario_speed, solve_clamped, solve_free, summary_json, write_outputs,
};
use crate::units::Dim;

use super::analyze::refused;
use super::{
    CacheArgs, Common, EXIT_DIAGNOSTICS, EXIT_OK, EXIT_USAGE, Format, Terminal, emit, load_program,
};

#[derive(Args, Debug)]
pub struct FlutterArgs {
    pub file: PathBuf,
    #[arg(long)]
    pub scenario: String,
    /// The fin alone, clamped at its root (the fin designer's case); without it the free
    /// flexible vehicle (its modes and rigid-body motions, every fin's panels, the body's
    /// quasi-steady aerodynamics).
    #[arg(long)]
    pub clamped: bool,
    /// Altitude of the air (default: the scenario's initial altitude).
    #[arg(long)]
    pub altitude: Option<String>,
    /// Mach number of the aerodynamics (default: the scenario's initial Mach).
    #[arg(long)]
    pub mach: Option<String>,
    /// Speed range START:STOP:COUNT with units (default 0.1 a to 3 a, 40 speeds).
    #[arg(long, value_name = "START:STOP:COUNT")]
    pub speeds: Option<String>,
    /// Number of clamped-fin modes (default 6; a fixture: its `modes`; the free vehicle uses
    /// its compiled modes).
    #[arg(long)]
    pub modes: Option<usize>,
    #[arg(long, value_enum, default_value_t = AeroChoice::DoubletLattice)]
    pub aero: AeroChoice,
    /// Find the fin thickness whose flutter speed is the target speed, by root finding:
    /// START:STOP:COUNT lengths (COUNT thicknesses scanned for a bracket, then refined).
    #[arg(long, value_name = "START:STOP:COUNT")]
    pub critical_thickness: Option<String>,
    /// The target speed of --critical-thickness (default: the scenario's initial speed).
    #[arg(long)]
    pub target_speed: Option<String>,
    /// Matched point: iterate the Mach number of the aerodynamics until the flutter speed is
    /// that Mach's speed at the altitude (`V_F(M) = M a(h)`).
    #[arg(long, conflicts_with_all = ["mach", "critical_thickness"])]
    pub match_point: bool,
    /// Directory for vg.csv and flutter.json (written only when the solution succeeds).
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub common: Common,
    #[command(flatten)]
    pub cache: CacheArgs,
}

pub fn cmd_flutter(a: &FlutterArgs, term: Terminal) -> u8 {
    let format = a.common.output.format;
    if a.modes == Some(0) {
        eprintln!("error: --modes must be at least 1");
        return EXIT_USAGE;
    }
    let mut c = cli_values::CliChecker::new();
    let h = a
        .altitude
        .as_deref()
        .map(|t| c.quantity("--altitude", t, Dim::LENGTH));
    let m = a
        .mach
        .as_deref()
        .map(|t| c.quantity("--mach", t, Dim::NONE));
    let v = a
        .speeds
        .as_deref()
        .map(|t| c.range("--speeds", t, Dim::VELOCITY));
    let crit = a
        .critical_thickness
        .as_deref()
        .map(|t| c.range("--critical-thickness", t, Dim::LENGTH));
    let target = a
        .target_speed
        .as_deref()
        .map(|t| c.quantity("--target-speed", t, Dim::VELOCITY));
    if let Err(e) = c.finish() {
        return refused(e, format, term);
    }
    let mut checked = match load_program(std::slice::from_ref(&a.file), &a.common, term) {
        Ok(c) => c,
        Err(code) => return code,
    };
    if let Some(t) = checked.program.tunnel_test(&a.scenario) {
        let speeds = v.flatten().map(|r| r.values());
        return super::tunnel::cmd_tunnel(a, t, m.flatten(), speeds, &checked.sources, term);
    }
    let Some(sc) = checked.program.scenario(&a.scenario).cloned() else {
        return super::unknown_scenario(&checked.program, &a.scenario);
    };
    let n_modes = a.modes.unwrap_or(CLAMPED_MODES);
    let altitude = h.flatten().unwrap_or_else(|| scenario_altitude(&sc));
    let air = match Standard1976::new().at(altitude) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: --altitude: {e}");
            return EXIT_USAGE;
        }
    };
    let mach = match m.flatten() {
        Some(m) => m,
        None => scenario_speed(&sc, air.speed_of_sound) / air.speed_of_sound,
    };
    let speeds = match v.flatten() {
        Some(r) => r.values(),
        None => crate::ops::flutter::default_speeds(a.aero, a.clamped, air.speed_of_sound),
    };
    let condition = Condition {
        altitude,
        mach,
        density: air.density,
        speed_of_sound: air.speed_of_sound,
        pressure: air.pressure,
    };
    // `--critical-thickness`: the thicknesses to scan and the target speed.
    let scan = match crit.flatten() {
        None => None,
        Some(range) => {
            let v0 = target
                .flatten()
                .unwrap_or_else(|| scenario_speed(&sc, air.speed_of_sound));
            if v0.is_nan() || v0 <= 0.0 {
                eprintln!(
                    "error: --critical-thickness needs a target speed: the scenario starts at rest, give --target-speed"
                );
                return EXIT_USAGE;
            }
            Some((range.values(), v0))
        }
    };
    if !a.clamped {
        if a.modes.is_some() {
            eprintln!(
                "error: --modes chooses the modes of the clamped fin (--clamped) or of a fixture; the free vehicle uses its compiled modes (the vehicle's `modes` block)"
            );
            return EXIT_USAGE;
        }
        return cmd_free(a, &mut checked, &sc, condition, &speeds, scan, term);
    }
    // The GAF tables of every solution below go through the artifact cache.
    let cache = Cache::resolve(a.cache.cache_dir.as_deref());
    let critical = match scan {
        None => None,
        Some((ts, v0)) => {
            let solve = |t: f64| -> Result<f64, FinFlutterError> {
                let mut v = sc.vehicle.clone();
                if let Some(f) = v.fins.as_mut() {
                    f.thickness.value = t;
                }
                let r = solve_clamped(
                    &v,
                    condition,
                    &speeds,
                    n_modes,
                    a.aero.model(),
                    Some(&cache),
                )?;
                Ok(flutter_speed_of(&r))
            };
            match critical_thickness(&solve, ts, v0) {
                Ok(c) => Some((c, v0)),
                Err(e) => {
                    let d = Diagnostic::error(flutter_code(&e), format!("flutter: {e}"))
                        .label(sc.name.span, "in this scenario");
                    emit(&[d], &checked.sources, format, term);
                    return EXIT_DIAGNOSTICS;
                }
            }
        }
    };
    let result = if a.match_point {
        match solve_matched(condition, &speeds, |c| {
            solve_clamped(
                &sc.vehicle,
                c,
                &speeds,
                n_modes,
                a.aero.model(),
                Some(&cache),
            )
        }) {
            Ok(r) => r,
            Err(code) => return code,
        }
    } else {
        solve_clamped(
            &sc.vehicle,
            condition,
            &speeds,
            n_modes,
            a.aero.model(),
            Some(&cache),
        )
    };
    let mut r = match result {
        Ok(r) => r,
        Err(e) => {
            let d = flutter_diagnostic(&e, &sc, ", use fewer --modes");
            emit(&[d], &checked.sources, format, term);
            return EXIT_DIAGNOSTICS;
        }
    };
    r.critical_thickness = critical;
    finish(a, &r, term)
}

/// `--match-point`: [`match_point`] from `condition`'s Mach, each Mach one solution by
/// `solve` (the clamped fin or the free vehicle); the last solution carries the point. A
/// solver error (a transonic Mach of the iteration) is returned as the unmatched solve's
/// would be; no flutter point or no convergence is printed and ends the command (the exit
/// code in `Err`).
fn solve_matched(
    condition: Condition,
    speeds: &[f64],
    mut solve: impl FnMut(Condition) -> Result<FinFlutter, FinFlutterError>,
) -> Result<Result<FinFlutter, FinFlutterError>, u8> {
    let found = match_point(
        |m| {
            let r = solve(Condition {
                mach: m,
                ..condition
            })?;
            let v = match r.solution.answer() {
                FlutterAnswer::Flutter(f) => Some(f.speed),
                _ => None,
            };
            Ok((v, r))
        },
        condition.mach,
        condition.speed_of_sound,
    );
    match found {
        Ok((mp, mut r)) => {
            r.matched = Some(mp);
            Ok(Ok(r))
        }
        Err(MatchError::Solve(e)) => Ok(Err(e)),
        Err(MatchError::NoFlutter { mach }) => {
            eprintln!(
                "error: no matched point: no flutter point at Mach {mach:.4} up to {:.1} m/s (the largest speed tried)",
                speeds.iter().copied().fold(0.0, f64::max)
            );
            Err(EXIT_DIAGNOSTICS)
        }
        Err(MatchError::NotConverged { machs }) => {
            eprintln!(
                "error: no matched point in {MATCH_MAX} p-k solutions (Machs tried: {machs:.4?})"
            );
            Err(EXIT_DIAGNOSTICS)
        }
    }
}

/// Writes the outputs (only after a successful solution) and prints the summary.
fn finish(a: &FlutterArgs, r: &FinFlutter, _term: Terminal) -> u8 {
    let format = a.common.output.format;
    if let Some(w) = r.gaf_cache.as_ref().and_then(|g| g.warning.as_ref()) {
        eprintln!("warning: {w}");
    }
    if let Some(out) = &a.out {
        if let Err(e) = write_outputs(out, r) {
            eprintln!("error: cannot write `{}`: {e}", out.display());
            return EXIT_USAGE;
        }
    }
    match format {
        Format::Human => out!("{}", report_text(r)),
        Format::Json => outln!(
            "{}",
            serde_json::to_string_pretty(&summary_json(r)).unwrap_or_default()
        ),
    }
    EXIT_OK
}

/// The free vehicle's case of `cmd_flutter`: compile (through the artifact cache) and plan
/// the scenario, solve, write and print as the clamped case.
fn cmd_free(
    a: &FlutterArgs,
    checked: &mut crate::check::Checked,
    sc: &ir::Scenario,
    condition: Condition,
    speeds: &[f64],
    scan: Option<(Vec<f64>, f64)>,
    term: Terminal,
) -> u8 {
    let format = a.common.output.format;
    let scenario_speed = scenario_speed(sc, condition.speed_of_sound);
    let refuse = |e: &FinFlutterError, sources| {
        emit(&[flutter_diagnostic(e, sc, "")], sources, format, term);
        EXIT_DIAGNOSTICS
    };
    // Refusals that need no structure come before the compile.
    if sc.vehicle.fins.is_none() {
        return refuse(&FinFlutterError::NoFins, &checked.sources);
    }
    let cache_dir = a.cache.cache_dir.as_deref();
    let outcome =
        match super::compile::compile_cached(checked, &sc.vehicle, cache_dir, format, term) {
            Ok(o) => o,
            Err(code) => return code,
        };
    let cache = crate::artifact::Cache::resolve(cache_dir);
    let plan = match super::compile::plan_cached(sc, &outcome.compiled, &outcome.key, &cache) {
        Ok((p, _)) => p,
        Err(e) => {
            eprintln!("error: cannot plan scenario `{}`: {e}", sc.name.value);
            return EXIT_DIAGNOSTICS;
        }
    };
    let variant = Variant {
        plan,
        scenario: sc.clone(),
        compiled: outcome.compiled,
    };
    // `--critical-thickness`: each thickness's vehicle recompiled and planned through the
    // artifact cache (the free vehicle's modes are the whole structure's).
    let critical = match scan {
        None => None,
        Some((ts, v0)) => {
            let solve = |t: f64| -> Result<f64, FinFlutterError> {
                let mut s = sc.clone();
                if let Some(f) = s.vehicle.fins.as_mut() {
                    f.thickness.value = t;
                }
                let variant = crate::ops::linear::variant_for(s, cache_dir, &mut |w| {
                    eprintln!("warning: {w}")
                })
                .map_err(|e| FinFlutterError::Vehicle(format!("thickness {t} m: {e}")))?;
                let r = solve_free(&variant, condition, speeds, a.aero.model(), scenario_speed)?;
                Ok(flutter_speed_of(&r))
            };
            match critical_thickness(&solve, ts, v0) {
                Ok(c) => Some((c, v0)),
                Err(e) => return refuse(&e, &checked.sources),
            }
        }
    };
    let result = if a.match_point {
        match solve_matched(condition, speeds, |c| {
            solve_free(&variant, c, speeds, a.aero.model(), scenario_speed)
        }) {
            Ok(r) => r,
            Err(code) => return code,
        }
    } else {
        solve_free(&variant, condition, speeds, a.aero.model(), scenario_speed)
    };
    match result {
        Ok(mut r) => {
            r.critical_thickness = critical;
            finish(a, &r, term)
        }
        Err(e) => {
            emit(
                &[flutter_diagnostic(&e, sc, "")],
                &checked.sources,
                format,
                term,
            );
            EXIT_DIAGNOSTICS
        }
    }
}
