//! The planar vehicle: what the planar models of thesis 6.1-6.2 need from the compiled
//! vehicle and its coefficient tables, and the flight condition they are evaluated at.
//!
//! # Mass properties
//! Total mass `m`, centre of mass `x_cg` and pitch inertia `J` about the centre of mass come
//! from the compiled vehicle (`CompiledVehicle::reduced.mass`, `centre_of_mass`,
//! `inertia_cm[1][1]`, the integrals (2.5.4)-(2.5.6) of the FE mass matrix) at the fin
//! thickness `t0` the vehicle declares. A stability map sweeps the thickness without
//! recompiling the FE model: each fin is a flat plate of constant thickness (Table 4.1), so its
//! mass is `rho_f A_f t` and changing `t0 -> t` adds `dm_i = rho_f A_f (t - t0)` at the fin's
//! planform centroid `(x_fc, r_fc)` (radius `r_fc` along the span direction of fin i at roll
//! angle `delta_i`). Then
//! `m(t) = m0 + sum dm_i`, `x_cg(t) = (m0 x_cg0 + sum dm_i x_fc)/m(t)` and, by the parallel-axis
//! theorem about the pitch axis (body y),
//! `J(t) = J0 + m0 (x_cg0 - x_cg)^2 + sum dm_i [(x_fc - x_cg)^2 + (r_fc sin delta_i)^2]`.
//! The chordwise and spanwise spread of the added plate mass about its own centroid is
//! neglected (for SPHADS-1 it is under 1 % of the fins' own pitch inertia). At `t = t0` the
//! compiled values are returned exactly.
//!
//! # The flapping fin (eqs. (6.1), (6.10)-(6.11))
//! The planar models have one fin coordinate `delta`, the deflection of the fin centre of
//! pressure normal to the fin in the pitch plane (body x-z). Fin i (roll angle `delta_i`,
//! normal `(0, -sin delta_i, cos delta_i)`) has a pitch-plane normal component
//! `cos delta_i`: a symmetric flap in which fin i deflects `cos(delta_i) delta` along its
//! normal has kinetic energy `1/2 sum cos^2(delta_i) m_1 delta'^2`, strain energy
//! `1/2 sum cos^2(delta_i) k_1 delta^2`, and its normal forces, each proportional to
//! `cos(delta_i) alpha`, project on the pitch plane with another `cos(delta_i)`. So every fin
//! quantity of the planar models is one fin's value times `n_eff = sum cos^2 delta_i` (2 for a
//! cruciform: the two fins whose span is normal to the pitch plane): `m_f = n_eff rho_f A_f t`,
//! `k = n_eff 24 E I / L^3` (6.10) with `I = c t^3/12` (6.11), `L` the span and `c` the mean
//! geometric chord `A_f/L` of the trapezoid, and the fin normal-force slope
//! `C_Nalpha,f (S_f/S) = n_eff C_Nalpha,1` with `C_Nalpha,1` the slope of ONE fin on the
//! reference area S read from the runtime's fin table (which already holds `S_f/S` and the
//! body-fin interference).

use crate::aero::atmosphere::{Atmosphere, AtmosphereState, Standard1976};
use crate::aero::estimator::EstimatedTables;
use crate::aero::tables::{Axis, CoefficientTable};
use crate::check::ir::{self, OutOfRange, Structure};
use crate::runtime::forces::{aero_tables, gravity::gravity_at};
use crate::structure::compile::CompiledVehicle;

use super::PlanarError;

/// Half-width of the central differences in angle of attack, deg. The runtime's tables are
/// piecewise linear in alpha with grid points at 0 and +-2 deg (estimator grid), so a +-1 deg
/// central difference gives the slope the runtime sees at small incidence.
pub const ALPHA_STEP_DEG: f64 = 1.0;
/// Half-width of the central differences in Mach.
pub const MACH_STEP: f64 = 0.01;

