//! The `warnings` of a run's `summary.json` and its terminal output: the check-time warnings
//! of the files (material constants, motor dimensions, ...) and the warnings only the flight
//! can decide (a parachute's altitude trigger above the apogee, a larger canopy opening at
//! apogee before a smaller one).
//!
//! Each warning is `{"code", "message", "file", "line", "column"}` (the location, 1-based,
//! is null where there is none).

use serde_json::{Value, json};

use crate::check::ir::{Scenario, Trigger};
use crate::diagnostics::{self, Diagnostic, Severity};
use crate::run::RunOutput;
use crate::syntax::SourceMap;

/// The check-time warnings among `diags`, as `summary.json` entries.
pub fn check_warnings(diags: &[Diagnostic], sources: &SourceMap) -> Vec<Value> {
    let warnings: Vec<Diagnostic> = diags
        .iter()
        .filter(|d| d.severity == Severity::Warning)
        .cloned()
        .collect();
    diagnostics::to_json(&warnings, sources)
        .into_iter()
        .map(|d| {
            json!({
                "code": d.code,
                "message": d.message,
                "file": d.file,
                "line": d.line,
                "column": d.column,
            })
        })
        .collect()
}

/// Warnings about the recovery that only the flight decides (`run::` codes), located at the
/// parachute blocks of the scenario.
///
/// * `run::parachute::above_apogee`: a parachute triggered at `altitude(h)` with `h` above
///   the flight's apogee (height above the ground). The trigger is "on descent through h",
///   so such a parachute opens at apogee (run/mod.rs, the altitude trigger is armed from
///   apogee on and met at once), with whatever opens there too.
/// * `run::parachute::order`: a canopy opening at apogee (triggered there, by `apogee` or by
///   an altitude trigger above it) with a larger drag area than one that opens later: the
///   drogue and the main swapped, which drifts the descent far (the 5.7 km).
pub fn flight_warnings(
    sc: &Scenario,
    o: &RunOutput,
    ground_altitude: f64,
    sources: &SourceMap,
) -> Vec<Value> {
    let mut out = Vec::new();
    let ev = &o.events;
    let Some(apogee) = ev.apogee else {
        return out;
    };
    let ground = ground_altitude;
    let apogee_height = apogee.altitude() - ground;
    let located = |span: crate::syntax::Span, code: &str, message: String| {
        let (line, column) = sources.line_col(span.file, span.start);
        json!({
            "code": code,
            "message": message,
            "file": sources.get(span.file).map(|f| f.name.clone()),
            "line": line,
            "column": column,
        })
    };
    for p in &sc.parachutes {
        if let Trigger::Altitude(h) = p.trigger.value {
            if h > apogee_height {
                out.push(located(
                    p.trigger.span,
                    "run::parachute::above_apogee",
                    format!(
                        "parachute `{}` is set to open on descent through {h} m, but the apogee is {apogee_height:.1} m above the ground: it opened at apogee (t = {:.3} s) instead",
                        p.name.value, apogee.t
                    ),
                ));
            }
        }
    }
    // Trigger time of each deployed parachute (name -> t).
    let trigger_t = |name: &str| {
        ev.deployments
            .iter()
            .find(|(n, _, _)| n == name)
            .map(|(_, trig, _)| trig.t)
    };
    // "At apogee": triggered at the apogee's time (the run locates both events by bisection
    // of the step's dense output, far finer than this).
    let tol = 1e-6;
    for first in &sc.parachutes {
        let Some(t1) = trigger_t(&first.name.value) else {
            continue;
        };
        if (t1 - apogee.t).abs() > tol {
            continue;
        }
        for later in &sc.parachutes {
            let Some(t2) = trigger_t(&later.name.value) else {
                continue;
            };
            if t2 > t1 + tol && later.cd_area.value < first.cd_area.value {
                out.push(located(
                    first.name.span,
                    "run::parachute::order",
                    format!(
                        "parachute `{}` (cd_area {} m^2) opened at apogee (t = {:.3} s), before the smaller `{}` ({} m^2, t = {:.3} s): drogue and main swapped?",
                        first.name.value,
                        first.cd_area.value,
                        t1,
                        later.name.value,
                        later.cd_area.value,
                        t2
                    ),
                ));
            }
        }
    }
    out
}

/// Adds `warnings` to a run's summary (after those already there); creates the list.
pub fn add_to_summary(summary: &mut Value, warnings: Vec<Value>) {
    if let Some(map) = summary.as_object_mut() {
        let list = map
            .entry("warnings")
            .or_insert_with(|| Value::Array(Vec::new()));
        if let Some(l) = list.as_array_mut() {
            l.extend(warnings);
        }
    }
}

/// One terminal line per warning of a summary: `warning[CODE]: MESSAGE (FILE:LINE:COLUMN)`.
pub fn terminal_lines(summary: &Value) -> Vec<String> {
    summary["warnings"]
        .as_array()
        .map(|l| {
            l.iter()
                .map(|w| {
                    let mut s = format!(
                        "warning[{}]: {}",
                        w["code"].as_str().unwrap_or(""),
                        w["message"].as_str().unwrap_or("")
                    );
                    if let (Some(f), Some(line), Some(col)) =
                        (w["file"].as_str(), w["line"].as_u64(), w["column"].as_u64())
                    {
                        s.push_str(&format!(" ({f}:{line}:{col})"));
                    }
                    s
                })
                .collect()
        })
        .unwrap_or_default()
}
