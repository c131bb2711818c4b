//! The built-in coefficient estimator, used when a vehicle gives no tables (`aero builtin`).
//! It produces a body and a fin [`CoefficientTable`] on a fixed grid and can write them in the
//! CSV layout of [`super::tables`], so users can inspect and replace them.
//!
//! Body (coefficients on the reference area S = pi d^2/4, lengths in calibres of d):
//! - normal force, Jorgensen (NASA TR R-474, 1973, eq. 1) with base area = S:
//!   C_N = sin(2 alpha) cos(alpha/2) [nose, potential, slender-body C_Nalpha = 2 /rad]
//!   plus eta C_dc (A_p/S) sin^2 alpha [viscous crossflow], C_dc = 1.2 (subcritical
//!   circular cylinder), eta = 1 (Allen's crossflow analogy without Jorgensen's finite-length
//!   factor, which he tabulates as about 0.6-0.75; replace the table for better values).
//!   A tube (no nose) has no potential term.
//! - potential term at the nose centre of pressure: for any nose closed at the tip whose base
//!   is the body's, slender-body theory gives C_Nalpha = 2 (A_base/S) = 2 /rad and the
//!   centre of pressure x_cp = L - V/A_base aft of the tip (V the nose volume; Barrowman
//!   1967; Niskanen 2009, sec. 3.2.1: X_B = (l A(l) - V)/(A(l) - A(0)) with A(0) = 0 for a
//!   closed tip): 2/3 of the nose length for the cone, the profile's volume by quadrature
//!   for the other shapes of `check::nose`; crossflow term at the planform centroid (the
//!   nose's side view by quadrature).
//! - C_M = sum C_N,part (x_part - x_ref)/b_b about the reference point (5.3.3), positive
//!   nose up (x forward, so a force ahead of the c.g. pitches the nose up).
//! - the grid's angles of attack span every flow direction, -180..180 deg
//!   ([`estimator_alpha`]): the normal-force terms above are Jorgensen's for 0..180 deg (they
//!   vanish at 180 deg, the flow along the axis from behind);
//! - axial force C_A: the zero-lift value below times Niskanen's scaling with the angle of
//!   attack ([`axial_scaling`]: 1.3 at 17 deg, 0 at 90 deg, reversed beyond, so that it
//!   opposes air from behind); the zero-lift value:
//!   - skin friction by Reynolds number and surface roughness (Niskanen 2009, sec. 3.4.1;
//!     OpenRocket technical documentation, `doc/techdoc/chapter-aerodynamic-properties.tex`,
//!     "Skin friction drag"; [`skin_friction`]): the fully turbulent flat plate
//!     C_f = 1/(1.50 ln Re - 5.6)^2 (its value at Re = 1e4 below it), and above the critical
//!     Reynolds number R_crit = 51 (R_s/L)^-1.039 the roughness-limited C_f = 0.032
//!     (R_s/L)^0.2 (R_s the roughness height of `aero { finish }`, OpenRocket's named finishes
//!     [`FINISHES`], default regular paint 60 um); compressibility factors 1 - 0.1 M^2
//!     subsonic for both, supersonic 1/(1 + 0.15 M^2)^0.58 turbulent and 1/(1 + 0.18 M^2)
//!     roughness-limited, linear in Mach on 0.9..1.1 as OpenRocket's `BarrowmanCalculator`
//!     applies them; the larger of the two corrected values (the source: the roughness value
//!     is not used where it is below the turbulent one). Re and R_s/L on the body length;
//!     times wetted area / S and the body's cylindrical correction 1 + 1/(2 f_B), f_B = length
//!     / largest diameter ([`body_friction_correction`]);
//!   - base drag (Niskanen 2009, eq. 3.94, after Hoerner): 0.12 + 0.13 M^2 for M < 1,
//!     0.25/M above;
//!   - cone nose wave drag above Mach 1 (Fleeman, "Tactical Missile Design", 2nd ed., 2006,
//!     sharp-cone fit): (1.59 + 1.83/M^2) [atan(0.5/(L_n/d))]^1.69 (angle in rad); ramped
//!     linearly from 0 at M = 0.9 to its M = 1.2 value (our transonic blend). An ogive
//!     takes the cone's of equal length and base times (0.72 (k - 0.5)^2 + 0.82) (Niskanen
//!     2009, App. B.4 and B.5, after the Handbook of Supersonic Aerodynamics, p. 239: the
//!     tangent ogive k = 1 about the cone's, the secant ogive k = 0.5 18 % below it, at Mach
//!     1.6-2.5 and nose fineness 2-3.5); the other shapes (elliptical, parabolic, power,
//!     Haack) Stoney's measured pressure drag at fineness 3 (NASA TR R-100, 1961, as
//!     OpenRocket transcribes it) interpolated in the shape parameter and carried to the
//!     nose's fineness as Niskanen 2009, App. B ("Ellipsoidal, power, parabolic and Haack
//!     series nose cones"), does ([`nose_pressure_drag`]; no blend of
//!     ours: the data start below Mach 1);
//!   - skin friction's wetted area: the nose's true surface (`NoseShape::wetted_area`);
//!   - launch lugs and rail buttons (`body { launch_lug { } rail_button { } }`) as OpenRocket
//!     24.12 computes them ([`launch_guide_drag`]): a lug's frontal annulus `0.7 (C_stag +
//!     C_base)` plus its bore's Darcy-Weisbach pressure loss with the Swamee-Jain friction
//!     factor; a button's cross-flow cylinder drag (Gowen & Perkins, NACA TN 2960) at the mean
//!     Mach over its height in the turbulent boundary layer, times C_stag, on its side area.
//!
//! Fins (per fin, on S, alpha = the fin's own angle of attack):
//! - subsonic, Barrowman (1967) / Diederich: C_Nalpha = 2 pi A (A_f/S) / (2 + sqrt(4 +
//!   (beta A / cos Lambda_c)^2)), beta = sqrt|1 - M^2|, A = 2 s^2/A_f (the two-panel aspect
//!   ratio of a fin and its mirror image), Lambda_c the mid-chord sweep;
//! - supersonic (M >= [`FIN_SUPERSONIC_FROM`] = 1.1), the steady supersonic lifting surface
//!   of `panel::supersonic` (linear theory with the fin's leading-edge, tip and trailing-edge
//!   Mach cones, valid for subsonic and supersonic leading edges; [`FIN_LATTICE`] panels,
//!   extrapolated): C_Nalpha (A_f/S) and its centre of pressure. Two-dimensional Ackeret
//!   theory, 4/sqrt(M^2 - 1), which this replaced, is its limit for a supersonic leading edge
//!   and a large beta A; for a subsonic leading edge or a small beta A it over-predicts
//!   (K_T(B) C_Nalpha 14.0 /rad against 6.54 on S for the issue-33 fin at M 1.2,
//!   docs/validation.md);
//! - transonic: linear in Mach between the subsonic value at M = 0.9 and the supersonic
//!   value at M = 1.1 (our blend). The limits are those of linear theory for thin fins:
//!   the transonic similarity parameter |M^2 - 1| / ((gamma + 1) tau M^2)^(2/3) (Spreiter;
//!   Anderson, *Modern Compressible Flow*, 3rd ed., 11.x) must be of order 1 or more; for
//!   tau = t/c = 0.05 it is 1.0 at M = 0.90 and 0.97 at M = 1.1;
//! - body-fin interference K_T(B) = 1 + r/(s + r) (Barrowman), multiplying C_N;
//! - C_N = K_T(B) C_Nalpha alpha (alpha in rad; linear, as (5.4.6)) up to the stall at 20 deg,
//!   held at its stall value to 90 deg and mirrored, `C_N(alpha) = C_N(180 deg - alpha)`,
//!   for air from the trailing edge ([`fin_incidence`]); C_A times [`axial_scaling`] at the
//!   fin's own angle of attack;
//! - centre of pressure aft of the root leading edge: subsonic Barrowman
//!   x_f = x_t/3 (c_r + 2 c_t)/(c_r + c_t) + (c_r + c_t - c_r c_t/(c_r + c_t))/6, i.e. the
//!   quarter point of the mean aerodynamic chord; supersonic the lifting surface's centre of
//!   pressure; blended linearly on 0.9..1.1 like C_Nalpha;
//! - C_A: skin friction on both faces (2 A_f / S) with the body's C_f, at the rocket's
//!   Reynolds number and relative roughness R_s/L (L the body length), as the source gives it:
//!   one C_f for the whole wetted area (Niskanen 2009, sec. 3.4.1, eq. of (C_D)_friction;
//!   OpenRocket's `calculateFrictionCD`). The fin's own chord would be the flat plate its
//!   boundary layer grows on, and issue 34 asked for it; measured (dev build, same binary,
//!   the fins' Re and R_s on c_mac instead): Bella Lui 1107 m against OpenRocket's 1190 m
//!   (-7.0 %) instead of 1137 m (-4.4 %), the simple model rocket's C6 304.1 m against
//!   316.6 m (-3.9 %) instead of 315.4 m (-0.4 %): for 0.15 m fins on a 2 m rocket at
//!   75 m/s, regular paint, C_f 0.0067 on the chord against 0.0040 on the length (both
//!   roughness-limited), a fin drag the OpenRocket comparisons do not bear out. Corrected
//!   for the fin's thickness t by (1 + 2 t / c_mac) (Niskanen 2009, sec. 3.4.2,
//!   OpenRocket's `FinSetCalc`); plus the pressure drag of its edges on the frontal area t s
//!   (Niskanen 2009, sec. 3.4.4, after Barrowman 1967 pp. 48-57 and Hoerner, *Fluid-Dynamic
//!   Drag*, 1965): the leading edge, `0.85 q_stag/q` for a square edge (the blunt cylinder,
//!   Niskanen App. B.1: q_stag/q = 1 + M^2/4 + M^4/40 below Mach 1, 1.84 - 0.76/M^2 +
//!   0.166/M^4 + 0.035/M^6 above) or Barrowman's rounded edge ((1 - M^2)^-0.417 - 1 below
//!   Mach 0.9, 1 - 1.785 (M - 0.9) to Mach 1, 1.214 - 0.502/M^2 + 0.1095/M^4 above), times
//!   cos^2 Gamma_L (Gamma_L the leading-edge sweep; Hoerner's cross-flow principle); the
//!   trailing edge, the body's base drag for a square edge, half of it for a rounded one,
//!   zero for an airfoil's tapering edge; and the supersonic thickness wave drag of the
//!   `airfoil` section, taken as biconvex, on the planform area A_f
//!   ([`thickness_wave_drag`]): Ackeret's `(16/3) tau^2 / sqrt(M^2 - 1)` with simple sweep
//!   theory, `(16/3) tau^2 cos Lambda_c / sqrt(M^2 cos^2 Lambda_c - 1)` (tau = t/c_mac, derived
//!   in the function's doc), zero below a normal Mach of 1, ramped from 0 at M_n = 1 to its
//!   value where linear theory becomes valid (transonic similarity parameter 1); the square
//!   and rounded sections' faces are parallel to the flow and have no thickness drag beyond
//!   their edges' (Niskanen leaves the supersonic fin wave drag open, sec. 3.4.4). Without a profile (`EstimatedTables::estimate`) the fin is a flat plate of no
//!   thickness: friction only.
//!
//! Rate derivatives (the optional `cn_q`, `cm_q` columns of the body table, used by
//! `body_aero { rate_terms = true }`; see [`body_rate_derivatives`] for the derivation):
//! - conventions: per radian of the non-dimensional rate `ω b_b/(2V)` with `b_b = d`, moments
//!   about the coefficient reference point (x_ref) and nose-up positive as C_M above, the
//!   rotation taken about x_ref with the angle of attack at x_ref held fixed; each column is
//!   the sum of the q and α̇ derivatives (C_Nq + C_Nα̇, C_mq + C_mα̇), because the α̇ of the
//!   thesis (5.3.22) is the kinematic rate of the flow direction in the rotating key-node
//!   frame, which equals the pitch rate q when the flight path does not turn;
//! - body potential part, slender-body (Munk) momentum theory, Mach independent:
//!   `C_Nq + C_Nα̇ = 4 (A_b (l - s_r) + Vol)/(S d)`, `C_mq + C_mα̇ = -4 A_b (l - s_r)²/(S d²)`
//!   (`s_r` the reference point's distance aft of the nose, A_b the base area, Vol the body
//!   volume);
//! - body viscous part, Allen's crossflow term of the static C_N above differentiated along
//!   the body: `C_Nq = 4 C_dc |sin α| cos α ∫ d(s)(s - s_r) ds/(S d)`,
//!   `C_mq = -4 C_dc |sin α| cos α ∫ d(s)(s - s_r)² ds/(S d²)` (zero at α = 0);
//! - fins, for reference and checks ([`fin_rate_derivatives`]; NOT in the body table): the
//!   pitch rate changes each fin's angle of attack by `q l_f/V` at the arm `l_f` of its centre
//!   of pressure aft of x_ref (Barrowman 1967 lift slopes at the fin moment arm, the damping
//!   sum of Mandell, Caporaso & Bengen, "Topics in Advanced Model Rocketry", 1973):
//!   `C_Nq = 2 n_eff K_T(B) C_Nα,1 l_f/d`, `C_mq = -2 n_eff K_T(B) C_Nα,1 (l_f/d)²`. The runtime's
//!   fin block already carries this effect through the velocity of the fin (5.4.8), so
//!   adding it to the body table would count it twice.
//!
//! Transitions and boat tails (`check::transition`, issue 34): the reference length is then
//! the largest diameter (S = pi b_b^2/4 on it), the nose's potential slope 2 A_base/S; each
//! transition adds Barrowman's `C_Nalpha = 2 (A_aft - A_fore)/S` (negative on a boat tail) at
//! `X = (l A(l) - V)/(A(l) - A(0))` aft of its fore end (Barrowman 1967, sec. 3, eq. 3-36 ff.;
//! Niskanen 2009, sec. 3.2.1; `TransitionGeom::potential`), with the nose's alpha dependence
//! `sin 2alpha cos(alpha/2)`, whose slope at 0 is 2; its side view to the crossflow planform
//! and its surface to the wetted area; base drag on the aft end's area; a boat tail's
//! pressure drag from the base drag (Niskanen 2009, sec. 3.4.3, as OpenRocket's
//! `SymmetricComponentCalc` computes it: the base drag coefficient on the frontal area
//! A_fore - A_aft, times 1 up to the fineness l/(d_fore - d_aft) = 1, (3 - l/(d_fore -
//! d_aft))/2 up to 3, 0 beyond); a widening transition the sharp cone's wave drag above at
//! its own half-angle on its frontal area; rate derivatives with A_b the aft end's area.
//! Fins take the body radius under their root chord for K_T(B) and their root.
//!
//! Further fin sets (`fins NAME`, issue 34; [`RigidFinSet`], [`fin_set_coefficients`]) are
//! rigid and part of the BODY table: each adds `n_eff K_T(B) C_Nalpha,1 alpha` with
//! `n_eff = N/2` (the pitch-plane sum of its fins, exact for three or more evenly spaced)
//! at its centre of pressure (the same slope and centre of pressure as the fins above, its
//! own planform and body radius), N times one fin's C_A (the same friction, edge pressure and
//! thickness wave drag, its own thickness and cross-section), and to the rate columns its
//! pitch damping ([`fin_rate_derivatives`] with `n_eff`; it has no fin block to carry it).
//! Their roll: the forcing of their cant and their roll damping, in the body table's roll
//! columns `cl_0`, `cl_p` ([`fin_set_roll`]; written only for a vehicle with further sets).
//! No interference between sets (a canard's downwash on the fins behind it), as in
//! OpenRocket ([`fin_set_coefficients`]). The fin table stays the unnamed set's.
//!
//! The thesis itself used Missile DATCOM tables (5.5); these are simple engineering methods.

