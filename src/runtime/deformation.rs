//! The largest elastic displacement over the structure's nodes, `max_i |S_trans,i η|`, for
//! the `max_deformation` stop condition and output channel (outside the right-hand side).
//!
//! `S_trans,i` is the 3 x n block of translation rows of node `i` of the mode shapes `S`
//! (thesis eq. 3.1.1: `u_i = S_i η`). Two things make it cheap on every accepted step and
//! every output row:
//! - each node's block is bounded by Cauchy-Schwarz on each of its rows,
//!   `|S_i η| ≤ ‖S_i‖_F ‖η‖`, and the nodes are stored in order of decreasing `‖S_i‖_F`, so
//!   the maximum is found by evaluating nodes in that order until the next bound falls below
//!   the largest displacement found (every later node's bound is smaller still): on SPHADS-1
//!   the fin tips come first and the body nodes are never evaluated. Each evaluated node
//!   computes `S_i η` in the same order of operations as the plain loop (modes in order), so
//!   the maximum has the same bits;
//! - the stop check first compares the largest bound `max_i ‖S_i‖_F ‖η‖` with the limit and
//!   evaluates the exact maximum only when the bound reaches it.

/// The node translation shapes of a plan, rearranged for [`Self::max_displacement`].
#[derive(Debug, Clone)]
pub struct NodeDeformation {
    n: usize,
    /// The node blocks `S_i` (row-major 3 x n) in order of decreasing `‖S_i‖_F`.
    blocks: Vec<f64>,
    /// `‖S_i‖_F` in the same order (decreasing).
    bounds: Vec<f64>,
}

/// The relative margin on the Cauchy-Schwarz bounds for the rounding of `‖S_i‖_F ‖η‖`
/// (a few ulps of `n`-term sums; 1e-9 is far above them).
const BOUND_MARGIN: f64 = 1e-9;

impl NodeDeformation {
    /// From the row-major node blocks of [`crate::plan::Plan::node_translation_shapes`]:
    /// node `i`, axis `d`, mode `m` at `(3 i + d) n + m`.
    pub fn new(node_translation_shapes: &[f64], n: usize) -> Self {
        if n == 0 {
            return Self {
                n,
                blocks: Vec::new(),
                bounds: Vec::new(),
            };
        }
        let nodes: Vec<&[f64]> = node_translation_shapes.chunks_exact(3 * n).collect();
        let norms: Vec<f64> = nodes
            .iter()
            .map(|b| b.iter().map(|s| s * s).sum::<f64>().sqrt())
            .collect();
        let mut order: Vec<usize> = (0..nodes.len()).collect();
        // Stable: equal norms keep the node order, so the layout is deterministic.
        order.sort_by(|&a, &b| norms[b].total_cmp(&norms[a]));
        Self {
            n,
            blocks: order
                .iter()
                .flat_map(|&i| nodes[i].iter().copied())
                .collect(),
            bounds: order.iter().map(|&i| norms[i]).collect(),
        }
    }

    /// `max_i |S_trans,i η|`, m (0 without modes or nodes).
    pub fn max_displacement(&self, eta: &[f64]) -> f64 {
        let n = self.n;
        if n == 0 || self.bounds.is_empty() {
            return 0.0;
        }
        let eta = &eta[..n];
        let norm = eta.iter().map(|e| e * e).sum::<f64>().sqrt();
        let mut best = 0.0_f64;
        for (block, bound) in self.blocks.chunks_exact(3 * n).zip(&self.bounds) {
            if bound * norm * (1.0 + BOUND_MARGIN) < best {
                break;
            }
            let mut u = [0.0_f64; 3];
            for (d, ud) in u.iter_mut().enumerate() {
                for (s, e) in block[d * n..(d + 1) * n].iter().zip(eta) {
                    *ud += e * s;
                }
            }
            best = best.max((u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt());
        }
        best
    }

    /// `max_i |S_trans,i η| > limit`; the exact maximum only when the bound reaches the
    /// limit.
    pub fn exceeds(&self, eta: &[f64], limit: f64) -> bool {
        let Some(&largest) = self.bounds.first() else {
            return false;
        };
        let norm = eta.iter().take(self.n).map(|e| e * e).sum::<f64>().sqrt();
        if largest * norm * (1.0 + BOUND_MARGIN) <= limit {
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
        let nd = NodeDeformation::new(&s, n);
        for t in 0..20 {
            let eta: Vec<f64> = (0..n).map(|m| ((t * 3 + m) as f64).sin() * 1e-3).collect();
            let (a, b) = (nd.max_displacement(&eta), direct(&eta));
            assert_eq!(a.to_bits(), b.to_bits(), "{a} {b}");
            for limit in [0.5 * b, 0.999_999 * b, 1.000_001 * b, 2.0 * b, 1e3 * b] {
                assert_eq!(nd.exceeds(&eta, limit), b > limit, "{limit} {b}");
            }
        }
        assert_eq!(NodeDeformation::new(&[], 0).max_displacement(&[]), 0.0);
    }
}
