//! The flutter analyses a user asks for (`flexflight analyze flutter`): the p-k solution of
//! the fin clamped at its root ([`crate::analysis::flutter::fin`]) or of the free flexible
//! vehicle ([`crate::analysis::flutter::vehicle`]) at a flight condition, with the V-g / V-f
//! table, the flutter and divergence points and NACA TN 4197 alongside; the matched point;
//! the critical thickness; and the flutter margin over a flown scenario with its boundary
//! through the artifact cache.

use std::fmt::Write as _;
use std::path::Path;

use crate::aero::atmosphere::{Atmosphere, Standard1976};
use crate::aero::panel::{Lattice, PanelError};
use crate::analysis::flutter::fin::{
    FinAero, FinFlutterError, FinFlutterSettings, FinModes, bridged, chordwise_for,
    clamped_fin_modes, fin_lattice, gaf_table_bridged, solve_with,
};
use crate::analysis::flutter::margin::{
    BOUNDARY_REVISION, Boundary, BoundaryArtifact, BoundaryFin, BoundarySpec, solve_boundary,
    vehicle_spec,
};
use crate::analysis::flutter::pk::{FlutterAnswer, PkSolution};
use crate::analysis::flutter::vehicle::{N_RIGID, VehicleFlutter};
use crate::analysis::linear::Variant;
use crate::analysis::tn4197::{Tn4197Fin, Tn4197Form};
use crate::artifact::{Cache, CacheKey, CacheKeyBuilder, CacheOutcome};
use crate::check::ir;
use crate::diagnostics::Diagnostic;

/// The aerodynamics of the generalised forces.
// `clap::ValueEnum` so that the command line takes it as it is (`--aero`).
#[derive(Copy, Clone, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum AeroChoice {
    /// The harmonic vortex lattice with a convected wake (subsonic, Göthert) and, supersonic,
    /// the same methods as the doublet lattice (`--aero unsteady`, also `vortex-lattice`).
    #[value(alias = "vortex-lattice")]
    Unsteady,
    /// The flight's quasi-steady panel map (no wake lag, no apparent mass).
    QuasiSteady,
    /// The default (issue 33): the doublet-lattice method (subsonic, the compressible
    /// unsteady kernel, its lattice meeting the box rules automatically) and, supersonic, the
    /// Mach box or unsteady piston theory.
    DoubletLattice,
}

impl AeroChoice {
    pub fn model(self) -> FinAero {
        match self {
            AeroChoice::QuasiSteady => FinAero::QuasiSteady,
            AeroChoice::Unsteady => FinAero::Unsteady,
            AeroChoice::DoubletLattice => FinAero::DoubletLattice,
        }
    }
}

/// The flight condition of the analysis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Condition {
    pub altitude: f64,
    pub mach: f64,
    pub density: f64,
    pub speed_of_sound: f64,
    pub pressure: f64,
}

/// A solved fin flutter case.
pub struct FinFlutter {
    pub modes: FinModes,
    pub condition: Condition,
    pub aero: FinAero,
    pub solution: PkSolution,
    /// The speed (and branch) where a p-k iteration failed and the sweep was cut.
    pub truncated: Option<(f64, usize)>,
    /// The result of `--critical-thickness` and its target speed.
    pub critical_thickness: Option<(CriticalThickness, f64)>,
    /// The free vehicle's case (`None`: the clamped fin). Then `modes` is fin 0's spline
    /// container of the vehicle's coordinates (names and vacuum frequencies, rigid at 0).
    pub free_vehicle: Option<FreeVehicle>,
    /// The `--match-point` iteration that chose `condition.mach`.
    pub matched: Option<MatchedPoint>,
    /// The clamped fin's GAF table through the cache (`None`: the free vehicle, or no cache).
    pub gaf_cache: Option<GafCacheUse>,
    /// The transonic bridge of the generalised forces, in the band (`fin::bridged`).
    pub bridge: Option<crate::analysis::flutter::fin::TransonicBridge>,
}

/// How a clamped-fin solution got its GAF table ([`super::gaf_cache`]).
#[derive(Clone, Debug, PartialEq)]
pub struct GafCacheUse {
    /// The entry's key (hex), `None` when no key could be made.
    pub hash: Option<String>,
    /// `hit`, `miss` or `rebuilt`.
    pub outcome: &'static str,
    /// Why the table could not be stored or looked up, if so.
    pub warning: Option<String>,
}

/// A matched flutter point: the Mach numbers tried, in order (the last is the solution's),
/// and the final residual `V_F(M)/a - M`.
#[derive(Clone, Debug, PartialEq)]
pub struct MatchedPoint {
    pub machs: Vec<f64>,
    pub residual: f64,
}

/// Tolerance of the matched point on `V_F(M)/a - M` (Mach units).
pub const MATCH_TOL: f64 = 1e-4;
/// Largest number of p-k solutions of the matched-point iteration.
pub const MATCH_MAX: usize = 12;

/// Why no matched point was found.
#[derive(Clone, Debug, PartialEq)]
pub enum MatchError<E> {
    /// A p-k solution failed (e.g. a transonic Mach: `FinFlutterError::Transonic`).
    Solve(E),
    /// No flutter point in the speed range at this Mach.
    NoFlutter { mach: f64 },
    /// Not converged in [`MATCH_MAX`] solutions; the Mach numbers tried.
    NotConverged { machs: Vec<f64> },
}

/// The matched point of a flutter speed `v_f(M)` at the speed of sound `a`: the root of
/// `g(M) = v_f(M)/a - M` by the secant method, started at `m0` and at the fixed-point step
/// `v_f(m0)/a` (the flutter speed depends weakly on the Mach number through the
/// compressibility of the aerodynamics, so `g` is close to `c - M` and the secant converges
/// in a few solutions). `v_f` returns `None` when the sweep holds no flutter point, with the
/// solution it made (`T`); the last solution is returned with the point.
pub fn match_point<E, T>(
    mut v_f: impl FnMut(f64) -> Result<(Option<f64>, T), E>,
    m0: f64,
    a: f64,
) -> Result<(MatchedPoint, T), MatchError<E>> {
    let mut g = |m: f64| -> Result<(f64, T), MatchError<E>> {
        match v_f(m).map_err(MatchError::Solve)? {
            (Some(v), t) => Ok((v / a - m, t)),
            (None, _) => Err(MatchError::NoFlutter { mach: m }),
        }
    };
    let mut machs = vec![m0];
    let (mut g0, t) = g(m0)?;
    if g0.abs() <= MATCH_TOL {
        return Ok((
            MatchedPoint {
                machs,
                residual: g0,
            },
            t,
        ));
    }
    let mut m1 = m0 + g0;
    loop {
        machs.push(m1);
        let (g1, t) = g(m1)?;
        if g1.abs() <= MATCH_TOL {
            return Ok((
                MatchedPoint {
                    machs,
                    residual: g1,
                },
                t,
            ));
        }
        if machs.len() >= MATCH_MAX || g1 == g0 {
            return Err(MatchError::NotConverged { machs });
        }
        let m2 = m1 - g1 * (m1 - machs[machs.len() - 2]) / (g1 - g0);
        (g0, m1) = (g1, m2.max(0.0));
    }
}

/// What the free-vehicle case adds to the report.
#[derive(Clone, Debug, PartialEq)]
pub struct FreeVehicle {
    pub n_elastic: usize,
    pub fins: usize,
    pub body_aero: bool,
    pub lattice: (usize, usize),
    /// The scenario's speed (the rigid roots are reported at the sweep speed nearest it).
    pub scenario_speed: f64,
}

/// What the thickness root finding found.
#[derive(Clone, Debug, PartialEq)]
pub enum CriticalThickness {
    /// The thickness (m) whose flutter speed is the target, and the evaluations it took.
    Found { thickness: f64, evaluations: usize },
    /// No sign change of `V_F(t) - V_target` over the scanned thicknesses: `V_F` at the
    /// thinnest and thickest (infinite: no flutter up to the largest speed).
    NotBracketed {
        thinnest: (f64, f64),
        thickest: (f64, f64),
    },
}

