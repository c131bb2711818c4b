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
//! 4. The method per Mach is [`super::steady_method`] (issue 33): the vortex lattice to 0.9;
//!    from 1.1 the steady supersonic constant-pressure panels ([`super::supersonic`]: normalwash
//!    at their collocation points, forces at the centroids), valid for subsonic leading edges,
//!    or piston theory where its criterion holds (`M >= 2.5` and a supersonic leading edge);
//!    between 0.9 and 1.1 the transfer matrix is the linear blend in Mach of those at 0.9
//!    (vortex lattice) and 1.1 (supersonic panels), the transonic bridge.

use super::piston::{self, Correction};
use super::spline::{SplineError, surface_spline};
use super::{Lattice, PanelError, Spacing, SteadyMethod, steady_method, supersonic, vlm};
use crate::aero::estimator::planform;
use crate::check::ir;
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
    #[error("the vehicle has no unnamed `fins` block (its flexible set)")]
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
    // The mesh generator's fin frame.
    let (es, normal) = fin_axes(f, angle.value);
    let members: Vec<usize> = (0..c.node_components.len())
        .filter(|&k| usize::try_from(c.node_components[k]).ok() == Some(fin))
        .collect();
    if members.is_empty() {
        return Err(FinPanelError::EmptyFin(fin));
    }
    let dot = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let y_root = fin_y_root(c, v, fin, &es);
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
                let (x_le, c_eta) = if f.outline.is_trapezoidal() {
                    (
                        eta * f.span.value * f.leading_edge_sweep.value.tan(),
                        f.root_chord.value + (f.tip_chord.value - f.root_chord.value) * eta,
                    )
                } else {
                    (f.edges().le(p[1]), f.edges().chord(p[1]))
                };
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

/// The Mach-independent part of one fin at one regime: the input map `I` (`np x cols`) and
/// the output map `O` (`rows x np`) of the module doc.
struct Projection {
    input: Vec<f64>,
    output: Vec<f64>,
}

impl Projection {
    fn new(
        s: &FinStructure,
        n: usize,
        eval: &[[f64; 2]],
        force: &[[f64; 2]],
        scale: f64,
        fin: usize,
    ) -> Result<Projection, FinPanelError> {
        let np = eval.len();
        let nn = s.nodes.len();
        let spline = |pts: &[[f64; 2]]| {
            surface_spline(&s.nodes, pts, scale)
                .map_err(|error| FinPanelError::Spline { fin, error })
        };
        let (gc, gx) = spline(eval)?;
        let (gf, _) = spline(force)?;
        // Z = G N (points x n).
        let project = |g: &[f64]| -> Vec<f64> {
            let mut z = vec![0.0; np * n];
            for p in 0..np {
                for kk in 0..nn {
                    let w = g[p * nn + kk];
                    for j in 0..n {
                        z[p * n + j] += w * s.normal_rows[kk * n + j];
                    }
                }
            }
            z
        };
        let (zc, zx, zf) = (project(&gc), project(&gx), project(&gf));
        let (rows, cols) = (n + 3, 2 * n + 3);
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
        let mut output = vec![0.0; rows * np];
        for p in 0..np {
            for j in 0..n {
                output[j * np + p] = zf[p * n + j];
            }
            output[n * np + p] = 1.0;
            output[(n + 1) * np + p] = force[p][1];
            output[(n + 2) * np + p] = force[p][0];
        }
        Ok(Projection { input, output })
    }

    /// `T = O K I` for the force map `k` (`np x np`).
    fn transfer(&self, k: &[f64], n: usize) -> Vec<f64> {
        let (rows, cols) = (n + 3, 2 * n + 3);
        let np = self.input.len() / cols;
        let mut ki = vec![0.0; np * cols];
        for p in 0..np {
            for r in 0..np {
                let kv = k[p * np + r];
                if kv != 0.0 {
                    for c in 0..cols {
                        ki[p * cols + c] += kv * self.input[r * cols + c];
                    }
                }
            }
        }
        let mut t = vec![0.0; rows * cols];
        for r in 0..rows {
            for p in 0..np {
                let o = self.output[r * np + p];
                if o != 0.0 {
                    for c in 0..cols {
                        t[r * cols + c] += o * ki[p * cols + c];
                    }
                }
            }
        }
        t
    }
}

