//! Deformation frames: the FE mesh deformed by the modal coordinates at one time, magnified,
//! in a front view and an isometric 3-D view.
//!
//! The elastic displacement of node i is `u_i = sum_j Phi_(6i+d, j) eta_j` for d = 0..2,
//! the translational rows of the selected (fixity-adjusted) shapes of the compiled vehicle
//! (the deformation field `u_f = S eta` of the floating frame, ch. 2); rotations are not
//! drawn. Positions are body-frame coordinates (x forward, z down, origin at the nose).

use plotters::coord::Shift;
use plotters::prelude::*;

use super::plot::{Figure, PALETTE, draw_err, font, tick_label};
use super::{ReportError, ensure_font};
use crate::structure::compile::CompiledVehicle;

/// The undeformed mesh and its mode shapes.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshGeometry {
    /// Undeformed node positions, body frame, m.
    pub positions: Vec<[f64; 3]>,
    /// -1 body, i >= 0 fin i.
    pub components: Vec<i32>,
    /// Node index pairs drawn as lines (element edges). Empty when the topology is not
    /// known: then the body nodes are joined in x order and fin nodes drawn as dots.
    pub edges: Vec<[usize; 2]>,
    /// Row-major `6 * n_nodes` x `mode_names.len()` shapes.
    pub shapes: Vec<f64>,
    /// Mode names in the order of eta (the history's columns are `eta_<name>`).
    pub mode_names: Vec<String>,
}

impl MeshGeometry {
    /// The geometry of a compiled vehicle, with the given element edges (may be empty).
    pub fn from_compiled(c: &CompiledVehicle, edges: Vec<[usize; 2]>) -> Self {
        MeshGeometry {
            positions: c.node_positions.clone(),
            components: c.node_components.clone(),
            edges,
            shapes: c.shapes.clone(),
            mode_names: c.modes.iter().map(|m| m.name.clone()).collect(),
        }
    }

    /// Translational elastic displacement of every node for the modal coordinates `eta`
    /// (in the order of `mode_names`; missing trailing values count as 0).
    pub fn displacements(&self, eta: &[f64]) -> Vec<[f64; 3]> {
        let m = self.mode_names.len();
        (0..self.positions.len())
            .map(|i| {
                let mut u = [0.0; 3];
                for (d, ud) in u.iter_mut().enumerate() {
                    let row = (6 * i + d) * m;
                    *ud = (0..m.min(eta.len()))
                        .map(|j| self.shapes.get(row + j).copied().unwrap_or(0.0) * eta[j])
                        .sum();
                }
                u
            })
            .collect()
    }

    /// Largest distance of a node from the body axis (the span seen in the front view),
    /// or the body length when every node is on the axis; 1 for an empty mesh.
    pub fn reference_span(&self) -> f64 {
        let radial = self
            .positions
            .iter()
            .map(|p| p[1].hypot(p[2]))
            .fold(0.0, f64::max);
        if radial > 0.0 {
            return radial;
        }
        let (lo, hi) = self
            .positions
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p[0]), hi.max(p[0]))
            });
        if hi > lo { hi - lo } else { 1.0 }
    }

    /// The edges to draw: the element edges, or (without topology) the body nodes joined
    /// in x order.
    fn drawn_edges(&self) -> Vec<[usize; 2]> {
        if !self.edges.is_empty() {
            return self.edges.clone();
        }
        let mut body: Vec<usize> = (0..self.positions.len())
            .filter(|&i| self.components.get(i) == Some(&-1))
            .collect();
        body.sort_by(|&a, &b| self.positions[a][0].total_cmp(&self.positions[b][0]));
        body.windows(2).map(|w| [w[0], w[1]]).collect()
    }
}

/// The magnification that makes the largest displacement over all `etas` equal to
/// `fraction` of the reference span (1 when nothing moves).
pub fn auto_magnification(geom: &MeshGeometry, etas: &[Vec<f64>], fraction: f64) -> f64 {
    let max_u = etas
        .iter()
        .flat_map(|eta| geom.displacements(eta))
        .map(|u| (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt())
        .fold(0.0, f64::max);
    if max_u > 0.0 && max_u.is_finite() {
        fraction * geom.reference_span() / max_u
    } else {
        1.0
    }
}

/// Front view, looking aft from ahead of the nose: screen right is -y, screen up is -z.
pub fn front_view(p: [f64; 3]) -> (f64, f64) {
    (-p[1], -p[2])
}

/// Isometric view of the right-handed axes (-x, y, -z): the nose points up and right,
/// +y down and right, z (down) straight down:
/// `s_x = (x + y) cos 30 deg`, `s_y = -z + (x - y) sin 30 deg`.
pub fn isometric_view(p: [f64; 3]) -> (f64, f64) {
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    ((p[0] + p[1]) * c, -p[2] + (p[0] - p[1]) * s)
}

/// One frame: the mesh at time `t` with modal coordinates `eta`, displacements times
/// `magnify`.
#[derive(Clone, Debug)]
pub struct DeformationFrame<'a> {
    /// The undeformed mesh and its shapes.
    pub geometry: &'a MeshGeometry,
    /// Modal coordinates at `t`, in the order of `geometry.mode_names`.
    pub eta: Vec<f64>,
    /// Time of the frame, s.
    pub t: f64,
    /// Factor on the displacements.
    pub magnify: f64,
    /// Caption above both views.
    pub title: String,
}

