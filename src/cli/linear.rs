//! `flexflight analyze linear` and `flexflight analyze linear-map`: the linearised 3-D model
//! of a scenario ([`crate::analysis::linear`]) and its fin thickness x Mach map.

use std::fmt::Write as _;
use std::path::Path;

use crate::analysis::linear::{LinearAnalysis, Variant, analyse, linear_map};
use crate::analysis::linearise::LineariseOptions;
use crate::analysis::roots::RootKind;
use crate::artifact::Cache;
use crate::check::{DiskLoader, check_files, ir};
use crate::diagnostics::{self, RenderOptions};
use crate::structure::compile::{CompiledVehicle, compile};

use super::compile::{cache_key, compile_cached};
use super::{Common, EXIT_DIAGNOSTICS, EXIT_OK, EXIT_USAGE, Format, Terminal, load_program};

/// How many participating states are listed per root.
const TOP_STATES: usize = 3;

/// Checks `file` with the `sets` overrides, compiles the scenario's vehicle through the
/// artifact cache and plans the scenario, without touching the terminal (errors come back
/// rendered as text). The map calls this once per fin thickness.
pub fn load_variant(
    file: &Path,
    scenario: &str,
    sets: &[String],
    cache_dir: Option<&Path>,
) -> Result<Variant, String> {
    let checked = check_files(&[file.to_path_buf()], sets, &DiskLoader);
    if checked.has_errors() {
        return Err(diagnostics::render(
            &checked.diagnostics,
            &checked.sources,
            RenderOptions {
                width: 100,
                color: false,
                unicode: false,
            },
        ));
    }
    let sc = checked
        .program
        .scenario(scenario)
        .cloned()
        .ok_or_else(|| format!("no scenario named `{scenario}`"))?;
    variant_for(sc, cache_dir)
}

/// Compiles the checked scenario `sc`'s vehicle through the artifact cache and plans `sc`
/// (errors as text): [`load_variant`] after the check, and `analyze flutter`'s free-vehicle
/// `--critical-thickness` once per thickness.
pub fn variant_for(sc: ir::Scenario, cache_dir: Option<&Path>) -> Result<Variant, String> {
    let key = cache_key(&sc.vehicle).map_err(|e| format!("cannot read an FE file: {e}"))?;
    let cache = Cache::resolve(cache_dir);
    let (art, _) = cache
        .get_or_build(&key, || compile(&sc.vehicle).map(|(c, _)| c))
        .map_err(|e| e.to_string())?;
    let compiled = rkyv::deserialize::<CompiledVehicle, rkyv::rancor::Error>(art.get())
        .map_err(|e| format!("artifact could not be read back: {e}"))?;
    let (plan, _) =
        super::compile::plan_cached(&sc, &compiled, &key, &cache).map_err(|e| e.to_string())?;
    Ok(Variant {
        plan,
        scenario: sc,
        compiled,
    })
}

/// `flexflight analyze linear`.
pub fn cmd_linear(
    file: &Path,
    scenario: &str,
    frozen_gravity: bool,
    common: &Common,
    cache_dir: Option<&Path>,
    term: Terminal,
) -> u8 {
    let mut checked = match load_program(&[file.to_path_buf()], common, term) {
        Ok(c) => c,
        Err(code) => return code,
    };
    let Some(sc) = checked.program.scenario(scenario).cloned() else {
        eprintln!("error: no scenario named `{scenario}`");
        return EXIT_USAGE;
    };
    let format = common.output.format;
    let outcome = match compile_cached(&mut checked, &sc.vehicle, cache_dir, format, term) {
        Ok(o) => o,
        Err(code) => return code,
    };
    let cache = Cache::resolve(cache_dir);
    let plan = match super::compile::plan_cached(&sc, &outcome.compiled, &outcome.key, &cache) {
        Ok((p, _)) => p,
        Err(e) => {
            eprintln!("error: cannot plan scenario `{scenario}`: {e}");
            return EXIT_DIAGNOSTICS;
        }
    };
    let variant = Variant {
        plan,
        scenario: sc,
        compiled: outcome.compiled,
    };
    let options = LineariseOptions {
        gravity_follows_attitude: !frozen_gravity,
        ..LineariseOptions::default()
    };
    let result = match analyse(&variant, options) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: linearisation failed: {e}");
            return EXIT_DIAGNOSTICS;
        }
    };
    match format {
        Format::Human => out!("{}", report_text(&variant, &result)),
        Format::Json => {
            let json = serde_json::json!({
                "scenario": scenario,
                "vehicle": variant.plan.vehicle,
                "mode_names": variant.plan.mode_names,
                "options": options,
                "analysis": result,
            });
            outln!(
                "{}",
                serde_json::to_string_pretty(&json).unwrap_or_default()
            );
        }
    }
    EXIT_OK
}

