//! Marching squares: the level curves of a field sampled on a rectangular grid, as line
//! segments (the contour lines of the stability maps, Figs 6.3-6.8).
//!
//! Within each grid cell the field is taken as linear along every cell edge, so a crossing
//! of `level` on the edge from corner a to corner b lies at
//! `p = p_a + (level - f_a) / (f_b - f_a) (p_b - p_a)`; corners with `f >= level` count as
//! "above". The two saddle cases (diagonally opposite corners above) are resolved with the
//! mean of the four corners (the bilinear value at the cell centre): if it is above, the
//! above corners are joined through the centre. Cells with a non-finite corner are skipped.

/// One contour segment, from `a` to `b`, in the grid's (x, y) coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// First end, (x, y).
    pub a: [f64; 2],
    /// Second end, (x, y).
    pub b: [f64; 2],
}

impl Segment {
    /// Euclidean length.
    pub fn length(&self) -> f64 {
        (self.b[0] - self.a[0]).hypot(self.b[1] - self.a[1])
    }
}

/// The segments of the curve `f(x, y) = level` of a field on the grid `xs` x `ys`.
///
/// `values` is row-major with one row per y: `values[j * xs.len() + i] = f(xs[i], ys[j])`.
/// `xs` and `ys` must be monotonic; a grid whose sizes do not match `values` gives no
/// segments. Segments of zero length (a corner exactly on the level) are dropped.
pub fn contour_segments(xs: &[f64], ys: &[f64], values: &[f64], level: f64) -> Vec<Segment> {
    let (nx, ny) = (xs.len(), ys.len());
    let mut out = Vec::new();
    if nx < 2 || ny < 2 || values.len() != nx * ny {
        return out;
    }
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            // Corners counter-clockwise from (i, j): 0 = (i, j), 1 = (i+1, j),
            // 2 = (i+1, j+1), 3 = (i, j+1).
            let p = [
                [xs[i], ys[j]],
                [xs[i + 1], ys[j]],
                [xs[i + 1], ys[j + 1]],
                [xs[i], ys[j + 1]],
            ];
            let f = [
                values[j * nx + i],
                values[j * nx + i + 1],
                values[(j + 1) * nx + i + 1],
                values[(j + 1) * nx + i],
            ];
            if f.iter().any(|v| !v.is_finite()) {
                continue;
            }
            let case = f
                .iter()
                .enumerate()
                .fold(0usize, |c, (k, &v)| c | (usize::from(v >= level) << k));
            // Edge k joins corner k and corner (k + 1) % 4; it is always interpolated from
            // its corner of lower grid index, so the cells on both sides of an edge compute
            // bit-identical crossings.
            let cross = |k: usize| -> [f64; 2] {
                let (a, b) = match k {
                    0 => (0, 1),
                    1 => (1, 2),
                    2 => (3, 2),
                    _ => (0, 3),
                };
                let t = (level - f[a]) / (f[b] - f[a]);
                [
                    p[a][0] + t * (p[b][0] - p[a][0]),
                    p[a][1] + t * (p[b][1] - p[a][1]),
                ]
            };
            let centre_above = f.iter().sum::<f64>() / 4.0 >= level;
            // Pairs of crossed edges for each case (edges 0 bottom, 1 right, 2 top, 3 left).
            let pairs: &[(usize, usize)] = match case {
                0 | 15 => &[],
                1 | 14 => &[(3, 0)],
                2 | 13 => &[(0, 1)],
                3 | 12 => &[(3, 1)],
                4 | 11 => &[(1, 2)],
                6 | 9 => &[(0, 2)],
                7 | 8 => &[(3, 2)],
                // Saddles: corners 0 and 2 above (5), or 1 and 3 above (10).
                5 if centre_above => &[(3, 2), (0, 1)],
                5 => &[(3, 0), (1, 2)],
                10 if centre_above => &[(3, 0), (1, 2)],
                10 => &[(3, 2), (0, 1)],
                _ => &[],
            };
            for &(e1, e2) in pairs {
                let s = Segment {
                    a: cross(e1),
                    b: cross(e2),
                };
                if s.length() > 0.0 {
                    out.push(s);
                }
            }
        }
    }
    out
}

