//! The AGARD 445.6 wing, weakened model 3, in air: planform, the published vibration and
//! flutter data, and a plate finite-element model of the wing clamped at its root.
//!
//! # Sources
//!
//! - \[Y87\] E. C. Yates Jr., "AGARD standard aeroelastic configurations for dynamic response.
//!   Candidate configuration I.-Wing 445.6", NASA TM 100492, August 1987; the same text as
//!   AGARD Report 765 (1988). The wing was tested in the NASA Langley Transonic Dynamics
//!   Tunnel; the flutter data of the weakened model 3 in air are those of Yates, Land &
//!   Foughner, NASA TN D-1616 (1963), reproduced in \[Y87\].
//! - The numbers below were read from public transcriptions of \[Y87\], not from a scan of the
//!   report itself (no copy of the report was reachable from this machine):
//!   - planform, measured frequencies: the report's figure 1 / table as quoted in MBDyn's
//!     `tests/plates/agard/agard.awk` (P. Masarati, after the Code_Aster model of G.
//!     Romanelli: "From NASA-TM-100492 ... Figure 1 ... s 2.5 ft, 2b_s 1.833 ft, 2b_t 1.208
//!     ft"), and the 9.60 Hz / 38.17 Hz first bending / torsion frequencies quoted with the
//!     same planform in several DLM validation scripts;
//!   - the flutter table (Mach, density, mass ratio, speed, speed index, flutter frequency,
//!     `ω_α = 239.3 rad/s`): G. Dimitriadis, SDPMflut (PyPI `sdpmflut` 0.6.7,
//!     `AGARD445_6_new/flutter_SDPM_AGARD_new.py`), "Run data from wind tunnel flutter tests
//!     of wing 3 (weakened). Source: ... AGARD REPORT No.765";
//!   - the NACA 65A004 half-thickness ordinates at tenths of the chord and the material
//!     constants of the weakened wing (isotropic `E = 0.47072e6 psi`, `G = 0.059745e6 psi`,
//!     `ν = 0.31`; and the orthotropic equivalent `E_1 = 3.151 GPa`, `E_2 = 0.4162 GPa`,
//!     `G_12 = 0.4392 GPa`, `ν_12 = 0.31` of the Code_Aster model, the values of the
//!     equivalent orthotropic plate used throughout the literature since Kolonay's 1996
//!     Purdue thesis): MBDyn `agard.awk` as above.
//!
//!   The tests check that the published columns agree with each other (speed index from
//!   speed, mass ratio and `ω_α`; one wing mass from every `μ ρ`), which catches a
//!   transcription error in any one number.
//!
//! # Planform and reference quantities
//!
//! Semispan `s = 2.5 ft = 0.762 m`, root chord `c_r = 1.833 ft = 0.5587 m` (streamwise), tip
//! chord `c_t = 1.208 ft = 0.3682 m` (taper 0.659), quarter-chord sweep 45°, so the leading
//! edge is swept by `atan(tan 45° + (c_r - c_t)/(4 s)) = 46.74°`; NACA 65A004 section
//! (streamwise). Reference semichord `b_s = c_r/2`, reference frequency `ω_α = 239.3 rad/s`
//! (the value that reproduces \[Y87\]'s speed-index column; the measured first torsion
//! frequency 38.17 Hz is 239.8 rad/s). Flutter speed index `V_f/(b_s ω_α sqrt(μ))`, mass
//! ratio `μ = m/(ρ V_cone)` with `V_cone = π s (c_r² + c_r c_t + c_t²)/12` the volume of the
//! conical frustum whose bases are the root and tip chords (\[Y87\] symbols). Every `μ ρ` of
//! the table gives the same panel mass, `m = 1.866 kg` (0.1279 slug) — the mass this module
//! gives the model.
//!
//! # The structural model
//!
//! A flat plate on the planform, clamped along the root chord, of MITC4 shells
//! ([`crate::structure::generate::cantilever_plate_model`]) whose thickness follows the
//! section, `t(x, y) = c(y) τ(x/c)`, `τ` twice the NACA 65A004 half-thickness ordinate
//! (linear between tenths of the chord, averaged over the element by Gauss quadrature), as
//! in the Code_Aster / MBDyn model above. Two materials:
//!
//! - [`Material::Orthotropic`]: the equivalent orthotropic lamina of the literature, grain
//!   (direction 1) along the spanwise grid lines (lines of constant chord fraction; the
//!   quarter-chord one is swept 45°) or along the 45° line itself ([`Grain`]);
//!   transverse shear `G_13 = G_23 = G_12` (not published; a thin plate barely feels it);
//! - [`Material::Isotropic`]: `E = 0.47072e6 psi` with `ν = 0.31` (the isotropic element
//!   cannot also carry the published `G = 0.059745e6 psi`: `E/(2G) - 1 = 2.94` is no Poisson
//!   ratio), to show what the isotropic element makes of the wing.
//!
//! The density is NOT a published constant of the model: it is the published wing mass over
//! the plate's volume, so the FE mass is the tested wing's. Nothing is tuned to the
//! frequencies.
//!
//! # Mode shapes
//!
//! Node positions are given in the wing's own frame: `x` chordwise aft of the root leading
//! edge, `y` spanwise from the root; `w` is the displacement normal to the plate along
//! `z = x × y` (the lattice frame of [`crate::runtime::aero::panel`]), per unit modal
//! coordinate of the mass-normalised mode (`φᵀ M φ = 1`, so `w` is in m/sqrt(kg)).

use faer::{Mat, c64};

use super::goland::{FT, SLUG};
use super::pk::{FlutterError, FlutterModel, GafFn, GafTable};
use crate::runtime::aero::FinPlanform;
use crate::runtime::aero::panel::dlm::Dlm;
use crate::runtime::aero::panel::harmonic::{self, HarmonicVlm, WakeSettings};
use crate::runtime::aero::panel::spline::{SplineError, surface_spline};
use crate::runtime::aero::panel::{Lattice, PanelError, Spacing, vlm};
use crate::structure::fe_model::FeModel;
use crate::structure::generate::{
    FinSpec, GenerateError, MaterialProps, cantilever_fin_model, cantilever_plate_model,
    orthotropic_plane_stress, shell_element_lamina,
};
use crate::structure::modal::{self, ModalError};

/// Pounds per square inch in pascals (1 lbf / (0.0254 m)²).
pub const PSI: f64 = 4.448_221_615_260_5 / (0.0254 * 0.0254);

/// Semispan `s`, m (2.5 ft).
pub const SEMISPAN: f64 = 2.5 * FT;
/// Root chord (streamwise), m (1.833 ft).
pub const ROOT_CHORD: f64 = 1.833 * FT;
/// Tip chord (streamwise), m (1.208 ft).
pub const TIP_CHORD: f64 = 1.208 * FT;
/// Quarter-chord sweep, rad (45°).
pub const QUARTER_CHORD_SWEEP: f64 = std::f64::consts::FRAC_PI_4;
/// Maximum thickness of the NACA 65A004 section, fraction of the chord.
pub const THICKNESS_RATIO: f64 = 0.04;
/// NACA 65A004 half-thickness `z/c` at `x/c = 0, 0.1, ..., 1.0` (module doc).
pub const HALF_THICKNESS: [f64; 11] = [
    0.0, 0.01216, 0.01649, 0.01894, 0.01996, 0.01952, 0.01742, 0.014, 0.00966, 0.0049, 0.00009,
];

