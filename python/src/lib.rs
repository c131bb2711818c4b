//! `flexflight._native`: the Python binding of the operations layer ([`flexflight::ops`]).
//!
//! A thin layer: each method converts its arguments, calls one operation with the GIL
//! released (`Python::allow_threads`), and converts the result. Structured results cross as
//! JSON text (the same `serde_json` values the command line writes to `summary.json` and
//! `flutter.json`, read by Python's `json.loads`: shortest round-trip floats, so the same
//! numbers) and the history as the rows' IEEE-754 bytes (the same bits). Errors become
//! `flexflight.Error` with the diagnostics' code, message, file, line, column and help
//! (`flexflight::diagnostics::to_json`). The public API and its documentation are the
//! Python package `flexflight` (`python/flexflight/__init__.py`).

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use flexflight::check::{DiskLoader, check_files};
use flexflight::diagnostics::{Diagnostic, to_json};
use flexflight::ops::flutter::{AeroChoice, FlutterRequest};
use flexflight::ops::run::Flown;
use flexflight::ops::{OpsError, Project};
use flexflight::syntax::SourceMap;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyTuple};

/// A JSON value as Python objects (`json.loads` of its text).
fn json_to_py(py: Python<'_>, v: &serde_json::Value) -> PyResult<PyObject> {
    let text = serde_json::to_string(v)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    Ok(py.import("json")?.call_method1("loads", (text,))?.unbind())
}

/// The diagnostics as JSON (code, severity, message, file, line, column, labels, help).
fn diagnostics_json(d: &[Diagnostic], sources: &SourceMap) -> serde_json::Value {
    serde_json::to_value(to_json(d, sources)).unwrap_or(serde_json::Value::Null)
}

/// `flexflight.Error(message, code, diagnostics)` (built by `flexflight._errors`).
fn error(py: Python<'_>, message: String, code: Option<&str>, diags: serde_json::Value) -> PyErr {
    let made = (|| -> PyResult<PyErr> {
        let d = json_to_py(py, &diags)?;
        let e = py
            .import("flexflight._errors")?
            .getattr("_from_native")?
            .call1((message.clone(), code, d))?;
        Ok(PyErr::from_value(e))
    })();
    made.unwrap_or_else(|e| e)
}

/// An [`OpsError`] as `flexflight.Error`; diagnostics located with `sources`.
fn ops_error(py: Python<'_>, e: OpsError, sources: Option<&SourceMap>) -> PyErr {
    match e {
        OpsError::Diagnostics(d) => {
            let empty = SourceMap::new();
            let j = diagnostics_json(&d, sources.unwrap_or(&empty));
            let code = d.first().map(|d| d.code);
            let msg = d
                .first()
                .map_or_else(|| "diagnostics".to_string(), |d| d.message.clone());
            error(py, msg, code, j)
        }
        OpsError::Usage(m) => error(py, m, Some("usage"), serde_json::json!([])),
        OpsError::Coded { code, message, .. } => {
            error(py, message, Some(code), serde_json::json!([]))
        }
    }
}

/// `check_files` of `files` with `sets`: every diagnostic (errors and warnings) as JSON.
#[pyfunction]
fn check(py: Python<'_>, files: Vec<PathBuf>, sets: Vec<String>) -> PyResult<PyObject> {
    for f in &files {
        if !f.is_file() {
            return Err(error(
                py,
                format!("cannot read `{}`: no such file", f.display()),
                Some("usage"),
                serde_json::json!([]),
            ));
        }
    }
    let j = py.allow_threads(|| {
        let c = check_files(&files, &sets, &DiskLoader);
        diagnostics_json(&c.diagnostics, &c.sources)
    });
    json_to_py(py, &j)
}

/// An open project: the checked files (`ops::Project`).
#[pyclass(module = "flexflight._native")]
struct NativeProject {
    inner: Mutex<Project>,
    /// The files and overrides it was opened with (a sweep re-checks each case from them).
    files: Vec<PathBuf>,
    sets: Vec<String>,
}

/// The mutex's project even after a panic elsewhere (the project is only read or extended).
fn lock(m: &Mutex<Project>) -> std::sync::MutexGuard<'_, Project> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// Calls the Python `progress(t, t_end)` at most ten times a second and once at the end; the
/// first exception it raises stops the calls and is raised after the work.
struct PyProgress {
    callback: Option<Py<PyAny>>,
    last: Option<Instant>,
    failed: Option<PyErr>,
}

