//! NASTRAN OUTPUT4 (OP4), ASCII form.
//!
//! Layout read here (as written by NASTRAN's OUTPUT4 with FORMATTED and by pyNastran):
//! a header line `ncols nrows form type` (four I8 fields), the name (A8) and a Fortran format
//! such as `1P,3E23.16`; then, per column, a record `icol irow nw` (three integers) followed
//! by the values in the declared format. Dense columns (`irow > 0`) hold consecutive rows
//! starting at `irow`. Sparse columns (`irow = 0`) hold strings, each announced by an integer
//! line `IS = irow + 65536 (L + 1)` (or, for BIGMAT, `nrows < 0` in the header, a line
//! `L irow`). The matrix ends with a record whose `icol` exceeds `ncols`. `nw` counts values
//! (pyNastran) or words (two per double value, NASTRAN): both are accepted and checked.
//!
//! Forms: 6 (symmetric; one triangle may be omitted), 1 (square) and 2 (rectangular, which
//! must be square here) are read; real types 1 and 2 only. Binary files go to `op4_binary`.

use std::path::Path;

use super::assemble::{RawMatrix, ReadOptions, Storage, build_model};
use super::bulk::parse_bulk;
use super::error::{FeReadError, SourceLocation};
use super::read_text;
use crate::structure::fe_model::FeModel;

/// One matrix of an OP4 file.
#[derive(Clone, Debug)]
pub struct Op4Matrix {
    pub name: String,
    /// NASTRAN form code (1 square, 2 rectangular, 6 symmetric, ...).
    pub form: i64,
    pub matrix: RawMatrix,
}

/// Reads M and K (by the names in `opts`) from an OP4 file (ASCII or binary, detected from the
/// first record length), and the node positions from
/// the GRID cards of a bulk data file. Rows follow the grids in ascending id order, NASTRAN's
/// internal order of the a-set without resequencing.
pub fn read_op4_model(
    op4: &Path,
    grid_bulk: &Path,
    opts: &ReadOptions,
) -> Result<FeModel, FeReadError> {
    let bulk = parse_bulk(&read_text(grid_bulk)?, grid_bulk)?;
    let bytes = std::fs::read(op4)
        .map_err(|e| FeReadError::Io(SourceLocation::line(op4, 0), e.to_string()))?;
    let matrices = if super::op4_binary::looks_like_binary_op4(&bytes) {
        super::op4_binary::parse_op4_binary(&bytes, op4)?
    } else {
        parse_op4_ascii(&read_text(op4)?, op4)?
    };
    let take = |name: &str| {
        matrices
            .iter()
            .find(|m| m.name.eq_ignore_ascii_case(name))
            .map(|m| m.matrix.clone())
            .ok_or_else(|| {
                let found: Vec<&str> = matrices.iter().map(|m| m.name.as_str()).collect();
                FeReadError::MissingMatrix(
                    SourceLocation::line(op4, 0),
                    format!("no matrix '{name}' (found {found:?})"),
                )
            })
    };
    let m = take(&opts.mass_name)?;
    let k = take(&opts.stiffness_name)?;
    build_model(bulk.nodes(), bulk.elements.clone(), m, k, opts)
}

struct Lines<'a> {
    lines: Vec<&'a str>,
    next: usize,
}

impl<'a> Lines<'a> {
    /// The next line and its 1-based number.
    fn peek(&self) -> Option<(usize, &'a str)> {
        self.lines.get(self.next).map(|l| (self.next + 1, *l))
    }
    fn advance(&mut self) {
        self.next += 1;
    }
    fn eof_line(&self) -> usize {
        self.lines.len() + 1
    }
}

/// A line of integers only (record or string header), as opposed to a line of values.
fn integers(line: &str) -> Option<Vec<i64>> {
    if line.contains(['.', 'E', 'e', 'D', 'd']) {
        return None;
    }
    line.split_whitespace()
        .map(|t| t.parse::<i64>().ok())
        .collect()
}

