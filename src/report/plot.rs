//! Drawing primitives: multi-series time plots and the filled sigma_d stability map with
//! contour lines (thesis Figs 6.3-6.8). Every figure is drawn by a [`Figure`] onto any
//! plotters backend; [`save_svg_png`] writes both an SVG and a PNG of it.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::contour::{contour_segments, nice_levels};
use super::map::StabilityMap;
use super::{FONT_FAMILY, ReportError, ensure_font};

/// Default figure size in pixels (PNG) and user units (SVG).
pub const FIGURE_SIZE: (u32, u32) = (960, 600);

/// Above this many points a series is thinned for drawing (min and max of each bucket
/// kept, so peaks survive).
pub const MAX_POINTS_PER_SERIES: usize = 4000;

/// Line colours, in the order series are drawn.
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// Something that can draw itself onto a plotters drawing area.
pub trait Figure {
    /// Draw the whole figure onto `root` (which it may fill with a background).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError>;
}

/// One line of a time plot.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Abscissae (usually time, s).
    pub xs: Vec<f64>,
    /// Ordinates, one per abscissa.
    pub ys: Vec<f64>,
}

/// A point marked on a plot (a filled circle, with its label in the legend), e.g. the
/// first violation of the flutter margin or the flutter point of a V-g diagram.
#[derive(Clone, Debug, PartialEq)]
pub struct MarkedPoint {
    pub x: f64,
    pub y: f64,
    pub label: String,
}

/// A plot of several series against one x axis, with legend, axis labels and grid.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TimePlot {
    /// Caption above the plot.
    pub title: String,
    /// Axis label with unit, e.g. "t (s)".
    pub x_label: String,
    /// Axis label with unit, e.g. "angle (deg)".
    pub y_label: String,
    /// The lines, drawn in [`PALETTE`] order.
    pub series: Vec<Series>,
    /// Events marked as labelled vertical lines at their abscissa (flight events: rail
    /// exit, burnout, apogee, deployments, landing); those outside the x range are skipped.
    pub markers: Vec<(f64, String)>,
    /// Abscissa intervals shaded over the whole height (e.g. untrusted rows), drawn under
    /// the lines; one legend entry, [`TimePlot::shaded_label`], when there are any.
    pub shaded: Vec<(f64, f64)>,
    /// Legend text of the shaded intervals.
    pub shaded_label: String,
    /// Points marked with a filled circle, each with its label in the legend.
    pub points: Vec<MarkedPoint>,
    /// `Some(min_span)`: equal axes (one metre per pixel on both, for a map-like plot such
    /// as the ground track), each axis spanning at least `min_span` so round-off is not
    /// drawn as a curve.
    pub equal_axes_min_span: Option<f64>,
}

/// Colour of [`TimePlot::shaded`] intervals.
pub const SHADE: RGBColor = RGBColor(253, 208, 162);

/// Colour of [`TimePlot::points`].
pub const POINT_COLOUR: RGBColor = RGBColor(0, 0, 0);

/// Stroke width of the series lines, in pixels.
pub const LINE_WIDTH: u32 = 2;

pub(crate) fn draw_err<E: std::fmt::Display>(e: E) -> ReportError {
    ReportError::Draw(e.to_string())
}

pub(crate) fn font(size: u32) -> TextStyle<'static> {
    (FONT_FAMILY, size).into_font().color(&BLACK)
}

/// A tick label for `v` on an axis spanning `span`: two decimals more than the tick step
/// (about a tenth of the span) needs, trailing zeros dropped; scientific notation for very
/// small or large numbers; rounding noise next to zero shown as 0.
pub fn tick_label(v: f64, span: f64) -> String {
    let span = span.abs().max(1e-300);
    if v == 0.0 || v.abs() < 1e-9 * span {
        return "0".into();
    }
    let mag = v.abs().max(span);
    if !(1e-3..1e6).contains(&mag) {
        return format!("{v:.2e}");
    }
    let decimals = (2.0 - (span / 10.0).log10().floor()).clamp(0.0, 10.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The finite range of some values, widened by 5 % (and to a unit interval when flat).
pub fn padded_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return (-1.0, 1.0);
    }
    if hi - lo <= 1e-12 * lo.abs().max(hi.abs()).max(1e-300) {
        let d = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return (lo - d, hi + d);
    }
    let pad = 0.05 * (hi - lo);
    (lo - pad, hi + pad)
}

