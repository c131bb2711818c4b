//! Atmosphere models (thesis 4.5.1).
//!
//! The thesis uses the 1976 standard atmosphere, approximated by closed forms below 20 km
//! (eqs. (4.5.1)-(4.5.8)) and by tables above. Here the full U.S. Standard Atmosphere 1976
//! (NOAA-S/T 76-1562, NASA-TM-X-74335; "USSA76" below) is implemented from -0.5 km to 86 km
//! geometric altitude, which contains the thesis' formulas as special cases:
//!
//! - (4.5.1)-(4.5.6) are the gradient-layer formulas of the first layer with
//!   theta = T/T_SL, delta = theta^(g0 M0 / (R* |L|)) = theta^5.256 and
//!   sigma = theta^(5.256 - 1) = theta^4.256 (USSA76 eqs. 23 and 33a);
//! - (4.5.7), read as delta = delta_c exp[-g (h - h_c)/(R T_c)] (see REFERENCE-NOTES), is the
//!   isothermal-layer formula (USSA76 eq. 33b);
//! - (4.5.8) sigma = delta/theta is the equation of state rho = p / (R T) (USSA76 eq. 42).
//!
//! A user-supplied profile ([`TableAtmosphere`]) replaces the "customized configuration"
//! the thesis mentions at the end of 4.5.1.
//!
//! Evaluating an atmosphere ([`Atmosphere::at`]) never allocates and never returns NaN: an
//! altitude outside the model's range is an [`AtmosphereError`].

use std::path::{Path, PathBuf};

/// Standard acceleration of gravity g0, m/s^2 (USSA76 Table 2).
pub const G0: f64 = 9.80665;
/// Universal gas constant R*, J/(kmol K) (USSA76 Table 2; the 1976 value, not CODATA).
pub const R_STAR: f64 = 8.31432e3;
/// Sea-level mean molecular weight M0, kg/kmol (USSA76 Table 2).
pub const M0: f64 = 28.9644;
/// Specific gas constant of air R = R*/M0 = 287.05287 J/(kg K).
pub const R_AIR: f64 = R_STAR / M0;
/// Effective Earth radius r0 for geopotential altitude, m (USSA76 Table 2).
pub const EARTH_RADIUS: f64 = 6_356_766.0;
/// Ratio of specific heats gamma (USSA76 eq. 50).
pub const GAMMA: f64 = 1.4;
/// Sutherland's constant beta, kg/(s m K^1/2) (USSA76 eq. 51).
pub const SUTHERLAND_BETA: f64 = 1.458e-6;
/// Sutherland's constant S, K (USSA76 eq. 51).
pub const SUTHERLAND_S: f64 = 110.4;

/// Lowest geometric altitude of [`Standard1976`], m.
pub const STANDARD_MIN_ALTITUDE: f64 = -500.0;
/// Highest geometric altitude of [`Standard1976`], m (top of the homosphere model).
pub const STANDARD_MAX_ALTITUDE: f64 = 86_000.0;

/// Base geopotential heights H_b of the seven layers and the top of the last, m' (USSA76
/// Table 4).
const LAYER_BASE_H: [f64; 8] = [
    0.0, 11_000.0, 20_000.0, 32_000.0, 47_000.0, 51_000.0, 71_000.0, 84_852.0,
];
/// Molecular-scale temperature gradients L_M,b of the seven layers, K/m' (USSA76 Table 4).
const LAYER_LAPSE: [f64; 7] = [-6.5e-3, 0.0, 1.0e-3, 2.8e-3, 0.0, -2.8e-3, -2.0e-3];
/// Sea-level temperature T0, K, and pressure P0, Pa (USSA76 Table 2).
const T0: f64 = 288.15;
const P0: f64 = 101_325.0;

