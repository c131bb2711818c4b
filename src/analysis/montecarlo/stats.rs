//! Statistics of a Monte Carlo table, each with its confidence interval and the method
//! named:
//!
//! - mean with the normal-theory interval `x̄ ± z s/√n` (central limit theorem; `s` the
//!   sample standard deviation with `n - 1`);
//! - percentiles by linear interpolation between order statistics (Hyndman & Fan, "Sample
//!   quantiles in statistical packages", Am. Stat. 50, 1996, definition 7, numpy's default),
//!   with the distribution-free interval between order statistics of ranks
//!   `nq ∓ z sqrt(n q (1 - q))` (rounded outward; W. J. Conover, "Practical Nonparametric
//!   Statistics", 3rd ed., 1999, §3.2, the normal approximation of the binomial);
//! - proportions (P(margin < 1.15), P(flutter)) with the Wilson score interval
//!   (E. B. Wilson, "Probable inference, the law of succession, and statistical inference",
//!   JASA 22, 1927; recommended over the Wald interval by Brown, Cai & DasGupta, Stat. Sci.
//!   16, 2001), which stays inside [0, 1] and is not empty at 0 or n successes;
//! - the landing ellipses from the sample covariance's eigen-decomposition: the `k`-sigma
//!   ellipse is `{x : (x - m)ᵀ C⁻¹ (x - m) ≤ k²}` (Mahalanobis radius `k`, semi-axes
//!   `k sqrt(λ)`), which holds `1 - exp(-k²/2)` of a bivariate normal (the chi-square
//!   distribution with 2 degrees of freedom: 39.3 %, 86.5 %, 98.9 % for k = 1, 2, 3; it is
//!   not the 68/95/99.7 % of one dimension). Each ellipse reports that expected share and
//!   the share of samples inside it;
//! - sensitivity: Spearman's rank correlation of each drawn input with the minimum flutter
//!   margin (ties take their average rank; C. Spearman, Am. J. Psychol. 15, 1904).
//!
//! `z = 1.959963984540054` (two-sided 95 %).

use serde::Serialize;

/// Two-sided 95 % standard normal quantile.
pub const Z95: f64 = 1.959_963_984_540_054;

/// The Wilson score interval of `k` successes in `n` trials at the normal quantile `z`.
pub fn wilson(k: usize, n: usize, z: f64) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let (nf, p) = (n as f64, k as f64 / n as f64);
    let z2 = z * z;
    let centre = (p + z2 / (2.0 * nf)) / (1.0 + z2 / nf);
    let half = z / (1.0 + z2 / nf) * (p * (1.0 - p) / nf + z2 / (4.0 * nf * nf)).sqrt();
    // At 0 or n successes the bound is exactly 0 or 1 (the rounding of centre - half
    // would leave a few 1e-18).
    let lo = if k == 0 {
        0.0
    } else {
        (centre - half).max(0.0)
    };
    let hi = if k == n {
        1.0
    } else {
        (centre + half).min(1.0)
    };
    (lo, hi)
}

/// Percentile `q` in [0, 1] of sorted `x` (Hyndman & Fan definition 7).
pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    let n = sorted.len();
    if n == 0 {
        return f64::NAN;
    }
    let h = (n - 1) as f64 * q;
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(n - 1);
    sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
}

/// The distribution-free 95 % interval of percentile `q` of sorted `x` (module doc).
pub fn percentile_interval(sorted: &[f64], q: f64) -> (f64, f64) {
    let n = sorted.len();
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    let nf = n as f64;
    let s = Z95 * (nf * q * (1.0 - q)).sqrt();
    // 1-based ranks, rounded outward, clamped to the sample.
    let j = ((nf * q - s).floor() as i64).clamp(1, n as i64) as usize;
    let k = ((nf * q + s).ceil() as i64 + 1).clamp(1, n as i64) as usize;
    (sorted[j - 1], sorted[k - 1])
}

/// One output's distribution.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Distribution {
    pub n: usize,
    pub mean: f64,
    pub mean_ci95: [f64; 2],
    pub std: f64,
    pub min: f64,
    pub max: f64,
    /// `(q, value, [lo, hi])` for q = 1, 5, 25, 50, 75, 95, 99 %.
    pub percentiles: Vec<Percentile>,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Percentile {
    pub q: f64,
    pub value: f64,
    pub ci95: [f64; 2],
}

/// The distribution of the finite values of `x` (`None` when there are fewer than 2).
pub fn distribution(x: &[f64]) -> Option<Distribution> {
    let mut v: Vec<f64> = x.iter().copied().filter(|x| x.is_finite()).collect();
    let n = v.len();
    if n < 2 {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let nf = n as f64;
    let mean = v.iter().sum::<f64>() / nf;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (nf - 1.0);
    let std = var.sqrt();
    let half = Z95 * std / nf.sqrt();
    Some(Distribution {
        n,
        mean,
        mean_ci95: [mean - half, mean + half],
        std,
        min: v[0],
        max: v[n - 1],
        percentiles: [0.01, 0.05, 0.25, 0.5, 0.75, 0.95, 0.99]
            .iter()
            .map(|&q| {
                let (lo, hi) = percentile_interval(&v, q);
                Percentile {
                    q,
                    value: percentile(&v, q),
                    ci95: [lo, hi],
                }
            })
            .collect(),
    })
}

/// A proportion with its Wilson interval.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Proportion {
    pub count: usize,
    pub of: usize,
    pub p: f64,
    pub ci95: [f64; 2],
    pub method: &'static str,
}

