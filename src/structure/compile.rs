//! The structural compiler: a checked vehicle (IR) to a [`CompiledVehicle`]: build or read
//! the FE model, solve the modes, select and localise them as the vehicle file asks, adjust
//! their fixity about the origin node (3.3), and compute the reduced coefficients (ch. 2-3).
//!
//! Architecture invariant: this module is pure (no cache, no terminal); reading FE files is
//! the only IO, and every failure is a [`StructureError`] that points at the vehicle file.

use std::path::Path;

use faer::Mat;
use serde::Serialize;

use super::coefficients::{CoefficientError, ReducedModel, fix_modes_at_origin, reduce};
use super::fe_io::{self, DofOrder, FeReadError, ReadOptions};
use super::fe_model::{Component, DOF_PER_NODE, FeModel};
use super::generate::{self, GenerateError, GeneratorSpec};
use super::modal::{self, ModalError};
use super::selection::{FinLayout, ModeInfo, SelectionError, select};
use crate::check::ir::{self, FinKeyNodes, NodeRef, Structure, Vehicle};
use crate::syntax::Span;

/// Revision of the numerical pipeline (FE generation, modal analysis, mode selection and
/// reduction). It is part of the cache key: bump it whenever a change makes the same inputs
/// compile to different numbers, so that no stale artifact is served. 2: fin clusters of
/// [`crate::structure::selection::FIN_CLUSTER_TOLERANCE`]. 3: modal damping gives the free
/// vehicle's elastic modes the requested ratio (`coefficients::reduce`). 4: hard body
/// stations within 1e-3 of a division of each other are one (`generate::mesh`). 5: a nose's
/// solid-tip end within 0.3 of a division of the tip is no station, its element integrated in
/// two parts (`generate::mesh`, `generate::beam`). 6: a fin cluster is completed with its
/// roll combination (`selection::complete_fin_cluster`), and a selection unmet by the modes
/// solved is tried on more ([`compile_model`]).
pub const PIPELINE_REVISION: u32 = 6;

/// Everything later stages need from the structure, as plain archivable data.
#[derive(Clone, Debug, Serialize, rkyv::Archive, rkyv::Serialize, rkyv::Deserialize)]
pub struct CompiledVehicle {
    pub vehicle: String,
    pub reduced: ReducedModel,
    /// One entry per selected (flexible) mode, in the order of eta.
    pub modes: Vec<CompiledMode>,
    /// Frequencies (Hz) of all elastic modes computed, for reports.
    pub candidate_frequencies_hz: Vec<f64>,
    pub n_rigid: u32,
    /// Undeformed node positions, body frame, m.
    pub node_positions: Vec<[f64; 3]>,
    pub node_ids: Vec<u64>,
    /// -1 body, i >= 0 fin i.
    pub node_components: Vec<i32>,
    /// Selected shapes after fixity: row-major, `6 * n_nodes` rows by `modes.len()` columns.
    pub shapes: Vec<f64>,
    pub origin_node: u32,
    pub key_body: u32,
    /// -1 when there is no nozzle key node.
    pub key_nozzle: i64,
    pub key_fins: Vec<u32>,
    /// Centre of mass (c / m), m.
    pub centre_of_mass: [f64; 3],
    /// Inertia about the centre of mass, kg m^2.
    pub inertia_cm: [[f64; 3]; 3],
    /// With a motor: `reduced`, the mass properties and the modes are the vehicle's at
    /// ignition (the modal basis is that of the full vehicle), and this is the propellant
    /// grain's contribution at full load on the same basis (stiffness and damping zero);
    /// the vehicle with propellant fraction `f` is `reduced - (1 - f) propellant`.
    pub propellant: Option<ReducedModel>,
}

#[derive(Clone, Debug, Serialize, rkyv::Archive, rkyv::Serialize, rkyv::Deserialize)]
pub struct CompiledMode {
    pub name: String,
    /// body_bending | fin_flap | fin_twist | other
    pub class: String,
    /// Fin index (0-based) or -1.
    pub fin: i32,
    pub frequency_hz: f64,
    pub generalised_mass: f64,
    pub body_fraction: f64,
}

