//! Flutter of the free flexible vehicle (issue 13, deliverable 2b): the p-k method of
//! [`super::pk`] on the compiled reduced model's free-free elastic modes and the six
//! rigid-body motions, with the fins' panel generalised forces of [`super::fin`] and the
//! body's quasi-steady aerodynamics of the flight.
//!
//! # Coordinates
//!
//! `x = (r, θ, η)`: `r` the (small) translation of the body-frame origin (the reduced model's
//! origin node) and `θ` the small rotation of the body frame, both measured from the
//! reference motion, straight flight at speed `V` along the body `x` axis, in the axes of the
//! reference body frame (a Galilean frame moving with the reference); `η` the modal
//! coordinates of the selected modes (`CompiledVehicle.reduced`, the floating-frame
//! shapes after fixity, as the flight integrates them). All six rigid motions are kept, as
//! zero-frequency coordinates, in the manner of MSC Nastran SOL 145 for a free-free
//! vehicle, where the SUPORTed rigid-body modes enter the modal basis with zero stiffness
//! (Rodden & Johnson, *MSC/NASTRAN Aeroelastic Analysis User's Guide*, 1994, §2.6 and
//! ch. 3 on rigid-body modes): the fins' flutter modes couple with the vehicle's pitch,
//! yaw and plunge (the short period, body-freedom flutter) and with roll (antisymmetric fin
//! modes), and the floating frame's inertial coupling `P̄`, `H̄` (3.2.3, 3.2.5) ties the
//! rigid motions to the modes. The axial translation couples only through `P̄` and the
//! drag; it is kept for completeness (it costs two roots).
//!
//! # Generalised mass and stiffness
//!
//! The kinetic energy of the reduced model is `T = ½ vᵀ M_tot(η) v`, `v = (V_B, ω_B, η̇)`
//! (`runtime::eom`, eqs. 3.2.2-3.2.12). About the reference (`ω_B = 0`, `η = 0`), with the
//! inertial velocity of the origin `V e_x + ṙ`, `T = ½ m V² + V e_x · d/dt(...) + ½ ẋᵀ
//! M_tot(0) ẋ + O(3)`: the term linear in `V` is a total time derivative of the first
//! moment's inertial position and drops out of Lagrange's equations (Galilean invariance),
//! and the gyroscopic terms `ω×p` are second order. So the generalised mass is
//! `M = M_tot(0) = [[m 1, -c^×, P̄], [c^×, J, H̄], [P̄ᵀ, H̄ᵀ, M̄]]` (`c` the first moment,
//! `J` the second moment about the origin, `M̄ = Sᵀ M S` as the reduced model defines
//! them; for the SPHADS-1 free-free shapes `M̄` is diagonal, not the identity), and the
//! stiffness `K = diag(0₆, K̄)`, `K̄ = Sᵀ K S` (3.2.20). The reduced model's viscous modal
//! damping `C̄` is left out, as is structural damping: the classical boundary is the
//! `g = 0` crossing (as in the clamped case, [`super::fin`]). Gravity is left out: it only
//! turns the flight path (the slow roots `analyze linear` sets apart), it does not act on the
//! flutter coalescence.
//!
//! # Fin aerodynamics
//!
//! Per fin, the spline nodes and normal modal rows of the flight's panel model
//! (`aero::panel::fin_model::fin_structure`: the fin's FE nodes, the root row
//! attached to the body), extended by six columns for the rigid motions: a point at body
//! position `p` moves by `u = r + θ × p`, and its panel-normal displacement is
//! `z = -n · u` (`n` the fin's mesh normal, as `fin_structure`). The body position of a
//! spline node is rebuilt from its fin coordinates, `p = (x_LE,root - x) e_x + (y +
//! y_root) e_s` (exact without cant; cant is ignored in the aerodynamics, as in the panel
//! issue). A rigid rotation's normal displacement is linear over the fin plane, so the
//! spline reproduces it and its slope exactly (the spline is exact on linear fields,
//! `aero::panel::spline`): the slope `-∂z/∂x` of a pitch or yaw rotation is the
//! incidence it causes, `-i ν z` its plunge velocity, exactly the rigid normalwash of the
//! flight model (`fin_model`, the `a_0, a_x, a_y` columns). Each fin's `Q(k)` is then
//! [`super::fin::gaf_table`] on those rows (quasi-steady or the harmonic lattice with wake
//! subsonic, unsteady piston theory supersonic), and the vehicle's is the sum over the fins.
//!
//! # Body aerodynamics
//!
//! Quasi-steady, from the same tables and the same force block the flight uses
//! (`runtime::forces::body_aero`, the scenario's plan): the loads `f = (F_B, G_B, Q)` of the
//! block are differentiated by central differences at the reference state (`V_B = (V, 0,
//! 0)`, `ω_B = 0`, `η = η̇ = 0`, the scenario's altitude; steps of `analysis::linearise`),
//! `J = ∂f/∂(V_B, ω_B, η, η̇)`. In the coordinates `x`, to first order `V_B = V e_x + ṙ - θ
//! × V e_x` (`C_BI = 1 - θ^×`, eq. 4.4.9), `ω_B = θ̇`, and the inertial components of the
//! force and moment are `(1 + θ^×) (F_B, G_B)`, so
//! `f_x = D x + C ẋ` with `D = [0, -V J_V E - F₀^× ⊕ G₀^×, J_η]` (`E θ = θ × e_x`, `F₀`,
//! `G₀` the reference loads, the rotation of the reference drag) and `C = [J_V, J_ω, J_η̇]`.
//! For harmonic motion at `ω = k V / b` this is `q Q_B(k) x` with
//! `Q_B(k) = D / q₀ + i k (V / (q₀ b)) C`, taken at the reference speed `V` and scaled with
//! `q` over the sweep (`D ∝ q`, `C ∝ q / V` at fixed Mach: the same scaling as the fins'
//! quasi-steady map). The body's unsteady lag is neglected (its lift is slender-body and
//! crossflow theory, itself quasi-steady).
//!
//! Branches of identical fins can continue onto the same root (`pk`'s nearest-root
//! continuation is not exclusive); their flutter points are then one root's, listed once.
//!
//! # Start roots and divergence
//!
//! The six rigid branches all have the vacuum root 0, so continuation from `i ω_j` would put
//! them on one root: they start instead from the roots of the quasi-steady eigenproblem at
//! the lowest speed (`k` at the floor), the `2·6` of smallest modulus, the complex ones (the
//! pitch and yaw short periods) first, then the real ones by decreasing modulus (roll
//! subsidence, then the exact zeros of the free translations and of the flight-path angle).
//! The divergence reported is that of the elastic coordinates with the floating frame held
//! (`det(K̄ - q Q^R_ηη(0)) = 0`): a free vehicle has no static divergence of its rigid
//! coordinates other than its static instability, which shows as a real positive rigid
//! root of the p-k solution.
//!
//! # Results (SPHADS-1, 0.875 mm fins, Mach 0.624 of 200 m/s, 5 km; `tests/flutter_vehicle.rs`)
//!
//! - Unsteady panels: flutter at 196.24 m/s, 90.69 Hz, k = 0.471 (fin twist). The clamped
//!   fin with the same modal content (one bending, one torsion mode) flutters at 196.25 m/s,
//!   with four modes at 194.8 m/s: the body's participation is negligible at these fin
//!   frequencies, the +0.7 % to the 4-mode clamped fin is the vehicle's mode selection.
//! - Quasi-steady panels: 199.57 m/s, 88.79 Hz (clamped, 2 modes: 199.53 m/s). `analyze
//!   linear` (the quasi-steady lifting-surface flight model) puts the boundary of the 0.875
//!   mm fins at 200 m/s: -0.2 %; the unsteady p-k is -1.9 % from it, the wake lag and the
//!   apparent mass that the quasi-steady map omits.
//! - Without air the roots are the vacuum roots to 1e-9 (the rigid ones at 0 to
//!   `sqrt(ε) ω_max`, a double root), and the vacuum frequencies are the FE model's
//!   free-free frequencies to 8.5e-8.
//! - Rigid limit (4 mm fins, 200 m/s): no elastic flutter below 960 m/s; the rigid short
//!   period is 11.3 % below `analyze linear`'s with the panels' rigid loads (the lattice has
//!   no fin-body interference: 1/1.276 of the flight tables' fin pitch stiffness) and 5.6 %
//!   above it with the flight's own fin loads ([`flight_gaf`]); that last difference is the
//!   same (+3.7 to +5.5 %) with the lifting-surface fins at every thickness from 4 to 0.6 mm,
//!   so it lies between the two formulations, not in the aerodynamics, and is not explained
//!   (not gravity: `analyze linear` without it gives the same root; the decelerating
//!   reference and the p-k's `iω` for `p` are estimated at 0.2-0.3 %). The thesis
//!   scenarios' key-node fin model (`vehicles/sphads1.vdl`) gives thin fins a large
//!   aeroelastic loss of pitch stiffness that the panels do not (docs/validation.md,
//!   "Flexible fins"): compare the p-k with `analyze linear` on `model = lifting_surface`.