pub fn proportion(count: usize, of: usize) -> Proportion {
    let (lo, hi) = wilson(count, of, Z95);
    Proportion {
        count,
        of,
        p: if of == 0 {
            f64::NAN
        } else {
            count as f64 / of as f64
        },
        ci95: [lo, hi],
        method: "Wilson score interval, 95 %",
    }
}

/// A `k`-sigma ellipse of a 2-D sample.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Ellipse {
    pub k: f64,
    /// Semi-axes, m: along the major axis, then the minor one.
    pub semi_major: f64,
    pub semi_minor: f64,
    /// Angle of the major axis from the x axis towards the y axis, rad.
    pub angle: f64,
    /// The share of a bivariate normal inside: `1 - exp(-k²/2)`.
    pub expected_share: f64,
    /// The share of the samples inside.
    pub observed_share: f64,
}

/// The mean, covariance and 1/2/3-sigma ellipses of points `(x, y)` (module doc).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Ellipses {
    pub n: usize,
    pub mean: [f64; 2],
    /// `[[cxx, cxy], [cxy, cyy]]` with `n - 1`.
    pub covariance: [[f64; 2]; 2],
    pub ellipses: Vec<Ellipse>,
}

pub fn ellipses(points: &[(f64, f64)]) -> Option<Ellipses> {
    let p: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    let n = p.len();
    if n < 3 {
        return None;
    }
    let nf = n as f64;
    let mx = p.iter().map(|q| q.0).sum::<f64>() / nf;
    let my = p.iter().map(|q| q.1).sum::<f64>() / nf;
    let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
    for (x, y) in &p {
        a += (x - mx) * (x - mx);
        b += (x - mx) * (y - my);
        c += (y - my) * (y - my);
    }
    let (a, b, c) = (a / (nf - 1.0), b / (nf - 1.0), c / (nf - 1.0));
    // Eigenvalues of [[a, b], [b, c]]; the major axis at 0.5 atan2(2b, a - c).
    let mean_l = 0.5 * (a + c);
    let r = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let (l1, l2) = (mean_l + r, (mean_l - r).max(0.0));
    let angle = 0.5 * (2.0 * b).atan2(a - c);
    let det = a * c - b * b;
    let mahalanobis2 = |x: f64, y: f64| {
        let (dx, dy) = (x - mx, y - my);
        (c * dx * dx - 2.0 * b * dx * dy + a * dy * dy) / det
    };
    let ellipses = [1.0, 2.0, 3.0]
        .iter()
        .map(|&k| {
            let inside = if det > 0.0 {
                p.iter()
                    .filter(|(x, y)| mahalanobis2(*x, *y) <= k * k)
                    .count()
            } else {
                0
            };
            Ellipse {
                k,
                semi_major: k * l1.sqrt(),
                semi_minor: k * l2.sqrt(),
                angle,
                expected_share: 1.0 - (-0.5 * k * k).exp(),
                observed_share: inside as f64 / nf,
            }
        })
        .collect();
    Some(Ellipses {
        n,
        mean: [mx, my],
        covariance: [[a, b], [b, c]],
        ellipses,
    })
}

/// Ranks from 1, ties sharing their average rank.
pub fn ranks(x: &[f64]) -> Vec<f64> {
    let mut idx: Vec<usize> = (0..x.len()).collect();
    idx.sort_by(|&i, &j| x[i].total_cmp(&x[j]));
    let mut r = vec![0.0; x.len()];
    let mut i = 0;
    while i < idx.len() {
        let mut j = i;
        while j + 1 < idx.len() && x[idx[j + 1]] == x[idx[i]] {
            j += 1;
        }
        let avg = 0.5 * ((i + 1) + (j + 1)) as f64;
        for &k in &idx[i..=j] {
            r[k] = avg;
        }
        i = j + 1;
    }
    r
}

/// Pearson's correlation (NaN when either is constant).
pub fn pearson(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len()) as f64;
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    sxy / (sxx * syy).sqrt()
}

/// Spearman's rank correlation of the pairs whose both values are finite.
pub fn spearman(x: &[f64], y: &[f64]) -> Option<f64> {
    let (a, b): (Vec<f64>, Vec<f64>) = x
        .iter()
        .zip(y)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (*a, *b))
        .unzip();
    if a.len() < 3 {
        return None;
    }
    let r = pearson(&ranks(&a), &ranks(&b));
    r.is_finite().then_some(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wilson_matches_its_closed_form_at_the_edges() {
        // 0 of n: [0, z²/(n + z²)].
        let (lo, hi) = wilson(0, 100, Z95);
        assert_eq!(lo, 0.0);
        assert!((hi - Z95 * Z95 / (100.0 + Z95 * Z95)).abs() < 1e-15);
        let (lo, hi) = wilson(100, 100, Z95);
        assert!((lo - 100.0 / (100.0 + Z95 * Z95)).abs() < 1e-15 && hi == 1.0);
    }

    #[test]
    fn percentiles_interpolate_and_ranks_average_ties() {
        let v = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(percentile(&v, 0.5), 2.5);
        assert_eq!(percentile(&v, 0.0), 1.0);
        assert_eq!(percentile(&v, 1.0), 4.0);
        assert_eq!(ranks(&[3.0, 1.0, 3.0, 2.0]), vec![3.5, 1.0, 3.5, 2.0]);
        assert_eq!(
            spearman(&[1.0, 2.0, 3.0, 4.0], &[10.0, 20.0, 25.0, 100.0]),
            Some(1.0)
        );
    }
}
