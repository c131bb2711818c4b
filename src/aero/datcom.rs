//! Missile DATCOM's printed output (`for006.dat`) as an aerodynamic source (thesis 5.5: the
//! thesis tabulated Missile DATCOM output; Blake, "Missile DATCOM User's Manual - 1997
//! Fortran 90 Revision", AFRL-VA-WP-TR-1998-3009).
//!
//! # What is read
//!
//! The file is a sequence of pages, each opening with the banner line
//! `***** THE USAF AUTOMATED MISSILE DATCOM * REV ... *****     CASE   n` and a `PAGE   m`
//! line, then the page's titles. The pages read here are:
//!
//! - `STATIC AERODYNAMICS FOR BODY-FIN SET ...` (or `... FOR BODY ALONE`): the complete
//!   configuration's `ALPHA CN CM CA CY CLN CLL` table ([`StaticTable`]) or, on a page whose
//!   block says `DERIVATIVES (PER DEGREE)` / `(PER RADIAN)`, the derivative table
//!   `ALPHA CNA CMA CYB CLNB CLLB` ([`DerivativeTable`], the unit as the header says);
//! - `BODY ALONE PARTIAL OUTPUT` (printed with the `PART` control card): the body alone's
//!   axial components `CA-FRIC CA-PRES/WAVE CA-BASE CA-PROT CA-SEP CA-ALP` and normal-force
//!   and pitching-moment components `CN-POTEN CN-VISC CN-SEP CM-POTEN CM-VISC CM-SEP`
//!   ([`BodyAloneTable`], the sums);
//! - `AERODYNAMIC FORCE AND MOMENT SYNTHESIS` / `FIN SET n IN PRESENCE OF THE BODY` (also
//!   `PART`): fin set n's contribution to the configuration, `ALPHA CN CM CA CY CLN CLL`,
//!   body-fin interference included ([`FinSetTable`]).
//!
//! Every such page carries the block `FLIGHT CONDITIONS AND REFERENCE QUANTITIES`: `MACH NO`,
//! `REYNOLDS NO` (per unit length), `ALTITUDE` when the case gave one, `REF AREA`, `MOMENT
//! CENTER` (the moment reference, XCG, measured aft from the body's origin: the nose tip
//! unless the case moved the nose with `XO`), `REF LENGTH`, with their units (FT, IN, M or CM
//! as the case's `DIM` card chose). They are converted to SI here ([`Conditions`]); each printed
//! number keeps its resolution (half a unit of its last printed digit: DATCOM prints the
//! reference area to three decimals, so `0.013 M**2` is any area in [0.0125, 0.0135]).
//!
//! # How it is parsed
//!
//! Line by line with nom: the banner, the `KEY = value UNIT` pairs of the conditions block
//! and the table rows are recognisers; a table's columns are matched to its header's names by
//! their right-aligned end columns, so a blank cell (DATCOM leaves `CA-PROT` empty when the
//! case has no protuberance) is a missing value, never a shifted one. Fortran's `******`
//! (a number too wide for its field) is read as missing. Every error names the 1-based line
//! and column.

use std::fmt;

use nom::IResult;

use crate::aero::tables::{CoefficientTable, TableKind};
use crate::check::ir::OutOfRange;
use nom::Parser;
use nom::bytes::complete::{tag, take_until};
use nom::character::complete::{space0, space1};
use nom::combinator::{opt, rest};
use nom::number::complete::double;
use nom::sequence::preceded;

/// The banner that opens every page.
const BANNER: &str = "THE USAF AUTOMATED MISSILE DATCOM";

/// The line that closes a complete run.
const END_OF_JOB: &str = "*** END OF JOB ***";

/// A parse error with its 1-based line and column.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("line {line}, column {column}: {message}")]
pub struct DatcomError {
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl DatcomError {
    fn new(line: usize, column: usize, message: impl Into<String>) -> Self {
        DatcomError {
            line,
            column,
            message: message.into(),
        }
    }
}

/// A printed number and its resolution (half a unit of its last printed digit), in SI.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Printed {
    pub value: f64,
    pub resolution: f64,
}

impl Printed {
    /// True when `x` rounds to the printed value (within the resolution, plus a relative
    /// 1e-9 for the unit conversion).
    pub fn admits(&self, x: f64) -> bool {
        (x - self.value).abs() <= self.resolution + 1e-9 * self.value.abs().max(x.abs())
    }
}

/// The length unit of a case (its `DIM` card).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LengthUnit {
    Feet,
    Inches,
    Metres,
    Centimetres,
}

impl LengthUnit {
    /// Metres per unit (exact: the international foot and inch).
    pub fn metres(self) -> f64 {
        match self {
            LengthUnit::Feet => 0.3048,
            LengthUnit::Inches => 0.0254,
            LengthUnit::Metres => 1.0,
            LengthUnit::Centimetres => 0.01,
        }
    }

    fn from_token(t: &str) -> Option<Self> {
        match t {
            "FT" => Some(LengthUnit::Feet),
            "IN" => Some(LengthUnit::Inches),
            "M" => Some(LengthUnit::Metres),
            "CM" => Some(LengthUnit::Centimetres),
            _ => None,
        }
    }
}

impl fmt::Display for LengthUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            LengthUnit::Feet => "FT",
            LengthUnit::Inches => "IN",
            LengthUnit::Metres => "M",
            LengthUnit::Centimetres => "CM",
        })
    }
}

/// The flight conditions and reference quantities of one page, in SI.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conditions {
    pub mach: f64,
    /// Altitude in m, when the case gave one (else DATCOM prints the Reynolds number only).
    pub altitude: Option<f64>,
    /// Reynolds number per metre.
    pub reynolds_per_m: Option<f64>,
    /// Reference area, m^2.
    pub reference_area: Printed,
    /// Moment reference (XCG), m aft of the body's origin.
    pub moment_center: Printed,
    /// Longitudinal reference length, m.
    pub reference_length: Printed,
    /// The case's length unit.
    pub unit: LengthUnit,
}

/// The complete configuration's static coefficients against alpha (deg) at one condition.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticTable {
    pub case: u32,
    /// 1-based line of the page banner.
    pub line: usize,
    pub conditions: Conditions,
    pub alpha_deg: Vec<f64>,
    pub cn: Vec<f64>,
    pub cm: Vec<f64>,
    pub ca: Vec<f64>,
    /// Lateral-directional columns, `None` when the page does not print them.
    pub cy: Option<Vec<f64>>,
    pub cln: Option<Vec<f64>>,
    pub cll: Option<Vec<f64>>,
}

