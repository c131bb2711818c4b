//! Leeward load reduction of a fin due to flow blockage (thesis 5.4.4, eqs. (5.4.24)-(5.4.31)).
//!
//! Windward fins (0 <= delta_tot <= 180 deg) carry their full computed load. A leeward fin
//! (180 < delta_tot < 360 deg) is scaled by f_LW = exp(-tau x_delta) (5.4.29) with
//! x_delta = 1 - cos(delta_tot - 180 deg) (5.4.30). The time constant tau follows from the
//! known value at delta_tot = 225 deg (the "x" cruciform at roll 45 deg, (5.4.26)-(5.4.28)):
//! tau(alpha) = -ln f_LW(225 deg, alpha) / x_delta(225 deg) (our reading of the garbled (5.4.31),
//! see REFERENCE-NOTES). The thesis states the profile is symmetric about 270 deg, where the
//! fin points straight downwind; (5.4.30) alone is not (x_delta keeps growing to 2 at 360 deg),
//! so (5.4.29)-(5.4.30) are applied on 180..270 deg and mirrored: delta -> 540 deg - delta for
//! 270 < delta < 360. The factor is then continuous with the windward value 1 at 180 and 360.

/// Angle of attack (deg) above which the windward/leeward split of (5.4.26)-(5.4.27) stays
/// constant.
pub const LEEWARD_ALPHA_LIMIT_DEG: f64 = 65.0;

/// Fraction of the total fin normal force carried by the windward fins of a cruciform at
/// roll 45 deg, eq. (5.4.26): 0.5 + 0.4 alpha/65 (alpha in degrees, held constant above 65).
/// Negative alpha is taken by magnitude (the split depends on the incidence, not its sign).
pub fn windward_share(alpha_deg: f64) -> f64 {
    let a = alpha_deg.abs().min(LEEWARD_ALPHA_LIMIT_DEG);
    0.5 + 0.4 * a / LEEWARD_ALPHA_LIMIT_DEG
}

/// f_LW(225 deg, alpha) = (c_n)_LW / (c_n)_WW, eq. (5.4.28), with (c_n)_LW from (5.4.27)
/// (= 1 - (c_n)_WW for unit total load).
pub fn leeward_factor_at_225(alpha_deg: f64) -> f64 {
    let ww = windward_share(alpha_deg);
    (1.0 - ww) / ww
}

/// x_delta = 1 - cos(delta_tot - 180 deg), eq. (5.4.30); `delta_tot_deg` in degrees.
pub fn x_delta(delta_tot_deg: f64) -> f64 {
    1.0 - (delta_tot_deg - 180.0).to_radians().cos()
}

/// `x_delta(225 deg) = 1 - cos 45 deg` (5.4.30), the bits of [`x_delta`]`(225.0)` (tested).
const X_DELTA_225: f64 = 0.292_893_218_813_452_4;

/// The exponential rate tau(alpha) = -ln f_LW(225 deg, alpha) / x_delta(225 deg), our reading
/// of eq. (5.4.31): it makes (5.4.29) reproduce (5.4.28) at delta_tot = 225 deg.
pub fn leeward_tau(alpha_deg: f64) -> f64 {
    -leeward_factor_at_225(alpha_deg).ln() / X_DELTA_225
}

/// Leeward reduction factor f_LW(delta_tot, alpha), eqs. (5.4.24)-(5.4.31).
///
/// `delta_tot_deg` is the net fin orientation delta_i + theta_yz of (5.4.24), any real value
/// (it is wrapped into [0, 360)); `alpha_deg` the angle of attack in degrees. Returns 1 for
/// windward fins (0 <= delta_tot <= 180 deg) and exp(-tau x_delta) (5.4.29) for leeward ones,
/// mirrored about the minimum at 270 deg (see the module doc). Non-finite input gives 1 (no reduction) rather than NaN loads.
pub fn f_lw(delta_tot_deg: f64, alpha_deg: f64) -> f64 {
    f_lw_with(delta_tot_deg, || alpha_deg)
}

/// [`f_lw`] with the angle of attack computed only when the fin is leeward (a windward fin,
/// or a non-finite orientation, gives 1 whatever the angle of attack): the same values.
#[inline]
pub fn f_lw_with(delta_tot_deg: f64, alpha_deg: impl FnOnce() -> f64) -> f64 {
    if !delta_tot_deg.is_finite() {
        return 1.0;
    }
    let d = delta_tot_deg.rem_euclid(360.0);
    if d <= 180.0 {
        return 1.0;
    }
    let alpha_deg = alpha_deg();
    if !alpha_deg.is_finite() {
        return 1.0;
    }
    // Mirror 270..360 onto 270..180 (symmetry about 270 deg stated in 5.4.4).
    let d = if d > 270.0 { 540.0 - d } else { d };
    (-leeward_tau(alpha_deg) * x_delta(d)).exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_225_deg_constant_has_the_bits_of_x_delta() {
        assert_eq!(X_DELTA_225.to_bits(), x_delta(225.0).to_bits());
    }

    #[test]
    fn windward_fins_get_full_load() {
        for d in [0.0, 45.0, 90.0, 135.0, 180.0, 360.0, -180.0] {
            assert_eq!(f_lw(d, 20.0), 1.0, "delta_tot {d}");
        }
    }

    #[test]
    fn value_at_225_matches_5_4_28() {
        // alpha = 20 deg: (c_n)_WW = 0.5 + 0.4*20/65 = 0.623077, (c_n)_LW = 0.376923,
        // f_LW = 0.376923/0.623077 = 0.604938 (hand calculation).
        assert!((f_lw(225.0, 20.0) - 0.604_938).abs() < 1e-6);
        // Just past 180 deg the factor is continuous with the windward value 1.
        assert!((f_lw(180.0 + 1e-6, 20.0) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn minimum_at_270_and_symmetric() {
        // x_delta(270) = 1, x_delta(225) = 1 - cos 45 = 0.292893;
        // f(270) = f(225)^(1/0.292893) = 0.604938^3.414214 = 0.179 (hand: ln 0.604938 = -0.502628,
        // * 3.414214 = -1.716081, exp = 0.179769).
        assert!((f_lw(270.0, 20.0) - 0.179_769).abs() < 1e-6);
        for off in [5.0, 20.0, 45.0, 80.0] {
            let a = f_lw(270.0 - off, 30.0);
            let b = f_lw(270.0 + off, 30.0);
            assert!((a - b).abs() < 1e-12, "offset {off}: {a} vs {b}");
            assert!(a > f_lw(270.0, 30.0));
        }
        // Continuous with the windward value at 360 deg.
        assert!((f_lw(360.0 - 1e-6, 20.0) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn zero_alpha_no_reduction_and_alpha_saturates() {
        assert!((f_lw(270.0, 0.0) - 1.0).abs() < 1e-12);
        assert_eq!(f_lw(250.0, 65.0), f_lw(250.0, 80.0));
        assert_eq!(f_lw(250.0, -10.0), f_lw(250.0, 10.0));
    }
}
