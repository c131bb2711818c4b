//! `aero { source = datcom("for006.dat", case = N, fin_set = N) }`: the call's arguments,
//! and the file read, parsed and turned into the flight's tables at `check`
//! ([`crate::aero::datcom`]), so a bad file, a grid that does not close or a reference
//! quantity the vehicle contradicts is a diagnostic before anything runs. Errors in the file
//! are labelled at its line and column (code `vdl::aero::datcom`).

use std::path::{Path, PathBuf};

use crate::aero::datcom::{self, Mismatch, Selection, VehicleReference};
use crate::diagnostics::Diagnostic;
use crate::syntax::ast::{Value, ValueKind};
use crate::syntax::span::Span;

use super::Cx;
use super::fields as f;
use super::ir::{Aero, AeroSource, Fins, Forces};
use crate::syntax::Spanned;

const CODE: &str = "vdl::aero::datcom";

/// The file and selection of a `datcom(...)` call; `None` (reported) when malformed.
pub(crate) fn call(cx: &mut Cx, v: &Value) -> Option<(Spanned<PathBuf>, Selection)> {
    f::record_keywords(["datcom"].into_iter());
    let ValueKind::Call { name, args } = &v.kind else {
        return None;
    };
    if name.name != "datcom" {
        return None;
    }
    let mut file = None;
    let mut sel = Selection::default();
    let mut ok = true;
    for a in args {
        match a.name.as_ref().map(|n| n.name.as_str()) {
            None if file.is_none() => {
                let s = f::string(cx, &a.value)?;
                file = cx
                    .resolve_file(&s, a.value.span, "Missile DATCOM output")
                    .map(|p| Spanned::new(p, a.value.span));
                ok &= file.is_some();
            }
            Some("case") => sel.case = f::count(cx, &a.value, 1, 9999).map(|n| n as u32),
            Some("fin_set") => sel.fin_set = f::count(cx, &a.value, 1, 9999).map(|n| n as u32),
            _ => {
                cx.push(
                    Diagnostic::error(
                        "vdl::type::mismatch",
                        "`datcom(...)` takes the file, then `case = N` and `fin_set = N`",
                    )
                    .label(a.value.span, "unexpected argument"),
                );
                ok = false;
            }
        }
    }
    if file.is_none() && ok {
        cx.push(
            Diagnostic::error("vdl::field::missing", "`datcom(...)` needs the file")
                .label(v.span, "no file")
                .with_help("`source = datcom(\"for006.dat\")`"),
        );
    }
    if !ok {
        return None;
    }
    Some((file?, sel))
}

/// Reads, parses and converts the vehicle's DATCOM file; `false` (reported) when it cannot
/// give the flight's tables.
pub(crate) fn check_vehicle(
    cx: &mut Cx,
    aero: &Aero,
    fins: Option<&Fins>,
    forces: Option<&Forces>,
) -> bool {
    let AeroSource::Datcom {
        file,
        case,
        fin_set,
        out_of_range,
    } = &aero.source
    else {
        return true;
    };
    if let Some(ba) = forces.and_then(|f| f.body_aero.as_ref()) {
        if ba.rate_terms {
            cx.push(
                Diagnostic::error(
                    "vdl::aero::rate_columns",
                    "`rate_terms = true` needs rate derivatives in the body table; a DATCOM source gives none",
                )
                .label(ba.span, "rate terms asked for here")
                .label(file.span, "the aerodynamics come from this DATCOM file"),
            );
            return false;
        }
    }
    let text = match cx.loader.read(&file.value) {
        Ok(t) => t,
        Err(e) => {
            cx.push(
                Diagnostic::error(CODE, format!("cannot read {}: {e}", file.value.display()))
                    .label(file.span, "named here"),
            );
            return false;
        }
    };
    let parsed = match datcom::parse(&text) {
        Ok(p) => p,
        Err(e) => {
            let d = Diagnostic::error(CODE, format!("{}: {}", file.value.display(), e.message));
            let d = at_line(cx, &file.value, &text, e.line, e.column, d);
            cx.push(d.label(file.span, "DATCOM output named here"));
            return false;
        }
    };
    let vref = VehicleReference {
        area: aero.reference_area.value,
        length: aero.reference_length.value,
        point_x: aero.reference_point.value[0],
        fins: fins.map(|fi| {
            (
                fi.count.value,
                fi.root_trailing_edge_x.value + fi.root_chord.value,
            )
        }),
    };
    let sel = Selection {
        case: *case,
        fin_set: *fin_set,
    };
    match datcom::tables(&parsed, &file.value, sel, &vref, out_of_range.value) {
        Ok(_) => true,
        Err(e) => {
            let mut d = Diagnostic::error(CODE, format!("{}: {}", file.value.display(), e));
            if let Some(line) = e.line {
                d = at_line(cx, &file.value, &text, line, 1, d);
            }
            let (span, what) = match e.mismatch {
                Some(Mismatch::Area) => (aero.reference_area.span, "the vehicle's reference area"),
                Some(Mismatch::Length) => {
                    (aero.reference_length.span, "the vehicle's reference length")
                }
                Some(Mismatch::Point) => {
                    (aero.reference_point.span, "the vehicle's reference point")
                }
                None => (file.span, "DATCOM output named here"),
            };
            d = d.label(span, what);
            if e.mismatch.is_some() {
                d = d
                    .label(file.span, "DATCOM output named here")
                    .with_help("DATCOM's coefficients are on its SREF and LREF about its XCG (from the nose tip): give the vehicle the same `reference_area`, `reference_length` and `reference_point = (-XCG, 0, 0)`");
            }
            cx.push(d);
            false
        }
    }
}

/// Labels `d` at `line`, `column` of the DATCOM file (added to the source map).
fn at_line(
    cx: &mut Cx,
    path: &Path,
    text: &str,
    line: usize,
    column: usize,
    d: Diagnostic,
) -> Diagnostic {
    let mut start = 0;
    for (k, l) in text.split_inclusive('\n').enumerate() {
        if k + 1 == line {
            let t = l.trim_end_matches(['\n', '\r']);
            let from = start + (column.saturating_sub(1)).min(t.len());
            let to = (start + t.len()).max(from + 1).min(start + l.len().max(1));
            let id = match cx.sources.find(path) {
                Some(id) => id,
                None => cx.sources.add(
                    path.to_path_buf(),
                    path.display().to_string(),
                    text.to_string(),
                ),
            };
            return d.label(Span::new(id, from, to), "here");
        }
        start += l.len();
    }
    d
}
