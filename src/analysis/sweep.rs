//! Variant sweeps, the pure part: expanding a checked [`Sweep`] into numbered cases, shards
//! of a case list, the row every case contributes to `sweep.csv`, and merging shard tables.
//! Running the cases (files, threads, progress) is `cli::sweep`.
//!
//! Case numbering is the contract that makes sharding, resuming and merging work: case `k`
//! of a grid is the row-major index over the axes in declaration order (the last axis varies
//! fastest); of a zip, the position along the axes. Its id is `case_` followed by `k` padded
//! to the width of the largest index, so ids sort like indices.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::check::ir::{Combine, Sweep};

/// One case of a sweep.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepCase {
    /// Position in the full (unsharded) case list.
    pub index: usize,
    /// `case_0007`: the directory name under `DIR/cases/`.
    pub id: String,
    /// `(path, value)` overrides, one per axis, values as VDL text.
    pub overrides: Vec<(String, String)>,
}

impl SweepCase {
    /// The overrides in the `PATH=VALUE` form of `--set`.
    pub fn set_strings(&self) -> Vec<String> {
        self.overrides
            .iter()
            .map(|(p, v)| format!("{p}={v}"))
            .collect()
    }
}

/// Every case of a sweep, in index order.
pub fn expand(sweep: &Sweep) -> Vec<SweepCase> {
    let n = sweep.case_count();
    let width = n.saturating_sub(1).to_string().len().max(4);
    (0..n)
        .map(|index| {
            let picks: Vec<usize> = match sweep.combine {
                Combine::Zip => vec![index; sweep.axes.len()],
                Combine::Grid => {
                    let mut rest = index;
                    let mut picks = vec![0; sweep.axes.len()];
                    for (k, axis) in sweep.axes.iter().enumerate().rev() {
                        let len = axis.values.len().max(1);
                        picks[k] = rest % len;
                        rest /= len;
                    }
                    picks
                }
            };
            SweepCase {
                index,
                id: format!("case_{index:0width$}"),
                overrides: sweep
                    .axes
                    .iter()
                    .zip(&picks)
                    .map(|(a, &k)| (a.path.clone(), a.values[k].clone()))
                    .collect(),
            }
        })
        .collect()
}

/// A shard `I/N` of a case list: the cases whose index is `I` modulo `N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

/// Why a shard specification was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShardError {
    #[error("`{0}` is not a shard: write I/N with 0 <= I < N, or `env`")]
    Syntax(String),
    #[error("`--shard env` needs {0} in the environment (set by a Slurm job array)")]
    MissingEnv(&'static str),
    #[error("{name}=`{value}` is not a non-negative integer")]
    BadEnv { name: &'static str, value: String },
    #[error("shard index {index} is not below the shard count {count}")]
    OutOfRange { index: usize, count: usize },
}

/// Environment variable holding the shard index under `--shard env`.
pub const SHARD_INDEX_ENV: &str = "SLURM_ARRAY_TASK_ID";
/// Environment variable holding the shard count under `--shard env`.
pub const SHARD_COUNT_ENV: &str = "SLURM_ARRAY_TASK_COUNT";

impl Shard {
    /// The whole sweep.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parse `I/N`, or `env` to read [`SHARD_INDEX_ENV`] and [`SHARD_COUNT_ENV`] through
    /// `env` (pass `|k| std::env::var(k).ok()`). A Slurm array `--array=0-(N-1)` gives
    /// exactly these: task ids 0..N and the task count N.
    pub fn parse(text: &str, env: impl Fn(&str) -> Option<String>) -> Result<Shard, ShardError> {
        let (index, count) = if text.trim() == "env" {
            let read = |name: &'static str| {
                let v = env(name).ok_or(ShardError::MissingEnv(name))?;
                v.trim().parse::<usize>().map_err(|_| ShardError::BadEnv {
                    name,
                    value: v.clone(),
                })
            };
            (read(SHARD_INDEX_ENV)?, read(SHARD_COUNT_ENV)?)
        } else {
            let bad = || ShardError::Syntax(text.to_string());
            let (i, n) = text.split_once('/').ok_or_else(bad)?;
            (
                i.trim().parse().map_err(|_| bad())?,
                n.trim().parse().map_err(|_| bad())?,
            )
        };
        if count == 0 || index >= count {
            return Err(ShardError::OutOfRange { index, count });
        }
        Ok(Shard { index, count })
    }

    /// Does this shard run case `index`?
    pub fn takes(&self, index: usize) -> bool {
        index % self.count == self.index
    }
}

