//! The Monte Carlo random stream: every draw is a pure function of `(seed, sample, slot)`,
//! so a sample's inputs do not depend on which thread, job or shard runs it, nor on how
//! many samples ran before it.
//!
//! ## Uniforms
//!
//! The generator is a counter-based hash built from the SplitMix64 output function (Steele,
//! Lea & Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014; the
//! constants are those of `java.util.SplittableRandom` and of Vigna's `splitmix64.c`):
//!
//! ```text
//! mix(z)     = z += 0x9E3779B97F4A7C15;
//!              z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9;
//!              z = (z ^ (z >> 27)) * 0x94D049BB133111EB;
//!              z ^ (z >> 31)                       (wrapping 64-bit arithmetic)
//! bits(s,i,j) = mix(mix(mix(s) ^ i) ^ j)
//! u(s,i,j)    = ((bits >> 11) + 0.5) / 2^53        in (0, 1), never 0 or 1
//! ```
//!
//! `s` is the dispersion's `seed`, `i` the sample index, `j` the slot (the entry's position
//! in the `vary` block). **Stability promise:** the uniforms are integer arithmetic and one
//! exact conversion, so they are the same bits on every machine and in every version of
//! flexflight that keeps this formula (a change would be a breaking change, said in the
//! changelog). The transformations to each distribution below use `ln`, `exp` and `sqrt`
//! of the platform's libm, so a drawn value is the same bits on one platform and build, and
//! agrees to about 1e-15 relative elsewhere.
//!
//! ## Normals
//!
//! `z = Φ⁻¹(u)` by Acklam's rational approximation (P. J. Acklam, "An algorithm for computing
//! the inverse normal cumulative distribution function", 2003; relative error below
//! 1.15e-9) refined by one Halley step on `Φ(z) - u` (the refinement Acklam's note gives),
//! with `Φ` from [`normal_cdf`]. The inverse CDF is used rather than Box-Muller so that one
//! uniform gives one normal and a truncated normal is a rescaled uniform.

/// The SplitMix64 output function (module doc).
pub fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The uniform in (0, 1) of `(seed, sample, slot)` (module doc).
pub fn uniform(seed: u64, sample: u64, slot: u64) -> f64 {
    let bits = mix(mix(mix(seed) ^ sample) ^ slot);
    ((bits >> 11) as f64 + 0.5) * (1.0 / 9_007_199_254_740_992.0)
}

/// The standard normal density.
pub fn normal_pdf(x: f64) -> f64 {
    (-0.5 * x * x).exp() / (2.0 * std::f64::consts::PI).sqrt()
}

/// The standard normal CDF `Φ(x)`, by Hart's double-precision algorithm 5666 (J. F. Hart et
/// al., "Computer Approximations", Wiley 1968) as written by G. West, "Better approximations
/// to cumulative normal functions", Wilmott Magazine, 2005 (West states about 1e-15; against
/// an independent `erfc` it is within 2.2e-16 absolute on [-8, 8]; the lower tail computed
/// directly, so small probabilities keep their relative accuracy).
/// `Φ(0) = 1/2` exactly (the constant terms' ratio); the tests check `Φ' = φ` and
/// `Φ(Φ⁻¹(p)) = p`.
pub fn normal_cdf(x: f64) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    let a = x.abs();
    let tail = if a > 37.0 {
        0.0
    } else {
        let e = (-0.5 * a * a).exp();
        if a < 7.071_067_811_865_47 {
            let mut n = 3.526_249_659_989_11e-2 * a + 0.700_383_064_443_688;
            n = n * a + 6.373_962_203_531_65;
            n = n * a + 33.912_866_078_383;
            n = n * a + 112.079_291_497_871;
            n = n * a + 221.213_596_169_931;
            n = n * a + 220.206_867_912_376;
            let mut d = 8.838_834_764_831_84e-2 * a + 1.755_667_163_182_64;
            d = d * a + 16.064_177_579_207;
            d = d * a + 86.780_732_202_946_1;
            d = d * a + 296.564_248_779_674;
            d = d * a + 637.333_633_378_831;
            d = d * a + 793.826_512_519_948;
            d = d * a + 440.413_735_824_752;
            e * n / d
        } else {
            let mut b = a + 0.65;
            b = a + 4.0 / b;
            b = a + 3.0 / b;
            b = a + 2.0 / b;
            b = a + 1.0 / b;
            e / b / 2.506_628_274_631
        }
    };
    if x > 0.0 { 1.0 - tail } else { tail }
}

