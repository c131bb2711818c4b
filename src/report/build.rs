//! Assemble a report directory: draw every figure of a run or a map into `out`, then the
//! index page. Inputs arrive already read (history, map, mesh); this module only writes
//! figure files and `index.html` inside `out`.

use std::path::{Path, PathBuf};

use super::ReportError;
use super::figures::PlannedFigure;
use super::figures::{ModeGroup, plan_figures};
use super::history::History;
use super::index::{IndexEntry, index_html};
use super::map::StabilityMap;
use super::mesh::{DeformationFrame, MeshGeometry, auto_magnification};
use super::plot::{FIGURE_SIZE, Series, TimePlot, save_svg_png};

/// Fraction of the reference span the largest magnified displacement is scaled to when the
/// magnification is automatic.
pub const AUTO_MAGNIFY_FRACTION: f64 = 0.1;

/// Number of evenly spaced deformation frames (the last at the final time) when the run
/// gives none of the default frame times ([`default_frame_times`]).
pub const DEFAULT_FRAMES: usize = 4;

/// The ascent's time axis runs past apogee by this fraction of the time to apogee (at least
/// [`ASCENT_MARGIN_MIN_S`]), so the turn over the top is seen.
pub const ASCENT_MARGIN_FRACTION: f64 = 0.05;

/// The smallest time (s) the ascent's axis runs past apogee.
pub const ASCENT_MARGIN_MIN_S: f64 = 1.0;

/// Figures whose channels mean nothing once a recovery device is out (the vehicle hangs
/// from it and is frozen to a rigid body; the aerodynamic tables do not describe it): the
/// angle of attack and sideslip, the attitude and the static margin. They are drawn up to
/// the first deployment only.
pub const NOT_UNDER_CANOPIES: [&str; 3] = ["alpha", "attitude", "static_margin"];

/// The phases of a flight, from `summary.json`'s `flight` events, for splitting the time
/// axes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Phases {
    /// Time of apogee (s), if the flight reached one.
    pub apogee: Option<f64>,
    /// Time of the first deployment of a recovery device (s).
    pub first_deployment: Option<f64>,
}

impl Phases {
    /// The end of the ascent's time axis for a history ending at `t_end` and starting at
    /// `t0`: apogee plus [`ASCENT_MARGIN_FRACTION`] of the time to apogee (at least
    /// [`ASCENT_MARGIN_MIN_S`]); `None` (one axis) without an apogee or when the history
    /// ends before that time.
    pub fn ascent_end(&self, t0: f64, t_end: f64) -> Option<f64> {
        let a = self.apogee?;
        let end = a + (ASCENT_MARGIN_FRACTION * (a - t0)).max(ASCENT_MARGIN_MIN_S);
        (end < t_end).then_some(end)
    }
}

/// The part of a plot with abscissa in `[a, b]` (series, marked points and shaded
/// intervals cut to it).
pub fn clip_plot(plot: &TimePlot, a: f64, b: f64) -> TimePlot {
    let inside = |x: f64| x >= a && x <= b;
    TimePlot {
        series: plot
            .series
            .iter()
            .map(|s| {
                let (xs, ys) =
                    s.xs.iter()
                        .zip(&s.ys)
                        .filter(|(x, _)| inside(**x))
                        .map(|(x, y)| (*x, *y))
                        .unzip();
                Series {
                    label: s.label.clone(),
                    xs,
                    ys,
                }
            })
            .collect(),
        points: plot
            .points
            .iter()
            .filter(|p| inside(p.x))
            .cloned()
            .collect(),
        shaded: plot
            .shaded
            .iter()
            .map(|&(x0, x1)| (x0.max(a), x1.min(b)))
            .filter(|(x0, x1)| x0 <= x1)
            .collect(),
        ..plot.clone()
    }
}

fn has_points(plot: &TimePlot) -> bool {
    plot.series.iter().any(|s| s.xs.len() >= 2)
}

