//! The flight's flutter boundary of a fin whose thickness lies between compiled thicknesses
//! (issue 35: a fin-thickness dispersion without one cold boundary per sample).
//!
//! ## What is interpolated, and why in `ln t`
//!
//! Every cell of a [`Boundary`] is a flutter speed `V_F(M, h; t)` of the same clamped fin, the
//! same grid and the same p-k settings; only the plate thickness `t` differs. The shell
//! element is exactly `t K1 + t^3 K3` and `t M1 + t^3 M3`, the isotropic one and an
//! orthotropic fin's lamina element alike (`D_m = Q̄ t`, `D_b = Q̄ t^3/12`, transverse shear
//! and drilling `∝ G12 t`: test `the_element_is_t_k1_plus_t_cubed_k3` takes both), so for a plate in bending the frequencies go as
//! `t` and the generalised stiffness as `t^3`; the classical flutter-speed parameter of
//! NACA TN 4197 (Martin 1958) gives `V_F ∝ (t/c)^{3/2}` at fixed planform and air. A power
//! law is a straight line in `(ln t, ln V_F)`, so the node values are interpolated linearly
//! in `ln t`:
//!
//! `ln V_F(t) = (1 - s) ln V_F(t_k) + s ln V_F(t_{k+1})`, `s = ln(t/t_k) / ln(t_{k+1}/t_k)`,
//!
//! which reproduces any power law `V_F = C t^p` exactly; what it misses is the curvature of
//! `ln V_F` in `ln t` (membrane terms, the aerodynamic coupling), an error
//! `|d² ln V_F / d(ln t)²| h² / 8` for nodes `h` apart in `ln t`. Measured on the K1000T
//! (`tools/boundary_thickness_interp.py`, docs/performance.md): with `h = 0.072-0.078` the
//! largest relative error over the grid's valid cells is 3.1e-5, below the quadratic's
//! 5.0e-5, i.e. at the boundary solve's own resolution rather than at the truncation.
//!
//! The clamped modes' frequencies `ω_i ∝ t` in bending are interpolated in the same way. The
//! flags of a cell (`lower_bound`, `upper_bound`) are the OR of the two nodes' flags; a Mach
//! node's sweep range spans both nodes' (its lowest speed is the lattice's resolution limit,
//! which moves with the fin's frequencies) and a cell's sweep counts as started above its
//! range when either node's did; so an interpolated cell is never reported as more certain
//! than either node it comes from. A thickness outside the nodes is
//! refused, never extrapolated.

use super::margin::{Boundary, BoundaryFin};

/// Why a boundary could not be interpolated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ThicknessInterpError {
    #[error("thickness {t} m lies outside the nodes {lo} m to {hi} m (never extrapolated)")]
    Outside { t: f64, lo: f64, hi: f64 },
    #[error("the node boundaries at {lo} m and {hi} m do not share their grid")]
    Grid { lo: f64, hi: f64 },
    #[error("node thicknesses must be positive and increasing: {lo} m, {hi} m")]
    Nodes { lo: f64, hi: f64 },
}

