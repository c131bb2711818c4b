//! Reports (`flexflight report DIR`): figures (SVG + PNG) and `DIR/report/index.html` for a run
//! directory (`history.csv`, `summary.json`) or a map directory (`map.csv`).
//!
//! Only `DIR/report/` is written; the run's own files are never touched.
use std::path::{Path, PathBuf};

use crate::artifact::{self, Cache, CacheKey};
use crate::report::ReportError;
use crate::report::build::{
    Phases, ReportOutput, RunReportOptions, map_figures, replace_manifest, run_figures,
};
use crate::report::figures::ModeGroup;
use crate::report::history::read_history;
use crate::report::map::{OverlayCurve, parse_overlay_csv, read_map_csv};
use crate::report::mesh::MeshGeometry;
use crate::structure::compile::{CompiledVehicle, build_model};
use crate::structure::fe_model::ElementKind;

use crate::check::{DiskLoader, check_files};
use crate::ops::OpsError;

/// Options of `flexflight report`.
pub struct ReportArgs<'a> {
    pub dir: &'a Path,
    /// Comma-separated frame times (s), e.g. "0.1,0.5".
    pub frames: Option<&'a str>,
    /// "auto" or a number.
    pub magnify: Option<&'a str>,
    /// The vehicle file of the run, to draw the mesh with its element edges.
    pub vehicle_file: Option<&'a Path>,
    pub cache_dir: Option<&'a Path>,
}

/// What a report wrote.
#[derive(Debug)]
pub struct ReportDone {
    /// `report/index.html`.
    pub index: PathBuf,
    /// Files of an earlier report that this one no longer draws, removed.
    pub removed: Vec<PathBuf>,
    /// What could not be drawn and why (the report is still written).
    pub warnings: Vec<String>,
    /// Figures drawn and skipped, and the files written.
    pub drawn: usize,
    pub skipped: usize,
    pub files: usize,
}

/// A report error as an operation's error: unreadable data is the input's fault, the rest
/// the environment's.
fn fail(e: &ReportError) -> OpsError {
    OpsError::Coded {
        code: e.code(),
        message: e.to_string(),
        input: matches!(
            e,
            ReportError::Csv { .. } | ReportError::Summary { .. } | ReportError::Data(_)
        ),
    }
}

/// Parse `--frames 0.1,0.5,...`.
pub fn parse_frames(s: &str) -> Result<Vec<f64>, String> {
    s.split(',')
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .map(|p| {
            p.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("--frames: `{p}` is not a time in seconds"))
        })
        .collect()
}

/// Parse `--magnify auto|X` (X > 0).
pub fn parse_magnify(s: &str) -> Result<Option<f64>, String> {
    if s.eq_ignore_ascii_case("auto") {
        return Ok(None);
    }
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(Some(v)),
        _ => Err(format!(
            "--magnify: `{s}` is neither `auto` nor a positive number"
        )),
    }
}

fn parse_hex_key(hex: &str) -> Option<CacheKey> {
    if hex.len() != 64 {
        return None;
    }
    let mut key = [0u8; 32];
    for (k, byte) in key.iter_mut().enumerate() {
        *byte = u8::from_str_radix(hex.get(2 * k..2 * k + 2)?, 16).ok()?;
    }
    Some(CacheKey(key))
}