/// Measured natural frequencies of the weakened model 3, Hz: first bending, first torsion,
/// second bending, second torsion (\[Y87\]).
pub const MEASURED_HZ: [f64; 4] = [9.60, 38.17, 48.35, 91.54];
/// Reference frequency of the speed index, rad/s (\[Y87\]; module doc).
pub const OMEGA_ALPHA: f64 = 239.3;

/// Isotropic Young's modulus of the weakened wing, Pa (0.47072e6 psi, module doc).
pub const E_ISOTROPIC: f64 = 0.47072e6 * PSI;
/// Shear modulus of the weakened wing, Pa (0.059745e6 psi, module doc).
pub const G_ISOTROPIC: f64 = 0.059745e6 * PSI;
/// Poisson's ratio (0.31).
pub const POISSON: f64 = 0.31;
/// Equivalent orthotropic lamina (module doc): `E_1`, `E_2`, `G_12`, Pa.
pub const E1: f64 = 3.151e9;
pub const E2: f64 = 0.4162e9;
pub const G12: f64 = 0.4392e9;

/// One flutter point of the weakened model 3 in air (\[Y87\], SI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlutterTest {
    pub mach: f64,
    /// Test-section density, kg/m³.
    pub density: f64,
    /// Mass ratio `μ` (module doc).
    pub mass_ratio: f64,
    /// Flutter speed, m/s.
    pub speed: f64,
    /// `V_f/(b_s ω_α sqrt(μ))` as published.
    pub speed_index: f64,
    /// Flutter frequency, rad/s.
    pub omega: f64,
}

impl FlutterTest {
    /// `ω_f/ω_α`.
    pub fn frequency_ratio(&self) -> f64 {
        self.omega / OMEGA_ALPHA
    }
}

const fn test(
    mach: f64,
    rho_slug_ft3: f64,
    mu: f64,
    v_ft_s: f64,
    fsi: f64,
    omega: f64,
) -> FlutterTest {
    FlutterTest {
        mach,
        density: rho_slug_ft3 * SLUG / (FT * FT * FT),
        mass_ratio: mu,
        speed: v_ft_s * FT,
        speed_index: fsi,
        omega,
    }
}

/// The published flutter points in air, weakened model 3 (module doc for the source):
/// density in slug/ft³, speed in ft/s as published, converted exactly. The subsonic points
/// of the table are M = 0.499 .. 0.960; the report's M = 0.338 point and the supersonic
/// points (M = 1.072, 1.141) were not in the transcription reached, so they are absent.
pub const FLUTTER_TESTS: [FlutterTest; 6] = [
    test(0.499, 0.000830, 33.465, 565.8, 0.4459, 128.1),
    test(0.678, 0.000404, 68.753, 759.1, 0.4174, 113.0),
    test(0.901, 0.000193, 143.920, 973.4, 0.3700, 101.1),
    test(0.954, 0.000123, 225.820, 1008.4, 0.3059, 91.1),
    test(0.957, 0.000123, 225.820, 1013.8, 0.3076, 87.3),
    test(0.960, 0.000123, 225.820, 1020.2, 0.3095, 87.9),
];

/// Reference semichord `b_s = c_r/2`, m.
pub fn semichord() -> f64 {
    0.5 * ROOT_CHORD
}

/// Leading-edge sweep, rad: `atan(tan Λ_c/4 + (c_r - c_t)/(4 s))` (straight edges).
pub fn leading_edge_sweep() -> f64 {
    (QUARTER_CHORD_SWEEP.tan() + (ROOT_CHORD - TIP_CHORD) / (4.0 * SEMISPAN)).atan()
}

/// Volume of the conical frustum of the mass ratio, m³ (module doc).
pub fn cone_volume() -> f64 {
    let (cr, ct) = (ROOT_CHORD, TIP_CHORD);
    std::f64::consts::PI * SEMISPAN * (cr * cr + cr * ct + ct * ct) / 12.0
}

/// Panel mass `μ ρ V_cone` of a flutter point, kg.
pub fn panel_mass(t: &FlutterTest) -> f64 {
    t.mass_ratio * t.density * cone_volume()
}

/// The wing mass the model carries: the mean of [`panel_mass`] over [`FLUTTER_TESTS`], kg.
pub fn wing_mass() -> f64 {
    FLUTTER_TESTS.iter().map(panel_mass).sum::<f64>() / FLUTTER_TESTS.len() as f64
}

/// Section thickness over chord `τ(x/c) = 2 z/c` (linear between the tabulated ordinates).
pub fn thickness_over_chord(xc: f64) -> f64 {
    let u = (xc.clamp(0.0, 1.0)) * 10.0;
    let k = (u.floor() as usize).min(9);
    let f = u - k as f64;
    2.0 * (HALF_THICKNESS[k] * (1.0 - f) + HALF_THICKNESS[k + 1] * f)
}

/// Direction of the grain of the orthotropic lamina.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Grain {
    /// Along the element's spanwise grid line (a line of constant chord fraction).
    GridLines,
    /// Along the 45° quarter-chord line, the same in every element.
    QuarterChord,
}

/// Plate material of the model (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Material {
    Orthotropic(Grain),
    Isotropic,
}

/// Mesh and material of a model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ModelSpec {
    pub chord_elements: usize,
    pub span_elements: usize,
    pub material: Material,
}

impl Default for ModelSpec {
    fn default() -> Self {
        ModelSpec {
            chord_elements: 16,
            span_elements: 16,
            material: Material::Orthotropic(Grain::GridLines),
        }
    }
}

