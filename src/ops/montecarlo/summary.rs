//! `statistics.json` and `statistics.txt` from the rows of `samples.csv` (so a merge of
//! shards gives the same statistics as one run of all the samples).

use std::fmt::Write as _;

use serde_json::json;

use super::runner::Manifest;
use crate::analysis::montecarlo::stats::{distribution, ellipses, proportion, spearman};

/// The speed-margin criterion of the flutter margin (`analysis::flutter::margin`).
pub const CRITERION: f64 = crate::analysis::flutter::margin::CRITERION;

/// The outputs whose distributions are reported: column, label, unit.
pub const REPORTED: &[(&str, &str, &str)] = &[
    ("apogee_m", "apogee", "m"),
    ("max_mach", "max Mach", ""),
    ("max_q_pa", "max q", "Pa"),
    ("off_rail_speed_m_s", "off-rail speed", "m/s"),
    ("min_static_margin_cal", "min static margin", "cal"),
    ("flutter_margin_min", "min flutter margin V_F/V", ""),
];

fn column(manifest: &Manifest, rows: &[Vec<String>], name: &str) -> Vec<f64> {
    let Some(c) = manifest.columns.iter().position(|h| h == name) else {
        return vec![f64::NAN; rows.len()];
    };
    rows.iter()
        .map(|r| {
            r.get(c)
                .and_then(|s| s.parse::<f64>().ok())
                .unwrap_or(f64::NAN)
        })
        .collect()
}

fn text_column<'r>(manifest: &Manifest, rows: &'r [Vec<String>], name: &str) -> Vec<&'r str> {
    let c = manifest.columns.iter().position(|h| h == name);
    rows.iter()
        .map(|r| c.and_then(|c| r.get(c)).map_or("", String::as_str))
        .collect()
}

/// The statistics of the rows (module [`crate::analysis::montecarlo::stats`] for the methods).
pub fn statistics(manifest: &Manifest, rows: &[Vec<String>]) -> serde_json::Value {
    let status = text_column(manifest, rows, "status");
    let ok: Vec<usize> = (0..rows.len()).filter(|&k| status[k] == "ok").collect();
    let ok_rows: Vec<Vec<String>> = ok.iter().map(|&k| rows[k].clone()).collect();
    let verdicts = text_column(manifest, &ok_rows, "verdict");
    let ids_where = |want: &dyn Fn(&str) -> bool| -> Vec<&str> {
        (0..rows.len())
            .filter(|&k| want(status[k]))
            .filter_map(|k| rows[k].get(1).map(String::as_str))
            .collect()
    };
    // `incomplete`: flown, but the integration failed before the flight reached a stop of
    // its scenario (a flight cut short: out of the statistics); `failed`: not flown.
    let incomplete = ids_where(&|s| s == "incomplete");
    let failed = ids_where(&|s| s != "ok" && s != "incomplete");
    let mut outputs = serde_json::Map::new();
    for (col, _, unit) in REPORTED {
        let v = column(manifest, &ok_rows, col);
        outputs.insert(
            (*col).to_string(),
            json!({ "unit": unit, "distribution": distribution(&v) }),
        );
    }
    let lx = column(manifest, &ok_rows, "landing_x_m");
    let ly = column(manifest, &ok_rows, "landing_y_m");
    let points: Vec<(f64, f64)> = lx.iter().copied().zip(ly.iter().copied()).collect();
    let margin = column(manifest, &ok_rows, "flutter_margin_min");
    let with_margin = margin.iter().filter(|m| m.is_finite()).count();
    let below = margin
        .iter()
        .filter(|m| m.is_finite() && **m < CRITERION)
        .count();
    let flutter = verdicts.iter().filter(|v| **v == "flutter").count();
    let any_verdict: Vec<&str> = ok
        .iter()
        .zip(&verdicts)
        .filter(|(_, v)| !v.is_empty())
        .filter_map(|(&k, _)| rows[k].get(1).map(String::as_str))
        .collect();
    let sensitivity: Vec<serde_json::Value> = manifest
        .entries
        .iter()
        .enumerate()
        .map(|(j, e)| {
            let x = column(manifest, &ok_rows, &manifest.columns[2 + j]);
            json!({
                "input": e.path,
                "spearman_flutter_margin": spearman(&x, &margin),
                "spearman_apogee": spearman(&x, &column(manifest, &ok_rows, "apogee_m")),
            })
        })
        .collect();
    json!({
        "dispersion": manifest.dispersion,
        "scenario": manifest.scenario,
        "seed": manifest.seed,
        "samples": rows.len(),
        "succeeded": ok.len(),
        "failed": failed.len(),
        "failed_samples": failed,
        "incomplete": incomplete.len(),
        "incomplete_samples": incomplete,
        "outputs": outputs,
        "landing": {
            "frame": "inertial x and y of the landing point from the pad, m",
            "ellipses": ellipses(&points),
            "scaling": "k-sigma ellipse = Mahalanobis radius k of the sample covariance; holds 1 - exp(-k^2/2) of a bivariate normal (chi-square, 2 degrees of freedom)",
        },
        "flutter": {
            "criterion_speed_margin": CRITERION,
            "samples_with_margin": with_margin,
            "p_margin_below_criterion": proportion(below, with_margin),
            "p_flutter": proportion(flutter, ok.len()),
        },
        "verdict_samples": any_verdict,
        "sensitivity": {
            "method": "Spearman rank correlation of each drawn input with the output, over the samples that succeeded",
            "inputs": sensitivity,
        },
    })
}

