//! Matrix Market mass/stiffness files with a node table CSV and an optional element CSV.
//!
//! Matrix Market: `%%MatrixMarket matrix coordinate real symmetric|general` (also `integer`
//! or `double` for the field), `%` comment lines, a size line `nrows ncols nnz`, then `nnz`
//! lines `i j value` with 1-based indices. Row/column index `i` is DOF `(i-1) mod 6` of node
//! `(i-1) / 6` in node-table order (the component order given by [`DofOrder`]).
//!
//! Node table CSV: header `id,x,y,z`, then one row per node, positions in metres in the body
//! frame. Node `k` of the table owns matrix rows `6k .. 6k+6`.
//!
//! Element CSV (optional, for plots and reports only): header `id,kind,n1,n2,...` (as many
//! `n` columns as the longest element needs), then rows `id,kind,node ids...` where `kind` is
//! `beam` or `link` (exactly 2 nodes) or `shell` (3 or 4 nodes); trailing empty node fields
//! are allowed. Node ids refer to the node table. Lines starting with `#` are comments.
//!
//! [`DofOrder`]: super::DofOrder

use std::path::Path;

use super::assemble::{RawMatrix, ReadOptions, Storage, build_model, check_unique_ids};
use super::error::{FeReadError, SourceLocation};
use super::read_text;
use crate::structure::fe_model::{Component, Element, ElementKind, FeModel, Node};

/// Reads M, K (Matrix Market), the node table and optionally the element list.
pub fn read_matrix_market_model(
    mass: &Path,
    stiffness: &Path,
    nodes: &Path,
    elements: Option<&Path>,
    opts: &ReadOptions,
) -> Result<FeModel, FeReadError> {
    let (nodes_v, _) = parse_nodes_csv(&read_text(nodes)?, nodes)?;
    let elements_v = match elements {
        Some(p) => parse_elements_csv(&read_text(p)?, p, &nodes_v)?,
        None => Vec::new(),
    };
    let m = parse_matrix_market(&read_text(mass)?, mass)?;
    let k = parse_matrix_market(&read_text(stiffness)?, stiffness)?;
    build_model(nodes_v, elements_v, m, k, opts)
}

/// 1-based column of the byte offset of `token` inside `line` (both from the same string).
fn column_of(line: &str, token: &str) -> usize {
    (token.as_ptr() as usize).saturating_sub(line.as_ptr() as usize) + 1
}

/// Parses a Matrix Market coordinate file into raw entries (0-based indices).
pub fn parse_matrix_market(text: &str, path: &Path) -> Result<RawMatrix, FeReadError> {
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let (hl, header) = lines
        .next()
        .ok_or_else(|| FeReadError::Truncated(SourceLocation::line(path, 1), "empty file"))?;
    let words: Vec<String> = header
        .split_whitespace()
        .map(str::to_ascii_lowercase)
        .collect();
    let w = |k: usize| words.get(k).map(String::as_str).unwrap_or("");
    if w(0) != "%%matrixmarket" || w(1) != "matrix" {
        return Err(FeReadError::UnknownHeader(
            SourceLocation::line(path, hl),
            format!(
                "expected '%%MatrixMarket matrix coordinate real symmetric|general', found '{header}'"
            ),
        ));
    }
    if w(2) != "coordinate" || !matches!(w(3), "real" | "double" | "integer") {
        return Err(FeReadError::Unsupported(
            SourceLocation::line(path, hl),
            format!("only 'coordinate real' Matrix Market files are read, found '{header}'"),
        ));
    }
    let storage = match w(4) {
        "symmetric" => Storage::Symmetric,
        "general" => Storage::General,
        other => {
            return Err(FeReadError::Unsupported(
                SourceLocation::line(path, hl),
                format!("symmetry '{other}' (expected symmetric or general)"),
            ));
        }
    };
    let mut data = lines.filter(|(_, l)| !l.trim_start().starts_with('%') && !l.trim().is_empty());
    let last_line = text.lines().count();
    let (sl, size_line) = data.next().ok_or_else(|| {
        FeReadError::Truncated(SourceLocation::line(path, last_line + 1), "no size line")
    })?;
    let sizes = parse_usizes(size_line, sl, path, 3)?;
    let (nrows, ncols, nnz) = (sizes[0], sizes[1], sizes[2]);
    let mut entries = Vec::with_capacity(nnz);
    for (ln, line) in data {
        if entries.len() == nnz {
            return Err(FeReadError::BadRecord(
                SourceLocation::line(path, ln),
                format!("more entries than the {nnz} declared on line {sl}"),
            ));
        }
        let toks: Vec<&str> = line.split_whitespace().collect();
        if toks.len() != 3 {
            return Err(FeReadError::BadRecord(
                SourceLocation::line(path, ln),
                format!("expected 'row col value', found {} fields", toks.len()),
            ));
        }
        let idx = |t: &str| -> Result<usize, FeReadError> {
            match t.parse::<usize>() {
                Ok(v) if v >= 1 => Ok(v - 1),
                _ => Err(FeReadError::BadNumber(
                    SourceLocation::at(path, ln, column_of(line, t)),
                    format!("'{t}' is not a 1-based index"),
                )),
            }
        };
        let (i, j) = (idx(toks[0])?, idx(toks[1])?);
        let v = parse_real(toks[2], line, ln, path)?;
        if i >= nrows || j >= ncols {
            return Err(FeReadError::IndexOutOfRange(
                SourceLocation::line(path, ln),
                format!("({}, {}) outside {nrows} x {ncols}", i + 1, j + 1),
            ));
        }
        entries.push((i, j, v, ln));
    }
    if entries.len() < nnz {
        return Err(FeReadError::Truncated(
            SourceLocation::line(path, last_line + 1),
            format!(
                "{} of the {nnz} entries declared on line {sl}",
                entries.len()
            ),
        ));
    }
    Ok(RawMatrix {
        path: path.to_path_buf(),
        header_line: sl,
        nrows,
        ncols,
        storage,
        entries,
    })
}

