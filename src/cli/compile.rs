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
/// parts that shape the FE model and the modes, without spans), the bytes of every
/// referenced FE file, and (through the builder) the compiler and format versions.
pub fn cache_key(v: &Vehicle) -> std::io::Result<CacheKey> {
    let mut b = CacheKeyBuilder::new("compiled-vehicle");
    let canon = |x: serde_json::Value| strip_spans(x).to_string();
    let json = |x: &dyn erased::Ser| x.to_json();
    b.text(
        "pipeline revision",
        &crate::structure::compile::PIPELINE_REVISION.to_string(),
    );
    b.text("name", &v.name.value);
    b.text("material", &canon(json(&v.material)));
    b.text("structure", &canon(json(&v.structure)));
    b.text("fins", &canon(json(&v.fins)));
    b.text("origin", &canon(json(&v.origin)));
    b.text("key_nodes", &canon(json(&v.key_nodes)));
    b.text("modes", &canon(json(&v.modes)));
    for f in referenced_files(v) {
        b.file("fe-file", f)?;
    }
    Ok(b.finish())
}

mod erased {
    /// Serialise anything serde can, without naming its type.
    pub trait Ser {
        fn to_json(&self) -> serde_json::Value;
    }
    impl<T: serde::Serialize> Ser for T {
        fn to_json(&self) -> serde_json::Value {
            serde_json::to_value(self).unwrap_or(serde_json::Value::Null)
        }
    }
}

/// Remove span fields so that moving text around a file does not change the key.
pub fn strip_spans(v: serde_json::Value) -> serde_json::Value {
    use serde_json::Value;
    match v {
        Value::Object(map) => Value::Object(
            map.into_iter()
                .filter(|(k, _)| !matches!(k.as_str(), "span" | "span_" | "header"))
                .map(|(k, v)| (k, strip_spans(v)))
                .collect(),
        ),
        Value::Array(a) => Value::Array(a.into_iter().map(strip_spans).collect()),
        other => other,
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
            print!("{}", summary_text(&o.compiled));
            println!("artifact       {}", o.path.display());
            println!("hash           {}", o.key);
            println!(
                "time           {:.3} s ({})",
                o.seconds,
                match &o.outcome {
                    CacheOutcome::Hit => "cache hit",
                    CacheOutcome::Miss => "compiled",
                    CacheOutcome::Rebuilt { .. } => "rebuilt after a bad cached artifact",
                }
            );
        }
        Format::Json => println!(
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
                        println!("{}", serde_json::to_string_pretty(&c).unwrap_or_default())
                    }
                    Format::Human => {
                        print!("{}", summary_text(&c));
                        println!("coefficients (3.2.1), row-major:");
                        let r = serde_json::to_value(&c.reduced).unwrap_or_default();
                        if let serde_json::Value::Object(map) = r {
                            for (k, v) in map {
                                println!("  {k} = {v}");
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
        Err(e) => {
            eprintln!("error[{}]: {e}", e.code());
            EXIT_DIAGNOSTICS
        }
    }
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
    b.text(
        "vehicle",
        &serde_json::to_string(v).map_err(std::io::Error::other)?,
    );
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