/// Thin a series to at most about `max_points` points: the x range is cut into buckets and
/// each bucket keeps its first point and its minimum and maximum, in x order.
pub fn decimate(xs: &[f64], ys: &[f64], max_points: usize) -> Vec<(f64, f64)> {
    let n = xs.len().min(ys.len());
    let all = || xs.iter().copied().zip(ys.iter().copied()).take(n);
    if n <= max_points || max_points < 3 {
        return all()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect();
    }
    let buckets = max_points / 3;
    let per = n.div_ceil(buckets);
    let mut out = Vec::with_capacity(3 * buckets + 1);
    for start in (0..n).step_by(per) {
        let end = (start + per).min(n);
        let idx: Vec<usize> = (start..end)
            .filter(|&k| xs[k].is_finite() && ys[k].is_finite())
            .collect();
        let Some(&first) = idx.first() else { continue };
        let lo = idx
            .iter()
            .copied()
            .fold(first, |a, k| if ys[k] < ys[a] { k } else { a });
        let hi = idx
            .iter()
            .copied()
            .fold(first, |a, k| if ys[k] > ys[a] { k } else { a });
        let mut keep = vec![first, lo, hi];
        keep.sort_unstable();
        keep.dedup();
        out.extend(keep.into_iter().map(|k| (xs[k], ys[k])));
    }
    out
}

/// The chart of a [`TimePlot`]: caption, margins and label areas. The plotting area's
/// pixel size depends only on these and the root's size ([`TimePlot::draw`] and
/// [`plot_area_size`] share it).
pub(crate) fn time_chart<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    title: &str,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>, ReportError> {
    ChartBuilder::on(root)
        .caption(title, font(24))
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(90)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(draw_err)
}

/// The plotting area (inside the axes) of a [`TimePlot`] of `size` pixels, as pixel
/// ranges `(x_range, y_range)`, half-open: laid out on a scratch bitmap with the same
/// chart builder as the figure.
pub fn plot_area_pixels(
    title: &str,
    size: (u32, u32),
) -> Result<(std::ops::Range<i32>, std::ops::Range<i32>), ReportError> {
    ensure_font()?;
    let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
    let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
    let chart = time_chart(&root, title, (0.0, 1.0), (0.0, 1.0))?;
    Ok(chart.plotting_area().get_pixel_range())
}

/// Width and height in pixels of a [`TimePlot`]'s plotting area on a root of `size`.
pub fn plot_area_size(title: &str, size: (u32, u32)) -> Result<(f64, f64), ReportError> {
    let (xr, yr) = plot_area_pixels(title, size)?;
    Ok((
        f64::from((xr.end - xr.start).max(1)),
        f64::from((yr.end - yr.start).max(1)),
    ))
}

/// Axis ranges with one unit per the same number of pixels on both axes: each data range
/// widened to at least `min_span`, then the axis with less data per pixel widened about
/// its centre until both have the same scale. `area` is the plotting area in pixels.
pub fn equal_axes(
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    min_span: f64,
    area: (f64, f64),
) -> ((f64, f64), (f64, f64)) {
    let min_span = if min_span.is_finite() && min_span > 0.0 {
        min_span
    } else {
        1.0
    };
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let (sx, sy) = ((x1 - x0).max(min_span), (y1 - y0).max(min_span));
    let per_pixel = (sx / area.0).max(sy / area.1);
    let (hx, hy) = (0.5 * per_pixel * area.0, 0.5 * per_pixel * area.1);
    ((cx - hx, cx + hx), (cy - hy, cy + hy))
}

