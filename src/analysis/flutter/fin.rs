//! The fin designer's flutter case (issue 13, deliverable 2a): one fin of the vehicle clamped
//! at its root, its shell modes, and the generalised aerodynamic forces of the fin panels
//! (issue 12's lattice) for the p-k solver of [`super::pk`].
//!
//! # Structure
//!
//! The fin is the vehicle's generated fin (`structure::generate::cantilever_fin_model`: the
//! same shell mesh, material and thickness as in the vehicle, every root DOF removed). Its
//! lowest `n` elastic modes, mass-normalised (`φᵀ M φ = I`), are the generalised coordinates:
//! generalised mass `I`, stiffness `diag(ω_j²)`. No structural damping is assumed unless given
//! (the classical flutter boundary is the `g = 0` crossing; Rodden & Johnson, MSC Nastran
//! Aeroelastic Analysis User's Guide, §2.6). A clamped root is the usual fin-flutter idealisation
//! (NACA TN 4197 assumes it); the flexible vehicle's own modes are analysed by `analyze
//! linear`, whose body participation a clamped root ignores.
//!
//! Fin coordinates are those of `aero::panel` (`x` aft of the root leading edge,
//! `y` out along the span from the root, panel `+z = x_aft × e_s`). The cantilever mesh lies
//! in the body `x-y` plane with its root on `y = 0`; with cant `γ` its normal is
//! `n = e_a × e_s = (-sin γ, 0, cos γ)` and the panel normal displacement is `z = -n · u`
//! (as `fin_model::fin_structure`). The clamped root row is added to the spline's nodes with
//! zero displacement, so the spline's slope near the root sees the clamp. Cant is ignored in
//! the aerodynamics (as in the panel issue): the lattice lies on the uncanted planform.
//!
//! # Generalised aerodynamic forces
//!
//! For harmonic motion `η e^{iωt}`, `ν = ω / V = k / b` (`b` the reference semichord), the
//! normalwash angle of `aero::panel` is `α_e = -∂z/∂x - (1/V) ∂z/∂t = (-Z_x - i ν Z_c) η`
//! at the normalwash points (`Z_x`, `Z_c` the spline's slope and value rows times the modal
//! normal displacements), the panel forces `F = q K(ν, M) α_e` at the force points, and the
//! generalised forces by virtual work `Q = Z_fᵀ F` (`Z_f` the spline's value rows at the force
//! points; `aero::panel::spline`, "consistent forces"):
//!
//! `Q(k) = Z_fᵀ K(k/b, M) (-Z_x - i (k/b) Z_c)`, the `q Q(k) η` of [`super::pk`].
//!
//! Two force maps `K` are offered ([`FinAero`]): the quasi-steady one of the flight
//! (`vlm::force_map` / `piston::force_map`, `K` independent of `ν`: Theodorsen's `C(k) = 1`,
//! no apparent mass) and the unsteady one (`panel::harmonic`, the vortex lattice with a
//! harmonic wake; piston theory, being local, has the same map in both); a third,
//! [`FinAero::DoubletLattice`], replaces the subsonic harmonic vortex lattice by the
//! doublet-lattice method of `panel::dlm` (the compressible unsteady kernel instead of
//! Göthert's stretch; `n` force points at the box quarter chords). The doublet lattice is the
//! default of `analyze flutter` and of the flight margin (issue 33: the better validated of
//! the two, docs/validation.md); their lattices add spanwise strips until every box meets
//! its aspect-ratio rule (`panel::dlm::spanwise_for`), while a lattice given here explicitly
//! ([`FinFlutterSettings`]) is used as given and refused if its boxes are too wide.
//!
//! # The transonic band: a bridge in the aerodynamic matrices (issue 33)
//!
//! Linear theory has no answer near Mach 1 (its lift grows like `1/|β|` from both sides) and
//! each method stops where its own error says so ([`bridge_ends`]):
//!
//! * the subsonic end `M_lo`: the harmonic vortex lattice at [`panel::SUBSONIC_LIMIT`] = 0.9
//!   (Göthert's stretch drops the acoustic terms, of relative size `4kM²/β²`: 17 k at 0.9,
//!   `panel::harmonic`); the doublet lattice at its [`crate::aero::panel::dlm::MACH_LIMIT`] =
//!   0.95 (there `β² = 0.0975` and the kernel's acoustic wavelength `2πβ²/(νM)` reaches the
//!   box-size rule, `panel::dlm`); the quasi-steady vortex lattice at 0.9;
//! * the supersonic end `M_hi`: the Mach box at [`machbox::MIN_MACH`] = 1.1 (its boxes are
//!   `β` times longer than wide, so a fixed box count along the chord leaves fewer columns on
//!   the span as `β -> 0`; measured at the default 32 boxes against the steady
//!   constant-pressure panels, `machbox_tests::first_mach_from_the_box_error`, the slope error
//!   is within the method's 2.5 % tolerance at 1.1 and above; see the test for the figures
//!   at 1.02-1.075); the quasi-steady map at [`panel::SUPERSONIC_LIMIT`] = 1.2 (piston theory).
//!
//! Between them, `M_lo < M < M_hi`, the generalised forces are the straight line in Mach
//! between the two end tables at the SAME reduced frequencies,
//!
//! `Q(k, M) = (1 - t) Q(k, M_lo) + t Q(k, M_hi)`, `t = (M - M_lo)/(M_hi - M_lo)`
//!
//! (entry by entry; the natural spline in `k` of [`GafTable`] is linear in its data, so the
//! bridged table's spline is the same blend of the two splines). Linear in `M` rather than in a
//! Prandtl-Glauert variable: both ends' `1/|β|` factors are infinite at `M = 1`, where real
//! (transonic, nonlinear) flow gives finite loads, so no `β`-based variable is right inside the
//! band; the straight line is the one choice that assumes nothing between the ends.
//!
//! *Uncertainty (derived).* Inside the band nothing in linear theory prefers one way of
//! joining the two ends over another, so the uncertainty is the spread between two choices
//! that respect both ends: the straight line, and the nearer end held to the middle of the
//! band (each method used as far as it can be, the jump at `t = 1/2`). They differ by
//! `min(t, 1 - t)` of the jump `Q(k, M_hi) - Q(k, M_lo)`, entry by entry, so the stated
//! relative uncertainty of the bridged table is
//!
//! `u_Q = min(t, 1 - t) max_k |Q(k, M_hi) - Q(k, M_lo)|_F / |Q(k, M)|_F`,
//!
//! measured on the case's own two end tables (never tuned): zero at the ends, where each
//! method is trusted, largest mid-band. On SPHADS-1's fin (3 modes, `k <= 0.5`) the jump
//! relative to the mid-band table is 0.72 (unsteady: vortex lattice at 0.9 against the Mach
//! box at 1.1), 0.67 (doublet lattice from 0.95) and 1.36 (quasi-steady: piston theory with
//! Ackeret's factor at 1.2), so mid-band `u_Q` is 0.34-0.68 and the speed's `u` 16-30 % (measured by
//! `the_bridge_is_linear_in_mach_between_its_end_tables`, `tests/flutter_fin.rs`). No transonic dip is modelled: real
//! transonic flow lowers the flutter speed inside the band (AGARD 445.6: 16-17 % from Mach
//! 0.901 to 0.954-0.960, docs/validation.md), which this straight line cannot show. Scaling the aerodynamic matrices
//! by `1 + u_Q` scales the flutter dynamic pressure by `1/(1 + u_Q)` (exactly for the
//! quasi-steady `Q`, to first order in the slope of `Q(k)` otherwise), so the flutter SPEED's
//! relative uncertainty is `u = sqrt(1 + u_Q) - 1` ([`TransonicBridge::uncertainty`]); the
//! reports name the method `transonic bridge (+-u %)` and the flight margin divides its margin
//! by `1 + u` ([`super::margin`]).

