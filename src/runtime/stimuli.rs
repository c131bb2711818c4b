//! The gust stimulus generator (thesis 4.5.2): wind velocity as a function of time, from
//! the scenario's `stimulus` blocks (IR: [`crate::check::ir::StimulusKind`]).
//!
//! The thesis' generator acts "for a predetermined fraction of time" (a pulse) or "follows a
//! more continuous and elaborate profile, such as a sinusoid", or is random. Here:
//!
//! - rectangular pulse: v for start <= t < start + duration;
//! - 1 - cos gust: v/2 (1 - cos(2 pi (t - start)/duration)) for t in [start, start + duration];
//! - sine: v sin(2 pi f (t - start)) for t in [start, start + duration];
//! - continuous turbulence, Dryden or von Karman (MIL-F-8785C section 3.7.2; transfer
//!   functions of MIL-HDBK-1797 appendix), seeded.
//!
//! Turbulence is generated at plan time ([`Stimuli::new`]) as a time series on a fixed grid
//! and interpolated linearly during the run, so [`Stimuli::wind`] never allocates and a
//! run is reproducible bit for bit from the seed. The shaping filters depend on the airspeed
//! V (Taylor's frozen-turbulence hypothesis: spatial frequency Omega = omega / V); V is a
//! plan-time parameter, the initial airspeed, and is not updated during the run.
//!
//! Turbulence components are along the body axes (MIL-F-8785C defines u_g, v_g, w_g in body
//! axes); pulses use the frame their stimulus names.

use nalgebra::{DMatrix, DVector};

use crate::check::ir::{Frame, Stimulus, StimulusKind, TurbulenceModel};
use crate::syntax::Span;

/// Turbulence grid: at most this many samples per series.
pub const MAX_TURBULENCE_SAMPLES: usize = 2_000_000;
/// Turbulence grid step as a fraction of the correlation time L/V.
pub const STEPS_PER_CORRELATION_TIME: f64 = 20.0;

/// Why the stimuli could not be planned.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StimulusError {
    #[error("stimulus `{name}`: {what} must be {expected}, found {value}")]
    BadParameter {
        name: String,
        span: Span,
        what: &'static str,
        expected: &'static str,
        value: f64,
    },
    #[error(
        "stimulus `{name}`: turbulence needs a positive finite airspeed to set its time \
         scale L/V, found {airspeed} m/s"
    )]
    NoAirspeed {
        name: String,
        span: Span,
        airspeed: f64,
    },
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum PulseShape {
    Rectangular,
    OneMinusCosine,
    Sine { frequency: f64 },
}

#[derive(Clone, Debug, PartialEq)]
struct Pulse {
    shape: PulseShape,
    start: f64,
    duration: f64,
    velocity: [f64; 3],
    frame: Frame,
}

impl Pulse {
    /// The pulse's wind at `t` (module doc formulas).
    fn at(&self, t: f64) -> [f64; 3] {
        let end = self.start + self.duration;
        let factor = match self.shape {
            PulseShape::Rectangular if t >= self.start && t < end => 1.0,
            PulseShape::OneMinusCosine if t >= self.start && t <= end => {
                let phase = 2.0 * std::f64::consts::PI * (t - self.start) / self.duration;
                0.5 * (1.0 - phase.cos())
            }
            PulseShape::Sine { frequency } if t >= self.start && t <= end => {
                (2.0 * std::f64::consts::PI * frequency * (t - self.start)).sin()
            }
            _ => 0.0,
        };
        self.velocity.map(|v| factor * v)
    }
}

/// A turbulence series on a uniform grid (body axes).
#[derive(Clone, Debug, PartialEq)]
struct TurbulenceSeries {
    start: f64,
    step: f64,
    samples: Vec<[f64; 3]>,
}

