//! Diagnostics: the one place where spans become miette reports.
//!
//! Every stage produces [`Diagnostic`] values (plain data: a stable code, a message, labelled
//! spans, an optional help). This module renders them with miette's graphical handler (used
//! by the binary and, with a fixed theme and width, by the snapshot tests) or as JSON for
//! `--format json`. The library never installs a global miette hook.

use std::fmt;

use miette::{GraphicalReportHandler, GraphicalTheme, LabeledSpan, NamedSource, SourceSpan};
use serde::Serialize;

use crate::syntax::{SourceMap, Span};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Error,
    Warning,
}

/// A labelled span: where, and what to say there.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Label {
    pub span: Span,
    pub message: String,
}

/// One diagnostic. The first label is the primary location.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Diagnostic {
    /// Stable code, e.g. `vdl::unit::mismatch`. Documented in the README; never renamed.
    pub code: &'static str,
    pub severity: Severity,
    pub message: String,
    pub labels: Vec<Label>,
    pub help: Option<String>,
}

impl Diagnostic {
    pub fn error(code: &'static str, message: impl Into<String>) -> Self {
        Diagnostic {
            code,
            severity: Severity::Error,
            message: message.into(),
            labels: Vec::new(),
            help: None,
        }
    }

    pub fn warning(code: &'static str, message: impl Into<String>) -> Self {
        Diagnostic {
            severity: Severity::Warning,
            ..Diagnostic::error(code, message)
        }
    }

    pub fn label(mut self, span: Span, message: impl Into<String>) -> Self {
        self.labels.push(Label {
            span,
            message: message.into(),
        });
        self
    }

    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    pub fn primary_span(&self) -> Option<Span> {
        self.labels.first().map(|l| l.span)
    }

    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// A diagnostic bound to its sources, implementing `miette::Diagnostic`. Labels in the
/// primary file are shown on its snippet; labels in other files become related reports.
struct Bound<'a> {
    diag: &'a Diagnostic,
    sources: &'a SourceMap,
    /// Which labels this report shows (indices into `diag.labels`).
    labels: Vec<usize>,
    source: Option<NamedSource<String>>,
    related: Vec<Bound<'a>>,
    /// A related report carries only a label, no message of its own.
    is_related: bool,
}

impl<'a> Bound<'a> {
    fn new(diag: &'a Diagnostic, sources: &'a SourceMap) -> Self {
        let primary_file = diag.primary_span().map(|s| s.file);
        let mut labels = Vec::new();
        let mut others: Vec<usize> = Vec::new();
        for (k, l) in diag.labels.iter().enumerate() {
            if Some(l.span.file) == primary_file {
                labels.push(k);
            } else {
                others.push(k);
            }
        }
        let source = primary_file
            .and_then(|f| sources.get(f))
            .map(|f| NamedSource::new(f.name.clone(), f.text.to_string()).with_language("vdl"));
        let related = others
            .into_iter()
            .map(|k| {
                let f = sources.get(diag.labels[k].span.file);
                Bound {
                    diag,
                    sources,
                    labels: vec![k],
                    source: f.map(|f| NamedSource::new(f.name.clone(), f.text.to_string())),
                    related: Vec::new(),
                    is_related: true,
                }
            })
            .collect();
        Bound {
            diag,
            sources,
            labels,
            source,
            related,
            is_related: false,
        }
    }
}

impl fmt::Debug for Bound<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.diag.message)
    }
}

impl fmt::Display for Bound<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_related {
            let k = self.labels.first().copied().unwrap_or(0);
            match self.diag.labels.get(k) {
                Some(l) => f.write_str(&l.message),
                None => Ok(()),
            }
        } else {
            f.write_str(&self.diag.message)
        }
    }
}

impl std::error::Error for Bound<'_> {}

