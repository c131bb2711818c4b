//! The report's `index.html`: the answer first (the flight's verdict, its flutter margin,
//! the flight's key figures and every warning, [`lead_html`]), then every figure (SVG
//! shown, PNG linked) with its caption, and the figures that were skipped with the reason.

use serde_json::Value;

/// One entry of the index.
#[derive(Clone, Debug, PartialEq)]
pub struct IndexEntry {
    /// Caption under the figure (or of the skipped figure).
    pub caption: String,
    /// File names relative to the report directory (`x.svg`, `x.png`); `Err(reason)` for
    /// a figure that was not drawn.
    pub files: Result<(String, String), String>,
}

/// Escape text for HTML.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The stop reasons of a run that ended as planned (`summary.json`'s `stop_reason`): the
/// stop time, or the ground. Any other ends the flight early and the page says so.
pub const NORMAL_STOPS: [&str; 2] = ["completed", "ground"];

fn num(v: &Value) -> Option<f64> {
    v.as_f64().filter(|x| x.is_finite())
}

/// `t = 1.234 s, Mach 0.91, 1234 m` from an object with `t`, `mach`, `altitude` (the parts
/// present).
fn where_when(v: &Value) -> String {
    let mut parts = Vec::new();
    if let Some(t) = num(&v["t"]) {
        parts.push(format!("t = {t:.3} s"));
    }
    if let Some(m) = num(&v["mach"]) {
        parts.push(format!("Mach {m:.3}"));
    }
    if let Some(h) = num(&v["altitude"]) {
        parts.push(format!("altitude {h:.0} m"));
    }
    parts.join(", ")
}

/// How the page judges a run: `bad` (a verdict, a margin not met, an early stop), `good`
/// (margin met, normal stop), `unknown` otherwise.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    Good,
    Bad,
    Unknown,
}

