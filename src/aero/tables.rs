//! Aerodynamic coefficient tables (thesis 5.5; the thesis tabulated Missile DATCOM output
//! over Mach, angle of attack and altitude).
//!
//! # CSV layout
//!
//! Long format, one grid point per row, comma separated, with a header line:
//!
//! ```text
//! # body coefficients (comment lines start with '#'; blank lines are ignored)
//! mach,alpha_deg,altitude_m,cn,ca,cm
//! 0.5,0,0,0,0.31,0
//! 0.5,2,0,0.0698,0.31,0.91
//! ...
//! ```
//!
//! - Body tables ([`TableKind::Body`]): `mach,alpha_deg,altitude_m,cn,ca,cm`. C_N and C_A are
//!   the normal and axial force coefficients of the fuselage alone in the coefficient frame,
//!   C_M the pitching moment about the coefficient reference point (the nominal c.g.),
//!   positive nose up; all on the reference area S and reference length b_b of eqs.
//!   (5.3.1)-(5.3.3).
//! - Fin tables ([`TableKind::Fin`]): `mach,alpha_deg,altitude_m,cn,ca,x_cp_m`: the normal
//!   and axial force coefficients of ONE fin (body-fin interference included) at its own
//!   angle of attack alpha_f (5.4.5)-(5.4.14), on the same reference area S, and the
//!   chordwise centre of pressure in metres aft of the root-chord leading edge.
//!
//! - Optional rate columns, body tables only: `mach,alpha_deg,altitude_m,cn,ca,cm,cn_q,cm_q`.
//!   `cn_q` is C_Nq + C_Nα̇ and `cm_q` is C_mq + C_mα̇ of the fuselage alone, per radian of
//!   the non-dimensional rate `ω b_b/(2V)`, for a rotation about the moment reference point
//!   with the angle of attack taken there (the convention of the thesis' C_Nα̇, C_Mα̇ in
//!   (5.3.7)-(5.3.8), whose α̇ (5.3.22) is the kinematic rate of the flow direction in the
//!   rotating nodal frame, `q` in a pure pitch rotation; see
//!   [`crate::runtime::forces::body_aero`]). Positive `cn_q` is a normal force in the
//!   direction of positive C_N for a nose-up rate; pitch damping is `cm_q < 0`. A table
//!   without these columns stays valid; `body_aero { rate_terms = true }` then refuses to
//!   start (it has no derivatives to apply). Fin tables hold no rate columns: the fin block
//!   sees the rotation through the velocity of the fin itself (5.4.8).
//!
//! - Optional roll columns, body tables with the rate columns only:
//!   `mach,alpha_deg,altitude_m,cn,ca,cm,cn_q,cm_q,cl_0,cl_p`. `cl_0` is the roll moment
//!   coefficient at zero roll rate (about body +x, on S and b_b: the cant of the further,
//!   rigid fin sets, whose aerodynamics the body table holds) and `cl_p` the roll damping
//!   derivative `dC_l / d(p b_b/(2V))` per radian, negative for damping. The built-in
//!   estimator writes them for a vehicle with further fin sets
//!   ([`crate::aero::estimator::fin_set_roll`]); the body block applies them whenever the
//!   table has them ([`crate::runtime::forces::body_aero`]).
//!
//! The grid must be full: every combination of the distinct Mach, alpha and altitude values
//! present must appear exactly once. Rows may come in any order, but each axis must introduce
//! its values in strictly increasing order (a value smaller than one already seen on the same
//! axis, and not itself seen before, is reported as a non-monotonic axis). Angles are degrees,
//! altitude metres. All numbers must be finite.
//!
//! # Lookup
//!
//! Multilinear (trilinear) interpolation between the eight surrounding grid points; an axis
//! with a single value is constant along it. Outside an axis range the table's
//! [`OutOfRange`] policy applies: `Stop` returns [`TableError::OutOfRange`] naming the axis,
//! value and range; `Clamp` holds the edge value. One exception makes every table cover a
//! launch from Mach 0: below the lowest Mach of a table whose lowest Mach is at most
//! [`HELD_BELOW_MACH`] (0.3) the lowest-Mach values are held under either policy. Subsonic
//! coefficients tend to constants as M -> 0 (the Prandtl-Glauert factor 1/sqrt(1 - M^2)
//! differs from 1 by less than 4.9 % below M = 0.3), so the hold is the incompressible
//! limit, not an extrapolation. Lookups do not allocate: the grid index
//! uses precomputed strides.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::check::ir::OutOfRange;

/// Below the lowest Mach of a table that starts at or below this Mach, the lowest-Mach
/// values are held (the incompressible limit; see the module doc).
pub const HELD_BELOW_MACH: f64 = 0.3;

/// Which coefficients a table holds (three value columns after the three axes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableKind {
    /// Fuselage alone: `cn, ca, cm`.
    Body,
    /// One fin: `cn, ca, x_cp_m`.
    Fin,
}

impl TableKind {
    /// The six column names, in order.
    pub fn columns(self) -> [&'static str; 6] {
        match self {
            TableKind::Body => ["mach", "alpha_deg", "altitude_m", "cn", "ca", "cm"],
            TableKind::Fin => ["mach", "alpha_deg", "altitude_m", "cn", "ca", "x_cp_m"],
        }
    }

    /// The header line.
    pub fn header(self) -> String {
        self.columns().join(",")
    }

    /// The optional rate columns after the six of [`Self::columns`] (body tables only).
    pub fn rate_columns(self) -> &'static [&'static str] {
        match self {
            TableKind::Body => &RATE_COLUMNS,
            TableKind::Fin => &[],
        }
    }

    /// The header line with the rate columns.
    pub fn header_with_rates(self) -> String {
        std::iter::once(self.header().as_str())
            .chain(self.rate_columns().iter().copied())
            .collect::<Vec<_>>()
            .join(",")
    }

    /// The optional roll columns after the rate columns (body tables only).
    pub fn roll_columns(self) -> &'static [&'static str] {
        match self {
            TableKind::Body => &ROLL_COLUMNS,
            TableKind::Fin => &[],
        }
    }

    /// The header line with the rate and the roll columns.
    pub fn header_with_roll(self) -> String {
        std::iter::once(self.header_with_rates().as_str())
            .chain(self.roll_columns().iter().copied())
            .collect::<Vec<_>>()
            .join(",")
    }

    /// What the header may be, for errors.
    fn expected_header(self) -> String {
        if self.rate_columns().is_empty() {
            self.header()
        } else {
            format!(
                "{}`, `{}` or `{}",
                self.header(),
                self.header_with_rates(),
                self.header_with_roll()
            )
        }
    }
}