/// The flight events of a run's `summary.json` (`flight`), as (time, label) markers.
fn flight_events(summary: &serde_json::Value) -> Vec<(f64, String)> {
    let f = &summary["flight"];
    let mut out = Vec::new();
    for (key, label) in [
        ("rail_exit", "rail exit"),
        ("burnout", "burnout"),
        ("apogee", "apogee"),
        ("landing", "landing"),
    ] {
        if let Some(t) = f[key]["t"].as_f64() {
            out.push((t, label.to_string()));
        }
    }
    if let Some(d) = f["deployments"].as_array() {
        for dep in d {
            if let (Some(t), Some(n)) = (dep["deployment"]["t"].as_f64(), dep["name"].as_str()) {
                out.push((t, format!("{n} deploys")));
            }
        }
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// The compiled vehicle recorded in `summary.json`: the artifact at its recorded path, or
/// the one with its hash in the cache directory.
fn load_compiled(
    summary: &serde_json::Value,
    cache_dir: Option<&Path>,
) -> Result<CompiledVehicle, String> {
    let key = summary
        .get("artifact_hash")
        .and_then(|v| v.as_str())
        .and_then(parse_hex_key)
        .ok_or("summary.json has no valid `artifact_hash`")?;
    let mut candidates: Vec<PathBuf> = Vec::new();
    if let Some(p) = summary.get("artifact").and_then(|v| v.as_str()) {
        candidates.push(PathBuf::from(p));
    }
    candidates.push(Cache::resolve(cache_dir).path_for(&key));
    let mut last = String::new();
    for path in candidates {
        match artifact::load::<CompiledVehicle>(&path, &key) {
            Ok(art) => {
                return rkyv::deserialize::<CompiledVehicle, rkyv::rancor::Error>(art.get())
                    .map_err(|e| format!("artifact {}: {e}", path.display()));
            }
            Err(e) => last = format!("{}: {e}", path.display()),
        }
    }
    Err(last)
}

/// Element edges of the run's FE model, rebuilt from the vehicle file (the scenario's
/// vehicle, with its overrides, when the file declares the scenario). Checked against the
/// artifact's node ids.
fn mesh_edges(
    file: &Path,
    summary: &serde_json::Value,
    compiled: &CompiledVehicle,
) -> Result<Vec<[usize; 2]>, String> {
    let checked = check_files(&[file.to_path_buf()], &[], &DiskLoader);
    if checked.has_errors() {
        let first = checked
            .diagnostics
            .iter()
            .find(|d| d.severity == crate::diagnostics::Severity::Error)
            .map_or_else(String::new, |d| format!(": {}", d.message));
        return Err(format!("`{}` does not check{first}", file.display()));
    }
    let scenario = summary.get("scenario").and_then(|v| v.as_str());
    let vehicle = scenario
        .and_then(|s| checked.program.scenario(s))
        .map(|s| &s.vehicle)
        .or_else(|| {
            checked
                .program
                .vehicles
                .iter()
                .find(|v| v.name.value == compiled.vehicle)
        })
        .ok_or_else(|| {
            format!(
                "`{}` declares neither the scenario nor the vehicle `{}`",
                file.display(),
                compiled.vehicle
            )
        })?;
    let model = build_model(vehicle).map_err(|e| e.to_string())?;
    let ids: Vec<u64> = model.nodes.iter().map(|n| n.id).collect();
    if ids != compiled.node_ids {
        return Err(format!(
            "the FE model of `{}` ({} nodes) is not the one in the artifact ({} nodes)",
            file.display(),
            ids.len(),
            compiled.node_ids.len()
        ));
    }
    let mut edges: Vec<[usize; 2]> = Vec::new();
    for e in &model.elements {
        let n = &e.nodes;
        match e.kind {
            ElementKind::Shell if n.len() >= 3 => {
                for k in 0..n.len() {
                    edges.push([n[k], n[(k + 1) % n.len()]]);
                }
            }
            _ => edges.extend(n.windows(2).map(|w| [w[0], w[1]])),
        }
    }
    for e in &mut edges {
        e.sort_unstable();
    }
    edges.sort_unstable();
    edges.dedup();
    Ok(edges)
}

/// The overlay curves of a map directory: every `overlay_<label>.csv` (columns x, y), in
/// name order; `_` in the label is shown as a space.
fn read_overlays(dir: &Path) -> Result<Vec<OverlayCurve>, ReportError> {
    let read_err = |source| ReportError::Read {
        path: dir.to_path_buf(),
        source,
    };
    let mut files: Vec<(String, PathBuf)> = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(read_err)? {
        let path = entry.map_err(read_err)?.path();
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().to_string())
            .unwrap_or_default();
        if let Some(label) = name
            .strip_prefix("overlay_")
            .and_then(|n| n.strip_suffix(".csv"))
        {
            files.push((label.replace('_', " "), path));
        }
    }
    files.sort();
    files
        .into_iter()
        .map(|(label, path)| {
            let text = crate::report::read_text(&path)?;
            parse_overlay_csv(&text, &label, &path)
        })
        .collect()
}

/// Draws the report of `args.dir` into `args.dir/report/` (module doc). Reads every input
/// before writing anything.
pub fn build_report(args: &ReportArgs) -> Result<ReportDone, OpsError> {
    let dir = args.dir;
    if !dir.is_dir() {
        return Err(OpsError::Coded {
            code: "report::read",
            message: format!(
                "`{}` is not a directory (expected a run directory with history.csv and summary.json, or a map directory with map.csv)",
                dir.display()
            ),
            input: false,
        });
    }
    let frame_times = args
        .frames
        .map(parse_frames)
        .transpose()
        .map_err(OpsError::Usage)?
        .unwrap_or_default();
    let magnify = args
        .magnify
        .map(parse_magnify)
        .transpose()
        .map_err(OpsError::Usage)?
        .flatten();
    let history_path = dir.join("history.csv");
    let map_path = dir.join("map.csv");
    let vg_path = dir.join("vg.csv");
    if !history_path.is_file() && !map_path.is_file() && !vg_path.is_file() {
        return Err(OpsError::Coded {
            code: "report::read",
            message: format!(
                "`{}` has no history.csv, map.csv or vg.csv: nothing to report",
                dir.display()
            ),
            input: false,
        });
    }
    // Read everything before writing anything.
    let map = if map_path.is_file() {
        match read_map_csv(&map_path).and_then(|mut m| {
            m.overlays = read_overlays(dir)?;
            Ok(m)
        }) {
            Ok(m) => Some(m),
            Err(e) => return Err(fail(&e)),
        }
    } else {
        None
    };
    let history = if history_path.is_file() {
        match read_history(&history_path) {
            Ok(h) => Some(h),
            Err(e) => return Err(fail(&e)),
        }
    } else {
        None
    };
    let vg = if vg_path.is_file() {
        match crate::report::build::read_vg_csv(&vg_path) {
            Ok(v) => Some(v),
            Err(e) => return Err(fail(&e)),
        }
    } else {
        None
    };
    // flutter.json beside vg.csv: the condition and flutter point for the V-g titles.
    let flutter_json_path = dir.join("flutter.json");
    let flutter_json = if vg.is_some() && flutter_json_path.is_file() {
        match read_json(flutter_json_path) {
            Ok(v) => Some(v),
            Err(e) => return Err(fail(&e)),
        }
    } else {
        None
    };
    let margin_path = dir.join("flutter_margin.csv");
    let flutter_margin = if history.is_some() && margin_path.is_file() {
        match read_history(&margin_path) {
            Ok(h) => Some(h),
            Err(e) => return Err(fail(&e)),
        }
    } else {
        None
    };
    let summary_path = dir.join("summary.json");
    let summary = if history.is_some() && summary_path.is_file() {
        match read_json(summary_path) {
            Ok(v) => Some(v),
            Err(e) => return Err(fail(&e)),
        }
    } else {
        None
    };
    let mut warnings = Vec::new();
    let compiled = match &summary {
        Some(s) => match load_compiled(s, args.cache_dir) {
            Ok(c) => Some(c),
            Err(e) => {
                warnings.push(format!(
                    "no deformation frames: cannot load the artifact ({e})"
                ));
                None
            }
        },
        None if history.is_some() => {
            warnings.push("no summary.json: no deformation frames".to_string());
            None
        }
        None => None,
    };
    let edges = match (&compiled, args.vehicle_file, &summary) {
        (Some(c), Some(file), Some(s)) => match mesh_edges(file, s, c) {
            Ok(e) => e,
            Err(msg) => {
                warnings.push(format!("mesh drawn without element edges: {msg}"));
                Vec::new()
            }
        },
        _ => Vec::new(),
    };
    let mesh = compiled
        .as_ref()
        .map(|c| MeshGeometry::from_compiled(c, edges));

    let out = dir.join("report");
    if let Err(e) = std::fs::create_dir_all(&out) {
        return Err(fail(&ReportError::Write {
            path: out,
            message: e.to_string(),
        }));
    }
    let mut report = ReportOutput::default();
    let mut facts: Vec<(String, String)> = Vec::new();
    if let Some(m) = &map {
        if let Err(e) = map_figures(m, &out, &mut report) {
            return Err(fail(&e));
        }
        facts.push((
            "map".into(),
            format!("{} x {} points", m.xs.len(), m.ys.len()),
        ));
    }
    if let Some(v) = &vg {
        let condition = flutter_json
            .as_ref()
            .map(crate::report::build::FlutterCondition::from_json)
            .unwrap_or_default();
        if let Err(e) = crate::report::build::flutter_figures(v, &condition, &out, &mut report) {
            return Err(fail(&e));
        }
        facts.push(("flutter".into(), format!("{} branches", v.len())));
    }
    if let Some(h) = &history {
        let classes: Vec<(String, ModeGroup)> = compiled
            .as_ref()
            .map(|c| {
                c.modes
                    .iter()
                    .map(|m| (m.name.clone(), ModeGroup::from_class(&m.class)))
                    .collect()
            })
            .unwrap_or_default();
        let group = |name: &str| {
            classes
                .iter()
                .find(|(n, _)| n == name)
                .map_or_else(|| ModeGroup::from_name(name), |(_, g)| *g)
        };
        let flight = summary.as_ref().map(|s| &s["flight"]);
        let at = |key: &str| flight.and_then(|f| f[key]["t"].as_f64());
        let options = RunReportOptions {
            frame_times,
            magnify,
            events: summary.as_ref().map(flight_events).unwrap_or_default(),
            flutter_margin,
            criterion: summary
                .as_ref()
                .and_then(|s| s["flutter_margin"]["criterion_speed_margin"].as_f64()),
            phases: Phases {
                apogee: at("apogee"),
                first_deployment: flight
                    .and_then(|f| f["deployments"].as_array())
                    .and_then(|d| {
                        d.iter()
                            .filter_map(|x| x["deployment"]["t"].as_f64())
                            .reduce(f64::min)
                    }),
            },
            max_q: at("max_dynamic_pressure"),
            burnout: at("burnout"),
        };
        if let Err(e) = run_figures(h, &group, mesh.as_ref(), &options, &out, &mut report) {
            return Err(fail(&e));
        }
        if let Some(s) = &summary {
            for key in [
                "scenario",
                "vehicle",
                "stop_reason",
                "t_end",
                "rows",
                "artifact_hash",
            ] {
                if let Some(v) = s.get(key) {
                    let text = v.as_str().map_or_else(|| v.to_string(), str::to_string);
                    facts.push((key.to_string(), text));
                }
            }
        }
    }
    let title = match &summary {
        Some(s) => format!(
            "flexflight report: {}",
            s.get("scenario").and_then(|v| v.as_str()).unwrap_or("run")
        ),
        None => format!("flexflight report: {}", dir.display()),
    };
    // A run's page leads with the answer: verdict, flight figures and every warning.
    let lead = match &summary {
        Some(s) => crate::report::index::lead_html(s, &warnings, &report.notes),
        None => {
            for w in &warnings {
                facts.push(("note".into(), w.clone()));
            }
            for n in &report.notes {
                facts.push(("note".into(), n.clone()));
            }
            String::new()
        }
    };
    let index = match report.write_index(&out, &title, &lead, &facts) {
        Ok(p) => p,
        Err(e) => return Err(fail(&e)),
    };
    let removed = match replace_manifest(&out, &report.files) {
        Ok(removed) => removed,
        Err(e) => {
            warnings.push(e.to_string());
            Vec::new()
        }
    };
    let drawn = report.entries.iter().filter(|e| e.files.is_ok()).count();
    Ok(ReportDone {
        index,
        removed,
        warnings,
        drawn,
        skipped: report.entries.len() - drawn,
        files: report.files.len(),
    })
}

/// A JSON file of a run or analysis directory (`summary.json`, `flutter.json`); a file that
/// cannot be read or parsed is a `ReportError::Summary` naming it.
fn read_json(path: std::path::PathBuf) -> Result<serde_json::Value, ReportError> {
    std::fs::read_to_string(&path)
        .map_err(|e| e.to_string())
        .and_then(|t| serde_json::from_str(&t).map_err(|e| e.to_string()))
        .map_err(|message| ReportError::Summary { path, message })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_parse() {
        assert_eq!(parse_frames("0.1, 0.5,1").unwrap(), vec![0.1, 0.5, 1.0]);
        assert!(parse_frames("0.1,x").is_err());
        assert_eq!(parse_magnify("auto").unwrap(), None);
        assert_eq!(parse_magnify("250").unwrap(), Some(250.0));
        assert!(parse_magnify("-1").is_err());
        let k = parse_hex_key(&"0a".repeat(32)).unwrap();
        assert_eq!(k.0, [10u8; 32]);
        assert!(parse_hex_key("zz").is_none());
    }
}
