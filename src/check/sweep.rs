//! Checking `sweep` blocks: each axis is a path and a list of values; every value is applied
//! to the scenario as an override and checked, so a bad path or value is reported before
//! any case runs.

use crate::diagnostics::Diagnostic;
use crate::syntax::Spanned;
use crate::syntax::ast::{Block, EntryKind, Number, Value, ValueKind, path_string};
use crate::syntax::print::value_text;

use super::fields::{self as f, Fields};
use super::ir::*;
use super::scenario::check_scenario;
use super::{Cx, Decls, OtherKind, SetOverride};

/// More cases than this in one sweep is refused (a typo in a range should not fill a disk).
pub const MAX_CASES: usize = 1_000_000;

pub(crate) fn check_sweep(
    cx: &mut Cx,
    b: &Block,
    decls: &Decls,
    program: &Program,
    sets: &[SetOverride],
) -> Option<Sweep> {
    let name = b.name.as_ref()?;
    let mut fl = Fields::new(cx, format!("sweep `{}`", name.name), b.header, &b.body);
    let scen_v = fl.required(cx, "scenario", "subsonic_t06");
    let analysis = match fl.value("analysis") {
        Some(v) => f::keyword(
            cx,
            v,
            &[
                ("run", SweepAnalysis::Run),
                ("planar_pinned", SweepAnalysis::PlanarPinned),
                ("planar_unpinned", SweepAnalysis::PlanarUnpinned),
                ("linear3d", SweepAnalysis::Linear3d),
            ],
        )
        .map(|a| Spanned::new(a, v.span)),
        None => Some(Spanned::new(SweepAnalysis::Run, b.header)),
    };
    let frozen_v = fl.value("frozen_gravity");
    let grid = fl.block("grid");
    let zip = fl.block("zip");
    fl.finish(cx);
    // `frozen_gravity` is an option of the linearisation: refused with any other analysis.
    let frozen_gravity = match frozen_v {
        None => Some(false),
        Some(v) => match (f::boolean(cx, v), &analysis) {
            (Some(b), Some(a)) if a.value == SweepAnalysis::Linear3d => Some(b),
            (Some(_), Some(a)) => {
                cx.push(
                    Diagnostic::error(
                        "vdl::sweep::option",
                        "`frozen_gravity` is an option of `analysis = linear3d` only",
                    )
                    .label(v.span, "not used by this analysis")
                    .label(a.span, "the sweep's analysis")
                    .with_help("remove `frozen_gravity`, or set `analysis = linear3d`"),
                );
                None
            }
            _ => None,
        },
    };

    let scenario_block = scen_v.and_then(|v| {
        let others = [OtherKind {
            kind: "vehicle",
            blocks: &decls.vehicles,
            label: Some("a sweep varies a scenario"),
            help: Some("declare a scenario that flies this vehicle and sweep that"),
        }];
        let i = super::reference(cx, v, "scenario", &decls.scenarios, &others)?;
        let name = decls.scenarios[i].name.as_ref()?.name.clone();
        Some((i, decls.scenarios[i], name))
    });
    let (combine, axes_block) = match (grid, zip) {
        (Some(g), None) => (Combine::Grid, g),
        (None, Some(z)) => (Combine::Zip, z),
        (Some(_), Some(z)) => {
            cx.push(
                Diagnostic::error(
                    "vdl::sweep::combine",
                    "a sweep has either a `grid` or a `zip` block, not both",
                )
                .label(z.header, "second block"),
            );
            return None;
        }
        (None, None) => {
            cx.push(
                Diagnostic::error(
                    "vdl::block::missing",
                    "a sweep needs a `grid { ... }` or `zip { ... }` block of axes",
                )
                .label(b.header, "no axes")
                .with_help("e.g. `grid { fins.thickness = [0.4 mm, 0.6 mm] }`"),
            );
            return None;
        }
    };
    let mut axes = Vec::new();
    let mut ok = true;
    for e in &axes_block.body.entries {
        let EntryKind::Assign(a) = &e.kind else {
            cx.push(
                Diagnostic::error(
                    "vdl::sweep::axis",
                    "a sweep axis is `path = [values]` or `path = range(...)`",
                )
                .label(e.span, "not an axis"),
            );
            ok = false;
            continue;
        };
        let Some(values) = axis_values(cx, &a.value) else {
            ok = false;
            continue;
        };
        // Check every value through the scenario, as an override.
        if let Some((_, sb, _)) = &scenario_block {
            let before = cx.diags.len();
            for v in &values {
                let mut all: Vec<SetOverride> = sets.to_vec();
                all.push(SetOverride {
                    path: a.path.clone(),
                    value: v.clone(),
                });
                check_scenario(cx, sb, decls, &program.materials, &all);
                if cx.diags.len() > before {
                    ok = false;
                    break;
                }
            }
        }
        let si_values = values.iter().map(|v| si_scalar(cx, v)).collect();
        axes.push(SweepAxis {
            path: path_string(&a.path),
            span: e.span,
            values: values.iter().map(value_text).collect(),
            si_values,
        });
    }
    if axes.is_empty() && ok {
        cx.push(
            Diagnostic::error("vdl::sweep::empty", "the sweep has no axes")
                .label(axes_block.header, "add `path = [values]` lines"),
        );
        return None;
    }
    if combine == Combine::Zip {
        if let Some(first) = axes.first() {
            for ax in &axes[1..] {
                if ax.values.len() != first.values.len() {
                    cx.push(
                        Diagnostic::error(
                            "vdl::sweep::zip",
                            format!(
                                "zipped axes differ in length ({} and {})",
                                first.values.len(),
                                ax.values.len()
                            ),
                        )
                        .label(ax.span, format!("{} values", ax.values.len()))
                        .label(first.span, format!("{} values", first.values.len())),
                    );
                    ok = false;
                }
            }
        }
    }
    let (scenario, _, _) = scenario_block?;
    let sweep = Sweep {
        name: Spanned::new(name.name.clone(), name.span),
        span: b.header,
        scenario,
        analysis: analysis?,
        frozen_gravity: frozen_gravity?,
        combine,
        axes,
    };
    if sweep.case_count() > MAX_CASES {
        cx.push(
            Diagnostic::error(
                "vdl::sweep::size",
                format!(
                    "the sweep has {} cases (at most {MAX_CASES})",
                    sweep.case_count()
                ),
            )
            .label(axes_block.header, "too many cases"),
        );
        return None;
    }
    // The scenario index must refer to the checked program's list: find by name.
    let scen_name = decls
        .scenarios
        .get(scenario)
        .and_then(|s| s.name.as_ref())
        .map(|n| n.name.clone());
    let idx = scen_name.and_then(|n| program.scenarios.iter().position(|s| s.name.value == n));
    match (ok, idx) {
        (true, Some(i)) => Some(Sweep {
            scenario: i,
            ..sweep
        }),
        _ => None,
    }
}