/// The fixed columns of `sweep.csv` before the axis columns.
pub const LEADING_COLUMNS: &[&str] = &["index", "case_id"];
/// The fixed columns of `sweep.csv` after the axis columns.
pub const TRAILING_COLUMNS: &[&str] = &[
    "status",
    "stop_reason",
    "t_end",
    "steps",
    "fit_stimulus",
    "fit_channel",
    "sigma_d",
    "omega_d",
    "frequency_hz",
    "fit_r_squared",
    "stability_class",
    "error",
];

/// The header of `sweep.csv`: index, case id, one column per axis path, then the results.
pub fn table_header(sweep: &Sweep) -> Vec<String> {
    LEADING_COLUMNS
        .iter()
        .map(|s| s.to_string())
        .chain(sweep.axes.iter().map(|a| a.path.clone()))
        .chain(TRAILING_COLUMNS.iter().map(|s| s.to_string()))
        .collect()
}

/// What a case produced, as one row of `sweep.csv` (all text, floats in Rust's shortest
/// round-trip form, so equal results give equal bytes).
pub fn case_row(case: &SweepCase, outcome: &Result<serde_json::Value, String>) -> Vec<String> {
    let mut row = vec![case.index.to_string(), case.id.clone()];
    row.extend(case.overrides.iter().map(|(_, v)| v.clone()));
    let text = |v: Option<&serde_json::Value>| match v {
        None | Some(serde_json::Value::Null) => String::new(),
        Some(serde_json::Value::String(s)) => s.clone(),
        Some(other) => other.to_string(),
    };
    match outcome {
        Ok(summary) if summary.get("stability").is_some() => {
            // An eigen-analysis case (planar or linearised 3-D): its least stable root.
            let st = summary.get("stability");
            let g = |k: &str| text(st.and_then(|x| x.get(k)));
            let omega = st
                .and_then(|x| x.get("omega_d"))
                .and_then(serde_json::Value::as_f64);
            row.extend([
                "ok".to_string(),
                String::new(),
                String::new(),
                String::new(),
                String::new(),
                text(summary.get("analysis")),
                g("sigma_d"),
                g("omega_d"),
                omega.map_or(String::new(), |w| {
                    (w / (2.0 * std::f64::consts::PI)).to_string()
                }),
                String::new(),
                g("class"),
                String::new(),
            ]);
        }
        Ok(summary) => {
            let fit = dominant_fit(summary);
            let f = |k: &str| text(fit.and_then(|x| x.get("fit")).and_then(|x| x.get(k)));
            row.extend([
                "ok".to_string(),
                text(summary.get("stop_reason")),
                text(summary.get("t_end")),
                text(summary.get("accepted_steps")),
                text(fit.and_then(|x| x.get("stimulus"))),
                text(fit.and_then(|x| x.get("channel"))),
                f("sigma_d"),
                f("omega_d"),
                f("frequency_hz"),
                f("r_squared"),
                String::new(),
                String::new(),
            ]);
        }
        Err(e) => {
            row.push("failed".into());
            row.extend(std::iter::repeat_n(
                String::new(),
                TRAILING_COLUMNS.len() - 2,
            ));
            // One line: the table is read by spreadsheets and shell tools.
            row.push(e.split_whitespace().collect::<Vec<_>>().join(" "));
        }
    }
    row
}

/// The fit a sweep row reports: the first response window (in time order) whose fit of the
/// first default channel succeeded, else the first successful fit of any channel.
pub fn dominant_fit(summary: &serde_json::Value) -> Option<&serde_json::Value> {
    let fits = summary.get("identification")?.as_array()?;
    let ok = |x: &&serde_json::Value| x.get("fit").is_some();
    let first_channel = super::gust_response::DEFAULT_CHANNELS.first().copied();
    fits.iter()
        .filter(ok)
        .find(|x| x.get("channel").and_then(|c| c.as_str()) == first_channel)
        .or_else(|| fits.iter().find(ok))
}

/// `DIR/sweep.json`: what a table belongs to, so shards can be checked before merging.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepManifest {
    pub sweep: String,
    pub scenario: String,
    pub case_count: usize,
    pub shard: Shard,
    pub columns: Vec<String>,
}