/// Draw a polyline as separate two-point segments, never as one wide path.
///
/// Why: plotters' bitmap backend (plotters-backend 0.3.7, `rasterizer/path.rs`,
/// `compute_polygon_vertex`) fills a path wider than one pixel as a single polygon whose
/// vertex at each joint is the intersection of the two segments' offset edges. Only the
/// outer side of a joint is capped (at 4 half-widths); on the inner side of a sharp
/// reversal (a spike, or a fast oscillation a pixel apart) the two offset edges are nearly
/// parallel and meet far away, so the polygon reaches across the title and axis labels and
/// the fill paints a thick stroke there (the SVG backend writes a `<polyline>` and the
/// viewer's miter limit saves it). A two-point path is a quadrilateral whose corners lie
/// within half the stroke width of its two ends, so nothing is drawn more than a pixel
/// outside the data's bounding box.
pub fn draw_segments<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    pts: &[(f64, f64)],
    style: ShapeStyle,
) -> Result<(), ReportError> {
    chart
        .draw_series(
            pts.windows(2)
                .map(|w| PathElement::new(vec![w[0], w[1]], style)),
        )
        .map_err(draw_err)?;
    Ok(())
}

impl Figure for TimePlot {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        ensure_font()?;
        root.fill(&WHITE).map_err(draw_err)?;
        let thinned: Vec<Vec<(f64, f64)>> = self
            .series
            .iter()
            .map(|s| decimate(&s.xs, &s.ys, MAX_POINTS_PER_SERIES))
            .collect();
        let points = self
            .points
            .iter()
            .filter(|p| p.x.is_finite() && p.y.is_finite());
        let (x0, x1) = {
            let xs = thinned
                .iter()
                .flatten()
                .map(|p| p.0)
                .chain(points.clone().map(|p| p.x));
            let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
            if lo < hi {
                (lo, hi)
            } else {
                padded_range([lo, hi].into_iter())
            }
        };
        let (y0, y1) = padded_range(
            thinned
                .iter()
                .flatten()
                .map(|p| p.1)
                .chain(points.clone().map(|p| p.y)),
        );
        let ((x0, x1), (y0, y1)) = match self.equal_axes_min_span {
            Some(span) => {
                let area = plot_area_size(&self.title, root.dim_in_pixel())?;
                equal_axes(padded_range([x0, x1].into_iter()), (y0, y1), span, area)
            }
            None => ((x0, x1), (y0, y1)),
        };
        // When the legend would hide data in every corner, make room above the data
        // (not on equal axes, whose scale is fixed).
        let n = self.series.len() + self.points.len() + usize::from(!self.shaded.is_empty());
        let (corner, hidden) = legend_corner(&thinned, (x0, x1), (y0, y1), n);
        let (legend_at, y1) = if hidden == 0 || self.equal_axes_min_span.is_some() {
            (corner, y1)
        } else {
            let h = legend_height_fraction(n);
            (
                SeriesLabelPosition::UpperRight,
                y1 + (y1 - y0) * h / (1.0 - h),
            )
        };
        let mut chart = time_chart(root, &self.title, (x0, x1), (y0, y1))?;
        chart
            .configure_mesh()
            .x_desc(self.x_label.as_str())
            .y_desc(self.y_label.as_str())
            .axis_desc_style(font(18))
            .label_style(font(14))
            .x_label_formatter(&|v| tick_label(*v, x1 - x0))
            .y_label_formatter(&|v| tick_label(*v, y1 - y0))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(200, 200, 200))
            .draw()
            .map_err(draw_err)?;
        let bands: Vec<(f64, f64)> = self
            .shaded
            .iter()
            .map(|&(a, b)| (a.max(x0), b.min(x1)))
            .filter(|(a, b)| a.is_finite() && b.is_finite() && a <= b)
            .collect();
        if !bands.is_empty() {
            chart
                .draw_series(
                    bands
                        .iter()
                        .map(|&(a, b)| Rectangle::new([(a, y0), (b, y1)], SHADE.filled())),
                )
                .map_err(draw_err)?
                .label(self.shaded_label.as_str())
                .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 24, y + 6)], SHADE.filled()));
        }
        for (k, (s, pts)) in self.series.iter().zip(&thinned).enumerate() {
            let color = PALETTE[k % PALETTE.len()];
            draw_segments(&mut chart, pts, color.stroke_width(LINE_WIDTH))?;
            // The legend entry, on an empty series.
            chart
                .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
                .map_err(draw_err)?
                .label(s.label.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(LINE_WIDTH))
                });
        }
        let marker_style = RGBColor(120, 120, 120).stroke_width(1);
        for (k, (x, label)) in self.markers.iter().enumerate() {
            if !(x0..=x1).contains(x) {
                continue;
            }
            // Dashed: short segments along the line.
            let dashes = 40;
            chart
                .draw_series((0..dashes).filter(|d| d % 2 == 0).map(|d| {
                    let a = y0 + (y1 - y0) * d as f64 / dashes as f64;
                    let b = y0 + (y1 - y0) * (d + 1) as f64 / dashes as f64;
                    PathElement::new(vec![(*x, a), (*x, b)], marker_style)
                }))
                .map_err(draw_err)?;
            // Labels stagger downwards so neighbouring events stay readable.
            // Near the right edge the label goes to the left of its line, inside the frame.
            let y = y1 - (y1 - y0) * (0.04 + 0.05 * (k % 4) as f64);
            let (text, style) = if (x - x0) > 0.85 * (x1 - x0) {
                (
                    format!("{label} "),
                    font(13).pos(Pos::new(HPos::Right, VPos::Top)),
                )
            } else {
                (format!(" {label}"), font(13))
            };
            chart
                .draw_series(std::iter::once(Text::new(text, (*x, y), style)))
                .map_err(draw_err)?;
        }
        for p in points {
            chart
                .draw_series(std::iter::once(Circle::new(
                    (p.x, p.y),
                    6,
                    POINT_COLOUR.filled(),
                )))
                .map_err(draw_err)?
                .label(p.label.as_str())
                .legend(|(x, y)| Circle::new((x + 12, y), 6, POINT_COLOUR.filled()));
        }
        if n > 0 {
            chart
                .configure_series_labels()
                .label_font(font(14))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .position(legend_at)
                .draw()
                .map_err(draw_err)?;
        }
        root.present().map_err(draw_err)
    }
}