use faer::c64;
use rayon::prelude::*;

use super::pk::{FlutterError, FlutterModel, GafTable, PkSettings, PkSolution, pk_solve_screened};
use crate::aero::estimator::FinPlanform;
use crate::aero::estimator::planform;
use crate::aero::panel::dlm::{Dlm, MAX_BOX_ASPECT, max_box_aspect};
use crate::aero::panel::harmonic::{self, HarmonicMap, HarmonicVlm, WakeSettings};
use crate::aero::panel::machbox::{self, MachBox};
use crate::aero::panel::piston::{self, Correction};
use crate::aero::panel::spline::{SplineError, surface_spline};
use crate::aero::panel::{self, Lattice, PanelError, Regime, Spacing, vlm};
use crate::check::ir;
use crate::structure::compile::generator_spec;
use crate::structure::{generate, modal};

/// Which panel force map the generalised forces use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FinAero {
    /// The flight's quasi-steady map (`K` independent of the reduced frequency).
    QuasiSteady,
    /// The harmonic vortex lattice (subsonic) and unsteady piston theory (supersonic).
    Unsteady,
    /// The doublet-lattice method (subsonic, `panel::dlm`: the compressible unsteady kernel)
    /// and unsteady piston theory (supersonic).
    DoubletLattice,
}

impl FinAero {
    pub fn name(self) -> &'static str {
        match self {
            FinAero::QuasiSteady => "quasi_steady",
            FinAero::Unsteady => "unsteady",
            FinAero::DoubletLattice => "doublet_lattice",
        }
    }

    /// Whether the map depends on the reduced frequency (a harmonic model).
    pub fn is_harmonic(self) -> bool {
        self != FinAero::QuasiSteady
    }
}

