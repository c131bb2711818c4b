//! The aerodynamics of a plan: coefficient tables, fin load weights and key-node rows.
//!
//! [`resolve`] builds the body and fin aerodynamic blocks of a vehicle (thesis 5.3-5.5,
//! App. A) from the checked vehicle and its compiled structure: the coefficient tables
//! (read from the vehicle's CSV files, or produced by the built-in estimator), each fin's
//! nodes with their non-dimensional span/chord positions and load weights on the fin
//! table's Mach grid (with the distribution lumped per grid Mach), and the shape rows at
//! the key nodes. The plan owns the result ([`PlanAero`]); a run only copies it.
//!
//! The part that depends on the vehicle alone and costs time (the estimated tables, the
//! fin load weights and, for `fin_aero { model = lifting_surface }`, the fin panel matrices
//! per grid Mach), [`VehicleAero`], is kept content-addressed in the artifact cache
//! as an [`AeroArtifact`] keyed by the structural key and the whole checked vehicle (see
//! `cli::compile::aero_cache_key`), so a warm run does not rebuild it. Everything else
//! (key-node rows, node positions, the lumped sums) is rebuilt from the compiled vehicle,
//! which is cheap and keeps the artifact small.

use std::path::Path;

use serde::Serialize;

use crate::aero::atmosphere::Standard1976;
use crate::aero::estimator::EstimatedTables;
use crate::aero::fin_loads::FinLoadTable;
use crate::aero::panel::fin_model::{FinTransfer, PanelModel, PanelSettings};
use crate::aero::tables::{Axis, CoefficientTable, TableKind};
use crate::check::ir::{self, AeroSource};
use crate::runtime::forces::{AeroForceError, BodyAero, FinAero, aero_tables};
use crate::runtime::stimuli::Stimuli;
use crate::structure::compile::CompiledVehicle;

/// Revision of the vehicle-only aerodynamics (estimator, fin load weights). It is part of
/// the aero cache key: bump it whenever a change makes the same vehicle give different
/// tables or weights, so that no stale artifact is served. 3: the fin tables' supersonic slope
/// and centre of pressure from the steady supersonic lifting surface (issue 33). 4: the fin
/// axial coefficient sees the fin's thickness and cross-section (issue 34; conical noses'
/// body tables are unchanged). 5: the lifting-surface panel matrices above Mach 1 from the
/// steady supersonic panels where piston theory's criterion fails, the band 0.9-1.1 bridged
/// (issue 33). 6: skin friction by Reynolds number and surface roughness (OpenRocket's law,
/// the body's fineness correction; issue 34). 7: the body table's roll columns for a vehicle
/// with further fin sets (their cant's roll forcing and roll damping; issue 34). 8: the
/// built-in tables span every flow direction (-180..180 deg), the fins' normal force held
/// at its stall value beyond 20 deg and mirrored for air from behind, the axial
/// coefficients scaled with the angle of attack (Niskanen's scaling, reversed beyond 90 deg).
pub const AERO_REVISION: u32 = 8;

/// Source label of the estimated body table (as [`EstimatedTables::estimate`] names it).
const BUILTIN_BODY: &str = "builtin-body.csv";
/// Source label of the estimated fin table.
const BUILTIN_FIN: &str = "builtin-fins.csv";

/// The aerodynamic blocks of a plan, built before the run.
#[derive(Debug, Clone)]
pub struct PlanAero {
    /// The body and fin coefficient tables the blocks use.
    pub tables: EstimatedTables,
    /// True when the tables come from the built-in estimator (`aero { source = builtin }`).
    pub estimated: bool,
    pub body: Option<BodyAero>,
    pub fin: Option<FinAero>,
}

impl PlanAero {
    /// The part of the aerodynamics that depends on the vehicle alone (for the cache).
    pub fn vehicle_part(&self) -> VehicleAero {
        VehicleAero {
            tables: self.tables.clone(),
            estimated: self.estimated,
            fin_loads: self
                .fin
                .as_ref()
                .map_or_else(Vec::new, FinAero::load_tables),
            panels: self.fin.as_ref().and_then(FinAero::panel_model).cloned(),
        }
    }

