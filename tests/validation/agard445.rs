//! The AGARD 445.6 wing, weakened model 3, in air: planform, the published vibration and
//! flutter data, and a plate finite-element model of the wing clamped at its root.
//!
//! # Sources
//!
//! - \[Y87\] E. C. Yates Jr., "AGARD standard aeroelastic configurations for dynamic response.
//!   Candidate configuration I.-Wing 445.6", NASA TM 100492, August 1987; the same text as
//!   AGARD Report 765 (1988). The wing was tested in the NASA Langley Transonic Dynamics
//!   Tunnel; the flutter data of the weakened model 3 in air are those of Yates, Land &
//!   Foughner, NASA TN D-1616 (1963), reproduced in \[Y87\].
//! - The numbers below were read from public transcriptions of \[Y87\], not from a scan of the
//!   report itself (no copy of the report was reachable from this machine):
//!   - planform, measured frequencies: the report's figure 1 / table as quoted in MBDyn's
//!     `tests/plates/agard/agard.awk` (P. Masarati, after the Code_Aster model of G.
//!     Romanelli: "From NASA-TM-100492 ... Figure 1 ... s 2.5 ft, 2b_s 1.833 ft, 2b_t 1.208
//!     ft"), and the 9.60 Hz / 38.17 Hz first bending / torsion frequencies quoted with the
//!     same planform in several DLM validation scripts;
//!   - the flutter table (Mach, density, mass ratio, speed, speed index, flutter frequency,
//!     `ω_α = 239.3 rad/s`): G. Dimitriadis, SDPMflut (PyPI `sdpmflut` 0.6.7,
//!     `AGARD445_6_new/flutter_SDPM_AGARD_new.py`), "Run data from wind tunnel flutter tests
//!     of wing 3 (weakened). Source: ... AGARD REPORT No.765";
//!   - the NACA 65A004 half-thickness ordinates at tenths of the chord and the material
//!     constants of the weakened wing (isotropic `E = 0.47072e6 psi`, `G = 0.059745e6 psi`,
//!     `ν = 0.31`; and the orthotropic equivalent `E_1 = 3.151 GPa`, `E_2 = 0.4162 GPa`,
//!     `G_12 = 0.4392 GPa`, `ν_12 = 0.31` of the Code_Aster model, the values of the
//!     equivalent orthotropic plate used throughout the literature since Kolonay's 1996
//!     Purdue thesis): MBDyn `agard.awk` as above.
//!
//!   The tests check that the published columns agree with each other (speed index from
//!   speed, mass ratio and `ω_α`; one wing mass from every `μ ρ`), which catches a
//!   transcription error in any one number.
//!
//! # Planform and reference quantities
//!
//! Semispan `s = 2.5 ft = 0.762 m`, root chord `c_r = 1.833 ft = 0.5587 m` (streamwise), tip
//! chord `c_t = 1.208 ft = 0.3682 m` (taper 0.659), quarter-chord sweep 45°, so the leading
//! edge is swept by `atan(tan 45° + (c_r - c_t)/(4 s)) = 46.74°`; NACA 65A004 section
//! (streamwise). Reference semichord `b_s = c_r/2`, reference frequency `ω_α = 239.3 rad/s`
//! (the value that reproduces \[Y87\]'s speed-index column; the measured first torsion
//! frequency 38.17 Hz is 239.8 rad/s). Flutter speed index `V_f/(b_s ω_α sqrt(μ))`, mass
//! ratio `μ = m/(ρ V_cone)` with `V_cone = π s (c_r² + c_r c_t + c_t²)/12` the volume of the
//! conical frustum whose bases are the root and tip chords (\[Y87\] symbols). Every `μ ρ` of
//! the table gives the same panel mass, `m = 1.866 kg` (0.1279 slug) — the mass this module
//! gives the model.
//!
//! # The structural model
//!
//! A flat plate on the planform, clamped along the root chord, of MITC4 shells
//! ([`flexflight::structure::generate::cantilever_plate_model`]) whose thickness follows the
//! section, `t(x, y) = c(y) τ(x/c)`, `τ` twice the NACA 65A004 half-thickness ordinate
//! (linear between tenths of the chord, averaged over the element by Gauss quadrature), as
//! in the Code_Aster / MBDyn model above. Two materials:
//!
//! - [`Material::Orthotropic`]: the equivalent orthotropic lamina of the literature, grain
//!   (direction 1) along the spanwise grid lines (lines of constant chord fraction; the
//!   quarter-chord one is swept 45°) or along the 45° line itself ([`Grain`]);
//!   transverse shear `G_13 = G_23 = G_12` (not published; a thin plate barely feels it);
//! - [`Material::Isotropic`]: `E = 0.47072e6 psi` with `ν = 0.31` (the isotropic element
//!   cannot also carry the published `G = 0.059745e6 psi`: `E/(2G) - 1 = 2.94` is no Poisson
//!   ratio), to show what the isotropic element makes of the wing.
//!
//! The density is NOT a published constant of the model: it is the published wing mass over
//! the plate's volume, so the FE mass is the tested wing's. Nothing is tuned to the
//! frequencies.
//!
//! # Mode shapes
//!
//! Node positions are given in the wing's own frame: `x` chordwise aft of the root leading
//! edge, `y` spanwise from the root; `w` is the displacement normal to the plate along
//! `z = x × y` (the lattice frame of [`flexflight::aero::panel`]), per unit modal
//! coordinate of the mass-normalised mode (`φᵀ M φ = 1`, so `w` is in m/sqrt(kg)).