/// Parses every matrix of an ASCII OP4 file.
pub fn parse_op4_ascii(text: &str, path: &Path) -> Result<Vec<Op4Matrix>, FeReadError> {
    let mut lines = Lines {
        lines: text.lines().collect(),
        next: 0,
    };
    let mut out = Vec::new();
    while let Some((hl, header)) = lines.peek() {
        lines.advance();
        if header.trim().is_empty() {
            continue;
        }
        out.push(parse_matrix(&mut lines, hl, header, path)?);
    }
    if out.is_empty() {
        return Err(FeReadError::Truncated(
            SourceLocation::line(path, 1),
            "no OP4 matrix header",
        ));
    }
    Ok(out)
}

fn parse_matrix(
    lines: &mut Lines<'_>,
    hl: usize,
    header: &str,
    path: &Path,
) -> Result<Op4Matrix, FeReadError> {
    let bad_header = |why: &str| {
        FeReadError::UnknownHeader(
            SourceLocation::line(path, hl),
            format!("{why}; expected 'ncols nrows form type NAME 1P,3E23.16', found '{header}'"),
        )
    };
    let head: String = header.chars().take(32).collect();
    let ints = integers(&head)
        .filter(|v| v.len() == 4)
        .ok_or_else(|| bad_header("four integers expected"))?;
    let (ncols, nrows_signed, form, typ) = (ints[0], ints[1], ints[2], ints[3]);
    let name: String = header
        .chars()
        .skip(32)
        .take(8)
        .collect::<String>()
        .trim()
        .to_string();
    let fmt: String = header
        .chars()
        .skip(40)
        .collect::<String>()
        .trim()
        .to_ascii_uppercase();
    let (per_line, width) = parse_format(&fmt).ok_or_else(|| bad_header("unknown value format"))?;
    if name.is_empty() || ncols <= 0 || nrows_signed == 0 {
        return Err(bad_header("bad size or missing name"));
    }
    if !matches!(typ, 1 | 2) {
        return Err(FeReadError::Unsupported(
            SourceLocation::line(path, hl),
            format!("matrix {name} has type {typ}; only real types 1 and 2 are read"),
        ));
    }
    let storage = match form {
        6 => Storage::Symmetric,
        1 | 2 => Storage::General,
        _ => {
            return Err(FeReadError::Unsupported(
                SourceLocation::line(path, hl),
                format!("matrix {name} has form {form}; forms 1, 2 and 6 are read"),
            ));
        }
    };
    let bigmat = nrows_signed < 0;
    let nrows = nrows_signed.unsigned_abs() as usize;
    let ncols = ncols as usize;
    let mut entries = Vec::new();
    let truncated = |lines: &Lines<'_>, what: String| {
        FeReadError::Truncated(SourceLocation::line(path, lines.eof_line()), what)
    };
    loop {
        let (rl, rec) = lines.peek().ok_or_else(|| {
            truncated(
                lines,
                format!("matrix {name} (header line {hl}) has no terminating column record"),
            )
        })?;
        lines.advance();
        let r = integers(rec).filter(|v| v.len() == 3).ok_or_else(|| {
            FeReadError::BadRecord(
                SourceLocation::line(path, rl),
                format!("expected column record 'icol irow nw', found '{rec}'"),
            )
        })?;
        let (icol, irow, nw) = (r[0], r[1], r[2]);
        if icol as usize > ncols {
            // Terminator: skip its dummy value line(s).
            read_values(lines, per_line, width, nw.max(0) as usize, path)?;
            break;
        }
        if icol < 1 || irow < 0 || nw < 0 {
            return Err(FeReadError::BadRecord(
                SourceLocation::line(path, rl),
                format!("bad column record '{rec}'"),
            ));
        }
        let col = icol as usize - 1;
        if irow > 0 {
            let values = read_values(lines, per_line, width, nw as usize, path)?;
            check_count(nw, values.len(), typ, rl, path, lines)?;
            for (k, (v, line)) in values.into_iter().enumerate() {
                entries.push((irow as usize - 1 + k, col, v, line));
            }
        } else {
            // Sparse strings until the next 3-integer record.
            while let Some((sl, s)) = lines.peek() {
                let Some(ints) = integers(s) else {
                    return Err(FeReadError::BadRecord(
                        SourceLocation::line(path, sl),
                        "values without a string header",
                    ));
                };
                let start_row = match (bigmat, ints.as_slice()) {
                    (_, [_, _, _]) => break,
                    (true, [_, row]) => *row,
                    (false, [is]) => is - 65536 * (is / 65536),
                    _ => {
                        return Err(FeReadError::BadRecord(
                            SourceLocation::line(path, sl),
                            format!("bad string header '{s}'"),
                        ));
                    }
                };
                lines.advance();
                if start_row < 1 {
                    return Err(FeReadError::BadRecord(
                        SourceLocation::line(path, sl),
                        format!("bad string header '{s}'"),
                    ));
                }
                let values = read_values(lines, per_line, width, usize::MAX, path)?;
                if values.is_empty() {
                    return Err(truncated(
                        lines,
                        format!("string at line {sl} has no values"),
                    ));
                }
                for (k, (v, line)) in values.into_iter().enumerate() {
                    entries.push((start_row as usize - 1 + k, col, v, line));
                }
            }
        }
    }
    entries.retain(|e| e.2 != 0.0);
    for &(i, j, _, line) in &entries {
        if i >= nrows || j >= ncols {
            return Err(FeReadError::IndexOutOfRange(
                SourceLocation::line(path, line),
                format!(
                    "({}, {}) outside {nrows} x {ncols} matrix {name}",
                    i + 1,
                    j + 1
                ),
            ));
        }
    }
    Ok(Op4Matrix {
        name,
        form,
        matrix: RawMatrix {
            path: path.to_path_buf(),
            header_line: hl,
            nrows,
            ncols,
            storage,
            entries,
        },
    })
}