/// Why a fin flutter case could not be built or solved.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FinFlutterError {
    #[error("the vehicle has no unnamed `fins` block (its flexible set)")]
    NoFins,
    #[error(
        "a clamped fin needs a generated structure (`structure {{ generate {{ ... }} }}`); an imported FE model has no separable fin root"
    )]
    NotGenerated,
    #[error("the clamped fin model could not be built: {0}")]
    Generate(String),
    #[error("the clamped fin's modes could not be computed: {0}")]
    Modal(String),
    #[error("the clamped fin has fewer elastic modes ({got}) than requested ({wanted})")]
    TooFewModes { got: usize, wanted: usize },
    #[error("fin panels: {0}")]
    Panel(#[from] PanelError),
    #[error("fin spline: {0}")]
    Spline(#[from] SplineError),
    #[error("flutter solution: {0}")]
    Flutter(#[from] FlutterError),
    #[error("free vehicle: {0}")]
    Vehicle(String),
    #[error(
        "the transonic bridge at Mach {mach} needs the same reduced frequencies in its two end tables"
    )]
    BridgeMismatch { mach: f64 },
    #[error(
        "the doublet-lattice boxes reach an aspect ratio (width over chord) of {ratio:.2}, above {limit}, where the parabolic approximation of the kernel across a box is poor (Rodden, Taylor & McIntosh 1998)"
    )]
    WideBoxes { ratio: f64, limit: f64 },
}

/// The clamped fin's modes as the panels see them.
#[derive(Clone, Debug, PartialEq)]
pub struct FinModes {
    pub planform: FinPlanform,
    /// Spline nodes in fin coordinates (m): the shell nodes, then the clamped root row.
    pub nodes: Vec<[f64; 2]>,
    /// Panel-normal displacement per unit modal coordinate, row-major `nodes x n`.
    pub normal_rows: Vec<f64>,
    /// Natural frequencies, rad/s, ascending.
    pub omega: Vec<f64>,
    /// Mode names, e.g. "mode 1 (bending, 112.3 Hz)".
    pub names: Vec<String>,
    /// Fin thickness, m, and its material's in-plane shear modulus, Pa (`G12` of a lamina),
    /// for TN 4197 alongside.
    pub thickness: f64,
    pub shear_modulus: f64,
}

impl FinModes {
    pub fn order(&self) -> usize {
        self.omega.len()
    }
    /// The reference semichord `b` of the reduced frequency: half the root chord (the
    /// convention of AGARD 445.6 and NACA TN 4197's root-chord based parameters).
    pub fn b_ref(&self) -> f64 {
        0.5 * self.planform.root_chord
    }
}

/// The lowest `n_modes` elastic modes of fin 0 of `v` clamped at its root (module doc).
pub fn clamped_fin_modes(v: &ir::Vehicle, n_modes: usize) -> Result<FinModes, FinFlutterError> {
    let f = v.fins.as_ref().ok_or(FinFlutterError::NoFins)?;
    let ir::Structure::Generate(g) = &v.structure else {
        return Err(FinFlutterError::NotGenerated);
    };
    let spec = generator_spec(v, g);
    let fin = spec.fins.ok_or(FinFlutterError::NoFins)?;
    let model = generate::cantilever_fin_model(&fin)
        .map_err(|e| FinFlutterError::Generate(e.to_string()))?;
    let modes = modal::solve(&model, n_modes).map_err(|e| FinFlutterError::Modal(e.to_string()))?;
    let elastic = modes.omega2.len() - modes.n_rigid;
    if elastic < n_modes {
        return Err(FinFlutterError::TooFewModes {
            got: elastic,
            wanted: n_modes,
        });
    }
    let root_le_x = fin.root_trailing_edge_x + fin.root_chord;
    let (sg, cg) = fin.cant.sin_cos();
    let mut nodes = Vec::with_capacity(model.nodes.len() + fin.chord_elements + 1);
    let mut rows = Vec::with_capacity(nodes.capacity() * n_modes);
    for (k, node) in model.nodes.iter().enumerate() {
        let r = node.position;
        nodes.push([root_le_x - r[0], r[1]]);
        for j in 0..n_modes {
            let col = modes.n_rigid + j;
            let ux = modes.shapes[(6 * k, col)];
            let uz = modes.shapes[(6 * k + 2, col)];
            // z = -n · u, n = (-sin γ, 0, cos γ).
            rows.push(sg * ux - cg * uz);
        }
    }
    for i in 0..=fin.chord_elements {
        let (x, _) = fin.planform_point(i, 0);
        nodes.push([root_le_x - x, 0.0]);
        rows.extend(std::iter::repeat_n(0.0, n_modes));
    }
    let omega: Vec<f64> = (0..n_modes)
        .map(|j| modes.omega2[modes.n_rigid + j].max(0.0).sqrt())
        .collect();
    let pf = planform(f, 0.0);
    let names = (0..n_modes)
        .map(|j| {
            format!(
                "mode {} ({}, {:.1} Hz)",
                j + 1,
                mode_kind(&nodes, &rows, n_modes, j, &pf),
                omega[j] / (2.0 * std::f64::consts::PI)
            )
        })
        .collect();
    Ok(FinModes {
        planform: pf,
        nodes,
        normal_rows: rows,
        omega,
        names,
        thickness: fin.thickness,
        shear_modulus: fin.in_plane_shear_modulus(),
    })
}

