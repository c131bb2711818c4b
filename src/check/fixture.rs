//! Checking `fixture` blocks (a lifting surface clamped at its root, the wind-tunnel model of
//! a flutter test) and the scenarios that test one (`scenario NAME { fixture = ...; tunnel
//! { ... } }`).

use crate::diagnostics::Diagnostic;
use crate::syntax::Spanned;
use crate::syntax::ast::{Block, EntryKind, ValueKind};
use crate::syntax::print::value_text;
use crate::units::Dim;

use super::fields::{self as f, Fields};
use super::ir::*;
use super::overrides::{self, is_scenario_path};
use super::{Cx, Decls, OtherKind, SetOverride, patch, vehicle};

/// The most quads along either side of a fixture's plate mesh.
pub const MAX_ELEMENTS: usize = 200;

/// Does this scenario block test a fixture (a `fixture = ...` line)?
pub(crate) fn is_tunnel_scenario(b: &Block) -> bool {
    b.body.entries.iter().any(|e| match &e.kind {
        EntryKind::Assign(a) => a.path.len() == 1 && a.path[0].name == "fixture",
        _ => false,
    })
}

pub(crate) fn check_fixture(cx: &mut Cx, b: &Block, materials: &[Material]) -> Option<Fixture> {
    let name = b.name.as_ref()?;
    let mut fl = Fields::new(cx, format!("fixture `{}`", name.name), b.header, &b.body);
    let material = fl
        .required(cx, "material", "aluminium_6061_t6")
        .and_then(|v| vehicle::material_ref(cx, v, materials));
    let surface_b = fl.required_block(cx, "surface");
    let mesh_b = fl.block("mesh");
    let modes = match fl.value("modes") {
        Some(v) => f::count(cx, v, 1, 50).map(|n| Spanned::new(n, v.span)),
        None => Some(Spanned::new(4, b.header)),
    };
    let spanwise_panels = match fl.value("spanwise_panels") {
        Some(v) => f::count(cx, v, 1, 100).map(|n| Spanned::new(n, v.span)),
        None => Some(Spanned::new(12, b.header)),
    };
    let reference_frequency = fl
        .value("reference_frequency")
        .map(|v| f::positive(f::quantity(cx, v, Dim::ANGULAR_VELOCITY), cx));
    fl.finish(cx);
    let (chord_elements, span_elements) = match mesh_b {
        Some(mb) => {
            let mut ml = Fields::new(cx, "the `mesh` block", mb.header, &mb.body);
            let mut n = |cx: &mut Cx, field: &'static str| match ml.value(field) {
                Some(v) => f::count(cx, v, 1, MAX_ELEMENTS).map(|n| Spanned::new(n, v.span)),
                None => Some(Spanned::new(16, mb.header)),
            };
            let c = n(cx, "chord_elements");
            let s = n(cx, "span_elements");
            ml.finish(cx);
            (c, s)
        }
        None => (
            Some(Spanned::new(16, b.header)),
            Some(Spanned::new(16, b.header)),
        ),
    };
    let surface = surface_b.and_then(|sb| check_surface(cx, sb, material.as_ref()));
    Some(Fixture {
        name: Spanned::new(name.name.clone(), name.span),
        span: b.header,
        surface: surface?,
        modes: modes?,
        chord_elements: chord_elements?,
        span_elements: span_elements?,
        spanwise_panels: spanwise_panels?,
        reference_frequency: reference_frequency.flatten(),
    })
}