fn si_scalar(cx: &mut Cx, v: &Value) -> Option<f64> {
    match &v.kind {
        ValueKind::Quantity { number, unit: None } => Some(number.value),
        ValueKind::Quantity {
            number,
            unit: Some(u),
        } => {
            let mut scratch = Cx {
                sources: crate::syntax::SourceMap::new(),
                diags: Vec::new(),
                loader: cx.loader,
            };
            f::resolve_unit(&mut scratch, u).map(|unit| number.value * unit.scale)
        }
        _ => None,
    }
}

/// Expand an axis: a list, or `range(start, stop, count = N)` / `range(start, stop, step = S)`.
pub(crate) fn axis_values(cx: &mut Cx, v: &Value) -> Option<Vec<Value>> {
    match &v.kind {
        ValueKind::List(items) if !items.is_empty() => Some(items.clone()),
        ValueKind::List(_) => {
            cx.push(
                Diagnostic::error("vdl::sweep::empty", "this axis has no values")
                    .label(v.span, "empty list"),
            );
            None
        }
        ValueKind::Call { name, args } if name.name == "range" => expand_range(cx, v, args),
        _ => {
            cx.push(
                Diagnostic::error(
                    "vdl::sweep::axis",
                    format!("expected a list or `range(...)`, found {}", v.describe()),
                )
                .label(v.span, "not a set of values")
                .with_help("e.g. `[0.4 mm, 0.6 mm]` or `range(0.3 mm, 1.0 mm, count = 8)`"),
            );
            None
        }
    }
}