use std::path::Path;

use crate::check::ir::OutOfRange;

use super::tables::{CoefficientTable, TableError, TableKind};

/// Nose shape of the body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NoseShape {
    /// A plain tube (no nose).
    Tube,
    /// A sharp cone of the given length, m.
    Cone { length: f64 },
    /// A nose of another profile (`check::nose`: ogive, elliptical, parabolic, power, Haack)
    /// of the given length, m, closed at the tip, its base the body's diameter.
    Profile {
        length: f64,
        shape: crate::check::ir::NoseShape,
    },
}

/// Body of revolution for the estimator.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyShape {
    /// Overall length, m.
    pub length: f64,
    /// Diameter of the nose's base and of the tube behind it up to the first transition, m;
    /// with no transitions also the reference length b_b.
    pub diameter: f64,
    pub nose: NoseShape,
    /// Coefficient reference point (nominal c.g.) body x, m (<= 0; x forward from the nose).
    pub reference_x: f64,
    /// Transitions and boat tails, fore to aft (`check::transition`).
    pub transitions: Vec<crate::check::transition::TransitionGeom>,
    /// Surface roughness height R_s of the body and fins, m (`aero { finish }`; OpenRocket's
    /// default [`DEFAULT_ROUGHNESS`]).
    pub roughness: f64,
    /// Launch lugs and rail buttons on the body ([`launch_guide_drag`]).
    pub guides: Vec<LaunchGuide>,
    /// Further, rigid fin sets (`fins NAME`, issue 34): part of the body's coefficients
    /// ([`fin_set_coefficients`]).
    pub fin_sets: Vec<RigidFinSet>,
}

/// A further, rigid fin set of the body (`fins NAME`): its planform (body radius under its
/// root), thickness and cross-section, fin count, and the body x of its root leading edge.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidFinSet {
    pub planform: FinPlanform,
    pub profile: FinProfile,
    pub count: usize,
    /// Body x of the root leading edge, m (<= 0).
    pub root_le_x: f64,
    /// Cant angle, rad (`fins { cant }`; the sign convention of the unnamed set's).
    pub cant: f64,
}

impl RigidFinSet {
    /// A further set of the checked vehicle on the body `b` (`planform` with the body radius
    /// under its root chord).
    pub fn of(f: &crate::check::ir::Fins, b: &crate::check::ir::BodyGeometry) -> Self {
        RigidFinSet {
            planform: planform(f, b.radius_under(f)),
            profile: FinProfile {
                thickness: f.thickness.value,
                section: f.cross_section.value,
            },
            count: f.count.value,
            root_le_x: f.root_trailing_edge_x.value + f.root_chord.value,
            cant: f.cant.value,
        }
    }

    /// The pitch-plane count `n_eff = N/2`: the fin at roll angle delta from the plane of the
    /// angle of attack sees `alpha cos delta` and puts the share `cos delta` of its normal
    /// force into that plane, and `sum_i cos^2(phi + delta_i) = N/2` for any roll phi when
    /// N >= 3 fins are evenly spaced (Barrowman 1967; as [`super::static_margin`] sums the
    /// unnamed set). For one or two fins, or uneven angles, it is the average over roll of
    /// that sum (N/2 for any angles: the mean of cos^2 is 1/2); the body table is a body of
    /// revolution's (no roll, no side force), so the roll dependence is not represented.
    pub fn pitch_plane_count(&self) -> f64 {
        0.5 * self.count as f64
    }
}

/// The coefficients a further, rigid fin set adds to the body's (C_N, C_A, C_M on the
/// reference area `s_ref` and length `d_ref`, moment about `reference_x`) at one condition,
/// with its `(slope on A_f, x_cp)` at this Mach (`FinPlanform::linear`) computed by the
/// caller. The unnamed set's methods, reused: C_N = n_eff K_T(B) C_Nalpha,1 alpha
/// ([`RigidFinSet::pitch_plane_count`], Barrowman's K_T(B) at the body radius under its root)
/// at the centre of pressure `x_le,root - x_cp`; C_A = N times one fin's axial coefficient
/// ([`fin_axial`]: friction, edge pressure drag by cross-section, thickness wave drag), at
/// the rocket's Reynolds number as the unnamed set's. The sets do not interfere with each
/// other's flow: a forward set's downwash on the sets behind it is not modelled. That is
/// OpenRocket's model (Niskanen 2009, sec. 3.2, OpenRocket's `doc/techdoc/
/// chapter-aerodynamic-properties.tex`, read): Barrowman's method computes the normal force
/// and centre of pressure of each component separately and combines them, with the
/// body-fin interference as its only correction term, and its fin-fin interference factor
/// counts only the parallel fins of one set (N_tot). That factor for more than four fins
/// (0.948 to 0.750, after MIL-HDBK-762) is not applied here, as it is not for the unnamed set.
#[allow(clippy::too_many_arguments)]
pub fn fin_set_coefficients(
    set: &RigidFinSet,
    (slope, x_cp): (f64, f64),
    (roughness, rocket_length): (f64, f64),
    (s_ref, d_ref, reference_x): (f64, f64, f64),
    mach: f64,
    alpha_deg: f64,
    altitude_m: f64,
) -> [f64; 3] {
    let f = &set.planform;
    let cn = set.pitch_plane_count() * f.interference() * slope * f.area() / s_ref
        * fin_incidence(alpha_deg);
    let ca = axial_scaling(alpha_deg)
        * set.count as f64
        * fin_axial(
            f,
            Some(set.profile),
            roughness,
            rocket_length,
            s_ref,
            mach,
            altitude_m,
        );
    let x = set.root_le_x - x_cp;
    [cn, ca, cn * (x - reference_x) / d_ref]
}

/// The roll coefficients `[cl_0, cl_p]` a further, rigid fin set adds to the body table's
/// roll columns (`aero::tables` module doc), with its `slope` (normal-force slope of one fin
/// on its own area A_f, per rad, at this Mach: `FinPlanform::linear`), on the reference area
/// `s_ref` and length `d_ref`.
///
/// Forcing (Niskanen 2009, sec. 3.6.1, eq. (3.69), read in OpenRocket's
/// `doc/techdoc/chapter-aerodynamic-properties.tex`): the cant delta is an angle of attack of
/// every fin, whose normal force acts at the mean aerodynamic chord's span station, so
/// `C_lf = N (y_MAC + r_t) (C_Nalpha)_1 delta / d` with `(C_Nalpha)_1 = slope A_f / S`,
/// `y_MAC = (1/A_f) ∫ y c dy` ([`FinPlanform::y_mac`]) and `r_t` the body radius at the set.
/// No body-fin interference factor, as the equation is published; OpenRocket's code
/// (`FinSetCalc`) multiplies it by `1 + tau`, `tau = r_t/(s + r_t)`.
///
/// Damping (Niskanen 2009, sec. 3.6.2, eq. (3.71)): a strip at `xi = r_t + y` of a fin
/// rolling at `p` sees the angle of attack `p xi / V`, so the fins' moment is
/// `-N q k (p / V) ∫ c xi^2 dy` with `k` the strips' lift slope, and
/// `C_ld = N k (p/V) I_2 / (S d)`, `I_2 = ∫ c (r_t + y)^2 dy` ([`FinPlanform::roll_integral`]).
/// Niskanen takes `k` the two-dimensional slope `2 pi / beta` below Mach 1 (and the first
/// term of the supersonic strip pressure above), with a linear blend through the transonic
/// band in OpenRocket's code; here `k` is the fin's own three-dimensional slope `slope`, the
/// one the forcing and the pitch-plane normal force take. Derivation of the choice: strip
/// theory's loading is proportional to the local chord times the section slope, and scaling
/// it so that the fin's total lift per unit angle is the fin's known slope keeps forcing and
/// damping on one lift model (the two-dimensional slope overstates a low-aspect-ratio fin's
/// damping by `2 pi / slope`, 2 to 3 for rocket fins); the equilibrium roll rate, forcing =
/// damping, is then `p_eq = V delta (y_MAC + r_t) A_f / I_2`, independent of the slope and of
/// Mach, which is Niskanen's eq. (3.73) where his slopes agree. Per `p_hat = p d/(2V)`:
/// `cl_p = -2 N slope I_2 / (S d^2)`. Both are linear in the cant and the rate: the stall of
/// the tips at a large roll rate (OpenRocket clips the strip's angle at 15 deg) is not
/// modelled.
pub fn fin_set_roll(set: &RigidFinSet, slope: f64, s_ref: f64, d_ref: f64) -> [f64; 2] {
    let f = &set.planform;
    let n = set.count as f64;
    let cl_0 = n * (f.y_mac() + f.body_radius) * slope * f.area() / s_ref * set.cant / d_ref;
    let cl_p = -2.0 * n * slope * f.roll_integral() / (s_ref * d_ref * d_ref);
    [cl_0, cl_p]
}

/// A launch lug or rail button on the body, for its drag ([`launch_guide_drag`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LaunchGuide {
    /// A tube along the body: length, outer and inner (bore) diameter, m.
    Lug {
        length: f64,
        outer_diameter: f64,
        inner_diameter: f64,
    },
    /// A rail button: its distance aft of the nose tip, its outer diameter and total height
    /// above the body, and the notch's (inner) diameter and height (0 and 0: a plain pin), m.
    Button {
        from_tip: f64,
        outer_diameter: f64,
        height: f64,
        inner_diameter: f64,
        inner_height: f64,
    },
}

