//! `flexflight compile`, `inspect` and `modes`: render the structural compiler's results
//! ([`crate::ops::compile`], [`crate::ops::inspect`]).

use std::path::Path;

use crate::artifact::CacheOutcome;
use crate::check::Checked;
use crate::check::ir::Vehicle;
use crate::ops::OpsError;
use crate::ops::compile::{CachedAero, CompileOutcome, summary_json, summary_text};
use crate::ops::inspect::{Inspected, human_tree, inspect};

use super::{EXIT_DIAGNOSTICS, EXIT_USAGE, Format, Terminal, emit};

/// [`crate::ops::compile::compile_cached`] for a command: on failure the diagnostics or the
/// message are printed and the exit code returned; a rebuilt artifact is a warning.
pub fn compile_cached(
    checked: &mut Checked,
    vehicle: &Vehicle,
    cache_dir: Option<&Path>,
    format: Format,
    term: Terminal,
) -> Result<CompileOutcome, u8> {
    match crate::ops::compile::compile_cached(checked, vehicle, cache_dir) {
        Ok(o) => {
            if let CacheOutcome::Rebuilt { .. } = &o.outcome {
                eprintln!("warning: {}", o.outcome);
            }
            Ok(o)
        }
        Err(e) => Err(fail(&e, checked, format, term)),
    }
}

/// Prints an operation's error and returns its exit code: diagnostics (rendered on the
/// checked sources) exit 1, a usage error 2, a coded failure 1 when the input is at fault,
/// else 2.
pub fn fail(e: &OpsError, checked: &Checked, format: Format, term: Terminal) -> u8 {
    match e {
        OpsError::Diagnostics(d) => {
            emit(d, &checked.sources, format, term);
            EXIT_DIAGNOSTICS
        }
        OpsError::Usage(m) => {
            eprintln!("error: {m}");
            EXIT_USAGE
        }
        OpsError::Coded {
            code,
            message,
            input,
        } => {
            eprintln!("error[{code}]: {message}");
            if *input { EXIT_DIAGNOSTICS } else { EXIT_USAGE }
        }
    }
}

/// [`crate::ops::compile::plan_cached`] with its cache warnings printed.
pub fn plan_cached(
    sc: &crate::check::ir::Scenario,
    c: &crate::structure::compile::CompiledVehicle,
    structural: &crate::artifact::CacheKey,
    cache: &crate::artifact::Cache,
) -> Result<(crate::plan::Plan, Option<CachedAero>), crate::plan::PlanError> {
    crate::ops::compile::plan_cached(sc, c, structural, cache, &mut |w| eprintln!("warning: {w}"))
}

pub fn print_outcome(o: &CompileOutcome, format: Format) {
    match format {
        Format::Human => {
            out!("{}", summary_text(&o.compiled));
            outln!("artifact       {}", o.path.display());
            outln!("hash           {}", o.key);
            outln!(
                "time           {:.3} s ({})",
                o.seconds,
                match &o.outcome {
                    CacheOutcome::Hit => "cache hit",
                    CacheOutcome::Miss => "compiled",
                    CacheOutcome::Rebuilt { .. } => "rebuilt after a bad cached artifact",
                }
            );
        }
        Format::Json => outln!(
            "{}",
            serde_json::to_string_pretty(&summary_json(o)).unwrap_or_default()
        ),
    }
}

/// `inspect`: every coefficient of an artifact file.
pub fn cmd_inspect(path: &Path, format: Format) -> u8 {
    match inspect(path) {
        Ok(Inspected::Vehicle(c)) => {
            match format {
                Format::Json => {
                    outln!("{}", serde_json::to_string_pretty(&c).unwrap_or_default())
                }
                Format::Human => {
                    out!("{}", summary_text(&c));
                    outln!("coefficients (3.2.1), row-major:");
                    let r = serde_json::to_value(&c.reduced).unwrap_or_default();
                    if let serde_json::Value::Object(map) = r {
                        for (k, v) in map {
                            outln!("  {k} = {v}");
                        }
                    }
                }
            }
            0
        }
        Ok(Inspected::Other(value)) => {
            match format {
                Format::Json => outln!(
                    "{}",
                    serde_json::to_string_pretty(&value).unwrap_or_default()
                ),
                Format::Human => out!("{}", human_tree(&value, 0)),
            }
            0
        }
        Err(OpsError::Usage(m)) => {
            eprintln!("error: {m}");
            EXIT_USAGE
        }
        Err(e) => {
            eprintln!(
                "error{}",
                match &e {
                    OpsError::Coded { code, message, .. } => format!("[{code}]: {message}"),
                    other => format!(": {other}"),
                }
            );
            EXIT_DIAGNOSTICS
        }
    }
}