impl crate::artifact::ArtifactPayload for CompiledVehicle {
    const SCHEMA: &'static str = "CompiledVehicle v1: vehicle, reduced(ReducedModel v1), modes[name,class,fin,frequency_hz,generalised_mass,body_fraction], candidate_frequencies_hz, n_rigid, node_positions, node_ids, node_components, shapes(row-major), origin_node, key_body, key_nozzle, key_fins, centre_of_mass, inertia_cm, propellant(Option<ReducedModel v1>)";
}

/// Why a vehicle's structure could not be compiled.
#[derive(Debug, thiserror::Error)]
pub enum StructureError {
    #[error("{0}")]
    Read(#[from] FeReadError),
    #[error("the FE generator refused the vehicle: {error}")]
    Generate { error: GenerateError, span: Span },
    #[error("modal analysis failed: {error}")]
    Modal { error: ModalError, span: Span },
    #[error("mode selection cannot be met: {error}")]
    Selection { error: SelectionError, span: Span },
    #[error("reduced coefficients: {error}")]
    Coefficients { error: CoefficientError, span: Span },
    #[error("{message}")]
    Node { message: String, span: Span },
    #[error("{message}")]
    Damping { message: String, span: Span },
}

impl StructureError {
    pub fn code(&self) -> &'static str {
        match self {
            StructureError::Read(e) => e.code(),
            StructureError::Generate { error, .. } => error.code(),
            StructureError::Modal { error, .. } => error.code(),
            StructureError::Selection { error, .. } => error.code(),
            StructureError::Coefficients { .. } => "structure::coefficients",
            StructureError::Node { .. } => "structure::key_node",
            StructureError::Damping { .. } => "structure::damping",
        }
    }

    /// The span in the vehicle file the error belongs to (reader errors point into the FE
    /// file instead: see [`StructureError::Read`]).
    pub fn span(&self) -> Option<Span> {
        match self {
            StructureError::Read(_) => None,
            StructureError::Generate { span, .. }
            | StructureError::Modal { span, .. }
            | StructureError::Selection { span, .. }
            | StructureError::Coefficients { span, .. }
            | StructureError::Node { span, .. }
            | StructureError::Damping { span, .. } => Some(*span),
        }
    }
}

/// The generator's input for a vehicle whose structure is `generate`.
pub fn generator_spec(v: &Vehicle, g: &ir::Generate) -> GeneratorSpec {
    let mat = |m: &ir::Material| generate::MaterialProps {
        youngs_modulus: m.youngs_modulus.value,
        poisson: m.poisson.value,
        density: m.density.value,
    };
    let fin_spec = |f: &ir::Fins| generate::FinSpec {
        count: f.count.value,
        span: f.span.value,
        root_chord: f.root_chord.value,
        tip_chord: f.tip_chord.value,
        sweep: f.leading_edge_sweep.value,
        thickness: f.thickness.value,
        cant: f.cant.value,
        angles: f.angles.iter().map(|a| a.value).collect(),
        root_trailing_edge_x: f.root_trailing_edge_x.value,
        span_elements: generate::FinSpec::strips_for(&f.outline, g.fin_span_elements.value),
        chord_elements: g.fin_chord_elements.value,
        material: mat(&f.material),
        lamina: f
            .material
            .orthotropic
            .as_ref()
            .map(|o| generate::FinLamina {
                e2: o.e2.value,
                g12: o.g12.value,
                grain: f.grain.angle(),
            }),
        outline: f.outline.clone(),
    };
    GeneratorSpec {
        body: generate::BodySpec {
            length: g.body.length.value,
            outer_diameter: g.body.diameter.value,
            wall_thickness: g.body.wall.value,
            nose_length: g.body.nose_length.value,
            nose_shape: g.body.nose_shape.value,
            transitions: g.body.transition_geoms(),
            elements: g.body.elements.value,
            theory: match g.body.theory.value {
                ir::BeamTheory::EulerBernoulli => generate::BeamTheory::EulerBernoulli,
                ir::BeamTheory::Timoshenko => generate::BeamTheory::Timoshenko,
            },
            material: mat(&v.material),
        },
        fins: v.fins.as_ref().map(&fin_spec),
        rigid_fins: v.fin_sets.iter().map(|s| fin_spec(&s.fins)).collect(),
        point_masses: g
            .point_masses
            .iter()
            .map(|p| generate::PointMass {
                name: p.name.value.clone(),
                position: p.position.value,
                mass: p.mass.value,
                inertia: p.inertia.value,
            })
            .collect(),
        distributed_masses: g
            .distributed_masses
            .iter()
            .map(|d| generate::DistributedMass {
                name: d.name.value.clone(),
                x_from: d.from.value,
                x_to: d.to.value,
                mass: d.mass.value,
            })
            .chain(fillet_mass(v, g))
            .collect(),
    }
}

