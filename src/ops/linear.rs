//! The linearised 3-D model of a scenario ([`crate::analysis::linear`]): a scenario's variant
//! (compiled and planned through the cache) and the human report of its roots.

use std::fmt::Write as _;
use std::path::Path;

use crate::analysis::linear::{LinearAnalysis, Variant};
use crate::analysis::roots::RootKind;
use crate::artifact::Cache;
use crate::check::{DiskLoader, check_files, ir};
use crate::diagnostics::{self, RenderOptions};
use crate::structure::compile::{CompiledVehicle, compile};

use super::compile::cache_key;

/// How many participating states are listed per root.
pub const TOP_STATES: usize = 3;

/// Checks `file` with the `sets` overrides, compiles the scenario's vehicle through the
/// artifact cache and plans the scenario (errors come back rendered as text, cache warnings
/// go to `warn`). The map calls this once per fin thickness.
pub fn load_variant(
    file: &Path,
    scenario: &str,
    sets: &[String],
    cache_dir: Option<&Path>,
    warn: &mut dyn FnMut(String),
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
    variant_for(sc, cache_dir, warn)
}

/// Compiles the checked scenario `sc`'s vehicle through the artifact cache and plans `sc`
/// (errors as text): [`load_variant`] after the check, and `analyze flutter`'s free-vehicle
/// `--critical-thickness` once per thickness.
pub fn variant_for(
    sc: ir::Scenario,
    cache_dir: Option<&Path>,
    warn: &mut dyn FnMut(String),
) -> Result<Variant, String> {
    let key = cache_key(&sc.vehicle).map_err(|e| format!("cannot read an FE file: {e}"))?;
    let cache = Cache::resolve(cache_dir);
    let (art, _) = cache
        .get_or_build(&key, || compile(&sc.vehicle).map(|(c, _)| c))
        .map_err(|e| e.to_string())?;
    let compiled = rkyv::deserialize::<CompiledVehicle, rkyv::rancor::Error>(art.get())
        .map_err(|e| format!("artifact could not be read back: {e}"))?;
    let (plan, _) = super::compile::plan_cached(&sc, &compiled, &key, &cache, warn)
        .map_err(|e| e.to_string())?;
    Ok(Variant {
        plan,
        scenario: sc,
        compiled,
    })
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

/// A scenario trimmed and linearised: the variant (compiled vehicle, plan), the options and
/// the analysis.
pub struct Linearised {
    pub variant: Variant,
    pub options: crate::analysis::linearise::LineariseOptions,
    pub analysis: LinearAnalysis,
}

/// `analyze linear` of scenario `scenario` of `checked`: the vehicle compiled and the
/// scenario planned through the cache in `cache_dir` (cache warnings to `warn`), trimmed and
/// linearised ([`crate::analysis::linear::analyse`]); gravity rotates with the attitude
/// unless `frozen_gravity`. The operation of the command line and the Python package.
pub fn linearise(
    checked: &mut crate::check::Checked,
    scenario: &str,
    frozen_gravity: bool,
    cache_dir: Option<&Path>,
    warn: &mut dyn FnMut(String),
) -> Result<Linearised, super::OpsError> {
    use crate::analysis::linearise::LineariseOptions;
    let Some(sc) = checked.program.scenario(scenario).cloned() else {
        return Err(super::unknown_scenario(&checked.program, scenario));
    };
    let outcome = super::compile::compile_cached(checked, &sc.vehicle, cache_dir)?;
    let cache = Cache::resolve(cache_dir);
    let (plan, _) = super::compile::plan_cached(&sc, &outcome.compiled, &outcome.key, &cache, warn)
        .map_err(|e| super::OpsError::Diagnostics(vec![super::run::plan_diagnostic(&e, &sc)]))?;
    let variant = Variant {
        plan,
        scenario: sc,
        compiled: outcome.compiled,
    };
    let options = LineariseOptions {
        gravity_follows_attitude: !frozen_gravity,
        ..LineariseOptions::default()
    };
    let analysis = crate::analysis::linear::analyse(&variant, options).map_err(|e| {
        super::OpsError::Coded {
            code: "analysis::linear::failed",
            message: format!("linearisation failed: {e}"),
            input: true,
        }
    })?;
    Ok(Linearised {
        variant,
        options,
        analysis,
    })
}

/// `analyze linear --format json`: the scenario, vehicle, mode names, options and analysis.
pub fn to_json(r: &Linearised) -> serde_json::Value {
    serde_json::json!({
        "scenario": r.variant.scenario.name.value,
        "vehicle": r.variant.plan.vehicle,
        "mode_names": r.variant.plan.mode_names,
        "options": r.options,
        "analysis": r.analysis,
    })
}

/// [`linearise`] as `analyze linear --format json` prints it.
pub fn linear_json(
    checked: &mut crate::check::Checked,
    scenario: &str,
    frozen_gravity: bool,
    cache_dir: Option<&Path>,
    warn: &mut dyn FnMut(String),
) -> Result<serde_json::Value, super::OpsError> {
    linearise(checked, scenario, frozen_gravity, cache_dir, warn).map(|r| to_json(&r))
}
