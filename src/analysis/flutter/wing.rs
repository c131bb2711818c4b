//! A lifting surface clamped at its root: the wind-tunnel model of a flutter test (a
//! `fixture` of the language), its plate finite-element model, modes and flutter problems
//! with the fin panels' quasi-steady or unsteady generalised forces.
//!
//! # The structural model
//!
//! A flat plate on the trapezoidal planform, clamped along the root chord, of MITC4 shells
//! ([`crate::structure::generate::cantilever_plate_model`]) on the fin generator's grid
//! (`chord_elements` x `span_elements` quads; lines of constant chord fraction run
//! spanwise). The thickness is constant, or follows a tabulated section,
//! `t(x, y) = c(y) τ(x/c)` with `τ` twice the tabulated half-thickness over chord (linear
//! between evenly spaced stations from the leading edge to the trailing edge), averaged over
//! each element's chordwise extent by Gauss quadrature at its mid-span chord (exact for the
//! piecewise-linear `τ`). The lamina is isotropic (`E`, `ν`, `G = E/(2(1+ν))`) or the
//! orthotropic plane-stress lamina `E_1, E_2, ν_12, G_12` of
//! [`crate::structure::generate::orthotropic_plane_stress`] with the grain (direction 1)
//! along each element's spanwise grid line ([`Grain::GridLines`]) or along one straight line
//! swept by a given angle ([`Grain::Swept`]); the transverse shear modulus is `G_12` (not
//! published for the AGARD wing; a thin plate barely feels it). The density is the
//! material's, or the surface's mass over the plate's volume on the mesh
//! ([`WingDensity::Mass`]), so the FE mass is the tested model's.
//!
//! # Mode shapes
//!
//! Node positions are given in the wing's own frame: `x` chordwise aft of the root leading
//! edge, `y` spanwise from the root; `w` is the displacement normal to the plate along
//! `z = x × y` (the lattice frame of [`crate::aero::panel`]), per unit modal
//! coordinate of the mass-normalised mode (`φᵀ M φ = 1`, so `w` is in m/sqrt(kg)).
//!
//! # Reference quantities
//!
//! The reduced frequency is `k = ω b / V` with `b` half the root chord (the convention of
//! AGARD 445.6, E. C. Yates Jr., NASA TM 100492, 1987, and of NACA TN 4197's root-chord
//! parameters). [`WingSpec::mass_ratio`] is Yates' `μ = m/(ρ V_cone)`, `V_cone` the volume of
//! the conical frustum whose bases are the root and tip chords, and the flutter speed index
//! is `V_f/(b ω_α sqrt(μ))` for a reference frequency `ω_α` (Yates' symbols).

use faer::{Mat, c64};
use rayon::prelude::*;

use super::pk::{FlutterError, FlutterModel, GafFn, GafTable};
use crate::aero::FinPlanform;
use crate::aero::panel::dlm::Dlm;
use crate::aero::panel::harmonic::{self, HarmonicVlm, WakeSettings};
use crate::aero::panel::machbox::{self, MachBox};
use crate::aero::panel::spline::{SplineError, surface_spline};
use crate::aero::panel::{Lattice, PanelError, Spacing, vlm};
use crate::structure::fe_model::FeModel;
use crate::structure::generate::{
    FinSpec, GenerateError, MaterialProps, cantilever_fin_model, cantilever_plate_model,
    orthotropic_plane_stress, shell_element_lamina,
};
use crate::structure::modal::{self, ModalError};

/// Direction of the grain of an orthotropic lamina.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Grain {
    /// Along the element's spanwise grid line (a line of constant chord fraction).
    GridLines,
    /// Along a straight line swept back by this angle (rad) from the spanwise normal to the
    /// flow, the same in every element (AGARD 445.6: its 45° quarter-chord line).
    Swept(f64),
}