/// Ranges of equal scale on both axes for an area of `w` x `h` pixels.
fn equal_aspect(points: &[(f64, f64)], w: u32, h: u32) -> ((f64, f64), (f64, f64)) {
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in points
        .iter()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
    {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if x0 > x1 {
        return ((-1.0, 1.0), (-1.0, 1.0));
    }
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let per_px = ((x1 - x0) / f64::from(w.max(1)))
        .max((y1 - y0) / f64::from(h.max(1)))
        .max(1e-9)
        * 1.1;
    let (hw, hh) = (0.5 * per_px * f64::from(w), 0.5 * per_px * f64::from(h));
    ((cx - hw, cx + hw), (cy - hh, cy + hh))
}

fn component_colour(c: i32) -> RGBColor {
    if c < 0 {
        RGBColor(30, 30, 30)
    } else {
        PALETTE[(c as usize) % PALETTE.len()]
    }
}

impl DeformationFrame<'_> {
    fn draw_view<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        caption: &str,
        labels: (&str, &str),
        project: fn([f64; 3]) -> (f64, f64),
    ) -> Result<(), ReportError> {
        let g = self.geometry;
        let u = g.displacements(&self.eta);
        let deformed: Vec<[f64; 3]> = g
            .positions
            .iter()
            .zip(&u)
            .map(|(p, d)| {
                [
                    p[0] + self.magnify * d[0],
                    p[1] + self.magnify * d[1],
                    p[2] + self.magnify * d[2],
                ]
            })
            .collect();
        let before: Vec<(f64, f64)> = g.positions.iter().map(|p| project(*p)).collect();
        let after: Vec<(f64, f64)> = deformed.iter().map(|p| project(*p)).collect();
        let all: Vec<(f64, f64)> = before.iter().chain(&after).copied().collect();
        let (w, h) = area.dim_in_pixel();
        let (xr, yr) = equal_aspect(&all, w.saturating_sub(80), h.saturating_sub(100));
        let mut chart = ChartBuilder::on(area)
            .caption(caption, font(18))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
            .map_err(draw_err)?;
        chart
            .configure_mesh()
            .x_desc(labels.0)
            .y_desc(labels.1)
            .axis_desc_style(font(14))
            .label_style(font(12))
            .x_label_formatter(&|v| tick_label(*v, xr.1 - xr.0))
            .y_label_formatter(&|v| tick_label(*v, yr.1 - yr.0))
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()
            .map_err(draw_err)?;
        let edges = g.drawn_edges();
        let line = |pts: &[(f64, f64)], e: &[usize; 2]| -> Option<Vec<(f64, f64)>> {
            Some(vec![*pts.get(e[0])?, *pts.get(e[1])?])
        };
        chart
            .draw_series(edges.iter().filter_map(|e| {
                Some(PathElement::new(
                    line(&before, e)?,
                    RGBColor(190, 190, 190).stroke_width(1),
                ))
            }))
            .map_err(draw_err)?;
        chart
            .draw_series(edges.iter().filter_map(|e| {
                // An edge from the body to a fin root belongs to the fin.
                let c = (*g.components.get(e[0])?).max(*g.components.get(e[1])?);
                let c = component_colour(c);
                Some(PathElement::new(line(&after, e)?, c.stroke_width(2)))
            }))
            .map_err(draw_err)?;
        if g.edges.is_empty() {
            chart
                .draw_series(
                    after
                        .iter()
                        .zip(&g.components)
                        .map(|(p, c)| Circle::new(*p, 2, component_colour(*c).filled())),
                )
                .map_err(draw_err)?;
        }
        Ok(())
    }
}

impl Figure for DeformationFrame<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        ensure_font()?;
        root.fill(&WHITE).map_err(draw_err)?;
        let root = root.titled(&self.title, font(22)).map_err(draw_err)?;
        let (w, _) = root.dim_in_pixel();
        let (left, right) = root.split_horizontally(w * 2 / 5);
        self.draw_view(
            &left,
            "front view (looking aft)",
            ("-y (m)", "-z (m)"),
            front_view,
        )?;
        self.draw_view(
            &right,
            "isometric view (grey: undeformed)",
            ("(x + y) cos 30 (m)", "-z + (x - y) sin 30 (m)"),
            isometric_view,
        )?;
        root.present().map_err(draw_err)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_node_geometry() -> MeshGeometry {
        // Two nodes, one mode moving node 1 by (0, 0, 2) per unit eta.
        let mut shapes = vec![0.0; 12];
        shapes[6 + 2] = 2.0;
        MeshGeometry {
            positions: vec![[0.0, 0.0, 0.0], [-1.0, 0.0, 0.5]],
            components: vec![-1, 0],
            edges: vec![],
            shapes,
            mode_names: vec!["fin1_flap".into()],
        }
    }

    #[test]
    fn displacement_is_shape_times_eta() {
        let g = two_node_geometry();
        let u = g.displacements(&[0.25]);
        assert_eq!(u[0], [0.0, 0.0, 0.0]);
        assert_eq!(u[1], [0.0, 0.0, 0.5]);
        assert_eq!(g.reference_span(), 0.5);
        // Largest displacement 2 * 0.1 = 0.2 must become 10 % of 0.5.
        let m = auto_magnification(&g, &[vec![0.0], vec![-0.1]], 0.1);
        assert!((m * 0.2 - 0.05).abs() < 1e-15, "{m}");
        assert_eq!(auto_magnification(&g, &[vec![0.0]], 0.1), 1.0);
    }

    #[test]
    fn views_put_the_nose_up_right_and_z_down() {
        let (sx, sy) = isometric_view([1.0, 0.0, 0.0]);
        assert!(sx > 0.0 && sy > 0.0);
        let (sx, sy) = isometric_view([0.0, 0.0, 1.0]);
        assert!(sx == 0.0 && sy < 0.0);
        assert_eq!(front_view([0.0, 1.0, 2.0]), (-1.0, -2.0));
    }
}