/// Fin geometry and material of the planar models.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FinGeometry {
    /// Number of fins n.
    pub count: usize,
    /// Roll angles delta_i, rad.
    pub angles: Vec<f64>,
    /// `n_eff = sum cos^2 delta_i`: fins acting in the pitch plane (see the module doc).
    pub pitch_plane_fins: f64,
    /// Span L, m.
    pub span: f64,
    pub root_chord: f64,
    pub tip_chord: f64,
    /// Planform area A_f of one fin, m^2.
    pub area: f64,
    /// Mean geometric chord c = A_f / L, m (the chord of (6.11)).
    pub mean_chord: f64,
    /// Body x of the root leading edge, m.
    pub root_leading_edge_x: f64,
    /// Chordwise distance from the root leading edge back to the tip leading edge, m
    /// (`L tan Lambda_LE`).
    pub tip_le_offset: f64,
    /// Body x of the planform centroid, m.
    pub centroid_x: f64,
    /// Radius of the planform centroid from the body axis, m.
    pub centroid_radius: f64,
    /// Young's modulus E along the span, Pa (of a lamina: `E` with the grain spanwise, `E2`
    /// with it chordwise), the modulus of the spanwise bending of (6.10)-(6.11).
    pub youngs_modulus: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// The in-plane shear modulus `G12` of a lamina, Pa (`None`: isotropic, `E/(2(1+nu))`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub g12: Option<f64>,
    /// Density, kg/m^3.
    pub density: f64,
    /// Thickness declared by the vehicle (the compiled one), m.
    pub declared_thickness: f64,
}

impl FinGeometry {
    /// In-plane shear modulus, Pa: a lamina's `G12`, else G = E / (2 (1 + nu)).
    pub fn shear_modulus(&self) -> f64 {
        self.g12
            .unwrap_or(self.youngs_modulus / (2.0 * (1.0 + self.poisson)))
    }

    /// Stiffness of one fin at its mid-span, eqs. (6.10)-(6.11): `24 E I / L^3`,
    /// `I = c t^3 / 12`.
    pub fn stiffness_one(&self, thickness: f64) -> f64 {
        let i = self.mean_chord * thickness.powi(3) / 12.0;
        24.0 * self.youngs_modulus * i / self.span.powi(3)
    }

    /// Mass of one flat-plate fin, kg.
    pub fn mass_one(&self, thickness: f64) -> f64 {
        self.density * self.area * thickness
    }
}

/// Rigid mass properties in the pitch plane at one fin thickness.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PitchMassProperties {
    /// Total mass m, kg.
    pub mass: f64,
    /// Body x of the centre of mass, m (<= 0).
    pub x_cg: f64,
    /// Pitch inertia J about the centre of mass, kg m^2.
    pub inertia: f64,
}

/// The planar view of a compiled vehicle; see the module doc.
#[derive(Clone, Debug)]
pub struct PlanarVehicle {
    pub name: String,
    /// Mass properties of the compiled vehicle (at `fins.declared_thickness`).
    pub compiled: PitchMassProperties,
    pub fins: FinGeometry,
    /// Reference area S, m^2, and length b, m (5.3.1)-(5.3.3).
    pub reference_area: f64,
    pub reference_length: f64,
    /// Body x of the coefficient reference point, m.
    pub reference_x: f64,
    /// `body_aero { rate_terms }`: use the body table's rate columns (`cn_q`, `cm_q`), as the
    /// runtime's body block does.
    pub rate_terms: bool,
    /// Scale gravity with altitude (5.1.2), as the vehicle's gravity block.
    pub gravity_altitude_correction: bool,
    tables: EstimatedTables,
    atmosphere: Standard1976,
}

/// Air and speed at one flight condition.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FlightCondition {
    /// Geometric altitude, m.
    pub altitude: f64,
    /// Airspeed V (V0 of 6.2), m/s.
    pub speed: f64,
    pub mach: f64,
    pub density: f64,
    pub pressure: f64,
    pub temperature: f64,
    pub speed_of_sound: f64,
    /// q = rho V^2 / 2, Pa.
    pub dynamic_pressure: f64,
    /// Gravity g at the altitude, m/s^2 (5.1.2).
    pub gravity: f64,
}

/// Aerodynamic coefficients and their derivatives at one condition, read from the SAME
/// tables the runtime's force blocks use (zero angle of attack; per radian).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AeroDerivatives {
    /// Body C_Nalpha on S, /rad.
    pub cn_alpha_body: f64,
    /// Body C_Malpha about the reference point on S b, /rad (nose up positive).
    pub cm_alpha_body: f64,
    /// Body C_A at alpha = 0.
    pub ca_body: f64,
    /// dC_A/dMach of the body.
    pub ca_mach_body: f64,
    /// dC_A/dalpha of the body, /rad (zero for a symmetric table).
    pub ca_alpha_body: f64,
    /// C_Nalpha of ONE fin on S, /rad.
    pub cn_alpha_fin: f64,
    /// C_A of one fin at alpha = 0.
    pub ca_fin: f64,
    pub ca_mach_fin: f64,
    pub ca_alpha_fin: f64,
    /// Fin centre of pressure, m aft of the root leading edge.
    pub x_cp_fin: f64,
}

