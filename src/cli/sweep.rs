//! `flexflight sweep` and `flexflight merge`: run a sweep's cases ([`crate::ops::sweep`])
//! with a progress bar, join shard tables.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::analysis::sweep::{Shard, merge, ranges};
use crate::ops::Progress;
use crate::ops::sweep::{SweepOptions, read_shard, run_sweep, write_merged};

use super::{Common, EXIT_DIAGNOSTICS, EXIT_OK, EXIT_USAGE, Format, Terminal, load_program};

/// A progress bar on standard error (`N/M cases, rate, elapsed, ETA`); warnings printed
/// above it.
pub struct Bar(ProgressBar, &'static str);

impl Bar {
    pub fn new() -> Bar {
        Bar::counting("cases")
    }
    /// A bar whose units are `unit` (`cases`, `samples`).
    pub fn counting(unit: &'static str) -> Bar {
        Bar(
            ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr()),
            unit,
        )
    }
}

impl Default for Bar {
    fn default() -> Self {
        Bar::new()
    }
}

impl Progress for Bar {
    fn start(&self, label: &str, total: u64) {
        self.0.set_length(total);
        if let Ok(style) = ProgressStyle::with_template(&format!(
            "{{prefix}} [{{bar:30}}] {{pos}}/{{len}} {}, {{per_sec}}, {{elapsed}} elapsed, ETA {{eta}}",
            self.1
        )) {
            self.0.set_style(style.progress_chars("=> "));
        }
        self.0.set_prefix(label.to_string());
    }
    fn inc(&self, n: u64) {
        self.0.inc(n);
    }
    fn finish(&self) {
        self.0.finish_and_clear();
    }
    fn warning(&self, text: &str) {
        self.0.suspend(|| eprintln!("warning: {text}"));
    }
}

/// What `flexflight sweep` was asked to run.
#[derive(Clone, Copy, Debug)]
pub struct SweepRequest<'a> {
    pub file: &'a Path,
    pub sweep: &'a str,
    pub jobs: Option<usize>,
    /// `I/N` or `env`.
    pub shard: Option<&'a str>,
    pub out: &'a Path,
}

/// `flexflight sweep`.
pub fn cmd_sweep(
    req: SweepRequest<'_>,
    common: &Common,
    cache_dir: Option<&Path>,
    term: Terminal,
) -> u8 {
    let SweepRequest {
        file,
        sweep: sweep_name,
        jobs,
        shard,
        out,
    } = req;
    let shard = match shard.map(|s| Shard::parse(s, |k| std::env::var(k).ok())) {
        None => Shard::ALL,
        Some(Ok(s)) => s,
        Some(Err(e)) => {
            eprintln!("error: {e}");
            return EXIT_USAGE;
        }
    };
    let checked = match load_program(&[file.to_path_buf()], common, term) {
        Ok(c) => c,
        Err(code) => return code,
    };
    let program = &checked.program;
    let Some(sweep) = program.sweep(sweep_name) else {
        let declared = program.sweeps.iter().map(|s| s.name.value.as_str());
        return super::unknown_name("sweep", sweep_name, declared);
    };
    let Some(scenario) = program.scenarios.get(sweep.scenario) else {
        eprintln!("error: sweep `{sweep_name}` names a scenario that did not check");
        return EXIT_DIAGNOSTICS;
    };
    let opts = SweepOptions {
        jobs: jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from)),
        shard,
        cache_dir: cache_dir.map(Path::to_path_buf),
        sets: common.sets.clone(),
        progress: std::io::stderr()
            .is_terminal()
            .then(|| Arc::new(Bar::new()) as Arc<dyn Progress>),
    };
    match run_sweep(file, sweep, &scenario.name.value, out, &opts) {
        Ok(r) => {
            let line = format!(
                "sweep {}: shard {}/{}: {} case(s), {} run, {} resumed, {} failed, {} structural variant(s), {:.2} s -> {}",
                r.manifest.sweep,
                shard.index,
                shard.count,
                r.rows.len(),
                r.ran,
                r.skipped,
                r.failed,
                r.artifacts,
                r.wall_seconds,
                out.display()
            );
            match common.output.format {
                Format::Human => eprintln!("{line}"),
                Format::Json => outln!(
                    "{}",
                    serde_json::json!({
                        "sweep": r.manifest.sweep, "shard": r.manifest.shard,
                        "cases": r.rows.len(), "ran": r.ran, "resumed": r.skipped,
                        "failed": r.failed, "artifacts": r.artifacts,
                        "wall_time_s": r.wall_seconds, "out": out,
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

/// `flexflight merge`: join shard directories into one table. Exit 1 when cases are
/// missing (the merged table is still written) or the shards disagree.
pub fn cmd_merge(dirs: &[PathBuf], out: &Path) -> u8 {
    let mut tables = Vec::new();
    for d in dirs {
        match read_shard(d) {
            Ok(t) => tables.push(t),
            Err(e) => {
                eprintln!("error: {e}");
                return EXIT_USAGE;
            }
        }
    }
    let merged = match merge(&tables) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_DIAGNOSTICS;
        }
    };
    if let Err(e) = write_merged(out, &merged) {
        eprintln!("error: {e}");
        return EXIT_USAGE;
    }
    eprintln!(
        "merged {} table(s): {} of {} case(s) -> {}",
        tables.len(),
        merged.rows.len(),
        merged.manifest.case_count,
        out.join("sweep.csv").display()
    );
    if merged.missing.is_empty() {
        EXIT_OK
    } else {
        eprintln!(
            "error: {} case(s) missing: {}",
            merged.missing.len(),
            ranges(&merged.missing)
        );
        EXIT_DIAGNOSTICS
    }
}