fn expand_range(cx: &mut Cx, v: &Value, args: &[crate::syntax::ast::Arg]) -> Option<Vec<Value>> {
    let usage = |cx: &mut Cx, msg: &str| {
        cx.push(
            Diagnostic::error("vdl::sweep::range", msg.to_string())
                .label(v.span, "bad range")
                .with_help(
                    "write `range(START, STOP, count = N)` or `range(START, STOP, step = S)`",
                ),
        );
    };
    let [a, b, c] = args else {
        usage(
            cx,
            "`range` takes a start, a stop and `count = N` or `step = S`",
        );
        return None;
    };
    let (
        ValueKind::Quantity {
            number: n0,
            unit: u0,
        },
        ValueKind::Quantity {
            number: n1,
            unit: u1,
        },
    ) = (&a.value.kind, &b.value.kind)
    else {
        usage(
            cx,
            "the start and stop of a range are numbers or quantities",
        );
        return None;
    };
    let ut =
        |u: &Option<crate::syntax::ast::UnitExpr>| u.as_ref().map(crate::syntax::print::unit_text);
    if ut(u0) != ut(u1) {
        usage(
            cx,
            "the start and stop of a range must be written in the same unit",
        );
        return None;
    }
    let (x0, x1) = (n0.value, n1.value);
    let values: Vec<f64> = match c.name.as_ref().map(|n| n.name.as_str()) {
        Some("count") => {
            let n = f::count(cx, &c.value, 1, super::sweep::MAX_CASES)?;
            if n == 1 {
                vec![x0]
            } else {
                (0..n)
                    .map(|k| x0 + (x1 - x0) * k as f64 / (n - 1) as f64)
                    .collect()
            }
        }
        Some("step") => {
            let ValueKind::Quantity {
                number: s,
                unit: us,
            } = &c.value.kind
            else {
                usage(cx, "`step` is a number or quantity");
                return None;
            };
            if ut(us) != ut(u0) {
                usage(
                    cx,
                    "the step must be written in the same unit as the start and stop",
                );
                return None;
            }
            let s = s.value;
            if s == 0.0 || (x1 - x0) * s < 0.0 || !s.is_finite() {
                usage(
                    cx,
                    "the step is zero or points away from the stop: the range is empty",
                );
                return None;
            }
            let n = ((x1 - x0) / s + 1e-9).floor() + 1.0;
            if !(1.0..=MAX_CASES as f64).contains(&n) {
                usage(cx, "the range has too many values");
                return None;
            }
            (0..n as usize).map(|k| x0 + s * k as f64).collect()
        }
        _ => {
            usage(
                cx,
                "the third argument of `range` is `count = N` or `step = S`",
            );
            return None;
        }
    };
    Some(
        values
            .into_iter()
            .map(|x| {
                let text = short(x);
                Value {
                    kind: ValueKind::Quantity {
                        number: Number {
                            value: text.parse().unwrap_or(x),
                            text,
                            span: v.span,
                        },
                        unit: u0.clone(),
                    },
                    span: v.span,
                }
            })
            .collect(),
    )
}

/// Shortest text of `x` rounded to 12 significant digits (so 0.1 + 0.2 prints as 0.3).
pub fn short(x: f64) -> String {
    let rounded: f64 = format!("{x:.11e}").parse().unwrap_or(x);
    format!("{rounded}")
}
