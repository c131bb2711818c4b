//! Mesh layout: body stations along the body line and the fin quad grids.
//!
//! Body stations are the union of
//! - "hard" stations, kept exactly because the geometry or a mass changes there: the nose
//!   tip x = 0, the tail x = -L, the end of the nose x = -l_n, the point where the nose
//!   stops being solid (r_o = t: x = -t l_n / R on a cone) unless it lies within 0.3 of a
//!   division of another hard station (the element across it is integrated in two parts:
//!   `beam::beam_element`), both ends of every transition,
//!   both ends of every distributed mass, and
//!   the x of every fin root node (so each root node has a body node at the same x), unless
//!   another hard station lies within 1e-3 of a division of it (a canted fin's root ends: the
//!   root node is then linked to that station with its offset, not given a sliver element);
//!   any hard station within 1e-3 of a division ([`SLIVER`]) of one listed before it in this
//!   order is that station (the nose tip and the tail always kept exactly): two ends written
//!   a few micrometres apart (an imported design's rounded stations; a transition ending
//!   where a mass begins) would otherwise bound a sliver element whose stiffness over its
//!   mass swamps the modal solve (it found mechanisms or did not finish); a distributed mass
//!   whose end moves so keeps its line density, so its total moves by that fraction of its
//!   length (1e-5 for 5 um on 0.45 m);
//! - the `elements` uniform divisions of [-L, 0], dropping any that falls within 0.3 of a
//!   division of a hard station (to avoid slivers).
//!
//! Stations closer than 1e-12 L are merged. Node 0 is the nose tip; nodes run aft.

use super::assembly::NodeMap;
use super::spec::{BodySpec, FinSpec, GeneratorSpec};
use nalgebra::{Matrix3, Vector3};

/// Body stations, from x = 0 (nose tip) down to x = -L (module doc).
pub fn body_stations(spec: &GeneratorSpec) -> Vec<f64> {
    let body = &spec.body;
    let l = body.length;
    let mut hard = vec![0.0, -l];
    if body.nose_length > 0.0 {
        hard.push(-body.nose_length);
    }
    for t in &body.transitions {
        hard.push(-t.start);
        hard.push(-t.end());
    }
    for d in &spec.distributed_masses {
        hard.push(d.x_from);
        hard.push(d.x_to);
    }
    let h = l / body.elements as f64;
    // Near-coincident hard stations are one: the first listed wins (module doc).
    let mut kept: Vec<f64> = Vec::with_capacity(hard.len());
    for &x in &hard {
        if kept.iter().all(|&s| (s - x).abs() > SLIVER * h) {
            kept.push(x);
        }
    }
    let mut hard = kept;
    // The nose's solid-tip end, unless it lies within 0.3 of a division of another hard
    // station: the beam element across it is then integrated in its two parts
    // (`beam::beam_element`), as exactly as with a node there, and no sliver element is made
    // (an elliptical nose's r ~ sqrt(s) makes it t^2 l_n / (2 R^2) from the tip: 36 um on a
    // RockSim test design, whose element's K_ii/M_ii of 3e16 hid the body's modes).
    if body.nose_length > 0.0 {
        let s0 = body.nose_shape.solid_tip_end(
            body.wall_thickness,
            0.5 * body.outer_diameter,
            body.nose_length,
        );
        if s0 < body.nose_length && hard.iter().all(|&s| (s + s0).abs() > 0.3 * h) {
            hard.push(-s0);
        }
    }
    // A fin root node's station, unless another hard station lies within `SLIVER` h of it:
    // the root node is then linked to that station with its small x offset
    // (`NodeMap::Slave`), where a station of its own would leave a sliver element. A canted
    // fin's root nodes sit `(1 - cos cant)` of their distance from the pivot forward of the
    // root's ends: 25 um ahead of SPHADS-1's tail at 1 deg, whose sliver beam's stiffness
    // swamped the modal solve (it did not finish, or found mechanisms).
    if let Some(f) = &spec.fins {
        for x in fin_root_stations(f) {
            if hard.iter().all(|&s| (s - x).abs() > SLIVER * h) {
                hard.push(x);
            }
        }
    }
    let mut all = hard.clone();
    for k in 1..body.elements {
        let x = -(k as f64) * h;
        if hard.iter().all(|&s| (s - x).abs() > 0.3 * h) {
            all.push(x);
        }
    }
    all.sort_by(|a, b| b.total_cmp(a));
    all.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * l);
    all
}