/// Ratio M/M0 of the mean molecular weight from 80 to 86 km geometric altitude in 0.5 km
/// steps (USSA76 Table 8); below 80 km the ratio is 1. The kinetic temperature is
/// T = T_M (M/M0) (USSA76 eq. 22); the ratio is interpolated linearly between entries.
const MOLECULAR_WEIGHT_RATIO: [f64; 13] = [
    1.000000, 0.999996, 0.999989, 0.999971, 0.999941, 0.999909, 0.999870, 0.999829, 0.999786,
    0.999741, 0.999694, 0.999641, 0.999579,
];
const MOLECULAR_WEIGHT_RATIO_START: f64 = 80_000.0;
const MOLECULAR_WEIGHT_RATIO_STEP: f64 = 500.0;

/// Free-stream air properties at one altitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AtmosphereState {
    /// Kinetic temperature T, K.
    pub temperature: f64,
    /// Static pressure p, Pa.
    pub pressure: f64,
    /// Density rho, kg/m^3.
    pub density: f64,
    /// Speed of sound a, m/s.
    pub speed_of_sound: f64,
    /// Dynamic viscosity mu, Pa s.
    pub viscosity: f64,
}

/// Why an atmosphere could not be evaluated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AtmosphereError {
    #[error("altitude {altitude_m} m is outside the atmosphere model's range [{min_m}, {max_m}] m")]
    OutOfRange {
        altitude_m: f64,
        min_m: f64,
        max_m: f64,
    },
    #[error("altitude is not a finite number ({altitude_m})")]
    NotFinite { altitude_m: f64 },
}

/// An atmosphere: air properties as a function of geometric altitude above sea level.
pub trait Atmosphere {
    /// Air properties at `altitude_m` (geometric, m). Never allocates; an altitude outside
    /// the model's range is an error, never NaN.
    fn at(&self, altitude_m: f64) -> Result<AtmosphereState, AtmosphereError>;
}

/// The air of the last altitude [`Standard1976`] was evaluated at, for the force blocks of
/// one right-hand side: the body and the fin block both need the air at the body origin's
/// altitude, and [`Standard1976`] is a pure function of the altitude (it has no parameters:
/// [`Standard1976::new`] is its only constructor), so the second block reads the first
/// one's result, with its bits, instead of a second evaluation (two `powf` in the
/// troposphere). Keyed on the altitude's bits; an error is not kept.
#[derive(Clone, Copy, Debug, Default)]
pub struct AirMemo {
    last: Option<(u64, AtmosphereState)>,
}

impl AirMemo {
    /// `model.at(altitude_m)`, from the memo when the altitude is the last one's.
    pub fn at(
        &mut self,
        model: &Standard1976,
        altitude_m: f64,
    ) -> Result<AtmosphereState, AtmosphereError> {
        if let Some((bits, air)) = self.last
            && bits == altitude_m.to_bits()
        {
            return Ok(air);
        }
        let air = model.at(altitude_m)?;
        self.last = Some((altitude_m.to_bits(), air));
        Ok(air)
    }
}

/// Geopotential altitude H = r0 Z / (r0 + Z) of the geometric altitude Z, both in m
/// (USSA76 eq. 18).
pub fn geopotential_altitude(geometric_m: f64) -> f64 {
    EARTH_RADIUS * geometric_m / (EARTH_RADIUS + geometric_m)
}

/// Geometric altitude Z = r0 H / (r0 - H) of the geopotential altitude H, both in m
/// (inverse of USSA76 eq. 18).
pub fn geometric_altitude(geopotential_m: f64) -> f64 {
    EARTH_RADIUS * geopotential_m / (EARTH_RADIUS - geopotential_m)
}

/// Dynamic viscosity by Sutherland's law mu = beta T^(3/2) / (T + S) (USSA76 eq. 51).
pub fn sutherland_viscosity(temperature: f64) -> f64 {
    SUTHERLAND_BETA * temperature * temperature.sqrt() / (temperature + SUTHERLAND_S)
}