/// "bending" when the tip row's leading- and trailing-edge nodes move the same way, else
/// "torsion" (the nodal line runs along the span).
fn mode_kind(
    nodes: &[[f64; 2]],
    rows: &[f64],
    n: usize,
    j: usize,
    pf: &FinPlanform,
) -> &'static str {
    let tip = nodes.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
    let on_tip: Vec<usize> = (0..nodes.len())
        .filter(|&k| (nodes[k][1] - tip).abs() < 1e-9 * pf.span.max(1.0))
        .collect();
    let le = on_tip
        .iter()
        .copied()
        .min_by(|&a, &b| nodes[a][0].total_cmp(&nodes[b][0]));
    let te = on_tip
        .iter()
        .copied()
        .max_by(|&a, &b| nodes[a][0].total_cmp(&nodes[b][0]));
    match (le, te) {
        (Some(a), Some(b)) if rows[a * n + j] * rows[b * n + j] >= 0.0 => "bending",
        (Some(_), Some(_)) => "torsion",
        _ => "mode",
    }
}

/// A complex panel force map at one Mach and reduced frequency: panel forces
/// `F = q K α_e`, `K` row-major `force.len() x eval.len()`.
#[derive(Clone, Debug, PartialEq)]
pub struct PanelMap {
    pub eval: Vec<[f64; 2]>,
    pub force: Vec<[f64; 2]>,
    pub k: Vec<c64>,
}

/// The quasi-steady map of the flight at a trusted Mach (vortex lattice at control points and
/// bound mid-points, or piston theory at the centroids).
pub fn quasi_steady_map(
    lattice: &Lattice,
    mach: f64,
    correction: Correction,
) -> Result<PanelMap, FinFlutterError> {
    let n = lattice.len();
    let (eval, force, k) = match panel::regime(mach)? {
        Regime::Subsonic => (
            lattice.panels.iter().map(|p| p.control).collect(),
            lattice.panels.iter().map(|p| p.bound_mid()).collect(),
            vlm::force_map(lattice, mach)?,
        ),
        Regime::Supersonic => {
            let c: Vec<[f64; 2]> = lattice.panels.iter().map(|p| p.centroid).collect();
            (c.clone(), c, piston::force_map(lattice, mach, correction)?)
        }
        Regime::Transonic { .. } => {
            return Err(PanelError::Untrusted(mach, "quasi-steady map").into());
        }
    };
    debug_assert_eq!(k.len(), n * n);
    Ok(PanelMap {
        eval,
        force,
        k: k.into_iter().map(|v| c64::new(v, 0.0)).collect(),
    })
}

/// The spline rows of the modes at a map's points: `Z_c`, `Z_x` (eval x n) and `Z_f`
/// (force x n).
struct PointRows {
    zc: Vec<f64>,
    zx: Vec<f64>,
    zf: Vec<f64>,
}

fn point_rows(modes: &FinModes, map: &PanelMap) -> Result<PointRows, FinFlutterError> {
    let n = modes.order();
    let nn = modes.nodes.len();
    let scale = modes.planform.root_chord;
    let project = |g: &[f64], np: usize| -> Vec<f64> {
        let mut z = vec![0.0; np * n];
        for p in 0..np {
            for k in 0..nn {
                let w = g[p * nn + k];
                if w != 0.0 {
                    for j in 0..n {
                        z[p * n + j] += w * modes.normal_rows[k * n + j];
                    }
                }
            }
        }
        z
    };
    let (gc, gx) = surface_spline(&modes.nodes, &map.eval, scale)?;
    let (gf, _) = surface_spline(&modes.nodes, &map.force, scale)?;
    Ok(PointRows {
        zc: project(&gc, map.eval.len()),
        zx: project(&gx, map.eval.len()),
        zf: project(&gf, map.force.len()),
    })
}