/// Two stations closer than this fraction of the uniform division are one (a fin root
/// node's and another hard station's: [`body_stations`]).
pub const SLIVER: f64 = 1e-3;

/// x of the body station under each root node of a fin (chordwise index 0..=chord_elements).
pub fn fin_root_stations(f: &FinSpec) -> Vec<f64> {
    (0..=f.chord_elements)
        .map(|i| {
            let (x, _) = f.planform_point(i, 0);
            f.pivot_x() + (x - f.pivot_x()) * f.cant.cos()
        })
        .collect()
}

/// Index of the station nearest to x (stations descending).
pub fn nearest_station(stations: &[f64], x: f64) -> usize {
    let mut best = 0;
    for (i, s) in stations.iter().enumerate() {
        if (s - x).abs() < (stations[best] - x).abs() {
            best = i;
        }
    }
    best
}

/// Orthonormal fin frame (e_a chordwise, e_b spanwise, n = e_a x e_b) of a fin at angle
/// delta with cant angle `cant` (FinSpec::cant). Rows of the returned matrix are e_a, e_b, n,
/// so local = T * body.
pub fn fin_frame(delta: f64, cant: f64) -> Matrix3<f64> {
    let ex = Vector3::new(1.0, 0.0, 0.0);
    let es = Vector3::new(0.0, delta.cos(), delta.sin());
    let n0 = ex.cross(&es); // (0, -sin, cos)
    let ea = cant.cos() * ex + cant.sin() * n0;
    let n = ea.cross(&es);
    Matrix3::from_rows(&[ea.transpose(), es.transpose(), n.transpose()])
}

/// One fin laid out: body-frame positions of the grid points and the local (a, b)
/// coordinates used by the shell elements.
pub struct FinGrid {
    /// Rows of the local frame: e_a, e_b, n.
    pub frame: Matrix3<f64>,
    /// `points[j][i]`: body-frame position of chordwise i, spanwise j.
    pub points: Vec<Vec<[f64; 3]>>,
    /// `local[j][i]`: (a, b) in the fin plane.
    pub local: Vec<Vec<[f64; 2]>>,
}

/// Lay out fin grid points: root at `root_radius` from the body axis, along span direction
/// (0, cos delta, sin delta); chordwise coordinate a = x - x_pivot turned by the cant.
pub fn fin_grid(f: &FinSpec, delta: f64, root_radius: f64) -> FinGrid {
    let frame = fin_frame(delta, f.cant);
    let ea = frame.row(0).transpose();
    let es = frame.row(1).transpose();
    let origin = Vector3::new(f.pivot_x(), 0.0, 0.0) + root_radius * es;
    let mut points = Vec::with_capacity(f.span_elements + 1);
    let mut local = Vec::with_capacity(f.span_elements + 1);
    for j in 0..=f.span_elements {
        let mut prow = Vec::with_capacity(f.chord_elements + 1);
        let mut lrow = Vec::with_capacity(f.chord_elements + 1);
        for i in 0..=f.chord_elements {
            let (x, eta) = f.planform_point(i, j);
            let a = x - f.pivot_x();
            let p = origin + a * ea + eta * es;
            prow.push([p[0], p[1], p[2]]);
            lrow.push([a, eta]);
        }
        points.push(prow);
        local.push(lrow);
    }
    FinGrid {
        frame,
        points,
        local,
    }
}

/// Node maps of the fin grid: spanwise rows j >= 1 become global nodes numbered from
/// `first_node` (row by row, chordwise fastest); the root row j = 0 maps through `root`.
pub fn fin_node_maps(
    f: &FinSpec,
    first_node: usize,
    root: impl Fn(usize) -> NodeMap,
) -> Vec<Vec<NodeMap>> {
    let nc = f.chord_elements + 1;
    let pointed = f.pointed_tip();
    (0..=f.span_elements)
        .map(|j| {
            (0..nc)
                .map(|i| {
                    if j == 0 {
                        root(i)
                    } else if pointed && j == f.span_elements {
                        // The collapsed tip: one node.
                        NodeMap::Node(first_node + (j - 1) * nc)
                    } else {
                        NodeMap::Node(first_node + (j - 1) * nc + i)
                    }
                })
                .collect()
        })
        .collect()
}

/// Outer radius of the body where the fins sit (they must be on a section of one diameter:
/// `check::transition`), at the middle of the root chord `pivot_x`.
pub fn fin_root_radius(body: &BodySpec, pivot_x: f64) -> f64 {
    crate::check::transition::section_radius(0.5 * body.outer_diameter, &body.transitions, -pivot_x)
}