/// The thickness `t` with `V_F(t) = v0`: the scan `ts` (ascending) finds the first sign
/// change of `V_F - v0` (a fin without flutter in the sweep counts as above), then the
/// Illinois variant of regula falsi (Dowell & Jarratt, BIT 11, 1971) refines it to 1e-6 of
/// the bracket (in thickness) or 1e-9 of `v0` (in speed).
pub fn critical_thickness(
    solve: &dyn Fn(f64) -> Result<f64, FinFlutterError>,
    ts: Vec<f64>,
    v0: f64,
) -> Result<CriticalThickness, FinFlutterError> {
    let mut evaluations = 0usize;
    let mut prev: Option<(f64, f64)> = None;
    let mut bracket = None;
    let mut first = None;
    let mut last = None;
    for &t in &ts {
        evaluations += 1;
        let raw = solve(t)?;
        let g = if raw.is_finite() { raw - v0 } else { v0 };
        first.get_or_insert((t, raw));
        last = Some((t, raw));
        if g == 0.0 {
            return Ok(CriticalThickness::Found {
                thickness: t,
                evaluations,
            });
        }
        if let Some((tp, gp)) = prev {
            if gp < 0.0 && g > 0.0 || gp > 0.0 && g < 0.0 {
                bracket = Some((tp, gp, t, g));
                break;
            }
        }
        prev = Some((t, g));
    }
    let Some((mut a, mut fa, mut b, mut fb)) = bracket else {
        return Ok(CriticalThickness::NotBracketed {
            thinnest: first.unwrap_or((f64::NAN, f64::NAN)),
            thickest: last.unwrap_or((f64::NAN, f64::NAN)),
        });
    };
    let mut f = |t: f64| -> Result<f64, FinFlutterError> {
        evaluations += 1;
        let v = solve(t)?;
        // Finite stand-in for "no flutter": well above the target.
        Ok(if v.is_finite() { v - v0 } else { v0 })
    };
    let width = (b - a).abs();
    let mut side = 0i8;
    for _ in 0..60 {
        let c = (a * fb - b * fa) / (fb - fa);
        let fc = f(c)?;
        if fc.abs() <= 1e-9 * v0 || (b - a).abs() <= 1e-6 * width {
            return Ok(CriticalThickness::Found {
                thickness: c,
                evaluations,
            });
        }
        if (fc < 0.0) == (fb < 0.0) {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        } else {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        }
    }
    Ok(CriticalThickness::Found {
        thickness: 0.5 * (a + b),
        evaluations,
    })
}

pub fn scenario_altitude(sc: &ir::Scenario) -> f64 {
    if let Some(l) = &sc.launch {
        return l.site_altitude.value;
    }
    match &sc.initial.position {
        ir::InitialPosition::Altitude(h) => h.value,
        ir::InitialPosition::Inertial(p) => -p.value[2],
    }
}

pub fn scenario_speed(sc: &ir::Scenario, a: f64) -> f64 {
    match &sc.initial.velocity {
        ir::InitialVelocity::Mach(m) => m.value * a,
        ir::InitialVelocity::Body(v) => {
            let v = v.value;
            (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
        }
    }
}

/// The flutter speed `--critical-thickness` roots: the critical flutter point's, infinite
/// without one; unstable at the lowest speed, that speed (flutter at or below it: a bound,
/// below the target whenever the target is in the sweep).
pub fn flutter_speed_of(r: &FinFlutter) -> f64 {
    match r.solution.answer() {
        FlutterAnswer::Flutter(f) => f.speed,
        FlutterAnswer::Below(v) => v,
        FlutterAnswer::Stable => f64::INFINITY,
    }
}

/// The p-k settings of a sweep over `speeds`: reduced frequencies up to 1.2 times the
/// highest structural frequency `w_max` at the lowest speed (reference semichord `b_ref`),
/// 40 of them; for the unsteady lattice, enough chordwise panels on `layout`'s fin for that
/// reduced frequency (the box-size rule), up to [`MAX_CHORDWISE`] (beyond it the lattice
/// check refuses the case).
pub fn sweep_settings(
    aero: FinAero,
    speeds: &[f64],
    w_max: f64,
    b_ref: f64,
    layout: &FinModes,
) -> FinFlutterSettings {
    let mut settings = FinFlutterSettings {
        aero,
        ..FinFlutterSettings::default()
    };
    let v_min = speeds.iter().copied().fold(f64::INFINITY, f64::min);
    settings.k_max = (1.2 * w_max * b_ref / v_min).max(0.1);
    settings.k_count = 40;
    if aero.is_harmonic() {
        settings.chordwise =
            chordwise_for(layout, settings.k_max, settings.chordwise).min(MAX_CHORDWISE);
    }
    if aero == FinAero::DoubletLattice {
        // The automatic lattice of the doublet lattice: strips for its box aspect ratio
        // (`dlm::spanwise_for`); where none suffice the default 12 stay, and the analysis
        // refuses the wide boxes with its diagnostic.
        settings.spanwise = crate::aero::panel::dlm::spanwise_for(
            &layout.planform,
            settings.chordwise,
            settings.spanwise,
            crate::aero::panel::Spacing::Cosine,
        )
        .unwrap_or(settings.spanwise);
    }
    settings
}

/// The diagnostic of a failed flutter solution, labelled at the scenario; a lattice too
/// coarse for the sweep gets the remedies (`more`: the case's own, e.g. `, use fewer
/// --modes`).
pub fn flutter_diagnostic(e: &FinFlutterError, sc: &ir::Scenario, more: &str) -> Diagnostic {
    let d = Diagnostic::error(flutter_code(e), format!("flutter: {e}"))
        .label(sc.name.span, "in this scenario");
    match e {
        FinFlutterError::Panel(PanelError::TooCoarse { .. }) => d.with_help(format!(
            "the lattice has at most {MAX_CHORDWISE} chordwise panels: raise the lowest speed of --speeds{more}, or --aero quasi-steady"
        )),
        FinFlutterError::WideBoxes { .. } => d.with_help(
            "the chordwise box count follows the box-size rule at the lowest speed: raise the lowest speed of --speeds (fewer, longer boxes), or use the vortex lattice (--aero unsteady)",
        ),
        _ => d,
    }
}

/// The free vehicle's p-k solution at `condition` over `speeds` (the reduced-frequency
/// table and the lattice sized as [`solve_clamped`] does, on the highest vehicle mode).
pub fn solve_free(
    variant: &Variant,
    condition: Condition,
    speeds: &[f64],
    aero: FinAero,
    scenario_speed: f64,
) -> Result<FinFlutter, FinFlutterError> {
    super::sequential_linear_algebra();
    let coords = crate::analysis::flutter::vehicle::vehicle_coordinates(variant)?;
    let w_max = coords.omega_elastic.iter().copied().fold(0.0, f64::max);
    let settings = sweep_settings(aero, speeds, w_max, coords.b_ref(), &coords.fins[0]);
    let VehicleFlutter {
        coordinates,
        solution,
        truncated,
        body_aero,
        lattice,
        vacuum_omega,
        bridge,
    } = crate::analysis::flutter::vehicle::solve_coordinates(
        variant,
        coords,
        condition.mach,
        condition.density,
        condition.altitude,
        condition.speed_of_sound,
        speeds,
        &settings,
        true,
    )?;
    let n_elastic = coordinates.order() - N_RIGID;
    let fins = coordinates.fins.len();
    let mut modes = coordinates
        .fins
        .into_iter()
        .next()
        .ok_or(FinFlutterError::NoFins)?;
    // The report lists the branches (vacuum modes of the free vehicle), not the coordinates.
    modes.names = solution.names.clone();
    modes.omega = vacuum_omega;
    Ok(FinFlutter {
        modes,
        condition,
        aero,
        solution,
        truncated,
        critical_thickness: None,
        matched: None,
        gaf_cache: None,
        bridge,
        free_vehicle: Some(FreeVehicle {
            n_elastic,
            fins,
            body_aero,
            lattice,
            scenario_speed,
        }),
    })
}

/// `hit`, `miss` or `rebuilt`.
pub fn outcome_name(o: &CacheOutcome) -> &'static str {
    match o {
        CacheOutcome::Hit => "hit",
        CacheOutcome::Miss => "miss",
        CacheOutcome::Rebuilt { .. } => "rebuilt",
    }
}

pub fn flutter_code(e: &FinFlutterError) -> &'static str {
    match e {
        FinFlutterError::NotGenerated => "analysis::flutter::not_generated",
        FinFlutterError::NoFins => "analysis::flutter::no_fins",
        FinFlutterError::Panel(PanelError::TooCoarse { .. }) => "analysis::flutter::too_few_panels",
        FinFlutterError::WideBoxes { .. }
        | FinFlutterError::Panel(PanelError::WideBoxes { .. }) => "analysis::flutter::wide_boxes",
        _ => "analysis::flutter::failed",
    }
}