impl TurbulenceSeries {
    fn at(&self, t: f64) -> [f64; 3] {
        let x = (t - self.start) / self.step;
        let last = self.samples.len().saturating_sub(1);
        // NaN fails the comparison and yields no wind.
        if !(x >= 0.0 && x <= last as f64) {
            return [0.0; 3];
        }
        let i = (x.floor() as usize).min(last.saturating_sub(1));
        let f = x - i as f64;
        let (a, b) = (self.samples[i], self.samples[(i + 1).min(last)]);
        [0, 1, 2].map(|k| a[k] + f * (b[k] - a[k]))
    }
}

/// Largest number of rows of a steady-wind table (fixed-size storage: the lookup never
/// allocates and the struct stays `Clone` without a heap copy per block).
pub const MAX_WIND_ROWS: usize = 64;

/// The steady wind of a scenario's `wind` block, inertial frame (x north, y east, z down),
/// as a function of the height `z` above the ground.
///
/// A wind "from" direction `psi` (meteorological convention, clockwise from north) blows
/// toward `psi + 180 deg`: its velocity is `-V (cos psi, sin psi, 0)`.
/// - constant: `V` at every height;
/// - power law (Hellmann; e.g. Peterson and Hennessey, J. Appl. Meteorol. 17, 1978, eq. 1):
///   `V(z) = V_ref (z / z_ref)^alpha` for `z > 0`, zero at and below the ground; `alpha = 1/7`
///   is the usual neutral-stability value over open ground;
/// - table: rows `(z_k, V_k, psi_k)`; the north and east components are interpolated
///   linearly in `z` (continuous, no wrap-around of the direction) and held below the first
///   and above the last row.
#[derive(Clone, Debug, PartialEq)]
pub struct SteadyWind {
    ground_altitude: f64,
    kind: SteadyKind,
}

#[derive(Clone, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)] // fixed-size table: no heap copy per block
enum SteadyKind {
    Constant([f64; 3]),
    PowerLaw {
        at_reference: [f64; 3],
        reference_height: f64,
        exponent: f64,
    },
    Table {
        len: usize,
        heights: [f64; MAX_WIND_ROWS],
        north: [f64; MAX_WIND_ROWS],
        east: [f64; MAX_WIND_ROWS],
    },
}

fn wind_from(speed: f64, direction: f64) -> [f64; 3] {
    [-speed * direction.cos(), -speed * direction.sin(), 0.0]
}

impl SteadyWind {
    /// The wind of a checked profile over a ground at `ground_altitude` (m above sea level).
    /// Tables longer than [`MAX_WIND_ROWS`] keep their first rows (the checker refuses them).
    pub fn new(profile: &crate::check::ir::WindProfile, ground_altitude: f64) -> Self {
        use crate::check::ir::WindProfile as P;
        let kind = match profile {
            P::Constant { speed, direction } => {
                SteadyKind::Constant(wind_from(speed.value, direction.value))
            }
            P::PowerLaw {
                speed,
                direction,
                reference_height,
                exponent,
            } => SteadyKind::PowerLaw {
                at_reference: wind_from(speed.value, direction.value),
                reference_height: reference_height.value,
                exponent: exponent.value,
            },
            P::Table(rows) => {
                let len = rows.len().min(MAX_WIND_ROWS);
                let mut heights = [0.0; MAX_WIND_ROWS];
                let mut north = [0.0; MAX_WIND_ROWS];
                let mut east = [0.0; MAX_WIND_ROWS];
                for (k, r) in rows.iter().take(len).enumerate() {
                    let w = wind_from(r.speed, r.direction);
                    heights[k] = r.height;
                    north[k] = w[0];
                    east[k] = w[1];
                }
                SteadyKind::Table {
                    len,
                    heights,
                    north,
                    east,
                }
            }
        };
        SteadyWind {
            ground_altitude,
            kind,
        }
    }

