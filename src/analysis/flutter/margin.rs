//! The flutter margin over a flight (issue 13, deliverable 5).
//!
//! # The boundary
//!
//! The flutter speed of the clamped fin ([`super::fin`]) depends on the Mach number (through
//! the panel aerodynamics) and on the air density (through the mass ratio), so it is a
//! surface `V_F(M, h)`. It is precomputed by p-k solutions on a grid of trusted Mach numbers
//! and of altitudes (laid out from the vehicle and its site, below), each at fixed Mach and
//! density: the "unmatched" p-k solution of Rodden & Johnson (MSC Nastran Aeroelastic User's
//! Guide §2.6), in which speed is varied at the node's Mach and density. Between nodes the
//! boundary is interpolated bilinearly in `(M, h)` (of `V_F sqrt(ρ)`, below). The transonic
//! band has nodes of its own (0.95, 1.0, 1.05): each is solved like any other node, on
//! generalised forces bridged in the aerodynamic matrices between the band's ends
//! ([`super::fin::bridged`]: `Q(k, M)` linear in Mach between the last subsonic and the first
//! supersonic method's tables), never by blending flutter speeds. Such a node carries the
//! bridge's stated flutter-speed uncertainty `u` ([`Boundary::uncertainty`]); a row that uses
//! it is flagged with it (`BoundaryPoint::uncertainty`, the larger of its two Mach nodes'
//! unless it sits on a node) and the verdict counts its margin divided by `1 + u`, the
//! conservative side of the uncertainty. The band's nodes and its two end nodes share one
//! reduced-frequency grid (up to `1.2 ω_max b` over the lowest speed among them), so a bridged
//! node blends the end nodes' own tables, each built once.
//!
//! A node where no flutter point is found up to the largest speed tried carries that speed
//! and is flagged as a lower bound (the margin there is at least the value written).
//!
//! # The margin
//!
//! At each output row, with airspeed `V = M a(h)`: the speed margin `V_F / V` and the
//! dynamic-pressure margin `q_F / q = (V_F / V)²` (same density). The criterion is the usual
//! 15 % on equivalent airspeed (14 CFR 25.629(b)(1): aeroelastically stable up to `1.15 V_D`;
//! MIL-A-8870C 3.1.1: a 15 % flutter margin on equivalent airspeed); since `V_EAS = V
//! sqrt(ρ/ρ_0)` and both speeds are at the same density, the EAS margin equals `V_F / V`.
//!
//! # The vehicle's boundary (cached)
//!
//! In a run the boundary is a property of the vehicle and of the scenario's site, not of the
//! flight: [`vehicle_spec`] lays its grid out before anything is flown, and the CLI caches the
//! solved boundary content-addressed next to the structure (`cli::flutter::cached_boundary`;
//! key `cli::flutter::boundary_key`: the inputs of the clamped fin's modes, the whole
//! [`BoundarySpec`] and [`BOUNDARY_REVISION`]), so a warm run does no eigen-solve and no p-k
//! for its margin.
//!
//! - Mach nodes ([`vehicle_mach_nodes`]): the subsonic `0, 0.3, 0.6, 0.9`; when the vehicle's
//!   fin coefficient table reaches past 0.9, the band's [`TRANSONIC_NODES`] `0.95, 1.0, 1.05`,
//!   the Mach box's first Mach `1.1`, then `1.2`, the built-in estimator's supersonic nodes
//!   `1.5, 2, 2.5, 3, 4, 5` below the table's last Mach, and that last Mach (the same nodes
//!   as the estimator's table for a table of its own; never one node per table node: a
//!   table tabulated every 0.01 would cost a sweep per node). A flight cannot be flown past
//!   its table's last Mach without leaving the table; a row above the last node is outside
//!   the grid.
//! - Altitude nodes ([`altitude_nodes`]): the floor (100 m below a launch site, for the
//!   landing row; sea level or the initial altitude, whichever is lower, for a flight started
//!   in mid-air), then the levels [`ALTITUDE_LEVELS`] above it up to the ceiling
//!   [`CEILING`] = 30 km (the estimator's table top).
//! - Speeds per Mach node `M`: 40 speeds from `v_lo` to `v_hi = 3 max(M, 1) a_ref`, `a_ref`
//!   the largest speed of sound over the altitude nodes (a flight at `M` flies at most
//!   `M a_ref`, so margins up to at least 3 are resolved); `v_lo = 0.1 v_hi`, raised
//!   for the unsteady lattice to the lowest speed at which the lattice resolves the highest
//!   mode's reduced frequency with 20 % to spare (box-size rule,
//!   `panel::harmonic::check_resolution`) on [`MARGIN_CHORDWISE`] chordwise panels.
//!
//! A row outside the grid (Mach above the last node, altitude below the floor or above the
//! ceiling) is evaluated at the nearest grid point, flagged `in_grid = 0`, counted, and kept
//! out of the minimum that decides the criterion: never silently extrapolated.
//!
//! Between altitude nodes the interpolated quantity is `V_F sqrt(ρ)` (proportional to
//! `sqrt(q_F)`, the equivalent flutter airspeed), not `V_F`. Derivation (the sources give no
//! rule): in the p-k equation of [`super::pk`], `(p² I + diag(ω²) - q Q(k)) η = 0`, density
//! enters only through `q = ρ V² / 2` and, with `k = ω b / V`, through the speed at which a
//! given `q` is reached. Where `Q(k)` varies slowly with `k` (the quasi-steady limit: `Q`
//! linear in `k` with a small slope) the flutter condition fixes `q_F` alone, so `V_F sqrt(ρ)
//! = sqrt(2 q_F)` is independent of altitude while `V_F` itself grows like `exp(h / 2H)`
//! (`H` about 8.5 km). On the K1000T fin's boundary `V_F sqrt(ρ)` changes by 0.3 % from the
//! site to 5 km where `V_F` changes by 29 %; at mid-interval between two altitude nodes 2.6
//! km apart the interpolated `V_F` is within 1.3e-4 of a direct p-k solution, against 3.0e-3
//! for linear interpolation of `V_F` (`tests/flutter_boundary.rs`). At a node the value is
//! the node's own.
//!
//! Below each node's first speed the p-k equation is screened on the leading modes
//! ([`super::pk::screen_below`]: the table resolves the lower branches' reduced frequencies
//! far below the speed at which it resolves the highest one), and the node's flutter speed
//! is the answer of [`super::pk::PkSolution::answer`]: the lowest crossing bracketed by a
//! stable speed below it, never a crossing above a branch already unstable.
//!
//! A node unstable at its lowest speed solved carries that speed, an upper bound of `V_F`
//! (`upper_bound`); its margin is then at most `v_lo / V`.
//!
//! A node whose p-k iteration does not converge at the lowest speed of its sweep (so that
//! no speed below the failure is left to cut the sweep at, `pk::pk_solve_cut`; seen at
//! Mach 1.73 and 15 km on Calisto's fin: the fourth mode at 174 m/s, k = 4.3, with piston
//! theory) is solved from the next speed up, and so on while at least two speeds remain; the
//! speed its sweep started at is kept per node ([`Boundary::node_lowest_speeds`]) and every
//! row that uses such a node is flagged (`raised_start`): a flutter crossing that opens and
//! closes again below the raised start would not be seen there. Unstable at the raised start,
//! the node is an upper bound as above.

