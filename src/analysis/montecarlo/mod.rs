//! Monte Carlo dispersion (issue 35), the pure part: drawing each sample's inputs from a
//! checked [`Dispersion`], the per-sample row of `samples.csv`, and the statistics of a
//! finished table ([`stats`]). Running the samples (threads, cache, files) is [`runner`].
//!
//! ## Drawing a sample
//!
//! Sample `i` draws one uniform `u_j = stream::uniform(seed, i, j)` per entry `j` of the
//! `vary` block (in the order written). Without correlations the entry's value is its
//! inverse CDF at `u_j`:
//!
//! - normal: `mean + sd Φ⁻¹(u)`;
//! - uniform: `min + (max - min) u`;
//! - truncated normal on `[a, b]`: `mean + sd Φ⁻¹(Φ(α) + u (Φ(β) - Φ(α)))` with
//!   `α = (a - mean)/sd`, `β = (b - mean)/sd` (the inverse-CDF method for a truncated
//!   distribution, e.g. Devroye, "Non-Uniform Random Variate Generation", 1986, §II.2.2);
//! - triangular on `[a, b]` with mode `c`: `a + sqrt(u (b - a)(c - a))` for
//!   `u < (c - a)/(b - a)`, else `b - sqrt((1 - u)(b - a)(b - c))`.
//!
//! Correlations use a Gaussian copula: for the entries named in a correlation, `z = Φ⁻¹(u)`,
//! `z' = L z` with `L` the Cholesky factor of the correlation matrix (computed at check),
//! then a normal entry takes `mean + sd z'_j` (so two normal entries have exactly the
//! correlation written) and any other takes its inverse CDF at `Φ(z'_j)` (the correlation
//! written is then that of the normal scores, a rank correlation of
//! `(6/π) asin(ρ/2)`; Kruskal 1958). Entries in no correlation keep `u_j` itself, so adding
//! a correlation between two entries changes no other entry's draws.
//!
//! Sample `i`'s id is `sample_` and `i` padded to at least 4 digits, so ids sort like
//! indices; shards take the samples with `i % N == I` (as sweeps, `analysis::sweep::Shard`).

pub mod stats;
pub mod stream;

use crate::check::ir::{Dispersion, DispersionLaw};

use stream::{normal_cdf, normal_quantile, uniform};

/// The value of `d` at the probability `u` in (0, 1) (its inverse CDF; module doc).
pub fn inverse_cdf(d: &DispersionLaw, u: f64) -> f64 {
    match *d {
        DispersionLaw::Normal { mean, sd } => mean + sd * normal_quantile(u),
        DispersionLaw::Uniform { min, max } => min + (max - min) * u,
        DispersionLaw::TruncatedNormal { mean, sd, min, max } => {
            let (pa, pb) = (normal_cdf((min - mean) / sd), normal_cdf((max - mean) / sd));
            (mean + sd * normal_quantile(pa + u * (pb - pa))).clamp(min, max)
        }
        DispersionLaw::Triangular { min, mode, max } => {
            let w = max - min;
            if u * w < mode - min {
                min + (u * w * (mode - min)).sqrt()
            } else {
                max - ((1.0 - u) * w * (max - mode)).sqrt()
            }
        }
    }
}

/// The drawn inputs of sample `index`, one per entry, in the entries' units (module doc).
pub fn draw(d: &Dispersion, index: u64) -> Vec<f64> {
    let n = d.entries.len();
    let u: Vec<f64> = (0..n as u64).map(|j| uniform(d.seed, index, j)).collect();
    let mut correlated = vec![false; n];
    for c in &d.correlations {
        correlated[c.a] = true;
        correlated[c.b] = true;
    }
    let z: Vec<f64> = u.iter().map(|&p| normal_quantile(p)).collect();
    d.entries
        .iter()
        .enumerate()
        .map(|(j, e)| {
            if !correlated[j] || d.cholesky.len() != n * n {
                return inverse_cdf(&e.distribution, u[j]);
            }
            let zj: f64 = (0..=j).map(|k| d.cholesky[j * n + k] * z[k]).sum();
            match e.distribution {
                DispersionLaw::Normal { mean, sd } => mean + sd * zj,
                ref other => inverse_cdf(other, normal_cdf(zj)),
            }
        })
        .collect()
}