/// The blunt cylinder's pressure drag on its frontal area, `0.85 q_stag/q` (Niskanen 2009,
/// App. B.1; OpenRocket's `BarrowmanCalculator.calculateStagnationCD`).
pub fn stagnation_drag(mach: f64) -> f64 {
    0.85 * stagnation_pressure_ratio(mach)
}

/// Rail button drag coefficient of a circular cylinder in cross flow against Mach, as
/// OpenRocket 24.12 transcribes it (`RailButtonCalc`, "from Gowen and Perkins, Drag of
/// Circular Cylinders for a Wide Range of Reynolds Numbers and Mach Numbers, NACA TN 2960,
/// Figure 7"; we have read OpenRocket's transcription, not the report): (Mach, C_D),
/// interpolated linearly.
pub const CYLINDER_CROSSFLOW_CD: [(f64, f64); 12] = [
    (0.0, 1.2),
    (0.2, 1.22),
    (0.3, 1.25),
    (0.4, 1.3),
    (0.5, 1.4),
    (0.6, 1.5),
    (0.7, 1.6),
    (1.0, 2.1),
    (1.6, 1.5),
    (2.0, 1.45),
    (2.8, 1.33),
    (100.0, 1.33),
];

fn cylinder_crossflow_cd(m: f64) -> f64 {
    let t = &CYLINDER_CROSSFLOW_CD;
    let m = m.clamp(t[0].0, t[t.len() - 1].0);
    let i = t
        .iter()
        .position(|p| p.0 >= m)
        .unwrap_or(t.len() - 1)
        .max(1);
    let (a, b) = (t[i - 1], t[i]);
    a.1 + (b.1 - a.1) * (m - a.0) / (b.0 - a.0)
}

/// The axial coefficient of a launch lug or rail button on the reference area `s_ref`, at
/// Mach `mach` with the air's speed of sound `sound`, m/s, and kinematic viscosity `nu`,
/// m^2/s, on a surface of roughness `roughness`, m. As OpenRocket 24.12 computes them (read in
/// its source at commit 8fa969d8; its technical documentation, sec. "Parasitic drag",
/// still describes the older model of Niskanen 2009, sec. 3.4.6, `max(1.3 - 0.3 l/d, 1)
/// C_stag` on `pi r_o^2 - pi r_i^2 max(1 - l/d, 0)`):
/// - a lug (`TubeCalc`): the pressure drag `0.7 (C_stag + C_base)` on its frontal annulus
///   `pi (r_o^2 - r_i^2)` ([`stagnation_drag`], [`base_drag`]) plus the pressure loss of the
///   flow through its bore, Darcy-Weisbach `Delta p = f (l/d_i) rho v^2/2` on the bore's
///   area, i.e. `C_D = f l/d_i` on `pi r_i^2`, with the Swamee-Jain friction factor
///   `f = 0.25/[log10(eps/(3.7 d_i) + 5.74/Re^0.9)]^2` (Swamee & Jain, *J. Hydraulics Div.
///   ASCE* 102, 1976), `Re = v d_i/nu`, eps the surface roughness;
/// - a button (`RailButtonCalc`): the cross-flow cylinder's C_D ([`CYLINDER_CROSSFLOW_CD`])
///   at the mean Mach over its height in the body's boundary layer, whose thickness is the
///   turbulent flat plate's `delta = 0.37 x Re_x^-0.2` at its distance x from the tip
///   (linear velocity profile: mean Mach `(h - delta/2) M/h` when it stands out of the
///   layer, `(h/2)/delta M` inside), times `(M_mean/M)^2` (the force on the free stream's
///   dynamic pressure) and [`stagnation_drag`], on its side area `h d_o - (d_o - d_i) h_i`.
///
/// The Reynolds numbers are taken at `max(M, FRICTION_REYNOLDS_MIN_MACH)`, like the skin
/// friction's, so the tables start at Mach 0 with the values of Mach 0.1.
pub fn launch_guide_drag(
    g: &LaunchGuide,
    roughness: f64,
    s_ref: f64,
    mach: f64,
    sound: f64,
    nu: f64,
) -> f64 {
    let pi = std::f64::consts::PI;
    let m = mach.max(FRICTION_REYNOLDS_MIN_MACH);
    let v = m * sound;
    match *g {
        LaunchGuide::Lug {
            length,
            outer_diameter,
            inner_diameter,
        } => {
            let (ro, ri) = (0.5 * outer_diameter, 0.5 * inner_diameter);
            let frontal = pi * (ro * ro - ri * ri);
            let pressure = 0.7 * (stagnation_drag(mach) + base_drag(mach)) * frontal;
            let bore = if inner_diameter > 0.0 {
                let re = v * inner_diameter / nu;
                let f = 0.25
                    / (roughness / (3.7 * inner_diameter) + 5.74 / re.powf(0.9))
                        .log10()
                        .powi(2);
                f * length / inner_diameter * pi * ri * ri
            } else {
                0.0
            };
            (pressure + bore) / s_ref
        }
        LaunchGuide::Button {
            from_tip,
            outer_diameter,
            height,
            inner_diameter,
            inner_height,
        } => {
            let area = height * outer_diameter - (outer_diameter - inner_diameter) * inner_height;
            let x = from_tip.max(1e-6);
            let re_x = v * x / nu;
            let delta = 0.37 * x / re_x.powf(0.2);
            let ratio = if height > delta {
                (height - 0.5 * delta) / height
            } else {
                0.5 * height / delta
            };
            let cd = cylinder_crossflow_cd(ratio * mach) * ratio * ratio;
            cd * stagnation_drag(mach) * area / s_ref
        }
    }
}

impl BodyShape {
    /// The reference length b_b and diameter of the reference area S = pi b_b^2/4: the
    /// largest diameter of the body (the diameter when it has one).
    pub fn reference_diameter(&self) -> f64 {
        crate::check::transition::max_diameter(self.diameter, &self.transitions)
    }

    /// The outer radius of the aft end.
    pub fn base_radius(&self) -> f64 {
        self.transitions
            .last()
            .map_or(0.5 * self.diameter, |t| t.r_aft)
    }
}

/// A fin planform: a trapezoid, or any outline of `check::fin_outline` (issue 34), whose
/// `root_chord`, `tip_chord` and `tip_le_offset` are then those of the equivalent trapezoid
/// (same span, root chord, area and leading edge of the mean aerodynamic chord) and whose
/// [`FinPlanform::le_at`], [`FinPlanform::chord_at`], area, mean aerodynamic chord and
/// mid-chord sweep follow the true edges (Niskanen 2009, sec. 3.2.2).
#[derive(Clone, Debug, PartialEq)]
pub struct FinPlanform {
    /// Span s (root to tip), m.
    pub span: f64,
    pub root_chord: f64,
    pub tip_chord: f64,
    /// Chordwise distance from the root leading edge back to the tip leading edge, m
    /// (x_t = s tan Lambda_LE; root minus tip chord for an unswept trailing edge).
    pub tip_le_offset: f64,
    /// Body radius at the fins, m.
    pub body_radius: f64,
    /// The outline (trapezoidal: the fields above).
    pub outline: crate::check::ir::FinOutline,
}

impl FinPlanform {
    /// A planform with unswept trailing edge (as App. A.2.6 assumes).
    pub fn unswept_trailing_edge(
        span: f64,
        root_chord: f64,
        tip_chord: f64,
        body_radius: f64,
    ) -> Self {
        FinPlanform {
            span,
            root_chord,
            tip_chord,
            tip_le_offset: root_chord - tip_chord,
            body_radius,
            outline: crate::check::ir::FinOutline::Trapezoidal,
        }
    }

