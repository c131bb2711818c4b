//! Motor thrust curves T(t) (thesis 5.2: the thrust magnitude is read from an input array of
//! time and thrust and interpolated during the run).
//!
//! Two formats:
//! - RASP `.eng` (<https://www.thrustcurve.org/info/raspformat.html>): `;` comment lines, a
//!   header `name diameter_mm length_mm delays propellant_kg total_kg maker`, then one
//!   `time_s thrust_N` pair per line. One motor per file.
//! - CSV: a header line `time_s,thrust_N`, then `time,thrust` rows (`#` comments).
//!
//! Conventions outside the data points, following OpenRocket's motor loaders
//! (`AbstractMotorLoader.finalizeThrustCurve`, used by `RASPMotorLoader`): if the first point
//! is after t = 0, a point (0, 0) is prepended, so thrust ramps linearly from zero at
//! ignition to the first tabulated value (RASP files conventionally omit the ignition point;
//! the original RASP curves "assumed the (0,0) point"). After the last point the thrust is
//! zero; a last point with non-zero thrust therefore ends in a step to zero (OpenRocket
//! appends a zero-thrust point at the same time). Before ignition (t < 0) the thrust is zero.

use std::path::{Path, PathBuf};

/// Why a thrust curve could not be read. Lines are 1-based.
#[derive(Debug, thiserror::Error)]
pub enum ThrustCurveError {
    #[error("{}: cannot read the thrust curve: {source}", file.display())]
    Io {
        file: PathBuf,
        source: std::io::Error,
    },
    #[error("{}:{line}: missing {what}", file.display())]
    MissingField {
        file: PathBuf,
        line: usize,
        what: &'static str,
    },
    #[error("{}:{line}: unexpected extra field `{text}`", file.display())]
    ExtraField {
        file: PathBuf,
        line: usize,
        text: String,
    },
    #[error("{}:{line}: {what} `{text}` is not a finite number", file.display())]
    NotFinite {
        file: PathBuf,
        line: usize,
        what: &'static str,
        text: String,
    },
    #[error("{}:{line}: negative thrust {thrust_n} N", file.display())]
    NegativeThrust {
        file: PathBuf,
        line: usize,
        thrust_n: f64,
    },
    #[error("{}:{line}: negative time {time_s} s", file.display())]
    NegativeTime {
        file: PathBuf,
        line: usize,
        time_s: f64,
    },
    #[error(
        "{}:{line}: time {time_s} s is not after the previous point's {previous_s} s",
        file.display()
    )]
    TimeNotIncreasing {
        file: PathBuf,
        line: usize,
        time_s: f64,
        previous_s: f64,
    },
    #[error("{}:{line}: {what} must be positive, found {value}", file.display())]
    NonPositive {
        file: PathBuf,
        line: usize,
        what: &'static str,
        value: f64,
    },
    #[error(
        "{}:{line}: propellant mass {propellant_kg} kg exceeds the total mass {total_kg} kg",
        file.display()
    )]
    PropellantExceedsTotal {
        file: PathBuf,
        line: usize,
        propellant_kg: f64,
        total_kg: f64,
    },
    #[error("{}:{line}: expected the header `time_s,thrust_N`, found `{found}`", file.display())]
    BadHeader {
        file: PathBuf,
        line: usize,
        found: String,
    },
    #[error("{}: the thrust curve has no data points", file.display())]
    EmptyCurve { file: PathBuf },
}

/// A motor's thrust as a function of time since ignition, piecewise linear between points.
#[derive(Clone, Debug, PartialEq)]
pub struct ThrustCurve {
    /// Strictly increasing times, s; starts at 0 (see the module doc).
    times: Vec<f64>,
    /// Thrust at `times`, N, non-negative.
    thrust: Vec<f64>,
    /// Motor designation (RASP header) or the file stem (CSV).
    pub name: String,
    /// Propellant mass, kg (RASP header; `None` for CSV curves).
    pub propellant_mass: Option<f64>,
    /// Loaded motor mass, kg (RASP header; `None` for CSV curves).
    pub total_mass: Option<f64>,
    /// Motor diameter, m (RASP header).
    pub diameter: Option<f64>,
    /// Motor length, m (RASP header).
    pub length: Option<f64>,
    /// Manufacturer code (RASP header).
    pub maker: Option<String>,
}