/// Default number of speeds of the free vehicle's sweep (0.3 a or 0.1 a to 3 a).
pub const FREE_SPEEDS: usize = 120;

/// Clamped-fin modes of `analyze flutter --clamped` without `--modes`.
pub const CLAMPED_MODES: usize = 6;

/// The most chordwise panels `analyze flutter` lays out for the unsteady lattice.
pub const MAX_CHORDWISE: usize = 32;

/// The clamped fin's p-k solution at `condition` over `speeds` (the reduced-frequency table
/// reaches the highest mode's `k` at the lowest speed, with 20 % to spare).
pub fn solve_clamped(
    v: &ir::Vehicle,
    condition: Condition,
    speeds: &[f64],
    n_modes: usize,
    aero: FinAero,
    cache: Option<&Cache>,
) -> Result<FinFlutter, FinFlutterError> {
    super::sequential_linear_algebra();
    let modes = clamped_fin_modes(v, n_modes)?;
    let w_max = modes.omega.iter().copied().fold(0.0, f64::max);
    let settings = sweep_settings(aero, speeds, w_max, modes.b_ref(), &modes);
    let lattice: Lattice = fin_lattice(&modes, &settings)?;
    let mut gaf_cache: Option<GafCacheUse> = None;
    // In the transonic band the two end tables (each through the cache) are blended
    // (`fin::bridged`); the cache use reported is the last table's, `miss` if any missed.
    let (gaf, bridge) = match cache {
        None => gaf_table_bridged(&modes, &lattice, condition.mach, &settings)?,
        Some(cache) => bridged(condition.mach, aero, |m| {
            let c = super::gaf_cache::cached_gaf_table(v, &modes, &lattice, m, &settings, cache)?;
            let missed = gaf_cache.as_ref().is_some_and(|g| g.outcome != "hit");
            let previous = gaf_cache.take();
            gaf_cache = Some(GafCacheUse {
                hash: c.key.map(|k| k.to_hex()),
                outcome: if missed {
                    previous.as_ref().map_or("miss", |g| g.outcome)
                } else {
                    outcome_name(&c.outcome)
                },
                warning: match &c.outcome {
                    CacheOutcome::Rebuilt { .. } => Some(format!("GAF table: {}", c.outcome)),
                    _ => c.warning.or(previous.and_then(|g| g.warning)),
                },
            });
            Ok::<_, FinFlutterError>(c.table)
        })?,
    };
    let (solution, truncated) = solve_with(&modes, &gaf, condition.density, speeds)?;
    Ok(FinFlutter {
        bridge,
        gaf_cache,
        modes,
        condition,
        aero,
        solution,
        truncated,
        critical_thickness: None,
        free_vehicle: None,
        matched: None,
    })
}

fn tn4197(r: &FinFlutter) -> Tn4197Fin {
    Tn4197Fin {
        shear_modulus: r.modes.shear_modulus,
        span: r.modes.planform.span,
        root_chord: r.modes.planform.root_chord,
        tip_chord: r.modes.planform.tip_chord,
        thickness: r.modes.thickness,
        tip_le_offset: r.modes.planform.tip_le_offset,
    }
}

fn hz(w: f64) -> f64 {
    w / (2.0 * std::f64::consts::PI)
}

pub fn report_text(r: &FinFlutter) -> String {
    let c = &r.condition;
    let s = &r.solution;
    let mut t = String::new();
    let case = match &r.free_vehicle {
        None => "clamped fin".to_string(),
        Some(fv) => format!(
            "free flexible vehicle ({N_RIGID} rigid + {} elastic coordinates, {} fins' panels {} x {}, body aerodynamics {})",
            fv.n_elastic,
            fv.fins,
            fv.lattice.0,
            fv.lattice.1,
            if fv.body_aero {
                "quasi-steady from the flight's tables"
            } else {
                "none (no body block in the plan)"
            }
        ),
    };
    let _ = writeln!(
        t,
        "{case}, {} fin aerodynamics ({}), Mach {:.4}, altitude {:.0} m (rho {:.4} kg/m3, a {:.2} m/s)",
        r.aero.name(),
        crate::analysis::flutter::fin::aero_method_bridged(
            &r.modes.planform,
            c.mach,
            r.aero,
            r.bridge.as_ref()
        ),
        c.mach,
        c.altitude,
        c.density,
        c.speed_of_sound
    );
    if let Some(g) = &r.gaf_cache {
        let _ = writeln!(
            t,
            "generalised aerodynamic forces Q(k): {}",
            match g.outcome {
                "hit" => "read from the cache",
                "rebuilt" => "built (the cache entry was invalid) and stored",
                _ => "built and stored in the cache",
            }
        );
    }
    let _ = writeln!(
        t,
        "{}",
        if r.free_vehicle.is_some() {
            "branches (vacuum modes of the free vehicle):"
        } else {
            "modes:"
        }
    );
    for (j, name) in r.modes.names.iter().enumerate() {
        let _ = writeln!(t, "  {}  {name}", j + 1);
    }
    let answer = s.answer();
    let extra = match answer {
        FlutterAnswer::Flutter(f) => {
            format!(" (Mach {:.3} at this altitude)", f.speed / c.speed_of_sound)
        }
        _ => String::new(),
    };
    let _ = writeln!(
        t,
        "{}",
        answer.headline(s.speeds.last().copied().unwrap_or(0.0), &extra)
    );
    if let Some(sc) = &s.screen {
        let _ = writeln!(t, "  {}", sc.line());
    }
    if let (FlutterAnswer::Flutter(f), Some(g)) = (answer, s.critical()) {
        if g.speed > f.speed {
            let _ = writeln!(
                t,
                "  the sweep proper's lowest crossing is higher, V = {:.2} m/s ({}): the flutter speed is the screen's",
                g.speed, g.name
            );
        }
    }
    if let Some((v, j)) = r.truncated {
        let _ = writeln!(
            t,
            "warning: the p-k iteration of branch {} did not converge at V = {v:.1} m/s: the sweep ends below it",
            j + 1
        );
    }
    if !s.unstable_at_start.is_empty() {
        let _ = writeln!(
            t,
            "warning: branches already unstable at the lowest speed: {:?}",
            s.unstable_at_start
        );
    }
    if let Some(fv) = &r.free_vehicle {
        rigid_lines(&mut t, s, fv.scenario_speed);
    }
    let div = if r.free_vehicle.is_some() {
        "divergence (elastic coordinates, frame held)"
    } else {
        "divergence"
    };
    match &s.divergence {
        Some(d) => {
            let _ = writeln!(
                t,
                "{div}: V = {:.2} m/s, q = {:.1} kPa ({})",
                d.speed,
                d.q / 1e3,
                d.name
            );
        }
        None => {
            let _ = writeln!(t, "{div}: none");
        }
    }
    if let Some(mp) = &r.matched {
        let _ = writeln!(
            t,
            "matched point: Mach {:.4} at {:.0} m (V_F / a - M = {:.1e}; {} p-k solutions, Machs {:.4?})",
            r.condition.mach,
            r.condition.altitude,
            mp.residual,
            mp.machs.len(),
            mp.machs
        );
    }
    match &r.critical_thickness {
        Some((
            CriticalThickness::Found {
                thickness,
                evaluations,
            },
            v0,
        )) => {
            let _ = writeln!(
                t,
                "critical thickness: {:.4} mm (flutter speed {v0:.2} m/s; {evaluations} p-k solutions)",
                thickness * 1e3
            );
        }
        Some((CriticalThickness::NotBracketed { thinnest, thickest }, v0)) => {
            let _ = writeln!(
                t,
                "critical thickness: not in the range: flutter speed {:.1} m/s at {:.4} mm and {:.1} m/s at {:.4} mm against the target {v0:.2} m/s (inf: none in the sweep)",
                thinnest.1,
                thinnest.0 * 1e3,
                thickest.1,
                thickest.0 * 1e3
            );
        }
        None => {}
    }
    let fin = tn4197(r);
    for form in Tn4197Form::ALL {
        let _ = writeln!(
            t,
            "NACA TN 4197 ({}): flutter speed {:.2} m/s",
            form.name(),
            fin.flutter_speed_in(form, c.pressure, c.speed_of_sound)
        );
    }
    t
}

