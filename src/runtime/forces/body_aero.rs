//! Fuselage-alone aerodynamics through the body key node (thesis 5.3, eqs. (5.3.1)-(5.3.33)).
//!
//! # Algorithm (the summary list at the end of 5.3.2)
//! 1. Key-node deformation from the selected shapes: `u_bn = S_u η`, `θ_bn = S_θ η` and their
//!    rates (`S_u`, `S_θ` the translation and rotation rows of the key node). Nodal frame
//!    `C_bn,B = 1 - θ_bn^×` (5.3.10)-(5.3.11).
//! 2. Velocity of the key node relative to the air, body axes (5.3.12)-(5.3.13):
//!    `V_b = V_B + ω_B × (r_bn + u_bn) + u̇_bn - V_w`, with `V_w = w_B + C_BI w_I` (the
//!    body-frame and the inertial-frame parts of [`Stimuli::wind`]). We use the deformed
//!    position `r_bn + u_bn`: it is the velocity of the material point the loads act on.
//!    In the nodal frame: `V_bn = C_bn,B V_b`.
//! 3. Aerodynamic frame ba (5.3.15)-(5.3.18): `x_ba = x_bn`, `y_ba = (V × x_bn)/|V × x_bn|`,
//!    `z_ba = x_ba × y_ba`. With `V_bn = (V_x, V_y, V_z)` and `r = sqrt(V_y² + V_z²)` this is
//!    `y_ba = (0, V_z, -V_y)/r`, `z_ba = (0, V_y, V_z)/r`: the ba frame is rolled into the plane
//!    of the total angle of attack, so `β_b = 0` (5.3.21) and
//!    `α_b = atan2(r, V_x)` (the exact form of (5.3.19); (5.3.20) is its small-angle limit),
//!    always >= 0. At `r = 0` (no crossflow) the ba frame is taken equal to bn.
//! 4. Rates (5.3.22)-(5.3.25), used only with `rate_terms`:
//!    `α̇_b = (ż_baᵀ V - z_baᵀ(ω_B × V))/|V|`, `β̇_b = (ẏ_baᵀ V - y_baᵀ(ω_B × V))/|V|`, with
//!    the ba axes turning with the key node's elastic rotation, `ż_ba = θ̇ × z_ba`,
//!    `ẏ_ba = θ̇ × y_ba`; so `α̇_b = -z_baᵀ((ω_B + θ̇) × V)/|V|` and
//!    `β̇_b = -y_baᵀ((ω_B + θ̇) × V)/|V|` (ω_bn of (5.3.14)). For the unrolled frame
//!    `z_ba = e3`, `y_ba = e2` this is the thesis' `ż_ba = (θ̇_y, -θ̇_x, 0)`, `ẏ_ba = (-θ̇_z, 0,
//!    θ̇_x)` (5.3.23), (5.3.25); the thesis takes those columns of `θ̇^×` for any roll of the
//!    ba frame, which is right only at zero roll. Closed forms of the state, no finite
//!    differences and no stored history. This α̇ is the rate of the flow direction in the
//!    rotating key-node frame: in a pure pitch rotation `α̇_b = q`, whatever the flight path
//!    does, so the derivatives it multiplies are the sums C_Nq + C_Nα̇ and C_mq + C_mα̇.
//! 5. Coefficients at (Mach, α_b in degrees, altitude `-z`), Mach from the 1976 speed of sound.
//!    The rate derivatives `cn_q` = C_Nq + C_Nα̇ and `cm_q` = C_mq + C_mα̇ (per rad of
//!    `ω b/(2V)`, about the reference point) are the optional rate columns of the body table
//!    ([`crate::aero::tables`], written by the built-in estimator); with
//!    `rate_terms` and a table without them the block cannot be built
//!    ([`AeroForceError::NoRateColumns`]).
//! 6. Loads in the coefficient frame co, `C_co,ba = diag(-1, -1, 1)` (5.3.27), at the
//!    reference point: x_co points aft, so the axial force is `+C_A q S` along x_co; the normal
//!    force opposes the crossflow, `-C_N q S` along z_co = z_ba (5.3.1)-(5.3.2); the pitching
//!    moment `C_M q S b` is positive nose up, i.e. about +y_ba = -y_co (5.3.3):
//!    `F_co = q S (C_A, 0, -C_N)`, `M_co = q S b (0, -C_M, 0)`; then `F_ba = C_co,baᵀ F_co`,
//!    `M_ba = C_co,baᵀ M_co` (5.3.28). The rate loads, in ba axes at the reference point:
//!    `F_rate = -q S k cn_q (0, β̇_b, α̇_b)`, `M_rate = q S b k cm_q (0, α̇_b, -β̇_b)`,
//!    `k = b/(2V)`. The thesis writes `C_N = C_Nα α + C_Nα̇ (α̇ + β̇)` (5.3.8) with the symmetry
//!    `C_Nα̇ = C_Nβ̇`, which would put the out-of-plane rate β̇ into the in-plane normal force;
//!    for a body of revolution the response to β̇ (a rate of the flow across the α plane,
//!    along y_ba) is the response to α̇ turned by 90 deg about x: a side force along `-y_ba`
//!    and a moment about `-z_ba` (the rotation taking z_ba to y_ba takes y_ba to -z_ba). So
//!    the rate loads are `-q S k cn_q ρ_⊥` and `-q S b k cm_q (e1 × ρ_⊥)` with
//!    `ρ_⊥ = α̇_b z_ba + β̇_b y_ba`, the flow-direction rate across the body axis: independent
//!    of how the ba frame is rolled (continuous through α_b = 0, where the frame flips), and
//!    for a body rate `(p, q, r)` at `V = (V, 0, 0)` exactly `cn_q (0, r, -q)` in force and
//!    `cm_q (0, q, r)` in moment, the standard pitch and yaw damping. With the table's roll
//!    columns (the further, rigid fin sets' cant and roll damping, `aero::tables`), a roll
//!    moment about `x_ba = x_bn`: `q S b (cl_0 + cl_p p b/(2V))`, `p` the body's roll rate
//!    at the key node (rigid plus the key node's elastic rotation rate); applied whenever
//!    the table has the columns (the damping belongs with the forcing), `rate_terms` or not.
//! 7. Back to the nodal and body frames (5.3.30)-(5.3.32): `F_bn = C_ba,bnᵀ F_ba`,
//!    `F_B = C_bn,Bᵀ F_bn = F_bn + θ_bn × F_bn` (and the same for the moment).
//! 8. Transfer from the reference point to the key node (5.3.29): the reference point moves
//!    with the key node (the ba frame is attached to it), so with the constant lever arm
//!    `d = r_ref - r_bn` (undeformed) the moment about the key node is `M_bn = M + d × F`
//!    (body axes; the thesis mixes frames here, which only differs at second order in θ).
//!    About the body origin (5.3.33): `G_B = M_bn + (r_bn + u_bn) × F_B`.
//! 9. Modal forces by virtual work of a force and a moment at the key node (5.3.x, as
//!    (5.4.21)): `Q = S_uᵀ F_B + S_θᵀ M_bn`.
//!
//! Table lookups never allocate: the query is clamped to the table axes here before the
//! lookup; with the `stop` policy an out-of-range query is recorded as an [`AeroFault`] (read
//! it with [`BodyAero::fault`]) and the clamped value is used for this evaluation, so the run
//! driver can stop the run at the end of the step.