/// The human report: trim, then one line per root (conjugate pairs once).
pub fn report_text(variant: &Variant, r: &LinearAnalysis) -> String {
    let mut s = String::new();
    let c = &r.condition;
    let _ = writeln!(
        s,
        "linearised model of `{}` ({}), ballistic reference, alpha = 0",
        variant.plan.scenario, variant.plan.vehicle
    );
    let _ = writeln!(
        s,
        "condition   V = {:.3} m/s, Mach {:.4}, altitude {:.1} m, q = {:.1} Pa",
        c.speed, c.mach, c.altitude, c.dynamic_pressure
    );
    let t = &r.trim;
    let _ = writeln!(
        s,
        "trim        {} ({} Newton iterations, scaled residual {:.2e}){}",
        if r.trim_converged {
            "static elastic balance found"
        } else {
            "NOT converged, linearised about eta = 0"
        },
        t.iterations,
        t.residual,
        r.trim_message
            .as_ref()
            .map_or(String::new(), |m| format!(": {m}"))
    );
    let a = &t.rigid_acceleration;
    let _ = writeln!(
        s,
        "            dV_B/dt = ({:.4}, {:.4}, {:.4}) m/s^2, domega_B/dt = ({:.3e}, {:.3e}, {:.3e}) rad/s^2",
        a[0], a[1], a[2], a[3], a[4], a[5]
    );
    for (m, e) in variant.plan.mode_names.iter().zip(&t.eta) {
        let _ = writeln!(s, "            eta_{m} = {e:.6e}");
    }
    let e = &r.eigen;
    let _ = writeln!(
        s,
        "stability   {}: sigma_d = {:.6} 1/s, omega_d = {:.4} rad/s ({:.4} Hz); max Re over all roots {:.3e}",
        e.class.name(),
        e.sigma_d,
        e.omega_d,
        e.omega_d / std::f64::consts::TAU,
        e.max_real_all
    );
    if let (Some(scale), Some(rate)) = (e.flight_path_scale, e.flight_path_rate) {
        let _ = writeln!(
            s,
            "flight path Lambda = (2 a_D + sqrt(2) g)/V = {:.4} 1/s (a_D {:.3} m/s^2, g {:.4} m/s^2): {}",
            rate,
            scale.aero_acceleration,
            scale.gravity,
            match e.flight_path_sigma {
                Some(x) => format!(
                    "slowest drift max Re {x:.5} 1/s (the trim's trajectory, not the vehicle's stability)"
                ),
                None => "no flight-path roots".to_string(),
            }
        );
    }
    let _ = writeln!(
        s,
        "{:>14} {:>14} {:>9} {:>10} {:>10}  top states (participation)",
        "Re (1/s)", "Im (rad/s)", "zeta", "f_n (Hz)", "f_d (Hz)"
    );
    for root in e.roots.iter().filter(|x| x.imag >= 0.0) {
        let top: Vec<String> = root
            .top_states(TOP_STATES)
            .iter()
            .map(|(k, p)| format!("{} {:.0}%", r.model.state_names[*k], 100.0 * p))
            .collect();
        let _ = writeln!(
            s,
            "{:>14.6} {:>14.6} {:>9.4} {:>10.4} {:>10.4}  {}{}",
            root.real,
            root.imag,
            root.damping_ratio,
            root.natural_frequency_hz,
            root.frequency_hz,
            top.join(", "),
            match root.kind {
                RootKind::Neutral => "  (neutral)",
                RootKind::FlightPath => "  (flight path)",
                RootKind::Dynamic => "",
            }
        );
    }
    s
}

/// `flexflight analyze linear-map`: fin thickness x Mach, `DIR/map.csv`. The ranges carry
/// units (`--thickness 0.3mm:1.2mm:10`), checked like vehicle-file values.
#[allow(clippy::too_many_arguments)]
pub fn cmd_linear_map(
    file: &Path,
    scenario: &str,
    thickness: &str,
    mach: &str,
    frozen_gravity: bool,
    common: &Common,
    cache_dir: Option<&Path>,
    out: &Path,
    term: Terminal,
) -> u8 {
    let format = common.output.format;
    let (ts, ms) = match super::analyze::map_ranges(thickness, mach, None, format, term) {
        Ok((t, m, _)) => (t, m),
        Err(code) => return code,
    };
    let (thickness_m, ms) = (ts.values(), ms.values());
    let started = std::time::Instant::now();
    let load = |t: f64| {
        let mut sets = common.sets.clone();
        // Rust's shortest round-trip form: the override is the grid value to the last bit.
        sets.push(format!("fins.thickness={t} m"));
        load_variant(file, scenario, &sets, cache_dir)
    };
    let options = LineariseOptions {
        gravity_follows_attitude: !frozen_gravity,
        ..LineariseOptions::default()
    };
    let result = match linear_map(&thickness_m, &ms, load, options) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: linear map failed: {e}");
            return EXIT_DIAGNOSTICS;
        }
    };
    if let Err(e) = std::fs::create_dir_all(out).and_then(|_| {
        result
            .map
            .write_csv_file(&out.join("map.csv"), "thickness_m", "mach")
    }) {
        eprintln!(
            "error: cannot write `{}`: {e}",
            out.join("map.csv").display()
        );
        return EXIT_USAGE;
    }
    let unstable = result
        .map
        .class
        .iter()
        .filter(|c| c.name() != "stable")
        .count();
    let drifting = result
        .map
        .flight_path_sigma
        .iter()
        .filter(|x| **x > 0.0)
        .count();
    match common.output.format {
        Format::Human => eprintln!(
            "{} x {} points ({} unstable, {} with a growing flight-path root, {} without trim) at {:.0} m in {:.2} s -> {}",
            thickness_m.len(),
            ms.len(),
            unstable,
            drifting,
            result.trim_failures.len(),
            result.altitude,
            started.elapsed().as_secs_f64(),
            out.join("map.csv").display()
        ),
        Format::Json => outln!(
            "{}",
            serde_json::to_string_pretty(&result).unwrap_or_default()
        ),
    }
    EXIT_OK
}
