//! Reading a block's entries as typed fields.
//!
//! A [`Fields`] reader wraps one block body. Each typed getter marks the entry it reads as
//! used and remembers the field name, so [`Fields::finish`] can report every entry nobody
//! asked for as unknown, with a "did you mean" drawn from the names that were asked for.
//! The schema of the language is therefore exactly the code that reads it.

use std::cell::RefCell;
use std::collections::HashMap;

use crate::diagnostics::{Diagnostic, did_you_mean};
use crate::syntax::Span;
use crate::syntax::ast::{Block, Body, EntryKind, Value, ValueKind};
use crate::units::{self, Dim, Unit};

use super::Cx;
use super::ir::{Q, V3};

/// What one [`Fields`] reader asked for: the schema of one block as the checker reads it.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockSchema {
    /// The block's header (`kind NAME`) in the checked sources.
    pub header: Span,
    /// Every field the reader asked for, required or not.
    pub fields: Vec<&'static str>,
    /// The fields it requires.
    pub required: Vec<&'static str>,
    /// The sub-blocks it asked for.
    pub blocks: Vec<&'static str>,
}

/// What [`record_schema`] saw: one entry per block read, and every keyword option offered.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SchemaRecord {
    pub blocks: Vec<BlockSchema>,
    /// The options of every keyword field read (`dryden`, `von_karman`, `stop`, ...).
    pub keywords: Vec<&'static str>,
}

thread_local! {
    static RECORDER: RefCell<Option<SchemaRecord>> = const { RefCell::new(None) };
}

/// Runs `f` (a check) and returns what the [`Fields`] readers on this thread asked for
/// while it ran: the language's schema is the code that reads it, and this is how tests
/// compare the README's field tables with it. Costs nothing when not recording.
pub fn record_schema<R>(f: impl FnOnce() -> R) -> (R, SchemaRecord) {
    let previous = RECORDER.with(|r| r.replace(Some(SchemaRecord::default())));
    let out = f();
    let record = RECORDER.with(|r| r.replace(previous)).unwrap_or_default();
    (out, record)
}

fn record(f: impl FnOnce(&mut SchemaRecord)) {
    RECORDER.with(|r| {
        if let Some(rec) = r.borrow_mut().as_mut() {
            f(rec);
        }
    });
}

pub struct Fields<'b> {
    what: String,
    header: Span,
    entries: Vec<(&'b EntryKind, Span, bool)>,
    known_fields: Vec<&'static str>,
    known_blocks: Vec<&'static str>,
    /// Required fields reported missing (a misspelling of one is reported once, as unknown).
    missing: Vec<&'static str>,
    /// Every field asked for as required (for [`record_schema`]).
    required_names: Vec<&'static str>,
}

/// Unnamed blocks a body may hold any number of times (`body { launch_lug { } launch_lug
/// { } }`, transitions fore to aft): not duplicates.
const REPEATABLE: [&str; 3] = ["launch_lug", "rail_button", "transition"];

impl<'b> Fields<'b> {
    /// Wrap a body; reports duplicated fields and blocks at once.
    pub fn new(cx: &mut Cx, what: impl Into<String>, header: Span, body: &'b Body) -> Self {
        let what = what.into();
        let mut seen: HashMap<String, Span> = HashMap::new();
        let mut entries = Vec::new();
        for e in &body.entries {
            let key = match &e.kind {
                EntryKind::Assign(a) => Some((a.path_string(), a.path_span())),
                EntryKind::Block(b) => Some((
                    match &b.name {
                        Some(n) => format!("{} {}", b.kind.name, n.name),
                        None => b.kind.name.clone(),
                    },
                    b.header,
                )),
                EntryKind::Import { .. } => None,
            };
            // Unnamed blocks that may be given any number of times.
            let repeats = matches!(&e.kind, EntryKind::Block(b)
                if b.name.is_none() && REPEATABLE.contains(&b.kind.name.as_str()));
            if let Some((key, span)) = key.filter(|_| !repeats) {
                if let Some(first) = seen.get(&key) {
                    cx.push(
                        Diagnostic::error(
                            "vdl::duplicate",
                            format!("`{key}` is given twice in {what}"),
                        )
                        .label(span, "given again here")
                        .label(*first, "first given here")
                        .with_help("remove one of them"),
                    );
                    continue;
                }
                seen.insert(key, span);
            }
            entries.push((&e.kind, e.span, false));
        }
        Fields {
            what,
            header,
            entries,
            known_fields: Vec::new(),
            known_blocks: Vec::new(),
            missing: Vec::new(),
            required_names: Vec::new(),
        }
    }

    pub fn header(&self) -> Span {
        self.header
    }

