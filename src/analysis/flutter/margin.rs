//! The flutter margin over a flight (issue 13, deliverable 5).
//!
//! # The boundary
//!
//! The flutter speed of the clamped fin ([`super::fin`]) depends on the Mach number (through
//! the panel aerodynamics) and on the air density (through the mass ratio), so it is a
//! surface `V_F(M, h)`. It is precomputed by p-k solutions on a grid of trusted Mach numbers
//! (subsonic `0, 0.3, 0.6, 0.9`; supersonic from 1.2 in steps of 0.3 past the flight's maximum,
//! only when the flight exceeds Mach 0.9) and of altitudes spanning the flight (three levels
//! from the lowest to the highest altitude flown), each at fixed Mach and density: the
//! "unmatched" p-k solution of Rodden & Johnson (MSC Nastran Aeroelastic User's Guide §2.6), in
//! which speed is varied at the node's Mach and density. Between nodes `V_F` is bilinear in
//! `(M, h)`. In the transonic gap `0.9 < M < 1.2` it is the linear blend of the 0.9 and 1.2
//! nodes and every such row is flagged untrusted (neither theory holds there; the flight's
//! panel loads are bridged the same way, `runtime::aero::panel::Regime`).
//!
//! A node where no flutter point is found up to the largest speed tried carries that speed
//! and is flagged as a lower bound (the margin there is at least the value written); a node
//! already unstable at the lowest speed carries the lowest speed (conservative).
//!
//! # The margin
//!
//! At each output row, with airspeed `V = M a(h)`: the speed margin `V_F / V` and the
//! dynamic-pressure margin `q_F / q = (V_F / V)²` (same density). The criterion is the usual
//! 15 % on equivalent airspeed (14 CFR 25.629(b)(1): aeroelastically stable up to `1.15 V_D`;
//! MIL-A-8870C 3.1.1: a 15 % flutter margin on equivalent airspeed); since `V_EAS = V
//! sqrt(ρ/ρ_0)` and both speeds are at the same density, the EAS margin equals `V_F / V`.

use super::fin::{
    FinFlutterError, FinFlutterSettings, FinModes, fin_lattice, flutter_model, gaf_table,
};
use super::pk::{PkSettings, pk_solve_cut};
use crate::runtime::aero::panel::{SUBSONIC_LIMIT, SUPERSONIC_LIMIT};
use crate::runtime::atmosphere::{Atmosphere, Standard1976};

/// The required speed margin `V_F / V` (15 % on equivalent airspeed).
pub const CRITERION: f64 = 1.15;

/// A flutter boundary `V_F(M, h)` on a grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Boundary {
    pub machs: Vec<f64>,
    pub altitudes: Vec<f64>,
    /// `V_F` (m/s), row-major `machs x altitudes`.
    pub speeds: Vec<f64>,
    /// Whether the node's value is a lower bound (no flutter up to the largest speed).
    pub lower_bound: Vec<bool>,
    /// The largest speed tried, m/s.
    pub largest_speed: f64,
}

/// The Mach nodes for a flight reaching `max_mach` (module doc).
pub fn mach_nodes(max_mach: f64) -> Vec<f64> {
    let mut m = vec![0.0, 0.3, 0.6, SUBSONIC_LIMIT];
    if max_mach > SUBSONIC_LIMIT {
        let mut x = SUPERSONIC_LIMIT;
        m.push(x);
        while x < max_mach {
            x += 0.3;
            m.push(x);
        }
    }
    m
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
    let atm = Standard1976::new();
    let v_lo = 0.1 * largest_speed;
    let speeds: Vec<f64> = (0..30)
        .map(|i| v_lo + (largest_speed - v_lo) * i as f64 / 29.0)
        .collect();
    let mut s = *settings;
    let w_max = modes.omega.iter().copied().fold(0.0, f64::max);
    s.k_max = (1.2 * w_max * modes.b_ref() / v_lo).max(0.1);
    s.k_count = s.k_count.max(40);
    let lattice = fin_lattice(modes, &s)?;
    let mut out = Vec::with_capacity(machs.len() * altitudes.len());
    let mut lower = Vec::with_capacity(out.capacity());
    for &m in machs {
        let gaf = gaf_table(modes, &lattice, m, &s)?;
        for &h in altitudes {
            let air = atm
                .at(h)
                .map_err(|e| FinFlutterError::Generate(format!("atmosphere: {e}")))?;
            let model = flutter_model(modes, air.density);
            // A branch whose p-k iteration does not converge at some speed (near zero
            // frequency at high speed) ends the sweep there, as in `analyze flutter`: the
            // node is solved on the speeds below it, and without a flutter point there it is a
            // lower bound at the last speed solved.
            let (sol, _) = pk_solve_cut(&model, &gaf, &speeds, PkSettings::default())?;
            let sp = &sol.speeds;
            if !sol.unstable_at_start.is_empty() {
                out.push(sp[0]);
                lower.push(false);
            } else if let Some(f) = sol.critical() {
                out.push(f.speed);
                lower.push(false);
            } else {
                out.push(sp[sp.len() - 1]);
                lower.push(true);
            }
        }
    }
    Ok(Boundary {
        machs: machs.to_vec(),
        altitudes: altitudes.to_vec(),
        speeds: out,
        lower_bound: lower,
        largest_speed,
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
    /// Both theories are trusted at this Mach (outside the transonic gap).
    pub trusted: bool,
    /// Some node used is a lower bound.
    pub lower_bound: bool,
}

impl Boundary {
    /// `V_F` at `(mach, altitude)`, bilinear (module doc). Machs beyond the grid are clamped.
    pub fn at(&self, mach: f64, altitude: f64) -> BoundaryPoint {
        let na = self.altitudes.len();
        let (i, tm) = bracket(&self.machs, mach);
        let (j, th) = bracket(&self.altitudes, altitude);
        let i1 = (i + 1).min(self.machs.len() - 1);
        let j1 = (j + 1).min(na - 1);
        let v = |a: usize, b: usize| self.speeds[a * na + b];
        let lb = |a: usize, b: usize| self.lower_bound[a * na + b];
        let along = |a: usize| (1.0 - th) * v(a, j) + th * v(a, j1);
        BoundaryPoint {
            flutter_speed: (1.0 - tm) * along(i) + tm * along(i1),
            trusted: !(mach > SUBSONIC_LIMIT && mach < SUPERSONIC_LIMIT),
            lower_bound: lb(i, j) || lb(i, j1) || lb(i1, j) || lb(i1, j1),
        }
    }
}