    /// Replaces the stimuli (wind and gusts) the blocks see.
    pub fn set_stimuli(&mut self, stimuli: &Stimuli) {
        if let Some(b) = &mut self.body {
            b.set_stimuli(stimuli.clone());
        }
        if let Some(b) = &mut self.fin {
            b.set_stimuli(stimuli.clone());
        }
    }
}

/// What of the aerodynamics depends only on the vehicle and costs time to build: the
/// coefficient tables and each fin's load weights on the fin table's Mach grid.
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleAero {
    pub tables: EstimatedTables,
    pub estimated: bool,
    /// One per fin, in fin order (empty without fin aerodynamics).
    pub fin_loads: Vec<FinLoadTable>,
    /// The fin panel matrices on the fin table's Mach grid (lifting-surface model only).
    pub panels: Option<PanelModel>,
}

/// The cached form of [`VehicleAero`]: the estimated tables as their CSV text (which reads
/// back bit for bit: [`CoefficientTable::to_csv`] prints shortest round-trip floats) and
/// the raw load weights and panel matrices. Tables read from files are not stored: their
/// bytes are part of the key and they are read again.
#[derive(Clone, Debug, PartialEq, rkyv::Archive, rkyv::Serialize, rkyv::Deserialize)]
pub struct AeroArtifact {
    pub body_table_csv: Option<String>,
    pub fin_table_csv: Option<String>,
    pub fin_loads: Vec<FinLoadWeights>,
    pub fin_panels: Option<FinPanels>,
}

/// The fin panel matrices ([`PanelModel`]): lattice settings, Mach grid and each fin's
/// transfer matrices `(n + 3) x (2 n + 3)` per grid Mach, row-major, concatenated by Mach.
#[derive(Clone, Debug, PartialEq, rkyv::Archive, rkyv::Serialize, rkyv::Deserialize)]
pub struct FinPanels {
    pub chordwise: u64,
    pub spanwise: u64,
    /// 0 uniform, 1 cosine.
    pub spacing: u8,
    /// 0 none, 1 Ackeret.
    pub correction: u8,
    pub machs: Vec<f64>,
    pub n_modes: u64,
    pub transfer: Vec<Vec<f64>>,
}

impl FinPanels {
    fn new(m: &PanelModel) -> Self {
        use crate::aero::panel::Spacing;
        use crate::aero::panel::piston::Correction;
        FinPanels {
            chordwise: m.settings.chordwise as u64,
            spanwise: m.settings.spanwise as u64,
            spacing: u8::from(m.settings.spacing == Spacing::Cosine),
            correction: u8::from(m.settings.correction == Correction::Ackeret),
            machs: m.machs.clone(),
            n_modes: m.fins.first().map_or(0, |t| t.n as u64),
            transfer: m.fins.iter().map(|t| t.t.clone()).collect(),
        }
    }

    /// Back to a [`PanelModel`]; an error when a size does not fit.
    fn to_model(&self) -> Result<PanelModel, String> {
        use crate::aero::panel::Spacing;
        use crate::aero::panel::piston::Correction;
        let n = usize::try_from(self.n_modes).map_err(|e| e.to_string())?;
        let size = self.machs.len() * (n + 3) * (2 * n + 3);
        if let Some(t) = self.transfer.iter().find(|t| t.len() != size) {
            return Err(format!(
                "cached panel matrices hold {} values, expected {size}",
                t.len()
            ));
        }
        let settings = PanelSettings {
            chordwise: usize::try_from(self.chordwise).map_err(|e| e.to_string())?,
            spanwise: usize::try_from(self.spanwise).map_err(|e| e.to_string())?,
            spacing: match self.spacing {
                0 => Spacing::Uniform,
                1 => Spacing::Cosine,
                x => return Err(format!("cached panel spacing {x} is unknown")),
            },
            correction: match self.correction {
                0 => Correction::None,
                1 => Correction::Ackeret,
                x => return Err(format!("cached piston correction {x} is unknown")),
            },
        };
        Ok(PanelModel {
            settings,
            machs: self.machs.clone(),
            fins: self
                .transfer
                .iter()
                .map(|t| FinTransfer { n, t: t.clone() })
                .collect(),
        })
    }
}

