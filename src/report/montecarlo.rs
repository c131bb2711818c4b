//! The figures of a Monte Carlo dispersion (`flexflight montecarlo`, issue 35): the landing
//! points with their 1/2/3-sigma ellipses on the ground, histograms of an output (apogee,
//! minimum flutter margin) and the inputs' rank-correlation bars.
//!
//! Histogram bins: the Freedman-Diaconis width `h = 2 IQR n^(-1/3)` (D. Freedman and
//! P. Diaconis, "On the histogram as a density estimator: L2 theory", Z.
//! Wahrscheinlichkeitstheorie verw. Gebiete 57, 453-476, 1981), the count clamped to 5..60;
//! Sturges' `1 + log2 n` bins when the interquartile range is zero (H. A. Sturges, "The
//! choice of a class interval", J. Amer. Statist. Assoc. 21, 65-66, 1926). The bins are a
//! pure function of the values, so the figures are the same bits for the same table.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::plot::{
    Figure, LINE_WIDTH, PALETTE, draw_err, draw_segments, equal_axes, font, padded_range,
    plot_area_size, tick_label, time_chart,
};
use super::{ReportError, ensure_font};
use crate::analysis::montecarlo::stats::{Ellipses, percentile};

/// The bin edges of a histogram of the finite `values` (module doc); empty without values.
pub fn bin_edges(values: &[f64]) -> Vec<f64> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return Vec::new();
    }
    v.sort_by(f64::total_cmp);
    let (lo, hi) = (v[0], v[v.len() - 1]);
    if hi <= lo {
        let d = if lo == 0.0 { 0.5 } else { 0.05 * lo.abs() };
        return vec![lo - d, hi + d];
    }
    let n = v.len() as f64;
    let iqr = percentile(&v, 0.75) - percentile(&v, 0.25);
    let bins = if iqr > 0.0 {
        ((hi - lo) / (2.0 * iqr * n.powf(-1.0 / 3.0))).ceil()
    } else {
        (1.0 + n.log2()).ceil()
    }
    .clamp(5.0, 60.0) as usize;
    let w = (hi - lo) / bins as f64;
    (0..=bins)
        .map(|k| if k == bins { hi } else { lo + w * k as f64 })
        .collect()
}

/// The count of `values` in each bin of `edges` (bins half-open, the last one closed).
pub fn bin_counts(values: &[f64], edges: &[f64]) -> Vec<usize> {
    let bins = edges.len().saturating_sub(1);
    let mut counts = vec![0usize; bins];
    if bins == 0 {
        return counts;
    }
    for &x in values.iter().filter(|x| x.is_finite()) {
        let k = edges[1..].partition_point(|&e| e <= x).min(bins - 1);
        if x >= edges[0] {
            counts[k] += 1;
        }
    }
    counts
}

/// A histogram of one output over the samples, with vertical marker lines (the criterion,
/// the mean).
#[derive(Clone, Debug, PartialEq)]
pub struct Histogram {
    pub title: String,
    pub x_label: String,
    pub values: Vec<f64>,
    /// Dashed vertical lines with their labels.
    pub markers: Vec<(f64, String)>,
}

