//! The panel models of a compiled vehicle's fins, projected on its modes per Mach (issue 12,
//! deliverables 1-4).
//!
//! # Per fin
//!
//! 1. The fin's FE nodes (component tag `i`) in fin coordinates ([`super`]): `x = x_LE,root -
//!    x_body` aft of the root leading edge (body x, exact without cant, as
//!    `runtime::forces::fin_aero` locates the nodes), `y = r · e_s - y_root` along the span
//!    (`y_root` the body radius for a generated structure, the innermost node for an imported
//!    one). When the root row is not among the fin's nodes (the generator ties it rigidly to the
//!    body) it is added as virtual nodes attached rigidly to the nearest body node, as the
//!    key-node model does. The normal modal rows: `z_k = -n · S_u,k η`, `n` the fin normal of
//!    the mesh frame (`structure::generate::mesh::fin_frame`), since the panel `+z` is
//!    `x_aft × e_s = -n`.
//! 2. The surface spline ([`super::spline`]) from those nodes to the panel points: `Z_c`
//!    (values, at the normalwash points), `Z_x` (chordwise slopes there), `Z_f` (values at the
//!    force points). Vortex lattice: control points and bound mid-points; piston theory: the
//!    centroids for both.
//! 3. The normalwash angle of [`super`] from the modal coordinates and the rigid motion,
//!
//!    `α_e = -Z_x η - Z_c η̇ / V + a_0 + a_x x + a_y y`,
//!
//!    where `a_0, a_x, a_y` describe the rigid motion's normalwash, linear over the fin plane
//!    (a uniform incidence, and the `x` and `y` gradients that an angular velocity produces:
//!    `n · (ω × r)` is linear in `r`). The panel forces `F = q K α_e` (K of [`super::vlm`] or
//!    [`super::piston`]) are reduced to the outputs
//!
//!    `y = O F`, `O = [Z_fᵀ; 1ᵀ; y_fᵀ; x_fᵀ]`: the generalised forces `Q` (the virtual work
//!    `δW = Σ_p F_p δz_p = Σ_p F_p (Z_f δη)_p`), the net normal force (N, along `+z`), its
//!    moment about the root chord line `Σ F_p y_p` (the root bending moment, N m) and its
//!    moment arm sum `Σ F_p x_p` (for the centre of pressure),
//!
//!    so that `y = q T u`, `u = [η; η̇ / V; a_0; a_x; a_y]`, `T = O K I`, `I = [-Z_x, -Z_c, 1,
//!    x_c, y_c]`. `T` (`(n + 3) x (2 n + 3)`) is the fin's aerodynamic transfer matrix at that
//!    Mach: its `Q`-rows and `η`-columns are the aerodynamic stiffness (times `q`), its `Q`-rows
//!    and `η̇`-columns the aerodynamic damping (times `q / V`), the `a`-columns the coupling with
//!    the rigid incidence and rates.
//! 4. Between `M = 0.9` and `1.2` the transfer matrix is the linear blend in Mach of those at
//!    0.9 (vortex lattice) and 1.2 (piston theory) ([`super::Regime`]).

use super::piston::{self, Correction};
use super::spline::{SplineError, surface_spline};
use super::{Lattice, PanelError, Regime, Spacing, regime, vlm};
use crate::check::ir;
use crate::runtime::forces::body_aero::planform;
use crate::runtime::forces::fin_aero::rigid_rows;
use crate::structure::compile::CompiledVehicle;

/// Lattice size and supersonic options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PanelSettings {
    pub chordwise: usize,
    pub spanwise: usize,
    pub spacing: Spacing,
    pub correction: Correction,
}

impl Default for PanelSettings {
    /// 8 x 12 cosine-spaced panels (the SPHADS-1 lift slope is within 0.5 % of the 32 x 64
    /// value, `lift_slope_converges_with_panel_count`), Ackeret-corrected piston theory.
    fn default() -> Self {
        PanelSettings {
            chordwise: 8,
            spanwise: 12,
            spacing: Spacing::Cosine,
            correction: Correction::Ackeret,
        }
    }
}

/// Why a fin's panel model could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FinPanelError {
    #[error("the vehicle declares no fins")]
    NoFins,
    #[error("fin {0} has no FE nodes")]
    EmptyFin(usize),
    #[error("fin {fin}: {error}")]
    Panel { fin: usize, error: PanelError },
    #[error("fin {fin}: {error}")]
    Spline { fin: usize, error: SplineError },
}

/// One fin's structure as the panels see it.
#[derive(Clone, Debug, PartialEq)]
pub struct FinStructure {
    /// Node positions in fin coordinates (m).
    pub nodes: Vec<[f64; 2]>,
    /// Normal displacement per unit modal coordinate, row-major `nodes x n`.
    pub normal_rows: Vec<f64>,
}