/// One fin's load weights: `weights[i * n_nodes + k]` is node k's weight at `machs[i]`.
#[derive(Clone, Debug, PartialEq, rkyv::Archive, rkyv::Serialize, rkyv::Deserialize)]
pub struct FinLoadWeights {
    pub machs: Vec<f64>,
    pub n_nodes: u64,
    pub weights: Vec<f64>,
}

impl crate::artifact::ArtifactPayload for AeroArtifact {
    const SCHEMA: &'static str = "AeroArtifact v2: body_table_csv Option<String>, fin_table_csv Option<String> (CoefficientTable::to_csv of the estimated tables), fin_loads [machs Vec<f64>, n_nodes u64, weights Vec<f64> row-major by Mach], fin_panels Option<[chordwise u64, spanwise u64, spacing u8, correction u8, machs Vec<f64>, n_modes u64, transfer [Vec<f64> (n+3)x(2n+3) row-major per Mach]]>";
}

impl AeroArtifact {
    /// The cached form of `v`.
    pub fn new(v: &VehicleAero) -> Self {
        AeroArtifact {
            body_table_csv: v.estimated.then(|| v.tables.body.to_csv()),
            fin_table_csv: v.estimated.then(|| v.tables.fin.to_csv()),
            fin_loads: v
                .fin_loads
                .iter()
                .map(|t| FinLoadWeights {
                    machs: t.machs().to_vec(),
                    n_nodes: t.n_nodes() as u64,
                    weights: t.weights().to_vec(),
                })
                .collect(),
            fin_panels: v.panels.as_ref().map(FinPanels::new),
        }
    }

    /// Back to [`VehicleAero`] for the checked vehicle `v` (the one the key was made of):
    /// estimated tables parsed from their text, file tables read again.
    pub fn to_vehicle_aero(&self, v: &ir::Vehicle) -> Result<VehicleAero, AeroForceError> {
        let (tables, estimated) = match (&v.aero.source, &self.body_table_csv, &self.fin_table_csv)
        {
            (AeroSource::Builtin { out_of_range, .. }, Some(body), Some(fin)) => {
                let parse = |kind, label: &str, text: &str| {
                    CoefficientTable::parse_csv(kind, Path::new(label), text, out_of_range.value)
                };
                (
                    EstimatedTables {
                        body: parse(TableKind::Body, BUILTIN_BODY, body.as_str())?,
                        fin: parse(TableKind::Fin, BUILTIN_FIN, fin.as_str())?,
                    },
                    true,
                )
            }
            (AeroSource::Tables { .. } | AeroSource::Datcom { .. }, None, None) => {
                (aero_tables(v)?, false)
            }
            _ => {
                return Err(AeroForceError::Cached(
                    "the cached aerodynamics do not match the vehicle's aero source".into(),
                ));
            }
        };
        let fin_loads = self
            .fin_loads
            .iter()
            .map(|f| {
                FinLoadTable::from_weights(f.machs.clone(), f.n_nodes as usize, f.weights.clone())
                    .map_err(AeroForceError::FinLoad)
            })
            .collect::<Result<_, _>>()?;
        let panels = self
            .fin_panels
            .as_ref()
            .map(FinPanels::to_model)
            .transpose()
            .map_err(AeroForceError::Cached)?;
        Ok(VehicleAero {
            tables,
            estimated,
            fin_loads,
            panels,
        })
    }
}