/// Builds the panel model of every fin of `c` (checked vehicle `v`) on the Mach grid `machs`.
/// Every fin has the declared planform, so the force maps are computed once per Mach and
/// shared; the splines are computed once per fin and regime.
pub fn compile(
    c: &CompiledVehicle,
    v: &ir::Vehicle,
    machs: &[f64],
    settings: PanelSettings,
) -> Result<PanelModel, FinPanelError> {
    let f = v.fins.as_ref().ok_or(FinPanelError::NoFins)?;
    let n = c.modes.len();
    let pf = planform(f, 0.0);
    let perr = |error| FinPanelError::Panel { fin: 0, error };
    let lattice =
        Lattice::new(&pf, settings.chordwise, settings.spanwise, settings.spacing).map_err(perr)?;
    let controls: Vec<[f64; 2]> = lattice.panels.iter().map(|p| p.control).collect();
    let bounds: Vec<[f64; 2]> = lattice.panels.iter().map(|p| p.bound_mid()).collect();
    let centroids: Vec<[f64; 2]> = lattice.panels.iter().map(|p| p.centroid).collect();
    let methods: Vec<SteadyMethod> = machs
        .iter()
        .map(|&m| steady_method(&pf, m))
        .collect::<Result<_, _>>()
        .map_err(perr)?;
    let collocation: Vec<[f64; 2]> = lattice
        .panels
        .iter()
        .map(|p| supersonic::collocation_point(&p.corners))
        .collect();
    // Every method's projection and the two bridge maps are always built (cheap next to the
    // per-Mach maps), so no branch below can miss one.
    let mut projections = Vec::with_capacity(f.angles.len());
    for fin in 0..f.angles.len() {
        let s = fin_structure(c, v, fin)?;
        let scale = pf.root_chord;
        let sub = Projection::new(&s, n, &controls, &bounds, scale, fin)?;
        let sup = Projection::new(&s, n, &centroids, &centroids, scale, fin)?;
        let pan = Projection::new(&s, n, &collocation, &centroids, scale, fin)?;
        projections.push((sub, sup, pan));
    }
    let mut fins: Vec<FinTransfer> = (0..f.angles.len())
        .map(|_| FinTransfer { n, t: Vec::new() })
        .collect();
    let klo = vlm::force_map(&lattice, super::SUBSONIC_LIMIT).map_err(perr)?;
    let khi = supersonic::force_map(&lattice, super::machbox::MIN_MACH).map_err(perr)?;
    for (&mach, r) in machs.iter().zip(&methods) {
        match r {
            SteadyMethod::VortexLattice => {
                let k = vlm::force_map(&lattice, mach).map_err(perr)?;
                for (out, (sub, _, _)) in fins.iter_mut().zip(&projections) {
                    out.t.extend(sub.transfer(&k, n));
                }
            }
            SteadyMethod::Piston => {
                let k = piston::force_map(&lattice, mach, settings.correction).map_err(perr)?;
                for (out, (_, sup, _)) in fins.iter_mut().zip(&projections) {
                    out.t.extend(sup.transfer(&k, n));
                }
            }
            SteadyMethod::SupersonicPanels => {
                let k = supersonic::force_map(&lattice, mach).map_err(perr)?;
                for (out, (_, _, pan)) in fins.iter_mut().zip(&projections) {
                    out.t.extend(pan.transfer(&k, n));
                }
            }
            SteadyMethod::Bridge { t: w } => {
                for (out, (sub, _, pan)) in fins.iter_mut().zip(&projections) {
                    let lo = sub.transfer(&klo, n);
                    let hi = pan.transfer(&khi, n);
                    out.t
                        .extend(lo.iter().zip(&hi).map(|(a, b)| (1.0 - w) * a + w * b));
                }
            }
        }
    }
    Ok(PanelModel {
        settings,
        machs: machs.to_vec(),
        fins,
    })
}

impl PanelModel {
    /// Human summary for `flexflight plan`: per grid Mach, fin 0's rigid normal-force slope
    /// on its own area, centre of pressure and spanwise load centre (from the uniform-incidence
    /// column), and the diagonal aerodynamic stiffness `T_jj` (`Q/q` per unit `η`, m²) and
    /// damping `T_j,n+j` (`Q V/q` per unit `η̇`, m²) of the fin's own modes.
    pub fn summary_text(&self, c: &CompiledVehicle, fin_area: f64) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        let st = &self.settings;
        let _ = writeln!(
            s,
            "fin panels: {} x {} {:?} lattice per fin; vortex lattice (Prandtl-Glauert) M <= {}, steady supersonic panels M >= {} (piston theory, {:?}, where M >= {} with a supersonic leading edge), linear blend between",
            st.chordwise,
            st.spanwise,
            st.spacing,
            super::SUBSONIC_LIMIT,
            super::machbox::MIN_MACH,
            st.correction,
            super::machbox::PISTON_MIN_MACH
        );
        let Some(t) = self.fins.first() else {
            return s;
        };
        let n = t.n;
        let cols = t.cols();
        let own: Vec<usize> = (0..n).filter(|&j| c.modes[j].fin == 0).collect();
        let _ = write!(s, "  fin 0:   Mach  C_Na/rad  x_cp/m  y_cp/m");
        for &j in &own {
            let _ = write!(s, "  K[{0}] m^2  C[{0}] m^2", c.modes[j].name);
        }
        s.push('\n');
        for (g, mach) in self.machs.iter().enumerate() {
            let m = t.at(g);
            let f = m[n * cols + 2 * n];
            let _ = write!(
                s,
                "         {:6.3}  {:8.4}  {:6.4}  {:6.4}",
                mach,
                f / fin_area,
                m[(n + 2) * cols + 2 * n] / f,
                m[(n + 1) * cols + 2 * n] / f
            );
            for &j in &own {
                let _ = write!(
                    s,
                    "  {:+.3e}  {:+.3e}",
                    m[j * cols + j],
                    m[j * cols + n + j]
                );
            }
            s.push('\n');
        }
        s
    }
}