use crate::aero::FinLoadError;
use crate::aero::atmosphere::{AirMemo, Standard1976};
use crate::aero::estimator::{
    BodyShape, EstimatedTables, FinPlanform, FinProfile, NoseShape, planform,
};
use crate::aero::tables::{Axis, CoefficientTable, TableError, TableHint};
use crate::check::ir::{self, AeroSource, OutOfRange, Structure};
use crate::runtime::eom::{ForceModel, StateView};
use crate::runtime::kinematics::{cross, dot, mat_vec};
use crate::runtime::stimuli::Stimuli;
use crate::structure::compile::CompiledVehicle;

/// Why an aerodynamic force block could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AeroForceError {
    #[error("coefficient table: {0}")]
    Table(#[from] TableError),
    #[error("fin load distribution: {0}")]
    FinLoad(#[from] FinLoadError),
    #[error(
        "the built-in aerodynamic estimator needs the generated body geometry (diameter, length, nose); give `aero {{ source = tables ... }}` for an imported FE model"
    )]
    NoBodyGeometry,
    #[error(
        "`body_aero {{ rate_terms = true }}` needs the rate derivatives, but the body table {} has no `cn_q,cm_q` columns (add them, or set `rate_terms = false`)",
        path.display()
    )]
    NoRateColumns { path: std::path::PathBuf },
    #[error("vehicle `{vehicle}` has fin aerodynamics but no `fins` block")]
    NoFins { vehicle: String },
    #[error("Missile DATCOM output {}: {message}", path.display())]
    Datcom {
        path: std::path::PathBuf,
        message: String,
    },
    #[error("{what} node index {index} is outside the compiled model ({n_nodes} nodes)")]
    BadNode {
        what: &'static str,
        index: usize,
        n_nodes: usize,
    },
    #[error(
        "compiled shapes hold {found} values, expected {expected} (6 x {n_nodes} nodes x {n_modes} modes)"
    )]
    ShapeSize {
        found: usize,
        expected: usize,
        n_nodes: usize,
        n_modes: usize,
    },
    #[error(
        "the compiled vehicle has {key_nodes} fin key nodes, the `fins` block has {declared} fins"
    )]
    FinCount { key_nodes: usize, declared: usize },
    #[error("fin panel model: {0}")]
    FinPanels(#[from] crate::aero::panel::fin_model::FinPanelError),
    #[error("cached aerodynamics: {0}")]
    Cached(String),
    #[error("fin {fin} has no nodes in the compiled model")]
    EmptyFin { fin: usize },
    #[error(
        "fin {fin}, node {node}: at span fraction {eta} and chord fraction {xi}, outside the declared planform"
    )]
    NodeOffPlanform {
        fin: usize,
        node: usize,
        eta: f64,
        xi: f64,
    },
}

