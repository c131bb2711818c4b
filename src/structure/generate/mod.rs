//! Built-in FE generator: a beam-and-shell model of a finned rocket, so that a user needs no
//! external FE package.
//!
//! The vehicle (what `analytic_mass_properties` describes and what the mesh represents):
//! - body: a circular tube of outer diameter D and wall t from x = 0 to x = -L, with an
//!   optional conical nose whose outer radius grows linearly from 0 at the tip to D/2 at
//!   x = -l_n, same wall t (solid near the tip where r_o < t). The beam elements integrate
//!   the varying section exactly (see `beam`), so the model's mass, first moment and
//!   inertia tensor are those of this tapered geometry, not of a stepped approximation.
//! - fins: flat trapezoidal plates of constant thickness, root on the tube's outer surface,
//!   meshed with MITC4 shells (see `shell`) and joined to the body line by rigid links
//!   (the root row of fin nodes is eliminated; see `assembly`).
//! - further fin sets (`fins NAME`, `GeneratorSpec::rigid_fins`, issue 34): not meshed; each
//!   set's plates (the same geometry as the meshed fins', `mass_properties::add_fin`) are one
//!   rigid body lumped at the body node nearest its centre of mass, its 6 x 6 block the
//!   set's exact mass, first moment and inertia tensor (products included) about that node
//!   (`mass_properties::rigid_fin_set`). No node, element or mode comes from it.
//! - point masses: rigid bodies lumped at the nearest body node with a rigid offset (6 x 6
//!   block [[m I, -m d^x], [m d^x, I_c - m d^x d^x]]).
//! - distributed masses: uniform line masses on the body axis (no rotary inertia), through
//!   the beam's consistent translational mass; mesh stations at both ends.
//!
//! Node numbering: body nodes first, from the nose tip (index 0, id 1: the default origin
//! node of the floating frame, thesis 2.5.2) aft; then fin 0's free nodes row by row from
//! root to tip, then fin 1, ... Ids are 1-based indices.

mod assembly;
mod beam;
mod mass_properties;
mod mesh;
mod shell;
mod spec;

pub use assembly::{NodeMap, offset_mass_block, rigid_link, skew};
pub use beam::{TubeSection, section_at};
pub use mass_properties::{
    MassProperties, analytic_mass_properties, rigid_body_projection, rigid_body_vectors,
    rigid_fin_set,
};
pub use shell::{Mat24, orthotropic_plane_stress, shell_element, shell_element_lamina};
pub use spec::{
    BeamTheory, BodySpec, DistributedMass, FinLamina, FinSpec, GeneratorSpec, MaterialProps,
    PointMass,
};

use nalgebra::{Matrix3, Matrix6};

use crate::structure::fe_model::{Component, Element, ElementKind, FeModel, Node};
use assembly::Assembler;

/// Errors of the generator; every variant says which input was wrong and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GenerateError {
    #[error("{what} = {value}: {reason}")]
    BadGeometry {
        what: &'static str,
        value: f64,
        reason: &'static str,
    },
    #[error("{part} material: {field} = {value} is not physical")]
    BadMaterial {
        part: &'static str,
        field: &'static str,
        value: f64,
    },
    #[error("{what} must be at least 1")]
    ZeroElements { what: &'static str },
    #[error("fins.angles has {given} entries for {count} fins")]
    FinAngles { count: usize, given: usize },
    #[error(
        "fin root spans x = {root_from} .. {root_to}, outside the cylindrical body x = {body_from} .. {body_to}"
    )]
    FinOutsideBody {
        root_from: f64,
        root_to: f64,
        body_from: f64,
        body_to: f64,
    },
    #[error("mass '{name}' at x = {x} lies outside the body (x from -{length} to 0)")]
    MassOutsideBody { name: String, x: f64, length: f64 },
    #[error("mass '{name}': {field} = {value} is not allowed")]
    BadMass {
        name: String,
        field: &'static str,
        value: f64,
    },
    #[error("sparse assembly failed: {0}")]
    Assembly(String),
}

impl GenerateError {
    /// Stable machine-readable code, e.g. "generate::bad_geometry".
    pub fn code(&self) -> &'static str {
        match self {
            Self::BadGeometry { .. } => "generate::bad_geometry",
            Self::BadMaterial { .. } => "generate::bad_material",
            Self::ZeroElements { .. } => "generate::zero_elements",
            Self::FinAngles { .. } => "generate::bad_fin_angles",
            Self::FinOutsideBody { .. } => "generate::fin_outside_body",
            Self::MassOutsideBody { .. } => "generate::mass_outside_body",
            Self::BadMass { .. } => "generate::bad_mass",
            Self::Assembly(_) => "generate::assembly",
        }
    }
}

