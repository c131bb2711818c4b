//! `flexflight montecarlo`: parse, call `ops::montecarlo::runner`, print, exit. The
//! merge of Monte Carlo shards is `flexflight merge` (it recognises `montecarlo.json`).

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use crate::analysis::sweep::{Shard, ranges};
use crate::ops::montecarlo::runner::{MonteCarloOptions, merge, run_dispersion, write_tables};

use super::{Common, EXIT_DIAGNOSTICS, EXIT_OK, EXIT_USAGE, Format, Terminal, load_program};

/// What `flexflight montecarlo` was asked to run.
#[derive(Clone, Copy, Debug)]
pub struct MonteCarloRequest<'a> {
    pub file: &'a Path,
    pub dispersion: &'a str,
    pub samples: Option<usize>,
    pub jobs: Option<usize>,
    pub shard: Option<&'a str>,
    pub out: &'a Path,
    pub flutter_margin: Option<bool>,
    /// The reference path: full runs and summaries.
    pub full_outputs: bool,
    /// Each sample's flutter boundary at its own thickness (no interpolation).
    pub exact_boundaries: bool,
}

/// `flexflight montecarlo`.
pub fn cmd_montecarlo(
    req: MonteCarloRequest<'_>,
    common: &Common,
    cache_dir: Option<&Path>,
    term: Terminal,
) -> u8 {
    let shard = match req
        .shard
        .map(|s| Shard::parse(s, |k| std::env::var(k).ok()))
    {
        None => Shard::ALL,
        Some(Ok(s)) => s,
        Some(Err(e)) => {
            eprintln!("error: {e}");
            return EXIT_USAGE;
        }
    };
    if req.samples == Some(0) {
        eprintln!("error: --samples must be at least 1");
        return EXIT_USAGE;
    }
    let checked = match load_program(&[req.file.to_path_buf()], common, term) {
        Ok(c) => c,
        Err(code) => return code,
    };
    let program = &checked.program;
    let Some(d) = program.dispersion(req.dispersion) else {
        let declared = program.dispersions.iter().map(|s| s.name.value.as_str());
        return super::unknown_name("dispersion", req.dispersion, declared);
    };
    let Some(scenario) = program.scenarios.get(d.scenario) else {
        eprintln!(
            "error: dispersion `{}` names a scenario that did not check",
            req.dispersion
        );
        return EXIT_DIAGNOSTICS;
    };
    let opts = MonteCarloOptions {
        samples: req.samples.unwrap_or(d.samples),
        jobs: req
            .jobs
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from)),
        shard,
        cache_dir: cache_dir.map(Path::to_path_buf),
        sets: common.sets.clone(),
        progress: std::io::stderr().is_terminal().then(|| {
            std::sync::Arc::new(super::sweep::Bar::counting("samples"))
                as std::sync::Arc<dyn crate::ops::Progress>
        }),
        flutter_margin: req.flutter_margin,
        full_summary: req.full_outputs,
        exact_boundaries: req.exact_boundaries,
    };
    match run_dispersion(req.file, d, &scenario.name.value, req.out, &opts) {
        Ok(r) => {
            match common.output.format {
                Format::Human => {
                    eprint!("{}", r.summary);
                    eprintln!(
                        "montecarlo {}: shard {}/{}: {} sample(s), {} run, {} resumed, {} failed, {} incomplete, {} structural variant(s), {:.2} s -> {}",
                        r.manifest.dispersion,
                        shard.index,
                        shard.count,
                        r.rows.len(),
                        r.ran,
                        r.skipped,
                        r.failed,
                        r.incomplete,
                        r.artifacts,
                        r.wall_seconds,
                        req.out.display()
                    );
                    let stages: Vec<String> = r
                        .phases
                        .stages()
                        .iter()
                        .map(|(n, s)| format!("{n} {s:.2} s"))
                        .collect();
                    eprintln!("time in the samples' stages: {}", stages.join(", "));
                }
                Format::Json => outln!(
                    "{}",
                    serde_json::json!({
                        "dispersion": r.manifest.dispersion, "shard": r.manifest.shard,
                        "samples": r.rows.len(), "ran": r.ran, "resumed": r.skipped,
                        "failed": r.failed, "incomplete": r.incomplete, "artifacts": r.artifacts,
                        "wall_time_s": r.wall_seconds, "out": req.out,
                        "stage_seconds": r.phases,
                    })
                ),
            }
            EXIT_OK
        }
        Err(e) => {
            eprintln!("error: {e}");
            EXIT_USAGE
        }
    }
}

/// `flexflight merge` of Monte Carlo shards (directories with `montecarlo.json`).
pub fn cmd_merge_montecarlo(dirs: &[PathBuf], out: &Path) -> u8 {
    let (manifest, rows, missing) = match merge(dirs) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_DIAGNOSTICS;
        }
    };
    if let Err(e) = std::fs::create_dir_all(out) {
        eprintln!("error: cannot create `{}`: {e}", out.display());
        return EXIT_USAGE;
    }
    let mpath = out.join("montecarlo.json");
    let text = serde_json::to_string_pretty(&manifest).unwrap_or_default() + "\n";
    if let Err(e) = crate::ops::montecarlo::runner::write_atomic(&mpath, &text) {
        eprintln!("error: cannot write `{}`: {e}", mpath.display());
        return EXIT_USAGE;
    }
    match write_tables(out, &manifest, &rows) {
        Ok(summary) => eprint!("{summary}"),
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_USAGE;
        }
    }
    eprintln!(
        "merged {} shard(s): {} of {} sample(s) -> {}",
        dirs.len(),
        rows.len(),
        manifest.samples,
        out.join("samples.csv").display()
    );
    if missing.is_empty() {
        EXIT_OK
    } else {
        eprintln!(
            "error: {} sample(s) missing: {}",
            missing.len(),
            ranges(&missing)
        );
        EXIT_DIAGNOSTICS
    }
}