/// A condition met during a right-hand-side evaluation that the run driver must act on
/// (recorded without allocating; the first one is kept).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AeroFault {
    /// A coefficient table with the `stop` policy was queried outside its range.
    TableOutOfRange { axis: Axis, value: f64 },
    /// The altitude left the atmosphere model's range.
    Atmosphere { altitude_m: f64 },
    /// A non-finite state reached the aerodynamics.
    NonFinite,
}

/// The body and fin coefficient tables of a vehicle: the CSV files of `aero { source =
/// tables }`, or the built-in estimator (5.5) on the generated geometry.
pub fn aero_tables(v: &ir::Vehicle) -> Result<EstimatedTables, AeroForceError> {
    match &v.aero.source {
        AeroSource::Tables {
            body,
            fins,
            out_of_range,
        } => Ok(EstimatedTables {
            body: CoefficientTable::read_csv(
                crate::aero::TableKind::Body,
                &body.value,
                out_of_range.value,
            )?,
            fin: CoefficientTable::read_csv(
                crate::aero::TableKind::Fin,
                &fins.value,
                out_of_range.value,
            )?,
        }),
        AeroSource::Datcom {
            file,
            case,
            fin_set,
            out_of_range,
        } => {
            use crate::aero::datcom;
            let path = file.value.clone();
            let err = |message: String| AeroForceError::Datcom {
                path: path.clone(),
                message,
            };
            let text = std::fs::read_to_string(&path).map_err(|e| err(e.to_string()))?;
            let parsed = datcom::parse(&text).map_err(|e| err(e.to_string()))?;
            let vref = datcom::VehicleReference {
                area: v.aero.reference_area.value,
                length: v.aero.reference_length.value,
                point_x: v.aero.reference_point.value[0],
                fins: v.fins.as_ref().map(|f| {
                    (
                        f.count.value,
                        f.root_trailing_edge_x.value + f.root_chord.value,
                    )
                }),
            };
            let sel = datcom::Selection {
                case: *case,
                fin_set: *fin_set,
            };
            let t = datcom::tables(&parsed, &path, sel, &vref, out_of_range.value)
                .map_err(|e| err(e.to_string()))?;
            Ok(EstimatedTables {
                body: t.body,
                fin: t.fin,
            })
        }
        AeroSource::Builtin {
            out_of_range,
            roughness,
        } => {
            let Structure::Generate(g) = &v.structure else {
                return Err(AeroForceError::NoBodyGeometry);
            };
            let b = &g.body;
            let body = BodyShape {
                length: b.length.value,
                diameter: b.diameter.value,
                nose: if b.nose_length.value > 0.0 && b.nose_shape.value.is_conical() {
                    NoseShape::Cone {
                        length: b.nose_length.value,
                    }
                } else if b.nose_length.value > 0.0 {
                    NoseShape::Profile {
                        length: b.nose_length.value,
                        shape: b.nose_shape.value,
                    }
                } else {
                    NoseShape::Tube
                },
                reference_x: v.aero.reference_point.value[0],
                transitions: b.transition_geoms(),
                roughness: roughness.value,
                guides: launch_guides(b),
                fin_sets: v
                    .fin_sets
                    .iter()
                    .map(|s| crate::aero::estimator::RigidFinSet::of(&s.fins, b))
                    .collect(),
            };
            let fin = match &v.fins {
                Some(f) => planform(f, b.radius_under(f)),
                // No fins: a placeholder planform; the fin table is then never used.
                None => FinPlanform::unswept_trailing_edge(0.1, 0.1, 0.1, 0.5 * b.diameter.value),
            };
            let profile = v.fins.as_ref().map(|f| FinProfile {
                thickness: f.thickness.value,
                section: f.cross_section.value,
            });
            Ok(EstimatedTables::estimate_with_profile(
                &body,
                &fin,
                profile,
                out_of_range.value,
            )?)
        }
    }
}