use crate::goland::{FT, SLUG};
use flexflight::aero::FinPlanform;
pub use flexflight::analysis::flutter::wing::{
    Grain, QuasiSteadyProblem, UnsteadyAero, UnsteadyProblem, UnsteadySettings,
    WingError as AgardError, WingModes, k_max_for, quasi_steady_problem, sign_changes,
    unsteady_problem,
};
use flexflight::analysis::flutter::wing::{
    WingDensity, WingMaterial, WingSpec, WingThickness, section_thickness_over_chord,
};
use flexflight::structure::fe_model::FeModel;

/// Pounds per square inch in pascals (1 lbf / (0.0254 m)²).
pub const PSI: f64 = 4.448_221_615_260_5 / (0.0254 * 0.0254);

/// Semispan `s`, m (2.5 ft).
pub const SEMISPAN: f64 = 2.5 * FT;
/// Root chord (streamwise), m (1.833 ft).
pub const ROOT_CHORD: f64 = 1.833 * FT;
/// Tip chord (streamwise), m (1.208 ft).
pub const TIP_CHORD: f64 = 1.208 * FT;
/// Quarter-chord sweep, rad (45°).
pub const QUARTER_CHORD_SWEEP: f64 = std::f64::consts::FRAC_PI_4;
/// Maximum thickness of the NACA 65A004 section, fraction of the chord.
pub const THICKNESS_RATIO: f64 = 0.04;
/// NACA 65A004 half-thickness `z/c` at `x/c = 0, 0.1, ..., 1.0` (module doc).
pub const HALF_THICKNESS: [f64; 11] = [
    0.0, 0.01216, 0.01649, 0.01894, 0.01996, 0.01952, 0.01742, 0.014, 0.00966, 0.0049, 0.00009,
];

/// Measured natural frequencies of the weakened model 3, Hz: first bending, first torsion,
/// second bending, second torsion (\[Y87\]).
pub const MEASURED_HZ: [f64; 4] = [9.60, 38.17, 48.35, 91.54];
/// Reference frequency of the speed index, rad/s (\[Y87\]; module doc).
pub const OMEGA_ALPHA: f64 = 239.3;

/// Isotropic Young's modulus of the weakened wing, Pa (0.47072e6 psi, module doc).
pub const E_ISOTROPIC: f64 = 0.47072e6 * PSI;
/// Shear modulus of the weakened wing, Pa (0.059745e6 psi, module doc).
pub const G_ISOTROPIC: f64 = 0.059745e6 * PSI;
/// Poisson's ratio (0.31).
pub const POISSON: f64 = 0.31;
/// Equivalent orthotropic lamina (module doc): `E_1`, `E_2`, `G_12`, Pa.
pub const E1: f64 = 3.151e9;
pub const E2: f64 = 0.4162e9;
pub const G12: f64 = 0.4392e9;

/// One flutter point of the weakened model 3 in air (\[Y87\], SI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlutterTest {
    pub mach: f64,
    /// Test-section density, kg/m³.
    pub density: f64,
    /// Mass ratio `μ` (module doc).
    pub mass_ratio: f64,
    /// Flutter speed, m/s.
    pub speed: f64,
    /// `V_f/(b_s ω_α sqrt(μ))` as published.
    pub speed_index: f64,
    /// Flutter frequency, rad/s.
    pub omega: f64,
}

impl FlutterTest {
    /// `ω_f/ω_α`.
    pub fn frequency_ratio(&self) -> f64 {
        self.omega / OMEGA_ALPHA
    }
}