/// The time plots of a figure over the flight's phases: `(stem, caption, plot or reason)`.
/// With an ascent end ([`Phases::ascent_end`]) the ascent (first row to that end) and the
/// descent (apogee to the last row) each get their own axis (`<stem>` and
/// `<stem>_descent`); figures of [`NOT_UNDER_CANOPIES`] stop at the first deployment.
pub fn split_phases(
    fig: &PlannedFigure,
    plot: &TimePlot,
    phases: &Phases,
    (t0, t_end): (f64, f64),
) -> Vec<(String, String, Result<TimePlot, String>)> {
    let canopy_end = if NOT_UNDER_CANOPIES.contains(&fig.stem.as_str()) {
        phases.first_deployment
    } else {
        None
    }
    .unwrap_or(f64::INFINITY);
    let canopy_reason = |d: f64| {
        format!(
            "not drawn under the canopies: meaningless after the first deployment (t = {d:.3} s)"
        )
    };
    let Some(split) = phases.ascent_end(t0, t_end) else {
        let p = clip_plot(plot, t0, canopy_end);
        let p = if has_points(&p) {
            Ok(p)
        } else {
            Err(canopy_reason(canopy_end))
        };
        return vec![(fig.stem.clone(), fig.caption.clone(), p)];
    };
    let apogee = phases.apogee.unwrap_or(split);
    let mut ascent = clip_plot(plot, t0, split.min(canopy_end));
    ascent.title = format!("{} (ascent)", plot.title);
    let mut descent = clip_plot(plot, apogee, t_end.min(canopy_end));
    descent.title = format!("{} (descent)", plot.title);
    let cut = |p: TimePlot| {
        if has_points(&p) {
            Ok(p)
        } else {
            Err(canopy_reason(canopy_end))
        }
    };
    vec![
        (
            fig.stem.clone(),
            format!(
                "{}: ascent, t = {t0:.3} to {:.3} s (apogee at {apogee:.3} s)",
                fig.caption,
                split.min(canopy_end)
            ),
            cut(ascent),
        ),
        (
            format!("{}_descent", fig.stem),
            format!(
                "{}: descent, t = {apogee:.3} to {:.3} s",
                fig.caption,
                t_end.min(canopy_end)
            ),
            cut(descent),
        ),
    ]
}