fn check_count(
    nw: i64,
    got: usize,
    typ: i64,
    rl: usize,
    path: &Path,
    lines: &Lines<'_>,
) -> Result<(), FeReadError> {
    let nw = nw as usize;
    if got == nw || (typ == 2 && 2 * got == nw) {
        return Ok(());
    }
    let loc = if lines.peek().is_none() {
        FeReadError::Truncated(
            SourceLocation::line(path, lines.eof_line()),
            format!("column record at line {rl} announces {nw} words, {got} values follow"),
        )
    } else {
        FeReadError::BadRecord(
            SourceLocation::line(path, rl),
            format!("column record announces {nw} words, {got} values follow"),
        )
    };
    Err(loc)
}

/// `1P,3E23.16` -> (3, 23). Accepts E or D edit descriptors, with or without the scale factor.
fn parse_format(fmt: &str) -> Option<(usize, usize)> {
    let spec = fmt.rsplit(',').next()?.trim();
    let pos = spec.find(['E', 'D'])?;
    let per_line: usize = spec[..pos].parse().ok()?;
    let width: usize = spec[pos + 1..].split('.').next()?.parse().ok()?;
    (per_line > 0 && width > 0).then_some((per_line, width))
}

/// Reads consecutive value lines (fixed-width fields); stops at an integer line, at EOF, or
/// once `limit` values are read.
fn read_values(
    lines: &mut Lines<'_>,
    per_line: usize,
    width: usize,
    limit: usize,
    path: &Path,
) -> Result<Vec<(f64, usize)>, FeReadError> {
    let mut out = Vec::new();
    while let Some((ln, line)) = lines.peek() {
        if integers(line).is_some() || out.len() >= limit {
            break;
        }
        lines.advance();
        let chars: Vec<char> = line.trim_end().chars().collect();
        if chars.len() > per_line * width {
            return Err(FeReadError::BadRecord(
                SourceLocation::line(path, ln),
                format!("more than {per_line} values of width {width}"),
            ));
        }
        for (k, chunk) in chars.chunks(width).enumerate() {
            let t: String = chunk.iter().collect();
            let loc = || SourceLocation::at(path, ln, 1 + k * width);
            let v = super::numbers::parse_nastran_real(&t).ok_or_else(|| {
                FeReadError::BadNumber(loc(), format!("'{}' is not a number", t.trim()))
            })?;
            if !v.is_finite() {
                return Err(FeReadError::NonFinite(loc(), format!("'{}'", t.trim())));
            }
            out.push((v, ln));
        }
    }
    Ok(out)
}
