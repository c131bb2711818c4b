//! Quantities and ranges typed on the command line (`--thickness 0.3mm:1.2mm:10`,
//! `--mach 0.5:2.5:21`, `--altitude 5km`), checked exactly like values in a vehicle file:
//! each end is parsed by the language's value parser and converted by the checker's unit
//! reader ([`super::fields::quantity`], the unit table of [`crate::units`]), so a bare
//! number where a unit is needed is `vdl::unit::missing`, a unit of the wrong dimension
//! `vdl::unit::mismatch`, and so on. The text of each flag becomes a source named after the
//! flag (`<--thickness>`), so the diagnostics point at the column of the bad part.

use std::path::PathBuf;

use crate::diagnostics::Diagnostic;
use crate::syntax::ast::Value;
use crate::syntax::parser::parse_standalone_value;
use crate::syntax::{FileId, SourceMap, Span};
use crate::units::Dim;

use super::fields;
use super::{Cx, MemoryLoader, push_parse_errors_pub};

/// A checked `START:STOP:COUNT` range in SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuantityRange {
    pub start: f64,
    pub stop: f64,
    pub count: usize,
}

/// The diagnostics of a refused command-line value, with the sources they point into.
#[derive(Debug)]
pub struct CliValueError {
    pub diagnostics: Vec<Diagnostic>,
    pub sources: SourceMap,
}

/// The most points one range may ask for (a typo should not start a week-long map).
pub const MAX_RANGE_POINTS: usize = 100_000;

/// Text of the whole flag with everything outside `start..end` blanked, so that a part
/// parses with spans that are byte offsets into the whole flag.
fn isolate(text: &str, start: usize, end: usize) -> String {
    text.char_indices()
        .map(|(i, c)| if i >= start && i < end { c } else { ' ' })
        .collect()
}

fn value_at(cx: &mut Cx, file: FileId, text: &str, start: usize, end: usize) -> Option<Value> {
    if text[start..end].trim().is_empty() {
        cx.push(
            Diagnostic::error("analysis::range", "a value is missing here")
                .label(Span::new(file, start, end.max(start)), "empty"),
        );
        return None;
    }
    match parse_standalone_value(file, &isolate(text, start, end)) {
        Ok(v) => Some(v),
        Err(e) => {
            push_parse_errors_pub(cx, vec![e]);
            None
        }
    }
}

/// Checks several command-line values into one set of sources and diagnostics, so that
/// every refused part of every flag is reported together.
#[derive(Debug, Default)]
pub struct CliChecker {
    sources: SourceMap,
    diags: Vec<Diagnostic>,
}

impl CliChecker {
    pub fn new() -> Self {
        Self::default()
    }

    fn with_cx<T>(
        &mut self,
        flag: &str,
        text: &str,
        f: impl FnOnce(&mut Cx, FileId) -> Option<T>,
    ) -> Option<T> {
        let loader = MemoryLoader::default();
        let mut cx = Cx {
            sources: std::mem::take(&mut self.sources),
            diags: std::mem::take(&mut self.diags),
            loader: &loader,
        };
        let before = cx.diags.len();
        let name = format!("<{flag}>");
        let file = cx.sources.add(PathBuf::from(&name), name, text);
        let out = f(&mut cx, file);
        let failed = cx.diags.len() > before;
        self.sources = cx.sources;
        self.diags = cx.diags;
        if failed { None } else { out }
    }

    /// See [`check_range`].
    pub fn range(&mut self, flag: &str, text: &str, dim: Dim) -> Option<QuantityRange> {
        self.with_cx(flag, text, |cx, file| range_in(cx, file, text, dim))
    }

    /// See [`check_quantity_any_sign`].
    pub fn quantity(&mut self, flag: &str, text: &str, dim: Dim) -> Option<f64> {
        self.with_cx(flag, text, |cx, file| quantity_in(cx, file, text, dim))
    }

    /// `Ok` if nothing was refused, else every diagnostic with the sources.
    pub fn finish(self) -> Result<(), CliValueError> {
        if self.diags.is_empty() {
            Ok(())
        } else {
            Err(CliValueError {
                diagnostics: self.diags,
                sources: self.sources,
            })
        }
    }
}

fn single<T>(f: impl FnOnce(&mut CliChecker) -> Option<T>) -> Result<T, CliValueError> {
    let mut c = CliChecker::new();
    let out = f(&mut c);
    c.finish()?;
    out.ok_or_else(|| CliValueError {
        diagnostics: Vec::new(),
        sources: SourceMap::new(),
    })
}

/// One positive quantity of dimension `dim`, in SI (`--altitude 5km` takes any finite
/// value: see [`check_quantity_any_sign`]).
pub fn check_quantity_any_sign(flag: &str, text: &str, dim: Dim) -> Result<f64, CliValueError> {
    single(|c| c.quantity(flag, text, dim))
}

fn quantity_in(cx: &mut Cx, file: FileId, text: &str, dim: Dim) -> Option<f64> {
    let v = value_at(cx, file, text, 0, text.len())?;
    let q = fields::quantity(cx, &v, dim)?;
    fields::check_range(Some(q), cx, f64::is_finite, "a finite value").map(|q| q.value)
}

/// `START:STOP:COUNT` with START and STOP quantities of dimension `dim` (a unit on each,
/// unless `dim` is dimensionless), both positive, STOP > START for COUNT >= 2 and
/// STOP = START for COUNT = 1.
pub fn check_range(flag: &str, text: &str, dim: Dim) -> Result<QuantityRange, CliValueError> {
    single(|c| c.range(flag, text, dim))
}