    /// Wind velocity at `altitude` (m above sea level), inertial frame. Never allocates.
    pub fn at(&self, altitude: f64) -> [f64; 3] {
        let z = altitude - self.ground_altitude;
        match &self.kind {
            SteadyKind::Constant(w) => *w,
            SteadyKind::PowerLaw {
                at_reference,
                reference_height,
                exponent,
            } => {
                if z.is_nan() || z <= 0.0 {
                    return [0.0; 3];
                }
                let f = (z / reference_height).powf(*exponent);
                at_reference.map(|c| c * f)
            }
            SteadyKind::Table {
                len,
                heights,
                north,
                east,
            } => {
                let n = *len;
                if n == 0 || z.is_nan() {
                    return [0.0; 3];
                }
                if z <= heights[0] {
                    return [north[0], east[0], 0.0];
                }
                if z >= heights[n - 1] {
                    return [north[n - 1], east[n - 1], 0.0];
                }
                let k = heights[..n].partition_point(|&h| h <= z).clamp(1, n - 1) - 1;
                let f = (z - heights[k]) / (heights[k + 1] - heights[k]);
                [
                    north[k] + f * (north[k + 1] - north[k]),
                    east[k] + f * (east[k + 1] - east[k]),
                    0.0,
                ]
            }
        }
    }
}

/// The planned stimuli of one run.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Stimuli {
    pulses: Vec<Pulse>,
    turbulence: Vec<TurbulenceSeries>,
    /// The scenario's steady wind (inertial frame, a function of altitude).
    steady: Option<SteadyWind>,
    /// The end of the run's current integration segment when it is one of the pulses'
    /// switch times ([`Self::switch_times`]; `None` otherwise): the wind there is then the
    /// left-hand limit, evaluated one ulp before, so that the segment's last step sees the
    /// forcing of the side it integrates (a rectangular pulse is right-continuous, a sine's
    /// end left-continuous).
    left_of: Option<f64>,
}