/// Every fin set's root fillets (the vehicle's `fins` and its further sets) as a line mass on
/// the body over the set's root chord
/// ([`ir::Fillet::mass`], at the body's radius under the fins). Like every distributed mass
/// it is on the body axis: the fillets' own roll inertia, `m (R + r/5)²` with OpenRocket's
/// radial centroid, is left out (0.5 % of the K1000T vehicle's roll inertia for 10 mm
/// fillets, docs/language.md).
fn fillet_mass<'a>(
    v: &'a Vehicle,
    g: &'a ir::Generate,
) -> impl Iterator<Item = generate::DistributedMass> + 'a {
    let primary = v.fins.iter().map(|f| ("fin fillets".to_string(), f));
    let further = v
        .fin_sets
        .iter()
        .map(|s| (format!("fin fillets of `{}`", s.name.value), &s.fins));
    primary.chain(further).filter_map(move |(name, f)| {
        let fillet = f.fillet.as_ref()?;
        let x_te = f.root_trailing_edge_x.value;
        Some(generate::DistributedMass {
            name,
            x_from: x_te + f.root_chord.value,
            x_to: x_te,
            mass: fillet.mass(
                f.count.value,
                f.root_chord.value,
                g.body.root_radius(Some(f)),
            ),
        })
    })
}

/// Build (generate) or read the FE model of a vehicle.
pub fn build_model(v: &Vehicle) -> Result<FeModel, StructureError> {
    match &v.structure {
        Structure::Generate(g) => {
            let spec = generator_spec(v, g);
            generate::generate(&spec).map_err(|error| StructureError::Generate {
                error,
                span: g.span,
            })
        }
        Structure::Files(f) => {
            let order = f.dof_order.value.map(usize::from);
            let opts = ReadOptions {
                dof_order: DofOrder::new(order)?,
                mass_name: f.mass_matrix.value.clone(),
                stiffness_name: f.stiffness_matrix.value.clone(),
                ..ReadOptions::default()
            };
            let mut model = match f.format.value {
                ir::FeFormat::MatrixMarket => fe_io::read_matrix_market_model(
                    &f.mass.value,
                    &f.stiffness.value,
                    &f.nodes.value,
                    f.elements.as_ref().map(|e| e.value.as_path()),
                    &opts,
                )?,
                ir::FeFormat::Op4 => fe_io::read_op4_model(&f.mass.value, &f.nodes.value, &opts)?,
                ir::FeFormat::Dmig => fe_io::read_bulk_model(&f.mass.value, &opts)?,
            };
            for n in &mut model.nodes {
                n.position = n.position.map(|c| c * f.length_scale.value);
            }
            fe_io::validate(&model)?;
            Ok(model)
        }
    }
}

fn node_index(model: &FeModel, r: &NodeRef, what: &str) -> Result<usize, StructureError> {
    match r {
        NodeRef::Id(id) => model
            .node_index(id.value)
            .ok_or_else(|| StructureError::Node {
                message: format!("{what}: the FE model has no node with id {}", id.value),
                span: id.span,
            }),
        NodeRef::Nearest(p) => {
            nearest(model, p.value, |_| true).ok_or_else(|| StructureError::Node {
                message: format!("{what}: the FE model has no nodes"),
                span: p.span,
            })
        }
    }
}

fn nearest(model: &FeModel, p: [f64; 3], keep: impl Fn(usize) -> bool) -> Option<usize> {
    let d2 = |q: [f64; 3]| (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) + (q[2] - p[2]).powi(2);
    (0..model.nodes.len())
        .filter(|&i| keep(i))
        .min_by(|&a, &b| d2(model.nodes[a].position).total_cmp(&d2(model.nodes[b].position)))
}