fn range_in(cx: &mut Cx, file: FileId, text: &str, dim: Dim) -> Option<QuantityRange> {
    {
        let colons: Vec<usize> = text.match_indices(':').map(|(i, _)| i).collect();
        let [c1, c2] = colons.as_slice() else {
            cx.push(
                Diagnostic::error(
                    "analysis::range",
                    format!("`{text}` is not a range START:STOP:COUNT"),
                )
                .label(Span::new(file, 0, text.len()), "expected START:STOP:COUNT")
                .with_help(match dim {
                    Dim::NONE => "e.g. --mach 0.5:2.5:21".to_string(),
                    _ => "e.g. --thickness 0.3mm:1.2mm:10 (each end with its unit)".to_string(),
                }),
            );
            return None;
        };
        let (c1, c2) = (*c1, *c2);
        let a = value_at(cx, file, text, 0, c1);
        let b = value_at(cx, file, text, c1 + 1, c2);
        let n = value_at(cx, file, text, c2 + 1, text.len());
        let positive = |cx: &mut Cx, v: Option<Value>| {
            let q = fields::quantity(cx, &v?, dim);
            fields::check_range(q, cx, |x| x.is_finite() && x > 0.0, "a positive value")
        };
        let start = positive(cx, a);
        let stop = positive(cx, b);
        let count = n.and_then(|n| fields::count(cx, &n, 1, MAX_RANGE_POINTS));
        let (start, stop, count) = (start?, stop?, count?);
        let span = Span::new(file, 0, c2);
        if count == 1 && start.value != stop.value {
            cx.push(
                Diagnostic::error("analysis::range", "one point needs START = STOP")
                    .label(span, "START and STOP differ"),
            );
            return None;
        }
        if count > 1 && stop.value <= start.value {
            cx.push(
                Diagnostic::error("analysis::range", "STOP must exceed START")
                    .label(stop.span, "not above START")
                    .label(start.span, "START"),
            );
            return None;
        }
        Some(QuantityRange {
            start: start.value,
            stop: stop.value,
            count,
        })
    }
}

impl QuantityRange {
    /// The `count` values from `start` to `stop`, evenly spaced (both ends included).
    pub fn values(&self) -> Vec<f64> {
        if self.count == 1 {
            return vec![self.start];
        }
        let step = (self.stop - self.start) / (self.count - 1) as f64;
        (0..self.count)
            .map(|k| self.start + step * k as f64)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn codes(e: &CliValueError) -> Vec<&str> {
        e.diagnostics.iter().map(|d| d.code).collect()
    }

    #[test]
    fn ranges_carry_units_and_convert_to_si() {
        let r = check_range("--thickness", "0.3mm:1.2mm:10", Dim::LENGTH).unwrap();
        assert_eq!((r.start, r.stop, r.count), (0.3e-3, 1.2e-3, 10));
        let r = check_range("--thickness", "0.3 mm:0.12 cm:4", Dim::LENGTH).unwrap();
        assert_eq!((r.start, r.stop), (0.3e-3, 1.2e-3));
        let r = check_range("--mach", "0.5:2.5:21", Dim::NONE).unwrap();
        assert_eq!(r.values().len(), 21);
        assert_eq!(r.values()[20], 2.5);
        assert_eq!(
            check_range("--mach", "2:2:1", Dim::NONE).unwrap().values(),
            vec![2.0]
        );
    }

    #[test]
    fn a_bare_number_where_a_unit_is_needed_is_a_diagnostic_at_its_column() {
        let e = check_range("--thickness", "0.4:3.0:5", Dim::LENGTH).unwrap_err();
        assert_eq!(codes(&e), ["vdl::unit::missing", "vdl::unit::missing"]);
        let spans: Vec<(u32, u32)> = e
            .diagnostics
            .iter()
            .map(|d| (d.labels[0].span.start, d.labels[0].span.end))
            .collect();
        assert_eq!(spans, [(0, 3), (4, 7)]);
        let e = check_range("--thickness", "0.4mm:3:5", Dim::LENGTH).unwrap_err();
        assert_eq!(codes(&e), ["vdl::unit::missing"]);
        let e = check_range("--mach", "0.5 m:2:5", Dim::NONE).unwrap_err();
        assert_eq!(codes(&e), ["vdl::unit::mismatch"]);
        let e = check_range("--thickness", "0.4 s:1 mm:5", Dim::LENGTH).unwrap_err();
        assert_eq!(codes(&e), ["vdl::unit::mismatch"]);
        let e = check_range("--thickness", "0.4 mn:1 mm:5", Dim::LENGTH).unwrap_err();
        assert_eq!(codes(&e), ["vdl::unit::unknown"]);
        let e = check_quantity_any_sign("--altitude", "5000", Dim::LENGTH).unwrap_err();
        assert_eq!(codes(&e), ["vdl::unit::missing"]);
        assert_eq!(
            check_quantity_any_sign("--altitude", "5 km", Dim::LENGTH).unwrap(),
            5000.0
        );
    }

    #[test]
    fn bad_ranges_are_refused() {
        for (bad, code) in [
            ("1mm:2mm", "analysis::range"),
            ("1mm:2mm:3:4", "analysis::range"),
            ("1mm:2mm:0", "vdl::value::range"),
            ("1mm:2mm:2.5", "vdl::type::mismatch"),
            ("2mm:1mm:5", "analysis::range"),
            ("0mm:1mm:5", "vdl::value::range"),
            ("-1mm:1mm:5", "vdl::value::range"),
            ("1mm:2mm:1", "analysis::range"),
            ("1mm::3", "analysis::range"),
            ("a:2mm:3", "vdl::type::mismatch"),
        ] {
            let e = check_range("--thickness", bad, Dim::LENGTH).unwrap_err();
            assert!(codes(&e).contains(&code), "{bad}: {:?}", codes(&e));
        }
    }
}
