//! Operations: the library's API for everything a user can ask of flexflight (issue 36).
//!
//! Each operation takes a request (files, `--set` overrides, a cache directory, names) and
//! returns data or an [`OpsError`] that carries its diagnostics; warnings and progress go to
//! callbacks the caller gives. Operations never print, never read the terminal and never end
//! the process: the command line (`crate::cli`) and any other front end (the Python package,
//! an editor, a notebook) render what they return and choose what to do with it.
//!
//! Architecture invariant: `ops` imports every stage below it and nothing above it (never
//! `crate::cli`); `tests/layering.rs` checks it.

pub mod compile;
pub mod files;
pub mod floatfmt;
pub mod flutter;
pub mod gaf_cache;
pub mod inspect;
pub mod linear;
pub mod montecarlo;
pub mod planar;
pub mod report;
pub mod run;
pub mod sweep;
pub mod tunnel;
pub mod warnings;

use std::path::{Path, PathBuf};

use crate::artifact::Cache;
use crate::check::{Checked, DiskLoader, check_files};
use crate::diagnostics::Diagnostic;

/// Why an operation could not give its result.
#[derive(Debug)]
pub enum OpsError {
    /// The input is wrong: diagnostics pointing into the project's sources (the caller
    /// renders them with [`Project::checked`]'s `sources`, or the ones the operation names).
    Diagnostics(Vec<Diagnostic>),
    /// The request cannot be met as asked (an unknown name, a file that cannot be read or
    /// written, a bad option): a message for the user.
    Usage(String),
    /// A failure with a stable code (`artifact::...`, `run::cannot_start`): a message, and
    /// whether the input is at fault (`true`) or the environment (`false`).
    Coded {
        code: &'static str,
        message: String,
        input: bool,
    },
}

impl std::fmt::Display for OpsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            OpsError::Diagnostics(d) => match d.first() {
                Some(d) => write!(f, "{}", d.message),
                None => write!(f, "diagnostics"),
            },
            OpsError::Usage(m) => write!(f, "{m}"),
            OpsError::Coded { code, message, .. } => write!(f, "[{code}] {message}"),
        }
    }
}

impl std::error::Error for OpsError {}

/// Where a long operation reports its progress and its warnings (a terminal's progress bar,
/// a notebook's widget, a log). Called from worker threads.
pub trait Progress: Send + Sync {
    /// The work begins: `total` units under `label`.
    fn start(&self, label: &str, total: u64);
    /// `n` more units are done.
    fn inc(&self, n: u64);
    /// The work is over.
    fn finish(&self);
    /// A warning to show the user (the operation goes on).
    fn warning(&self, text: &str);
}

/// Makes faer's dense linear algebra (LU, Cholesky, eigen-solves, products) run on one
/// thread in this process. faer reads a process-wide setting whose default is all of rayon's
/// threads, and its parallel kernels split the work by thread count, which changes the last
/// bits of a result: the same analysis then differed between machines, and within one
/// process before and after a flight. Determinism (the same inputs, the same bits) comes
/// first; the operations parallelise over independent cases (sweep points, samples, Mach
/// nodes) instead. Called when a project opens, by the CLI before any command, and by the
/// operations that take checked inputs directly (`tests/parallelism.rs`).
pub fn sequential_linear_algebra() {
    faer::set_global_parallelism(faer::Par::Seq);
}

/// A checked set of vehicle files and where compiled artifacts are cached: what every
/// operation on a model starts from.
pub struct Project {
    /// The checked program, its sources and its warnings (a project opens only without
    /// errors).
    pub checked: Checked,
    /// The cache directory (`None`: `$FLEXFLIGHT_CACHE`, else `target/flexflight-cache`).
    pub cache_dir: Option<PathBuf>,
}

impl Project {
    /// Checks `files` with the `--set`-style overrides `sets` (`PATH=VALUE`). A missing file
    /// is [`OpsError::Usage`]; errors in the files are [`OpsError::Diagnostics`] (with the
    /// checked sources, to render them). Warnings stay in `checked.diagnostics`.
    // The checked sources travel with the error so that the caller can locate its
    // diagnostics; opening a project is once per front-end call, the size costs nothing.
    #[allow(clippy::result_large_err)]
    pub fn open(
        files: &[PathBuf],
        sets: &[String],
        cache_dir: Option<&Path>,
    ) -> Result<Project, (OpsError, Option<Checked>)> {
        sequential_linear_algebra();
        for f in files {
            if !f.is_file() {
                return Err((
                    OpsError::Usage(format!("cannot read `{}`: no such file", f.display())),
                    None,
                ));
            }
        }
        let checked = check_files(files, sets, &DiskLoader);
        if checked.has_errors() {
            let d = checked.diagnostics.clone();
            return Err((OpsError::Diagnostics(d), Some(checked)));
        }
        Ok(Project {
            checked,
            cache_dir: cache_dir.map(Path::to_path_buf),
        })
    }

    /// The artifact cache of this project.
    pub fn cache(&self) -> Cache {
        Cache::resolve(self.cache_dir.as_deref())
    }
}

/// A scenario name that names no flown scenario: a wind-tunnel scenario is named as such
/// (only the flutter analysis takes it), anything else as unknown with the declared names.
pub fn unknown_scenario(program: &crate::check::ir::Program, name: &str) -> OpsError {
    if program.tunnel_test(name).is_some() {
        return OpsError::Usage(format!(
            "scenario `{name}` tests a fixture in a wind tunnel: it is not flown; `flexflight analyze flutter FILE --scenario {name}` takes it"
        ));
    }
    unknown_name(
        "scenario",
        name,
        program.scenarios.iter().map(|s| s.name.value.as_str()),
    )
}

/// A name the program does not declare, with the names it does declare.
pub fn unknown_name<'a>(
    kind: &str,
    name: &str,
    declared: impl Iterator<Item = &'a str>,
) -> OpsError {
    let names: Vec<&str> = declared.collect();
    OpsError::Usage(format!(
        "no {kind} named `{name}`; declared: {}",
        if names.is_empty() {
            "none".to_string()
        } else {
            names.join(", ")
        }
    ))
}