impl Figure for Histogram {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        ensure_font()?;
        root.fill(&WHITE).map_err(draw_err)?;
        let edges = bin_edges(&self.values);
        let counts = bin_counts(&self.values, &edges);
        let (x0, x1) = padded_range(
            edges
                .iter()
                .copied()
                .chain(self.markers.iter().map(|m| m.0)),
        );
        let top = counts.iter().copied().max().unwrap_or(1).max(1) as f64 * 1.15;
        let mut chart = time_chart(root, &self.title, (x0, x1), (0.0, top))?;
        chart
            .configure_mesh()
            .x_desc(self.x_label.as_str())
            .y_desc("samples")
            .axis_desc_style(font(18))
            .label_style(font(14))
            .x_label_formatter(&|v| tick_label(*v, x1 - x0))
            .y_label_formatter(&|v| tick_label(*v, top))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(200, 200, 200))
            .draw()
            .map_err(draw_err)?;
        let fill = PALETTE[0].mix(0.6).filled();
        chart
            .draw_series(
                edges
                    .windows(2)
                    .zip(&counts)
                    .map(|(e, &c)| Rectangle::new([(e[0], 0.0), (e[1], c as f64)], fill)),
            )
            .map_err(draw_err)?;
        chart
            .draw_series(edges.windows(2).zip(&counts).map(|(e, &c)| {
                Rectangle::new([(e[0], 0.0), (e[1], c as f64)], PALETTE[0].stroke_width(1))
            }))
            .map_err(draw_err)?;
        for (k, (x, label)) in self.markers.iter().enumerate() {
            let colour = PALETTE[(k + 1) % PALETTE.len()];
            let dashes = 40;
            chart
                .draw_series((0..dashes).filter(|d| d % 2 == 0).map(|d| {
                    let a = top * d as f64 / dashes as f64;
                    let b = top * (d + 1) as f64 / dashes as f64;
                    PathElement::new(vec![(*x, a), (*x, b)], colour.stroke_width(LINE_WIDTH))
                }))
                .map_err(draw_err)?;
            let y = top * (0.97 - 0.06 * k as f64);
            let (text, style) = if (x - x0) > 0.7 * (x1 - x0) {
                (
                    format!("{label} "),
                    font(14).pos(Pos::new(HPos::Right, VPos::Top)),
                )
            } else {
                (format!(" {label}"), font(14))
            };
            chart
                .draw_series(std::iter::once(Text::new(text, (*x, y), style)))
                .map_err(draw_err)?;
        }
        root.present().map_err(draw_err)
    }
}

/// The landing points on the ground (horizontal and vertical coordinates from the pad, equal
/// axes) with the 1/2/3-sigma ellipses of their sample covariance and the pad.
#[derive(Clone, Debug, PartialEq)]
pub struct LandingPlot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub points: Vec<(f64, f64)>,
    pub ellipses: Option<Ellipses>,
}

/// The points of an ellipse's outline, closed (`n` segments).
fn outline(mean: [f64; 2], a: f64, b: f64, angle: f64, n: usize) -> Vec<(f64, f64)> {
    let (s, c) = angle.sin_cos();
    (0..=n)
        .map(|k| {
            let th = std::f64::consts::TAU * (k % n) as f64 / n as f64;
            let (u, v) = (a * th.cos(), b * th.sin());
            (mean[0] + c * u - s * v, mean[1] + s * u + c * v)
        })
        .collect()
}

impl Figure for LandingPlot {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        ensure_font()?;
        root.fill(&WHITE).map_err(draw_err)?;
        let rings: Vec<(String, Vec<(f64, f64)>)> = self
            .ellipses
            .iter()
            .flat_map(|e| {
                e.ellipses.iter().map(|el| {
                    (
                        format!(
                            "{}-sigma ellipse ({:.0} % of the samples)",
                            el.k,
                            100.0 * el.observed_share
                        ),
                        outline(e.mean, el.semi_major, el.semi_minor, el.angle, 240),
                    )
                })
            })
            .collect();
        let finite: Vec<(f64, f64)> = self
            .points
            .iter()
            .copied()
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect();
        let all = || {
            finite
                .iter()
                .copied()
                .chain(rings.iter().flat_map(|r| r.1.iter().copied()))
                .chain(std::iter::once((0.0, 0.0)))
        };
        let xr = padded_range(all().map(|p| p.0));
        let yr = padded_range(all().map(|p| p.1));
        let area = plot_area_size(&self.title, root.dim_in_pixel())?;
        let ((x0, x1), (y0, y1)) = equal_axes(xr, yr, 10.0, area);
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
        let dot = PALETTE[0].mix(0.55).filled();
        chart
            .draw_series(finite.iter().map(|&p| Circle::new(p, 2, dot)))
            .map_err(draw_err)?
            .label(format!("landing points ({})", finite.len()))
            .legend(move |(x, y)| Circle::new((x + 12, y), 3, dot));
        for (k, (label, pts)) in rings.iter().enumerate() {
            let colour = PALETTE[(k + 1) % PALETTE.len()];
            draw_segments(&mut chart, pts, colour.stroke_width(LINE_WIDTH))?;
            chart
                .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
                .map_err(draw_err)?
                .label(label.as_str())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(LINE_WIDTH))
                });
        }
        chart
            .draw_series(std::iter::once(TriangleMarker::new(
                (0.0, 0.0),
                7,
                BLACK.filled(),
            )))
            .map_err(draw_err)?
            .label("pad")
            .legend(|(x, y)| TriangleMarker::new((x + 12, y), 6, BLACK.filled()));
        chart
            .configure_series_labels()
            .label_font(font(14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(draw_err)?;
        root.present().map_err(draw_err)
    }
}