/// Errors of [`wing_modes`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AgardError {
    #[error(transparent)]
    Generate(#[from] GenerateError),
    #[error(transparent)]
    Modal(#[from] ModalError),
    #[error("{0} modes requested, the model has {1}")]
    TooFewModes(usize, usize),
    #[error(transparent)]
    Panel(#[from] PanelError),
    #[error(transparent)]
    Spline(#[from] SplineError),
    #[error(transparent)]
    Flutter(#[from] FlutterError),
}

/// The FE model, its modes and the normal displacement of each mode at the nodes.
pub struct WingModes {
    pub model: FeModel,
    /// Natural frequencies, Hz, ascending.
    pub frequencies_hz: Vec<f64>,
    /// Mass-normalised shapes over all DOFs, one column per mode.
    pub shapes: Mat<f64>,
    /// Node positions: `x` chordwise aft of the root leading edge, m.
    pub x: Vec<f64>,
    /// Node positions: `y` spanwise from the root, m.
    pub y: Vec<f64>,
    /// `w[mode][node]`: displacement along `z = x × y` (module doc), m/sqrt(kg).
    pub w: Vec<Vec<f64>>,
    /// Nodes per spanwise row (chordwise fastest, from the trailing edge; rows from the
    /// first row off the root to the tip).
    pub row_len: usize,
    /// Total mass of the model, kg.
    pub mass: f64,
}

/// The planform as a fin of the generator: root trailing edge at `x_body = -c_r`, so the root
/// leading edge is at `x_body = 0` and the chordwise coordinate aft of it is `-x_body`.
fn fin_spec(spec: &ModelSpec, thickness: f64, material: MaterialProps) -> FinSpec {
    FinSpec {
        count: 1,
        span: SEMISPAN,
        root_chord: ROOT_CHORD,
        tip_chord: TIP_CHORD,
        sweep: leading_edge_sweep(),
        thickness,
        cant: 0.0,
        angles: vec![],
        root_trailing_edge_x: -ROOT_CHORD,
        span_elements: spec.span_elements,
        chord_elements: spec.chord_elements,
        material,
    }
}

/// Mean of `τ` over the chord fraction `[u0, u1]` (4-point Gauss-Legendre on each tenth of
/// the chord it overlaps; `τ` is linear there, so this is exact).
fn mean_thickness_over_chord(u0: f64, u1: f64) -> f64 {
    let (lo, hi) = (u0.min(u1), u0.max(u1));
    let mut sum = 0.0;
    let mut a = lo;
    while a < hi {
        let b = (((a * 10.0).floor() + 1.0) / 10.0).min(hi);
        // Two-point Gauss is exact for a linear integrand on [a, b].
        let (m, h) = (0.5 * (a + b), 0.5 * (b - a) / 3f64.sqrt());
        sum += 0.5 * (b - a) * (thickness_over_chord(m - h) + thickness_over_chord(m + h));
        a = b;
    }
    sum / (hi - lo)
}

/// Thickness of quad (i, j) of the fin grid: local chord at the quad's mid-span times the
/// mean `τ` over its chordwise extent (i counts from the trailing edge).
fn element_thickness(f: &FinSpec, i: usize, j: usize) -> f64 {
    let eta = (j as f64 + 0.5) / f.span_elements as f64;
    let chord = f.root_chord + (f.tip_chord - f.root_chord) * eta;
    let n = f.chord_elements as f64;
    // Chord fraction from the leading edge of the quad's two chordwise stations.
    let (u0, u1) = (1.0 - i as f64 / n, 1.0 - (i as f64 + 1.0) / n);
    chord * mean_thickness_over_chord(u1, u0)
}

/// Area of a quad from its corners (shoelace).
fn quad_area(ab: &[[f64; 2]; 4]) -> f64 {
    let mut s = 0.0;
    for i in 0..4 {
        let (p, q) = (ab[i], ab[(i + 1) % 4]);
        s += p[0] * q[1] - q[0] * p[1];
    }
    0.5 * s
}

/// Volume of the plate of varying thickness on the fin grid of `f`, m³.
fn plate_volume(f: &FinSpec) -> f64 {
    let mut v = 0.0;
    for j in 0..f.span_elements {
        for i in 0..f.chord_elements {
            let p = |ci: usize, cj: usize| {
                let (x, eta) = f.planform_point(ci, cj);
                [x, eta]
            };
            let ab = [p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)];
            v += element_thickness(f, i, j) * quad_area(&ab);
        }
    }
    v
}

/// Builds the clamped FE model of `spec` (module doc).
pub fn wing_model(spec: &ModelSpec) -> Result<FeModel, AgardError> {
    let mass = wing_mass();
    let iso = |rho: f64| MaterialProps {
        youngs_modulus: E_ISOTROPIC,
        poisson: POISSON,
        density: rho,
    };
    match spec.material {
        Material::Isotropic => {
            // Constant thickness: the section's mean thickness over the planform (the
            // plate's volume is the wing's), so rho = m / V.
            let probe = fin_spec(spec, 1.0, iso(1.0));
            let volume = plate_volume(&probe);
            let area = 0.5 * (ROOT_CHORD + TIP_CHORD) * SEMISPAN;
            let t = volume / area;
            Ok(cantilever_fin_model(&fin_spec(
                spec,
                t,
                iso(mass / volume),
            ))?)
        }
        Material::Orthotropic(grain) => {
            let probe = fin_spec(spec, 1.0, iso(1.0));
            let rho = mass / plate_volume(&probe);
            let f = probe.clone();
            let quarter = {
                // Local a points forward (toward the leading edge), b outboard: a line
                // swept back by 45° runs along (-sin 45°, cos 45°).
                let d = (-QUARTER_CHORD_SWEEP.sin(), QUARTER_CHORD_SWEEP.cos());
                d.1.atan2(d.0)
            };
            let model = cantilever_plate_model(&probe, |i, j, ab| {
                let theta = match grain {
                    Grain::QuarterChord => quarter,
                    Grain::GridLines => {
                        let da = ab[3][0] + ab[2][0] - ab[0][0] - ab[1][0];
                        let db = ab[3][1] + ab[2][1] - ab[0][1] - ab[1][1];
                        db.atan2(da)
                    }
                };
                let q = orthotropic_plane_stress(E1, E2, POISSON, G12, theta);
                shell_element_lamina(ab, element_thickness(&f, i, j), &q, G12, rho)
            })?;
            Ok(model)
        }
    }
}

/// The lowest `count` modes of the model of `spec` (module doc).
pub fn wing_modes(spec: &ModelSpec, count: usize) -> Result<WingModes, AgardError> {
    let model = wing_model(spec)?;
    let modes = modal::solve(&model, count)?;
    let n_el = modes.omega2.len() - modes.n_rigid;
    if n_el < count {
        return Err(AgardError::TooFewModes(count, n_el));
    }
    let freqs = modes.elastic_frequencies_hz();
    let nn = model.nodes.len();
    let shapes = Mat::from_fn(model.n_dof(), count, |r, c| {
        modes.shapes[(r, modes.n_rigid + c)]
    });
    let x = model.nodes.iter().map(|n| -n.position[0]).collect();
    let y = model.nodes.iter().map(|n| n.position[1]).collect();
    // z = x_aft × y = -(e_a × e_b) = -n: the FE normal displacement with its sign flipped.
    let w = (0..count)
        .map(|c| (0..nn).map(|i| -shapes[(6 * i + 2, c)]).collect())
        .collect();
    // Total mass: a unit translation along z.
    let mut unit = Mat::<f64>::zeros(model.n_dof(), 1);
    for i in 0..nn {
        unit[(6 * i + 2, 0)] = 1.0;
    }
    let mu = &model.mass * &unit;
    let mass = (0..nn).map(|i| mu[(6 * i + 2, 0)]).sum();
    Ok(WingModes {
        model,
        frequencies_hz: freqs[..count].to_vec(),
        shapes,
        x,
        y,
        w,
        row_len: spec.chord_elements + 1,
        mass,
    })
}

/// Sign changes along a line of values, ignoring values below `1e-3` of the largest.
pub fn sign_changes(values: &[f64]) -> usize {
    let big = values.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let mut last = 0.0_f64;
    let mut n = 0;
    for &v in values {
        if v.abs() < 1e-3 * big {
            continue;
        }
        if last != 0.0 && v.signum() != last.signum() {
            n += 1;
        }
        last = v;
    }
    n
}

impl WingModes {
    /// `w` of `mode` along the leading edge (root to tip, without the clamped root).
    pub fn leading_edge(&self, mode: usize) -> Vec<f64> {
        self.w[mode]
            .chunks(self.row_len)
            .map(|row| row[self.row_len - 1])
            .collect()
    }

    /// `w` of `mode` along the trailing edge.
    pub fn trailing_edge(&self, mode: usize) -> Vec<f64> {
        self.w[mode]
            .chunks(self.row_len)
            .map(|row| row[0])
            .collect()
    }

    /// `w` of `mode` along the tip chord, trailing edge to leading edge.
    pub fn tip_chord(&self, mode: usize) -> Vec<f64> {
        let n = self.w[mode].len();
        self.w[mode][n - self.row_len..].to_vec()
    }

    /// The mode's kind read from its [`WingModes::nodal_signature`] (the four signatures of
    /// the test `mode_shapes_identified_by_nodal_lines`), `None` for any other.
    pub fn kind(&self, mode: usize) -> Option<&'static str> {
        match self.nodal_signature(mode) {
            (0, 0, 0) => Some("1st bending"),
            (0, 0, 1) => Some("1st torsion"),
            (0, 1, 0) => Some("2nd bending"),
            (1, 1, 1) => Some("2nd torsion"),
            _ => None,
        }
    }

    /// Nodal-line signature of `mode`: sign changes along (leading edge, trailing edge, tip
    /// chord).
    pub fn nodal_signature(&self, mode: usize) -> (usize, usize, usize) {
        (
            sign_changes(&self.leading_edge(mode)),
            sign_changes(&self.trailing_edge(mode)),
            sign_changes(&self.tip_chord(mode)),
        )
    }
}

/// A flutter problem of [`quasi_steady_problem`]: the modal model and its GAF.
pub type QuasiSteadyProblem<F> = (FlutterModel, GafFn<F>);

/// The planform as the panel model's fin (root at the reflection plane).
pub fn planform() -> FinPlanform {
    FinPlanform {
        span: SEMISPAN,
        root_chord: ROOT_CHORD,
        tip_chord: TIP_CHORD,
        tip_le_offset: SEMISPAN * leading_edge_sweep().tan(),
        body_radius: 0.0,
    }
}

/// The flutter problem of the wing's modes with the QUASI-STEADY vortex-lattice GAF (not the
/// unsteady one the validation calls for; labelled so wherever it is reported).
///
/// Modal mass `I`, stiffness `diag(ω²)`. Aerodynamics: the vortex-lattice force map `K` of
/// [`vlm::force_map`] (`F = q K α_e`, Prandtl-Glauert) with the harmonic normalwash of mode
/// `j`, `α_e = -∂z_j/∂x - i (k/b) z_j` at the control points (the linearised tangency
/// condition of [`crate::runtime::aero::panel`], `∂/∂t = iω`, `ω/V = k/b`), and the work of
/// the panel forces on mode `i` at the force points:
///
/// `Q_ij(k) = Σ_p z_i(f_p) Σ_r K_pr (-∂z_j/∂x - i (k/b) z_j)(c_r) = A_ij + i (k/b) B_ij`.
///
/// The mode shapes reach the lattice by [`surface_spline`] through the FE nodes and the
/// clamped root nodes (`z = 0`). This is Theodorsen's `C(k) = 1` with no apparent mass
/// (module doc of [`vlm`]).
pub fn quasi_steady_problem(
    modes: &WingModes,
    mach: f64,
    density: f64,
    chordwise: usize,
    spanwise: usize,
) -> Result<QuasiSteadyProblem<impl Fn(f64, &mut [c64]) + use<>>, AgardError> {
    let lattice = Lattice::new(&planform(), chordwise, spanwise, Spacing::Uniform)?;
    let kmap = vlm::force_map(&lattice, mach)?;
    let n = lattice.len();
    let count = modes.w.len();
    let controls: Vec<[f64; 2]> = lattice.panels.iter().map(|p| p.control).collect();
    let forces: Vec<[f64; 2]> = lattice.panels.iter().map(|p| p.bound_mid()).collect();
    let rows = mode_rows(modes, &controls, &forces)?;
    let (z_c, zx_c, z_f) = (&rows.z_c, &rows.zx_c, &rows.z_f);
    let work = |i: usize, alpha: &[f64]| -> f64 {
        (0..n)
            .map(|p| z_f[i][p] * (0..n).map(|r| kmap[p * n + r] * alpha[r]).sum::<f64>())
            .sum()
    };
    let mut a = vec![0.0; count * count];
    let mut b = vec![0.0; count * count];
    for j in 0..count {
        let slope: Vec<f64> = zx_c[j].iter().map(|v| -v).collect();
        let disp: Vec<f64> = z_c[j].iter().map(|v| -v).collect();
        for i in 0..count {
            a[i * count + j] = work(i, &slope);
            b[i * count + j] = work(i, &disp);
        }
    }
    let bs = semichord();
    let gaf = GafFn {
        order: count,
        k_max: 1e3,
        f: move |k: f64, out: &mut [c64]| {
            for e in 0..a.len() {
                out[e] = c64::new(a[e], k / bs * b[e]);
            }
        },
    };
    Ok((modal_model(modes, density), gaf))
}

/// The modes' spline rows at a panel map's points, one vector per mode: value `z_c` and
/// chordwise slope `zx_c` at the normalwash points, value `z_f` at the force points.
struct ModeRows {
    z_c: Vec<Vec<f64>>,
    zx_c: Vec<Vec<f64>>,
    z_f: Vec<Vec<f64>>,
}

/// [`ModeRows`] by [`surface_spline`] through the FE nodes and the clamped root nodes (`z =
/// 0` at the chordwise stations of the root row).
fn mode_rows(
    modes: &WingModes,
    eval: &[[f64; 2]],
    force: &[[f64; 2]],
) -> Result<ModeRows, AgardError> {
    let root = modes.row_len;
    let mut nodes: Vec<[f64; 2]> = (0..root)
        .map(|i| [ROOT_CHORD * (1.0 - i as f64 / (root - 1) as f64), 0.0])
        .collect();
    nodes.extend(modes.x.iter().zip(&modes.y).map(|(&x, &y)| [x, y]));
    let (g, gx) = surface_spline(&nodes, eval, ROOT_CHORD)?;
    let (gf, _) = surface_spline(&nodes, force, ROOT_CHORD)?;
    let nn = nodes.len();
    let apply = |m: &[f64], w: &[f64], np: usize| -> Vec<f64> {
        (0..np)
            .map(|p| (0..nn).map(|k| m[p * nn + k] * w[k]).sum())
            .collect()
    };
    let full: Vec<Vec<f64>> = modes
        .w
        .iter()
        .map(|w| {
            let mut v = vec![0.0; root];
            v.extend_from_slice(w);
            v
        })
        .collect();
    Ok(ModeRows {
        z_c: full.iter().map(|w| apply(&g, w, eval.len())).collect(),
        zx_c: full.iter().map(|w| apply(&gx, w, eval.len())).collect(),
        z_f: full.iter().map(|w| apply(&gf, w, force.len())).collect(),
    })
}

/// The modal flutter model: mass `I`, stiffness `diag(ω²)`, no damping, `b_s`, `density`.
fn modal_model(modes: &WingModes, density: f64) -> FlutterModel {
    let count = modes.w.len();
    let mut stiffness = vec![0.0; count * count];
    let mut mass = vec![0.0; count * count];
    for i in 0..count {
        mass[i * count + i] = 1.0;
        let w = 2.0 * std::f64::consts::PI * modes.frequencies_hz[i];
        stiffness[i * count + i] = w * w;
    }
    let names = (0..count)
        .map(|i| match modes.kind(i) {
            Some(kind) => format!("mode {} ({kind})", i + 1),
            None => format!("mode {}", i + 1),
        })
        .collect();
    FlutterModel {
        names,
        mass,
        stiffness,
        damping: vec![0.0; count * count],
        structural_g: 0.0,
        b_ref: semichord(),
        density,
    }
}

/// The subsonic unsteady aerodynamics of [`unsteady_problem`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnsteadyAero {
    /// The harmonic vortex lattice of [`harmonic`] (convected ringed wake, Göthert
    /// compressibility), `2n` force points.
    VortexLattice,
    /// The doublet-lattice method of [`crate::runtime::aero::panel::dlm`] (the compressible unsteady kernel), `n` force
    /// points at the box quarter-chord mid-points.
    DoubletLattice,
}

/// The lattice and reduced-frequency table of [`unsteady_problem`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnsteadySettings {
    pub aero: UnsteadyAero,
    /// Highest reduced frequency `k = ω b_s / V` of the table.
    pub k_max: f64,
    /// Number of tabulated reduced frequencies, `k_i = k_max (i/(count-1))²`.
    pub k_count: usize,
    /// Spanwise strips of the lattice; the chordwise count follows from `k_max`
    /// ([`chordwise_for`]), at least `min_chordwise` (for a convergence study).
    pub spanwise: usize,
    pub min_chordwise: usize,
}