/// `Q(k) = Z_fᵀ K (-Z_x - i (k/b) Z_c)` (module doc), row-major `n x n`.
fn gaf_matrix(rows: &PointRows, map: &PanelMap, n: usize, nu: f64) -> Vec<c64> {
    let (ne, nf) = (map.eval.len(), map.force.len());
    // A = -Z_x - i ν Z_c (ne x n).
    let a: Vec<c64> = (0..ne * n)
        .map(|e| c64::new(-rows.zx[e], -nu * rows.zc[e]))
        .collect();
    // KA (nf x n).
    let mut ka = vec![c64::new(0.0, 0.0); nf * n];
    for p in 0..nf {
        for r in 0..ne {
            let kv = map.k[p * ne + r];
            if kv != c64::new(0.0, 0.0) {
                for j in 0..n {
                    ka[p * n + j] += kv * a[r * n + j];
                }
            }
        }
    }
    virtual_work(rows, &ka, nf, n)
}

/// `Q = Z_fᵀ F`: the generalised forces of panel forces `f` (`nf x n`, one column per mode's
/// motion) by virtual work at the force points.
fn virtual_work(rows: &PointRows, f: &[c64], nf: usize, n: usize) -> Vec<c64> {
    let mut q = vec![c64::new(0.0, 0.0); n * n];
    for p in 0..nf {
        for i in 0..n {
            let z = rows.zf[p * n + i];
            if z != 0.0 {
                for j in 0..n {
                    q[i * n + j] += f[p * n + j] * z;
                }
            }
        }
    }
    q
}

/// Settings of a fin flutter solution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FinFlutterSettings {
    pub aero: FinAero,
    pub chordwise: usize,
    pub spanwise: usize,
    pub correction: Correction,
    /// Reduced frequencies of the GAF table: `count` values from 0 to `k_max`.
    pub k_count: usize,
    pub k_max: f64,
}

impl Default for FinFlutterSettings {
    fn default() -> Self {
        FinFlutterSettings {
            aero: FinAero::QuasiSteady,
            chordwise: 8,
            spanwise: 12,
            correction: Correction::Ackeret,
            k_count: 20,
            k_max: 2.0,
        }
    }
}

/// The lattice of the fin for `settings`.
pub fn fin_lattice(
    modes: &FinModes,
    settings: &FinFlutterSettings,
) -> Result<Lattice, FinFlutterError> {
    Ok(Lattice::new(
        &modes.planform,
        settings.chordwise,
        settings.spanwise,
        Spacing::Cosine,
    )?)
}

/// The reduced frequencies of the GAF table of `settings`: `k_count` (at least 2) evenly
/// spaced from 0 to `k_max`; two for the quasi-steady map, whose `Q(k) = Q(0) + i (k/b) Z_fᵀ K
/// (-Z_c)` is exactly linear in `k` (the natural spline through two knots is that line).
pub fn gaf_ks(settings: &FinFlutterSettings) -> Vec<f64> {
    let count = match settings.aero {
        FinAero::QuasiSteady => 2,
        FinAero::Unsteady | FinAero::DoubletLattice => settings.k_count.max(2),
    };
    (0..count)
        .map(|i| settings.k_max * i as f64 / (count - 1) as f64)
        .collect()
}

/// The tabulated `Q(k)` of the clamped fin at Mach `mach` (module doc), bridged in the
/// transonic band ([`gaf_table_bridged`]).
pub fn gaf_table(
    modes: &FinModes,
    lattice: &Lattice,
    mach: f64,
    settings: &FinFlutterSettings,
) -> Result<GafTable, FinFlutterError> {
    Ok(gaf_table_bridged(modes, lattice, mach, settings)?.0)
}

/// The tabulated `Q(k)` of the clamped fin at Mach `mach` and, in the transonic band of
/// `settings.aero`, the bridge it was made by (module doc).
pub fn gaf_table_bridged(
    modes: &FinModes,
    lattice: &Lattice,
    mach: f64,
    settings: &FinFlutterSettings,
) -> Result<(GafTable, Option<TransonicBridge>), FinFlutterError> {
    bridged(mach, settings.aero, |m| {
        direct_gaf_table(modes, lattice, m, settings)
    })
}

/// The end Machs `(M_lo, M_hi)` of the transonic bridge of `aero` (module doc): the last
/// Mach of its subsonic method and the first of its supersonic one.
pub fn bridge_ends(aero: FinAero) -> (f64, f64) {
    match aero {
        FinAero::QuasiSteady => (panel::SUBSONIC_LIMIT, panel::SUPERSONIC_LIMIT),
        FinAero::Unsteady => (panel::SUBSONIC_LIMIT, machbox::MIN_MACH),
        FinAero::DoubletLattice => (crate::aero::panel::dlm::MACH_LIMIT, machbox::MIN_MACH),
    }
}

/// Whether Mach `mach` lies strictly inside the transonic band of `aero`.
pub fn in_bridge(mach: f64, aero: FinAero) -> bool {
    let (lo, hi) = bridge_ends(aero);
    mach > lo && mach < hi
}

