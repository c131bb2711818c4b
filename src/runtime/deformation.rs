//! The largest elastic displacement over the structure's nodes, `max_i |S_trans,i η|`, for
//! the `max_deformation` stop condition and output channel (outside the right-hand side).
//!
//! `S_trans,i` is the 3 x n block of translation rows of node `i` of the mode shapes `S`
//! (thesis eq. 3.1.1: `u_i = S_i η`). Two things make it cheap on every accepted step:
//! - the shapes are stored mode by mode (`3 N` entries per mode), so `u = Σ_m η_m S_:,m` is
//!   one contiguous axpy per mode;
//! - the stop check first compares the bound `|S_i η| ≤ ‖S_i‖_F ‖η‖` (Cauchy-Schwarz on each
//!   row of `S_i`), maximised over the nodes once, with the limit, and evaluates the exact
//!   maximum only when the bound reaches it.

/// The node translation shapes of a plan, rearranged for [`Self::max_displacement`].
#[derive(Debug, Clone)]
pub struct NodeDeformation {
    n: usize,
    /// `S_trans` column by column: entry `(node, axis)` of mode `m` at `m 3N + 3 node + axis`.
    shapes_by_mode: Vec<f64>,
    /// `max_i ‖S_i‖_F`.
    bound: f64,
    /// `u = S η` (3N).
    u: Vec<f64>,
}

impl NodeDeformation {
    /// From the row-major node blocks of [`crate::plan::Plan::node_translation_shapes`]:
    /// node `i`, axis `d`, mode `m` at `(3 i + d) n + m`.
    pub fn new(node_translation_shapes: &[f64], n: usize) -> Self {
        let rows = node_translation_shapes.len().checked_div(n).unwrap_or(0);
        let mut shapes_by_mode = vec![0.0; rows * n];
        let mut bound: f64 = 0.0;
        for node in node_translation_shapes.chunks_exact((3 * n).max(1)) {
            bound = bound.max(node.iter().map(|s| s * s).sum::<f64>().sqrt());
        }
        for r in 0..rows {
            for m in 0..n {
                shapes_by_mode[m * rows + r] = node_translation_shapes[r * n + m];
            }
        }
        Self {
            n,
            shapes_by_mode,
            bound,
            u: vec![0.0; rows],
        }
    }

    /// `max_i |S_trans,i η|`, m (0 without modes or nodes).
    pub fn max_displacement(&mut self, eta: &[f64]) -> f64 {
        let rows = self.u.len();
        if self.n == 0 || rows == 0 {
            return 0.0;
        }
        self.u.fill(0.0);
        for (m, e) in eta.iter().take(self.n).enumerate() {
            let col = &self.shapes_by_mode[m * rows..(m + 1) * rows];
            for (u, s) in self.u.iter_mut().zip(col) {
                *u += e * s;
            }
        }
        self.u
            .chunks_exact(3)
            .map(|u| (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt())
            .fold(0.0, f64::max)
    }

    /// `max_i |S_trans,i η| > limit`; the exact maximum only when the bound reaches the
    /// limit (the margin `1e-9` covers the rounding of the bound).
    pub fn exceeds(&mut self, eta: &[f64], limit: f64) -> bool {
        let norm = eta.iter().map(|e| e * e).sum::<f64>().sqrt();
        if self.bound * norm * (1.0 + 1e-9) <= limit {
            return false;
        }
        self.max_displacement(eta) > limit
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rearranged maximum equals the direct one (node by node, row by row), and the
    /// bounded check agrees with the exact comparison on both sides of the limit.
    #[test]
    fn maximum_and_bounded_check_match_the_direct_evaluation() {
        let (nodes, n) = (37, 4);
        let s: Vec<f64> = (0..3 * nodes * n)
            .map(|k| ((k * 7919 % 1013) as f64 / 1013.0 - 0.5) * (1.0 + (k % 5) as f64))
            .collect();
        let direct = |eta: &[f64]| -> f64 {
            s.chunks_exact(3 * n)
                .map(|node| {
                    (0..3)
                        .map(|d| {
                            let u: f64 = (0..n).map(|m| node[d * n + m] * eta[m]).sum();
                            u * u
                        })
                        .sum::<f64>()
                        .sqrt()
                })
                .fold(0.0, f64::max)
        };
        let mut nd = NodeDeformation::new(&s, n);
        for t in 0..20 {
            let eta: Vec<f64> = (0..n).map(|m| ((t * 3 + m) as f64).sin() * 1e-3).collect();
            let (a, b) = (nd.max_displacement(&eta), direct(&eta));
            assert!((a - b).abs() <= 1e-15 * b, "{a} {b}");
            for limit in [0.5 * b, 0.999_999 * b, 1.000_001 * b, 2.0 * b, 1e3 * b] {
                assert_eq!(nd.exceeds(&eta, limit), b > limit, "{limit} {b}");
            }
        }
        assert_eq!(NodeDeformation::new(&[], 0).max_displacement(&[]), 0.0);
    }
}