/// Fraction of the plot height a legend of `n` entries takes (with its margins).
fn legend_height_fraction(n: usize) -> f64 {
    (0.045 * n as f64 + 0.06).min(0.9)
}

/// The corner of the plot where the legend hides the fewest data points, and how many it
/// hides: each corner's box is 35 % of the width and `legend_height_fraction` of the
/// height; ties keep the order upper right, upper left, lower right, lower left.
pub fn legend_corner(
    series: &[Vec<(f64, f64)>],
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    n: usize,
) -> (SeriesLabelPosition, usize) {
    let h = legend_height_fraction(n);
    let w = 0.35;
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let mut best = (usize::MAX, SeriesLabelPosition::UpperRight);
    for (pos, right, upper) in corners {
        let hidden = series
            .iter()
            .flatten()
            .filter(|(x, y)| {
                let u = (x - x0) / (x1 - x0);
                let v = (y - y0) / (y1 - y0);
                let in_x = if right { u > 1.0 - w } else { u < w };
                let in_y = if upper { v > 1.0 - h } else { v < h };
                in_x && in_y
            })
            .count();
        if hidden < best.0 {
            best = (hidden, pos);
        }
    }
    (best.1, best.0)
}

/// The diverging colour of a sigma_d value: white at 0, blue towards `lo` < 0 (stable),
/// red towards `hi` > 0 (unstable); grey for NaN.
pub fn diverging_colour(v: f64, lo: f64, hi: f64) -> RGBColor {
    if !v.is_finite() {
        return RGBColor(190, 190, 190);
    }
    let blend = |to: (f64, f64, f64), t: f64| {
        let t = t.clamp(0.0, 1.0);
        let c = |a: f64| (255.0 + t * (a - 255.0)).round() as u8;
        RGBColor(c(to.0), c(to.1), c(to.2))
    };
    if v < 0.0 {
        blend((33.0, 102.0, 172.0), if lo < 0.0 { v / lo } else { 1.0 })
    } else {
        blend((178.0, 24.0, 43.0), if hi > 0.0 { v / hi } else { 0.0 })
    }
}

/// Sub-cells per grid cell along each axis for the filled map, so the picture has about
/// `target` cells a side whatever the grid.
fn subdivisions(n: usize, target: usize) -> usize {
    if n < 2 {
        1
    } else {
        target.div_ceil(n - 1).clamp(1, 16)
    }
}

