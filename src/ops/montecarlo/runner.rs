//! Running a dispersion: every sample of this shard checked, compiled through the artifact
//! cache, flown, its flutter margin evaluated, its outputs written; then `samples.csv`,
//! `statistics.json` and `statistics.txt` for the samples of the shard.
//!
//! Layout of an output directory:
//! - `montecarlo.json`: the dispersion (entries, seed), sample count, shard and columns;
//! - `samples/<sample_id>.json`: one file per finished sample (its drawn inputs, the
//!   checked variant's hash and its outputs, or its error); its presence with the same
//!   inputs and variant means done;
//! - `samples.csv`, `statistics.json`, `statistics.txt` (module [`crate::analysis::montecarlo::stats`]).
//!
//! Determinism: a sample's inputs are a pure function of (seed, index) (`crate::analysis::montecarlo::stream`);
//! each sample runs on one thread with faer's parallelism sequential; rows are written in
//! index order; so every file is byte-identical whatever `--jobs` is, and a shard's rows
//! are the full run's rows of its indices. Every file is written to a temporary name and
//! renamed, so an interrupted run leaves only complete files and a re-run skips the samples
//! already done.
//!
//! Sharing: samples whose structure is the same (the same structural cache key: a
//! dispersion of the wind, the launch, the parachutes or the site) share one compiled
//! artifact and one set of aerodynamic tables, and the flutter boundary of one vehicle is
//! built once and then read from the cache. A drawn input that enters the structure (fin
//! thickness, a material constant, a point mass, the motor's size) gives each sample its
//! own structural key: that sample compiles its own artifact and builds its own flutter
//! boundary (both through the cache, so a re-run reads them back). That is the cost of a
//! structural dispersion; docs/performance.md measures it.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::analysis::sweep::Shard;
use crate::artifact::{Cache, CacheKey};
use crate::check::ir::{Dispersion, DispersionEntry, Scenario};
use crate::check::{DiskLoader, check_scenario_files};
use crate::ops::compile::{CachedAero, CompileOutcome, aero_cache_key, vehicle_aero_cached};

use crate::analysis::montecarlo::{
    SampleOutputs, draw, sample_id, set_strings, table_csv, table_header, table_row,
};

/// How to run a dispersion.
#[derive(Clone, Debug)]
pub struct MonteCarloOptions {
    /// Samples (default: the dispersion's `samples`).
    pub samples: usize,
    pub jobs: usize,
    pub shard: Shard,
    pub cache_dir: Option<PathBuf>,
    /// `--set` overrides applied to every sample before its draws.
    pub sets: Vec<String>,
    pub progress: bool,
    /// Compute the flutter margin of each sample (`None`: when the scenario has a launch).
    pub flutter_margin: Option<bool>,
}

/// `montecarlo.json`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Manifest {
    pub dispersion: String,
    pub scenario: String,
    pub seed: u64,
    pub samples: usize,
    pub shard: Shard,
    pub entries: Vec<DispersionEntry>,
    pub columns: Vec<String>,
    /// The stream's definition, for whoever reads the directory later.
    pub stream: String,
}

/// What a run did.
#[derive(Clone, Debug)]
pub struct MonteCarloReport {
    pub manifest: Manifest,
    pub rows: Vec<Vec<String>>,
    pub ran: usize,
    pub skipped: usize,
    pub failed: usize,
    /// Distinct structural variants (artifacts) among the samples run.
    pub artifacts: usize,
    pub wall_seconds: f64,
    /// The text summary (`statistics.txt`).
    pub summary: String,
}

