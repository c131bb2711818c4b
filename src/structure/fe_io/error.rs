//! The error type of every FE reader.
//!
//! Every variant carries the file (`path`), the 1-based `line` (0 when the problem is not tied
//! to one line, for example a check of the assembled model), the 1-based `column` where it is
//! meaningful (0 otherwise) and a `message` saying what was wrong. `code()` gives a stable
//! identifier for diagnostics ("fe::read::asymmetric", ...).

use std::fmt;
use std::path::{Path, PathBuf};

/// Where an error was found: file, 1-based line and 1-based column (0 = not applicable).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourceLocation {
    pub path: PathBuf,
    pub line: usize,
    pub column: usize,
}

impl SourceLocation {
    /// A location in `path` at `line` (1-based), no column.
    pub fn line(path: &Path, line: usize) -> Self {
        Self {
            path: path.to_path_buf(),
            line,
            column: 0,
        }
    }

    /// A location in `path` at `line` and `column` (both 1-based).
    pub fn at(path: &Path, line: usize, column: usize) -> Self {
        Self {
            path: path.to_path_buf(),
            line,
            column,
        }
    }
}

impl fmt::Display for SourceLocation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if self.line > 0 {
            write!(f, ":{}", self.line)?;
            if self.column > 0 {
                write!(f, ":{}", self.column)?;
            }
        }
        Ok(())
    }
}

macro_rules! fe_read_error {
    ($( $(#[$doc:meta])* $variant:ident => $code:literal, $what:literal; )*) => {
        /// A reader rejected its input. See the module documentation for the fields.
        #[derive(Debug, Clone, PartialEq, thiserror::Error)]
        pub enum FeReadError {
            $(
                $(#[$doc])*
                #[error("{}: {}: {message}", SourceLocation { path: path.clone(), line: *line, column: *column }, $what)]
                $variant { path: PathBuf, line: usize, column: usize, message: String },
            )*
        }

        impl FeReadError {
            /// Stable identifier of the kind of error, e.g. `"fe::read::asymmetric"`.
            pub fn code(&self) -> &'static str {
                match self { $( Self::$variant { .. } => $code, )* }
            }

            /// The file the error was found in.
            pub fn path(&self) -> &Path {
                match self { $( Self::$variant { path, .. } => path, )* }
            }

            /// 1-based line (0 when not tied to a line).
            pub fn line(&self) -> usize {
                match self { $( Self::$variant { line, .. } => *line, )* }
            }

            /// 1-based column (0 when not applicable).
            pub fn column(&self) -> usize {
                match self { $( Self::$variant { column, .. } => *column, )* }
            }

            /// What was wrong, without the location.
            pub fn message(&self) -> &str {
                match self { $( Self::$variant { message, .. } => message, )* }
            }
        }

        /// Constructors taking a [`SourceLocation`].
        impl FeReadError {
            $(
                #[allow(non_snake_case, dead_code)]
                pub(crate) fn $variant(loc: SourceLocation, message: impl Into<String>) -> Self {
                    Self::$variant { path: loc.path, line: loc.line, column: loc.column, message: message.into() }
                }
            )*
        }
    };
}

fe_read_error! {
    /// The file could not be opened or read.
    Io => "fe::read::io", "cannot read file";
    /// The first line (or a matrix header) is not a format this reader knows.
    UnknownHeader => "fe::read::unknown_header", "unknown header";
    /// The file ends before the data it announced.
    Truncated => "fe::read::truncated", "file is truncated";
    /// A number could not be parsed.
    BadNumber => "fe::read::bad_number", "unparsable number";
    /// A record or card does not have the expected shape.
    BadRecord => "fe::read::bad_record", "malformed record";
    /// A feature of the format that this reader does not implement (complex matrices,
    /// non-basic coordinate systems, scalar points).
    Unsupported => "fe::read::unsupported", "unsupported input";
    /// A matrix is not square.
    NotSquare => "fe::read::not_square", "matrix is not square";
    /// Matrix size is not 6 x the number of nodes.
    SizeNotSixPerNode => "fe::read::size_not_6_per_node", "matrix size is not 6 x number of nodes";
    /// M and K have different sizes.
    SizeMismatch => "fe::read::size_mismatch", "mass and stiffness sizes differ";
    /// A row or column index outside the declared size.
    IndexOutOfRange => "fe::read::index_out_of_range", "index out of range";
    /// The same matrix entry is given twice.
    DuplicateEntry => "fe::read::duplicate_entry", "duplicate matrix entry";
    /// A matrix stored in general (or square) form is not symmetric within tolerance.
    Asymmetric => "fe::read::asymmetric", "matrix is not symmetric";
    /// NaN or infinity in the data.
    NonFinite => "fe::read::non_finite", "value is NaN or infinite";
    /// A negative diagonal entry of M or K.
    NegativeDiagonal => "fe::read::negative_diagonal", "negative diagonal entry";
    /// A node id appears twice.
    DuplicateNode => "fe::read::duplicate_node", "duplicate node id";
    /// A node id is referenced but not defined.
    MissingNode => "fe::read::missing_node", "node id not defined";
    /// A named matrix (MAA, KAA, ...) is not in the file.
    MissingMatrix => "fe::read::missing_matrix", "matrix not found";
    /// The DOF order passed by the caller is not a permutation of the 6 components.
    BadDofOrder => "fe::read::bad_dof_order", "DOF order is not a permutation of 0..6";
    /// The mass matrix is not positive semi-definite (see [`super::validate`]).
    MassNotPositiveSemiDefinite => "fe::read::mass_not_psd", "mass matrix is not positive semi-definite";
}