/// Fin key nodes: for `fin_point(span = s, chord = c)` the fin-j node nearest to the point
/// at fraction s of the span from the root and fraction c of the local chord aft of the
/// leading edge (5.4.17-5.4.18 use the same non-dimensional positions).
fn fin_key_nodes(
    model: &FeModel,
    comps: &[Component],
    v: &Vehicle,
) -> Result<Vec<usize>, StructureError> {
    let Some(f) = &v.fins else {
        return Ok(Vec::new());
    };
    match &v.key_nodes.fins {
        FinKeyNodes::None => Ok(Vec::new()),
        FinKeyNodes::PerFin(refs) => refs
            .iter()
            .enumerate()
            .map(|(j, r)| node_index(model, r, &format!("fin {} key node", j + 1)))
            .collect(),
        FinKeyNodes::Fraction { span, chord } => {
            let mut out = Vec::new();
            for (j, delta) in f.angles.iter().enumerate() {
                let on_fin = |i: usize| comps[i] == Component::Fin(j as u16);
                let (c, s) = (delta.value.cos(), delta.value.sin());
                let radial = |i: usize| {
                    let q = model.nodes[i].position;
                    q[1] * c + q[2] * s
                };
                let r_root = (0..model.nodes.len())
                    .filter(|&i| on_fin(i))
                    .map(radial)
                    .fold(f64::INFINITY, f64::min);
                if !r_root.is_finite() {
                    return Err(StructureError::Node {
                        message: format!("fin {}: the FE model has no nodes on this fin", j + 1),
                        span: v.key_nodes.span,
                    });
                }
                let eta = span.value * f.span.value;
                let (local_chord, x_le) = if f.outline.is_trapezoidal() {
                    (
                        f.root_chord.value + (f.tip_chord.value - f.root_chord.value) * span.value,
                        f.root_trailing_edge_x.value + f.root_chord.value
                            - eta * f.leading_edge_sweep.value.tan(),
                    )
                } else {
                    // The true edges (issue 34).
                    let e = f.edges();
                    (
                        e.chord(eta),
                        f.root_trailing_edge_x.value + f.root_chord.value - e.le(eta),
                    )
                };
                let x = x_le - chord.value * local_chord;
                let r = r_root + eta;
                let target = [x, r * c, r * s];
                out.push(nearest(model, target, on_fin).unwrap_or(0));
            }
            Ok(out)
        }
    }
}

/// The most elastic modes computed to meet a selection.
const MAX_MODES: usize = 400;

/// How many elastic modes to compute first so the selection can be met (more are computed
/// while it is unmet: [`compile_model`]).
fn modes_wanted(v: &Vehicle, n_fins: usize) -> usize {
    let mut n = 0;
    for r in &v.modes.rules {
        n += match r {
            ir::ModeRule::Indices(i) => i.value.iter().copied().max().unwrap_or(0),
            ir::ModeRule::BandHz { .. } => 60,
            ir::ModeRule::Class { count, .. } => match count.value {
                ir::ModeCount::Count(k) => 4 * k,
                ir::ModeCount::PerFin => 4 * n_fins,
            },
        };
    }
    n.clamp(24, MAX_MODES)
}

/// Compile a checked vehicle.
pub fn compile(v: &Vehicle) -> Result<(CompiledVehicle, FeModel), StructureError> {
    let model = build_model(v)?;
    compile_model(v, model)
}