/// Horizontal bars: each input's Spearman rank correlation with an output, in the order
/// given, from -1 to 1 (an input without a value is drawn without a bar).
#[derive(Clone, Debug, PartialEq)]
pub struct SensitivityBars {
    pub title: String,
    pub x_label: String,
    pub bars: Vec<(String, Option<f64>)>,
}

impl Figure for SensitivityBars {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        ensure_font()?;
        root.fill(&WHITE).map_err(draw_err)?;
        let n = self.bars.len().max(1) as f64;
        let mut chart = time_chart(root, &self.title, (-1.0, 1.0), (0.0, n))?;
        chart
            .configure_mesh()
            .x_desc(self.x_label.as_str())
            .axis_desc_style(font(18))
            .label_style(font(14))
            .disable_y_mesh()
            .y_labels(0)
            .x_label_formatter(&|v| tick_label(*v, 2.0))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(200, 200, 200))
            .draw()
            .map_err(draw_err)?;
        for (k, (name, r)) in self.bars.iter().enumerate() {
            // The first bar at the top.
            let y = n - k as f64 - 0.5;
            if let Some(r) = r.filter(|r| r.is_finite()) {
                let colour = if r >= 0.0 { PALETTE[0] } else { PALETTE[1] };
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(0.0, y - 0.3), (r, y + 0.3)],
                        colour.filled(),
                    )))
                    .map_err(draw_err)?;
            }
            // The name on the side of zero away from the bar, then the value.
            let r_text = r.map_or("-".to_string(), |r| format!("{r:+.3}"));
            let right = r.is_some_and(|r| r >= 0.0);
            let (x, anchor) = if right {
                (-0.02, HPos::Right)
            } else {
                (0.02, HPos::Left)
            };
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("{name} ({r_text})"),
                    (x, y),
                    font(14).pos(Pos::new(anchor, VPos::Center)),
                )))
                .map_err(draw_err)?;
        }
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(0.0, 0.0), (0.0, n)],
                BLACK.stroke_width(1),
            )))
            .map_err(draw_err)?;
        root.present().map_err(draw_err)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every finite value falls in exactly one bin, the extremes included; the bins cover
    /// the range without gaps.
    #[test]
    fn bins_count_every_value_once() {
        let v: Vec<f64> = (0..1000)
            .map(|k| ((k * 7919) % 1000) as f64 * 0.37 - 50.0)
            .chain([f64::NAN, f64::INFINITY])
            .collect();
        let e = bin_edges(&v);
        assert!(e.len() >= 6 && e.len() <= 61, "{}", e.len());
        assert!(e.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(e[0], -50.0);
        assert_eq!(e[e.len() - 1], 999.0 * 0.37 - 50.0);
        assert_eq!(bin_counts(&v, &e).iter().sum::<usize>(), 1000);
        let flat = [3.0; 10];
        let e = bin_edges(&flat);
        assert_eq!(bin_counts(&flat, &e), vec![10]);
        assert!(bin_edges(&[]).is_empty());
    }

    /// Freedman-Diaconis: the bin width of a uniform sample is 2 IQR n^(-1/3), the IQR
    /// half the range.
    #[test]
    fn freedman_diaconis_width() {
        let n = 1000;
        let v: Vec<f64> = (0..n).map(|k| k as f64 / (n - 1) as f64).collect();
        let e = bin_edges(&v);
        let bins = e.len() - 1;
        let expected = (1.0 / (2.0 * 0.5 * (n as f64).powf(-1.0 / 3.0))).ceil() as usize;
        assert_eq!(bins, expected);
    }

    /// An ellipse's outline is at Mahalanobis radius 1 of its own axes, closed.
    #[test]
    fn outline_is_the_ellipse() {
        let (a, b, th) = (30.0, 10.0, 0.7_f64);
        let p = outline([5.0, -2.0], a, b, th, 64);
        assert_eq!(p[0], p[64]);
        for (x, y) in p {
            let (dx, dy) = (x - 5.0, y + 2.0);
            let u = dx * th.cos() + dy * th.sin();
            let v = -dx * th.sin() + dy * th.cos();
            assert!(((u / a).powi(2) + (v / b).powi(2) - 1.0).abs() < 1e-12);
        }
    }
}
