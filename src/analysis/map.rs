//! Stability maps over fin thickness x Mach (thesis Figs 6.3-6.8): sigma_d, omega_d and the
//! class at every grid point, the TN 4197 flutter Mach next to them (Martin's original form
//! and Bennett's revised one, Peak of Flight 615, for the boundaries; the Peak of Flight 291
//! form as a column of `map.csv`), per-thickness stability boundaries, and the CSV files.
//!
//! [`StabilityMap`] is the plain data a plot takes: `xs` (Mach, the thesis' horizontal axis),
//! `ys` (fin thickness, m) and row-major grids indexed `[iy][ix]`.

use std::path::Path;

use serde::Serialize;

use super::planar::{
    self, Altitude, PlanarError, PlanarKind, PlanarVehicle, Stability, condition_at,
};
use super::tn4197::{Tn4197Fin, Tn4197Form};

/// The class of one grid point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CellClass {
    Stable,
    Neutral,
    Flutter,
    Divergence,
    /// No terminal-velocity equilibrium in the atmosphere's range at this point.
    NoEquilibrium,
    /// The analysis failed at this point (table range, mass matrix, eigen solver).
    Failed,
}

impl CellClass {
    /// Snake-case name used in CSV.
    pub fn name(self) -> &'static str {
        match self {
            CellClass::Stable => "stable",
            CellClass::Neutral => "neutral",
            CellClass::Flutter => "flutter",
            CellClass::Divergence => "divergence",
            CellClass::NoEquilibrium => "no_equilibrium",
            CellClass::Failed => "failed",
        }
    }
}

impl From<Stability> for CellClass {
    fn from(s: Stability) -> Self {
        match s {
            Stability::Stable => CellClass::Stable,
            Stability::Neutral => CellClass::Neutral,
            Stability::Flutter => CellClass::Flutter,
            Stability::Divergence => CellClass::Divergence,
        }
    }
}

/// A stability map as plain data for plotting: grids are `[iy][ix]`; points without a result
/// hold NaN in `sigma` and `omega`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StabilityMap {
    /// Axis titles, e.g. "Mach" and "fin thickness (m)".
    pub x_label: String,
    pub y_label: String,
    pub xs: Vec<f64>,
    pub ys: Vec<f64>,
    /// sigma_d = max Re(lambda), 1/s.
    pub sigma: Vec<Vec<f64>>,
    /// omega_d, rad/s.
    pub omega: Vec<Vec<f64>>,
    pub class: Vec<Vec<CellClass>>,
}

/// A planar map with what went into each point.
#[derive(Clone, Debug, Serialize)]
pub struct PlanarMap {
    pub kind: PlanarKind,
    /// `xs` = Mach, `ys` = fin thickness (m).
    pub map: StabilityMap,
    /// Altitude (m) and airspeed (m/s) of each point (NaN where there is none).
    pub altitude: Vec<Vec<f64>>,
    pub speed: Vec<Vec<f64>>,
    /// TN 4197 flutter Mach at each point's altitude, Martin's original form: the one the
    /// boundaries, `boundary.csv`, `critical_thickness.csv` and `overlay_TN_4197.csv` use.
    pub tn4197_mach: Vec<Vec<f64>>,
    /// The same in the Peak of Flight 291 / RocketPy form (sqrt(2) higher), for comparison
    /// (`map.csv` only).
    pub tn4197_pof291_mach: Vec<Vec<f64>>,
    /// The same in Bennett's revised form (Peak of Flight 615, eps from the planform's
    /// centroid): `map.csv`, the `tn4197_pof615` columns of `boundary.csv` and
    /// `critical_thickness.csv`, and `overlay_TN_4197_PoF_615.csv`.
    pub tn4197_pof615_mach: Vec<Vec<f64>>,
    /// Why points failed, as `(iy, ix, message)` (no-equilibrium points included).
    pub failures: Vec<(usize, usize, String)>,
}

/// Where a boundary lies along the Mach axis for one thickness.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "status", content = "mach")]
pub enum BoundaryMach {
    /// The lowest Mach where the quantity crosses zero upwards, by linear interpolation.
    Crossing(f64),
    /// Already unstable at the lowest Mach of the map.
    BelowRange,
    /// Stable over the whole Mach range.
    AboveRange,
}

impl BoundaryMach {
    /// (value or empty, status) for CSV.
    fn csv(self) -> (String, &'static str) {
        match self {
            BoundaryMach::Crossing(m) => (format!("{m}"), "crossing"),
            BoundaryMach::BelowRange => (String::new(), "below_range"),
            BoundaryMach::AboveRange => (String::new(), "above_range"),
        }
    }
}

