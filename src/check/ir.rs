//! The typed intermediate representation produced by the checker.
//!
//! Everything is in SI units (lengths m, masses kg, times s, angles rad, pressures Pa);
//! every value keeps the span it was written at, so later stages (structure, plan, runtime,
//! analysis) can point their own errors at the vehicle file. Paths of referenced files are
//! resolved (relative to the declaring file) and known to exist at check time.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::syntax::{Span, Spanned};

pub use super::nose::NoseShape;

/// A scalar in SI with its span.
pub type Q = Spanned<f64>;
/// A 3-vector in SI with its span.
pub type V3 = Spanned<[f64; 3]>;

/// Everything declared by the checked files (imports included).
#[derive(Clone, Debug, Default)]
pub struct Program {
    pub materials: Vec<Material>,
    pub vehicles: Vec<Vehicle>,
    pub scenarios: Vec<Scenario>,
    pub sweeps: Vec<Sweep>,
    /// Wind-tunnel models: a lifting surface clamped at its root.
    pub fixtures: Vec<Fixture>,
    /// Scenarios that test a fixture in a wind tunnel (`scenario NAME { fixture = ... }`).
    pub tunnel_tests: Vec<TunnelTest>,
    /// Monte Carlo dispersions of a scenario.
    pub dispersions: Vec<Dispersion>,
}

impl Program {
    pub fn vehicle(&self, name: &str) -> Option<&Vehicle> {
        self.vehicles.iter().find(|v| v.name.value == name)
    }
    pub fn scenario(&self, name: &str) -> Option<&Scenario> {
        self.scenarios.iter().find(|s| s.name.value == name)
    }
    pub fn sweep(&self, name: &str) -> Option<&Sweep> {
        self.sweeps.iter().find(|s| s.name.value == name)
    }
    pub fn dispersion(&self, name: &str) -> Option<&Dispersion> {
        self.dispersions.iter().find(|s| s.name.value == name)
    }
    pub fn tunnel_test(&self, name: &str) -> Option<&TunnelTest> {
        self.tunnel_tests.iter().find(|s| s.name.value == name)
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Material {
    pub name: Spanned<String>,
    /// Young's modulus E, Pa.
    pub youngs_modulus: Q,
    /// Poisson's ratio nu, 0 < nu < 0.5.
    pub poisson: Q,
    /// Density rho, kg/m^3.
    pub density: Q,
    /// Yield stress, Pa (optional: the fin stress monitor needs it).
    pub yield_stress: Option<Q>,
    /// Ultimate stress, Pa.
    pub ultimate_stress: Option<Q>,
    /// An orthotropic lamina (`E2`, `G12` written): `E` is then the modulus along the grain
    /// and `nu` is `nu_12`. A fixture's surface and a vehicle's fins take one; the body is
    /// isotropic.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orthotropic: Option<Orthotropic>,
}

/// `fins { grain = chordwise | spanwise }`: the 1-direction of the fins' lamina along the
/// root chord (default) or normal to it, along the span.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum FinGrain {
    #[default]
    Chordwise,
    Spanwise,
}

impl FinGrain {
    pub fn is_chordwise(&self) -> bool {
        *self == FinGrain::Chordwise
    }
    /// The grain's angle from the root chord, rad, counter-clockwise about the fin's normal
    /// in the generator's local frame (`a` along the root chord toward the leading edge, `b`
    /// outboard): 0 or pi/2.
    pub fn angle(&self) -> f64 {
        match self {
            FinGrain::Chordwise => 0.0,
            FinGrain::Spanwise => std::f64::consts::FRAC_PI_2,
        }
    }
}

impl Material {
    /// The in-plane shear modulus, Pa: `G12` of a lamina, else `E / (2 (1 + nu))`.
    pub fn in_plane_shear_modulus(&self) -> f64 {
        match &self.orthotropic {
            Some(o) => o.g12.value,
            None => self.youngs_modulus.value / (2.0 * (1.0 + self.poisson.value)),
        }
    }
}

/// The transverse constants of an orthotropic lamina (plane stress).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Orthotropic {
    /// Young's modulus across the grain, Pa.
    pub e2: Q,
    /// In-plane shear modulus, Pa.
    pub g12: Q,
}