impl Stimuli {
    /// Plans the stimuli for a run of `stop_time` seconds at initial airspeed `airspeed`
    /// (m/s; used only by turbulence), generating the turbulence series now.
    pub fn new(
        stimuli: &[Stimulus],
        airspeed: f64,
        stop_time: f64,
    ) -> Result<Stimuli, StimulusError> {
        let mut planned = Stimuli::default();
        for stimulus in stimuli {
            let name = &stimulus.name.value;
            let span = stimulus.name.span;
            let check = |value: f64, what: &'static str, positive: bool| {
                let ok = value.is_finite() && if positive { value > 0.0 } else { value >= 0.0 };
                if ok {
                    Ok(value)
                } else {
                    Err(StimulusError::BadParameter {
                        name: name.clone(),
                        span,
                        what,
                        expected: if positive {
                            "positive and finite"
                        } else {
                            "non-negative and finite"
                        },
                        value,
                    })
                }
            };
            let check_vector = |v: [f64; 3], what: &'static str| {
                for c in v {
                    if !c.is_finite() {
                        return Err(StimulusError::BadParameter {
                            name: name.clone(),
                            span,
                            what,
                            expected: "finite",
                            value: c,
                        });
                    }
                }
                Ok(v)
            };
            let pulse = |shape, start: f64, duration: f64, velocity, frame: &Frame| {
                Ok::<_, StimulusError>(Pulse {
                    shape,
                    start: check(start, "start", false)?,
                    duration: check(duration, "duration", true)?,
                    velocity: check_vector(velocity, "velocity")?,
                    frame: *frame,
                })
            };
            match &stimulus.kind {
                StimulusKind::Gust {
                    start,
                    duration,
                    velocity,
                    frame,
                } => planned.pulses.push(pulse(
                    PulseShape::Rectangular,
                    start.value,
                    duration.value,
                    velocity.value,
                    frame,
                )?),
                StimulusKind::OneMinusCosine {
                    start,
                    duration,
                    velocity,
                    frame,
                } => planned.pulses.push(pulse(
                    PulseShape::OneMinusCosine,
                    start.value,
                    duration.value,
                    velocity.value,
                    frame,
                )?),
                StimulusKind::Sine {
                    start,
                    duration,
                    amplitude,
                    frequency,
                    frame,
                } => {
                    let frequency = check(frequency.value, "frequency", true)?;
                    planned.pulses.push(pulse(
                        PulseShape::Sine { frequency },
                        start.value,
                        duration.value,
                        amplitude.value,
                        frame,
                    )?)
                }
                StimulusKind::Turbulence {
                    model,
                    intensity,
                    scale_length,
                    seed,
                    start,
                    duration,
                } => {
                    let intensity = check(intensity.value, "intensity", false)?;
                    let scale_length = check(scale_length.value, "scale length", true)?;
                    let start = check(start.value, "start", false)?;
                    let duration = check(duration.value, "duration", true)?;
                    if !(airspeed.is_finite() && airspeed > 0.0) {
                        return Err(StimulusError::NoAirspeed {
                            name: name.clone(),
                            span,
                            airspeed,
                        });
                    }
                    let end = (start + duration).min(stop_time);
                    if end <= start {
                        continue; // starts after the run: no wind
                    }
                    planned.turbulence.push(generate_turbulence(
                        model.value,
                        intensity,
                        scale_length / airspeed,
                        seed.value,
                        start,
                        end,
                    ));
                }
            }
        }
        Ok(planned)
    }

    /// The pulses' switch times, s (each pulse's start and end: where its wind jumps or
    /// has a kink), in no particular order.
    pub fn switch_times(&self) -> impl Iterator<Item = f64> + '_ {
        self.pulses
            .iter()
            .flat_map(|p| [p.start, p.start + p.duration])
    }

    /// Sets (or clears) the segment end at which the wind is the left-hand limit
    /// (see the field `left_of`).
    pub fn set_left_of(&mut self, t: Option<f64>) {
        self.left_of = t;
    }

    /// Wind velocity at time `t`, m/s: (body-frame part, inertial-frame part). Never
    /// allocates.
    pub fn wind(&self, t: f64) -> ([f64; 3], [f64; 3]) {
        let t = match self.left_of {
            Some(c) if t >= c && c > 0.0 => f64::from_bits(c.to_bits() - 1),
            _ => t,
        };
        let mut body = [0.0; 3];
        let mut inertial = [0.0; 3];
        for pulse in &self.pulses {
            let v = pulse.at(t);
            let target = match pulse.frame {
                Frame::Body => &mut body,
                Frame::Inertial => &mut inertial,
            };
            for k in 0..3 {
                target[k] += v[k];
            }
        }
        for series in &self.turbulence {
            let v = series.at(t);
            for k in 0..3 {
                body[k] += v[k];
            }
        }
        (body, inertial)
    }

    /// Adds the scenario's steady wind (profile over a ground at `ground_altitude`).
    pub fn set_steady_wind(
        &mut self,
        profile: &crate::check::ir::WindProfile,
        ground_altitude: f64,
    ) {
        self.steady = Some(SteadyWind::new(profile, ground_altitude));
    }

    /// [`Self::wind`] plus the steady wind at `altitude` (m above sea level), added to the
    /// inertial part. Never allocates.
    pub fn wind_at(&self, t: f64, altitude: f64) -> ([f64; 3], [f64; 3]) {
        let (body, mut inertial) = self.wind(t);
        if let Some(s) = &self.steady {
            let w = s.at(altitude);
            for k in 0..3 {
                inertial[k] += w[k];
            }
        }
        (body, inertial)
    }

    /// The turbulence samples of the `index`-th turbulence stimulus on its grid:
    /// (start s, step s, samples). For tests and output.
    pub fn turbulence_series(&self, index: usize) -> Option<(f64, f64, &[[f64; 3]])> {
        self.turbulence
            .get(index)
            .map(|s| (s.start, s.step, s.samples.as_slice()))
    }
}

// ------------------------------------------------------------------------------------------
// Turbulence
// ------------------------------------------------------------------------------------------