/// The plate's lamina.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WingMaterial {
    Isotropic {
        youngs_modulus: f64,
        poisson: f64,
    },
    /// Plane-stress orthotropic lamina; `e1` along the grain.
    Orthotropic {
        e1: f64,
        e2: f64,
        nu12: f64,
        g12: f64,
        grain: Grain,
    },
}

/// The plate's thickness.
#[derive(Clone, Debug, PartialEq)]
pub enum WingThickness {
    /// Constant, m.
    Constant(f64),
    /// Half-thickness over chord `z/c` at evenly spaced chord fractions from the leading
    /// edge (0) to the trailing edge (1), at least two stations (module doc).
    Section(Vec<f64>),
}

/// Where the plate's density comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WingDensity {
    /// kg/m³.
    Density(f64),
    /// The surface's mass, kg: density = mass / the plate's volume on the mesh.
    Mass(f64),
}

/// A lifting surface clamped at its root (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct WingSpec {
    pub span: f64,
    pub root_chord: f64,
    pub tip_chord: f64,
    /// Leading-edge sweep, rad.
    pub leading_edge_sweep: f64,
    pub thickness: WingThickness,
    pub material: WingMaterial,
    pub density: WingDensity,
    pub chord_elements: usize,
    pub span_elements: usize,
}

/// Errors of the clamped surface's model and flutter problems.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WingError {
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
    #[error("the section needs at least two half-thickness stations, none negative")]
    Section,
    #[error(
        "the lattice would need {needed} chordwise panels (more than {most}) to resolve the highest mode's reduced frequency at the lowest speed {v_min:.1} m/s"
    )]
    TooManyPanels {
        needed: usize,
        most: usize,
        v_min: f64,
    },
}

impl From<super::fin::FinFlutterError> for WingError {
    /// The errors of the transonic bridge (`fin::bridged`): its table and panel errors as
    /// such, anything else (mismatched end tables) as a panel error at its Mach.
    fn from(e: super::fin::FinFlutterError) -> Self {
        use super::fin::FinFlutterError as F;
        match e {
            F::Flutter(f) => WingError::Flutter(f),
            F::Panel(p) => WingError::Panel(p),
            F::BridgeMismatch { mach } => {
                WingError::Panel(PanelError::Untrusted(mach, "transonic bridge"))
            }
            // `blend_tables` makes no other error.
            _ => WingError::Panel(PanelError::Untrusted(f64::NAN, "transonic bridge")),
        }
    }
}

/// Thickness over chord `τ(u) = 2 z/c` of a tabulated section at chord fraction `u` from
/// the leading edge (linear between the stations).
pub fn section_thickness_over_chord(half: &[f64], u: f64) -> f64 {
    let m = half.len().saturating_sub(1).max(1);
    let s = u.clamp(0.0, 1.0) * m as f64;
    let k = (s.floor() as usize).min(m - 1);
    let f = s - k as f64;
    2.0 * (half[k] * (1.0 - f) + half[(k + 1).min(half.len() - 1)] * f)
}