/// The `--set` overrides of drawn values: `PATH=VALUE UNIT`, the value in Rust's shortest
/// round-trip form (the override reads back the same number).
pub fn set_strings(d: &Dispersion, values: &[f64]) -> Vec<String> {
    d.entries
        .iter()
        .zip(values)
        .map(|(e, x)| {
            if e.unit.is_empty() {
                format!("{}={x}", e.path)
            } else {
                format!("{}={x} {}", e.path, e.unit)
            }
        })
        .collect()
}

/// The id of sample `index` of `count`: `sample_0007`.
pub fn sample_id(index: usize, count: usize) -> String {
    let width = count.saturating_sub(1).to_string().len().max(4);
    format!("sample_{index:0width$}")
}

/// The summary outputs of one sample, in the order of [`OUTPUT_COLUMNS`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SampleOutputs {
    pub stop_reason: String,
    /// `flutter`, `divergence`, `model_limit`, or empty when the flight stayed in its model.
    pub verdict: String,
    pub apogee_m: Option<f64>,
    pub t_apogee_s: Option<f64>,
    pub max_mach: Option<f64>,
    pub max_q_pa: Option<f64>,
    pub off_rail_speed_m_s: Option<f64>,
    pub min_static_margin_cal: Option<f64>,
    /// Landing point: north and east of the pad, m (the inertial x and y).
    pub landing_x_m: Option<f64>,
    pub landing_y_m: Option<f64>,
    pub flutter_margin_min: Option<f64>,
}

/// The columns after the index, the id and the drawn inputs.
pub const OUTPUT_COLUMNS: &[&str] = &[
    "status",
    "stop_reason",
    "verdict",
    "apogee_m",
    "t_apogee_s",
    "max_mach",
    "max_q_pa",
    "off_rail_speed_m_s",
    "min_static_margin_cal",
    "landing_x_m",
    "landing_y_m",
    "flutter_margin_min",
    "error",
];

impl SampleOutputs {
    /// Read from a run's `summary.json` (`flight`, `verdict`, `flutter_margin`).
    pub fn from_summary(s: &serde_json::Value) -> Self {
        let f = &s["flight"];
        let num = |v: &serde_json::Value| v.as_f64();
        SampleOutputs {
            stop_reason: s["stop_reason"].as_str().unwrap_or_default().to_string(),
            verdict: s["verdict"]["kind"]
                .as_str()
                .unwrap_or_default()
                .to_string(),
            apogee_m: num(&f["apogee"]["height"]),
            t_apogee_s: num(&f["apogee"]["t"]),
            max_mach: num(&f["max_mach"]["value"]),
            max_q_pa: num(&f["max_dynamic_pressure"]["value"]),
            off_rail_speed_m_s: num(&f["off_rail_speed"]),
            min_static_margin_cal: num(&f["static_margin_calibres"]["min"]["value"]),
            landing_x_m: num(&f["landing"]["position"][0]),
            landing_y_m: num(&f["landing"]["position"][1]),
            // The minimum over every fin set where the vehicle has further sets.
            flutter_margin_min: num(&s["flutter_margin"]["minimum_over_sets"]["speed_margin"])
                .or_else(|| num(&s["flutter_margin"]["minimum"]["speed_margin"])),
        }
    }
}

/// Shortest round-trip text of `x` (empty for `None`).
fn cell(x: Option<f64>) -> String {
    x.map(|v| format!("{v}")).unwrap_or_default()
}

