//! Identification of the response after each stimulus, as in thesis Tables 6.1-6.2: the
//! window of a channel from the end of a stimulus to the start of the next one (or the end
//! of the run) is fitted by [`identify`], eq. (6.30).

use rayon::prelude::*;
use serde::Serialize;

use crate::check::ir::{Stimulus, StimulusKind};
use crate::run::RunOutput;

use super::identify::{Identification, IdentifyOptions, identify};

/// Channels fitted by default: the flap coordinate of fin 1 and the angle of attack.
pub const DEFAULT_CHANNELS: &[&str] = &["eta_fin1_flap", "alpha"];

/// The fit of one channel after one stimulus.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StimulusFit {
    /// Name of the stimulus.
    pub stimulus: String,
    pub channel: String,
    /// Window, s: end of the stimulus to the next stimulus or the end of the run.
    pub window_start: f64,
    pub window_end: f64,
    /// The fit, when it succeeded.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fit: Option<Identification>,
    /// Why there is no fit (window too short, flat signal, channel missing).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// `(start, end)` of a stimulus, s.
pub fn stimulus_interval(s: &Stimulus) -> (f64, f64) {
    let (start, duration) = match &s.kind {
        StimulusKind::Gust {
            start, duration, ..
        }
        | StimulusKind::OneMinusCosine {
            start, duration, ..
        }
        | StimulusKind::Sine {
            start, duration, ..
        }
        | StimulusKind::Turbulence {
            start, duration, ..
        } => (start.value, duration.value),
    };
    (start, start + duration)
}

/// The free-response windows: for each stimulus in order of start time, from its end to the
/// start of the next stimulus that begins after that end, or to `t_end`. Windows that would
/// be empty (the run stopped during the stimulus) are kept with `end <= start`.
pub fn response_windows(stimuli: &[Stimulus], t_end: f64) -> Vec<(String, f64, f64)> {
    let mut spans: Vec<(String, f64, f64)> = stimuli
        .iter()
        .map(|s| {
            let (a, b) = stimulus_interval(s);
            (s.name.value.clone(), a, b)
        })
        .collect();
    spans.sort_by(|x, y| x.1.total_cmp(&y.1).then(x.0.cmp(&y.0)));
    spans
        .iter()
        .map(|(name, _, end)| {
            let next = spans
                .iter()
                .map(|s| s.1)
                .filter(|&a| a >= *end)
                .fold(t_end, f64::min);
            (name.clone(), *end, next.min(t_end))
        })
        .collect()
}

