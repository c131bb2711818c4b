//! Attitude kinematics: Euler parameters (thesis 4.4.2-4.4.3) and Euler angles (4.4.1).
//!
//! Convention (Hughes, as in the thesis): the Euler parameters are stored as
//! `q = (ε1, ε2, ε3, η)` with `ε = a sin(φ/2)`, `η = cos(φ/2)` (eqs. 4.4.6-4.4.7), and
//! `C(ε, η) = (η² - εᵀε) 1 + 2 ε εᵀ - 2 η ε^×` (eq. 4.4.9, explicit 4.4.10) is `C_BI`, the
//! matrix that takes inertial components to body components (eq. 5.1.3 uses it so). The
//! body-to-inertial matrix is its transpose `C_IB = C_BIᵀ`. The rates are
//! `ε̇ = ½ (ε^× + η 1) ω_B`, `η̇ = -½ εᵀ ω_B` (eqs. 4.4.11-4.4.12), which are exactly
//! `Ċ_BI = -ω_B^× C_BI`.

/// 3x3 matrix, `[row][col]`.
pub type Mat3 = [[f64; 3]; 3];

/// `C_BI(q)` from the Euler parameters `q = (ε1, ε2, ε3, η)`, eq. (4.4.10).
///
/// `q` is used as given: callers that integrate `q` keep `|q| = 1` (see
/// [`normalize_euler_parameters`]); [`c_bi_normalized`] divides by `|q|²` first.
pub fn c_bi(q: &[f64; 4]) -> Mat3 {
    let [e1, e2, e3, h] = *q;
    [
        [
            1.0 - 2.0 * (e2 * e2 + e3 * e3),
            2.0 * (e1 * e2 + e3 * h),
            2.0 * (e1 * e3 - e2 * h),
        ],
        [
            2.0 * (e1 * e2 - e3 * h),
            1.0 - 2.0 * (e1 * e1 + e3 * e3),
            2.0 * (e2 * e3 + e1 * h),
        ],
        [
            2.0 * (e1 * e3 + e2 * h),
            2.0 * (e2 * e3 - e1 * h),
            1.0 - 2.0 * (e1 * e1 + e2 * e2),
        ],
    ]
}

/// `C_BI(q / |q|)`: eq. (4.4.10) of the normalised parameters, so that a norm drift of the
/// integrated `q` never leaks into the rotation (the rotation is a function of the direction
/// of `q` only). Returns the identity for `q = 0`.
pub fn c_bi_normalized(q: &[f64; 4]) -> Mat3 {
    let n2 = q.iter().map(|x| x * x).sum::<f64>();
    if n2 > 0.0 && n2.is_finite() {
        let s = 1.0 / n2.sqrt();
        c_bi(&[q[0] * s, q[1] * s, q[2] * s, q[3] * s])
    } else {
        c_bi(&[0.0, 0.0, 0.0, 1.0])
    }
}

/// Transpose of a 3x3 matrix (`C_IB = C_BIᵀ`).
pub fn transpose(a: &Mat3) -> Mat3 {
    let mut t = [[0.0; 3]; 3];
    for (i, row) in a.iter().enumerate() {
        for (k, x) in row.iter().enumerate() {
            t[k][i] = *x;
        }
    }
    t
}

/// `a b` for a 3x3 matrix and a 3-vector.
pub fn mat_vec(a: &Mat3, b: &[f64; 3]) -> [f64; 3] {
    [
        a[0][0] * b[0] + a[0][1] * b[1] + a[0][2] * b[2],
        a[1][0] * b[0] + a[1][1] * b[1] + a[1][2] * b[2],
        a[2][0] * b[0] + a[2][1] * b[1] + a[2][2] * b[2],
    ]
}

/// `aᵀ b` for a 3x3 matrix and a 3-vector.
pub fn mat_t_vec(a: &Mat3, b: &[f64; 3]) -> [f64; 3] {
    [
        a[0][0] * b[0] + a[1][0] * b[1] + a[2][0] * b[2],
        a[0][1] * b[0] + a[1][1] * b[1] + a[2][1] * b[2],
        a[0][2] * b[0] + a[1][2] * b[1] + a[2][2] * b[2],
    ]
}

/// Cross product `a × b = a^× b`.
pub fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Dot product.
pub fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Euler parameter rates `q̇ = (ε̇, η̇)`, eqs. (4.4.11)-(4.4.12):
/// `ε̇ = ½ (ε^× + η 1) ω_B`, `η̇ = -½ εᵀ ω_B`.
///
/// Linear in `q`, so scaling `q` scales `q̇` by the same factor (used by the step projection
/// in `eom`).
pub fn euler_parameter_rates(q: &[f64; 4], omega_b: &[f64; 3]) -> [f64; 4] {
    let eps = [q[0], q[1], q[2]];
    let eta = q[3];
    let ex = cross(&eps, omega_b);
    [
        0.5 * (ex[0] + eta * omega_b[0]),
        0.5 * (ex[1] + eta * omega_b[1]),
        0.5 * (ex[2] + eta * omega_b[2]),
        -0.5 * dot(&eps, omega_b),
    ]
}

/// Divides `q` by its norm (the unit constraint 4.4.8) and returns the factor applied,
/// `1/|q|`; returns `None` (and leaves `q`) if `|q|` is zero or not finite.
pub fn normalize_euler_parameters(q: &mut [f64]) -> Option<f64> {
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !(n > 0.0 && n.is_finite()) {
        return None;
    }
    let s = 1.0 / n;
    q.iter_mut().for_each(|x| *x *= s);
    Some(s)
}

