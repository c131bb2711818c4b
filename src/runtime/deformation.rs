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
//!   the fin tips come first. The nodes are evaluated eight at a time with the vector unit
//!   (lanes over the rows), each row computing `S_i η` in the same order of operations as
//!   the plain loop (modes in order), so the maximum has the same bits;
//! - the stop check first compares the largest bound `max_i ‖S_i‖_F ‖η‖` with the limit and
//!   evaluates the exact maximum only when the bound reaches it.

/// Nodes evaluated together: 8 nodes are 24 rows, six AVX2 registers of accumulators.
const CHUNK: usize = 8;
const ROWS: usize = 3 * CHUNK;

/// The node translation shapes of a plan, rearranged for [`Self::max_displacement`].
#[derive(Debug, Clone)]
pub struct NodeDeformation {
    n: usize,
    /// The node blocks in order of decreasing `‖S_i‖_F`, in chunks of [`CHUNK`] nodes
    /// (the last padded with zero rows); inside a chunk mode-major: mode `m`, node `k`,
    /// axis `d` at `m ROWS + 3 k + d`, so one mode's 24 rows are one contiguous vector.
    chunks: Vec<f64>,
    /// `‖S_i‖_F` of each chunk's first node (the largest of the chunk; decreasing).
    chunk_bounds: Vec<f64>,
    arch: pulp::Arch,
}

/// The relative margin on the Cauchy-Schwarz bounds for the rounding of `‖S_i‖_F ‖η‖`
/// (a few ulps of `n`-term sums; 1e-9 is far above them).
const BOUND_MARGIN: f64 = 1e-9;

impl NodeDeformation {
    /// From the row-major node blocks of [`crate::plan::Plan::node_translation_shapes`]:
    /// node `i`, axis `d`, mode `m` at `(3 i + d) n + m`.
    pub fn new(node_translation_shapes: &[f64], n: usize) -> Self {
        let arch = pulp::Arch::new();
        if n == 0 {
            return Self {
                n,
                chunks: Vec::new(),
                chunk_bounds: Vec::new(),
                arch,
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
        let n_chunks = order.len().div_ceil(CHUNK);
        let mut chunks = vec![0.0; n_chunks * ROWS * n];
        for (j, &i) in order.iter().enumerate() {
            let (c, k) = (j / CHUNK, j % CHUNK);
            for d in 0..3 {
                for m in 0..n {
                    chunks[c * ROWS * n + m * ROWS + 3 * k + d] = nodes[i][d * n + m];
                }
            }
        }
        Self {
            n,
            chunks,
            chunk_bounds: order.iter().step_by(CHUNK).map(|&i| norms[i]).collect(),
            arch,
        }
    }

    /// `max_i |S_trans,i η|`, m (0 without modes or nodes).
    ///
    /// Compiled for the widest vector unit found at run time (pulp's dispatch): the lanes
    /// run over the rows of a chunk, and each row's sum is still taken over the modes in
    /// order from `0.0`, without fused multiply-adds, so the result has the bits of the
    /// plain node-by-node loop (tested). A chunk is skipped, with every later one, once
    /// the bound of its first node is below the largest displacement found.
    pub fn max_displacement(&self, eta: &[f64]) -> f64 {
        self.arch.dispatch(self.op(eta))
    }

    fn op<'a>(&'a self, eta: &'a [f64]) -> MaxOp<'a> {
        MaxOp {
            n: self.n,
            chunks: &self.chunks,
            chunk_bounds: &self.chunk_bounds,
            eta: &eta[..self.n.min(eta.len())],
        }
    }

    /// `max_i |S_trans,i η| > limit`; the exact maximum only when the bound reaches the
    /// limit.
    pub fn exceeds(&self, eta: &[f64], limit: f64) -> bool {
        let Some(&largest) = self.chunk_bounds.first() else {
            return false;
        };
        let norm = eta.iter().take(self.n).map(|e| e * e).sum::<f64>().sqrt();
        if largest * norm * (1.0 + BOUND_MARGIN) <= limit {
            return false;
        }
        self.max_displacement(eta) > limit
    }
}

/// [`NodeDeformation::max_displacement`] as a [`pulp::WithSimd`] operation.
struct MaxOp<'a> {
    n: usize,
    chunks: &'a [f64],
    chunk_bounds: &'a [f64],
    eta: &'a [f64],
}

impl pulp::WithSimd for MaxOp<'_> {
    type Output = f64;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> f64 {
        let MaxOp {
            n,
            chunks,
            chunk_bounds,
            eta,
        } = self;
        if n == 0 || chunk_bounds.is_empty() || eta.len() < n {
            return 0.0;
        }
        let norm = eta.iter().map(|e| e * e).sum::<f64>().sqrt();
        let mut best = 0.0_f64;
        for (chunk, bound) in chunks.chunks_exact(ROWS * n).zip(chunk_bounds) {
            if bound * norm * (1.0 + BOUND_MARGIN) < best {
                break;
            }
            let mut u = [0.0_f64; ROWS];
            for (col, e) in chunk.chunks_exact(ROWS).zip(eta) {
                for (ur, s) in u.iter_mut().zip(col) {
                    *ur += e * s;
                }
            }
            for k in 0..CHUNK {
                let (a, b, c) = (u[3 * k], u[3 * k + 1], u[3 * k + 2]);
                best = best.max((a * a + b * b + c * c).sqrt());
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rearranged maximum equals the direct one (node by node, row by row), and the
    /// bounded check agrees with the exact comparison on both sides of the limit.
    #[test]
    fn maximum_and_bounded_check_match_the_direct_evaluation() {
        for (nodes, n) in [
            (37, 4),
            (1, 1),
            (7, 3),
            (8, 10),
            (9, 10),
            (200, 10),
            (65, 7),
        ] {
            maximum_matches_direct(nodes, n);
        }
        assert_eq!(NodeDeformation::new(&[], 0).max_displacement(&[]), 0.0);
    }

    /// The vectorised maximum against the plain node-by-node loop, bit for bit, on the
    /// vector unit found here and on pulp's scalar fallback, with the chunk edges of
    /// [`CHUNK`] nodes crossed (1, 7, 8, 9, 65 nodes).
    fn maximum_matches_direct(nodes: usize, n: usize) {
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
            assert_eq!(
                a.to_bits(),
                b.to_bits(),
                "{nodes} nodes, {n} modes: {a} {b}"
            );
            let scalar = pulp::Simd::vectorize(pulp::Scalar, nd.op(&eta));
            assert_eq!(scalar.to_bits(), b.to_bits(), "scalar {scalar} {b}");
            for limit in [0.5 * b, 0.999_999 * b, 1.000_001 * b, 2.0 * b, 1e3 * b] {
                assert_eq!(nd.exceeds(&eta, limit), b > limit, "{limit} {b}");
            }
        }
    }
}