use super::fin::{
    FinAero, FinFlutterError, FinFlutterSettings, FinModes, bridge_ends, bridged, fin_lattice,
    flutter_model, gaf_table, in_bridge,
};
use super::pk::GafTable;
use super::pk::{FlutterAnswer, FlutterError, PkSettings, pk_solve_cut, screen_below};
use crate::aero::atmosphere::{Atmosphere, STANDARD_MIN_ALTITUDE, Standard1976};
use crate::aero::panel::piston::Correction;
use crate::aero::panel::{self, Regime, SUBSONIC_LIMIT, SUPERSONIC_LIMIT};

/// The required speed margin `V_F / V` (15 % on equivalent airspeed).
pub const CRITERION: f64 = 1.15;

/// Revision of the boundary's computation, part of its cache key: change it whenever the
/// solution of a given [`BoundarySpec`] would change.
pub const BOUNDARY_REVISION: &str = "flight flutter boundary r6 (r5 plus the p-k first-order form scaled by the highest modal frequency, a branch unstable at the lowest speed only above the round-off damping G_NOISE, the doublet lattice the default subsonic method with automatic strips and its own 0.95 node floored by the box rule): transonic nodes 0.95, 1.0, 1.05 and 1.1 on Q(k, M) bridged linearly in Mach between the band's ends (fin::bridged) with the stated speed uncertainty per Mach node, the band's nodes and ends on one k grid (the band's lowest speed); Mach box (panel::machbox) above Mach 1.1 where piston theory's criterion fails, its nodes floored by the box rule as the subsonic ones; clamped fin (fin::clamped_fin_modes), unmatched p-k per (Mach, altitude) node (pk_solve_cut), node speeds [max(0.1 v_hi, box-rule floor), v_hi], a node not converging at its lowest speed started at the next, k table to 1.2 omega_max b / v_lo, the leading-mode screen below the first speed (pk::screen_below) and the answer rule (pk::PkSolution::answer), US Standard Atmosphere 1976";

/// The ceiling of the margin's altitude grid, m (the built-in estimator's table top).
pub const CEILING: f64 = 30_000.0;

/// The altitude levels of the grid above its floor, m (module doc).
pub const ALTITUDE_LEVELS: [f64; 8] = [
    2_500.0, 5_000.0, 7_500.0, 10_000.0, 15_000.0, 20_000.0, 25_000.0, 30_000.0,
];

/// Speeds per Mach node of the flight margin's sweeps.
pub const MARGIN_SPEEDS: usize = 40;

/// Chordwise panels of the margin's unsteady lattice (`analyze flutter`'s most).
pub const MARGIN_CHORDWISE: usize = 32;

