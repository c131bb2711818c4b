//! Running a dispersion: every sample of this shard checked, compiled through the artifact
//! cache, flown, its flutter margin evaluated, its outputs written; then `samples.csv`,
//! `statistics.json` and `statistics.txt` for the samples of the shard.
//!
//! Layout of an output directory:
//! - `montecarlo.json`: the dispersion (entries, seed), sample count, shard and columns;
//! - `samples/<sample_id>.json`: one file per finished sample (its drawn inputs, the
//!   checked variant's hash and its outputs, or its error); its presence with the same
//!   inputs and variant means done;
//! - `samples.csv`, `statistics.json`, `statistics.txt` (module [`crate::analysis::montecarlo::stats`]);
//! - `figures/*.svg` and `*.png`: landing ellipses, histograms of the apogee and of the
//!   minimum flutter margin, sensitivity bars ([`super::summary::write_figures`]).
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

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::analysis::sweep::Shard;
use crate::artifact::{Cache, CacheKey};
use crate::check::ir::{Dispersion, DispersionEntry, Scenario};
use crate::check::{DiskLoader, Loader, check_scenario_files};
use crate::ops::Progress;
use crate::ops::compile::{CachedAero, CompileOutcome, aero_cache_key, vehicle_aero_cached};

use super::family::ThicknessFamily;

use crate::analysis::montecarlo::{
    SampleOutputs, draw, sample_id, set_strings, table_csv, table_header, table_row,
};

/// How to run a dispersion.
#[derive(Clone)]
pub struct MonteCarloOptions {
    /// Samples (default: the dispersion's `samples`).
    pub samples: usize,
    pub jobs: usize,
    pub shard: Shard,
    pub cache_dir: Option<PathBuf>,
    /// `--set` overrides applied to every sample before its draws.
    pub sets: Vec<String>,
    /// Where progress (samples done of the shard's samples to run) and warnings go
    /// (`None`: nowhere); `ops` never draws it.
    pub progress: Option<Arc<dyn Progress>>,
    /// Compute the flutter margin of each sample (`None`: when the scenario has a launch).
    pub flutter_margin: Option<bool>,
    /// Take each sample's outputs from the complete run summary (`ops::run::summary_json`,
    /// what `flexflight run` writes) instead of the fast path ([`sample_outputs`]); the two
    /// give the same bits (tests/montecarlo.rs), the reference is slower.
    pub full_summary: bool,
    /// Every sample's flutter boundary solved at its own fin thickness, never interpolated
    /// between compiled thicknesses ([`super::family`]).
    pub exact_boundaries: bool,
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
    /// The fin thicknesses (m) the samples' flutter boundaries are interpolated between
    /// ([`super::family`]); absent when each sample has its own boundary.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub boundary_nodes: Option<Vec<f64>>,
    /// The integrator the samples flew with and its tolerances (the dispersion's
    /// `integrator`, or the scenario's; a `--set run.integrator=...` over both), e.g.
    /// `exponential, rtol 1e-7, atol 1e-9`; absent when no sample checked.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub integrator: Option<String>,
}

/// What a run did.
#[derive(Clone, Debug)]
pub struct MonteCarloReport {
    pub manifest: Manifest,
    pub rows: Vec<Vec<String>>,
    pub ran: usize,
    pub skipped: usize,
    pub failed: usize,
    /// Samples (run or resumed) whose integration failed before their flight reached a
    /// stop: `incomplete` in `samples.csv`, out of the statistics.
    pub incomplete: usize,
    /// Distinct structural variants (artifacts) among the samples run.
    pub artifacts: usize,
    pub wall_seconds: f64,
    /// The text summary (`statistics.txt`).
    pub summary: String,
    /// Where the samples' time went, summed over the samples run (not written to the
    /// output directory, whose files depend only on the inputs).
    pub phases: PhaseSeconds,
}

