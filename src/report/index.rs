//! The report's `index.html`: every figure (SVG shown, PNG linked) with its caption, and
//! the figures that were skipped with the reason.

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

/// The page: a title, a few `(key, value)` facts about the run, then the figures.
pub fn index_html(title: &str, facts: &[(String, String)], entries: &[IndexEntry]) -> String {
    let mut s = String::new();
    s.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    s.push_str(&format!("<title>{}</title>\n", escape(title)));
    s.push_str(
        "<style>body{font-family:sans-serif;max-width:1000px;margin:auto;padding:1em}\
         figure{margin:1.5em 0}img{max-width:100%;border:1px solid #ddd}\
         td{padding:0 1em 0 0}.skipped{color:#a33}</style>\n</head>\n<body>\n",
    );
    s.push_str(&format!("<h1>{}</h1>\n", escape(title)));
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
    s.push_str("</body>\n</html>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn links_and_skips() {
        let html = index_html(
            "Run <a>",
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