    /// The value of a plain field, if written.
    pub fn value(&mut self, name: &'static str) -> Option<&'b Value> {
        self.known_fields.push(name);
        for (kind, _, used) in &mut self.entries {
            if let EntryKind::Assign(a) = kind {
                if a.path.len() == 1 && a.path[0].name == name {
                    *used = true;
                    return Some(&a.value);
                }
            }
        }
        None
    }

    /// The value of a required field; reports `vdl::field::missing` if absent.
    pub fn required(
        &mut self,
        cx: &mut Cx,
        name: &'static str,
        example: &str,
    ) -> Option<&'b Value> {
        self.required_names.push(name);
        let v = self.value(name);
        if v.is_none() {
            self.missing.push(name);
            cx.push(
                Diagnostic::error(
                    "vdl::field::missing",
                    format!("{} needs {} `{name}` field", self.what, article(name)),
                )
                .label(self.header, format!("`{name}` is missing here"))
                .with_help(format!("add a line such as `{name} = {example}`")),
            );
        }
        v
    }

    /// The single block of a kind, if written.
    pub fn block(&mut self, kind: &'static str) -> Option<&'b Block> {
        self.blocks(kind).into_iter().next()
    }

    /// A required block; reports `vdl::block::missing` if absent.
    pub fn required_block(&mut self, cx: &mut Cx, kind: &'static str) -> Option<&'b Block> {
        let b = self.block(kind);
        if b.is_none() {
            cx.push(
                Diagnostic::error(
                    "vdl::block::missing",
                    format!(
                        "{} needs {} `{kind} {{ ... }}` block",
                        self.what,
                        article(kind)
                    ),
                )
                .label(self.header, format!("no `{kind}` block in here")),
            );
        }
        b
    }

    /// All blocks of a kind, in order.
    pub fn blocks(&mut self, kind: &'static str) -> Vec<&'b Block> {
        self.known_blocks.push(kind);
        let mut out = Vec::new();
        for (k, _, used) in &mut self.entries {
            if let EntryKind::Block(b) = k {
                if b.kind.name == kind {
                    *used = true;
                    out.push(b);
                }
            }
        }
        out
    }

    /// Report everything nobody read.
    pub fn finish(self, cx: &mut Cx) {
        record(|r| {
            let mut fields = self.known_fields.clone();
            fields.dedup();
            r.blocks.push(BlockSchema {
                header: self.header,
                fields,
                required: self.required_names.clone(),
                blocks: self.known_blocks.clone(),
            })
        });
        for (kind, span, used) in self.entries {
            if used {
                continue;
            }
            match kind {
                EntryKind::Import { path_span, .. } => cx.push(
                    Diagnostic::error(
                        "vdl::import::placement",
                        format!("`import` may only appear at the top of a file, not in {}", self.what),
                    )
                    .label(*path_span, "move this import to the top level"),
                ),
                EntryKind::Assign(a) if a.path.len() > 1 => cx.push(
                    Diagnostic::error(
                        "vdl::field::dotted",
                        format!("dotted paths like `{}` are only allowed in `with`, `grid` and `zip` blocks", a.path_string()),
                    )
                    .label(a.path_span(), "dotted path here")
                    .with_help("write the field inside its block instead"),
                ),
                EntryKind::Assign(a) => {
                    let name = &a.path[0].name;
                    let mut d = Diagnostic::error(
                        "vdl::field::unknown",
                        format!("unknown field `{name}` in {}", self.what),
                    )
                    .label(a.path[0].span, "not a field of this block");
                    let fields = self.known_fields.iter().copied();
                    if let Some(s) = did_you_mean(name, fields) {
                        if self.missing.contains(&s) {
                            // `thicknes = ...` for a required `thickness`: one error, not two.
                            let missing = format!("{} needs {} `{s}` field", self.what, article(s));
                            cx.diags.retain(|d| {
                                !(d.code == "vdl::field::missing"
                                    && d.message == missing
                                    && d.primary_span() == Some(self.header))
                            });
                        }
                        d = d.with_help(format!("did you mean `{s}`?"));
                    } else if self.known_blocks.contains(&name.as_str()) {
                        d = d.with_help(format!("`{name}` is a block: write `{name} {{ ... }}`"));
                    } else {
                        d = d.with_help(format!("known fields: {}", list(&self.known_fields)));
                    }
                    cx.push(d);
                }
                EntryKind::Block(b) => {
                    let name = &b.kind.name;
                    let mut d = Diagnostic::error(
                        "vdl::block::unknown",
                        format!("unknown block `{name}` in {}", self.what),
                    )
                    .label(b.kind.span, "not a block of this kind");
                    if let Some(s) = did_you_mean(name, self.known_blocks.iter().copied()) {
                        d = d.with_help(format!("did you mean `{s}`?"));
                    } else if self.known_fields.contains(&name.as_str()) {
                        d = d.with_help(format!("`{name}` is a field: write `{name} = ...`"));
                    } else if self.known_blocks.is_empty() {
                        d = d.with_help("this block takes no nested blocks");
                    } else {
                        d = d.with_help(format!("known blocks: {}", list(&self.known_blocks)));
                    }
                    let _ = span;
                    cx.push(d);
                }
            }
        }
    }
}

/// "a" or "an" before a field name (`an aero block`, `a mass field`).
fn article(word: &str) -> &'static str {
    if word.starts_with(['a', 'e', 'i', 'o', 'u', 'A', 'E', 'I', 'O', 'U']) {
        "an"
    } else {
        "a"
    }
}

fn list(names: &[&str]) -> String {
    let mut v: Vec<&str> = names.to_vec();
    v.sort_unstable();
    v.dedup();
    v.iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

// ------------------------------------------------------------------------------------------
// Typed values

fn type_error(cx: &mut Cx, v: &Value, expected: &str) {
    cx.push(
        Diagnostic::error(
            "vdl::type::mismatch",
            format!("expected {expected}, found {}", v.describe()),
        )
        .label(v.span, format!("this should be {expected}")),
    );
}

/// Resolve a unit expression to (scale, dimension).
pub fn resolve_unit(cx: &mut Cx, u: &crate::syntax::ast::UnitExpr) -> Option<Unit> {
    let mut unit = Unit::ONE;
    let mut ok = true;
    for f in &u.factors {
        match units::lookup(&f.name.name) {
            Some(base) => unit = unit.times(base.powi(f.exponent)),
            None => {
                let mut d = Diagnostic::error(
                    "vdl::unit::unknown",
                    format!("unknown unit `{}`", f.name.name),
                )
                .label(f.name.span, "not a unit flexflight knows");
                d = match did_you_mean(&f.name.name, units::names()) {
                    Some(s) => d.with_help(format!("did you mean `{s}`?")),
                    None => d.with_help(format!(
                        "known units: {}",
                        units::names().collect::<Vec<_>>().join(", ")
                    )),
                };
                cx.push(d);
                ok = false;
            }
        }
    }
    ok.then_some(unit)
}

fn dim_phrase(dim: Dim) -> String {
    match dim.name() {
        Some(n) => format!("{n} ({})", dim.si_unit()),
        None => format!("a quantity in {}", dim.si_unit()),
    }
}

/// Convert written numbers with an optional unit to SI, checking the dimension.
fn to_si(
    cx: &mut Cx,
    v: &Value,
    unit: Option<&crate::syntax::ast::UnitExpr>,
    dim: Dim,
) -> Option<f64> {
    match unit {
        None if dim == Dim::NONE => Some(1.0),
        None => {
            cx.push(
                Diagnostic::error(
                    "vdl::unit::missing",
                    format!("this number needs a unit of {}", dim_phrase(dim)),
                )
                .label(v.span, "no unit given")
                .with_help(format!("append a unit, e.g. `{}`", example_unit(dim))),
            );
            None
        }
        Some(u) => {
            let unit = resolve_unit(cx, u)?;
            if unit.dim != dim {
                let found = match unit.dim.name() {
                    Some(n) => n.to_string(),
                    None => unit.dim.si_unit(),
                };
                cx.push(
                    Diagnostic::error(
                        "vdl::unit::mismatch",
                        format!("expected {}, found {found}", dim_phrase(dim)),
                    )
                    .label(u.span, format!("this unit is {found}"))
                    .with_help(format!(
                        "use a unit of {}, e.g. `{}`",
                        dim_phrase(dim),
                        example_unit(dim)
                    )),
                );
                return None;
            }
            Some(unit.scale)
        }
    }
}

/// A unit of the dimension to suggest: a named SI unit if the table has one, else the SI
/// unit written out (`kg/m^3`), which is itself valid unit syntax.
fn example_unit(dim: Dim) -> String {
    units::UNITS
        .iter()
        .find(|(_, s, d)| *d == dim && *s == 1.0)
        .or_else(|| units::UNITS.iter().find(|(_, _, d)| *d == dim))
        .map_or_else(|| dim.si_unit(), |(n, _, _)| (*n).to_string())
}

/// A scalar quantity of the given dimension, in SI.
pub fn quantity(cx: &mut Cx, v: &Value, dim: Dim) -> Option<Q> {
    match &v.kind {
        ValueKind::Quantity { number, unit } => {
            let scale = to_si(cx, v, unit.as_ref(), dim)?;
            Some(Q::new(number.value * scale, v.span))
        }
        _ => {
            type_error(cx, v, &dim_phrase(dim));
            None
        }
    }
}

/// A dimensionless number.
pub fn number(cx: &mut Cx, v: &Value) -> Option<Q> {
    quantity(cx, v, Dim::NONE)
}

/// A vector of `n` components of the given dimension, in SI.
pub fn vector(
    cx: &mut Cx,
    v: &Value,
    dim: Dim,
    n: usize,
) -> Option<(Vec<f64>, crate::syntax::Span)> {
    match &v.kind {
        ValueKind::Vector { components, unit } => {
            if components.len() != n {
                cx.push(
                    Diagnostic::error(
                        "vdl::vector::arity",
                        format!("expected {n} components, found {}", components.len()),
                    )
                    .label(
                        v.span,
                        format!("this vector has {} components", components.len()),
                    ),
                );
                return None;
            }
            let scale = to_si(cx, v, unit.as_ref(), dim)?;
            Some((components.iter().map(|c| c.value * scale).collect(), v.span))
        }
        _ => {
            type_error(
                cx,
                v,
                &format!("a vector `(x, y, z) unit` of {}", dim_phrase(dim)),
            );
            None
        }
    }
}

pub fn vector3(cx: &mut Cx, v: &Value, dim: Dim) -> Option<V3> {
    let (c, span) = vector(cx, v, dim, 3)?;
    Some(V3::new([c[0], c[1], c[2]], span))
}

/// A non-negative integer.
pub fn integer(cx: &mut Cx, v: &Value) -> Option<u64> {
    if let ValueKind::Quantity { number, unit: None } = &v.kind {
        let x = number.value;
        if x >= 0.0 && x.fract() == 0.0 && x < 9.0e15 && !number.text.contains(['.', 'e', 'E']) {
            // x is a whole, non-negative number below 2^53: the conversion is exact.
            return Some(x as u64);
        }
    }
    type_error(cx, v, "a whole number");
    None
}

pub fn count(cx: &mut Cx, v: &Value, min: usize, max: usize) -> Option<usize> {
    let n = integer(cx, v)?;
    let n = usize::try_from(n).unwrap_or(usize::MAX);
    if n < min || n > max {
        cx.push(
            Diagnostic::error(
                "vdl::value::range",
                format!("{n} is out of range: expected {min} to {max}"),
            )
            .label(v.span, "out of range"),
        );
        return None;
    }
    Some(n)
}

pub fn boolean(cx: &mut Cx, v: &Value) -> Option<bool> {
    if let ValueKind::Bool(b) = v.kind {
        return Some(b);
    }
    type_error(cx, v, "`true` or `false`");
    None
}

pub fn string(cx: &mut Cx, v: &Value) -> Option<String> {
    if let ValueKind::Str(s) = &v.kind {
        return Some(s.clone());
    }
    type_error(cx, v, "a quoted string");
    None
}

/// Records keyword values a checker function accepts in a form `keyword` does not see (the
/// names of calls such as `power(0.5)`), for the documentation test's schema.
pub fn record_keywords(names: impl Iterator<Item = &'static str>) {
    record(|r| r.keywords.extend(names));
}

/// A keyword from a fixed set.
pub fn keyword<T: Copy>(cx: &mut Cx, v: &Value, options: &[(&'static str, T)]) -> Option<T> {
    record(|r| r.keywords.extend(options.iter().map(|(n, _)| *n)));
    let names: Vec<&str> = options.iter().map(|(n, _)| *n).collect();
    if let ValueKind::Name(id) = &v.kind {
        if let Some((_, t)) = options.iter().find(|(n, _)| *n == id.name) {
            return Some(*t);
        }
        let mut d = Diagnostic::error(
            "vdl::value::keyword",
            format!("`{}` is not one of {}", id.name, list(&names)),
        )
        .label(v.span, "unknown option");
        if let Some(s) = did_you_mean(&id.name, names.iter().copied()) {
            d = d.with_help(format!("did you mean `{s}`?"));
        }
        cx.push(d);
        return None;
    }
    type_error(cx, v, &format!("one of {}", list(&names)));
    None
}

/// Check a condition on a scalar; report `vdl::value::range` with `expected` otherwise.
pub fn check_range(
    q: Option<Q>,
    cx: &mut Cx,
    ok: impl Fn(f64) -> bool,
    expected: &str,
) -> Option<Q> {
    let q = q?;
    if ok(q.value) {
        Some(q)
    } else {
        cx.push(
            Diagnostic::error(
                "vdl::value::range",
                format!("value out of range: expected {expected}"),
            )
            .label(q.span, format!("expected {expected}")),
        );
        None
    }
}

pub fn positive(q: Option<Q>, cx: &mut Cx) -> Option<Q> {
    check_range(q, cx, |x| x > 0.0, "a positive value")
}

pub fn non_negative(q: Option<Q>, cx: &mut Cx) -> Option<Q> {
    check_range(q, cx, |x| x >= 0.0, "a value >= 0")
}