/// Mean of `τ` over the chord fraction `[u0, u1]` (two-point Gauss-Legendre on each station
/// interval it overlaps; `τ` is linear there, so this is exact).
fn mean_thickness_over_chord(half: &[f64], u0: f64, u1: f64) -> f64 {
    let m = (half.len().max(2) - 1) as f64;
    let (lo, hi) = (u0.min(u1), u0.max(u1));
    let mut sum = 0.0;
    let mut a = lo;
    while a < hi {
        let b = (((a * m).floor() + 1.0) / m).min(hi);
        // Two-point Gauss is exact for a linear integrand on [a, b].
        let (c, h) = (0.5 * (a + b), 0.5 * (b - a) / 3f64.sqrt());
        sum += 0.5
            * (b - a)
            * (section_thickness_over_chord(half, c - h)
                + section_thickness_over_chord(half, c + h));
        a = b;
    }
    sum / (hi - lo)
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

/// The material of the grid probe: [`cantilever_plate_model`] does not use the fin's
/// material (the element closure carries it), and the volume needs only the grid.
const PROBE: MaterialProps = MaterialProps {
    youngs_modulus: 1.0,
    poisson: 0.3,
    density: 1.0,
};

impl WingSpec {
    /// The planform as a fin of the generator: root trailing edge at `x_body = -c_r`, so the
    /// root leading edge is at `x_body = 0` and the chordwise coordinate aft of it is
    /// `-x_body`.
    fn fin_spec(&self, thickness: f64, material: MaterialProps) -> FinSpec {
        FinSpec {
            count: 1,
            span: self.span,
            root_chord: self.root_chord,
            tip_chord: self.tip_chord,
            sweep: self.leading_edge_sweep,
            thickness,
            cant: 0.0,
            angles: vec![],
            root_trailing_edge_x: -self.root_chord,
            span_elements: self.span_elements,
            chord_elements: self.chord_elements,
            material,
            lamina: None,
            outline: crate::check::ir::FinOutline::Trapezoidal,
        }
    }

    /// Thickness of quad (i, j) of the grid: constant, or the local chord at the quad's
    /// mid-span times the mean `τ` over its chordwise extent (i counts from the trailing
    /// edge).
    fn element_thickness(&self, i: usize, j: usize) -> f64 {
        match &self.thickness {
            WingThickness::Constant(t) => *t,
            WingThickness::Section(half) => {
                let eta = (j as f64 + 0.5) / self.span_elements as f64;
                let chord = self.root_chord + (self.tip_chord - self.root_chord) * eta;
                let n = self.chord_elements as f64;
                // Chord fraction from the leading edge of the quad's two chordwise stations.
                let (u0, u1) = (1.0 - i as f64 / n, 1.0 - (i as f64 + 1.0) / n);
                chord * mean_thickness_over_chord(half, u1, u0)
            }
        }
    }

    /// Volume of the plate on the mesh, m³.
    pub fn plate_volume(&self) -> f64 {
        let f = self.fin_spec(1.0, PROBE);
        let mut v = 0.0;
        for j in 0..f.span_elements {
            for i in 0..f.chord_elements {
                let p = |ci: usize, cj: usize| {
                    let (x, eta) = f.planform_point(ci, cj);
                    [x, eta]
                };
                let ab = [p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)];
                v += self.element_thickness(i, j) * quad_area(&ab);
            }
        }
        v
    }

    /// The plate's density, kg/m³.
    pub fn density_kg_m3(&self) -> f64 {
        match self.density {
            WingDensity::Density(rho) => rho,
            WingDensity::Mass(m) => m / self.plate_volume(),
        }
    }

    /// The plate's mass, kg (density times the volume on the mesh).
    pub fn mass(&self) -> f64 {
        match self.density {
            WingDensity::Mass(m) => m,
            WingDensity::Density(rho) => rho * self.plate_volume(),
        }
    }

    /// The planform as the panel model's surface (root at the reflection plane).
    pub fn planform(&self) -> FinPlanform {
        FinPlanform {
            span: self.span,
            root_chord: self.root_chord,
            tip_chord: self.tip_chord,
            tip_le_offset: self.span * self.leading_edge_sweep.tan(),
            body_radius: 0.0,
            outline: crate::check::ir::FinOutline::Trapezoidal,
        }
    }

    /// Volume of the conical frustum of Yates' mass ratio, m³ (module doc).
    pub fn cone_volume(&self) -> f64 {
        let (cr, ct) = (self.root_chord, self.tip_chord);
        std::f64::consts::PI * self.span * (cr * cr + cr * ct + ct * ct) / 12.0
    }

    /// Yates' mass ratio `μ = m/(ρ_air V_cone)` of the plate's mass (module doc).
    pub fn mass_ratio(&self, air_density: f64) -> f64 {
        self.mass() / (air_density * self.cone_volume())
    }

    /// Builds the clamped FE model (module doc).
    pub fn model(&self) -> Result<FeModel, WingError> {
        if let WingThickness::Section(half) = &self.thickness {
            if half.len() < 2 || !half.iter().all(|h| h.is_finite() && *h >= 0.0) {
                return Err(WingError::Section);
            }
        }
        let rho = self.density_kg_m3();
        match (self.material, &self.thickness) {
            (
                WingMaterial::Isotropic {
                    youngs_modulus,
                    poisson,
                },
                WingThickness::Constant(t),
            ) => Ok(cantilever_fin_model(&self.fin_spec(
                *t,
                MaterialProps {
                    youngs_modulus,
                    poisson,
                    density: rho,
                },
            ))?),
            (material, _) => {
                let probe = self.fin_spec(1.0, PROBE);
                let (e1, e2, nu12, g12, grain) = match material {
                    WingMaterial::Isotropic {
                        youngs_modulus,
                        poisson,
                    } => (
                        youngs_modulus,
                        youngs_modulus,
                        poisson,
                        youngs_modulus / (2.0 * (1.0 + poisson)),
                        Grain::GridLines,
                    ),
                    WingMaterial::Orthotropic {
                        e1,
                        e2,
                        nu12,
                        g12,
                        grain,
                    } => (e1, e2, nu12, g12, grain),
                };
                let swept = |sweep: f64| {
                    // Local a points forward (toward the leading edge), b outboard: a line
                    // swept back by Λ runs along (-sin Λ, cos Λ).
                    let d = (-sweep.sin(), sweep.cos());
                    d.1.atan2(d.0)
                };
                let model = cantilever_plate_model(&probe, |i, j, ab| {
                    let theta = match grain {
                        Grain::Swept(sweep) => swept(sweep),
                        Grain::GridLines => {
                            let da = ab[3][0] + ab[2][0] - ab[0][0] - ab[1][0];
                            let db = ab[3][1] + ab[2][1] - ab[0][1] - ab[1][1];
                            db.atan2(da)
                        }
                    };
                    let q = orthotropic_plane_stress(e1, e2, nu12, g12, theta);
                    shell_element_lamina(ab, self.element_thickness(i, j), &q, g12, rho)
                })?;
                Ok(model)
            }
        }
    }

    /// The lowest `count` modes of the model (module doc).
    pub fn modes(&self, count: usize) -> Result<WingModes, WingError> {
        let model = self.model()?;
        let modes = modal::solve(&model, count)?;
        let n_el = modes.omega2.len() - modes.n_rigid;
        if n_el < count {
            return Err(WingError::TooFewModes(count, n_el));
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
            row_len: self.chord_elements + 1,
            mass,
            planform: self.planform(),
        })
    }
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
    /// The planform the modes were computed on (the panel model's surface).
    pub planform: FinPlanform,
}

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
    /// The reference semichord `b`: half the root chord (module doc).
    pub fn semichord(&self) -> f64 {
        0.5 * self.planform.root_chord
    }

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