    /// The true edges (`check::fin_outline`).
    pub fn edges(&self) -> crate::check::fin_outline::Edges<'_> {
        crate::check::fin_outline::Edges {
            outline: &self.outline,
            span: self.span,
            root_chord: self.root_chord,
            tip_chord: self.tip_chord,
            tip_le_offset: self.tip_le_offset,
        }
    }

    /// Local chord at span fraction eta (linear taper for the trapezoid).
    pub fn chord_at(&self, eta: f64) -> f64 {
        if self.outline.is_trapezoidal() {
            self.root_chord + (self.tip_chord - self.root_chord) * eta
        } else {
            self.edges().chord(eta * self.span)
        }
    }

    /// The (equivalent) trapezoid's chord at span fraction eta: App. A's load distributions
    /// (`aero::fin_loads`) are derived for the trapezoid and take it for any outline.
    pub fn trapezoid_chord_at(&self, eta: f64) -> f64 {
        self.root_chord + (self.tip_chord - self.root_chord) * eta
    }

    /// Leading edge at span fraction eta, m aft of the root leading edge.
    pub fn le_at(&self, eta: f64) -> f64 {
        if self.outline.is_trapezoidal() {
            self.tip_le_offset * eta
        } else {
            self.edges().le(eta * self.span)
        }
    }

    /// Planform area A_f of one fin.
    pub fn area(&self) -> f64 {
        if self.outline.is_trapezoidal() {
            0.5 * (self.root_chord + self.tip_chord) * self.span
        } else {
            self.edges().area()
        }
    }

    /// Two-panel aspect ratio A = 2 s^2 / A_f.
    pub fn aspect_ratio(&self) -> f64 {
        2.0 * self.span * self.span / self.area()
    }

    /// tan of the semi-apex angle omega of the generating triangle of the leading edge
    /// (App. A.2.6): omega is the angle between the root chord and the leading edge,
    /// tan omega = s / x_t = cot Lambda_LE (infinite for an unswept or forward-swept leading
    /// edge). With an unswept trailing edge x_t = c_r - c_t, the thesis' s / (c_r - c_t).
    pub fn tan_semi_apex(&self) -> f64 {
        let d = self.tip_le_offset;
        if d <= 0.0 {
            f64::INFINITY
        } else {
            self.span / d
        }
    }

    /// Chordwise distance from the root trailing edge back to the tip trailing edge, m:
    /// s tan Lambda_TE = x_t - (c_r - c_t) (0 for an unswept trailing edge, negative for a
    /// trailing edge swept forward).
    pub fn te_offset(&self) -> f64 {
        self.tip_le_offset - (self.root_chord - self.tip_chord)
    }

    /// Mid-chord sweep angle Lambda_c, rad; for another outline the angle whose cosine is
    /// the span average of the local mid-chord line's (Niskanen 2009, sec. 3.2.2).
    pub fn mid_chord_sweep(&self) -> f64 {
        if !self.outline.is_trapezoidal() {
            return self.edges().cos_mid_chord_sweep().clamp(-1.0, 1.0).acos();
        }
        ((self.tip_le_offset + 0.5 * self.tip_chord - 0.5 * self.root_chord) / self.span).atan()
    }

    /// Mean aerodynamic chord and its leading-edge offset aft of the root leading edge:
    /// Barrowman's closed forms for the trapezoid, `(1/A) ∫ c² dy` and `(1/A) ∫ x_le c dy`
    /// for another outline (Niskanen 2009, sec. 3.2.2; `check::fin_outline`).
    pub fn mean_aerodynamic_chord(&self) -> (f64, f64) {
        if !self.outline.is_trapezoidal() {
            return self.edges().mean_aerodynamic_chord();
        }
        let (cr, ct) = (self.root_chord, self.tip_chord);
        let mac = 2.0 / 3.0 * (cr + ct - cr * ct / (cr + ct));
        let x_le = self.tip_le_offset * (cr + 2.0 * ct) / (3.0 * (cr + ct));
        (mac, x_le)
    }

    /// Span station of the mean aerodynamic chord from the root, m: `y_MAC = (1/A_f) ∫ y c dy`
    /// (Niskanen 2009, sec. 3.2.2; for the trapezoid `s (c_r + 2 c_t) / (3 (c_r + c_t))`).
    pub fn y_mac(&self) -> f64 {
        if self.outline.is_trapezoidal() {
            let (cr, ct) = (self.root_chord, self.tip_chord);
            return self.span * (cr + 2.0 * ct) / (3.0 * (cr + ct));
        }
        let m = self.edges().moments();
        m[3] / m[0]
    }

    /// `I_2 = ∫_0^s c(y) (r_t + y)^2 dy`, m^4, the roll damping integral of one fin
    /// ([`fin_set_roll`]). The trapezoid and the ellipse in closed form (Niskanen 2009,
    /// sec. 3.6.2: `(c_r + c_t)/2 r^2 s + (c_r + 2 c_t)/3 r s^2 + (c_r + 3 c_t)/12 s^3`, and
    /// `c_r (pi/4 r^2 s + 2/3 r s^2 + pi/16 s^3)`); a polygon by Simpson's rule on each
    /// segment between its corners, exact there (the chord is linear on a segment, the
    /// integrand a cubic).
    pub fn roll_integral(&self) -> f64 {
        let (r, s) = (self.body_radius, self.span);
        let pi = std::f64::consts::PI;
        match self.outline {
            crate::check::ir::FinOutline::Trapezoidal => {
                let (cr, ct) = (self.root_chord, self.tip_chord);
                0.5 * (cr + ct) * r * r * s
                    + (cr + 2.0 * ct) / 3.0 * r * s * s
                    + (cr + 3.0 * ct) / 12.0 * s * s * s
            }
            crate::check::ir::FinOutline::Elliptical => {
                self.root_chord
                    * (0.25 * pi * r * r * s + 2.0 / 3.0 * r * s * s + pi / 16.0 * s * s * s)
            }
            crate::check::ir::FinOutline::Freeform { .. } => {
                let e = self.edges();
                let mut sum = 0.0;
                for w in e.breakpoints().windows(2) {
                    let (y0, y1) = (w[0], w[1]);
                    let g = |y: f64| e.chord(y) * (r + y) * (r + y);
                    sum += (y1 - y0) / 6.0 * (g(y0) + 4.0 * g(0.5 * (y0 + y1)) + g(y1));
                }
                sum
            }
        }
    }

    /// Per-fin normal-force slope on reference area `s_ref`, per rad, WITHOUT interference.
    pub fn cn_alpha(&self, mach: f64, s_ref: f64) -> f64 {
        self.linear(mach).0 * self.area() / s_ref
    }

    /// Body-fin interference factor K_T(B) = 1 + r/(s + r) (Barrowman).
    pub fn interference(&self) -> f64 {
        1.0 + self.body_radius / (self.span + self.body_radius)
    }

    /// Chordwise centre of pressure aft of the root leading edge, m: quarter MAC subsonic
    /// (equal to Barrowman's x_f), the supersonic lifting surface's from Mach 1.1, blended on
    /// 0.9..1.1.
    pub fn x_cp(&self, mach: f64) -> f64 {
        self.linear(mach).1
    }

    /// Subsonic Barrowman/Diederich slope on the fin's own area A_f, per rad.
    fn subsonic_slope(&self, m: f64) -> f64 {
        let beta = (1.0 - m * m).abs().sqrt();
        let a = self.aspect_ratio();
        let k = beta * a / self.mid_chord_sweep().cos();
        2.0 * std::f64::consts::PI * a / (2.0 + (4.0 + k * k).sqrt())
    }

    /// The steady supersonic lifting surface (`panel::supersonic`): normal-force slope on A_f
    /// per rad and centre of pressure (m aft of the root leading edge) at Mach `mach > 1`,
    /// Richardson-extrapolated from uniform `n x n` and `2n x 2n` lattices, `n` =
    /// [`FIN_LATTICE`] (the method converges at first order in the panel size, so
    /// `2 f(2n) - f(n)`; the force and the moment are extrapolated, the centre of pressure is
    /// their ratio). A pointed tip (c_t = 0, which the lattice cannot panel) is given the chord
    /// 1e-6 c_r: its load share is of that order. NaN when the planform cannot be panelled
    /// (non-finite or non-positive dimensions, refused by the checker), so the table
    /// constructor reports it.
    pub fn supersonic_lifting_surface(&self, mach: f64) -> (f64, f64) {
        use super::panel::{Lattice, Spacing, supersonic};
        let mut p = self.clone();
        if p.tip_chord == 0.0 && p.outline.is_trapezoidal() {
            p.tip_chord = 1e-6 * p.root_chord;
        }
        let at = |n: usize| {
            Lattice::new(&p, n, n, Spacing::Uniform)
                .and_then(|l| supersonic::slope_and_centre(&l, mach))
                .unwrap_or((f64::NAN, f64::NAN))
        };
        let (coarse, fine) = (at(FIN_LATTICE), at(2 * FIN_LATTICE));
        let slope = 2.0 * fine.0 - coarse.0;
        let moment = 2.0 * fine.0 * fine.1 - coarse.0 * coarse.1;
        (slope, moment / slope)
    }

    /// (slope on A_f per rad, x_cp) at Mach `mach`, blended on 0.9..1.1.
    fn linear(&self, mach: f64) -> (f64, f64) {
        let (mac, x_le) = self.mean_aerodynamic_chord();
        let sub = (
            self.subsonic_slope(mach.min(TRANSONIC_LO)),
            x_le + 0.25 * mac,
        );
        if mach <= TRANSONIC_LO {
            return sub;
        }
        let sup = self.supersonic_lifting_surface(mach.max(FIN_SUPERSONIC_FROM));
        if mach >= FIN_SUPERSONIC_FROM {
            return sup;
        }
        let t = (mach - TRANSONIC_LO) / (FIN_SUPERSONIC_FROM - TRANSONIC_LO);
        ((1.0 - t) * sub.0 + t * sup.0, (1.0 - t) * sub.1 + t * sup.1)
    }
}

/// Upper Mach of the subsonic branches.
const TRANSONIC_LO: f64 = 0.9;
/// Lower Mach of the fins' supersonic lifting surface in the built-in tables (the criterion
/// is in the module doc).
pub const FIN_SUPERSONIC_FROM: f64 = 1.1;
/// Panels per side of the coarse lattice of the supersonic lifting surface in the built-in
/// tables (extrapolated with the doubled lattice; within 1 % of the exact linear-theory slope
/// of a delta fin with a subsonic leading edge, `panel::supersonic_tests`).
pub const FIN_LATTICE: usize = 6;

/// Subsonic branch below M = 0.9, supersonic above 1.2, linear in Mach between their values
/// at 0.9 and 1.2 (the body's wave drag).
fn transonic_blend(mach: f64, sub: impl Fn(f64) -> f64, sup: impl Fn(f64) -> f64) -> f64 {
    const LO: f64 = TRANSONIC_LO;
    const HI: f64 = 1.2;
    if mach <= LO {
        sub(mach)
    } else if mach >= HI {
        sup(mach)
    } else {
        let t = (mach - LO) / (HI - LO);
        (1.0 - t) * sub(LO) + t * sup(HI)
    }
}

/// Zero-lift pressure drag of noses of fineness ratio 3 against Mach, (Mach, C_D on the base
/// area), from Stoney, "Collection of Zero-Lift Drag Data on Bodies of Revolution from
/// Free-Flight Investigations", NASA TR R-100, 1961, p. 16, as OpenRocket 24.12 transcribes
/// them (`SymmetricComponentCalc`; we have read OpenRocket's transcription, not the report):
/// the ellipsoid, the power series x^(1/4), x^(1/2), x^(3/4), the von Kármán and LV-Haack
/// noses, the parabola and the 1/2 and 3/4 parabolas. Linear between points, the end values
/// beyond them (OpenRocket's `LinearInterpolator`).
pub mod stoney {
    pub const ELLIPSOID: &[(f64, f64)] = &[
        (1.2, 0.110),
        (1.25, 0.128),
        (1.3, 0.140),
        (1.4, 0.148),
        (1.6, 0.152),
        (2.0, 0.159),
        (2.4, 0.162),
    ];
    pub const X14: &[(f64, f64)] = &[
        (1.2, 0.140),
        (1.3, 0.156),
        (1.4, 0.169),
        (1.6, 0.192),
        (1.8, 0.206),
        (2.2, 0.227),
        (2.6, 0.241),
        (3.0, 0.249),
        (3.6, 0.252),
    ];
    pub const X12: &[(f64, f64)] = &[
        (0.925, 0.0),
        (0.95, 0.014),
        (1.0, 0.050),
        (1.05, 0.060),
        (1.1, 0.059),
        (1.2, 0.081),
        (1.3, 0.084),
        (1.7, 0.085),
        (2.0, 0.078),
    ];
    pub const X34: &[(f64, f64)] = &[
        (0.8, 0.0),
        (0.9, 0.015),
        (1.0, 0.078),
        (1.06, 0.121),
        (1.2, 0.110),
        (1.4, 0.098),
        (1.6, 0.090),
        (2.0, 0.084),
        (2.8, 0.078),
        (3.4, 0.074),
    ];
    pub const VON_KARMAN: &[(f64, f64)] = &[
        (0.9, 0.0),
        (0.95, 0.010),
        (1.0, 0.027),
        (1.05, 0.055),
        (1.1, 0.070),
        (1.2, 0.081),
        (1.4, 0.095),
        (1.6, 0.097),
        (2.0, 0.091),
        (3.0, 0.083),
    ];
    pub const LV_HAACK: &[(f64, f64)] = &[
        (0.9, 0.0),
        (0.95, 0.010),
        (1.0, 0.024),
        (1.05, 0.066),
        (1.1, 0.084),
        (1.2, 0.100),
        (1.4, 0.114),
        (1.6, 0.117),
        (2.0, 0.113),
    ];
    pub const PARABOLIC: &[(f64, f64)] = &[
        (0.95, 0.0),
        (0.975, 0.016),
        (1.0, 0.041),
        (1.05, 0.092),
        (1.1, 0.109),
        (1.2, 0.119),
        (1.4, 0.113),
        (1.7, 0.108),
    ];
    pub const PARABOLIC_12: &[(f64, f64)] = &[
        (0.8, 0.0),
        (0.9, 0.016),
        (0.95, 0.042),
        (1.0, 0.100),
        (1.05, 0.126),
        (1.1, 0.125),
        (1.3, 0.100),
        (1.5, 0.090),
        (1.8, 0.088),
    ];
    pub const PARABOLIC_34: &[(f64, f64)] = &[
        (0.9, 0.0),
        (0.95, 0.023),
        (1.0, 0.073),
        (1.05, 0.098),
        (1.1, 0.107),
        (1.2, 0.106),
        (1.4, 0.089),
        (1.7, 0.082),
    ];

    /// Linear interpolation in a table, the end values beyond it.
    pub fn at(t: &[(f64, f64)], m: f64) -> f64 {
        if m <= t[0].0 {
            return t[0].1;
        }
        for w in t.windows(2) {
            if m <= w[1].0 {
                let (a, b) = (w[0], w[1]);
                return a.1 + (b.1 - a.1) * (m - a.0) / (b.0 - a.0);
            }
        }
        t[t.len() - 1].1
    }
}

/// OpenRocket's conical nose pressure drag on the base area (Niskanen 2009, App. B, the conical
/// nose; its
/// `SymmetricComponentCalc.calculateOgiveNoseInterpolator` with parameter 0), used here only
/// as the end of the power and parabolic series where Stoney's data stop: `sin phi` at Mach 1,
/// `2.1 sin^2 phi + 0.5 sin phi / sqrt(M^2 - 1)` from Mach 1.3, and between them the cubic
/// with those values and the slopes `4/(gamma + 1) (1 - 0.5 sin phi)` at Mach 1 and
/// `-1.1341 sin phi` at 1.3 (phi the cone's half-angle); below Mach 1 its Mach-1 value (the
/// constant extension of OpenRocket's table, which starts at Mach 1).
fn or_cone_pressure_drag(sin_phi: f64, m: f64) -> f64 {
    let (c1, c13) = (sin_phi, 2.1 * sin_phi * sin_phi + 0.6019 * sin_phi);
    if m >= 1.3 {
        return 2.1 * sin_phi * sin_phi + 0.5 * sin_phi / (m * m - 1.0).sqrt();
    }
    let m = m.max(1.0);
    let (d1, d13) = (4.0 / 2.4 * (1.0 - 0.5 * c1), -1.1341 * sin_phi);
    // Cubic Hermite on [1, 1.3].
    let h = 0.3;
    let t = (m - 1.0) / h;
    let (t2, t3) = (t * t, t * t * t);
    (2.0 * t3 - 3.0 * t2 + 1.0) * c1
        + (t3 - 2.0 * t2 + t) * h * d1
        + (-2.0 * t3 + 3.0 * t2) * c13
        + (t3 - t2) * h * d13
}