/// SplitMix64 (Steele, Lea, Flood 2014; Vigna's reference constants) with Box-Muller
/// normals. Deterministic across platforms: integer arithmetic plus `ln`, `sqrt`, `cos`.
pub(crate) struct NormalSource {
    state: u64,
    spare: Option<f64>,
}

impl NormalSource {
    pub(crate) fn new(seed: u64) -> Self {
        NormalSource {
            state: seed,
            spare: None,
        }
    }

    /// The next 64 random bits (also the tests' random inputs elsewhere in the crate).
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in (0, 1]: 53 random bits, shifted off zero so `ln` is finite.
    fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 1.0) * (1.0 / (1u64 << 53) as f64)
    }

    /// Standard normal by the Box-Muller transform.
    fn normal(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        let r = (-2.0 * self.uniform().ln()).sqrt();
        let theta = 2.0 * std::f64::consts::PI * self.uniform();
        self.spare = Some(r * theta.sin());
        r * theta.cos()
    }
}

/// A rational shaping filter H(s~) = N(s~)/D(s~) in the dimensionless Laplace variable
/// s~ = (L/V) s (coefficients in ascending powers; deg N < deg D).
struct ShapingFilter {
    numerator: &'static [f64],
    denominator: &'static [f64],
}

const SQRT_3: f64 = 1.732_050_807_568_877_2;

/// Dryden longitudinal: H_u = 1 / (1 + (L/V) s) (MIL-HDBK-1797; spectrum
/// Phi_u = sigma^2 (2L/pi) / (1 + (L Omega)^2), MIL-F-8785C eq. for the Dryden form).
const DRYDEN_U: ShapingFilter = ShapingFilter {
    numerator: &[1.0],
    denominator: &[1.0, 1.0],
};
/// Dryden lateral/vertical: H_v = (1 + sqrt(3) (L/V) s) / (1 + (L/V) s)^2 (MIL-HDBK-1797;
/// Phi_v = sigma^2 (L/pi) (1 + 3 (L Omega)^2) / (1 + (L Omega)^2)^2, MIL-F-8785C).
const DRYDEN_VW: ShapingFilter = ShapingFilter {
    numerator: &[1.0, SQRT_3],
    denominator: &[1.0, 2.0, 1.0],
};
/// von Karman longitudinal, rational approximation (MIL-HDBK-1797, as used by the
/// MathWorks "Von Karman Wind Turbulence Model"): H_u = (1 + 0.25 (L/V) s) /
/// (1 + 1.357 (L/V) s + 0.1987 (L/V)^2 s^2), approximating
/// Phi_u = sigma^2 (2L/pi) / (1 + (1.339 L Omega)^2)^(5/6) (MIL-F-8785C).
const VON_KARMAN_U: ShapingFilter = ShapingFilter {
    numerator: &[1.0, 0.25],
    denominator: &[1.0, 1.357, 0.1987],
};
/// von Karman lateral/vertical, rational approximation (MIL-HDBK-1797):
/// H_v = (1 + 2.7478 tau s + 0.3398 (tau s)^2) / (1 + 2.9958 tau s + 1.9754 (tau s)^2
/// plus 0.1539 (tau s)^3) with tau = 2 L_v/V in the handbook's notation, i.e. tau = L/V
/// with MIL-F-8785C's L, approximating Phi_v = sigma^2 (L/pi) (1 + 8/3 (1.339 L Omega)^2)
/// divided by (1 + (1.339 L Omega)^2)^(11/6).
const VON_KARMAN_VW: ShapingFilter = ShapingFilter {
    numerator: &[1.0, 2.7478, 0.3398],
    denominator: &[1.0, 2.9958, 1.9754, 0.1539],
};

