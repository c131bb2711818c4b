//! `analyze flutter FILE --scenario NAME` of a wind-tunnel scenario: the fixture's surface
//! clamped at its root ([`crate::analysis::flutter::wing`]) at the tunnel's Mach number and
//! air density, a p-k sweep over the tunnel speeds (not a matched point: the tunnel sets the
//! density and Mach, the speed varies, as in the published analyses of AGARD 445.6).
use std::fmt::Write as _;
use std::path::Path;

use crate::aero::panel::dlm::Dlm;
use crate::aero::panel::harmonic::{HarmonicVlm, WakeSettings};
use crate::aero::panel::{Lattice, Spacing, vlm};
use crate::analysis::flutter::pk::{FlutterAnswer, PkSettings, PkSolution, pk_solve, screen_below};
use crate::analysis::flutter::wing::{
    Grain, UnsteadyAero, UnsteadySettings, WingDensity, WingError, WingMaterial, WingModes,
    WingSpec, WingThickness, chordwise_for, k_max_for, quasi_steady_problem, unsteady_problem,
};
use crate::check::ir;

use super::flutter::{AeroChoice, MAX_CHORDWISE, vg_table};

/// Reduced frequencies of the unsteady table (`k_i = k_max (i/24)²`; the AGARD 445.6 tests
/// converge with it: 49 give the same flutter speed to 0.1 %, docs/validation.md).
pub const K_COUNT: usize = 25;

/// The analysis model of a checked fixture.
pub fn wing_spec(x: &ir::Fixture) -> WingSpec {
    let s = &x.surface;
    let m = &s.material;
    WingSpec {
        span: s.span.value,
        root_chord: s.root_chord.value,
        tip_chord: s.tip_chord.value,
        leading_edge_sweep: s.leading_edge_sweep.value,
        thickness: match &s.thickness {
            ir::SurfaceThickness::Constant(t) => WingThickness::Constant(t.value),
            ir::SurfaceThickness::Section(h) => WingThickness::Section(h.value.clone()),
        },
        material: match &m.orthotropic {
            None => WingMaterial::Isotropic {
                youngs_modulus: m.youngs_modulus.value,
                poisson: m.poisson.value,
            },
            Some(o) => WingMaterial::Orthotropic {
                e1: m.youngs_modulus.value,
                e2: o.e2.value,
                nu12: m.poisson.value,
                g12: o.g12.value,
                grain: match s.grain {
                    ir::SurfaceGrain::GridLines => Grain::GridLines,
                    ir::SurfaceGrain::Swept(a) => Grain::Swept(a),
                },
            },
        },
        density: match &s.mass {
            Some(mass) => WingDensity::Mass(mass.value),
            None => WingDensity::Density(m.density.value),
        },
        chord_elements: x.chord_elements.value,
        span_elements: x.span_elements.value,
    }
}

/// A solved wind-tunnel flutter case.
pub struct TunnelFlutter {
    pub name: String,
    pub fixture: String,
    pub spec: WingSpec,
    pub modes: WingModes,
    pub mach: f64,
    pub density: f64,
    pub aero: AeroChoice,
    /// Lattice chordwise x spanwise panels.
    pub panels: (usize, usize),
    pub reference_frequency: Option<f64>,
    pub solution: PkSolution,
    /// The aerodynamic method at this Mach as the reports name it (the subsonic lattice, the
    /// transonic bridge with its uncertainty, the Mach box or piston theory).
    pub method: String,
    /// The transonic bridge of the generalised forces, in the band (`fin::bridged`).
    pub bridge: Option<crate::analysis::flutter::fin::TransonicBridge>,
}