/// Wall time of each stage of a sample, s, summed over samples (with `--jobs N` the sums
/// add the workers' times, so they can exceed the run's wall time).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct PhaseSeconds {
    /// The sample's variant parsed and checked with its drawn overrides, and its keys.
    pub check: f64,
    /// The shared artifact and aerodynamics looked up (built by the first sample of a key).
    pub compile: f64,
    /// The simulation plan.
    pub plan: f64,
    /// The flight (integration and output rows).
    pub flight: f64,
    /// The summary's outputs from the flight.
    pub summary: f64,
    /// The flutter margin along the flight (boundary read from the cache).
    pub margin: f64,
    /// `samples/<id>.json` written.
    pub write: f64,
}

impl PhaseSeconds {
    fn add(&mut self, o: &PhaseSeconds) {
        self.check += o.check;
        self.compile += o.compile;
        self.plan += o.plan;
        self.flight += o.flight;
        self.summary += o.summary;
        self.margin += o.margin;
        self.write += o.write;
    }
    /// The stages as (name, seconds), in order.
    pub fn stages(&self) -> [(&'static str, f64); 7] {
        [
            ("check", self.check),
            ("compile", self.compile),
            ("plan", self.plan),
            ("flight", self.flight),
            ("summary", self.summary),
            ("margin", self.margin),
            ("write", self.write),
        ]
    }
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
    #[error("cannot draw the figures: {0}")]
    Figure(#[from] crate::report::ReportError),
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
    /// How the flutter boundary was had, when interpolated (`ThicknessFamily::describe`).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    boundary: String,
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

fn prepare(
    file: &Path,
    scenario: &str,
    sets: &[String],
    loader: &MemoLoader,
) -> Result<Prepared, String> {
    let checked = check_scenario_files(&[file.to_path_buf()], sets, scenario, loader);
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

/// The files a dispersion's samples read (the vehicle files, imports, thrust curves,
/// tables), each read from the disk once and then served from memory: the samples' checks
/// do not read the disk again, and every sample sees the same contents even if a file is
/// edited while the run goes on.
#[derive(Default)]
pub struct MemoLoader {
    files: Mutex<BTreeMap<PathBuf, FileRead>>,
}

/// A file's text, or the kind and text of the error reading it.
type FileRead = Result<String, (std::io::ErrorKind, String)>;

impl Loader for MemoLoader {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        let mut files = self
            .files
            .lock()
            .map_err(|_| std::io::Error::other("the file memo was poisoned"))?;
        let r = files.entry(path.to_path_buf()).or_insert_with(|| {
            std::fs::read_to_string(path).map_err(|e| (e.kind(), e.to_string()))
        });
        r.clone()
            .map_err(|(kind, text)| std::io::Error::new(kind, text))
    }
    fn exists(&self, path: &Path) -> bool {
        DiskLoader.exists(path)
    }
}

/// The finished record of a sample with these inputs and variant, if there is one.
fn finished(
    dir: &Path,
    id: &str,
    inputs: &[f64],
    variant: &str,
    boundary: &str,
) -> Option<SampleRecord> {
    let text = std::fs::read_to_string(dir.join(format!("{id}.json"))).ok()?;
    let r: SampleRecord = serde_json::from_str(&text).ok()?;
    let same_inputs = r.inputs.len() == inputs.len()
        && r.inputs
            .iter()
            .zip(inputs)
            .all(|(a, b)| a.to_bits() == b.to_bits());
    // An incomplete sample's record is a result too (the same inputs fail the same way).
    let flown = r.status == "ok" || r.status == "incomplete";
    (flown && same_inputs && r.variant == variant && r.boundary == boundary).then_some(r)
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
    // The dispersion's integrator is an override before the user's `--set`s, which may
    // name another.
    let opts = &MonteCarloOptions {
        sets: d
            .integrator
            .map(|i| format!("run.integrator={}", i.name()))
            .into_iter()
            .chain(opts.sets.iter().cloned())
            .collect(),
        ..opts.clone()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.jobs.max(1))
        .build()
        .map_err(|e| MonteCarloError::ThreadPool {
            jobs: opts.jobs,
            reason: e.to_string(),
        })?;
    let header = table_header(d);
    let loader = MemoLoader::default();
    let family = if opts.exact_boundaries {
        None
    } else {
        thickness_family(file, d, scenario, opts, &loader)
    };
    let boundary = family.as_ref().map(|f| f.describe()).unwrap_or_default();
    let indices: Vec<usize> = (0..opts.samples).filter(|&i| opts.shard.takes(i)).collect();
    let inputs: Vec<Vec<f64>> = indices.iter().map(|&i| draw(d, i as u64)).collect();
    let mut phases = PhaseSeconds::default();
    let prepared: Vec<(Result<Prepared, String>, f64)> = pool.install(|| {
        indices
            .par_iter()
            .zip(inputs.par_iter())
            .map(|(_, x)| {
                let t0 = Instant::now();
                let mut sets = opts.sets.clone();
                sets.extend(set_strings(d, x));
                (
                    prepare(file, scenario, &sets, &loader),
                    t0.elapsed().as_secs_f64(),
                )
            })
            .collect()
    });
    phases.check = prepared.iter().map(|p| p.1).sum();
    let prepared: Vec<Result<Prepared, String>> = prepared.into_iter().map(|p| p.0).collect();
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
        boundary_nodes: family.as_ref().map(|f| f.nodes.clone()),
        integrator: prepared
            .iter()
            .find_map(|p| p.as_ref().ok())
            .map(|p| integrator_text(&p.scenario.run)),
    };
    let samples_dir = out.join("samples");
    std::fs::create_dir_all(&samples_dir).map_err(io_err(&samples_dir))?;
    let mpath = out.join("montecarlo.json");
    write_atomic(
        &mpath,
        &(serde_json::to_string_pretty(&manifest).unwrap_or_default() + "\n"),
    )
    .map_err(io_err(&mpath))?;

    let ids: Vec<String> = indices
        .iter()
        .map(|&i| sample_id(i, opts.samples))
        .collect();
    let mut outcomes: Vec<Option<Result<SampleOutputs, String>>> = (0..indices.len())
        .map(|k| {
            let p = prepared[k].as_ref().ok()?;
            finished(&samples_dir, &ids[k], &inputs[k], &p.variant, &boundary)
                .and_then(|r| r.outputs.as_ref().map(|o| Ok(SampleOutputs::from(o))))
        })
        .collect();
    let todo: Vec<usize> = (0..indices.len())
        .filter(|&k| outcomes[k].is_none())
        .collect();
    let skipped = indices.len() - todo.len();

    let progress = opts.progress.as_deref();
    if let Some(p) = progress {
        p.start(&format!("montecarlo {}", d.name.value), todo.len() as u64);
    }

    let cache = Cache::resolve(opts.cache_dir.as_deref());
    let ok_prep = || todo.iter().filter_map(|&k| prepared[k].as_ref().ok());
    let compiled: Shared<Result<Arc<CompileOutcome>, String>> =
        Shared::new(ok_prep().map(|p| p.key));
    let aero: Shared<Option<Arc<CachedAero>>> = Shared::new(ok_prep().filter_map(|p| p.aero_key));
    let artifacts = compiled.len();

    let results: Vec<(Result<SampleOutputs, String>, PhaseSeconds)> = pool.install(|| {
        todo.par_iter()
            .map(|&k| {
                let mut ph = PhaseSeconds::default();
                let result = prepared[k].as_ref().map_err(Clone::clone).and_then(|p| {
                    let r = run_sample(p, &compiled, &aero, &cache, opts, family.as_ref(), &mut ph);
                    compiled.done(&p.key);
                    if let Some(a) = &p.aero_key {
                        aero.done(a);
                    }
                    r
                });
                let t_write = Instant::now();
                let record = SampleRecord {
                    index: indices[k],
                    inputs: inputs[k].clone(),
                    variant: prepared[k]
                        .as_ref()
                        .map(|p| p.variant.clone())
                        .unwrap_or_default(),
                    status: match &result {
                        Ok(o) => crate::analysis::montecarlo::sample_status(o),
                        Err(_) => "failed",
                    }
                    .to_string(),
                    error: result.as_ref().err().cloned(),
                    outputs: result.as_ref().ok().map(OutputsRecord::from),
                    boundary: boundary.clone(),
                };
                let path = samples_dir.join(format!("{}.json", ids[k]));
                let text = serde_json::to_string_pretty(&record).unwrap_or_default() + "\n";
                let written = write_atomic(&path, &text);
                ph.write = t_write.elapsed().as_secs_f64();
                if let Some(p) = progress {
                    p.inc(1);
                }
                let r = match written {
                    Ok(()) => result,
                    Err(e) => Err(format!("{}: {e}", path.display())),
                };
                (r, ph)
            })
            .collect()
    });
    if let Some(p) = progress {
        p.finish();
    }
    let failed = results.iter().filter(|r| r.0.is_err()).count();
    for (&k, (r, ph)) in todo.iter().zip(results) {
        outcomes[k] = Some(r);
        phases.add(&ph);
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
    let incomplete = outcomes
        .iter()
        .flatten()
        .filter(|r| {
            r.as_ref()
                .is_ok_and(|o| crate::analysis::montecarlo::sample_status(o) == "incomplete")
        })
        .count();
    Ok(MonteCarloReport {
        manifest,
        rows,
        ran: todo.len(),
        skipped,
        failed,
        incomplete,
        artifacts,
        wall_seconds: started.elapsed().as_secs_f64(),
        summary,
        phases,
    })
}

/// `exponential, rtol 1e-7, atol 1e-9`.
fn integrator_text(run: &crate::check::ir::RunSettings) -> String {
    format!(
        "{}, rtol {:e}, atol {:e}",
        run.integrator.value.name(),
        run.rtol.value,
        run.atol.value
    )
}

/// Write `samples.csv`, `statistics.json`, `statistics.txt` and `figures/` for `rows`;
/// returns the text.
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
    super::summary::write_figures(out, manifest, rows, &stats)?;
    Ok(text)
}

/// The thickness family of `d` (module [`super::family`]): the nodes from the smallest and
/// largest thickness drawn over all `opts.samples` samples (not only this shard's), each in
/// metres as its sample's variant checks it; `None` when `d` does not qualify, the two
/// extreme samples do not check, or the range gives one node.
fn thickness_family(
    file: &Path,
    d: &Dispersion,
    scenario: &str,
    opts: &MonteCarloOptions,
    loader: &MemoLoader,
) -> Option<ThicknessFamily> {
    let j = super::family::thickness_entry(d)?;
    let drawn: Vec<(f64, usize)> = (0..opts.samples)
        .map(|i| (draw(d, i as u64)[j], i))
        .collect();
    let lo = drawn.iter().copied().min_by(|a, b| a.0.total_cmp(&b.0))?;
    let hi = drawn.iter().copied().max_by(|a, b| a.0.total_cmp(&b.0))?;
    let metres = |i: usize| {
        let mut sets = opts.sets.clone();
        sets.extend(set_strings(d, &draw(d, i as u64)));
        let p = prepare(file, scenario, &sets, loader).ok()?;
        p.scenario.vehicle.fins.as_ref().map(|f| f.thickness.value)
    };
    ThicknessFamily::new(metres(lo.1)?, metres(hi.1)?)
}

/// Compile (shared), plan, fly and post-process one sample.
fn run_sample(
    p: &Prepared,
    compiled: &Shared<Result<Arc<CompileOutcome>, String>>,
    aero: &Shared<Option<Arc<CachedAero>>>,
    cache: &Cache,
    opts: &MonteCarloOptions,
    family: Option<&ThicknessFamily>,
    ph: &mut PhaseSeconds,
) -> Result<SampleOutputs, String> {
    let sc = &p.scenario;
    let t0 = Instant::now();
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
    let t1 = Instant::now();
    ph.compile = (t1 - t0).as_secs_f64();
    let plan = crate::plan::build_with_aero(sc, &c.compiled, cached.as_ref().map(|a| &a.aero))
        .map_err(|e| format!("plan::invalid: {e}"))?;
    let t2 = Instant::now();
    ph.plan = (t2 - t1).as_secs_f64();
    let (output, peaks) = if opts.full_summary {
        crate::run::run(&plan, &c.compiled.reduced, &mut |_, _| {}).map(|o| (o, None))
    } else {
        crate::run::run_without_descent_rows(&plan, &c.compiled.reduced).map(|(o, p)| (o, Some(p)))
    }
    .map_err(|e| format!("run::cannot_start: {e}"))?;
    let t3 = Instant::now();
    ph.flight = (t3 - t2).as_secs_f64();
    let margin = opts.flutter_margin.unwrap_or(sc.launch.is_some()).then(|| {
        let table_machs = plan.aero.as_ref().map_or_else(
            || crate::aero::estimator::ESTIMATOR_MACH.to_vec(),
            |a| a.tables.fin.axis(crate::aero::tables::Axis::Mach).to_vec(),
        );
        match family {
            Some(f) => {
                crate::ops::flutter::flight_margin_with(sc, &output, &table_machs, &|v, spec| {
                    f.boundary(v, spec, cache)
                })
            }
            None => crate::ops::flutter::flight_margin(sc, &output, &table_machs, cache),
        }
        .json
    });
    let t4 = Instant::now();
    ph.margin = (t4 - t3).as_secs_f64();
    let outputs = if opts.full_summary {
        let mut summary = crate::ops::run::summary_json(&plan, &c, &output);
        if let (Some(map), Some(m)) = (summary.as_object_mut(), margin) {
            map.insert("flutter_margin".into(), m);
        }
        SampleOutputs::from_summary(&summary)
    } else {
        sample_outputs(&plan, &output, peaks.as_ref(), margin.as_ref())
    };
    ph.summary = t4.elapsed().as_secs_f64();
    Ok(outputs)
}

/// A sample's outputs from its flight: the stop code, the verdict's kind, the flight
/// summary (`ops::run::flight_summary`: apogee, max Mach and max q over the rows, off-rail
/// speed, min static margin, landing) and the flutter margin's minimum, by the same
/// functions as `summary.json`, so with the same bits, without the rest of the run summary
/// (extrema of every channel, energy balance, mass, the identification of the response
/// after each stimulus), which a Monte Carlo sample does not read.
///
/// `peaks`: the flight was run without its rows under a canopy
/// (`run::run_without_descent_rows`); the max Mach and max q are then the larger of the
/// rows' and the skipped rows' peaks, the rows' on a tie (they come first in time), which
/// is the first maximum over all the rows, as `flight_summary` takes it. The other outputs
/// do not read the rows under a canopy: the apogee, off-rail speed and landing are events,
/// the static margin's minimum ends at the apogee or the first deployment, and the flutter
/// margin covers the flight up to the first deployment (`ops::flutter::flight_margin`).
pub fn sample_outputs(
    plan: &crate::plan::Plan,
    o: &crate::run::RunOutput,
    peaks: Option<&crate::run::DescentPeaks>,
    flutter_margin: Option<&serde_json::Value>,
) -> SampleOutputs {
    let s = serde_json::json!({
        "stop_reason": o.stop.code(),
        "verdict": { "kind": o.verdict.as_ref().map(|v| v.kind.code()) },
        "flight": crate::ops::run::flight_summary(plan, o),
        "flutter_margin": flutter_margin,
    });
    let mut out = SampleOutputs::from_summary(&s);
    let larger = |rows: Option<f64>, skipped: Option<(f64, f64)>| match (rows, skipped) {
        (Some(r), Some((p, _))) if p > r => Some(p),
        (None, Some((p, _))) => Some(p),
        (r, _) => r,
    };
    if let Some(p) = peaks {
        out.max_mach = larger(out.max_mach, p.mach);
        out.max_q_pa = larger(out.max_q_pa, p.dynamic_pressure);
    }
    out
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
                || f.boundary_nodes != m.boundary_nodes
                || f.integrator != m.integrator
            {
                return Err(format!(
                    "`{}` is another dispersion run (dispersion, seed, samples, entries, boundary nodes or integrator differ)",
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