/// The U.S. Standard Atmosphere 1976 from -0.5 km to 86 km geometric altitude.
///
/// Seven layers in geopotential altitude H with linear molecular-scale temperature
/// T_M = T_M,b + L_M,b (H - H_b) (USSA76 eq. 23). Pressure in a layer with L_M,b != 0 is
/// p = p_b [T_M,b / T_M]^(g0 M0 / (R* L_M,b)) (USSA76 eq. 33a; eq. (4.5.3) of the thesis in
/// the first layer), and in an isothermal layer p = p_b exp[-g0 M0 (H - H_b) / (R* T_M,b)]
/// (USSA76 eq. 33b; thesis eq. (4.5.7)). Density rho = p M0 / (R* T_M) (USSA76 eq. 42;
/// thesis eq. (4.5.8)), speed of sound a = sqrt(gamma R* T_M / M0) (USSA76 eq. 50, with
/// T/M = T_M/M0), viscosity by Sutherland's law of the kinetic temperature
/// T = T_M (M/M0) (USSA76 eqs. 22 and 51; M/M0 from Table 8 between 80 and 86 km).
#[derive(Clone, Debug)]
pub struct Standard1976 {
    /// Molecular-scale temperature T_M,b at each layer base, K.
    base_temperature: [f64; 7],
    /// Pressure p_b at each layer base, Pa, from the layer formulas applied upwards.
    base_pressure: [f64; 7],
}

impl Default for Standard1976 {
    fn default() -> Self {
        Self::new()
    }
}

impl Standard1976 {
    /// Builds the model: the base temperatures and pressures of the seven layers follow
    /// from T0, P0 and the lapse rates by applying the layer formulas upwards.
    pub fn new() -> Standard1976 {
        let mut base_temperature = [0.0; 7];
        let mut base_pressure = [0.0; 7];
        base_temperature[0] = T0;
        base_pressure[0] = P0;
        for b in 1..7 {
            let dh = LAYER_BASE_H[b] - LAYER_BASE_H[b - 1];
            base_temperature[b] = base_temperature[b - 1] + LAYER_LAPSE[b - 1] * dh;
            base_pressure[b] = layer_pressure(
                base_pressure[b - 1],
                base_temperature[b - 1],
                LAYER_LAPSE[b - 1],
                dh,
            );
        }
        Standard1976 {
            base_temperature,
            base_pressure,
        }
    }

    /// Air properties at geopotential altitude `h_m` (m'), the argument of the USSA76
    /// tables keyed by H. Range: H(-0.5 km) to 84.852 km'.
    pub fn at_geopotential(&self, h_m: f64) -> Result<AtmosphereState, AtmosphereError> {
        if !h_m.is_finite() {
            return Err(AtmosphereError::NotFinite { altitude_m: h_m });
        }
        let z = geometric_altitude(h_m);
        self.evaluate(z, h_m)
    }

    fn evaluate(&self, z: f64, h: f64) -> Result<AtmosphereState, AtmosphereError> {
        // A slack of 1e-9 m lets the round trip Z -> H -> Z land on the end points.
        let slack = 1e-9;
        if !(STANDARD_MIN_ALTITUDE - slack..=STANDARD_MAX_ALTITUDE + slack).contains(&z) {
            return Err(AtmosphereError::OutOfRange {
                altitude_m: z,
                min_m: STANDARD_MIN_ALTITUDE,
                max_m: STANDARD_MAX_ALTITUDE,
            });
        }
        // Layer b with H_b <= H < H_{b+1}; the first layer also covers H < 0.
        let b = LAYER_BASE_H[1..7].partition_point(|&hb| hb <= h);
        let dh = h - LAYER_BASE_H[b];
        let molecular_temperature = self.base_temperature[b] + LAYER_LAPSE[b] * dh;
        let pressure = layer_pressure(
            self.base_pressure[b],
            self.base_temperature[b],
            LAYER_LAPSE[b],
            dh,
        );
        let density = pressure / (R_AIR * molecular_temperature);
        let speed_of_sound = (GAMMA * R_AIR * molecular_temperature).sqrt();
        let temperature = molecular_temperature * molecular_weight_ratio(z);
        Ok(AtmosphereState {
            temperature,
            pressure,
            density,
            speed_of_sound,
            viscosity: sutherland_viscosity(temperature),
        })
    }
}