const fn test(
    mach: f64,
    rho_slug_ft3: f64,
    mu: f64,
    v_ft_s: f64,
    fsi: f64,
    omega: f64,
) -> FlutterTest {
    FlutterTest {
        mach,
        density: rho_slug_ft3 * SLUG / (FT * FT * FT),
        mass_ratio: mu,
        speed: v_ft_s * FT,
        speed_index: fsi,
        omega,
    }
}

/// The published flutter points in air, weakened model 3 (module doc for the source):
/// density in slug/ft³, speed in ft/s as published, converted exactly. The subsonic points
/// of the table are M = 0.499 .. 0.960; the report's M = 0.338 point and the supersonic
/// points (M = 1.072, 1.141) were not in the transcription reached, so they are absent.
pub const FLUTTER_TESTS: [FlutterTest; 6] = [
    test(0.499, 0.000830, 33.465, 565.8, 0.4459, 128.1),
    test(0.678, 0.000404, 68.753, 759.1, 0.4174, 113.0),
    test(0.901, 0.000193, 143.920, 973.4, 0.3700, 101.1),
    test(0.954, 0.000123, 225.820, 1008.4, 0.3059, 91.1),
    test(0.957, 0.000123, 225.820, 1013.8, 0.3076, 87.3),
    test(0.960, 0.000123, 225.820, 1020.2, 0.3095, 87.9),
];

/// Reference semichord `b_s = c_r/2`, m.
pub fn semichord() -> f64 {
    0.5 * ROOT_CHORD
}

/// Leading-edge sweep, rad: `atan(tan Λ_c/4 + (c_r - c_t)/(4 s))` (straight edges).
pub fn leading_edge_sweep() -> f64 {
    (QUARTER_CHORD_SWEEP.tan() + (ROOT_CHORD - TIP_CHORD) / (4.0 * SEMISPAN)).atan()
}

/// Volume of the conical frustum of the mass ratio, m³ (module doc).
pub fn cone_volume() -> f64 {
    let (cr, ct) = (ROOT_CHORD, TIP_CHORD);
    std::f64::consts::PI * SEMISPAN * (cr * cr + cr * ct + ct * ct) / 12.0
}

/// Panel mass `μ ρ V_cone` of a flutter point, kg.
pub fn panel_mass(t: &FlutterTest) -> f64 {
    t.mass_ratio * t.density * cone_volume()
}

/// The wing mass the model carries: the mean of [`panel_mass`] over [`FLUTTER_TESTS`], kg.
pub fn wing_mass() -> f64 {
    FLUTTER_TESTS.iter().map(panel_mass).sum::<f64>() / FLUTTER_TESTS.len() as f64
}

/// Section thickness over chord `τ(x/c) = 2 z/c` (linear between the tabulated ordinates).
pub fn thickness_over_chord(xc: f64) -> f64 {
    section_thickness_over_chord(&HALF_THICKNESS, xc)
}

/// Plate material of the model (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Material {
    Orthotropic(Grain),
    Isotropic,
}

/// Mesh and material of a model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelSpec {
    pub chord_elements: usize,
    pub span_elements: usize,
    pub material: Material,
}

impl Default for ModelSpec {
    fn default() -> Self {
        ModelSpec {
            chord_elements: 16,
            span_elements: 16,
            material: Material::Orthotropic(Grain::GridLines),
        }
    }
}

/// The surface of `spec` (module doc): the orthotropic plate with the section's thickness and
/// the wing's mass, or the isotropic plate of the section's mean thickness (the plate's volume
/// is the section's) with the density of the section's volume.
pub fn wing_spec(spec: &ModelSpec) -> WingSpec {
    let section = WingSpec {
        span: SEMISPAN,
        root_chord: ROOT_CHORD,
        tip_chord: TIP_CHORD,
        leading_edge_sweep: leading_edge_sweep(),
        thickness: WingThickness::Section(HALF_THICKNESS.to_vec()),
        material: WingMaterial::Orthotropic {
            e1: E1,
            e2: E2,
            nu12: POISSON,
            g12: G12,
            grain: Grain::GridLines,
        },
        density: WingDensity::Mass(wing_mass()),
        chord_elements: spec.chord_elements,
        span_elements: spec.span_elements,
    };
    match spec.material {
        Material::Orthotropic(grain) => WingSpec {
            material: WingMaterial::Orthotropic {
                e1: E1,
                e2: E2,
                nu12: POISSON,
                g12: G12,
                grain,
            },
            ..section
        },
        Material::Isotropic => {
            let volume = section.plate_volume();
            let area = 0.5 * (ROOT_CHORD + TIP_CHORD) * SEMISPAN;
            WingSpec {
                thickness: WingThickness::Constant(volume / area),
                material: WingMaterial::Isotropic {
                    youngs_modulus: E_ISOTROPIC,
                    poisson: POISSON,
                },
                density: WingDensity::Density(wing_mass() / volume),
                ..section
            }
        }
    }
}