impl Figure for StabilityMap {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        ensure_font()?;
        self.validate()?;
        root.fill(&WHITE).map_err(draw_err)?;
        let (w, _) = root.dim_in_pixel();
        let (main, bar) = root.split_horizontally(w.saturating_sub(130));
        let (lo, hi) = self.value_range().unwrap_or((-1.0, 1.0));
        let (nx, ny) = (self.xs.len(), self.ys.len());
        let (x0, x1) = (self.xs[0], self.xs[nx - 1]);
        let (y0, y1) = (self.ys[0], self.ys[ny - 1]);
        let mut chart = ChartBuilder::on(&main)
            .caption(&self.title, font(24))
            .margin(12)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(draw_err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(self.x_label.as_str())
            .y_desc(self.y_label.as_str())
            .axis_desc_style(font(18))
            .label_style(font(14))
            .x_label_formatter(&|v| tick_label(*v, x1 - x0))
            .y_label_formatter(&|v| tick_label(*v, y1 - y0))
            .draw()
            .map_err(draw_err)?;
        // Filled map: each grid cell cut into sub-cells coloured by the bilinear value at
        // their centre.
        let (kx, ky) = (subdivisions(nx, 80), subdivisions(ny, 80));
        let mut cells = Vec::with_capacity((nx - 1) * (ny - 1) * kx * ky);
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let f = [
                    self.at(i, j),
                    self.at(i + 1, j),
                    self.at(i, j + 1),
                    self.at(i + 1, j + 1),
                ];
                let (xa, xb, ya, yb) = (self.xs[i], self.xs[i + 1], self.ys[j], self.ys[j + 1]);
                for b in 0..ky {
                    for a in 0..kx {
                        let (s0, s1) = (a as f64 / kx as f64, (a + 1) as f64 / kx as f64);
                        let (t0, t1) = (b as f64 / ky as f64, (b + 1) as f64 / ky as f64);
                        let (s, t) = (0.5 * (s0 + s1), 0.5 * (t0 + t1));
                        let v = (1.0 - s) * (1.0 - t) * f[0]
                            + s * (1.0 - t) * f[1]
                            + (1.0 - s) * t * f[2]
                            + s * t * f[3];
                        let colour = diverging_colour(v, lo, hi);
                        cells.push(Rectangle::new(
                            [
                                (xa + s0 * (xb - xa), ya + t0 * (yb - ya)),
                                (xa + s1 * (xb - xa), ya + t1 * (yb - ya)),
                            ],
                            colour.filled(),
                        ));
                    }
                }
            }
        }
        chart.draw_series(cells).map_err(draw_err)?;
        // Contour lines: thin grey at nice levels, the zero contour bold black.
        for level in nice_levels(lo, hi, 10).into_iter().filter(|l| *l != 0.0) {
            let segs = contour_segments(&self.xs, &self.ys, &self.values, level);
            chart
                .draw_series(segs.into_iter().map(|s| {
                    PathElement::new(
                        vec![(s.a[0], s.a[1]), (s.b[0], s.b[1])],
                        RGBColor(70, 70, 70).stroke_width(1),
                    )
                }))
                .map_err(draw_err)?;
        }
        let zero = contour_segments(&self.xs, &self.ys, &self.values, 0.0);
        let has_zero = !zero.is_empty();
        chart
            .draw_series(zero.into_iter().map(|s| {
                PathElement::new(
                    vec![(s.a[0], s.a[1]), (s.b[0], s.b[1])],
                    BLACK.stroke_width(4),
                )
            }))
            .map_err(draw_err)?
            .label("sigma_d = 0 (stability boundary)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], BLACK.stroke_width(4)));
        for (k, curve) in self.overlays.iter().enumerate() {
            let colour = PALETTE[(k + 3) % PALETTE.len()];
            let pts: Vec<(f64, f64)> = curve.points.iter().map(|p| (p[0], p[1])).collect();
            draw_segments(&mut chart, &pts, colour.stroke_width(3))?;
            chart
                .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
                .map_err(draw_err)?
                .label(curve.label.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
                });
        }
        if has_zero || !self.overlays.is_empty() {
            chart
                .configure_series_labels()
                .label_font(font(14))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .position(SeriesLabelPosition::UpperLeft)
                .draw()
                .map_err(draw_err)?;
        }
        draw_colour_bar(&bar, lo, hi, &self.value_label)?;
        root.present().map_err(draw_err)
    }
}