/// One shard's table, as read back.
#[derive(Clone, Debug, PartialEq)]
pub struct ShardTable {
    /// Where it came from (for messages).
    pub source: String,
    pub manifest: SweepManifest,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

/// Why shard tables cannot be merged.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MergeError {
    #[error("nothing to merge")]
    Empty,
    #[error("{table} belongs to {found}, the first table to {expected}")]
    Mismatch {
        table: String,
        expected: String,
        found: String,
    },
    #[error("{table}: row {row} has no valid case index")]
    BadIndex { table: String, row: usize },
    #[error("case {index} appears twice: in {first} and in {second}")]
    Duplicate {
        index: usize,
        first: String,
        second: String,
    },
}

/// The merged table and the cases no shard had.
#[derive(Clone, Debug, PartialEq)]
pub struct MergedTable {
    pub manifest: SweepManifest,
    pub rows: Vec<Vec<String>>,
    pub missing: Vec<usize>,
}

/// Join shard tables: same sweep, case count and columns; rows ordered by case index; a
/// case in two tables is an error, a case in none is listed in `missing`.
pub fn merge(tables: &[ShardTable]) -> Result<MergedTable, MergeError> {
    let first = tables.first().ok_or(MergeError::Empty)?;
    let describe = |t: &ShardTable| {
        format!(
            "sweep `{}` ({} cases, columns {})",
            t.manifest.sweep,
            t.manifest.case_count,
            t.header.join(",")
        )
    };
    let mut by_index: BTreeMap<usize, (usize, &Vec<String>)> = BTreeMap::new();
    for (k, t) in tables.iter().enumerate() {
        if t.manifest.sweep != first.manifest.sweep
            || t.manifest.case_count != first.manifest.case_count
            || t.header != first.header
        {
            return Err(MergeError::Mismatch {
                table: t.source.clone(),
                expected: describe(first),
                found: describe(t),
            });
        }
        for (r, row) in t.rows.iter().enumerate() {
            let index = row
                .first()
                .and_then(|s| s.parse::<usize>().ok())
                .filter(|&i| i < t.manifest.case_count)
                .ok_or_else(|| MergeError::BadIndex {
                    table: t.source.clone(),
                    row: r + 1,
                })?;
            if let Some((j, _)) = by_index.insert(index, (k, row)) {
                return Err(MergeError::Duplicate {
                    index,
                    first: tables[j].source.clone(),
                    second: t.source.clone(),
                });
            }
        }
    }
    let missing = (0..first.manifest.case_count)
        .filter(|i| !by_index.contains_key(i))
        .collect();
    Ok(MergedTable {
        manifest: SweepManifest {
            shard: Shard::ALL,
            ..first.manifest.clone()
        },
        rows: by_index.into_values().map(|(_, r)| r.clone()).collect(),
        missing,
    })
}