/// The header of `samples.csv`.
pub fn table_header(d: &Dispersion) -> Vec<String> {
    let mut h = vec!["index".to_string(), "sample_id".to_string()];
    h.extend(d.entries.iter().map(|e| {
        if e.unit.is_empty() {
            e.path.clone()
        } else {
            format!("{} [{}]", e.path, e.unit)
        }
    }));
    h.extend(OUTPUT_COLUMNS.iter().map(|s| s.to_string()));
    h
}

/// A flown sample's status: `incomplete` when its integration failed before the flight
/// reached a stop of its scenario ([`crate::run::RunStop::is_incomplete`]: its outputs are a
/// flight cut short, kept in the table and out of the statistics), else `ok`. A sample that
/// could not be flown at all is `failed`.
pub fn sample_status(o: &SampleOutputs) -> &'static str {
    if crate::run::RunStop::is_incomplete_code(&o.stop_reason) {
        "incomplete"
    } else {
        "ok"
    }
}

/// One row of `samples.csv`.
pub fn table_row(
    index: usize,
    id: &str,
    inputs: &[f64],
    r: &Result<SampleOutputs, String>,
) -> Vec<String> {
    let mut row = vec![index.to_string(), id.to_string()];
    row.extend(inputs.iter().map(|x| format!("{x}")));
    match r {
        Ok(o) => row.extend([
            sample_status(o).to_string(),
            o.stop_reason.clone(),
            o.verdict.clone(),
            cell(o.apogee_m),
            cell(o.t_apogee_s),
            cell(o.max_mach),
            cell(o.max_q_pa),
            cell(o.off_rail_speed_m_s),
            cell(o.min_static_margin_cal),
            cell(o.landing_x_m),
            cell(o.landing_y_m),
            cell(o.flutter_margin_min),
            if sample_status(o) == "incomplete" {
                format!(
                    "the integration failed ({}): a flight cut short",
                    o.stop_reason
                )
            } else {
                String::new()
            },
        ]),
        Err(e) => {
            row.push("failed".to_string());
            row.extend(std::iter::repeat_n(String::new(), OUTPUT_COLUMNS.len() - 2));
            row.push(e.replace(['\n', '\r'], " "));
        }
    }
    row
}

/// `samples.csv` text from a header and rows.
pub fn table_csv(header: &[String], rows: &[Vec<String>]) -> Result<String, csv::Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(header)?;
    for r in rows {
        w.write_record(r)?;
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The inverse CDFs map the median and the bounds where they should.
    #[test]
    fn inverse_cdfs_hit_their_quantiles() {
        let n = DispersionLaw::Normal { mean: 2.0, sd: 0.1 };
        assert_eq!(inverse_cdf(&n, 0.5), 2.0);
        assert!((inverse_cdf(&n, normal_cdf(1.0)) - 2.1).abs() < 1e-12);
        let t = DispersionLaw::Triangular {
            min: 1.0,
            mode: 2.0,
            max: 4.0,
        };
        // F(c) = 1/3: the mode.
        assert!((inverse_cdf(&t, 1.0 / 3.0) - 2.0).abs() < 1e-12);
        assert!(inverse_cdf(&t, 1e-12) > 1.0 && inverse_cdf(&t, 1.0 - 1e-12) < 4.0);
        let tn = DispersionLaw::TruncatedNormal {
            mean: 0.0,
            sd: 1.0,
            min: -0.5,
            max: 2.0,
        };
        for k in 1..100 {
            let x = inverse_cdf(&tn, k as f64 / 100.0);
            assert!((-0.5..=2.0).contains(&x));
        }
        // Its CDF at x is (Φ(x) - Φ(a)) / (Φ(b) - Φ(a)): invert at u = 0.3.
        let x = inverse_cdf(&tn, 0.3);
        let f = (normal_cdf(x) - normal_cdf(-0.5)) / (normal_cdf(2.0) - normal_cdf(-0.5));
        assert!((f - 0.3).abs() < 1e-12, "{f}");
    }
}