/// The launch lugs and rail buttons of a generated body, for the estimator's drag.
fn launch_guides(b: &ir::BodyGeometry) -> Vec<crate::aero::estimator::LaunchGuide> {
    use crate::aero::estimator::LaunchGuide;
    let lugs = b.launch_lugs.iter().map(|l| LaunchGuide::Lug {
        length: l.length.value,
        outer_diameter: l.outer_diameter.value,
        inner_diameter: l.inner_diameter.value,
    });
    let buttons = b.rail_buttons.iter().map(|r| {
        let (inner_diameter, inner_height) = r
            .notch
            .as_ref()
            .map_or((0.0, 0.0), |(d, h)| (d.value, h.value));
        LaunchGuide::Button {
            from_tip: -r.station.value,
            outer_diameter: r.outer_diameter.value,
            height: r.height.value,
            inner_diameter,
            inner_height,
        }
    });
    lugs.chain(buttons).collect()
}

/// The six shape rows of one node (translations then rotations), copied at construction.
#[derive(Clone, Debug)]
pub(crate) struct NodeRows {
    /// Index of the node in the compiled model.
    pub index: usize,
    /// Undeformed body-frame position.
    pub position: [f64; 3],
    /// Row-major 6 x n.
    rows: Vec<f64>,
    /// The same six rows mode by mode (`cols[6 m + d] = rows[d n + m]`), for [`Self::apply`].
    cols: Vec<f64>,
    n: usize,
}

impl NodeRows {
    pub(crate) fn new(
        c: &CompiledVehicle,
        node: usize,
        what: &'static str,
    ) -> Result<Self, AeroForceError> {
        let n_nodes = c.node_positions.len();
        let n = c.modes.len();
        if c.shapes.len() != 6 * n_nodes * n {
            return Err(AeroForceError::ShapeSize {
                found: c.shapes.len(),
                expected: 6 * n_nodes * n,
                n_nodes,
                n_modes: n,
            });
        }
        if node >= n_nodes {
            return Err(AeroForceError::BadNode {
                what,
                index: node,
                n_nodes,
            });
        }
        Ok(NodeRows::from_rows(
            node,
            c.node_positions[node],
            c.shapes[6 * node * n..6 * (node + 1) * n].to_vec(),
            n,
        ))
    }

    /// From the row-major `6 x n` rows of a node.
    fn from_rows(index: usize, position: [f64; 3], rows: Vec<f64>, n: usize) -> Self {
        let cols = (0..6 * n).map(|k| rows[(k % 6) * n + k / 6]).collect();
        NodeRows {
            index,
            position,
            rows,
            cols,
            n,
        }
    }

    /// The six rows (u, v, w, θx, θy, θz), row-major 6 x n.
    pub(crate) fn rows(&self) -> &[f64] {
        &self.rows
    }

    /// `(S_u q, S_θ q)` for modal coordinates (or rates) `q`: the six sums side by side over
    /// the modes (six independent chains instead of one after another), each in the order
    /// of the modes from the start value of `f64`'s `Sum`, so the bits of the row-by-row
    /// `iter().sum()` (tested). The flight uses [`Self::apply_pair`].
    #[cfg(test)]
    pub(crate) fn apply(&self, q: &[f64]) -> ([f64; 3], [f64; 3]) {
        // As the zip of each row with `q`: the shorter of the two (`zip` below).
        let start: f64 = std::iter::empty::<f64>().sum();
        let mut out = [start; 6];
        for (col, &x) in self.cols.chunks_exact(6).zip(q) {
            for d in 0..6 {
                out[d] += col[d] * x;
            }
        }
        ([out[0], out[1], out[2]], [out[3], out[4], out[5]])
    }