/// The fin's FE nodes in fin coordinates and their normal modal rows (module doc, step 1).
pub fn fin_structure(
    c: &CompiledVehicle,
    v: &ir::Vehicle,
    fin: usize,
) -> Result<FinStructure, FinPanelError> {
    let f = v.fins.as_ref().ok_or(FinPanelError::NoFins)?;
    let angle = f.angles.get(fin).ok_or(FinPanelError::EmptyFin(fin))?;
    let n = c.modes.len();
    // The mesh generator's fin frame (`structure::generate::mesh::fin_frame`): span
    // e_s = (0, cos δ, sin δ), canted chord e_a = cos γ x̂ + sin γ (x̂ × e_s), n = e_a × e_s.
    let (sd, cd) = angle.value.sin_cos();
    let (sg, cg) = f.cant.value.sin_cos();
    let es = [0.0, cd, sd];
    let ea = [cg, -sg * sd, sg * cd];
    let normal = [
        ea[1] * es[2] - ea[2] * es[1],
        ea[2] * es[0] - ea[0] * es[2],
        ea[0] * es[1] - ea[1] * es[0],
    ];
    let members: Vec<usize> = (0..c.node_components.len())
        .filter(|&k| usize::try_from(c.node_components[k]).ok() == Some(fin))
        .collect();
    if members.is_empty() {
        return Err(FinPanelError::EmptyFin(fin));
    }
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let y_root = match &v.structure {
        ir::Structure::Generate(g) => 0.5 * g.body.diameter.value,
        ir::Structure::Files(_) => members
            .iter()
            .map(|&k| dot(&c.node_positions[k], &es))
            .fold(f64::INFINITY, f64::min),
    };
    let root_le_x = f.root_trailing_edge_x.value + f.root_chord.value;
    let mut nodes = Vec::with_capacity(members.len());
    let mut normal_rows = Vec::with_capacity(members.len() * n);
    let push_rows = |rows: &[f64], out: &mut Vec<f64>| {
        for j in 0..n {
            out.push(-(0..3).map(|d| normal[d] * rows[d * n + j]).sum::<f64>());
        }
    };
    for &k in &members {
        let r = c.node_positions[k];
        nodes.push([root_le_x - r[0], dot(&r, &es) - y_root]);
        push_rows(&c.shapes[6 * k * n..(6 * k + 3) * n], &mut normal_rows);
    }
    let y_min = nodes.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    if y_min > 1e-6 * f.span.value {
        // Virtual root row under the innermost row's chord positions.
        let mut xs: Vec<f64> = nodes
            .iter()
            .filter(|p| (p[1] - y_min).abs() < 1e-6 * f.span.value)
            .map(|p| {
                let eta = p[1] / f.span.value;
                let x_le = eta * f.span.value * f.leading_edge_sweep.value.tan();
                let c_eta = f.root_chord.value + (f.tip_chord.value - f.root_chord.value) * eta;
                (p[0] - x_le) / c_eta
            })
            .collect();
        xs.sort_by(f64::total_cmp);
        xs.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        for xi in xs {
            let x = xi * f.root_chord.value;
            let p = [root_le_x - x, y_root * es[1], y_root * es[2]];
            let (rows, _) = rigid_rows(c, &p).ok_or(FinPanelError::EmptyFin(fin))?;
            nodes.push([x, 0.0]);
            push_rows(&rows, &mut normal_rows);
        }
    }
    Ok(FinStructure { nodes, normal_rows })
}

/// The per-Mach transfer matrices of one fin (module doc, step 3).
#[derive(Clone, Debug, PartialEq)]
pub struct FinTransfer {
    /// Number of modal coordinates.
    pub n: usize,
    /// `(n + 3) x (2 n + 3)` row-major per Mach, concatenated in the order of the Mach grid.
    pub t: Vec<f64>,
}

impl FinTransfer {
    pub fn rows(&self) -> usize {
        self.n + 3
    }
    pub fn cols(&self) -> usize {
        2 * self.n + 3
    }
    /// The transfer matrix at grid Mach `g`.
    pub fn at(&self, g: usize) -> &[f64] {
        let sz = self.rows() * self.cols();
        &self.t[g * sz..(g + 1) * sz]
    }
}

/// Panel matrices of every fin of a compiled vehicle on a Mach grid.
#[derive(Clone, Debug, PartialEq)]
pub struct PanelModel {
    pub settings: PanelSettings,
    pub machs: Vec<f64>,
    pub fins: Vec<FinTransfer>,
}