/// The fewest uniform chordwise panels whose root-chord panel meets the box-size rule of
/// [`harmonic::check_resolution`] at `k_max`: `Δx = c_r / n <= 0.08 · 2π b_s / k_max`.
pub fn chordwise_for(k_max: f64) -> usize {
    let dx = harmonic::BOX_RULE * 2.0 * std::f64::consts::PI * semichord() / k_max;
    ((ROOT_CHORD / dx).ceil() as usize).max(1)
}

/// The reduced frequency a sweep starting at `v_min` needs: `1.2 ω_max b_s / v_min`, the
/// highest mode's `k` at the lowest speed with 20 % to spare (the rule of `analyze flutter`).
pub fn k_max_for(modes: &WingModes, v_min: f64) -> f64 {
    let w =
        2.0 * std::f64::consts::PI * modes.frequencies_hz.iter().fold(0.0_f64, |a, &f| a.max(f));
    1.2 * w * semichord() / v_min
}

/// The UNSTEADY flutter problem of [`unsteady_problem`].
pub struct UnsteadyProblem {
    pub model: FlutterModel,
    pub gaf: GafTable,
    /// The lattice used: chordwise x spanwise panels (uniform), and its wake rings.
    pub chordwise: usize,
    pub spanwise: usize,
    pub wake_rings: usize,
}