/// The verdict lines of a run's `summary.json`, most important first, and the outcome.
/// Reads every key defensively: `verdict`, `warnings` and the new `flutter_margin` keys
/// may be absent or null (summaries written before them).
pub fn verdict_lines(summary: &Value) -> (Outcome, Vec<String>) {
    let mut lines = Vec::new();
    let mut bad = false;
    let mut good = false;
    let v = &summary["verdict"];
    if v.is_object() {
        bad = true;
        let kind = v["kind"].as_str().unwrap_or("verdict");
        let what = match kind {
            "flutter" => "FLUTTER".to_string(),
            "divergence" => "DIVERGENCE".to_string(),
            "model_limit" => "MODEL LIMIT reached".to_string(),
            other => other.to_uppercase(),
        };
        let mut s = format!("{what} at {}", where_when(v));
        if let Some(q) = num(&v["dynamic_pressure"]) {
            s.push_str(&format!(", q = {:.1} kPa", q / 1e3));
        }
        if let Some(a) = num(&v["airspeed"]) {
            s.push_str(&format!(", airspeed {a:.1} m/s"));
        }
        // `message` is the terminal's line: the same facts as the lines below, not repeated.
        lines.push(s);
        if let Some(c) = v["criterion"].as_str() {
            lines.push(format!("criterion: {c}"));
        }
        if let Some(modes) = v["modes"].as_array() {
            for m in modes {
                let mut s = format!("mode {}", m["name"].as_str().unwrap_or("?"));
                if let Some(g) = num(&m["growth_rate"]) {
                    s.push_str(&format!(", growth rate {g:.4} 1/s"));
                }
                if let Some(f) = num(&m["frequency_hz"]) {
                    s.push_str(&format!(", {f:.2} Hz"));
                }
                lines.push(s);
            }
        }
    }
    let fm = &summary["flutter_margin"];
    if fm.is_object() {
        if fm["computed"] == Value::Bool(false) {
            lines.push(format!(
                "Flutter margin not computed: {}",
                fm["reason"].as_str().unwrap_or("no reason given")
            ));
        } else {
            let crit = num(&fm["criterion_speed_margin"]).unwrap_or(1.15);
            let min = &fm["minimum"];
            let min_text = match num(&min["speed_margin"]) {
                Some(m) => format!("min V_F/V = {m:.3} at {}", where_when(min)),
                None => "no row with airspeed".to_string(),
            };
            match fm["meets_criterion"].as_bool() {
                Some(true) if !bad => {
                    good = true;
                    lines.push(format!(
                        "Flutter margin met: {min_text} (criterion V_F/V >= {crit})"
                    ));
                }
                Some(_) => {
                    bad = true;
                    lines.push(format!(
                        "Flutter margin NOT met: {min_text} (criterion V_F/V >= {crit})"
                    ));
                }
                None => lines.push(format!("Flutter margin undecided: {min_text}")),
            }
            for (key, what) in [
                ("first_violation", "first violation of the criterion"),
                ("first_below_one", "first V_F/V below 1"),
            ] {
                let p = &fm[key];
                if p.is_object() {
                    let m = num(&p["margin"])
                        .map(|m| format!(" (V_F/V = {m:.3})"))
                        .unwrap_or_default();
                    lines.push(format!("{what} at {}{m}", where_when(p)));
                }
            }
            for (key, what) in [
                ("time_below_criterion_s", "time below the criterion"),
                ("time_below_one_s", "time below V_F/V = 1"),
            ] {
                if let Some(s) = num(&fm[key]).filter(|s| *s > 0.0) {
                    lines.push(format!("{what}: {s:.3} s"));
                }
            }
            if let Some(story) = fm["story"].as_str() {
                lines.push(story.to_string());
            }
        }
    }
    if let Some(stop) = summary["stop_reason"].as_str() {
        if !NORMAL_STOPS.contains(&stop) {
            bad = true;
            let detail = summary["stop_detail"]
                .as_str()
                .map(|d| format!(" ({d})"))
                .unwrap_or_default();
            let at = num(&summary["t_end"])
                .map(|t| format!(" at t = {t:.3} s"))
                .unwrap_or_default();
            lines.push(format!(
                "The flight stopped early: stop reason `{stop}`{detail}{at}"
            ));
        }
    }
    let outcome = if bad {
        Outcome::Bad
    } else if good {
        Outcome::Good
    } else {
        Outcome::Unknown
    };
    (outcome, lines)
}