/// Solves the tunnel test `t` with `aero` over `speeds` with `n_modes` modes.
pub fn solve_tunnel(
    t: &ir::TunnelTest,
    mach: f64,
    speeds: &[f64],
    n_modes: usize,
    aero: AeroChoice,
) -> Result<TunnelFlutter, WingError> {
    let spec = wing_spec(&t.fixture);
    let spec_planform = spec.planform();
    // The aerodynamic model's Mach range first, on a one-panel lattice: a Mach it refuses
    // is said before the plate's eigen-solve.
    // The unsteady choices answer any Mach (their lattice, the transonic bridge, the Mach box
    // or piston theory: `wing::unsteady_problem`); the quasi-steady one is subsonic only.
    let probe = Lattice::new(&spec.planform(), 1, 1, Spacing::Uniform)?;
    crate::aero::panel::regime(mach)?;
    let (_, top) = crate::analysis::flutter::fin::bridge_ends(aero.model());
    match aero {
        AeroChoice::Unsteady if mach <= top => {
            if !crate::analysis::flutter::fin::in_bridge(mach, aero.model()) {
                HarmonicVlm::new(&probe, mach, &WakeSettings::default())?;
            }
        }
        AeroChoice::DoubletLattice if mach <= top => {
            if !crate::analysis::flutter::fin::in_bridge(mach, aero.model()) {
                Dlm::new(&probe, mach)?;
            }
        }
        AeroChoice::Unsteady | AeroChoice::DoubletLattice => {}
        AeroChoice::QuasiSteady => {
            vlm::force_map(&probe, mach)?;
        }
    }
    let modes = spec.modes(n_modes)?;
    let density = t.density.value;
    let spanwise = t.fixture.spanwise_panels.value;
    let mut bridge = None;
    let (solution, panels) = match aero {
        AeroChoice::QuasiSteady => {
            let chordwise = chordwise_for(&modes.planform, k_max_for(&modes, speeds[0]));
            let (model, gaf) = quasi_steady_problem(&modes, mach, density, chordwise, spanwise)?;
            (screened(&model, &gaf, speeds)?, (chordwise, spanwise))
        }
        AeroChoice::Unsteady | AeroChoice::DoubletLattice => {
            let mut settings = UnsteadySettings {
                aero: if aero == AeroChoice::Unsteady {
                    UnsteadyAero::VortexLattice
                } else {
                    UnsteadyAero::DoubletLattice
                },
                k_max: k_max_for(&modes, speeds[0]),
                k_count: K_COUNT,
                spanwise,
                min_chordwise: 0,
            };
            let chordwise = chordwise_for(&modes.planform, settings.k_max);
            if chordwise > MAX_CHORDWISE {
                return Err(WingError::TooManyPanels {
                    needed: chordwise,
                    most: MAX_CHORDWISE,
                    v_min: speeds[0],
                });
            }
            // The doublet lattice's automatic strips (`dlm::spanwise_for`) unless the fixture
            // gives `spanwise_panels` (the default 12 carries the block's header span): an
            // explicit count is used as given and refused if its boxes are too wide.
            let explicit = t.fixture.spanwise_panels.span != t.fixture.span;
            if aero == AeroChoice::DoubletLattice && !explicit {
                settings.spanwise = crate::aero::panel::dlm::spanwise_for(
                    &modes.planform,
                    chordwise,
                    spanwise,
                    Spacing::Uniform,
                )?;
            }
            let p = unsteady_problem(&modes, mach, density, &settings)?;
            bridge = p.bridge;
            (
                screened(&p.model, &p.gaf, speeds)?,
                (p.chordwise, p.spanwise),
            )
        }
    };
    Ok(TunnelFlutter {
        name: t.name.value.clone(),
        fixture: t.fixture.name.value.clone(),
        reference_frequency: t.fixture.reference_frequency.map(|q| q.value),
        spec,
        modes,
        mach,
        density,
        aero,
        panels,
        solution,
        method: match aero {
            AeroChoice::QuasiSteady => aero_name(aero).to_string(),
            _ => crate::analysis::flutter::fin::aero_method_bridged(
                &spec_planform,
                mach,
                aero.model(),
                bridge.as_ref(),
            ),
        },
        bridge,
    })
}

pub fn tunnel_code(e: &WingError) -> &'static str {
    match e {
        WingError::TooManyPanels { .. } => "analysis::flutter::too_few_panels",
        WingError::Panel(crate::aero::panel::PanelError::WideBoxes { .. }) => {
            "analysis::flutter::wide_boxes"
        }
        _ => "analysis::flutter::failed",
    }
}

fn hz(w: f64) -> f64 {
    w / (2.0 * std::f64::consts::PI)
}

pub fn aero_name(a: AeroChoice) -> &'static str {
    match a {
        AeroChoice::Unsteady => "unsteady vortex lattice (convected wake, Göthert)",
        AeroChoice::DoubletLattice => "doublet lattice",
        AeroChoice::QuasiSteady => "quasi-steady vortex lattice",
    }
}

/// The flutter speed index `V/(b ω_α sqrt μ)` and frequency ratio `ω/ω_α` of a point
/// (Yates 1987), when the fixture gives `ω_α`.
fn indices(r: &TunnelFlutter, speed: f64, omega: f64) -> Option<(f64, f64)> {
    let w_a = r.reference_frequency?;
    let mu = r.spec.mass_ratio(r.density);
    Some((speed / (r.modes.semichord() * w_a * mu.sqrt()), omega / w_a))
}