    /// [`Self::apply`] of `q` and of `qd` in one pass over the columns (twelve independent
    /// chains), each sum with the bits of its own `apply`: `(S_u q, S_θ q, S_u qd, S_θ qd)`.
    #[inline]
    pub(crate) fn apply_pair(&self, q: &[f64], qd: &[f64]) -> [[f64; 3]; 4] {
        let start: f64 = std::iter::empty::<f64>().sum();
        let (mut a, mut b) = ([start; 6], [start; 6]);
        for ((col, &x), &xd) in self.cols.chunks_exact(6).zip(q).zip(qd) {
            for d in 0..6 {
                a[d] += col[d] * x;
                b[d] += col[d] * xd;
            }
        }
        [
            [a[0], a[1], a[2]],
            [a[3], a[4], a[5]],
            [b[0], b[1], b[2]],
            [b[3], b[4], b[5]],
        ]
    }

    /// The row-by-row form of [`Self::apply`], the reference of its bits.
    #[cfg(test)]
    fn apply_by_row(&self, q: &[f64]) -> ([f64; 3], [f64; 3]) {
        let mut out = [0.0; 6];
        for (d, o) in out.iter_mut().enumerate() {
            let row = &self.rows[d * self.n..(d + 1) * self.n];
            *o = row.iter().zip(q).map(|(s, x)| s * x).sum();
        }
        ([out[0], out[1], out[2]], [out[3], out[4], out[5]])
    }

    /// `Q += S_uᵀ f + S_θᵀ m`.
    pub(crate) fn add_transpose(&self, f: &[f64; 3], m: &[f64; 3], q: &mut [f64]) {
        for d in 0..6 {
            let load = if d < 3 { f[d] } else { m[d - 3] };
            if load == 0.0 {
                continue;
            }
            let row = &self.rows[d * self.n..(d + 1) * self.n];
            for (qm, s) in q.iter_mut().zip(row) {
                *qm += s * load;
            }
        }
    }
}

/// Relative air velocity of a node in body axes (5.3.12)-(5.3.13) / (5.4.8):
/// `V_B + ω_B × p + u̇ - (w_B + C_BI w_I)` with `p` the deformed node position.
pub(crate) fn relative_velocity(
    state: &StateView,
    p: &[f64; 3],
    u_dot: &[f64; 3],
    wind: &([f64; 3], [f64; 3]),
) -> [f64; 3] {
    relative_velocity_rotated(state, p, u_dot, &(wind.0, mat_vec(&state.c_bi, &wind.1)))
}

/// [`relative_velocity`] with the inertial-frame wind already in body axes (`wind.1 = C_bi
/// w_i`, computed once per evaluation by a block that needs it at several points): the same
/// operations in the same order, so the same bits.
pub(crate) fn relative_velocity_rotated(
    state: &StateView,
    p: &[f64; 3],
    u_dot: &[f64; 3],
    wind: &([f64; 3], [f64; 3]),
) -> [f64; 3] {
    let (w_b, w_i) = wind;
    let rot = cross(&state.angular_velocity, p);
    [0, 1, 2].map(|k| state.velocity[k] + rot[k] + u_dot[k] - w_b[k] - w_i[k])
}

/// Clamps `value` into a table axis; records a fault when the table's policy is `stop`.
pub(crate) fn clamp_axis(
    table: &CoefficientTable,
    axis: Axis,
    value: f64,
    fault: &mut Option<AeroFault>,
) -> f64 {
    let a = table.axis(axis);
    let (lo, hi) = (a[0], a[a.len() - 1]);
    if table.outside(axis, value) && table.policy() == OutOfRange::Stop && fault.is_none() {
        *fault = Some(AeroFault::TableOutOfRange { axis, value });
    }
    value.clamp(lo, hi)
}

/// The table query point `(Mach, alpha in degrees, altitude)`, each clamped into its axis
/// (faults recorded as in [`clamp_axis`]); shared by the body and fin blocks.
pub(crate) fn clamped_query(
    table: &CoefficientTable,
    mach: f64,
    alpha_deg: f64,
    altitude: f64,
    fault: &mut Option<AeroFault>,
) -> [f64; 3] {
    [
        clamp_axis(table, Axis::Mach, mach, fault),
        clamp_axis(table, Axis::AlphaDeg, alpha_deg, fault),
        clamp_axis(table, Axis::AltitudeM, altitude, fault),
    ]
}