use faer::c64;

use super::fin::{FinFlutterError, FinFlutterSettings, FinModes, gaf_table};
use super::pk::{
    Divergence, FlutterModel, GafTable, K_FLOOR, PkSettings, PkSolution, divergence, pk_roots,
    pk_solve_cut_started,
};
use crate::aero::atmosphere::{Atmosphere, Standard1976};
use crate::aero::estimator::planform;
use crate::aero::panel::fin_model::fin_structure;
use crate::aero::panel::{Lattice, Spacing};
use crate::analysis::linear::{Variant, ballistic_plan};
use crate::analysis::linearise::step_size;
use crate::run::build_force_blocks;
use crate::runtime::eom::{ForceModel, StateLayout, StateView};
use crate::runtime::forces::ForceBlock;

/// Number of rigid coordinates (`r`, `θ`).
pub const N_RIGID: usize = 6;

/// Names of the rigid coordinates.
pub const RIGID_NAMES: [&str; N_RIGID] = [
    "rigid x (axial)",
    "rigid y (lateral)",
    "rigid z (plunge)",
    "rigid roll",
    "rigid pitch",
    "rigid yaw",
];

/// The free vehicle's generalised coordinates as the p-k solver and the panels see them.
#[derive(Clone, Debug, PartialEq)]
pub struct VehicleCoordinates {
    /// Coordinate names: the six rigid motions, then the modes.
    pub names: Vec<String>,
    /// Generalised mass `M_tot(0)` and stiffness `diag(0, K̄)`, row-major `N x N`.
    pub mass: Vec<f64>,
    pub stiffness: Vec<f64>,
    /// Per fin: its spline nodes and the normal rows of all `N` coordinates (the
    /// [`FinModes`] container; `omega` holds the vacuum frequency of the coordinate, 0 for
    /// the rigid ones).
    pub fins: Vec<FinModes>,
    /// The elastic modes' natural frequencies `ω_m` (rad/s) as the reduced model has them.
    pub omega_elastic: Vec<f64>,
}