/// How a table in the transonic band was made (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransonicBridge {
    /// The end Machs.
    pub low: f64,
    pub high: f64,
    /// The weight `t` of the high end.
    pub t: f64,
    /// `u_Q`, the relative uncertainty of the bridged matrices: `min(t, 1 - t)` times the
    /// largest relative jump between the ends (module doc).
    pub matrix_uncertainty: f64,
    /// `u = sqrt(1 + u_Q) - 1`, the relative uncertainty of the flutter speed.
    pub uncertainty: f64,
}

impl TransonicBridge {
    /// The method's name in reports: `transonic bridge (+-X %)` and its ends.
    pub fn name(&self, low: &str, high: &str) -> String {
        format!(
            "transonic bridge (+-{:.1} %): Q(k) linear in Mach between {low} at Mach {} and {high} at Mach {}",
            100.0 * self.uncertainty,
            self.low,
            self.high
        )
    }
}

/// The bridged table at `mach` from the end tables `lo` (at `low`) and `hi` (at `high`),
/// which must share their reduced frequencies (module doc).
pub fn blend_tables(
    lo: &GafTable,
    hi: &GafTable,
    mach: f64,
    low: f64,
    high: f64,
) -> Result<(GafTable, TransonicBridge), FinFlutterError> {
    if lo.ks() != hi.ks() || lo.order() != hi.order() {
        return Err(FinFlutterError::BridgeMismatch { mach });
    }
    let t = (mach - low) / (high - low);
    let w = t.min(1.0 - t);
    let mut values = Vec::with_capacity(lo.ks().len());
    let mut u_q: f64 = 0.0;
    for i in 0..lo.ks().len() {
        let (a, b) = (lo.at(i), hi.at(i));
        let v: Vec<c64> = a
            .iter()
            .zip(b)
            .map(|(x, y)| *x * (1.0 - t) + *y * t)
            .collect();
        let jump = a
            .iter()
            .zip(b)
            .map(|(x, y)| (*y - *x).norm_sqr())
            .sum::<f64>()
            .sqrt();
        let size = v.iter().map(|x| x.norm_sqr()).sum::<f64>().sqrt();
        if size > 0.0 {
            u_q = u_q.max(w * jump / size);
        }
        values.push(v);
    }
    let table = GafTable::new(lo.order(), lo.ks().to_vec(), values)?;
    Ok((
        table,
        TransonicBridge {
            low,
            high,
            t,
            matrix_uncertainty: u_q,
            uncertainty: (1.0 + u_q).sqrt() - 1.0,
        },
    ))
}

/// The table `build(mach)` outside the transonic band of `aero`, the blend of `build(M_lo)`
/// and `build(M_hi)` inside it (module doc).
pub fn bridged<E: From<FinFlutterError>>(
    mach: f64,
    aero: FinAero,
    mut build: impl FnMut(f64) -> Result<GafTable, E>,
) -> Result<(GafTable, Option<TransonicBridge>), E> {
    if !in_bridge(mach, aero) {
        return Ok((build(mach)?, None));
    }
    let (low, high) = bridge_ends(aero);
    let lo = build(low)?;
    let hi = build(high)?;
    let (table, b) = blend_tables(&lo, &hi, mach, low, high)?;
    Ok((table, Some(b)))
}

/// The tabulated `Q(k)` of the clamped fin at a Mach outside the transonic band (module doc).
fn direct_gaf_table(
    modes: &FinModes,
    lattice: &Lattice,
    mach: f64,
    settings: &FinFlutterSettings,
) -> Result<GafTable, FinFlutterError> {
    let n = modes.order();
    let b = modes.b_ref();
    let ks = gaf_ks(settings);
    let values = match settings.aero {
        FinAero::QuasiSteady => {
            let map = quasi_steady_map(lattice, mach, settings.correction)?;
            let rows = point_rows(modes, &map)?;
            ks.iter()
                .map(|&k| gaf_matrix(&rows, &map, n, k / b))
                .collect()
        }
        FinAero::Unsteady | FinAero::DoubletLattice => {
            unsteady_values(modes, lattice, mach, settings, &ks)?
        }
    };
    Ok(GafTable::new(n, ks, values)?)
}

