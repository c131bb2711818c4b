//! The canonical printer behind `flexflight fmt`: two-space indentation, one entry per line,
//! `a = b` with single spaces, units in canonical order (`kg/m^3`), comments and single blank
//! lines kept. Numbers are printed exactly as written, so formatting never changes a value.
//! Invariant (tested on every shipped file): `print(parse(print(parse(x)))) == print(parse(x))`
//! and both trees are equal up to spans.

use super::ast::*;

/// Print a whole file canonically.
pub fn print_tree(tree: &SourceTree) -> String {
    let mut out = String::new();
    print_body(&mut out, &tree.body, 0, true);
    out
}

fn indent(out: &mut String, level: usize) {
    for _ in 0..level {
        out.push_str("  ");
    }
}

fn print_comment(out: &mut String, c: &Comment) {
    out.push('#');
    out.push_str(c.text.trim_end());
}

fn print_body(out: &mut String, body: &Body, level: usize, top: bool) {
    for (k, e) in body.entries.iter().enumerate() {
        let is_block = matches!(e.kind, EntryKind::Block(_));
        let prev_block = k > 0 && matches!(body.entries[k - 1].kind, EntryKind::Block(_));
        // Top-level blocks are always separated by one blank line.
        let blank = k > 0 && (e.trivia.blank_before || (top && (is_block || prev_block)));
        if blank {
            out.push('\n');
        }
        print_comment_lines(out, &e.trivia.leading, level);
        if e.trivia.blank_after_leading && !e.trivia.leading.is_empty() {
            out.push('\n');
        }
        indent(out, level);
        print_entry(out, &e.kind, level);
        if let Some(c) = &e.trivia.trailing {
            out.push(' ');
            print_comment(out, c);
        }
        out.push('\n');
    }
    if !body.trailing_comments.is_empty() {
        if body.blank_before_trailing && !body.entries.is_empty() {
            out.push('\n');
        }
        print_comment_lines(out, &body.trailing_comments, level);
    }
}

/// Own-line comments, keeping single blank lines between them.
fn print_comment_lines(out: &mut String, comments: &[Comment], level: usize) {
    for (k, c) in comments.iter().enumerate() {
        if k > 0 && c.blank_before {
            out.push('\n');
        }
        indent(out, level);
        print_comment(out, c);
        out.push('\n');
    }
}

fn print_entry(out: &mut String, kind: &EntryKind, level: usize) {
    match kind {
        EntryKind::Import { path, .. } => {
            out.push_str("import ");
            print_string(out, path);
        }
        EntryKind::Assign(a) => {
            out.push_str(&a.path_string());
            out.push_str(" = ");
            print_value(out, &a.value);
        }
        EntryKind::Block(b) => {
            out.push_str(&b.kind.name);
            if let Some(n) = &b.name {
                out.push(' ');
                out.push_str(&n.name);
            }
            if b.body.entries.is_empty() && b.body.trailing_comments.is_empty() {
                out.push_str(" {}");
            } else {
                out.push_str(" {\n");
                print_body(out, &b.body, level + 1, false);
                indent(out, level);
                out.push('}');
            }
        }
    }
}

fn print_string(out: &mut String, s: &str) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            c => out.push(c),
        }
    }
    out.push('"');
}

/// The canonical text of a unit expression: positive exponents first (`*`), then `/`.
pub fn unit_text(u: &UnitExpr) -> String {
    let mut s = String::new();
    let pos: Vec<_> = u.factors.iter().filter(|f| f.exponent > 0).collect();
    let neg: Vec<_> = u.factors.iter().filter(|f| f.exponent < 0).collect();
    if pos.is_empty() {
        for (k, f) in neg.iter().enumerate() {
            if k > 0 {
                s.push('*');
            }
            s.push_str(&format!("{}^{}", f.name.name, f.exponent));
        }
        return s;
    }
    for (k, f) in pos.iter().enumerate() {
        if k > 0 {
            s.push('*');
        }
        s.push_str(&f.name.name);
        if f.exponent != 1 {
            s.push_str(&format!("^{}", f.exponent));
        }
    }
    for f in neg {
        s.push('/');
        s.push_str(&f.name.name);
        if f.exponent != -1 {
            s.push_str(&format!("^{}", -f.exponent));
        }
    }
    s
}

/// Print one value canonically (also used by diagnostics and `plan` output).
pub fn print_value(out: &mut String, v: &Value) {
    match &v.kind {
        ValueKind::Quantity { number, unit } => {
            out.push_str(&number.text);
            if let Some(u) = unit {
                out.push(' ');
                out.push_str(&unit_text(u));
            }
        }
        ValueKind::Vector { components, unit } => {
            out.push('(');
            for (k, c) in components.iter().enumerate() {
                if k > 0 {
                    out.push_str(", ");
                }
                out.push_str(&c.text);
            }
            out.push(')');
            if let Some(u) = unit {
                out.push(' ');
                out.push_str(&unit_text(u));
            }
        }
        ValueKind::Str(s) => print_string(out, s),
        ValueKind::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
        ValueKind::Name(n) => out.push_str(&n.name),
        ValueKind::Call { name, args } => {
            out.push_str(&name.name);
            out.push('(');
            for (k, a) in args.iter().enumerate() {
                if k > 0 {
                    out.push_str(", ");
                }
                if let Some(n) = &a.name {
                    out.push_str(&n.name);
                    out.push_str(" = ");
                }
                print_value(out, &a.value);
            }
            out.push(')');
        }
        ValueKind::List(items) => {
            out.push('[');
            for (k, it) in items.iter().enumerate() {
                if k > 0 {
                    out.push_str(", ");
                }
                print_value(out, it);
            }
            out.push(']');
        }
    }
}

/// A value as canonical text.
pub fn value_text(v: &Value) -> String {
    let mut s = String::new();
    print_value(&mut s, v);
    s
}