impl PlanarVehicle {
    /// Builds the planar vehicle from the checked vehicle (after overrides) and its compiled
    /// structure. Errors: no `fins` block, or the coefficient tables cannot be read/built.
    pub fn new(v: &ir::Vehicle, compiled: &CompiledVehicle) -> Result<Self, PlanarError> {
        let Some(f) = &v.fins else {
            return Err(PlanarError::NoFins {
                vehicle: v.name.value.clone(),
            });
        };
        if f.count.value == 0 {
            return Err(PlanarError::NoFins {
                vehicle: v.name.value.clone(),
            });
        }
        let tables = aero_tables(v).map_err(|e| PlanarError::Aero(e.to_string()))?;
        let n = f.count.value;
        let angles: Vec<f64> = if f.angles.len() == n {
            f.angles.iter().map(|a| a.value).collect()
        } else {
            (0..n)
                .map(|i| 2.0 * std::f64::consts::PI * i as f64 / n as f64)
                .collect()
        };
        let span = f.span.value;
        let (cr, ct) = (f.root_chord.value, f.tip_chord.value);
        let area = 0.5 * (cr + ct) * span;
        let x_le_tip = span * f.leading_edge_sweep.value.tan();
        let root_le_x = f.root_trailing_edge_x.value + cr;
        // Trapezoid centroid: spanwise (cr + 2 ct)/(3 (cr + ct)) L from the root; chordwise
        // the mean of the local mid-chord weighted by the local chord.
        let eta_c = (cr + 2.0 * ct) / (3.0 * (cr + ct));
        // x aft of the root LE of the area centroid: integral of c(eta)(x_le(eta) + c/2).
        let xi_c = {
            let nq = 64;
            let (mut num, mut den) = (0.0, 0.0);
            for k in 0..nq {
                let eta = (k as f64 + 0.5) / nq as f64;
                let c = cr + (ct - cr) * eta;
                num += c * (x_le_tip * eta + 0.5 * c);
                den += c;
            }
            num / den
        };
        let body_radius = match &v.structure {
            Structure::Generate(g) => g.body.root_radius(v.fins.as_ref()),
            Structure::Files(_) => compiled
                .node_positions
                .iter()
                .zip(&compiled.node_components)
                .filter(|(_, c)| **c >= 0)
                .map(|(p, _)| (p[1] * p[1] + p[2] * p[2]).sqrt())
                .fold(f64::INFINITY, f64::min),
        };
        let body_radius = if body_radius.is_finite() {
            body_radius
        } else {
            0.0
        };
        let fins = FinGeometry {
            count: n,
            pitch_plane_fins: angles.iter().map(|d| d.cos().powi(2)).sum(),
            angles,
            span,
            root_chord: cr,
            tip_chord: ct,
            area,
            mean_chord: area / span,
            root_leading_edge_x: root_le_x,
            tip_le_offset: x_le_tip,
            centroid_x: root_le_x - xi_c,
            centroid_radius: body_radius + eta_c * span,
            youngs_modulus: match (&f.material.orthotropic, f.grain) {
                (Some(o), crate::check::ir::FinGrain::Chordwise) => o.e2.value,
                _ => f.material.youngs_modulus.value,
            },
            poisson: f.material.poisson.value,
            g12: f.material.orthotropic.as_ref().map(|o| o.g12.value),
            density: f.material.density.value,
            declared_thickness: f.thickness.value,
        };
        let compiled_props = PitchMassProperties {
            mass: compiled.reduced.mass,
            x_cg: compiled.centre_of_mass[0],
            inertia: compiled.inertia_cm[1][1],
        };
        let rate_terms = v.forces.body_aero.as_ref().is_some_and(|b| b.rate_terms);
        Ok(PlanarVehicle {
            name: v.name.value.clone(),
            compiled: compiled_props,
            fins,
            reference_area: v.aero.reference_area.value,
            reference_length: v.aero.reference_length.value,
            reference_x: v.aero.reference_point.value[0],
            rate_terms,
            gravity_altitude_correction: v
                .forces
                .gravity
                .as_ref()
                .is_some_and(|g| g.altitude_correction),
            tables,
            atmosphere: Standard1976::new(),
        })
    }