/// The rigid branches' roots at the sweep speed nearest `v` (the short periods, roll).
fn rigid_lines(t: &mut String, s: &PkSolution, v: f64) {
    let Some(i) = (0..s.speeds.len())
        .min_by(|&x, &y| (s.speeds[x] - v).abs().total_cmp(&(s.speeds[y] - v).abs()))
    else {
        return;
    };
    let _ = writeln!(t, "rigid branches at V = {:.2} m/s:", s.speeds[i]);
    for j in 0..N_RIGID.min(s.roots.len()) {
        let p = s.roots[j][i].p;
        let _ = writeln!(
            t,
            "  {}  p = {:.4} {:+.4}i 1/s ({:.3} Hz)",
            j + 1,
            p.re,
            p.im,
            hz(p.im)
        );
    }
}

pub fn summary_json(r: &FinFlutter) -> serde_json::Value {
    let c = &r.condition;
    let s = &r.solution;
    let fin = tn4197(r);
    let tn = |form: Tn4197Form| {
        serde_json::json!({
            "form": form,
            "flutter_speed_m_s": fin.flutter_speed_in(form, c.pressure, c.speed_of_sound),
            "flutter_mach": fin.flutter_mach_in(form, c.pressure),
        })
    };
    let free = r.free_vehicle.as_ref().map(|fv| {
        serde_json::json!({
            "rigid_coordinates": N_RIGID,
            "elastic_modes": fv.n_elastic,
            "fins": fv.fins,
            "panels": [fv.lattice.0, fv.lattice.1],
            "body_aero_quasi_steady": fv.body_aero,
            "divergence_of": "elastic coordinates with the floating frame held",
        })
    });
    serde_json::json!({
        "case": if r.free_vehicle.is_some() { "free_vehicle" } else { "clamped_fin" },
        "free_vehicle": free,
        "aero": r.aero,
        "aero_method": crate::analysis::flutter::fin::aero_method_bridged(&r.modes.planform, c.mach, r.aero, r.bridge.as_ref()),
        "transonic_bridge": r.bridge.as_ref().map(bridge_json),
        "mach": c.mach,
        "altitude_m": c.altitude,
        "fin_thickness_m": r.modes.thickness,
        "density_kg_m3": c.density,
        "speed_of_sound_m_s": c.speed_of_sound,
        "modes": r.modes.names.iter().zip(&r.modes.omega).map(|(n, w)| serde_json::json!({
            "name": n, "frequency_hz": hz(*w)
        })).collect::<Vec<_>>(),
        "flutter": s.flutter.iter().map(|f| serde_json::json!({
            "speed_m_s": f.speed,
            "frequency_hz": hz(f.omega),
            "dynamic_pressure_pa": f.q,
            "reduced_frequency": f.k,
            "mode": f.name,
            "partner": f.partner.as_ref().map(|p| p.1.clone()),
        })).collect::<Vec<_>>(),
        "largest_speed_m_s": s.speeds.last(),
        "sweep_cut_at_m_s": r.truncated.map(|t| t.0),
        "critical_thickness": r.critical_thickness.as_ref().map(|(c, v0)| match c {
            CriticalThickness::Found { thickness, evaluations } => serde_json::json!({
                "target_speed_m_s": v0, "thickness_m": thickness, "evaluations": evaluations
            }),
            CriticalThickness::NotBracketed { thinnest, thickest } => serde_json::json!({
                "target_speed_m_s": v0, "found": false,
                "thinnest": {"thickness_m": thinnest.0, "flutter_speed_m_s": if thinnest.1.is_finite() { Some(thinnest.1) } else { None }},
                "thickest": {"thickness_m": thickest.0, "flutter_speed_m_s": if thickest.1.is_finite() { Some(thickest.1) } else { None }},
            }),
        }),
        "matched_point": r.matched.as_ref().map(|mp| serde_json::json!({
            "mach": r.condition.mach, "machs_tried": mp.machs, "residual": mp.residual
        })),
        "unstable_at_lowest_speed": s.unstable_at_start,
        "answer": s.answer().json(),
        "screen": s.screen.as_ref().map(|sc| sc.json()),
        "divergence": s.divergence.as_ref().map(|d| serde_json::json!({
            "speed_m_s": d.speed, "dynamic_pressure_pa": d.q, "mode": d.name
        })),
        "tn4197": { "martin": tn(Tn4197Form::Martin), "peak_of_flight_291": tn(Tn4197Form::PeakOfFlight291), "peak_of_flight_615": tn(Tn4197Form::PeakOfFlight615), "epsilon": fin.epsilon(), "thickness_ratio_chord": "root" },
        "gaf_cache": r.gaf_cache.as_ref().map(|g| serde_json::json!({
            "outcome": g.outcome, "hash": g.hash, "warning": g.warning
        })),
    })
}

/// `vg.csv`: one row per speed and branch.
pub fn vg_csv(r: &FinFlutter) -> String {
    vg_table(&r.solution)
}

/// The V-g / V-f table of a p-k solution: one row per speed and branch.
pub fn vg_table(s: &PkSolution) -> String {
    let mut t = String::from("speed_m_s,branch,name,g,frequency_hz,k,p_re,p_im\n");
    for (j, branch) in s.roots.iter().enumerate() {
        for root in branch {
            let _ = writeln!(
                t,
                "{},{},\"{}\",{},{},{},{},{}",
                root.speed,
                j,
                s.names[j],
                root.g().map_or(String::new(), |g| g.to_string()),
                hz(root.omega()),
                root.k,
                root.p.re,
                root.p.im
            );
        }
    }
    t
}

pub fn write_outputs(out: &Path, r: &FinFlutter) -> std::io::Result<()> {
    let json = serde_json::to_string_pretty(&summary_json(r)).unwrap_or_default();
    let vg = vg_csv(r);
    super::files::write_all_atomic(
        &[out],
        &[(out.join("vg.csv"), &vg), (out.join("flutter.json"), &json)],
    )
}

/// The flutter margin of a flown scenario ([`crate::analysis::flutter::margin`]):
/// `summary.json`'s `flutter_margin`, `flutter_margin.csv` and the terminal line.
pub struct FlightMargin {
    pub json: serde_json::Value,
    /// Empty when no margin could be computed.
    pub csv: String,
    pub line: String,
    /// Warnings of the boundary's cache (a rebuilt or unstorable artifact), for the caller
    /// to show.
    pub warnings: Vec<String>,
}

/// The flutter margin's history over a flight: when it first fell below the criterion and
/// below 1, for how long, in which spans (row times; a row's interval runs to the next row).
#[derive(Debug, Default)]
struct MarginStory {
    /// (row, margin) of the first row below the criterion / below 1.
    first_violation: Option<(usize, f64)>,
    first_below_one: Option<(usize, f64)>,
    below_criterion: f64,
    below_one: f64,
    spans_criterion: Vec<[f64; 2]>,
    spans_one: Vec<[f64; 2]>,
}

impl MarginStory {
    fn add(&mut self, i: usize, t: f64, dt: f64, margin: f64) {
        use crate::analysis::flutter::margin::CRITERION;
        for (limit, first, total, spans) in [
            (
                CRITERION,
                &mut self.first_violation,
                &mut self.below_criterion,
                &mut self.spans_criterion,
            ),
            (
                1.0,
                &mut self.first_below_one,
                &mut self.below_one,
                &mut self.spans_one,
            ),
        ] {
            if margin >= limit {
                continue;
            }
            first.get_or_insert((i, margin));
            *total += dt;
            match spans.last_mut() {
                // Contiguous with the last span (this row starts where it ended).
                Some(s) if s[1] >= t => s[1] = t + dt,
                _ => spans.push([t, t + dt]),
            }
        }
    }