/// The default deformation frame times: at maximum dynamic pressure (`max_q`, from
/// `summary.json`, else the row of largest `dynamic_pressure`), at burnout, and at the
/// largest `max_deformation` of the history, in time order (coinciding times once); each
/// with what it marks. Empty when the run gives none of them.
pub fn default_frame_times(
    h: &History,
    max_q: Option<f64>,
    burnout: Option<f64>,
) -> Vec<(f64, String)> {
    let argmax = |name: &str| -> Option<f64> {
        let c = h.column(name)?;
        let t = h.time();
        (0..c.len())
            .filter(|&r| c[r].is_finite())
            .reduce(|a, b| if c[b] > c[a] { b } else { a })
            .map(|r| t[r])
    };
    let mut out: Vec<(f64, String)> = [
        (max_q.or_else(|| argmax("dynamic_pressure")), "max q"),
        (burnout, "burnout"),
        (argmax("max_deformation"), "largest deformation"),
    ]
    .into_iter()
    .filter_map(|(t, what)| Some((t.filter(|t| t.is_finite())?, what.to_string())))
    .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut merged: Vec<(f64, String)> = Vec::new();
    for (t, what) in out {
        match merged.last_mut() {
            Some(last) if last.0 == t => last.1 = format!("{}, {what}", last.1),
            _ => merged.push((t, what)),
        }
    }
    merged
}

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
    /// The speed margin criterion `V_F / V` (`summary.json`'s
    /// `flutter_margin.criterion_speed_margin`; 1.15 when absent).
    pub criterion: Option<f64>,
    /// Apogee and first deployment, for the ascent and descent axes.
    pub phases: Phases,
    /// Time of maximum dynamic pressure (`summary.json`), for the default frames.
    pub max_q: Option<f64>,
    /// Time of burnout (`summary.json`), for the default frames.
    pub burnout: Option<f64>,
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

    /// Write `out/index.html` with `title`, the `lead` (HTML, see
    /// [`super::index::lead_html`]) and `facts`; adds it to `files`.
    pub fn write_index(
        &mut self,
        out: &Path,
        title: &str,
        lead: &str,
        facts: &[(String, String)],
    ) -> Result<PathBuf, ReportError> {
        let path = out.join("index.html");
        std::fs::write(&path, index_html(title, lead, facts, &self.entries)).map_err(|e| {
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
        let mut f = super::figures::flutter_margin(m, options.criterion.unwrap_or(1.15));
        if let Ok(p) = &mut f.plot {
            p.markers = options.events.clone();
        }
        figures.push(f);
    }
    let t = h.time();
    let span = (
        t.first().copied().unwrap_or(0.0),
        t.last().copied().unwrap_or(0.0),
    );
    for fig in figures {
        match &fig.plot {
            // The ground track is not a time plot.
            Ok(plot) if fig.stem == "ground_track" => {
                let files = save_svg_png(plot, &out.join(&fig.stem), FIGURE_SIZE)?;
                report.push_drawn(fig.caption.clone(), files);
            }
            Ok(plot) => {
                for (stem, caption, p) in split_phases(&fig, plot, &options.phases, span) {
                    match p {
                        Ok(p) => {
                            let files = save_svg_png(&p, &out.join(&stem), FIGURE_SIZE)?;
                            report.push_drawn(caption, files);
                        }
                        Err(reason) => report.push_skipped(caption, reason),
                    }
                }
            }
            Err(reason) => report.push_skipped(fig.caption.clone(), reason.clone()),
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
    let (times, whats): (Vec<f64>, Vec<String>) = if options.frame_times.is_empty() {
        let d = default_frame_times(h, options.max_q, options.burnout);
        if d.is_empty() {
            frame_times(h, &[], DEFAULT_FRAMES)
                .into_iter()
                .map(|t| (t, String::new()))
                .unzip()
        } else {
            d.into_iter().unzip()
        }
    } else {
        options
            .frame_times
            .iter()
            .map(|t| (*t, String::new()))
            .unzip()
    };
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
    for (k, ((t, eta), what)) in times.iter().zip(etas).zip(&whats).enumerate() {
        let at = if what.is_empty() {
            String::new()
        } else {
            format!(" ({what})")
        };
        let frame = DeformationFrame {
            geometry: mesh,
            eta,
            t: *t,
            magnify,
            title: format!("Deformed mesh at t = {t:.4} s{at} (displacements x {magnify:.3e})"),
        };
        let files = save_svg_png(
            &frame,
            &out.join(format!("frame_{:02}", k + 1)),
            (1200, 600),
        )?;
        report.push_drawn(
            format!(
                "Deformed FE mesh at t = {t:.4} s{at}, front and isometric views, displacements magnified x {magnify:.3e}"
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

    fn plot_0_to_100() -> TimePlot {
        let t: Vec<f64> = (0..=1000).map(|k| k as f64 * 0.1).collect();
        TimePlot {
            title: "x".into(),
            series: vec![Series {
                label: "a".into(),
                ys: t.clone(),
                xs: t,
            }],
            ..TimePlot::default()
        }
    }

    fn fig(stem: &str) -> PlannedFigure {
        PlannedFigure {
            stem: stem.into(),
            caption: "c".into(),
            plot: Err(String::new()),
        }
    }

    /// The ascent runs to apogee + max(5 %, 1 s) on its own axis, the descent from apogee;
    /// figures meaningless under canopies stop at the first deployment; without apogee (or
    /// when the history ends first) one axis.
    #[test]
    fn phases_split_the_time_axis() {
        let p = plot_0_to_100();
        let phases = Phases {
            apogee: Some(40.0),
            first_deployment: Some(41.0),
        };
        let parts = split_phases(&fig("mach"), &p, &phases, (0.0, 100.0));
        let stems: Vec<&str> = parts.iter().map(|x| x.0.as_str()).collect();
        assert_eq!(stems, ["mach", "mach_descent"]);
        let range = |r: &Result<TimePlot, String>| {
            let xs = &r.as_ref().unwrap().series[0].xs;
            (xs[0], *xs.last().unwrap())
        };
        assert_eq!(range(&parts[0].2), (0.0, 42.0));
        assert_eq!(range(&parts[1].2), (40.0, 100.0));
        let parts = split_phases(&fig("alpha"), &p, &phases, (0.0, 100.0));
        assert_eq!(range(&parts[0].2), (0.0, 41.0));
        // 40 to 41 s: the descent before the canopy.
        assert_eq!(range(&parts[1].2), (40.0, 41.0));
        let at_apogee = Phases {
            apogee: Some(40.0),
            first_deployment: Some(40.0),
        };
        let parts = split_phases(&fig("attitude"), &p, &at_apogee, (0.0, 100.0));
        assert!(parts[1].2.as_ref().unwrap_err().contains("canopies"));
        // Short apogee: at least one second past it.
        assert_eq!(
            Phases {
                apogee: Some(4.0),
                first_deployment: None
            }
            .ascent_end(0.0, 100.0),
            Some(5.0)
        );
        for phases in [
            Phases::default(),
            Phases {
                apogee: Some(99.5),
                first_deployment: None,
            },
        ] {
            let parts = split_phases(&fig("mach"), &p, &phases, (0.0, 100.0));
            assert_eq!(parts.len(), 1);
            assert_eq!(range(&parts[0].2), (0.0, 100.0));
        }
    }

    /// Default frames: max q, burnout and the largest deformation, in time order, with
    /// coinciding times merged; none of them: the evenly spaced fallback.
    #[test]
    fn default_frames_are_at_max_q_burnout_and_largest_deformation() {
        let h = parse_history(
            "t,dynamic_pressure,max_deformation\n0,0,0\n1,5,0.1\n2,9,0.3\n3,4,0.2\n",
            Path::new("h"),
        )
        .unwrap();
        assert_eq!(
            default_frame_times(&h, None, Some(1.5)),
            vec![
                (1.5, "burnout".to_string()),
                (2.0, "max q, largest deformation".to_string())
            ]
        );
        assert_eq!(
            default_frame_times(&h, Some(2.2), None),
            vec![
                (2.0, "largest deformation".to_string()),
                (2.2, "max q".to_string())
            ]
        );
        let bare = parse_history("t,a\n0,0\n1,0\n", Path::new("h")).unwrap();
        assert!(default_frame_times(&bare, None, None).is_empty());
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

/// The condition and flutter point of a flutter solution, from its `flutter.json`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlutterCondition {
    pub mach: Option<f64>,
    pub altitude_m: Option<f64>,
    pub fin_thickness_m: Option<f64>,
    /// The first (lowest-speed) flutter point: speed (m/s), frequency (Hz), branch name.
    pub flutter: Option<(f64, f64, String)>,
}

impl FlutterCondition {
    /// From `flutter.json` (`analyze flutter --out`); absent keys stay `None`.
    pub fn from_json(v: &serde_json::Value) -> Self {
        let f = &v["flutter"][0];
        FlutterCondition {
            mach: v["mach"].as_f64(),
            altitude_m: v["altitude_m"].as_f64(),
            fin_thickness_m: v["fin_thickness_m"].as_f64(),
            flutter: match (f["speed_m_s"].as_f64(), f["frequency_hz"].as_f64()) {
                (Some(speed), Some(hz)) => Some((
                    speed,
                    hz,
                    f["mode"].as_str().unwrap_or_default().to_string(),
                )),
                _ => None,
            },
        }
    }

    /// The condition for a title: `Mach 2, 5000 m, fin 1.00 mm` (the parts known).
    pub fn text(&self) -> String {
        let mut parts = Vec::new();
        if let Some(m) = self.mach {
            parts.push(format!("Mach {m:.3}"));
        }
        if let Some(h) = self.altitude_m {
            parts.push(format!("{h:.0} m"));
        }
        if let Some(t) = self.fin_thickness_m {
            parts.push(format!("fin {:.3} mm", t * 1e3));
        }
        parts.join(", ")
    }
}

/// The V-g and V-f diagrams of a flutter solution; titles carry the condition and the
/// flutter point is marked (at g = 0 on V-g, at its frequency on V-f).
pub fn flutter_figures(
    branches: &[VgBranch],
    condition: &FlutterCondition,
    out: &Path,
    report: &mut ReportOutput,
) -> Result<(), ReportError> {
    use super::plot::MarkedPoint;
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
    let cond = condition.text();
    let point = |on_g: bool| -> Vec<MarkedPoint> {
        condition
            .flutter
            .iter()
            .map(|(v, hz, name)| MarkedPoint {
                x: *v,
                y: if on_g { 0.0 } else { *hz },
                label: format!(
                    "flutter: {v:.1} m/s, {hz:.2} Hz{}",
                    if name.is_empty() {
                        String::new()
                    } else {
                        format!(" ({name})")
                    }
                ),
            })
            .collect()
    };
    for (stem, name, caption, y_label, s, on_g) in [
        (
            "vg",
            "V-g",
            "V-g: damping g = 2 Re(p)/Im(p) of each branch against speed (flutter where g crosses 0)",
            "g",
            series(|b| &b.g),
            true,
        ),
        (
            "vf",
            "V-f",
            "V-f: frequency of each branch against speed",
            "frequency (Hz)",
            series(|b| &b.f),
            false,
        ),
    ] {
        let title = if cond.is_empty() {
            name.to_string()
        } else {
            format!("{name}: {cond}")
        };
        let plot = TimePlot {
            title: title.clone(),
            x_label: "V (m/s)".to_string(),
            y_label: y_label.to_string(),
            series: s,
            points: point(on_g),
            ..TimePlot::default()
        };
        let files = save_svg_png(&plot, &out.join(stem), FIGURE_SIZE)?;
        let caption = if cond.is_empty() {
            caption.to_string()
        } else {
            format!("{caption}; {cond}")
        };
        report.push_drawn(caption, files);
    }
    Ok(())
}