/// Builds the clamped FE model of `spec` (module doc).
pub fn wing_model(spec: &ModelSpec) -> Result<FeModel, AgardError> {
    wing_spec(spec).model()
}

/// The lowest `count` modes of the model of `spec` (module doc).
pub fn wing_modes(spec: &ModelSpec, count: usize) -> Result<WingModes, AgardError> {
    wing_spec(spec).modes(count)
}

/// The planform as the panel model's surface (root at the reflection plane).
pub fn planform() -> FinPlanform {
    wing_spec(&ModelSpec::default()).planform()
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    /// The published columns agree with each other: the speed index recomputed from speed,
    /// mass ratio, `b_s` and `ω_α` matches the published one within the sum of the
    /// half-units of the printed digits of V, μ, ω_α and the index (achieved 2.2e-4 relative
    /// at worst, M = 0.954, against a bound of 3.9e-4 there), and every `μ ρ` gives the same
    /// panel mass (spread 7e-5 relative).
    #[test]
    fn published_columns_are_consistent() {
        for t in &FLUTTER_TESTS {
            let fsi = t.speed / (semichord() * OMEGA_ALPHA * t.mass_ratio.sqrt());
            let err = (fsi / t.speed_index - 1.0).abs();
            let v_ft = t.speed / FT;
            let bound = 0.5e-4 / t.speed_index
                + 0.05 / v_ft
                + 0.05 / OMEGA_ALPHA
                + 0.5 * 0.5e-3 / t.mass_ratio;
            println!(
                "M {}: FSI {fsi:.5} vs {} ({err:.1e}, bound {bound:.1e})",
                t.mach, t.speed_index
            );
            assert!(err < bound, "M {}: {fsi} vs {}", t.mach, t.speed_index);
        }
        let m: Vec<f64> = FLUTTER_TESTS.iter().map(panel_mass).collect();
        let (lo, hi) = m
            .iter()
            .fold((f64::MAX, 0.0_f64), |(a, b), &v| (a.min(v), b.max(v)));
        println!("panel mass {lo:.5} .. {hi:.5} kg");
        assert!((hi - lo) / lo < 1e-4, "{m:?}");
        assert!((wing_mass() - 1.866).abs() < 1e-3, "{}", wing_mass());
    }

    #[test]
    fn planform_figures() {
        assert!((leading_edge_sweep().to_degrees() - 46.736).abs() < 1e-3);
        assert!((TIP_CHORD / ROOT_CHORD - 0.659).abs() < 1e-3);
        assert!((thickness_over_chord(0.4) - 0.03992).abs() < 1e-12);
        assert!((thickness_over_chord(0.45) - 0.5 * (0.03992 + 0.03904)).abs() < 1e-12);
    }

    fn report(spec: &ModelSpec) -> WingModes {
        let m = wing_modes(spec, 4).unwrap();
        println!(
            "{:?} {}x{}: mass off the clamped row {:.4} kg (wing {:.4})",
            spec.material,
            spec.chord_elements,
            spec.span_elements,
            m.mass,
            wing_mass()
        );
        for (k, (f, want)) in m.frequencies_hz.iter().zip(MEASURED_HZ).enumerate() {
            println!(
                "  mode {}: {f:.3} Hz vs {want} ({:+.2} %), signature {:?}",
                k + 1,
                100.0 * (f / want - 1.0),
                m.nodal_signature(k)
            );
        }
        m
    }

    fn errors(m: &WingModes) -> Vec<f64> {
        m.frequencies_hz
            .iter()
            .zip(MEASURED_HZ)
            .map(|(f, want)| f / want - 1.0)
            .collect()
    }

    /// The equivalent orthotropic plate (16 x 16 quads, grain along the spanwise grid lines)
    /// against the measured frequencies: -5.31 %, -0.74 %, -0.26 %, -0.22 % (mode 1 is the
    /// outlier, and stays so on a 24 x 24 mesh: -5.17 %). Tolerances: 6 % on mode 1, 1 % on
    /// modes 2-4.
    #[test]
    fn frequencies_against_measured() {
        let spec = ModelSpec::default();
        let m = report(&spec);
        let e = errors(&m);
        // The density is the published mass over the plate's volume.
        let w = wing_spec(&spec);
        assert!(w.plate_volume() > 0.0);
        assert_eq!(w.density_kg_m3(), wing_mass() / w.plate_volume());
        // The clamped row takes about half a strip of the mass off the free nodes.
        assert!(m.mass < wing_mass() && m.mass > wing_mass() * (1.0 - 1.0 / 16.0));
        println!("errors: grid-line grain {e:?}");
        assert!(e[0].abs() < 0.06, "{e:?}");
        for k in 1..4 {
            assert!(e[k].abs() < 0.01, "mode {}: {e:?}", k + 1);
        }
    }

    /// The grain along the 45° line and the isotropic plate (printed, docs/validation.md):
    /// 45°: -6.13, -0.05, -1.67, +1.03 %; isotropic: -26.2, -12.5, +6.7, -4.3 %.
    #[test]
    #[ignore = "slow (two more models); run with --ignored to print"]
    fn material_sensitivity() {
        let spec = ModelSpec::default();
        let quarter = report(&ModelSpec {
            material: Material::Orthotropic(Grain::Swept(QUARTER_CHORD_SWEEP)),
            ..spec
        });
        let iso = report(&ModelSpec {
            material: Material::Isotropic,
            ..spec
        });
        println!("errors: 45 deg grain {:?}", errors(&quarter));
        println!("errors: isotropic {:?}", errors(&iso));
        // The isotropic plate cannot carry the wood's torsional softness: its first bending
        // is the worst of the three models.
        assert!(errors(&iso)[0] < errors(&quarter)[0]);
    }

    /// The four modes are, in order, first bending, first torsion, second bending, second
    /// torsion, read from their nodal lines: sign changes along (leading edge, trailing edge,
    /// tip chord) = (0, 0, 0): no nodal line but the root; (0, 0, 1): one line running
    /// spanwise, crossing the tip chord; (0, 1, 0): one line across the span, from the
    /// trailing edge; (1, 1, 1): a spanwise and a cross-span line.
    #[test]
    fn mode_shapes_identified_by_nodal_lines() {
        let m = wing_modes(&ModelSpec::default(), 4).unwrap();
        let want = [(0, 0, 0), (0, 0, 1), (0, 1, 0), (1, 1, 1)];
        for (k, w) in want.iter().enumerate() {
            assert_eq!(m.nodal_signature(k), *w, "mode {}", k + 1);
        }
        let kinds: Vec<_> = (0..4).map(|k| m.kind(k)).collect();
        assert_eq!(
            kinds,
            [
                Some("1st bending"),
                Some("1st torsion"),
                Some("2nd bending"),
                Some("2nd torsion")
            ]
        );
        // First bending: the tip moves one way at both edges; first torsion: the tip's
        // leading and trailing edges move in opposite directions.
        let tip = |k: usize| {
            let t = m.tip_chord(k);
            (t[0], t[t.len() - 1])
        };
        assert!(tip(0).0 * tip(0).1 > 0.0);
        assert!(tip(1).0 * tip(1).1 < 0.0);
        // Mass-normalised: phi^T M phi = 1.
        for k in 0..4 {
            let phi = m.shapes.col(k);
            let mut v = Mat::<f64>::zeros(phi.nrows(), 1);
            for r in 0..phi.nrows() {
                v[(r, 0)] = phi[r];
            }
            let mv = &m.model.mass * &v;
            let g: f64 = (0..phi.nrows()).map(|r| phi[r] * mv[(r, 0)]).sum();
            assert!((g - 1.0).abs() < 1e-9, "mode {k}: {g}");
        }
    }

    /// The QUASI-STEADY flutter case (vortex lattice 12 x 12, `C(k) = 1`, no apparent mass)
    /// at the subsonic test points with the published density: printed against the
    /// experiment, not asserted (this is not the unsteady comparison of issue 13). Asserted
    /// only: a flutter point exists below 400 m/s and is the torsion branch.
    #[test]
    #[ignore = "slow (three p-k sweeps); run with --ignored to print the table"]
    fn quasi_steady_flutter_table() {
        use flexflight::analysis::flutter::pk::{PkSettings, pk_solve};
        let modes = wing_modes(&ModelSpec::default(), 4).unwrap();
        let speeds: Vec<f64> = (1..=80).map(|i| 5.0 * i as f64).collect();
        println!("| M | FSI exp | FSI quasi-steady | diff | w_f/w_a exp | quasi-steady | diff |");
        for t in FLUTTER_TESTS.iter().filter(|t| t.mach < 0.95) {
            let (model, gaf) = quasi_steady_problem(&modes, t.mach, t.density, 12, 12).unwrap();
            let sol = pk_solve(&model, &gaf, &speeds, PkSettings::default()).unwrap();
            let f = sol.critical().expect("no flutter point below 400 m/s");
            let fsi = f.speed / (semichord() * OMEGA_ALPHA * t.mass_ratio.sqrt());
            let ratio = f.omega / OMEGA_ALPHA;
            println!(
                "| {} | {} | {fsi:.4} | {:+.1} % | {:.4} | {ratio:.4} | {:+.1} % | {} with {:?}, V {:.1} m/s",
                t.mach,
                t.speed_index,
                100.0 * (fsi / t.speed_index - 1.0),
                t.frequency_ratio(),
                100.0 * (ratio / t.frequency_ratio() - 1.0),
                f.name,
                f.partner.as_ref().map(|p| &p.1),
                f.speed
            );
            assert!(f.name.contains("torsion"), "{}", f.name);
        }
    }

    /// The unsteady case of the tests below: 4 modes of the default model, the sweep
    /// `V_MIN..=400` m/s by 5, `k_max` from [`k_max_for`] at `V_MIN` (3.21), 25 tabulated `k`,
    /// 12 spanwise strips (chordwise from the box-size rule: 13).
    const V_MIN: f64 = 60.0;

    struct UnsteadyResult {
        spanwise: usize,
        fsi: f64,
        ratio: f64,
        speed: f64,
        name: String,
        partner: Option<String>,
        chordwise: usize,
        wake_rings: usize,
    }

    fn unsteady_flutter(
        modes: &WingModes,
        t: &FlutterTest,
        k_count: usize,
        spanwise: usize,
        min_chordwise: usize,
        aero: UnsteadyAero,
    ) -> Result<UnsteadyResult, AgardError> {
        use flexflight::analysis::flutter::pk::{PkSettings, pk_solve};
        let speeds: Vec<f64> = (0..=((400.0 - V_MIN) / 5.0) as usize)
            .map(|i| V_MIN + 5.0 * i as f64)
            .collect();
        let settings = UnsteadySettings {
            aero,
            k_max: k_max_for(modes, V_MIN),
            k_count,
            spanwise,
            min_chordwise,
        };
        let p = unsteady_problem(modes, t.mach, t.density, &settings)?;
        let sol = pk_solve(&p.model, &p.gaf, &speeds, PkSettings::default())?;
        let f = sol.critical().expect("no flutter point below 400 m/s");
        Ok(UnsteadyResult {
            fsi: f.speed / (semichord() * OMEGA_ALPHA * t.mass_ratio.sqrt()),
            ratio: f.omega / OMEGA_ALPHA,
            speed: f.speed,
            name: f.name.clone(),
            partner: f.partner.as_ref().map(|p| p.1.clone()),
            chordwise: p.chordwise,
            spanwise: p.spanwise,
            wake_rings: p.wake_rings,
        })
    }

    fn print_unsteady(t: &FlutterTest, r: &UnsteadyResult) {
        println!(
            "| {} | {} | {:.4} | {:+.1} % | {:.4} | {:.4} | {:+.1} % | {} with {:?}, V {:.1} m/s, {} x {} panels, {} wake rings",
            t.mach,
            t.speed_index,
            r.fsi,
            100.0 * (r.fsi / t.speed_index - 1.0),
            t.frequency_ratio(),
            r.ratio,
            100.0 * (r.ratio / t.frequency_ratio() - 1.0),
            r.name,
            r.partner,
            r.speed,
            r.chordwise,
            r.spanwise,
            r.wake_rings
        );
    }

    /// The UNSTEADY flutter case at M = 0.499 against the experiment (a regression fence on
    /// the published comparison, not a fit): achieved FSI 0.4512 (exp. 0.4459, +1.2 %),
    /// frequency ratio 0.6153 (exp. 0.5353, +15.0 %), first torsion with first bending at
    /// 174.5 m/s (docs/validation.md says why the frequency is high).
    #[test]
    fn unsteady_flutter_m0499() {
        let modes = wing_modes(&ModelSpec::default(), 4).unwrap();
        let t = &FLUTTER_TESTS[0];
        let r = unsteady_flutter(&modes, t, 25, 12, 0, UnsteadyAero::VortexLattice).unwrap();
        print_unsteady(t, &r);
        assert_eq!(r.chordwise, 13);
        assert!(r.name.contains("torsion"), "{}", r.name);
        assert!(r.partner.as_deref().is_some_and(|p| p.contains("bending")));
        let (e_fsi, e_ratio) = (
            r.fsi / t.speed_index - 1.0,
            r.ratio / t.frequency_ratio() - 1.0,
        );
        // Achieved +1.2 % and +15.0 %.
        assert!(e_fsi.abs() < 0.02, "FSI {} ({e_fsi:+.3})", r.fsi);
        assert!(
            e_ratio.abs() < 0.16,
            "frequency ratio {} ({e_ratio:+.3})",
            r.ratio
        );
    }

    /// Convergence of the M = 0.499 unsteady case (printed): the k table doubled, the
    /// chordwise and the spanwise panels doubled; then sensitivities (not comparisons): the
    /// same density at M = 0 and 0.3, 6 modes, the grain along the 45° line. Printed
    /// (docs/validation.md): 49 k 0.4512 / 0.6154; 26 x 12 0.4508 / 0.6222; 13 x 24
    /// 0.4568 / 0.6120; M = 0 0.4608 / 0.6083; M = 0.3 0.4574 / 0.6107; 45° grain 0.4588 /
    /// 0.6143; 6 modes: the same torsion-bending point 0.4508 / 0.6214, plus spurious
    /// crossings of mode 6, an in-plane mode (max |w| 2.7e-10) whose damping is round-off.
    #[test]
    #[ignore = "slow (four p-k sweeps, one on 26 x 12 and one on 13 x 24 panels)"]
    fn unsteady_convergence() {
        let modes = wing_modes(&ModelSpec::default(), 4).unwrap();
        let t = &FLUTTER_TESTS[0];
        for (k_count, spanwise, chordwise) in [(25, 12, 0), (49, 12, 0), (25, 12, 26), (25, 24, 0)]
        {
            let r = unsteady_flutter(
                &modes,
                t,
                k_count,
                spanwise,
                chordwise,
                UnsteadyAero::VortexLattice,
            )
            .unwrap();
            print!("{k_count} k: ");
            print_unsteady(t, &r);
        }
        // Compressibility sensitivity (not a comparison): the same density at M = 0 and 0.3.
        for mach in [0.0, 0.3] {
            let r = unsteady_flutter(
                &modes,
                &FlutterTest { mach, ..*t },
                25,
                12,
                0,
                UnsteadyAero::VortexLattice,
            )
            .unwrap();
            print!("M {mach} with the M = 0.499 density: ");
            print_unsteady(t, &r);
        }
        // Structural sensitivity: 6 modes instead of 4; the grain along the 45° line.
        let six = wing_modes(&ModelSpec::default(), 6).unwrap();
        println!("6 modes: {:?} Hz", six.frequencies_hz);
        // The largest normal displacement of each mode (an in-plane mode has next to none).
        let w_max: Vec<f64> = six
            .w
            .iter()
            .map(|w| w.iter().fold(0.0_f64, |a, v| a.max(v.abs())))
            .collect();
        println!("  max |w| per mode {w_max:?}");
        let settings = UnsteadySettings {
            aero: UnsteadyAero::VortexLattice,
            k_max: k_max_for(&six, V_MIN),
            k_count: 25,
            spanwise: 12,
            min_chordwise: 0,
        };
        let p = unsteady_problem(&six, t.mach, t.density, &settings).unwrap();
        let speeds: Vec<f64> = (0..=68).map(|i| V_MIN + 5.0 * i as f64).collect();
        let sol = flexflight::analysis::flutter::pk::pk_solve(
            &p.model,
            &p.gaf,
            &speeds,
            flexflight::analysis::flutter::pk::PkSettings::default(),
        )
        .unwrap();
        println!(
            "  {} x {} panels, unstable at the first speed: {:?}",
            p.chordwise, p.spanwise, sol.unstable_at_start
        );
        for f in &sol.flutter {
            println!(
                "  flutter: {} with {:?} at {:.1} m/s, FSI {:.4}, w/w_a {:.4}, k {:.3}",
                f.name,
                f.partner.as_ref().map(|p| &p.1),
                f.speed,
                f.speed / (semichord() * OMEGA_ALPHA * t.mass_ratio.sqrt()),
                f.omega / OMEGA_ALPHA,
                f.k
            );
        }
        let quarter = wing_modes(
            &ModelSpec {
                material: Material::Orthotropic(Grain::Swept(QUARTER_CHORD_SWEEP)),
                ..ModelSpec::default()
            },
            4,
        )
        .unwrap();
        let r = unsteady_flutter(&quarter, t, 25, 12, 0, UnsteadyAero::VortexLattice).unwrap();
        print!("45 deg grain: ");
        print_unsteady(t, &r);
    }

    /// The unsteady table at M = 0.499 and 0.678 (printed), and M = 0.901, which the
    /// harmonic lattice refuses (beyond its trusted M = 0.9).
    #[test]
    #[ignore = "slow (p-k sweeps); run with --ignored to print the table"]
    fn unsteady_flutter_table() {
        let modes = wing_modes(&ModelSpec::default(), 4).unwrap();
        for t in FLUTTER_TESTS.iter().filter(|t| t.mach < 0.95) {
            match unsteady_flutter(&modes, t, 25, 12, 0, UnsteadyAero::VortexLattice) {
                Ok(r) => print_unsteady(t, &r),
                Err(e) => println!("| {} | refused: {e} |", t.mach),
            }
        }
    }

    /// The DOUBLET-LATTICE flutter case at M = 0.499 and 0.678 against the experiment (a
    /// regression fence on the published comparison, not a fit; the same lattice, k table and
    /// sweep as [`unsteady_flutter_m0499`]): achieved FSI 0.4529 (+1.6 %) and 0.4316 (+3.4 %),
    /// frequency ratio 0.5851 (+9.3 %) and 0.5298 (+12.2 %), the first-bending branch
    /// coalescing with first torsion at 175.2 and 239.2 m/s (docs/validation.md).
    #[test]
    fn dlm_flutter_m0499_m0678() {
        let modes = wing_modes(&ModelSpec::default(), 4).unwrap();
        for (t, fsi_tol, ratio_tol) in [
            (&FLUTTER_TESTS[0], 0.02, 0.10),
            (&FLUTTER_TESTS[1], 0.04, 0.13),
        ] {
            let r = unsteady_flutter(&modes, t, 25, 12, 0, UnsteadyAero::DoubletLattice).unwrap();
            print_unsteady(t, &r);
            assert_eq!((r.chordwise, r.wake_rings), (13, 0));
            let pair = format!("{} {}", r.name, r.partner.as_deref().unwrap_or(""));
            assert!(
                pair.contains("torsion") && pair.contains("bending"),
                "{pair}"
            );
            let (e_fsi, e_ratio) = (
                r.fsi / t.speed_index - 1.0,
                r.ratio / t.frequency_ratio() - 1.0,
            );
            assert!(
                e_fsi.abs() < fsi_tol,
                "M {}: FSI {} ({e_fsi:+.3})",
                t.mach,
                r.fsi
            );
            assert!(
                e_ratio.abs() < ratio_tol,
                "M {}: frequency ratio {} ({e_ratio:+.3})",
                t.mach,
                r.ratio
            );
        }
    }

    /// The doublet-lattice table (printed): M = 0.499, 0.678, 0.901 with the DLM (the same
    /// lattice, k table and p-k sweep as the vortex-lattice case), then the M = 0.499 density
    /// at M = 0 and 0.3 (compressibility sensitivity), the chordwise and the spanwise doubling
    /// at M = 0.678 and 0.901.
    #[test]
    #[ignore = "slow (nine p-k sweeps); run with --ignored to print the table"]
    fn dlm_flutter_table() {
        let modes = wing_modes(&ModelSpec::default(), 4).unwrap();
        for t in FLUTTER_TESTS.iter().filter(|t| t.mach < 0.95) {
            match unsteady_flutter(&modes, t, 25, 12, 0, UnsteadyAero::DoubletLattice) {
                Ok(r) => print_unsteady(t, &r),
                Err(e) => println!("| {} | refused: {e} |", t.mach),
            }
        }
        let t = &FLUTTER_TESTS[0];
        for mach in [0.0, 0.3] {
            let r = unsteady_flutter(
                &modes,
                &FlutterTest { mach, ..*t },
                25,
                12,
                0,
                UnsteadyAero::DoubletLattice,
            )
            .unwrap();
            print!("DLM at M {mach} with the M = 0.499 density: ");
            print_unsteady(t, &r);
        }
        for (t, spanwise, chordwise) in [
            (&FLUTTER_TESTS[1], 12, 26),
            (&FLUTTER_TESTS[1], 24, 0),
            (&FLUTTER_TESTS[2], 12, 26),
            (&FLUTTER_TESTS[2], 24, 0),
        ] {
            let r = unsteady_flutter(
                &modes,
                t,
                25,
                spanwise,
                chordwise,
                UnsteadyAero::DoubletLattice,
            )
            .unwrap();
            print!("DLM {spanwise} strips, chordwise >= {chordwise}: ");
            print_unsteady(t, &r);
        }
    }

    /// Mesh convergence of the default model (printed): 8 x 8, 12 x 12, 16 x 16, 24 x 24.
    #[test]
    #[ignore = "slow (24 x 24 mesh); run with --ignored to print the table"]
    fn mesh_convergence() {
        for n in [8, 12, 16, 24] {
            let _ = report(&ModelSpec {
                chord_elements: n,
                span_elements: n,
                ..ModelSpec::default()
            });
        }
    }
}
