//! Theodorsen's unsteady thin-airfoil theory: the function `C(k)` and the generalised
//! aerodynamic forces of the typical section in plunge and pitch.
//!
//! # Theodorsen's function (Theodorsen, "General theory of aerodynamic instability and the
//! mechanism of flutter", NACA Report 496, 1935; Hodges & Pierce, *Introduction to Structural
//! Dynamics and Aeroelasticity*, 2nd ed., 2011, §5.4)
//!
//! `C(k) = H_1^(2)(k) / (H_1^(2)(k) + i H_0^(2)(k))`, `H_n^(2) = J_n - i Y_n`,
//!
//! with the reduced frequency `k = ω b / U` (`b` the semichord). `C(0) = 1` (the steady
//! limit), `C(∞) = 1/2`. The Bessel functions are those of [`super::bessel`].
//!
//! # Airloads of the typical section (Theodorsen 1935; Hodges & Pierce §5.4, the lift and
//! pitching moment for plunge and pitch, flap omitted)
//!
//! Plunge `h` (positive down), pitch `θ` (nose up) about the elastic axis at `a b` aft of
//! mid-chord, airspeed `U`, density `ρ`. Lift (up) and moment about the elastic axis (nose up):
//!
//! `L = π ρ b² (ḧ + U θ̇ - b a θ̈) + 2 π ρ U b C(k) [ḣ + U θ + b (1/2 - a) θ̇]`,
//!
//! `M = π ρ b² [b a ḧ - U b (1/2 - a) θ̇ - b² (1/8 + a²) θ̈]
//!      + 2 π ρ U b² (a + 1/2) C(k) [ḣ + U θ + b (1/2 - a) θ̇]`.
//!
//! For harmonic motion `(h, θ) e^{iωt}` and with `q = ρU²/2`, `πρb²ω² = 2πq k²`,
//! `ρ U b ω = 2 q k` (derived), so with the coordinates `η = (h/b, θ)` and the virtual work
//! `δW = -L δh + M δθ` the generalised forces per unit span are `q b² Q(k) η` with
//!
//! `Q_11 = 2π k² - 4π i k C`,
//! `Q_12 = -[2π i k + 2π a k² + 4π C (1 + (1/2 - a) i k)]`,
//! `Q_21 = -2π a k² + 4π (a + 1/2) i k C`,
//! `Q_22 = -2π (1/2 - a) i k + 2π (1/8 + a²) k² + 4π (a + 1/2) C (1 + (1/2 - a) i k)`
//!
//! (derived here from `L` and `M`; the steady limit `Q_12 = -4π` is the lift `2π q (2b) θ`,
//! `Q_22 = 4π (a + 1/2)` its moment about the elastic axis).

use faer::c64;

use super::bessel::j0_j1_y0_y1;

/// Theodorsen's function `C(k)` for `k >= 0` (NaN for a negative or non-finite `k`).
pub fn theodorsen(k: f64) -> c64 {
    if k == 0.0 {
        return c64::new(1.0, 0.0);
    }
    if !(k.is_finite() && k > 0.0) {
        return c64::new(f64::NAN, f64::NAN);
    }
    let (j0, j1, y0, y1) = j0_j1_y0_y1(k);
    let h1 = c64::new(j1, -y1);
    let h0 = c64::new(j0, -y0);
    h1 / (h1 + c64::new(0.0, 1.0) * h0)
}

/// The typical-section generalised aerodynamic force matrix `Q(k)` (row-major 2 x 2) on
/// `η = (h/b, θ)`, elastic axis at `a` semichords aft of mid-chord: the generalised forces are
/// `q b² Q(k) η` per unit span (module doc).
pub fn section_gaf(a: f64, k: f64) -> [c64; 4] {
    let pi = std::f64::consts::PI;
    let c = theodorsen(k);
    let i = c64::new(0.0, 1.0);
    let k2 = k * k;
    let one = c64::new(1.0, 0.0);
    let lag = one + i * ((0.5 - a) * k);
    let q11 = c64::new(2.0 * pi * k2, 0.0) - i * (4.0 * pi * k) * c;
    let q12 = -(i * (2.0 * pi * k) + c64::new(2.0 * pi * a * k2, 0.0) + c * lag * (4.0 * pi));
    let q21 = c64::new(-2.0 * pi * a * k2, 0.0) + i * (4.0 * pi * (a + 0.5) * k) * c;
    let q22 = -(i * (2.0 * pi * (0.5 - a) * k))
        + c64::new(2.0 * pi * (0.125 + a * a) * k2, 0.0)
        + c * lag * (4.0 * pi * (a + 0.5));
    [q11, q12, q21, q22]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The standard four-digit table of `C(k) = F + iG` (as printed in Bisplinghoff, Ashley &
    /// Halfman, *Aeroelasticity*, 1955, ch. 5), and the limits `C(0) = 1`, `C(∞) = 1/2`.
    #[test]
    fn theodorsen_matches_table_and_limits() {
        for (k, f, g) in [
            (0.1, 0.8319, -0.1723),
            (0.2, 0.7276, -0.1886),
            (0.5, 0.5979, -0.1507),
            (1.0, 0.5394, -0.1003),
        ] {
            let c = theodorsen(k);
            assert!((c.re - f).abs() < 6e-5, "F({k}) = {}", c.re);
            assert!((c.im - g).abs() < 6e-5, "G({k}) = {}", c.im);
        }
        assert_eq!(theodorsen(0.0), c64::new(1.0, 0.0));
        let c = theodorsen(1e-6);
        assert!((c.re - 1.0).abs() < 1e-4 && c.im.abs() < 1e-4, "{c:?}");
        let c = theodorsen(200.0);
        assert!((c.re - 0.5).abs() < 1e-5 && c.im.abs() < 1e-3, "{c:?}");
        assert!(theodorsen(-1.0).re.is_nan());
    }

    /// The steady limit of the section forces is thin-airfoil theory: lift slope 2π on the chord
    /// `2b`, acting at the quarter chord.
    #[test]
    fn steady_section_forces_are_thin_airfoil_theory() {
        let pi = std::f64::consts::PI;
        let a = -0.2;
        let q = section_gaf(a, 0.0);
        assert!(q[0].norm() == 0.0 && q[2].norm() == 0.0);
        assert!((q[1].re + 4.0 * pi).abs() < 1e-14 && q[1].im == 0.0);
        assert!((q[3].re - 4.0 * pi * (a + 0.5)).abs() < 1e-14 && q[3].im == 0.0);
    }
}