/// The derivative block of a static page.
#[derive(Clone, Debug, PartialEq)]
pub struct DerivativeTable {
    pub case: u32,
    pub line: usize,
    pub conditions: Conditions,
    /// As the block's header says: `(PER RADIAN)` (true) or `(PER DEGREE)`.
    pub per_radian: bool,
    pub alpha_deg: Vec<f64>,
    pub cna: Vec<f64>,
    pub cma: Vec<f64>,
}

impl DerivativeTable {
    /// `CNA` per radian whatever the file's unit.
    pub fn cna_per_rad(&self) -> Vec<f64> {
        self.per_rad(&self.cna)
    }

    /// `CMA` per radian whatever the file's unit.
    pub fn cma_per_rad(&self) -> Vec<f64> {
        self.per_rad(&self.cma)
    }

    fn per_rad(&self, v: &[f64]) -> Vec<f64> {
        let k = if self.per_radian {
            1.0
        } else {
            180.0 / std::f64::consts::PI
        };
        v.iter().map(|x| x * k).collect()
    }
}

/// The body alone (`BODY ALONE PARTIAL OUTPUT`): sums of DATCOM's components.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyAloneTable {
    pub case: u32,
    pub line: usize,
    pub conditions: Conditions,
    pub alpha_deg: Vec<f64>,
    /// CN-POTEN + CN-VISC + CN-SEP.
    pub cn: Vec<f64>,
    /// CM-POTEN + CM-VISC + CM-SEP, about the moment center.
    pub cm: Vec<f64>,
    /// CA-FRIC + CA-PRES/WAVE + CA-BASE + CA-PROT + CA-SEP + CA-ALP (blank cells are zero).
    pub ca: Vec<f64>,
}

/// Fin set n in the presence of the body (its contribution, interference included).
#[derive(Clone, Debug, PartialEq)]
pub struct FinSetTable {
    pub case: u32,
    pub line: usize,
    pub fin_set: u32,
    pub conditions: Conditions,
    pub alpha_deg: Vec<f64>,
    pub cn: Vec<f64>,
    pub cm: Vec<f64>,
    pub ca: Vec<f64>,
}

/// Everything read from one `for006.dat`, in file order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DatcomOutput {
    pub complete: Vec<StaticTable>,
    pub derivatives: Vec<DerivativeTable>,
    pub body_alone: Vec<BodyAloneTable>,
    pub fin_sets: Vec<FinSetTable>,
    /// Number of page banners that carry a case number.
    pub pages: usize,
}

/// One line of the file with its 1-based number.
#[derive(Clone, Copy)]
struct Line<'a> {
    no: usize,
    text: &'a str,
}

type R<'a, T> = IResult<&'a str, T>;

/// `1         ***** THE USAF AUTOMATED MISSILE DATCOM * REV 3/99 *****     CASE   1`:
/// the case number, or `None` for a banner without one (the input echo's page).
fn banner(s: &str) -> Option<Option<u32>> {
    let r: R<'_, _> = (
        opt(nom::character::complete::char('1')),
        space0,
        tag("*****"),
        space0,
        tag(BANNER),
        take_until("*****"),
        tag("*****"),
        opt(preceded(
            (space1, tag("CASE"), space1),
            nom::character::complete::u32,
        )),
    )
        .parse(s);
    r.ok().map(|(_, t)| t.7)
}

/// A table header: its column names with their end columns (0-based byte offsets).
fn header_columns(s: &str) -> Vec<(&str, usize)> {
    let mut out = Vec::new();
    let b = s.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b' ' {
            i += 1;
            continue;
        }
        let start = i;
        while i < b.len() && b[i] != b' ' {
            i += 1;
        }
        out.push((&s[start..i], i));
    }
    out
}

/// A number as DATCOM prints it (`.00`, `-.0000`, `1.000E+07`), or `******` (`None`).
fn cell(s: &str) -> R<'_, Option<f64>> {
    if let Ok((r, _)) = nom::bytes::complete::is_a::<_, _, nom::error::Error<&str>>("*")(s) {
        return Ok((r, None));
    }
    double.map(Some).parse(s)
}

/// A table row: every token with its end column; `Err(column)` at the first token that is
/// not a number.
fn row_cells(s: &str) -> Result<Vec<(Option<f64>, usize)>, usize> {
    let mut out = Vec::new();
    let mut rest_s = s;
    loop {
        let (r, _) = space0::<_, nom::error::Error<&str>>(rest_s).unwrap_or((rest_s, ""));
        if r.is_empty() {
            return Ok(out);
        }
        let col = s.len() - r.len();
        match cell(r) {
            Ok((r2, v)) if r2.is_empty() || r2.starts_with(' ') => {
                out.push((v, s.len() - r2.len()));
                rest_s = r2;
            }
            _ => return Err(col),
        }
    }
}

struct Table<'a> {
    names: Vec<&'a str>,
    columns: Vec<Vec<Option<f64>>>,
    /// 1-based line of each row.
    lines: Vec<usize>,
}

impl<'a> Table<'a> {
    fn column(&self, name: &str) -> Option<&Vec<Option<f64>>> {
        self.names
            .iter()
            .position(|n| *n == name)
            .map(|k| &self.columns[k])
    }
}

fn parse_table<'a>(lines: &[Line<'a>], h: usize) -> Result<(Table<'a>, usize), DatcomError> {
    let head = header_columns(lines[h].text);
    let names: Vec<&str> = head.iter().map(|(n, _)| *n).collect();
    let mut columns = vec![Vec::new(); names.len()];
    let mut rows = Vec::new();
    let mut i = h + 1;
    // DATCOM sometimes leaves one blank line between the header and the first row.
    while i < lines.len() && lines[i].text.trim().is_empty() && rows.is_empty() && i == h + 1 {
        i += 1;
    }
    while i < lines.len() {
        let l = lines[i];
        if l.text.trim().is_empty() || banner(l.text).is_some() {
            break;
        }
        let cells = match row_cells(l.text) {
            Ok(c) => c,
            Err(col) => {
                return Err(DatcomError::new(
                    l.no,
                    col + 1,
                    format!(
                        "expected a row of numbers under the header `{}` (line {})",
                        lines[h].text.trim(),
                        lines[h].no
                    ),
                ));
            }
        };
        let mut row = vec![None; names.len()];
        for (v, end) in cells {
            let k = head
                .iter()
                .enumerate()
                .min_by_key(|(_, (_, e))| e.abs_diff(end))
                .map(|(k, _)| k)
                .unwrap_or(0);
            if head[k].1.abs_diff(end) > 6 || row[k].is_some() {
                return Err(DatcomError::new(
                    l.no,
                    end,
                    format!(
                        "a value that lines up with no column of the header `{}` (line {})",
                        lines[h].text.trim(),
                        lines[h].no
                    ),
                ));
            }
            row[k] = Some(v);
        }
        for (k, v) in row.into_iter().enumerate() {
            columns[k].push(v.flatten());
        }
        rows.push(l.no);
        i += 1;
    }
    if rows.is_empty() {
        return Err(DatcomError::new(
            lines[h].no,
            1,
            format!("the table `{}` has no rows", lines[h].text.trim()),
        ));
    }
    Ok((
        Table {
            names,
            columns,
            lines: rows,
        },
        i,
    ))
}