/// What the last evaluation saw (for output and tests).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyAeroSample {
    /// Total angle of attack α_b, rad (>= 0).
    pub alpha: f64,
    /// α̇_b and β̇_b of (5.3.22)-(5.3.24), rad/s.
    pub alpha_dot: f64,
    pub beta_dot: f64,
    pub mach: f64,
    /// Dynamic pressure, Pa.
    pub dynamic_pressure: f64,
    /// Body-axes force and moment about the key node.
    pub force: [f64; 3],
    pub moment_key_node: [f64; 3],
}

/// The fuselage aerodynamic force block (thesis 5.3); see the module doc.
#[derive(Clone, Debug)]
pub struct BodyAero {
    key: NodeRows,
    /// `r_ref - r_bn` (undeformed), m.
    lever: [f64; 3],
    area: f64,
    length: f64,
    table: CoefficientTable,
    atmosphere: Standard1976,
    stimuli: Stimuli,
    /// `body_aero { rate_terms }`: apply the table's rate columns.
    rate_terms: bool,
    /// The table brackets of the previous evaluation, tried first.
    hint: TableHint,
    fault: Option<AeroFault>,
    last: BodyAeroSample,
}

impl BodyAero {
    /// Builds the block for the compiled vehicle `c` of the checked vehicle `v` with the body
    /// coefficient table `table` (see [`aero_tables`]). Rate terms follow
    /// `v.forces.body_aero.rate_terms`, with the derivatives of the table's rate columns
    /// (an error when it has none).
    pub fn new(
        c: &CompiledVehicle,
        v: &ir::Vehicle,
        table: CoefficientTable,
        atmosphere: Standard1976,
        stimuli: Stimuli,
    ) -> Result<Self, AeroForceError> {
        let key = NodeRows::new(c, c.key_body as usize, "body key node")?;
        let r_ref = v.aero.reference_point.value;
        let lever = [0, 1, 2].map(|k| r_ref[k] - key.position[k]);
        let rate_terms = v.forces.body_aero.as_ref().is_some_and(|b| b.rate_terms);
        if rate_terms && !table.has_rates() {
            return Err(AeroForceError::NoRateColumns {
                path: table.source().to_path_buf(),
            });
        }
        Ok(BodyAero {
            key,
            lever,
            area: v.aero.reference_area.value,
            length: v.aero.reference_length.value,
            table,
            atmosphere,
            stimuli,
            rate_terms,
            hint: TableHint::default(),
            fault: None,
            last: BodyAeroSample::default(),
        })
    }

    /// Replaces the stimuli (wind and gusts) the block sees: blocks built once for a vehicle
    /// serve every scenario of it.
    pub fn set_stimuli(&mut self, stimuli: Stimuli) {
        self.stimuli = stimuli;
    }

    /// [`Stimuli::set_left_of`] on the block's stimuli.
    pub fn set_wind_left_of(&mut self, t: Option<f64>) {
        self.stimuli.set_left_of(t);
    }

    /// The first fault met since construction (or [`Self::clear_fault`]).
    pub fn fault(&self) -> Option<AeroFault> {
        self.fault
    }

    /// True when a table lookup or the atmosphere went out of range.
    pub fn out_of_range(&self) -> bool {
        self.fault.is_some()
    }

    /// Forgets a recorded fault.
    pub fn clear_fault(&mut self) {
        self.fault = None;
    }

    /// What the last evaluation computed.
    pub fn last(&self) -> BodyAeroSample {
        self.last
    }

    /// Index of the body key node in the compiled model.
    pub fn key_node(&self) -> usize {
        self.key.index
    }

    /// Undeformed position of the body key node, m.
    pub fn key_node_position(&self) -> [f64; 3] {
        self.key.position
    }

    /// The shape rows at the body key node (u, v, w, θx, θy, θz; 6 x n, row-major).
    pub fn key_node_rows(&self) -> &[f64] {
        self.key.rows()
    }

    /// `r_ref - r_bn` (undeformed), m.
    pub fn lever(&self) -> [f64; 3] {
        self.lever
    }

    /// The body coefficient table.
    pub fn table(&self) -> &CoefficientTable {
        &self.table
    }
}

