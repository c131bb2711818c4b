//! NASTRAN bulk data (`.bdf`, `.dat`) and punch (`.pch`) files: GRID cards, DMIG matrices and
//! a few element cards (for plotting only).
//!
//! Card formats: small field (8-character fields, 8 per line), large field (name ending in
//! `*`, 16-character fields, 4 per line, continuation lines starting with `*`) and free field
//! (comma separated; a name ending in `*` means 4 data fields per line). Continuation lines
//! start with `+`, `*`, a comma, or a blank first field. Tabs expand to 8-column stops. `$`
//! starts a comment line. If a `BEGIN BULK` line is present, only the cards after it are
//! read; `ENDDATA` ends the deck. Reals may use Fortran exponents (`1.0D+00`, `1.0-3`).
//!
//! GRID: `ID CP X1 X2 X3 CD PS SEID`; only the basic coordinate system is supported (CP and
//! CD blank or 0). Nodes are stored in ascending id order (NASTRAN's internal order).
//!
//! DMIG: a header card `NAME 0 IFO TIN TOUT POLAR - NCOL` (IFO 6 symmetric, 1 square; TIN 1 or
//! 2, real) and column cards `NAME GJ CJ - G1 C1 A1 B1 G2 C2 A2 B2 ...`. Grid `G` component
//! `C` (1..6, in the file's DOF order) is row `6 * index(G) + C - 1`.
//!
//! Elements: CBAR, CBEAM, CROD (`EID PID GA GB`) -> beam; CQUAD4, CTRIA3 -> shell; RBAR
//! (`EID GA GB`) -> link. Other cards are ignored.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::assemble::{RawMatrix, ReadOptions, Storage, build_model, check_unique_ids};
use super::error::{FeReadError, SourceLocation};
use super::read_text;
use crate::structure::fe_model::{Component, DOF_PER_NODE, Element, ElementKind, FeModel, Node};

/// A GRID card.
#[derive(Clone, Debug, PartialEq)]
pub struct GridCard {
    pub id: u64,
    pub position: [f64; 3],
    pub line: usize,
}

/// One DMIG matrix: header data and entries `(GJ, CJ, GI, CI, value, line, column)`.
#[derive(Clone, Debug)]
pub struct Dmig {
    pub name: String,
    pub ifo: i64,
    pub header_line: usize,
    pub entries: Vec<(u64, usize, u64, usize, f64, usize, usize)>,
}

/// The parsed content of a bulk data file.
#[derive(Clone, Debug)]
pub struct BulkData {
    pub path: PathBuf,
    /// Grids in ascending id order.
    pub grids: Vec<GridCard>,
    pub dmigs: Vec<Dmig>,
    /// Elements with node indices into `grids`.
    pub elements: Vec<Element>,
}

impl BulkData {
    /// The grids as FE nodes (ascending id order).
    pub fn nodes(&self) -> Vec<Node> {
        self.grids
            .iter()
            .map(|g| Node {
                id: g.id,
                position: g.position,
                component: Component::Unknown,
            })
            .collect()
    }

    /// The DMIG matrix `name` as raw entries on the `6 * grids` DOFs.
    pub fn dmig_matrix(&self, name: &str) -> Result<RawMatrix, FeReadError> {
        let d = self
            .dmigs
            .iter()
            .find(|d| d.name.eq_ignore_ascii_case(name))
            .ok_or_else(|| {
                let found: Vec<&str> = self.dmigs.iter().map(|d| d.name.as_str()).collect();
                FeReadError::MissingMatrix(
                    SourceLocation::line(&self.path, 0),
                    format!("no DMIG '{name}' (found {found:?})"),
                )
            })?;
        let index: HashMap<u64, usize> = self
            .grids
            .iter()
            .enumerate()
            .map(|(i, g)| (g.id, i))
            .collect();
        let n = DOF_PER_NODE * self.grids.len();
        let mut entries = Vec::with_capacity(d.entries.len());
        for &(gj, cj, gi, ci, v, line, col) in &d.entries {
            let dof = |g: u64, c: usize| {
                index
                    .get(&g)
                    .map(|&i| DOF_PER_NODE * i + c - 1)
                    .ok_or_else(|| {
                        FeReadError::MissingNode(
                            SourceLocation::at(&self.path, line, col),
                            format!("DMIG {} refers to grid {g}, which has no GRID card", d.name),
                        )
                    })
            };
            entries.push((dof(gi, ci)?, dof(gj, cj)?, v, line));
        }
        let storage = if d.ifo == 6 {
            Storage::Symmetric
        } else {
            Storage::General
        };
        Ok(RawMatrix {
            path: self.path.clone(),
            header_line: d.header_line,
            nrows: n,
            ncols: n,
            storage,
            entries,
        })
    }
}