    /// One paragraph: the boundary's story and the time-domain flight's, and where they
    /// disagree (None for a flight that never came below the criterion and stayed in its model).
    fn text(
        &self,
        o: &crate::run::RunOutput,
        points: &[crate::analysis::flutter::margin::BoundaryPoint],
        cm: usize,
        ch: usize,
    ) -> Option<String> {
        use crate::analysis::flutter::margin::CRITERION;
        let mut s = String::new();
        let at = |i: usize| {
            let r = &o.rows[i];
            format!(
                "t = {:.3} s (Mach {:.3}, {:.0} m{})",
                r[0],
                r[cm],
                r[ch],
                if points[i].trusted && points[i].in_grid {
                    ""
                } else {
                    ", an untrusted row"
                }
            )
        };
        if let Some((i, m)) = self.first_violation {
            let _ = write!(
                s,
                "The margin first fell below {CRITERION} at {} (V_F/V = {m:.3}) and stayed below it {:.3} s in all",
                at(i),
                self.below_criterion
            );
            match self.first_below_one {
                Some((j, m1)) => {
                    let _ = write!(
                        s,
                        "; the flight crossed the clamped-fin flutter boundary (V_F/V < 1) at {} (V_F/V = {m1:.3}) and flew {:.3} s beyond it.",
                        at(j),
                        self.below_one
                    );
                }
                None => s.push_str("; it never fell below 1 (the boundary was not crossed)."),
            }
        }
        match (&o.verdict, self.first_below_one) {
            (Some(v), _) if v.flow => {
                let _ = write!(
                    s,
                    " The flight ended at t = {:.3} s with a model limit of its aerodynamics (air from behind the vehicle), not of its structure: the margin covers the flight up to there.",
                    v.t
                );
            }
            (Some(v), Some((j, _))) => {
                let _ = write!(
                    s,
                    " The time-domain flight left its model at t = {:.3} s ({}, Mach {:.3}), {:.3} s after the boundary was crossed. They are two models: the flight flies the free vehicle with its own fin loads (the flight's quasi-steady panels, no wake lag), the boundary is the clamped fin with unsteady panels; and a growing mode needs time to reach the model's bound.",
                    v.t,
                    v.kind.code(),
                    o.rows.last().map_or(f64::NAN, |r| r[cm]),
                    v.t - o.rows[j][0]
                );
            }
            (Some(v), None) => {
                let _ = write!(
                    s,
                    " The time-domain flight left its model at t = {:.3} s ({}) although the clamped-fin boundary was never crossed: the flight's free vehicle (body modes, every fin, the flight's quasi-steady fin loads) is not the clamped fin, so the two models disagree here; trust the verdict, which is what this flight's model did.",
                    v.t,
                    v.kind.code()
                );
            }
            (None, Some(_)) => s.push_str(
                " The time-domain flight did not leave its model: its modes did not grow to the model's bound while the margin was below 1 (the flight's quasi-steady fin loads have no wake lag and its free vehicle is not the clamped fin). The margin is the conservative answer.",
            ),
            (None, None) => {}
        }
        (!s.is_empty()).then(|| s.trim_start().to_string())
    }
}

fn margin_skipped(why: String) -> FlightMargin {
    FlightMargin {
        line: format!("flutter margin: not computed ({why})"),
        json: serde_json::json!({ "computed": false, "reason": why }),
        csv: String::new(),
        warnings: Vec::new(),
    }
}

/// Number of clamped-fin modes of the flight margin.
pub const MARGIN_MODES: usize = 4;

/// The aerodynamics of the flight margin: the default of `analyze flutter`, the doublet
/// lattice (issue 33).
pub const MARGIN_AERO: FinAero = FinAero::DoubletLattice;

/// The cache key of a vehicle's flutter boundary: exactly the inputs the clamped fin's modes
/// are computed from ([`clamped_fin_modes`]: the `fins` block whole, with its material,
/// planform, thickness and cant, by its canonical serialisation; the fin mesh density of
/// `structure { generate { ... } }`; the structural pipeline revision), the whole
/// [`BoundarySpec`] (grid, sweeps, modes, aerodynamics, lattice, p-k settings),
/// [`BOUNDARY_REVISION`], the payload schema and (through the builder) the compiler and
/// format versions. The body, its masses and the motor are left out: the clamped fin does not
/// see them, so a motor or payload variant shares the boundary. `Generate` is destructured
/// without `..`, so a field added to it does not compile until it is hashed here or stated not
/// to shape the clamped fin.
pub fn boundary_key(v: &ir::Vehicle, spec: &BoundarySpec) -> std::io::Result<CacheKey> {
    use crate::artifact::ArtifactPayload;
    let mut b = CacheKeyBuilder::new("flutter-boundary");
    b.text("revision", BOUNDARY_REVISION);
    b.text("schema", BoundaryArtifact::SCHEMA);
    hash_clamped_fin(&mut b, v)?;
    canon(&mut b, "spec", spec)?;
    Ok(b.finish())
}

fn canon(
    b: &mut CacheKeyBuilder,
    label: &str,
    x: &dyn super::compile::erased::Ser,
) -> std::io::Result<()> {
    x.add_to(b, label).map_err(std::io::Error::other)
}

/// Adds to `b` exactly the inputs of `v` the clamped fin's modes are computed from
/// ([`clamped_fin_modes`]): the `fins` block whole, the fin mesh density of `structure {
/// generate { ... } }` and the structural pipeline revision (the doc of [`boundary_key`]).
pub fn hash_clamped_fin(b: &mut CacheKeyBuilder, v: &ir::Vehicle) -> std::io::Result<()> {
    b.u64(
        "pipeline revision",
        u64::from(crate::structure::compile::PIPELINE_REVISION),
    );
    canon(b, "fins", &v.fins)?;
    match &v.structure {
        ir::Structure::Generate(g) => {
            let ir::Generate {
                span: _,
                fin_span_elements,
                fin_chord_elements,
                // The clamped fin's mesh is the fin alone (`generate::cantilever_fin_model`).
                body: _,
                point_masses: _,
                distributed_masses: _,
            } = g;
            canon(b, "fin span elements", fin_span_elements)?;
            canon(b, "fin chord elements", fin_chord_elements)?;
        }
        // No clamped fin can be built (the margin says so); hashed whole all the same.
        other => canon(b, "structure", other)?,
    }
    Ok(())
}

/// A vehicle's flutter boundary through the cache.
pub struct CachedBoundary {
    pub boundary: Boundary,
    pub fin: BoundaryFin,
    /// `None` when no key could be made (the boundary was solved and not stored).
    pub key: Option<CacheKey>,
    pub outcome: CacheOutcome,
    /// Why the boundary could not be stored or looked up, if so (the run goes on).
    pub warning: Option<String>,
}

/// The boundary of `spec` for `v`'s clamped fin: read from `cache` when a valid entry exists
/// (no eigen-solve, no p-k), else solved and stored. A corrupt, truncated, stale or
/// ill-fitting entry is never used: it is rebuilt and replaced ([`CacheOutcome::Rebuilt`]).
/// A cache that cannot be written is a warning, not an error.
pub fn cached_boundary(
    v: &ir::Vehicle,
    spec: &BoundarySpec,
    cache: &Cache,
) -> Result<CachedBoundary, FinFlutterError> {
    let key = boundary_key(v, spec);
    let mut warning = None;
    let outcome = match &key {
        Err(e) => {
            warning = Some(format!("no cache key for the flutter boundary: {e}"));
            CacheOutcome::Miss
        }
        Ok(key) => match cache.lookup::<BoundaryArtifact>(key) {
            Ok(Some(art)) => {
                let read = rkyv::deserialize::<BoundaryArtifact, rkyv::rancor::Error>(art.get())
                    .map_err(|e| e.to_string())
                    .and_then(|a| a.to_boundary(spec));
                match read {
                    Ok((boundary, fin)) => {
                        return Ok(CachedBoundary {
                            boundary,
                            fin,
                            key: Some(*key),
                            outcome: CacheOutcome::Hit,
                            warning: None,
                        });
                    }
                    Err(message) => CacheOutcome::Rebuilt {
                        reason: crate::artifact::ArtifactError::InvalidPayload {
                            path: cache.path_for(key),
                            message,
                        },
                    },
                }
            }
            Ok(None) => CacheOutcome::Miss,
            Err(reason) => CacheOutcome::Rebuilt { reason },
        },
    };
    let modes = clamped_fin_modes(v, spec.modes)?;
    let boundary = solve_boundary(&modes, spec)?;
    let fin = BoundaryFin::new(&modes);
    let key = key.ok();
    if let Some(k) = &key {
        let art = BoundaryArtifact::new(&boundary, &fin);
        if let Err(e) = crate::artifact::write_atomic(cache.dir(), k, &art) {
            warning = Some(format!(
                "cannot store the flutter boundary in the cache: {e}"
            ));
        }
    }
    Ok(CachedBoundary {
        boundary,
        fin,
        key,
        outcome,
        warning,
    })
}