impl VehicleCoordinates {
    pub fn order(&self) -> usize {
        self.names.len()
    }
    /// The reference semichord: half the fins' root chord (as the clamped fin).
    pub fn b_ref(&self) -> f64 {
        self.fins[0].b_ref()
    }
}

fn vehicle_error(e: impl std::fmt::Display) -> FinFlutterError {
    FinFlutterError::Vehicle(e.to_string())
}

/// The coordinates of the free vehicle of `variant` (module doc).
pub fn vehicle_coordinates(variant: &Variant) -> Result<VehicleCoordinates, FinFlutterError> {
    let v = &variant.scenario.vehicle;
    let c = &variant.compiled;
    let f = v.fins.as_ref().ok_or(FinFlutterError::NoFins)?;
    let red = &c.reduced;
    let n = c.modes.len();
    let nn = N_RIGID + n;
    if red.modal_mass.len() != n * n
        || red.modal_stiffness.len() != n * n
        || red.p_bar.len() != 3 * n
        || red.h_bar.len() != 3 * n
        || red.omega2.len() != n
    {
        return Err(vehicle_error(
            "the reduced model's matrices do not match its modes",
        ));
    }
    // M_tot(0) = [[m 1, -c^x, P̄], [c^x, J, H̄], [P̄ᵀ, H̄ᵀ, M̄]] (module doc).
    let mut mass = vec![0.0; nn * nn];
    let cm = red.first_moment;
    let cx = [
        [0.0, -cm[2], cm[1]],
        [cm[2], 0.0, -cm[0]],
        [-cm[1], cm[0], 0.0],
    ];
    for i in 0..3 {
        mass[i * nn + i] = red.mass;
        for j in 0..3 {
            mass[i * nn + 3 + j] = -cx[i][j];
            mass[(3 + i) * nn + j] = cx[i][j];
            mass[(3 + i) * nn + 3 + j] = red.inertia[i][j];
        }
        for m in 0..n {
            let p = red.p_bar[i * n + m];
            let h = red.h_bar[i * n + m];
            mass[i * nn + N_RIGID + m] = p;
            mass[(N_RIGID + m) * nn + i] = p;
            mass[(3 + i) * nn + N_RIGID + m] = h;
            mass[(N_RIGID + m) * nn + 3 + i] = h;
        }
    }
    let mut stiffness = vec![0.0; nn * nn];
    for a in 0..n {
        for b in 0..n {
            mass[(N_RIGID + a) * nn + N_RIGID + b] = red.modal_mass[a * n + b];
            stiffness[(N_RIGID + a) * nn + N_RIGID + b] = red.modal_stiffness[a * n + b];
        }
    }
    let omega_elastic: Vec<f64> = red.omega2.iter().map(|w| w.max(0.0).sqrt()).collect();
    let mut names: Vec<String> = RIGID_NAMES.iter().map(|s| s.to_string()).collect();
    names.extend(
        c.modes
            .iter()
            .map(|m| format!("{} ({}, {:.1} Hz)", m.name, m.class, m.frequency_hz)),
    );
    let mut omega = vec![0.0; N_RIGID];
    omega.extend(&omega_elastic);
    let pf = planform(f, 0.0);
    let y_root = match &v.structure {
        crate::check::ir::Structure::Generate(g) => g.body.root_radius(v.fins.as_ref()),
        // An imported structure: `fin_structure` measures the span from the innermost node.
        crate::check::ir::Structure::Files(_) => f64::NAN,
    };
    let root_le_x = f.root_trailing_edge_x.value + f.root_chord.value;
    let mut fins = Vec::with_capacity(f.angles.len());
    for (fin, angle) in f.angles.iter().enumerate() {
        let s = fin_structure(c, v, fin).map_err(vehicle_error)?;
        let (sd, cd) = angle.value.sin_cos();
        let (sg, cg) = f.cant.value.sin_cos();
        let es = [0.0, cd, sd];
        let ea = [cg, -sg * sd, sg * cd];
        let normal = cross(&ea, &es);
        let y0 = if y_root.is_nan() {
            innermost(c, fin, &es)
        } else {
            y_root
        };
        let mut rows = Vec::with_capacity(s.nodes.len() * nn);
        for (k, node) in s.nodes.iter().enumerate() {
            let p = [
                root_le_x - node[0],
                (node[1] + y0) * es[1],
                (node[1] + y0) * es[2],
            ];
            // Translations: z = -n · e_i; rotations: z = -n · (e_i × p) = -e_i · (p × n).
            let pn = cross(&p, &normal);
            rows.extend([-normal[0], -normal[1], -normal[2], -pn[0], -pn[1], -pn[2]]);
            rows.extend_from_slice(&s.normal_rows[k * n..(k + 1) * n]);
        }
        fins.push(FinModes {
            planform: pf.clone(),
            nodes: s.nodes,
            normal_rows: rows,
            omega: omega.clone(),
            names: names.clone(),
            thickness: f.thickness.value,
            // G12 of a lamina, else G = E / (2 (1 + ν)) (as `generate::FinSpec`).
            shear_modulus: f.material.in_plane_shear_modulus(),
        });
    }
    if fins.is_empty() {
        return Err(FinFlutterError::NoFins);
    }
    Ok(VehicleCoordinates {
        names,
        mass,
        stiffness,
        fins,
        omega_elastic,
    })
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The innermost span position of fin `fin`'s nodes (an imported structure's root).
fn innermost(c: &crate::structure::compile::CompiledVehicle, fin: usize, es: &[f64; 3]) -> f64 {
    (0..c.node_components.len())
        .filter(|&k| usize::try_from(c.node_components[k]).ok() == Some(fin))
        .map(|k| {
            let r = c.node_positions[k];
            r[0] * es[0] + r[1] * es[1] + r[2] * es[2]
        })
        .fold(f64::INFINITY, f64::min)
}