impl PyProgress {
    fn call(&mut self, t: f64, t_end: f64, force: bool) {
        let Some(cb) = &self.callback else { return };
        if self.failed.is_some() {
            return;
        }
        if !force && self.last.is_some_and(|l| l.elapsed().as_secs_f64() < 0.1) {
            return;
        }
        self.last = Some(Instant::now());
        Python::with_gil(|py| {
            let r = cb.call1(py, (t, t_end)).and_then(|_| py.check_signals());
            if let Err(e) = r {
                self.failed = Some(e);
            }
        });
    }
}

/// [`flexflight::ops::Progress`] for Python: `progress(done, total)` at most ten times a
/// second (and at the start and the end), from whichever worker thread finished a unit,
/// with the GIL taken for the call; warnings are collected. The first exception the
/// callback raises stops the calls and is raised after the work.
struct PyCountProgress {
    callback: Option<Py<PyAny>>,
    state: Mutex<CountState>,
}

#[derive(Default)]
struct CountState {
    done: u64,
    total: u64,
    last: Option<Instant>,
    failed: Option<PyErr>,
    warnings: Vec<String>,
}

impl PyCountProgress {
    fn report(&self, force: bool) {
        let Some(cb) = &self.callback else { return };
        let mut s = self.state.lock().unwrap_or_else(|p| p.into_inner());
        if s.failed.is_some() || (!force && s.last.is_some_and(|l| l.elapsed().as_secs_f64() < 0.1))
        {
            return;
        }
        s.last = Some(Instant::now());
        let (done, total) = (s.done, s.total);
        // The state's lock is held through the call: calls never overlap, in order.
        let r = Python::with_gil(|py| {
            cb.call1(py, (done, total))
                .and_then(|_| py.check_signals())
                .err()
        });
        if let Some(e) = r {
            s.failed = Some(e);
        }
    }

    fn into_parts(self) -> (Option<PyErr>, Vec<String>) {
        let s = self.state.into_inner().unwrap_or_else(|p| p.into_inner());
        (s.failed, s.warnings)
    }
}

impl flexflight::ops::Progress for PyCountProgress {
    fn start(&self, _label: &str, total: u64) {
        if let Ok(mut s) = self.state.lock() {
            s.total = total;
            s.done = 0;
        }
        self.report(true);
    }
    fn inc(&self, n: u64) {
        if let Ok(mut s) = self.state.lock() {
            s.done += n;
        }
        self.report(false);
    }
    fn finish(&self) {
        self.report(true);
    }
    fn warning(&self, text: &str) {
        if let Ok(mut s) = self.state.lock() {
            s.warnings.push(text.to_string());
        }
    }
}

/// A zero-lift drag curve: the altitude, m, and its `(mach, cd)` points.
type DragCurve = (f64, Vec<(f64, f64)>);

#[pymethods]
impl NativeProject {
    /// Checks `files` with the `--set` overrides `sets`; raises on errors.
    #[new]
    #[pyo3(signature = (files, sets, cache_dir=None))]
    fn new(
        py: Python<'_>,
        files: Vec<PathBuf>,
        sets: Vec<String>,
        cache_dir: Option<PathBuf>,
    ) -> PyResult<Self> {
        // The error (the ops error and the check it came from) is boxed across the thread
        // boundary: it is large, the success small.
        match py
            .allow_threads(|| Project::open(&files, &sets, cache_dir.as_deref()).map_err(Box::new))
        {
            Ok(p) => Ok(NativeProject {
                inner: Mutex::new(p),
                files,
                sets,
            }),
            Err(b) => {
                let (e, checked) = *b;
                Err(ops_error(py, e, checked.as_ref().map(|c| &c.sources)))
            }
        }
    }

    /// The warnings of the check (JSON list).
    fn warnings(&self, py: Python<'_>) -> PyResult<PyObject> {
        let p = lock(&self.inner);
        json_to_py(
            py,
            &diagnostics_json(&p.checked.diagnostics, &p.checked.sources),
        )
    }

    /// Names of the declared vehicles, flown scenarios and wind-tunnel scenarios.
    fn names(&self) -> (Vec<String>, Vec<String>, Vec<String>) {
        let p = lock(&self.inner);
        let prog = &p.checked.program;
        (
            prog.vehicles.iter().map(|v| v.name.value.clone()).collect(),
            prog.scenarios
                .iter()
                .map(|s| s.name.value.clone())
                .collect(),
            prog.tunnel_tests
                .iter()
                .map(|t| t.name.value.clone())
                .collect(),
        )
    }

