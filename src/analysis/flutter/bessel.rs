//! Bessel functions of the first and second kind of orders 0 and 1 for real `x > 0`, the
//! ingredients of Theodorsen's function ([`super::theodorsen`]). Implemented here (no crate of
//! the dependency set provides them).
//!
//! # Method
//!
//! - `0 < x <= 25`: `J_n` by Miller's backward recurrence (Abramowitz & Stegun, *Handbook of
//!   Mathematical Functions*, 1964, 9.12 and the recurrence 9.1.27
//!   `J_{n-1}(x) = (2n/x) J_n(x) - J_{n+1}(x)`), normalised by the Neumann identity
//!   `1 = J_0(x) + 2 Σ_{k>=1} J_{2k}(x)` (A&S 9.1.46). The recurrence is stable downwards, so
//!   every `J_n` comes out with an absolute error of a few ulps. `Y_0` from its Neumann series
//!   (A&S 9.1.88)
//!
//!   `Y_0(x) = (2/π) (ln(x/2) + γ) J_0(x) - (4/π) Σ_{k>=1} (-1)^k J_{2k}(x) / k`,
//!
//!   and `Y_1 = -Y_0'` (A&S 9.1.28) from its term-by-term derivative, derived here with
//!   `J_0' = -J_1` and `J_{2k}' = (J_{2k-1} - J_{2k+1}) / 2` (A&S 9.1.27):
//!
//!   `Y_1(x) = -(2/(π x)) J_0(x) + (2/π) (ln(x/2) + γ) J_1(x)
//!             + (2/π) Σ_{k>=1} (-1)^k (J_{2k-1}(x) - J_{2k+1}(x)) / k`.
//!
//! - `x > 25`: Hankel's asymptotic expansions (A&S 9.2.5, 9.2.6 with 9.2.9, 9.2.10), summed
//!   until the terms stop decreasing; at `x = 25` the smallest term is below `1e-20`.
//!
//! Tested against tabulated values (A&S Table 9.1), the Wronskian
//! `J_1 Y_0 - J_0 Y_1 = 2/(π x)` (A&S 9.1.16) and continuity across `x = 25`.

use std::f64::consts::PI;

/// Euler's constant γ.
const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;

/// Where the asymptotic expansion takes over from Miller's recurrence.
const ASYMPTOTIC_FROM: f64 = 25.0;

/// `(J_0, J_1, Y_0, Y_1)` at `x > 0`. Returns NaNs for `x <= 0` or a non-finite `x`.
pub fn j0_j1_y0_y1(x: f64) -> (f64, f64, f64, f64) {
    if !(x.is_finite() && x > 0.0) {
        return (f64::NAN, f64::NAN, f64::NAN, f64::NAN);
    }
    if x > ASYMPTOTIC_FROM {
        let (j0, y0) = hankel_asymptotic(0.0, x);
        let (j1, y1) = hankel_asymptotic(1.0, x);
        return (j0, j1, y0, y1);
    }
    // Miller: start well above x (the J_n decay like (e x / 2n)^n beyond n ~ x).
    let start = {
        let n = (x + 30.0 + 6.0 * x.sqrt()).ceil() as usize;
        n + (n % 2) // even
    };
    let mut j = vec![0.0_f64; start + 2];
    j[start] = 1e-300_f64.sqrt(); // 1e-150: room to grow
    for n in (1..=start).rev() {
        j[n - 1] = 2.0 * n as f64 / x * j[n] - j[n + 1];
        if j[n - 1].abs() > 1e250 {
            // Rescale everything computed so far.
            for v in j[n - 1..].iter_mut() {
                *v *= 1e-250;
            }
        }
    }
    let mut norm = j[0];
    let mut k = 2;
    while k <= start {
        norm += 2.0 * j[k];
        k += 2;
    }
    for v in j.iter_mut() {
        *v /= norm;
    }
    let log_term = (x / 2.0).ln() + EULER_GAMMA;
    let (mut s0, mut s1) = (0.0, 0.0);
    let mut k = 1;
    while 2 * k < start {
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        s0 += sign * j[2 * k] / k as f64;
        s1 += sign * (j[2 * k - 1] - j[2 * k + 1]) / k as f64;
        k += 1;
    }
    let y0 = 2.0 / PI * log_term * j[0] - 4.0 / PI * s0;
    let y1 = -2.0 / (PI * x) * j[0] + 2.0 / PI * log_term * j[1] + 2.0 / PI * s1;
    (j[0], j[1], y0, y1)
}