/// Compile a vehicle from an FE model already built.
pub fn compile_model(
    v: &Vehicle,
    model: FeModel,
) -> Result<(CompiledVehicle, FeModel), StructureError> {
    let fins = v.fins.as_ref().map(|f| FinLayout {
        angles: f.angles.iter().map(|a| a.value).collect(),
    });
    let comps = super::selection::components(&model, fins.as_ref());
    // The motor at ignition: casing and full grain on the body nodes; the grain's mass
    // matrix alone is reduced on the same modes below.
    let (model, propellant_mass) = match &v.motor {
        Some(motor) => {
            let (full, prop) = super::motor::with_motor(&model, &comps, motor).map_err(|e| {
                StructureError::Node {
                    message: format!("motor `{}`: {e}", motor.name.value),
                    span: motor.header,
                }
            })?;
            (full, Some(prop))
        }
        None => (model, None),
    };
    let origin = node_index(&model, &v.origin, "origin")?;
    let origin_span = match &v.origin {
        NodeRef::Id(s) => s.span,
        NodeRef::Nearest(p) => p.span,
    };
    // The origin node carries the body frame (2.5.2): it must carry translational mass.
    let o = origin * DOF_PER_NODE;
    let diag: f64 = (0..3)
        .map(|k| {
            let col = o + k;
            let sym = model.mass.symbolic();
            sym.col_range(col)
                .find(|&idx| sym.row_idx()[idx] == col)
                .map_or(0.0, |idx| model.mass.val()[idx])
        })
        .fold(f64::INFINITY, f64::min);
    if diag.is_nan() || diag <= 0.0 {
        return Err(StructureError::Node {
            message: format!(
                "the origin node (id {}) carries no mass: it cannot hold the body frame",
                model.nodes[origin].id
            ),
            span: origin_span,
        });
    }
    let key_body = node_index(&model, &v.key_nodes.body, "body key node")?;
    let key_nozzle = match (&v.key_nodes.nozzle, &v.motor) {
        (Some(r), _) => Some(node_index(&model, r, "nozzle key node")?),
        // The motor's aft end (the nozzle exit) on the body.
        (None, Some(m)) => nearest(&model, m.position.value, |i| {
            comps.get(i).is_none_or(|c| *c == Component::Body)
        }),
        (None, None) => None,
    };
    let key_fins = fin_key_nodes(&model, &comps, v)?;

    let n_fins = fins.as_ref().map_or(0, |f| f.angles.len());
    // The selection is met from the lowest modes; `modes_wanted` is a first guess of how
    // many it needs. A body with many modes below its fins' (a long, soft tube: RockSim's
    // BodyTubeChildrenTest, whose fins' first twist lies above its 36 lowest modes) needs
    // more: while the selection is unmet and the model has more modes, solve again for
    // twice as many, up to MAX_MODES. A selection met at the first guess is unchanged.
    let mut wanted = modes_wanted(v, n_fins);
    let (modes, mut selection) = loop {
        let modes = modal::solve(&model, wanted).map_err(|error| StructureError::Modal {
            error,
            span: structure_span(v),
        })?;
        let n_rigid = modes.n_rigid;
        let n_elastic = modes.shapes.ncols() - n_rigid;
        let elastic = modes.shapes.as_ref().subcols(n_rigid, n_elastic);
        match select(
            &model,
            &modes.omega2[n_rigid..],
            elastic,
            fins.as_ref(),
            &v.modes.rules,
        ) {
            Ok(selection) => break (modes, selection),
            Err(SelectionError::Unmet(_)) if n_elastic >= wanted && wanted < MAX_MODES => {
                wanted = (2 * wanted).min(MAX_MODES);
            }
            Err(error) => {
                return Err(StructureError::Selection {
                    error,
                    span: v.modes.span,
                });
            }
        }
    };
    let n_rigid = modes.n_rigid;
    normalise_signs(&mut selection.shapes);
    let n = selection.info.len();
    let damping: Vec<f64> = match v.modes.damping.len() {
        0 => vec![0.0; n],
        1 => vec![v.modes.damping[0].value; n],
        k if k == n => v.modes.damping.iter().map(|d| d.value).collect(),
        k => {
            return Err(StructureError::Damping {
                message: format!(
                    "{k} damping ratios for {n} selected modes: give one, or one per mode"
                ),
                span: v.modes.damping[0].span,
            });
        }
    };
    let shapes: Mat<f64> = if v.modes.fixity_origin {
        fix_modes_at_origin(&model, origin, selection.shapes.as_ref()).map_err(|error| {
            StructureError::Coefficients {
                error,
                span: v.modes.span,
            }
        })?
    } else {
        selection.shapes.clone()
    };
    let reduced =
        reduce(&model, origin, shapes.as_ref(), &selection.omega2, &damping).map_err(|error| {
            StructureError::Coefficients {
                error,
                span: structure_span(v),
            }
        })?;

    // The propellant's coefficients on the same shapes (module doc of `runtime::motor`):
    // every mass coefficient is linear in M, so the vehicle at propellant fraction f is
    // `reduced - (1 - f) propellant`. K and the damping belong to the structure alone.
    let propellant = match propellant_mass {
        Some(mp) => {
            let prop_model = FeModel {
                nodes: model.nodes.clone(),
                mass: mp,
                stiffness: model.stiffness.clone(),
                elements: Vec::new(),
            };
            let mut p = reduce(
                &prop_model,
                origin,
                shapes.as_ref(),
                &selection.omega2,
                &vec![0.0; n],
            )
            .map_err(|error| StructureError::Coefficients {
                error,
                span: structure_span(v),
            })?;
            p.modal_stiffness.fill(0.0);
            p.modal_damping.fill(0.0);
            Some(p)
        }
        None => None,
    };
    let m = reduced.mass;
    let c = reduced.first_moment;
    let com = [c[0] / m, c[1] / m, c[2] / m];
    // Parallel-axis theorem: J_cm = J_o - m (|r|^2 1 - r r^T) with r the centre of mass.
    let r2 = com.iter().map(|x| x * x).sum::<f64>();
    let mut inertia_cm = reduced.inertia;
    for a in 0..3 {
        for b in 0..3 {
            let delta = if a == b { 1.0 } else { 0.0 };
            inertia_cm[a][b] -= m * (r2 * delta - com[a] * com[b]);
        }
    }
    let n_dof = model.n_dof();
    let mut flat = Vec::with_capacity(n_dof * n);
    for i in 0..n_dof {
        for j in 0..n {
            flat.push(shapes[(i, j)]);
        }
    }
    let compiled = CompiledVehicle {
        vehicle: v.name.value.clone(),
        modes: selection
            .info
            .iter()
            .enumerate()
            .map(|(j, info)| {
                compiled_mode(
                    info,
                    reduced.modal_mass.get(j * n + j).copied().unwrap_or(0.0),
                )
            })
            .collect(),
        reduced,
        candidate_frequencies_hz: selection
            .candidates
            .iter()
            .map(|c| c.frequency_hz)
            .collect(),
        n_rigid: n_rigid as u32,
        node_positions: model.nodes.iter().map(|n| n.position).collect(),
        node_ids: model.nodes.iter().map(|n| n.id).collect(),
        node_components: comps
            .iter()
            .map(|c| match c {
                Component::Fin(i) => i32::from(*i),
                _ => -1,
            })
            .collect(),
        shapes: flat,
        origin_node: origin as u32,
        key_body: key_body as u32,
        key_nozzle: key_nozzle.map_or(-1, |k| k as i64),
        key_fins: key_fins.iter().map(|&k| k as u32).collect(),
        centre_of_mass: com,
        inertia_cm,
        propellant,
    };
    Ok((compiled, model))
}