/// Transonic and supersonic pressure (wave) drag of an elliptical, parabolic-series,
/// power-series or Haack nose of fineness `f_n = L/d` on its base area (Niskanen 2009, App.
/// B, "Ellipsoidal, power, parabolic and Haack series nose cones" and "Summary of nose cone
/// drag calculation"; OpenRocket's
/// `SymmetricComponentCalc.calculateNoseInterpolator`): Stoney's fineness-3 curve of the shape
/// ([`stoney`]), linearly interpolated in the shape parameter between the tabulated shapes
/// (power n between the blunt cylinder (n = 0), 1/4, 1/2, 3/4 and the cone (n = 1); parabola
/// K between the cone (K = 0), 1/2, 3/4 and 1; Haack C between von Kármán (0) and LV-Haack
/// (1/3); C above 1/3, which OpenRocket does not take, the LV-Haack curve); then carried to
/// the nose's fineness by `C_0 (C_3/C_0)^(log_4 (f_n + 1))` with `C_0` the blunt cylinder's
/// [`stagnation_drag`]; below the first Mach of the curve, if its value there is 0.001 or
/// more, `a M^b + 0.8 sin^2 phi` fitted to its value and slope there (phi the joint angle at
/// the base from the profile's radius at 0.99 L, as OpenRocket takes it). OpenRocket tabulates
/// the result on its curves' Mach points and interpolates linearly; this evaluates it at the
/// Mach asked.
pub fn nose_pressure_drag(
    shape: crate::check::ir::NoseShape,
    f_n: f64,
    r: f64,
    l: f64,
    mach: f64,
) -> f64 {
    use crate::check::ir::NoseShape as S;
    let cone_sin = 1.0 / (1.0 + 4.0 * f_n * f_n).sqrt();
    let blunt = stagnation_drag;
    // The fineness-3 curve at Mach m, and the Mach where its tabulated part starts.
    let curve = |m: f64| -> f64 {
        let lerp = |a: f64, b: f64, p: f64| p * b + (1.0 - p) * a;
        match shape {
            S::Elliptical => stoney::at(stoney::ELLIPSOID, m),
            S::Power { n } if n <= 0.25 => lerp(blunt(m), stoney::at(stoney::X14, m), n * 4.0),
            S::Power { n } if n <= 0.5 => lerp(
                stoney::at(stoney::X14, m),
                stoney::at(stoney::X12, m),
                (n - 0.25) * 4.0,
            ),
            S::Power { n } if n <= 0.75 => lerp(
                stoney::at(stoney::X12, m),
                stoney::at(stoney::X34, m),
                (n - 0.5) * 4.0,
            ),
            S::Power { n } => lerp(
                stoney::at(stoney::X34, m),
                or_cone_pressure_drag(cone_sin, m),
                (n - 0.75) * 4.0,
            ),
            S::Parabolic { k } if k <= 0.5 => lerp(
                or_cone_pressure_drag(cone_sin, m),
                stoney::at(stoney::PARABOLIC_12, m),
                k * 2.0,
            ),
            S::Parabolic { k } if k <= 0.75 => lerp(
                stoney::at(stoney::PARABOLIC_12, m),
                stoney::at(stoney::PARABOLIC_34, m),
                (k - 0.5) * 4.0,
            ),
            S::Parabolic { k } => lerp(
                stoney::at(stoney::PARABOLIC_34, m),
                stoney::at(stoney::PARABOLIC, m),
                (k - 0.75) * 4.0,
            ),
            S::Haack { c } => lerp(
                stoney::at(stoney::VON_KARMAN, m),
                stoney::at(stoney::LV_HAACK, m),
                (c * 3.0).min(1.0),
            ),
            // Cones and ogives take the Fleeman fit (module doc); not called for them.
            S::Conical | S::Ogive { .. } => f64::NAN,
        }
    };
    // The first Mach of the blended curve: the smaller of its tables' first points (the blunt
    // cylinder's and the cone's start at 0 and 1).
    let first = match shape {
        S::Elliptical => 1.2,
        S::Power { n } if n <= 0.25 => 0.0,
        S::Power { n } if n <= 0.5 => 0.925,
        S::Power { n } if n <= 0.75 => 0.8,
        S::Power { .. } => 0.8,
        S::Parabolic { k } if k <= 0.5 => 0.8,
        S::Parabolic { k } if k <= 0.75 => 0.8,
        S::Parabolic { .. } => 0.9,
        S::Haack { .. } => 0.9,
        S::Conical | S::Ogive { .. } => 0.0,
    };
    let log4 = (f_n + 1.0).ln() / 4f64.ln();
    let scaled = |m: f64| {
        let stag = blunt(m);
        stag * (curve(m) / stag).powf(log4)
    };
    if mach >= first {
        return scaled(mach);
    }
    let v0 = scaled(first);
    if v0 < 0.001 {
        return 0.0;
    }
    let joint = {
        let rr = shape.radius(0.99 * l, r, l);
        (r - rr) / (r - rr).hypot(0.01 * l)
    };
    let cd0 = 0.8 * joint * joint;
    let deriv = (scaled(first + 0.01) - v0) / 0.01;
    if cd0 >= v0 - 0.01 || deriv <= 0.01 {
        // OpenRocket leaves the curve's first value below its first Mach then.
        return v0;
    }
    let b = first * deriv / (v0 - cd0);
    let a = (v0 - cd0) / first.powf(b);
    a * mach.powf(b) + cd0
}

/// Temperature K, density kg/m^3, speed of sound m/s and dynamic viscosity Pa s from the
/// runtime's U.S. Standard Atmosphere 1976 (thesis 4.5.1), for Reynolds numbers; the altitude
/// is clamped to the model's range (-0.5 km to 86 km), so the lookup cannot fail.
fn atmosphere(h: f64) -> (f64, f64, f64, f64) {
    use crate::aero::atmosphere::{Atmosphere, Standard1976};
    match Standard1976::new().at(h.clamp(-500.0, 86_000.0)) {
        Ok(a) => (a.temperature, a.density, a.speed_of_sound, a.viscosity),
        Err(_) => (f64::NAN, f64::NAN, f64::NAN, f64::NAN),
    }
}

/// Below this Mach the Reynolds number of the friction law is taken at this Mach: the
/// turbulent flat-plate law has no limit as Re -> 0, and the coefficient multiplies a dynamic
/// pressure that vanishes there (at M = 0.1, sea level, 34 m/s, the estimator's second grid
/// Mach). So the tables start at Mach 0 with the friction of M = 0.1.
pub const FRICTION_REYNOLDS_MIN_MACH: f64 = 0.1;

// The language's surface finishes (`aero { finish }`), owned by the checker that reads them.
pub use crate::check::finish::{DEFAULT_ROUGHNESS, FINISHES, finish_roughness, openrocket_finish};

/// The turbulent flat-plate friction coefficient before any correction (Niskanen 2009, sec.
/// 3.4.1; OpenRocket technical documentation, "Skin friction coefficients"):
/// `C_f = 1/(1.50 ln R - 5.6)^2` from `R = 1e4`, and below it the value at `1e4`, which the
/// source gives as `1.48e-2` (the formula's own value there is 0.014818; we use the
/// formula's, so the law is continuous).
pub fn turbulent_friction(re: f64) -> f64 {
    let r = re.max(1.0e4);
    1.0 / (1.50 * r.ln() - 5.6).powi(2)
}

/// The roughness-limited friction coefficient `C_f = 0.032 (R_s/L)^0.2` (same sources),
/// independent of the Reynolds number; it takes over above the critical Reynolds number
/// [`critical_reynolds`]. Zero for a perfectly smooth surface (`R_s = 0`).
pub fn roughness_limited_friction(roughness_ratio: f64) -> f64 {
    if roughness_ratio > 0.0 {
        0.032 * roughness_ratio.powf(0.2)
    } else {
        0.0
    }
}

/// The critical Reynolds number of the roughness `R_crit = 51 (R_s/L)^-1.039` (same
/// sources), above which the friction is the roughness-limited value; infinite for `R_s = 0`.
pub fn critical_reynolds(roughness_ratio: f64) -> f64 {
    if roughness_ratio > 0.0 {
        51.0 * roughness_ratio.powf(-1.039)
    } else {
        f64::INFINITY
    }
}

/// The compressibility factors of the friction coefficient (Niskanen 2009, sec. 3.4.1;
/// technical documentation, "Compressibility corrections"): `(turbulent, roughness-limited)`,
/// both `1 - 0.1 M^2` subsonic, `1/(1 + 0.15 M^2)^0.58` and `1/(1 + 0.18 M^2)` supersonic,
/// linear in Mach between their values at 0.9 and 1.1, as OpenRocket applies them "continuously
/// around Mach 1" (`BarrowmanCalculator.calculateFrictionCoefficient` and
/// `calculateRoughnessCorrection`; the documentation is silent on the band).
pub fn friction_compressibility(mach: f64) -> (f64, f64) {
    let sub = |m: f64| 1.0 - 0.1 * m * m;
    let turb = |m: f64| 1.0 / (1.0 + 0.15 * m * m).powf(0.58);
    let rough = |m: f64| 1.0 / (1.0 + 0.18 * m * m);
    if mach < 0.9 {
        (sub(mach), sub(mach))
    } else if mach > 1.1 {
        (turb(mach), rough(mach))
    } else {
        // OpenRocket blends the turbulent factors evaluated at the Mach itself, the
        // roughness factors at the band's ends; we write it as it does.
        let t = (mach - 0.9) / 0.2;
        (
            (1.0 - t) * sub(mach) + t * turb(mach),
            (1.0 - t) * sub(0.9) + t * rough(1.1),
        )
    }
}

/// Skin-friction coefficient for Reynolds number `re` (on the length `L` of the surface) at
/// Mach `mach` on a surface of relative roughness `roughness_ratio = R_s/L`: the larger of
/// the compressibility-corrected turbulent and roughness-limited values (Niskanen 2009, sec.
/// 3.4.1: "the corrected roughness-limited value should not be used if it would yield a
/// value smaller than the corresponding turbulent value"; OpenRocket takes
/// `max(C_f, C_f,rough)` for its default, fully turbulent boundary layer). The two cross near
/// [`critical_reynolds`] (within 0.63 to 1.33 R_crit for R_s/L from 1e-6 to 1e-3, the
/// roughness ratios of rockets and their fins; the source's two fits part further outside
/// it), so the maximum is the source's piecewise law made continuous. OpenRocket's optional
/// "perfect finish" (laminar flow up to Re 5.39e5) is not modelled: its default, and this
/// law, assume a fully turbulent boundary layer.
pub fn skin_friction(re: f64, mach: f64, roughness_ratio: f64) -> f64 {
    let (kt, kr) = friction_compressibility(mach);
    (turbulent_friction(re) * kt).max(roughness_limited_friction(roughness_ratio) * kr)
}

/// The body's wetted-area correction for its cylindrical geometry `1 + 1/(2 f_B)`, `f_B` the
/// fineness ratio length / largest diameter (Niskanen 2009, sec. 3.4.1; technical
/// documentation, "Skin friction drag coefficient", with the fineness ratio as its "Flow and
/// geometry parameters" defines it). OpenRocket's code (`BarrowmanCalculator.calculateFrictionCD`) divides the
/// length by the largest radius instead, which halves the correction; we follow the
/// documented definition (on a body of fineness 15 the two differ by 1.7 % of the body's
/// friction).
pub fn body_friction_correction(length: f64, max_diameter: f64) -> f64 {
    1.0 + max_diameter / (2.0 * length)
}

/// The nose's length and the body x of its centre of pressure (<= 0) on a body of diameter
/// `d`: Barrowman's x_cp = L - V/A_base aft of the tip (module doc), A_base = pi d^2/4 (the
/// nose's base is the body's); 2L/3 for the cone. A tube: (0, 0).
pub fn nose_centre_of_pressure(nose: NoseShape, d: f64) -> (f64, f64) {
    match nose {
        NoseShape::Tube => (0.0, 0.0),
        NoseShape::Cone { length } => (length, -2.0 / 3.0 * length),
        NoseShape::Profile { length, shape } => {
            let a_base = std::f64::consts::PI * d * d / 4.0;
            let v = shape.volume(0.5 * d, length);
            (length, -(length - v / a_base))
        }
    }
}

/// Body coefficients (C_N, C_A, C_M) at one condition; see the module doc. With further fin
/// sets ([`BodyShape::fin_sets`]) their coefficients are added ([`fin_set_coefficients`]).
pub fn body_coefficients(b: &BodyShape, mach: f64, alpha_deg: f64, altitude_m: f64) -> [f64; 3] {
    let lins: Vec<(f64, f64)> = b.fin_sets.iter().map(|s| s.planform.linear(mach)).collect();
    body_coefficients_with(b, &lins, mach, alpha_deg, altitude_m)
}

