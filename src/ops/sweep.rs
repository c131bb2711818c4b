//! Sweeps (`flexflight sweep`, `flexflight merge`): run the cases of a sweep in parallel, one
//! directory of outputs per case and one table row per case; join shard tables.
//!
//! Layout of an output directory:
//! - `sweep.json`: the sweep, its case count, the shard and the table columns;
//! - `sweep.csv`: one row per case of the shard, in case order;
//! - `cases/<case_id>/history.csv`, `summary.json` (as `flexflight run`, plus `status` and a
//!   `sweep_case` object), or `error.txt` for a case that failed.
//!
//! Determinism: each case runs single-threaded (faer's global parallelism is set to
//! sequential) and the rows are collected in case order, so `sweep.csv` is byte-identical
//! whatever `--jobs` is. Resume: a case whose `summary.json` says `"status": "ok"` for the
//! same overrides and the same checked variant (a hash of the scenario IR, so an edited
//! file or `--set` invalidates it) is not run again; its row is rebuilt from that file.
//! Every file is written atomically (temporary file, then rename), so an interrupted sweep loses no finished case.
//! A failed case leaves `error.txt` and no `summary.json`, so a re-run tries it again.
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};
use std::time::Instant;

use rayon::prelude::*;

use crate::analysis::sweep::{
    MergedTable, Shard, ShardTable, SweepCase, SweepManifest, case_row, expand, parse_table,
    table_csv, table_header,
};
use crate::artifact::{Cache, CacheKey, GetOrBuildError};
use crate::check::ir::{Scenario, Sweep, SweepAnalysis};
use crate::check::{DiskLoader, check_scenario_files};
use crate::run;
use crate::structure::compile::{CompiledVehicle, compile};

use super::Progress;
use super::compile::{CachedAero, CompileOutcome, aero_cache_key, cache_key, vehicle_aero_cached};
use super::files::write_atomic;

/// How to run a sweep.
#[derive(Clone)]
pub struct SweepOptions {
    /// Worker threads (at least 1).
    pub jobs: usize,
    pub shard: Shard,
    /// Cache directory (`None`: `$FLEXFLIGHT_CACHE`, else `target/flexflight-cache`).
    pub cache_dir: Option<PathBuf>,
    /// `--set` overrides applied to every case before the case's own.
    pub sets: Vec<String>,
    /// Where progress (cases done of the shard's cases to run) and warnings go (`None`:
    /// nowhere).
    pub progress: Option<Arc<dyn Progress>>,
}

/// What a sweep did.
#[derive(Clone, Debug)]
pub struct SweepReport {
    pub manifest: SweepManifest,
    /// The rows written to `sweep.csv`.
    pub rows: Vec<Vec<String>>,
    /// Cases run now, cases skipped because they were finished, cases that failed.
    pub ran: usize,
    pub skipped: usize,
    pub failed: usize,
    /// Distinct structural variants (artifacts) the run cases used.
    pub artifacts: usize,
    pub wall_seconds: f64,
}

/// Why a sweep could not run at all (a failing case is not an error: it is recorded).
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
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

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> SweepError + '_ {
    move |source| SweepError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Run (this shard of) `sweep`, declared in `file`, writing into `out`.