/// The keys of the conditions block, longest first where one ends another.
const KEYS: [&str; 11] = [
    "LAT REF LENGTH",
    "REF LENGTH",
    "MACH NO",
    "REYNOLDS NO",
    "ALTITUDE",
    "DYNAMIC PRESSURE",
    "SIDESLIP",
    "ROLL",
    "REF AREA",
    "MOMENT CENTER",
    "PRESSURE",
];

/// One `KEY = value` pair with the text after the value up to the next key (its unit).
#[derive(Debug)]
struct Pair<'a> {
    key: &'a str,
    value: f64,
    /// The printed digits, for the resolution.
    digits: &'a str,
    unit: &'a str,
    column: usize,
}

/// `     MACH NO  =       2.36                REYNOLDS NO = 3.000E+06 /FT`.
fn pairs(s: &str) -> Option<Vec<Pair<'_>>> {
    let mut out: Vec<Pair<'_>> = Vec::new();
    let mut input = s;
    let mut key_text: &str;
    let first: R<'_, &str> = take_until("=").parse(input);
    let (r, k) = first.ok()?;
    key_text = k;
    input = r;
    loop {
        let key = KEYS.iter().find(|k| key_text.trim_end().ends_with(*k))?;
        if let Some(prev) = out.last_mut() {
            let t = key_text.trim_end();
            prev.unit = t[..t.len() - key.len()].trim();
        } else if key_text.trim() != *key {
            return None;
        }
        let p: R<'_, (&str, &str, &str)> =
            (tag("="), space0, nom::combinator::recognize(double)).parse(input);
        let (r, (_, _, digits)) = p.ok()?;
        let column = s.len() - input.len() + 1;
        let value: f64 = digits.parse().ok()?;
        out.push(Pair {
            key,
            value,
            digits,
            unit: "",
            column,
        });
        match take_until::<_, _, nom::error::Error<&str>>("=").parse(r) {
            Ok((r2, k2)) => {
                key_text = k2;
                input = r2;
            }
            Err(_) => {
                let t: R<'_, &str> = rest.parse(r);
                out.last_mut()?.unit = t.ok()?.1.trim();
                return Some(out);
            }
        }
    }
}

/// Half a unit of the last printed digit of `digits` (`0.013` -> 5e-4; `3.000E+06` -> 5e2).
fn resolution(digits: &str) -> f64 {
    let (mantissa, exp) = match digits.find(['E', 'e']) {
        Some(k) => (&digits[..k], digits[k + 1..].parse::<i32>().unwrap_or(0)),
        None => (digits, 0),
    };
    let decimals = mantissa.find('.').map_or(0, |k| mantissa.len() - k - 1) as i32;
    0.5 * 10f64.powi(exp - decimals)
}