/// The flutter problem of the wing's modes with the UNSTEADY vortex-lattice GAF (the
/// harmonic vortex lattice with a convected wake of [`harmonic`], Göthert compressibility),
/// tabulated over `k` for the p-k solver.
///
/// The same structure as [`quasi_steady_problem`] (modal mass `I`, stiffness `diag(ω²)`,
/// modes splined with the clamped root, virtual work at the force points), with the complex
/// map of [`HarmonicVlm::forces`] in place of the quasi-steady one:
///
/// `Q(k) = Z_fᵀ F`, `F = K(k/b_s, M) (-Z_x - i (k/b_s) Z_c)`
///
/// (as `analysis::flutter::fin`'s `unsteady_values`; `F` has `2n` rows: the Kutta-Joukowski
/// forces at the bound mid-points, then the `ρ ∂Δφ/∂t` forces at the ring-area centroids, so
/// `Z_f` is splined at both). The lattice is uniform (as the quasi-steady case), `spanwise`
/// strips and [`chordwise_for`]`(k_max)` chordwise panels (or `min_chordwise`, if more), so the box-size rule holds at
/// every tabulated `k`; the wake is [`WakeSettings::default`]. `M > 0.9` is refused by the
/// vortex lattice ([`PanelError::Untrusted`]). With [`UnsteadyAero::DoubletLattice`] the map is
/// [`Dlm::forces`] instead (`n` force points, no wake: the kernel carries it), accepted up to
/// [`crate::runtime::aero::panel::dlm::MACH_LIMIT`].
pub fn unsteady_problem(
    modes: &WingModes,
    mach: f64,
    density: f64,
    settings: &UnsteadySettings,
) -> Result<UnsteadyProblem, AgardError> {
    let chordwise = chordwise_for(settings.k_max).max(settings.min_chordwise);
    let lattice = Lattice::new(&planform(), chordwise, settings.spanwise, Spacing::Uniform)?;
    enum Map {
        Vlm(HarmonicVlm),
        Dlm(Dlm),
    }
    let map = match settings.aero {
        UnsteadyAero::VortexLattice => {
            let vlm = HarmonicVlm::new(&lattice, mach, &WakeSettings::default())?;
            vlm.check_resolution(settings.k_max / semichord())?;
            Map::Vlm(vlm)
        }
        UnsteadyAero::DoubletLattice => {
            let d = Dlm::new(&lattice, mach)?;
            d.check_resolution(settings.k_max / semichord())?;
            Map::Dlm(d)
        }
    };
    let m0 = match &map {
        Map::Vlm(v) => v.map(0.0)?,
        Map::Dlm(d) => d.map(0.0)?,
    };
    let rows = mode_rows(modes, &m0.eval, &m0.force)?;
    let count = modes.w.len();
    let (ne, nf) = (m0.eval.len(), m0.force.len());
    let bs = semichord();
    let nk = settings.k_count.max(2);
    let ks: Vec<f64> = (0..nk)
        .map(|i| {
            let s = i as f64 / (nk - 1) as f64;
            settings.k_max * s * s
        })
        .collect();
    let mut values = Vec::with_capacity(nk);
    for &k in &ks {
        let nu = k / bs;
        // α (ne x count, row-major): column j is mode j's -Z_x - i ν Z_c.
        let mut alpha = vec![c64::new(0.0, 0.0); ne * count];
        for p in 0..ne {
            for j in 0..count {
                alpha[p * count + j] = c64::new(-rows.zx_c[j][p], -nu * rows.z_c[j][p]);
            }
        }
        let f = match &map {
            Map::Vlm(v) => v.forces(nu, &alpha, count)?,
            Map::Dlm(d) => d.forces(nu, &alpha, count)?,
        };
        let mut q = vec![c64::new(0.0, 0.0); count * count];
        for p in 0..nf {
            for i in 0..count {
                let z = rows.z_f[i][p];
                for j in 0..count {
                    q[i * count + j] += f[p * count + j] * z;
                }
            }
        }
        values.push(q);
    }
    Ok(UnsteadyProblem {
        model: modal_model(modes, density),
        gaf: GafTable::new(count, ks, values)?,
        chordwise,
        spanwise: settings.spanwise,
        wake_rings: match &map {
            Map::Vlm(v) => v.wake_rings(),
            Map::Dlm(_) => 0,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The published columns agree with each other: the speed index recomputed from speed,
    /// mass ratio, `b_s` and `ω_α` matches the published one within the sum of the
    /// half-units of the printed digits of V, μ, ω_α and the index (achieved 2.2e-4 relative
    /// at worst, M = 0.954, against a bound of 3.9e-4 there), and every `μ ρ` gives the same
    /// panel mass (spread 7e-5 relative).
    #[test]
    fn published_columns_are_consistent() {
        for t in &FLUTTER_TESTS {
            let fsi = t.speed / (semichord() * OMEGA_ALPHA * t.mass_ratio.sqrt());
            let err = (fsi / t.speed_index - 1.0).abs();
            let v_ft = t.speed / FT;
            let bound = 0.5e-4 / t.speed_index
                + 0.05 / v_ft
                + 0.05 / OMEGA_ALPHA
                + 0.5 * 0.5e-3 / t.mass_ratio;
            println!(
                "M {}: FSI {fsi:.5} vs {} ({err:.1e}, bound {bound:.1e})",
                t.mach, t.speed_index
            );
            assert!(err < bound, "M {}: {fsi} vs {}", t.mach, t.speed_index);
        }
        let m: Vec<f64> = FLUTTER_TESTS.iter().map(panel_mass).collect();
        let (lo, hi) = m
            .iter()
            .fold((f64::MAX, 0.0_f64), |(a, b), &v| (a.min(v), b.max(v)));
        println!("panel mass {lo:.5} .. {hi:.5} kg");
        assert!((hi - lo) / lo < 1e-4, "{m:?}");
        assert!((wing_mass() - 1.866).abs() < 1e-3, "{}", wing_mass());
    }

    #[test]
    fn planform_figures() {
        assert!((leading_edge_sweep().to_degrees() - 46.736).abs() < 1e-3);
        assert!((TIP_CHORD / ROOT_CHORD - 0.659).abs() < 1e-3);
        assert!((thickness_over_chord(0.4) - 0.03992).abs() < 1e-12);
        assert!((thickness_over_chord(0.45) - 0.5 * (0.03992 + 0.03904)).abs() < 1e-12);
    }

    fn report(spec: &ModelSpec) -> WingModes {
        let m = wing_modes(spec, 4).unwrap();
        println!(
            "{:?} {}x{}: mass off the clamped row {:.4} kg (wing {:.4})",
            spec.material,
            spec.chord_elements,
            spec.span_elements,
            m.mass,
            wing_mass()
        );
        for (k, (f, want)) in m.frequencies_hz.iter().zip(MEASURED_HZ).enumerate() {
            println!(
                "  mode {}: {f:.3} Hz vs {want} ({:+.2} %), signature {:?}",
                k + 1,
                100.0 * (f / want - 1.0),
                m.nodal_signature(k)
            );
        }
        m
    }

    fn errors(m: &WingModes) -> Vec<f64> {
        m.frequencies_hz
            .iter()
            .zip(MEASURED_HZ)
            .map(|(f, want)| f / want - 1.0)
            .collect()
    }

    /// The equivalent orthotropic plate (16 x 16 quads, grain along the spanwise grid lines)
    /// against the measured frequencies: -5.31 %, -0.74 %, -0.26 %, -0.22 % (mode 1 is the
    /// outlier, and stays so on a 24 x 24 mesh: -5.17 %). Tolerances: 6 % on mode 1, 1 % on
    /// modes 2-4.
    #[test]
    fn frequencies_against_measured() {
        let spec = ModelSpec::default();
        let m = report(&spec);
        let e = errors(&m);
        // The density is the published mass over the plate's volume.
        let probe = fin_spec(
            &spec,
            1.0,
            MaterialProps {
                youngs_modulus: 1.0,
                poisson: 0.3,
                density: 1.0,
            },
        );
        assert!(plate_volume(&probe) > 0.0);
        // The clamped row takes about half a strip of the mass off the free nodes.
        assert!(m.mass < wing_mass() && m.mass > wing_mass() * (1.0 - 1.0 / 16.0));
        println!("errors: grid-line grain {e:?}");
        assert!(e[0].abs() < 0.06, "{e:?}");
        for k in 1..4 {
            assert!(e[k].abs() < 0.01, "mode {}: {e:?}", k + 1);
        }
    }

    /// The grain along the 45° line and the isotropic plate (printed, docs/validation.md):
    /// 45°: -6.13, -0.05, -1.67, +1.03 %; isotropic: -26.2, -12.5, +6.7, -4.3 %.
    #[test]
    #[ignore = "slow (two more models); run with --ignored to print"]
    fn material_sensitivity() {
        let spec = ModelSpec::default();
        let quarter = report(&ModelSpec {
            material: Material::Orthotropic(Grain::QuarterChord),
            ..spec
        });
        let iso = report(&ModelSpec {
            material: Material::Isotropic,
            ..spec
        });
        println!("errors: 45 deg grain {:?}", errors(&quarter));
        println!("errors: isotropic {:?}", errors(&iso));
        // The isotropic plate cannot carry the wood's torsional softness: its first bending
        // is the worst of the three models.
        assert!(errors(&iso)[0] < errors(&quarter)[0]);
    }

    /// The four modes are, in order, first bending, first torsion, second bending, second
    /// torsion, read from their nodal lines: sign changes along (leading edge, trailing edge,
    /// tip chord) = (0, 0, 0): no nodal line but the root; (0, 0, 1): one line running
    /// spanwise, crossing the tip chord; (0, 1, 0): one line across the span, from the
    /// trailing edge; (1, 1, 1): a spanwise and a cross-span line.
    #[test]
    fn mode_shapes_identified_by_nodal_lines() {
        let m = wing_modes(&ModelSpec::default(), 4).unwrap();
        let want = [(0, 0, 0), (0, 0, 1), (0, 1, 0), (1, 1, 1)];
        for (k, w) in want.iter().enumerate() {
            assert_eq!(m.nodal_signature(k), *w, "mode {}", k + 1);
        }
        let kinds: Vec<_> = (0..4).map(|k| m.kind(k)).collect();
        assert_eq!(
            kinds,
            [
                Some("1st bending"),
                Some("1st torsion"),
                Some("2nd bending"),
                Some("2nd torsion")
            ]
        );
        // First bending: the tip moves one way at both edges; first torsion: the tip's
        // leading and trailing edges move in opposite directions.
        let tip = |k: usize| {
            let t = m.tip_chord(k);
            (t[0], t[t.len() - 1])
        };
        assert!(tip(0).0 * tip(0).1 > 0.0);
        assert!(tip(1).0 * tip(1).1 < 0.0);
        // Mass-normalised: phi^T M phi = 1.
        for k in 0..4 {
            let phi = m.shapes.col(k);
            let mut v = Mat::<f64>::zeros(phi.nrows(), 1);
            for r in 0..phi.nrows() {
                v[(r, 0)] = phi[r];
            }
            let mv = &m.model.mass * &v;
            let g: f64 = (0..phi.nrows()).map(|r| phi[r] * mv[(r, 0)]).sum();
            assert!((g - 1.0).abs() < 1e-9, "mode {k}: {g}");
        }
    }

    /// The QUASI-STEADY flutter case (vortex lattice 12 x 12, `C(k) = 1`, no apparent mass)
    /// at the subsonic test points with the published density: printed against the
    /// experiment, not asserted (this is not the unsteady comparison of issue 13). Asserted
    /// only: a flutter point exists below 400 m/s and is the torsion branch.
    #[test]
    #[ignore = "slow (three p-k sweeps); run with --ignored to print the table"]
    fn quasi_steady_flutter_table() {
        use super::super::pk::{PkSettings, pk_solve};
        let modes = wing_modes(&ModelSpec::default(), 4).unwrap();
        let speeds: Vec<f64> = (1..=80).map(|i| 5.0 * i as f64).collect();
        println!("| M | FSI exp | FSI quasi-steady | diff | w_f/w_a exp | quasi-steady | diff |");
        for t in FLUTTER_TESTS.iter().filter(|t| t.mach < 0.95) {
            let (model, gaf) = quasi_steady_problem(&modes, t.mach, t.density, 12, 12).unwrap();
            let sol = pk_solve(&model, &gaf, &speeds, PkSettings::default()).unwrap();
            let f = sol.critical().expect("no flutter point below 400 m/s");
            let fsi = f.speed / (semichord() * OMEGA_ALPHA * t.mass_ratio.sqrt());
            let ratio = f.omega / OMEGA_ALPHA;
            println!(
                "| {} | {} | {fsi:.4} | {:+.1} % | {:.4} | {ratio:.4} | {:+.1} % | {} with {:?}, V {:.1} m/s",
                t.mach,
                t.speed_index,
                100.0 * (fsi / t.speed_index - 1.0),
                t.frequency_ratio(),
                100.0 * (ratio / t.frequency_ratio() - 1.0),
                f.name,
                f.partner.as_ref().map(|p| &p.1),
                f.speed
            );
            assert!(f.name.contains("torsion"), "{}", f.name);
        }
    }

    /// The unsteady case of the tests below: 4 modes of the default model, the sweep
    /// `V_MIN..=400` m/s by 5, `k_max` from [`k_max_for`] at `V_MIN` (3.21), 25 tabulated `k`,
    /// 12 spanwise strips (chordwise from the box-size rule: 13).
    const V_MIN: f64 = 60.0;

    struct UnsteadyResult {
        spanwise: usize,
        fsi: f64,
        ratio: f64,
        speed: f64,
        name: String,
        partner: Option<String>,
        chordwise: usize,
        wake_rings: usize,
    }

    fn unsteady_flutter(
        modes: &WingModes,
        t: &FlutterTest,
        k_count: usize,
        spanwise: usize,
        min_chordwise: usize,
        aero: UnsteadyAero,
    ) -> Result<UnsteadyResult, AgardError> {
        use super::super::pk::{PkSettings, pk_solve};
        let speeds: Vec<f64> = (0..=((400.0 - V_MIN) / 5.0) as usize)
            .map(|i| V_MIN + 5.0 * i as f64)
            .collect();
        let settings = UnsteadySettings {
            aero,
            k_max: k_max_for(modes, V_MIN),
            k_count,
            spanwise,
            min_chordwise,
        };
        let p = unsteady_problem(modes, t.mach, t.density, &settings)?;
        let sol = pk_solve(&p.model, &p.gaf, &speeds, PkSettings::default())?;
        let f = sol.critical().expect("no flutter point below 400 m/s");
        Ok(UnsteadyResult {
            fsi: f.speed / (semichord() * OMEGA_ALPHA * t.mass_ratio.sqrt()),
            ratio: f.omega / OMEGA_ALPHA,
            speed: f.speed,
            name: f.name.clone(),
            partner: f.partner.as_ref().map(|p| p.1.clone()),
            chordwise: p.chordwise,
            spanwise: p.spanwise,
            wake_rings: p.wake_rings,
        })
    }

    fn print_unsteady(t: &FlutterTest, r: &UnsteadyResult) {
        println!(
            "| {} | {} | {:.4} | {:+.1} % | {:.4} | {:.4} | {:+.1} % | {} with {:?}, V {:.1} m/s, {} x {} panels, {} wake rings",
            t.mach,
            t.speed_index,
            r.fsi,
            100.0 * (r.fsi / t.speed_index - 1.0),
            t.frequency_ratio(),
            r.ratio,
            100.0 * (r.ratio / t.frequency_ratio() - 1.0),
            r.name,
            r.partner,
            r.speed,
            r.chordwise,
            r.spanwise,
            r.wake_rings
        );
    }

    /// The UNSTEADY flutter case at M = 0.499 against the experiment (a regression fence on
    /// the published comparison, not a fit): achieved FSI 0.4512 (exp. 0.4459, +1.2 %),
    /// frequency ratio 0.6153 (exp. 0.5353, +15.0 %), first torsion with first bending at
    /// 174.5 m/s (docs/validation.md says why the frequency is high).
    #[test]
    fn unsteady_flutter_m0499() {
        let modes = wing_modes(&ModelSpec::default(), 4).unwrap();
        let t = &FLUTTER_TESTS[0];
        let r = unsteady_flutter(&modes, t, 25, 12, 0, UnsteadyAero::VortexLattice).unwrap();
        print_unsteady(t, &r);
        assert_eq!(r.chordwise, 13);
        assert!(r.name.contains("torsion"), "{}", r.name);
        assert!(r.partner.as_deref().is_some_and(|p| p.contains("bending")));
        let (e_fsi, e_ratio) = (
            r.fsi / t.speed_index - 1.0,
            r.ratio / t.frequency_ratio() - 1.0,
        );
        // Achieved +1.2 % and +15.0 %.
        assert!(e_fsi.abs() < 0.02, "FSI {} ({e_fsi:+.3})", r.fsi);
        assert!(
            e_ratio.abs() < 0.16,
            "frequency ratio {} ({e_ratio:+.3})",
            r.ratio
        );
    }

    /// Convergence of the M = 0.499 unsteady case (printed): the k table doubled, the
    /// chordwise and the spanwise panels doubled; then sensitivities (not comparisons): the
    /// same density at M = 0 and 0.3, 6 modes, the grain along the 45° line. Printed
    /// (docs/validation.md): 49 k 0.4512 / 0.6154; 26 x 12 0.4508 / 0.6222; 13 x 24
    /// 0.4568 / 0.6120; M = 0 0.4608 / 0.6083; M = 0.3 0.4574 / 0.6107; 45° grain 0.4588 /
    /// 0.6143; 6 modes: the same torsion-bending point 0.4508 / 0.6214, plus spurious
    /// crossings of mode 6, an in-plane mode (max |w| 2.7e-10) whose damping is round-off.
    #[test]
    #[ignore = "slow (four p-k sweeps, one on 26 x 12 and one on 13 x 24 panels)"]
    fn unsteady_convergence() {
        let modes = wing_modes(&ModelSpec::default(), 4).unwrap();
        let t = &FLUTTER_TESTS[0];
        for (k_count, spanwise, chordwise) in [(25, 12, 0), (49, 12, 0), (25, 12, 26), (25, 24, 0)]
        {
            let r = unsteady_flutter(
                &modes,
                t,
                k_count,
                spanwise,
                chordwise,
                UnsteadyAero::VortexLattice,
            )
            .unwrap();
            print!("{k_count} k: ");
            print_unsteady(t, &r);
        }
        // Compressibility sensitivity (not a comparison): the same density at M = 0 and 0.3.
        for mach in [0.0, 0.3] {
            let r = unsteady_flutter(
                &modes,
                &FlutterTest { mach, ..*t },
                25,
                12,
                0,
                UnsteadyAero::VortexLattice,
            )
            .unwrap();
            print!("M {mach} with the M = 0.499 density: ");
            print_unsteady(t, &r);
        }
        // Structural sensitivity: 6 modes instead of 4; the grain along the 45° line.
        let six = wing_modes(&ModelSpec::default(), 6).unwrap();
        println!("6 modes: {:?} Hz", six.frequencies_hz);
        // The largest normal displacement of each mode (an in-plane mode has next to none).
        let w_max: Vec<f64> = six
            .w
            .iter()
            .map(|w| w.iter().fold(0.0_f64, |a, v| a.max(v.abs())))
            .collect();
        println!("  max |w| per mode {w_max:?}");
        let settings = UnsteadySettings {
            aero: UnsteadyAero::VortexLattice,
            k_max: k_max_for(&six, V_MIN),
            k_count: 25,
            spanwise: 12,
            min_chordwise: 0,
        };
        let p = unsteady_problem(&six, t.mach, t.density, &settings).unwrap();
        let speeds: Vec<f64> = (0..=68).map(|i| V_MIN + 5.0 * i as f64).collect();
        let sol = super::super::pk::pk_solve(
            &p.model,
            &p.gaf,
            &speeds,
            super::super::pk::PkSettings::default(),
        )
        .unwrap();
        println!(
            "  {} x {} panels, unstable at the first speed: {:?}",
            p.chordwise, p.spanwise, sol.unstable_at_start
        );
        for f in &sol.flutter {
            println!(
                "  flutter: {} with {:?} at {:.1} m/s, FSI {:.4}, w/w_a {:.4}, k {:.3}",
                f.name,
                f.partner.as_ref().map(|p| &p.1),
                f.speed,
                f.speed / (semichord() * OMEGA_ALPHA * t.mass_ratio.sqrt()),
                f.omega / OMEGA_ALPHA,
                f.k
            );
        }
        let quarter = wing_modes(
            &ModelSpec {
                material: Material::Orthotropic(Grain::QuarterChord),
                ..ModelSpec::default()
            },
            4,
        )
        .unwrap();
        let r = unsteady_flutter(&quarter, t, 25, 12, 0, UnsteadyAero::VortexLattice).unwrap();
        print!("45 deg grain: ");
        print_unsteady(t, &r);
    }

    /// The unsteady table at M = 0.499 and 0.678 (printed), and M = 0.901, which the
    /// harmonic lattice refuses (beyond its trusted M = 0.9).
    #[test]
    #[ignore = "slow (p-k sweeps); run with --ignored to print the table"]
    fn unsteady_flutter_table() {
        let modes = wing_modes(&ModelSpec::default(), 4).unwrap();
        for t in FLUTTER_TESTS.iter().filter(|t| t.mach < 0.95) {
            match unsteady_flutter(&modes, t, 25, 12, 0, UnsteadyAero::VortexLattice) {
                Ok(r) => print_unsteady(t, &r),
                Err(e) => println!("| {} | refused: {e} |", t.mach),
            }
        }
    }

    /// The DOUBLET-LATTICE flutter case at M = 0.499 and 0.678 against the experiment (a
    /// regression fence on the published comparison, not a fit; the same lattice, k table and
    /// sweep as [`unsteady_flutter_m0499`]): achieved FSI 0.4529 (+1.6 %) and 0.4316 (+3.4 %),
    /// frequency ratio 0.5851 (+9.3 %) and 0.5298 (+12.2 %), the first-bending branch
    /// coalescing with first torsion at 175.2 and 239.2 m/s (docs/validation.md).
    #[test]
    fn dlm_flutter_m0499_m0678() {
        let modes = wing_modes(&ModelSpec::default(), 4).unwrap();
        for (t, fsi_tol, ratio_tol) in [
            (&FLUTTER_TESTS[0], 0.02, 0.10),
            (&FLUTTER_TESTS[1], 0.04, 0.13),
        ] {
            let r = unsteady_flutter(&modes, t, 25, 12, 0, UnsteadyAero::DoubletLattice).unwrap();
            print_unsteady(t, &r);
            assert_eq!((r.chordwise, r.wake_rings), (13, 0));
            let pair = format!("{} {}", r.name, r.partner.as_deref().unwrap_or(""));
            assert!(
                pair.contains("torsion") && pair.contains("bending"),
                "{pair}"
            );
            let (e_fsi, e_ratio) = (
                r.fsi / t.speed_index - 1.0,
                r.ratio / t.frequency_ratio() - 1.0,
            );
            assert!(
                e_fsi.abs() < fsi_tol,
                "M {}: FSI {} ({e_fsi:+.3})",
                t.mach,
                r.fsi
            );
            assert!(
                e_ratio.abs() < ratio_tol,
                "M {}: frequency ratio {} ({e_ratio:+.3})",
                t.mach,
                r.ratio
            );
        }
    }

    /// The doublet-lattice table (printed): M = 0.499, 0.678, 0.901 with the DLM (the same
    /// lattice, k table and p-k sweep as the vortex-lattice case), then the M = 0.499 density
    /// at M = 0 and 0.3 (compressibility sensitivity), the chordwise and the spanwise doubling
    /// at M = 0.678 and 0.901.
    #[test]
    #[ignore = "slow (nine p-k sweeps); run with --ignored to print the table"]
    fn dlm_flutter_table() {
        let modes = wing_modes(&ModelSpec::default(), 4).unwrap();
        for t in FLUTTER_TESTS.iter().filter(|t| t.mach < 0.95) {
            match unsteady_flutter(&modes, t, 25, 12, 0, UnsteadyAero::DoubletLattice) {
                Ok(r) => print_unsteady(t, &r),
                Err(e) => println!("| {} | refused: {e} |", t.mach),
            }
        }
        let t = &FLUTTER_TESTS[0];
        for mach in [0.0, 0.3] {
            let r = unsteady_flutter(
                &modes,
                &FlutterTest { mach, ..*t },
                25,
                12,
                0,
                UnsteadyAero::DoubletLattice,
            )
            .unwrap();
            print!("DLM at M {mach} with the M = 0.499 density: ");
            print_unsteady(t, &r);
        }
        for (t, spanwise, chordwise) in [
            (&FLUTTER_TESTS[1], 12, 26),
            (&FLUTTER_TESTS[1], 24, 0),
            (&FLUTTER_TESTS[2], 12, 26),
            (&FLUTTER_TESTS[2], 24, 0),
        ] {
            let r = unsteady_flutter(
                &modes,
                t,
                25,
                spanwise,
                chordwise,
                UnsteadyAero::DoubletLattice,
            )
            .unwrap();
            print!("DLM {spanwise} strips, chordwise >= {chordwise}: ");
            print_unsteady(t, &r);
        }
    }

    /// Mesh convergence of the default model (printed): 8 x 8, 12 x 12, 16 x 16, 24 x 24.
    #[test]
    #[ignore = "slow (24 x 24 mesh); run with --ignored to print the table"]
    fn mesh_convergence() {
        for n in [8, 12, 16, 24] {
            let _ = report(&ModelSpec {
                chord_elements: n,
                span_elements: n,
                ..ModelSpec::default()
            });
        }
    }
}