fn parse_usizes(
    line: &str,
    ln: usize,
    path: &Path,
    count: usize,
) -> Result<Vec<usize>, FeReadError> {
    let toks: Vec<&str> = line.split_whitespace().collect();
    if toks.len() != count {
        return Err(FeReadError::BadRecord(
            SourceLocation::line(path, ln),
            format!("expected {count} integers, found '{line}'"),
        ));
    }
    toks.iter()
        .map(|t| {
            t.parse::<usize>().map_err(|_| {
                FeReadError::BadNumber(
                    SourceLocation::at(path, ln, column_of(line, t)),
                    format!("'{t}' is not an integer"),
                )
            })
        })
        .collect()
}

fn parse_real(tok: &str, line: &str, ln: usize, path: &Path) -> Result<f64, FeReadError> {
    let loc = || SourceLocation::at(path, ln, column_of(line, tok));
    let v = super::numbers::parse_nastran_real(tok).ok_or_else(|| {
        FeReadError::BadNumber(loc(), format!("'{}' is not a number", tok.trim()))
    })?;
    if !v.is_finite() {
        return Err(FeReadError::NonFinite(loc(), format!("'{}'", tok.trim())));
    }
    Ok(v)
}

/// Splits a CSV line on commas, keeping each field's 1-based column.
fn csv_fields(line: &str) -> Vec<(&str, usize)> {
    let mut out = Vec::new();
    let mut start = 0;
    for (k, c) in line.char_indices() {
        if c == ',' {
            out.push((line[start..k].trim(), start + 1));
            start = k + 1;
        }
    }
    out.push((line[start..].trim(), start + 1));
    out
}