/// The conditions block starting at `lines[i]` (the line after its title).
fn conditions(lines: &[Line<'_>], i: usize) -> Result<Conditions, DatcomError> {
    let mut found: Vec<(Pair<'_>, usize)> = Vec::new();
    let mut k = i;
    while k < lines.len() && k < i + 8 {
        let t = lines[k].text;
        if t.trim().is_empty() {
            if !found.is_empty() {
                break;
            }
            k += 1;
            continue;
        }
        match pairs(t) {
            Some(ps) => found.extend(ps.into_iter().map(|p| (p, lines[k].no))),
            None => break,
        }
        k += 1;
    }
    let at = lines.get(i).map_or(0, |l| l.no);
    let get = |key: &str| found.iter().find(|(p, _)| p.key == key);
    let need = |key: &str| {
        get(key).ok_or_else(|| {
            DatcomError::new(
                at,
                1,
                format!("the FLIGHT CONDITIONS AND REFERENCE QUANTITIES block has no `{key}`"),
            )
        })
    };
    let mach = need("MACH NO")?;
    let area = need("REF AREA")?;
    let center = need("MOMENT CENTER")?;
    let length = need("REF LENGTH")?;
    let unit_of = |p: &(Pair<'_>, usize), suffix: &str| {
        let u = p.0.unit;
        u.strip_suffix(suffix)
            .and_then(LengthUnit::from_token)
            .ok_or_else(|| {
                DatcomError::new(
                    p.1,
                    p.0.column,
                    format!(
                        "`{}` has the unit `{u}`, expected FT{suffix}, IN{suffix}, M{suffix} or CM{suffix}",
                        p.0.key
                    ),
                )
            })
    };
    let unit = unit_of(area, "**2")?;
    for (p, suffix) in [(center, ""), (length, "")] {
        let u = unit_of(p, suffix)?;
        if u != unit {
            return Err(DatcomError::new(
                p.1,
                p.0.column,
                format!(
                    "`{}` is in {u} but the reference area in {unit}**2",
                    p.0.key
                ),
            ));
        }
    }
    let m = unit.metres();
    let printed = |p: &Pair<'_>, scale: f64| Printed {
        value: p.value * scale,
        resolution: resolution(p.digits) * scale,
    };
    let altitude = match get("ALTITUDE") {
        Some((p, line)) => {
            let u = LengthUnit::from_token(p.unit).ok_or_else(|| {
                DatcomError::new(*line, p.column, format!("altitude unit `{}`", p.unit))
            })?;
            Some(p.value * u.metres())
        }
        None => None,
    };
    let reynolds_per_m = match get("REYNOLDS NO") {
        Some((p, line)) => {
            let u = p
                .unit
                .strip_prefix('/')
                .and_then(LengthUnit::from_token)
                .ok_or_else(|| {
                    DatcomError::new(
                        *line,
                        p.column,
                        format!("Reynolds number unit `{}`", p.unit),
                    )
                })?;
            Some(p.value / u.metres())
        }
        None => None,
    };
    let cond = Conditions {
        mach: mach.0.value,
        altitude,
        reynolds_per_m,
        reference_area: printed(&area.0, m * m),
        moment_center: printed(&center.0, m),
        reference_length: printed(&length.0, m),
        unit,
    };
    for (p, line) in [mach, area, length] {
        if !(p.value.is_finite() && p.value > 0.0) {
            return Err(DatcomError::new(
                *line,
                p.column,
                format!("`{}` must be positive, found {}", p.key, p.digits),
            ));
        }
    }
    Ok(cond)
}

fn values(t: &Table<'_>, name: &str, at: usize) -> Result<Vec<f64>, DatcomError> {
    let c = t
        .column(name)
        .ok_or_else(|| DatcomError::new(at, 1, format!("the table has no `{name}` column")))?;
    c.iter()
        .zip(&t.lines)
        .map(|(v, l)| {
            v.ok_or_else(|| DatcomError::new(*l, 1, format!("no value in column `{name}`")))
        })
        .collect()
}

fn optional(t: &Table<'_>, name: &str, at: usize) -> Result<Option<Vec<f64>>, DatcomError> {
    match t.column(name) {
        Some(_) => values(t, name, at).map(Some),
        None => Ok(None),
    }
}

/// A sum of columns, blank cells zero; the columns must exist.
fn sum(t: &Table<'_>, names: &[&str], at: usize) -> Result<Vec<f64>, DatcomError> {
    let mut out = vec![0.0; t.lines.len()];
    for n in names {
        let c = t
            .column(n)
            .ok_or_else(|| DatcomError::new(at, 1, format!("the table has no `{n}` column")))?;
        for (o, v) in out.iter_mut().zip(c) {
            *o += v.unwrap_or(0.0);
        }
    }
    Ok(out)
}

/// Parses a whole `for006.dat`.
pub fn parse(text: &str) -> Result<DatcomOutput, DatcomError> {
    let lines: Vec<Line<'_>> = text
        .lines()
        .enumerate()
        .map(|(k, t)| Line { no: k + 1, text: t })
        .collect();
    // Page starts.
    let starts: Vec<(usize, u32)> = lines
        .iter()
        .enumerate()
        .filter_map(|(k, l)| banner(l.text).flatten().map(|c| (k, c)))
        .collect();
    if !lines.iter().any(|l| banner(l.text).is_some()) {
        return Err(DatcomError::new(
            1,
            1,
            format!("not Missile DATCOM output: no `{BANNER}` banner"),
        ));
    }
    // DATCOM closes every run with this line: without it the file was cut (a table cut
    // between rows would otherwise read as a shorter table).
    if !lines
        .iter()
        .rev()
        .take_while(|l| banner(l.text).is_none())
        .any(|l| l.text.trim() == END_OF_JOB)
    {
        return Err(DatcomError::new(
            lines.len().max(1),
            1,
            format!("the file ends without DATCOM's closing `{END_OF_JOB}` line (truncated?)"),
        ));
    }
    let mut out = DatcomOutput {
        pages: starts.len(),
        ..Default::default()
    };
    for (n, &(s, case)) in starts.iter().enumerate() {
        let end = starts.get(n + 1).map_or(lines.len(), |p| p.0);
        let page = &lines[s..end];
        let banner_line = page[0].no;
        let titles: Vec<&str> = page.iter().take(6).map(|l| l.text.trim()).collect();
        let has = |t: &str| titles.iter().any(|x| x.starts_with(t));
        let static_page = titles
            .iter()
            .any(|x| x.starts_with("STATIC AERODYNAMICS FOR"));
        let body_partial = has("BODY ALONE PARTIAL OUTPUT");
        let synthesis = has("AERODYNAMIC FORCE AND MOMENT SYNTHESIS");
        if !(static_page || body_partial || synthesis) {
            continue;
        }
        let Some(ci) = page.iter().position(|l| {
            l.text
                .contains("FLIGHT CONDITIONS AND REFERENCE QUANTITIES")
        }) else {
            return Err(DatcomError::new(
                banner_line,
                1,
                "a page of coefficients without its FLIGHT CONDITIONS AND REFERENCE QUANTITIES block (truncated?)",
            ));
        };
        let cond = conditions(page, ci + 1)?;
        let header = |first: &str, second: &str| {
            page.iter().position(|l| {
                let h = header_columns(l.text);
                h.len() >= 2 && h[0].0 == first && h[1].0 == second
            })
        };
        let missing = |what: &str| {
            DatcomError::new(
                banner_line,
                1,
                format!("this page ends before its {what} (truncated?)"),
            )
        };
        if static_page {
            if let Some(h) = header("ALPHA", "CN") {
                let (t, _) = parse_table(page, h)?;
                let at = page[h].no;
                out.complete.push(StaticTable {
                    case,
                    line: banner_line,
                    conditions: cond,
                    alpha_deg: values(&t, "ALPHA", at)?,
                    cn: values(&t, "CN", at)?,
                    cm: values(&t, "CM", at)?,
                    ca: values(&t, "CA", at)?,
                    cy: optional(&t, "CY", at)?,
                    cln: optional(&t, "CLN", at)?,
                    cll: optional(&t, "CLL", at)?,
                });
            } else if let Some(h) = header("ALPHA", "CNA") {
                let unit_line = page[..h]
                    .iter()
                    .rev()
                    .find(|l| l.text.contains("DERIVATIVES ("))
                    .ok_or_else(|| {
                        DatcomError::new(
                            page[h].no,
                            1,
                            "a derivative table without its `DERIVATIVES (PER DEGREE)` or `(PER RADIAN)` header",
                        )
                    })?;
                let per_radian = if unit_line.text.contains("(PER RADIAN)") {
                    true
                } else if unit_line.text.contains("(PER DEGREE)") {
                    false
                } else {
                    return Err(DatcomError::new(
                        unit_line.no,
                        1,
                        "derivatives neither `(PER DEGREE)` nor `(PER RADIAN)`",
                    ));
                };
                let (t, _) = parse_table(page, h)?;
                let at = page[h].no;
                out.derivatives.push(DerivativeTable {
                    case,
                    line: banner_line,
                    conditions: cond,
                    per_radian,
                    alpha_deg: values(&t, "ALPHA", at)?,
                    cna: values(&t, "CNA", at)?,
                    cma: values(&t, "CMA", at)?,
                });
            } else {
                return Err(missing("coefficient table"));
            }
        } else if body_partial {
            let h = header("ALPHA", "CA-FRIC").ok_or_else(|| missing("axial table"))?;
            let (ta, _) = parse_table(page, h)?;
            let h2 = header("ALPHA", "CN-POTEN").ok_or_else(|| missing("normal-force table"))?;
            let (tn, _) = parse_table(page, h2)?;
            let (at, at2) = (page[h].no, page[h2].no);
            let alpha = values(&ta, "ALPHA", at)?;
            let alpha2 = values(&tn, "ALPHA", at2)?;
            if alpha != alpha2 {
                return Err(DatcomError::new(
                    at2,
                    1,
                    format!(
                        "the normal-force table's alphas differ from the axial table's (line {at})"
                    ),
                ));
            }
            out.body_alone.push(BodyAloneTable {
                case,
                line: banner_line,
                conditions: cond,
                alpha_deg: alpha,
                cn: sum(&tn, &["CN-POTEN", "CN-VISC", "CN-SEP"], at2)?,
                cm: sum(&tn, &["CM-POTEN", "CM-VISC", "CM-SEP"], at2)?,
                ca: sum(
                    &ta,
                    &[
                        "CA-FRIC",
                        "CA-PRES/WAVE",
                        "CA-BASE",
                        "CA-PROT",
                        "CA-SEP",
                        "CA-ALP",
                    ],
                    at,
                )?,
            });
        } else if synthesis {
            let Some(fl) = page
                .iter()
                .find(|l| l.text.contains("IN PRESENCE OF THE BODY"))
            else {
                continue;
            };
            let fin_set = fin_set_number(fl.text).ok_or_else(|| {
                DatcomError::new(
                    fl.no,
                    1,
                    "`IN PRESENCE OF THE BODY` without a fin set number",
                )
            })?;
            let h = header("ALPHA", "CN").ok_or_else(|| missing("fin set table"))?;
            let (t, _) = parse_table(page, h)?;
            let at = page[h].no;
            out.fin_sets.push(FinSetTable {
                case,
                line: banner_line,
                fin_set,
                conditions: cond,
                alpha_deg: values(&t, "ALPHA", at)?,
                cn: values(&t, "CN", at)?,
                cm: values(&t, "CM", at)?,
                ca: values(&t, "CA", at)?,
            });
        }
    }
    Ok(out)
}

/// `---------------FIN SET 2 IN PRESENCE OF THE BODY----------------` -> 2.
fn fin_set_number(s: &str) -> Option<u32> {
    let r: R<'_, u32> = preceded(
        (take_until("FIN SET"), tag("FIN SET"), space1),
        nom::character::complete::u32,
    )
    .parse(s);
    r.ok().map(|(_, n)| n)
}