    /// `compile`'s JSON (mass properties, modes, artifact) of `vehicle` through the cache.
    #[pyo3(signature = (vehicle=None))]
    fn compile(&self, py: Python<'_>, vehicle: Option<String>) -> PyResult<PyObject> {
        let mut p = lock(&self.inner);
        let p = &mut *p;
        let r = py.allow_threads(|| {
            let v = flexflight::ops::compile::pick_vehicle(&p.checked, vehicle.as_deref())
                .map_err(OpsError::Usage)?
                .clone();
            flexflight::ops::compile::compile_cached(&mut p.checked, &v, p.cache_dir.as_deref())
                .map(|o| flexflight::ops::compile::summary_json(&o))
        });
        match r {
            Ok(j) => json_to_py(py, &j),
            Err(e) => Err(ops_error(py, e, Some(&p.checked.sources))),
        }
    }

    /// Flies `scenario` (`ops::run::{prepare, fly}`); returns the run and the warnings.
    #[pyo3(signature = (scenario, flutter_margin=None, progress=None))]
    fn run(
        &self,
        py: Python<'_>,
        scenario: String,
        flutter_margin: Option<bool>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<(NativeRun, Vec<String>)> {
        let mut guard = lock(&self.inner);
        let p = &mut *guard;
        let mut prog = PyProgress {
            callback: progress,
            last: None,
            failed: None,
        };
        let cache_dir = p.cache_dir.clone();
        let (r, warnings) = py.allow_threads(|| {
            let mut warnings = Vec::new();
            let r = (|| {
                let prep = flexflight::ops::run::prepare(
                    &mut p.checked,
                    &scenario,
                    cache_dir.as_deref(),
                    &mut |w| warnings.push(w),
                )?;
                let t_end = prep.plan.stop.stop_time;
                prog.call(0.0, t_end, true);
                let flown = flexflight::ops::run::fly(
                    &prep,
                    &p.checked.sources,
                    flutter_margin,
                    cache_dir.as_deref(),
                    &mut |t, te| prog.call(t, te, false),
                    &mut |_| {},
                )?;
                prog.call(flown.output.t_end, t_end, true);
                let n_fins = prep
                    .scenario
                    .vehicle
                    .fins
                    .as_ref()
                    .map_or(0, |f| f.count.value);
                let h = flexflight::ops::flutter::scenario_altitude(&prep.scenario);
                let drag = flexflight::ops::run::drag_curve(&prep.plan, n_fins, h);
                Ok::<_, OpsError>((flown, drag, h))
            })();
            if let Ok((f, ..)) = &r {
                if let Some(m) = &f.margin {
                    warnings.extend(m.warnings.iter().cloned());
                }
            }
            (r, warnings)
        });
        if let Some(e) = prog.failed.take() {
            return Err(e);
        }
        match r {
            Ok((flown, drag, drag_altitude)) => Ok((
                NativeRun {
                    flown,
                    drag,
                    drag_altitude,
                },
                warnings,
            )),
            Err(e) => Err(ops_error(py, e, Some(&p.checked.sources))),
        }
    }

    /// `flexflight sweep` of the sweep `name` into `out` (`ops::sweep::run_sweep`): the
    /// summary as JSON and the warnings; the table is `out/sweep.csv`. Cases run on `jobs`
    /// threads with the GIL released; a finished case in `out` is not run again.
    #[pyo3(signature = (name, out, jobs=None, shard=None, progress=None))]
    fn sweep(
        &self,
        py: Python<'_>,
        name: String,
        out: PathBuf,
        jobs: Option<usize>,
        shard: Option<String>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<(PyObject, Vec<String>)> {
        use flexflight::analysis::sweep::Shard;
        let usage = |py: Python<'_>, m: String| error(py, m, Some("usage"), serde_json::json!([]));
        let [file] = self.files.as_slice() else {
            return Err(usage(
                py,
                "a sweep runs on a project opened from one file".into(),
            ));
        };
        let shard = match shard.map(|s| Shard::parse(&s, |k| std::env::var(k).ok())) {
            None => Shard::ALL,
            Some(Ok(s)) => s,
            Some(Err(e)) => return Err(usage(py, e.to_string())),
        };
        if jobs == Some(0) {
            return Err(usage(py, "jobs must be at least 1".into()));
        }
        let p = lock(&self.inner);
        let program = &p.checked.program;
        let Some(sweep) = program.sweep(&name).cloned() else {
            let e = flexflight::ops::unknown_name(
                "sweep",
                &name,
                program.sweeps.iter().map(|s| s.name.value.as_str()),
            );
            return Err(ops_error(py, e, Some(&p.checked.sources)));
        };
        let Some(scenario) = program
            .scenarios
            .get(sweep.scenario)
            .map(|s| s.name.value.clone())
        else {
            return Err(usage(
                py,
                format!("sweep `{name}` names a scenario that did not check"),
            ));
        };
        let cache_dir = p.cache_dir.clone();
        drop(p);
        let prog = std::sync::Arc::new(PyCountProgress {
            callback: progress,
            state: Mutex::new(CountState::default()),
        });
        let opts = flexflight::ops::sweep::SweepOptions {
            jobs: jobs
                .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from)),
            shard,
            cache_dir,
            sets: self.sets.clone(),
            progress: Some(prog.clone() as std::sync::Arc<dyn flexflight::ops::Progress>),
        };
        let r = py.allow_threads(|| {
            flexflight::ops::sweep::run_sweep(file, &sweep, &scenario, &out, &opts)
        });
        drop(opts);
        let (failed, warnings) = match std::sync::Arc::try_unwrap(prog) {
            Ok(p) => p.into_parts(),
            Err(_) => (None, Vec::new()),
        };
        if let Some(e) = failed {
            return Err(e);
        }
        match r {
            Ok(r) => {
                let j = serde_json::json!({
                    "sweep": r.manifest.sweep, "scenario": r.manifest.scenario,
                    "shard": r.manifest.shard, "cases": r.rows.len(), "ran": r.ran,
                    "resumed": r.skipped, "failed": r.failed, "artifacts": r.artifacts,
                    "wall_time_s": r.wall_seconds,
                });
                Ok((json_to_py(py, &j)?, warnings))
            }
            Err(e) => Err(error(py, e.to_string(), Some("io"), serde_json::json!([]))),
        }
    }

