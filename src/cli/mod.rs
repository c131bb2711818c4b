//! The command-line front end: argument parsing, file IO, terminal output and exit codes.
//!
//! Exit codes: 0 clean, 1 diagnostics (the input is wrong), 2 usage or IO error, 141 standard
//! output closed by its reader ([`write_stdout`]).
//! Architecture invariant: this is the only module that touches the terminal and the
//! process; the stages it calls return data.

/// `print!` to standard output through [`write_stdout`]: a reader that went away ends the
/// process quietly ([`EXIT_BROKEN_PIPE`]) instead of panicking as `print!` does.
macro_rules! out {
    ($($t:tt)*) => { $crate::cli::write_stdout(format_args!($($t)*), false) };
}

/// `println!` to standard output through [`write_stdout`] (see [`out!`]).
macro_rules! outln {
    () => { $crate::cli::write_stdout(format_args!(""), true) };
    ($($t:tt)*) => { $crate::cli::write_stdout(format_args!($($t)*), true) };
}

pub mod analyze;
pub mod compile;
pub mod flutter;
mod fmt;
pub mod import;
pub mod linear;
pub mod montecarlo;
pub mod report;
pub mod run;
pub mod sweep;
pub mod tunnel;

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::check::{Checked, DiskLoader, check_files};
use crate::diagnostics::{self, Diagnostic, RenderOptions};
use crate::syntax::SourceMap;