/// Parses the node table (`id,x,y,z`). Returns the nodes and the line of each.
pub fn parse_nodes_csv(text: &str, path: &Path) -> Result<(Vec<Node>, Vec<usize>), FeReadError> {
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (hl, header) = rows
        .next()
        .ok_or_else(|| FeReadError::Truncated(SourceLocation::line(path, 1), "empty node table"))?;
    let names: Vec<String> = csv_fields(header)
        .iter()
        .map(|(f, _)| f.to_ascii_lowercase())
        .collect();
    if names != ["id", "x", "y", "z"] {
        return Err(FeReadError::UnknownHeader(
            SourceLocation::line(path, hl),
            format!("expected 'id,x,y,z', found '{header}'"),
        ));
    }
    let mut nodes = Vec::new();
    let mut lines = Vec::new();
    for (ln, line) in rows {
        let f = csv_fields(line);
        if f.len() != 4 {
            return Err(FeReadError::BadRecord(
                SourceLocation::line(path, ln),
                format!("expected 4 fields 'id,x,y,z', found {}", f.len()),
            ));
        }
        let id = f[0].0.parse::<u64>().map_err(|_| {
            FeReadError::BadNumber(
                SourceLocation::at(path, ln, f[0].1),
                format!("node id '{}'", f[0].0),
            )
        })?;
        let mut position = [0.0; 3];
        for (k, p) in position.iter_mut().enumerate() {
            let (t, col) = f[k + 1];
            *p = super::numbers::parse_nastran_real(t).ok_or_else(|| {
                FeReadError::BadNumber(
                    SourceLocation::at(path, ln, col),
                    format!("'{t}' is not a number"),
                )
            })?;
            if !p.is_finite() {
                return Err(FeReadError::NonFinite(
                    SourceLocation::at(path, ln, col),
                    format!("'{t}'"),
                ));
            }
        }
        nodes.push(Node {
            id,
            position,
            component: Component::Unknown,
        });
        lines.push(ln);
    }
    check_unique_ids(&nodes, &lines, path)?;
    Ok((nodes, lines))
}

/// Parses the element list (`id,kind,n1,n2,...`), mapping node ids to indices into `nodes`.
pub fn parse_elements_csv(
    text: &str,
    path: &Path,
    nodes: &[Node],
) -> Result<Vec<Element>, FeReadError> {
    let index: std::collections::HashMap<u64, usize> =
        nodes.iter().enumerate().map(|(i, n)| (n.id, i)).collect();
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (hl, header) = rows.next().ok_or_else(|| {
        FeReadError::Truncated(SourceLocation::line(path, 1), "empty element list")
    })?;
    let names: Vec<String> = csv_fields(header)
        .iter()
        .map(|(f, _)| f.to_ascii_lowercase())
        .collect();
    let nodes_ok = names.len() > 2
        && names[2..]
            .iter()
            .enumerate()
            .all(|(k, n)| *n == format!("n{}", k + 1));
    if names.len() < 3 || names[0] != "id" || names[1] != "kind" || !nodes_ok {
        return Err(FeReadError::UnknownHeader(
            SourceLocation::line(path, hl),
            format!("expected 'id,kind,n1,n2,...', found '{header}'"),
        ));
    }
    let mut out = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for (ln, line) in rows {
        let f = csv_fields(line);
        let id = f[0].0.parse::<u64>().map_err(|_| {
            FeReadError::BadNumber(
                SourceLocation::at(path, ln, f[0].1),
                format!("element id '{}'", f[0].0),
            )
        })?;
        if !seen.insert(id) {
            return Err(FeReadError::BadRecord(
                SourceLocation::line(path, ln),
                format!("element {id} defined twice"),
            ));
        }
        let (kind_text, kind_col) = f.get(1).copied().unwrap_or(("", line.len() + 1));
        let (kind, allowed): (ElementKind, &[usize]) = match kind_text.to_ascii_lowercase().as_str()
        {
            "beam" => (ElementKind::Beam, &[2]),
            "link" => (ElementKind::Link, &[2]),
            "shell" => (ElementKind::Shell, &[3, 4]),
            other => {
                return Err(FeReadError::BadRecord(
                    SourceLocation::at(path, ln, kind_col),
                    format!("element kind '{other}' (expected beam, shell or link)"),
                ));
            }
        };
        let mut idx = Vec::new();
        for &(t, col) in f.iter().skip(2).filter(|(t, _)| !t.is_empty()) {
            let nid = t.parse::<u64>().map_err(|_| {
                FeReadError::BadNumber(SourceLocation::at(path, ln, col), format!("node id '{t}'"))
            })?;
            let i = index.get(&nid).copied().ok_or_else(|| {
                FeReadError::MissingNode(
                    SourceLocation::at(path, ln, col),
                    format!("element {id} uses node {nid}"),
                )
            })?;
            idx.push(i);
        }
        if !allowed.contains(&idx.len()) {
            return Err(FeReadError::BadRecord(
                SourceLocation::line(path, ln),
                format!(
                    "element {id} of kind {kind_text} has {} nodes, expected {allowed:?}",
                    idx.len()
                ),
            ));
        }
        out.push(Element {
            id,
            kind,
            nodes: idx,
        });
    }
    Ok(out)
}
