//! Stability-map data: sigma_d (the largest real part of the eigenvalues, 1/s) on a grid of
//! fin thickness x Mach (thesis Figs 6.3-6.8), and its CSV form.

use std::path::Path;

use super::ReportError;

/// A curve drawn over a map, e.g. the NACA TN 4197 flutter boundary.
#[derive(Clone, Debug, PartialEq)]
pub struct OverlayCurve {
    /// Legend text.
    pub label: String,
    /// Points in the map's (x, y) coordinates.
    pub points: Vec<[f64; 2]>,
}

/// sigma_d sampled on a rectangular grid.
///
/// `values` is row-major with one row per y value:
/// `values[j * xs.len() + i] = sigma_d(xs[i], ys[j])`; NaN marks a point with no result
/// (drawn grey, ignored by the contours).
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityMap {
    /// Increasing x values (e.g. fin thickness, mm).
    pub xs: Vec<f64>,
    /// Increasing y values (e.g. Mach).
    pub ys: Vec<f64>,
    /// sigma_d (1/s), row-major, one row per y value.
    pub values: Vec<f64>,
    /// Axis label with unit, e.g. "fin thickness (mm)".
    pub x_label: String,
    /// Axis label with unit, e.g. "Mach".
    pub y_label: String,
    /// What the colours show, e.g. "sigma_d (1/s)".
    pub value_label: String,
    /// Caption above the map.
    pub title: String,
    /// Curves drawn over the map, with legend entries.
    pub overlays: Vec<OverlayCurve>,
}

impl StabilityMap {
    /// A sigma_d map over fin thickness (mm) x Mach with the default labels and no
    /// overlays; `values` row-major, one row per Mach value. Checked by
    /// [`StabilityMap::validate`].
    pub fn new(xs: Vec<f64>, ys: Vec<f64>, values: Vec<f64>) -> Result<Self, ReportError> {
        let map = StabilityMap {
            xs,
            ys,
            values,
            x_label: "fin thickness (mm)".into(),
            y_label: "Mach".into(),
            value_label: "sigma_d (1/s)".into(),
            title: "Stability map: sigma_d".into(),
            overlays: Vec::new(),
        };
        map.validate()?;
        Ok(map)
    }

    /// Check that the grid is consistent: sizes match, axes strictly increasing and finite.
    pub fn validate(&self) -> Result<(), ReportError> {
        let (nx, ny) = (self.xs.len(), self.ys.len());
        if nx < 2 || ny < 2 {
            return Err(ReportError::Data(format!(
                "a stability map needs at least 2 x 2 grid points, got {nx} x {ny}"
            )));
        }
        if self.values.len() != nx * ny {
            return Err(ReportError::Data(format!(
                "a {nx} x {ny} map needs {} values, got {}",
                nx * ny,
                self.values.len()
            )));
        }
        for (name, axis) in [("x", &self.xs), ("y", &self.ys)] {
            if axis.iter().any(|v| !v.is_finite()) || axis.windows(2).any(|w| w[1] <= w[0]) {
                return Err(ReportError::Data(format!(
                    "the map's {name} values must be finite and strictly increasing"
                )));
            }
        }
        Ok(())
    }

    /// The value at grid point (i, j).
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.values
            .get(j * self.xs.len() + i)
            .copied()
            .unwrap_or(f64::NAN)
    }

    /// Smallest and largest finite value, if any.
    pub fn value_range(&self) -> Option<(f64, f64)> {
        let finite = self.values.iter().copied().filter(|v| v.is_finite());
        finite.fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
    }

    /// Write the map as CSV `x,y,sigma_d` (header named after `x_label`/`y_label` is not
    /// used: the columns are always `x,y,sigma_d`), one row per grid point, x fastest.
    pub fn to_csv(&self) -> String {
        let mut s = String::from("x,y,sigma_d\n");
        for (j, y) in self.ys.iter().enumerate() {
            for (i, x) in self.xs.iter().enumerate() {
                s.push_str(&format!("{x},{y},{}\n", self.at(i, j)));
            }
        }
        s
    }
}

