//! `flexflight analyze`: the planar eigen-stability models of thesis ch. 6 and their
//! stability maps.
//!
//! - `analyze planar --pinned|--unpinned FILE --scenario NAME [--format json]`: every
//!   parameter used, M, C, K, A, the eigenvalues and the verdict at the scenario's initial
//!   condition (the unpinned model at the altitude where drag balances weight at the
//!   scenario's speed).
//! - `analyze map --planar --pinned|--unpinned FILE --scenario NAME --thickness A:B:N
//!   --mach A:B:N [--altitude H|equilibrium] --out DIR`: `DIR/map.csv` and
//!   `DIR/boundary.csv` (see [`crate::analysis::map`]).
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use clap::{ArgGroup, Args, Subcommand};

use crate::analysis::map::{BoundaryMach, CriticalThickness, planar_map};
use crate::analysis::planar::{Altitude, PlanarAnalysis, PlanarError, PlanarKind, PlanarVehicle};
use crate::check::cli_values::{self, CliValueError, QuantityRange};
use crate::check::ir::Scenario;
use crate::diagnostics::Diagnostic;
use crate::syntax::SourceMap;
use crate::units::Dim;

use super::compile::compile_cached;
use super::{
    CacheArgs, Common, EXIT_DIAGNOSTICS, EXIT_OK, EXIT_USAGE, Format, Terminal, emit, load_program,
};
use crate::ops::planar::{
    analyse_at_initial_condition, analysis_text, initial_condition, planar_diagnostic, tn4197_json,
};

/// The analyses.
#[derive(Subcommand, Debug)]
pub enum AnalyzeCommand {
    /// Planar eigen-stability analysis (thesis 6.1 pinned, 6.2 unpinned) at a scenario's
    /// initial condition: prints every parameter, M, C, K, A and the eigenvalues.
    Planar(PlanarArgs),
    /// A stability map over fin thickness x Mach: writes DIR/map.csv and DIR/boundary.csv.
    Map(MapArgs),
    /// The p-k flutter solution of the fin clamped at its root at a scenario's altitude and
    /// Mach: V-g / V-f (DIR/vg.csv), flutter and divergence points, TN 4197 alongside.
    Flutter(super::flutter::FlutterArgs),
    /// The linearised 3-D model (`linear`, `linear-map`).
    #[command(flatten)]
    Linear(super::linear::Analyze),
}

/// Which planar model.
#[derive(Args, Debug, Clone)]
#[command(group(ArgGroup::new("model").required(true).args(["pinned", "unpinned"])))]
pub struct ModelChoice {
    /// The pinned (wind-tunnel) model of thesis 6.1.
    #[arg(long)]
    pub pinned: bool,
    /// The unpinned (terminal-velocity free fall) model of thesis 6.2.
    #[arg(long)]
    pub unpinned: bool,
}

impl ModelChoice {
    fn kind(&self) -> PlanarKind {
        if self.unpinned {
            PlanarKind::Unpinned
        } else {
            PlanarKind::Pinned
        }
    }
}

#[derive(Args, Debug)]
pub struct PlanarArgs {
    #[command(flatten)]
    pub model: ModelChoice,
    pub file: PathBuf,
    #[arg(long)]
    pub scenario: String,
    #[command(flatten)]
    pub common: Common,
    #[command(flatten)]
    pub cache: CacheArgs,
}

#[derive(Args, Debug)]
pub struct MapArgs {
    /// Use the planar models (the only kind of map this command draws).
    #[arg(long)]
    pub planar: bool,
    #[command(flatten)]
    pub model: ModelChoice,
    pub file: PathBuf,
    #[arg(long)]
    pub scenario: String,
    /// Fin thickness grid START:STOP:COUNT, each end with a length unit (0.3mm:1.2mm:10).
    #[arg(long, value_name = "START:STOP:COUNT")]
    pub thickness: String,
    /// Mach grid START:STOP:COUNT (dimensionless: 0.5:2.5:21).
    #[arg(long, value_name = "START:STOP:COUNT")]
    pub mach: String,
    /// Altitude with a length unit (5km), or `equilibrium` (the terminal-velocity altitude
    /// of each point). Default: the scenario's altitude for --pinned, equilibrium for
    /// --unpinned.
    #[arg(long)]
    pub altitude: Option<String>,
    /// Output directory (created if needed).
    #[arg(long)]
    pub out: PathBuf,
    #[command(flatten)]
    pub common: Common,
    #[command(flatten)]
    pub cache: CacheArgs,
}

/// Run an `analyze` subcommand.
pub fn cmd_analyze(cmd: &AnalyzeCommand, term: Terminal) -> u8 {
    match cmd {
        AnalyzeCommand::Planar(a) => cmd_planar(a, term),
        AnalyzeCommand::Map(a) => cmd_map(a, term),
        AnalyzeCommand::Flutter(a) => super::flutter::cmd_flutter(a, term),
        AnalyzeCommand::Linear(a) => super::linear::cmd_analyze_linear(a, term),
    }
}