/// Points and the transfer of one fin at one regime.
fn transfer_for(
    lattice: &Lattice,
    s: &FinStructure,
    n: usize,
    k: &[f64],
    eval: &[[f64; 2]],
    force: &[[f64; 2]],
    scale: f64,
    fin: usize,
) -> Result<Vec<f64>, FinPanelError> {
    let np = lattice.len();
    let nn = s.nodes.len();
    let spline = |pts: &[[f64; 2]]| {
        surface_spline(&s.nodes, pts, scale).map_err(|error| FinPanelError::Spline { fin, error })
    };
    let (gc, gx) = spline(eval)?;
    let (gf, _) = spline(force)?;
    // Z = G N (points x n).
    let project = |g: &[f64]| -> Vec<f64> {
        let mut z = vec![0.0; np * n];
        for p in 0..np {
            for kk in 0..nn {
                let w = g[p * nn + kk];
                if w != 0.0 {
                    for j in 0..n {
                        z[p * n + j] += w * s.normal_rows[kk * n + j];
                    }
                }
            }
        }
        z
    };
    let (zc, zx, zf) = (project(&gc), project(&gx), project(&gf));
    let cols = 2 * n + 3;
    let rows = n + 3;
    // I (np x cols).
    let mut input = vec![0.0; np * cols];
    for p in 0..np {
        for j in 0..n {
            input[p * cols + j] = -zx[p * n + j];
            input[p * cols + n + j] = -zc[p * n + j];
        }
        input[p * cols + 2 * n] = 1.0;
        input[p * cols + 2 * n + 1] = eval[p][0];
        input[p * cols + 2 * n + 2] = eval[p][1];
    }
    // K I (np x cols).
    let mut ki = vec![0.0; np * cols];
    for p in 0..np {
        for r in 0..np {
            let kv = k[p * np + r];
            if kv != 0.0 {
                for c in 0..cols {
                    ki[p * cols + c] += kv * input[r * cols + c];
                }
            }
        }
    }
    // O K I.
    let mut t = vec![0.0; rows * cols];
    for p in 0..np {
        let mut o = Vec::with_capacity(rows);
        o.extend_from_slice(&zf[p * n..(p + 1) * n]);
        o.extend_from_slice(&[1.0, force[p][1], force[p][0]]);
        for (r, ov) in o.iter().enumerate() {
            for c in 0..cols {
                t[r * cols + c] += ov * ki[p * cols + c];
            }
        }
    }
    Ok(t)
}

/// Builds the panel model of every fin of `c` (checked vehicle `v`) on the Mach grid `machs`.
pub fn compile(
    c: &CompiledVehicle,
    v: &ir::Vehicle,
    machs: &[f64],
    settings: PanelSettings,
) -> Result<PanelModel, FinPanelError> {
    let f = v.fins.as_ref().ok_or(FinPanelError::NoFins)?;
    let n = c.modes.len();
    let mut fins = Vec::with_capacity(f.angles.len());
    for fin in 0..f.angles.len() {
        let s = fin_structure(c, v, fin)?;
        let pf = planform(f, 0.0);
        let perr = |error| FinPanelError::Panel { fin, error };
        let lattice = Lattice::new(&pf, settings.chordwise, settings.spanwise, settings.spacing)
            .map_err(perr)?;
        let controls: Vec<[f64; 2]> = lattice.panels.iter().map(|p| p.control).collect();
        let bounds: Vec<[f64; 2]> = lattice.panels.iter().map(|p| p.bound_mid()).collect();
        let centroids: Vec<[f64; 2]> = lattice.panels.iter().map(|p| p.centroid).collect();
        let scale = pf.root_chord;
        let sub = |mach: f64| -> Result<Vec<f64>, FinPanelError> {
            let k = vlm::force_map(&lattice, mach).map_err(perr)?;
            transfer_for(&lattice, &s, n, &k, &controls, &bounds, scale, fin)
        };
        let sup = |mach: f64| -> Result<Vec<f64>, FinPanelError> {
            let k = piston::force_map(&lattice, mach, settings.correction).map_err(perr)?;
            transfer_for(&lattice, &s, n, &k, &centroids, &centroids, scale, fin)
        };
        let mut t = Vec::new();
        let mut bridge: Option<(Vec<f64>, Vec<f64>)> = None;
        for &mach in machs {
            match regime(mach).map_err(perr)? {
                Regime::Subsonic => t.extend(sub(mach)?),
                Regime::Supersonic => t.extend(sup(mach)?),
                Regime::Transonic { t: w } => {
                    if bridge.is_none() {
                        bridge = Some((sub(super::SUBSONIC_LIMIT)?, sup(super::SUPERSONIC_LIMIT)?));
                    }
                    let (lo, hi) = bridge.as_ref().expect("set above");
                    t.extend(lo.iter().zip(hi).map(|(a, b)| (1.0 - w) * a + w * b));
                }
            }
        }
        fins.push(FinTransfer { n, t });
    }
    Ok(PanelModel {
        settings,
        machs: machs.to_vec(),
        fins,
    })
}