/// The short text summary (`statistics.txt`).
pub fn text(manifest: &Manifest, s: &serde_json::Value) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "dispersion {} of scenario {}: {} samples (seed {}), {} succeeded, {} failed, {} incomplete",
        manifest.dispersion,
        manifest.scenario,
        s["samples"],
        manifest.seed,
        s["succeeded"],
        s["failed"],
        s["incomplete"]
    );
    if let Some(i) = &manifest.integrator {
        let _ = writeln!(t, "integrator: {i}");
    }
    let _ = writeln!(
        t,
        "{:<26} {:>12} {:>12} {:>12} {:>12} {:>12}   (95 % interval of the mean)",
        "output", "mean", "std", "p5", "p50", "p95"
    );
    for (col, label, unit) in REPORTED {
        let d = &s["outputs"][*col]["distribution"];
        if d.is_null() {
            let _ = writeln!(t, "{:<26} (no values)", label);
            continue;
        }
        let p = |q: usize| d["percentiles"][q]["value"].as_f64().unwrap_or(f64::NAN);
        let f = |x: f64| format!("{x:.4}");
        let name = if unit.is_empty() {
            (*label).to_string()
        } else {
            format!("{label} [{unit}]")
        };
        let _ = writeln!(
            t,
            "{:<26} {:>12} {:>12} {:>12} {:>12} {:>12}   [{}, {}]",
            name,
            f(d["mean"].as_f64().unwrap_or(f64::NAN)),
            f(d["std"].as_f64().unwrap_or(f64::NAN)),
            f(p(1)),
            f(p(3)),
            f(p(5)),
            f(d["mean_ci95"][0].as_f64().unwrap_or(f64::NAN)),
            f(d["mean_ci95"][1].as_f64().unwrap_or(f64::NAN)),
        );
    }
    let e = &s["landing"]["ellipses"];
    if !e.is_null() {
        let _ = writeln!(
            t,
            "landing: mean ({:.1}, {:.1}) m from the pad",
            e["mean"][0].as_f64().unwrap_or(f64::NAN),
            e["mean"][1].as_f64().unwrap_or(f64::NAN)
        );
        for el in e["ellipses"].as_array().into_iter().flatten() {
            let _ = writeln!(
                t,
                "  {}-sigma ellipse: semi-axes {:.1} m x {:.1} m at {:.1} deg, holds {:.1} % of the samples ({:.1} % expected of a normal)",
                el["k"],
                el["semi_major"].as_f64().unwrap_or(f64::NAN),
                el["semi_minor"].as_f64().unwrap_or(f64::NAN),
                el["angle"].as_f64().unwrap_or(f64::NAN).to_degrees(),
                100.0 * el["observed_share"].as_f64().unwrap_or(f64::NAN),
                100.0 * el["expected_share"].as_f64().unwrap_or(f64::NAN),
            );
        }
    }
    let fl = &s["flutter"];
    let pr = |p: &serde_json::Value| {
        format!(
            "{}/{} = {:.4} [{:.4}, {:.4}]",
            p["count"],
            p["of"],
            p["p"].as_f64().unwrap_or(f64::NAN),
            p["ci95"][0].as_f64().unwrap_or(f64::NAN),
            p["ci95"][1].as_f64().unwrap_or(f64::NAN)
        )
    };
    let _ = writeln!(
        t,
        "P(flutter margin < {CRITERION}): {} (Wilson 95 %)",
        pr(&fl["p_margin_below_criterion"])
    );
    let _ = writeln!(
        t,
        "P(flutter verdict): {} (Wilson 95 %)",
        pr(&fl["p_flutter"])
    );
    let vs = s["verdict_samples"].as_array().map_or(0, Vec::len);
    if vs > 0 {
        let _ = writeln!(
            t,
            "{vs} sample(s) ended in a verdict (statistics.json: verdict_samples)"
        );
    }
    let _ = writeln!(
        t,
        "sensitivity (Spearman rank correlation with the min flutter margin):"
    );
    for i in s["sensitivity"]["inputs"].as_array().into_iter().flatten() {
        let r = i["spearman_flutter_margin"].as_f64();
        let _ = writeln!(
            t,
            "  {:<32} {}",
            i["input"].as_str().unwrap_or_default(),
            r.map_or("-".to_string(), |r| format!("{r:+.3}"))
        );
    }
    t
}