impl ThrustCurve {
    /// Reads a `.eng` file (RASP) or, for any other extension, a CSV file.
    pub fn read(path: &Path) -> Result<ThrustCurve, ThrustCurveError> {
        // A bundled curve (`motor { designation = ... }`) is named by a virtual path.
        if let Some(text) = super::catalogue::bundled_text(path) {
            return Self::parse_eng(text, path);
        }
        let text = std::fs::read_to_string(path).map_err(|source| ThrustCurveError::Io {
            file: path.to_path_buf(),
            source,
        })?;
        let is_eng = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("eng"));
        if is_eng {
            Self::parse_eng(&text, path)
        } else {
            Self::parse_csv(&text, path)
        }
    }

    /// Parses RASP `.eng` text; `file` names the source in errors.
    pub fn parse_eng(text: &str, file: &Path) -> Result<ThrustCurve, ThrustCurveError> {
        let err_file = || file.to_path_buf();
        let mut header: Option<RaspHeader> = None;
        let mut points = CurveBuilder::new(file);
        for (index, raw) in text.lines().enumerate() {
            let line = index + 1;
            let content = raw.trim();
            if content.is_empty() || content.starts_with(';') {
                continue;
            }
            let fields: Vec<&str> = content.split_whitespace().collect();
            if header.is_none() {
                header = Some(RaspHeader::parse(&fields, file, line)?);
                continue;
            }
            let time = field(&fields, 0, "time", file, line)?;
            let thrust = field(&fields, 1, "thrust", file, line)?;
            if let Some(extra) = fields.get(2) {
                return Err(ThrustCurveError::ExtraField {
                    file: err_file(),
                    line,
                    text: (*extra).to_string(),
                });
            }
            points.push(time, thrust, line)?;
        }
        let header = header.ok_or_else(|| ThrustCurveError::EmptyCurve { file: err_file() })?;
        let (times, thrust) = points.finish()?;
        Ok(ThrustCurve {
            times,
            thrust,
            name: header.name,
            propellant_mass: Some(header.propellant_kg),
            total_mass: Some(header.total_kg),
            diameter: Some(header.diameter_mm * 1e-3),
            length: Some(header.length_mm * 1e-3),
            maker: Some(header.maker),
        })
    }

    /// Parses CSV text (`time_s,thrust_N` header); `file` names the source in errors and its
    /// stem becomes the curve's name.
    pub fn parse_csv(text: &str, file: &Path) -> Result<ThrustCurve, ThrustCurveError> {
        let mut seen_header = false;
        let mut points = CurveBuilder::new(file);
        for (index, raw) in text.lines().enumerate() {
            let line = index + 1;
            let content = raw.trim();
            if content.is_empty() || content.starts_with('#') {
                continue;
            }
            let fields: Vec<&str> = content.split(',').map(str::trim).collect();
            if !seen_header {
                let ok = fields.len() == 2
                    && fields[0].eq_ignore_ascii_case("time_s")
                    && fields[1].eq_ignore_ascii_case("thrust_N");
                if !ok {
                    return Err(ThrustCurveError::BadHeader {
                        file: file.to_path_buf(),
                        line,
                        found: content.to_string(),
                    });
                }
                seen_header = true;
                continue;
            }
            let time = field(&fields, 0, "time", file, line)?;
            let thrust = field(&fields, 1, "thrust", file, line)?;
            if let Some(extra) = fields.get(2) {
                return Err(ThrustCurveError::ExtraField {
                    file: file.to_path_buf(),
                    line,
                    text: (*extra).to_string(),
                });
            }
            points.push(time, thrust, line)?;
        }
        let (times, thrust) = points.finish()?;
        let name = file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        Ok(ThrustCurve {
            times,
            thrust,
            name,
            propellant_mass: None,
            total_mass: None,
            diameter: None,
            length: None,
            maker: None,
        })
    }

    /// Builds a curve from points already in memory (same checks and end conventions as
    /// the readers; errors name `<memory>` and the 1-based point index as the line).
    pub fn from_points(name: &str, points: &[(f64, f64)]) -> Result<ThrustCurve, ThrustCurveError> {
        let file = Path::new("<memory>");
        let mut builder = CurveBuilder::new(file);
        for (i, &(t, f)) in points.iter().enumerate() {
            for (v, what) in [(t, "time"), (f, "thrust")] {
                if !v.is_finite() {
                    return Err(ThrustCurveError::NotFinite {
                        file: file.to_path_buf(),
                        line: i + 1,
                        what,
                        text: v.to_string(),
                    });
                }
            }
            builder.push(t, f, i + 1)?;
        }
        let (times, thrust) = builder.finish()?;
        Ok(ThrustCurve {
            times,
            thrust,
            name: name.to_string(),
            propellant_mass: None,
            total_mass: None,
            diameter: None,
            length: None,
            maker: None,
        })
    }

    /// Thrust at time `t` since ignition, N: linear interpolation between points, zero
    /// before ignition and after the last point (module doc). Never allocates.
    pub fn thrust_at(&self, t: f64) -> f64 {
        let n = self.times.len();
        let (Some(&first), Some(&last)) = (self.times.first(), self.times.last()) else {
            return 0.0;
        };
        // NaN fails both comparisons below and falls through to zero as well.
        if !(t >= first && t <= last) {
            return 0.0;
        }
        if n == 1 {
            return self.thrust[0];
        }
        // Segment i with times[i] <= t <= times[i + 1].
        let i = self.times.partition_point(|&x| x <= t).clamp(1, n - 1) - 1;
        let (t0, t1) = (self.times[i], self.times[i + 1]);
        let f = (t - t0) / (t1 - t0);
        self.thrust[i] + f * (self.thrust[i + 1] - self.thrust[i])
    }

    /// Total impulse I = integral of T dt, N s: exact for the piecewise-linear curve
    /// (trapezoidal sum over the points, including the implied (0, 0) ramp).
    pub fn total_impulse(&self) -> f64 {
        self.times
            .windows(2)
            .zip(self.thrust.windows(2))
            .map(|(t, f)| 0.5 * (f[0] + f[1]) * (t[1] - t[0]))
            .sum()
    }

    /// The curve's points in time, s: where the thrust is only continuous (a kink of the
    /// piecewise-linear curve) or jumps (the first and last points).
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// Burn time: the time of the last point, s (thrust is zero afterwards).
    pub fn burn_time(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// Average thrust over the burn, N.
    pub fn average_thrust(&self) -> f64 {
        let tb = self.burn_time();
        if tb > 0.0 {
            self.total_impulse() / tb
        } else {
            0.0
        }
    }

    /// The curve's points (time s, thrust N), after the (0, 0) convention was applied.
    pub fn points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.times.iter().copied().zip(self.thrust.iter().copied())
    }

    /// The curve of a motor whose total impulse is `impulse` times and whose burn time is
    /// `burn_time` times this one's, the shape kept: `F'(t) = (impulse / burn_time)
    /// F(t / burn_time)` (times stretched by `burn_time`, thrust scaled by `impulse /
    /// burn_time`, so `∫F' dt = impulse ∫F dt` exactly for the trapezoid rule of
    /// [`Self::total_impulse`]). The scatter of a motor lot, as RocketPy's stochastic
    /// motor varies `total_impulse` and `burn_out_time`. Both factors must be positive
    /// and finite (the checker's `motor_scale` range).
    pub fn scaled(&self, impulse: f64, burn_time: f64) -> ThrustCurve {
        let k = impulse / burn_time;
        ThrustCurve {
            times: self.times.iter().map(|t| t * burn_time).collect(),
            thrust: self.thrust.iter().map(|f| f * k).collect(),
            ..self.clone()
        }
    }
}