impl miette::Diagnostic for Bound<'_> {
    fn code<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        if self.is_related {
            None
        } else {
            Some(Box::new(self.diag.code))
        }
    }

    fn severity(&self) -> Option<miette::Severity> {
        Some(match self.diag.severity {
            Severity::Error => miette::Severity::Error,
            Severity::Warning => miette::Severity::Warning,
        })
    }

    fn help<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        if self.is_related {
            return None;
        }
        self.diag
            .help
            .as_ref()
            .map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        self.source.as_ref().map(|s| s as &dyn miette::SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        self.source.as_ref()?;
        let it = self.labels.iter().enumerate().map(move |(n, &k)| {
            let l = &self.diag.labels[k];
            let mut start = l.span.start as usize;
            // miette draws no label at the very end of the text ("found end of file"):
            // point at the last character instead, so the location is still shown.
            if l.span.is_empty() {
                if let Some(text) = self.sources.get(l.span.file).map(|f| f.text.as_ref()) {
                    if start >= text.len() {
                        // Just after the last visible character (on the final line
                        // break if there is one, else on that character itself).
                        let visible = text.trim_end_matches(['\n', '\r']).len();
                        start = if visible < text.len() {
                            visible
                        } else {
                            visible.saturating_sub(1)
                        };
                        while !text.is_char_boundary(start) {
                            start -= 1;
                        }
                    }
                }
            }
            let span = SourceSpan::new(start.into(), l.span.len());
            let text = if l.message.is_empty() {
                None
            } else {
                Some(l.message.clone())
            };
            if n == 0 && !self.is_related {
                LabeledSpan::new_primary_with_span(text, span)
            } else {
                LabeledSpan::new_with_span(text, span)
            }
        });
        Some(Box::new(it))
    }

    fn related<'b>(&'b self) -> Option<Box<dyn Iterator<Item = &'b dyn miette::Diagnostic> + 'b>> {
        if self.related.is_empty() {
            return None;
        }
        Some(Box::new(
            self.related.iter().map(|r| r as &dyn miette::Diagnostic),
        ))
    }
}

/// How to draw reports.
#[derive(Clone, Copy, Debug)]
pub struct RenderOptions {
    pub width: usize,
    pub color: bool,
    pub unicode: bool,
}

impl RenderOptions {
    /// Fixed theme and width, for snapshot tests.
    pub fn plain(width: usize) -> Self {
        RenderOptions {
            width,
            color: false,
            unicode: true,
        }
    }
}

/// Render diagnostics with miette's graphical handler.
pub fn render(diags: &[Diagnostic], sources: &SourceMap, opts: RenderOptions) -> String {
    let theme = match (opts.unicode, opts.color) {
        (true, true) => GraphicalTheme::unicode(),
        (true, false) => GraphicalTheme::unicode_nocolor(),
        (false, true) => GraphicalTheme {
            characters: miette::ThemeCharacters::ascii(),
            ..GraphicalTheme::unicode()
        },
        (false, false) => GraphicalTheme::ascii(),
    };
    let handler = GraphicalReportHandler::new_themed(theme)
        .with_width(opts.width)
        .with_links(false)
        .with_urls(false);
    let mut out = String::new();
    for d in diags {
        let bound = Bound::new(d, sources);
        if handler.render_report(&mut out, &bound).is_err() {
            out.push_str(&format!("{}: {}\n", d.code, d.message));
        }
    }
    out
}

/// Machine-readable form of a diagnostic (for `--format json`).
#[derive(Debug, Serialize)]
pub struct JsonDiagnostic {
    pub code: &'static str,
    pub severity: Severity,
    pub message: String,
    pub file: Option<String>,
    pub line: Option<usize>,
    pub column: Option<usize>,
    pub labels: Vec<JsonLabel>,
    pub help: Option<String>,
}

#[derive(Debug, Serialize)]
pub struct JsonLabel {
    pub file: Option<String>,
    pub line: usize,
    pub column: usize,
    pub end_line: usize,
    pub end_column: usize,
    pub message: String,
}

pub fn to_json(diags: &[Diagnostic], sources: &SourceMap) -> Vec<JsonDiagnostic> {
    diags
        .iter()
        .map(|d| {
            let labels: Vec<JsonLabel> = d
                .labels
                .iter()
                .map(|l| {
                    let (line, column) = sources.line_col(l.span.file, l.span.start);
                    let (end_line, end_column) = sources.line_col(l.span.file, l.span.end);
                    JsonLabel {
                        file: sources.get(l.span.file).map(|f| f.name.clone()),
                        line,
                        column,
                        end_line,
                        end_column,
                        message: l.message.clone(),
                    }
                })
                .collect();
            JsonDiagnostic {
                code: d.code,
                severity: d.severity,
                message: d.message.clone(),
                file: labels.first().and_then(|l| l.file.clone()),
                line: labels.first().map(|l| l.line),
                column: labels.first().map(|l| l.column),
                labels,
                help: d.help.clone(),
            }
        })
        .collect()
}

/// Levenshtein distance, for "did you mean" suggestions.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0; b.len() + 1];
    for (i, ca) in a.chars().enumerate() {
        cur[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            cur[j + 1] = sub.min(prev[j + 1] + 1).min(cur[j] + 1);
        }
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

/// The closest candidate within a distance that scales with the word's length.
pub fn did_you_mean<'a>(
    word: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    let limit = (word.chars().count() / 3).max(1) + 1;
    candidates
        .into_iter()
        .map(|c| (edit_distance(&word.to_lowercase(), &c.to_lowercase()), c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, c)| (*d, *c))
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions() {
        assert_eq!(
            did_you_mean("thicknes", ["thickness", "span"]),
            Some("thickness")
        );
        assert_eq!(did_you_mean("zzz", ["thickness", "span"]), None);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }
}