fn check_surface(cx: &mut Cx, b: &Block, material: Option<&Material>) -> Option<Surface> {
    let mut fl = Fields::new(cx, "the `surface` block", b.header, &b.body);
    let len = |cx: &mut Cx, fl: &mut Fields, n: &'static str, ex: &str| {
        let q = fl
            .required(cx, n, ex)
            .and_then(|v| f::quantity(cx, v, Dim::LENGTH));
        f::positive(q, cx)
    };
    let span = len(cx, &mut fl, "span", "0.762 m");
    let root = len(cx, &mut fl, "root_chord", "0.559 m");
    let tip = len(cx, &mut fl, "tip_chord", "0.368 m");
    let sweeps: Vec<(&'static str, Spanned<f64>)> = [
        "leading_edge_sweep",
        "quarter_chord_sweep",
        "trailing_edge_sweep",
    ]
    .into_iter()
    .filter_map(|n| {
        let v = fl.value(n)?;
        let q = f::check_range(
            f::quantity(cx, v, Dim::ANGLE),
            cx,
            |x| x.abs() < 1.4,
            "|sweep| < 80 deg",
        )?;
        Some((n, q))
    })
    .collect();
    let thickness_v = fl.value("thickness");
    let section_v = fl.value("half_thickness");
    let grain_v = fl.value("grain");
    let mass = fl
        .value("mass")
        .map(|v| f::positive(f::quantity(cx, v, Dim::MASS), cx));
    fl.finish(cx);
    if let (Some(r), Some(t)) = (root, tip) {
        if t.value > r.value {
            cx.push(
                Diagnostic::error(
                    "vdl::value::range",
                    "the tip chord is longer than the root chord",
                )
                .label(t.span, "tip chord")
                .label(r.span, "root chord"),
            );
            return None;
        }
    }
    let (s, cr, ct) = (span?, root?, tip?);
    // Leading-edge sweep from the one given: the chord fraction u's line is swept by
    // tan Λ_u = tan Λ_LE - u (c_r - c_t)/s (straight edges), so tan Λ_LE = tan Λ_u + u (c_r - c_t)/s.
    let leading_edge_sweep = match sweeps.as_slice() {
        [(which, q)] => {
            let u = match *which {
                "leading_edge_sweep" => 0.0,
                "quarter_chord_sweep" => 0.25,
                _ => 1.0,
            };
            let tan_le = q.value.tan() + u * (cr.value - ct.value) / s.value;
            Spanned::new(if u == 0.0 { q.value } else { tan_le.atan() }, q.span)
        }
        [] => {
            cx.push(
                Diagnostic::error(
                    "vdl::field::missing",
                    "the `surface` block needs one of `leading_edge_sweep`, `quarter_chord_sweep` or `trailing_edge_sweep`",
                )
                .label(b.header, "sweep missing")
                .with_help("AGARD 445.6: `quarter_chord_sweep = 45 deg`"),
            );
            return None;
        }
        [_, (_, second), ..] => {
            cx.push(
                Diagnostic::error("vdl::fins::sweep", "give one sweep of the surface, not two")
                    .label(second.span, "second sweep"),
            );
            return None;
        }
    };
    let thickness = match (thickness_v, section_v) {
        (Some(tv), None) => {
            SurfaceThickness::Constant(f::positive(f::quantity(cx, tv, Dim::LENGTH), cx)?)
        }
        (None, Some(sv)) => SurfaceThickness::Section(section(cx, sv)?),
        (Some(_), Some(sv)) => {
            cx.push(
                Diagnostic::error(
                    "vdl::fixture::thickness",
                    "give `thickness` (a flat plate) or `half_thickness` (a section), not both",
                )
                .label(sv.span, "second thickness"),
            );
            return None;
        }
        (None, None) => {
            cx.push(
                Diagnostic::error(
                    "vdl::field::missing",
                    "the `surface` block needs `thickness` or `half_thickness`",
                )
                .label(b.header, "thickness missing")
                .with_help("`thickness = 2 mm` for a flat plate, or `half_thickness = [z/c, ...]` at evenly spaced chord fractions"),
            );
            return None;
        }
    };
    let material = material?.clone();
    let grain = match grain_v {
        None => SurfaceGrain::GridLines,
        Some(v) if material.orthotropic.is_none() => {
            vehicle::grain_without_lamina(cx, v.span, &material, "material");
            return None;
        }
        Some(v) => grain(cx, v)?,
    };
    Some(Surface {
        span_: b.header,
        span: s,
        root_chord: cr,
        tip_chord: ct,
        leading_edge_sweep,
        thickness,
        material,
        grain,
        mass: mass.flatten(),
    })
}

/// `half_thickness = [z/c, ...]`: at least two stations, each in `[0, 0.25)`, some positive.
fn section(cx: &mut Cx, v: &crate::syntax::ast::Value) -> Option<Spanned<Vec<f64>>> {
    let ValueKind::List(items) = &v.kind else {
        cx.push(
            Diagnostic::error(
                "vdl::type::mismatch",
                format!("expected a list of numbers, found {}", v.describe()),
            )
            .label(v.span, "write e.g. `[0, 0.012, 0.02, 0.012, 0]`"),
        );
        return None;
    };
    let values: Vec<f64> = items
        .iter()
        .map(|it| {
            f::check_range(
                f::number(cx, it),
                cx,
                |x| (0.0..0.25).contains(&x),
                "0 <= z/c < 0.25",
            )
            .map(|q| q.value)
        })
        .collect::<Option<Vec<_>>>()?;
    if values.len() < 2 || values.iter().all(|&x| x == 0.0) {
        cx.push(
            Diagnostic::error(
                "vdl::fixture::thickness",
                "a section needs at least two stations and some thickness",
            )
            .label(v.span, format!("{} stations", values.len())),
        );
        return None;
    }
    Some(Spanned::new(values, v.span))
}