pub fn report_text(r: &TunnelFlutter) -> String {
    let mut t = String::new();
    let s = &r.solution;
    let _ = writeln!(
        t,
        "scenario {}: fixture {} clamped at its root ({} x {} plate, mass {:.4} kg, density {:.2} kg/m3), {} aerodynamics ({}) on {} x {} panels, Mach {:.4}, air density {:.5} kg/m3, mass ratio {:.3}",
        r.name,
        r.fixture,
        r.spec.chord_elements,
        r.spec.span_elements,
        r.spec.mass(),
        r.spec.density_kg_m3(),
        aero_name(r.aero),
        r.method,
        r.panels.0,
        r.panels.1,
        r.mach,
        r.density,
        r.spec.mass_ratio(r.density)
    );
    let _ = writeln!(t, "modes:");
    for (j, name) in s.names.iter().enumerate() {
        let _ = writeln!(
            t,
            "  {}  {name}, {:.3} Hz",
            j + 1,
            r.modes.frequencies_hz[j]
        );
    }
    let answer = s.answer();
    let _ = writeln!(
        t,
        "{}",
        answer.headline(s.speeds.last().copied().unwrap_or(0.0), "")
    );
    if let FlutterAnswer::Flutter(f) = answer {
        if let Some((fsi, ratio)) = indices(r, f.speed, f.omega) {
            let _ = writeln!(
                t,
                "  flutter speed index {fsi:.4}, frequency ratio {ratio:.4} (reference frequency {:.2} rad/s)",
                r.reference_frequency.unwrap_or(f64::NAN)
            );
        }
    }
    if let Some(sc) = &s.screen {
        let _ = writeln!(t, "  {}", sc.line());
    }
    if !s.unstable_at_start.is_empty() {
        let _ = writeln!(
            t,
            "warning: branches already unstable at the lowest speed: {:?}",
            s.unstable_at_start
        );
    }
    match &s.divergence {
        Some(d) => {
            let _ = writeln!(
                t,
                "divergence: V = {:.2} m/s, q = {:.1} kPa ({})",
                d.speed,
                d.q / 1e3,
                d.name
            );
        }
        None => {
            let _ = writeln!(t, "divergence: none");
        }
    }
    t
}

pub fn summary_json(r: &TunnelFlutter) -> serde_json::Value {
    let s = &r.solution;
    serde_json::json!({
        "case": "fixture",
        "scenario": r.name,
        "fixture": r.fixture,
        "aero": match r.aero {
            AeroChoice::Unsteady => "unsteady",
            AeroChoice::DoubletLattice => "doublet_lattice",
            AeroChoice::QuasiSteady => "quasi_steady",
        },
        "panels": [r.panels.0, r.panels.1],
        "aero_method": r.method,
        "transonic_bridge": r.bridge.as_ref().map(super::flutter::bridge_json),
        "mach": r.mach,
        "density_kg_m3": r.density,
        "surface_mass_kg": r.spec.mass(),
        "mass_ratio": r.spec.mass_ratio(r.density),
        "reference_frequency_rad_s": r.reference_frequency,
        "modes": s.names.iter().zip(&r.modes.frequencies_hz).map(|(n, f)| serde_json::json!({
            "name": n, "frequency_hz": f
        })).collect::<Vec<_>>(),
        "flutter": s.flutter.iter().map(|f| {
            let idx = indices(r, f.speed, f.omega);
            serde_json::json!({
                "speed_m_s": f.speed,
                "frequency_hz": hz(f.omega),
                "dynamic_pressure_pa": f.q,
                "reduced_frequency": f.k,
                "mode": f.name,
                "partner": f.partner.as_ref().map(|p| p.1.clone()),
                "speed_index": idx.map(|i| i.0),
                "frequency_ratio": idx.map(|i| i.1),
            })
        }).collect::<Vec<_>>(),
        "largest_speed_m_s": s.speeds.last(),
        "unstable_at_lowest_speed": s.unstable_at_start,
        "answer": s.answer().json(),
        "screen": s.screen.as_ref().map(|sc| sc.json()),
        "divergence": s.divergence.as_ref().map(|d| serde_json::json!({
            "speed_m_s": d.speed, "dynamic_pressure_pa": d.q, "mode": d.name
        })),
    })
}

pub fn write_outputs(out: &Path, r: &TunnelFlutter) -> std::io::Result<()> {
    let json = serde_json::to_string_pretty(&summary_json(r)).unwrap_or_default();
    let vg = vg_table(&r.solution);
    super::files::write_all_atomic(
        &[out],
        &[(out.join("vg.csv"), &vg), (out.join("flutter.json"), &json)],
    )
}

/// The tunnel's p-k sweep over `speeds` with the screen below its first speed
/// ([`screen_below`]: no flutter below the lowest tunnel speed goes unseen).
pub fn screened(
    model: &crate::analysis::flutter::pk::FlutterModel,
    gaf: &dyn crate::analysis::flutter::pk::Gaf,
    speeds: &[f64],
) -> Result<PkSolution, crate::analysis::flutter::pk::FlutterError> {
    let mut s = pk_solve(model, gaf, speeds, PkSettings::default())?;
    s.screen = screen_below(model, gaf, s.speeds[0], PkSettings::default())?;
    Ok(s)
}