/// The model's own and the TN 4197 boundary at one thickness.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Boundary {
    pub thickness: f64,
    /// Lowest Mach where sigma_d crosses 0.
    pub model: BoundaryMach,
    /// Lowest Mach where Mach - TN 4197 flutter Mach crosses 0.
    pub tn4197: BoundaryMach,
    /// The same for Bennett's form (Peak of Flight 615).
    pub tn4197_pof615: BoundaryMach,
}

/// Where the stability boundary lies along the thickness axis at one Mach number.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "status", content = "thickness")]
pub enum CriticalThickness {
    /// Every thicker fin of the map is stable: the highest thickness where the quantity
    /// crosses zero downwards (unstable below, stable above), by linear interpolation.
    Crossing(f64),
    /// Stable at every thickness of the map.
    BelowRange,
    /// Unstable at the thickest fin of the map.
    AboveRange,
}

/// Per Mach: the critical thickness of the model (sigma_d = 0) and of TN 4197
/// (flutter Mach = Mach), the thesis' way of reading Figs 6.3-6.8.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MachBoundary {
    pub mach: f64,
    pub model: CriticalThickness,
    pub tn4197: CriticalThickness,
    /// Bennett's form (Peak of Flight 615).
    pub tn4197_pof615: CriticalThickness,
}

/// The thickness above which `f` stays negative (stable): the highest downward zero
/// crossing of `f` along `ys` (ascending), by linear interpolation; NaN points skipped.
pub fn critical_thickness(ys: &[f64], f: &[f64]) -> CriticalThickness {
    let pts: Vec<(f64, f64)> = ys
        .iter()
        .zip(f)
        .filter(|(_, v)| v.is_finite())
        .map(|(y, v)| (*y, *v))
        .collect();
    match pts.last() {
        None => return CriticalThickness::BelowRange,
        Some((_, v)) if *v >= 0.0 => return CriticalThickness::AboveRange,
        Some(_) => {}
    }
    for w in pts.windows(2).rev() {
        let ((y0, v0), (y1, v1)) = (w[0], w[1]);
        if v0 >= 0.0 && v1 < 0.0 {
            return CriticalThickness::Crossing(y0 + (y1 - y0) * v0 / (v0 - v1));
        }
    }
    CriticalThickness::BelowRange
}

/// A grid axis: `count` equally spaced values from `start` to `stop` (on the command line,
/// `START:STOP:COUNT` with units, checked by [`crate::check::cli_values::check_range`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridRange {
    pub start: f64,
    pub stop: f64,
    pub count: usize,
}

impl GridRange {
    /// The values.
    pub fn values(&self) -> Vec<f64> {
        if self.count == 1 {
            return vec![self.start];
        }
        let step = (self.stop - self.start) / (self.count - 1) as f64;
        (0..self.count)
            .map(|k| self.start + step * k as f64)
            .collect()
    }
}

/// Sweeps fin thickness (`thicknesses`, m) x Mach (`machs`) with the planar model `kind`
/// at `altitude` (fixed, or the equilibrium altitude of each point). Points that fail are
/// recorded (class, NaN) and the sweep goes on.
pub fn planar_map(
    vehicle: &PlanarVehicle,
    kind: PlanarKind,
    thicknesses: &[f64],
    machs: &[f64],
    altitude: Altitude,
) -> PlanarMap {
    let (ny, nx) = (thicknesses.len(), machs.len());
    let grid = || vec![vec![f64::NAN; nx]; ny];
    let mut sigma = grid();
    let mut omega = grid();
    let mut alt = grid();
    let mut speed = grid();
    let mut tn = grid();
    let mut tn_pof = grid();
    let mut tn_615 = grid();
    let mut class = vec![vec![CellClass::Failed; nx]; ny];
    let mut failures = Vec::new();
    let f = &vehicle.fins;
    for (iy, &t) in thicknesses.iter().enumerate() {
        let tn_fin = Tn4197Fin {
            shear_modulus: f.shear_modulus(),
            span: f.span,
            root_chord: f.root_chord,
            tip_chord: f.tip_chord,
            thickness: t,
            tip_le_offset: f.tip_le_offset,
        };
        for (ix, &m) in machs.iter().enumerate() {
            let result = condition_at(vehicle, t, m, altitude).and_then(|c| {
                alt[iy][ix] = c.altitude;
                speed[iy][ix] = c.speed;
                tn[iy][ix] = tn_fin.flutter_mach_in(Tn4197Form::Martin, c.pressure);
                tn_pof[iy][ix] = tn_fin.flutter_mach_in(Tn4197Form::PeakOfFlight291, c.pressure);
                tn_615[iy][ix] = tn_fin.flutter_mach_in(Tn4197Form::PeakOfFlight615, c.pressure);
                planar::verdict(&planar::parameters(vehicle, kind, t, c)?)
            });
            match result {
                Ok(v) => {
                    sigma[iy][ix] = v.sigma_d;
                    omega[iy][ix] = v.omega_d;
                    class[iy][ix] = v.class.into();
                }
                Err(e) => {
                    if matches!(e, PlanarError::NoEquilibrium { .. }) {
                        class[iy][ix] = CellClass::NoEquilibrium;
                    }
                    failures.push((iy, ix, e.to_string()));
                }
            }
        }
    }
    PlanarMap {
        kind,
        map: StabilityMap {
            x_label: "Mach".to_string(),
            y_label: "fin thickness (m)".to_string(),
            xs: machs.to_vec(),
            ys: thicknesses.to_vec(),
            sigma,
            omega,
            class,
        },
        altitude: alt,
        speed,
        tn4197_mach: tn,
        tn4197_pof291_mach: tn_pof,
        tn4197_pof615_mach: tn_615,
        failures,
    }
}

