//! Variant overrides: `with { fins.thickness = 0.4 mm }` in a scenario, `--set PATH=VALUE`
//! on the command line, and the axes of a sweep all use the same mechanism: the dotted path
//! is applied to the syntax tree of the vehicle (or scenario) *before* it is checked, so an
//! override is checked exactly like a value written in place, and a bad path is reported by
//! the same unknown-field logic (with "did you mean") at the override's span.

use crate::diagnostics::Diagnostic;
use crate::syntax::ast::{
    Assign, Block, Body, Entry, EntryKind, Ident, Trivia, Value, path_string,
};

/// First path segments that address the scenario rather than its vehicle.
pub const SCENARIO_ROOTS: &[&str] = &[
    "initial",
    "run",
    "stimuli",
    "launch",
    "wind",
    "tunnel",
    "parachute",
    "motor_scale",
];

/// Does this path address a scenario field (rather than the vehicle)?
pub fn is_scenario_path(path: &[Ident]) -> bool {
    path.first()
        .is_some_and(|p| SCENARIO_ROOTS.contains(&p.name.as_str()))
}

/// Apply `path = value` to a block body. Missing intermediate blocks are created (the
/// checker then reports them if they are not blocks of that kind).
pub fn apply(body: &mut Body, path: &[Ident], value: &Value) -> Result<(), Diagnostic> {
    let Some((last, parents)) = path.split_last() else {
        return Ok(());
    };
    let span = path.first().map_or(value.span, |f| f.span.to(value.span));
    let mut cur = body;
    for (depth, seg) in parents.iter().enumerate() {
        // `KIND.NAME`: the kind before the name of a block of that kind says nothing more
        // (`parachute.main.cd_area` is the block `parachute main`).
        let next = parents.get(depth + 1).unwrap_or(last);
        let kind_of_next = cur.entries.iter().any(|e| {
            matches!(&e.kind, EntryKind::Block(b) if b.kind.name == seg.name
                && b.name.as_ref().is_some_and(|n| n.name == next.name))
        });
        if kind_of_next && depth + 1 < parents.len() {
            continue;
        }
        // Is the segment a plain field? Then the path goes through a value: an error.
        let is_field = cur.entries.iter().any(|e| {
            matches!(&e.kind, EntryKind::Assign(a) if a.path.len() == 1 && a.path[0].name == seg.name)
        });
        if is_field {
            return Err(Diagnostic::error(
                "vdl::override::path",
                format!(
                    "`{}` is a field, not a block: `{}` cannot go inside it",
                    path_string(&path[..=depth]),
                    path_string(path)
                ),
            )
            .label(seg.span, "a field, not a block"));
        }
        let idx = find_block(cur, &seg.name);
        let idx = match idx {
            Some(i) => i,
            None => {
                cur.entries.push(Entry {
                    trivia: Trivia::default(),
                    kind: EntryKind::Block(Block {
                        kind: seg.clone(),
                        name: None,
                        body: Body::default(),
                        header: seg.span,
                    }),
                    span,
                });
                cur.entries.len() - 1
            }
        };
        let Some(EntryKind::Block(b)) = cur.entries.get_mut(idx).map(|e| &mut e.kind) else {
            return Ok(());
        };
        cur = &mut b.body;
    }
    if find_block(cur, &last.name).is_some() {
        return Err(Diagnostic::error(
            "vdl::override::path",
            format!("`{}` is a block, not a field", path_string(path)),
        )
        .label(last.span, "this names a block")
        .with_help(format!(
            "set one of its fields, e.g. `{}.enabled = false`",
            path_string(path)
        )));
    }
    let new = Assign {
        path: vec![last.clone()],
        value: value.clone(),
    };
    for e in &mut cur.entries {
        if let EntryKind::Assign(a) = &mut e.kind {
            if a.path.len() == 1 && a.path[0].name == last.name {
                // Keep the override's spans so errors point at the override.
                *a = new;
                e.span = span;
                return Ok(());
            }
        }
    }
    cur.entries.push(Entry {
        trivia: Trivia::default(),
        kind: EntryKind::Assign(new),
        span,
    });
    Ok(())
}

fn find_block(body: &Body, seg: &str) -> Option<usize> {
    let by_name = body.entries.iter().position(
        |e| matches!(&e.kind, EntryKind::Block(b) if b.name.as_ref().is_some_and(|n| n.name == seg)),
    );
    // A block of that kind: the unnamed one first (`fins.thickness` is the unnamed `fins`
    // block's, whatever named `fins canards { }` blocks stand before it).
    let unnamed = || {
        body.entries.iter().position(
            |e| matches!(&e.kind, EntryKind::Block(b) if b.kind.name == seg && b.name.is_none()),
        )
    };
    by_name.or_else(unnamed).or_else(|| {
        body.entries
            .iter()
            .position(|e| matches!(&e.kind, EntryKind::Block(b) if b.kind.name == seg))
    })
}
