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
use crate::analysis::planar::{
    self, Altitude, PlanarAnalysis, PlanarError, PlanarKind, PlanarVehicle, Speed,
};
use crate::analysis::tn4197::{Tn4197Fin, Tn4197Form};
use crate::check::cli_values::{self, CliValueError, QuantityRange};
use crate::check::ir::{InitialPosition, InitialVelocity, Scenario};
use crate::diagnostics::Diagnostic;
use crate::syntax::SourceMap;
use crate::units::Dim;

use super::compile::compile_cached;
use super::{
    CacheArgs, Common, EXIT_DIAGNOSTICS, EXIT_OK, EXIT_USAGE, Format, Terminal, emit, load_program,
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
    Linear(super::Analyze),
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
        AnalyzeCommand::Linear(a) => super::cmd_analyze_linear(a, term),
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

/// A planar error as a diagnostic pointing at the scenario.
fn planar_diagnostic(e: &PlanarError, sc: &Scenario) -> Diagnostic {
    match e {
        PlanarError::NoFins { .. } => Diagnostic::error("analysis::planar::no_fins", e.to_string())
            .label(sc.vehicle.span, "this vehicle has no `fins` block"),
        PlanarError::NoEquilibrium { .. } => {
            Diagnostic::error("analysis::planar::no_equilibrium", e.to_string())
                .label(sc.initial.span, "at this initial speed")
                .with_help(
                    "the unpinned model (6.2) flies at terminal velocity: drag must equal weight somewhere between -0.5 km and 86 km at this speed (drag too small: a higher speed; too large: a lower one); the pinned model has no such condition",
                )
        }
        _ => Diagnostic::error("analysis::planar::failed", e.to_string())
            .label(sc.name.span, "while analysing this scenario"),
    }
}

/// Initial altitude (m) and airspeed (m/s) of a scenario.
fn initial_condition(sc: &Scenario, v: &PlanarVehicle) -> Result<(f64, f64), PlanarError> {
    let h = match &sc.initial.position {
        InitialPosition::Altitude(h) => h.value,
        InitialPosition::Inertial(p) => -p.value[2],
    };
    let speed = match &sc.initial.velocity {
        InitialVelocity::Body(vb) => vb.value.iter().map(|x| x * x).sum::<f64>().sqrt(),
        InitialVelocity::Mach(m) => m.value * v.condition_at_speed(h, 1.0)?.speed_of_sound,
    };
    Ok((h, speed))
}

fn analyse_scenario(l: &Loaded, kind: PlanarKind) -> Result<PlanarAnalysis, PlanarError> {
    analyse_at_initial_condition(&l.scenario, &l.vehicle, kind)
}

/// The planar analysis of `kind` at the scenario's initial speed and altitude (the unpinned
/// model at its equilibrium altitude for that speed), with the declared fin thickness; used
/// by `analyze planar` and by sweeps with `analysis = planar_pinned | planar_unpinned`.
pub fn analyse_at_initial_condition(
    scenario: &Scenario,
    v: &PlanarVehicle,
    kind: PlanarKind,
) -> Result<PlanarAnalysis, PlanarError> {
    let t = v.fins.declared_thickness;
    let (h, speed) = initial_condition(scenario, v)?;
    let h = match kind {
        PlanarKind::Pinned => h,
        PlanarKind::Unpinned => {
            let mp = v.mass_properties(t)?;
            planar::equilibrium_altitude(v, mp.mass, Speed::Airspeed(speed))?
        }
    };
    let c = v.condition_at_speed(h, speed)?;
    planar::analyse(planar::parameters(v, kind, t, c)?)
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

/// The TN 4197 fin of the analysed vehicle at the analysis' fin thickness.
fn tn4197_fin(v: &PlanarVehicle, r: &PlanarAnalysis) -> Tn4197Fin {
    let f = &v.fins;
    Tn4197Fin {
        shear_modulus: f.shear_modulus(),
        span: f.span,
        root_chord: f.root_chord,
        tip_chord: f.tip_chord,
        thickness: r.parameters.thickness,
        tip_le_offset: f.tip_le_offset,
    }
}

/// The TN 4197 flutter Mach and speed at the analysis' condition in the three published
/// forms (see [`crate::analysis::tn4197`]).
fn tn4197_json(v: &PlanarVehicle, r: &PlanarAnalysis) -> serde_json::Value {
    let fin = tn4197_fin(v, r);
    let c = &r.parameters.condition;
    let one = |form: Tn4197Form| {
        serde_json::json!({
            "form": form,
            "flutter_mach": fin.flutter_mach_in(form, c.pressure),
            "flutter_speed_m_s": fin.flutter_speed_in(form, c.pressure, c.speed_of_sound),
        })
    };
    let mut j = serde_json::json!({
        "shear_modulus_pa": fin.shear_modulus,
        "aspect_ratio": fin.aspect_ratio(),
        "thickness_ratio": fin.thickness / fin.root_chord,
        "thickness_ratio_chord": "root",
        "epsilon": fin.epsilon(),
        "pressure_pa": c.pressure,
    });
    for form in Tn4197Form::ALL {
        j[form.key()] = one(form);
    }
    j
}

/// The human report of one analysis.
pub fn analysis_text(v: &PlanarVehicle, r: &PlanarAnalysis) -> String {
    let p = &r.parameters;
    let c = &p.condition;
    let mp = &p.mass_properties;
    let f = &v.fins;
    let mut s = String::new();
    let opt = |x: Option<f64>| {
        x.map_or("none (body load is a couple)".to_string(), |x| {
            format!("{x:.6} m")
        })
    };
    let _ = writeln!(
        s,
        "planar {} model (thesis {}), vehicle {}",
        p.kind.name(),
        if p.kind == PlanarKind::Pinned {
            "6.1"
        } else {
            "6.2"
        },
        v.name
    );
    let _ = writeln!(s, "flight condition");
    let _ = writeln!(s, "  altitude            {:.3} m", c.altitude);
    let _ = writeln!(
        s,
        "  airspeed V          {:.4} m/s   Mach {:.5}",
        c.speed, c.mach
    );
    let _ = writeln!(
        s,
        "  density             {:.6e} kg/m^3   pressure {:.6e} Pa   a {:.4} m/s",
        c.density, c.pressure, c.speed_of_sound
    );
    let _ = writeln!(
        s,
        "  dynamic pressure q  {:.6e} Pa   g {:.5} m/s^2",
        c.dynamic_pressure, c.gravity
    );
    let _ = writeln!(s, "vehicle (fin thickness t = {:.4e} m)", p.thickness);
    let _ = writeln!(
        s,
        "  mass m              {:.6} kg   weight W {:.6e} N",
        mp.mass, p.weight
    );
    let _ = writeln!(
        s,
        "  centre of mass x    {:.6} m   pitch inertia J {:.6e} kg m^2",
        mp.x_cg, mp.inertia
    );
    let _ = writeln!(
        s,
        "  fins                {} (pitch-plane n_eff {:.4}), span L {:.5} m, mean chord c {:.5} m, area S_f {:.6e} m^2",
        f.count, p.pitch_plane_fins, f.span, f.mean_chord, p.fin_area
    );
    let _ = writeln!(
        s,
        "  fin material        E {:.4e} Pa, rho {:.1} kg/m^3, nu {:.4}",
        f.youngs_modulus, f.density, f.poisson
    );
    let _ = writeln!(
        s,
        "  I = c t^3/12        {:.6e} m^4 (6.11)",
        p.fin_bending_inertia
    );
    let _ = writeln!(
        s,
        "  k = n_eff 24EI/L^3  {:.6e} N/m (6.10)",
        p.fin_stiffness
    );
    let _ = writeln!(s, "  m_f                 {:.6e} kg", p.fin_mass);
    let _ = writeln!(s, "geometry");
    let _ = writeln!(
        s,
        "  S {:.6e} m^2, b {:.5} m",
        p.reference_area, p.reference_length
    );
    let _ = writeln!(s, "  body c.p. x         {}", opt(p.x_cp_body));
    let _ = writeln!(s, "  a (forward of c.g.) {}", opt(p.a));
    let _ = writeln!(
        s,
        "  fin c.p. x          {:.6} m   d (aft of c.g.) {:.6} m",
        p.x_cp_fin, p.d
    );
    let ae = &p.aero;
    let _ = writeln!(s, "coefficients (runtime tables, alpha = 0, per rad)");
    let _ = writeln!(
        s,
        "  body C_Nalpha {:.6}  C_Malpha(ref) {:.6}  C_A {:.6}  dC_A/dMach {:.6}  C_Aalpha {:.6}",
        ae.cn_alpha_body, ae.cm_alpha_body, ae.ca_body, ae.ca_mach_body, ae.ca_alpha_body
    );
    let _ = writeln!(
        s,
        "  fin  C_Nalpha {:.6}  C_A {:.6}  dC_A/dMach {:.6}  C_Aalpha {:.6}  x_cp {:.6} m aft of root LE (one fin, on S)",
        ae.cn_alpha_fin, ae.ca_fin, ae.ca_mach_fin, ae.ca_alpha_fin, ae.x_cp_fin
    );
    let _ = writeln!(
        s,
        "  rate derivatives    C_Nalpha-dot {:.4}  C_Malpha-dot {:.4}",
        p.cn_alpha_dot, p.cm_alpha_dot
    );
    let _ = writeln!(s, "loads per unit state");
    let _ = writeln!(
        s,
        "  P_b = qS C_Nalpha,B {:.6e} N/rad   P_f {:.6e} N/rad   M_b {:.6e} N m/rad",
        p.body_lift, p.fin_lift, p.body_moment
    );
    let _ = writeln!(
        s,
        "  A_f0 {:.6e} N   A_0 {:.6e} N   axial damping {:.6e} N s/m",
        p.fin_axial_force, p.axial_force, p.axial_damping
    );
    let matrix = |s: &mut String, name: &str, rows: &[Vec<f64>]| {
        let _ = writeln!(s, "{name}");
        for row in rows {
            let cells: Vec<String> = row.iter().map(|x| format!("{x:>14.6e}")).collect();
            let _ = writeln!(s, "  [{}]", cells.join(" "));
        }
    };
    let _ = writeln!(
        s,
        "coordinates x = ({})   state X = ({})",
        r.coordinates.join(", "),
        r.state.join(", ")
    );
    matrix(&mut s, "M (6.7/6.27)", &r.mass);
    matrix(&mut s, "C (6.8/6.29)", &r.damping);
    matrix(&mut s, "K (6.9/6.28)", &r.stiffness);
    matrix(&mut s, "A (6.13)", &r.state_matrix);
    let _ = writeln!(s, "eigenvalues");
    let mut ev = r.eigenvalues.clone();
    ev.sort_by(|a, b| b.re.total_cmp(&a.re).then(b.im.total_cmp(&a.im)));
    for e in &ev {
        let _ = writeln!(
            s,
            "  {:>14.6e} {:+14.6e} i   ({:.4} Hz)",
            e.re,
            e.im,
            e.im.abs() / (2.0 * std::f64::consts::PI)
        );
    }
    let vd = &r.verdict;
    let _ = writeln!(
        s,
        "sigma_d {:.6e} 1/s   omega_d {:.6e} rad/s ({:.4} Hz)   {}",
        vd.sigma_d,
        vd.omega_d,
        vd.omega_d / (2.0 * std::f64::consts::PI),
        vd.class.name()
    );
    let fin = tn4197_fin(v, r);
    let _ = writeln!(
        s,
        "NACA TN 4197 flutter boundary (G {:.4e} Pa, A = b^2/S {:.5}, t/c_r {:.5e} (root chord), eps {:.5}, p {:.6e} Pa)",
        fin.shear_modulus,
        fin.aspect_ratio(),
        fin.thickness / fin.root_chord,
        fin.epsilon(),
        c.pressure
    );
    for form in Tn4197Form::ALL {
        let _ = writeln!(
            s,
            "  {:<50} flutter Mach {:.5}   V_f {:.3} m/s",
            form.name(),
            fin.flutter_mach_in(form, c.pressure),
            fin.flutter_speed_in(form, c.pressure, c.speed_of_sound)
        );
    }
    s
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