/// The body's quasi-steady generalised forces at the reference (module doc): `Q_B(k) = d +
/// i k c1`, row-major `N x N` each.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyGaf {
    pub d: Vec<f64>,
    pub c1: Vec<f64>,
}

/// Which of the flight's aerodynamic force blocks [`flight_gaf`] differentiates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlightBlocks {
    /// The body block (`runtime::forces::body_aero`): the body aerodynamics of the p-k model.
    Body,
    /// The fin blocks (`runtime::forces::fin_aero`, the scenario's fin model): the flight's
    /// quasi-steady fin loads, for comparison with the panel generalised forces.
    Fins,
}

/// The body aerodynamics of the scenario's plan differentiated at speed `speed` and
/// altitude `altitude` (module doc); `None` when the plan has no body aerodynamics block.
pub fn body_gaf(
    variant: &Variant,
    speed: f64,
    altitude: f64,
    b_ref: f64,
) -> Result<Option<BodyGaf>, FinFlutterError> {
    flight_gaf(variant, FlightBlocks::Body, speed, altitude, b_ref)
}

/// The quasi-steady generalised forces of the flight's own force blocks `which`, by central
/// differences at the reference (module doc, "Body aerodynamics"); `None` when the plan has
/// no such block.
pub fn flight_gaf(
    variant: &Variant,
    which: FlightBlocks,
    speed: f64,
    altitude: f64,
    b_ref: f64,
) -> Result<Option<BodyGaf>, FinFlutterError> {
    let plan = ballistic_plan(&variant.plan);
    let blocks = build_force_blocks(&plan, &variant.compiled.reduced).map_err(vehicle_error)?;
    let mut body: Vec<ForceBlock> = blocks
        .blocks
        .into_iter()
        .filter(|b| match which {
            FlightBlocks::Body => matches!(b, ForceBlock::BodyAero(_)),
            FlightBlocks::Fins => matches!(b, ForceBlock::FinAero(_)),
        })
        .collect();
    // The blocks' own air: their loads scale with the 1976 atmosphere's q at `altitude`.
    let density = Standard1976::new()
        .at(altitude)
        .map_err(vehicle_error)?
        .density;
    if body.is_empty() {
        return Ok(None);
    }
    let n = variant.compiled.modes.len();
    let nn = N_RIGID + n;
    let layout = StateLayout { n };
    let mut x0 = vec![0.0; layout.len()];
    x0[StateLayout::POSITION + 2] = -altitude;
    x0[StateLayout::ATTITUDE + 3] = 1.0;
    x0[StateLayout::VELOCITY] = speed;
    let mut loads = |x: &[f64]| -> Vec<f64> {
        let mut out = vec![0.0; N_RIGID + n];
        let view = StateView::new(layout, x);
        for b in &mut body {
            b.generalized_forces(0.0, &view, &mut out);
        }
        out
    };
    let f0 = loads(&x0);
    // Perturbed states: V_B (3), ω_B (3), η (n), η̇ (n).
    let mut cols: Vec<(usize, f64)> = Vec::with_capacity(6 + 2 * n);
    for i in 0..3 {
        cols.push((
            StateLayout::VELOCITY + i,
            step_size(x0[StateLayout::VELOCITY + i], speed),
        ));
    }
    for i in 0..3 {
        cols.push((StateLayout::ANGULAR_VELOCITY + i, step_size(0.0, 1.0)));
    }
    let shapes = &variant.compiled.shapes;
    let n_nodes = variant.compiled.node_positions.len();
    for m in 0..n {
        // s_m: the amplitude that moves some node by 1 m (analysis::linearise).
        let mut big = 0.0_f64;
        for k in 0..n_nodes {
            let t: f64 = (0..3)
                .map(|d| shapes[(6 * k + d) * n + m].powi(2))
                .sum::<f64>()
                .sqrt();
            big = big.max(t);
        }
        let s = if big > 0.0 { 1.0 / big } else { 1.0 };
        cols.push((StateLayout::ETA + m, step_size(0.0, s)));
    }
    let w = &variant.compiled.reduced.omega2;
    for m in 0..n {
        let s = cols[6 + m].1 / f64::EPSILON.cbrt();
        cols.push((
            StateLayout::ETA + n + m,
            step_size(0.0, w[m].max(0.0).sqrt().max(1.0) * s),
        ));
    }
    // J (nn x (6 + 2n)).
    let nc = cols.len();
    let mut jac = vec![0.0; nn * nc];
    let mut x = x0.clone();
    for (c, &(idx, h)) in cols.iter().enumerate() {
        x[idx] = x0[idx] + h;
        let fp = loads(&x);
        x[idx] = x0[idx] - h;
        let fm = loads(&x);
        x[idx] = x0[idx];
        for r in 0..nn {
            jac[r * nc + c] = (fp[r] - fm[r]) / (2.0 * h);
        }
    }
    if jac.iter().chain(&f0).any(|v| !v.is_finite()) {
        return Err(vehicle_error(
            "the body aerodynamics are not finite at the reference",
        ));
    }
    let q0 = 0.5 * density * speed * speed;
    let mut d = vec![0.0; nn * nn];
    let mut c1 = vec![0.0; nn * nn];
    let skew = |v: &[f64]| [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]];
    let (fx, gx) = (skew(&f0[0..3]), skew(&f0[3..6]));
    for r in 0..nn {
        let j = |c: usize| jac[r * nc + c];
        // θ columns: -V J_V E, with E θ = θ × e_x = (0, θ_z, -θ_y).
        // (J_V E)_θy = -J_Vz, (J_V E)_θz = J_Vy.
        d[r * nn + 4] += speed * j(2);
        d[r * nn + 5] -= speed * j(1);
        for m in 0..n {
            d[r * nn + N_RIGID + m] = j(6 + m);
        }
        for i in 0..3 {
            c1[r * nn + i] = j(i);
            c1[r * nn + 3 + i] = j(3 + i);
        }
        for m in 0..n {
            c1[r * nn + N_RIGID + m] = j(6 + n + m);
        }
    }
    // The reference loads turned with the body: (1 + θ^×) F₀ = F₀ - F₀^× θ.
    for i in 0..3 {
        for k in 0..3 {
            d[i * nn + 3 + k] -= fx[i][k];
            d[(3 + i) * nn + 3 + k] -= gx[i][k];
        }
    }
    let scale_c = speed / (q0 * b_ref);
    for v in &mut d {
        *v /= q0;
    }
    for v in &mut c1 {
        *v *= scale_c;
    }
    Ok(Some(BodyGaf { d, c1 }))
}