/// [`body_coefficients`] with each further set's `(slope, x_cp)` at this Mach given.
fn body_coefficients_with(
    b: &BodyShape,
    lins: &[(f64, f64)],
    mach: f64,
    alpha_deg: f64,
    altitude_m: f64,
) -> [f64; 3] {
    let mut c = body_alone_coefficients(b, mach, alpha_deg, altitude_m);
    let d_ref = b.reference_diameter();
    let s_ref = std::f64::consts::PI * d_ref * d_ref / 4.0;
    for (set, &lin) in b.fin_sets.iter().zip(lins) {
        let s = fin_set_coefficients(
            set,
            lin,
            (b.roughness, b.length),
            (s_ref, d_ref, b.reference_x),
            mach,
            alpha_deg,
            altitude_m,
        );
        for k in 0..3 {
            c[k] += s[k];
        }
    }
    c
}

/// The body's own coefficients (C_N, C_A, C_M), without further fin sets.
fn body_alone_coefficients(b: &BodyShape, mach: f64, alpha_deg: f64, altitude_m: f64) -> [f64; 3] {
    let pi = std::f64::consts::PI;
    let d = b.diameter;
    let d_ref = b.reference_diameter();
    let s_ref = pi * d_ref * d_ref / 4.0;
    let a = alpha_deg.to_radians();
    let (nose_len, x_nose_cp) = nose_centre_of_pressure(b.nose, d);
    // The nose's slope 2 A_base/S: 2 /rad when its base is the reference diameter.
    let nose_area_ratio = if d == d_ref { 1.0 } else { (d / d_ref).powi(2) };
    let cn_pot = if nose_len > 0.0 {
        nose_area_ratio * (2.0 * a).sin() * (0.5 * a).cos()
    } else {
        0.0
    };
    // Planform area: the nose's side view (the cone's triangle) plus the rectangle of the
    // cylinder, and the nose's planform centroid aft of the tip.
    let (a_nose, nose_centroid) = match b.nose {
        NoseShape::Profile { length, shape } => shape.planform(0.5 * d, length),
        _ => (0.5 * d * nose_len, 2.0 / 3.0 * nose_len),
    };
    // The tube's sections of one diameter between the transitions, and the transitions:
    // (planform area, its centroid's body x, wetted area) each.
    let mut pieces: Vec<(f64, f64, f64)> = Vec::with_capacity(2 * b.transitions.len() + 1);
    let (mut from, mut rs) = (nose_len, 0.5 * d);
    for t in &b.transitions {
        pieces.push((
            (2.0 * rs) * (t.start - from),
            -(from + t.start) / 2.0,
            pi * (2.0 * rs) * (t.start - from),
        ));
        let (area, centroid) = t.planform();
        pieces.push((area, -centroid, t.wetted_area()));
        (from, rs) = (t.end(), t.r_aft);
    }
    pieces.push((
        (2.0 * rs) * (b.length - from),
        -(from + b.length) / 2.0,
        pi * (2.0 * rs) * (b.length - from),
    ));
    let mut a_p = a_nose;
    let mut x_num = a_nose * (-nose_centroid);
    for &(area, x, _) in &pieces {
        a_p += area;
        x_num += area * x;
    }
    let x_p = x_num / a_p;
    const C_DC: f64 = 1.2;
    let cn_cross = C_DC * (a_p / s_ref) * a.sin() * a.sin().abs();
    let mut cn = cn_pot + cn_cross;
    let mut cm_num = cn_pot * (x_nose_cp - b.reference_x) + cn_cross * (x_p - b.reference_x);
    // Each transition's potential normal force, Barrowman's 2 (A_aft - A_fore)/S per rad
    // (negative on a boat tail) with the nose's alpha dependence, at its centre of pressure
    // (`TransitionGeom::potential`).
    for t in &b.transitions {
        let (da, s_cp) = t.potential();
        let cn_t = (da / s_ref) * (2.0 * a).sin() * (0.5 * a).cos();
        cn += cn_t;
        cm_num += cn_t * (-s_cp - b.reference_x);
    }
    let cm = cm_num / d_ref;
    // Axial force.
    let (_, rho, sound, mu) = atmosphere(altitude_m);
    let v = mach.max(FRICTION_REYNOLDS_MIN_MACH) * sound;
    let re = rho * v * b.length / mu;
    let nose_wetted = match b.nose {
        NoseShape::Profile { length, shape } => shape.wetted_area(0.5 * d, length),
        _ => {
            let slant = (0.25 * d * d + nose_len * nose_len).sqrt();
            std::f64::consts::PI * 0.5 * d * slant
        }
    };
    let mut wetted = nose_wetted;
    for &(_, _, w) in &pieces {
        wetted += w;
    }
    let friction = skin_friction(re, mach, b.roughness / b.length)
        * body_friction_correction(b.length, d_ref)
        * wetted
        / s_ref;
    let base_cd = if mach < 1.0 {
        0.12 + 0.13 * mach * mach
    } else {
        0.25 / mach
    };
    // On the base's own area (Niskanen 2009, sec. 3.4.5): the reference area's when the body
    // ends at the reference diameter.
    let r_base = b.base_radius();
    let base = if 2.0 * r_base == d_ref {
        base_cd
    } else {
        base_cd * pi * r_base * r_base / s_ref
    };
    // Transitions' pressure drag (Niskanen 2009, sec. 3.4.3; OpenRocket's
    // `SymmetricComponentCalc.calculatePressureCD`): a narrowing one (boat tail) takes the
    // base drag on its frontal area A_fore - A_aft, times 1 for a fineness
    // g = l/(d_fore - d_aft) <= 1, (3 - g)/2 for 1 < g < 3, 0 from 3 on; a widening one the
    // nose's sharp-cone wave drag (below) at its own half-angle atan((r_aft - r_fore)/l) on
    // its frontal area A_aft - A_fore.
    let mut transition_drag = 0.0;
    for t in &b.transitions {
        let frontal = pi * (t.r_fore * t.r_fore - t.r_aft * t.r_aft).abs() / s_ref;
        if t.narrows() {
            let g = t.length / (2.0 * (t.r_fore - t.r_aft));
            let factor = if g <= 1.0 {
                1.0
            } else if g < 3.0 {
                (3.0 - g) / 2.0
            } else {
                0.0
            };
            transition_drag += base_cd * frontal * factor;
        } else {
            let half_angle = ((t.r_aft - t.r_fore) / t.length).atan();
            let fit = |m: f64| (1.59 + 1.83 / (m * m)) * half_angle.powf(1.69);
            transition_drag += frontal * transonic_blend(mach, |_| 0.0, fit);
        }
    }
    let wave = if nose_len > 0.0 {
        let half_angle = (0.5 / (nose_len / d)).atan();
        let fit = |m: f64| (1.59 + 1.83 / (m * m)) * half_angle.powf(1.69);
        match b.nose {
            // Ogives: the cone's wave drag times Niskanen's shape factor (module doc).
            NoseShape::Profile {
                shape: crate::check::ir::NoseShape::Ogive { k },
                ..
            } => {
                let factor = 0.72 * (k - 0.5) * (k - 0.5) + 0.82;
                transonic_blend(mach, |_| 0.0, |m| factor * fit(m))
            }
            // The other profiles: Stoney's data at fineness 3 (module doc).
            NoseShape::Profile { length, shape } => {
                nose_pressure_drag(shape, length / d, 0.5 * d, length, mach)
            }
            _ => transonic_blend(mach, |_| 0.0, fit),
        }
    } else {
        0.0
    };
    // The nose's wave drag is on its base area.
    let wave = nose_area_ratio * wave;
    let guides: f64 = b
        .guides
        .iter()
        .map(|g| launch_guide_drag(g, b.roughness, s_ref, mach, sound, mu / rho))
        .sum();
    let ca0 = if b.transitions.is_empty() {
        friction + base + wave + guides
    } else {
        friction + base + wave + transition_drag + guides
    };
    [cn, ca0 * axial_scaling(alpha_deg), cm]
}

/// Angle of attack, deg, from which a fin's normal force no longer grows: OpenRocket's
/// stall angle (24.12, `FinSetCalc.STALL_ANGLE`, 20 deg, above which its fin normal force
/// is held at its 20-degree value).
pub const FIN_STALL_DEG: f64 = 20.0;

/// The angle, rad, that a fin's linear normal force `C_Nalpha (A_f/S) x` takes in place of
/// its angle of attack `alpha_deg` (any real value, deg; the built-in tables span
/// -180..180): `sign(alpha) min(|alpha|, 20 deg, 180 deg - |alpha|)`.
///
/// # Derivation
/// Up to the stall angle [`FIN_STALL_DEG`] it is the angle itself (the linear theory of the
/// module doc). From there to 90 deg the normal force is held at its stall value, as
/// OpenRocket 24.12 holds it (`FinSetCalc`: `C_N = C_Nalpha min(alpha, 20 deg)`). Beyond
/// 90 deg the air reaches the fin from its trailing edge at the angle `180 deg - |alpha|`
/// to its plane, and the normal component of the velocity, `V sin alpha`, keeps its sign:
/// a thin flat plate's normal force depends on the flow's angle to its plane and not on
/// which edge meets the flow first (Barrowman's subsonic slope of the module doc depends on
/// the mid-chord sweep through `cos Lambda_c` only, unchanged when the flow is reversed, as
/// are the span and the area), so `C_N(alpha) = C_N(180 deg -
/// alpha)` there. OpenRocket keeps the held value up to 180 deg; this is ours, and it makes
/// the normal force vanish continuously as the flow comes to lie along the fin from behind
/// (a tail-first fall, `tests/verdict.rs`) instead of keeping its stall value while its
/// direction flips with the sign of a vanishing crossflow. The centre of pressure stays that
/// of the linear theory at every angle (as OpenRocket's); the flexible fins' load is
/// distributed with the same weights (`runtime::forces::fin_aero`).
pub fn fin_incidence(alpha_deg: f64) -> f64 {
    let a = alpha_deg.abs();
    let held = a.min(FIN_STALL_DEG).min((180.0 - a).max(0.0));
    held.copysign(alpha_deg).to_radians()
}

/// The factor on the zero-lift axial coefficient at angle of attack `alpha_deg` (deg, any
/// real value; the body's total angle of attack or a fin's own).
///
/// Niskanen 2009, sec. 3.4.7 in the technical documentation's numbering ("Axial drag
/// coefficient", OpenRocket's
/// `doc/techdoc/chapter-aerodynamic-properties.tex`): "a two-part polynomial function that
/// starts from 1 at alpha = 0, increases to 1.3 at alpha = 17 deg and then decreases to zero
/// at alpha = 90 deg; the derivative is also zero at these points", an empirical fit to
/// experimental data (more frontal area and pressure changes at incidence, less of the drag
/// along the axis). OpenRocket 24.12 (`BarrowmanCalculator.calculateAxialCD`) also sets the
/// second derivative zero at 90 deg, which with the four conditions stated makes the second
/// part a quartic; we take the same. The two parts, derived from those conditions:
/// - `0 <= alpha <= 17 deg`: the cubic with f(0) = 1, f'(0) = 0, f(17) = 1.3, f'(17) = 0,
///   `f = 1 + 0.3 (3 t^2 - 2 t^3)`, `t = alpha/17 deg`;
/// - `17 <= alpha <= 90 deg`: with `u = (90 deg - alpha)/73 deg`, the quartic with a triple
///   zero at 90 deg, `f = 1.3 u^3 (a + b u)`; f = 1.3 at u = 1 gives `a + b = 1`, and
///   f'(17) = 0, i.e. `d/du [u^3 (a + b u)] = 3 a + 4 b = 0` at u = 1, gives `a = 4`,
///   `b = -3`: `f = 1.3 (4 u^3 - 3 u^4)`.
///
/// Beyond 90 deg the air comes from behind and the axial force must oppose it: `f(alpha) =
/// -f(180 deg - alpha)` (the same size as the forward flow's at the mirrored angle,
/// OpenRocket's choice too; a body's drag flying backwards is not modelled on its own). The
/// factor is even in alpha.
pub fn axial_scaling(alpha_deg: f64) -> f64 {
    let a = alpha_deg.abs().min(180.0);
    let (a, sign) = if a > 90.0 {
        (180.0 - a, -1.0)
    } else {
        (a, 1.0)
    };
    let f = if a <= 17.0 {
        let t = a / 17.0;
        1.0 + 0.3 * t * t * (3.0 - 2.0 * t)
    } else {
        let u = (90.0 - a) / 73.0;
        1.3 * u * u * u * (4.0 - 3.0 * u)
    };
    sign * f
}