struct RaspHeader {
    name: String,
    diameter_mm: f64,
    length_mm: f64,
    propellant_kg: f64,
    total_kg: f64,
    maker: String,
}

impl RaspHeader {
    const FIELDS: [&'static str; 7] = [
        "motor name",
        "diameter (mm)",
        "length (mm)",
        "delays",
        "propellant mass (kg)",
        "total mass (kg)",
        "manufacturer",
    ];

    fn parse(fields: &[&str], file: &Path, line: usize) -> Result<RaspHeader, ThrustCurveError> {
        if fields.len() < 7 {
            return Err(ThrustCurveError::MissingField {
                file: file.to_path_buf(),
                line,
                what: Self::FIELDS[fields.len()],
            });
        }
        if let Some(extra) = fields.get(7) {
            return Err(ThrustCurveError::ExtraField {
                file: file.to_path_buf(),
                line,
                text: (*extra).to_string(),
            });
        }
        let mut numbers = [0.0; 4];
        for (k, index) in [1, 2, 4, 5].into_iter().enumerate() {
            let what = Self::FIELDS[index];
            numbers[k] = field(fields, index, what, file, line)?;
            if numbers[k] <= 0.0 {
                return Err(ThrustCurveError::NonPositive {
                    file: file.to_path_buf(),
                    line,
                    what,
                    value: numbers[k],
                });
            }
        }
        let [diameter_mm, length_mm, propellant_kg, total_kg] = numbers;
        if propellant_kg > total_kg {
            return Err(ThrustCurveError::PropellantExceedsTotal {
                file: file.to_path_buf(),
                line,
                propellant_kg,
                total_kg,
            });
        }
        Ok(RaspHeader {
            name: fields[0].to_string(),
            diameter_mm,
            length_mm,
            propellant_kg,
            total_kg,
            maker: fields[6].to_string(),
        })
    }
}