/// The flutter problem of the wing's modes with the QUASI-STEADY vortex-lattice GAF (not the
/// unsteady one the validation calls for; labelled so wherever it is reported).
///
/// Modal mass `I`, stiffness `diag(ω²)`. Aerodynamics: the vortex-lattice force map `K` of
/// [`vlm::force_map`] (`F = q K α_e`, Prandtl-Glauert) with the harmonic normalwash of mode
/// `j`, `α_e = -∂z_j/∂x - i (k/b) z_j` at the control points (the linearised tangency
/// condition of [`crate::aero::panel`], `∂/∂t = iω`, `ω/V = k/b`), and the work of
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
) -> Result<QuasiSteadyProblem<impl Fn(f64, &mut [c64]) + use<>>, WingError> {
    let lattice = Lattice::new(&modes.planform, chordwise, spanwise, Spacing::Uniform)?;
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
    let bs = modes.semichord();
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
) -> Result<ModeRows, WingError> {
    let root = modes.row_len;
    let root_chord = modes.planform.root_chord;
    let mut nodes: Vec<[f64; 2]> = (0..root)
        .map(|i| [root_chord * (1.0 - i as f64 / (root - 1) as f64), 0.0])
        .collect();
    nodes.extend(modes.x.iter().zip(&modes.y).map(|(&x, &y)| [x, y]));
    let (g, gx) = surface_spline(&nodes, eval, root_chord)?;
    let (gf, _) = surface_spline(&nodes, force, root_chord)?;
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
        b_ref: modes.semichord(),
        density,
    }
}