impl Atmosphere for Standard1976 {
    fn at(&self, altitude_m: f64) -> Result<AtmosphereState, AtmosphereError> {
        if !altitude_m.is_finite() {
            return Err(AtmosphereError::NotFinite { altitude_m });
        }
        self.evaluate(altitude_m, geopotential_altitude(altitude_m))
    }
}

/// Pressure at height `dh` above a layer base with pressure `p_b`, molecular-scale
/// temperature `t_b` and gradient `lapse` (USSA76 eqs. 33a/33b; thesis (4.5.3), (4.5.7)).
fn layer_pressure(p_b: f64, t_b: f64, lapse: f64, dh: f64) -> f64 {
    let g0_over_r = G0 / R_AIR;
    if lapse == 0.0 {
        p_b * (-g0_over_r * dh / t_b).exp()
    } else {
        let t = t_b + lapse * dh;
        p_b * (t_b / t).powf(g0_over_r / lapse)
    }
}

/// M/M0 at geometric altitude `z` (USSA76 Table 8, linear between entries; 1 below 80 km).
fn molecular_weight_ratio(z: f64) -> f64 {
    if z <= MOLECULAR_WEIGHT_RATIO_START {
        return 1.0;
    }
    let x = (z - MOLECULAR_WEIGHT_RATIO_START) / MOLECULAR_WEIGHT_RATIO_STEP;
    let last = MOLECULAR_WEIGHT_RATIO.len() - 1;
    if x >= last as f64 {
        return MOLECULAR_WEIGHT_RATIO[last];
    }
    // x is finite and in [0, last) here, so the truncation is in range.
    let i = x.floor() as usize;
    let f = x - i as f64;
    MOLECULAR_WEIGHT_RATIO[i] + f * (MOLECULAR_WEIGHT_RATIO[i + 1] - MOLECULAR_WEIGHT_RATIO[i])
}

// ------------------------------------------------------------------------------------------
// User tables
// ------------------------------------------------------------------------------------------

/// A column of an atmosphere table, for error messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableColumn {
    Altitude,
    Temperature,
    Pressure,
    Density,
    SpeedOfSound,
}

impl std::fmt::Display for TableColumn {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            TableColumn::Altitude => "altitude_m",
            TableColumn::Temperature => "temperature_K",
            TableColumn::Pressure => "pressure_Pa",
            TableColumn::Density => "density_kg_m3",
            TableColumn::SpeedOfSound => "speed_of_sound_m_s",
        })
    }
}

const TABLE_HEADER: [&str; 5] = [
    "altitude_m",
    "temperature_K",
    "pressure_Pa",
    "density_kg_m3",
    "speed_of_sound_m_s",
];

/// Why an atmosphere table could not be read. Lines are 1-based.
#[derive(Debug, thiserror::Error)]
pub enum AtmosphereTableError {
    #[error("{}: cannot read the atmosphere table: {source}", file.display())]
    Io {
        file: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "{}:{line}: expected the header `altitude_m,temperature_K,pressure_Pa,density_kg_m3` \
         (optionally `,speed_of_sound_m_s`), found `{found}`",
        file.display()
    )]
    BadHeader {
        file: PathBuf,
        line: usize,
        found: String,
    },
    #[error("{}:{line}: missing value for {column}", file.display())]
    MissingValue {
        file: PathBuf,
        line: usize,
        column: TableColumn,
    },
    #[error("{}:{line}: {count} fields, expected {expected}", file.display())]
    WrongFieldCount {
        file: PathBuf,
        line: usize,
        count: usize,
        expected: usize,
    },
    #[error("{}:{line}: {column} `{text}` is not a finite number", file.display())]
    NotANumber {
        file: PathBuf,
        line: usize,
        column: TableColumn,
        text: String,
    },
    #[error("{}:{line}: {column} must be positive, found {value}", file.display())]
    NonPositive {
        file: PathBuf,
        line: usize,
        column: TableColumn,
        value: f64,
    },
    #[error(
        "{}:{line}: altitude {altitude_m} m does not increase (previous row: {previous_m} m)",
        file.display()
    )]
    NonIncreasingAltitude {
        file: PathBuf,
        line: usize,
        altitude_m: f64,
        previous_m: f64,
    },
    #[error("{}: an atmosphere table needs at least two rows, found {rows}", file.display())]
    TooFewRows { file: PathBuf, rows: usize },
}

