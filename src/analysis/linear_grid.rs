//! Stability maps: a plain grid of `sigma_d`, `omega_d` and the stability class over two
//! swept axes (fin thickness x Mach in Figs 6.3-6.8 and 6.11), shared by the planar and the
//! linearised 3-D analyses, and its CSV form.

use std::io::Write;
use std::path::Path;

use serde::Serialize;

/// How the least-stable root behaves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StabilityClass {
    /// Every (non-neutral) root has `Re λ <= 0`.
    Stable,
    /// The least-stable root is complex with `Re λ > 0`: a growing oscillation.
    Flutter,
    /// The least-stable root is real and positive: a monotonic departure.
    Divergence,
}

impl StabilityClass {
    /// Lower-case name, as written to CSV and JSON.
    pub fn name(&self) -> &'static str {
        match self {
            StabilityClass::Stable => "stable",
            StabilityClass::Flutter => "flutter",
            StabilityClass::Divergence => "divergence",
        }
    }
}

/// A grid over `xs` x `ys`. The value at `(xs[i], ys[j])` sits at index `j * xs.len() + i`
/// (row-major with one row per `y`, the layout of a contour plot's `z[y][x]`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StabilityMap {
    /// First axis (fin thickness, m, for the thickness x Mach maps).
    pub xs: Vec<f64>,
    /// Second axis (Mach).
    pub ys: Vec<f64>,
    /// `sigma_d`, 1/s.
    pub sigma: Vec<f64>,
    /// `omega_d`, rad/s.
    pub omega: Vec<f64>,
    /// Class of the least-stable root of the vehicle's dynamics.
    pub class: Vec<StabilityClass>,
    /// `max Re λ` of the flight-path roots (the trim's slow drift, not part of `sigma_d`
    /// and the class: [`super::roots`]), 1/s; NaN where there are none.
    pub flight_path_sigma: Vec<f64>,
}

impl StabilityMap {
    /// Index of `(xs[i], ys[j])`.
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.xs.len() + i
    }

    /// Writes `x_name,y_name,sigma_d,omega_d,class,flight_path_sigma`, one line per grid
    /// point (rows of constant `y`, `x` fastest), floats in Rust's shortest round-trip form.
    pub fn write_csv(&self, w: &mut dyn Write, x_name: &str, y_name: &str) -> std::io::Result<()> {
        writeln!(
            w,
            "{x_name},{y_name},sigma_d,omega_d,class,flight_path_sigma"
        )?;
        for (j, y) in self.ys.iter().enumerate() {
            for (i, x) in self.xs.iter().enumerate() {
                let k = self.index(i, j);
                writeln!(
                    w,
                    "{x},{y},{},{},{},{}",
                    self.sigma[k],
                    self.omega[k],
                    self.class[k].name(),
                    self.flight_path_sigma[k]
                )?;
            }
        }
        Ok(())
    }

    /// [`Self::write_csv`] into a file (written to a temporary name, then renamed).
    pub fn write_csv_file(&self, path: &Path, x_name: &str, y_name: &str) -> std::io::Result<()> {
        let mut buf = Vec::new();
        self.write_csv(&mut buf, x_name, y_name)?;
        let tmp = path.with_extension("csv.tmp");
        std::fs::write(&tmp, buf)?;
        std::fs::rename(&tmp, path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_lists_every_point_row_by_row() {
        let m = StabilityMap {
            xs: vec![1.0, 2.0, 3.0],
            ys: vec![0.5, 0.7],
            sigma: vec![-1.0, 0.0, 2.5, -0.5, 1.0, 3.0],
            omega: vec![1.0, 0.0, 0.0, 2.0, 4.0, 0.0],
            class: vec![
                StabilityClass::Stable,
                StabilityClass::Stable,
                StabilityClass::Divergence,
                StabilityClass::Stable,
                StabilityClass::Flutter,
                StabilityClass::Divergence,
            ],
            flight_path_sigma: vec![f64::NAN, f64::NAN, 0.04, f64::NAN, f64::NAN, -0.1],
        };
        assert_eq!(m.index(2, 1), 5);
        let mut buf = Vec::new();
        m.write_csv(&mut buf, "thickness_m", "mach").unwrap();
        let text = String::from_utf8(buf).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "thickness_m,mach,sigma_d,omega_d,class,flight_path_sigma"
        );
        assert_eq!(lines.len(), 7);
        assert_eq!(lines[3], "3,0.5,2.5,0,divergence,0.04");
        assert_eq!(lines[5], "2,0.7,1,4,flutter,NaN");
    }
}