/// The lowest x where `f` crosses zero upwards (f < 0 then f >= 0), by linear
/// interpolation; points with NaN are skipped.
pub fn lowest_crossing(xs: &[f64], f: &[f64]) -> BoundaryMach {
    let pts: Vec<(f64, f64)> = xs
        .iter()
        .zip(f)
        .filter(|(_, y)| y.is_finite())
        .map(|(x, y)| (*x, *y))
        .collect();
    match pts.first() {
        None => return BoundaryMach::AboveRange,
        Some((_, y)) if *y >= 0.0 => return BoundaryMach::BelowRange,
        Some(_) => {}
    }
    for w in pts.windows(2) {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        if y0 < 0.0 && y1 >= 0.0 {
            return BoundaryMach::Crossing(x0 + (x1 - x0) * (-y0) / (y1 - y0));
        }
    }
    BoundaryMach::AboveRange
}

impl PlanarMap {
    /// Per thickness: the model's boundary (sigma_d = 0) and the TN 4197 boundary
    /// (Mach = flutter Mach).
    pub fn boundaries(&self) -> Vec<Boundary> {
        let xs = &self.map.xs;
        self.map
            .ys
            .iter()
            .enumerate()
            .map(|(iy, &t)| {
                let excess =
                    |row: &[f64]| -> Vec<f64> { xs.iter().zip(row).map(|(m, f)| m - f).collect() };
                Boundary {
                    thickness: t,
                    model: lowest_crossing(xs, &self.map.sigma[iy]),
                    tn4197: lowest_crossing(xs, &excess(&self.tn4197_mach[iy])),
                    tn4197_pof615: lowest_crossing(xs, &excess(&self.tn4197_pof615_mach[iy])),
                }
            })
            .collect()
    }

    /// Per Mach: the model's and the TN 4197 critical thickness.
    pub fn mach_boundaries(&self) -> Vec<MachBoundary> {
        let ys = &self.map.ys;
        self.map
            .xs
            .iter()
            .enumerate()
            .map(|(ix, &mach)| {
                let sigma: Vec<f64> = self.map.sigma.iter().map(|r| r[ix]).collect();
                let excess =
                    |g: &[Vec<f64>]| -> Vec<f64> { g.iter().map(|r| mach - r[ix]).collect() };
                MachBoundary {
                    mach,
                    model: critical_thickness(ys, &sigma),
                    tn4197: critical_thickness(ys, &excess(&self.tn4197_mach)),
                    tn4197_pof615: critical_thickness(ys, &excess(&self.tn4197_pof615_mach)),
                }
            })
            .collect()
    }

    /// `critical_thickness.csv`: per Mach, the model's and the TN 4197 critical thickness.
    pub fn write_critical_thickness_csv(&self, path: &Path) -> Result<(), csv::Error> {
        let mut w = csv::Writer::from_path(path)?;
        w.write_record([
            "mach",
            "model_critical_thickness_m",
            "model_status",
            "tn4197_critical_thickness_m",
            "tn4197_status",
            "tn4197_pof615_critical_thickness_m",
            "tn4197_pof615_status",
        ])?;
        let cell = |c: CriticalThickness| match c {
            CriticalThickness::Crossing(t) => (t.to_string(), "crossing"),
            CriticalThickness::BelowRange => (String::new(), "below_range"),
            CriticalThickness::AboveRange => (String::new(), "above_range"),
        };
        for b in self.mach_boundaries() {
            let (m, ms) = cell(b.model);
            let (t, ts) = cell(b.tn4197);
            let (b6, bs) = cell(b.tn4197_pof615);
            w.write_record([
                b.mach.to_string(),
                m,
                ms.to_string(),
                t,
                ts.to_string(),
                b6,
                bs.to_string(),
            ])?;
        }
        w.flush()?;
        Ok(())
    }