/// The flight's key figures from `summary.json`'s `flight` (absent ones left out): stop
/// reason, apogee, max Mach, max q, off-rail speed, burnout, landing, static margin.
pub fn flight_facts(summary: &Value) -> Vec<(String, String)> {
    let f = &summary["flight"];
    let mut out = Vec::new();
    if let Some(s) = summary["stop_reason"].as_str() {
        let end = num(&summary["t_end"])
            .map(|t| format!(" at t = {t:.3} s"))
            .unwrap_or_default();
        out.push(("stop reason".to_string(), format!("{s}{end}")));
    }
    let ap = &f["apogee"];
    if let (Some(h), Some(t)) = (num(&ap["altitude"]).or(num(&ap["height"])), num(&ap["t"])) {
        let above = num(&ap["height"])
            .filter(|g| ap["altitude"].is_number() && *g != h)
            .map(|g| format!(" ({g:.1} m above the ground)"))
            .unwrap_or_default();
        out.push((
            "apogee".to_string(),
            format!("{h:.1} m{above} at t = {t:.3} s"),
        ));
    }
    let vt = |v: &Value, unit: &str, scale: f64, digits: usize| -> Option<String> {
        let x = num(&v["value"])? * scale;
        let t = num(&v["t"])
            .map(|t| format!(" at t = {t:.3} s"))
            .unwrap_or_default();
        Some(format!("{x:.digits$}{unit}{t}"))
    };
    if let Some(s) = vt(&f["max_mach"], "", 1.0, 3) {
        out.push(("max Mach".to_string(), s));
    }
    if let Some(s) = vt(&f["max_dynamic_pressure"], " kPa", 1e-3, 2) {
        out.push(("max dynamic pressure".to_string(), s));
    }
    if let Some(v) = num(&f["off_rail_speed"]) {
        out.push(("off-rail speed".to_string(), format!("{v:.2} m/s")));
    }
    let b = &f["burnout"];
    if let Some(t) = num(&b["t"]) {
        let v = num(&b["speed"])
            .map(|v| format!(", {v:.1} m/s"))
            .unwrap_or_default();
        let h = num(&b["altitude"])
            .map(|h| format!(", altitude {h:.0} m"))
            .unwrap_or_default();
        out.push(("burnout".to_string(), format!("t = {t:.3} s{v}{h}")));
    }
    if let Some(d) = f["deployments"].as_array() {
        for dep in d {
            if let Some(t) = num(&dep["deployment"]["t"]) {
                out.push((
                    format!(
                        "{} deploys",
                        dep["name"].as_str().unwrap_or("recovery device")
                    ),
                    format!("t = {t:.3} s"),
                ));
            }
        }
    }
    let l = &f["landing"];
    if let Some(t) = num(&l["t"]) {
        let r = num(&l["ground_range"])
            .map(|r| format!(", {r:.1} m from the pad"))
            .unwrap_or_default();
        let v = num(&l["speed"])
            .map(|v| format!(", {v:.2} m/s"))
            .unwrap_or_default();
        out.push(("landing".to_string(), format!("t = {t:.3} s{r}{v}")));
    }
    let sm = &f["static_margin_calibres"];
    let mut parts = Vec::new();
    if let Some(m) = num(&sm["min"]["value"]) {
        let t = num(&sm["min"]["t"])
            .map(|t| format!(" (t = {t:.3} s)"))
            .unwrap_or_default();
        parts.push(format!("min {m:.2}{t}"));
    }
    if let Some(m) = num(&sm["at_rail_exit"]) {
        parts.push(format!("{m:.2} at rail exit"));
    }
    if let Some(m) = num(&sm["at_max_q"]) {
        parts.push(format!("{m:.2} at max q"));
    }
    if !parts.is_empty() {
        out.push((
            "static margin (cal, rail exit to apogee)".to_string(),
            parts.join(", "),
        ));
    }
    out
}

/// Every warning of a run: `summary.json`'s `warnings` (`code`, `message`, optional
/// `file`, `line`, `column`), the flutter margin's untrusted rows, then `extra` (the
/// report's own warnings).
pub fn warning_lines(summary: &Value, extra: &[String]) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(ws) = summary["warnings"].as_array() {
        for w in ws {
            let mut s = String::new();
            if let Some(c) = w["code"].as_str() {
                s.push_str(&format!("warning[{c}]: "));
            }
            if let Some(f) = w["file"].as_str() {
                s.push_str(f);
                for k in ["line", "column"] {
                    if let Some(n) = w[k].as_u64() {
                        s.push_str(&format!(":{n}"));
                    }
                }
                s.push_str(": ");
            }
            s.push_str(w["message"].as_str().unwrap_or(""));
            out.push(s);
        }
    }
    let fm = &summary["flutter_margin"];
    for (key, what) in [
        (
            "transonic_rows",
            "flutter margin rows in the transonic band (bridged aerodynamic matrices: margin counted divided by 1 + its stated uncertainty)",
        ),
        (
            "outside_grid_rows",
            "flutter margin rows outside the boundary's grid (untrusted)",
        ),
        (
            "upper_bound_rows",
            "flutter margin rows using a node already unstable at its lowest speed (V_F at most the value)",
        ),
        (
            "raised_start_rows",
            "flutter margin rows using a node whose p-k sweep starts higher",
        ),
    ] {
        if let Some(n) = fm[key].as_u64().filter(|n| *n > 0) {
            out.push(format!("{n} {what}"));
        }
    }
    out.extend(extra.iter().cloned());
    out
}

