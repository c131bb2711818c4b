//! Assemble a report directory: draw every figure of a run or a map into `out`, then the
//! index page. Inputs arrive already read (history, map, mesh); this module only writes
//! figure files and `index.html` inside `out`.

use std::path::{Path, PathBuf};

use super::ReportError;
use super::figures::{ModeGroup, plan_figures};
use super::history::History;
use super::index::{IndexEntry, index_html};
use super::map::StabilityMap;
use super::mesh::{DeformationFrame, MeshGeometry, auto_magnification};
use super::plot::{FIGURE_SIZE, save_svg_png};

/// Fraction of the reference span the largest magnified displacement is scaled to when the
/// magnification is automatic.
pub const AUTO_MAGNIFY_FRACTION: f64 = 0.1;

/// Default number of deformation frames (evenly spaced, the last at the final time).
pub const DEFAULT_FRAMES: usize = 4;

/// What to draw for a run.
#[derive(Clone, Debug, Default)]
pub struct RunReportOptions {
    /// Frame times (s); empty: [`DEFAULT_FRAMES`] evenly spaced times after the first row.
    pub frame_times: Vec<f64>,
    /// Displacement magnification; `None`: automatic ([`AUTO_MAGNIFY_FRACTION`]).
    pub magnify: Option<f64>,
    /// Flight events (time, label) marked on every time plot (from `summary.json`).
    pub events: Vec<(f64, String)>,
    /// The run's `flutter_margin.csv`, when it wrote one.
    pub flutter_margin: Option<History>,
}

/// The result of a report: index entries in page order and every file written.
#[derive(Clone, Debug, Default)]
pub struct ReportOutput {
    /// Index entries, drawn and skipped, in page order.
    pub entries: Vec<IndexEntry>,
    /// Every file written.
    pub files: Vec<PathBuf>,
    /// Notes for the user (skipped figures, missing modal columns, magnification).
    pub notes: Vec<String>,
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default()
}

impl ReportOutput {
    fn push_drawn(&mut self, caption: String, files: Vec<PathBuf>) {
        let names = (
            files.first().map(|p| file_name(p)).unwrap_or_default(),
            files.get(1).map(|p| file_name(p)).unwrap_or_default(),
        );
        self.entries.push(IndexEntry {
            caption,
            files: Ok(names),
        });
        self.files.extend(files);
    }

    fn push_skipped(&mut self, caption: String, reason: String) {
        self.entries.push(IndexEntry {
            caption,
            files: Err(reason),
        });
    }

    /// Write `out/index.html` with `title` and `facts`; adds it to `files`.
    pub fn write_index(
        &mut self,
        out: &Path,
        title: &str,
        facts: &[(String, String)],
    ) -> Result<PathBuf, ReportError> {
        let path = out.join("index.html");
        std::fs::write(&path, index_html(title, facts, &self.entries)).map_err(|e| {
            ReportError::Write {
                path: path.clone(),
                message: e.to_string(),
            }
        })?;
        self.files.push(path.clone());
        Ok(path)
    }
}

/// Name of the list of files a report wrote, kept in the report directory.
pub const MANIFEST: &str = ".flexflight-report-files";

/// Record the files of this report in `out/MANIFEST` and delete the files an earlier
/// report listed there that this one did not write again (e.g. `frame_04.*` after a report
/// with fewer frames). Only files named in the manifest and lying directly in `out` are
/// removed, so nothing a user put there is touched. Returns the files removed.
pub fn replace_manifest(out: &Path, written: &[PathBuf]) -> Result<Vec<PathBuf>, ReportError> {
    let manifest = out.join(MANIFEST);
    let names: Vec<String> = written.iter().map(|p| file_name(p)).collect();
    let mut removed = Vec::new();
    if let Ok(old) = std::fs::read_to_string(&manifest) {
        for name in old.lines().map(str::trim).filter(|n| !n.is_empty()) {
            let plain = !name.contains(['/', '\\']) && name != ".." && name != ".";
            if plain && !names.iter().any(|n| n == name) {
                let path = out.join(name);
                if path.is_file() && std::fs::remove_file(&path).is_ok() {
                    removed.push(path);
                }
            }
        }
    }
    std::fs::write(&manifest, names.join("\n") + "\n").map_err(|e| ReportError::Write {
        path: manifest.clone(),
        message: e.to_string(),
    })?;
    Ok(removed)
}

/// Draw a stability map into `out/map.svg` and `out/map.png`.
pub fn map_figures(
    map: &StabilityMap,
    out: &Path,
    report: &mut ReportOutput,
) -> Result<(), ReportError> {
    let files = save_svg_png(map, &out.join("map"), FIGURE_SIZE)?;
    report.push_drawn(
        format!(
            "{}: sigma_d over {} x {} (blue stable, red unstable; bold: sigma_d = 0)",
            map.title, map.x_label, map.y_label
        ),
        files,
    );
    Ok(())
}