/// "Nice" contour levels covering `[lo, hi]`: about `target` multiples of 1, 2 or 5 times a
/// power of ten, always including 0 when the range straddles it.
pub fn nice_levels(lo: f64, hi: f64, target: usize) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo || target == 0 {
        return Vec::new();
    }
    let raw = (hi - lo) / target as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// sigma = x - y on a grid whose nodes avoid the diagonal: the zero contour is the
    /// diagonal, every endpoint lies on it, and the pieces add up to its length inside the
    /// grid, from (0.5, 0.5) to (2.5, 2.5).
    #[test]
    fn zero_contour_of_x_minus_y_is_the_diagonal() {
        let xs = [0.0, 1.0, 2.0, 3.0];
        let ys = [0.5, 1.5, 2.5];
        let values: Vec<f64> = ys
            .iter()
            .flat_map(|y| xs.iter().map(move |x| x - y))
            .collect();
        let segs = contour_segments(&xs, &ys, &values, 0.0);
        assert!(!segs.is_empty());
        for s in &segs {
            for p in [s.a, s.b] {
                assert!(
                    (p[0] - p[1]).abs() < 1e-12,
                    "endpoint {p:?} off the diagonal"
                );
                assert!(
                    (0.5..=2.5).contains(&p[0]),
                    "endpoint {p:?} outside the grid"
                );
            }
        }
        let total: f64 = segs.iter().map(Segment::length).sum();
        assert!((total - 2.0 * 2f64.sqrt()).abs() < 1e-12, "length {total}");
        let mut ends: Vec<f64> = segs.iter().flat_map(|s| [s.a[0], s.b[0]]).collect();
        ends.sort_by(f64::total_cmp);
        assert_eq!(ends.first().copied(), Some(0.5));
        assert_eq!(ends.last().copied(), Some(2.5));
        // Crossings at the grid lines x = 1, 2 and y = 1.5 (each shared by two cells).
        for x in [1.0, 1.5, 2.0] {
            assert!(ends.iter().filter(|e| (**e - x).abs() < 1e-12).count() >= 2);
        }
    }

    #[test]
    fn non_zero_level_is_shifted_diagonal() {
        let xs = [0.0, 1.0, 2.0, 3.0];
        let ys = [0.5, 1.5, 2.5];
        let values: Vec<f64> = ys
            .iter()
            .flat_map(|y| xs.iter().map(move |x| x - y))
            .collect();
        let segs = contour_segments(&xs, &ys, &values, 0.25);
        assert!(!segs.is_empty());
        for s in &segs {
            for p in [s.a, s.b] {
                assert!((p[0] - p[1] - 0.25).abs() < 1e-12, "{p:?}");
            }
        }
        let total: f64 = segs.iter().map(Segment::length).sum();
        // From (0.75, 0.5) to (2.75, 2.5).
        assert!((total - 2.0 * 2f64.sqrt()).abs() < 1e-12, "length {total}");
    }

    /// A circle r = 1 of f = x^2 + y^2: endpoints on edges are linear interpolants, so
    /// they lie within the grid-spacing error of the circle and enclose it.
    #[test]
    fn circle_is_closed_and_close() {
        // 40 points: no grid node lies exactly on the circle.
        let n = 40;
        let g: Vec<f64> = (0..n)
            .map(|k| -2.0 + 4.0 * k as f64 / (n - 1) as f64)
            .collect();
        let values: Vec<f64> = g
            .iter()
            .flat_map(|y| g.iter().map(move |x| x * x + y * y))
            .collect();
        let segs = contour_segments(&g, &g, &values, 1.0);
        let h = 4.0 / 39.0;
        for s in &segs {
            for p in [s.a, s.b] {
                let r = p[0].hypot(p[1]);
                assert!((r - 1.0).abs() < h * h, "r = {r}");
            }
        }
        let total: f64 = segs.iter().map(Segment::length).sum();
        assert!((total - 2.0 * std::f64::consts::PI).abs() < 0.01, "{total}");
        // Closed: every endpoint is shared by exactly two segments.
        let key = |p: [f64; 2]| ((p[0] * 1e9).round() as i64, (p[1] * 1e9).round() as i64);
        let mut count = std::collections::HashMap::new();
        for s in &segs {
            *count.entry(key(s.a)).or_insert(0) += 1;
            *count.entry(key(s.b)).or_insert(0) += 1;
        }
        assert!(count.values().all(|&c| c == 2));
    }

    #[test]
    fn saddle_is_resolved_by_the_centre_and_nan_cells_skipped() {
        // f = x y on [-1, 1]^2 with one cell: corners alternate in sign; centre value 0
        // counts as above, so the two above corners (-1,-1) and (1,1) are joined: the
        // segments cut off the corners (1,-1) and (-1,1).
        let segs = contour_segments(&[-1.0, 1.0], &[-1.0, 1.0], &[1.0, -1.0, -1.0, 1.0], 0.0);
        assert_eq!(segs.len(), 2);
        let mut got: Vec<[f64; 2]> = segs.iter().flat_map(|s| [s.a, s.b]).collect();
        got.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
        assert_eq!(got, vec![[-1.0, 0.0], [0.0, -1.0], [0.0, 1.0], [1.0, 0.0]]);
        let pairs: Vec<bool> = segs
            .iter()
            .map(|s| (s.a[0] + s.b[0]).abs() == 1.0 && (s.a[1] + s.b[1]).abs() == 1.0)
            .collect();
        // Each segment joins a midpoint of an x edge and one of a y edge next to the same
        // below corner: (0,-1)-(1,0) around (1,-1) and (-1,0)-(0,1) around (-1,1).
        assert_eq!(pairs, vec![true, true]);
        let around = |s: &Segment| [(s.a[0] + s.b[0]).signum(), (s.a[1] + s.b[1]).signum()];
        let mut corners: Vec<[f64; 2]> = segs.iter().map(around).collect();
        corners.sort_by(|p, q| p[0].total_cmp(&q[0]));
        assert_eq!(corners, vec![[-1.0, 1.0], [1.0, -1.0]]);
        let nan = contour_segments(&[0.0, 1.0], &[0.0, 1.0], &[f64::NAN, -1.0, 1.0, 1.0], 0.0);
        assert!(nan.is_empty());
        assert!(contour_segments(&[0.0, 1.0], &[0.0], &[0.0, 1.0], 0.5).is_empty());
    }

    #[test]
    fn nice_levels_include_zero() {
        let l = nice_levels(-37.0, 112.0, 10);
        assert!(l.contains(&0.0));
        assert_eq!(l.first().copied(), Some(-20.0));
        assert_eq!(l.last().copied(), Some(100.0));
    }
}