impl ForceModel for BodyAero {
    fn generalized_forces(&mut self, t: f64, state: &StateView, out: &mut [f64]) {
        self.forces_with(t, state, &mut AirMemo::default(), out);
    }
}

impl BodyAero {
    /// [`ForceModel::generalized_forces`] with the air read through `memo` (shared by the
    /// blocks of one right-hand side, [`super::ForceBlocks`]).
    pub fn forces_with(&mut self, t: f64, state: &StateView, memo: &mut AirMemo, out: &mut [f64]) {
        self.evaluate::<true>(t, state, memo, out);
    }

    /// What a run's stop check needs at an accepted state, and only that: the block's fault
    /// (non-finite airspeed, the atmosphere, a table query outside a `stop` table, a failed
    /// lookup), raised by the code of [`Self::forces_with`] up to the table lookup; no
    /// loads, and the last sample is not updated.
    pub fn check_with(&mut self, t: f64, state: &StateView, memo: &mut AirMemo) {
        self.evaluate::<false>(t, state, memo, &mut []);
    }

    /// [`Self::forces_with`] (`LOADS`) or [`Self::check_with`].
    #[inline(always)]
    fn evaluate<const LOADS: bool>(
        &mut self,
        t: f64,
        state: &StateView,
        memo: &mut AirMemo,
        out: &mut [f64],
    ) {
        let [u, theta, u_dot, theta_dot] = self.key.apply_pair(state.eta, state.eta_dot);
        let p = [0, 1, 2].map(|k| self.key.position[k] + u[k]);
        let wind = self.stimuli.wind_at(t, -state.position[2]);
        let v_b = relative_velocity(state, &p, &u_dot, &wind);
        // Nodal frame (5.3.11): C_bn,B v = v - θ × v.
        let tv = cross(&theta, &v_b);
        let v_bn = [0, 1, 2].map(|k| v_b[k] - tv[k]);
        let speed = dot(&v_bn, &v_bn).sqrt();
        let altitude = -state.position[2];
        if !(speed.is_finite() && altitude.is_finite()) {
            self.fault.get_or_insert(AeroFault::NonFinite);
            return;
        }
        if speed == 0.0 {
            if LOADS {
                self.last = BodyAeroSample::default();
            }
            return;
        }
        let Ok(air) = memo.at(&self.atmosphere, altitude) else {
            self.fault.get_or_insert(AeroFault::Atmosphere {
                altitude_m: altitude,
            });
            return;
        };
        // ba frame (5.3.15)-(5.3.18), rows expressed in bn axes.
        let r = (v_bn[1] * v_bn[1] + v_bn[2] * v_bn[2]).sqrt();
        let (y_ba, z_ba) = if r > 0.0 {
            (
                [0.0, v_bn[2] / r, -v_bn[1] / r],
                [0.0, v_bn[1] / r, v_bn[2] / r],
            )
        } else {
            ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0])
        };
        let alpha = r.atan2(v_bn[0]);
        let q = 0.5 * air.density * speed * speed;
        let mach = speed / air.speed_of_sound;
        let [m_q, a_q, h_q] = clamped_query(
            &self.table,
            mach,
            alpha.to_degrees(),
            altitude,
            &mut self.fault,
        );
        let Ok((coef, rates, roll)) = self.table.body_hinted(m_q, a_q, h_q, &mut self.hint) else {
            self.fault.get_or_insert(AeroFault::NonFinite);
            return;
        };
        if !LOADS {
            // A missing rate column is the one fault left below.
            if self.rate_terms && rates.is_none() {
                self.fault.get_or_insert(AeroFault::NonFinite);
            }
            return;
        }
        let (cn, cm) = (coef.cn, coef.cm);
        // Coefficient frame (5.3.27) and back to ba (5.3.28): F_ba = diag(-1,-1,1) F_co.
        let qs = q * self.area;
        let f_co = [coef.ca * qs, 0.0, -cn * qs];
        let m_co = [0.0, -cm * qs * self.length, 0.0];
        let mut f_ba = [-f_co[0], -f_co[1], f_co[2]];
        let mut m_ba = [-m_co[0], -m_co[1], m_co[2]];
        let (mut alpha_dot, mut beta_dot) = (0.0, 0.0);
        if self.rate_terms {
            let Some(rd) = rates else {
                self.fault.get_or_insert(AeroFault::NonFinite);
                return;
            };
            // (5.3.22)-(5.3.25) with the ba axes turning with the key node (module doc).
            let w = [0, 1, 2].map(|k| state.angular_velocity[k] + theta_dot[k]);
            let wv = cross(&w, &v_bn);
            alpha_dot = -dot(&z_ba, &wv) / speed;
            beta_dot = -dot(&y_ba, &wv) / speed;
            // Rate loads in ba axes at the reference point (module doc, step 6).
            let k = self.length / (2.0 * speed);
            let (fn_k, m_k) = (-qs * k * rd.cn_q, qs * self.length * k * rd.cm_q);
            f_ba[1] += fn_k * beta_dot;
            f_ba[2] += fn_k * alpha_dot;
            m_ba[1] += m_k * alpha_dot;
            m_ba[2] -= m_k * beta_dot;
        }
        if let Some(rl) = roll {
            // The further fin sets' roll (the table's roll columns, `aero::tables`): about
            // x_ba = e1, the body axis at the key node, with the roll rate the body's there,
            // `p_hat = p b_b/(2V)`.
            let p = state.angular_velocity[0] + theta_dot[0];
            m_ba[0] += qs * self.length * (rl.cl_0 + rl.cl_p * p * self.length / (2.0 * speed));
        }
        // ba -> bn (5.3.30)-(5.3.31): C_ba,bnᵀ x = x_ba x0 + y_ba x1 + z_ba x2 (x_ba = e1).
        let to_bn = |x: [f64; 3]| {
            [
                x[0],
                y_ba[1] * x[1] + z_ba[1] * x[2],
                y_ba[2] * x[1] + z_ba[2] * x[2],
            ]
        };
        let (f_bn, m_bn) = (to_bn(f_ba), to_bn(m_ba));
        // bn -> B (5.3.32): C_bn,Bᵀ = 1 + θ^×.
        let to_b = |x: [f64; 3]| {
            let c = cross(&theta, &x);
            [x[0] + c[0], x[1] + c[1], x[2] + c[2]]
        };
        let (f_b, m_ref_b) = (to_b(f_bn), to_b(m_bn));
        // Transfer from the reference point to the key node (5.3.29).
        let arm = cross(&self.lever, &f_b);
        let m_key = [0, 1, 2].map(|k| m_ref_b[k] + arm[k]);
        // About the body origin (5.3.33).
        let pf = cross(&p, &f_b);
        for k in 0..3 {
            out[k] += f_b[k];
            out[3 + k] += m_key[k] + pf[k];
        }
        self.key.add_transpose(&f_b, &m_key, &mut out[6..]);
        self.last = BodyAeroSample {
            alpha,
            alpha_dot,
            beta_dot,
            mach,
            dynamic_pressure: q,
            force: f_b,
            moment_key_node: m_key,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The six sums side by side (and the twelve of `apply_pair`) have the bits of the
    /// row-by-row sums, for 0 to 12 modes,
    /// with zeros of both signs among the shapes and coordinates.
    #[test]
    fn node_rows_side_by_side_have_the_bits_of_the_row_sums() {
        let mut rng = crate::testutil::XorShift64Star::new(0x0123_4567_89ab_cdef);
        let mut next = move || {
            // The low bits pick a signed zero or a decade, the high 53 the value.
            let bits = rng.next_u64();
            let u = (bits >> 11) as f64 / (1u64 << 53) as f64;
            match bits % 8 {
                0 => 0.0,
                1 => -0.0,
                _ => (u - 0.5) * 10f64.powi(((bits >> 3) % 9) as i32 - 4),
            }
        };
        let bits = |a: ([f64; 3], [f64; 3])| {
            [a.0, a.1]
                .concat()
                .iter()
                .map(|v| v.to_bits())
                .collect::<Vec<_>>()
        };
        for n in 0..=12 {
            for _ in 0..200 {
                let rows =
                    NodeRows::from_rows(0, [0.0; 3], (0..6 * n).map(|_| next()).collect(), n);
                let q: Vec<f64> = (0..n).map(|_| next()).collect();
                let qd: Vec<f64> = (0..n).map(|_| next()).collect();
                assert_eq!(bits(rows.apply(&q)), bits(rows.apply_by_row(&q)), "n {n}");
                let [u, th, ud, thd] = rows.apply_pair(&q, &qd);
                assert_eq!(bits((u, th)), bits(rows.apply_by_row(&q)), "n {n}");
                assert_eq!(bits((ud, thd)), bits(rows.apply_by_row(&qd)), "n {n}");
            }
        }
    }
}