/// `sweep.csv` text of a header and rows.
pub fn table_csv(header: &[String], rows: &[Vec<String>]) -> Result<String, csv::Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(header)?;
    for r in rows {
        w.write_record(r)?;
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// Parse `sweep.csv` text into its header and rows.
pub fn parse_table(text: &str) -> Result<(Vec<String>, Vec<Vec<String>>), csv::Error> {
    let mut r = csv::Reader::from_reader(text.as_bytes());
    let header = r.headers()?.iter().map(str::to_string).collect();
    let mut rows = Vec::new();
    for rec in r.records() {
        rows.push(rec?.iter().map(str::to_string).collect());
    }
    Ok((header, rows))
}

/// Compress a sorted index list into `a-b` ranges for messages.
pub fn ranges(indices: &[usize]) -> String {
    let mut parts = Vec::new();
    let mut k = 0;
    while k < indices.len() {
        let mut j = k;
        while j + 1 < indices.len() && indices[j + 1] == indices[j] + 1 {
            j += 1;
        }
        parts.push(if j == k {
            indices[k].to_string()
        } else {
            format!("{}-{}", indices[k], indices[j])
        });
        k = j + 1;
    }
    parts.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::ir::{SweepAnalysis, SweepAxis};
    use crate::syntax::{Span, Spanned};

    fn sweep(combine: Combine, axes: &[(&str, &[&str])]) -> Sweep {
        let span = Span::default();
        Sweep {
            name: Spanned::new("s".into(), span),
            span,
            scenario: 0,
            analysis: Spanned::new(SweepAnalysis::Run, span),
            frozen_gravity: false,
            combine,
            axes: axes
                .iter()
                .map(|(p, v)| SweepAxis {
                    path: p.to_string(),
                    span,
                    values: v.iter().map(|s| s.to_string()).collect(),
                    si_values: vec![None; v.len()],
                })
                .collect(),
        }
    }

    #[test]
    fn grid_is_row_major_with_the_last_axis_fastest() {
        let s = sweep(
            Combine::Grid,
            &[("a", &["1", "2"]), ("b", &["x", "y", "z"])],
        );
        let cases = expand(&s);
        assert_eq!(cases.len(), 6);
        assert_eq!(cases[4].id, "case_0004");
        assert_eq!(
            cases[4].overrides,
            vec![("a".into(), "2".into()), ("b".into(), "y".into())]
        );
        assert_eq!(cases[1].set_strings(), vec!["a=1", "b=y"]);
        let z = expand(&sweep(
            Combine::Zip,
            &[("a", &["1", "2"]), ("b", &["x", "y"])],
        ));
        assert_eq!(z[1].overrides[1].1, "y");
        assert_eq!(z.len(), 2);
    }

    #[test]
    fn shards_partition_the_cases_and_read_slurm_variables() {
        let env = |k: &str| match k {
            "SLURM_ARRAY_TASK_ID" => Some("2".to_string()),
            "SLURM_ARRAY_TASK_COUNT" => Some("3".to_string()),
            _ => None,
        };
        assert_eq!(Shard::parse("env", env), Ok(Shard { index: 2, count: 3 }));
        assert_eq!(
            Shard::parse(" 1/4", |_| None),
            Ok(Shard { index: 1, count: 4 })
        );
        assert!(matches!(
            Shard::parse("4/4", |_| None),
            Err(ShardError::OutOfRange { .. })
        ));
        assert!(matches!(
            Shard::parse("1-4", |_| None),
            Err(ShardError::Syntax(_))
        ));
        assert_eq!(
            Shard::parse("env", |_| None),
            Err(ShardError::MissingEnv(SHARD_INDEX_ENV))
        );
        let shards = [
            Shard { index: 0, count: 3 },
            Shard { index: 1, count: 3 },
            Shard { index: 2, count: 3 },
        ];
        for i in 0..20 {
            assert_eq!(shards.iter().filter(|s| s.takes(i)).count(), 1);
        }
    }

    fn table(source: &str, shard: Shard, rows: &[usize]) -> ShardTable {
        ShardTable {
            source: source.into(),
            manifest: SweepManifest {
                sweep: "s".into(),
                scenario: "sc".into(),
                case_count: 5,
                shard,
                columns: vec!["index".into(), "v".into()],
            },
            header: vec!["index".into(), "v".into()],
            rows: rows
                .iter()
                .map(|i| vec![i.to_string(), format!("r{i}")])
                .collect(),
        }
    }

    #[test]
    fn merge_orders_by_index_and_detects_duplicates_and_gaps() {
        let a = table("a", Shard { index: 0, count: 2 }, &[0, 2, 4]);
        let b = table("b", Shard { index: 1, count: 2 }, &[3, 1]);
        let m = merge(&[b.clone(), a.clone()]).unwrap();
        assert_eq!(
            m.rows.iter().map(|r| r[1].as_str()).collect::<Vec<_>>(),
            ["r0", "r1", "r2", "r3", "r4"]
        );
        assert!(m.missing.is_empty());
        assert_eq!(m.manifest.shard, Shard::ALL);
        let gap = merge(std::slice::from_ref(&a)).unwrap();
        assert_eq!(gap.missing, vec![1, 3]);
        assert!(matches!(
            merge(&[a.clone(), a.clone()]),
            Err(MergeError::Duplicate { index: 0, .. })
        ));
        let mut other = b.clone();
        other.manifest.case_count = 6;
        assert!(matches!(
            merge(&[a, other]),
            Err(MergeError::Mismatch { .. })
        ));
        assert_eq!(ranges(&[1, 2, 3, 7, 9, 10]), "1-3, 7, 9-10");
    }

    #[test]
    fn a_failed_case_row_keeps_its_error_on_one_line() {
        let case = SweepCase {
            index: 3,
            id: "case_0003".into(),
            overrides: vec![("a".into(), "1 mm".into())],
        };
        let row = case_row(&case, &Err("plan::invalid: bad\n  here".into()));
        assert_eq!(row.len(), 3 + TRAILING_COLUMNS.len());
        assert_eq!(row[3], "failed");
        assert_eq!(row.last().unwrap(), "plan::invalid: bad here");
        let text = table_csv(
            &["index".into(), "case_id".into()],
            &[vec!["3".into(), "a,b".into()]],
        )
        .unwrap();
        assert_eq!(
            parse_table(&text).unwrap().1,
            vec![vec!["3".to_string(), "a,b".to_string()]]
        );
    }
}