    /// `map.csv`: one row per point, thickness slowest.
    pub fn write_csv(&self, path: &Path) -> Result<(), csv::Error> {
        let mut w = csv::Writer::from_path(path)?;
        w.write_record([
            "thickness_m",
            "mach",
            "altitude_m",
            "speed_m_s",
            "sigma_d",
            "omega_d",
            "class",
            "tn4197_flutter_mach",
            "tn4197_pof291_flutter_mach",
            "tn4197_pof615_flutter_mach",
        ])?;
        let m = &self.map;
        for (iy, t) in m.ys.iter().enumerate() {
            for (ix, mach) in m.xs.iter().enumerate() {
                w.write_record([
                    t.to_string(),
                    mach.to_string(),
                    self.altitude[iy][ix].to_string(),
                    self.speed[iy][ix].to_string(),
                    m.sigma[iy][ix].to_string(),
                    m.omega[iy][ix].to_string(),
                    m.class[iy][ix].name().to_string(),
                    self.tn4197_mach[iy][ix].to_string(),
                    self.tn4197_pof291_mach[iy][ix].to_string(),
                    self.tn4197_pof615_mach[iy][ix].to_string(),
                ])?;
            }
        }
        w.flush()?;
        Ok(())
    }

    /// `overlay_TN_4197.csv` (Martin's form) or `overlay_TN_4197_PoF_615.csv` (Bennett's,
    /// `pof615`): the NACA TN 4197 flutter boundary as a curve (thickness in m, Mach) in the
    /// axes of `map.csv`, for the thicknesses where it lies inside the Mach range;
    /// `flexflight report` draws every overlay over the map.
    pub fn write_tn4197_overlay(&self, path: &Path, pof615: bool) -> Result<(), csv::Error> {
        let mut w = csv::Writer::from_path(path)?;
        w.write_record(["thickness_m", "mach"])?;
        for b in self.boundaries() {
            let curve = if pof615 { b.tn4197_pof615 } else { b.tn4197 };
            if let BoundaryMach::Crossing(m) = curve {
                w.write_record([b.thickness.to_string(), m.to_string()])?;
            }
        }
        w.flush()?;
        Ok(())
    }

    /// `boundary.csv`: per thickness, the model's and the TN 4197 boundary Mach.
    pub fn write_boundary_csv(&self, path: &Path) -> Result<(), csv::Error> {
        let mut w = csv::Writer::from_path(path)?;
        w.write_record([
            "thickness_m",
            "model_boundary_mach",
            "model_status",
            "tn4197_boundary_mach",
            "tn4197_status",
            "tn4197_pof615_boundary_mach",
            "tn4197_pof615_status",
        ])?;
        for b in self.boundaries() {
            let (m, ms) = b.model.csv();
            let (t, ts) = b.tn4197.csv();
            let (b6, bs) = b.tn4197_pof615.csv();
            w.write_record([
                b.thickness.to_string(),
                m,
                ms.to_string(),
                t,
                ts.to_string(),
                b6,
                bs.to_string(),
            ])?;
        }
        w.flush()?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_values_include_both_ends() {
        let r = GridRange {
            start: 0.5,
            stop: 1.5,
            count: 3,
        };
        assert_eq!(r.values(), vec![0.5, 1.0, 1.5]);
        let one = GridRange {
            start: 2.0,
            stop: 2.0,
            count: 1,
        };
        assert_eq!(one.values(), vec![2.0]);
    }

    #[test]
    fn critical_thickness_is_the_highest_downward_crossing() {
        let ys = [0.1, 0.2, 0.3, 0.4];
        // Unstable, stable, unstable, stable: the last crossing (0.3 -> 0.4) counts.
        assert_eq!(
            critical_thickness(&ys, &[1.0, -1.0, 1.0, -3.0]),
            CriticalThickness::Crossing(0.325)
        );
        assert_eq!(
            critical_thickness(&ys, &[-1.0; 4]),
            CriticalThickness::BelowRange
        );
        assert_eq!(
            critical_thickness(&ys, &[-1.0, -1.0, -1.0, 0.5]),
            CriticalThickness::AboveRange
        );
    }

    #[test]
    fn crossing_is_interpolated() {
        let xs = [0.5, 1.0, 1.5, 2.0];
        // -1 at 1.0, +1 at 1.5: crossing at 1.25.
        assert_eq!(
            lowest_crossing(&xs, &[-2.0, -1.0, 1.0, 3.0]),
            BoundaryMach::Crossing(1.25)
        );
        assert_eq!(
            lowest_crossing(&xs, &[0.1, 1.0, 1.0, 3.0]),
            BoundaryMach::BelowRange
        );
        assert_eq!(lowest_crossing(&xs, &[-1.0; 4]), BoundaryMach::AboveRange);
        // NaN points are skipped: the crossing is between 0.5 and 1.5.
        assert_eq!(
            lowest_crossing(&xs, &[-1.0, f64::NAN, 1.0, 1.0]),
            BoundaryMach::Crossing(1.0)
        );
    }
}