/// Everything a boundary depends on besides the clamped fin's modes (which the cache key
/// covers by the fin's own inputs): the grid, the sweeps, the aerodynamics and the solver
/// settings. Serialised whole into the cache key.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BoundarySpec {
    /// Mach nodes, ascending.
    pub machs: Vec<f64>,
    /// Altitude nodes, m, ascending.
    pub altitudes: Vec<f64>,
    /// Per Mach node, the nominal lowest and largest speed of its sweep, m/s (the lowest is
    /// raised to the box-rule floor for the unsteady lattice, module doc).
    pub speed_ranges: Vec<[f64; 2]>,
    /// Speeds per sweep.
    pub speed_count: usize,
    /// Clamped-fin modes.
    pub modes: usize,
    /// The panel aerodynamics.
    pub aero: FinAero,
    /// Lattice panels (for the doublet lattice `spanwise` is the least count: strips are
    /// added until its boxes meet their aspect-ratio rule, `dlm::spanwise_for`).
    pub chordwise: usize,
    pub spanwise: usize,
    /// Ackeret's correction of piston theory (`piston::Correction::Ackeret`) or none.
    pub piston_ackeret: bool,
    /// Reduced frequencies of each GAF table (unsteady; the quasi-steady table is exact with
    /// two).
    pub k_count: usize,
    /// The p-k iteration's tolerance (`PkSettings::k_tolerance`).
    pub k_tolerance: f64,
}

impl BoundarySpec {
    /// The fin flutter settings of the spec (k_max is set per node).
    pub fn fin_settings(&self) -> FinFlutterSettings {
        FinFlutterSettings {
            aero: self.aero,
            chordwise: self.chordwise,
            spanwise: self.spanwise,
            correction: if self.piston_ackeret {
                Correction::Ackeret
            } else {
                Correction::None
            },
            k_count: self.k_count,
            k_max: 2.0,
        }
    }
}

/// A flutter boundary `V_F(M, h)` on a grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Boundary {
    pub machs: Vec<f64>,
    pub altitudes: Vec<f64>,
    /// Air density at each altitude node, kg/m³ (1976 atmosphere).
    pub densities: Vec<f64>,
    /// `V_F` (m/s), row-major `machs x altitudes`.
    pub speeds: Vec<f64>,
    /// Whether the node's value is a lower bound (no flutter up to the largest speed).
    pub lower_bound: Vec<bool>,
    /// Whether the node was unstable at its lowest speed (the value is an upper bound).
    pub upper_bound: Vec<bool>,
    /// Per Mach node, the lowest and the largest speed of its sweep, m/s.
    pub speed_ranges: Vec<[f64; 2]>,
    /// Per node (row-major as `speeds`), the speed its p-k sweep was solved from, m/s: the
    /// Mach node's lowest speed, or a higher one where the iteration did not converge there
    /// (module doc).
    pub node_lowest_speeds: Vec<f64>,
    /// The largest speed tried, m/s.
    pub largest_speed: f64,
    /// Per Mach node, the relative uncertainty `u` of its flutter speed: the transonic
    /// bridge's (`fin::TransonicBridge::uncertainty`), 0 outside the band.
    pub uncertainty: Vec<f64>,
}

/// The supersonic Mach nodes of the margin above [`SUPERSONIC_LIMIT`] (the built-in
/// estimator's, `aero::estimator::ESTIMATOR_MACH`).
pub const SUPERSONIC_NODES: [f64; 6] = [1.5, 2.0, 2.5, 3.0, 4.0, 5.0];

/// The margin's Mach nodes inside the transonic band and at its supersonic end (module doc):
/// the bridged `0.95, 1.0, 1.05` (0.95 is the doublet lattice's own last Mach) and the Mach
/// box's first, 1.1.
pub const TRANSONIC_NODES: [f64; 4] = [0.95, 1.0, 1.05, panel::machbox::MIN_MACH];

/// The Mach nodes of a vehicle whose fin coefficient table has the Mach axis `table_machs`
/// (module doc): `0, 0.3, 0.6, 0.9`, then, if the table reaches past 0.9, the
/// [`TRANSONIC_NODES`], `1.2`, the
/// [`SUPERSONIC_NODES`] below the table's last Mach node, and that last node. The grid does
/// not follow the table's own resolution: a table tabulated every 0.01 in Mach would
/// otherwise give one p-k sweep per node and altitude (examples/calisto: 81 supersonic
/// nodes, 729 sweeps, 30 s).
pub fn vehicle_mach_nodes(table_machs: &[f64]) -> Vec<f64> {
    let top = table_machs
        .iter()
        .copied()
        .filter(|m| m.is_finite())
        .fold(0.0, f64::max);
    let mut m = vec![0.0, 0.3, 0.6, SUBSONIC_LIMIT];
    if top > SUBSONIC_LIMIT {
        m.extend(TRANSONIC_NODES);
        m.push(SUPERSONIC_LIMIT);
        m.extend(SUPERSONIC_NODES.iter().copied().filter(|&x| x < top));
        if top > SUPERSONIC_LIMIT {
            m.push(top);
        }
    }
    m
}