    /// The altitudes the analysis may query, m: the atmosphere's `(lo, hi)` narrowed to the
    /// altitude axis of every coefficient table with the `stop` out-of-range policy (a
    /// clamping table accepts any altitude).
    pub fn altitude_range(&self, lo: f64, hi: f64) -> (f64, f64) {
        [&self.tables.body, &self.tables.fin]
            .into_iter()
            .filter(|t| t.policy() == OutOfRange::Stop)
            .fold((lo, hi), |(lo, hi), t| {
                let a = t.axis(Axis::AltitudeM);
                (lo.max(a[0]), hi.min(a[a.len() - 1]))
            })
    }

    /// Mass properties with fins of thickness `t` (module doc); errors when the mass or the
    /// inertia would not be positive.
    pub fn mass_properties(&self, thickness: f64) -> Result<PitchMassProperties, PlanarError> {
        if !(thickness.is_finite() && thickness > 0.0) {
            return Err(PlanarError::BadThickness { thickness });
        }
        let c = self.compiled;
        let dm_one =
            self.fins.mass_one(thickness) - self.fins.mass_one(self.fins.declared_thickness);
        let n = self.fins.count as f64;
        let mass = c.mass + n * dm_one;
        if !(mass.is_finite() && mass > 0.0) {
            return Err(PlanarError::BadThickness { thickness });
        }
        let x_fc = self.fins.centroid_x;
        let x_cg = (c.mass * c.x_cg + n * dm_one * x_fc) / mass;
        let r = self.fins.centroid_radius;
        let spread: f64 = self
            .fins
            .angles
            .iter()
            .map(|d| (x_fc - x_cg).powi(2) + (r * d.sin()).powi(2))
            .sum();
        let inertia = c.inertia + c.mass * (c.x_cg - x_cg).powi(2) + dm_one * spread;
        if !(inertia.is_finite() && inertia > 0.0) {
            return Err(PlanarError::BadThickness { thickness });
        }
        Ok(PitchMassProperties {
            mass,
            x_cg,
            inertia,
        })
    }

    /// The flight condition at geometric altitude `altitude` and Mach `mach`.
    pub fn condition_at_mach(
        &self,
        altitude: f64,
        mach: f64,
    ) -> Result<FlightCondition, PlanarError> {
        let air = self.air(altitude)?;
        Ok(self.condition(altitude, mach * air.speed_of_sound, &air))
    }

    /// The flight condition at geometric altitude `altitude` and airspeed `speed`.
    pub fn condition_at_speed(
        &self,
        altitude: f64,
        speed: f64,
    ) -> Result<FlightCondition, PlanarError> {
        let air = self.air(altitude)?;
        Ok(self.condition(altitude, speed, &air))
    }

    fn air(&self, altitude: f64) -> Result<AtmosphereState, PlanarError> {
        self.atmosphere
            .at(altitude)
            .map_err(|e| PlanarError::Atmosphere(e.to_string()))
    }

    fn condition(&self, altitude: f64, speed: f64, air: &AtmosphereState) -> FlightCondition {
        FlightCondition {
            altitude,
            speed,
            mach: speed / air.speed_of_sound,
            density: air.density,
            pressure: air.pressure,
            temperature: air.temperature,
            speed_of_sound: air.speed_of_sound,
            dynamic_pressure: 0.5 * air.density * speed * speed,
            gravity: gravity_at(altitude, self.gravity_altitude_correction),
        }
    }

    /// The coefficients at `c` (alpha = 0) and their central differences; see
    /// [`AeroDerivatives`].
    pub fn aero(&self, c: &FlightCondition) -> Result<AeroDerivatives, PlanarError> {
        let body = &self.tables.body;
        let fin = &self.tables.fin;
        let h = c.altitude;
        let m = c.mach;
        let da = ALPHA_STEP_DEG;
        let per_rad = 1.0 / (2.0 * da).to_radians();
        let b_p = lookup(body, m, da, h)?;
        let b_m = lookup(body, m, -da, h)?;
        let b_0 = lookup(body, m, 0.0, h)?;
        let f_p = lookup(fin, m, da, h)?;
        let f_m = lookup(fin, m, -da, h)?;
        let f_0 = lookup(fin, m, 0.0, h)?;
        // Mach differences, kept inside the table (one-sided at an edge).
        let (m_lo, m_hi) = mach_stencil(body, m);
        let b_lo = lookup(body, m_lo, 0.0, h)?;
        let b_hi = lookup(body, m_hi, 0.0, h)?;
        let (fm_lo, fm_hi) = mach_stencil(fin, m);
        let fl = lookup(fin, fm_lo, 0.0, h)?;
        let fh = lookup(fin, fm_hi, 0.0, h)?;
        let slope = |hi: f64, lo: f64, dx: f64| if dx > 0.0 { (hi - lo) / dx } else { 0.0 };
        Ok(AeroDerivatives {
            cn_alpha_body: (b_p[0] - b_m[0]) * per_rad,
            cm_alpha_body: (b_p[2] - b_m[2]) * per_rad,
            ca_body: b_0[1],
            ca_mach_body: slope(b_hi[1], b_lo[1], m_hi - m_lo),
            ca_alpha_body: (b_p[1] - b_m[1]) * per_rad,
            cn_alpha_fin: (f_p[0] - f_m[0]) * per_rad,
            ca_fin: f_0[1],
            ca_mach_fin: slope(fh[1], fl[1], fm_hi - fm_lo),
            ca_alpha_fin: (f_p[1] - f_m[1]) * per_rad,
            x_cp_fin: f_0[2],
        })
    }

