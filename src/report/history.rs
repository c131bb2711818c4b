//! A run's `history.csv` (written by `flexflight run`): a header of channel names, then one
//! row per output time, first column `t`.

use std::path::Path;

use super::ReportError;

/// The columns of a history, by channel name.
#[derive(Clone, Debug, PartialEq)]
pub struct History {
    pub channels: Vec<String>,
    /// `columns[c][r]`: channel `c` at row `r`.
    pub columns: Vec<Vec<f64>>,
}

impl History {
    /// The column of a channel, if present.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.channels
            .iter()
            .position(|c| c == name)
            .and_then(|k| self.columns.get(k))
            .map(Vec::as_slice)
    }

    /// The time column `t`.
    pub fn time(&self) -> &[f64] {
        self.column("t").unwrap_or(&[])
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }

    /// A channel at time `t`, linearly interpolated between the rows around it (clamped to
    /// the first and last rows).
    pub fn interpolate(&self, name: &str, t: f64) -> Option<f64> {
        let ts = self.time();
        let v = self.column(name)?;
        if ts.is_empty() {
            return None;
        }
        let k = ts.partition_point(|x| *x <= t);
        if k == 0 {
            return v.first().copied();
        }
        if k >= ts.len() {
            return v.last().copied();
        }
        let (t0, t1) = (ts[k - 1], ts[k]);
        let w = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
        Some(v[k - 1] + w * (v[k] - v[k - 1]))
    }
}

/// Parse `history.csv` text; `path` is for messages (lines 1-based, header line 1).
///
/// Every row must have one number per channel; the first column must be `t` and
/// non-decreasing.
pub fn parse_history(text: &str, path: &Path) -> Result<History, ReportError> {
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
        .map_err(|e| err(1, format!("cannot read the header: {e}")))?;
    let channels: Vec<String> = header.iter().map(str::to_string).collect();
    if channels.first().map(String::as_str) != Some("t") {
        return Err(err(
            1,
            format!(
                "the first column must be `t`, found `{}`",
                channels.first().map_or("", String::as_str)
            ),
        ));
    }
    let mut columns = vec![Vec::new(); channels.len()];
    let mut last_t = f64::NEG_INFINITY;
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            err(line, format!("{e}"))
        })?;
        let line = record.position().map_or(0, |p| p.line());
        for (c, field) in record.iter().enumerate() {
            let v: f64 = field.parse().map_err(|_| {
                err(
                    line,
                    format!("`{field}` is not a number (column `{}`)", channels[c]),
                )
            })?;
            if c == 0 {
                if v.is_nan() || v < last_t {
                    return Err(err(line, format!("time {v} goes backwards")));
                }
                last_t = v;
            }
            columns[c].push(v);
        }
    }
    if columns[0].is_empty() {
        return Err(err(1, "the history has no rows".into()));
    }
    Ok(History { channels, columns })
}

/// Read `history.csv` (see [`parse_history`]).
pub fn read_history(path: &Path) -> Result<History, ReportError> {
    parse_history(&super::read_text(path)?, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(t: &str) -> Result<History, ReportError> {
        parse_history(t, Path::new("history.csv"))
    }

    #[test]
    fn columns_and_interpolation() {
        let h = parse("t,alpha,eta_a\n0,1,0\n0.5,2,1e-3\n1,4,-2e-3\n").unwrap();
        assert_eq!(h.rows(), 3);
        assert_eq!(h.column("alpha"), Some(&[1.0, 2.0, 4.0][..]));
        assert_eq!(h.interpolate("alpha", 0.75), Some(3.0));
        assert_eq!(h.interpolate("alpha", -1.0), Some(1.0));
        assert_eq!(h.interpolate("alpha", 9.0), Some(4.0));
        assert!(h.interpolate("beta", 0.1).is_none());
    }

    #[test]
    fn malformed_rows_give_their_line() {
        let e = parse("t,alpha\n0,1\n0.1,x\n").unwrap_err();
        assert!(e.to_string().starts_with("history.csv:3:"), "{e}");
        let e = parse("t,alpha\n0,1\n0.1,2\n0.2\n").unwrap_err();
        assert!(matches!(e, ReportError::Csv { line: 4, .. }), "{e}");
        let e = parse("t,alpha\n0,1\n-1,2\n").unwrap_err();
        assert!(matches!(e, ReportError::Csv { line: 3, .. }), "{e}");
        let e = parse("alpha,t\n0,1\n").unwrap_err();
        assert!(matches!(e, ReportError::Csv { line: 1, .. }), "{e}");
        let e = parse("t,alpha\n").unwrap_err();
        assert!(matches!(e, ReportError::Csv { line: 1, .. }), "{e}");
    }
}