/// Builds the aerodynamic blocks of vehicle `v` flown by `c` with `stimuli`, or `None`
/// when neither `body_aero` nor `fin_aero` is on. With `cached` (the [`VehicleAero`] of
/// the same vehicle, from the cache or a previous plan) the tables and load weights are
/// taken from it instead of being rebuilt; the blocks are the same bits either way.
pub fn resolve(
    v: &ir::Vehicle,
    c: &CompiledVehicle,
    stimuli: &Stimuli,
    cached: Option<&VehicleAero>,
) -> Result<Option<PlanAero>, AeroForceError> {
    let wants_body = v.forces.body_aero.is_some();
    let wants_fin = v.forces.fin_aero.is_some();
    if !wants_body && !wants_fin {
        return Ok(None);
    }
    let tables = match cached {
        Some(va) => va.tables.clone(),
        None => aero_tables(v)?,
    };
    let body = if wants_body {
        Some(BodyAero::new(
            c,
            v,
            tables.body.clone(),
            Standard1976::new(),
            stimuli.clone(),
        )?)
    } else {
        None
    };
    let fin = if wants_fin {
        Some(FinAero::with_cached(
            c,
            v,
            tables.fin.clone(),
            Standard1976::new(),
            stimuli.clone(),
            cached.map(|va| va.fin_loads.as_slice()),
            cached.and_then(|va| va.panels.as_ref()),
        )?)
    } else {
        None
    };
    Ok(Some(PlanAero {
        tables,
        estimated: matches!(v.aero.source, AeroSource::Builtin { .. }),
        body,
        fin,
    }))
}

/// Mach numbers at which `flexflight plan` shows the coefficients (those inside the
/// table's Mach range).
const SAMPLE_MACHS: [f64; 6] = [0.3, 0.6, 0.9, 1.2, 2.0, 3.0];
/// Angle of attack of the shown coefficients, deg.
const SAMPLE_ALPHA_DEG: f64 = 4.0;

/// What `flexflight plan` shows of the aerodynamics (serialised into `--format json`).
#[derive(Debug, Clone, Serialize)]
pub struct AeroSummary {
    /// `builtin` (estimated) or `tables` (read from the vehicle's files).
    pub source: &'static str,
    pub tables: Vec<TableSummary>,
    pub body: Option<BodySummary>,
    pub fins: Vec<FinSummary>,
    /// The fin aerodynamic model (`key_node` or `lifting_surface`), with fin aerodynamics.
    pub fin_model: Option<ir::FinAeroModel>,
}