/// Body rate derivatives `[C_Nq + C_Nα̇, C_mq + C_mα̇]` at angle of attack `alpha_deg`
/// (conventions in the module doc: per rad of `ω d/(2V)`, about the reference point).
///
/// # Derivation
/// Slender-body momentum theory (Munk 1924; Ashley & Landahl, "Aerodynamics of Wings and
/// Bodies", 1965, ch. 6; Nielsen, "Missile Aerodynamics", 1960, ch. 3): a cross-section of
/// area A(s), s the distance aft of the nose, seeing the crossflow `w(s, t) = V α(s, t)`
/// carries the normal force per unit length `n(s) = (∂/∂t + V ∂/∂s)(ρ A w)`. For a constant
/// α this is `ρ V² α A'`, whose integral `ρ V² α A_b = 2 q∞ α A_b` is the static slope
/// C_Nα = 2 A_b/S of the nose term above. A rotation at rate q (nose up) about `s_r` with the
/// angle of attack α_r at `s_r` gives `α(s) = α_r + q (s - s_r)/V` (a point aft of `s_r` moves
/// down), so the rate part is `n_q = ρ V q d/ds[A (s - s_r)]`; a uniform α̇ adds
/// `n_α̇ = ρ V A α̇`. Integrating, with `A(0) = 0` (pointed nose):
/// `N_q = ρ V q A_b (l - s_r)`, `N_α̇ = ρ V α̇ Vol`, and about `s_r` (nose up positive, so a
/// load aft of `s_r` has moment `-n (s - s_r)`), by parts,
/// `M_q = -ρ V q (A_b (l - s_r)² - Vol (s_c - s_r))`, `M_α̇ = -ρ V α̇ Vol (s_c - s_r)`
/// (s_c the centroid of the volume). With α̇ = q (the thesis' kinematic α̇, module doc) and
/// `C = F/(q∞ S (d or d²)) / (q d/(2V))`, `q∞ = ρ V²/2`:
/// `C_Nq + C_Nα̇ = 4 (A_b (l - s_r) + Vol)/(S d)` and `C_mq + C_mα̇ = -4 A_b (l - s_r)²/(S d²)`
/// (the volume terms cancel in the moment). A tube without a nose is taken as the limit of a
/// vanishing cone (the same formulas with `L_n = 0`).
///
/// The viscous crossflow term of the static model, `n_c = C_dc q∞ d(s) sin α |sin α|`
/// (Allen), with the local `α(s)` above, has the rate part
/// `C_dc q∞ d(s) 2 |sin α| cos α q (s - s_r)/V`; integrated as above,
/// `C_Nq = 4 C_dc |sin α| cos α I_1/(S d)`, `C_mq = -4 C_dc |sin α| cos α I_2/(S d²)` with
/// `I_k = ∫_0^l d(s) (s - s_r)^k ds` over the planform (cone: `d(s) = d s/L_n`). Allen's
/// term is quasi-steady: no α̇ part. Both parts are even in α, as the table is queried at
/// the total angle of attack.
pub fn body_rate_derivatives(b: &BodyShape, alpha_deg: f64) -> [f64; 2] {
    if !b.transitions.is_empty() {
        return rate_derivatives_with_transitions(b, alpha_deg);
    }
    let d = b.diameter;
    let s_ref = std::f64::consts::PI * d * d / 4.0;
    let l = b.length;
    let s_r = -b.reference_x;
    let (ln, profile) = match b.nose {
        NoseShape::Tube => (0.0, None),
        NoseShape::Cone { length } => (length, None),
        NoseShape::Profile { length, shape } => (length, Some(shape)),
    };
    // Potential (base area = S for the cylindrical afterbody).
    let vol = match profile {
        Some(shape) => shape.volume(0.5 * d, ln) + s_ref * (l - ln),
        None => s_ref * (ln / 3.0 + (l - ln)),
    };
    let cn_pot = 4.0 * (s_ref * (l - s_r) + vol) / (s_ref * d);
    let cm_pot = -4.0 * s_ref * (l - s_r).powi(2) / (s_ref * d * d);
    // Crossflow: planform moments about s_r (the nose's side view, by the profile's
    // quadrature, or the cone's triangle; then the cylinder's rectangle).
    let (i1_cone, i2_cone) = if let Some(shape) = profile {
        let r = 0.5 * d;
        (
            shape.integrate(r, ln, 0.0, ln, 64, |s, ro| 2.0 * ro * (s - s_r)),
            shape.integrate(r, ln, 0.0, ln, 64, |s, ro| 2.0 * ro * (s - s_r).powi(2)),
        )
    } else if ln > 0.0 {
        (
            d * (ln * ln / 3.0 - s_r * ln / 2.0),
            d * (ln.powi(3) / 4.0 - 2.0 * s_r * ln * ln / 3.0 + s_r * s_r * ln / 2.0),
        )
    } else {
        (0.0, 0.0)
    };
    let (e, o) = (l - s_r, ln - s_r);
    let i1 = i1_cone + d * (e * e - o * o) / 2.0;
    let i2 = i2_cone + d * (e.powi(3) - o.powi(3)) / 3.0;
    const C_DC: f64 = 1.2;
    let a = alpha_deg.to_radians();
    let k = 4.0 * C_DC * a.sin().abs() * a.cos();
    [
        cn_pot + k * i1 / (s_ref * d),
        cm_pot - k * i2 / (s_ref * d * d),
    ]
}

/// [`body_rate_derivatives`] of a body with transitions: the derivation there holds for any
/// A(s) with A(0) = 0 (A_b = A(l) the aft end's area, Vol the whole volume, I_k over the whole
/// planform); S and d are the reference area and length (the largest diameter).
fn rate_derivatives_with_transitions(b: &BodyShape, alpha_deg: f64) -> [f64; 2] {
    let pi = std::f64::consts::PI;
    let d = b.diameter;
    let d_ref = b.reference_diameter();
    let s_ref = pi * d_ref * d_ref / 4.0;
    let l = b.length;
    let s_r = -b.reference_x;
    let r = 0.5 * d;
    // Volume and planform moments of the nose.
    let (ln, mut vol, mut i1, mut i2) = match b.nose {
        NoseShape::Tube => (0.0, 0.0, 0.0, 0.0),
        NoseShape::Cone { length } => (
            length,
            pi * r * r * length / 3.0,
            d * (length * length / 3.0 - s_r * length / 2.0),
            d * (length.powi(3) / 4.0 - 2.0 * s_r * length * length / 3.0
                + s_r * s_r * length / 2.0),
        ),
        NoseShape::Profile { length, shape } => (
            length,
            shape.volume(r, length),
            shape.integrate(r, length, 0.0, length, 64, |s, ro| 2.0 * ro * (s - s_r)),
            shape.integrate(r, length, 0.0, length, 64, |s, ro| {
                2.0 * ro * (s - s_r).powi(2)
            }),
        ),
    };
    // Cylinders of radius rs on [p, q]: volume, and the planform moments in closed form.
    let mut cylinders = Vec::new();
    let (mut from, mut rs) = (ln, r);
    for t in &b.transitions {
        cylinders.push((rs, from, t.start));
        vol += t.volume();
        i1 += t.integrate(t.start, t.end(), |s, ro| 2.0 * ro * (s - s_r));
        i2 += t.integrate(t.start, t.end(), |s, ro| 2.0 * ro * (s - s_r).powi(2));
        (from, rs) = (t.end(), t.r_aft);
    }
    cylinders.push((rs, from, l));
    for (rs, p, q) in cylinders {
        vol += pi * rs * rs * (q - p);
        i1 += 2.0 * rs * ((q - s_r).powi(2) - (p - s_r).powi(2)) / 2.0;
        i2 += 2.0 * rs * ((q - s_r).powi(3) - (p - s_r).powi(3)) / 3.0;
    }
    let a_b = pi * b.base_radius().powi(2);
    let cn_pot = 4.0 * (a_b * (l - s_r) + vol) / (s_ref * d_ref);
    let cm_pot = -4.0 * a_b * (l - s_r).powi(2) / (s_ref * d_ref * d_ref);
    const C_DC: f64 = 1.2;
    let a = alpha_deg.to_radians();
    let k = 4.0 * C_DC * a.sin().abs() * a.cos();
    [
        cn_pot + k * i1 / (s_ref * d_ref),
        cm_pot - k * i2 / (s_ref * d_ref * d_ref),
    ]
}

/// Fin rate derivatives `[C_Nq, C_mq]` of `n_eff = Σ cos² δ_i` fins in the pitch plane
/// (per rad of `q d/(2V)`, about `reference_x`; module doc): each fin's angle of attack
/// changes by `q l_f/V`, `l_f = reference_x - x_cp` the arm of its centre of pressure aft of
/// the reference point, so `ΔN = q∞ S n_eff K_T(B) C_Nα,1 q l_f/V` at the arm `l_f`:
/// `C_Nq = 2 n_eff K_T(B) C_Nα,1 l_f/d`, `C_mq = -2 n_eff K_T(B) C_Nα,1 (l_f/d)²`.
/// `root_le_x` is the body x of the root leading edge (<= 0), `d` the reference length.
pub fn fin_rate_derivatives(
    f: &FinPlanform,
    s_ref: f64,
    d: f64,
    root_le_x: f64,
    reference_x: f64,
    n_eff: f64,
    mach: f64,
) -> [f64; 2] {
    let slope = n_eff * f.interference() * f.cn_alpha(mach, s_ref);
    let arm = reference_x - (root_le_x - f.x_cp(mach));
    [2.0 * slope * arm / d, -2.0 * slope * (arm / d).powi(2)]
}

/// The fin's thickness and cross-section, for its drag (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FinProfile {
    /// Thickness t, m.
    pub thickness: f64,
    pub section: crate::check::ir::FinSection,
}

/// Stagnation pressure over dynamic pressure, `q_stag/q` (Hoerner, pp. 15-2 and 16-3, as
/// Niskanen 2009, App. B.1, writes it).
pub fn stagnation_pressure_ratio(mach: f64) -> f64 {
    let m2 = mach * mach;
    if mach < 1.0 {
        1.0 + m2 / 4.0 + m2 * m2 / 40.0
    } else {
        1.84 - 0.76 / m2 + 0.166 / (m2 * m2) + 0.035 / (m2 * m2 * m2)
    }
}

/// Base drag coefficient on the base area (Niskanen 2009, eq. 3.94, after Fleeman):
/// 0.12 + 0.13 M^2 below Mach 1, 0.25/M above.
pub fn base_drag(mach: f64) -> f64 {
    if mach < 1.0 {
        0.12 + 0.13 * mach * mach
    } else {
        0.25 / mach
    }
}

/// Pressure drag of a leading edge perpendicular to the flow, on its frontal area: square
/// `0.85 q_stag/q`; rounded (and an airfoil's) Barrowman's fit (module doc).
pub fn leading_edge_drag(section: crate::check::ir::FinSection, mach: f64) -> f64 {
    use crate::check::ir::FinSection;
    match section {
        FinSection::Square => 0.85 * stagnation_pressure_ratio(mach),
        FinSection::Rounded | FinSection::Airfoil => {
            if mach < 0.9 {
                (1.0 - mach * mach).powf(-0.417) - 1.0
            } else if mach < 1.0 {
                1.0 - 1.785 * (mach - 0.9)
            } else {
                1.214 - 0.502 / (mach * mach) + 0.1095 / mach.powi(4)
            }
        }
    }
}

/// Pressure drag of a trailing edge on its frontal area: the base drag for a square edge,
/// half of it for a rounded one, none for an airfoil's tapering edge (module doc).
pub fn trailing_edge_drag(section: crate::check::ir::FinSection, mach: f64) -> f64 {
    use crate::check::ir::FinSection;
    match section {
        FinSection::Square => base_drag(mach),
        FinSection::Rounded => 0.5 * base_drag(mach),
        FinSection::Airfoil => 0.0,
    }
}