// ---------------------------------------------------------------------------------------
// The flight's tables from a parsed file.
// ---------------------------------------------------------------------------------------

/// Which part of a file the vehicle uses (`datcom("for006.dat", case = N, fin_set = N)`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Selection {
    /// Only this case's pages; `None`: every case (their Mach numbers and altitudes must
    /// not repeat).
    pub case: Option<u32>,
    /// The fin set that is the vehicle's `fins`; `None`: the file's only one.
    pub fin_set: Option<u32>,
}

/// What the vehicle says about the same quantities (SI, body frame: x forward from the
/// nose tip, so the moment reference is at x = -XCG).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VehicleReference {
    pub area: f64,
    pub length: f64,
    pub point_x: f64,
    /// `(count, x of the root chord's leading edge)` of the vehicle's fins, if it has any.
    pub fins: Option<(usize, f64)>,
}

/// Which vehicle quantity a file contradicts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mismatch {
    Area,
    Length,
    Point,
}

/// Why a parsed file cannot give the vehicle's tables; `line` is in the DATCOM file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct ConversionError {
    pub line: Option<usize>,
    pub message: String,
    pub mismatch: Option<Mismatch>,
}

fn conv(line: Option<usize>, message: impl Into<String>) -> ConversionError {
    ConversionError {
        line,
        message: message.into(),
        mismatch: None,
    }
}

/// The body and one-fin tables of a vehicle flown on a DATCOM file.
#[derive(Clone, Debug, PartialEq)]
pub struct DatcomTables {
    pub body: CoefficientTable,
    pub fin: CoefficientTable,
}

/// Below this |C_N| a fin set carries no normal force and its centre of pressure is taken
/// from the nearest angle of attack that has one.
const CN_ZERO: f64 = 1e-9;