/// A wind-tunnel model: one lifting surface clamped at its root along the tunnel wall (a
/// reflection plane), the fin designer's case written next to a rocket.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fixture {
    pub name: Spanned<String>,
    pub span: Span,
    pub surface: Surface,
    /// Elastic modes of the clamped surface in the flutter analysis.
    pub modes: Spanned<usize>,
    /// The surface's plate mesh: chordwise x spanwise quads.
    pub chord_elements: Spanned<usize>,
    pub span_elements: Spanned<usize>,
    /// Spanwise strips of the panel lattice (the chordwise count follows the box rule).
    pub spanwise_panels: Spanned<usize>,
    /// `ω_α` of the flutter speed index `V/(b ω_α sqrt μ)` (Yates 1987), rad/s.
    pub reference_frequency: Option<Q>,
}

/// The clamped lifting surface of a [`Fixture`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Surface {
    pub span_: Span,
    pub span: Q,
    pub root_chord: Q,
    pub tip_chord: Q,
    /// Leading-edge sweep, rad (derived when another sweep was given).
    pub leading_edge_sweep: Q,
    pub thickness: SurfaceThickness,
    pub material: Material,
    /// Direction of the grain (orthotropic material only).
    pub grain: SurfaceGrain,
    /// The surface's mass: the density is then mass / plate volume, not the material's.
    pub mass: Option<Q>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum SurfaceThickness {
    Constant(Q),
    /// Half-thickness over chord at evenly spaced chord fractions, leading to trailing edge.
    Section(Spanned<Vec<f64>>),
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum SurfaceGrain {
    /// Along the spanwise grid lines (lines of constant chord fraction).
    GridLines,
    /// Along a straight line swept back by this angle, rad.
    Swept(f64),
}

/// `scenario NAME { fixture = ...; tunnel { ... } }`: a flutter test of a fixture.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TunnelTest {
    pub name: Spanned<String>,
    pub span: Span,
    /// The fixture with the scenario's `with` and `--set` overrides applied.
    pub fixture: Fixture,
    pub overrides: Vec<Override>,
    pub mach: Q,
    /// Test-section air density, kg/m^3.
    pub density: Q,
    /// Tunnel speeds of the p-k sweep, m/s, increasing.
    pub speeds: Spanned<Vec<f64>>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Vehicle {
    pub name: Spanned<String>,
    /// Span of the whole `vehicle` header, for errors about the vehicle as a whole.
    pub span: Span,
    pub material: Material,
    pub structure: Structure,
    pub origin: NodeRef,
    pub key_nodes: KeyNodes,
    pub modes: ModeSelection,
    pub fins: Option<Fins>,
    /// Further fin sets (`fins NAME { ... }`, issue 34: canards, a second set), fore to aft
    /// as written: rigid (their mass a rigid body on the nearest body node, their
    /// aerodynamics in the built-in estimator's body table), never meshed or flexible.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fin_sets: Vec<FinSet>,
    pub aero: Aero,
    pub forces: Forces,
    /// The motor (propellant burning during the flight), if any.
    pub motor: Option<Motor>,
}

/// A solid motor inside the vehicle: its casing and propellant masses enter the structure
/// (the propellant as a separate mass whose fraction burns during the run), its curve gives
/// the thrust at its aft end.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Motor {
    pub name: Spanned<String>,
    /// Span of the `motor` block header.
    pub header: Span,
    /// Thrust curve: RASP `.eng` or CSV (t, N), read and checked at `check`.
    pub curve: Spanned<PathBuf>,
    /// Aft end of the motor (nozzle exit) on the body axis, body frame, m.
    pub position: V3,
    /// Motor length (forward from `position`), m.
    pub length: Q,
    /// Outer diameter of the motor (casing and grain), m.
    pub diameter: Q,
    /// Propellant mass at ignition, kg (the RASP header's unless given).
    pub propellant_mass: Q,
    /// Loaded motor mass (casing + propellant), kg (the RASP header's unless given).
    pub total_mass: Q,
}

/// Where the FE model comes from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Structure {
    Generate(Generate),
    Files(FeFiles),
}

/// The built-in FE generator's inputs (the fins come from the vehicle's `fins` block).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Generate {
    pub span: Span,
    pub body: BodyGeometry,
    /// Fin mesh density (elements along the span and along the chord).
    pub fin_span_elements: Spanned<usize>,
    pub fin_chord_elements: Spanned<usize>,
    pub point_masses: Vec<PointMass>,
    pub distributed_masses: Vec<DistributedMass>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyGeometry {
    pub length: Q,
    pub diameter: Q,
    pub wall: Q,
    /// Nose length (0: a plain tube).
    pub nose_length: Q,
    /// Nose profile (`conical` unless given; `check::nose`).
    pub nose_shape: Spanned<NoseShape>,
    pub elements: Spanned<usize>,
    pub theory: Spanned<BeamTheory>,
    /// Transitions and boat tails, fore to aft (`check::transition`; none: one diameter).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub transitions: Vec<Transition>,
    /// Launch lugs (`body { launch_lug { ... } }`; `check::launch_guide`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub launch_lugs: Vec<LaunchLug>,
    /// Rail buttons (`body { rail_button { ... } }`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rail_buttons: Vec<RailButton>,
}