/// One coefficient table: its grid, ranges and a few values.
#[derive(Debug, Clone, Serialize)]
pub struct TableSummary {
    /// `body` or `fin`.
    pub kind: &'static str,
    /// The file it was read from, or the estimator's label.
    pub source: String,
    pub columns: [&'static str; 6],
    pub mach: Vec<f64>,
    pub alpha_deg: Vec<f64>,
    pub altitude_m: Vec<f64>,
    /// `stop` or `clamp` outside the grid.
    pub out_of_range: ir::OutOfRange,
    /// The three value columns at `alpha = 4 deg`, the lowest tabulated altitude and a few
    /// Machs inside the grid; and `cn_alpha_per_rad = (cn(4) - cn(-4)) / 8 deg`.
    pub samples: Vec<CoefficientSample>,
}

/// The coefficients at one flight condition.
#[derive(Debug, Clone, Serialize)]
pub struct CoefficientSample {
    pub mach: f64,
    pub alpha_deg: f64,
    pub altitude_m: f64,
    /// The three value columns (`cn, ca, cm` or `cn, ca, x_cp_m`).
    pub values: [f64; 3],
    pub cn_alpha_per_rad: f64,
}

/// The body key node of `body_aero`.
#[derive(Debug, Clone, Serialize)]
pub struct BodySummary {
    pub key_node: usize,
    pub key_node_position: [f64; 3],
    /// `r_ref - r_bn`, m.
    pub lever: [f64; 3],
    /// Rows u, v, w, θx, θy, θz of `S` at the key node (6 x n, row-major).
    pub key_node_rows: Vec<f64>,
}

/// One fin of `fin_aero`.
#[derive(Debug, Clone, Serialize)]
pub struct FinSummary {
    /// 1-based.
    pub fin: usize,
    pub key_node: usize,
    pub key_node_position: [f64; 3],
    /// Rows u, v, w, θx, θy, θz of `S` at the fin key node (6 x n, row-major).
    pub key_node_rows: Vec<f64>,
    /// Load-carrying nodes (FE nodes of the fin plus virtual root nodes).
    pub nodes: usize,
    /// Virtual nodes added on the root chord (tied rigidly to the body).
    pub virtual_root_nodes: usize,
    /// The load weights at each Mach of the grid.
    pub weights: Vec<WeightSummary>,
}

/// The load weights of one fin at one Mach: their sum and first moments.
#[derive(Debug, Clone, Serialize)]
pub struct WeightSummary {
    pub mach: f64,
    /// `Σ w_k` (1 by construction).
    pub sum: f64,
    /// `Σ w_k η_k`, `Σ w_k ξ_k`: the centre of pressure in span and chord fractions.
    pub eta_cp: f64,
    pub xi_cp: f64,
    /// `Σ w_k r_k`: the centre of pressure in the body frame, m.
    pub position_cp: [f64; 3],
    pub max_weight: f64,
}

impl AeroSummary {
    /// The summary of `a`.
    pub fn new(a: &PlanAero) -> Self {
        let mut tables = Vec::new();
        if a.body.is_some() {
            tables.push(table_summary("body", &a.tables.body));
        }
        if a.fin.is_some() {
            tables.push(table_summary("fin", &a.tables.fin));
        }
        let body = a.body.as_ref().map(|b| BodySummary {
            key_node: b.key_node(),
            key_node_position: b.key_node_position(),
            lever: b.lever(),
            key_node_rows: b.key_node_rows().to_vec(),
        });
        let fins = a.fin.as_ref().map_or_else(Vec::new, |f| {
            (0..f.n_fins())
                .map(|i| {
                    let nodes = f.nodes(i);
                    let positions = f.node_positions(i);
                    let loads = f.load_table(i);
                    let weights = loads
                        .map(|t| {
                            (0..t.machs().len())
                                .map(|g| {
                                    let w = t.grid_weights(g);
                                    let mut cp = [0.0; 3];
                                    for (wk, r) in w.iter().zip(positions) {
                                        for d in 0..3 {
                                            cp[d] += wk * r[d];
                                        }
                                    }
                                    WeightSummary {
                                        mach: t.machs()[g],
                                        sum: w.iter().sum(),
                                        eta_cp: w.iter().zip(nodes).map(|(w, n)| w * n.eta).sum(),
                                        xi_cp: w.iter().zip(nodes).map(|(w, n)| w * n.xi).sum(),
                                        position_cp: cp,
                                        max_weight: w.iter().copied().fold(0.0, f64::max),
                                    }
                                })
                                .collect()
                        })
                        .unwrap_or_default();
                    FinSummary {
                        fin: i + 1,
                        key_node: f.key_node(i).unwrap_or(0),
                        key_node_position: f.key_node_position(i).unwrap_or_default(),
                        key_node_rows: f.key_node_rows(i).to_vec(),
                        nodes: nodes.len(),
                        virtual_root_nodes: f.virtual_root_nodes(i),
                        weights,
                    }
                })
                .collect()
        });
        AeroSummary {
            source: if a.estimated { "builtin" } else { "tables" },
            tables,
            body,
            fins,
            fin_model: a.fin.as_ref().map(FinAero::model),
        }
    }