/// The flight's tables from a parsed file (docs/language.md, "Missile DATCOM").
///
/// - Body table: the complete configuration minus the chosen fin set in the presence of the
///   body: `cn = CN - CN_f`, `ca = CA - CA_f`, `cm = CM - CM_f`, so body + fins is DATCOM's
///   complete configuration exactly, every other fin set (canards, a second tail) riding in
///   the body table. Coefficients are on SREF and LREF about XCG: the vehicle's reference
///   area, length and point must be what DATCOM printed (to its printed resolution), and
///   the vehicle's precise values are used (DATCOM prints SREF to three decimals).
/// - Fin table, one fin of `n` at its own angle of attack: with the fin block's model a
///   fin at roll angle δ from the pitch plane's normal sees α_f ≈ α cos δ and its normal
///   force projects with cos δ, so the set gives Σ cn_f(α cos δ_i) cos δ_i, which is
///   `(n/2) cn_f(α)` for the slope of any n >= 3 equally spaced fins (Σ cos² δ_i = n/2)
///   and exactly `2 cn_f(α)` for a cruciform in `+` at any α (the two fins in the plane of
///   α carry it all). Hence `cn = (2/n) CN_f(α)`; `ca = CA_f / n` (each fin's share of the
///   set's axial force); the centre of pressure `x_cp = XCG - LREF CM_f/CN_f` aft of the
///   nose, less the root leading edge's distance aft of the nose (DATCOM's stations are
///   taken from the nose tip, its default origin). Where CN_f = 0 (α = 0) the centre of
///   pressure of the nearest α with a normal force is held.
/// - Axes: Mach, alpha in degrees as printed, altitude (0 when the file gives a Reynolds
///   number instead: the table is then constant in altitude).
pub fn tables(
    out: &DatcomOutput,
    source: &std::path::Path,
    sel: Selection,
    vref: &VehicleReference,
    policy: OutOfRange,
) -> Result<DatcomTables, ConversionError> {
    let in_case = |c: u32| sel.case.is_none_or(|k| k == c);
    let pages: Vec<&StaticTable> = out.complete.iter().filter(|t| in_case(t.case)).collect();
    let Some(first) = pages.first() else {
        return Err(conv(
            None,
            match sel.case {
                Some(c) => format!("the file has no STATIC AERODYNAMICS page for case {c}"),
                None => "the file has no STATIC AERODYNAMICS page (CN, CM, CA against alpha)"
                    .to_string(),
            },
        ));
    };
    // The fin set.
    let mut sets: Vec<u32> = out
        .fin_sets
        .iter()
        .filter(|f| in_case(f.case))
        .map(|f| f.fin_set)
        .collect();
    sets.sort_unstable();
    sets.dedup();
    let fin_set = match (vref.fins, sel.fin_set, sets.as_slice()) {
        (None, None, []) => None,
        (None, _, _) => {
            return Err(conv(
                Some(first.line),
                "the file has fin sets but the vehicle has no `fins` block",
            ));
        }
        (Some(_), _, []) => {
            return Err(conv(
                Some(first.line),
                "the file has no `FIN SET n IN PRESENCE OF THE BODY` pages, so its body and fins cannot be told apart: run DATCOM with the PART control card",
            ));
        }
        (Some(_), Some(k), _) if sets.contains(&k) => Some(k),
        (Some(_), Some(k), _) => {
            return Err(conv(
                Some(first.line),
                format!("the file has no fin set {k} (it has {sets:?})"),
            ));
        }
        (Some(_), None, [k]) => Some(*k),
        (Some(_), None, _) => {
            return Err(conv(
                Some(first.line),
                format!(
                    "the file has fin sets {sets:?}: say which is the vehicle's `fins` with `fin_set = N`"
                ),
            ));
        }
    };
    let alphas = first.alpha_deg.clone();
    let with_altitude = first.conditions.altitude.is_some();
    let mut points: Vec<(f64, f64, &StaticTable, Option<&FinSetTable>)> = Vec::new();
    for t in &pages {
        let c = &t.conditions;
        if c.altitude.is_some() != with_altitude {
            return Err(conv(
                Some(t.line),
                format!(
                    "this page {} an altitude but the page on line {} {}",
                    if c.altitude.is_some() {
                        "gives"
                    } else {
                        "gives no"
                    },
                    first.line,
                    if with_altitude { "does" } else { "does not" }
                ),
            ));
        }
        let h = c.altitude.unwrap_or(0.0);
        if t.alpha_deg != alphas {
            return Err(conv(
                Some(t.line),
                format!(
                    "this page's angles of attack {:?} differ from those of the page on line {} {:?}: every page must share one alpha grid",
                    t.alpha_deg, first.line, alphas
                ),
            ));
        }
        if let Some((_, _, p, _)) = points.iter().find(|(m, a, _, _)| *m == c.mach && *a == h) {
            return Err(conv(
                Some(t.line),
                format!(
                    "Mach {} at altitude {h} m is given twice: by case {} (line {}) and case {} (this page); choose one with `case = N`",
                    c.mach, p.case, p.line, t.case
                ),
            ));
        }
        let reference = [
            (
                c.reference_area,
                vref.area,
                Mismatch::Area,
                "reference area",
                "m^2",
            ),
            (
                c.reference_length,
                vref.length,
                Mismatch::Length,
                "reference length",
                "m",
            ),
            (
                c.moment_center,
                -vref.point_x,
                Mismatch::Point,
                "moment centre (XCG aft of the nose)",
                "m",
            ),
        ];
        for (printed, vehicle, which, name, unit) in reference {
            if !printed.admits(vehicle) {
                return Err(ConversionError {
                    line: Some(t.line),
                    message: format!(
                        "the file's {name} is {} {unit} (to {} {unit}), the vehicle's {vehicle} {unit}",
                        printed.value, printed.resolution
                    ),
                    mismatch: Some(which),
                });
            }
        }
        let fin = match fin_set {
            None => None,
            Some(k) => {
                let f = out
                    .fin_sets
                    .iter()
                    .find(|f| f.case == t.case && f.fin_set == k && f.conditions.mach == c.mach && f.conditions.altitude == c.altitude)
                    .ok_or_else(|| conv(Some(t.line), format!("no `FIN SET {k} IN PRESENCE OF THE BODY` page for this page's Mach {} (case {})", c.mach, t.case)))?;
                if f.alpha_deg != alphas {
                    return Err(conv(
                        Some(f.line),
                        format!(
                            "fin set {k}'s angles of attack differ from the static page's on line {}",
                            t.line
                        ),
                    ));
                }
                Some(f)
            }
        };
        points.push((c.mach, h, t, fin));
    }
    let mut machs: Vec<f64> = points.iter().map(|p| p.0).collect();
    machs.sort_by(f64::total_cmp);
    machs.dedup();
    let mut alts: Vec<f64> = points.iter().map(|p| p.1).collect();
    alts.sort_by(f64::total_cmp);
    alts.dedup();
    let n_alpha = alphas.len();
    let mut body = Vec::with_capacity(machs.len() * n_alpha * alts.len());
    let mut fin = Vec::with_capacity(body.capacity());
    for &m in &machs {
        // Per altitude: the page, or a hole.
        let mut cols = Vec::with_capacity(alts.len());
        for &h in &alts {
            let p = points.iter().find(|p| p.0 == m && p.1 == h).ok_or_else(|| {
                conv(None, format!("the pages do not make a full grid: no page for Mach {m} at altitude {h} m"))
            })?;
            cols.push((p.2, p.3, fin_columns(p.2, p.3, vref)?));
        }
        for j in 0..n_alpha {
            for (t, f, fc) in &cols {
                let (fcn, fcm, fca) = f.map_or((0.0, 0.0, 0.0), |f| (f.cn[j], f.cm[j], f.ca[j]));
                body.push([t.cn[j] - fcn, t.ca[j] - fca, t.cm[j] - fcm]);
                fin.push(fc[j]);
            }
        }
    }
    let grid = |kind, points: &[[f64; 3]]| {
        CoefficientTable::from_grid(
            kind,
            source,
            [machs.clone(), alphas.clone(), alts.clone()],
            points,
            policy,
        )
        .map_err(|e| conv(None, e.to_string()))
    };
    Ok(DatcomTables {
        body: grid(TableKind::Body, &body)?,
        fin: grid(TableKind::Fin, &fin)?,
    })
}