/// Read a map from CSV text with a header naming the columns.
///
/// sigma_d is the column named `sigma_d`; x is the column named `x`, else the first column;
/// y the column named `y`, else the second. Columns with other names become the axis labels
/// (so `fin_thickness_mm,mach,sigma_d` works). The grid is the sorted distinct x and y
/// values; a grid point absent from the file is NaN, a point given twice is an error.
/// `path` is used only in error messages (lines are 1-based, the header is line 1).
pub fn parse_map_csv(text: &str, path: &Path) -> Result<StabilityMap, ReportError> {
    let err = |line: u64, message: String| ReportError::Csv {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header = reader
        .headers()
        .map_err(|e| err(1, format!("cannot read the header: {e}")))?
        .clone();
    let names: Vec<&str> = header.iter().collect();
    let find = |n: &str| names.iter().position(|h| *h == n);
    let col_v = find("sigma_d").ok_or_else(|| {
        err(
            1,
            format!("no `sigma_d` column (columns: {})", names.join(", ")),
        )
    })?;
    let others: Vec<usize> = (0..names.len()).filter(|&c| c != col_v).collect();
    let col_x = find("x").or_else(|| others.first().copied());
    let col_y = find("y").or_else(|| others.iter().copied().find(|&c| Some(c) != col_x));
    let (Some(col_x), Some(col_y)) = (col_x, col_y) else {
        return Err(err(
            1,
            "a map needs an x column, a y column and `sigma_d`".into(),
        ));
    };
    let mut points: Vec<(f64, f64, f64, u64)> = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            err(line, format!("{e}"))
        })?;
        let line = record.position().map_or(0, |p| p.line());
        let field = |c: usize, what: &str| -> Result<f64, ReportError> {
            let s = record
                .get(c)
                .ok_or_else(|| err(line, format!("missing the {what} column")))?;
            if s.eq_ignore_ascii_case("nan") || s.is_empty() {
                return Ok(f64::NAN);
            }
            s.parse::<f64>()
                .map_err(|_| err(line, format!("`{s}` is not a number ({what})")))
        };
        let (x, y, v) = (
            field(col_x, "x")?,
            field(col_y, "y")?,
            field(col_v, "sigma_d")?,
        );
        if !x.is_finite() || !y.is_finite() {
            return Err(err(line, "x and y must be finite numbers".into()));
        }
        points.push((x, y, v, line));
    }
    if points.is_empty() {
        return Err(err(1, "the map has no data rows".into()));
    }
    let axis = |f: fn(&(f64, f64, f64, u64)) -> f64| {
        let mut a: Vec<f64> = points.iter().map(f).collect();
        a.sort_by(f64::total_cmp);
        a.dedup();
        a
    };
    let xs = axis(|p| p.0);
    let ys = axis(|p| p.1);
    let mut values = vec![f64::NAN; xs.len() * ys.len()];
    let mut seen = vec![0u64; values.len()];
    for &(x, y, v, line) in &points {
        let i = xs.partition_point(|a| *a < x);
        let j = ys.partition_point(|a| *a < y);
        let k = j * xs.len() + i;
        if seen[k] != 0 {
            return Err(err(
                line,
                format!("grid point ({x}, {y}) already given on line {}", seen[k]),
            ));
        }
        seen[k] = line;
        values[k] = v;
    }
    let label = |c: usize, default: &str| match names[c] {
        "x" | "y" => default.to_string(),
        other => other.to_string(),
    };
    let map = StabilityMap {
        xs,
        ys,
        values,
        x_label: label(col_x, "fin thickness (mm)"),
        y_label: label(col_y, "Mach"),
        value_label: "sigma_d (1/s)".into(),
        title: "Stability map: sigma_d".into(),
        overlays: Vec::new(),
    };
    map.validate()?;
    Ok(map)
}