/// Roll, pitch, yaw `(φ, θ, ψ)` in radians from `C_BI = C1(φ) C2(θ) C3(ψ)`, eqs. (4.4.4)-(4.4.5):
/// `C13 = -sin θ`, `C23 = sin φ cos θ`, `C33 = cos φ cos θ`, `C12 = cos θ sin ψ`,
/// `C11 = cos θ cos ψ`. At `θ = ±90°` roll and yaw are not separable (the singularity the
/// thesis mentions); there the yaw is returned as 0 and the whole rotation about the vertical
/// goes into roll.
pub fn euler_angles(c_bi: &Mat3) -> [f64; 3] {
    let s_theta = (-c_bi[0][2]).clamp(-1.0, 1.0);
    let theta = s_theta.asin();
    if (1.0 - s_theta.abs()) < 1e-12 {
        // C21 = sinφ sinθ cosψ - cosφ sinψ, C22 = sinφ sinθ sinψ + cosφ cosψ with ψ = 0.
        let phi = (c_bi[1][0] * s_theta).atan2(c_bi[1][1]);
        return [phi, theta, 0.0];
    }
    let phi = c_bi[1][2].atan2(c_bi[2][2]);
    let psi = c_bi[0][1].atan2(c_bi[0][0]);
    [phi, theta, psi]
}

/// Euler parameters of the rotation `C_BI = C1(φ) C2(θ) C3(ψ)` (eq. 4.4.4), for initial
/// conditions: the product of the three elementary rotations, each `(a sin(φ/2), cos(φ/2))`
/// (eqs. 4.4.6-4.4.7), composed so that [`c_bi`] reproduces (4.4.5).
pub fn euler_parameters_from_angles(roll: f64, pitch: f64, yaw: f64) -> [f64; 4] {
    let (s1, c1) = (0.5 * roll).sin_cos();
    let (s2, c2) = (0.5 * pitch).sin_cos();
    let (s3, c3) = (0.5 * yaw).sin_cos();
    // C_BI(q_a ∘ q_b) = C_BI(q_a) C_BI(q_b) for this product (Hughes' composition rule).
    let compose = |a: [f64; 4], b: [f64; 4]| -> [f64; 4] {
        let (ea, ha) = ([a[0], a[1], a[2]], a[3]);
        let (eb, hb) = ([b[0], b[1], b[2]], b[3]);
        let x = cross(&ea, &eb);
        [
            ha * eb[0] + hb * ea[0] - x[0],
            ha * eb[1] + hb * ea[1] - x[1],
            ha * eb[2] + hb * ea[2] - x[2],
            ha * hb - dot(&ea, &eb),
        ]
    };
    let q1 = [s1, 0.0, 0.0, c1];
    let q2 = [0.0, s2, 0.0, c2];
    let q3 = [0.0, 0.0, s3, c3];
    compose(compose(q1, q2), q3)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mat_mul(a: &Mat3, b: &Mat3) -> Mat3 {
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for k in 0..3 {
                c[i][k] = (0..3).map(|j| a[i][j] * b[j][k]).sum();
            }
        }
        c
    }

    fn elementary(roll: f64, pitch: f64, yaw: f64) -> Mat3 {
        let (sf, cf) = roll.sin_cos();
        let (st, ct) = pitch.sin_cos();
        let (sp, cp) = yaw.sin_cos();
        let c1 = [[1.0, 0.0, 0.0], [0.0, cf, sf], [0.0, -sf, cf]];
        let c2 = [[ct, 0.0, -st], [0.0, 1.0, 0.0], [st, 0.0, ct]];
        let c3 = [[cp, sp, 0.0], [-sp, cp, 0.0], [0.0, 0.0, 1.0]];
        mat_mul(&mat_mul(&c1, &c2), &c3)
    }

    #[test]
    fn angles_round_trip_through_euler_parameters() {
        let (roll, pitch, yaw) = (0.3, -0.7, 2.1);
        let q = euler_parameters_from_angles(roll, pitch, yaw);
        let c = c_bi(&q);
        let e = elementary(roll, pitch, yaw);
        for i in 0..3 {
            for k in 0..3 {
                assert!((c[i][k] - e[i][k]).abs() < 1e-14, "{i}{k}");
            }
        }
        let a = euler_angles(&c);
        assert!((a[0] - roll).abs() < 1e-13);
        assert!((a[1] - pitch).abs() < 1e-13);
        assert!((a[2] - yaw).abs() < 1e-13);
    }

    #[test]
    fn rates_give_c_dot_equal_minus_omega_cross_c() {
        let q = euler_parameters_from_angles(0.4, 0.2, -1.0);
        let w = [0.3, -1.2, 0.7];
        let qd = euler_parameter_rates(&q, &w);
        let h = 1e-6;
        let qp: [f64; 4] = std::array::from_fn(|i| q[i] + h * qd[i]);
        let qm: [f64; 4] = std::array::from_fn(|i| q[i] - h * qd[i]);
        let (cp, cm, c) = (c_bi(&qp), c_bi(&qm), c_bi(&q));
        for i in 0..3 {
            for k in 0..3 {
                let cdot = (cp[i][k] - cm[i][k]) / (2.0 * h);
                // -(ω^× C)_ik
                let wx = [[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]];
                let expect = -(0..3).map(|j| wx[i][j] * c[j][k]).sum::<f64>();
                assert!((cdot - expect).abs() < 1e-8, "{i}{k}: {cdot} vs {expect}");
            }
        }
    }
}