/// The subsonic unsteady aerodynamics of [`unsteady_problem`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnsteadyAero {
    /// The harmonic vortex lattice of [`harmonic`] (convected ringed wake, Göthert
    /// compressibility), `2n` force points.
    VortexLattice,
    /// The doublet-lattice method of [`crate::aero::panel::dlm`] (the compressible unsteady kernel), `n` force
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
pub fn chordwise_for(planform: &FinPlanform, k_max: f64) -> usize {
    let dx = harmonic::BOX_RULE * std::f64::consts::PI * planform.root_chord / k_max;
    ((planform.root_chord / dx).ceil() as usize).max(1)
}

/// The reduced frequency a sweep starting at `v_min` needs: `1.2 ω_max b_s / v_min`, the
/// highest mode's `k` at the lowest speed with 20 % to spare (the rule of `analyze flutter`).
pub fn k_max_for(modes: &WingModes, v_min: f64) -> f64 {
    let w =
        2.0 * std::f64::consts::PI * modes.frequencies_hz.iter().fold(0.0_f64, |a, &f| a.max(f));
    1.2 * w * modes.semichord() / v_min
}

/// The UNSTEADY flutter problem of [`unsteady_problem`].
pub struct UnsteadyProblem {
    pub model: FlutterModel,
    pub gaf: GafTable,
    /// The lattice used: chordwise x spanwise panels (uniform), and its wake rings.
    pub chordwise: usize,
    pub spanwise: usize,
    pub wake_rings: usize,
    /// In the transonic band, the bridge the table was made by (`fin::bridged`).
    pub bridge: Option<super::fin::TransonicBridge>,
}

impl UnsteadyAero {
    /// The clamped fin's model with the same subsonic method (for the bridge's ends and the
    /// method names of `fin`).
    pub fn fin_aero(self) -> super::fin::FinAero {
        match self {
            UnsteadyAero::VortexLattice => super::fin::FinAero::Unsteady,
            UnsteadyAero::DoubletLattice => super::fin::FinAero::DoubletLattice,
        }
    }
}

