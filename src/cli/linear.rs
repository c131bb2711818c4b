//! `flexflight analyze linear` and `flexflight analyze linear-map`: the linearised 3-D model
//! of a scenario ([`crate::analysis::linear`], [`crate::ops::linear`]) and its fin thickness x
//! Mach map.

use std::path::Path;

use crate::analysis::linear::linear_map;
use crate::analysis::linearise::LineariseOptions;
use crate::ops::linear::{load_variant, report_text};

use clap::Subcommand;
use std::path::PathBuf;

use super::{
    CacheArgs, Common, EXIT_DIAGNOSTICS, EXIT_OK, EXIT_USAGE, Format, Terminal, load_program,
};

/// `flexflight analyze linear ...` and `analyze linear-map ...` (flattened into
/// [`analyze::AnalyzeCommand`]).
#[derive(Subcommand, Debug)]
pub enum Analyze {
    /// Linearise the 3-D model about a trimmed ballistic condition (the scenario's speed,
    /// altitude and attitude, alpha = 0): trim, eigenvalues, damping, frequency and the
    /// states that participate in each root.
    Linear {
        file: PathBuf,
        #[arg(long)]
        scenario: String,
        /// Keep gravity fixed in body axes instead of rotating it with the attitude
        /// perturbation (removes the slow gravity-driven roots of the frozen reference).
        #[arg(long)]
        frozen_gravity: bool,
        #[command(flatten)]
        common: Common,
        #[command(flatten)]
        cache: CacheArgs,
    },
    /// Map sigma_d of the linearised 3-D model over fin thickness x Mach (the FE model is
    /// recompiled, through the cache, for every thickness); writes DIR/map.csv.
    LinearMap {
        file: PathBuf,
        #[arg(long)]
        scenario: String,
        /// Fin thickness range START:STOP:COUNT, each end with a length unit
        /// (0.3mm:1.2mm:10: COUNT points from START to STOP).
        #[arg(long, value_name = "START:STOP:COUNT")]
        thickness: String,
        /// Mach range START:STOP:COUNT, dimensionless (speed = Mach x speed of sound at the
        /// scenario's altitude).
        #[arg(long, value_name = "START:STOP:COUNT")]
        mach: String,
        /// Keep gravity fixed in body axes (as `analyze linear --frozen-gravity`).
        #[arg(long)]
        frozen_gravity: bool,
        #[arg(long)]
        out: PathBuf,
        #[command(flatten)]
        common: Common,
        #[command(flatten)]
        cache: CacheArgs,
    },
}

/// Runs `analyze linear` / `analyze linear-map`.
pub fn cmd_analyze_linear(cmd: &Analyze, term: Terminal) -> u8 {
    match cmd {
        Analyze::Linear {
            file,
            scenario,
            frozen_gravity,
            common,
            cache,
        } => cmd_linear(
            file,
            scenario,
            *frozen_gravity,
            common,
            cache.cache_dir.as_deref(),
            term,
        ),
        Analyze::LinearMap {
            file,
            scenario,
            thickness,
            mach,
            frozen_gravity,
            out,
            common,
            cache,
        } => cmd_linear_map(
            file,
            scenario,
            thickness,
            mach,
            *frozen_gravity,
            common,
            cache.cache_dir.as_deref(),
            out,
            term,
        ),
    }
}

/// `flexflight analyze linear`.
pub fn cmd_linear(
    file: &Path,
    scenario: &str,
    frozen_gravity: bool,
    common: &Common,
    cache_dir: Option<&Path>,
    term: Terminal,
) -> u8 {
    let mut checked = match load_program(&[file.to_path_buf()], common, term) {
        Ok(c) => c,
        Err(code) => return code,
    };
    let format = common.output.format;
    let r = match crate::ops::linear::linearise(
        &mut checked,
        scenario,
        frozen_gravity,
        cache_dir,
        &mut |w| eprintln!("warning: {w}"),
    ) {
        Ok(r) => r,
        Err(e) => return super::compile::fail(&e, &checked, format, term),
    };
    match format {
        Format::Human => out!("{}", report_text(&r.variant, &r.analysis)),
        Format::Json => outln!(
            "{}",
            serde_json::to_string_pretty(&crate::ops::linear::to_json(&r)).unwrap_or_default()
        ),
    }
    EXIT_OK
}

/// `flexflight analyze linear-map`: fin thickness x Mach, `DIR/map.csv`. The ranges carry
/// units (`--thickness 0.3mm:1.2mm:10`), checked like vehicle-file values.
#[allow(clippy::too_many_arguments)]
pub fn cmd_linear_map(
    file: &Path,
    scenario: &str,
    thickness: &str,
    mach: &str,
    frozen_gravity: bool,
    common: &Common,
    cache_dir: Option<&Path>,
    out: &Path,
    term: Terminal,
) -> u8 {
    let format = common.output.format;
    let (ts, ms) = match super::analyze::map_ranges(thickness, mach, None, format, term) {
        Ok((t, m, _)) => (t, m),
        Err(code) => return code,
    };
    let (thickness_m, ms) = (ts.values(), ms.values());
    let started = std::time::Instant::now();
    let load = |t: f64| {
        let mut sets = common.sets.clone();
        // Rust's shortest round-trip form: the override is the grid value to the last bit.
        sets.push(format!("fins.thickness={t} m"));
        load_variant(file, scenario, &sets, cache_dir, &mut |w| {
            eprintln!("warning: {w}")
        })
    };
    let options = LineariseOptions {
        gravity_follows_attitude: !frozen_gravity,
        ..LineariseOptions::default()
    };
    let result = match linear_map(&thickness_m, &ms, load, options) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: linear map failed: {e}");
            return EXIT_DIAGNOSTICS;
        }
    };
    if let Err(e) = std::fs::create_dir_all(out).and_then(|_| {
        result
            .map
            .write_csv_file(&out.join("map.csv"), "thickness_m", "mach")
    }) {
        eprintln!(
            "error: cannot write `{}`: {e}",
            out.join("map.csv").display()
        );
        return EXIT_USAGE;
    }
    let unstable = result
        .map
        .class
        .iter()
        .filter(|c| c.name() != "stable")
        .count();
    let drifting = result
        .map
        .flight_path_sigma
        .iter()
        .filter(|x| **x > 0.0)
        .count();
    match common.output.format {
        Format::Human => eprintln!(
            "{} x {} points ({} unstable, {} with a growing flight-path root, {} without trim) at {:.0} m in {:.2} s -> {}",
            thickness_m.len(),
            ms.len(),
            unstable,
            drifting,
            result.trim_failures.len(),
            result.altitude,
            started.elapsed().as_secs_f64(),
            out.join("map.csv").display()
        ),
        Format::Json => outln!(
            "{}",
            serde_json::to_string_pretty(&result).unwrap_or_default()
        ),
    }
    EXIT_OK
}