    /// `flexflight montecarlo` of the dispersion `name` into `out`
    /// (`ops::montecarlo::runner::run_dispersion`): the run's summary as JSON and the
    /// warnings; the tables are `out/samples.csv`, `out/statistics.json` and `.txt`. Samples
    /// run on `jobs` threads with the GIL released; a finished sample in `out` is not run
    /// again. `full_outputs` takes each sample's outputs from the complete run summary
    /// (`--full-outputs`), `exact_boundaries` solves every sample's flutter boundary at its
    /// own fin thickness (`--exact-boundaries`).
    #[pyo3(signature = (name, out, samples=None, jobs=None, shard=None, flutter_margin=None, progress=None, full_outputs=false, exact_boundaries=false))]
    #[allow(clippy::too_many_arguments)]
    fn montecarlo(
        &self,
        py: Python<'_>,
        name: String,
        out: PathBuf,
        samples: Option<usize>,
        jobs: Option<usize>,
        shard: Option<String>,
        flutter_margin: Option<bool>,
        progress: Option<Py<PyAny>>,
        full_outputs: bool,
        exact_boundaries: bool,
    ) -> PyResult<(PyObject, Vec<String>)> {
        use flexflight::analysis::sweep::Shard;
        use flexflight::ops::montecarlo::runner::{MonteCarloOptions, run_dispersion};
        let usage = |py: Python<'_>, m: String| error(py, m, Some("usage"), serde_json::json!([]));
        let [file] = self.files.as_slice() else {
            return Err(usage(
                py,
                "a Monte Carlo runs on a project opened from one file".into(),
            ));
        };
        let shard = match shard.map(|s| Shard::parse(&s, |k| std::env::var(k).ok())) {
            None => Shard::ALL,
            Some(Ok(s)) => s,
            Some(Err(e)) => return Err(usage(py, e.to_string())),
        };
        if jobs == Some(0) || samples == Some(0) {
            return Err(usage(py, "jobs and samples must be at least 1".into()));
        }
        let p = lock(&self.inner);
        let program = &p.checked.program;
        let Some(d) = program.dispersion(&name).cloned() else {
            let e = flexflight::ops::unknown_name(
                "dispersion",
                &name,
                program.dispersions.iter().map(|s| s.name.value.as_str()),
            );
            return Err(ops_error(py, e, Some(&p.checked.sources)));
        };
        let Some(scenario) = program
            .scenarios
            .get(d.scenario)
            .map(|s| s.name.value.clone())
        else {
            return Err(usage(
                py,
                format!("dispersion `{name}` names a scenario that did not check"),
            ));
        };
        let cache_dir = p.cache_dir.clone();
        drop(p);
        let prog = std::sync::Arc::new(PyCountProgress {
            callback: progress,
            state: Mutex::new(CountState::default()),
        });
        let opts = MonteCarloOptions {
            samples: samples.unwrap_or(d.samples),
            jobs: jobs
                .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from)),
            shard,
            cache_dir,
            sets: self.sets.clone(),
            progress: Some(prog.clone() as std::sync::Arc<dyn flexflight::ops::Progress>),
            flutter_margin,
            full_summary: full_outputs,
            exact_boundaries,
        };
        let r = py.allow_threads(|| run_dispersion(file, &d, &scenario, &out, &opts));
        drop(opts);
        let (failed, warnings) = match std::sync::Arc::try_unwrap(prog) {
            Ok(p) => p.into_parts(),
            Err(_) => (None, Vec::new()),
        };
        if let Some(e) = failed {
            return Err(e);
        }
        match r {
            Ok(r) => {
                let j = serde_json::json!({
                    "dispersion": r.manifest.dispersion, "scenario": r.manifest.scenario,
                    "seed": r.manifest.seed, "shard": r.manifest.shard,
                    "samples": r.rows.len(), "ran": r.ran, "resumed": r.skipped,
                    "failed": r.failed, "incomplete": r.incomplete, "artifacts": r.artifacts,
                    "wall_time_s": r.wall_seconds, "stage_seconds": r.phases,
                    "text": r.summary,
                });
                Ok((json_to_py(py, &j)?, warnings))
            }
            Err(e) => Err(error(py, e.to_string(), Some("io"), serde_json::json!([]))),
        }
    }

    /// `analyze flutter` of `scenario` (`ops::flutter::solve_request`): the JSON of
    /// `flutter.json`, the text of `vg.csv` and the warnings.
    #[pyo3(signature = (scenario, clamped, altitude=None, mach=None, speeds=None, modes=None, aero="doublet-lattice"))]
    #[allow(clippy::too_many_arguments)]
    fn flutter(
        &self,
        py: Python<'_>,
        scenario: String,
        clamped: bool,
        altitude: Option<f64>,
        mach: Option<f64>,
        speeds: Option<Vec<f64>>,
        modes: Option<usize>,
        aero: &str,
    ) -> PyResult<(PyObject, String, Vec<String>)> {
        let aero = match aero {
            "unsteady" | "vortex-lattice" | "vortex_lattice" => AeroChoice::Unsteady,
            "quasi-steady" | "quasi_steady" => AeroChoice::QuasiSteady,
            "doublet-lattice" | "doublet_lattice" => AeroChoice::DoubletLattice,
            other => {
                return Err(error(
                    py,
                    format!(
                        "aero must be `doublet-lattice`, `vortex-lattice` (or `unsteady`) or `quasi-steady`, not `{other}`"
                    ),
                    Some("usage"),
                    serde_json::json!([]),
                ));
            }
        };
        let req = FlutterRequest {
            clamped,
            altitude,
            mach,
            speeds,
            modes,
            aero,
        };
        let mut guard = lock(&self.inner);
        let p = &mut *guard;
        let cache_dir = p.cache_dir.clone();
        let (r, warnings) = py.allow_threads(|| {
            let mut warnings = Vec::new();
            let r = flexflight::ops::flutter::solve_request(
                &mut p.checked,
                &scenario,
                &req,
                cache_dir.as_deref(),
                &mut |w| warnings.push(w),
            )
            .map(|r| {
                (
                    flexflight::ops::flutter::summary_json(&r),
                    flexflight::ops::flutter::vg_csv(&r),
                )
            });
            (r, warnings)
        });
        match r {
            Ok((j, vg)) => Ok((json_to_py(py, &j)?, vg, warnings)),
            Err(e) => Err(ops_error(py, e, Some(&p.checked.sources))),
        }
    }

    /// `analyze linear` of `scenario`: the JSON of `--format json`.
    #[pyo3(signature = (scenario, frozen_gravity=false))]
    fn linear(
        &self,
        py: Python<'_>,
        scenario: String,
        frozen_gravity: bool,
    ) -> PyResult<(PyObject, Vec<String>)> {
        let mut guard = lock(&self.inner);
        let p = &mut *guard;
        let cache_dir = p.cache_dir.clone();
        let (r, warnings) = py.allow_threads(|| {
            let mut warnings = Vec::new();
            let r = flexflight::ops::linear::linear_json(
                &mut p.checked,
                &scenario,
                frozen_gravity,
                cache_dir.as_deref(),
                &mut |w| warnings.push(w),
            );
            (r, warnings)
        });
        match r {
            Ok(j) => Ok((json_to_py(py, &j)?, warnings)),
            Err(e) => Err(ops_error(py, e, Some(&p.checked.sources))),
        }
    }
}