/// The boundary and fin data at thickness `t` (m) from those at the node thicknesses
/// `t_lo < t_hi` (module doc). At `t == t_lo` (`t_hi`) the node's own values, bit for bit.
pub fn interpolate(
    lo: (&Boundary, &BoundaryFin, f64),
    hi: (&Boundary, &BoundaryFin, f64),
    t: f64,
) -> Result<(Boundary, BoundaryFin), ThicknessInterpError> {
    let ((bl, fl, tl), (bh, fh, th)) = (lo, hi);
    if !(tl > 0.0 && th > tl) {
        return Err(ThicknessInterpError::Nodes { lo: tl, hi: th });
    }
    if !(t >= tl && t <= th) {
        return Err(ThicknessInterpError::Outside { t, lo: tl, hi: th });
    }
    let same = |a: &[f64], b: &[f64]| {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
    };
    let n = bl.speeds.len();
    if !same(&bl.machs, &bh.machs)
        || !same(&bl.altitudes, &bh.altitudes)
        || !same(&bl.densities, &bh.densities)
        || bl.speed_ranges.len() != bh.speed_ranges.len()
        || bl.speed_ranges.len() != bl.machs.len()
        || bl.uncertainty.len() != bl.machs.len()
        || bh.uncertainty.len() != bl.machs.len()
        || [
            bh.speeds.len(),
            bl.lower_bound.len(),
            bh.lower_bound.len(),
            bl.upper_bound.len(),
            bh.upper_bound.len(),
            bl.node_lowest_speeds.len(),
            bh.node_lowest_speeds.len(),
        ]
        .iter()
        .any(|&m| m != n)
        || fl.omega.len() != fh.omega.len()
    {
        return Err(ThicknessInterpError::Grid { lo: tl, hi: th });
    }
    let s = (t / tl).ln() / (th / tl).ln();
    let mix = |a: f64, b: f64| {
        if t == tl {
            a
        } else if t == th {
            b
        } else {
            ((1.0 - s) * a.ln() + s * b.ln()).exp()
        }
    };
    // A Mach node's sweep range: the lowest speed the lattice resolves depends on the fin's
    // frequencies (`margin::solve_boundary`), so it differs between thicknesses; the
    // interpolated range spans both, and a cell's sweep counts as raised (started above its
    // range) when either node's did.
    let ranges: Vec<[f64; 2]> = bl
        .speed_ranges
        .iter()
        .zip(&bh.speed_ranges)
        .map(|(a, b)| [a[0].min(b[0]), a[1].max(b[1])])
        .collect();
    let na = bl.altitudes.len();
    let node_lowest: Vec<f64> = (0..n)
        .map(|k| {
            let i = k / na.max(1);
            if bl.raised_start(i, k % na) || bh.raised_start(i, k % na) {
                bl.node_lowest_speeds[k].max(bh.node_lowest_speeds[k])
            } else {
                ranges[i][0]
            }
        })
        .collect();
    let or =
        |a: &[bool], b: &[bool]| -> Vec<bool> { a.iter().zip(b).map(|(x, y)| *x || *y).collect() };
    let boundary = Boundary {
        machs: bl.machs.clone(),
        altitudes: bl.altitudes.clone(),
        densities: bl.densities.clone(),
        speeds: bl
            .speeds
            .iter()
            .zip(&bh.speeds)
            .map(|(&a, &b)| mix(a, b))
            .collect(),
        lower_bound: or(&bl.lower_bound, &bh.lower_bound),
        upper_bound: or(&bl.upper_bound, &bh.upper_bound),
        largest_speed: ranges.iter().map(|r| r[1]).fold(0.0, f64::max),
        speed_ranges: ranges,
        node_lowest_speeds: node_lowest,
        // A transonic node's stated uncertainty (issue 33): the larger of the two
        // thicknesses', as the bound flags take either's.
        uncertainty: bl
            .uncertainty
            .iter()
            .zip(&bh.uncertainty)
            .map(|(a, b)| a.max(*b))
            .collect(),
    };
    let fin = BoundaryFin {
        mode_names: fl.mode_names.clone(),
        omega: fl
            .omega
            .iter()
            .zip(&fh.omega)
            .map(|(&a, &b)| mix(a, b))
            .collect(),
        thickness: t,
        ..fl.clone()
    };
    Ok((boundary, fin))
}

/// Largest spacing of neighbouring nodes in `ln t`: the measured 3.1e-5 (module doc) came
/// from nodes `ln(2.0/1.85) = 0.0780` and `ln(2.15/2.0) = 0.0723` apart, so no interval
/// wider than the wider measured one.
pub const MAX_LOG_SPACING: f64 = 0.078;

/// The node thicknesses covering `[t_min, t_max]` (m): `n = ceil(ln(t_max/t_min) / 0.078)`
/// intervals of equal length in `ln t`, `t_k = t_min (t_max/t_min)^(k/n)`, the last node
/// `t_max` itself. One node when `t_min == t_max`; empty for a range that is not positive and
/// finite.
pub fn nodes(t_min: f64, t_max: f64) -> Vec<f64> {
    if !(t_min > 0.0 && t_max >= t_min && t_max.is_finite()) {
        return Vec::new();
    }
    if t_max == t_min {
        return vec![t_min];
    }
    let span = (t_max / t_min).ln();
    let n = ((span / MAX_LOG_SPACING).ceil() as usize).max(1);
    (0..=n)
        .map(|k| {
            if k == n {
                t_max
            } else {
                t_min * (span * k as f64 / n as f64).exp()
            }
        })
        .collect()
}