/// A user atmosphere from a CSV table (`altitude_m,temperature_K,pressure_Pa,
/// density_kg_m3[,speed_of_sound_m_s]`, header required, `#` comments and blank lines
/// skipped), for the non-standard conditions of thesis 4.5.1.
///
/// Between rows: temperature and speed of sound are linear in altitude; pressure and density
/// are log-linear (exact for an isothermal layer, where both are exponential in altitude).
/// Both interpolants are monotone between rows. Without a speed-of-sound column,
/// a = sqrt(gamma R T) (USSA76 eq. 50). Viscosity is Sutherland's law of T (USSA76 eq. 51).
#[derive(Clone, Debug)]
pub struct TableAtmosphere {
    altitude: Vec<f64>,
    temperature: Vec<f64>,
    ln_pressure: Vec<f64>,
    ln_density: Vec<f64>,
    speed_of_sound: Option<Vec<f64>>,
}

impl TableAtmosphere {
    /// Reads a table from a file.
    pub fn read(path: &Path) -> Result<TableAtmosphere, AtmosphereTableError> {
        let text = std::fs::read_to_string(path).map_err(|source| AtmosphereTableError::Io {
            file: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text, path)
    }

    /// Parses table text; `file` names the source in errors.
    pub fn parse(text: &str, file: &Path) -> Result<TableAtmosphere, AtmosphereTableError> {
        let mut table = TableAtmosphere {
            altitude: Vec::new(),
            temperature: Vec::new(),
            ln_pressure: Vec::new(),
            ln_density: Vec::new(),
            speed_of_sound: None,
        };
        let mut columns: Option<usize> = None;
        for (index, raw) in text.lines().enumerate() {
            let line = index + 1;
            let content = raw.trim();
            if content.is_empty() || content.starts_with('#') {
                continue;
            }
            let fields: Vec<&str> = content.split(',').map(str::trim).collect();
            let Some(expected) = columns else {
                let n = fields.len();
                let matches = (4..=5).contains(&n)
                    && fields
                        .iter()
                        .zip(TABLE_HEADER)
                        .all(|(f, h)| f.eq_ignore_ascii_case(h));
                if !matches {
                    return Err(AtmosphereTableError::BadHeader {
                        file: file.to_path_buf(),
                        line,
                        found: content.to_string(),
                    });
                }
                columns = Some(n);
                if n == 5 {
                    table.speed_of_sound = Some(Vec::new());
                }
                continue;
            };
            if fields.len() != expected {
                return Err(AtmosphereTableError::WrongFieldCount {
                    file: file.to_path_buf(),
                    line,
                    count: fields.len(),
                    expected,
                });
            }
            let order = [
                TableColumn::Altitude,
                TableColumn::Temperature,
                TableColumn::Pressure,
                TableColumn::Density,
                TableColumn::SpeedOfSound,
            ];
            let mut values = [0.0; 5];
            for (k, (text, column)) in fields.iter().zip(order).enumerate() {
                values[k] = parse_table_value(text, column, file, line)?;
                if column != TableColumn::Altitude && values[k] <= 0.0 {
                    return Err(AtmosphereTableError::NonPositive {
                        file: file.to_path_buf(),
                        line,
                        column,
                        value: values[k],
                    });
                }
            }
            if let Some(&previous_m) = table.altitude.last()
                && values[0] <= previous_m
            {
                return Err(AtmosphereTableError::NonIncreasingAltitude {
                    file: file.to_path_buf(),
                    line,
                    altitude_m: values[0],
                    previous_m,
                });
            }
            table.altitude.push(values[0]);
            table.temperature.push(values[1]);
            table.ln_pressure.push(values[2].ln());
            table.ln_density.push(values[3].ln());
            if let Some(a) = table.speed_of_sound.as_mut() {
                a.push(values[4]);
            }
        }
        if table.altitude.len() < 2 {
            return Err(AtmosphereTableError::TooFewRows {
                file: file.to_path_buf(),
                rows: table.altitude.len(),
            });
        }
        Ok(table)
    }

    /// The altitude range covered by the table, m.
    pub fn range(&self) -> (f64, f64) {
        (
            self.altitude.first().copied().unwrap_or(0.0),
            self.altitude.last().copied().unwrap_or(0.0),
        )
    }
}

fn parse_table_value(
    text: &str,
    column: TableColumn,
    file: &Path,
    line: usize,
) -> Result<f64, AtmosphereTableError> {
    if text.is_empty() {
        return Err(AtmosphereTableError::MissingValue {
            file: file.to_path_buf(),
            line,
            column,
        });
    }
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(AtmosphereTableError::NotANumber {
            file: file.to_path_buf(),
            line,
            column,
            text: text.to_string(),
        }),
    }
}