/// The altitude nodes from `floor` (m): the floor, then [`ALTITUDE_LEVELS`] more than 500 m
/// above it, up to [`CEILING`] (at least 1 km above the floor).
pub fn altitude_nodes(floor: f64) -> Vec<f64> {
    let mut h = vec![floor];
    h.extend(
        ALTITUDE_LEVELS
            .iter()
            .copied()
            .filter(|&l| l > floor + 500.0 && l <= CEILING),
    );
    if h.len() == 1 {
        h.push(floor + 1_000.0);
    }
    h
}

/// The floor of the altitude grid of a scenario starting at `site` (m): 100 m below a launch
/// site, else sea level or `site`, whichever is lower; never below the 1976 atmosphere.
pub fn altitude_floor(site: f64, launch: bool) -> f64 {
    let f = if launch { site - 100.0 } else { site.min(0.0) };
    f.max(STANDARD_MIN_ALTITUDE)
}

/// The margin's boundary specification of a vehicle (fin table Mach axis `table_machs`) flown
/// from `site` (module doc), with `modes` clamped-fin modes and the aerodynamics `aero`.
pub fn vehicle_spec(
    table_machs: &[f64],
    site: f64,
    launch: bool,
    modes: usize,
    aero: FinAero,
) -> Result<BoundarySpec, FinFlutterError> {
    let machs = vehicle_mach_nodes(table_machs);
    let altitudes = altitude_nodes(altitude_floor(site, launch));
    let atm = Standard1976::new();
    let mut a_ref: f64 = 0.0;
    for &h in &altitudes {
        let air = atm
            .at(h)
            .map_err(|e| FinFlutterError::Generate(format!("atmosphere: {e}")))?;
        a_ref = a_ref.max(air.speed_of_sound);
    }
    let speed_ranges = machs
        .iter()
        .map(|&m| {
            let hi = 3.0 * m.max(1.0) * a_ref;
            [0.1 * hi, hi]
        })
        .collect();
    let d = FinFlutterSettings::default();
    Ok(BoundarySpec {
        machs,
        altitudes,
        speed_ranges,
        speed_count: MARGIN_SPEEDS,
        modes,
        aero,
        chordwise: match aero {
            FinAero::Unsteady | FinAero::DoubletLattice => MARGIN_CHORDWISE,
            FinAero::QuasiSteady => d.chordwise,
        },
        // The doublet lattice's strips follow its box rule alone (`dlm::spanwise_for` from
        // one strip in `solve_boundary`: the fewest with no box more than 3 times wider than
        // long); the vortex lattice keeps its 12 cosine strips.
        spanwise: match aero {
            FinAero::DoubletLattice => 1,
            FinAero::Unsteady | FinAero::QuasiSteady => d.spanwise,
        },
        piston_ackeret: d.correction == Correction::Ackeret,
        // 40 reduced frequencies for either lattice. With 20 for the doublet lattice (its
        // tables cost about twice as much per frequency) the spline in k put a wiggle of
        // 7e-5 into the margin as a function of the fin thickness, so a thickness family's
        // interpolated margin missed its exact one by 7.3e-5 against the stated 5e-6
        // (tests/montecarlo.rs; 1.5e-6 with 40); cost: docs/performance.md.
        k_count: 40,
        k_tolerance: PkSettings::default().k_tolerance,
    })
}

/// The aerodynamics of a flight margin on the fin `planform`: `preferred`, unless that is the
/// doublet lattice and its automatic strips ([`panel::dlm::spanwise_for`] with
/// [`MARGIN_CHORDWISE`] boxes along the chord) cannot meet its box rule on this fin; then the
/// vortex lattice ([`FinAero::Unsteady`], the method the doublet lattice replaced as the
/// default, validated on the same cases: docs/validation.md) and the reason, which the margin
/// reports. Which fins: an outline ending in a point along straight edges, whose last strip's
/// box aspect ratio is `2 s n_c / c_r` whatever the strip count (`spanwise_for`'s doc), or
/// one that would need more than [`panel::dlm::MAX_AUTO_STRIPS`] strips. Any other error of
/// the lattice is left to the boundary, which reports it.
pub fn margin_aero(
    planform: &crate::aero::estimator::FinPlanform,
    preferred: FinAero,
) -> (FinAero, Option<String>) {
    if preferred != FinAero::DoubletLattice {
        return (preferred, None);
    }
    match panel::dlm::spanwise_for(planform, MARGIN_CHORDWISE, 1, panel::Spacing::Cosine) {
        Err(panel::PanelError::WideBoxes { ratio, limit }) => (
            FinAero::Unsteady,
            Some(format!(
                "the doublet lattice's box rule cannot be met on this fin (its boxes stay {ratio:.1} times wider than long against at most {limit}, whatever the strip count: a fin ending in a point), so the margin uses the vortex lattice"
            )),
        ),
        _ => (preferred, None),
    }
}