/// The axial coefficient of one fin on reference area `s_ref` (module doc): skin friction
/// (the rocket's C_f, at the Reynolds number and relative roughness of its length
/// `rocket_length`, m; thickness-corrected with a profile) plus, with a profile, the pressure
/// drag of the leading edge (times cos^2 of its sweep) and the trailing edge on the frontal
/// area t s, and the `airfoil` section's thickness wave drag on the planform.
#[allow(clippy::too_many_arguments)]
pub fn fin_axial(
    f: &FinPlanform,
    profile: Option<FinProfile>,
    roughness: f64,
    rocket_length: f64,
    s_ref: f64,
    mach: f64,
    altitude_m: f64,
) -> f64 {
    let (_, rho, sound, mu) = atmosphere(altitude_m);
    let (mac, _) = f.mean_aerodynamic_chord();
    // The rocket's Reynolds number and relative roughness (module doc).
    let re = rho * mach.max(FRICTION_REYNOLDS_MIN_MACH) * sound * rocket_length / mu;
    let cf = skin_friction(re, mach, roughness / rocket_length);
    let Some(p) = profile else {
        return cf * 2.0 * f.area() / s_ref;
    };
    let friction = cf * (1.0 + 2.0 * p.thickness / mac) * 2.0 * f.area();
    // cos^2 of the leading-edge sweep; its span average along a curved or broken edge.
    let cos2_le = if f.outline.is_trapezoidal() {
        let cos_le = (f.span / f.span.hypot(f.tip_le_offset)).min(1.0);
        cos_le * cos_le
    } else {
        f.edges().mean_cos2_leading_edge()
    };
    let pressure =
        leading_edge_drag(p.section, mach) * cos2_le + trailing_edge_drag(p.section, mach);
    let wave = thickness_wave_drag(p.section, p.thickness / mac, f.mid_chord_sweep(), mach);
    (friction + pressure * p.thickness * f.span + wave * f.area()) / s_ref
}

/// Ackeret's constant K of the thickness wave drag `K tau^2 / beta` of a thin symmetric
/// section in two-dimensional supersonic flow: `16/3` for the biconvex (parabolic-arc)
/// section, our `airfoil` cross-section; 0 for the `square` and `rounded` sections, whose
/// faces are parallel to the flow (their edges' pressure drag is the edge terms). Derivation:
/// Ackeret's linear theory gives the surface pressure `C_p = 2 theta / beta` (theta the
/// local surface slope against the free stream, beta = sqrt(M^2 - 1); J. Ackeret,
/// "Luftkräfte auf Flügel, die mit größerer als Schallgeschwindigkeit bewegt werden", ZFM 16,
/// 1925; the integral below is derived here), so the drag of one
/// surface per unit span is `q int C_p theta dx = (2 q / beta) int theta^2 dx`; for the
/// parabolic arc `y = 2 t x (c - x)/c^2` on each face, `int_0^c theta^2 dx = 4 t^2/(3 c)`, and
/// both faces give `C_d = (2/beta) 2 (4/3) tau^2 = (16/3) tau^2/beta` on the chord (the
/// double wedge's is 4 tau^2/beta the same way).
pub fn thickness_wave_constant(section: crate::check::ir::FinSection) -> f64 {
    use crate::check::ir::FinSection;
    match section {
        FinSection::Airfoil => 16.0 / 3.0,
        FinSection::Square | FinSection::Rounded => 0.0,
    }
}

/// Thickness wave drag of a fin on its planform area (see [`thickness_wave_constant`]) with
/// simple sweep theory (the infinite swept wing, derived here): the section sees the normal Mach `M_n = M cos Lambda` and the thickness ratio
/// `tau / cos Lambda` on the normal chord `c cos Lambda`, so per unit length of the crest line
/// its drag along the normal is `q cos^2 Lambda (c cos Lambda) K (tau/cos Lambda)^2 / beta_n`
/// (`beta_n = sqrt(M_n^2 - 1)`; no pressure acts along the crest); the free-stream component
/// is that times cos Lambda, and on the strip's planform area `c cos Lambda` and `q`:
/// `C_D = K tau^2 cos Lambda / sqrt(M^2 cos^2 Lambda - 1)` (Lambda = 0: Ackeret's). Lambda is the
/// mid-chord sweep (the biconvex section's crest line) and tau = t / c_mac. Zero for a
/// subsonic normal Mach (the infinite swept wing has no wave drag there; a finite fin's tip
/// and root do, which is not modelled). Linear theory fails as `M_n -> 1`: valid where the
/// transonic similarity parameter `(M_n^2 - 1)/((gamma + 1) tau_n M_n^2)^(2/3)` is at least 1
/// (Spreiter; the module doc's criterion for the fins' lifting surface), i.e. from
/// `M_n*`; between `M_n = 1` and `M_n*` the drag is ramped linearly in `M_n` from 0 to its
/// value at `M_n*` (our blend, as the body's transonic wave drag is).
pub fn thickness_wave_drag(
    section: crate::check::ir::FinSection,
    tau: f64,
    sweep: f64,
    mach: f64,
) -> f64 {
    let k = thickness_wave_constant(section);
    let cos = sweep.cos();
    let mn = mach * cos;
    if k == 0.0 || mn <= 1.0 || tau.is_nan() || tau <= 0.0 {
        return 0.0;
    }
    const GAMMA: f64 = 1.4;
    let tau_n = tau / cos;
    let value = |m: f64| k * tau * tau * cos / (m * m - 1.0).sqrt();
    // The similarity parameter is 1 where m^2 - 1 = ((gamma + 1) tau_n m^2)^(2/3): solved by
    // fixed-point iteration from m = 1 (a contraction: the right side grows slowly with m).
    let mut m_star: f64 = 1.0;
    for _ in 0..60 {
        m_star = (1.0 + ((GAMMA + 1.0) * tau_n * m_star * m_star).powf(2.0 / 3.0)).sqrt();
    }
    if mn >= m_star {
        value(mn)
    } else {
        value(m_star) * (mn - 1.0) / (m_star - 1.0)
    }
}

/// Coefficients of one fin (C_N, C_A, x_cp) at one condition on reference area `s_ref`, the
/// fin a flat plate of surface roughness height `roughness`, m, on a rocket of length
/// `rocket_length`, m (its friction's Reynolds number).
pub fn fin_coefficients(
    f: &FinPlanform,
    (roughness, rocket_length): (f64, f64),
    s_ref: f64,
    mach: f64,
    alpha_deg: f64,
    altitude_m: f64,
) -> [f64; 3] {
    fin_coefficients_with(
        f,
        None,
        (roughness, rocket_length),
        f.linear(mach),
        s_ref,
        mach,
        alpha_deg,
        altitude_m,
    )
}

/// [`fin_coefficients`] with the Mach's (slope on A_f, x_cp) computed once by the caller.
#[allow(clippy::too_many_arguments)]
fn fin_coefficients_with(
    f: &FinPlanform,
    profile: Option<FinProfile>,
    (roughness, rocket_length): (f64, f64),
    (slope, x_cp): (f64, f64),
    s_ref: f64,
    mach: f64,
    alpha_deg: f64,
    altitude_m: f64,
) -> [f64; 3] {
    let cn = f.interference() * slope * f.area() / s_ref * fin_incidence(alpha_deg);
    let ca = axial_scaling(alpha_deg)
        * fin_axial(
            f,
            profile,
            roughness,
            rocket_length,
            s_ref,
            mach,
            altitude_m,
        );
    [cn, ca, x_cp]
}

/// The angles of attack of the estimator grid, deg: every flow direction, -180..180, by 2
/// deg up to the fins' stall at 20 deg and by 10 deg beyond (a tumbling or tail-first
/// fall; [`fin_incidence`], [`axial_scaling`]). The fins' kinks at 20 and 160 deg are grid
/// points.
pub fn estimator_alpha() -> Vec<f64> {
    let outer = (3..=18).map(|k| 10.0 * f64::from(k));
    let inner = (-10..=10).map(|k| 2.0 * f64::from(k));
    let mut a: Vec<f64> = outer.clone().rev().map(|x| -x).collect();
    a.extend(inner);
    a.extend(outer);
    a
}

/// The grid the estimator writes: Mach 0..5 (a launch starts at rest), alpha -180..180 deg
/// ([`estimator_alpha`]), altitude 0..30 km.
pub const ESTIMATOR_MACH: [f64; 18] = [
    0.0, 0.1, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 1.0, 1.05, 1.1, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0,
];
/// Altitudes of the estimator grid, m.
pub const ESTIMATOR_ALTITUDE: [f64; 6] = [0.0, 5_000.0, 10_000.0, 15_000.0, 20_000.0, 30_000.0];

/// The two tables the estimator produced.
#[derive(Clone, Debug, PartialEq)]
pub struct EstimatedTables {
    pub body: CoefficientTable,
    pub fin: CoefficientTable,
}

impl EstimatedTables {
    /// Estimates both tables (reference area pi d^2/4 of the body) with the given policy, the
    /// fin a flat plate of no thickness (friction only; [`Self::estimate_with_profile`]). The
    /// fins take the body's surface roughness ([`BodyShape::roughness`]).
    pub fn estimate(
        body: &BodyShape,
        fin: &FinPlanform,
        policy: OutOfRange,
    ) -> Result<Self, TableError> {
        Self::estimate_with_profile(body, fin, None, policy)
    }

    /// [`Self::estimate`] with the fin's thickness and cross-section in its drag.
    pub fn estimate_with_profile(
        body: &BodyShape,
        fin: &FinPlanform,
        profile: Option<FinProfile>,
        policy: OutOfRange,
    ) -> Result<Self, TableError> {
        let alpha = estimator_alpha();
        let axes = [
            ESTIMATOR_MACH.to_vec(),
            alpha.clone(),
            ESTIMATOR_ALTITUDE.to_vec(),
        ];
        let d_ref = body.reference_diameter();
        let s_ref = std::f64::consts::PI * d_ref * d_ref / 4.0;
        let mut bp = Vec::new();
        let mut br = Vec::new();
        // The further sets' roll columns (none without further sets: the table keeps its
        // eight columns).
        let mut bl = Vec::new();
        let mut fp = Vec::new();
        for &m in &ESTIMATOR_MACH {
            let lin = fin.linear(m);
            let set_lins: Vec<(f64, f64)> =
                body.fin_sets.iter().map(|s| s.planform.linear(m)).collect();
            // The further sets' pitch damping (they have no fin block to carry it through
            // their velocity): [`fin_rate_derivatives`] with their pitch-plane count.
            let mut set_rates = [0.0; 2];
            for s in &body.fin_sets {
                let r = fin_rate_derivatives(
                    &s.planform,
                    s_ref,
                    d_ref,
                    s.root_le_x,
                    body.reference_x,
                    s.pitch_plane_count(),
                    m,
                );
                set_rates[0] += r[0];
                set_rates[1] += r[1];
            }
            let mut roll = [0.0; 2];
            for (s, &(slope, _)) in body.fin_sets.iter().zip(&set_lins) {
                let r = fin_set_roll(s, slope, s_ref, d_ref);
                roll[0] += r[0];
                roll[1] += r[1];
            }
            for &a in &alpha {
                for &h in &ESTIMATOR_ALTITUDE {
                    bp.push(body_coefficients_with(body, &set_lins, m, a, h));
                    let r = body_rate_derivatives(body, a);
                    br.push([r[0] + set_rates[0], r[1] + set_rates[1]]);
                    bl.push(roll);
                    fp.push(fin_coefficients_with(
                        fin,
                        profile,
                        (body.roughness, body.length),
                        lin,
                        s_ref,
                        m,
                        a,
                        h,
                    ));
                }
            }
        }
        Ok(EstimatedTables {
            body: CoefficientTable::from_grid(
                TableKind::Body,
                "builtin-body.csv",
                axes.clone(),
                &bp,
                policy,
            )?
            .with_rates(&br)
            .and_then(|t| {
                if body.fin_sets.is_empty() {
                    Ok(t)
                } else {
                    t.with_roll(&bl)
                }
            })?,
            fin: CoefficientTable::from_grid(
                TableKind::Fin,
                "builtin-fins.csv",
                axes,
                &fp,
                policy,
            )?,
        })
    }

    /// Writes `body.csv` and `fins.csv` into `dir` (with a comment line naming the estimator).
    pub fn write(&self, dir: &Path) -> Result<(), TableError> {
        for (name, text) in self.files() {
            let path = dir.join(name);
            std::fs::write(&path, text).map_err(|e| TableError::Io {
                path,
                message: e.to_string(),
            })?;
        }
        Ok(())
    }

    /// The files [`Self::write`] writes: `body.csv` and `fins.csv` with their text.
    pub fn files(&self) -> [(&'static str, String); 2] {
        [(&self.body, "body.csv"), (&self.fin, "fins.csv")].map(|(t, name)| {
            (
                name,
                format!(
                    "# written by the flexflight built-in estimator (aero::estimator)\n{}",
                    t.to_csv()
                ),
            )
        })
    }
}

/// The planform of the `fins` block (x_t = s tan Λ_LE of the (equivalent) trapezoid, and
/// the outline).
pub fn planform(f: &crate::check::ir::Fins, body_radius: f64) -> FinPlanform {
    FinPlanform {
        span: f.span.value,
        root_chord: f.root_chord.value,
        tip_chord: f.tip_chord.value,
        tip_le_offset: f.span.value * f.leading_edge_sweep.value.tan(),
        body_radius,
        outline: f.outline.clone(),
    }
}