/// The lattice of the vehicle's fins (all fins share the declared planform).
pub fn vehicle_lattice(
    coords: &VehicleCoordinates,
    settings: &FinFlutterSettings,
) -> Result<Lattice, FinFlutterError> {
    Ok(Lattice::new(
        &coords.fins[0].planform,
        settings.chordwise,
        settings.spanwise,
        Spacing::Cosine,
    )?)
}

/// The vehicle's `Q(k)` at Mach `mach`: the sum over the fins of [`gaf_table`] on their
/// rows, plus the body's quasi-steady `Q_B(k)` (module doc).
pub fn vehicle_gaf(
    coords: &VehicleCoordinates,
    lattice: &Lattice,
    mach: f64,
    settings: &FinFlutterSettings,
    body: Option<&BodyGaf>,
) -> Result<GafTable, FinFlutterError> {
    let nn = coords.order();
    let mut ks: Vec<f64> = Vec::new();
    let mut sum: Vec<Vec<c64>> = Vec::new();
    for fin in &coords.fins {
        let t = gaf_table(fin, lattice, mach, settings)?;
        if sum.is_empty() {
            ks = t.ks().to_vec();
            sum = (0..ks.len()).map(|i| t.at(i).to_vec()).collect();
        } else {
            for (i, s) in sum.iter_mut().enumerate() {
                for (a, b) in s.iter_mut().zip(t.at(i)) {
                    *a += *b;
                }
            }
        }
    }
    if let Some(b) = body {
        for (i, s) in sum.iter_mut().enumerate() {
            let k = ks[i];
            for (e, v) in s.iter_mut().enumerate().take(nn * nn) {
                *v += c64::new(b.d[e], k * b.c1[e]);
            }
        }
    }
    Ok(GafTable::new(nn, ks, sum)?)
}