fn unsteady_values(
    modes: &FinModes,
    lattice: &Lattice,
    mach: f64,
    settings: &FinFlutterSettings,
    ks: &[f64],
) -> Result<Vec<Vec<c64>>, FinFlutterError> {
    let n = modes.order();
    let b = modes.b_ref();
    let regime = match panel::regime(mach)? {
        // The doublet lattice holds to its own limit, above the vortex lattice's.
        Regime::Transonic { .. }
            if settings.aero == FinAero::DoubletLattice
                && mach <= crate::aero::panel::dlm::MACH_LIMIT =>
        {
            Regime::Subsonic
        }
        r => r,
    };
    match regime {
        // Piston theory is local: its unsteady map is the quasi-steady one applied to the
        // complex normalwash (Ashley & Zartarian 1956; `panel::harmonic::piston_map`).
        Regime::Supersonic | Regime::Transonic { .. }
            if mach >= machbox::MIN_MACH && !machbox::piston_valid(&lattice.planform, mach) =>
        {
            let boxes = mach_boxes(&lattice.planform, mach, settings.k_max / b);
            let mb = MachBox::new(&lattice.planform, mach, boxes)?;
            let m0 = HarmonicMap {
                eval: mb.centres().to_vec(),
                force: mb.centres().to_vec(),
                k: Vec::new(),
            };
            harmonic_gafs(modes, m0, ks, b, n, |nu, alpha| mb.forces(nu, alpha, n))
        }
        Regime::Supersonic => {
            let h = harmonic::piston_map(lattice, mach, settings.correction)?;
            let map = PanelMap {
                eval: h.eval,
                force: h.force,
                k: h.k,
            };
            let rows = point_rows(modes, &map)?;
            Ok(ks
                .iter()
                .map(|&k| gaf_matrix(&rows, &map, n, k / b))
                .collect())
        }
        Regime::Transonic { .. } => Err(PanelError::Untrusted(mach, "harmonic panel model").into()),
        Regime::Subsonic if settings.aero == FinAero::DoubletLattice => {
            let ratio = max_box_aspect(lattice);
            if ratio > MAX_BOX_ASPECT {
                return Err(FinFlutterError::WideBoxes {
                    ratio,
                    limit: MAX_BOX_ASPECT,
                });
            }
            let dlm = Dlm::new(lattice, mach)?;
            harmonic_gafs(modes, dlm.map(0.0)?, ks, b, n, |nu, alpha| {
                dlm.forces(nu, alpha, n)
            })
        }
        Regime::Subsonic => {
            let vlm = HarmonicVlm::new(lattice, mach, &WakeSettings::default())?;
            harmonic_gafs(modes, vlm.map(0.0)?, ks, b, n, |nu, alpha| {
                vlm.forces(nu, alpha, n)
            })
        }
    }
}

/// The Mach boxes along the fin's streamwise extent at Mach `mach` for reduced frequencies up
/// to `nu_max` (1/m): [`machbox::DEFAULT_BOXES`], or more where the box rule `Δx <= 0.08 ·
/// 2π/ν` needs them. The grid's `Δx` is `β` times its column width, and its span holds a
/// whole number `round(s β boxes / extent)` of columns ([`MachBox::new`]), so `Δx` can come
/// out a little longer than `extent / boxes`: the count is raised until the grid's own `Δx`
/// meets the rule.
pub fn mach_boxes(planform: &FinPlanform, mach: f64, nu_max: f64) -> usize {
    let extent = planform
        .root_chord
        .max(planform.tip_le_offset + planform.tip_chord)
        - planform.tip_le_offset.min(0.0);
    let limit = harmonic::BOX_RULE * std::f64::consts::TAU / nu_max;
    let need = extent / limit;
    let mut boxes = if need.is_finite() {
        machbox::DEFAULT_BOXES.max(need.ceil() as usize)
    } else {
        machbox::DEFAULT_BOXES
    };
    let beta = (mach * mach - 1.0).max(0.0).sqrt();
    // The grid's Δx for a requested count (as `MachBox::new` lays it out).
    let dx = |boxes: usize| {
        let cols = ((planform.span * beta * boxes as f64 / extent).round() as usize).max(1);
        planform.span / cols as f64 * beta
    };
    // Each added box adds at most one column: at most as many steps as the count itself.
    let most = 2 * boxes;
    while boxes < most && limit.is_finite() && dx(boxes) > limit {
        boxes += 1;
    }
    boxes
}

/// The aerodynamic method of the generalised forces of `aero` on `planform` at Mach `mach`,
/// as the reports name it; in the transonic band the bridge with its uncertainty (`bridge`,
/// from the tables' own ends).
pub fn aero_method_bridged(
    planform: &FinPlanform,
    mach: f64,
    aero: FinAero,
    bridge: Option<&TransonicBridge>,
) -> String {
    match bridge {
        Some(b) => b.name(
            aero_method(planform, b.low, aero),
            aero_method(planform, b.high, aero),
        ),
        None => aero_method(planform, mach, aero).to_string(),
    }
}