/// The boundary specification of the flight margin of `sc` (module doc of
/// [`crate::analysis::flutter::margin`]): the vehicle's fin table Mach axis `table_machs` and
/// the scenario's site, not the flight.
pub fn margin_spec(
    sc: &ir::Scenario,
    table_machs: &[f64],
) -> Result<BoundarySpec, FinFlutterError> {
    margin_spec_and_fallback(sc, table_machs).map(|(s, _)| s)
}

/// [`margin_spec`] and, where the fin's outline keeps the doublet lattice from meeting its
/// box rule, why the spec takes the vortex lattice instead
/// ([`crate::analysis::flutter::margin::margin_aero`]).
pub fn margin_spec_and_fallback(
    sc: &ir::Scenario,
    table_machs: &[f64],
) -> Result<(BoundarySpec, Option<String>), FinFlutterError> {
    let (aero, fallback) = match &sc.vehicle.fins {
        Some(f) => crate::analysis::flutter::margin::margin_aero(
            &crate::aero::estimator::planform(f, 0.0),
            MARGIN_AERO,
        ),
        None => (MARGIN_AERO, None),
    };
    let spec = vehicle_spec(
        table_machs,
        scenario_altitude(sc),
        sc.launch.is_some(),
        MARGIN_MODES,
        aero,
    )?;
    Ok((spec, fallback))
}

/// The flutter margin at every output row of `o` (module doc of
/// [`crate::analysis::flutter::margin`]), the boundary through `cache`; `table_machs` is the
/// Mach axis of the vehicle's fin coefficient table.
pub fn flight_margin(
    sc: &ir::Scenario,
    o: &crate::run::RunOutput,
    table_machs: &[f64],
    cache: &Cache,
) -> FlightMargin {
    flight_margin_with(sc, o, table_machs, &|v, spec| {
        cached_boundary(v, spec, cache)
    })
}

/// [`flight_margin`] with the boundary from `boundary` instead of [`cached_boundary`] (a Monte
/// Carlo's thickness family, `ops::montecarlo::family`).
///
/// With further fin sets (`fins NAME`, issue 34) each set gets its own margin over the same
/// flight by the same machinery: the vehicle with that set as its `fins` (the clamped fin's
/// modes and boundary depend on the `fins` block and the fin mesh density alone,
/// [`hash_clamped_fin`]), so its planform, thickness and material, its own cached boundary.
/// The unnamed set's fields stay at the top level of the JSON; `sets` lists each further
/// set's (its `name` added), `minimum_over_sets` the smallest trusted minimum of all sets
/// (`speed_margin`, `set`) and `meets_criterion_all_sets` whether every set meets the
/// criterion; the line gets one line per set. The CSV is the unnamed set's.
pub fn flight_margin_with(
    sc: &ir::Scenario,
    o: &crate::run::RunOutput,
    table_machs: &[f64],
    boundary: &dyn Fn(&ir::Vehicle, &BoundarySpec) -> Result<CachedBoundary, FinFlutterError>,
) -> FlightMargin {
    let mut m = set_margin(sc, o, table_machs, boundary);
    if sc.vehicle.fin_sets.is_empty() {
        return m;
    }
    let speed = |j: &serde_json::Value| j["minimum"]["speed_margin"].as_f64();
    let mut lowest: Option<(f64, String)> = speed(&m.json).map(|x| (x, "fins".to_string()));
    let mut all_meet = m.json["meets_criterion"].as_bool();
    let mut sets = Vec::with_capacity(sc.vehicle.fin_sets.len());
    for s in &sc.vehicle.fin_sets {
        let mut one = sc.clone();
        one.vehicle.fins = Some(s.fins.clone());
        one.vehicle.fin_sets.clear();
        let sm = set_margin(&one, o, table_machs, boundary);
        let name = s.name.value.clone();
        let _ = write!(m.line, "\n  fin set `{name}`: {}", sm.line);
        m.warnings.extend(sm.warnings);
        if let Some(x) = speed(&sm.json) {
            if lowest.as_ref().is_none_or(|(l, _)| x < *l) {
                lowest = Some((x, name.clone()));
            }
        }
        all_meet = match (all_meet, sm.json["meets_criterion"].as_bool()) {
            (Some(a), Some(b)) => Some(a && b),
            _ => None,
        };
        let mut j = sm.json;
        if let Some(map) = j.as_object_mut() {
            map.insert("name".into(), serde_json::Value::String(name));
        }
        sets.push(j);
    }
    if let Some(map) = m.json.as_object_mut() {
        map.insert("sets".into(), serde_json::Value::Array(sets));
        map.insert(
            "minimum_over_sets".into(),
            serde_json::json!(
                lowest.map(|(x, set)| serde_json::json!({"speed_margin": x, "set": set}))
            ),
        );
        map.insert(
            "meets_criterion_all_sets".into(),
            serde_json::json!(all_meet),
        );
    }
    m
}