/// The colour scale beside a map.
fn draw_colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    lo: f64,
    hi: f64,
    label: &str,
) -> Result<(), ReportError> {
    let (b0, b1) = if hi > lo {
        (lo, hi)
    } else {
        (lo - 1.0, hi + 1.0)
    };
    let mut bar = ChartBuilder::on(area)
        .margin_top(60)
        .margin_bottom(62)
        .margin_right(10)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..1.0, b0..b1)
        .map_err(draw_err)?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(label)
        .axis_desc_style(font(16))
        .label_style(font(13))
        .y_label_formatter(&|v| tick_label(*v, b1 - b0))
        .draw()
        .map_err(draw_err)?;
    let steps = 100;
    bar.draw_series((0..steps).map(|k| {
        let a = b0 + (b1 - b0) * k as f64 / steps as f64;
        let b = b0 + (b1 - b0) * (k + 1) as f64 / steps as f64;
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            diverging_colour(0.5 * (a + b), lo, hi).filled(),
        )
    }))
    .map_err(draw_err)?;
    if b0 < 0.0 && b1 > 0.0 {
        bar.draw_series(std::iter::once(PathElement::new(
            vec![(0.0, 0.0), (1.0, 0.0)],
            BLACK.stroke_width(3),
        )))
        .map_err(draw_err)?;
    }
    Ok(())
}