/// The index `k` of the interval `[nodes[k], nodes[k + 1]]` holding `t`, if any.
pub fn bracket(nodes: &[f64], t: f64) -> Option<usize> {
    (0..nodes.len().saturating_sub(1)).find(|&k| t >= nodes[k] && t <= nodes[k + 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn boundary(scale: f64) -> (Boundary, BoundaryFin) {
        let b = Boundary {
            machs: vec![0.0, 0.5],
            altitudes: vec![0.0, 1000.0],
            densities: vec![1.225, 1.112],
            speeds: vec![100.0 * scale, 110.0 * scale, 120.0 * scale, 130.0 * scale],
            lower_bound: vec![false, true, false, false],
            upper_bound: vec![false, false, false, true],
            speed_ranges: vec![[10.0, 500.0], [10.0, 500.0]],
            node_lowest_speeds: vec![10.0, 10.0, 20.0, 10.0],
            largest_speed: 500.0,
            uncertainty: vec![0.0, 0.1 * scale],
        };
        let f = BoundaryFin {
            mode_names: vec!["a".into()],
            omega: vec![50.0 * scale],
            shear_modulus: 26e9,
            span: 0.1,
            root_chord: 0.2,
            tip_chord: 0.1,
            thickness: 0.0,
            tip_le_offset: 0.05,
        };
        (b, f)
    }

    /// A power law `V_F = C t^p` is reproduced to round-off between any two nodes; the nodes
    /// themselves bit for bit; flags OR'ed; outside the nodes refused.
    #[test]
    fn a_power_law_is_exact_and_nothing_is_extrapolated() {
        let p = 1.5;
        let (t0, t1): (f64, f64) = (1.85e-3, 2.0e-3);
        let (b0, f0) = boundary(t0.powf(p));
        let (b1, f1) = boundary(t1.powf(p));
        for t in [1.86e-3_f64, 1.9e-3, 1.95e-3, 1.99e-3] {
            let (b, f) = interpolate((&b0, &f0, t0), (&b1, &f1, t1), t).unwrap();
            let (want, _) = boundary(t.powf(p));
            for (x, y) in b.speeds.iter().zip(&want.speeds) {
                assert!((x / y - 1.0).abs() < 1e-14, "{x} {y}");
            }
            assert!((f.omega[0] / (50.0 * t.powf(p)) - 1.0).abs() < 1e-14);
            assert_eq!(f.thickness, t);
            assert_eq!(b.lower_bound, vec![false, true, false, false]);
        }
        // Ranges that differ (the lattice's lowest speed moves with t): spanned; the raised
        // start of node 2 of `lo` (20 > 10) kept, no other cell raised.
        let mut b1r = b1.clone();
        b1r.speed_ranges[0][0] = 12.0;
        b1r.node_lowest_speeds[0] = 12.0;
        b1r.node_lowest_speeds[1] = 12.0;
        let (b, _) = interpolate((&b0, &f0, t0), (&b1r, &f1, t1), 1.9e-3).unwrap();
        assert_eq!(b.speed_ranges[0], [10.0, 500.0]);
        let raised: Vec<bool> = (0..4).map(|k| b.raised_start(k / 2, k % 2)).collect();
        assert_eq!(raised, vec![false, false, true, false]);
        let (b, _) = interpolate((&b0, &f0, t0), (&b1, &f1, t1), t0).unwrap();
        assert_eq!(b.speeds, b0.speeds);
        let (b, _) = interpolate((&b0, &f0, t0), (&b1, &f1, t1), t1).unwrap();
        assert_eq!(b.speeds, b1.speeds);
        for t in [1.8e-3, 2.01e-3, f64::NAN] {
            assert!(matches!(
                interpolate((&b0, &f0, t0), (&b1, &f1, t1), t),
                Err(ThicknessInterpError::Outside { .. })
            ));
        }
        let mut other = b1.clone();
        other.machs[1] = 0.6;
        assert!(matches!(
            interpolate((&b0, &f0, t0), (&other, &f1, t1), 1.9e-3),
            Err(ThicknessInterpError::Grid { .. })
        ));
    }

    /// The nodes cover the range, start and end on it, and no two neighbours are more than
    /// [`MAX_LOG_SPACING`] apart in `ln t`; every thickness of the range has a bracket.
    #[test]
    fn the_nodes_cover_the_range_at_the_stated_spacing() {
        for (a, b) in [
            (1.85e-3, 2.15e-3),
            (1e-3, 1e-3),
            (0.5e-3, 4e-3),
            (2e-3, 2.0001e-3),
        ] {
            let n = nodes(a, b);
            assert_eq!((n[0], n[n.len() - 1]), (a, b));
            for w in n.windows(2) {
                assert!(w[1] > w[0] && (w[1] / w[0]).ln() <= MAX_LOG_SPACING * (1.0 + 1e-12));
            }
            for k in 0..=100 {
                let t = a + (b - a) * k as f64 / 100.0;
                assert!(n.len() == 1 || bracket(&n, t).is_some(), "{t}");
            }
        }
        assert_eq!(nodes(1.85e-3, 2.15e-3).len(), 3);
        assert!(nodes(0.0, 1.0).is_empty() && nodes(2.0, 1.0).is_empty());
    }
}