/// The loaded scenario, its planar vehicle and the sources (for diagnostics).
struct Loaded {
    scenario: Scenario,
    vehicle: PlanarVehicle,
    sources: SourceMap,
}

fn load(
    file: &Path,
    scenario: &str,
    common: &Common,
    cache: &CacheArgs,
    term: Terminal,
) -> Result<Loaded, u8> {
    let format = common.output.format;
    let mut checked = load_program(&[file.to_path_buf()], common, term)?;
    let Some(sc) = checked.program.scenario(scenario).cloned() else {
        return Err(super::unknown_scenario(&checked.program, scenario));
    };
    if sc.vehicle.fins.is_none() {
        let d = Diagnostic::error(
            "analysis::planar::no_fins",
            format!(
                "vehicle `{}` has no fins: the planar stability models need a `fins` block",
                sc.vehicle.name.value
            ),
        )
        .label(sc.vehicle.span, "this vehicle has no `fins` block")
        .with_help("add a `fins { ... }` block, or analyse a finned vehicle");
        emit(&[d], &checked.sources, format, term);
        return Err(EXIT_DIAGNOSTICS);
    }
    let outcome = compile_cached(
        &mut checked,
        &sc.vehicle,
        cache.cache_dir.as_deref(),
        format,
        term,
    )?;
    match PlanarVehicle::new(&sc.vehicle, &outcome.compiled) {
        Ok(vehicle) => Ok(Loaded {
            scenario: sc,
            vehicle,
            sources: checked.sources,
        }),
        Err(e) => {
            let d = planar_diagnostic(&e, &sc);
            emit(&[d], &checked.sources, format, term);
            Err(EXIT_DIAGNOSTICS)
        }
    }
}

fn analyse_scenario(l: &Loaded, kind: PlanarKind) -> Result<PlanarAnalysis, PlanarError> {
    analyse_at_initial_condition(&l.scenario, &l.vehicle, kind)
}

fn cmd_planar(a: &PlanarArgs, term: Terminal) -> u8 {
    let format = a.common.output.format;
    let l = match load(&a.file, &a.scenario, &a.common, &a.cache, term) {
        Ok(l) => l,
        Err(code) => return code,
    };
    match analyse_scenario(&l, a.model.kind()) {
        Ok(r) => {
            match format {
                Format::Human => out!("{}", analysis_text(&l.vehicle, &r)),
                Format::Json => outln!(
                    "{}",
                    serde_json::to_string_pretty(&serde_json::json!({
                        "vehicle": l.vehicle.name,
                        "scenario": l.scenario.name.value,
                        "fins": l.vehicle.fins,
                        "analysis": r,
                        "tn4197": tn4197_json(&l.vehicle, &r),
                    }))
                    .unwrap_or_default()
                ),
            }
            EXIT_OK
        }
        Err(e) => {
            emit(
                &[planar_diagnostic(&e, &l.scenario)],
                &l.sources,
                format,
                term,
            );
            EXIT_DIAGNOSTICS
        }
    }
}

fn usage(msg: String, format: Format, term: Terminal) -> u8 {
    let d = Diagnostic::error("analysis::range", msg);
    emit(&[d], &SourceMap::default(), format, term);
    EXIT_USAGE
}

/// A refused command-line value: its diagnostics (spans into the flag's text), exit 2.
pub(crate) fn refused(e: CliValueError, format: Format, term: Terminal) -> u8 {
    emit(&e.diagnostics, &e.sources, format, term);
    EXIT_USAGE
}

/// The thickness (length) and Mach (dimensionless) ranges of a map and an optional
/// altitude (length), checked like vehicle-file values ([`cli_values::check_range`]);
/// every refused part of every flag is reported, exit 2.
pub(crate) fn map_ranges(
    thickness: &str,
    mach: &str,
    altitude: Option<&str>,
    format: Format,
    term: Terminal,
) -> Result<(QuantityRange, QuantityRange, Option<f64>), u8> {
    let mut c = cli_values::CliChecker::new();
    let t = c.range("--thickness", thickness, Dim::LENGTH);
    let m = c.range("--mach", mach, Dim::NONE);
    let h = altitude.map(|text| c.quantity("--altitude", text, Dim::LENGTH));
    match (c.finish(), t, m) {
        (Ok(()), Some(t), Some(m)) => Ok((t, m, h.flatten())),
        (Err(e), _, _) => Err(refused(e, format, term)),
        _ => Err(EXIT_USAGE),
    }
}