/// A launch lug on the generated body: its drag in the built-in aerodynamics, its mass a
/// point mass on the axis at its middle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LaunchLug {
    pub span: Span,
    /// Body-x station of its fore end (< 0).
    pub station: Q,
    pub length: Q,
    pub outer_diameter: Q,
    /// The bore (0: a solid rod).
    pub inner_diameter: Q,
    pub mass: Q,
}

/// A rail button on the generated body: its drag in the built-in aerodynamics, its mass a
/// point mass on the axis at its station.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RailButton {
    pub span: Span,
    /// Body-x station of its centre (< 0).
    pub station: Q,
    pub outer_diameter: Q,
    /// Total height above the body.
    pub height: Q,
    /// The notch between the flanges, its diameter and height (none: a plain pin).
    pub notch: Option<(Q, Q)>,
    pub mass: Q,
}

/// A transition or boat tail of the generated body (`body { transition { ... } }`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Transition {
    pub span: Span,
    /// Body-x station of its fore end (< 0).
    pub fore_station: Q,
    pub length: Q,
    pub fore_diameter: Q,
    pub aft_diameter: Q,
    pub shape: Spanned<NoseShape>,
}

impl Transition {
    /// Its geometry in plain numbers.
    pub fn geom(&self) -> super::transition::TransitionGeom {
        super::transition::TransitionGeom {
            start: -self.fore_station.value,
            length: self.length.value,
            r_fore: 0.5 * self.fore_diameter.value,
            r_aft: 0.5 * self.aft_diameter.value,
            shape: self.shape.value,
        }
    }
}

impl BodyGeometry {
    /// The transitions' geometry, fore to aft.
    pub fn transition_geoms(&self) -> Vec<super::transition::TransitionGeom> {
        self.transitions.iter().map(Transition::geom).collect()
    }

    /// Outer radius at body station `x` (<= 0) aft of the nose (`check::transition`).
    pub fn radius_at(&self, x: f64) -> f64 {
        super::transition::section_radius(0.5 * self.diameter.value, &self.transition_geoms(), -x)
    }

    /// The body's radius under a fin set: at the middle of its root chord.
    pub fn radius_under(&self, fins: &Fins) -> f64 {
        self.radius_at(fins.root_trailing_edge_x.value + 0.5 * fins.root_chord.value)
    }

    /// The fins' root radius: [`Self::radius_under`] the fin set, the diameter's half without
    /// one.
    pub fn root_radius(&self, fins: Option<&Fins>) -> f64 {
        fins.map_or(0.5 * self.diameter.value, |f| self.radius_under(f))
    }