/// The `index`-th field as a finite number.
fn field(
    fields: &[&str],
    index: usize,
    what: &'static str,
    file: &Path,
    line: usize,
) -> Result<f64, ThrustCurveError> {
    let text = match fields.get(index) {
        Some(t) if !t.is_empty() => *t,
        _ => {
            return Err(ThrustCurveError::MissingField {
                file: file.to_path_buf(),
                line,
                what,
            });
        }
    };
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(ThrustCurveError::NotFinite {
            file: file.to_path_buf(),
            line,
            what,
            text: text.to_string(),
        }),
    }
}

/// Collects and checks points, then applies the end conventions of the module doc.
struct CurveBuilder<'a> {
    file: &'a Path,
    times: Vec<f64>,
    thrust: Vec<f64>,
}

impl<'a> CurveBuilder<'a> {
    fn new(file: &'a Path) -> Self {
        CurveBuilder {
            file,
            times: Vec::new(),
            thrust: Vec::new(),
        }
    }

    fn push(&mut self, time_s: f64, thrust_n: f64, line: usize) -> Result<(), ThrustCurveError> {
        let file = self.file.to_path_buf();
        if time_s < 0.0 {
            return Err(ThrustCurveError::NegativeTime { file, line, time_s });
        }
        if thrust_n < 0.0 {
            return Err(ThrustCurveError::NegativeThrust {
                file,
                line,
                thrust_n,
            });
        }
        if let Some(&previous_s) = self.times.last()
            && time_s <= previous_s
        {
            return Err(ThrustCurveError::TimeNotIncreasing {
                file,
                line,
                time_s,
                previous_s,
            });
        }
        self.times.push(time_s);
        self.thrust.push(thrust_n);
        Ok(())
    }

    fn finish(mut self) -> Result<(Vec<f64>, Vec<f64>), ThrustCurveError> {
        let Some(&first) = self.times.first() else {
            return Err(ThrustCurveError::EmptyCurve {
                file: self.file.to_path_buf(),
            });
        };
        if first > 0.0 {
            self.times.insert(0, 0.0);
            self.thrust.insert(0, 0.0);
        }
        Ok((self.times, self.thrust))
    }
}