/// The boundary of the clamped fin `modes` over `machs` x `altitudes`, speeds up to
/// `largest_speed` (30 speeds from 10 % of it).
pub fn boundary(
    modes: &FinModes,
    machs: &[f64],
    altitudes: &[f64],
    largest_speed: f64,
    settings: &FinFlutterSettings,
) -> Result<Boundary, FinFlutterError> {
    let spec = BoundarySpec {
        machs: machs.to_vec(),
        altitudes: altitudes.to_vec(),
        speed_ranges: vec![[0.1 * largest_speed, largest_speed]; machs.len()],
        speed_count: 30,
        modes: modes.order(),
        aero: settings.aero,
        chordwise: settings.chordwise,
        spanwise: settings.spanwise,
        piston_ackeret: settings.correction == Correction::Ackeret,
        k_count: settings.k_count.max(40),
        k_tolerance: PkSettings::default().k_tolerance,
    };
    solve_boundary(modes, &spec)
}

/// The lowest speed at which `lattice` resolves the reduced frequency of `omega_max` with 20 %
/// to spare: the box-size rule `Δx <= BOX_RULE · 2π / ν` on its longest panel chord
/// (`panel::harmonic::check_resolution`), `ν = 1.2 ω_max / V`.
fn box_rule_floor(lattice: &panel::Lattice, omega_max: f64) -> f64 {
    let dx = lattice
        .panels
        .iter()
        .map(|p| (p.corners[3][0] - p.corners[0][0]).max(p.corners[2][0] - p.corners[1][0]))
        .fold(0.0, f64::max);
    let nu_max = panel::harmonic::BOX_RULE * 2.0 * std::f64::consts::PI / dx;
    // A hair above, so that the check at exactly this speed passes despite rounding.
    1.2 * omega_max / nu_max * (1.0 + 1e-9)
}