/// Hankel's expansion of `(J_ν, Y_ν)` for large `x` (A&S 9.2.5-9.2.10): with `μ = 4ν²`,
/// `a_k = (μ - 1)(μ - 9)...(μ - (2k-1)²) / (k! (8x)^k)`, `P = Σ_j (-1)^j a_{2j}`,
/// `Q = Σ_j (-1)^j a_{2j+1}`, `χ = x - (ν/2 + 1/4) π`:
/// `J_ν = sqrt(2/(π x)) (P cos χ - Q sin χ)`, `Y_ν = sqrt(2/(π x)) (P sin χ + Q cos χ)`.
fn hankel_asymptotic(nu: f64, x: f64) -> (f64, f64) {
    let mu = 4.0 * nu * nu;
    let (mut p, mut q) = (1.0, 0.0);
    let mut term = 1.0_f64;
    let mut last = f64::INFINITY;
    for k in 1..200 {
        let odd = (2 * k - 1) as f64;
        term *= (mu - odd * odd) / (k as f64 * 8.0 * x);
        if term.abs() >= last || term == 0.0 {
            break;
        }
        last = term.abs();
        // k = 1: +Q, 2: -P, 3: -Q, 4: +P, 5: +Q, ...
        match k % 4 {
            1 => q += term,
            2 => p -= term,
            3 => q -= term,
            _ => p += term,
        }
        if term.abs() < 1e-18 {
            break;
        }
    }
    let chi = x - (0.5 * nu + 0.25) * PI;
    let (s, c) = chi.sin_cos();
    let f = (2.0 / (PI * x)).sqrt();
    (f * (p * c - q * s), f * (p * s + q * c))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A&S Table 9.1 (and 9.2 for x = 10), 10 significant digits or more.
    #[test]
    fn matches_tabulated_values() {
        let cases = [
            // x, J0, J1, Y0, Y1
            (
                1.0,
                0.765_197_686_557_966_6,
                0.440_050_585_744_933_5,
                0.088_256_964_215_676_96,
                -0.781_212_821_300_288_7,
            ),
            (
                5.0,
                -0.177_596_771_314_338_3,
                -0.327_579_137_591_465_2,
                -0.308_517_625_249_033_8,
                0.147_863_143_391_226_8,
            ),
            (
                10.0,
                -0.245_935_764_451_348_3,
                0.043_472_746_168_861_44,
                0.055_671_167_283_599_39,
                0.249_015_424_206_953_9,
            ),
            (
                0.1,
                0.997_501_562_066_040,
                0.049_937_526_036_242,
                -1.534_238_651_350_367,
                -6.458_951_094_702_027,
            ),
        ];
        for (x, j0, j1, y0, y1) in cases {
            let (a, b, c, d) = j0_j1_y0_y1(x);
            for (got, want) in [(a, j0), (b, j1), (c, y0), (d, y1)] {
                assert!(
                    (got - want).abs() < 2e-14 * want.abs().max(1.0),
                    "x = {x}: {got} vs {want}"
                );
            }
        }
    }

    /// The Wronskian `J_1 Y_0 - J_0 Y_1 = 2/(π x)` (A&S 9.1.16) over 1e-3 .. 60.
    #[test]
    fn wronskian_holds() {
        let mut x = 1e-3_f64;
        let mut worst = 0.0_f64;
        while x < 60.0 {
            let (j0, j1, y0, y1) = j0_j1_y0_y1(x);
            let w = (j1 * y0 - j0 * y1) * PI * x / 2.0;
            worst = worst.max((w - 1.0).abs());
            x *= 1.07;
        }
        assert!(worst < 1e-12, "worst Wronskian error {worst:e}");
    }

    /// The two methods agree at the switch point.
    #[test]
    fn continuous_at_the_switch() {
        let x = ASYMPTOTIC_FROM;
        let (a, b, c, d) = j0_j1_y0_y1(x);
        let (j0, y0) = hankel_asymptotic(0.0, x);
        let (j1, y1) = hankel_asymptotic(1.0, x);
        for (u, v) in [(a, j0), (b, j1), (c, y0), (d, y1)] {
            assert!((u - v).abs() < 1e-14, "{u} vs {v}");
        }
    }

    #[test]
    fn bad_argument_is_nan() {
        assert!(j0_j1_y0_y1(0.0).0.is_nan());
        assert!(j0_j1_y0_y1(-1.0).2.is_nan());
        assert!(j0_j1_y0_y1(f64::NAN).3.is_nan());
    }
}