/// The flutter model of the free vehicle at air density `density` (module doc).
pub fn flutter_model(coords: &VehicleCoordinates, density: f64) -> FlutterModel {
    let nn = coords.order();
    FlutterModel {
        names: coords.names.clone(),
        mass: coords.mass.clone(),
        stiffness: coords.stiffness.clone(),
        damping: vec![0.0; nn * nn],
        structural_g: 0.0,
        b_ref: coords.b_ref(),
        density,
    }
}

/// The start roots of the branches at speed `v0` (module doc): rigid branches from the
/// quasi-steady eigenproblem, elastic ones at `i ω_j`.
pub fn start_roots(
    model: &FlutterModel,
    gaf: &GafTable,
    v0: f64,
) -> Result<Vec<c64>, FinFlutterError> {
    let vac = model.vacuum_modes()?;
    let mut roots = pk_roots(model, gaf, v0, K_FLOOR)?;
    roots.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
    let nr = N_RIGID.min(vac.len());
    let b = model.b_ref;
    // A root is oscillatory when its reduced frequency is above the floor (as the p-k
    // iteration decides); the conjugate of each pair is dropped. Identical pairs (the pitch
    // and yaw short periods of a vehicle with fins all round) are both kept.
    let small: Vec<c64> = roots.into_iter().take(2 * nr).collect();
    let mut upper: Vec<c64> = small
        .iter()
        .filter(|p| p.im * b / v0 > 10.0 * K_FLOOR)
        .copied()
        .collect();
    upper.sort_by(|x, y| y.norm().total_cmp(&x.norm()));
    let mut real: Vec<c64> = small
        .iter()
        .filter(|p| p.im.abs() * b / v0 <= 10.0 * K_FLOOR)
        .map(|p| c64::new(p.re, 0.0))
        .collect();
    real.sort_by(|x, y| y.norm().total_cmp(&x.norm()));
    let small: Vec<c64> = upper.into_iter().chain(real).collect();
    let mut starts: Vec<c64> = small.into_iter().take(nr).collect();
    starts.resize(nr, c64::new(0.0, 0.0));
    starts.extend(vac.iter().skip(nr).map(|&(w, _)| c64::new(0.0, w)));
    Ok(starts)
}

