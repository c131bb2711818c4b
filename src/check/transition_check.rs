//! Checking `body { transition { ... } }` blocks (issue 34; the geometry is
//! `check::transition`, a leaf the aerodynamics and the structure import).

use crate::diagnostics::Diagnostic;
use crate::syntax::Spanned;
use crate::syntax::ast::Block;
use crate::units::Dim;

use super::Cx;
use super::fields::{self as f, Fields};
use super::ir::{BodyGeometry, Fins, Q, Transition};
use super::nose::NoseShape;

/// Check the `transition` blocks of a `body` block (module doc; docs/language.md): each
/// needs `fore_station` (body x of its fore end, < 0), `length` (> 0), `fore_diameter` and
/// `aft_diameter` (> 0, different: an equal pair is no transition, `vdl::transition::no_op`),
/// `shape` (a nose shape, `conical` unless given). The fore diameter must be the diameter of
/// the section ahead (`vdl::transition::mismatch`); a transition must lie behind the nose and
/// the previous transition, within the body (`vdl::transition::overlap`); the wall must be
/// thinner than half its smaller diameter (`vdl::value::range`). `None` after reporting.
pub(super) fn check_transitions(
    cx: &mut Cx,
    blocks: &[&Block],
    diameter: Option<&Q>,
    wall: Option<&Q>,
    nose_length: Option<&Q>,
    length: Option<&Q>,
) -> Option<Vec<Transition>> {
    let mut out = Vec::new();
    let mut ok = true;
    for b in blocks {
        let mut fl = Fields::new(cx, "a `transition` block", b.header, &b.body);
        let q = |cx: &mut Cx, fl: &mut Fields, name: &'static str, example: &str| {
            fl.required(cx, name, example)
                .and_then(|v| f::quantity(cx, v, Dim::LENGTH))
        };
        let station = q(cx, &mut fl, "fore_station", "-1.2 m");
        let station = f::check_range(
            station,
            cx,
            |x| x < 0.0,
            "a body station < 0 (aft of the nose tip)",
        );
        let len = q(cx, &mut fl, "length", "80 mm");
        let len = f::positive(len, cx);
        let df = q(cx, &mut fl, "fore_diameter", "102 mm");
        let df = f::positive(df, cx);
        let da = q(cx, &mut fl, "aft_diameter", "80 mm");
        let da = f::positive(da, cx);
        let shape = match fl.value("shape") {
            Some(v) => super::vehicle::nose_shape(cx, v),
            None => Some(Spanned::new(NoseShape::Conical, b.header)),
        };
        fl.finish(cx);
        match (station, len, df, da, shape) {
            (
                Some(fore_station),
                Some(length),
                Some(fore_diameter),
                Some(aft_diameter),
                Some(shape),
            ) => out.push(Transition {
                span: b.header,
                fore_station,
                length,
                fore_diameter,
                aft_diameter,
                shape,
            }),
            _ => ok = false,
        }
    }
    if !ok {
        return None;
    }
    let (Some(d0), Some(wall), Some(nose), Some(body_len)) = (diameter, wall, nose_length, length)
    else {
        return Some(out);
    };
    // Ahead of the first transition: the nose's base (or the tube's front).
    let mut prev_d = *d0;
    let mut prev_end = Spanned::new(nose.value, nose.span);
    let mut prev_is_nose = true;
    for t in &out {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
        if close(t.fore_diameter.value, t.aft_diameter.value) {
            cx.push(
                Diagnostic::error(
                    "vdl::transition::no_op",
                    "a transition whose fore and aft diameters are equal is no transition",
                )
                .label(t.aft_diameter.span, "aft diameter")
                .label(t.fore_diameter.span, "the same fore diameter")
                .with_help("remove the block: the tube continues at this diameter"),
            );
            ok = false;
            continue;
        }
        if !close(t.fore_diameter.value, prev_d.value) {
            cx.push(
                Diagnostic::error(
                    "vdl::transition::mismatch",
                    format!(
                        "the transition's fore diameter {} mm does not meet the section ahead of it ({} mm)",
                        t.fore_diameter.value * 1e3,
                        prev_d.value * 1e3
                    ),
                )
                .label(t.fore_diameter.span, "fore diameter")
                .label(prev_d.span, "the diameter of the section ahead")
                .with_help("a transition starts at the diameter of the section ahead of it and the body keeps its aft diameter behind it"),
            );
            ok = false;
        }
        let start = -t.fore_station.value;
        if start < prev_end.value * (1.0 - 1e-12) {
            cx.push(
                Diagnostic::error(
                    "vdl::transition::overlap",
                    if prev_is_nose {
                        "the transition overlaps the nose"
                    } else {
                        "the transition overlaps the transition ahead of it"
                    },
                )
                .label(t.fore_station.span, "fore end")
                .label(
                    prev_end.span,
                    if prev_is_nose {
                        "the nose ends here"
                    } else {
                        "the previous transition"
                    },
                ),
            );
            ok = false;
        }
        let end = start + t.length.value;
        if end > body_len.value * (1.0 + 1e-12) {
            cx.push(
                Diagnostic::error(
                    "vdl::transition::overlap",
                    format!(
                        "the transition ends {} m aft of the nose tip, behind the body's tail ({} m)",
                        end, body_len.value
                    ),
                )
                .label(t.length.span, "transition length")
                .label(body_len.span, "body length"),
            );
            ok = false;
        }
        let dmin = t.fore_diameter.value.min(t.aft_diameter.value);
        if 2.0 * wall.value >= dmin {
            cx.push(
                Diagnostic::error(
                    "vdl::value::range",
                    "the wall is as thick as the transition's smaller radius or more",
                )
                .label(wall.span, "wall thickness")
                .label(
                    if t.fore_diameter.value < t.aft_diameter.value {
                        t.fore_diameter.span
                    } else {
                        t.aft_diameter.span
                    },
                    "smaller diameter",
                ),
            );
            ok = false;
        }
        prev_d = t.aft_diameter;
        prev_end = Spanned::new(end, t.length.span);
        prev_is_nose = false;
    }
    ok.then_some(out)
}

/// A fin set's root chord on a transition (the fins must sit on a section of one diameter):
/// `vdl::transition::overlap` at both.
pub(super) fn check_fins_clear(cx: &mut Cx, body: &BodyGeometry, fins: &Fins) -> bool {
    let (aft, fore) = (
        -fins.root_trailing_edge_x.value,
        -fins.root_trailing_edge_x.value - fins.root_chord.value,
    );
    let mut ok = true;
    for t in &body.transitions {
        let g = t.geom();
        let eps = 1e-12 * g.end();
        if fore < g.end() - eps && aft > g.start + eps {
            cx.push(
                Diagnostic::error(
                    "vdl::transition::overlap",
                    "the fins' root chord lies on a transition: fins sit on a section of one diameter",
                )
                .label(t.fore_station.span, "this transition")
                .label(fins.root_trailing_edge_x.span, "the fins' root"),
            );
            ok = false;
        }
    }
    ok
}
