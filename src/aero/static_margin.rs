//! The static margin from the coefficient tables the aerodynamic force blocks use (the
//! plan builds it; the run driver evaluates it on every row).

/// The static margin of the vehicle from the SAME coefficient tables its aerodynamic blocks
/// use: with the normal-force slopes `C_N_alpha` by central difference at `alpha = ±2 deg`
/// (the estimator's grid spacing; one-sided over [0, 2] deg for a table whose alpha axis
/// starts at 0, which the body block allows since it only queries `alpha_b >= 0`), the body's centre of pressure
/// `x_b = x_ref + b C_M_alpha / C_N_alpha` (from (5.3.3): `C_M = C_N (x_cp - x_ref) / b`,
/// x forward), each fin's `x_f = x_le,root - x_cp,f` (the fin table's chordwise centre of
/// pressure aft of the root leading edge), and the fins' pitch-plane sum
/// `Σ_i C_N_alpha,f cos^2(delta_i) = (N/2) C_N_alpha,f`, exact for N >= 3 fins evenly spaced
/// (the fin at roll angle delta sees `alpha cos delta` and its normal force has the share
/// `cos delta` in the pitch plane; Barrowman 1967 sums the fins the same way). The total
/// centre of pressure is the slope-weighted mean, and the margin in calibres is
/// `(x_cg - x_cp) / d` with `x_cg` the undeformed mass centre at the row's time (it moves as
/// the propellant burns: `c̄ / m` of the coefficients at the current propellant fraction,
/// without the elastic `P̄ η`) and `d` the aerodynamic reference length (the body diameter
/// for the built-in estimator).
#[derive(Debug, Clone)]
pub struct StaticMargin {
    body: crate::aero::CoefficientTable,
    fin: crate::aero::CoefficientTable,
    fins: f64,
    x_ref: f64,
    length: f64,
    x_root_le: f64,
}

impl StaticMargin {
    /// The model of a vehicle with body and fin tables and fins (both aero blocks on).
    pub fn new(
        v: &crate::check::ir::Vehicle,
        compiled: &crate::structure::compile::CompiledVehicle,
        tables: &crate::aero::EstimatedTables,
    ) -> Option<Self> {
        let f = v.fins.as_ref()?;
        if v.forces.body_aero.is_none() || v.forces.fin_aero.is_none() {
            return None;
        }
        let m = compiled.reduced.mass;
        (m > 0.0).then(|| StaticMargin {
            body: tables.body.clone(),
            fin: tables.fin.clone(),
            fins: f.count.value as f64,
            x_ref: v.aero.reference_point.value[0],
            length: v.aero.reference_length.value,
            x_root_le: f.root_trailing_edge_x.value + f.root_chord.value,
        })
    }

    /// The centre of pressure `x_cp` (body frame, m) at `(mach, altitude)`, and the total
    /// `C_N_alpha` (1/rad). Queries are clamped into the tables (this is a monitor, never a stop).
    pub fn centre_of_pressure(&self, mach: f64, altitude: f64) -> Option<(f64, f64)> {
        let q = |t: &crate::aero::CoefficientTable, a: f64| {
            let ax = |k| t.axis(k);
            let m = mach.clamp(
                ax(crate::aero::Axis::Mach)[0],
                *ax(crate::aero::Axis::Mach).last()?,
            );
            let h = altitude.clamp(
                ax(crate::aero::Axis::AltitudeM)[0],
                *ax(crate::aero::Axis::AltitudeM).last()?,
            );
            t.lookup(m, a, h).ok()
        };
        // The difference over [-2, 2] deg, cut to the table's alpha axis: a body table may
        // start at alpha = 0 (the body block only queries alpha_b >= 0), where the slope is
        // the one-sided (C(2) - C(0))/2 deg, equal to the central one for coefficients odd in
        // alpha (a body of revolution).
        let pair = |t: &crate::aero::CoefficientTable| {
            let ax = t.axis(crate::aero::Axis::AlphaDeg);
            let lo = (-2f64).max(ax[0]);
            let hi = 2f64.min(*ax.last()?);
            (hi > lo).then_some((hi, lo))
        };
        let (hb, lb) = pair(&self.body)?;
        let (hf, lf) = pair(&self.fin)?;
        let (b_p, b_m) = (q(&self.body, hb)?, q(&self.body, lb)?);
        let (f_p, f_m) = (q(&self.fin, hf)?, q(&self.fin, lf)?);
        let (db, df) = ((hb - lb).to_radians(), (hf - lf).to_radians());
        let cn_b = (b_p[0] - b_m[0]) / db;
        let cm_b = (b_p[2] - b_m[2]) / db;
        let cn_f = 0.5 * self.fins * (f_p[0] - f_m[0]) / df;
        let x_cp_f = self.x_root_le - 0.5 * (f_p[2] + f_m[2]);
        let x_b = if cn_b != 0.0 {
            self.x_ref + self.length * cm_b / cn_b
        } else {
            self.x_ref
        };
        let cn = cn_b + cn_f;
        if !(cn.is_finite() && cn != 0.0) {
            return None;
        }
        Some(((cn_b * x_b + cn_f * x_cp_f) / cn, cn))
    }

    /// `(x_cg - x_cp) / d`, calibres, for the undeformed mass centre `x_cg` (body x, m).
    pub fn calibres(&self, mach: f64, altitude: f64, x_cg: f64) -> Option<f64> {
        self.centre_of_pressure(mach, altitude)
            .map(|(x, _)| (x_cg - x) / self.length)
    }
}