impl PanelModel {
    /// Grid interval and weight of `mach` (clamped to the grid ends; the grid ascends).
    /// None for a non-finite Mach or an empty grid.
    pub fn bracket(&self, mach: f64) -> Option<(usize, f64)> {
        let m = &self.machs;
        if !mach.is_finite() || m.is_empty() {
            return None;
        }
        if m.len() == 1 || mach <= m[0] {
            return Some((0, 0.0));
        }
        let last = m.len() - 1;
        if mach >= m[last] {
            return Some((last, 0.0));
        }
        let g = m.partition_point(|&x| x <= mach) - 1;
        Some((g, (mach - m[g]) / (m[g + 1] - m[g])))
    }

    /// The outputs `y = q T(M) u` of fin `fin` (module doc) for the inputs
    /// `u = [η; η̇ / V; a_0; a_x; a_y]`, with `T` interpolated linearly in Mach between grid
    /// points: `y = q ((1 - t) T_g u + t T_g+1 u)`. No allocation (the right-hand side's
    /// building block); false for an unknown fin, a bad Mach or wrongly sized slices.
    pub fn apply(&self, fin: usize, mach: f64, q: f64, u: &[f64], y: &mut [f64]) -> bool {
        let Some(t) = self.fins.get(fin) else {
            return false;
        };
        let (rows, cols) = (t.rows(), t.cols());
        if u.len() != cols || y.len() != rows {
            return false;
        }
        let Some((g, w)) = self.bracket(mach) else {
            return false;
        };
        let lo = t.at(g);
        let hi = if w > 0.0 { t.at(g + 1) } else { lo };
        for (r, out) in y.iter_mut().enumerate() {
            let (mut a, mut b) = (0.0, 0.0);
            for c in 0..cols {
                a += lo[r * cols + c] * u[c];
                b += hi[r * cols + c] * u[c];
            }
            *out = q * ((1.0 - w) * a + w * b);
        }
        true
    }
}

/// The body node (component tag < 0) nearest to the body point `p`; None without body nodes.
pub fn nearest_body_node(c: &CompiledVehicle, p: &[f64; 3]) -> Option<usize> {
    (0..c.node_positions.len())
        .filter(|&k| c.node_components[k] < 0)
        .min_by(|&a, &b| {
            let d = |k: usize| {
                let r = c.node_positions[k];
                (0..3).map(|e| (r[e] - p[e]).powi(2)).sum::<f64>()
            };
            d(a).total_cmp(&d(b))
        })
}

/// The body node that carries fin `fin`'s root as a rigid base (issue 38, item 3): the body
/// node nearest to the root chord's mid-point on the body surface (`x_LE,root - c_r / 2`, at
/// the root radius `y_root` along the span direction). None without fins or body nodes.
pub fn root_body_node(c: &CompiledVehicle, v: &ir::Vehicle, fin: usize) -> Option<usize> {
    let f = v.fins.as_ref()?;
    let angle = f.angles.get(fin)?;
    let (es, _) = fin_axes(f, angle.value);
    let y_root = fin_y_root(c, v, fin, &es);
    if !y_root.is_finite() {
        return None;
    }
    let x = f.root_trailing_edge_x.value + 0.5 * f.root_chord.value;
    nearest_body_node(c, &[x, y_root * es[1], y_root * es[2]])
}