/// The figures of a dispersion in `out/figures/` (SVG and PNG, module
/// [`crate::report::montecarlo`]): `landing` (points and 1/2/3-sigma ellipses, east to the
/// right and north up), `apogee`
/// and `flutter_margin` (histograms), `sensitivity_flutter_margin` and
/// `sensitivity_apogee` (Spearman bars); a figure without data is not drawn. Returns the
/// files written.
pub fn write_figures(
    out: &std::path::Path,
    manifest: &Manifest,
    rows: &[Vec<String>],
    stats: &serde_json::Value,
) -> Result<Vec<std::path::PathBuf>, crate::report::ReportError> {
    use crate::report::montecarlo::{Histogram, LandingPlot, SensitivityBars};
    use crate::report::plot::{FIGURE_SIZE, save_svg_png};
    let dir = out.join("figures");
    std::fs::create_dir_all(&dir).map_err(|e| crate::report::ReportError::Write {
        path: dir.clone(),
        message: e.to_string(),
    })?;
    let status = text_column(manifest, rows, "status");
    let ok_rows: Vec<Vec<String>> = rows
        .iter()
        .zip(&status)
        .filter(|(_, s)| **s == "ok")
        .map(|(r, _)| r.clone())
        .collect();
    let name = &manifest.dispersion;
    let mut written = Vec::new();
    let lx = column(manifest, &ok_rows, "landing_x_m");
    let ly = column(manifest, &ok_rows, "landing_y_m");
    // A map: east (inertial y) to the right, north (inertial x) up.
    let points: Vec<(f64, f64)> = ly
        .iter()
        .copied()
        .zip(lx.iter().copied())
        .filter(|(e, n)| e.is_finite() && n.is_finite())
        .collect();
    if !points.is_empty() {
        let fig = LandingPlot {
            title: format!("{name}: landing points and ellipses"),
            x_label: "east of the pad (m)".into(),
            y_label: "north of the pad (m)".into(),
            ellipses: ellipses(&points),
            points,
        };
        written.extend(save_svg_png(&fig, &dir.join("landing"), FIGURE_SIZE)?);
    }
    let apogee = column(manifest, &ok_rows, "apogee_m");
    if apogee.iter().any(|x| x.is_finite()) {
        let mean = stats["outputs"]["apogee_m"]["distribution"]["mean"].as_f64();
        let fig = Histogram {
            title: format!("{name}: apogee above the ground"),
            x_label: "apogee (m)".into(),
            values: apogee,
            markers: mean
                .map(|m| (m, format!("mean {m:.1} m")))
                .into_iter()
                .collect(),
        };
        written.extend(save_svg_png(&fig, &dir.join("apogee"), FIGURE_SIZE)?);
    }
    let margin = column(manifest, &ok_rows, "flutter_margin_min");
    let finite: Vec<f64> = margin.iter().copied().filter(|x| x.is_finite()).collect();
    if !finite.is_empty() {
        let (lo, hi) = finite
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        // The criterion is drawn when it does not squash the distribution to a sliver.
        let near = CRITERION >= lo - (hi - lo) && CRITERION <= hi + (hi - lo);
        let mut markers = Vec::new();
        if near {
            markers.push((CRITERION, format!("criterion {CRITERION}")));
        }
        if let Some(m) = stats["outputs"]["flutter_margin_min"]["distribution"]["mean"].as_f64() {
            markers.push((m, format!("mean {m:.3}")));
        }
        let below = if near {
            String::new()
        } else if lo > CRITERION {
            format!(" (all above the criterion {CRITERION})")
        } else {
            format!(" (criterion {CRITERION} off the axis)")
        };
        let fig = Histogram {
            title: format!("{name}: minimum flutter margin V_F/V{below}"),
            x_label: "min flutter margin V_F/V over the flight".into(),
            values: margin,
            markers,
        };
        written.extend(save_svg_png(
            &fig,
            &dir.join("flutter_margin"),
            FIGURE_SIZE,
        )?);
    }
    for (key, output, stem) in [
        (
            "spearman_flutter_margin",
            "min flutter margin",
            "sensitivity_flutter_margin",
        ),
        ("spearman_apogee", "apogee", "sensitivity_apogee"),
    ] {
        let bars: Vec<(String, Option<f64>)> = stats["sensitivity"]["inputs"]
            .as_array()
            .into_iter()
            .flatten()
            .map(|i| {
                (
                    i["input"].as_str().unwrap_or_default().to_string(),
                    i[key].as_f64(),
                )
            })
            .collect();
        if bars.iter().all(|b| b.1.is_none()) {
            continue;
        }
        let fig = SensitivityBars {
            title: format!("{name}: what drives the {output}"),
            x_label: format!("Spearman rank correlation with the {output}"),
            bars,
        };
        let h = (FIGURE_SIZE.1).max(140 + 40 * fig.bars.len() as u32);
        written.extend(save_svg_png(&fig, &dir.join(stem), (FIGURE_SIZE.0, h))?);
    }
    Ok(written)
}