/// The head of a run's page, above the figures: the verdict, the flight's key figures,
/// every warning (the summary's and the report's own `warnings`) and the report's `notes`
/// (all text escaped).
pub fn lead_html(summary: &Value, warnings: &[String], notes: &[String]) -> String {
    let (outcome, verdict) = verdict_lines(summary);
    let class = match outcome {
        Outcome::Good => "good",
        Outcome::Bad => "bad",
        Outcome::Unknown => "unknown",
    };
    let mut s = format!("<section id=\"verdict\" class=\"{class}\">\n<h2>Verdict</h2>\n");
    if verdict.is_empty() {
        s.push_str("<p>No verdict and no flutter margin in summary.json.</p>\n");
    } else {
        s.push_str(&format!(
            "<p class=\"headline\">{}</p>\n",
            escape(&verdict[0])
        ));
        if verdict.len() > 1 {
            s.push_str("<ul>\n");
            for l in &verdict[1..] {
                s.push_str(&format!("<li>{}</li>\n", escape(l)));
            }
            s.push_str("</ul>\n");
        }
    }
    s.push_str("</section>\n");
    let facts = flight_facts(summary);
    if !facts.is_empty() {
        s.push_str("<section id=\"flight\">\n<h2>Flight</h2>\n<table>\n");
        for (k, v) in facts {
            s.push_str(&format!(
                "<tr><td>{}</td><td>{}</td></tr>\n",
                escape(&k),
                escape(&v)
            ));
        }
        s.push_str("</table>\n</section>\n");
    }
    let warnings = warning_lines(summary, warnings);
    s.push_str(&format!(
        "<section id=\"warnings\">\n<h2>Warnings ({})</h2>\n",
        warnings.len()
    ));
    if warnings.is_empty() {
        s.push_str("<p>None.</p>\n");
    } else {
        s.push_str("<ul>\n");
        for w in warnings {
            s.push_str(&format!("<li>{}</li>\n", escape(&w)));
        }
        s.push_str("</ul>\n");
    }
    s.push_str("</section>\n");
    if !notes.is_empty() {
        s.push_str("<section id=\"notes\">\n<h2>Notes</h2>\n<ul>\n");
        for n in notes {
            s.push_str(&format!("<li>{}</li>\n", escape(n)));
        }
        s.push_str("</ul>\n</section>\n");
    }
    s
}

/// The page: a title, the lead (trusted HTML from [`lead_html`], or empty), a few
/// `(key, value)` facts about the run, then the figures.
pub fn index_html(
    title: &str,
    lead: &str,
    facts: &[(String, String)],
    entries: &[IndexEntry],
) -> String {
    let mut s = String::new();
    s.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    s.push_str(&format!("<title>{}</title>\n", escape(title)));
    s.push_str(
        "<style>body{font-family:sans-serif;max-width:1000px;margin:auto;padding:1em}\
         figure{margin:1.5em 0}img{max-width:100%;border:1px solid #ddd}\
         td{padding:0 1em 0 0}.skipped{color:#a33}\
         #verdict{padding:.5em 1em;border-left:6px solid #888}\
         #verdict.bad{border-color:#c00;background:#fee}\
         #verdict.good{border-color:#080;background:#efe}\
         .headline{font-size:1.3em;font-weight:bold}</style>\n</head>\n<body>\n",
    );
    s.push_str(&format!("<h1>{}</h1>\n", escape(title)));
    s.push_str(lead);
    if !facts.is_empty() {
        s.push_str("<table>\n");
        for (k, v) in facts {
            s.push_str(&format!(
                "<tr><td>{}</td><td>{}</td></tr>\n",
                escape(k),
                escape(v)
            ));
        }
        s.push_str("</table>\n");
    }
    for (n, e) in entries.iter().enumerate() {
        match &e.files {
            Ok((svg, png)) => s.push_str(&format!(
                "<figure id=\"fig{k}\">\n<a href=\"{svg}\"><img src=\"{svg}\" alt=\"{cap}\"></a>\n\
                 <figcaption>Figure {k}. {cap} (<a href=\"{svg}\">SVG</a>, <a href=\"{png}\">PNG</a>)</figcaption>\n</figure>\n",
                k = n + 1,
                svg = escape(svg),
                png = escape(png),
                cap = escape(&e.caption)
            )),
            Err(reason) => s.push_str(&format!(
                "<p class=\"skipped\">Skipped: {}: {}</p>\n",
                escape(&e.caption),
                escape(reason)
            )),
        }
    }
    s.push_str(LOAD_CHECK);
    s.push_str("</body>\n</html>\n");
    s
}