/// Reads GRID cards and the DMIG matrices named in `opts` (default MAA, KAA) from one file.
pub fn read_bulk_model(path: &Path, opts: &ReadOptions) -> Result<FeModel, FeReadError> {
    let bulk = parse_bulk(&read_text(path)?, path)?;
    let m = bulk.dmig_matrix(&opts.mass_name)?;
    let k = bulk.dmig_matrix(&opts.stiffness_name)?;
    build_model(bulk.nodes(), bulk.elements.clone(), m, k, opts)
}

/// An element card before node ids are resolved: (id, kind, [(grid id, column)], line).
type RawElement = (u64, ElementKind, Vec<(u64, usize)>, usize);

/// A data field with its location.
#[derive(Clone, Debug)]
struct Field {
    text: String,
    line: usize,
    column: usize,
}

/// A logical card: name and data fields over all its lines.
#[derive(Clone, Debug)]
struct Card {
    name: String,
    line: usize,
    fields: Vec<Field>,
}

fn expand_tabs(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    for c in line.chars() {
        if c == '\t' {
            out.push(' ');
            while out.len() % 8 != 0 {
                out.push(' ');
            }
        } else {
            out.push(c);
        }
    }
    out
}

/// Splits one physical line into (first field, data fields). Data fields are padded to the
/// line's field count (8 small, 4 large) so that positions stay aligned across lines.
fn split_line(line: &str, ln: usize) -> (String, Vec<Field>) {
    if line.contains(',') {
        let mut parts = Vec::new();
        let mut start = 0;
        for (k, c) in line.char_indices() {
            if c == ',' {
                parts.push((line[start..k].trim().to_string(), start + 1));
                start = k + 1;
            }
        }
        parts.push((line[start..].trim().to_string(), start + 1));
        let first = parts[0].0.clone();
        let large = first.ends_with('*');
        let per = if large { 4 } else { 8 };
        let mut fields: Vec<Field> = parts
            .into_iter()
            .skip(1)
            .take(per)
            .map(|(text, column)| Field {
                text,
                line: ln,
                column,
            })
            .collect();
        while fields.len() < per {
            fields.push(Field {
                text: String::new(),
                line: ln,
                column: line.len() + 1,
            });
        }
        return (first, fields);
    }
    let chars: Vec<char> = line.chars().collect();
    let slice = |a: usize, b: usize| -> String {
        chars
            .iter()
            .skip(a)
            .take(b.saturating_sub(a))
            .collect::<String>()
            .trim()
            .to_string()
    };
    let first = slice(0, 8);
    let (per, width) = if first.ends_with('*') {
        (4, 16)
    } else {
        (8, 8)
    };
    let fields = (0..per)
        .map(|k| Field {
            text: slice(8 + k * width, 8 + (k + 1) * width),
            line: ln,
            column: 9 + k * width,
        })
        .collect();
    (first, fields)
}

fn is_continuation(line: &str) -> bool {
    line.starts_with(['+', '*', ','])
        || (line.len() > 8 && line.chars().take(8).all(|c| c == ' ') && !line.trim().is_empty())
}

fn cards(text: &str, path: &Path) -> Result<Vec<Card>, FeReadError> {
    let all: Vec<&str> = text.lines().collect();
    let begin = all
        .iter()
        .position(|l| {
            l.trim().to_ascii_uppercase().starts_with("BEGIN")
                && l.to_ascii_uppercase().contains("BULK")
        })
        .map_or(0, |p| p + 1);
    let mut out: Vec<Card> = Vec::new();
    for (k, raw) in all.iter().enumerate().skip(begin) {
        let ln = k + 1;
        if raw.trim_start().starts_with('$') || raw.trim().is_empty() {
            continue;
        }
        let line = expand_tabs(raw.trim_end());
        if line.trim().eq_ignore_ascii_case("ENDDATA") {
            break;
        }
        let (first, fields) = split_line(&line, ln);
        if is_continuation(&line) {
            let Some(card) = out.last_mut() else {
                return Err(FeReadError::BadRecord(
                    SourceLocation::line(path, ln),
                    "continuation line without a card",
                ));
            };
            card.fields.extend(fields);
        } else {
            let name = first.trim_end_matches('*').to_ascii_uppercase();
            out.push(Card {
                name,
                line: ln,
                fields,
            });
        }
    }
    Ok(out)
}