/// The optional rate columns of a body table (module doc).
pub const RATE_COLUMNS: [&str; 2] = ["cn_q", "cm_q"];

/// The optional roll columns of a body table (module doc).
pub const ROLL_COLUMNS: [&str; 2] = ["cl_0", "cl_p"];

/// Most value columns a table holds (three coefficients, two rate derivatives, two roll
/// coefficients).
const MAX_VALUES: usize = 7;

/// One of the three table axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    Mach,
    AlphaDeg,
    AltitudeM,
}

impl fmt::Display for Axis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Axis::Mach => "mach",
            Axis::AlphaDeg => "alpha_deg",
            Axis::AltitudeM => "altitude_m",
        })
    }
}

const AXES: [Axis; 3] = [Axis::Mach, Axis::AlphaDeg, Axis::AltitudeM];

/// Errors reading, building or looking up a coefficient table. Reader errors name the file
/// and the 1-based line.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TableError {
    #[error("{}: cannot read coefficient table: {message}", path.display())]
    Io { path: PathBuf, message: String },
    #[error("{}: no header line (expected `{expected}`)", path.display())]
    MissingHeader { path: PathBuf, expected: String },
    #[error("{}:{line}: header must be `{expected}`, found `{found}`", path.display())]
    Header {
        path: PathBuf,
        line: usize,
        expected: String,
        found: String,
    },
    #[error("{}:{line}: expected {expected} comma-separated fields (as the header), found {found}", path.display())]
    FieldCount {
        path: PathBuf,
        line: usize,
        expected: usize,
        found: usize,
    },
    #[error("{}:{line}: column `{column}` is not a number: `{text}`", path.display())]
    NotANumber {
        path: PathBuf,
        line: usize,
        column: &'static str,
        text: String,
    },
    #[error("{}:{line}: column `{column}` is not finite: {value}", path.display())]
    NonFinite {
        path: PathBuf,
        line: usize,
        column: &'static str,
        value: f64,
    },
    #[error(
        "{}:{line}: duplicate grid point mach={mach}, alpha_deg={alpha_deg}, altitude_m={altitude_m} (first on line {first_line})",
        path.display()
    )]
    Duplicate {
        path: PathBuf,
        line: usize,
        first_line: usize,
        mach: f64,
        alpha_deg: f64,
        altitude_m: f64,
    },
    #[error(
        "{}:{line}: axis `{axis}` is not increasing: new value {value} comes after {previous}",
        path.display()
    )]
    NonMonotonic {
        path: PathBuf,
        line: usize,
        axis: Axis,
        value: f64,
        previous: f64,
    },
    #[error(
        "{}: grid hole: no row for mach={mach}, alpha_deg={alpha_deg}, altitude_m={altitude_m} (the grid must hold every combination of its {n_mach} x {n_alpha} x {n_altitude} axis values; last data line {last_line})",
        path.display()
    )]
    Hole {
        path: PathBuf,
        last_line: usize,
        mach: f64,
        alpha_deg: f64,
        altitude_m: f64,
        n_mach: usize,
        n_alpha: usize,
        n_altitude: usize,
    },
    #[error("{}: the table has no data rows", path.display())]
    Empty { path: PathBuf },
    #[error("{}: {axis} = {value} is outside the table range [{min}, {max}]", path.display())]
    OutOfRange {
        path: PathBuf,
        axis: Axis,
        value: f64,
        min: f64,
        max: f64,
    },
    #[error("{}: lookup with non-finite {axis} = {value}", path.display())]
    NonFiniteQuery {
        path: PathBuf,
        axis: Axis,
        value: f64,
    },
    #[error("{}: grid of {expected} points given {found} value rows", path.display())]
    Shape {
        path: PathBuf,
        expected: usize,
        found: usize,
    },
}

/// Body coefficients at one flight condition (eqs. (5.3.1)-(5.3.3)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyCoefficients {
    pub cn: f64,
    pub ca: f64,
    pub cm: f64,
}

/// Coefficients of one fin at one flight condition (eqs. (5.4.5), (5.4.12), (5.4.14)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FinCoefficients {
    pub cn: f64,
    pub ca: f64,
    /// Chordwise centre of pressure, m aft of the root-chord leading edge.
    pub x_cp_m: f64,
}

/// Rate derivatives of the fuselage at one flight condition (the optional `cn_q`, `cm_q`
/// columns; module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyRateCoefficients {
    /// C_Nq + C_Nα̇, per rad of `ω b/(2V)`.
    pub cn_q: f64,
    /// C_mq + C_mα̇ about the moment reference point, per rad of `ω b/(2V)`.
    pub cm_q: f64,
}

/// Roll coefficients of a body table at one flight condition (the optional `cl_0`, `cl_p`
/// columns; module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyRollCoefficients {
    /// Roll moment coefficient at zero roll rate (about body +x).
    pub cl_0: f64,
    /// `dC_l / d(p b_b/(2V))`, per rad.
    pub cl_p: f64,
}

/// The bracketing interval of a caller's previous query on each axis of a
/// [`CoefficientTable`] (Mach, alpha, altitude), tried first by the next query: a hint
/// only, it changes how fast an interval is found, never which (`CoefficientTable::bracket`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TableHint([usize; 3]);

/// A full-grid coefficient table over (Mach, alpha in degrees, altitude in m).
#[derive(Clone, Debug, PartialEq)]
pub struct CoefficientTable {
    kind: TableKind,
    /// Where the table came from (for errors); a label for built tables.
    source: PathBuf,
    axes: [Vec<f64>; 3],
    /// `width` values per grid point (3, 5 with the rate columns, 7 with the roll columns
    /// too); point (i, j, k)
    /// starts at i*strides[0] + j*strides[1] + k*strides[2].
    values: Vec<f64>,
    width: usize,
    strides: [usize; 3],
    policy: OutOfRange,
}