#[derive(Debug, thiserror::Error)]
pub enum MonteCarloError {
    #[error("cannot write `{path}`: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot start {jobs} worker threads: {reason}")]
    ThreadPool { jobs: usize, reason: String },
    #[error("cannot write the table: {0}")]
    Csv(#[from] csv::Error),
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> MonteCarloError + '_ {
    move |source| MonteCarloError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Write through a temporary file in the same directory, then rename.
pub fn write_atomic(path: &Path, text: &str) -> std::io::Result<()> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.mc.{}", std::process::id()));
    std::fs::write(&tmp, text)?;
    std::fs::rename(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

/// The record of one finished sample (`samples/<id>.json`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
struct SampleRecord {
    index: usize,
    inputs: Vec<f64>,
    /// blake3 of the checked scenario variant (empty when it did not check).
    variant: String,
    status: String,
    error: Option<String>,
    outputs: Option<OutputsRecord>,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
struct OutputsRecord {
    stop_reason: String,
    verdict: String,
    apogee_m: Option<f64>,
    t_apogee_s: Option<f64>,
    max_mach: Option<f64>,
    max_q_pa: Option<f64>,
    off_rail_speed_m_s: Option<f64>,
    min_static_margin_cal: Option<f64>,
    landing_x_m: Option<f64>,
    landing_y_m: Option<f64>,
    flutter_margin_min: Option<f64>,
}

impl From<&SampleOutputs> for OutputsRecord {
    fn from(o: &SampleOutputs) -> Self {
        OutputsRecord {
            stop_reason: o.stop_reason.clone(),
            verdict: o.verdict.clone(),
            apogee_m: o.apogee_m,
            t_apogee_s: o.t_apogee_s,
            max_mach: o.max_mach,
            max_q_pa: o.max_q_pa,
            off_rail_speed_m_s: o.off_rail_speed_m_s,
            min_static_margin_cal: o.min_static_margin_cal,
            landing_x_m: o.landing_x_m,
            landing_y_m: o.landing_y_m,
            flutter_margin_min: o.flutter_margin_min,
        }
    }
}

impl From<&OutputsRecord> for SampleOutputs {
    fn from(o: &OutputsRecord) -> Self {
        SampleOutputs {
            stop_reason: o.stop_reason.clone(),
            verdict: o.verdict.clone(),
            apogee_m: o.apogee_m,
            t_apogee_s: o.t_apogee_s,
            max_mach: o.max_mach,
            max_q_pa: o.max_q_pa,
            off_rail_speed_m_s: o.off_rail_speed_m_s,
            min_static_margin_cal: o.min_static_margin_cal,
            landing_x_m: o.landing_x_m,
            landing_y_m: o.landing_y_m,
            flutter_margin_min: o.flutter_margin_min,
        }
    }
}

/// The samples still to use a shared value, and the value.
type Cell<T> = (usize, Arc<OnceLock<T>>);

/// A value shared by the samples of one key, dropped when the last of them is done.
struct Shared<T> {
    cells: Mutex<BTreeMap<CacheKey, Cell<T>>>,
}

impl<T> Shared<T> {
    fn new(keys: impl Iterator<Item = CacheKey>) -> Self {
        let mut cells: BTreeMap<CacheKey, Cell<T>> = BTreeMap::new();
        for k in keys {
            cells.entry(k).or_insert((0, Arc::new(OnceLock::new()))).0 += 1;
        }
        Shared {
            cells: Mutex::new(cells),
        }
    }
    fn cell(&self, k: &CacheKey) -> Option<Arc<OnceLock<T>>> {
        let cells = self.cells.lock().ok()?;
        cells.get(k).map(|(_, c)| Arc::clone(c))
    }
    fn done(&self, k: &CacheKey) {
        if let Ok(mut cells) = self.cells.lock() {
            if let Some((left, _)) = cells.get_mut(k) {
                *left -= 1;
                if *left == 0 {
                    cells.remove(k);
                }
            }
        }
    }
    fn len(&self) -> usize {
        self.cells.lock().map_or(0, |c| c.len())
    }
}

/// A sample checked and keyed.
struct Prepared {
    scenario: Scenario,
    key: CacheKey,
    variant: String,
    aero_key: Option<CacheKey>,
}

fn prepare(file: &Path, scenario: &str, sets: &[String]) -> Result<Prepared, String> {
    let checked = check_scenario_files(&[file.to_path_buf()], sets, scenario, &DiskLoader);
    if checked.has_errors() {
        return Err(checked
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .map(|d| format!("{}: {}", d.code, d.message))
            .collect::<Vec<_>>()
            .join("; "));
    }
    let sc = checked
        .program
        .scenario(scenario)
        .cloned()
        .ok_or_else(|| format!("scenario `{scenario}` did not check"))?;
    let (key, variant, _) = crate::ops::sweep::case_fingerprints(&sc)?;
    let has_aero = sc.vehicle.forces.body_aero.is_some() || sc.vehicle.forces.fin_aero.is_some();
    let aero_key = if has_aero {
        aero_cache_key(&sc.vehicle, &key).ok()
    } else {
        None
    };
    Ok(Prepared {
        scenario: sc,
        key,
        variant,
        aero_key,
    })
}

/// The finished record of a sample with these inputs and variant, if there is one.
fn finished(dir: &Path, id: &str, inputs: &[f64], variant: &str) -> Option<SampleRecord> {
    let text = std::fs::read_to_string(dir.join(format!("{id}.json"))).ok()?;
    let r: SampleRecord = serde_json::from_str(&text).ok()?;
    let same_inputs = r.inputs.len() == inputs.len()
        && r.inputs
            .iter()
            .zip(inputs)
            .all(|(a, b)| a.to_bits() == b.to_bits());
    (r.status == "ok" && same_inputs && r.variant == variant).then_some(r)
}

/// Run (this shard of) `d`, declared in `file`, into `out`.
pub fn run_dispersion(
    file: &Path,
    d: &Dispersion,
    scenario: &str,
    out: &Path,
    opts: &MonteCarloOptions,
) -> Result<MonteCarloReport, MonteCarloError> {
    let started = Instant::now();
    crate::ops::sequential_linear_algebra();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.jobs.max(1))
        .build()
        .map_err(|e| MonteCarloError::ThreadPool {
            jobs: opts.jobs,
            reason: e.to_string(),
        })?;
    let header = table_header(d);
    let manifest = Manifest {
        dispersion: d.name.value.clone(),
        scenario: scenario.to_string(),
        seed: d.seed,
        samples: opts.samples,
        shard: opts.shard,
        entries: d.entries.clone(),
        columns: header.clone(),
        stream: "u(seed, i, j) = ((mix(mix(mix(seed) ^ i) ^ j) >> 11) + 0.5) / 2^53, mix the \
                 SplitMix64 output function; normals by Acklam's inverse CDF with a Halley step"
            .to_string(),
    };
    let samples_dir = out.join("samples");
    std::fs::create_dir_all(&samples_dir).map_err(io_err(&samples_dir))?;
    let mpath = out.join("montecarlo.json");
    write_atomic(
        &mpath,
        &(serde_json::to_string_pretty(&manifest).unwrap_or_default() + "\n"),
    )
    .map_err(io_err(&mpath))?;

    let indices: Vec<usize> = (0..opts.samples).filter(|&i| opts.shard.takes(i)).collect();
    let inputs: Vec<Vec<f64>> = indices.iter().map(|&i| draw(d, i as u64)).collect();
    let prepared: Vec<Result<Prepared, String>> = pool.install(|| {
        indices
            .par_iter()
            .zip(inputs.par_iter())
            .map(|(_, x)| {
                let mut sets = opts.sets.clone();
                sets.extend(set_strings(d, x));
                prepare(file, scenario, &sets)
            })
            .collect()
    });
    let ids: Vec<String> = indices
        .iter()
        .map(|&i| sample_id(i, opts.samples))
        .collect();
    let mut outcomes: Vec<Option<Result<SampleOutputs, String>>> = (0..indices.len())
        .map(|k| {
            let p = prepared[k].as_ref().ok()?;
            finished(&samples_dir, &ids[k], &inputs[k], &p.variant)
                .and_then(|r| r.outputs.as_ref().map(|o| Ok(SampleOutputs::from(o))))
        })
        .collect();
    let todo: Vec<usize> = (0..indices.len())
        .filter(|&k| outcomes[k].is_none())
        .collect();
    let skipped = indices.len() - todo.len();

    let bar = if opts.progress {
        ProgressBar::with_draw_target(Some(todo.len() as u64), ProgressDrawTarget::stderr())
    } else {
        ProgressBar::hidden()
    };
    if let Ok(style) = ProgressStyle::with_template(
        "{prefix} [{bar:30}] {pos}/{len} samples, {per_sec}, {elapsed} elapsed, ETA {eta}",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(format!("montecarlo {}", d.name.value));

    let cache = Cache::resolve(opts.cache_dir.as_deref());
    let ok_prep = || todo.iter().filter_map(|&k| prepared[k].as_ref().ok());
    let compiled: Shared<Result<Arc<CompileOutcome>, String>> =
        Shared::new(ok_prep().map(|p| p.key));
    let aero: Shared<Option<Arc<CachedAero>>> = Shared::new(ok_prep().filter_map(|p| p.aero_key));
    let artifacts = compiled.len();

    let results: Vec<Result<SampleOutputs, String>> = pool.install(|| {
        todo.par_iter()
            .map(|&k| {
                let result = prepared[k].as_ref().map_err(Clone::clone).and_then(|p| {
                    let r = run_sample(p, &compiled, &aero, &cache, opts.flutter_margin);
                    compiled.done(&p.key);
                    if let Some(a) = &p.aero_key {
                        aero.done(a);
                    }
                    r
                });
                let record = SampleRecord {
                    index: indices[k],
                    inputs: inputs[k].clone(),
                    variant: prepared[k]
                        .as_ref()
                        .map(|p| p.variant.clone())
                        .unwrap_or_default(),
                    status: if result.is_ok() { "ok" } else { "failed" }.to_string(),
                    error: result.as_ref().err().cloned(),
                    outputs: result.as_ref().ok().map(OutputsRecord::from),
                };
                let path = samples_dir.join(format!("{}.json", ids[k]));
                let text = serde_json::to_string_pretty(&record).unwrap_or_default() + "\n";
                let written = write_atomic(&path, &text);
                bar.inc(1);
                match written {
                    Ok(()) => result,
                    Err(e) => Err(format!("{}: {e}", path.display())),
                }
            })
            .collect()
    });
    bar.finish_and_clear();
    let failed = results.iter().filter(|r| r.is_err()).count();
    for (&k, r) in todo.iter().zip(results) {
        outcomes[k] = Some(r);
    }
    let rows: Vec<Vec<String>> = (0..indices.len())
        .map(|k| {
            let o = outcomes[k]
                .clone()
                .unwrap_or_else(|| Err("not run".to_string()));
            table_row(indices[k], &ids[k], &inputs[k], &o)
        })
        .collect();
    let summary = write_tables(out, &manifest, &rows)?;
    Ok(MonteCarloReport {
        manifest,
        rows,
        ran: todo.len(),
        skipped,
        failed,
        artifacts,
        wall_seconds: started.elapsed().as_secs_f64(),
        summary,
    })
}

/// Write `samples.csv`, `statistics.json` and `statistics.txt` for `rows`; returns the text.
pub fn write_tables(
    out: &Path,
    manifest: &Manifest,
    rows: &[Vec<String>],
) -> Result<String, MonteCarloError> {
    let t = out.join("samples.csv");
    write_atomic(&t, &table_csv(&manifest.columns, rows)?).map_err(io_err(&t))?;
    let stats = super::summary::statistics(manifest, rows);
    let s = out.join("statistics.json");
    write_atomic(
        &s,
        &(serde_json::to_string_pretty(&stats).unwrap_or_default() + "\n"),
    )
    .map_err(io_err(&s))?;
    let text = super::summary::text(manifest, &stats);
    let p = out.join("statistics.txt");
    write_atomic(&p, &text).map_err(io_err(&p))?;
    Ok(text)
}

/// Compile (shared), plan, fly and post-process one sample.
fn run_sample(
    p: &Prepared,
    compiled: &Shared<Result<Arc<CompileOutcome>, String>>,
    aero: &Shared<Option<Arc<CachedAero>>>,
    cache: &Cache,
    flutter_margin: Option<bool>,
) -> Result<SampleOutputs, String> {
    let sc = &p.scenario;
    let cell = compiled
        .cell(&p.key)
        .ok_or("the structural variant has no cell")?;
    let c = cell
        .get_or_init(|| crate::ops::sweep::compile_variant(cache, &p.key, &sc.vehicle))
        .clone()?;
    let cached = p.aero_key.and_then(|k| {
        let cell = aero.cell(&k)?;
        cell.get_or_init(|| {
            let a = vehicle_aero_cached(&sc.vehicle, &c.compiled, &c.key, cache)
                .ok()
                .flatten()?;
            Some(Arc::new(a))
        })
        .clone()
    });
    let plan = crate::plan::build_with_aero(sc, &c.compiled, cached.as_ref().map(|a| &a.aero))
        .map_err(|e| format!("plan::invalid: {e}"))?;
    let output = crate::run::run(&plan, &c.compiled.reduced, &mut |_, _| {})
        .map_err(|e| format!("run::cannot_start: {e}"))?;
    let mut summary = crate::ops::run::summary_json(&plan, &c, &output);
    if flutter_margin.unwrap_or(sc.launch.is_some()) {
        let table_machs = plan.aero.as_ref().map_or_else(
            || crate::aero::estimator::ESTIMATOR_MACH.to_vec(),
            |a| a.tables.fin.axis(crate::aero::tables::Axis::Mach).to_vec(),
        );
        let m = crate::ops::flutter::flight_margin(sc, &output, &table_machs, cache);
        if let Some(map) = summary.as_object_mut() {
            map.insert("flutter_margin".into(), m.json);
        }
    }
    Ok(SampleOutputs::from_summary(&summary))
}

/// A merge: the manifest (shard 0/1), the rows in index order, the missing indices.
pub type Merged = (Manifest, Vec<Vec<String>>, Vec<usize>);

/// Merge shard directories: the same dispersion, seed, sample count and columns; rows by
/// index, each once. Returns the merged manifest (shard 0/1), its rows and the missing
/// indices.
pub fn merge(dirs: &[PathBuf]) -> Result<Merged, String> {
    let mut first: Option<Manifest> = None;
    let mut by_index: BTreeMap<usize, Vec<String>> = BTreeMap::new();
    for dir in dirs {
        let read = |name: &str| {
            let p = dir.join(name);
            std::fs::read_to_string(&p).map_err(|e| format!("cannot read `{}`: {e}", p.display()))
        };
        let m: Manifest = serde_json::from_str(&read("montecarlo.json")?)
            .map_err(|e| format!("`{}`: {e}", dir.join("montecarlo.json").display()))?;
        if let Some(f) = &first {
            if f.dispersion != m.dispersion
                || f.seed != m.seed
                || f.samples != m.samples
                || f.columns != m.columns
                || f.entries != m.entries
            {
                return Err(format!(
                    "`{}` is another dispersion run (dispersion, seed, samples or entries differ)",
                    dir.display()
                ));
            }
        } else {
            first = Some(m.clone());
        }
        let text = read("samples.csv")?;
        let mut r = csv::Reader::from_reader(text.as_bytes());
        for rec in r.records() {
            let rec = rec.map_err(|e| format!("`{}`: {e}", dir.join("samples.csv").display()))?;
            let row: Vec<String> = rec.iter().map(str::to_string).collect();
            let idx: usize = row
                .first()
                .and_then(|s| s.parse().ok())
                .ok_or_else(|| format!("`{}`: a row without an index", dir.display()))?;
            if let Some(old) = by_index.get(&idx) {
                if *old != row {
                    return Err(format!("sample {idx} differs between shards"));
                }
            }
            by_index.insert(idx, row);
        }
    }
    let mut m = first.ok_or("no shard directories")?;
    m.shard = Shard::ALL;
    let missing: Vec<usize> = (0..m.samples)
        .filter(|i| !by_index.contains_key(i))
        .collect();
    Ok((m, by_index.into_values().collect(), missing))
}