/// Write `stem.svg` and `stem.png` of a figure of `size` pixels; returns both paths.
pub fn save_svg_png<F: Figure>(
    figure: &F,
    stem: &Path,
    size: (u32, u32),
) -> Result<Vec<PathBuf>, ReportError> {
    ensure_font()?;
    let with_ext = |ext: &str| {
        let mut s = stem.as_os_str().to_owned();
        s.push(ext);
        PathBuf::from(s)
    };
    let (svg, png) = (with_ext(".svg"), with_ext(".png"));
    let write_err = |path: &Path, e: ReportError| ReportError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    {
        let root = SVGBackend::new(&svg, size).into_drawing_area();
        figure.draw(&root).map_err(|e| write_err(&svg, e))?;
    }
    {
        let root = BitMapBackend::new(&png, size).into_drawing_area();
        figure.draw(&root).map_err(|e| write_err(&png, e))?;
    }
    Ok(vec![svg, png])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_tell_small_ticks_apart() {
        assert_eq!(tick_label(-0.0125, 0.05), "-0.0125");
        assert_eq!(tick_label(2.5e-6, 1e-5), "2.50e-6");
        assert_eq!(tick_label(250.0, 100.0), "250");
        assert_eq!(tick_label(0.0, 1.0), "0");
        assert_eq!(tick_label(1.5, 2.0), "1.5");
        assert_eq!(tick_label(0.25, 2.0), "0.25");
        assert_eq!(tick_label(-4.24e-22, 4e-6), "0");
    }

    #[test]
    fn legend_avoids_the_data() {
        let rising: Vec<(f64, f64)> = (0..=100).map(|k| (k as f64, k as f64)).collect();
        let (pos, hidden) = legend_corner(&[rising], (0.0, 100.0), (0.0, 100.0), 2);
        assert!(
            matches!(pos, SeriesLabelPosition::UpperLeft) && hidden == 0,
            "{pos:?}"
        );
        let flat_top: Vec<(f64, f64)> = (0..=100).map(|k| (k as f64, 95.0)).collect();
        let (pos, _) = legend_corner(
            std::slice::from_ref(&flat_top),
            (0.0, 100.0),
            (0.0, 100.0),
            1,
        );
        assert!(matches!(pos, SeriesLabelPosition::LowerRight), "{pos:?}");
        let flat_bottom: Vec<(f64, f64)> = (0..=100).map(|k| (k as f64, 5.0)).collect();
        let (_, hidden) = legend_corner(&[flat_top, flat_bottom], (0.0, 100.0), (0.0, 100.0), 2);
        assert!(hidden > 0, "every corner has data");
    }

    /// Equal axes: the same units per pixel on both, each span at least the minimum,
    /// the data inside, centred.
    #[test]
    fn equal_axes_have_one_scale() {
        let area = (840.0, 480.0);
        for (x, y, min) in [
            ((0.0, 0.0), (-2e-12, 2e-11), 10.0),
            ((-300.0, 1200.0), (0.0, 50.0), 10.0),
            ((0.0, 5.0), (-4000.0, 10.0), 40.0),
        ] {
            let ((x0, x1), (y0, y1)) = equal_axes(x, y, min, area);
            let (sx, sy) = ((x1 - x0) / area.0, (y1 - y0) / area.1);
            assert!((sx - sy).abs() <= 1e-12 * sx, "{sx} {sy}");
            assert!(x1 - x0 >= min * (1.0 - 1e-12) && y1 - y0 >= min * (1.0 - 1e-12));
            let eps = 1e-12 * (x1 - x0);
            assert!(x0 <= x.0 + eps && x1 >= x.1 - eps && y0 <= y.0 + eps && y1 >= y.1 - eps);
            // One of the two is tight: its span is the data's or the minimum.
            let tight = |s: f64, d: f64| (s - d.max(min)).abs() <= 1e-9 * s;
            assert!(tight(x1 - x0, x.1 - x.0) || tight(y1 - y0, y.1 - y.0));
        }
    }

    /// Red pixels outside the data's pixel box (plus 2 px) of a 400 x 300 picture of a
    /// dense zig-zag (ten points per pixel column swinging over the whole height, as a
    /// fast mode or a row-to-row sign flip is after decimation), drawn 2 px wide by `draw`.
    fn red_outside(
        draw: impl Fn(
            &mut ChartContext<'_, BitMapBackend<'_>, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
            &[(f64, f64)],
        ),
    ) -> usize {
        let size = (400u32, 300u32);
        let pts: Vec<(f64, f64)> = (0..3000)
            .map(|k| {
                let y = if k % 2 == 0 { 352.0 } else { -1.0 };
                (f64::from(k), y)
            })
            .collect();
        let mut buf = vec![255u8; (size.0 * size.1 * 3) as usize];
        {
            let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
            let mut chart = ChartBuilder::on(&root)
                .margin(50)
                .build_cartesian_2d(0.0..2999.0, -1.0..352.0)
                .unwrap();
            draw(&mut chart, &pts);
        }
        let mut n = 0;
        for y in 0..size.1 {
            for x in 0..size.0 {
                let k = ((y * size.0 + x) * 3) as usize;
                let red = buf[k] == 255 && buf[k + 1] == 0 && buf[k + 2] == 0;
                let inside = (48..=352).contains(&x) && (48..=252).contains(&y);
                if red && !inside {
                    n += 1;
                }
            }
        }
        n
    }

    /// The cause of issue 32's strokes across the PNGs' titles: plotters' bitmap backend
    /// fills a 2 px polyline through sharp reversals as one polygon whose inner joints
    /// land far outside the data. Drawn as segments ([`draw_segments`]), nothing lands
    /// more than the half width outside the data's pixel box.
    #[test]
    fn dense_reversals_stay_inside_the_data_box() {
        let wide_path = red_outside(|chart, pts| {
            chart
                .draw_series(LineSeries::new(
                    pts.iter().copied(),
                    RED.stroke_width(LINE_WIDTH),
                ))
                .unwrap();
        });
        assert!(
            wide_path > 100,
            "plotters' wide path: {wide_path} pixels outside"
        );
        let segments = red_outside(|chart, pts| {
            draw_segments(chart, pts, RED.stroke_width(LINE_WIDTH)).unwrap();
        });
        assert_eq!(segments, 0);
    }

    #[test]
    fn decimation_keeps_peaks() {
        let xs: Vec<f64> = (0..100_000).map(f64::from).collect();
        let mut ys = vec![0.0; xs.len()];
        ys[54_321] = 7.0;
        ys[77_777] = -3.0;
        let d = decimate(&xs, &ys, 3000);
        assert!(d.len() <= 3100, "{}", d.len());
        assert!(d.contains(&(54_321.0, 7.0)) && d.contains(&(77_777.0, -3.0)));
        assert!(d.windows(2).all(|w| w[0].0 < w[1].0));
    }
}