/// 6 x 6 block transform blockdiag(T, T).
fn block_frame(t: &Matrix3<f64>) -> Matrix6<f64> {
    let mut l = Matrix6::zeros();
    l.fixed_view_mut::<3, 3>(0, 0).copy_from(t);
    l.fixed_view_mut::<3, 3>(3, 3).copy_from(t);
    l
}

/// Assemble the shell elements of one fin grid. `maps[j][i]` says where grid point (i, j)
/// goes; `plot_node` gives the node index drawn for a grid point (None: element not drawn).
fn assemble_fin(
    f: &FinSpec,
    grid: &mesh::FinGrid,
    maps: &[Vec<NodeMap>],
    asm: &mut Assembler,
    elements: &mut Vec<Element>,
    plot_node: impl Fn(&NodeMap) -> Option<usize>,
) {
    assemble_fin_with(f, grid, maps, asm, elements, plot_node, |_, _, ab| {
        f.plate_element(ab)
    });
}

/// [`assemble_fin`] with the element matrices from `element(i, j, ab)` (quad i chordwise from
/// the trailing edge, j spanwise from the root, local corner coordinates `ab`).
fn assemble_fin_with(
    f: &FinSpec,
    grid: &mesh::FinGrid,
    maps: &[Vec<NodeMap>],
    asm: &mut Assembler,
    elements: &mut Vec<Element>,
    plot_node: impl Fn(&NodeMap) -> Option<usize>,
    element: impl Fn(usize, usize, &[[f64; 2]; 4]) -> (Mat24, Mat24),
) {
    let lam = block_frame(&grid.frame);
    asm.reserve_blocks(16 * f.span_elements * f.chord_elements);
    for j in 0..f.span_elements {
        for i in 0..f.chord_elements {
            let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let ab = corners.map(|(ci, cj)| grid.local[cj][ci]);
            let (kl, ml) = element(i, j, &ab);
            let node_maps = corners.map(|(ci, cj)| maps[cj][ci]);
            let block = |m: &Mat24, a: usize, b: usize| -> Matrix6<f64> {
                lam.transpose() * m.fixed_view::<6, 6>(6 * a, 6 * b) * lam
            };
            asm.add_element(&node_maps, |a, b| block(&kl, a, b), |a, b| block(&ml, a, b));
            let drawn: Option<Vec<usize>> = node_maps.iter().map(&plot_node).collect();
            if let Some(nodes) = drawn {
                elements.push(Element {
                    id: elements.len() as u64 + 1,
                    kind: ElementKind::Shell,
                    nodes,
                });
            }
        }
    }
}

/// Build the FE model of the vehicle described by `spec` (module doc for what it models).
///
/// Body elements: one per pair of adjacent stations (`mesh::body_stations`), so the count
/// is at least `body.elements`. Fins: `span_elements x chord_elements` quads each.
pub fn generate(spec: &GeneratorSpec) -> Result<FeModel, GenerateError> {
    spec::check(spec)?;
    let body = &spec.body;
    let stations = mesh::body_stations(spec);
    let mut nodes: Vec<Node> = stations
        .iter()
        .enumerate()
        .map(|(i, &x)| Node {
            id: i as u64 + 1,
            position: [x, 0.0, 0.0],
            component: Component::Body,
        })
        .collect();
    let n_body = nodes.len();
    let fin_layout = spec.fins.as_ref().map(|f| {
        let per_fin = f.nodes_per_fin();
        (f, per_fin, f.fin_angles())
    });
    let n_total = n_body + fin_layout.as_ref().map_or(0, |(f, per, _)| per * f.count);
    let mut asm = Assembler::new(n_total);
    let mut elements = Vec::new();

    // Body beams: element node 0 is the aft station (i + 1), node 1 the fore station (i).
    asm.reserve_blocks(4 * n_body);
    for i in 0..n_body - 1 {
        let (x_fore, x_aft) = (stations[i], stations[i + 1]);
        let mid = 0.5 * (x_fore + x_aft);
        let line_mass: f64 = spec
            .distributed_masses
            .iter()
            .filter(|d| mid > d.x_from.min(d.x_to) && mid < d.x_from.max(d.x_to))
            .map(|d| d.mass / (d.x_from - d.x_to).abs())
            .sum();
        let (k, m) = beam::beam_element(body, x_aft, x_fore, line_mass);
        let maps = [NodeMap::Node(i + 1), NodeMap::Node(i)];
        asm.add_element(
            &maps,
            |a, b| k.fixed_view::<6, 6>(6 * a, 6 * b).into_owned(),
            |a, b| m.fixed_view::<6, 6>(6 * a, 6 * b).into_owned(),
        );
        elements.push(Element {
            id: elements.len() as u64 + 1,
            kind: ElementKind::Beam,
            nodes: vec![i + 1, i],
        });
    }

    // Fins, root rows rigidly linked to the body stations at the same x.
    if let Some((f, per_fin, angles)) = &fin_layout {
        let root_x = mesh::fin_root_stations(f);
        for (k, &delta) in angles.iter().enumerate() {
            let grid = mesh::fin_grid(f, delta, mesh::fin_root_radius(body, f.pivot_x()));
            let first = n_body + k * per_fin;
            let maps = mesh::fin_node_maps(f, first, |i| {
                let master = mesh::nearest_station(&stations, root_x[i]);
                let p = grid.points[0][i];
                NodeMap::Slave {
                    master,
                    offset: [p[0] - stations[master], p[1], p[2]],
                }
            });
            for row in grid.points.iter().skip(1) {
                // A pointed tip's row is one node (`FinSpec::pointed_tip`).
                let row = if f.pointed_tip() && std::ptr::eq(row, &grid.points[f.span_elements]) {
                    &row[..1]
                } else {
                    &row[..]
                };
                for p in row {
                    nodes.push(Node {
                        id: nodes.len() as u64 + 1,
                        position: *p,
                        component: Component::Fin(k as u16),
                    });
                }
            }
            // Root-row quads are drawn from the master body nodes (the slaves have no node).
            assemble_fin(f, &grid, &maps, &mut asm, &mut elements, |m| match m {
                NodeMap::Node(i) => Some(*i),
                NodeMap::Slave { master, .. } => Some(*master),
                NodeMap::Fixed => None,
            });
        }
    }

    // Further fin sets: each a rigid body (its plates' exact mass, first moment and inertia
    // tensor, products included) on the body node nearest its centre of mass.
    for f in &spec.rigid_fins {
        let about_tip = mass_properties::rigid_fin_set(body, f, 0.0);
        let x_c = about_tip.first_moment[0] / about_tip.mass;
        let node = mesh::nearest_station(&stations, x_c);
        let block = mass_properties::rigid_fin_set(body, f, stations[node]).rigid_mass_matrix();
        asm.add_nodal_mass(node, &Matrix6::from_fn(|a, b| block[a][b]));
    }

    // Point masses at the nearest body node, with rigid offset.
    for p in &spec.point_masses {
        let node = mesh::nearest_station(&stations, p.position[0]);
        let d = [p.position[0] - stations[node], p.position[1], p.position[2]];
        asm.add_nodal_mass(node, &offset_mass_block(p.mass, &d, &p.inertia));
    }

    let (mass, stiffness) = asm.finish()?;
    Ok(FeModel {
        nodes,
        mass,
        stiffness,
        elements,
    })
}