/// The standard normal quantile `Φ⁻¹(p)` for `p` in (0, 1) (module doc); ±infinity at 0 and
/// 1, NaN outside.
pub fn normal_quantile(p: f64) -> f64 {
    if !(0.0..=1.0).contains(&p) || p.is_nan() {
        return f64::NAN;
    }
    if p == 0.0 {
        return f64::NEG_INFINITY;
    }
    if p == 1.0 {
        return f64::INFINITY;
    }
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    const P_LOW: f64 = 0.02425;
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let x = if p < P_LOW {
        tail((-2.0 * p.ln()).sqrt())
    } else if p <= 1.0 - P_LOW {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    };
    // One Halley step on e = Φ(x) - p (Acklam's refinement). In the upper tail e is formed
    // as (1 - p) - Φ(-x), the same number, from the lower tail, which keeps its accuracy.
    let e = if x > 0.0 {
        (1.0 - p) - normal_cdf(-x)
    } else {
        normal_cdf(x) - p
    };
    let u = e * (2.0 * std::f64::consts::PI).sqrt() * (0.5 * x * x).exp();
    x - u / (1.0 + 0.5 * x * u)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `Φ(0) = 1/2`, symmetry `Φ(-x) = 1 - Φ(x)`, and the derivative of `Φ` is the density
    /// (central differences, h = 1e-4: the truncation `h² Φ''' / 6` with `Φ''' = φ'' =
    /// (x² - 1) φ`, plus 10 %, and 2e-12 for rounding). An earlier version of this bound took
    /// `φ'''` for `Φ'''` and so failed at x = 0, where the truncation is `-h² φ(0) / 6`,
    /// 1.7e-9 relative: the difference quotient's own error, not Φ's.
    #[test]
    fn the_cdf_is_the_integral_of_the_density() {
        assert_eq!(normal_cdf(0.0), 0.5);
        for k in -80..=80 {
            let x = k as f64 * 0.1;
            assert!(
                (normal_cdf(-x) - (1.0 - normal_cdf(x))).abs() < 2e-16,
                "x = {x}"
            );
            let h = 1e-4;
            let d = (normal_cdf(x + h) - normal_cdf(x - h)) / (2.0 * h);
            assert!(
                (d - normal_pdf(x)).abs()
                    < 1.1 * h * h / 6.0 * ((x * x - 1.0) * normal_pdf(x)).abs() + 2e-12,
                "x = {x}: {d} vs {}",
                normal_pdf(x)
            );
        }
    }

    /// The quantile inverts the CDF, in the body and far in the tails.
    #[test]
    fn the_quantile_inverts_the_cdf() {
        for k in -80..=80 {
            let x = k as f64 * 0.1;
            let p = normal_cdf(x);
            let back = normal_quantile(p);
            // Above the median p = Φ(x) is stored to 1.1e-16 absolute, which moves the
            // quantile by 1.1e-16 / φ(x): the round trip cannot do better than that.
            let tol = 1e-12
                + if x > 0.0 {
                    4.5e-16 / normal_pdf(x)
                } else {
                    0.0
                };
            assert!((back - x).abs() < tol, "x = {x}: {back}");
        }
        assert_eq!(normal_quantile(0.5), 0.0);
        assert!(normal_quantile(0.0).is_infinite() && normal_quantile(1.0).is_infinite());
        assert!(normal_quantile(1.5).is_nan());
    }

    /// The uniforms are in (0, 1), pure functions of their key, and their first two moments
    /// over 100 000 draws are those of U(0, 1) within 5 standard errors.
    #[test]
    fn uniforms_are_keyed_and_uniform() {
        assert_eq!(uniform(7, 3, 1), uniform(7, 3, 1));
        assert_ne!(uniform(7, 3, 1), uniform(7, 3, 2));
        assert_ne!(uniform(7, 3, 1), uniform(8, 3, 1));
        let n = 100_000;
        let (mut s, mut s2) = (0.0, 0.0);
        for i in 0..n {
            let u = uniform(1, i, 0);
            assert!(u > 0.0 && u < 1.0);
            s += u;
            s2 += u * u;
        }
        let mean = s / n as f64;
        let var = s2 / n as f64 - mean * mean;
        // sd of the mean: sqrt(1/12 / n) = 9.1e-4; of the variance: sqrt(1/180 / n) = 2.4e-4.
        assert!((mean - 0.5).abs() < 5.0 * 9.2e-4, "{mean}");
        assert!((var - 1.0 / 12.0).abs() < 5.0 * 2.4e-4, "{var}");
        // The stream is pinned: these bits are the promise of the module doc.
        assert_eq!(mix(0), 0xE220_A839_7B1D_CDAF);
    }
}
