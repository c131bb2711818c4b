//! `inspect`: every value of an artifact file of the cache, whatever it holds (a compiled
//! vehicle, a vehicle's aerodynamics, a flutter boundary, a clamped fin's GAF table).

use std::path::Path;

use crate::artifact::{self, CacheKey};
use crate::ops::OpsError;
use crate::structure::compile::CompiledVehicle;

/// What an artifact file holds.
pub enum Inspected {
    /// A compiled vehicle (structure, modes, coefficients).
    Vehicle(Box<CompiledVehicle>),
    /// Any other artifact, as a JSON tree of its values.
    Other(serde_json::Value),
}

/// Reads and validates the artifact at `path` (its key is the one it stores: everything
/// else is checked). Errors carry the artifact's codes (`artifact::truncated`, ...); all of
/// them are the input's fault.
pub fn inspect(path: &Path) -> Result<Inspected, OpsError> {
    let coded = |code: &'static str, message: String| OpsError::Coded {
        code,
        message,
        input: true,
    };
    let bytes = std::fs::read(path)
        .map_err(|e| OpsError::Usage(format!("cannot read `{}`: {e}", path.display())))?;
    // The expected key is the one stored in the file: inspect validates everything else.
    let key_bytes: Option<[u8; 32]> = bytes.get(48..80).and_then(|s| s.try_into().ok());
    let Some(key_bytes) = key_bytes else {
        return Err(coded(
            "artifact::truncated",
            format!("`{}` is too short to be an artifact", path.display()),
        ));
    };
    let key = CacheKey(key_bytes);
    match artifact::load::<CompiledVehicle>(path, &key) {
        Ok(art) => rkyv::deserialize::<CompiledVehicle, rkyv::rancor::Error>(art.get())
            .map(|c| Inspected::Vehicle(Box::new(c)))
            .map_err(|e| coded("artifact::invalid_payload", e.to_string())),
        // Not a compiled vehicle: the other artifacts of the cache, told apart by their
        // payload schema (the header's schema hash).
        Err(e) if e.code() == "artifact::schema" => match inspect_other(path, &key) {
            Some(r) => r.map(Inspected::Other),
            None => Err(coded(e.code(), e.to_string())),
        },
        Err(e) => Err(coded(e.code(), e.to_string())),
    }
}

/// A vehicle's aerodynamics artifact (estimated tables, fin load weights, fin panel
/// matrices: [`crate::plan::aero::AeroArtifact`]), a flutter boundary
/// ([`crate::analysis::flutter::margin::BoundaryArtifact`]) or a clamped fin's GAF table
/// ([`super::gaf_cache::GafArtifact`]) as JSON; None when the file is none of them.
fn inspect_other(path: &Path, key: &CacheKey) -> Option<Result<serde_json::Value, OpsError>> {
    use crate::analysis::flutter::margin::BoundaryArtifact;
    use crate::plan::aero::AeroArtifact;
    let fail = |e: &dyn std::fmt::Display| {
        Some(Err(OpsError::Coded {
            code: "artifact::invalid_payload",
            message: e.to_string(),
            input: true,
        }))
    };
    let value = if let Ok(art) = artifact::load::<AeroArtifact>(path, key) {
        match rkyv::deserialize::<AeroArtifact, rkyv::rancor::Error>(art.get()) {
            Ok(a) => aero_artifact_json(&a),
            Err(e) => return fail(&e),
        }
    } else if let Ok(art) = artifact::load::<BoundaryArtifact>(path, key) {
        match rkyv::deserialize::<BoundaryArtifact, rkyv::rancor::Error>(art.get()) {
            Ok(b) => boundary_artifact_json(&b),
            Err(e) => return fail(&e),
        }
    } else if let Ok(art) = artifact::load::<super::gaf_cache::GafArtifact>(path, key) {
        match rkyv::deserialize::<super::gaf_cache::GafArtifact, rkyv::rancor::Error>(art.get()) {
            Ok(g) => gaf_artifact_json(&g),
            Err(e) => return fail(&e),
        }
    } else {
        return None;
    };
    Some(Ok(value))
}