/// Exact discretisation of a shaping filter driven by white noise, normalised to unit
/// output variance.
///
/// Controllable canonical form x' = A x + B w, y = C x (time in units of L/V). For white
/// noise of unit intensity the stationary covariance S solves A S + S A^T + B B^T = 0; over a
/// step h the state evolves as x_{k+1} = Phi x_k + e_k with Phi = exp(A h) and
/// e_k ~ N(0, S - Phi S Phi^T) (exact for the stationary process, any h). The output is
/// scaled by 1/sqrt(C S C^T), so the series has exactly the requested variance sigma^2
/// (for von Karman this fixes the small variance error of the rational approximation).
struct DiscreteFilter {
    phi: DMatrix<f64>,
    noise_factor: DMatrix<f64>,
    stationary_factor: DMatrix<f64>,
    output: DVector<f64>,
}

impl DiscreteFilter {
    fn new(filter: &ShapingFilter, h: f64) -> DiscreteFilter {
        let n = filter.denominator.len() - 1;
        let lead = filter.denominator[n];
        let mut a = DMatrix::zeros(n, n);
        for i in 0..n.saturating_sub(1) {
            a[(i, i + 1)] = 1.0;
        }
        for j in 0..n {
            a[(n - 1, j)] = -filter.denominator[j] / lead;
        }
        let mut output = DVector::zeros(n);
        for (j, &c) in filter.numerator.iter().enumerate().take(n) {
            output[j] = c / lead;
        }
        // Lyapunov equation by vectorisation: (I (x) A + A (x) I) vec S = -vec(B B^T).
        let eye = DMatrix::<f64>::identity(n, n);
        let big = eye.kronecker(&a) + a.kronecker(&eye);
        let mut rhs = DVector::zeros(n * n);
        rhs[n * n - 1] = -1.0; // B B^T has its only 1 at (n-1, n-1)
        // A is Hurwitz for every filter above, so the system is regular.
        let vec_s = big
            .lu()
            .solve(&rhs)
            .unwrap_or_else(|| DVector::zeros(n * n));
        let mut s = DMatrix::from_column_slice(n, n, vec_s.as_slice());
        s = 0.5 * (&s + s.transpose());
        let variance = (output.transpose() * &s * &output)[(0, 0)];
        let phi = (a * h).exp();
        let q = &s - &phi * &s * phi.transpose();
        DiscreteFilter {
            noise_factor: symmetric_factor(&q),
            stationary_factor: symmetric_factor(&s),
            phi,
            output: output / variance.sqrt(),
        }
    }

    /// Unit-variance output series of `count` samples.
    fn run(&self, normals: &mut NormalSource, count: usize, mut emit: impl FnMut(usize, f64)) {
        let n = self.phi.nrows();
        let mut w = DVector::zeros(n);
        let mut fill = |w: &mut DVector<f64>| w.iter_mut().for_each(|x| *x = normals.normal());
        fill(&mut w);
        let mut x = &self.stationary_factor * &w; // start in the stationary distribution
        for k in 0..count {
            emit(k, self.output.dot(&x));
            fill(&mut w);
            x = &self.phi * &x + &self.noise_factor * &w;
        }
    }
}

/// G with G G^T = M for a symmetric positive semi-definite M (eigenvalues below zero from
/// rounding are set to zero).
fn symmetric_factor(m: &DMatrix<f64>) -> DMatrix<f64> {
    let sym = 0.5 * (m + m.transpose());
    let eigen = sym.symmetric_eigen();
    let roots = eigen.eigenvalues.map(|l| l.max(0.0).sqrt());
    eigen.eigenvectors * DMatrix::from_diagonal(&roots)
}