fn cmd_map(a: &MapArgs, term: Terminal) -> u8 {
    let format = a.common.output.format;
    if !a.planar {
        return usage(
            "`analyze map` needs the kind of model: --planar (the only one available)".into(),
            format,
            term,
        );
    }
    let kind = a.model.kind();
    let fixed = a.altitude.as_deref().filter(|t| t.trim() != "equilibrium");
    let (thickness, mach, fixed_altitude) =
        match map_ranges(&a.thickness, &a.mach, fixed, format, term) {
            Ok(r) => r,
            Err(code) => return code,
        };
    let l = match load(&a.file, &a.scenario, &a.common, &a.cache, term) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let altitude = match (a.altitude.as_deref(), fixed_altitude, kind) {
        (Some(_), None, _) | (None, _, PlanarKind::Unpinned) => Altitude::Equilibrium,
        (Some(_), Some(h), PlanarKind::Pinned) => Altitude::Fixed(h),
        (Some(_), Some(_), PlanarKind::Unpinned) => {
            return usage(
                "--altitude: the unpinned model is defined only at its equilibrium altitude (omit --altitude or give `equilibrium`)".into(),
                format,
                term,
            );
        }
        (None, _, PlanarKind::Pinned) => match initial_condition(&l.scenario, &l.vehicle) {
            Ok((h, _)) => Altitude::Fixed(h),
            Err(e) => {
                emit(
                    &[planar_diagnostic(&e, &l.scenario)],
                    &l.sources,
                    format,
                    term,
                );
                return EXIT_DIAGNOSTICS;
            }
        },
    };
    let m = planar_map(
        &l.vehicle,
        kind,
        &thickness.values(),
        &mach.values(),
        altitude,
    );
    if let Err(e) = std::fs::create_dir_all(&a.out) {
        eprintln!("error: cannot create `{}`: {e}", a.out.display());
        return EXIT_USAGE;
    }
    for (name, r) in [
        ("map.csv", m.write_csv(&a.out.join("map.csv"))),
        (
            "boundary.csv",
            m.write_boundary_csv(&a.out.join("boundary.csv")),
        ),
        (
            "critical_thickness.csv",
            m.write_critical_thickness_csv(&a.out.join("critical_thickness.csv")),
        ),
        (
            "overlay_TN_4197.csv",
            m.write_tn4197_overlay(&a.out.join("overlay_TN_4197.csv"), false),
        ),
        (
            "overlay_TN_4197_PoF_615.csv",
            m.write_tn4197_overlay(&a.out.join("overlay_TN_4197_PoF_615.csv"), true),
        ),
    ] {
        if let Err(e) = r {
            eprintln!("error: cannot write `{}`: {e}", a.out.join(name).display());
            return EXIT_USAGE;
        }
    }
    let total = thickness.count * mach.count;
    let failed = m.failures.len();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "planar {} map: {} thickness x {} Mach points, {} without a result",
        kind.name(),
        thickness.count,
        mach.count,
        failed
    );
    let _ = writeln!(
        s,
        "{:>14} {:>16} {:>16} {:>16}",
        "thickness (mm)", "model boundary", "TN 4197 boundary", "PoF 615 boundary"
    );
    let show = |b: BoundaryMach| match b {
        BoundaryMach::Crossing(x) => format!("M {x:.4}"),
        BoundaryMach::BelowRange => "below range".to_string(),
        BoundaryMach::AboveRange => "above range".to_string(),
    };
    for b in m.boundaries() {
        let _ = writeln!(
            s,
            "{:>14.4} {:>16} {:>16} {:>16}",
            b.thickness * 1e3,
            show(b.model),
            show(b.tn4197),
            show(b.tn4197_pof615)
        );
    }
    let _ = writeln!(
        s,
        "{:>8} {:>22} {:>22} {:>22}",
        "Mach", "model t_crit (mm)", "TN 4197 t_crit (mm)", "PoF 615 t_crit (mm)"
    );
    let show_t = |c: CriticalThickness| match c {
        CriticalThickness::Crossing(t) => format!("{:.4}", t * 1e3),
        CriticalThickness::BelowRange => "below range".to_string(),
        CriticalThickness::AboveRange => "above range".to_string(),
    };
    for b in m.mach_boundaries() {
        let _ = writeln!(
            s,
            "{:>8.4} {:>22} {:>22} {:>22}",
            b.mach,
            show_t(b.model),
            show_t(b.tn4197),
            show_t(b.tn4197_pof615)
        );
    }
    let _ = writeln!(
        s,
        "wrote map.csv, boundary.csv, critical_thickness.csv, overlay_TN_4197.csv and overlay_TN_4197_PoF_615.csv in {}",
        a.out.display()
    );
    match format {
        Format::Human => out!("{s}"),
        Format::Json => outln!(
            "{}",
            serde_json::to_string_pretty(&serde_json::json!({
                "kind": kind,
                "points": total,
                "failed": failed,
                "boundaries": m.boundaries(),
                "critical_thickness": m.mach_boundaries(),
                "out": a.out,
            }))
            .unwrap_or_default()
        ),
    }
    if failed == total {
        // Nothing to show: say why (the first failure) and fail.
        if let Some((_, _, msg)) = m.failures.first() {
            let code = if m
                .map
                .class
                .iter()
                .flatten()
                .all(|c| *c == crate::analysis::map::CellClass::NoEquilibrium)
            {
                "analysis::planar::no_equilibrium"
            } else {
                "analysis::planar::failed"
            };
            let d = Diagnostic::error(
                code,
                format!("no point of the map could be analysed: {msg}"),
            )
            .label(l.scenario.name.span, "while mapping this scenario");
            emit(&[d], &l.sources, format, term);
        }
        return EXIT_DIAGNOSTICS;
    }
    EXIT_OK
}