/// Every value of an aerodynamics artifact; the panel matrices per fin and grid Mach as rows
/// of `T = O K I` (`(n + 3) x (2 n + 3)`: modal forces, normal force, root bending and
/// chordwise moments; columns `η`, `η̇ / V`, the rigid normalwash `1, ξ, η`).
fn aero_artifact_json(a: &crate::plan::aero::AeroArtifact) -> serde_json::Value {
    let panels = a.fin_panels.as_ref().map(|p| {
        let n = p.n_modes as usize;
        let (rows, cols) = (n + 3, 2 * n + 3);
        let fins: Vec<serde_json::Value> = p
            .transfer
            .iter()
            .map(|t| {
                let per_mach: Vec<serde_json::Value> = p
                    .machs
                    .iter()
                    .enumerate()
                    .map(|(g, mach)| {
                        let m: Vec<&[f64]> = t
                            .get(g * rows * cols..(g + 1) * rows * cols)
                            .unwrap_or(&[])
                            .chunks(cols)
                            .collect();
                        serde_json::json!({ "mach": mach, "transfer": m })
                    })
                    .collect();
                serde_json::Value::Array(per_mach)
            })
            .collect();
        serde_json::json!({
            "chordwise": p.chordwise,
            "spanwise": p.spanwise,
            "spacing": if p.spacing == 1 { "cosine" } else { "uniform" },
            "supersonic_correction": if p.correction == 1 { "ackeret" } else { "none" },
            "machs": p.machs,
            "modes": n,
            "rows": "modal forces (n), normal force, root bending moment, chordwise moment about the root leading edge",
            "columns": "eta (n), eta_dot / V (n), rigid normalwash 1, x, y",
            "fins": fins,
        })
    });
    let loads: Vec<serde_json::Value> = a
        .fin_loads
        .iter()
        .map(|w| {
            let n = w.n_nodes as usize;
            let per: Vec<&[f64]> = w.weights.chunks(n.max(1)).collect();
            serde_json::json!({ "machs": w.machs, "nodes": n, "weights": per })
        })
        .collect();
    serde_json::json!({
        "artifact": "aerodynamics",
        "estimated_body_table_csv": a.body_table_csv,
        "estimated_fin_table_csv": a.fin_table_csv,
        "fin_load_weights": loads,
        "fin_panels": panels,
    })
}

/// Every value of a clamped fin's GAF table: per reduced frequency the `n x n` matrix
/// `Q(k)` as rows of `[re, im]` pairs.
fn gaf_artifact_json(g: &super::gaf_cache::GafArtifact) -> serde_json::Value {
    let n = (g.order as usize).max(1);
    let tables: Vec<serde_json::Value> =
        g.ks.iter()
            .enumerate()
            .map(|(i, k)| {
                let rows: Vec<Vec<[f64; 2]>> = (0..n)
                    .map(|r| {
                        (0..n)
                            .map(|c| {
                                let j = i * n * n + r * n + c;
                                [
                                    g.re.get(j).copied().unwrap_or(f64::NAN),
                                    g.im.get(j).copied().unwrap_or(f64::NAN),
                                ]
                            })
                            .collect()
                    })
                    .collect();
                serde_json::json!({ "k": k, "q": rows })
            })
            .collect();
    serde_json::json!({
        "artifact": "clamped-fin generalised aerodynamic forces",
        "mach": g.mach,
        "reference_semichord_m": g.b_ref,
        "modes": g.mode_names,
        "omega_rad_s": g.omega,
        "q_of_k": tables,
    })
}

/// Every value of a flutter-boundary artifact.
fn boundary_artifact_json(
    b: &crate::analysis::flutter::margin::BoundaryArtifact,
) -> serde_json::Value {
    let na = b.altitudes.len().max(1);
    let speeds: Vec<&[f64]> = b.speeds.chunks(na).collect();
    serde_json::json!({
        "artifact": "flutter boundary",
        "machs": b.machs,
        "altitudes": b.altitudes,
        "densities": b.densities,
        "flutter_speeds_by_mach": speeds,
        "lower_bound": b.lower_bound,
        "upper_bound": b.upper_bound,
        "speed_ranges": b.speed_ranges,
        "node_lowest_speeds": b.node_lowest_speeds,
        "modes": b.mode_names,
        "omega": b.omega,
        "fin_shear_modulus_span_root_tip_thickness": b.fin,
    })
}

/// An indented `key: value` listing of a JSON tree (arrays of numbers on one line, a
/// multi-line string indented below its key).
pub fn human_tree(v: &serde_json::Value, depth: usize) -> String {
    use serde_json::Value;
    let inline = |x: &Value| -> Option<String> {
        match x {
            Value::String(t) if !t.contains('\n') => Some(t.clone()),
            Value::Array(a) if a.iter().all(Value::is_number) => Some(x.to_string()),
            Value::Array(_) | Value::Object(_) | Value::String(_) => None,
            _ => Some(x.to_string()),
        }
    };
    let pad = "  ".repeat(depth);
    let mut out = String::new();
    let mut entry = |label: String, x: &Value| match (inline(x), x) {
        (Some(l), _) => out += &format!("{pad}{label}: {l}\n"),
        (None, Value::String(t)) => {
            out += &format!("{pad}{label}:\n");
            for l in t.lines() {
                out += &format!("{pad}  {l}\n");
            }
        }
        (None, _) => out += &format!("{pad}{label}:\n{}", human_tree(x, depth + 1)),
    };
    match v {
        Value::Object(map) => map.iter().for_each(|(k, x)| entry(k.clone(), x)),
        Value::Array(items) => items
            .iter()
            .enumerate()
            .for_each(|(i, x)| entry(format!("[{i}]"), x)),
        x => entry(String::new(), x),
    }
    out
}