    /// The human lines of `flexflight plan`.
    pub fn text(&self, n_modes: usize) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        let _ = writeln!(s, "aerodynamics   {} coefficient tables", self.source);
        if let Some(m) = self.fin_model {
            let _ = writeln!(
                s,
                "  fin model      {}",
                match m {
                    ir::FinAeroModel::KeyNode =>
                        "key_node (thesis 5.4: tables at the fin key node)",
                    ir::FinAeroModel::LiftingSurface =>
                        "lifting_surface (rigid load from the tables, elastic increments from the panels)",
                }
            );
        }
        for t in &self.tables {
            let range = |a: &[f64]| match (a.first(), a.last()) {
                (Some(lo), Some(hi)) => format!("{lo} .. {hi} ({} values)", a.len()),
                _ => "empty".into(),
            };
            let _ = writeln!(
                s,
                "  {:<4} table  {} ({:?} outside the grid)",
                t.kind, t.source, t.out_of_range
            );
            let _ = writeln!(s, "    mach       {}", range(&t.mach));
            let _ = writeln!(s, "    alpha      {} deg", range(&t.alpha_deg));
            let _ = writeln!(s, "    altitude   {} m", range(&t.altitude_m));
            let c = &t.columns;
            let _ = writeln!(
                s,
                "    {:>6} {:>12} {:>12} {:>12} {:>14}   (alpha {} deg, altitude {} m)",
                "mach",
                c[3],
                c[4],
                c[5],
                "cn_alpha /rad",
                SAMPLE_ALPHA_DEG,
                t.samples.first().map_or(0.0, |x| x.altitude_m)
            );
            for x in &t.samples {
                let _ = writeln!(
                    s,
                    "    {:>6} {:>12.6} {:>12.6} {:>12.6} {:>14.6}",
                    x.mach, x.values[0], x.values[1], x.values[2], x.cn_alpha_per_rad
                );
            }
        }
        let rows = |r: &[f64]| -> String {
            if n_modes == 0 {
                return "(no modes)".into();
            }
            r.chunks(n_modes)
                .map(|row| {
                    let v: Vec<String> = row.iter().map(|x| format!("{x:.4e}")).collect();
                    format!("[{}]", v.join(" "))
                })
                .collect::<Vec<_>>()
                .join("\n                 ")
        };
        if let Some(b) = &self.body {
            let p = b.key_node_position;
            let _ = writeln!(
                s,
                "  body key node {} at ({:.4}, {:.4}, {:.4}) m; shape rows u v w rx ry rz:\n                 {}",
                b.key_node,
                p[0],
                p[1],
                p[2],
                rows(&b.key_node_rows)
            );
        }
        for f in &self.fins {
            let p = f.key_node_position;
            let _ = writeln!(
                s,
                "  fin {} key node {} at ({:.4}, {:.4}, {:.4}) m; shape rows u v w rx ry rz:\n                 {}",
                f.fin,
                f.key_node,
                p[0],
                p[1],
                p[2],
                rows(&f.key_node_rows)
            );
            let _ = writeln!(
                s,
                "    load weights over {} nodes ({} virtual on the root chord):",
                f.nodes, f.virtual_root_nodes
            );
            let _ = writeln!(
                s,
                "    {:>6} {:>10} {:>8} {:>8} {:>28} {:>10}",
                "mach", "sum", "eta_cp", "xi_cp", "centre of pressure (m)", "max w"
            );
            for w in &f.weights {
                let _ = writeln!(
                    s,
                    "    {:>6} {:>10.6} {:>8.4} {:>8.4}   ({:>7.4}, {:>7.4}, {:>7.4}) {:>10.4e}",
                    w.mach,
                    w.sum,
                    w.eta_cp,
                    w.xi_cp,
                    w.position_cp[0],
                    w.position_cp[1],
                    w.position_cp[2],
                    w.max_weight
                );
            }
        }
        s
    }
}

fn table_summary(kind: &'static str, t: &CoefficientTable) -> TableSummary {
    let mach = t.axis(Axis::Mach).to_vec();
    let alt = t.axis(Axis::AltitudeM)[0];
    let (lo, hi) = (mach[0], mach[mach.len() - 1]);
    let samples = SAMPLE_MACHS
        .iter()
        .copied()
        .filter(|m| (lo..=hi).contains(m))
        .filter_map(|m| {
            let v = t.lookup(m, SAMPLE_ALPHA_DEG, alt).ok()?;
            let minus = t.lookup(m, -SAMPLE_ALPHA_DEG, alt).ok()?;
            Some(CoefficientSample {
                mach: m,
                alpha_deg: SAMPLE_ALPHA_DEG,
                altitude_m: alt,
                values: v,
                cn_alpha_per_rad: (v[0] - minus[0]) / (2.0 * SAMPLE_ALPHA_DEG.to_radians()),
            })
        })
        .collect();
    TableSummary {
        kind,
        source: t.source().display().to_string(),
        columns: t.kind().columns(),
        mach,
        alpha_deg: t.axis(Axis::AlphaDeg).to_vec(),
        altitude_m: t.axis(Axis::AltitudeM).to_vec(),
        out_of_range: t.policy(),
        samples,
    }
}