/// The frame times: the requested ones, or `n` evenly spaced after the first row.
pub fn frame_times(h: &History, requested: &[f64], n: usize) -> Vec<f64> {
    if !requested.is_empty() {
        return requested.to_vec();
    }
    let t = h.time();
    let (Some(&t0), Some(&t1)) = (t.first(), t.last()) else {
        return Vec::new();
    };
    if t1 <= t0 {
        return vec![t0];
    }
    (1..=n)
        .map(|k| t0 + (t1 - t0) * k as f64 / n as f64)
        .collect()
}

/// Draw a run's figure set and (with a mesh) its deformation frames into `out`.
///
/// `mode_group` classifies a mode name; `mesh` is the compiled vehicle's geometry, if it
/// could be loaded.
pub fn run_figures(
    h: &History,
    mode_group: &dyn Fn(&str) -> ModeGroup,
    mesh: Option<&MeshGeometry>,
    options: &RunReportOptions,
    out: &Path,
    report: &mut ReportOutput,
) -> Result<(), ReportError> {
    let mut figures = plan_figures(h, mode_group);
    for f in &mut figures {
        if let Ok(p) = &mut f.plot {
            p.markers = options.events.clone();
        }
    }
    if h.column("speed").is_some() {
        figures.push(super::figures::ground_track(h));
    }
    if let Some(m) = &options.flutter_margin {
        let mut f = super::figures::flutter_margin(m);
        if let Ok(p) = &mut f.plot {
            p.markers = options.events.clone();
        }
        figures.push(f);
    }
    for fig in figures {
        match fig.plot {
            Ok(plot) => {
                let files = save_svg_png(&plot, &out.join(&fig.stem), FIGURE_SIZE)?;
                report.push_drawn(fig.caption, files);
            }
            Err(reason) => report.push_skipped(fig.caption, reason),
        }
    }
    let Some(mesh) = mesh else {
        report.push_skipped(
            "Deformation frames".into(),
            "the compiled vehicle (artifact) could not be loaded".into(),
        );
        return Ok(());
    };
    let missing: Vec<&str> = mesh
        .mode_names
        .iter()
        .filter(|m| h.column(&format!("eta_{m}")).is_none())
        .map(String::as_str)
        .collect();
    if !missing.is_empty() {
        report.notes.push(format!(
            "history.csv has no eta column for mode(s) {}: taken as 0 in the frames",
            missing.join(", ")
        ));
    }
    let times = frame_times(h, &options.frame_times, DEFAULT_FRAMES);
    let etas: Vec<Vec<f64>> = times
        .iter()
        .map(|&t| {
            mesh.mode_names
                .iter()
                .map(|m| h.interpolate(&format!("eta_{m}"), t).unwrap_or(0.0))
                .collect()
        })
        .collect();
    // One scale for every frame (so frames can be compared), from the largest
    // displacement over the frames drawn.
    let magnify = options
        .magnify
        .unwrap_or_else(|| auto_magnification(mesh, &etas, AUTO_MAGNIFY_FRACTION));
    report
        .notes
        .push(format!("deformation frames magnified x {magnify:.4e}"));
    if mesh.edges.is_empty() {
        report.notes.push(
            "no element topology (pass --vehicle-file): the body is drawn as a line through its nodes, fin nodes as dots"
                .into(),
        );
    }
    for (k, (t, eta)) in times.iter().zip(etas).enumerate() {
        let frame = DeformationFrame {
            geometry: mesh,
            eta,
            t: *t,
            magnify,
            title: format!("Deformed mesh at t = {t:.4} s (displacements x {magnify:.3e})"),
        };
        let files = save_svg_png(
            &frame,
            &out.join(format!("frame_{:02}", k + 1)),
            (1200, 600),
        )?;
        report.push_drawn(
            format!(
                "Deformed FE mesh at t = {t:.4} s, front and isometric views, displacements magnified x {magnify:.3e}"
            ),
            files,
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::history::parse_history;

    #[test]
    fn stale_files_of_an_earlier_report_are_removed_and_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let out = &dir.path().join("report");
        std::fs::create_dir(out).unwrap();
        for f in ["a.svg", "b.svg", "mine.txt"] {
            std::fs::write(out.join(f), "x").unwrap();
        }
        let removed = replace_manifest(out, &[out.join("a.svg"), out.join("b.svg")]).unwrap();
        assert!(removed.is_empty());
        let removed = replace_manifest(out, &[out.join("a.svg")]).unwrap();
        assert_eq!(removed, vec![out.join("b.svg")]);
        assert!(out.join("a.svg").is_file() && out.join("mine.txt").is_file());
        assert!(!out.join("b.svg").exists());
        // A manifest naming a file outside the report directory removes nothing there.
        std::fs::write(out.join(MANIFEST), "../keep\nmine.txt\n").unwrap();
        std::fs::write(dir.path().join("keep"), "x").unwrap();
        replace_manifest(out, &[out.join("a.svg")]).unwrap();
        assert!(dir.path().join("keep").is_file());
        assert!(!out.join("mine.txt").exists(), "listed in the manifest");
    }

    #[test]
    fn default_frames_are_evenly_spaced_after_the_start() {
        let h = parse_history("t,a\n0,0\n1,0\n2,0\n", Path::new("h")).unwrap();
        assert_eq!(frame_times(&h, &[], 4), vec![0.5, 1.0, 1.5, 2.0]);
        assert_eq!(frame_times(&h, &[0.3], 4), vec![0.3]);
    }
}

/// One branch of a flutter solution's `vg.csv` (`analyze flutter --out`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VgBranch {
    pub name: String,
    /// (speed, g) where the root oscillates.
    pub g: Vec<(f64, f64)>,
    /// (speed, frequency in Hz).
    pub f: Vec<(f64, f64)>,
}

