//! Checking `dispersion` blocks (Monte Carlo): the scenario, the sample count and seed, the
//! `vary { PATH = DISTRIBUTION(...) }` entries and the correlations between them.
//!
//! ```text
//! dispersion k1000_mc {
//!   scenario = k1000
//!   samples = 1000
//!   seed = 2026
//!   integrator = exponential   # optional (below)
//!   vary {
//!     fins.thickness = truncated_normal(mean = 2 mm, sd = 0.05 mm, min = 1.85 mm, max = 2.15 mm)
//!     wind.speed = uniform(min = 2 m/s, max = 8 m/s)
//!     launch.elevation = normal(mean = 85 deg, sd = 0.5 deg)
//!     parachute.main.cd_area = normal(mean = 4 m^2, rel = 0.05)
//!     launch.heading = triangular(min = 85 deg, mode = 90 deg, max = 95 deg)
//!   }
//!   correlations = [correlate("launch.elevation", "wind.speed", 0.3)]
//! }
//! ```
//!
//! Every parameter of an entry is written in one unit; `rel = r` gives the standard
//! deviation (normal, truncated normal) or the half-width (uniform) as the fraction `r` of
//! `|mean|`. Each written parameter value (mean, min, max, mode) is applied to the scenario
//! as an override and checked there, so an unknown path, a wrong unit or a value out of the
//! field's range is reported at check time with the override's span, exactly as for a sweep
//! axis. The correlation matrix must be positive definite: its Cholesky factor is computed
//! here and kept in the IR.
//!
//! `integrator` (optional): `scenario` flies every sample with the scenario's own `run {
//! integrator }`; a name (`dopri5`, `dop853`, `rk4`, `exponential`) flies them with that one.
//! Absent, the samples fly the exponential integrator unless the scenario's `run` block names
//! its integrator: a dispersion's outputs are statistics, and the exponential integrator's
//! differ from a tight-tolerance reference's by orders of magnitude less than their sampling
//! error, at a quarter of DOPRI5's cost (docs/montecarlo.md; a single `run` keeps DOPRI5 as
//! its default, docs/performance.md says why).

use crate::diagnostics::{Diagnostic, did_you_mean};
use crate::syntax::Spanned;
use crate::syntax::ast::{Arg, Block, EntryKind, Value, ValueKind, path_string};
use crate::syntax::print::unit_text;

use super::fields::{self as f, Fields};
use super::ir::*;
use super::scenario::check_scenario;
use super::{Cx, Decls, OtherKind, SetOverride};

/// More samples than this in one dispersion is refused.
pub const MAX_SAMPLES: usize = 10_000_000;