/// The aerodynamic method of the generalised forces of `aero` on `planform` at Mach `mach`
/// outside the transonic band ([`aero_method_bridged`] names the bridge), as the reports name it.
pub fn aero_method(planform: &FinPlanform, mach: f64, aero: FinAero) -> &'static str {
    let supersonic = mach >= machbox::MIN_MACH;
    if in_bridge(mach, aero) {
        return "transonic bridge";
    }
    match aero {
        FinAero::QuasiSteady if mach <= panel::SUBSONIC_LIMIT => {
            "quasi-steady vortex lattice (Prandtl-Glauert)"
        }
        FinAero::DoubletLattice if mach <= crate::aero::panel::dlm::MACH_LIMIT => "doublet lattice",
        FinAero::QuasiSteady => "quasi-steady piston theory",
        _ if supersonic && !machbox::piston_valid(planform, mach) => {
            "Mach box (harmonic supersonic potential)"
        }
        _ if supersonic => "unsteady piston theory",
        FinAero::DoubletLattice => "doublet lattice",
        FinAero::Unsteady => "harmonic vortex lattice (Goethert)",
    }
}

/// The generalised forces at each reduced frequency of `ks` (semichord `b`) of a harmonic
/// panel model whose points are those of its map at zero frequency `m0` (they do not depend
/// on ν: the spline rows once) and whose force amplitudes for the normalwash columns come
/// from `forces(ν, α)`: `α = -Z_x - i ν Z_c` (ne x n), `F = K α` (nf x n), `Q = Z_fᵀ F`.
fn harmonic_gafs(
    modes: &FinModes,
    m0: HarmonicMap,
    ks: &[f64],
    b: f64,
    n: usize,
    forces: impl Fn(f64, &[c64]) -> Result<Vec<c64>, PanelError> + Sync,
) -> Result<Vec<Vec<c64>>, FinFlutterError> {
    let points = PanelMap {
        eval: m0.eval,
        force: m0.force,
        k: Vec::new(),
    };
    let rows = point_rows(modes, &points)?;
    let (ne, nf) = (points.eval.len(), points.force.len());
    // The reduced frequencies are independent (each its own influence matrix and solve, the
    // same operations on any thread): in parallel, collected in order, so the table has the
    // same bits whatever the thread count.
    ks.par_iter()
        .map(|&k| -> Result<Vec<c64>, FinFlutterError> {
            let nu = k / b;
            let alpha: Vec<c64> = (0..ne * n)
                .map(|e| c64::new(-rows.zx[e], -nu * rows.zc[e]))
                .collect();
            let f = forces(nu, &alpha)?;
            Ok(virtual_work(&rows, &f, nf, n))
        })
        .collect()
}

/// The chordwise panel count the unsteady lattice needs up to reduced frequency `k_max`
/// (the box-size rule of `panel::harmonic::check_resolution`, `Δx <= 0.08 · 2π b / k` on the
/// root chord, the longest), at least `floor`.
pub fn chordwise_for(modes: &FinModes, k_max: f64, floor: usize) -> usize {
    let nu = k_max / modes.b_ref();
    if nu.is_nan() || nu <= 0.0 {
        return floor;
    }
    let dx = harmonic::BOX_RULE * 2.0 * std::f64::consts::PI / nu;
    floor.max((modes.planform.root_chord / dx).ceil() as usize)
}

/// The flutter model of the clamped fin at air density `density`: generalised mass `I`,
/// stiffness `diag(ω²)`, no damping.
pub fn flutter_model(modes: &FinModes, density: f64) -> FlutterModel {
    let n = modes.order();
    let mut mass = vec![0.0; n * n];
    let mut stiffness = vec![0.0; n * n];
    for j in 0..n {
        mass[j * n + j] = 1.0;
        stiffness[j * n + j] = modes.omega[j] * modes.omega[j];
    }
    FlutterModel {
        names: modes.names.clone(),
        mass,
        stiffness,
        damping: vec![0.0; n * n],
        structural_g: 0.0,
        b_ref: modes.b_ref(),
        density,
    }
}

/// The p-k solution of the clamped fin at Mach `mach` and density `density` over `speeds`
/// ([`pk_solve_cut`]: a branch that does not converge ends the sweep; the cut is returned).
pub fn solve_at(
    modes: &FinModes,
    lattice: &Lattice,
    mach: f64,
    density: f64,
    speeds: &[f64],
    settings: &FinFlutterSettings,
) -> Result<(PkSolution, Option<(f64, usize)>), FinFlutterError> {
    let gaf = gaf_table(modes, lattice, mach, settings)?;
    solve_with(modes, &gaf, density, speeds)
}

/// The p-k solution of the clamped fin on a GAF table built already (by [`gaf_table`], or
/// read from the cache) at density `density` over `speeds`.
pub fn solve_with(
    modes: &FinModes,
    gaf: &GafTable,
    density: f64,
    speeds: &[f64],
) -> Result<(PkSolution, Option<(f64, usize)>), FinFlutterError> {
    let model = flutter_model(modes, density);
    Ok(pk_solve_screened(
        &model,
        gaf,
        speeds,
        PkSettings::default(),
    )?)
}
