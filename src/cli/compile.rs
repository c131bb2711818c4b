//! `flexflight compile`, `inspect` and `modes`: the structural compiler behind the cache.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::artifact::{self, Cache, CacheKey, CacheKeyBuilder, CacheOutcome, GetOrBuildError};
use crate::check::Checked;
use crate::check::ir::Vehicle;
use crate::diagnostics::Diagnostic;
use crate::structure::compile::{CompiledVehicle, StructureError, compile, referenced_files};
use crate::syntax::{SourceMap, Span};

use super::{EXIT_DIAGNOSTICS, EXIT_USAGE, Format, Terminal, emit};

/// Pick the vehicle to compile: by name, or the only one declared in the root files.
pub fn pick_vehicle<'a>(checked: &'a Checked, name: Option<&str>) -> Result<&'a Vehicle, String> {
    let vs = &checked.program.vehicles;
    match name {
        Some(n) => vs.iter().find(|v| v.name.value == n).ok_or_else(|| {
            format!(
                "no vehicle named `{n}`; declared: {}",
                vs.iter()
                    .map(|v| v.name.value.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }),
        None => match vs.as_slice() {
            [v] => Ok(v),
            [] => Err("the files declare no vehicle".into()),
            _ => Err(format!(
                "the files declare several vehicles ({}); choose one with --vehicle",
                vs.iter()
                    .map(|v| v.name.value.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        },
    }
}

/// The cache key of a vehicle's structure: the canonical structural inputs (the IR of the
/// parts that shape the FE model and the modes), the bytes of every referenced FE file, and
/// (through the builder) the compiler and format versions.
///
/// Complete by construction: each part is hashed by its canonical serialisation
/// ([`artifact::canonical`]), which keeps every value and leaves out only source positions,
/// by their type; and `Vehicle` is destructured without `..`, so a field added to it does
/// not compile until it is either hashed here or stated not to shape the artifact.
pub fn cache_key(v: &Vehicle) -> std::io::Result<CacheKey> {
    let Vehicle {
        name,
        span: _,
        material,
        structure,
        origin,
        key_nodes,
        modes,
        fins,
        motor,
        // Not structural: the aerodynamics and the force blocks are resolved by the plan
        // and the runtime, never by the compiler.
        aero: _,
        forces: _,
    } = v;
    let mut b = CacheKeyBuilder::new("compiled-vehicle");
    let canon = |b: &mut CacheKeyBuilder, label: &str, x: &dyn erased::Ser| {
        x.add_to(b, label)
            .map(|_| ())
            .map_err(std::io::Error::other)
    };
    b.text(
        "pipeline revision",
        &crate::structure::compile::PIPELINE_REVISION.to_string(),
    );
    canon(&mut b, "name", name)?;
    canon(&mut b, "material", material)?;
    canon(&mut b, "structure", structure)?;
    canon(&mut b, "fins", fins)?;
    canon(&mut b, "origin", origin)?;
    canon(&mut b, "key_nodes", key_nodes)?;
    canon(&mut b, "modes", modes)?;
    canon(&mut b, "motor", motor)?;
    for f in referenced_files(v) {
        b.file("fe-file", f)?;
    }
    Ok(b.finish())
}

pub(crate) mod erased {
    use crate::artifact::{CacheKeyBuilder, canonical};
    /// Add anything serde can serialise to a key, without naming its type.
    pub trait Ser {
        fn add_to(&self, b: &mut CacheKeyBuilder, label: &str) -> Result<(), canonical::Error>;
    }
    impl<T: serde::Serialize> Ser for T {
        fn add_to(&self, b: &mut CacheKeyBuilder, label: &str) -> Result<(), canonical::Error> {
            b.canonical(label, self).map(|_| ())
        }
    }
}

/// A structure error as a diagnostic. Reader errors are shown on the FE file itself.
pub fn structure_diagnostic(e: &StructureError, sources: &mut SourceMap) -> Diagnostic {
    let d = Diagnostic::error(e.code(), e.to_string());
    match e {
        StructureError::Read(r) => {
            let path = r.path().to_path_buf();
            let text = std::fs::read_to_string(&path).unwrap_or_default();
            let span = line_span(&text, r.line(), r.column());
            let id = sources.add(path.clone(), path.display().to_string(), text);
            let d = Diagnostic::error(r.code(), r.to_string());
            match span {
                Some((s, t)) => d.label(Span::new(id, s, t), "here"),
                None => d.with_help(format!("in {}", path.display())),
            }
        }
        other => match other.span() {
            Some(span) => d.label(span, "while compiling this"),
            None => d,
        },
    }
}

fn line_span(text: &str, line: usize, column: usize) -> Option<(usize, usize)> {
    if line == 0 {
        return None;
    }
    let mut start = 0;
    for (k, l) in text.split_inclusive('\n').enumerate() {
        if k + 1 == line {
            let l_trim = l.trim_end_matches(['\n', '\r']);
            if column > 0 {
                let c = l_trim
                    .char_indices()
                    .nth(column - 1)
                    .map_or(l_trim.len(), |(i, _)| i);
                let end = l_trim[c..]
                    .find(char::is_whitespace)
                    .map_or(l_trim.len(), |e| c + e);
                return Some((start + c, start + end.max(c + 1).min(l_trim.len().max(c))));
            }
            return Some((start, start + l_trim.len()));
        }
        start += l.len();
    }
    None
}

pub struct CompileOutcome {
    pub compiled: CompiledVehicle,
    pub path: PathBuf,
    pub key: CacheKey,
    pub outcome: CacheOutcome,
    pub seconds: f64,
}

/// Compile through the cache. On failure, diagnostics are printed and the exit code returned.
pub fn compile_cached(
    checked: &mut Checked,
    vehicle: &Vehicle,
    cache_dir: Option<&Path>,
    format: Format,
    term: Terminal,
) -> Result<CompileOutcome, u8> {
    let t0 = Instant::now();
    let key = match cache_key(vehicle) {
        Ok(k) => k,
        Err(e) => {
            eprintln!(
                "error: cannot read an FE file of `{}`: {e}",
                vehicle.name.value
            );
            return Err(EXIT_USAGE);
        }
    };
    let cache = Cache::resolve(cache_dir);
    match cache.get_or_build(&key, || compile(vehicle).map(|(c, _)| c)) {
        Ok((art, outcome)) => {
            let compiled =
                match rkyv::deserialize::<CompiledVehicle, rkyv::rancor::Error>(art.get()) {
                    Ok(c) => c,
                    Err(e) => {
                        eprintln!(
                            "error: artifact {} could not be read back: {e}",
                            art.path()
                                .map_or(String::new(), |p| p.display().to_string())
                        );
                        return Err(EXIT_USAGE);
                    }
                };
            if let CacheOutcome::Rebuilt { .. } = &outcome {
                eprintln!("warning: {outcome}");
            }
            Ok(CompileOutcome {
                compiled,
                path: art.path().map(Path::to_path_buf).unwrap_or_default(),
                key,
                outcome,
                seconds: t0.elapsed().as_secs_f64(),
            })
        }
        Err(GetOrBuildError::Build(e)) => {
            let d = structure_diagnostic(&e, &mut checked.sources);
            emit(&[d], &checked.sources, format, term);
            Err(EXIT_DIAGNOSTICS)
        }
        Err(GetOrBuildError::Artifact(e)) => {
            eprintln!("error[{}]: {e}", e.code());
            Err(EXIT_USAGE)
        }
    }
}

/// The human summary printed by `compile`.
pub fn summary_text(c: &CompiledVehicle) -> String {
    let r = &c.reduced;
    let mut s = String::new();
    let _ = writeln!(s, "vehicle        {}", c.vehicle);
    let _ = writeln!(s, "total mass     {:.6} kg", r.mass);
    let _ = writeln!(
        s,
        "centre of mass ({:.6}, {:.6}, {:.6}) m  ({:.4} m aft of the nose)",
        c.centre_of_mass[0], c.centre_of_mass[1], c.centre_of_mass[2], -c.centre_of_mass[0]
    );
    let _ = writeln!(s, "inertia about the centre of mass (kg m^2):");
    for row in &c.inertia_cm {
        let _ = writeln!(
            s,
            "  [{:>14.6e} {:>14.6e} {:>14.6e}]",
            row[0], row[1], row[2]
        );
    }
    let _ = writeln!(
        s,
        "FE model       {} nodes, {} DOF, {} rigid-body modes",
        c.node_positions.len(),
        6 * c.node_positions.len(),
        c.n_rigid
    );
    let _ = writeln!(s, "selected modes:");
    let _ = writeln!(
        s,
        "  {:>3}  {:<20} {:<13} {:>4} {:>12} {:>14}",
        "#", "name", "class", "fin", "freq (Hz)", "gen. mass"
    );
    for (k, m) in c.modes.iter().enumerate() {
        let fin = if m.fin >= 0 {
            format!("{}", m.fin + 1)
        } else {
            "-".into()
        };
        let _ = writeln!(
            s,
            "  {:>3}  {:<20} {:<13} {:>4} {:>12.4} {:>14.6e}",
            k + 1,
            m.name,
            m.class,
            fin,
            m.frequency_hz,
            m.generalised_mass
        );
    }
    s
}

pub fn summary_json(o: &CompileOutcome) -> serde_json::Value {
    let c = &o.compiled;
    serde_json::json!({
        "vehicle": c.vehicle,
        "total_mass_kg": c.reduced.mass,
        "centre_of_mass_m": c.centre_of_mass,
        "inertia_cm_kg_m2": c.inertia_cm,
        "nodes": c.node_positions.len(),
        "rigid_modes": c.n_rigid,
        "modes": c.modes,
        "artifact": o.path,
        "hash": o.key.to_hex(),
        "seconds": o.seconds,
        "cache": match &o.outcome { CacheOutcome::Hit => "hit", CacheOutcome::Miss => "miss", CacheOutcome::Rebuilt { .. } => "rebuilt" },
    })
}

pub fn print_outcome(o: &CompileOutcome, format: Format) {
    match format {
        Format::Human => {
            out!("{}", summary_text(&o.compiled));
            outln!("artifact       {}", o.path.display());
            outln!("hash           {}", o.key);
            outln!(
                "time           {:.3} s ({})",
                o.seconds,
                match &o.outcome {
                    CacheOutcome::Hit => "cache hit",
                    CacheOutcome::Miss => "compiled",
                    CacheOutcome::Rebuilt { .. } => "rebuilt after a bad cached artifact",
                }
            );
        }
        Format::Json => outln!(
            "{}",
            serde_json::to_string_pretty(&summary_json(o)).unwrap_or_default()
        ),
    }
}

/// `inspect`: every coefficient of an artifact file.
pub fn cmd_inspect(path: &Path, format: Format) -> u8 {
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("error: cannot read `{}`: {e}", path.display());
            return EXIT_USAGE;
        }
    };
    // The expected key is the one stored in the file: inspect validates everything else.
    let key_bytes: Option<[u8; 32]> = bytes.get(48..80).and_then(|s| s.try_into().ok());
    let Some(key_bytes) = key_bytes else {
        eprintln!(
            "error[artifact::truncated]: `{}` is too short to be an artifact",
            path.display()
        );
        return EXIT_DIAGNOSTICS;
    };
    let key = CacheKey(key_bytes);
    match artifact::load::<CompiledVehicle>(path, &key) {
        Ok(art) => match rkyv::deserialize::<CompiledVehicle, rkyv::rancor::Error>(art.get()) {
            Ok(c) => {
                match format {
                    Format::Json => {
                        outln!("{}", serde_json::to_string_pretty(&c).unwrap_or_default())
                    }
                    Format::Human => {
                        out!("{}", summary_text(&c));
                        outln!("coefficients (3.2.1), row-major:");
                        let r = serde_json::to_value(&c.reduced).unwrap_or_default();
                        if let serde_json::Value::Object(map) = r {
                            for (k, v) in map {
                                outln!("  {k} = {v}");
                            }
                        }
                    }
                }
                0
            }
            Err(e) => {
                eprintln!("error[artifact::invalid_payload]: {e}");
                EXIT_DIAGNOSTICS
            }
        },
        // Not a compiled vehicle: the other artifacts of the cache, told apart by their
        // payload schema (the header's schema hash).
        Err(e) if e.code() == "artifact::schema" => inspect_other(path, &key, format)
            .unwrap_or_else(|| {
                eprintln!("error[{}]: {e}", e.code());
                EXIT_DIAGNOSTICS
            }),
        Err(e) => {
            eprintln!("error[{}]: {e}", e.code());
            EXIT_DIAGNOSTICS
        }
    }
}

/// `inspect` of a vehicle's aerodynamics artifact (estimated tables, fin load weights, fin
/// panel matrices: [`crate::plan::aero::AeroArtifact`]) or of its flutter boundary
/// ([`crate::analysis::flutter::margin::BoundaryArtifact`]) or of a clamped fin's GAF table
/// ([`super::gaf_cache::GafArtifact`]); None when the file is none of them.
fn inspect_other(path: &Path, key: &CacheKey, format: Format) -> Option<u8> {
    use crate::analysis::flutter::margin::BoundaryArtifact;
    use crate::plan::aero::AeroArtifact;
    let fail = |e: &dyn std::fmt::Display| {
        eprintln!("error[artifact::invalid_payload]: {e}");
        EXIT_DIAGNOSTICS
    };
    let value = if let Ok(art) = artifact::load::<AeroArtifact>(path, key) {
        match rkyv::deserialize::<AeroArtifact, rkyv::rancor::Error>(art.get()) {
            Ok(a) => aero_artifact_json(&a),
            Err(e) => return Some(fail(&e)),
        }
    } else if let Ok(art) = artifact::load::<BoundaryArtifact>(path, key) {
        match rkyv::deserialize::<BoundaryArtifact, rkyv::rancor::Error>(art.get()) {
            Ok(b) => boundary_artifact_json(&b),
            Err(e) => return Some(fail(&e)),
        }
    } else if let Ok(art) = artifact::load::<super::gaf_cache::GafArtifact>(path, key) {
        match rkyv::deserialize::<super::gaf_cache::GafArtifact, rkyv::rancor::Error>(art.get()) {
            Ok(g) => gaf_artifact_json(&g),
            Err(e) => return Some(fail(&e)),
        }
    } else {
        return None;
    };
    match format {
        Format::Json => outln!(
            "{}",
            serde_json::to_string_pretty(&value).unwrap_or_default()
        ),
        Format::Human => out!("{}", human_tree(&value, 0)),
    }
    Some(0)
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
fn human_tree(v: &serde_json::Value, depth: usize) -> String {
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

/// `modes --export DIR`: one CSV per selected mode, node by node.
pub fn export_modes(c: &CompiledVehicle, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let n = c.modes.len();
    let mut written = Vec::new();
    for (j, m) in c.modes.iter().enumerate() {
        let mut s = String::from("node_id,x,y,z,component,u,v,w,theta_x,theta_y,theta_z\n");
        for (i, p) in c.node_positions.iter().enumerate() {
            let comp = match c.node_components[i] {
                -1 => "body".to_string(),
                f => format!("fin{}", f + 1),
            };
            let _ = write!(s, "{},{},{},{},{}", c.node_ids[i], p[0], p[1], p[2], comp);
            for d in 0..6 {
                let _ = write!(s, ",{:e}", c.shapes[(6 * i + d) * n + j]);
            }
            s.push('\n');
        }
        let path = dir.join(format!("mode_{:02}_{}.csv", j + 1, m.name));
        super::fmt::write_atomic(&path, &s)?;
        written.push(path);
    }
    Ok(written)
}

/// The cache key of a vehicle's aerodynamics (estimated tables, fin load weights,
/// [`crate::plan::aero::AeroArtifact`]): the structural key `structural` (the FE model the
/// weights are spread over), the whole checked vehicle serialised with its spans (complete
/// by construction: no field can be left out; moving text only costs a rebuild), the bytes
/// of its coefficient table files, and [`crate::plan::aero::AERO_REVISION`].
pub fn aero_cache_key(v: &Vehicle, structural: &CacheKey) -> std::io::Result<CacheKey> {
    let mut b = CacheKeyBuilder::new("vehicle-aero");
    b.u64("aero revision", u64::from(crate::plan::aero::AERO_REVISION));
    b.bytes("structural key", structural.as_bytes());
    // The whole vehicle by its canonical serialisation: every value, source positions left
    // out by their type (moving text does not change the key).
    b.canonical("vehicle", v).map_err(std::io::Error::other)?;
    if let crate::check::ir::AeroSource::Tables { body, fins, .. } = &v.aero.source {
        b.file("body table", &body.value)?;
        b.file("fin table", &fins.value)?;
    }
    Ok(b.finish())
}

/// A vehicle's aerodynamics through the cache: what was used and how it was obtained.
pub struct CachedAero {
    pub aero: crate::plan::aero::VehicleAero,
    pub key: CacheKey,
    pub outcome: CacheOutcome,
    /// Why the result could not be stored, if it could not (the run goes on).
    pub warning: Option<String>,
}

/// The vehicle-only aerodynamics of `v` flown by `c` (structural key `structural`): read
/// from the cache, or built and stored. `Ok(None)` when the vehicle has no aerodynamic
/// force block, or when its key cannot be made (a table file that cannot be read: the plan
/// then reports it).
pub fn vehicle_aero_cached(
    v: &Vehicle,
    c: &CompiledVehicle,
    structural: &CacheKey,
    cache: &Cache,
) -> Result<Option<CachedAero>, crate::runtime::forces::AeroForceError> {
    use crate::plan::aero::{AeroArtifact, resolve};
    if v.forces.body_aero.is_none() && v.forces.fin_aero.is_none() {
        return Ok(None);
    }
    let Ok(key) = aero_cache_key(v, structural) else {
        return Ok(None);
    };
    let outcome = match cache.lookup::<AeroArtifact>(&key) {
        Ok(Some(art)) => {
            let read = rkyv::deserialize::<AeroArtifact, rkyv::rancor::Error>(art.get())
                .map_err(|e| e.to_string())
                .and_then(|a| a.to_vehicle_aero(v).map_err(|e| e.to_string()));
            match read {
                Ok(aero) => {
                    return Ok(Some(CachedAero {
                        aero,
                        key,
                        outcome: CacheOutcome::Hit,
                        warning: None,
                    }));
                }
                // A valid container whose contents do not fit this build: rebuild it.
                Err(message) => CacheOutcome::Rebuilt {
                    reason: artifact::ArtifactError::InvalidPayload {
                        path: cache.path_for(&key),
                        message,
                    },
                },
            }
        }
        Ok(None) => CacheOutcome::Miss,
        Err(reason) => CacheOutcome::Rebuilt { reason },
    };
    let Some(built) = resolve(v, c, &Default::default(), None)? else {
        return Ok(None);
    };
    let aero = built.vehicle_part();
    let warning = artifact::write_atomic(cache.dir(), &key, &AeroArtifact::new(&aero))
        .err()
        .map(|e| format!("cannot store the aerodynamics in the cache: {e}"));
    Ok(Some(CachedAero {
        aero,
        key,
        outcome,
        warning,
    }))
}

/// [`crate::plan::build`] with the vehicle's aerodynamics through the cache (a warm run
/// does not rebuild the estimated tables or the fin load weights). Also returns how they
/// were obtained (`None` without aerodynamics).
pub fn plan_cached(
    sc: &crate::check::ir::Scenario,
    c: &CompiledVehicle,
    structural: &CacheKey,
    cache: &Cache,
) -> Result<(crate::plan::Plan, Option<CachedAero>), crate::plan::PlanError> {
    match vehicle_aero_cached(&sc.vehicle, c, structural, cache) {
        Ok(Some(cached)) => {
            if let Some(w) = &cached.warning {
                eprintln!("warning: {w}");
            }
            if let CacheOutcome::Rebuilt { .. } = &cached.outcome {
                eprintln!("warning: aerodynamics: {}", cached.outcome);
            }
            let plan = crate::plan::build_with_aero(sc, c, Some(&cached.aero))?;
            Ok((plan, Some(cached)))
        }
        // Without aerodynamics, or when they cannot be built (the plan reports why, with
        // its span).
        Ok(None) | Err(_) => crate::plan::build(sc, c).map(|p| (p, None)),
    }
}