pub(crate) fn check_dispersion(
    cx: &mut Cx,
    b: &Block,
    decls: &Decls,
    program: &Program,
    sets: &[SetOverride],
) -> Option<Dispersion> {
    let name = b.name.as_ref()?;
    let mut fl = Fields::new(cx, format!("dispersion `{}`", name.name), b.header, &b.body);
    let scen_v = fl.required(cx, "scenario", "k1000");
    let samples_v = fl.required(cx, "samples", "1000");
    let seed_v = fl.required(cx, "seed", "2026");
    let corr_v = fl.value("correlations");
    let integrator_v = fl.value("integrator");
    let vary = fl.required_block(cx, "vary");
    fl.finish(cx);
    let samples = samples_v.and_then(|v| f::count(cx, v, 1, MAX_SAMPLES));
    let seed = seed_v.and_then(|v| f::integer(cx, v));
    let scenario_block = scen_v.and_then(|v| find_scenario(cx, v, decls));

    let mut ok = true;
    let mut entries = Vec::new();
    for e in vary.map(|v| v.body.entries.as_slice()).unwrap_or(&[]) {
        let EntryKind::Assign(a) = &e.kind else {
            cx.push(
                Diagnostic::error(
                    "vdl::dispersion::entry",
                    "a dispersion entry is `PATH = DISTRIBUTION(...)`",
                )
                .label(e.span, "not an entry")
                .with_help("e.g. `fins.thickness = normal(mean = 2 mm, sd = 0.05 mm)`"),
            );
            ok = false;
            continue;
        };
        let path = path_string(&a.path);
        if entries.iter().any(|x: &DispersionEntry| x.path == path) {
            cx.push(
                Diagnostic::error(
                    "vdl::duplicate",
                    format!("`{path}` is varied twice in this dispersion"),
                )
                .label(e.span, "given again here"),
            );
            ok = false;
            continue;
        }
        let Some((distribution, unit, written)) = distribution(cx, &a.value) else {
            ok = false;
            continue;
        };
        // Every written parameter goes through the scenario as an override.
        if let Some((sb, _)) = &scenario_block {
            let before = cx.diags.len();
            for v in written {
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
        entries.push(DispersionEntry {
            path,
            span: e.span,
            unit,
            distribution,
        });
    }
    if vary.is_some() && entries.is_empty() && ok {
        cx.push(
            Diagnostic::error("vdl::dispersion::empty", "the dispersion varies nothing")
                .label(b.header, "add `PATH = DISTRIBUTION(...)` lines to `vary`"),
        );
        return None;
    }
    let correlations = match corr_v {
        None => Some(Vec::new()),
        Some(v) => correlations(cx, v, &entries),
    };
    let cholesky = match &correlations {
        Some(c) if !c.is_empty() => {
            let n = entries.len();
            let mut r = vec![0.0; n * n];
            for i in 0..n {
                r[i * n + i] = 1.0;
            }
            for c in c {
                r[c.a * n + c.b] = c.rho;
                r[c.b * n + c.a] = c.rho;
            }
            match cholesky(&r, n) {
                Some(l) => Some(l),
                None => {
                    let mut d = Diagnostic::error(
                        "vdl::dispersion::correlation",
                        "the correlation matrix is not positive definite",
                    )
                    .with_help(
                        "no set of random variables has these correlations together: \
                         weaken them (|rho| < 1, and a chain a~b, b~c bounds a~c)",
                    );
                    if let Some(v) = corr_v {
                        d = d.label(v.span, "these correlations");
                    }
                    cx.push(d);
                    None
                }
            }
        }
        Some(_) => Some(Vec::new()),
        None => None,
    };
    let (sb, _) = scenario_block?;
    let integrator = match integrator_v {
        Some(v) => {
            let mut options: Vec<(&'static str, Option<Integrator>)> = vec![("scenario", None)];
            options.extend(Integrator::NAMES.iter().map(|&(n, i)| (n, Some(i))));
            f::keyword(cx, v, &options)
        }
        None if names_integrator(sb) => Some(None),
        None => Some(Some(Integrator::Exponential)),
    };
    let scen_name = sb.name.as_ref().map(|n| n.name.clone());
    let idx = scen_name.and_then(|n| program.scenarios.iter().position(|s| s.name.value == n));
    if !ok {
        return None;
    }
    Some(Dispersion {
        name: Spanned::new(name.name.clone(), name.span),
        span: b.header,
        scenario: idx?,
        samples: samples?,
        seed: seed?,
        entries,
        correlations: correlations?,
        cholesky: cholesky?,
        integrator: integrator?,
    })
}

/// Does the scenario's `run` block name its integrator? Then a dispersion without an
/// `integrator` field keeps it; otherwise its samples fly the exponential integrator, whose
/// statistics agree with a tight-tolerance reference within their sampling error at a
/// quarter of DOPRI5's cost (docs/montecarlo.md, `tools/mc_reference.py`).
fn names_integrator(scenario: &Block) -> bool {
    scenario.body.entries.iter().any(|e| {
        matches!(&e.kind, EntryKind::Block(run) if run.kind.name == "run"
        && run.body.entries.iter().any(|e| {
            matches!(&e.kind, EntryKind::Assign(a)
                if a.path.len() == 1 && a.path[0].name == "integrator")
        }))
    })
}

/// The scenario block a dispersion names (with its index in `decls.scenarios`).
fn find_scenario<'t>(cx: &mut Cx, v: &Value, decls: &Decls<'t>) -> Option<(&'t Block, usize)> {
    let others = [OtherKind {
        kind: "vehicle",
        blocks: &decls.vehicles,
        label: Some("a dispersion varies a scenario"),
        help: Some("declare a scenario that flies this vehicle and vary that"),
    }];
    super::reference(cx, v, "scenario", &decls.scenarios, &others).map(|i| (decls.scenarios[i], i))
}

/// A distribution call: the distribution (in the written unit), the unit's text and the
/// parameter values to check as overrides.
fn distribution<'v>(cx: &mut Cx, v: &'v Value) -> Option<(DispersionLaw, String, Vec<&'v Value>)> {
    let usage = |cx: &mut Cx, span, msg: String| {
        cx.push(
            Diagnostic::error("vdl::dispersion::distribution", msg)
                .label(span, "here")
                .with_help(
                    "write `normal(mean = M, sd = S)`, `normal(mean = M, rel = R)`, \
                     `uniform(min = A, max = B)`, `uniform(mean = M, rel = R)`, \
                     `truncated_normal(mean = M, sd = S, min = A, max = B)` or \
                     `triangular(min = A, mode = C, max = B)`",
                ),
        );
    };
    let ValueKind::Call { name, args } = &v.kind else {
        usage(
            cx,
            v.span,
            format!("expected a distribution, found {}", v.describe()),
        );
        return None;
    };
    let kinds: &[(&str, &[&str])] = &[
        ("normal", &["mean", "sd", "rel"]),
        ("uniform", &["min", "max", "mean", "rel"]),
        ("truncated_normal", &["mean", "sd", "rel", "min", "max"]),
        ("triangular", &["min", "mode", "max"]),
    ];
    let Some((_, allowed)) = kinds.iter().find(|(k, _)| *k == name.name) else {
        let mut d = Diagnostic::error(
            "vdl::dispersion::distribution",
            format!("unknown distribution `{}`", name.name),
        )
        .label(name.span, "not a distribution");
        d = match did_you_mean(&name.name, kinds.iter().map(|(k, _)| *k)) {
            Some(s) => d.with_help(format!("did you mean `{s}`?")),
            None => d.with_help("the distributions: normal, uniform, truncated_normal, triangular"),
        };
        cx.push(d);
        return None;
    };
    // Named arguments only, each once, each known.
    let mut got: Vec<(&str, &Arg)> = Vec::new();
    for a in args {
        let Some(n) = &a.name else {
            usage(
                cx,
                a.value.span,
                "a distribution's parameters are named (`mean = ...`)".into(),
            );
            return None;
        };
        if !allowed.contains(&n.name.as_str()) {
            let mut d = Diagnostic::error(
                "vdl::dispersion::distribution",
                format!("`{}` has no parameter `{}`", name.name, n.name),
            )
            .label(n.span, "unknown parameter");
            d = match did_you_mean(&n.name, allowed.iter().copied()) {
                Some(s) => d.with_help(format!("did you mean `{s}`?")),
                None => d.with_help(format!("its parameters: {}", allowed.join(", "))),
            };
            cx.push(d);
            return None;
        }
        if got.iter().any(|(k, _)| *k == n.name) {
            usage(cx, n.span, format!("`{}` is given twice", n.name));
            return None;
        }
        got.push((n.name.as_str(), a));
    }
    let arg = |k: &str| got.iter().find(|(n, _)| *n == k).map(|(_, a)| &a.value);
    // The unit: every dimensional parameter in the same one (`rel` is a plain number).
    let mut unit: Option<String> = None;
    for (k, a) in &got {
        let ValueKind::Quantity { unit: u, .. } = &a.value.kind else {
            usage(
                cx,
                a.value.span,
                format!(
                    "`{k}` is a number or a quantity, found {}",
                    a.value.describe()
                ),
            );
            return None;
        };
        if *k == "rel" {
            if u.is_some() {
                usage(
                    cx,
                    a.value.span,
                    "`rel` is a plain fraction of the mean (0.05 for 5 %)".into(),
                );
                return None;
            }
            continue;
        }
        let text = u.as_ref().map(unit_text).unwrap_or_default();
        match &unit {
            None => unit = Some(text),
            Some(first) if *first != text => {
                cx.push(
                    Diagnostic::error(
                        "vdl::dispersion::unit",
                        format!(
                            "the parameters of one distribution are written in one unit (`{first}` and `{text}`)"
                        ),
                    )
                    .label(a.value.span, format!("in `{text}`")),
                );
                return None;
            }
            Some(_) => {}
        }
    }
    let num = |k: &str| -> Option<f64> {
        match &arg(k)?.kind {
            ValueKind::Quantity { number, .. } => Some(number.value),
            _ => None,
        }
    };
    let need = |cx: &mut Cx, k: &str| -> Option<f64> {
        let x = num(k);
        if x.is_none() {
            usage(cx, v.span, format!("`{}` needs `{k}`", name.name));
        }
        x
    };
    let bad = |cx: &mut Cx, k: &str, msg: String| {
        let span = arg(k).map_or(v.span, |a| a.span);
        cx.push(Diagnostic::error("vdl::dispersion::parameter", msg).label(span, "here"));
    };
    // sd from `sd` or `rel`, exactly one of them.
    let spread = |cx: &mut Cx, mean: f64| -> Option<f64> {
        let (sd, rel) = (num("sd"), num("rel"));
        let s = match (sd, rel) {
            (Some(s), None) => s,
            (None, Some(r)) => {
                if r < 0.0 {
                    bad(cx, "rel", format!("`rel` is negative ({r})"));
                    return None;
                }
                r * mean.abs()
            }
            (Some(_), Some(_)) => {
                usage(cx, v.span, "give `sd` or `rel`, not both".into());
                return None;
            }
            (None, None) => {
                usage(cx, v.span, format!("`{}` needs `sd` or `rel`", name.name));
                return None;
            }
        };
        if s.is_nan() || s <= 0.0 || !s.is_finite() {
            let k = if sd.is_some() { "sd" } else { "rel" };
            bad(cx, k, format!("the spread must be positive, found {s}"));
            return None;
        }
        Some(s)
    };
    let ordered = |cx: &mut Cx, lo: f64, hi: f64| -> bool {
        if lo < hi {
            true
        } else {
            bad(
                cx,
                "min",
                format!("the bounds are inverted or empty: min = {lo} is not below max = {hi}"),
            );
            false
        }
    };
    let d = match name.name.as_str() {
        "normal" => {
            let mean = need(cx, "mean")?;
            DispersionLaw::Normal {
                mean,
                sd: spread(cx, mean)?,
            }
        }
        "uniform" => match (num("min"), num("max"), num("mean"), num("rel")) {
            (Some(lo), Some(hi), None, None) => {
                if !ordered(cx, lo, hi) {
                    return None;
                }
                DispersionLaw::Uniform { min: lo, max: hi }
            }
            (None, None, Some(m), Some(r)) => {
                if r.is_nan() || r <= 0.0 {
                    bad(cx, "rel", format!("`rel` must be positive, found {r}"));
                    return None;
                }
                let h = r * m.abs();
                if h.is_nan() || h <= 0.0 {
                    bad(
                        cx,
                        "mean",
                        "a relative width around a zero mean is empty".into(),
                    );
                    return None;
                }
                DispersionLaw::Uniform {
                    min: m - h,
                    max: m + h,
                }
            }
            _ => {
                usage(
                    cx,
                    v.span,
                    "`uniform` takes `min` and `max`, or `mean` and `rel`".into(),
                );
                return None;
            }
        },
        "truncated_normal" => {
            let mean = need(cx, "mean")?;
            let sd = spread(cx, mean)?;
            let (lo, hi) = (need(cx, "min")?, need(cx, "max")?);
            if !ordered(cx, lo, hi) {
                return None;
            }
            if !(lo <= mean && mean <= hi) {
                bad(
                    cx,
                    "mean",
                    format!("the mean {mean} is outside [min, max] = [{lo}, {hi}]"),
                );
                return None;
            }
            DispersionLaw::TruncatedNormal {
                mean,
                sd,
                min: lo,
                max: hi,
            }
        }
        _ => {
            let (lo, c, hi) = (need(cx, "min")?, need(cx, "mode")?, need(cx, "max")?);
            if !ordered(cx, lo, hi) {
                return None;
            }
            if !(lo <= c && c <= hi) {
                bad(
                    cx,
                    "mode",
                    format!("the mode {c} is outside [min, max] = [{lo}, {hi}]"),
                );
                return None;
            }
            DispersionLaw::Triangular {
                min: lo,
                mode: c,
                max: hi,
            }
        }
    };
    let written: Vec<&Value> = ["mean", "min", "mode", "max"]
        .iter()
        .filter_map(|k| arg(k))
        .collect();
    Some((d, unit.unwrap_or_default(), written))
}

/// `correlations = [correlate("PATH_A", "PATH_B", RHO), ...]`.
fn correlations(cx: &mut Cx, v: &Value, entries: &[DispersionEntry]) -> Option<Vec<Correlation>> {
    let usage = |cx: &mut Cx, span, msg: String| {
        cx.push(
            Diagnostic::error("vdl::dispersion::correlation", msg)
                .label(span, "here")
                .with_help("write `correlations = [correlate(\"motor.a\", \"motor.b\", 0.6)]`"),
        );
    };
    let ValueKind::List(items) = &v.kind else {
        usage(
            cx,
            v.span,
            format!(
                "expected a list of `correlate(...)`, found {}",
                v.describe()
            ),
        );
        return None;
    };
    let mut out: Vec<Correlation> = Vec::new();
    let mut ok = true;
    for it in items {
        let ValueKind::Call { name, args } = &it.kind else {
            usage(
                cx,
                it.span,
                "expected `correlate(\"PATH\", \"PATH\", RHO)`".into(),
            );
            ok = false;
            continue;
        };
        if name.name != "correlate" || args.len() != 3 || args.iter().any(|a| a.name.is_some()) {
            usage(
                cx,
                it.span,
                "expected `correlate(\"PATH\", \"PATH\", RHO)`".into(),
            );
            ok = false;
            continue;
        }
        let mut idx = [0usize; 2];
        let mut found = true;
        for (k, a) in args[..2].iter().enumerate() {
            let ValueKind::Str(p) = &a.value.kind else {
                usage(
                    cx,
                    a.value.span,
                    "the paths of a correlation are strings".into(),
                );
                found = false;
                continue;
            };
            match entries.iter().position(|e| e.path == *p) {
                Some(i) => idx[k] = i,
                None => {
                    let mut d = Diagnostic::error(
                        "vdl::dispersion::correlation",
                        format!("`{p}` is not varied in this dispersion"),
                    )
                    .label(a.value.span, "not an entry of `vary`");
                    if let Some(s) = did_you_mean(p, entries.iter().map(|e| e.path.as_str())) {
                        d = d.with_help(format!("did you mean `{s}`?"));
                    }
                    cx.push(d);
                    found = false;
                }
            }
        }
        let rho = match &args[2].value.kind {
            ValueKind::Quantity { number, unit: None } => number.value,
            _ => {
                usage(
                    cx,
                    args[2].value.span,
                    "the correlation is a plain number".into(),
                );
                ok = false;
                continue;
            }
        };
        if !found {
            ok = false;
            continue;
        }
        if idx[0] == idx[1] {
            usage(
                cx,
                it.span,
                "a correlation joins two different entries".into(),
            );
            ok = false;
            continue;
        }
        if !(rho > -1.0 && rho < 1.0) {
            cx.push(
                Diagnostic::error(
                    "vdl::dispersion::correlation",
                    format!("a correlation is strictly between -1 and 1, found {rho}"),
                )
                .label(args[2].value.span, "out of range")
                .with_help(
                    "a correlation of ±1 is one input, not two: vary one and derive the other",
                ),
            );
            ok = false;
            continue;
        }
        let (a, b) = (idx[0].min(idx[1]), idx[0].max(idx[1]));
        if out.iter().any(|c| c.a == a && c.b == b) {
            usage(cx, it.span, "this pair is correlated twice".into());
            ok = false;
            continue;
        }
        out.push(Correlation {
            a,
            b,
            rho,
            span: it.span,
        });
    }
    ok.then_some(out)
}

/// The lower-triangular Cholesky factor of the symmetric `n x n` matrix `a` (row-major), or
/// `None` when `a` is not positive definite (a pivot at or below `1e-12`, the matrix being a
/// correlation matrix of unit diagonal). Golub & Van Loan, "Matrix Computations", 4th ed.,
/// Algorithm 4.2.1 (the outer-product form written row by row).
pub fn cholesky(a: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            if i == j {
                if s.is_nan() || s <= 1e-12 {
                    return None;
                }
                l[i * n + i] = s.sqrt();
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
    }
    Some(l)
}