pub fn run_sweep(
    file: &Path,
    sweep: &Sweep,
    scenario: &str,
    out: &Path,
    opts: &SweepOptions,
) -> Result<SweepReport, SweepError> {
    let started = Instant::now();
    // Parallelism is across cases; inside a case faer works sequentially, so results do
    // not depend on the thread count and two levels of threads do not fight for 2 cores.
    crate::ops::sequential_linear_algebra();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.jobs.max(1))
        .build()
        .map_err(|e| SweepError::ThreadPool {
            jobs: opts.jobs,
            reason: e.to_string(),
        })?;
    let header = table_header(sweep);
    let manifest = SweepManifest {
        sweep: sweep.name.value.clone(),
        scenario: scenario.to_string(),
        case_count: sweep.case_count(),
        shard: opts.shard,
        columns: header.clone(),
    };
    let cases_dir = out.join("cases");
    std::fs::create_dir_all(&cases_dir).map_err(io_err(&cases_dir))?;
    let manifest_path = out.join("sweep.json");
    let manifest_text = serde_json::to_string_pretty(&manifest).unwrap_or_default() + "\n";
    write_atomic(&manifest_path, &manifest_text).map_err(io_err(&manifest_path))?;

    let cases: Vec<SweepCase> = expand(sweep)
        .into_iter()
        .filter(|c| opts.shard.takes(c.index))
        .collect();
    // Check every case (cheap): its variant's fingerprint decides whether a finished case
    // on disk is still this case.
    let checked: Vec<Result<Prepared, String>> = pool.install(|| {
        cases
            .par_iter()
            .map(|c| prepare_case(file, scenario, &opts.sets, c))
            .collect()
    });
    let mut outcomes: Vec<Option<Result<serde_json::Value, String>>> = cases
        .iter()
        .zip(&checked)
        .map(|(c, p)| {
            let variant = p.as_ref().ok()?.variant.as_str();
            finished(&cases_dir, c, variant).map(Ok)
        })
        .collect();
    let todo: Vec<usize> = (0..cases.len())
        .filter(|&k| outcomes[k].is_none())
        .collect();
    let skipped = cases.len() - todo.len();
    let prepared: Vec<&Result<Prepared, String>> = todo.iter().map(|&k| &checked[k]).collect();

    let progress = opts.progress.as_deref();
    if let Some(p) = progress {
        p.start(&format!("sweep {}", sweep.name.value), todo.len() as u64);
    }

    // Compile each distinct structural variant once.
    let mut variants: BTreeMap<String, (CacheKey, &CompiledVehicleInput)> = BTreeMap::new();
    for p in prepared.iter().copied().flatten() {
        variants
            .entry(p.key.to_hex())
            .or_insert((p.key, &p.scenario.vehicle));
    }
    let cache = Cache::resolve(opts.cache_dir.as_deref());
    let compiled: BTreeMap<String, Result<Arc<CompileOutcome>, String>> = pool.install(|| {
        variants
            .par_iter()
            .map(|(hex, (key, vehicle))| (hex.clone(), compile_variant(&cache, key, vehicle)))
            .collect()
    });

    // The vehicle-only aerodynamics (tables, fin load weights) per distinct vehicle (its
    // aero cache key), read from the cache or built by the first case that needs them; each
    // case's plan then builds its blocks from them with its own stimuli. They are a
    // function of the vehicle alone, so which case builds them does not change any result.
    let aero_blocks: BTreeMap<CacheKey, AeroCell> = prepared
        .iter()
        .copied()
        .flatten()
        .filter_map(|p| p.aero_key.map(|k| (k, OnceLock::new())))
        .collect();

    let results: Vec<Result<serde_json::Value, String>> = pool.install(|| {
        todo.par_iter()
            .zip(prepared.par_iter())
            .map(|(&k, prep)| {
                let case = &cases[k];
                let result = prep.as_ref().map_err(Clone::clone).and_then(|p| {
                    let c = compiled
                        .get(&p.key.to_hex())
                        .cloned()
                        .unwrap_or_else(|| Err("the structural variant was not compiled".into()))?;
                    let aero = p.aero_key.and_then(|k| aero_blocks.get(&k));
                    run_case(
                        p,
                        &c,
                        sweep,
                        case,
                        aero.map(|cell| (cell, &cache)),
                        progress,
                    )
                });
                let written = write_case(&cases_dir, case, &result);
                if let Some(p) = progress {
                    p.inc(1);
                }
                match written {
                    Ok(()) => result,
                    Err(e) => Err(format!("{}: {e}", cases_dir.join(&case.id).display())),
                }
            })
            .collect()
    });
    if let Some(p) = progress {
        p.finish();
    }
    let failed = results.iter().filter(|r| r.is_err()).count();
    for (&k, r) in todo.iter().zip(results) {
        outcomes[k] = Some(r);
    }
    let rows: Vec<Vec<String>> = cases
        .iter()
        .zip(&outcomes)
        .map(|(c, o)| case_row(c, o.as_ref().unwrap_or(&Err("not run".into()))))
        .collect();
    let table_path = out.join("sweep.csv");
    write_atomic(&table_path, &table_csv(&header, &rows)?).map_err(io_err(&table_path))?;
    Ok(SweepReport {
        manifest,
        rows,
        ran: todo.len(),
        skipped,
        failed,
        artifacts: compiled.len(),
        wall_seconds: started.elapsed().as_secs_f64(),
    })
}

type CompiledVehicleInput = crate::check::ir::Vehicle;

/// A vehicle's aerodynamics, obtained once for all the cases that fly it (`None`: the
/// vehicle has none, or they cannot be built and each case's plan reports why).
type AeroCell = OnceLock<Option<Arc<CachedAero>>>;

/// The summary of a finished case (`status` ok, same overrides, same checked variant), if
/// there is one.
fn finished(cases_dir: &Path, case: &SweepCase, variant: &str) -> Option<serde_json::Value> {
    let text = std::fs::read_to_string(cases_dir.join(&case.id).join("summary.json")).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    let c = v.get("sweep_case")?;
    let same = v.get("status")?.as_str()? == "ok"
        && c.get("overrides")? == &serde_json::to_value(&case.overrides).ok()?
        && c.get("variant")?.as_str()? == variant;
    same.then_some(v)
}