/// The flutter margin of the vehicle's unnamed `fins` set over the flight ([`flight_margin_with`]).
fn set_margin(
    sc: &ir::Scenario,
    o: &crate::run::RunOutput,
    table_machs: &[f64],
    boundary: &dyn Fn(&ir::Vehicle, &BoundarySpec) -> Result<CachedBoundary, FinFlutterError>,
) -> FlightMargin {
    use crate::analysis::flutter::margin::CRITERION;
    let started = std::time::Instant::now();
    let col = |n: &str| o.channels.iter().position(|c| c == n);
    let (Some(cm), Some(ch)) = (col("mach"), col("altitude")) else {
        return margin_skipped("the history has no mach and altitude channels".into());
    };
    if o.rows.is_empty() {
        return margin_skipped("the run wrote no rows".into());
    }
    if sc.vehicle.fins.is_none() {
        return margin_skipped(FinFlutterError::NoFins.to_string());
    }
    if !matches!(sc.vehicle.structure, ir::Structure::Generate(_)) {
        return margin_skipped(FinFlutterError::NotGenerated.to_string());
    }
    let (spec, aero_fallback) = match margin_spec_and_fallback(sc, table_machs) {
        Ok(s) => s,
        Err(e) => return margin_skipped(e.to_string()),
    };
    let cached = match boundary(&sc.vehicle, &spec) {
        Ok(c) => c,
        Err(e) => return margin_skipped(e.to_string()),
    };
    let mut cache_warnings = Vec::new();
    if let Some(w) = &cached.warning {
        cache_warnings.push(w.clone());
    }
    if let CacheOutcome::Rebuilt { .. } = &cached.outcome {
        cache_warnings.push(format!("flutter boundary: {}", cached.outcome));
    }
    let (b, finv) = (&cached.boundary, &cached.fin);
    let atm = Standard1976::new();
    let mut airspeed = Vec::with_capacity(o.rows.len());
    let mut sound = Vec::with_capacity(o.rows.len());
    for r in &o.rows {
        match atm.at(r[ch]) {
            Ok(a) => {
                airspeed.push(r[cm] * a.speed_of_sound);
                sound.push(a.speed_of_sound);
            }
            Err(e) => return margin_skipped(format!("atmosphere: {e}")),
        }
    }
    let mut csv = String::from(
        "t,mach,altitude,airspeed,flutter_speed,flutter_mach,speed_margin,q_margin,trusted,lower_bound,in_grid,uncertainty\n",
    );
    // (margin, row) minima: over the rows inside the grid, each margin divided by 1 + u (its
    // transonic bridge's stated uncertainty, `margin::BoundaryPoint::uncertainty`: the
    // conservative side), and over all rows.
    let mut min_trusted: Option<(f64, usize)> = None;
    let mut min_all: Option<(f64, usize)> = None;
    let mut untrusted = 0usize;
    let mut outside = 0usize;
    let mut above_lowest = 0usize;
    let mut raised = 0usize;
    let mut points = Vec::with_capacity(o.rows.len());
    // Under a canopy the fins are frozen with the rest of the vehicle (runtime::flight): the
    // margin covers the flight up to the first deployment.
    let t_canopy = o
        .events
        .deployments
        .iter()
        .map(|d| d.2.t)
        .fold(f64::INFINITY, f64::min);
    let mut story = MarginStory::default();
    for (i, r) in o.rows.iter().enumerate() {
        let (m, h, v) = (r[cm], r[ch], airspeed[i]);
        let p = b.at(m, h);
        points.push(p);
        // At rest (on the pad) the margin is undefined: no row.
        if v.is_nan() || v <= 0.0 || r[0] > t_canopy {
            continue;
        }
        let margin = p.flutter_speed / v;
        let dt = o
            .rows
            .get(i + 1)
            .map_or(0.0, |n| n[0].min(t_canopy) - r[0])
            .max(0.0);
        story.add(i, r[0], dt, margin);
        if !p.trusted {
            untrusted += 1;
        }
        if !p.in_grid {
            outside += 1;
        }
        if p.upper_bound {
            above_lowest += 1;
        }
        if p.raised_start {
            raised += 1;
        }
        if min_all.is_none_or(|(x, _)| margin < x) {
            min_all = Some((margin, i));
        }
        let conservative = margin / (1.0 + p.uncertainty);
        if p.in_grid && min_trusted.is_none_or(|(x, _)| conservative < x) {
            min_trusted = Some((conservative, i));
        }
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            r[0],
            m,
            h,
            v,
            p.flutter_speed,
            p.flutter_speed / sound[i],
            margin,
            margin * margin,
            p.trusted as u8,
            p.lower_bound as u8,
            p.in_grid as u8,
            p.uncertainty
        );
    }
    let fin = Tn4197Fin {
        shear_modulus: finv.shear_modulus,
        span: finv.span,
        root_chord: finv.root_chord,
        tip_chord: finv.tip_chord,
        thickness: finv.thickness,
        tip_le_offset: finv.tip_le_offset,
    };
    let at = |x: Option<(f64, usize)>| {
        x.map(|(margin, i)| {
            let r = &o.rows[i];
            let tn = atm.at(r[ch]).ok().map(|air| {
                serde_json::json!({
                    "martin_flutter_speed": fin.flutter_speed_in(Tn4197Form::Martin, air.pressure, air.speed_of_sound),
                    "peak_of_flight_291_flutter_speed": fin.flutter_speed_in(Tn4197Form::PeakOfFlight291, air.pressure, air.speed_of_sound),
                    "peak_of_flight_615_flutter_speed": fin.flutter_speed_in(Tn4197Form::PeakOfFlight615, air.pressure, air.speed_of_sound),
                })
            });
            serde_json::json!({
                "tn4197": tn,
                "speed_margin": margin,
                "q_margin": margin * margin,
                "t": r[0],
                "mach": r[cm],
                "altitude": r[ch],
                "airspeed": airspeed[i],
                "flutter_speed": points[i].flutter_speed,
                "lower_bound": points[i].lower_bound,
                "upper_bound": points[i].upper_bound,
                "trusted": points[i].trusted,
                "uncertainty": points[i].uncertainty,
                "raised_start": points[i].raised_start,
                "in_grid": points[i].in_grid,
            })
        })
    };
    let critical = min_trusted.or(min_all);
    // A flight that left its structural model never meets the criterion, whatever the
    // boundary says; one that ended at the flow's bound (air from behind: a tumbling fall)
    // is judged on the flight up to it.
    let structural_verdict = o.verdict.as_ref().filter(|v| !v.flow);
    let meets = critical.map(|(m, _)| m >= CRITERION && structural_verdict.is_none());
    let event = |x: Option<(usize, f64)>| {
        x.map(|(i, margin)| {
            let r = &o.rows[i];
            serde_json::json!({
                "t": r[0],
                "mach": r[cm],
                "altitude": r[ch],
                "airspeed": airspeed[i],
                "margin": margin,
                "trusted": points[i].trusted && points[i].in_grid,
            })
        })
    };
    let story_text = story.text(o, &points, cm, ch);
    let mut warnings = String::new();
    if let Some(why) = &aero_fallback {
        let _ = write!(warnings, "; warning: {why}");
    }
    if untrusted > 0 {
        let _ = write!(
            warnings,
            "; {untrusted} rows in the transonic band on bridged aerodynamic matrices (each margin counted divided by 1 + its stated uncertainty)"
        );
    }
    if outside > 0 {
        let _ = write!(
            warnings,
            "; warning: {outside} rows outside the boundary's grid (Mach {}..{}, altitude {:.0}..{:.0} m; evaluated at its edge, untrusted)",
            b.machs[0],
            b.machs[b.machs.len() - 1],
            b.altitudes[0],
            b.altitudes[b.altitudes.len() - 1]
        );
    }
    if above_lowest > 0 {
        let _ = write!(
            warnings,
            "; warning: {above_lowest} rows use a boundary node already unstable at its lowest speed (the flutter speed there is at most the value written)"
        );
    }
    if raised > 0 {
        let _ = write!(
            warnings,
            "; warning: {raised} rows use a boundary node whose p-k sweep did not converge at its lowest speed and starts higher (a flutter crossing below that start would not be seen)"
        );
    }
    let line = match critical {
        Some((m, i)) => format!(
            "flutter margin (clamped fin): min V_F/V = {:.3}{}{} at t = {:.3} s (Mach {:.3}, {:.0} m), criterion {CRITERION}: {}{warnings}",
            m,
            if points[i].lower_bound {
                " or more"
            } else {
                ""
            },
            if points[i].uncertainty > 0.0 {
                format!(
                    " (transonic bridge: V_F/V / (1 + u), u = {:.1} %)",
                    100.0 * points[i].uncertainty
                )
            } else {
                String::new()
            },
            o.rows[i][0],
            o.rows[i][cm],
            o.rows[i][ch],
            match (structural_verdict, m >= CRITERION) {
                (Some(v), _) => format!(
                    "NOT MET (the flight left its model: {} at t = {:.3} s)",
                    v.kind.code(),
                    v.t
                ),
                (None, true) => "met".into(),
                (None, false) => "NOT MET".into(),
            },
        ),
        None => "flutter margin: no row with airspeed".into(),
    };
    let line = match &story_text {
        Some(t) => format!("{line}\n  {t}"),
        None => line,
    };
    let json = serde_json::json!({
        "computed": true,
        "model": format!("fin clamped at its root, p-k with the unsteady fin panels ({}, subsonic; the transonic band bridged in Q(k, M); the Mach box or unsteady piston theory by its validity criterion, supersonic; analysis::flutter::fin), on a cached Mach x altitude boundary of the vehicle (analysis::flutter::margin)", match spec.aero {
            FinAero::DoubletLattice => "doublet lattice",
            FinAero::Unsteady => "harmonic vortex lattice with a convected wake",
            FinAero::QuasiSteady => "quasi-steady panels",
        }),
        "aero": spec.aero,
        "aero_fallback": aero_fallback,
        "criterion_speed_margin": CRITERION,
        "criterion_source": "15 % on equivalent airspeed (14 CFR 25.629(b)(1), MIL-A-8870C 3.1.1)",
        "meets_criterion": meets,
        "first_violation": event(story.first_violation),
        "first_below_one": event(story.first_below_one),
        "time_below_criterion_s": story.below_criterion,
        "time_below_one_s": story.below_one,
        "spans_below_criterion": story.spans_criterion,
        "spans_below_one": story.spans_one,
        "story": story_text,
        "rows_until": if t_canopy.is_finite() { Some(t_canopy) } else { None },
        "minimum": at(critical),
        "minimum_including_transonic": at(min_all),
        "transonic_rows": untrusted,
        "outside_grid_rows": outside,
        "upper_bound_rows": above_lowest,
        "raised_start_rows": raised,
        "modes": finv.mode_names,
        "boundary": {
            "machs": b.machs,
            "altitudes": b.altitudes,
            "flutter_speeds": b.speeds,
            "lower_bound": b.lower_bound,
            "upper_bound": b.upper_bound,
            "speed_ranges": b.speed_ranges,
            "node_lowest_speeds": b.node_lowest_speeds,
            "largest_speed": b.largest_speed,
        },
        "boundary_hash": cached.key.map(|k| k.to_hex()),
        "boundary_cache": outcome_name(&cached.outcome),
        "seconds": started.elapsed().as_secs_f64(),
    });
    FlightMargin {
        json,
        csv,
        line,
        warnings: cache_warnings,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The matched point of `V_F(M) = 300 - 50 M` m/s with `a = 300` m/s is `M = 6/7`
    /// (the secant is exact on a linear `g` after the fixed-point start); the iteration
    /// reports the Machs it solved at, passes a solver error through, and says when a Mach
    /// has no flutter point or when it does not converge.
    #[test]
    fn the_matched_point_iteration() {
        let mut calls = 0;
        let (mp, solved) = match_point::<(), usize>(
            |m| {
                calls += 1;
                Ok((Some(300.0 - 50.0 * m), calls))
            },
            0.5,
            300.0,
        )
        .unwrap();
        assert_eq!(solved, calls);
        let last = *mp.machs.last().unwrap();
        assert!((last - 6.0 / 7.0).abs() < 1e-12, "{last}");
        assert_eq!(mp.machs.len(), calls);
        assert_eq!(mp.machs.len(), 3);
        assert!(mp.residual.abs() <= MATCH_TOL);
        assert_eq!(
            match_point(|_| Err::<(Option<f64>, ()), _>("transonic"), 0.5, 300.0),
            Err(MatchError::Solve("transonic"))
        );
        assert_eq!(
            match_point::<(), ()>(|_| Ok((None, ())), 0.5, 300.0),
            Err(MatchError::NoFlutter { mach: 0.5 })
        );
        // A flutter speed that jumps with the Mach (g = ±0.2 alternately): never within tol.
        let mut flip = 1.0;
        let r = match_point::<(), ()>(
            |m| {
                flip = -flip;
                Ok((Some(300.0 * (m + 0.2 * flip)), ()))
            },
            0.5,
            300.0,
        );
        assert!(matches!(r, Err(MatchError::NotConverged { .. })), "{r:?}");
    }

    /// The root of a linear `V_F(t)` is found, and the reported number of p-k solutions is the
    /// number of calls made (the scan stops at the first bracket).
    #[test]
    fn critical_thickness_counts_the_solutions_it_made() {
        let calls = std::cell::Cell::new(0usize);
        let solve = |t: f64| -> Result<f64, FinFlutterError> {
            calls.set(calls.get() + 1);
            Ok(1000.0 * t)
        };
        let ts: Vec<f64> = (1..=10).map(|i| 0.1 * i as f64).collect();
        match critical_thickness(&solve, ts, 250.0).unwrap() {
            CriticalThickness::Found {
                thickness,
                evaluations,
            } => {
                assert!((thickness - 0.25).abs() < 1e-12, "{thickness}");
                assert_eq!(evaluations, calls.get());
            }
            other => panic!("{other:?}"),
        }
    }
}

