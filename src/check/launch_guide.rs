//! Checking `body { launch_lug { ... } rail_button { ... } }` blocks (issue 34): the launch
//! guides whose drag the built-in estimator adds (`aero::estimator::launch_guide_drag`) and
//! whose masses become point masses on the axis.
//!
//! `launch_lug`: `station` (body x of its fore end), `length`, `outer_diameter`,
//! `inner_diameter` (the bore, 0 for a rod, less than the outer diameter), `mass` (>= 0), all
//! required; the lug must lie on the body behind the nose (`vdl::value::range` at the
//! station). `rail_button`: `station` (body x of its centre), `outer_diameter`, `height` (its
//! total height above the body), `mass`, and optionally the notch between its flanges,
//! `inner_diameter` and `inner_height` together (less than the outer diameter and the
//! height); without them a plain pin.

use crate::diagnostics::Diagnostic;
use crate::syntax::Spanned;
use crate::syntax::ast::Block;
use crate::units::Dim;

use super::Cx;
use super::fields::{self as f, Fields};
use super::ir::{LaunchLug, PointMass, Q, RailButton};

fn length(cx: &mut Cx, fl: &mut Fields, name: &'static str, example: &str) -> Option<Q> {
    fl.required(cx, name, example)
        .and_then(|v| f::quantity(cx, v, Dim::LENGTH))
}

fn mass(cx: &mut Cx, fl: &mut Fields, example: &str) -> Option<Q> {
    let m = fl
        .required(cx, "mass", example)
        .and_then(|v| f::quantity(cx, v, Dim::MASS));
    f::non_negative(m, cx)
}

/// A station range `[aft, fore]` must lie on the body behind the nose: `[-length,
/// -nose_length]`.
fn on_body(
    cx: &mut Cx,
    station: &Q,
    fore: f64,
    aft: f64,
    nose: f64,
    body: f64,
    what: &str,
) -> bool {
    if fore > -nose || aft < -body {
        cx.push(
            Diagnostic::error(
                "vdl::value::range",
                format!(
                    "the {what} is off the body: it spans x = {aft:.4} m to {fore:.4} m, the body behind the nose x = {:.4} m to {:.4} m",
                    -body, -nose
                ),
            )
            .label(station.span, "station off the body"),
        );
        return false;
    }
    true
}

/// The launch lugs and rail buttons of a `body` block; `None` after reporting. `nose` and
/// `body` are the nose's and the body's lengths when they checked.
pub(super) fn check_launch_guides(
    cx: &mut Cx,
    lugs: &[&Block],
    buttons: &[&Block],
    nose: Option<f64>,
    body: Option<f64>,
) -> Option<(Vec<LaunchLug>, Vec<RailButton>)> {
    let mut ok = true;
    let mut out_lugs = Vec::new();
    for b in lugs {
        let mut fl = Fields::new(cx, "a `launch_lug` block", b.header, &b.body);
        let station = length(cx, &mut fl, "station", "-1.2 m");
        let len = f::positive(length(cx, &mut fl, "length", "50 mm"), cx);
        let od = f::positive(length(cx, &mut fl, "outer_diameter", "10 mm"), cx);
        let id = f::non_negative(length(cx, &mut fl, "inner_diameter", "8 mm"), cx);
        let m = mass(cx, &mut fl, "5 g");
        fl.finish(cx);
        let (Some(station), Some(len), Some(od), Some(id), Some(m)) = (station, len, od, id, m)
        else {
            ok = false;
            continue;
        };
        if id.value >= od.value {
            cx.push(
                Diagnostic::error(
                    "vdl::value::range",
                    "a launch lug's inner diameter must be less than its outer diameter",
                )
                .label(id.span, "inner diameter")
                .label(od.span, "outer diameter"),
            );
            ok = false;
            continue;
        }
        if let (Some(n), Some(l)) = (nose, body) {
            let fore = station.value;
            if !on_body(cx, &station, fore, fore - len.value, n, l, "launch lug") {
                ok = false;
                continue;
            }
        }
        out_lugs.push(LaunchLug {
            span: b.header,
            station,
            length: len,
            outer_diameter: od,
            inner_diameter: id,
            mass: m,
        });
    }
    let mut out_buttons = Vec::new();
    for b in buttons {
        let mut fl = Fields::new(cx, "a `rail_button` block", b.header, &b.body);
        let station = length(cx, &mut fl, "station", "-1.2 m");
        let od = f::positive(length(cx, &mut fl, "outer_diameter", "10 mm"), cx);
        let h = f::positive(length(cx, &mut fl, "height", "8 mm"), cx);
        let id_v = fl.value("inner_diameter");
        let ih_v = fl.value("inner_height");
        let notch = match (id_v, ih_v) {
            (None, None) => Some(None),
            (Some(a), Some(c)) => {
                let id = f::positive(f::quantity(cx, a, Dim::LENGTH), cx);
                let ih = f::positive(f::quantity(cx, c, Dim::LENGTH), cx);
                id.zip(ih).map(Some)
            }
            (Some(v), None) | (None, Some(v)) => {
                cx.push(
                    Diagnostic::error(
                        "vdl::value::range",
                        "a rail button's notch needs both `inner_diameter` and `inner_height`",
                    )
                    .label(v.span, "only one of the two")
                    .with_help("give both, or neither for a plain pin"),
                );
                None
            }
        };
        let m = mass(cx, &mut fl, "3 g");
        fl.finish(cx);
        let (Some(station), Some(od), Some(h), Some(notch), Some(m)) = (station, od, h, notch, m)
        else {
            ok = false;
            continue;
        };
        if let Some((id, ih)) = &notch {
            let bad = if id.value >= od.value {
                Some((
                    id.span,
                    "the notch's diameter must be less than the outer diameter",
                ))
            } else if ih.value >= h.value {
                Some((
                    ih.span,
                    "the notch's height must be less than the button's height",
                ))
            } else {
                None
            };
            if let Some((span, msg)) = bad {
                cx.push(Diagnostic::error("vdl::value::range", msg).label(span, "notch"));
                ok = false;
                continue;
            }
        }
        if let (Some(n), Some(l)) = (nose, body) {
            let (fore, aft) = (
                station.value + 0.5 * od.value,
                station.value - 0.5 * od.value,
            );
            if !on_body(cx, &station, fore, aft, n, l, "rail button") {
                ok = false;
                continue;
            }
        }
        out_buttons.push(RailButton {
            span: b.header,
            station,
            outer_diameter: od,
            height: h,
            notch,
            mass: m,
        });
    }
    ok.then_some((out_lugs, out_buttons))
}

/// The guides' masses as point masses on the axis (a lug's at its middle, a button's at its
/// station; none for a zero mass), named `launch_lug_N` and `rail_button_N` (from 1).
pub(crate) fn guide_masses(lugs: &[LaunchLug], buttons: &[RailButton]) -> Vec<PointMass> {
    let lug = lugs.iter().enumerate().map(|(i, l)| {
        (
            format!("launch_lug_{}", i + 1),
            l.span,
            l.station.value - 0.5 * l.length.value,
            l.mass,
        )
    });
    let button = buttons.iter().enumerate().map(|(i, b)| {
        (
            format!("rail_button_{}", i + 1),
            b.span,
            b.station.value,
            b.mass,
        )
    });
    lug.chain(button)
        .filter(|(_, _, _, m)| m.value > 0.0)
        .map(|(name, span, x, mass)| PointMass {
            name: Spanned::new(name, span),
            position: Spanned::new([x, 0.0, 0.0], mass.span),
            mass,
            inertia: Spanned::new([0.0; 3], mass.span),
        })
        .collect()
}