/// One fin's `[cn, ca, x_cp_m]` at every alpha of a page (see [`tables`]).
fn fin_columns(
    t: &StaticTable,
    f: Option<&FinSetTable>,
    vref: &VehicleReference,
) -> Result<Vec<[f64; 3]>, ConversionError> {
    let (Some(f), Some((n, x_le))) = (f, vref.fins) else {
        return Ok(vec![[0.0; 3]; t.alpha_deg.len()]);
    };
    let nf = n as f64;
    let xcg = -vref.point_x;
    let x_cp = |j: usize| xcg - vref.length * f.cm[j] / f.cn[j] + x_le;
    let lifting: Vec<usize> = (0..f.cn.len())
        .filter(|&j| f.cn[j].abs() > CN_ZERO)
        .collect();
    if lifting.is_empty() {
        return Err(conv(
            Some(f.line),
            format!(
                "fin set {} has no normal force at any angle of attack: its centre of pressure is undefined",
                f.fin_set
            ),
        ));
    }
    Ok((0..f.cn.len())
        .map(|j| {
            let k = *lifting
                .iter()
                .min_by(|a, b| {
                    let da = (t.alpha_deg[**a] - t.alpha_deg[j]).abs();
                    let db = (t.alpha_deg[**b] - t.alpha_deg[j]).abs();
                    da.total_cmp(&db)
                })
                .unwrap_or(&j);
            [2.0 / nf * f.cn[j], f.ca[j] / nf, x_cp(k)]
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    const OGIVE: &str = include_str!("../../tests/data/datcom/ogive_two_fin_sets_for006.dat");
    const JAVELIN: &str = include_str!("../../tests/data/datcom/javelin_for006.dat");

    #[test]
    fn banner_and_case_number() {
        assert_eq!(
            banner(
                "1         ***** THE USAF AUTOMATED MISSILE DATCOM * REV 3/99 *****     CASE   12"
            ),
            Some(Some(12))
        );
        assert_eq!(
            banner("1         ***** THE USAF AUTOMATED MISSILE DATCOM * REV 3/99 *****"),
            Some(None)
        );
        assert_eq!(banner("    THE USAF AUTOMATED MISSILE DATCOM"), None);
    }

    #[test]
    fn resolution_is_half_the_last_digit() {
        assert_eq!(resolution("0.013"), 5e-4);
        assert_eq!(resolution("3.000E+06"), 500.0);
        assert_eq!(resolution("18.750"), 5e-4);
        assert_eq!(resolution(".20"), 5e-3);
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1.0)
    }

    /// Values read by eye from `ogive_two_fin_sets_for006.dat` (case 1, pages 7, 12, 22, 23).
    #[test]
    fn ogive_fixture_values_read_by_eye() {
        let d = parse(OGIVE).unwrap();
        assert_eq!(d.complete.len(), 1);
        let c = &d.complete[0];
        assert_eq!((c.case, c.line), (1, 687));
        assert_eq!(c.conditions.unit, LengthUnit::Feet);
        assert_eq!(c.conditions.mach, 2.36);
        assert_eq!(c.conditions.altitude, None);
        assert!(close(c.conditions.reynolds_per_m.unwrap(), 3.0e6 / 0.3048));
        assert!(close(
            c.conditions.reference_area.value,
            11.045 * 0.3048 * 0.3048
        ));
        assert!(close(c.conditions.moment_center.value, 18.75 * 0.3048));
        assert!(close(c.conditions.reference_length.value, 3.75 * 0.3048));
        assert_eq!(c.alpha_deg, [0.0, 4.0, 8.0, 12.0, 16.0, 20.0, 24.0, 28.0]);
        assert_eq!((c.cn[1], c.cm[1], c.ca[1]), (1.154, -1.462, 0.371));
        assert_eq!((c.cn[7], c.cm[7], c.ca[7]), (9.949, -12.031, 0.343));
        assert_eq!(c.cy.as_ref().unwrap()[1], 0.0);
        let dv = &d.derivatives[0];
        assert!(!dv.per_radian);
        assert_eq!((dv.cna[0], dv.cma[0]), (0.2739, -0.3603));
        assert!(close(
            dv.cna_per_rad()[0],
            0.2739 * 180.0 / std::f64::consts::PI
        ));
        // Body alone: CN-POTEN + CN-VISC + CN-SEP = 0.196 + 0.047 + 0.000 at 4 deg; the
        // blank CA-PROT cell is a zero, not a shift of CA-SEP into its place.
        let b = &d.body_alone[0];
        assert!(close(b.cn[1], 0.196 + 0.047));
        assert!(close(b.cm[1], 0.697 - 0.022));
        assert!(close(b.ca[0], 0.0560 + 0.0969 + 0.0897));
        assert_eq!(d.fin_sets.len(), 2);
        let f2 = d.fin_sets.iter().find(|f| f.fin_set == 2).unwrap();
        assert_eq!((f2.cn[1], f2.cm[1], f2.ca[1]), (0.3934, -1.7272, 0.1041));
    }

    /// Values read by eye from `javelin_for006.dat` (metres, `DERIV RAD`, altitude given).
    #[test]
    fn javelin_fixture_values_read_by_eye() {
        let d = parse(JAVELIN).unwrap();
        let machs: Vec<f64> = d
            .complete
            .iter()
            .filter(|t| t.case == 1)
            .map(|t| t.conditions.mach)
            .collect();
        assert_eq!(machs, [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]);
        let c = &d.complete[0];
        assert_eq!(c.conditions.unit, LengthUnit::Metres);
        assert_eq!(c.conditions.altitude, Some(0.0));
        assert_eq!(c.conditions.reference_area.value, 0.013);
        assert_eq!(c.conditions.reference_area.resolution, 5e-4);
        // The case's SREF = 1.266768698E-02 is what the printed 0.013 rounds.
        assert!(c.conditions.reference_area.admits(1.266768698e-2));
        assert!(!c.conditions.reference_area.admits(1.2e-2));
        assert_eq!(c.alpha_deg.len(), 20);
        assert_eq!(
            (c.alpha_deg[14], c.cn[14], c.cm[14], c.ca[14]),
            (5.0, 1.773, -8.489, 0.169)
        );
        let dv = &d.derivatives[0];
        assert!(dv.per_radian);
        assert_eq!(
            (dv.alpha_deg[0], dv.cna[0], dv.cma[0]),
            (-65.0, 9.1604, -64.4233)
        );
        assert_eq!(dv.cna_per_rad()[0], 9.1604);
        // No PART card: no body-alone or fin-set pages.
        assert!(d.body_alone.is_empty() && d.fin_sets.is_empty());
    }

    /// A file cut inside a page of coefficients is an error at its last line, never a
    /// shorter table.
    #[test]
    fn truncated_file_is_an_error_with_its_line() {
        let lines: Vec<&str> = OGIVE.lines().collect();
        // Cut after the conditions block of page 22 (line 687), before its table.
        let end = format!("\n{END_OF_JOB}\n");
        let cut = lines[..696].join("\n") + &end;
        let e = parse(&cut).unwrap_err();
        assert_eq!(e.line, 687, "{e}");
        assert!(e.message.contains("truncated"), "{e}");
        // Cut inside the conditions block.
        let cut = lines[..692].join("\n") + &end;
        let e = parse(&cut).unwrap_err();
        assert!(e.message.contains("REF AREA"), "{e}");
        // Cut between two rows of the table: no closing line.
        let cut = lines[..703].join("\n");
        let e = parse(&cut).unwrap_err();
        assert_eq!(e.line, 703, "{e}");
        assert!(e.message.contains("END OF JOB"), "{e}");
    }

    #[test]
    fn text_that_is_not_datcom_output_is_refused_at_line_one() {
        let e = parse("mach,alpha_deg,altitude_m,cn,ca,cm\n0.5,0,0,0,0.3,0\n").unwrap_err();
        assert_eq!((e.line, e.column), (1, 1));
    }

    #[test]
    fn a_cell_that_is_not_a_number_is_an_error_at_its_column() {
        let text = OGIVE.replacen(
            "          4.00     1.154    -1.462",
            "          4.00     1.1x4    -1.462",
            1,
        );
        let e = parse(&text).unwrap_err();
        assert_eq!((e.line, e.column), (701, 20), "{e}");
    }

    const FT: f64 = 0.3048;

    fn ogive_vehicle() -> VehicleReference {
        VehicleReference {
            area: 11.045 * FT * FT,
            length: 3.75 * FT,
            point_x: -18.75 * FT,
            // Fin set 2: four panels, root leading edge XLE = 31.915 ft aft of the nose.
            fins: Some((4, -31.915 * FT)),
        }
    }

    fn ogive_tables(sel: Selection, v: &VehicleReference) -> Result<DatcomTables, ConversionError> {
        let d = parse(OGIVE).unwrap();
        tables(&d, std::path::Path::new("o.dat"), sel, v, OutOfRange::Clamp)
    }

    /// Body + fins is DATCOM's complete configuration at every alpha: C_N = cn_b + (n/2)
    /// cn_f and C_m = cm_b - (n/2) cn_f (x_cp - XCG)/LREF; the fin's centre of pressure at
    /// 4 deg by hand: 18.75 + 3.75 x 1.7272/0.3934 - 31.915 = 3.29922 ft.
    #[test]
    fn body_plus_fins_rebuild_the_complete_configuration() {
        let v = ogive_vehicle();
        let sel = Selection {
            case: None,
            fin_set: Some(2),
        };
        let t = ogive_tables(sel, &v).unwrap();
        let d = parse(OGIVE).unwrap();
        let c = &d.complete[0];
        for (j, &a) in c.alpha_deg.iter().enumerate() {
            let b = t.body.body(2.36, a, 0.0).unwrap();
            let f = t.fin.fin(2.36, a, 0.0).unwrap();
            assert!((b.cn + 2.0 * f.cn - c.cn[j]).abs() < 1e-12, "alpha {a}");
            assert!((b.ca + 4.0 * f.ca - c.ca[j]).abs() < 1e-12, "alpha {a}");
            let x_cp_aft_nose = f.x_cp_m + 31.915 * FT;
            let cm_f = -2.0 * f.cn * (x_cp_aft_nose - 18.75 * FT) / (3.75 * FT);
            assert!((b.cm + cm_f - c.cm[j]).abs() < 1e-12, "alpha {a}");
        }
        let f4 = t.fin.fin(2.36, 4.0, 0.0).unwrap();
        let by_hand = (18.75 + 3.75 * 1.7272 / 0.3934 - 31.915) * FT;
        assert!((f4.x_cp_m - by_hand).abs() < 1e-12);
        // At alpha = 0 the fin set has no normal force: the 4 deg centre of pressure holds.
        assert_eq!(t.fin.fin(2.36, 0.0, 0.0).unwrap().x_cp_m, f4.x_cp_m);
    }

    #[test]
    fn two_fin_sets_need_a_choice_and_a_missing_one_is_named() {
        let v = ogive_vehicle();
        let e = ogive_tables(Selection::default(), &v).unwrap_err();
        assert!(e.message.contains("fin_set = N"), "{e}");
        let e = ogive_tables(
            Selection {
                case: None,
                fin_set: Some(3),
            },
            &v,
        )
        .unwrap_err();
        assert!(e.message.contains("no fin set 3"), "{e}");
        let e = ogive_tables(
            Selection {
                case: Some(2),
                fin_set: Some(2),
            },
            &v,
        )
        .unwrap_err();
        assert!(e.message.contains("case 2"), "{e}");
    }

    /// A vehicle whose reference area, length or point is not what DATCOM printed is refused,
    /// naming the quantity; the printed resolution is the tolerance.
    #[test]
    fn reference_quantities_must_agree_with_the_vehicle() {
        let sel = Selection {
            case: None,
            fin_set: Some(2),
        };
        let ok = ogive_vehicle();
        // Within the printed resolution (11.045 ft^2 to 0.0005 ft^2).
        let mut v = ok;
        v.area = 11.0454 * FT * FT;
        assert!(ogive_tables(sel, &v).is_ok());
        for (which, v) in [
            (
                Mismatch::Area,
                VehicleReference {
                    area: 11.046 * FT * FT,
                    ..ok
                },
            ),
            (
                Mismatch::Length,
                VehicleReference {
                    length: 3.8 * FT,
                    ..ok
                },
            ),
            (
                Mismatch::Point,
                VehicleReference {
                    point_x: -18.0 * FT,
                    ..ok
                },
            ),
        ] {
            let e = ogive_tables(sel, &v).unwrap_err();
            assert_eq!(e.mismatch, Some(which), "{e}");
            assert_eq!(e.line, Some(687));
        }
    }

    #[test]
    fn a_file_without_the_part_card_cannot_split_body_and_fins() {
        let d = parse(JAVELIN).unwrap();
        let v = VehicleReference {
            area: 1.266768698e-2,
            length: 0.05,
            point_x: -0.446,
            fins: Some((4, -1.011)),
        };
        let e = tables(
            &d,
            std::path::Path::new("j.dat"),
            Selection::default(),
            &v,
            OutOfRange::Stop,
        )
        .unwrap_err();
        assert!(e.message.contains("PART"), "{e}");
        // Without fins, the body is the complete configuration; the deflection cases repeat
        // case 1's Mach numbers, so a case must be chosen.
        let v = VehicleReference { fins: None, ..v };
        let e = tables(
            &d,
            std::path::Path::new("j.dat"),
            Selection::default(),
            &v,
            OutOfRange::Stop,
        )
        .unwrap_err();
        assert!(e.message.contains("case = N"), "{e}");
        let t = tables(
            &d,
            std::path::Path::new("j.dat"),
            Selection {
                case: Some(1),
                fin_set: None,
            },
            &v,
            OutOfRange::Stop,
        )
        .unwrap();
        let b = t.body.body(0.1, 5.0, 0.0).unwrap();
        assert_eq!((b.cn, b.cm, b.ca), (1.773, -8.489, 0.169));
        // Between Mach 0.1 and 0.2 the table interpolates.
        assert!(t.body.body(0.15, 5.0, 0.0).is_ok());
    }
}
