//! `flexflight analyze linear` and `flexflight analyze linear-map`: the linearised 3-D model
//! of a scenario ([`crate::analysis::linear`]) and its fin thickness x Mach map.

use std::fmt::Write as _;
use std::path::Path;

use crate::analysis::linear::{LinearAnalysis, Variant, analyse, linear_map};
use crate::analysis::linearise::LineariseOptions;
use crate::artifact::Cache;
use crate::check::{DiskLoader, check_files};
use crate::diagnostics::{self, RenderOptions};
use crate::structure::compile::{CompiledVehicle, compile};

use super::compile::{cache_key, compile_cached};
use super::{Common, EXIT_DIAGNOSTICS, EXIT_OK, EXIT_USAGE, Format, Terminal, load_program};

/// How many participating states are listed per root.
const TOP_STATES: usize = 3;

/// Parses `A:B:N` into `N` evenly spaced values from `A` to `B` (`N >= 1`; `N = 1` gives `A`).
pub fn parse_range(s: &str) -> Result<Vec<f64>, String> {
    let parts: Vec<&str> = s.split(':').collect();
    let [a, b, n] = parts.as_slice() else {
        return Err(format!("`{s}` is not of the form A:B:N"));
    };
    let num = |t: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("`{t}` in `{s}` is not a finite number"))
    };
    let (a, b) = (num(a)?, num(b)?);
    let n: usize = n
        .trim()
        .parse()
        .map_err(|_| format!("`{n}` in `{s}` is not a whole number of points"))?;
    match n {
        0 => Err(format!("`{s}` asks for no points")),
        1 => Ok(vec![a]),
        _ => Ok((0..n)
            .map(|k| a + (b - a) * k as f64 / (n - 1) as f64)
            .collect()),
    }
}

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
        Format::Human => print!("{}", report_text(&variant, &result)),
        Format::Json => {
            let json = serde_json::json!({
                "scenario": scenario,
                "vehicle": variant.plan.vehicle,
                "mode_names": variant.plan.mode_names,
                "options": options,
                "analysis": result,
            });
            println!(
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
            if root.neutral { "  (neutral)" } else { "" }
        );
    }
    s
}

/// `flexflight analyze linear-map`: fin thickness (mm) x Mach, `DIR/map.csv`.
pub fn cmd_linear_map(
    file: &Path,
    scenario: &str,
    thickness_mm: &str,
    mach: &str,
    common: &Common,
    cache_dir: Option<&Path>,
    out: &Path,
) -> u8 {
    let (ts, ms) = match (parse_range(thickness_mm), parse_range(mach)) {
        (Ok(t), Ok(m)) => (t, m),
        (Err(e), _) => {
            eprintln!("error: --thickness: {e}");
            return EXIT_USAGE;
        }
        (_, Err(e)) => {
            eprintln!("error: --mach: {e}");
            return EXIT_USAGE;
        }
    };
    if let Some(t) = ts.iter().find(|t| **t <= 0.0) {
        eprintln!("error: --thickness: {t} mm is not a positive thickness");
        return EXIT_USAGE;
    }
    if let Some(m) = ms.iter().find(|m| **m <= 0.0) {
        eprintln!("error: --mach: {m} is not a positive Mach number");
        return EXIT_USAGE;
    }
    let thickness_m: Vec<f64> = ts.iter().map(|t| t * 1e-3).collect();
    let started = std::time::Instant::now();
    let load = |t: f64| {
        let mut sets = common.sets.clone();
        sets.push(format!("fins.thickness={} mm", t * 1e3));
        load_variant(file, scenario, &sets, cache_dir)
    };
    let result = match linear_map(&thickness_m, &ms, load, LineariseOptions::default()) {
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
    match common.output.format {
        Format::Human => eprintln!(
            "{} x {} points ({} unstable, {} without trim) at {:.0} m in {:.2} s -> {}",
            ts.len(),
            ms.len(),
            unstable,
            result.trim_failures.len(),
            result.altitude,
            started.elapsed().as_secs_f64(),
            out.join("map.csv").display()
        ),
        Format::Json => println!(
            "{}",
            serde_json::to_string_pretty(&result).unwrap_or_default()
        ),
    }
    EXIT_OK
}

#[cfg(test)]
mod tests {
    use super::parse_range;

    #[test]
    fn ranges_are_inclusive_and_checked() {
        assert_eq!(parse_range("0.3:1.0:8").unwrap().len(), 8);
        let r = parse_range("0.5:1.5:3").unwrap();
        assert_eq!(r, vec![0.5, 1.0, 1.5]);
        assert_eq!(parse_range("2:9:1").unwrap(), vec![2.0]);
        for bad in ["1:2", "1:2:0", "a:2:3", "1:2:x", "1:inf:3", "1:2:3:4"] {
            assert!(parse_range(bad).is_err(), "{bad}");
        }
    }
}