/// The boundary of the clamped fin `modes` on the grid and sweeps of `spec` (module doc).
pub fn solve_boundary(modes: &FinModes, spec: &BoundarySpec) -> Result<Boundary, FinFlutterError> {
    if spec.modes != modes.order() {
        return Err(FinFlutterError::TooFewModes {
            got: modes.order(),
            wanted: spec.modes,
        });
    }
    if spec.speed_ranges.len() != spec.machs.len() || spec.speed_count < 2 {
        return Err(FinFlutterError::Generate(
            "the boundary needs one speed range of at least two speeds per Mach node".into(),
        ));
    }
    let atm = Standard1976::new();
    let mut s = spec.fin_settings();
    if spec.aero == FinAero::DoubletLattice {
        // `spec.spanwise` is the least count: the doublet lattice's boxes also keep its
        // aspect-ratio rule (`dlm::spanwise_for`; the key covers the spec and the fin).
        s.spanwise = panel::dlm::spanwise_for(
            &modes.planform,
            s.chordwise,
            s.spanwise,
            panel::Spacing::Cosine,
        )?;
    }
    let w_max = modes.omega.iter().copied().fold(0.0, f64::max);
    let lattice = fin_lattice(modes, &s)?;
    let floor = match spec.aero {
        FinAero::Unsteady | FinAero::DoubletLattice => box_rule_floor(&lattice, w_max),
        FinAero::QuasiSteady => 0.0,
    };
    let densities = spec
        .altitudes
        .iter()
        .map(|&h| {
            atm.at(h)
                .map(|a| a.density)
                .map_err(|e| FinFlutterError::Generate(format!("atmosphere: {e}")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let n = spec.machs.len() * spec.altitudes.len();
    let mut out = Vec::with_capacity(n);
    let mut lower = Vec::with_capacity(n);
    let mut upper = Vec::with_capacity(n);
    let mut ranges = Vec::with_capacity(spec.machs.len());
    let mut node_lowest = Vec::with_capacity(n);
    let mut uncertainty = Vec::with_capacity(spec.machs.len());
    let pk = PkSettings {
        k_tolerance: spec.k_tolerance,
    };
    // The lowest speed of a node's sweep: the box-rule floor binds the lattices and the Mach
    // box (piston theory is local); the Mach box of `fin::mach_boxes` has as many boxes along
    // the fin as the lattice has panels along the root chord, so the same floor keeps it near
    // its default count. A bridged node's ends are a lattice and the Mach box: the same floor.
    let node_v_lo = |m: f64, lo: f64| -> Result<f64, FinFlutterError> {
        let mach_box = spec.aero.is_harmonic()
            && m >= panel::machbox::MIN_MACH
            && !panel::machbox::piston_valid(&modes.planform, m);
        let bridge = spec.aero.is_harmonic() && in_bridge(m, spec.aero);
        // The doublet lattice holds to its own limit (0.95), inside the vortex lattice's band.
        let lattice = matches!(panel::regime(m)?, Regime::Subsonic)
            || (spec.aero == FinAero::DoubletLattice && m <= panel::dlm::MACH_LIMIT);
        let sub = lattice || mach_box || bridge;
        Ok(if sub { lo.max(floor) } else { lo })
    };
    // The nodes of the transonic band and its two ends share one reduced-frequency grid (that
    // of the lowest speed among them), so each bridged node blends the end nodes' own tables:
    // built once, kept here by (Mach, k_max) bits.
    let (b_lo, b_hi) = bridge_ends(spec.aero);
    let mut band_v_lo = f64::INFINITY;
    for (&m, &[lo, _]) in spec.machs.iter().zip(&spec.speed_ranges) {
        if m >= b_lo && m <= b_hi {
            band_v_lo = band_v_lo.min(node_v_lo(m, lo)?);
        }
    }
    let mut tables: Vec<((u64, u64), GafTable)> = Vec::new();
    for (&m, &[lo, hi]) in spec.machs.iter().zip(&spec.speed_ranges) {
        let v_lo = node_v_lo(m, lo)?;
        if !(v_lo.is_finite() && hi > v_lo) {
            return Err(FinFlutterError::Generate(format!(
                "at Mach {m} the lowest speed the lattice resolves, {v_lo:.1} m/s, is not below the largest, {hi:.1} m/s"
            )));
        }
        let c = spec.speed_count;
        let speeds: Vec<f64> = (0..c)
            .map(|i| v_lo + (hi - v_lo) * i as f64 / (c - 1) as f64)
            .collect();
        ranges.push([v_lo, hi]);
        let v_table = if m >= b_lo && m <= b_hi {
            band_v_lo.min(v_lo)
        } else {
            v_lo
        };
        s.k_max = (1.2 * w_max * modes.b_ref() / v_table).max(0.1);
        let settings = s;
        let (gaf, bridge) = bridged(m, spec.aero, |mm| {
            let key = (mm.to_bits(), settings.k_max.to_bits());
            if let Some((_, t)) = tables.iter().find(|(k, _)| *k == key) {
                return Ok::<_, FinFlutterError>(t.clone());
            }
            let t = gaf_table(modes, &lattice, mm, &settings)?;
            tables.push((key, t.clone()));
            Ok(t)
        })?;
        uncertainty.push(bridge.map_or(0.0, |b| b.uncertainty));
        for &rho in &densities {
            let model = flutter_model(modes, rho);
            // A branch whose p-k iteration does not converge at some speed (near zero
            // frequency at high speed) ends the sweep there, as in `analyze flutter`: the
            // node is solved on the speeds below it, and without a flutter point there it is a
            // lower bound at the last speed solved. One that does not converge below the
            // second speed (nothing left to cut at) starts one speed higher (module doc).
            let mut start = 0;
            let sol = loop {
                match pk_solve_cut(&model, &gaf, &speeds[start..], pk) {
                    Err(FlutterError::NoConvergence { speed, .. })
                        if speed < speeds[start + 1] && speeds.len() - start > 2 =>
                    {
                        start += 1;
                    }
                    other => break other?.0,
                }
            };
            let mut sol = sol;
            sol.screen = screen_below(&model, &gaf, sol.speeds[0], pk)?;
            node_lowest.push(sol.lowest_speed());
            let sp = &sol.speeds;
            match sol.answer() {
                FlutterAnswer::Below(v) => {
                    out.push(v);
                    lower.push(false);
                    upper.push(true);
                }
                FlutterAnswer::Flutter(f) => {
                    out.push(f.speed);
                    lower.push(false);
                    upper.push(false);
                }
                FlutterAnswer::Stable => {
                    out.push(sp[sp.len() - 1]);
                    lower.push(true);
                    upper.push(false);
                }
            }
        }
    }
    let largest_speed = ranges.iter().map(|r| r[1]).fold(0.0, f64::max);
    Ok(Boundary {
        machs: spec.machs.clone(),
        altitudes: spec.altitudes.clone(),
        densities,
        speeds: out,
        lower_bound: lower,
        upper_bound: upper,
        speed_ranges: ranges,
        node_lowest_speeds: node_lowest,
        largest_speed,
        uncertainty,
    })
}

/// Bracket of `x` in ascending `grid` (clamped to the ends): `(i, t)` with the value
/// `(1 - t) v[i] + t v[i + 1]`.
fn bracket(grid: &[f64], x: f64) -> (usize, f64) {
    if grid.len() < 2 {
        return (0, 0.0);
    }
    let x = x.clamp(grid[0], grid[grid.len() - 1]);
    let i = grid
        .windows(2)
        .position(|w| x <= w[1])
        .unwrap_or(grid.len() - 2);
    let t = (x - grid[i]) / (grid[i + 1] - grid[i]);
    (i, t)
}

/// The boundary at one point of the flight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryPoint {
    pub flutter_speed: f64,
    /// No node used carries a stated uncertainty (`uncertainty == 0`: outside the transonic
    /// bridge).
    pub trusted: bool,
    /// The relative uncertainty `u` of `flutter_speed` (module doc): the transonic bridge's,
    /// the larger of the two Mach nodes used (the node's own on a node); 0 outside the band.
    pub uncertainty: f64,
    /// Some node used is a lower bound.
    pub lower_bound: bool,
    /// Some node used was unstable at its lowest speed (an upper bound).
    pub upper_bound: bool,
    /// The point lies inside the grid (else it was evaluated at the nearest grid point).
    pub in_grid: bool,
    /// Some node used had its sweep started above the Mach node's lowest speed (module doc).
    pub raised_start: bool,
}

impl Boundary {
    /// Whether node `(mach index i, altitude index j)` was solved from above its Mach node's
    /// lowest speed (module doc).
    pub fn raised_start(&self, i: usize, j: usize) -> bool {
        self.node_lowest_speeds[i * self.altitudes.len() + j] > self.speed_ranges[i][0]
    }

    /// `V_F` at `(mach, altitude)` (module doc): bilinear in `(M, h)` of `V_F sqrt(ρ)`, divided
    /// by `sqrt(ρ(h))`. A point outside the grid is evaluated at the nearest grid point and
    /// flagged (`in_grid`).
    pub fn at(&self, mach: f64, altitude: f64) -> BoundaryPoint {
        let na = self.altitudes.len();
        let (nm, (h0, h1)) = (
            self.machs.len(),
            (self.altitudes[0], self.altitudes[na - 1]),
        );
        let in_grid =
            mach >= self.machs[0] && mach <= self.machs[nm - 1] && altitude >= h0 && altitude <= h1;
        let hc = altitude.clamp(h0, h1);
        let (i, tm) = bracket(&self.machs, mach);
        let (j, th) = bracket(&self.altitudes, hc);
        let i1 = (i + 1).min(nm - 1);
        let j1 = (j + 1).min(na - 1);
        let rho = Standard1976::new()
            .at(hc)
            .map(|a| a.density)
            .unwrap_or(f64::NAN);
        let eas = |a: usize, b: usize| self.speeds[a * na + b] * self.densities[b].sqrt();
        let flag =
            |f: &[bool]| f[i * na + j] || f[i * na + j1] || f[i1 * na + j] || f[i1 * na + j1];
        let along = |a: usize| (1.0 - th) * eas(a, j) + th * eas(a, j1);
        let e = (1.0 - tm) * along(i) + tm * along(i1);
        // At a node the node's own value, bit for bit.
        let on = |t: f64| t == 0.0 || t == 1.0;
        let v = if on(tm) && on(th) {
            let a = if tm == 1.0 { i1 } else { i };
            let b = if th == 1.0 { j1 } else { j };
            self.speeds[a * na + b]
        } else {
            e / rho.sqrt()
        };
        let u = if tm == 0.0 {
            self.uncertainty[i]
        } else if tm == 1.0 {
            self.uncertainty[i1]
        } else {
            self.uncertainty[i].max(self.uncertainty[i1])
        };
        BoundaryPoint {
            flutter_speed: v,
            trusted: u == 0.0,
            uncertainty: u,
            lower_bound: flag(&self.lower_bound),
            upper_bound: flag(&self.upper_bound),
            in_grid,
            raised_start: self.raised_start(i, j)
                || self.raised_start(i, j1)
                || self.raised_start(i1, j)
                || self.raised_start(i1, j1),
        }
    }
}

/// The fin's data the margin reports beside the boundary (so that a warm run needs no
/// eigen-solve): the clamped modes' names and frequencies and the NACA TN 4197 inputs.
#[derive(Clone, Debug, PartialEq)]
pub struct BoundaryFin {
    pub mode_names: Vec<String>,
    /// rad/s.
    pub omega: Vec<f64>,
    pub shear_modulus: f64,
    pub span: f64,
    pub root_chord: f64,
    pub tip_chord: f64,
    pub thickness: f64,
    /// Root leading edge to tip leading edge, m (TN 4197 in Bennett's form).
    pub tip_le_offset: f64,
}

impl BoundaryFin {
    pub fn new(m: &FinModes) -> Self {
        BoundaryFin {
            mode_names: m.names.clone(),
            omega: m.omega.clone(),
            shear_modulus: m.shear_modulus,
            span: m.planform.span,
            root_chord: m.planform.root_chord,
            tip_chord: m.planform.tip_chord,
            thickness: m.thickness,
            tip_le_offset: m.planform.tip_le_offset,
        }
    }
}

/// The cached form of a vehicle's boundary and its fin data ([`BOUNDARY_REVISION`]; the
/// flags as bytes 0/1, row-major as [`Boundary::speeds`]).
#[derive(Clone, Debug, PartialEq, rkyv::Archive, rkyv::Serialize, rkyv::Deserialize)]
pub struct BoundaryArtifact {
    pub machs: Vec<f64>,
    pub altitudes: Vec<f64>,
    pub densities: Vec<f64>,
    pub speeds: Vec<f64>,
    pub lower_bound: Vec<u8>,
    pub upper_bound: Vec<u8>,
    /// `[lowest, largest]` per Mach node, flattened.
    pub speed_ranges: Vec<f64>,
    /// Per node, the speed its sweep started at.
    pub node_lowest_speeds: Vec<f64>,
    /// Per Mach node, the flutter speed's relative uncertainty (0 outside the band).
    pub uncertainty: Vec<f64>,
    pub mode_names: Vec<String>,
    pub omega: Vec<f64>,
    /// Shear modulus, span, root chord, tip chord, thickness, tip leading-edge offset.
    pub fin: Vec<f64>,
}

impl crate::artifact::ArtifactPayload for BoundaryArtifact {
    const SCHEMA: &'static str = "BoundaryArtifact v4: machs Vec<f64>, altitudes Vec<f64>, densities Vec<f64> (per altitude), speeds Vec<f64> (machs x altitudes row-major), lower_bound Vec<u8>, upper_bound Vec<u8>, speed_ranges Vec<f64> (2 per Mach), node_lowest_speeds Vec<f64> (per node), uncertainty Vec<f64> (per Mach), mode_names Vec<String>, omega Vec<f64>, fin Vec<f64> [G, span, root chord, tip chord, thickness, tip LE offset]";
}

impl BoundaryArtifact {
    pub fn new(b: &Boundary, f: &BoundaryFin) -> Self {
        BoundaryArtifact {
            machs: b.machs.clone(),
            altitudes: b.altitudes.clone(),
            densities: b.densities.clone(),
            speeds: b.speeds.clone(),
            lower_bound: b.lower_bound.iter().map(|&x| u8::from(x)).collect(),
            upper_bound: b.upper_bound.iter().map(|&x| u8::from(x)).collect(),
            speed_ranges: b.speed_ranges.iter().flatten().copied().collect(),
            node_lowest_speeds: b.node_lowest_speeds.clone(),
            uncertainty: b.uncertainty.clone(),
            mode_names: f.mode_names.clone(),
            omega: f.omega.clone(),
            fin: vec![
                f.shear_modulus,
                f.span,
                f.root_chord,
                f.tip_chord,
                f.thickness,
                f.tip_le_offset,
            ],
        }
    }

    /// Back to the boundary and the fin data, checked against the `spec` it was keyed by: an
    /// error (the entry is then rebuilt) when a size, a grid value or a flag does not fit, or a
    /// value is not finite and positive.
    pub fn to_boundary(&self, spec: &BoundarySpec) -> Result<(Boundary, BoundaryFin), String> {
        let (nm, na) = (spec.machs.len(), spec.altitudes.len());
        if self.machs != spec.machs || self.altitudes != spec.altitudes {
            return Err("the cached boundary's grid is not the requested one".into());
        }
        let n = nm * na;
        if self.densities.len() != na
            || self.speeds.len() != n
            || self.lower_bound.len() != n
            || self.upper_bound.len() != n
            || self.speed_ranges.len() != 2 * nm
            || self.node_lowest_speeds.len() != n
            || self.uncertainty.len() != nm
            || self.omega.len() != spec.modes
            || self.mode_names.len() != spec.modes
            || self.fin.len() != 6
        {
            return Err("the cached boundary's sizes do not fit its grid".into());
        }
        let positive = |v: &[f64]| v.iter().all(|x| x.is_finite() && *x > 0.0);
        if !positive(&self.densities)
            || !positive(&self.speeds)
            || !positive(&self.speed_ranges)
            || !positive(&self.node_lowest_speeds)
        {
            return Err("the cached boundary holds a value that is not finite and positive".into());
        }
        if !self.uncertainty.iter().all(|u| u.is_finite() && *u >= 0.0) {
            return Err(
                "the cached boundary holds an uncertainty that is not finite and >= 0".into(),
            );
        }
        let flags = |v: &[u8]| -> Result<Vec<bool>, String> {
            v.iter()
                .map(|&x| match x {
                    0 => Ok(false),
                    1 => Ok(true),
                    x => Err(format!("the cached boundary holds the flag {x}")),
                })
                .collect()
        };
        let speed_ranges: Vec<[f64; 2]> = self
            .speed_ranges
            .chunks_exact(2)
            .map(|c| [c[0], c[1]])
            .collect();
        let largest_speed = speed_ranges.iter().map(|r| r[1]).fold(0.0, f64::max);
        Ok((
            Boundary {
                machs: self.machs.clone(),
                altitudes: self.altitudes.clone(),
                densities: self.densities.clone(),
                speeds: self.speeds.clone(),
                lower_bound: flags(&self.lower_bound)?,
                upper_bound: flags(&self.upper_bound)?,
                speed_ranges,
                node_lowest_speeds: self.node_lowest_speeds.clone(),
                largest_speed,
                uncertainty: self.uncertainty.clone(),
            },
            BoundaryFin {
                mode_names: self.mode_names.clone(),
                omega: self.omega.clone(),
                shear_modulus: self.fin[0],
                span: self.fin[1],
                root_chord: self.fin[2],
                tip_chord: self.fin[3],
                thickness: self.fin[4],
                tip_le_offset: self.fin[5],
            },
        ))
    }
}