impl Atmosphere for TableAtmosphere {
    fn at(&self, altitude_m: f64) -> Result<AtmosphereState, AtmosphereError> {
        if !altitude_m.is_finite() {
            return Err(AtmosphereError::NotFinite { altitude_m });
        }
        let (min_m, max_m) = self.range();
        if !(min_m..=max_m).contains(&altitude_m) {
            return Err(AtmosphereError::OutOfRange {
                altitude_m,
                min_m,
                max_m,
            });
        }
        // Row i with altitude[i] <= z <= altitude[i + 1].
        let n = self.altitude.len();
        let i = self
            .altitude
            .partition_point(|&a| a <= altitude_m)
            .clamp(1, n - 1)
            - 1;
        let f = (altitude_m - self.altitude[i]) / (self.altitude[i + 1] - self.altitude[i]);
        let lerp = |v: &[f64]| v[i] + f * (v[i + 1] - v[i]);
        let temperature = lerp(&self.temperature);
        let speed_of_sound = match &self.speed_of_sound {
            Some(a) => lerp(a),
            None => (GAMMA * R_AIR * temperature).sqrt(),
        };
        Ok(AtmosphereState {
            temperature,
            pressure: lerp(&self.ln_pressure).exp(),
            density: lerp(&self.ln_density).exp(),
            speed_of_sound,
            viscosity: sutherland_viscosity(temperature),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Altitudes across the layers of the model, from below sea level to above 80 km.
    const ALTITUDES: [f64; 8] = [
        -400.0, 0.0, 5_000.0, 11_000.0, 15_000.0, 32_000.0, 50_000.0, 81_234.5,
    ];

    fn bits(a: &AtmosphereState) -> [u64; 5] {
        [
            a.temperature,
            a.pressure,
            a.density,
            a.speed_of_sound,
            a.viscosity,
        ]
        .map(f64::to_bits)
    }

    /// The memo serves every altitude with the bits of the model's own evaluation, whether
    /// it evaluates or reads back: in turn at altitudes 1 mm apart (a memo that ignored its
    /// key, or compared it loosely, would hand the neighbour's air back), again at the same
    /// altitude, and across the layers; an error is passed on, not kept.
    #[test]
    fn the_memo_gives_the_models_bits_at_every_altitude() {
        let model = Standard1976::new();
        let mut memo = AirMemo::default();
        for z0 in ALTITUDES {
            let z1 = z0 + 1e-3;
            for z in [z0, z0, z1, z0, z1, z1] {
                let want = model.at(z).unwrap();
                let got = memo.at(&model, z).unwrap();
                assert_eq!(bits(&got), bits(&want), "at {z} m");
            }
        }
        // The air 1 mm apart differs, so the comparison above can tell them apart.
        for z0 in ALTITUDES {
            let (a, b) = (model.at(z0).unwrap(), model.at(z0 + 1e-3).unwrap());
            assert_ne!(bits(&a), bits(&b), "at {z0} m");
        }
        let high = memo.at(&model, 90_000.0);
        assert!(matches!(high, Err(AtmosphereError::OutOfRange { .. })));
        let again = memo.at(&model, 81_234.5).unwrap();
        assert_eq!(bits(&again), bits(&model.at(81_234.5).unwrap()));
    }
}