/// Branch names: a rigid branch by its start root ("short period" when oscillatory, "real
/// root" or "neutral"); an elastic branch by its vacuum frequency and the selected mode
/// with the largest share of its kinetic energy (`|u_i|² M_ii` over the modal coordinates:
/// the rigid coordinates of a free-free mode carry the floating frame's motion, not its
/// identity).
pub fn branch_names(model: &FlutterModel, starts: &[c64]) -> Result<Vec<String>, FinFlutterError> {
    use faer::Mat;
    use faer::linalg::solvers::Solve;
    let nn = model.order();
    let m = Mat::<f64>::from_fn(nn, nn, |i, j| model.mass[i * nn + j]);
    let k = Mat::<f64>::from_fn(nn, nn, |i, j| model.stiffness[i * nn + j]);
    let a = m.partial_piv_lu().solve(&k);
    let evd = a
        .eigen()
        .map_err(|_| vehicle_error("the vacuum eigenproblem failed"))?;
    let (u, ev) = (evd.U(), evd.S());
    let mut modes: Vec<(f64, usize)> = (0..nn)
        .map(|j| {
            let w = ev[j].re.max(0.0).sqrt();
            let best = (N_RIGID..nn)
                .max_by(|&x, &y| {
                    let e = |i: usize| u[(i, j)].norm().powi(2) * model.mass[i * nn + i];
                    e(x).total_cmp(&e(y))
                })
                .unwrap_or(0);
            (w, best)
        })
        .collect();
    modes.sort_by(|x, y| x.0.total_cmp(&y.0));
    Ok((0..nn)
        .map(|j| {
            if j < N_RIGID {
                let p = starts[j];
                if p.im > 0.0 {
                    format!(
                        "rigid short period ({:.2} Hz at the first speed)",
                        p.im / std::f64::consts::TAU
                    )
                } else if p.norm() > 1e-6 {
                    format!("rigid real root ({:.3} 1/s at the first speed)", p.re)
                } else {
                    "rigid neutral".to_string()
                }
            } else {
                let (w, i) = modes[j];
                format!(
                    "vehicle mode {} ({:.1} Hz, mostly {})",
                    j - N_RIGID + 1,
                    w / std::f64::consts::TAU,
                    model.names[i]
                )
            }
        })
        .collect())
}

/// The divergence of the elastic coordinates with the floating frame held (module doc).
pub fn elastic_divergence(
    model: &FlutterModel,
    gaf: &GafTable,
) -> Result<Option<Divergence>, FinFlutterError> {
    let nn = model.order();
    let n = nn - N_RIGID;
    if n == 0 {
        return Ok(None);
    }
    let sub = |m: &[f64]| -> Vec<f64> {
        (0..n * n)
            .map(|e| m[(N_RIGID + e / n) * nn + N_RIGID + e % n])
            .collect()
    };
    let ks = gaf.ks().to_vec();
    let values: Vec<Vec<c64>> = (0..ks.len())
        .map(|i| {
            let q = gaf.at(i);
            (0..n * n)
                .map(|e| q[(N_RIGID + e / n) * nn + N_RIGID + e % n])
                .collect()
        })
        .collect();
    let elastic = FlutterModel {
        names: model.names[N_RIGID..].to_vec(),
        mass: sub(&model.mass),
        stiffness: sub(&model.stiffness),
        damping: sub(&model.damping),
        structural_g: model.structural_g,
        b_ref: model.b_ref,
        density: model.density,
    };
    let table = GafTable::new(n, ks, values)?;
    Ok(divergence(&elastic, &table)?)
}

