//! Compile through the cache: the structural artifact of a vehicle, its cache key, its
//! aerodynamics artifact, and the plan of a scenario with both (`flexflight compile`, `modes`,
//! `plan` and every command that flies or analyses a vehicle).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::artifact::{self, Cache, CacheKey, CacheKeyBuilder, CacheOutcome, GetOrBuildError};
use crate::check::Checked;
use crate::check::ir::Vehicle;
use crate::diagnostics::Diagnostic;
use crate::ops::OpsError;
use crate::structure::compile::{CompiledVehicle, StructureError, compile, referenced_files};
use crate::syntax::{SourceMap, Span};

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
        fin_sets,
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
    // The further sets' masses are rigid masses of the generated model. Hashed only when
    // present, so the key of a vehicle without them is the key it had before they existed.
    if !fin_sets.is_empty() {
        canon(&mut b, "fin sets", fin_sets)?;
    }
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

/// Compile through the cache. A structure error is a diagnostic on the vehicle or the FE
/// file ([`structure_diagnostic`], whose file is added to `checked.sources`).
pub fn compile_cached(
    checked: &mut Checked,
    vehicle: &Vehicle,
    cache_dir: Option<&Path>,
) -> Result<CompileOutcome, OpsError> {
    let t0 = Instant::now();
    let key = cache_key(vehicle).map_err(|e| {
        OpsError::Usage(format!(
            "cannot read an FE file of `{}`: {e}",
            vehicle.name.value
        ))
    })?;
    let cache = Cache::resolve(cache_dir);
    match cache.get_or_build(&key, || compile(vehicle).map(|(c, _)| c)) {
        Ok((art, outcome)) => {
            let compiled = rkyv::deserialize::<CompiledVehicle, rkyv::rancor::Error>(art.get())
                .map_err(|e| {
                    OpsError::Usage(format!(
                        "artifact {} could not be read back: {e}",
                        art.path()
                            .map_or(String::new(), |p| p.display().to_string())
                    ))
                })?;
            Ok(CompileOutcome {
                compiled,
                path: art.path().map(Path::to_path_buf).unwrap_or_default(),
                key,
                outcome,
                seconds: t0.elapsed().as_secs_f64(),
            })
        }
        Err(GetOrBuildError::Build(e)) => Err(OpsError::Diagnostics(vec![structure_diagnostic(
            &e,
            &mut checked.sources,
        )])),
        Err(GetOrBuildError::Artifact(e)) => Err(OpsError::Coded {
            code: e.code(),
            message: e.to_string(),
            input: false,
        }),
    }
}

/// The human summary of a compiled vehicle (`compile`, `inspect`).
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
        super::files::write_atomic(&path, &s)?;
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
    if let crate::check::ir::AeroSource::Datcom { file, .. } = &v.aero.source {
        b.file("datcom output", &file.value)?;
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
/// were obtained (`None` without aerodynamics); cache warnings go to `warn`.
pub fn plan_cached(
    sc: &crate::check::ir::Scenario,
    c: &CompiledVehicle,
    structural: &CacheKey,
    cache: &Cache,
    warn: &mut dyn FnMut(String),
) -> Result<(crate::plan::Plan, Option<CachedAero>), crate::plan::PlanError> {
    match vehicle_aero_cached(&sc.vehicle, c, structural, cache) {
        Ok(Some(cached)) => {
            if let Some(w) = &cached.warning {
                warn(w.clone());
            }
            if let CacheOutcome::Rebuilt { .. } = &cached.outcome {
                warn(format!("aerodynamics: {}", cached.outcome));
            }
            let plan = crate::plan::build_with_aero(sc, c, Some(&cached.aero))?;
            Ok((plan, Some(cached)))
        }
        // Without aerodynamics, or when they cannot be built (the plan reports why, with
        // its span).
        Ok(None) | Err(_) => crate::plan::build(sc, c).map(|p| (p, None)),
    }
}