/// A case checked and ready to compile and run.
struct Prepared {
    scenario: Scenario,
    key: CacheKey,
    /// blake3 of the checked scenario (with its vehicle) without spans: a finished case on
    /// disk is reused only if the file and `--set` still give exactly this variant.
    variant: String,
    /// The aero cache key of the vehicle (with aerodynamics): cases with the same key share
    /// one set of tables and fin load weights.
    aero_key: Option<CacheKey>,
}

/// Check the case's variant of the scenario and key its structure.
fn prepare_case(
    file: &Path,
    scenario: &str,
    sets: &[String],
    case: &SweepCase,
) -> Result<Prepared, String> {
    let mut all = sets.to_vec();
    all.extend(case.set_strings());
    let checked = check_scenario_files(&[file.to_path_buf()], &all, scenario, &DiskLoader);
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
    let (key, variant, _) = case_fingerprints(&sc)?;
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

/// The three fingerprints of a checked case: the cache key of its structure, the variant
/// (the whole scenario IR: decides whether a finished case on disk is still this case) and
/// the whole vehicle (the part of the aerodynamic cache key, `aero_cache_key`, that decides
/// which cases share aerodynamic blocks). The last two hash the
/// canonical serialisation (`artifact::canonical`): every value, source positions left out
/// by their type.
pub fn case_fingerprints(
    sc: &crate::check::ir::Scenario,
) -> Result<(CacheKey, String, String), String> {
    let key = cache_key(&sc.vehicle).map_err(|e| format!("cannot read an FE file: {e}"))?;
    let variant = crate::artifact::canonical::fingerprint(sc).map_err(|e| e.to_string())?;
    let vehicle =
        crate::artifact::canonical::fingerprint(&sc.vehicle).map_err(|e| e.to_string())?;
    Ok((key, variant, vehicle))
}

/// Compile one structural variant through the cache (built once, then memory-mapped).
pub(crate) fn compile_variant(
    cache: &Cache,
    key: &CacheKey,
    vehicle: &CompiledVehicleInput,
) -> Result<Arc<CompileOutcome>, String> {
    let t0 = Instant::now();
    match cache.get_or_build(key, || compile(vehicle).map(|(c, _)| c)) {
        Ok((art, outcome)) => {
            let compiled = rkyv::deserialize::<CompiledVehicle, rkyv::rancor::Error>(art.get())
                .map_err(|e| format!("the artifact could not be read back: {e}"))?;
            Ok(Arc::new(CompileOutcome {
                compiled,
                path: art.path().map(Path::to_path_buf).unwrap_or_default(),
                key: *key,
                outcome,
                seconds: t0.elapsed().as_secs_f64(),
            }))
        }
        Err(GetOrBuildError::Build(e)) => Err(format!("{}: {e}", e.code())),
        Err(GetOrBuildError::Artifact(e)) => Err(format!("{}: {e}", e.code())),
    }
}

/// Plan, run and identify one case; its summary as `flexflight run` writes it, plus the
/// case's identity. The history is attached under `"_history"` for [`write_case`].
fn run_case(
    prepared: &Prepared,
    compiled: &CompileOutcome,
    sweep: &Sweep,
    case: &SweepCase,
    aero: Option<(&AeroCell, &Cache)>,
    progress: Option<&dyn Progress>,
) -> Result<serde_json::Value, String> {
    let sc = &prepared.scenario;
    let identity = serde_json::json!({
        "sweep": sweep.name.value,
        "index": case.index,
        "case_id": case.id,
        "overrides": case.overrides,
        "variant": prepared.variant,
    });
    let analysis = serde_json::to_value(sweep.analysis.value)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default();
    let cached = aero.and_then(|(cell, cache)| {
        cell.get_or_init(|| {
            let c = vehicle_aero_cached(&sc.vehicle, &compiled.compiled, &compiled.key, cache)
                .ok()
                .flatten()?;
            if let (Some(w), Some(p)) = (&c.warning, progress) {
                p.warning(w);
            }
            Some(Arc::new(c))
        })
        .clone()
    });
    let p = crate::plan::build_with_aero(sc, &compiled.compiled, cached.as_ref().map(|c| &c.aero))
        .map_err(|e| format!("plan::invalid: {e}"))?;
    let stability = match sweep.analysis.value {
        SweepAnalysis::Run => None,
        SweepAnalysis::PlanarPinned | SweepAnalysis::PlanarUnpinned => {
            use crate::analysis::planar::{PlanarKind, PlanarVehicle};
            let kind = if sweep.analysis.value == SweepAnalysis::PlanarPinned {
                PlanarKind::Pinned
            } else {
                PlanarKind::Unpinned
            };
            let v = PlanarVehicle::new(&sc.vehicle, &compiled.compiled)
                .map_err(|e| format!("analysis::planar::failed: {e}"))?;
            let r = super::planar::analyse_at_initial_condition(sc, &v, kind)
                .map_err(|e| format!("analysis::planar::failed: {e}"))?;
            Some(serde_json::json!({
                "sigma_d": r.verdict.sigma_d,
                "omega_d": r.verdict.omega_d,
                "class": r.verdict.class.name(),
                "altitude_m": r.parameters.condition.altitude,
                "mach": r.parameters.condition.mach,
            }))
        }
        SweepAnalysis::Linear3d => {
            use crate::analysis::linear::{Variant, analyse};
            let variant = Variant {
                plan: p.clone(),
                scenario: sc.clone(),
                compiled: compiled.compiled.clone(),
            };
            let options = crate::analysis::linearise::LineariseOptions {
                gravity_follows_attitude: !sweep.frozen_gravity,
                ..Default::default()
            };
            let r =
                analyse(&variant, options).map_err(|e| format!("analysis::linear::failed: {e}"))?;
            Some(serde_json::json!({
                "sigma_d": r.eigen.sigma_d,
                "omega_d": r.eigen.omega_d,
                "class": r.eigen.class.name(),
                "flight_path_sigma": r.eigen.flight_path_sigma,
                "flight_path_rate": r.eigen.flight_path_rate,
                "frozen_gravity": sweep.frozen_gravity,
                "altitude_m": r.condition.altitude,
                "mach": r.condition.mach,
                "trim_converged": r.trim_converged,
            }))
        }
    };
    if let Some(stability) = stability {
        return Ok(serde_json::json!({
            "status": "ok",
            "analysis": analysis,
            "scenario": sc.name.value,
            "artifact_hash": compiled.key.to_hex(),
            "stability": stability,
            "sweep_case": identity,
        }));
    }
    let output = run::run(&p, &compiled.compiled.reduced, &mut |_, _| {})
        .map_err(|e| format!("run::cannot_start: {e}"))?;
    let mut summary = super::run::with_aero_cache(
        super::run::summary_json(&p, compiled, &output),
        cached.as_deref(),
    );
    if let Some(map) = summary.as_object_mut() {
        map.insert("status".into(), "ok".into());
        map.insert("sweep_case".into(), identity);
        map.insert("_history".into(), super::run::history_csv(&output).into());
    }
    Ok(summary)
}

/// Write a case's files: `history.csv` then `summary.json` (its presence means done), or
/// `error.txt`. Removes the in-memory history from the summary.
fn write_case(
    cases_dir: &Path,
    case: &SweepCase,
    result: &Result<serde_json::Value, String>,
) -> std::io::Result<()> {
    let dir = cases_dir.join(&case.id);
    std::fs::create_dir_all(&dir)?;
    match result {
        Ok(summary) => {
            let mut summary = summary.clone();
            let history = summary
                .as_object_mut()
                .and_then(|m| m.remove("_history"))
                .and_then(|h| h.as_str().map(str::to_string))
                .unwrap_or_default();
            if !history.is_empty() {
                write_atomic(&dir.join("history.csv"), &history)?;
            }
            let _ = std::fs::remove_file(dir.join("error.txt"));
            let text = serde_json::to_string_pretty(&summary).unwrap_or_default();
            write_atomic(&dir.join("summary.json"), &(text + "\n"))
        }
        Err(e) => write_atomic(&dir.join("error.txt"), &format!("{e}\n")),
    }
}

/// Read a shard's `sweep.json` and `sweep.csv`.
pub fn read_shard(dir: &Path) -> Result<ShardTable, String> {
    let read = |name: &str| {
        let p = dir.join(name);
        std::fs::read_to_string(&p).map_err(|e| format!("cannot read `{}`: {e}", p.display()))
    };
    let manifest: SweepManifest = serde_json::from_str(&read("sweep.json")?)
        .map_err(|e| format!("`{}`: {e}", dir.join("sweep.json").display()))?;
    let (header, rows) = parse_table(&read("sweep.csv")?)
        .map_err(|e| format!("`{}`: {e}", dir.join("sweep.csv").display()))?;
    Ok(ShardTable {
        source: dir.display().to_string(),
        manifest,
        header,
        rows,
    })
}

/// Write a merged table (`sweep.json` with shard 0/1, and `sweep.csv`) into `out`.
pub fn write_merged(out: &Path, merged: &MergedTable) -> Result<(), SweepError> {
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    let m = out.join("sweep.json");
    let text = serde_json::to_string_pretty(&merged.manifest).unwrap_or_default() + "\n";
    write_atomic(&m, &text).map_err(io_err(&m))?;
    let t = out.join("sweep.csv");
    write_atomic(&t, &table_csv(&merged.manifest.columns, &merged.rows)?).map_err(io_err(&t))
}