/// A flown scenario (`ops::run::Flown`).
#[pyclass(module = "flexflight._native")]
struct NativeRun {
    flown: Flown,
    /// `ops::run::drag_curve` at the scenario's initial altitude.
    drag: Option<Result<Vec<(f64, f64)>, String>>,
    drag_altitude: f64,
}

#[pymethods]
impl NativeRun {
    /// `summary.json`'s value.
    fn summary(&self, py: Python<'_>) -> PyResult<PyObject> {
        json_to_py(py, &self.flown.summary)
    }

    /// The history: channel names, row count and the rows' values as little-endian IEEE-754
    /// doubles, row after row.
    fn history<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let o = &self.flown.output;
        let mut bytes = Vec::with_capacity(o.rows.len() * o.channels.len() * 8);
        for r in &o.rows {
            for v in r {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        let b = PyBytes::new(py, &bytes);
        (o.channels.clone(), o.rows.len(), b).into_pyobject(py)
    }

    /// The zero-lift drag curve `(altitude, [(mach, cd)])` at the scenario's initial
    /// altitude (`ops::run::drag_curve`); `None` without coefficient tables.
    fn drag_curve(&self, py: Python<'_>) -> PyResult<Option<DragCurve>> {
        match &self.drag {
            None => Ok(None),
            Some(Ok(c)) => Ok(Some((self.drag_altitude, c.clone()))),
            Some(Err(e)) => Err(error(
                py,
                format!("drag curve: {e}"),
                Some("usage"),
                serde_json::json!([]),
            )),
        }
    }

    /// The text of `history.csv`.
    fn history_csv(&self) -> String {
        self.flown.history.clone()
    }

    /// The text of `flutter_margin.csv` (`None` when not computed).
    fn flutter_margin_csv(&self) -> Option<String> {
        self.flown
            .margin
            .as_ref()
            .filter(|m| !m.csv.is_empty())
            .map(|m| m.csv.clone())
    }

    /// The flight's events: JSON `{name: {t, position, velocity}}`, deployments as a list.
    fn events(&self, py: Python<'_>) -> PyResult<PyObject> {
        let ev = &self.flown.output.events;
        let point = |e: &flexflight::run::EventPoint| serde_json::json!({"t": e.t, "position": e.position, "velocity": e.velocity});
        let j = serde_json::json!({
            "rail_exit": ev.rail_exit.as_ref().map(point),
            "burnout": ev.burnout.as_ref().map(point),
            "apogee": ev.apogee.as_ref().map(point),
            "deployments": ev.deployments.iter().map(|(name, trigger, deploy)| serde_json::json!({
                "name": name, "trigger": point(trigger), "deployment": point(deploy)
            })).collect::<Vec<_>>(),
            "landing": ev.landing.as_ref().map(point),
        });
        json_to_py(py, &j)
    }

    /// Writes `history.csv`, `summary.json`, `flutter_margin.csv` and `aero_tables/` into
    /// `out` (`ops::run::write_outputs`: all or nothing).
    fn write(&self, py: Python<'_>, out: PathBuf) -> PyResult<()> {
        let r =
            py.allow_threads(|| flexflight::ops::run::write_outputs(Path::new(&out), &self.flown));
        r.map_err(|e| {
            error(
                py,
                format!("cannot write the run outputs to `{}`: {e}", out.display()),
                Some("usage"),
                serde_json::json!([]),
            )
        })
    }
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_class::<NativeProject>()?;
    m.add_class::<NativeRun>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