impl Card {
    fn text(&self, k: usize) -> &str {
        self.fields.get(k).map_or("", |f| f.text.as_str())
    }
    fn loc(&self, path: &Path, k: usize) -> SourceLocation {
        match self.fields.get(k) {
            Some(f) => SourceLocation::at(path, f.line, f.column),
            None => SourceLocation::line(path, self.line),
        }
    }
    fn int(&self, path: &Path, k: usize, what: &str) -> Result<i64, FeReadError> {
        let t = self.text(k);
        t.parse::<i64>().map_err(|_| {
            FeReadError::BadNumber(
                self.loc(path, k),
                format!("{} {what} '{t}' is not an integer", self.name),
            )
        })
    }
    fn int_or(&self, path: &Path, k: usize, what: &str, default: i64) -> Result<i64, FeReadError> {
        if self.text(k).is_empty() {
            Ok(default)
        } else {
            self.int(path, k, what)
        }
    }
    fn real_or_zero(&self, path: &Path, k: usize, what: &str) -> Result<f64, FeReadError> {
        let t = self.text(k);
        if t.is_empty() {
            return Ok(0.0);
        }
        let v = super::numbers::parse_nastran_real(t).ok_or_else(|| {
            FeReadError::BadNumber(
                self.loc(path, k),
                format!("{} {what} '{t}' is not a number", self.name),
            )
        })?;
        if !v.is_finite() {
            return Err(FeReadError::NonFinite(
                self.loc(path, k),
                format!("{} {what} '{t}'", self.name),
            ));
        }
        Ok(v)
    }
}

/// Parses GRID, DMIG and element cards of a bulk data / punch file.
pub fn parse_bulk(text: &str, path: &Path) -> Result<BulkData, FeReadError> {
    let mut grids = Vec::new();
    let mut dmigs: Vec<Dmig> = Vec::new();
    let mut raw_elements: Vec<RawElement> = Vec::new();
    let n_text_lines = text.lines().count();
    for card in cards(text, path)? {
        match card.name.as_str() {
            "GRID" => {
                let id = card.int(path, 0, "ID")?;
                if id < 1 {
                    return Err(FeReadError::BadRecord(
                        card.loc(path, 0),
                        format!("GRID id {id}"),
                    ));
                }
                for (k, what) in [(1, "CP"), (5, "CD")] {
                    if card.int_or(path, k, what, 0)? != 0 {
                        return Err(FeReadError::Unsupported(
                            card.loc(path, k),
                            format!(
                                "GRID {id}: {what} {} (only the basic system is supported)",
                                card.text(k)
                            ),
                        ));
                    }
                }
                let position = [
                    card.real_or_zero(path, 2, "X1")?,
                    card.real_or_zero(path, 3, "X2")?,
                    card.real_or_zero(path, 4, "X3")?,
                ];
                grids.push(GridCard {
                    id: id as u64,
                    position,
                    line: card.line,
                });
            }
            "DMIG" => parse_dmig(&card, path, &mut dmigs, n_text_lines)?,
            "CBAR" | "CBEAM" | "CROD" | "CQUAD4" | "CTRIA3" | "RBAR" => {
                let (kind, first, count) = match card.name.as_str() {
                    "CQUAD4" => (ElementKind::Shell, 2, 4),
                    "CTRIA3" => (ElementKind::Shell, 2, 3),
                    "RBAR" => (ElementKind::Link, 1, 2),
                    _ => (ElementKind::Beam, 2, 2),
                };
                let eid = card.int(path, 0, "EID")?;
                let mut g = Vec::with_capacity(count);
                for k in first..first + count {
                    g.push((card.int(path, k, "grid")? as u64, card.loc(path, k).column));
                }
                raw_elements.push((eid as u64, kind, g, card.line));
            }
            _ => {}
        }
    }
    grids.sort_by_key(|g| g.id);
    let nodes: Vec<Node> = grids
        .iter()
        .map(|g| Node {
            id: g.id,
            position: g.position,
            component: Component::Unknown,
        })
        .collect();
    let lines: Vec<usize> = grids.iter().map(|g| g.line).collect();
    check_unique_ids(&nodes, &lines, path)?;
    let index: HashMap<u64, usize> = grids.iter().enumerate().map(|(i, g)| (g.id, i)).collect();
    let mut elements = Vec::with_capacity(raw_elements.len());
    for (eid, kind, g, line) in raw_elements {
        let mut idx = Vec::with_capacity(g.len());
        for (gid, col) in g {
            idx.push(*index.get(&gid).ok_or_else(|| {
                FeReadError::MissingNode(
                    SourceLocation::at(path, line, col),
                    format!("element {eid} uses grid {gid}, which has no GRID card"),
                )
            })?);
        }
        elements.push(Element {
            id: eid,
            kind,
            nodes: idx,
        });
    }
    Ok(BulkData {
        path: path.to_path_buf(),
        grids,
        dmigs,
        elements,
    })
}