/// `grain = grid_lines` or `grain = swept(ANGLE)`.
fn grain(cx: &mut Cx, v: &crate::syntax::ast::Value) -> Option<SurfaceGrain> {
    match &v.kind {
        ValueKind::Name(id) if id.name == "grid_lines" => Some(SurfaceGrain::GridLines),
        ValueKind::Call { name, args }
            if name.name == "swept" && args.len() == 1 && args[0].name.is_none() =>
        {
            let q = f::check_range(
                f::quantity(cx, &args[0].value, Dim::ANGLE),
                cx,
                |x| x.abs() < 1.4,
                "|sweep| < 80 deg",
            )?;
            Some(SurfaceGrain::Swept(q.value))
        }
        _ => {
            cx.push(
                Diagnostic::error(
                    "vdl::type::mismatch",
                    format!("expected `grid_lines` or `swept(ANGLE)`, found {}", v.describe()),
                )
                .label(v.span, "not a grain direction")
                .with_help("`grid_lines`: along the lines of constant chord fraction; `swept(45 deg)`: along one straight line swept back by 45 deg"),
            );
            None
        }
    }
}

/// A scenario that tests a fixture: the fixture (with `with` and `--set` overrides), the
/// tunnel's Mach number, air density and speeds.
pub(crate) fn check_tunnel_test(
    cx: &mut Cx,
    b: &Block,
    decls: &Decls,
    materials: &[Material],
    sets: &[SetOverride],
) -> Option<TunnelTest> {
    let name = b.name.as_ref()?;
    let scenario_sets: Vec<&SetOverride> =
        sets.iter().filter(|s| is_scenario_path(&s.path)).collect();
    let b = &patch(cx, b, &scenario_sets);
    let mut fl = Fields::new(cx, format!("scenario `{}`", name.name), b.header, &b.body);
    let fixture_v = fl.value("fixture");
    let with_b = fl.block("with");
    let tunnel_b = fl.required_block(cx, "tunnel");
    fl.finish(cx);
    let fixture_block = fixture_v.and_then(|v| {
        let others = [OtherKind {
            kind: "vehicle",
            blocks: &decls.vehicles,
            label: None,
            help: Some("a flown scenario writes `vehicle = NAME`"),
        }];
        super::reference(cx, v, "fixture", &decls.fixtures, &others).map(|i| decls.fixtures[i])
    });
    let mut overrides_applied = Vec::new();
    let fixture = fixture_block.and_then(|fb| {
        let mut patched = fb.clone();
        if let Some(wb) = with_b {
            for e in &wb.body.entries {
                match &e.kind {
                    EntryKind::Assign(a) if !is_scenario_path(&a.path) => {
                        overrides_applied.push(Override {
                            path: a.path_string(),
                            value: value_text(&a.value),
                            span: e.span,
                        });
                        if let Err(d) = overrides::apply(&mut patched.body, &a.path, &a.value) {
                            cx.push(d);
                        }
                    }
                    _ => cx.push(
                        Diagnostic::error(
                            "vdl::override::syntax",
                            "a `with` block holds only `path = value` lines of the fixture",
                        )
                        .label(e.span, "not a fixture override"),
                    ),
                }
            }
        }
        for s in sets.iter().filter(|s| !is_scenario_path(&s.path)) {
            let span = s
                .path
                .first()
                .map_or(s.value.span, |p| p.span.to(s.value.span));
            overrides_applied.push(Override {
                path: crate::syntax::ast::path_string(&s.path),
                value: value_text(&s.value),
                span,
            });
            if let Err(d) = overrides::apply(&mut patched.body, &s.path, &s.value) {
                cx.push(d);
            }
        }
        check_fixture(cx, &patched, materials)
    });
    let tb = tunnel_b?;
    let mut tl = Fields::new(cx, "the `tunnel` block", tb.header, &tb.body);
    let mach = tl
        .required(cx, "mach", "0.499")
        .and_then(|v| f::number(cx, v));
    let mach = f::check_range(mach, cx, |m| (0.0..10.0).contains(&m), "0 <= Mach < 10");
    let density = tl
        .required(cx, "density", "0.4277 kg/m^3")
        .and_then(|v| f::quantity(cx, v, Dim::DENSITY));
    let density = f::positive(density, cx);
    let speeds_v = tl.required(cx, "speeds", "range(60 m/s, 400 m/s, step = 5 m/s)");
    tl.finish(cx);
    let speeds = speeds_v.and_then(|v| {
        let values = super::sweep::axis_values(cx, v)?;
        let speeds = values
            .iter()
            .map(|x| f::positive(f::quantity(cx, x, Dim::VELOCITY), cx).map(|q| q.value))
            .collect::<Option<Vec<f64>>>()?;
        if speeds.len() < 2 || speeds.windows(2).any(|w| w[1] <= w[0]) {
            cx.push(
                Diagnostic::error(
                    "vdl::fixture::speeds",
                    "the tunnel speeds must be at least two, increasing",
                )
                .label(v.span, format!("{} speeds", speeds.len())),
            );
            return None;
        }
        Some(Spanned::new(speeds, v.span))
    });
    Some(TunnelTest {
        name: Spanned::new(name.name.clone(), name.span),
        span: b.header,
        fixture: fixture?,
        overrides: overrides_applied,
        mach: mach?,
        density: density?,
        speeds: speeds?,
    })
}