/// Fit each of `channels` in each response window of a run. A channel the run does not
/// have, or a window that cannot be fitted, gives an entry with `error` set.
pub fn identify_after_stimuli(
    stimuli: &[Stimulus],
    output: &RunOutput,
    channels: &[&str],
    opts: &IdentifyOptions,
) -> Vec<StimulusFit> {
    let time_col = output.channels.iter().position(|c| c == "t");
    let jobs: Vec<(String, f64, f64, &str)> = response_windows(stimuli, output.t_end)
        .into_iter()
        .flat_map(|(stimulus, a, b)| {
            channels
                .iter()
                .map(move |&channel| (stimulus.clone(), a, b, channel))
        })
        .collect();
    // Each fit is independent of the others: fitted in parallel, collected in order (the
    // same results whatever the number of threads).
    jobs.into_par_iter()
        .map(|(stimulus, a, b, channel)| {
            let col = output.channels.iter().position(|c| c == channel);
            let result = match (time_col, col) {
                (Some(tc), Some(col)) => {
                    let (t, x): (Vec<f64>, Vec<f64>) = output
                        .rows
                        .iter()
                        // Half-open before the next stimulus: the row at its start
                        // already sees it (a sharp-edged gust steps `alpha` there).
                        .filter(|r| r[tc] >= a && (r[tc] < b || (b >= output.t_end && r[tc] <= b)))
                        .map(|r| (r[tc], r[col]))
                        .unzip();
                    identify(&t, &x, opts).map_err(|e| e.to_string())
                }
                _ => Err(format!("the run has no channel `{channel}`")),
            };
            let (fit, error) = match result {
                Ok(f) => (Some(f), None),
                Err(e) => (None, Some(e)),
            };
            StimulusFit {
                stimulus,
                channel: channel.to_string(),
                window_start: a,
                window_end: b,
                fit,
                error,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::ir::Frame;
    use crate::run::RunStop;
    use crate::syntax::{Span, Spanned};

    fn gust(name: &str, start: f64, duration: f64) -> Stimulus {
        fn q<T>(v: T) -> Spanned<T> {
            Spanned::new(v, Span::default())
        }
        Stimulus {
            name: q(name.to_string()),
            kind: StimulusKind::Gust {
                start: q(start),
                duration: q(duration),
                velocity: q([0.0, 0.0, 5.0]),
                frame: Frame::Body,
            },
        }
    }

    #[test]
    fn windows_run_from_each_stimulus_end_to_the_next_start_or_the_run_end() {
        // Written out of order, as in a file; the second gust starts inside the first.
        let s = [
            gust("late", 5.0, 0.1),
            gust("early", 1.0, 0.1),
            gust("inner", 1.05, 0.01),
        ];
        let w = response_windows(&s, 8.0);
        assert_eq!(
            w,
            vec![
                ("early".to_string(), 1.1, 5.0),
                ("inner".to_string(), 1.06, 5.0),
                ("late".to_string(), 5.1, 8.0),
            ]
        );
        // A run that stopped during a gust leaves an empty window.
        let w = response_windows(&s[..1], 5.05);
        assert!(w[0].2 < w[0].1);
    }

    /// A completed run of the channels `t` and `alpha`.
    fn alpha_output(rows: Vec<Vec<f64>>, t_end: f64) -> RunOutput {
        RunOutput {
            channels: vec!["t".into(), "alpha".into()],
            rows,
            stop: RunStop::Completed,
            stop_detail: String::new(),
            t_end,
            stats: Default::default(),
            wall_seconds: 0.0,
            events: Default::default(),
            verdict: None,
        }
    }

    #[test]
    fn a_window_stops_before_the_row_where_the_next_stimulus_starts() {
        // A decaying response after gust `a`, then gust `b` steps the channel at t = 1.5
        // (as a sharp-edged gust steps `alpha`): the row at 1.5 belongs to `b`'s response.
        let omega = 2.0 * std::f64::consts::PI * 3.0;
        let rows: Vec<Vec<f64>> = (0..=400)
            .map(|k| {
                let t = 0.005 * k as f64;
                let free = (-0.5 * (t - 0.5)).exp() * (omega * (t - 0.5)).sin();
                let x = if t < 0.5 {
                    0.0
                } else if t < 1.5 {
                    free
                } else {
                    free + 10.0
                };
                vec![t, x]
            })
            .collect();
        let out = alpha_output(rows, 2.0);
        let fits = identify_after_stimuli(
            &[gust("a", 0.4, 0.1), gust("b", 1.5, 0.1)],
            &out,
            &["alpha"],
            &IdentifyOptions::default(),
        );
        let f = fits[0].fit.as_ref().expect("the first window is fitted");
        assert_eq!(fits[0].window_end, 1.5);
        assert!(f.t_end < 1.5, "{f:?}");
        assert!(
            (f.sigma_d + 0.5).abs() < 1e-6 && (f.omega_d - omega).abs() < 1e-6,
            "{f:?}"
        );
        // The last window ends at the end of the run and keeps its last row.
        let g = fits[1].fit.as_ref().expect("the second window is fitted");
        assert!((g.t_end - 2.0).abs() < 1e-12, "{g:?}");
    }

    #[test]
    fn a_decaying_response_after_a_gust_is_fitted_and_a_missing_channel_reported() {
        let omega = 2.0 * std::f64::consts::PI * 2.0;
        let rows: Vec<Vec<f64>> = (0..=400)
            .map(|k| {
                let t = 0.005 * k as f64;
                let x = if t < 0.5 {
                    0.0
                } else {
                    (-0.4 * (t - 0.5)).exp() * (omega * (t - 0.5)).sin()
                };
                vec![t, x]
            })
            .collect();
        let out = alpha_output(rows, 2.0);
        let fits = identify_after_stimuli(
            &[gust("g", 0.4, 0.1)],
            &out,
            DEFAULT_CHANNELS,
            &IdentifyOptions::default(),
        );
        assert_eq!(fits.len(), 2);
        assert_eq!(fits[0].channel, "eta_fin1_flap");
        assert!(fits[0].error.as_deref().unwrap().contains("no channel"));
        let f = fits[1].fit.as_ref().unwrap();
        assert!(
            (f.sigma_d + 0.4).abs() < 1e-6 && (f.omega_d - omega).abs() < 1e-6,
            "{f:?}"
        );
        assert!((f.t_start - 0.5).abs() < 1e-12 && fits[1].window_end == 2.0);
    }
}