    /// The largest outer diameter (the default reference length).
    pub fn max_diameter(&self) -> f64 {
        super::transition::max_diameter(self.diameter.value, &self.transition_geoms())
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BeamTheory {
    EulerBernoulli,
    Timoshenko,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointMass {
    pub name: Spanned<String>,
    pub position: V3,
    pub mass: Q,
    /// Principal moments of inertia about its own centre, body axes, kg m^2.
    pub inertia: V3,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DistributedMass {
    pub name: Spanned<String>,
    /// Body-x stations (x <= 0) between which the mass is spread uniformly.
    pub from: Q,
    pub to: Q,
    pub mass: Q,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FeFormat {
    MatrixMarket,
    Op4,
    Dmig,
}

/// FE matrices exported from NASTRAN/ANSYS.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FeFiles {
    pub span: Span,
    pub format: Spanned<FeFormat>,
    /// Matrix Market: the mass and stiffness files. OP4/DMIG: the file holding both.
    pub mass: Spanned<PathBuf>,
    pub stiffness: Spanned<PathBuf>,
    /// Node coordinates: CSV (id,x,y,z) for Matrix Market, GRID bulk data otherwise.
    pub nodes: Spanned<PathBuf>,
    pub elements: Option<Spanned<PathBuf>>,
    /// Matrix names inside OP4/DMIG files.
    pub mass_matrix: Spanned<String>,
    pub stiffness_matrix: Spanned<String>,
    /// Position of u, v, w, theta_x, theta_y, theta_z within each node's 6 DOF in the file.
    pub dof_order: Spanned<[u8; 6]>,
    /// Multiply node coordinates by this to get metres.
    pub length_scale: Q,
}

/// How a node is designated.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum NodeRef {
    /// By the id in the FE model.
    Id(Spanned<u64>),
    /// The node nearest to a body-frame position.
    Nearest(V3),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct KeyNodes {
    pub span: Span,
    /// Body aerodynamics key node (5.3).
    pub body: NodeRef,
    /// Thrust key node (5.2); required when thrust is enabled.
    pub nozzle: Option<NodeRef>,
    /// Fin key nodes (5.4), one per fin.
    pub fins: FinKeyNodes,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum FinKeyNodes {
    /// None given (a vehicle with no fins).
    None,
    /// The fin node nearest to fractions of span (from the root) and chord (from the
    /// leading edge), applied to every fin.
    Fraction { span: Q, chord: Q },
    /// One node per fin.
    PerFin(Vec<NodeRef>),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModeSelection {
    pub span: Span,
    pub rules: Vec<ModeRule>,
    /// Mode fixity adjustment about the origin node (3.3).
    pub fixity_origin: bool,
    /// Modal damping ratio (one for all, or one per selected mode).
    pub damping: Vec<Q>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ModeRule {
    /// Elastic modes by 1-based index in frequency order.
    Indices(Spanned<Vec<usize>>),
    /// All elastic modes with frequency in [lo, hi], Hz converted to rad/s? No: stored in Hz.
    BandHz { lo: Q, hi: Q },
    /// Modes of a class.
    Class {
        class: Spanned<ModeClass>,
        count: Spanned<ModeCount>,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModeClass {
    BodyBending,
    FinFlap,
    FinTwist,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModeCount {
    Count(usize),
    PerFin,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fins {
    pub span_: Span,
    pub count: Spanned<usize>,
    pub span: Q,
    pub root_chord: Q,
    pub tip_chord: Q,
    /// Leading-edge sweep angle, rad (derived when the trailing-edge sweep was given).
    pub leading_edge_sweep: Q,
    pub thickness: Q,
    /// The fin's cross-section (its edges), for the built-in estimator's fin drag.
    pub cross_section: Spanned<FinSection>,
    pub cant: Q,
    /// Angular positions delta_i about body x, rad; default 2 pi (i-1)/n.
    pub angles: Vec<Q>,
    /// Body-x station of the root trailing edge (<= 0).
    pub root_trailing_edge_x: Q,
    /// The fins' material: `E`, `nu`, `rho`, and `E2`, `G12` with the fins' own overrides;
    /// an orthotropic lamina is allowed here (not for the body).
    pub material: Material,
    /// Direction of an orthotropic lamina's grain (its 1-direction, `E`) in the fin's plane.
    #[serde(default, skip_serializing_if = "FinGrain::is_chordwise")]
    pub grain: FinGrain,
    /// The outline (issue 34, `check::fin_outline`): trapezoidal (the fields above), elliptical
    /// or freeform. For the latter two `span` and `root_chord` are the fin's, and `tip_chord`
    /// and `leading_edge_sweep` those of its equivalent trapezoid (same span, root chord, area
    /// and leading edge of the mean aerodynamic chord), for the analyses that take a trapezoid.
    #[serde(default, skip_serializing_if = "FinOutline::is_trapezoidal")]
    pub outline: FinOutline,
    /// Root fillets (`fillet_radius`, `fillet_density`): their mass only, as OpenRocket
    /// counts them ([`Fillet`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fillet: Option<Fillet>,
}

/// A concave root fillet of radius `r` on each side of every fin, tangent to the fin and to
/// the body, along the fin's root chord; its mass is a line mass on the body over the root
/// chord (`structure::compile::generator_spec`). It stiffens the fin's root, which the
/// structure does not model (the fin's plate is attached to the body along its root as
/// without a fillet: the conservative side for flutter), and it is not in the aerodynamics
/// (OpenRocket 24.12 counts a fillet in the mass only: `FinSet.calculateFilletVolumeCentroid`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fillet {
    pub radius: Q,
    pub density: Q,
}

impl Fillet {
    /// Cross-section area of one fillet, m², between a body of radius `body_radius`, the fin
    /// (a plane through the body axis; the fin's thickness left out, as OpenRocket does) and
    /// the fillet's circular arc of radius `r`.
    ///
    /// Derivation (OpenRocket's `FinSet.calculateFilletCrossSection` states the same
    /// construction without a derivation). In the section plane put the body axis at O and
    /// the fin along the ray `z = 0, y > 0`. The fillet's circle (centre C, radius r) is
    /// tangent to the fin, so C is at height r above it, and tangent to the body from
    /// outside, so `|OC| = R + r`. Its tangent point T on the fin is the foot of C:
    /// `|OT| = sqrt((R + r)² - r²)`. The fillet is the part of the right triangle O T C
    /// (legs `|OT|` and `r`, area `r |OT| / 2`) outside both circles: the triangle minus the
    /// fillet circle's sector at C between CT and CO (angle `acos(r / (R + r))`, area
    /// `angle r² / 2`) and the body's sector at O between OT and OC (angle
    /// `asin(r / (R + r))`, area `angle R² / 2`). The two sectors do not overlap (the
    /// circles touch on OC only). Limits: `R → ∞` gives `r² (1 - π/4)`, the fillet between
    /// two perpendicular planes; `r → 0` gives 0. Tested against a numerical integration of
    /// the region (`tests/fin_fillets.rs`).
    pub fn section_area(body_radius: f64, r: f64) -> f64 {
        let hyp = body_radius + r;
        let ot = (hyp * hyp - r * r).sqrt();
        let at_c = (r / hyp).acos();
        let at_o = (r / hyp).asin();
        0.5 * r * ot - 0.5 * at_c * r * r - 0.5 * at_o * body_radius * body_radius
    }

    /// The fillets' total mass, kg: two per fin along the root chord `root_chord`.
    pub fn mass(&self, count: usize, root_chord: f64, body_radius: f64) -> f64 {
        2.0 * count as f64
            * Self::section_area(body_radius, self.radius.value)
            * root_chord
            * self.density.value
    }
}

/// A further, rigid fin set of a vehicle (`fins NAME { ... }`; `check::fin_sets`): the
/// fields of the `fins` block, checked by the same code.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FinSet {
    pub name: Spanned<String>,
    pub fins: Fins,
}

impl Fins {
    /// Body-x stations of the root chord's ends: (trailing edge, leading edge), aft < fore.
    pub fn root_stations(&self) -> (f64, f64) {
        (
            self.root_trailing_edge_x.value,
            self.root_trailing_edge_x.value + self.root_chord.value,
        )
    }

    /// The fin's edges (`check::fin_outline::Edges`): the true planform.
    pub fn edges(&self) -> super::fin_outline::Edges<'_> {
        super::fin_outline::Edges {
            outline: &self.outline,
            span: self.span.value,
            root_chord: self.root_chord.value,
            tip_chord: self.tip_chord.value,
            tip_le_offset: self.span.value * self.leading_edge_sweep.value.tan(),
        }
    }
}

pub use super::fin_outline::FinOutline;

/// A fin's cross-section, as OpenRocket offers them (Niskanen 2009, sec. 3.4.4): square
/// edges, rounded leading and trailing edges, or an airfoil (rounded leading edge, tapering
/// trailing edge).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FinSection {
    Square,
    Rounded,
    Airfoil,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Aero {
    pub span: Span,
    pub source: AeroSource,
    pub reference_area: Q,
    pub reference_length: Q,
    /// Coefficient reference point (nominal c.g.), body frame.
    pub reference_point: V3,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum AeroSource {
    /// The built-in estimator (slender body + Barrowman/linear supersonic theory); its
    /// tables clamp outside their grid unless `out_of_range = stop` is written.
    /// `roughness` is the surface roughness height R_s of body and fins, m (`finish = "name"`
    /// or `finish = 60 um`; OpenRocket's default regular paint, 60 um, when not written).
    Builtin {
        out_of_range: Spanned<OutOfRange>,
        roughness: Spanned<f64>,
    },
    /// CSV coefficient tables.
    Tables {
        body: Spanned<PathBuf>,
        fins: Spanned<PathBuf>,
        out_of_range: Spanned<OutOfRange>,
    },
    /// Missile DATCOM's printed output (`datcom("for006.dat", case = N, fin_set = N)`),
    /// turned into body and fin tables by [`crate::aero::datcom::tables`].
    Datcom {
        file: Spanned<PathBuf>,
        case: Option<u32>,
        fin_set: Option<u32>,
        out_of_range: Spanned<OutOfRange>,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OutOfRange {
    Stop,
    Clamp,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct Forces {
    pub gravity: Option<Gravity>,
    pub thrust: Option<Thrust>,
    pub body_aero: Option<BodyAero>,
    pub fin_aero: Option<FinAero>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Gravity {
    pub span: Span,
    /// Scale g by (R_E / (R_E + h))^2 (5.1.2).
    pub altitude_correction: bool,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Thrust {
    pub span: Span,
    /// Thrust curve: RASP `.eng` or CSV (t, N).
    pub curve: Spanned<PathBuf>,
    /// delta_T: translation of the thrust line from the nozzle key node, m (5.2).
    pub offset: V3,
    /// alpha_T: small rotation of the thrust vector, rad (5.2.2).
    pub misalignment: V3,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyAero {
    pub span: Span,
    /// Include the C_N and C_M rate terms (5.3.5-5.3.9).
    pub rate_terms: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Distribution {
    /// Fourier sine series span load subsonic, linear wing theory supersonic (App. A).
    Theory,
    /// Uniform over the fin's nodes (a simple reference).
    Uniform,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FinAero {
    pub span: Span,
    pub distribution: Spanned<Distribution>,
    /// Leeward reduction due to flow blockage (5.4.24-5.4.31).
    pub leeward_reduction: bool,
    /// Stop the run when a fin root stress exceeds this fraction of yield (5.6).
    pub stress_limit_fraction: Option<Q>,
    /// Where the fin's elastic incidence and velocity are taken (key-node model only).
    pub incidence: Spanned<FinIncidence>,
    /// How the fin's elastic deformation enters its loads.
    pub model: Spanned<FinAeroModel>,
}

/// The fin aerodynamic model (issue 12).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FinAeroModel {
    /// The thesis' model (5.4): the coefficient tables at the fin key node's elastic
    /// incidence and velocity (or their load-weighted mean, `incidence`).
    KeyNode,
    /// The rigid load from the coefficient tables at the undeformed fin, the elastic
    /// increments from the fin's panel model (vortex lattice / piston theory,
    /// `aero::panel`): independent of `key_nodes.fins`. The default.
    LiftingSurface,
}

/// Where the fin aerodynamics see the fin's deformation (5.4.3-5.4.10).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FinIncidence {
    /// At the fin key node, as the thesis does (its rotation and velocity).
    KeyNode,
    /// The load-weighted mean over the fin's nodes, `Σ w_k θ_k` and `Σ w_k u̇_k` with the
    /// distribution weights: the incidence at the centre of pressure of the load model.
    LoadWeighted,
}

// ------------------------------------------------------------------------------------------
// Scenarios

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scenario {
    pub name: Spanned<String>,
    pub span: Span,
    /// The vehicle after the scenario's `with` overrides (the variant that flies).
    pub vehicle: Vehicle,
    /// The overrides applied, as written (path, canonical value text, span).
    pub overrides: Vec<Override>,
    /// The initial conditions; with a `launch` block they are derived from it (at rest,
    /// pitched to the rail elevation, yawed to its heading; the plan puts the vehicle at the
    /// foot of the rail).
    pub initial: Initial,
    pub stimuli: Vec<Stimulus>,
    pub run: RunSettings,
    /// A launch from a rail at a site (`launch { ... }`), if written.
    pub launch: Option<Launch>,
    /// A steady wind in the inertial frame (`wind { ... }`), on top of the stimuli.
    pub wind: Option<Wind>,
    /// Recovery devices (`parachute NAME { ... }`), in the order written.
    pub parachutes: Vec<Parachute>,
    /// The scatter of this flight's motor (`motor_scale { impulse, burn_time }`), if written.
    pub motor_scale: Option<MotorScale>,
}

/// `motor_scale { impulse = 1.02; burn_time = 0.98 }`: the motor of this flight delivers
/// `impulse` times the curve's total impulse over `burn_time` times its burn time, the
/// curve's shape kept (`runtime::thrust::ThrustCurve::scaled`). A scenario field, so a
/// dispersion of it shares the vehicle's compiled structure.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MotorScale {
    pub span: Span,
    pub impulse: Q,
    pub burn_time: Q,
}

/// A launch from a rail: the vehicle slides along the rail (1-DOF) until it has travelled
/// `rail_length`, then flies freely; the ground is at the site altitude.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Launch {
    pub span: Span,
    /// Altitude of the launch site above sea level, m (inside the 1976 atmosphere).
    pub site_altitude: Q,
    /// Distance the vehicle travels along the rail before it is free, m (>= 0).
    pub rail_length: Q,
    /// Rail elevation above the horizon, rad (0 < elevation <= 90 deg).
    pub elevation: Q,
    /// Rail heading, rad, clockwise from inertial x (north) toward inertial y (east).
    pub heading: Q,
}

/// A steady wind, inertial frame (x north, y east, z down), as a function of the height
/// above the ground.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Wind {
    pub span: Span,
    pub profile: WindProfile,
}

/// How the steady wind varies with height `z` above the ground.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum WindProfile {
    /// The same speed and direction at every height.
    Constant { speed: Q, direction: Q },
    /// Power law `V(z) = V_ref (z / z_ref)^alpha` for `z > 0`, zero at and below the ground.
    PowerLaw {
        speed: Q,
        direction: Q,
        reference_height: Q,
        exponent: Q,
    },
    /// Speed and direction at heights (strictly increasing), interpolated linearly in the
    /// north and east components, held beyond the first and last height.
    Table(Vec<WindPoint>),
}

/// One row of a wind table: height above the ground (m), speed (m/s), and the direction the
/// wind blows FROM (rad, clockwise from north), as meteorologists give it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WindPoint {
    pub span: Span,
    pub height: f64,
    pub speed: f64,
    pub direction: f64,
}

/// A recovery device: from deployment on it adds the drag `-1/2 rho |V| V cd_area` along the
/// air-relative velocity, and the vehicle descends as a rigid point mass.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parachute {
    pub name: Spanned<String>,
    /// Drag area C_D S, m^2 (> 0).
    pub cd_area: Q,
    pub trigger: Spanned<Trigger>,
    /// Delay from the trigger to full deployment, s (>= 0).
    pub lag: Q,
}

/// What triggers a recovery device.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Trigger {
    /// At apogee (the vertical velocity changes sign).
    Apogee,
    /// On descent through this height above the ground, m.
    Altitude(f64),
    /// At this time after the start, s.
    Time(f64),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Override {
    pub path: String,
    pub value: String,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Initial {
    pub span: Span,
    pub velocity: InitialVelocity,
    /// omega_B, rad/s.
    pub angular_velocity: V3,
    pub attitude: Attitude,
    pub position: InitialPosition,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum InitialVelocity {
    /// V_B in the body frame, m/s.
    Body(V3),
    /// Along body x at this Mach number (speed of sound at the initial altitude).
    Mach(Q),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Attitude {
    /// Roll, pitch, yaw (4.4.1-4.4.5), rad.
    Euler(V3),
    /// Euler parameters (q0, q1, q2, q3), normalised (4.4.6).
    Quaternion(Spanned<[f64; 4]>),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum InitialPosition {
    /// Altitude above sea level, m (inertial x = y = 0, z = -h).
    Altitude(Q),
    /// Inertial position, z down, m.
    Inertial(V3),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Frame {
    Body,
    Inertial,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stimulus {
    pub name: Spanned<String>,
    pub kind: StimulusKind,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum StimulusKind {
    /// Rectangular gust pulse of wind velocity (4.5.2).
    Gust {
        start: Q,
        duration: Q,
        velocity: V3,
        frame: Frame,
    },
    /// 1 - cos gust: v(t) = v/2 (1 - cos(2 pi (t - start)/duration)).
    OneMinusCosine {
        start: Q,
        duration: Q,
        velocity: V3,
        frame: Frame,
    },
    /// Sinusoidal wind: v sin(2 pi f (t - start)) during [start, start + duration].
    Sine {
        start: Q,
        duration: Q,
        amplitude: V3,
        frequency: Q,
        frame: Frame,
    },
    /// Seeded continuous turbulence.
    Turbulence {
        model: Spanned<TurbulenceModel>,
        intensity: Q,
        scale_length: Q,
        seed: Spanned<u64>,
        start: Q,
        duration: Q,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TurbulenceModel {
    Dryden,
    VonKarman,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Integrator {
    /// Adaptive Dormand-Prince 5(4).
    Dopri5,
    /// Adaptive Dormand-Prince 8(5,3) (Hairer's DOP853).
    Dop853,
    /// Classical fixed-step Runge-Kutta 4.
    Rk4,
    /// Adaptive exponential Runge-Kutta ETD3(5) with the modal block integrated through its
    /// linearisation (`runtime::expint`).
    Exponential,
}

impl Integrator {
    /// Every integrator with its name in the language (`run { integrator = NAME }`).
    pub const NAMES: [(&'static str, Integrator); 4] = [
        ("dopri5", Integrator::Dopri5),
        ("dop853", Integrator::Dop853),
        ("rk4", Integrator::Rk4),
        ("exponential", Integrator::Exponential),
    ];

    /// The integrator's name in the language.
    pub fn name(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|(_, i)| *i == self)
            .map_or("dopri5", |(n, _)| n)
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunSettings {
    pub span: Span,
    pub stop_time: Q,
    pub integrator: Spanned<Integrator>,
    pub rtol: Q,
    pub atol: Q,
    /// Fixed step (RK4) or initial step (Dopri5), s.
    pub step: Q,
    /// Minimum step before the run stops with "step size underflow", s.
    pub min_step: Q,
    pub output_interval: Q,
    pub stop_on_ground: bool,
    pub max_alpha: Option<Q>,
    pub max_deformation: Option<Q>,
    /// Stop with a verdict at the model's own bounds (`plan::ModelLimits`); default true.
    pub model_limits: bool,
}

// ------------------------------------------------------------------------------------------
// Sweeps

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sweep {
    pub name: Spanned<String>,
    pub span: Span,
    /// Index into `Program::scenarios`.
    pub scenario: usize,
    pub analysis: Spanned<SweepAnalysis>,
    /// `frozen_gravity = true` (only with `analysis = linear3d`): gravity kept fixed in body
    /// axes in the linearisation, as `analyze linear --frozen-gravity`.
    pub frozen_gravity: bool,
    pub combine: Combine,
    pub axes: Vec<SweepAxis>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SweepAnalysis {
    /// Time-domain runs of the scenario.
    Run,
    PlanarPinned,
    PlanarUnpinned,
    Linear3d,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Combine {
    /// Cartesian product of the axes.
    Grid,
    /// Axes advance together (equal lengths).
    Zip,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepAxis {
    /// Override path (`fins.thickness`, `initial.altitude`).
    pub path: String,
    pub span: Span,
    /// The values as canonical VDL text, ready to apply as overrides.
    pub values: Vec<String>,
    /// The same values in SI, when scalar (for tables and plot axes).
    pub si_values: Vec<Option<f64>>,
}

impl Sweep {
    /// Number of cases.
    pub fn case_count(&self) -> usize {
        match self.combine {
            Combine::Grid => self.axes.iter().map(|a| a.values.len()).product(),
            Combine::Zip => self.axes.first().map_or(0, |a| a.values.len()),
        }
    }
}

// ------------------------------------------------------------------------------------------
// Dispersions (Monte Carlo)

/// A `dispersion NAME { ... }` block: the scenario, how many samples, the seed and the
/// inputs drawn per sample (`analysis::montecarlo`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Dispersion {
    pub name: Spanned<String>,
    pub span: Span,
    /// Index into `Program::scenarios`.
    pub scenario: usize,
    /// Samples drawn when `--samples` does not say.
    pub samples: usize,
    pub seed: u64,
    pub entries: Vec<DispersionEntry>,
    pub correlations: Vec<Correlation>,
    /// Lower-triangular Cholesky factor `L` of the entries' correlation matrix (row-major,
    /// `entries.len()` squared); empty when there are no correlations.
    pub cholesky: Vec<f64>,
    /// The integrator every sample flies with, over the scenario's `run { integrator }`
    /// (`None`: the scenario's own): the dispersion's `integrator` field; when it is absent,
    /// the exponential integrator unless the scenario's `run` block names one
    /// (`check::dispersion`, docs/montecarlo.md).
    #[serde(default)]
    pub integrator: Option<Integrator>,
}

/// One drawn input: an override path and its distribution, in the unit written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DispersionEntry {
    /// Override path (`fins.thickness`, `wind.speed`).
    pub path: String,
    pub span: Span,
    /// The unit the parameters are written in (`mm`), empty for a plain number; a drawn
    /// value is applied as the override `PATH=VALUE UNIT`.
    pub unit: String,
    pub distribution: DispersionLaw,
}

/// The distributions of a dispersion entry (parameters in the entry's unit).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum DispersionLaw {
    Normal {
        mean: f64,
        sd: f64,
    },
    Uniform {
        min: f64,
        max: f64,
    },
    TruncatedNormal {
        mean: f64,
        sd: f64,
        min: f64,
        max: f64,
    },
    Triangular {
        min: f64,
        mode: f64,
        max: f64,
    },
}

/// A correlation between two entries (indices into `Dispersion::entries`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Correlation {
    pub a: usize,
    pub b: usize,
    pub rho: f64,
    pub span: Span,
}