/// The normal displacement, in the panel's `+z` over the fin plane, of the rigid motion of
/// body node `node` per unit modal coordinate: `z_k(x, y) = c0_k + c1_k x + c2_k y` in fin
/// coordinates (module doc, step 1), returned as `[c0_k, c1_k, c2_k]` per mode (issue 38,
/// item 3).
///
/// A point at fin coordinates `(x, y)` has the body position `p = (x_LE,root - x) e_x + (y_root
/// + y) e_s` (exact without cant, as [`fin_structure`]); attached rigidly to the node it moves
/// by `u = S_u,m η + (S_θ,m η) × (p - r_m)`, linear in `p` and so in `(x, y)`, and its panel
/// normal displacement is `z = -n · u`. The three coefficients are therefore exact from the
/// values at `(0, 0)`, `(1, 0)` and `(0, 1)`.
pub fn rigid_normal_of_node(
    c: &CompiledVehicle,
    v: &ir::Vehicle,
    fin: usize,
    node: usize,
) -> Result<Vec<[f64; 3]>, FinPanelError> {
    let f = v.fins.as_ref().ok_or(FinPanelError::NoFins)?;
    let angle = f.angles.get(fin).ok_or(FinPanelError::EmptyFin(fin))?;
    let (es, normal) = fin_axes(f, angle.value);
    let n = c.modes.len();
    if node >= c.node_positions.len() || c.shapes.len() < 6 * (node + 1) * n {
        return Err(FinPanelError::EmptyFin(fin));
    }
    let y_root = fin_y_root(c, v, fin, &es);
    let root_le_x = f.root_trailing_edge_x.value + f.root_chord.value;
    let z = |x: f64, y: f64| -> Vec<f64> {
        let p = [root_le_x - x, (y_root + y) * es[1], (y_root + y) * es[2]];
        let rows = rows_attached(c, node, &p);
        (0..n)
            .map(|j| -(0..3).map(|d| normal[d] * rows[d * n + j]).sum::<f64>())
            .collect()
    };
    let (z00, z10, z01) = (z(0.0, 0.0), z(1.0, 0.0), z(0.0, 1.0));
    Ok((0..n)
        .map(|j| [z00[j], z10[j] - z00[j], z01[j] - z00[j]])
        .collect())
}

/// The span coordinate of fin `fin`'s root: the body radius for a generated structure, the
/// innermost fin node's `r · e_s` for an imported one (infinite without fin nodes).
fn fin_y_root(c: &CompiledVehicle, v: &ir::Vehicle, fin: usize, es: &[f64; 3]) -> f64 {
    match &v.structure {
        ir::Structure::Generate(g) => g.body.root_radius(v.fins.as_ref()),
        ir::Structure::Files(_) => (0..c.node_components.len())
            .filter(|&k| usize::try_from(c.node_components[k]).ok() == Some(fin))
            .map(|k| {
                let r = c.node_positions[k];
                r[0] * es[0] + r[1] * es[1] + r[2] * es[2]
            })
            .fold(f64::INFINITY, f64::min),
    }
}

/// The span direction `e_s` and the mesh normal `n` of a fin at angular position `delta`
/// (`structure::generate::mesh::fin_frame`): `e_s = (0, cos δ, sin δ)`, the canted chord
/// `e_a = cos γ x̂ + sin γ (x̂ × e_s)`, `n = e_a × e_s`.
fn fin_axes(f: &ir::Fins, delta: f64) -> ([f64; 3], [f64; 3]) {
    let (sd, cd) = delta.sin_cos();
    let (sg, cg) = f.cant.value.sin_cos();
    let es = [0.0, cd, sd];
    let ea = [cg, -sg * sd, sg * cd];
    let normal = [
        ea[1] * es[2] - ea[2] * es[1],
        ea[2] * es[0] - ea[0] * es[2],
        ea[0] * es[1] - ea[1] * es[0],
    ];
    (es, normal)
}

/// Translation rows (3 x n, row-major) of a point `p` rigidly attached to body node `m`:
/// `S_u,m - o^× S_θ,m` with `o = p - r_m`.
fn rows_attached(c: &CompiledVehicle, m: usize, p: &[f64; 3]) -> Vec<f64> {
    let n = c.modes.len();
    let r = c.node_positions[m];
    let o = [p[0] - r[0], p[1] - r[1], p[2] - r[2]];
    let skew = [[0.0, -o[2], o[1]], [o[2], 0.0, -o[0]], [-o[1], o[0], 0.0]];
    let s = |d: usize, j: usize| c.shapes[(6 * m + d) * n + j];
    let mut rows = vec![0.0; 3 * n];
    for d in 0..3 {
        for j in 0..n {
            rows[d * n + j] = s(d, j) - (0..3).map(|e| skew[d][e] * s(3 + e, j)).sum::<f64>();
        }
    }
    rows
}

/// Translation rows (3 x n, row-major) of a point `p` rigidly attached to the body node
/// nearest to it: `S_u,m - o^× S_θ,m` with `o = p - r_m`.
pub fn rigid_rows(c: &CompiledVehicle, p: &[f64; 3]) -> Option<(Vec<f64>, Vec<f64>)> {
    let n = c.modes.len();
    let m = nearest_body_node(c, p)?;
    // A rigid attachment rotates with the body node.
    Some((
        rows_attached(c, m, p),
        c.shapes[(6 * m + 3) * n..(6 * m + 6) * n].to_vec(),
    ))
}