/// Eigenvectors are defined up to sign: make the entry of largest magnitude of each mode
/// positive (the first such entry on ties), so artifacts and snapshots do not depend on the
/// eigensolver's arbitrary choice.
pub fn normalise_signs(shapes: &mut Mat<f64>) {
    for j in 0..shapes.ncols() {
        let mut best = (0usize, 0.0f64);
        for i in 0..shapes.nrows() {
            let a = shapes[(i, j)].abs();
            if a > best.1 * (1.0 + 1e-9) {
                best = (i, a);
            }
        }
        if shapes[(best.0, j)] < 0.0 {
            for i in 0..shapes.nrows() {
                shapes[(i, j)] = -shapes[(i, j)];
            }
        }
    }
}

fn compiled_mode(info: &ModeInfo, generalised_mass: f64) -> CompiledMode {
    CompiledMode {
        name: info.name.clone(),
        class: match info.kind {
            super::selection::Kind::BodyBending => "body_bending",
            super::selection::Kind::FinFlap => "fin_flap",
            super::selection::Kind::FinTwist => "fin_twist",
            super::selection::Kind::Other => "other",
        }
        .to_string(),
        fin: info.fin.map_or(-1, |f| f as i32),
        frequency_hz: info.frequency_hz,
        generalised_mass,
        body_fraction: info.body_fraction,
    }
}

fn structure_span(v: &Vehicle) -> Span {
    match &v.structure {
        Structure::Generate(g) => g.span,
        Structure::Files(f) => f.span,
    }
}

/// Files whose bytes enter the cache key.
pub fn referenced_files(v: &Vehicle) -> Vec<&Path> {
    match &v.structure {
        Structure::Generate(_) => Vec::new(),
        Structure::Files(f) => {
            let mut out = vec![
                f.mass.value.as_path(),
                f.stiffness.value.as_path(),
                f.nodes.value.as_path(),
            ];
            if let Some(e) = &f.elements {
                out.push(e.value.as_path());
            }
            out.sort();
            out.dedup();
            out
        }
    }
}