/// The default speeds of `analyze flutter` without `--speeds` at speed of sound `a`: from
/// 0.3 a (the harmonic lattices, which must resolve the highest mode's reduced frequency at
/// the lowest speed: box-size rule) or 0.1 a (the quasi-steady map) to 3 a, 40 speeds for
/// the clamped fin and [`FREE_SPEEDS`] for the free vehicle (whose branches cross in
/// frequency and come in near-identical sets, one per fin: continuation needs a finer step).
pub fn default_speeds(aero: AeroChoice, clamped: bool, a: f64) -> Vec<f64> {
    let lo = match aero {
        AeroChoice::Unsteady | AeroChoice::DoubletLattice => 0.3,
        AeroChoice::QuasiSteady => 0.1,
    } * a;
    let hi = 3.0 * a;
    let count = if clamped { 40 } else { FREE_SPEEDS };
    (0..count)
        .map(|i| lo + (hi - lo) * i as f64 / (count - 1) as f64)
        .collect()
}

/// A flutter analysis of a flown scenario as `analyze flutter` asks it (without
/// `--critical-thickness` and `--match-point`): the front ends' request.
#[derive(Clone, Debug)]
pub struct FlutterRequest {
    /// The fin alone clamped at its root (`true`) or the free flexible vehicle.
    pub clamped: bool,
    /// Altitude of the air, m (default: the scenario's initial altitude).
    pub altitude: Option<f64>,
    /// Mach number of the aerodynamics (default: the scenario's initial Mach).
    pub mach: Option<f64>,
    /// The speeds of the sweep, m/s (default: [`default_speeds`]).
    pub speeds: Option<Vec<f64>>,
    /// Clamped-fin modes (default [`CLAMPED_MODES`]; the free vehicle uses its compiled
    /// modes and refuses this).
    pub modes: Option<usize>,
    pub aero: AeroChoice,
}

/// Solves `req` for scenario `scenario` of `checked` (the Python package's `flutter`): the
/// condition and speeds defaulted as `analyze flutter` does, the clamped fin's GAF tables
/// and the free vehicle's structure through the cache in `cache_dir`. Cache warnings go to
/// `warn`.
pub fn solve_request(
    checked: &mut crate::check::Checked,
    scenario: &str,
    req: &FlutterRequest,
    cache_dir: Option<&Path>,
    warn: &mut dyn FnMut(String),
) -> Result<FinFlutter, super::OpsError> {
    use super::OpsError;
    let Some(sc) = checked.program.scenario(scenario).cloned() else {
        return Err(super::unknown_scenario(&checked.program, scenario));
    };
    if req.modes == Some(0) {
        return Err(OpsError::Usage("modes must be at least 1".into()));
    }
    if !req.clamped && req.modes.is_some() {
        return Err(OpsError::Usage(
            "modes chooses the modes of the clamped fin (clamped=True); the free vehicle uses its compiled modes (the vehicle's `modes` block)".into(),
        ));
    }
    if let Some(s) = &req.speeds {
        if s.is_empty() || s.iter().any(|v| !v.is_finite() || *v <= 0.0) {
            return Err(OpsError::Usage(
                "speeds must be a non-empty list of finite positive speeds (m/s)".into(),
            ));
        }
    }
    let altitude = req.altitude.unwrap_or_else(|| scenario_altitude(&sc));
    let air = Standard1976::new()
        .at(altitude)
        .map_err(|e| OpsError::Usage(format!("altitude: {e}")))?;
    let mach = req
        .mach
        .unwrap_or_else(|| scenario_speed(&sc, air.speed_of_sound) / air.speed_of_sound);
    if !mach.is_finite() || mach < 0.0 {
        return Err(OpsError::Usage(format!(
            "mach must be finite and not negative, not {mach}"
        )));
    }
    let speeds = req
        .speeds
        .clone()
        .unwrap_or_else(|| default_speeds(req.aero, req.clamped, air.speed_of_sound));
    let condition = Condition {
        altitude,
        mach,
        density: air.density,
        speed_of_sound: air.speed_of_sound,
        pressure: air.pressure,
    };
    let refuse = |e: &FinFlutterError| OpsError::Diagnostics(vec![flutter_diagnostic(e, &sc, "")]);
    if req.clamped {
        let cache = Cache::resolve(cache_dir);
        let n_modes = req.modes.unwrap_or(CLAMPED_MODES);
        let r = solve_clamped(
            &sc.vehicle,
            condition,
            &speeds,
            n_modes,
            req.aero.model(),
            Some(&cache),
        )
        .map_err(|e| {
            OpsError::Diagnostics(vec![flutter_diagnostic(&e, &sc, ", use fewer modes")])
        })?;
        if let Some(w) = r.gaf_cache.as_ref().and_then(|g| g.warning.clone()) {
            warn(w);
        }
        return Ok(r);
    }
    if sc.vehicle.fins.is_none() {
        return Err(refuse(&FinFlutterError::NoFins));
    }
    let outcome = super::compile::compile_cached(checked, &sc.vehicle, cache_dir)?;
    let cache = Cache::resolve(cache_dir);
    let (plan, _) = super::compile::plan_cached(&sc, &outcome.compiled, &outcome.key, &cache, warn)
        .map_err(|e| OpsError::Diagnostics(vec![super::run::plan_diagnostic(&e, &sc)]))?;
    let variant = Variant {
        plan,
        scenario: sc.clone(),
        compiled: outcome.compiled,
    };
    let v0 = scenario_speed(&sc, air.speed_of_sound);
    solve_free(&variant, condition, &speeds, req.aero.model(), v0).map_err(|e| refuse(&e))
}

/// The transonic bridge of a flutter answer (issue 33) as `summary.json` writes it, for the
/// clamped fin, the free vehicle and a tunnel fixture alike.
pub(crate) fn bridge_json(b: &crate::analysis::flutter::fin::TransonicBridge) -> serde_json::Value {
    serde_json::json!({
        "low_mach": b.low,
        "high_mach": b.high,
        "weight_high": b.t,
        "matrix_uncertainty": b.matrix_uncertainty,
        "speed_uncertainty": b.uncertainty,
    })
}