/// The unsteady flutter problem of the wing at any Mach (issue 33): [`direct_unsteady_problem`]
/// outside the transonic band of `settings.aero` (its subsonic lattice, or above Mach 1.1
/// the Mach box, unsteady piston theory where its criterion holds, as the clamped fin), and
/// inside it the blend of the band's two end tables at the same reduced frequencies
/// (`fin::bridged`, its uncertainty in [`UnsteadyProblem::bridge`]). The lattice reported is
/// the subsonic end's.
pub fn unsteady_problem(
    modes: &WingModes,
    mach: f64,
    density: f64,
    settings: &UnsteadySettings,
) -> Result<UnsteadyProblem, WingError> {
    let mut last: Option<UnsteadyProblem> = None;
    let (gaf, bridge) = super::fin::bridged(mach, settings.aero.fin_aero(), |m| {
        let p = direct_unsteady_problem(modes, m, density, settings)?;
        let g = p.gaf.clone();
        if last.is_none() {
            last = Some(p);
        }
        Ok::<_, WingError>(g)
    })?;
    let mut p = last.ok_or(WingError::Panel(PanelError::BadMach(mach)))?;
    p.gaf = gaf;
    p.bridge = bridge;
    Ok(p)
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
/// [`crate::aero::panel::dlm::MACH_LIMIT`]. From Mach 1.1 ([`machbox::MIN_MACH`]) either
/// choice uses the harmonic Mach box ([`MachBox::forces`], boxes from the box rule as
/// `fin::mach_boxes`), or unsteady piston theory with Ackeret's factor where
/// [`machbox::piston_valid`] holds, as the clamped fin does; [`unsteady_problem`] bridges the
/// band between.
pub fn direct_unsteady_problem(
    modes: &WingModes,
    mach: f64,
    density: f64,
    settings: &UnsteadySettings,
) -> Result<UnsteadyProblem, WingError> {
    let chordwise = chordwise_for(&modes.planform, settings.k_max).max(settings.min_chordwise);
    let lattice = Lattice::new(
        &modes.planform,
        chordwise,
        settings.spanwise,
        Spacing::Uniform,
    )?;
    enum Map {
        Vlm(HarmonicVlm),
        Dlm(Dlm),
        Box(MachBox),
        Piston(harmonic::HarmonicMap),
    }
    let supersonic = mach >= machbox::MIN_MACH;
    let map = match settings.aero {
        _ if supersonic && machbox::piston_valid(&modes.planform, mach) => {
            Map::Piston(harmonic::piston_map(
                &lattice,
                mach,
                crate::aero::panel::piston::Correction::Ackeret,
            )?)
        }
        _ if supersonic => Map::Box(MachBox::new(
            &modes.planform,
            mach,
            super::fin::mach_boxes(&modes.planform, mach, settings.k_max / modes.semichord()),
        )?),
        UnsteadyAero::VortexLattice => {
            let vlm = HarmonicVlm::new(&lattice, mach, &WakeSettings::default())?;
            vlm.check_resolution(settings.k_max / modes.semichord())?;
            Map::Vlm(vlm)
        }
        UnsteadyAero::DoubletLattice => {
            crate::aero::panel::dlm::check_boxes(&lattice)?;
            let d = Dlm::new(&lattice, mach)?;
            d.check_resolution(settings.k_max / modes.semichord())?;
            Map::Dlm(d)
        }
    };
    let m0 = match &map {
        Map::Vlm(v) => v.map(0.0)?,
        Map::Dlm(d) => d.map(0.0)?,
        Map::Box(b) => harmonic::HarmonicMap {
            eval: b.centres().to_vec(),
            force: b.centres().to_vec(),
            k: Vec::new(),
        },
        Map::Piston(h) => h.clone(),
    };
    let rows = mode_rows(modes, &m0.eval, &m0.force)?;
    let count = modes.w.len();
    let (ne, nf) = (m0.eval.len(), m0.force.len());
    let bs = modes.semichord();
    let nk = settings.k_count.max(2);
    let ks: Vec<f64> = (0..nk)
        .map(|i| {
            let s = i as f64 / (nk - 1) as f64;
            settings.k_max * s * s
        })
        .collect();
    // Each reduced frequency is independent (its own influence matrix and solve): in
    // parallel, collected in order, the same bits whatever the thread count.
    let values = ks
        .par_iter()
        .map(|&k| -> Result<Vec<c64>, WingError> {
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
                Map::Box(b) => b.forces(nu, &alpha, count)?,
                // Piston theory is local: F = K α with its frequency-independent map.
                Map::Piston(h) => {
                    let mut f = vec![c64::new(0.0, 0.0); nf * count];
                    for p in 0..nf {
                        for r in 0..ne {
                            let kv = h.k[p * ne + r];
                            for j in 0..count {
                                f[p * count + j] += kv * alpha[r * count + j];
                            }
                        }
                    }
                    f
                }
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
            Ok(q)
        })
        .collect::<Result<Vec<_>, WingError>>()?;
    Ok(UnsteadyProblem {
        model: modal_model(modes, density),
        gaf: GafTable::new(count, ks, values)?,
        chordwise,
        spanwise: settings.spanwise,
        wake_rings: match &map {
            Map::Vlm(v) => v.wake_rings(),
            _ => 0,
        },
        bridge: None,
    })
}
