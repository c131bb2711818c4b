//! `analyze flutter FILE --scenario NAME` of a wind-tunnel scenario: render the tunnel's p-k
//! sweep ([`crate::ops::tunnel`]).

use crate::analysis::flutter::wing::WingError;
use crate::check::ir;
use crate::diagnostics::Diagnostic;
use crate::ops::tunnel::{report_text, solve_tunnel, summary_json, tunnel_code, write_outputs};

use super::flutter::FlutterArgs;
use super::{EXIT_DIAGNOSTICS, EXIT_OK, EXIT_USAGE, Format, Terminal, emit};

pub fn cmd_tunnel(
    a: &FlutterArgs,
    t: &ir::TunnelTest,
    mach: Option<f64>,
    speeds: Option<Vec<f64>>,
    sources: &crate::syntax::SourceMap,
    term: Terminal,
) -> u8 {
    let format = a.common.output.format;
    let refused: Vec<&str> = [
        (a.altitude.is_some(), "--altitude"),
        (a.match_point, "--match-point"),
        (a.critical_thickness.is_some(), "--critical-thickness"),
        (a.target_speed.is_some(), "--target-speed"),
    ]
    .into_iter()
    .filter_map(|(given, flag)| given.then_some(flag))
    .collect();
    if !refused.is_empty() {
        eprintln!(
            "error: scenario `{}` tests a fixture in a wind tunnel, whose `tunnel` block sets the Mach number and the air density: {} do not apply (change the tunnel with --set tunnel.mach=... or --speeds)",
            t.name.value,
            refused.join(", ")
        );
        return EXIT_USAGE;
    }
    let mach = mach.unwrap_or(t.mach.value);
    let speeds = speeds.unwrap_or_else(|| t.speeds.value.clone());
    let n_modes = a.modes.unwrap_or(t.fixture.modes.value);
    let r = match solve_tunnel(t, mach, &speeds, n_modes, a.aero) {
        Ok(r) => r,
        Err(e) => {
            let mut d = Diagnostic::error(tunnel_code(&e), format!("flutter: {e}"))
                .label(t.name.span, "in this scenario");
            if matches!(e, WingError::Panel(_)) {
                d = d.with_help(
                    "a fixture's surface has subsonic panels only: the vortex lattice to Mach 0.9, the doublet lattice (--aero doublet-lattice) to Mach 0.95; piston theory is not wired for fixtures",
                );
            }
            emit(&[d], sources, format, term);
            return EXIT_DIAGNOSTICS;
        }
    };
    if let Some(out) = &a.out {
        if let Err(e) = write_outputs(out, &r) {
            eprintln!("error: cannot write `{}`: {e}", out.display());
            return EXIT_USAGE;
        }
    }
    match format {
        Format::Human => out!("{}", report_text(&r)),
        Format::Json => outln!(
            "{}",
            serde_json::to_string_pretty(&summary_json(&r)).unwrap_or_default()
        ),
    }
    EXIT_OK
}
