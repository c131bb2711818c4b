//! Stage 8, report: figures (SVG and PNG) and an HTML index for runs and stability maps.
//!
//! - [`plot`]: the drawing primitives: multi-series time plots and the filled sigma_d
//!   stability map with contour lines (zero contour bold) and overlay curves, as in the
//!   thesis' Figs 6.3-6.8;
//! - [`contour`]: marching squares on a rectangular grid;
//! - [`map`]: the [`StabilityMap`] data and its CSV form (`x, y, sigma_d`);
//! - [`history`]: reading a run's `history.csv` with line-numbered errors;
//! - [`figures`]: the thesis' figure set chosen from the columns of a history;
//! - [`mesh`]: deformed FE mesh frames (front and isometric views);
//! - [`index`]: the `index.html` page;
//! - [`montecarlo`]: the figures of a Monte Carlo dispersion (landing ellipses, histograms,
//!   sensitivity bars).
//!
//! Architecture invariant: text is drawn with the embedded DejaVu Sans font only (no
//! fontconfig, no system fonts), so reports render the same on a bare machine; drawing is
//! generic over the plotters backend, and the only IO is writing the figure files.

pub mod build;
pub mod contour;
pub mod figures;
pub mod history;
pub mod index;
pub mod map;
pub mod mesh;
pub mod montecarlo;
pub mod plot;

use std::path::PathBuf;
use std::sync::OnceLock;

pub use contour::{Segment, contour_segments};
pub use history::History;
pub use map::{OverlayCurve, StabilityMap};
pub use plot::{Series, TimePlot};

/// The font every figure uses, embedded so no system font lookup happens.
pub const FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// The family name figures ask plotters for (registered to [`FONT_BYTES`]).
pub const FONT_FAMILY: &str = "sans-serif";

/// Why a report or one of its figures could not be produced.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// An input file or directory cannot be read.
    #[error("cannot read `{path}`: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A figure or the index cannot be written.
    #[error("cannot write `{path}`: {message}")]
    Write { path: PathBuf, message: String },
    /// A malformed CSV file, at a line.
    #[error("{path}:{line}: {message}")]
    Csv {
        path: PathBuf,
        /// 1-based line of the file (the header is line 1).
        line: u64,
        message: String,
    },
    /// `summary.json` is not valid JSON.
    #[error("{path}: {message}")]
    Summary { path: PathBuf, message: String },
    /// plotters refused the embedded font.
    #[error("the embedded font could not be registered with plotters")]
    Font,
    /// A plotters backend failed.
    #[error("drawing failed: {0}")]
    Draw(String),
    /// Data that cannot make a figure.
    #[error("{0}")]
    Data(String),
}

impl ReportError {
    /// The stable diagnostic code (docs/diagnostic-codes.md).
    pub fn code(&self) -> &'static str {
        match self {
            ReportError::Read { .. } => "report::read",
            ReportError::Write { .. } => "report::write",
            ReportError::Csv { .. } => "report::csv",
            ReportError::Summary { .. } => "report::summary",
            ReportError::Font => "report::font",
            ReportError::Draw(_) => "report::draw",
            ReportError::Data(_) => "report::data",
        }
    }
}

/// Register the embedded DejaVu Sans under [`FONT_FAMILY`] (once per process). Every
/// drawing function calls it; calling it again is free.
pub fn ensure_font() -> Result<(), ReportError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        use plotters::style::FontStyle;
        [FontStyle::Normal, FontStyle::Bold]
            .into_iter()
            .all(|style| plotters::style::register_font(FONT_FAMILY, style, FONT_BYTES).is_ok())
    });
    if ok { Ok(()) } else { Err(ReportError::Font) }
}

/// The text of an input file, or [`ReportError::Read`] naming it.
pub fn read_text(path: &std::path::Path) -> Result<String, ReportError> {
    std::fs::read_to_string(path).map_err(|source| ReportError::Read {
        path: path.to_path_buf(),
        source,
    })
}