impl CoefficientTable {
    /// Builds a table from its axes and the three values of every grid point in row-major
    /// order (Mach slowest, altitude fastest). Axes must be strictly increasing and every
    /// number finite.
    pub fn from_grid(
        kind: TableKind,
        source: impl Into<PathBuf>,
        axes: [Vec<f64>; 3],
        points: &[[f64; 3]],
        policy: OutOfRange,
    ) -> Result<Self, TableError> {
        let source = source.into();
        for (a, axis) in axes.iter().zip(AXES) {
            if a.is_empty() {
                return Err(TableError::Empty { path: source });
            }
            for (k, w) in a.windows(2).enumerate() {
                if w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater) {
                    return Err(TableError::NonMonotonic {
                        path: source,
                        line: k + 2,
                        axis,
                        value: w[1],
                        previous: w[0],
                    });
                }
            }
        }
        let expected = axes[0].len() * axes[1].len() * axes[2].len();
        if points.len() != expected {
            return Err(TableError::Shape {
                path: source,
                expected,
                found: points.len(),
            });
        }
        let columns = kind.columns();
        for (n, p) in points.iter().enumerate() {
            for (c, &v) in p.iter().enumerate() {
                if !v.is_finite() {
                    return Err(TableError::NonFinite {
                        path: source,
                        line: n + 2,
                        column: columns[3 + c],
                        value: v,
                    });
                }
            }
        }
        let strides = [3 * axes[1].len() * axes[2].len(), 3 * axes[2].len(), 3];
        let values = points.iter().flat_map(|p| p.iter().copied()).collect();
        Ok(CoefficientTable {
            kind,
            source,
            axes,
            values,
            width: 3,
            strides,
            policy,
        })
    }

    /// Adds (or replaces) the rate columns (module doc) of every grid point, in the order of
    /// [`Self::from_grid`]; body tables only, every number finite; roll columns are kept.
    pub fn with_rates(self, rates: &[[f64; 2]]) -> Result<Self, TableError> {
        let columns = self.kind.rate_columns();
        self.with_pair(3, columns, rates)
    }

    /// Adds (or replaces) the roll columns (module doc) of every grid point, in the order of
    /// [`Self::from_grid`], to a body table with the rate columns; every number finite.
    pub fn with_roll(self, roll: &[[f64; 2]]) -> Result<Self, TableError> {
        let columns = self.kind.roll_columns();
        self.with_pair(5, columns, roll)
    }

    /// Puts the two columns `columns` (values `pairs`, one per grid point) at value columns
    /// `from` and `from + 1` of a table with at least `from` of them, keeping the columns
    /// before and after: a shape error when the table is narrower, the kind has no such
    /// columns or the count differs; a non-finite value names its column.
    fn with_pair(
        self,
        from: usize,
        columns: &'static [&'static str],
        pairs: &[[f64; 2]],
    ) -> Result<Self, TableError> {
        let n = self.values.len() / self.width;
        let fits = columns.len() == 2 && self.width >= from;
        if !fits || pairs.len() != n {
            return Err(TableError::Shape {
                path: self.source,
                expected: if fits { n } else { 0 },
                found: pairs.len(),
            });
        }
        for (k, r) in pairs.iter().enumerate() {
            for (c, &v) in r.iter().enumerate() {
                if !v.is_finite() {
                    return Err(TableError::NonFinite {
                        path: self.source,
                        line: k + 2,
                        column: columns[c],
                        value: v,
                    });
                }
            }
        }
        let (old, w) = (self.width, self.width.max(from + 2));
        let mut values = Vec::with_capacity(w * n);
        for (k, r) in pairs.iter().enumerate() {
            let row = &self.values[old * k..old * (k + 1)];
            values.extend_from_slice(&row[..from]);
            values.extend_from_slice(r);
            values.extend_from_slice(row.get(from + 2..).unwrap_or(&[]));
        }
        let (n1, n2) = (self.axes[1].len(), self.axes[2].len());
        Ok(CoefficientTable {
            values,
            width: w,
            strides: [w * n1 * n2, w * n2, w],
            ..self
        })
    }

    /// True when the table holds the rate columns.
    pub fn has_rates(&self) -> bool {
        self.width >= 5
    }

    /// True when the table holds the roll columns (after the rate columns).
    pub fn has_roll(&self) -> bool {
        self.width == 7
    }

    /// Reads a table file (see the module doc for the layout).
    pub fn read_csv(kind: TableKind, path: &Path, policy: OutOfRange) -> Result<Self, TableError> {
        let text = std::fs::read_to_string(path).map_err(|e| TableError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        Self::parse_csv(kind, path, &text, policy)
    }

    /// Parses table text; `path` names the source in errors.
    pub fn parse_csv(
        kind: TableKind,
        path: &Path,
        text: &str,
        policy: OutOfRange,
    ) -> Result<Self, TableError> {
        let base = kind.columns();
        let with_rates: Vec<&'static str> =
            base.iter().chain(kind.rate_columns()).copied().collect();
        let with_roll: Vec<&'static str> = with_rates
            .iter()
            .chain(kind.roll_columns())
            .copied()
            .collect();
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let Some((hline, header)) = lines.next() else {
            return Err(TableError::MissingHeader {
                path: path.to_path_buf(),
                expected: kind.expected_header(),
            });
        };
        let found: Vec<&str> = header.split(',').map(str::trim).collect();
        let columns: &[&'static str] = if found == base {
            &base
        } else if found.len() > base.len() && found == with_rates {
            &with_rates
        } else if found.len() > with_rates.len() && found == with_roll {
            &with_roll
        } else {
            return Err(TableError::Header {
                path: path.to_path_buf(),
                line: hline,
                expected: kind.expected_header(),
                found: header.to_string(),
            });
        };
        let ncol = columns.len();
        // Rows as (line, [numbers]); the rate columns, when present, follow the first six,
        // and the roll columns the rate columns.
        let mut rows: Vec<(usize, [f64; 10])> = Vec::new();
        let mut axes: [Vec<f64>; 3] = [Vec::new(), Vec::new(), Vec::new()];
        for (line, l) in lines {
            let fields: Vec<&str> = l.split(',').map(str::trim).collect();
            if fields.len() != ncol {
                return Err(TableError::FieldCount {
                    path: path.to_path_buf(),
                    line,
                    expected: ncol,
                    found: fields.len(),
                });
            }
            let mut row = [0.0; 10];
            for (c, f) in fields.iter().enumerate() {
                let v: f64 = f.parse().map_err(|_| TableError::NotANumber {
                    path: path.to_path_buf(),
                    line,
                    column: columns[c],
                    text: (*f).to_string(),
                })?;
                if !v.is_finite() {
                    return Err(TableError::NonFinite {
                        path: path.to_path_buf(),
                        line,
                        column: columns[c],
                        value: v,
                    });
                }
                row[c] = v;
            }
            for (a, axis) in AXES.iter().enumerate() {
                let v = row[a];
                if !axes[a].contains(&v) {
                    if let Some(&last) = axes[a].last()
                        && v < last
                    {
                        return Err(TableError::NonMonotonic {
                            path: path.to_path_buf(),
                            line,
                            axis: *axis,
                            value: v,
                            previous: last,
                        });
                    }
                    axes[a].push(v);
                }
            }
            rows.push((line, row));
        }
        let Some(&(last_line, _)) = rows.last() else {
            return Err(TableError::Empty {
                path: path.to_path_buf(),
            });
        };
        let n = [axes[0].len(), axes[1].len(), axes[2].len()];
        let mut slot_line = vec![0usize; n[0] * n[1] * n[2]];
        let mut points = vec![[0.0; 3]; n[0] * n[1] * n[2]];
        let mut rates = vec![[0.0; 2]; n[0] * n[1] * n[2]];
        let mut roll = vec![[0.0; 2]; n[0] * n[1] * n[2]];
        for &(line, row) in &rows {
            // Each value is in its axis (we pushed it), so position() succeeds.
            let idx: Vec<usize> = (0..3)
                .map(|a| axes[a].iter().position(|&x| x == row[a]).unwrap_or(0))
                .collect();
            let slot = (idx[0] * n[1] + idx[1]) * n[2] + idx[2];
            if slot_line[slot] != 0 {
                return Err(TableError::Duplicate {
                    path: path.to_path_buf(),
                    line,
                    first_line: slot_line[slot],
                    mach: row[0],
                    alpha_deg: row[1],
                    altitude_m: row[2],
                });
            }
            slot_line[slot] = line;
            points[slot] = [row[3], row[4], row[5]];
            rates[slot] = [row[6], row[7]];
            roll[slot] = [row[8], row[9]];
        }
        if let Some(slot) = slot_line.iter().position(|&l| l == 0) {
            let (i, rest) = (slot / (n[1] * n[2]), slot % (n[1] * n[2]));
            let (j, k) = (rest / n[2], rest % n[2]);
            return Err(TableError::Hole {
                path: path.to_path_buf(),
                last_line,
                mach: axes[0][i],
                alpha_deg: axes[1][j],
                altitude_m: axes[2][k],
                n_mach: n[0],
                n_alpha: n[1],
                n_altitude: n[2],
            });
        }
        let table = Self::from_grid(kind, path, axes, &points, policy)?;
        match ncol {
            6 => Ok(table),
            8 => table.with_rates(&rates),
            _ => table.with_rates(&rates)?.with_roll(&roll),
        }
    }

    /// The table in the CSV layout of the module doc (values printed so they read back
    /// exactly).
    pub fn to_csv(&self) -> String {
        let mut s = if self.has_roll() {
            self.kind.header_with_roll()
        } else if self.has_rates() {
            self.kind.header_with_rates()
        } else {
            self.kind.header()
        };
        s.push('\n');
        for (i, m) in self.axes[0].iter().enumerate() {
            for (j, a) in self.axes[1].iter().enumerate() {
                for (k, h) in self.axes[2].iter().enumerate() {
                    let o = i * self.strides[0] + j * self.strides[1] + k * self.strides[2];
                    s.push_str(&format!("{m},{a},{h}"));
                    for v in &self.values[o..o + self.width] {
                        s.push_str(&format!(",{v}"));
                    }
                    s.push('\n');
                }
            }
        }
        s
    }

    /// Writes [`Self::to_csv`] to `path`.
    pub fn write_csv(&self, path: &Path) -> Result<(), TableError> {
        std::fs::write(path, self.to_csv()).map_err(|e| TableError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        })
    }

    /// Where the table came from (a file, or a label for built tables).
    pub fn source(&self) -> &Path {
        &self.source
    }

    /// What the table holds.
    pub fn kind(&self) -> TableKind {
        self.kind
    }

    /// The values of one axis.
    pub fn axis(&self, axis: Axis) -> &[f64] {
        &self.axes[axis as usize]
    }

    /// The out-of-range policy.
    pub fn policy(&self) -> OutOfRange {
        self.policy
    }

    /// Is `value` on axis `a` in the held low-Mach band `0 <= M < M_min` (module doc)?
    fn held_below(&self, a: usize, value: f64) -> bool {
        let min = self.axes[a][0];
        a == Axis::Mach as usize && (0.0..min).contains(&value) && min <= HELD_BELOW_MACH
    }

    /// Is a query at `value` on `axis` outside what the table covers (the range of the axis,
    /// extended down to Mach 0 for tables starting at or below [`HELD_BELOW_MACH`])?
    pub fn outside(&self, axis: Axis, value: f64) -> bool {
        let a = &self.axes[axis as usize];
        (value < a[0] || value > a[a.len() - 1]) && !self.held_below(axis as usize, value)
    }

    /// Bracketing index and fraction on one axis, after the out-of-range policy. A value
    /// inside the axis takes the inlined path; a non-finite or outside one goes to
    /// [`Self::locate_outside`]. `hint` is the interval of the caller's previous query on
    /// this axis, tried first ([`Self::bracket`]) and updated.
    #[inline]
    fn locate(&self, a: usize, value: f64, hint: &mut usize) -> Result<(usize, f64), TableError> {
        let axis = &self.axes[a];
        let (min, max) = (axis[0], axis[axis.len() - 1]);
        if !(value >= min && value <= max) {
            return self.locate_outside(a, value, hint);
        }
        Ok(Self::bracket(axis, value, hint))
    }

    /// [`Self::locate`] for a value not inside `[min, max]` of its axis: an error when it is
    /// not finite, or outside under [`OutOfRange::Stop`] (but for the held low-Mach band);
    /// else clamped to the edge.
    #[cold]
    #[inline(never)]
    fn locate_outside(
        &self,
        a: usize,
        value: f64,
        hint: &mut usize,
    ) -> Result<(usize, f64), TableError> {
        let axis = &self.axes[a];
        if !value.is_finite() {
            return Err(TableError::NonFiniteQuery {
                path: self.source.clone(),
                axis: AXES[a],
                value,
            });
        }
        let (min, max) = (axis[0], axis[axis.len() - 1]);
        if self.policy == OutOfRange::Stop && !self.held_below(a, value) {
            return Err(TableError::OutOfRange {
                path: self.source.clone(),
                axis: AXES[a],
                value,
                min,
                max,
            });
        }
        Ok(Self::bracket(axis, value.clamp(min, max), hint))
    }

    /// Index `i` and fraction `t` of `v` (inside the axis) between nodes `i` and `i + 1`:
    /// `i` = (the first index whose value exceeds `v`, kept within `1..len-1`) - 1, i.e.
    /// `axis[i] <= v < axis[i + 1]`, or `i = len - 2` at the upper end. The interval `hint`
    /// is tried first and is taken only when it is that `i` (the axis ascends strictly), so
    /// the result does not depend on the hint; the search runs only when the query left it.
    #[inline]
    fn bracket(axis: &[f64], v: f64, hint: &mut usize) -> (usize, f64) {
        let len = axis.len();
        if len == 1 {
            return (0, 0.0);
        }
        let h = *hint;
        let i = if h + 1 < len && axis[h] <= v && (v < axis[h + 1] || h + 2 == len) {
            h
        } else {
            axis.partition_point(|&x| x <= v).clamp(1, len - 1) - 1
        };
        *hint = i;
        (i, (v - axis[i]) / (axis[i + 1] - axis[i]))
    }

    /// Trilinear interpolation of the three coefficient columns at (Mach, alpha deg,
    /// altitude m).
    pub fn lookup(
        &self,
        mach: f64,
        alpha_deg: f64,
        altitude_m: f64,
    ) -> Result<[f64; 3], TableError> {
        let v = self.interpolate(mach, alpha_deg, altitude_m, &mut TableHint::default())?;
        Ok([v[0], v[1], v[2]])
    }

    /// Trilinear interpolation of every value column (the unused tail stays zero).
    ///
    /// The eight corners in the order of their index (axis 0 the lowest bit), each weight
    /// the product `w_0 w_1 w_2` of the axes' `1 - t` or `t` from the left, a corner of zero
    /// weight skipped (`t = 0` on an axis it takes the upper node of, which may lie past the
    /// end of a one-node axis): the arithmetic of [`Self::interpolate_by_corner`], written out
    /// per axis instead of per corner and axis, so the same bits (tested).
    fn interpolate(
        &self,
        mach: f64,
        alpha_deg: f64,
        altitude_m: f64,
        hint: &mut TableHint,
    ) -> Result<[f64; MAX_VALUES], TableError> {
        let [h0, h1, h2] = &mut hint.0;
        let (i0, t0) = self.locate(0, mach, h0)?;
        let (i1, t1) = self.locate(1, alpha_deg, h1)?;
        let (i2, t2) = self.locate(2, altitude_m, h2)?;
        let [s0, s1, s2] = self.strides;
        // Per axis: (weight, offset) of the lower and the upper node; the upper one is
        // absent when its weight t is exactly zero.
        let axis = |i: usize, t: f64, s: usize| [(1.0 - t, i * s), (t, (i + 1) * s)];
        let (a0, a1, a2) = (axis(i0, t0, s0), axis(i1, t1, s1), axis(i2, t2, s2));
        let (n0, n1, n2) = (
            1 + usize::from(t0 != 0.0),
            1 + usize::from(t1 != 0.0),
            1 + usize::from(t2 != 0.0),
        );
        let w_n = self.width;
        let mut out = [0.0; MAX_VALUES];
        for &(w2, o2) in &a2[..n2] {
            for &(w1, o1) in &a1[..n1] {
                for &(w0, o0) in &a0[..n0] {
                    let w = w0 * w1 * w2;
                    if w != 0.0 {
                        let o = o0 + o1 + o2;
                        for (x, v) in out.iter_mut().zip(&self.values[o..o + w_n]) {
                            *x += w * v;
                        }
                    }
                }
            }
        }
        Ok(out)
    }

    /// The reference form of [`Self::interpolate`]: corner by corner, axis by axis.
    #[cfg(test)]
    fn interpolate_by_corner(
        &self,
        mach: f64,
        alpha_deg: f64,
        altitude_m: f64,
    ) -> Result<[f64; MAX_VALUES], TableError> {
        let q = [mach, alpha_deg, altitude_m];
        let mut base = [(0usize, 0.0f64); 3];
        for a in 0..3 {
            base[a] = self.locate(a, q[a], &mut 0)?;
        }
        let mut out = [0.0; MAX_VALUES];
        let w_n = self.width;
        for corner in 0..8usize {
            let mut w = 1.0;
            let mut o = 0;
            for (a, &(i, t)) in base.iter().enumerate() {
                let up = (corner >> a) & 1 == 1;
                if up {
                    if t == 0.0 {
                        w = 0.0;
                        break;
                    }
                    w *= t;
                    o += (i + 1) * self.strides[a];
                } else {
                    w *= 1.0 - t;
                    o += i * self.strides[a];
                }
            }
            if w != 0.0 {
                for (x, v) in out.iter_mut().zip(&self.values[o..o + w_n]) {
                    *x += w * v;
                }
            }
        }
        Ok(out)
    }

    /// Body coefficients (for a [`TableKind::Body`] table).
    pub fn body(
        &self,
        mach: f64,
        alpha_deg: f64,
        altitude_m: f64,
    ) -> Result<BodyCoefficients, TableError> {
        let [cn, ca, cm] = self.lookup(mach, alpha_deg, altitude_m)?;
        Ok(BodyCoefficients { cn, ca, cm })
    }

    /// The rate derivatives of a body table at (Mach, alpha deg, altitude m), `None` when
    /// the table has no rate columns. Same interpolation and policy as [`Self::lookup`].
    pub fn body_rates(
        &self,
        mach: f64,
        alpha_deg: f64,
        altitude_m: f64,
    ) -> Result<Option<BodyRateCoefficients>, TableError> {
        if !self.has_rates() {
            return Ok(None);
        }
        let v = self.interpolate(mach, alpha_deg, altitude_m, &mut TableHint::default())?;
        Ok(Some(BodyRateCoefficients {
            cn_q: v[3],
            cm_q: v[4],
        }))
    }

    /// The roll coefficients of a body table at (Mach, alpha deg, altitude m), `None` when
    /// the table has no roll columns. Same interpolation and policy as [`Self::lookup`].
    pub fn body_roll(
        &self,
        mach: f64,
        alpha_deg: f64,
        altitude_m: f64,
    ) -> Result<Option<BodyRollCoefficients>, TableError> {
        if !self.has_roll() {
            return Ok(None);
        }
        let v = self.interpolate(mach, alpha_deg, altitude_m, &mut TableHint::default())?;
        Ok(Some(BodyRollCoefficients {
            cl_0: v[5],
            cl_p: v[6],
        }))
    }

    /// [`Self::body`], [`Self::body_rates`] and [`Self::body_roll`] from one interpolation (every column is
    /// interpolated at once, so the same bits as the two calls), the brackets tried first
    /// on the caller's `hint` (the flight's right-hand side: the flight condition moves
    /// little between evaluations).
    pub fn body_hinted(
        &self,
        mach: f64,
        alpha_deg: f64,
        altitude_m: f64,
        hint: &mut TableHint,
    ) -> Result<
        (
            BodyCoefficients,
            Option<BodyRateCoefficients>,
            Option<BodyRollCoefficients>,
        ),
        TableError,
    > {
        let v = self.interpolate(mach, alpha_deg, altitude_m, hint)?;
        let rates = self.has_rates().then_some(BodyRateCoefficients {
            cn_q: v[3],
            cm_q: v[4],
        });
        let roll = self.has_roll().then_some(BodyRollCoefficients {
            cl_0: v[5],
            cl_p: v[6],
        });
        Ok((
            BodyCoefficients {
                cn: v[0],
                ca: v[1],
                cm: v[2],
            },
            rates,
            roll,
        ))
    }

    /// [`Self::fin`] with the brackets tried first on the caller's `hint`.
    pub fn fin_hinted(
        &self,
        mach: f64,
        alpha_deg: f64,
        altitude_m: f64,
        hint: &mut TableHint,
    ) -> Result<FinCoefficients, TableError> {
        let v = self.interpolate(mach, alpha_deg, altitude_m, hint)?;
        Ok(FinCoefficients {
            cn: v[0],
            ca: v[1],
            x_cp_m: v[2],
        })
    }

    /// Fin coefficients (for a [`TableKind::Fin`] table).
    pub fn fin(
        &self,
        mach: f64,
        alpha_deg: f64,
        altitude_m: f64,
    ) -> Result<FinCoefficients, TableError> {
        let [cn, ca, x_cp_m] = self.lookup(mach, alpha_deg, altitude_m)?;
        Ok(FinCoefficients { cn, ca, x_cp_m })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> &'static Path {
        Path::new("t.csv")
    }

    /// Values linear in each axis: trilinear interpolation must reproduce them exactly,
    /// including the mixed term m*a*h which is multilinear.
    fn f(m: f64, a: f64, h: f64) -> [f64; 3] {
        [
            1.0 + 2.0 * m - 0.5 * a + 1e-4 * h,
            m * a * h * 1e-3,
            3.0 - a,
        ]
    }

    fn grid_text(skip: Option<usize>) -> String {
        let mut s = String::from("# test\nmach,alpha_deg,altitude_m,cn,ca,cm\n");
        let mut n = 0;
        for m in [0.5, 1.0, 2.0] {
            for a in [0.0, 5.0, 10.0, 20.0] {
                for h in [0.0, 5000.0] {
                    if Some(n) != skip {
                        let v = f(m, a, h);
                        s.push_str(&format!("{m},{a},{h},{},{},{}\n", v[0], v[1], v[2]));
                    }
                    n += 1;
                }
            }
        }
        s
    }

    /// The per-axis interpolation has the bits of the corner-by-corner reference on every
    /// query: random points inside and outside the grid, exactly on nodes (t = 0) and at
    /// the last node of an axis, on one-node axes, with and without rate columns; whatever
    /// the bracket hint: the previous query's (as in a flight), none, or an arbitrary one
    /// (also past the end of the axis).
    #[test]
    fn interpolation_by_axis_has_the_bits_of_the_corner_by_corner_form() {
        let mut rng = crate::testutil::XorShift64Star::new(0x9e37_79b9_7f4a_7c15);
        let mut next = move || rng.unit();
        let shapes: [[Vec<f64>; 3]; 4] = [
            [
                vec![0.5, 1.0, 2.0],
                vec![0.0, 5.0, 10.0, 20.0],
                vec![0.0, 5000.0],
            ],
            [vec![0.3], vec![-10.0, 0.0, 4.0, 10.0], vec![0.0]],
            [
                vec![0.1, 0.6, 0.9, 1.2, 3.0],
                vec![0.0],
                vec![0.0, 1e3, 3e3, 1e4],
            ],
            [vec![0.0, 2.0], vec![0.0, 90.0], vec![0.0, 20e3]],
        ];
        let mut compared = 0;
        for (s, axes) in shapes.iter().enumerate() {
            let n: usize = axes.iter().map(Vec::len).product();
            let points: Vec<[f64; 3]> = (0..n)
                .map(|_| [next() - 0.5, 0.1 * next(), 3.0 * next() - 1.0])
                .collect();
            let rates: Vec<[f64; 2]> = (0..n).map(|_| [next(), -next()]).collect();
            let plain = CoefficientTable::from_grid(
                TableKind::Body,
                "t",
                axes.clone(),
                &points,
                OutOfRange::Clamp,
            )
            .unwrap();
            let with_rates = plain.clone().with_rates(&rates).unwrap();
            for t in [&plain, &with_rates] {
                let mut carried = TableHint::default();
                for k in 0..4000 {
                    let q: [f64; 3] = std::array::from_fn(|a| {
                        let ax = &axes[a];
                        let (lo, hi) = (ax[0], ax[ax.len() - 1]);
                        match k % 4 {
                            // On a node: t = 0 on that axis (or the last node).
                            0 => ax[(next() * ax.len() as f64) as usize % ax.len()],
                            // Outside, clamped to an end.
                            1 => lo - 1.0 + (hi - lo + 2.0) * next(),
                            _ => lo + (hi - lo) * next(),
                        }
                    });
                    let want = t.interpolate_by_corner(q[0], q[1], q[2]).unwrap();
                    let mut arbitrary = TableHint(std::array::from_fn(|a| {
                        (next() * (axes[a].len() + 3) as f64) as usize
                    }));
                    for hint in [&mut carried, &mut TableHint::default(), &mut arbitrary] {
                        let got = t.interpolate(q[0], q[1], q[2], hint).unwrap();
                        assert_eq!(
                            got.map(f64::to_bits),
                            want.map(f64::to_bits),
                            "shape {s}, query {q:?}, hint {hint:?}: {got:?} vs {want:?}"
                        );
                        compared += 1;
                    }
                }
            }
        }
        assert_eq!(compared, 4 * 2 * 4000 * 3);
    }

    #[test]
    fn multilinear_reproduces_multilinear_data() {
        let t =
            CoefficientTable::parse_csv(TableKind::Body, p(), &grid_text(None), OutOfRange::Stop)
                .unwrap();
        for (m, a, h) in [
            (0.7, 3.0, 1000.0),
            (1.5, 12.5, 4999.0),
            (2.0, 20.0, 0.0),
            (0.5, 0.0, 2500.0),
        ] {
            let got = t.lookup(m, a, h).unwrap();
            let want = f(m, a, h);
            for c in 0..3 {
                assert!(
                    (got[c] - want[c]).abs() < 1e-12,
                    "{m} {a} {h} col {c}: {got:?} vs {want:?}"
                );
            }
        }
        // Hand value: m=0.75, a=2.5, h=2500: cn = 1 + 1.5 - 1.25 + 0.25 = 1.5.
        assert!((t.body(0.75, 2.5, 2500.0).unwrap().cn - 1.5).abs() < 1e-12);
    }

    #[test]
    fn tables_starting_at_low_mach_hold_their_values_down_to_mach_0() {
        let axes = [vec![0.3, 1.0], vec![0.0, 10.0], vec![0.0]];
        let points = [
            [1.0, 2.0, 3.0],
            [1.5, 2.5, 3.5],
            [4.0, 5.0, 6.0],
            [4.5, 5.5, 6.5],
        ];
        let t = CoefficientTable::from_grid(
            TableKind::Body,
            "low.csv",
            axes,
            &points,
            OutOfRange::Stop,
        )
        .unwrap();
        for m in [0.0, 0.1, 0.299_999] {
            assert_eq!(
                t.lookup(m, 5.0, 0.0).unwrap(),
                [1.25, 2.25, 3.25],
                "M = {m}"
            );
            assert!(!t.outside(Axis::Mach, m));
        }
        assert!(
            t.lookup(-0.01, 5.0, 0.0).is_err(),
            "negative Mach is not a Mach"
        );
        assert!(t.outside(Axis::Mach, -0.01));
        assert!(
            t.lookup(1.01, 5.0, 0.0).is_err(),
            "the upper end still stops"
        );
        // A table that starts above Mach 0.3 is not held: the stop policy stops there.
        let axes = [vec![0.5, 1.0], vec![0.0, 10.0], vec![0.0]];
        let t = CoefficientTable::from_grid(
            TableKind::Body,
            "high.csv",
            axes,
            &points,
            OutOfRange::Stop,
        )
        .unwrap();
        assert!(t.lookup(0.2, 5.0, 0.0).is_err());
        assert!(t.outside(Axis::Mach, 0.2));
    }

    #[test]
    fn stop_and_clamp_policies() {
        let stop =
            CoefficientTable::parse_csv(TableKind::Body, p(), &grid_text(None), OutOfRange::Stop)
                .unwrap();
        let e = stop.lookup(2.5, 5.0, 0.0).unwrap_err();
        assert_eq!(
            e,
            TableError::OutOfRange {
                path: p().into(),
                axis: Axis::Mach,
                value: 2.5,
                min: 0.5,
                max: 2.0
            }
        );
        assert!(
            e.to_string()
                .contains("mach = 2.5 is outside the table range [0.5, 2]")
        );
        let clamp =
            CoefficientTable::parse_csv(TableKind::Body, p(), &grid_text(None), OutOfRange::Clamp)
                .unwrap();
        assert_eq!(
            clamp.lookup(2.5, -3.0, 9000.0).unwrap(),
            clamp.lookup(2.0, 0.0, 5000.0).unwrap()
        );
        assert!(matches!(
            clamp.lookup(f64::NAN, 0.0, 0.0),
            Err(TableError::NonFiniteQuery { .. })
        ));
    }

    #[test]
    fn round_trip_through_csv() {
        let t = CoefficientTable::parse_csv(
            TableKind::Fin,
            p(),
            &grid_text(None).replace(",cm", ",x_cp_m"),
            OutOfRange::Clamp,
        )
        .unwrap();
        let back = CoefficientTable::parse_csv(TableKind::Fin, p(), &t.to_csv(), OutOfRange::Clamp)
            .unwrap();
        assert_eq!(t, back);
    }

    #[test]
    fn optional_rate_columns() {
        // A six-column body table stays valid and has no rates.
        let plain =
            CoefficientTable::parse_csv(TableKind::Body, p(), &grid_text(None), OutOfRange::Stop)
                .unwrap();
        assert!(!plain.has_rates());
        assert_eq!(plain.body_rates(0.7, 3.0, 0.0).unwrap(), None);
        // The same grid with rate columns linear in each axis: interpolated exactly, the
        // coefficient columns unchanged, and the CSV round trip exact.
        let mut text = String::from("mach,alpha_deg,altitude_m,cn,ca,cm,cn_q,cm_q\n");
        for line in grid_text(None).lines().skip(2) {
            let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
            let (m, a, h) = (v[0], v[1], v[2]);
            text.push_str(&format!("{line},{},{}\n", 100.0 + m, -300.0 - a + 1e-3 * h));
        }
        let rated =
            CoefficientTable::parse_csv(TableKind::Body, p(), &text, OutOfRange::Stop).unwrap();
        assert!(rated.has_rates());
        let r = rated.body_rates(0.75, 2.5, 2500.0).unwrap().unwrap();
        assert!(
            (r.cn_q - 100.75).abs() < 1e-12 && (r.cm_q + 300.0).abs() < 1e-12,
            "{r:?}"
        );
        assert_eq!(
            rated.lookup(0.75, 2.5, 2500.0).unwrap(),
            plain.lookup(0.75, 2.5, 2500.0).unwrap()
        );
        // The one-interpolation form of the flight has the values of the two calls.
        for t in [&plain, &rated] {
            let mut hint = TableHint::default();
            for q in [(0.75, 2.5, 2500.0), (1.5, 12.5, 4999.0), (0.7, 3.0, 0.0)] {
                assert_eq!(
                    t.body_hinted(q.0, q.1, q.2, &mut hint).unwrap(),
                    (
                        t.body(q.0, q.1, q.2).unwrap(),
                        t.body_rates(q.0, q.1, q.2).unwrap(),
                        None
                    )
                );
            }
        }
        let back =
            CoefficientTable::parse_csv(TableKind::Body, p(), &rated.to_csv(), OutOfRange::Stop)
                .unwrap();
        assert_eq!(back, rated);
        // Rows must have as many fields as the header.
        let short = "mach,alpha_deg,altitude_m,cn,ca,cm,cn_q,cm_q\n0,0,0,1,1,1\n";
        assert!(matches!(
            CoefficientTable::parse_csv(TableKind::Body, p(), short, OutOfRange::Stop),
            Err(TableError::FieldCount {
                line: 2,
                expected: 8,
                found: 6,
                ..
            })
        ));
        // Fin tables take no rate columns; one of the two alone is no header either.
        for (kind, hdr) in [
            (
                TableKind::Fin,
                "mach,alpha_deg,altitude_m,cn,ca,x_cp_m,cn_q,cm_q",
            ),
            (TableKind::Body, "mach,alpha_deg,altitude_m,cn,ca,cm,cn_q"),
        ] {
            let e = CoefficientTable::parse_csv(kind, p(), &format!("{hdr}\n"), OutOfRange::Stop)
                .unwrap_err();
            assert!(matches!(e, TableError::Header { line: 1, .. }), "{e}");
        }
    }

    /// The roll columns (issue 34: the further fin sets' cant and roll damping) follow the
    /// rate columns: interpolated exactly where linear, the other columns unchanged, the CSV
    /// round trip exact; without the rate columns, or one of the two alone, no header.
    #[test]
    fn optional_roll_columns() {
        let mut rated_text = String::from("mach,alpha_deg,altitude_m,cn,ca,cm,cn_q,cm_q\n");
        let mut roll_text =
            String::from("mach,alpha_deg,altitude_m,cn,ca,cm,cn_q,cm_q,cl_0,cl_p\n");
        for line in grid_text(None).lines().skip(2) {
            let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
            let (m, a, h) = (v[0], v[1], v[2]);
            let rated = format!("{line},{},{}", 100.0 + m, -300.0 - a + 1e-3 * h);
            rated_text.push_str(&format!("{rated}\n"));
            roll_text.push_str(&format!("{rated},{},{}\n", 0.01 * m, -20.0 - m));
        }
        let rated =
            CoefficientTable::parse_csv(TableKind::Body, p(), &rated_text, OutOfRange::Stop)
                .unwrap();
        let rolled =
            CoefficientTable::parse_csv(TableKind::Body, p(), &roll_text, OutOfRange::Stop)
                .unwrap();
        assert!(rolled.has_rates() && rolled.has_roll() && !rated.has_roll());
        assert_eq!(rated.body_roll(0.75, 2.5, 2500.0).unwrap(), None);
        let r = rolled.body_roll(0.75, 2.5, 2500.0).unwrap().unwrap();
        assert!(
            (r.cl_0 - 0.0075).abs() < 1e-15 && (r.cl_p + 20.75).abs() < 1e-12,
            "{r:?}"
        );
        let mut hint = TableHint::default();
        let (c, rates, roll) = rolled.body_hinted(0.75, 2.5, 2500.0, &mut hint).unwrap();
        assert_eq!(c, rated.body(0.75, 2.5, 2500.0).unwrap());
        assert_eq!(rates, rated.body_rates(0.75, 2.5, 2500.0).unwrap());
        assert_eq!(roll, Some(r));
        let back =
            CoefficientTable::parse_csv(TableKind::Body, p(), &rolled.to_csv(), OutOfRange::Stop)
                .unwrap();
        assert_eq!(back, rolled);
        // Replacing the rate columns keeps the roll columns, and the other way round.
        let n_pts = rolled.to_csv().lines().count() - 1;
        let re = rolled
            .clone()
            .with_rates(&vec![[1.0, -2.0]; n_pts])
            .unwrap();
        let (c2, rates2, roll2) = re.body_hinted(0.75, 2.5, 2500.0, &mut hint).unwrap();
        assert_eq!((c2, roll2), (c, Some(r)));
        assert_eq!(rates2.map(|x| (x.cn_q, x.cm_q)), Some((1.0, -2.0)));
        let re = rolled.clone().with_roll(&vec![[0.5, -3.0]; n_pts]).unwrap();
        let (c3, rates3, roll3) = re.body_hinted(0.75, 2.5, 2500.0, &mut hint).unwrap();
        assert_eq!((c3, rates3), (c, rates));
        assert_eq!(roll3.map(|x| (x.cl_0, x.cl_p)), Some((0.5, -3.0)));
        // Built: the roll columns need the rate columns.
        let plain =
            CoefficientTable::parse_csv(TableKind::Body, p(), &grid_text(None), OutOfRange::Stop)
                .unwrap();
        let n = plain.to_csv().lines().count() - 1;
        assert!(matches!(
            plain.with_roll(&vec![[0.0; 2]; n]),
            Err(TableError::Shape { expected: 0, .. })
        ));
        for hdr in [
            "mach,alpha_deg,altitude_m,cn,ca,cm,cl_0,cl_p",
            "mach,alpha_deg,altitude_m,cn,ca,cm,cn_q,cm_q,cl_0",
        ] {
            let e = CoefficientTable::parse_csv(
                TableKind::Body,
                p(),
                &format!("{hdr}\n"),
                OutOfRange::Stop,
            )
            .unwrap_err();
            assert!(matches!(e, TableError::Header { line: 1, .. }), "{e}");
        }
    }

    #[test]
    fn reader_errors_name_line() {
        // Hole: point 5 (mach 0.5, alpha 10, altitude 5000) missing.
        let e = CoefficientTable::parse_csv(
            TableKind::Body,
            p(),
            &grid_text(Some(5)),
            OutOfRange::Stop,
        )
        .unwrap_err();
        assert!(
            matches!(
                e,
                TableError::Hole {
                    mach: 0.5,
                    alpha_deg: 10.0,
                    altitude_m: 5000.0,
                    ..
                }
            ),
            "{e}"
        );
        // Duplicate of line 3 on line 5.
        let dup = "mach,alpha_deg,altitude_m,cn,ca,cm\n\n0,0,0,1,1,1\n0,1,0,1,1,1\n0,0,0,2,2,2\n";
        let e =
            CoefficientTable::parse_csv(TableKind::Body, p(), dup, OutOfRange::Stop).unwrap_err();
        assert!(
            matches!(
                e,
                TableError::Duplicate {
                    line: 5,
                    first_line: 3,
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().starts_with("t.csv:5: duplicate"));
        // Non-monotonic alpha: 5 then a new value 2.
        let nm = "mach,alpha_deg,altitude_m,cn,ca,cm\n0,0,0,1,1,1\n0,5,0,1,1,1\n0,2,0,1,1,1\n";
        let e =
            CoefficientTable::parse_csv(TableKind::Body, p(), nm, OutOfRange::Stop).unwrap_err();
        assert!(
            matches!(
                e,
                TableError::NonMonotonic {
                    line: 4,
                    axis: Axis::AlphaDeg,
                    ..
                }
            ),
            "{e}"
        );
        let nf = "mach,alpha_deg,altitude_m,cn,ca,cm\n0,0,0,1,NaN,1\n";
        let e =
            CoefficientTable::parse_csv(TableKind::Body, p(), nf, OutOfRange::Stop).unwrap_err();
        assert!(
            matches!(
                e,
                TableError::NonFinite {
                    line: 2,
                    column: "ca",
                    ..
                }
            ),
            "{e}"
        );
        let inf = "mach,alpha_deg,altitude_m,cn,ca,cm\n0,0,0,1,inf,1\n";
        assert!(matches!(
            CoefficientTable::parse_csv(TableKind::Body, p(), inf, OutOfRange::Stop),
            Err(TableError::NonFinite { line: 2, .. })
        ));
        let bad = "mach,alpha_deg,altitude_m,cn,ca,cm\n0,0,0,1,x,1\n";
        assert!(matches!(
            CoefficientTable::parse_csv(TableKind::Body, p(), bad, OutOfRange::Stop),
            Err(TableError::NotANumber {
                line: 2,
                column: "ca",
                ..
            })
        ));
        let short = "mach,alpha_deg,altitude_m,cn,ca,cm\n0,0,0,1,1\n";
        assert!(matches!(
            CoefficientTable::parse_csv(TableKind::Body, p(), short, OutOfRange::Stop),
            Err(TableError::FieldCount {
                line: 2,
                found: 5,
                ..
            })
        ));
        let hdr = "mach,alpha,altitude_m,cn,ca,cm\n";
        assert!(matches!(
            CoefficientTable::parse_csv(TableKind::Body, p(), hdr, OutOfRange::Stop),
            Err(TableError::Header { line: 1, .. })
        ));
    }
}