/// Parse an overlay curve from CSV text with a header and two numeric columns (x, y, in
/// the map's coordinates), in drawing order. `path` is for messages.
pub fn parse_overlay_csv(
    text: &str,
    label: &str,
    path: &Path,
) -> Result<OverlayCurve, ReportError> {
    let err = |line: u64, message: String| ReportError::Csv {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let width = reader
        .headers()
        .map_err(|e| err(1, format!("cannot read the header: {e}")))?
        .len();
    if width < 2 {
        return Err(err(1, "an overlay needs two columns, x and y".into()));
    }
    let mut points = Vec::new();
    for record in reader.records() {
        let record =
            record.map_err(|e| err(e.position().map_or(0, |p| p.line()), e.to_string()))?;
        let line = record.position().map_or(0, |p| p.line());
        let mut xy = [0.0; 2];
        for (k, v) in xy.iter_mut().enumerate() {
            let s = record.get(k).unwrap_or("");
            *v = s
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| err(line, format!("`{s}` is not a finite number")))?;
        }
        points.push(xy);
    }
    Ok(OverlayCurve {
        label: label.to_string(),
        points,
    })
}

/// Read a map CSV file (see [`parse_map_csv`]).
pub fn read_map_csv(path: &Path) -> Result<StabilityMap, ReportError> {
    parse_map_csv(&super::read_text(path)?, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(t: &str) -> Result<StabilityMap, ReportError> {
        parse_map_csv(t, Path::new("map.csv"))
    }

    #[test]
    fn grid_is_rebuilt_in_any_row_order_with_holes_as_nan() {
        let m = parse("x,y,sigma_d\n1,0.5,-2\n0,0.5,-1\n0,1.0,3\n1,1.0,nan\n2,0.5,7\n").unwrap();
        assert_eq!(m.xs, vec![0.0, 1.0, 2.0]);
        assert_eq!(m.ys, vec![0.5, 1.0]);
        assert_eq!(m.at(0, 0), -1.0);
        assert_eq!(m.at(1, 0), -2.0);
        assert_eq!(m.at(2, 0), 7.0);
        assert_eq!(m.at(0, 1), 3.0);
        assert!(m.at(1, 1).is_nan());
        assert!(m.at(2, 1).is_nan(), "absent point");
        let again = parse(&m.to_csv()).unwrap();
        assert_eq!(again.xs, m.xs);
        assert_eq!(again.at(2, 0), 7.0);
    }

    #[test]
    fn named_columns_become_axis_labels() {
        let m = parse("fin_thickness_mm,mach,sigma_d,omega_d\n0.5,0.8,1,9\n0.6,0.8,2,9\n0.5,0.9,3,9\n0.6,0.9,4,9\n").unwrap();
        assert_eq!(m.x_label, "fin_thickness_mm");
        assert_eq!(m.y_label, "mach");
        assert_eq!(m.at(1, 1), 4.0);
    }

    #[test]
    fn overlay_curves_parse_with_line_numbers() {
        let path = Path::new("overlay_tn4197.csv");
        let c = parse_overlay_csv("thickness,mach\n0.5,1.2\n0.7,1.6\n", "TN 4197", path).unwrap();
        assert_eq!(c.points, vec![[0.5, 1.2], [0.7, 1.6]]);
        let e = parse_overlay_csv("x,y\n0.5,1.2\n0.7,inf\n", "TN 4197", path).unwrap_err();
        assert!(e.to_string().starts_with("overlay_tn4197.csv:3:"), "{e}");
        assert!(StabilityMap::new(vec![0.0, 1.0], vec![0.0, 1.0], vec![0.0; 3]).is_err());
    }

    #[test]
    fn errors_carry_line_numbers() {
        let e = parse("x,y,sigma_d\n0,0,1\n1,0,oops\n").unwrap_err();
        assert!(matches!(e, ReportError::Csv { line: 3, .. }), "{e}");
        assert!(e.to_string().starts_with("map.csv:3:"), "{e}");
        let e = parse("x,y,sigma_d\n0,0,1\n1,0\n").unwrap_err();
        assert!(matches!(e, ReportError::Csv { line: 3, .. }), "{e}");
        let e = parse("x,y,sigma_d\n0,0,1\n1,0,2\n0,0,5\n").unwrap_err();
        assert!(
            matches!(e, ReportError::Csv { line: 4, .. }) && e.to_string().contains("line 2"),
            "{e}"
        );
        let e = parse("x,y,z\n0,0,1\n").unwrap_err();
        assert!(matches!(e, ReportError::Csv { line: 1, .. }), "{e}");
        let e = parse("x,y,sigma_d\n0,0,1\n").unwrap_err();
        assert!(matches!(e, ReportError::Data(_)), "a 1 x 1 grid: {e}");
    }
}
