//! `flexflight plan` and `flexflight run`: render a scenario's plan, and fly it with
//! [`crate::ops::run`] (progress bar, terminal lines, exit status).

use std::io::IsTerminal;
use std::path::Path;
use std::time::Instant;

use crate::check::Checked;
use crate::ops::run::{
    Prepared, fin_panels_text, flight_line, flight_summary, fly, prepare, verdict_line,
    write_outputs,
};
use crate::plan;

use super::{
    Common, EXIT_INCOMPLETE, EXIT_OK, EXIT_USAGE, EXIT_VERDICT, Format, Terminal, load_program,
};

/// Check, compile and plan, the structure and the aerodynamics through the cache; errors
/// printed, their exit code returned.
fn prepare_with_scenario(
    file: &Path,
    scenario: &str,
    common: &Common,
    cache_dir: Option<&Path>,
    term: Terminal,
) -> Result<(Prepared, Checked), u8> {
    let mut checked: Checked = load_program(&[file.to_path_buf()], common, term)?;
    match prepare(&mut checked, scenario, cache_dir, &mut |w| {
        eprintln!("warning: {w}")
    }) {
        Ok(p) => Ok((p, checked)),
        Err(e) => Err(super::compile::fail(
            &e,
            &checked,
            common.output.format,
            term,
        )),
    }
}

/// `flexflight plan`: the plan as a human summary or JSON.
pub fn cmd_plan(
    file: &Path,
    scenario: &str,
    common: &Common,
    cache_dir: Option<&Path>,
    term: Terminal,
) -> u8 {
    let (prep, _) = match prepare_with_scenario(file, scenario, common, cache_dir, term) {
        Ok(x) => x,
        Err(code) => return code,
    };
    let (p, sc, compiled) = (&prep.plan, &prep.scenario, &prep.compiled);
    match common.output.format {
        Format::Human => {
            out!("{}", plan::summary_text(p));
            out!("{}", plan::fin_corners_text(&sc.vehicle));
            match p.aero.as_ref().and_then(|a| a.fin.as_ref()) {
                // The lifting-surface model's matrices, as the run uses them (from the cache).
                Some(f) if f.panel_model().is_some() => {
                    if let (Some(m), Some(fi)) = (f.panel_model(), sc.vehicle.fins.as_ref()) {
                        let area = 0.5 * (fi.root_chord.value + fi.tip_chord.value) * fi.span.value;
                        out!("{}", m.summary_text(&compiled.compiled, area));
                    }
                }
                _ => out!("{}", fin_panels_text(sc, &compiled.compiled)),
            }
        }
        Format::Json => outln!("{}", serde_json::to_string_pretty(p).unwrap_or_default()),
    }
    EXIT_OK
}

/// `flexflight run`: check, compile, plan, integrate, then write `history.csv` and
/// `summary.json` into `out` (created if needed; nothing is written unless the run ran).
pub fn cmd_run(
    file: &Path,
    scenario: &str,
    common: &Common,
    cache_dir: Option<&Path>,
    out: &Path,
    flutter_margin: Option<bool>,
    term: Terminal,
) -> u8 {
    let (prep, checked) = match prepare_with_scenario(file, scenario, common, cache_dir, term) {
        Ok(x) => x,
        Err(code) => return code,
    };
    let p = &prep.plan;
    // A progress bar on a terminal (simulated time against the stop time, in ms), nothing
    // otherwise; redrawn at most every 0.1 s so it costs nothing per step.
    let bar = if std::io::stderr().is_terminal() {
        indicatif::ProgressBar::with_draw_target(
            Some((p.stop.stop_time * 1e3).max(1.0) as u64),
            indicatif::ProgressDrawTarget::stderr_with_hz(10),
        )
    } else {
        indicatif::ProgressBar::hidden()
    };
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "{prefix} [{bar:30}] t = {msg} s, {elapsed} elapsed, ETA {eta}",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(format!("run {scenario}"));
    let mut last_update = Instant::now();
    let mut progress = |t: f64, _t_end: f64| {
        if last_update.elapsed().as_secs_f64() > 0.1 {
            last_update = Instant::now();
            bar.set_position((t * 1e3) as u64);
            bar.set_message(format!("{t:.4}"));
        }
    };
    let flown = fly(
        &prep,
        &checked.sources,
        flutter_margin,
        cache_dir,
        &mut progress,
        &mut |_| {},
    );
    bar.finish_and_clear();
    let flown = match flown {
        Ok(f) => f,
        Err(e) => return super::compile::fail(&e, &checked, common.output.format, term),
    };
    if let Some(m) = &flown.margin {
        for w in &m.warnings {
            eprintln!("warning: {w}");
        }
    }
    if let Err(e) = write_outputs(out, &flown) {
        eprintln!(
            "error: cannot write the run outputs to `{}`: {e}",
            out.display()
        );
        return EXIT_USAGE;
    }
    let (output, summary) = (&flown.output, &flown.summary);
    if common.output.format == Format::Human {
        eprintln!(
            "{}: {} at t = {} s ({} rows, {} steps, {:.3} s) -> {}",
            p.scenario,
            output.stop.code(),
            output.t_end,
            output.rows.len(),
            output.stats.accepted,
            output.wall_seconds,
            out.display()
        );
        if let Some(line) = verdict_line(p, output) {
            eprintln!("{line}");
        }
        if output.stop.is_incomplete() {
            eprintln!(
                "INCOMPLETE: the integration failed at t = {} s ({}) before the flight reached \
                 a stop of its scenario; the outputs are a flight cut short (exit status 4)",
                output.t_end, output.stop_detail
            );
        }
        if let Some(line) = flight_line(&flight_summary(p, output)) {
            eprintln!("{line}");
        }
        if let Some(line) = flown.margin.as_ref().map(|m| m.line.as_str()) {
            eprintln!("{line}");
        }
        for line in crate::ops::warnings::terminal_lines(summary) {
            eprintln!("  {line}");
        }
    } else {
        outln!(
            "{}",
            serde_json::to_string_pretty(summary).unwrap_or_default()
        );
    }
    if output.stop.is_verdict() {
        EXIT_VERDICT
    } else if output.stop.is_incomplete() {
        EXIT_INCOMPLETE
    } else {
        EXIT_OK
    }
}