fn parse_dmig(
    card: &Card,
    path: &Path,
    dmigs: &mut Vec<Dmig>,
    n_text_lines: usize,
) -> Result<(), FeReadError> {
    let name = card.text(0).to_ascii_uppercase();
    if name.is_empty() {
        return Err(FeReadError::BadRecord(
            card.loc(path, 0),
            "DMIG without a matrix name",
        ));
    }
    let second = card.int(path, 1, "GJ")?;
    if second == 0 {
        let ifo = card.int(path, 2, "IFO")?;
        let tin = card.int(path, 3, "TIN")?;
        if !matches!(ifo, 1 | 6) {
            return Err(FeReadError::Unsupported(
                card.loc(path, 2),
                format!("DMIG {name}: IFO {ifo} (1 square or 6 symmetric are read)"),
            ));
        }
        if !matches!(tin, 1 | 2) {
            return Err(FeReadError::Unsupported(
                card.loc(path, 3),
                format!("DMIG {name}: TIN {tin} (only real matrices are read)"),
            ));
        }
        if dmigs.iter().any(|d| d.name == name) {
            return Err(FeReadError::BadRecord(
                SourceLocation::line(path, card.line),
                format!("second header for DMIG {name}"),
            ));
        }
        dmigs.push(Dmig {
            name,
            ifo,
            header_line: card.line,
            entries: Vec::new(),
        });
        return Ok(());
    }
    let Some(d) = dmigs.iter_mut().find(|d| d.name == name) else {
        return Err(FeReadError::BadRecord(
            SourceLocation::line(path, card.line),
            format!("DMIG {name} column before its header card"),
        ));
    };
    let gj = second;
    let cj = card.int(path, 2, "CJ")?;
    let comp = |c: i64, k: usize| -> Result<usize, FeReadError> {
        match c {
            1..=6 => Ok(c as usize),
            0 => Err(FeReadError::Unsupported(
                card.loc(path, k),
                format!("DMIG {name}: scalar point (component 0)"),
            )),
            _ => Err(FeReadError::BadRecord(
                card.loc(path, k),
                format!("DMIG {name}: component {c} (expected 1..6)"),
            )),
        }
    };
    let cj = comp(cj, 2)?;
    if gj < 1 {
        return Err(FeReadError::BadRecord(
            card.loc(path, 1),
            format!("DMIG {name}: grid {gj}"),
        ));
    }
    let mut n_entries = 0;
    let mut k = 4;
    while k < card.fields.len() {
        if (k..k + 4).all(|i| card.text(i).is_empty()) {
            k += 4;
            continue;
        }
        let gi = card.int(path, k, "GI")?;
        if gi < 1 {
            return Err(FeReadError::BadRecord(
                card.loc(path, k),
                format!("DMIG {name}: grid {gi}"),
            ));
        }
        let ci = comp(card.int(path, k + 1, "CI")?, k + 1)?;
        if card.text(k + 2).is_empty() {
            return Err(FeReadError::BadRecord(
                card.loc(path, k + 2),
                format!("DMIG {name}: missing value"),
            ));
        }
        let v = card.real_or_zero(path, k + 2, "value")?;
        let loc = card.loc(path, k);
        d.entries
            .push((gj as u64, cj, gi as u64, ci, v, loc.line, loc.column));
        n_entries += 1;
        k += 4;
    }
    if n_entries == 0 {
        let last_line = card.fields.last().map_or(card.line, |f| f.line);
        return Err(if last_line >= n_text_lines {
            FeReadError::Truncated(
                SourceLocation::line(path, n_text_lines + 1),
                format!(
                    "DMIG {name} column card at line {} has no entries",
                    card.line
                ),
            )
        } else {
            FeReadError::BadRecord(
                SourceLocation::line(path, card.line),
                format!("DMIG {name} column card has no entries"),
            )
        });
    }
    Ok(())
}