    /// The body rate derivatives `(C_Nq + C_Nα̇, C_mq + C_mα̇)` at zero incidence (the body
    /// table's rate columns, about the reference point, per rad of `θ' b/(2V)`), the same
    /// numbers the runtime's body block applies; zero without `rate_terms`, an error when
    /// `rate_terms` is on and the table has no rate columns (as the runtime refuses to start).
    pub fn rate_derivatives(&self, c: &FlightCondition) -> Result<(f64, f64), PlanarError> {
        if !self.rate_terms {
            return Ok((0.0, 0.0));
        }
        let t = &self.tables.body;
        let [m, a, h] = clamped(t, c.mach, 0.0, c.altitude)?;
        match t.body_rates(m, a, h) {
            Ok(Some(r)) => Ok((r.cn_q, r.cm_q)),
            Ok(None) => Err(PlanarError::Aero(format!(
                "`body_aero {{ rate_terms = true }}` needs the rate derivatives, but the body table {} has no `cn_q,cm_q` columns",
                t.source().display()
            ))),
            Err(e) => Err(PlanarError::Aero(e.to_string())),
        }
    }

    /// Total axial force at zero incidence, N: body plus all n fins, `q S (C_A,B + n C_A,f)`.
    pub fn axial_force(&self, c: &FlightCondition) -> Result<f64, PlanarError> {
        let b = lookup(&self.tables.body, c.mach, 0.0, c.altitude)?;
        let f = lookup(&self.tables.fin, c.mach, 0.0, c.altitude)?;
        Ok(c.dynamic_pressure * self.reference_area * (b[1] + self.fins.count as f64 * f[1]))
    }
}

/// A table lookup with the runtime's policy: clamped into the axes (as
/// `runtime::forces::body_aero::clamped_query`), an error when the table's policy is `stop`.
fn lookup(
    t: &CoefficientTable,
    mach: f64,
    alpha_deg: f64,
    alt: f64,
) -> Result<[f64; 3], PlanarError> {
    let q = clamped(t, mach, alpha_deg, alt)?;
    t.lookup(q[0], q[1], q[2])
        .map_err(|e| PlanarError::Aero(e.to_string()))
}

/// The query point clamped into the table's axes, an error when the table's policy is `stop`
/// and a value is outside.
fn clamped(
    t: &CoefficientTable,
    mach: f64,
    alpha_deg: f64,
    alt: f64,
) -> Result<[f64; 3], PlanarError> {
    let mut q = [mach, alpha_deg, alt];
    for (v, axis) in q
        .iter_mut()
        .zip([Axis::Mach, Axis::AlphaDeg, Axis::AltitudeM])
    {
        let a = t.axis(axis);
        let (lo, hi) = (a[0], a[a.len() - 1]);
        if (*v < lo || *v > hi) && t.policy() == OutOfRange::Stop {
            return Err(PlanarError::TableRange {
                axis: axis.to_string(),
                value: *v,
                min: lo,
                max: hi,
            });
        }
        *v = v.clamp(lo, hi);
    }
    Ok(q)
}

/// Mach points of the central difference, kept inside the table's Mach axis.
fn mach_stencil(t: &CoefficientTable, m: f64) -> (f64, f64) {
    let a = t.axis(Axis::Mach);
    let (lo, hi) = (a[0], a[a.len() - 1]);
    ((m - MACH_STEP).clamp(lo, hi), (m + MACH_STEP).clamp(lo, hi))
}