/// The page's last element: once the page has loaded, says on the page which figures
/// failed to load (a moved or missing file) and records the counts on `<body>`
/// (`data-figures-loaded`, `data-figures-failed`) for a headless browser's DOM dump.
pub const LOAD_CHECK: &str = r#"<p id="load-check"></p>
<script>
window.addEventListener("load", function () {
  var bad = [];
  for (var i = 0; i < document.images.length; i++) {
    var im = document.images[i];
    if (!im.complete || im.naturalWidth === 0) { bad.push(im.getAttribute("src")); }
  }
  document.body.setAttribute("data-figures-loaded", String(document.images.length - bad.length));
  document.body.setAttribute("data-figures-failed", String(bad.length));
  if (bad.length > 0) {
    var p = document.getElementById("load-check");
    p.className = "skipped";
    p.textContent = bad.length + " figure(s) failed to load: " + bad.join(", ");
  }
});
</script>
"#;

#[cfg(test)]
mod tests {
    use super::*;

    /// Verdict lines from summaries old and new: absent keys are no verdict, a met margin
    /// with a normal stop is good, an early stop is bad.
    #[test]
    fn verdicts_read_old_and_new_summaries() {
        let v = |s: &str| verdict_lines(&serde_json::from_str(s).unwrap());
        assert_eq!(v("{}"), (Outcome::Unknown, vec![]));
        let (o, l) = v(
            r#"{"stop_reason": "ground", "verdict": null, "flutter_margin":
            {"computed": true, "meets_criterion": true,
             "minimum": {"speed_margin": 1.5, "t": 2, "mach": 0.7, "altitude": 500},
             "first_violation": null}}"#,
        );
        assert_eq!(o, Outcome::Good);
        assert_eq!(
            l,
            [
                "Flutter margin met: min V_F/V = 1.500 at t = 2.000 s, Mach 0.700, altitude 500 m (criterion V_F/V >= 1.15)"
            ]
        );
        let (o, l) = v(
            r#"{"stop_reason": "max_deformation", "stop_detail": "3 m", "t_end": 4,
            "flutter_margin": {"computed": false, "reason": "no fins"}}"#,
        );
        assert_eq!(o, Outcome::Bad);
        assert_eq!(l[0], "Flutter margin not computed: no fins");
        assert_eq!(
            l[1],
            "The flight stopped early: stop reason `max_deformation` (3 m) at t = 4.000 s"
        );
        let html = lead_html(
            &serde_json::json!({"warnings": [{"code": "a::b", "message": "<x>"}]}),
            &["note & more".to_string()],
            &["magnified".to_string()],
        );
        assert!(
            html.contains("<h2>Notes</h2>\n<ul>\n<li>magnified</li>"),
            "{html}"
        );
        assert!(html.contains("<li>warning[a::b]: &lt;x&gt;</li>"), "{html}");
        assert!(html.contains("<li>note &amp; more</li>"), "{html}");
        assert!(html.contains("Warnings (2)"));
    }

    #[test]
    fn links_and_skips() {
        let html = index_html(
            "Run <a>",
            "",
            &[("stop".into(), "ground".into())],
            &[
                IndexEntry {
                    caption: "Mach number".into(),
                    files: Ok(("mach.svg".into(), "mach.png".into())),
                },
                IndexEntry {
                    caption: "Fin aerodynamic forces".into(),
                    files: Err("no columns".into()),
                },
            ],
        );
        assert!(html.contains("<title>Run &lt;a&gt;</title>"));
        assert!(html.contains("<img src=\"mach.svg\""));
        assert!(html.contains("href=\"mach.png\""));
        assert!(html.contains("Skipped: Fin aerodynamic forces: no columns"));
    }
}