/// The shell mesh of a single fin, clamped along its root chord (all root DOFs removed),
/// for checking the plate elements against cantilever-plate results. The fin lies in the
/// body x-y plane (delta = 0) with its root on y = 0; `fin.count`, `angles` and the body
/// placement are ignored. Nodes: rows j = 1..=span_elements, chordwise fastest.
pub fn cantilever_fin_model(fin: &FinSpec) -> Result<FeModel, GenerateError> {
    cantilever_plate_model(fin, |_, _, ab| fin.plate_element(ab))
}

/// [`cantilever_fin_model`] with the element matrices (local frame, see `shell`) given by
/// `element(i, j, ab)` for quad i chordwise (0 at the trailing edge) and j spanwise (0 at the
/// root), `ab` its local corner coordinates (a = x - pivot_x, toward the leading edge; b
/// spanwise): a plate of varying thickness or an anisotropic lamina
/// ([`shell_element_lamina`]). `fin.thickness` is checked (positive) but not used;
/// `fin.material` is not used.
pub fn cantilever_plate_model(
    fin: &FinSpec,
    element: impl Fn(usize, usize, &[[f64; 2]; 4]) -> (Mat24, Mat24),
) -> Result<FeModel, GenerateError> {
    let mut f = fin.clone();
    f.count = 1;
    f.angles.clear();
    spec::check_fin_planform(&f)?;
    let grid = mesh::fin_grid(&f, 0.0, 0.0);
    let maps = mesh::fin_node_maps(&f, 0, |_| NodeMap::Fixed);
    let pointed = f.pointed_tip();
    let nodes: Vec<Node> = grid
        .points
        .iter()
        .skip(1)
        .enumerate()
        .flat_map(|(j, row)| {
            if pointed && j + 1 == f.span_elements {
                &row[..1]
            } else {
                &row[..]
            }
        })
        .enumerate()
        .map(|(i, p)| Node {
            id: i as u64 + 1,
            position: *p,
            component: Component::Fin(0),
        })
        .collect();
    let mut asm = Assembler::new(nodes.len());
    let mut elements = Vec::new();
    let plot = |m: &NodeMap| match m {
        NodeMap::Node(i) => Some(*i),
        _ => None,
    };
    assemble_fin_with(&f, &grid, &maps, &mut asm, &mut elements, plot, element);
    let (mass, stiffness) = asm.finish()?;
    Ok(FeModel {
        nodes,
        mass,
        stiffness,
        elements,
    })
}