#[derive(Parser, Debug)]
#[command(
    name = "flexflight",
    version,
    about = "Flight simulation and stability analysis of flexible rockets"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Check vehicle files: syntax, units, references, ranges. Exit 0 clean, 1 with diagnostics.
    Check {
        /// Vehicle description files (.vdl).
        #[arg(required = true)]
        files: Vec<PathBuf>,
        #[command(flatten)]
        common: Common,
    },
    /// Compile a vehicle's structure (FE model, modes, reduced coefficients) into the cache.
    Compile {
        /// Vehicle description file.
        file: PathBuf,
        /// The vehicle to compile (needed when the file declares several).
        #[arg(long)]
        vehicle: Option<String>,
        #[command(flatten)]
        common: Common,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Print every coefficient of a compiled artifact (.ffa).
    Inspect {
        artifact: PathBuf,
        #[command(flatten)]
        output: Output,
    },
    /// Compile (through the cache) and write the selected mode shapes as CSV, node by node.
    Modes {
        file: PathBuf,
        #[arg(long)]
        vehicle: Option<String>,
        /// Directory to write mode_NN_NAME.csv files into.
        #[arg(long)]
        export: PathBuf,
        #[command(flatten)]
        common: Common,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Print a scenario's simulation plan: initial state, integrator, stop conditions, force
    /// blocks, stimuli, output channels.
    Plan {
        file: PathBuf,
        /// The scenario to plan.
        #[arg(long)]
        scenario: String,
        #[command(flatten)]
        common: Common,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Run a scenario in the time domain; writes DIR/history.csv and DIR/summary.json.
    Run {
        file: PathBuf,
        /// The scenario to run.
        #[arg(long)]
        scenario: String,
        /// Output directory (created if needed; nothing is written if the run cannot start).
        #[arg(long)]
        out: PathBuf,
        /// Compute the flutter margin over the flight (clamped-fin boundary; on by default
        /// for a launch from a rail, off otherwise).
        #[arg(long, conflicts_with = "no_flutter_margin")]
        flutter_margin: bool,
        /// Skip the flutter margin.
        #[arg(long)]
        no_flutter_margin: bool,
        #[command(flatten)]
        common: Common,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Stability analyses: planar eigen-stability models (thesis 6.1-6.2) and stability maps.
    Analyze {
        #[command(subcommand)]
        command: analyze::AnalyzeCommand,
    },
    /// Draw a run's figures (or a stability map) as SVG and PNG with an HTML index in
    /// DIR/report/.
    Report {
        /// A run directory (history.csv, summary.json) or a map directory (map.csv).
        dir: PathBuf,
        /// Times (s) of the deformation frames, comma-separated (default: 4 evenly spaced).
        #[arg(long, value_name = "T1,T2,...")]
        frames: Option<String>,
        /// Displacement magnification of the frames: `auto` (largest = 10 % of the span) or
        /// a number.
        #[arg(long, value_name = "auto|X")]
        magnify: Option<String>,
        /// The run's vehicle file: the FE mesh is rebuilt from it to draw element edges.
        #[arg(long)]
        vehicle_file: Option<PathBuf>,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Run the cases of a sweep in parallel: DIR/cases/<case_id>/ per case, DIR/sweep.csv.
    /// Finished cases are skipped on a re-run.
    Sweep {
        file: PathBuf,
        /// The sweep to run.
        #[arg(long)]
        sweep: String,
        /// Worker threads (default: the number of cores).
        #[arg(long)]
        jobs: Option<usize>,
        /// Run only cases with index % N == I: `I/N`, or `env` to read SLURM_ARRAY_TASK_ID
        /// and SLURM_ARRAY_TASK_COUNT.
        #[arg(long, value_name = "I/N|env")]
        shard: Option<String>,
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
        #[command(flatten)]
        common: Common,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Monte Carlo: fly the samples of a `dispersion` in parallel; DIR/samples.csv,
    /// DIR/statistics.json and .txt. Finished samples are skipped on a re-run.
    Montecarlo {
        file: PathBuf,
        /// The dispersion to run.
        #[arg(long)]
        dispersion: String,
        /// Samples (default: the dispersion's `samples`).
        #[arg(long)]
        samples: Option<usize>,
        /// Worker threads (default: the number of cores).
        #[arg(long)]
        jobs: Option<usize>,
        /// Run only samples with index % N == I: `I/N`, or `env` (Slurm job arrays).
        #[arg(long, value_name = "I/N|env")]
        shard: Option<String>,
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
        /// Skip the flutter margin of each sample (on by default for a launch from a rail).
        #[arg(long)]
        no_flutter_margin: bool,
        /// Fly every sample with all its rows and read its outputs from the complete run
        /// summary (the reference of the fast path: the same results, slower).
        #[arg(long)]
        full_outputs: bool,
        /// Solve each sample's flutter boundary at its own fin thickness instead of
        /// interpolating between boundaries compiled at a few thicknesses.
        #[arg(long)]
        exact_boundaries: bool,
        #[command(flatten)]
        common: Common,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Join the tables of sweep or Monte Carlo shards (DIR/sweep.csv or DIR/samples.csv)
    /// into one, in index order.
    Merge {
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Output directory for the merged sweep.csv and sweep.json.
        #[arg(long)]
        out: PathBuf,
    },
    /// Import an OpenRocket design (.ork) as a vehicle file with a scenario per stored
    /// simulation; the thrust curves it names are written beside it.
    Import {
        /// The design (.ork: plain XML, gzip or ZIP).
        design: PathBuf,
        /// The vehicle file to write (nothing is written on an error).
        #[arg(short = 'o', long = "out")]
        out: PathBuf,
        /// A directory of RASP .eng thrust curves searched before the bundled catalogue.
        #[arg(long = "motor-dir")]
        motor_dirs: Vec<PathBuf>,
        /// The stiffness of a design material the standard library does not map:
        /// 'NAME=E,nu' with E in GPa or MPa, e.g. 'Cardboard=2.5 GPa,0.3'.
        #[arg(long = "material", value_name = "NAME=E,nu")]
        materials: Vec<String>,
        /// The motor to fly, by designation ('AeroTech K1000T'): supplies one where the
        /// design stores none and replaces the design's where it does.
        #[arg(long = "motor", value_name = "DESIGNATION")]
        motor: Option<String>,
        #[command(flatten)]
        output: Output,
    },
    /// Format vehicle files canonically (in place, or report with --check).
    Fmt {
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Do not write; exit 1 if any file is not formatted.
        #[arg(long)]
        check: bool,
        #[command(flatten)]
        output: Output,
    },
}

/// Options shared by commands that read a vehicle or scenario.
#[derive(Args, Debug, Clone, Default)]
pub struct Common {
    /// Override a field: PATH=VALUE with the syntax of `with`, e.g. --set 'fins.thickness=0.6 mm'.
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub sets: Vec<String>,
    #[command(flatten)]
    pub output: Output,
}

#[derive(Args, Debug, Clone, Default)]
pub struct CacheArgs {
    /// Cache directory (default: $FLEXFLIGHT_CACHE, else target/flexflight-cache).
    #[arg(long)]
    pub cache_dir: Option<PathBuf>,
}

#[derive(Args, Debug, Clone, Default)]
pub struct Output {
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    pub format: Format,
}

#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Format {
    #[default]
    Human,
    Json,
}

/// How the terminal wants diagnostics drawn (decided by the binary).
#[derive(Clone, Copy, Debug)]
pub struct Terminal {
    pub render: RenderOptions,
}

pub const EXIT_OK: u8 = 0;
pub const EXIT_DIAGNOSTICS: u8 = 1;
pub const EXIT_USAGE: u8 = 2;
/// `run`: the flight left its model (a flutter, divergence or model-limit verdict); its
/// outputs are written and end at the verdict.
pub const EXIT_VERDICT: u8 = 3;
/// `run`: the integration failed before the flight reached any of its stops
/// (`step_underflow`, `non_finite`, `max_steps`: `RunStop::is_incomplete`); its outputs are
/// written, say `complete: false` and end where it failed, a flight cut short.
pub const EXIT_INCOMPLETE: u8 = 4;
/// Standard output was closed by its reader (`flexflight inspect X | head`): 128 + SIGPIPE,
/// the status a shell reports for a tool the signal ended.
pub const EXIT_BROKEN_PIPE: u8 = 141;

/// Writes `args` (and a newline) to standard output. A reader that went away
/// (`ErrorKind::BrokenPipe`) ends the process quietly with [`EXIT_BROKEN_PIPE`]; any other
/// write error ends it with a message and [`EXIT_USAGE`]. Output files are written before the
/// summary is printed, so nothing the command owes the user is lost.
pub fn write_stdout(args: std::fmt::Arguments<'_>, newline: bool) {
    let mut o = std::io::stdout().lock();
    let r = o
        .write_fmt(args)
        .and_then(|()| if newline { o.write_all(b"\n") } else { Ok(()) });
    if let Err(e) = r {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(i32::from(EXIT_BROKEN_PIPE));
        }
        eprintln!("error: cannot write to standard output: {e}");
        std::process::exit(i32::from(EXIT_USAGE));
    }
}

/// Run a parsed command line.
pub fn run(cli: Cli, term: Terminal) -> ExitCode {
    crate::ops::sequential_linear_algebra();
    let code = match cli.command {
        Command::Check { files, common } => cmd_check(&files, &common, term),
        Command::Import {
            design,
            out,
            motor_dirs,
            materials,
            motor,
            output,
        } => import::cmd_import(
            &design,
            &out,
            &motor_dirs,
            &materials,
            motor.as_deref(),
            output.format,
            term,
        ),
        Command::Fmt {
            files,
            check,
            output,
        } => fmt::cmd_fmt(&files, check, output.format, term),
        Command::Compile {
            file,
            vehicle,
            common,
            cache,
        } => compile::cmd_compile(
            &file,
            vehicle.as_deref(),
            &common,
            cache.cache_dir.as_deref(),
            None,
            term,
        ),
        Command::Plan {
            file,
            scenario,
            common,
            cache,
        } => run::cmd_plan(&file, &scenario, &common, cache.cache_dir.as_deref(), term),
        Command::Run {
            file,
            scenario,
            out,
            flutter_margin,
            no_flutter_margin,
            common,
            cache,
        } => run::cmd_run(
            &file,
            &scenario,
            &common,
            cache.cache_dir.as_deref(),
            &out,
            match (flutter_margin, no_flutter_margin) {
                (true, _) => Some(true),
                (_, true) => Some(false),
                _ => None,
            },
            term,
        ),
        Command::Analyze { command } => analyze::cmd_analyze(&command, term),
        Command::Report {
            dir,
            frames,
            magnify,
            vehicle_file,
            cache,
        } => report::cmd_report(
            &crate::ops::report::ReportArgs {
                dir: &dir,
                frames: frames.as_deref(),
                magnify: magnify.as_deref(),
                vehicle_file: vehicle_file.as_deref(),
                cache_dir: cache.cache_dir.as_deref(),
            },
            term,
        ),
        Command::Sweep {
            file,
            sweep,
            jobs,
            shard,
            out,
            common,
            cache,
        } => sweep::cmd_sweep(
            sweep::SweepRequest {
                file: &file,
                sweep: &sweep,
                jobs,
                shard: shard.as_deref(),
                out: &out,
            },
            &common,
            cache.cache_dir.as_deref(),
            term,
        ),
        Command::Montecarlo {
            file,
            dispersion,
            samples,
            jobs,
            shard,
            out,
            no_flutter_margin,
            full_outputs,
            exact_boundaries,
            common,
            cache,
        } => montecarlo::cmd_montecarlo(
            montecarlo::MonteCarloRequest {
                file: &file,
                dispersion: &dispersion,
                samples,
                jobs,
                shard: shard.as_deref(),
                out: &out,
                flutter_margin: no_flutter_margin.then_some(false),
                full_outputs,
                exact_boundaries,
            },
            &common,
            cache.cache_dir.as_deref(),
            term,
        ),
        Command::Merge { dirs, out }
            if dirs.iter().any(|d| d.join("montecarlo.json").is_file()) =>
        {
            montecarlo::cmd_merge_montecarlo(&dirs, &out)
        }
        Command::Merge { dirs, out } => sweep::cmd_merge(&dirs, &out),
        Command::Inspect { artifact, output } => compile::cmd_inspect(&artifact, output.format),
        Command::Modes {
            file,
            vehicle,
            export,
            common,
            cache,
        } => compile::cmd_compile(
            &file,
            vehicle.as_deref(),
            &common,
            cache.cache_dir.as_deref(),
            Some(&export),
            term,
        ),
    };
    ExitCode::from(code)
}

/// Print diagnostics in the chosen format to stderr (human) or stdout (json).
pub fn emit(diags: &[Diagnostic], sources: &SourceMap, format: Format, term: Terminal) {
    match format {
        Format::Human => {
            let text = diagnostics::render(diags, sources, term.render);
            let _ = std::io::stderr().write_all(text.as_bytes());
        }
        Format::Json => {
            let json = serde_json::json!({ "diagnostics": diagnostics::to_json(diags, sources) });
            outln!(
                "{}",
                serde_json::to_string_pretty(&json).unwrap_or_default()
            );
        }
    }
}

/// Check files; print diagnostics; return the result if there were no errors.
pub fn load_program(files: &[PathBuf], common: &Common, term: Terminal) -> Result<Checked, u8> {
    for f in files {
        if !f.is_file() {
            eprintln!("error: cannot read `{}`: no such file", f.display());
            return Err(EXIT_USAGE);
        }
    }
    let checked = check_files(files, &common.sets, &DiskLoader);
    if !checked.diagnostics.is_empty() {
        // Warnings alone (the input is usable) go to standard error in both formats: with
        // `--format json` standard output holds the command's one JSON document (`check`'s
        // lists them in its `diagnostics`, `run`'s summary in its `warnings`).
        let format = if checked.has_errors() {
            common.output.format
        } else {
            Format::Human
        };
        emit(&checked.diagnostics, &checked.sources, format, term);
    }
    if checked.has_errors() {
        Err(EXIT_DIAGNOSTICS)
    } else {
        Ok(checked)
    }
}

fn cmd_check(files: &[PathBuf], common: &Common, term: Terminal) -> u8 {
    match load_program(files, common, term) {
        Err(code) => code,
        Ok(checked) => {
            let p = &checked.program;
            match common.output.format {
                Format::Human => {
                    let fixtures = if p.fixtures.is_empty() && p.tunnel_tests.is_empty() {
                        String::new()
                    } else {
                        format!(
                            ", {} fixture(s), {} wind-tunnel scenario(s)",
                            p.fixtures.len(),
                            p.tunnel_tests.len()
                        )
                    };
                    let warnings = match checked.diagnostics.len() {
                        0 => String::new(),
                        n => format!(", {n} warning(s)"),
                    };
                    eprintln!(
                        "ok: {} material(s), {} vehicle(s), {} scenario(s), {} sweep(s){fixtures}{warnings}",
                        p.materials.len(),
                        p.vehicles.len(),
                        p.scenarios.len(),
                        p.sweeps.len()
                    )
                }
                Format::Json => {
                    let json = serde_json::json!({
                        "diagnostics": diagnostics::to_json(&checked.diagnostics, &checked.sources),
                        "materials": p.materials.iter().map(|m| &m.name.value).collect::<Vec<_>>(),
                        "vehicles": p.vehicles.iter().map(|v| &v.name.value).collect::<Vec<_>>(),
                        "scenarios": p.scenarios.iter().map(|s| &s.name.value).collect::<Vec<_>>(),
                        "sweeps": p.sweeps.iter().map(|s| &s.name.value).collect::<Vec<_>>(),
                        "fixtures": p.fixtures.iter().map(|x| &x.name.value).collect::<Vec<_>>(),
                        "tunnel_scenarios": p.tunnel_tests.iter().map(|t| &t.name.value).collect::<Vec<_>>(),
                    });
                    outln!(
                        "{}",
                        serde_json::to_string_pretty(&json).unwrap_or_default()
                    );
                }
            }
            EXIT_OK
        }
    }
}

/// A scenario name that names no flown scenario ([`crate::ops::unknown_scenario`]),
/// printed; returns the usage exit code.
pub(crate) fn unknown_scenario(program: &crate::check::ir::Program, name: &str) -> u8 {
    eprintln!("error: {}", crate::ops::unknown_scenario(program, name));
    EXIT_USAGE
}

/// A name the program does not declare ([`crate::ops::unknown_name`]), printed; returns the
/// usage exit code.
pub(crate) fn unknown_name<'a>(
    kind: &str,
    name: &str,
    declared: impl Iterator<Item = &'a str>,
) -> u8 {
    eprintln!("error: {}", crate::ops::unknown_name(kind, name, declared));
    EXIT_USAGE
}