/// Reads `vg.csv` (header `speed_m_s,branch,name,g,frequency_hz,k,p_re,p_im`; `name` quoted,
/// `g` empty for a non-oscillatory root). Malformed lines are errors with their line.
pub fn read_vg_csv(path: &Path) -> Result<Vec<VgBranch>, ReportError> {
    let text = std::fs::read_to_string(path).map_err(|source| ReportError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let bad = |line: usize, message: String| ReportError::Csv {
        path: path.to_path_buf(),
        line: line as u64,
        message,
    };
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, h)) if h.starts_with("speed_m_s,branch,name,g,frequency_hz") => {}
        _ => return Err(bad(1, "not a vg.csv header".into())),
    }
    let mut branches: Vec<VgBranch> = Vec::new();
    for (i, l) in lines {
        // speed,branch,"name",g,frequency,...: the name is the only quoted field.
        let (Some(q0), Some(q1)) = (l.find('"'), l.rfind('"')) else {
            return Err(bad(i + 1, "no quoted branch name".into()));
        };
        if q1 <= q0 {
            return Err(bad(i + 1, "no quoted branch name".into()));
        }
        let head: Vec<&str> = l[..q0].split(',').collect();
        let tail: Vec<&str> = l[q1 + 1..].split(',').collect();
        let num = |s: &str| -> Result<f64, ReportError> {
            s.trim()
                .parse::<f64>()
                .map_err(|_| bad(i + 1, format!("`{s}` is not a number")))
        };
        if head.len() < 3 || tail.len() < 3 {
            return Err(bad(i + 1, "too few fields".into()));
        }
        let speed = num(head[0])?;
        let branch: usize = head[1]
            .trim()
            .parse()
            .map_err(|_| bad(i + 1, format!("`{}` is not a branch index", head[1])))?;
        if branch > 1000 {
            return Err(bad(i + 1, "branch index too large".into()));
        }
        if branches.len() <= branch {
            branches.resize(branch + 1, VgBranch::default());
        }
        let b = &mut branches[branch];
        b.name = l[q0 + 1..q1].to_string();
        if !tail[1].trim().is_empty() {
            b.g.push((speed, num(tail[1])?));
        }
        b.f.push((speed, num(tail[2])?));
    }
    Ok(branches)
}

/// The V-g and V-f diagrams of a flutter solution.
pub fn flutter_figures(
    branches: &[VgBranch],
    out: &Path,
    report: &mut ReportOutput,
) -> Result<(), ReportError> {
    use super::plot::{Series, TimePlot};
    let series = |pick: fn(&VgBranch) -> &Vec<(f64, f64)>| -> Vec<Series> {
        branches
            .iter()
            .filter(|b| !pick(b).is_empty())
            .map(|b| Series {
                label: b.name.clone(),
                xs: pick(b).iter().map(|p| p.0).collect(),
                ys: pick(b).iter().map(|p| p.1).collect(),
            })
            .collect()
    };
    for (stem, caption, y_label, s) in [
        (
            "vg",
            "V-g: damping g = 2 Re(p)/Im(p) of each branch against speed (flutter where g crosses 0)",
            "g",
            series(|b| &b.g),
        ),
        (
            "vf",
            "V-f: frequency of each branch against speed",
            "frequency (Hz)",
            series(|b| &b.f),
        ),
    ] {
        let plot = TimePlot {
            title: caption.split(':').next().unwrap_or(caption).to_string(),
            x_label: "V (m/s)".to_string(),
            y_label: y_label.to_string(),
            series: s,
            markers: Vec::new(),
        };
        let files = save_svg_png(&plot, &out.join(stem), FIGURE_SIZE)?;
        report.push_drawn(caption.to_string(), files);
    }
    Ok(())
}