/// A solved free-vehicle case.
#[derive(Clone, Debug, PartialEq)]
pub struct VehicleFlutter {
    pub coordinates: VehicleCoordinates,
    pub solution: PkSolution,
    pub truncated: Option<(f64, usize)>,
    /// Whether the body's aerodynamics were included (the plan has a body block).
    pub body_aero: bool,
    pub lattice: (usize, usize),
    /// Vacuum frequencies of the branches (rad/s, ascending; the rigid ones 0).
    pub vacuum_omega: Vec<f64>,
    /// The transonic bridge of the fins' tables, in the band (`fin::bridged`).
    pub bridge: Option<super::fin::TransonicBridge>,
}

/// The p-k solution of the free vehicle of `variant` at Mach `mach`, density `density` and
/// altitude `altitude` over `speeds` (the body aerodynamics differentiated at `mach · a`,
/// `speed_of_sound` the `a` at that altitude).
#[allow(clippy::too_many_arguments)]
pub fn solve_vehicle(
    variant: &Variant,
    mach: f64,
    density: f64,
    altitude: f64,
    speed_of_sound: f64,
    speeds: &[f64],
    settings: &FinFlutterSettings,
    with_body: bool,
) -> Result<VehicleFlutter, FinFlutterError> {
    let coords = vehicle_coordinates(variant)?;
    solve_coordinates(
        variant,
        coords,
        mach,
        density,
        altitude,
        speed_of_sound,
        speeds,
        settings,
        with_body,
    )
}

/// [`solve_vehicle`] on given coordinates (tests alter them).
#[allow(clippy::too_many_arguments)]
pub fn solve_coordinates(
    variant: &Variant,
    coords: VehicleCoordinates,
    mach: f64,
    density: f64,
    altitude: f64,
    speed_of_sound: f64,
    speeds: &[f64],
    settings: &FinFlutterSettings,
    with_body: bool,
) -> Result<VehicleFlutter, FinFlutterError> {
    crate::aero::panel::regime(mach)?;
    let lattice = vehicle_lattice(&coords, settings)?;
    let body = if with_body {
        body_gaf(variant, mach * speed_of_sound, altitude, coords.b_ref())?
    } else {
        None
    };
    // In the transonic band the fins' tables are bridged between the band's ends
    // (`fin::bridged`); the body's quasi-steady loads, at the flight's speed, are the same in
    // both ends and so in the blend.
    let (gaf, bridge) = super::fin::bridged(mach, settings.aero, |m| {
        vehicle_gaf(&coords, &lattice, m, settings, body.as_ref())
    })?;
    let mut r = solve_gaf(coords, gaf, density, speeds, body.is_some(), settings)?;
    r.bridge = bridge;
    Ok(r)
}

/// The p-k solution on given coordinates and generalised forces (start roots, sweep,
/// divergence and names as [`solve_vehicle`]).
pub fn solve_gaf(
    coords: VehicleCoordinates,
    gaf: GafTable,
    density: f64,
    speeds: &[f64],
    body_aero: bool,
    settings: &FinFlutterSettings,
) -> Result<VehicleFlutter, FinFlutterError> {
    let model = flutter_model(&coords, density);
    let v0 = speeds.first().copied().unwrap_or(f64::NAN);
    let starts = start_roots(&model, &gaf, v0)?;
    let (mut solution, truncated) =
        pk_solve_cut_started(&model, &gaf, speeds, PkSettings::default(), &starts)?;
    solution.divergence = elastic_divergence(&model, &gaf)?;
    solution.names = branch_names(&model, &starts)?;
    // Branches of identical fins can continue onto one root (the continuation is not
    // exclusive, module doc of `pk`): one flutter point per root (speed and frequency
    // equal to 1e-8), the first branch's.
    let mut unique: Vec<super::pk::FlutterPoint> = Vec::with_capacity(solution.flutter.len());
    for f in std::mem::take(&mut solution.flutter) {
        let same = |u: &super::pk::FlutterPoint| {
            (u.speed - f.speed).abs() <= 1e-8 * f.speed
                && (u.omega - f.omega).abs() <= 1e-8 * f.omega.abs().max(1.0)
        };
        if !unique.iter().any(same) {
            unique.push(f);
        }
    }
    solution.flutter = unique;
    for f in &mut solution.flutter {
        f.name = solution.names[f.mode].clone();
        if let Some(p) = &mut f.partner {
            p.1 = solution.names[p.0].clone();
        }
    }
    let vacuum_omega = model.vacuum_modes()?.iter().map(|m| m.0).collect();
    Ok(VehicleFlutter {
        vacuum_omega,
        coordinates: coords,
        solution,
        truncated,
        body_aero,
        lattice: (settings.chordwise, settings.spanwise),
        bridge: None,
    })
}