/// Generates the three body-axis components on [start, end] with time constant
/// `tau` = L/V: grid step tau/20 (coarser if that would exceed
/// [`MAX_TURBULENCE_SAMPLES`]); one independent normal stream per axis, drawn in the order
/// u, v, w from one SplitMix64 sequence.
fn generate_turbulence(
    model: TurbulenceModel,
    intensity: f64,
    tau: f64,
    seed: u64,
    start: f64,
    end: f64,
) -> TurbulenceSeries {
    let span = end - start;
    let step = (tau / STEPS_PER_CORRELATION_TIME).max(span / (MAX_TURBULENCE_SAMPLES - 1) as f64);
    // span/step <= MAX_TURBULENCE_SAMPLES - 1, so the count is bounded.
    let count = (span / step).ceil() as usize + 1;
    let (longitudinal, lateral) = match model {
        TurbulenceModel::Dryden => (DRYDEN_U, DRYDEN_VW),
        TurbulenceModel::VonKarman => (VON_KARMAN_U, VON_KARMAN_VW),
    };
    let h = step / tau;
    let mut samples = vec![[0.0; 3]; count];
    let mut normals = NormalSource::new(seed);
    for (axis, filter) in [(0, &longitudinal), (1, &lateral), (2, &lateral)] {
        DiscreteFilter::new(filter, h).run(&mut normals, count, |k, y| {
            samples[k][axis] = intensity * y;
        });
    }
    TurbulenceSeries {
        start,
        step,
        samples,
    }
}

#[cfg(test)]
mod wind_tests {
    use super::*;
    use crate::check::ir::{WindPoint, WindProfile};
    use crate::syntax::{Span, Spanned};

    fn q(v: f64) -> Spanned<f64> {
        Spanned::new(v, Span::default())
    }

    #[test]
    fn constant_wind_blows_from_its_direction() {
        let w = SteadyWind::new(
            &WindProfile::Constant {
                speed: q(5.0),
                direction: q(270f64.to_radians()),
            },
            100.0,
        );
        // From the west: toward the east (+y).
        let v = w.at(1234.0);
        assert!(
            v[0].abs() < 1e-15 && (v[1] - 5.0).abs() < 1e-15 && v[2] == 0.0,
            "{v:?}"
        );
    }

    #[test]
    fn the_power_law_scales_with_the_height_above_the_ground() {
        let w = SteadyWind::new(
            &WindProfile::PowerLaw {
                speed: q(5.0),
                direction: q(0.0),
                reference_height: q(10.0),
                exponent: q(1.0 / 7.0),
            },
            100.0,
        );
        // From the north, toward -x; 40 m above a ground at 100 m: 5 x 4^(1/7).
        assert_eq!(w.at(140.0)[0], -5.0 * 4f64.powf(1.0 / 7.0));
        assert_eq!(w.at(110.0)[0], -5.0);
        assert_eq!(w.at(100.0), [0.0; 3]);
        assert_eq!(w.at(50.0), [0.0; 3]);
    }

    #[test]
    fn a_wind_table_interpolates_components_and_holds_its_ends() {
        let row = |h: f64, v: f64, d: f64| WindPoint {
            span: Span::default(),
            height: h,
            speed: v,
            direction: d.to_radians(),
        };
        let w = SteadyWind::new(
            &WindProfile::Table(vec![row(0.0, 2.0, 270.0), row(100.0, 4.0, 180.0)]),
            0.0,
        );
        let (a, b) = ([0.0, 2.0], [4.0, 0.0]); // toward east, then toward north
        let mid = w.at(25.0);
        for k in 0..2 {
            let want = a[k] + 0.25 * (b[k] - a[k]);
            assert!((mid[k] - want).abs() < 1e-14, "{mid:?}");
        }
        assert!((w.at(-10.0)[1] - 2.0).abs() < 1e-14);
        assert!((w.at(500.0)[0] - 4.0).abs() < 1e-14);
        // Added to the stimuli's inertial part, by altitude.
        let mut s = Stimuli::default();
        s.set_steady_wind(
            &WindProfile::Table(vec![row(0.0, 2.0, 270.0), row(100.0, 4.0, 180.0)]),
            0.0,
        );
        assert_eq!(s.wind_at(3.0, 25.0).1, mid);
        assert_eq!(s.wind_at(3.0, 25.0).0, [0.0; 3]);
    }
}
