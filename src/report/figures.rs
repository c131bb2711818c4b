//! The thesis' figure set for a run (ch. 6: angle of attack, fin flap and twist
//! coordinates, body bending, velocities, Mach, aerodynamic loads, attitude, energies and
//! momenta), chosen from the columns a `history.csv` actually has.

use super::history::History;
use super::plot::{MarkedPoint, Series, TimePlot};

/// Angles (deg) drawn unwrapped: roll and yaw (heading) are written in (-180, 180] and
/// jump by 360 deg when they pass +-180 (near gimbal lock, pitch +-90 deg, both swing
/// through it); pitch lies in [-90, 90] and never wraps.
pub const UNWRAPPED: [&str; 2] = ["roll", "yaw"];

/// Unwrap an angle in degrees: each value is moved by a whole number of turns so that it
/// lies within 180 deg of the previous unwrapped value (the smallest rotation between
/// consecutive samples, as numpy's `unwrap` with period 360). Values are unchanged modulo
/// 360; non-finite values are passed through and do not move the reference.
pub fn unwrap_degrees(v: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(v.len());
    let mut prev: Option<f64> = None;
    for &x in v {
        if !x.is_finite() {
            out.push(x);
            continue;
        }
        let y = match prev {
            None => x,
            Some(p) => x - 360.0 * ((x - p) / 360.0).round(),
        };
        out.push(y);
        prev = Some(y);
    }
    out
}

/// The smallest span (m) of either axis of the ground track: the larger of 10 m and 1 % of
/// the largest horizontal distance from the first point, so a vertical flight's
/// round-off (1e-11 m) is not drawn as a curve.
pub fn ground_track_min_span(east: &[f64], north: &[f64]) -> f64 {
    let (e0, n0) = (
        east.first().copied().unwrap_or(0.0),
        north.first().copied().unwrap_or(0.0),
    );
    let range = east
        .iter()
        .zip(north)
        .map(|(e, n)| (e - e0).hypot(n - n0))
        .filter(|d| d.is_finite())
        .fold(0.0, f64::max);
    (0.01 * range).max(10.0)
}

/// What kind of deformation a mode is, for grouping the `eta_*` columns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModeGroup {
    /// Fin bending out of its plane (class `fin_flap`).
    FinFlap,
    /// Fin torsion (class `fin_twist`).
    FinTwist,
    /// Body bending (class `body_bending`).
    BodyBending,
    /// Anything else.
    Other,
}

impl ModeGroup {
    /// From the class the structural compiler gave a mode (`CompiledMode::class`).
    pub fn from_class(class: &str) -> Self {
        match class {
            "fin_flap" => ModeGroup::FinFlap,
            "fin_twist" => ModeGroup::FinTwist,
            "body_bending" => ModeGroup::BodyBending,
            _ => ModeGroup::Other,
        }
    }

    /// Guessed from a mode's name when no artifact is at hand.
    pub fn from_name(name: &str) -> Self {
        if name.contains("flap") {
            ModeGroup::FinFlap
        } else if name.contains("twist") {
            ModeGroup::FinTwist
        } else if name.contains("bending") || name.starts_with("body") {
            ModeGroup::BodyBending
        } else {
            ModeGroup::Other
        }
    }
}

/// One figure of the set: drawn from the history, or skipped with the reason.
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedFigure {
    /// File stem (no extension), e.g. `alpha`.
    pub stem: String,
    /// Caption for the index page.
    pub caption: String,
    /// `Err(reason)` when the columns it needs are absent.
    pub plot: Result<TimePlot, String>,
}

/// Picks the columns of a figure from a history.
type ColumnSelector = Box<dyn Fn(&History) -> Vec<String>>;

/// A figure's recipe: which columns, with which legend labels.
struct Recipe {
    stem: &'static str,
    caption: &'static str,
    title: &'static str,
    y_label: &'static str,
    /// Column selector (empty when none of its columns exist).
    columns: ColumnSelector,
    /// What the selector looks for, for the skipped-figure note.
    wanted: &'static str,
}

fn exact(names: &'static [&'static str]) -> ColumnSelector {
    Box::new(move |h| {
        names
            .iter()
            .filter(|n| h.column(n).is_some())
            .map(|n| n.to_string())
            .collect()
    })
}

fn matching(pred: impl Fn(&str) -> bool + 'static) -> ColumnSelector {
    Box::new(move |h| h.channels.iter().filter(|c| pred(c)).cloned().collect())
}

/// An aerodynamic load column: contains `aero`, the part (`body`/`fin`) and the quantity
/// (`force`/`moment`), e.g. `aero_body_force_x` or `force_fin_aero_z`.
fn aero(part: &'static str, what: &'static str) -> ColumnSelector {
    matching(move |c| c.contains("aero") && c.contains(part) && c.contains(what))
}

/// The ground track: the nose tip's north position against its east position (inertial
/// x against y), when the history has them.
pub fn ground_track(h: &History) -> PlannedFigure {
    let plot = match (h.column("p_inertial_y"), h.column("p_inertial_x")) {
        (Some(east), Some(north)) => Ok(TimePlot {
            title: "Ground track".to_string(),
            x_label: "east (m)".to_string(),
            y_label: "north (m)".to_string(),
            series: vec![Series {
                label: "nose tip".to_string(),
                xs: east.to_vec(),
                ys: north.to_vec(),
            }],
            equal_axes_min_span: Some(ground_track_min_span(east, north)),
            ..TimePlot::default()
        }),
        _ => Err("no columns: wanted p_inertial_x, p_inertial_y".to_string()),
    };
    PlannedFigure {
        stem: "ground_track".to_string(),
        caption: "Ground track (inertial x north against y east), equal axes, each at least 10 m or 1 % of the range".to_string(),
        plot,
    }
}

/// Rows of `flutter_margin.csv` the margin marks: `trusted` 0 (a stated uncertainty: the transonic bridge)
/// or `in_grid` 0 (outside the boundary's grid); as time intervals reaching half-way to
/// the neighbouring rows.
pub fn untrusted_intervals(m: &History) -> Vec<(f64, f64)> {
    let t = m.time();
    let flag = |name: &str, r: usize| m.column(name).is_some_and(|c| c[r] == 0.0);
    let bad: Vec<bool> = (0..t.len())
        .map(|r| flag("trusted", r) || flag("in_grid", r))
        .collect();
    let mid = |a: usize, b: usize| 0.5 * (t[a] + t[b]);
    let mut out = Vec::new();
    let mut r = 0;
    while r < t.len() {
        if !bad[r] {
            r += 1;
            continue;
        }
        let start = r;
        while r + 1 < t.len() && bad[r + 1] {
            r += 1;
        }
        let a = if start == 0 {
            t[0]
        } else {
            mid(start - 1, start)
        };
        let b = if r + 1 == t.len() {
            t[r]
        } else {
            mid(r, r + 1)
        };
        out.push((a, b));
        r += 1;
    }
    out
}

/// The first row inside the grid whose speed margin `V_F / V`, divided by `1 + u` (its
/// `uncertainty`, the transonic bridge's; the verdict's conservative side), is below
/// `criterion`: `(t, mach, margin)` (the divided margin). Without an `uncertainty` column
/// (older files) a row with `trusted` 0 is left out, as the verdict then did.
pub fn first_violation(m: &History, criterion: f64) -> Option<(f64, f64, f64)> {
    let t = m.time();
    let (mach, margin) = (m.column("mach")?, m.column("speed_margin")?);
    let ok = |name: &str, r: usize| m.column(name).is_none_or(|c| c[r] != 0.0);
    let u = m.column("uncertainty");
    let counted = |r: usize| u.map_or(margin[r], |u| margin[r] / (1.0 + u[r]));
    (0..t.len())
        .find(|&r| (u.is_some() || ok("trusted", r)) && ok("in_grid", r) && counted(r) < criterion)
        .map(|r| (t[r], mach[r], counted(r)))
}

/// Flight Mach against the clamped fin's flutter Mach over time (`flutter_margin.csv`),
/// with the untrusted rows shaded and the first violation of `criterion` (`V_F / V`, 1.15
/// unless `summary.json` says otherwise) marked.
pub fn flutter_margin(m: &History, criterion: f64) -> PlannedFigure {
    let t = m.time().to_vec();
    let plot = match (m.column("mach"), m.column("flutter_mach")) {
        (Some(mach), Some(fm)) if !t.is_empty() => Ok(TimePlot {
            title: "Flight Mach and flutter Mach (fin clamped at its root)".to_string(),
            x_label: "t (s)".to_string(),
            y_label: "Mach".to_string(),
            series: vec![
                Series {
                    label: "flight".to_string(),
                    xs: t.clone(),
                    ys: mach.to_vec(),
                },
                Series {
                    label: "flutter".to_string(),
                    xs: t.clone(),
                    ys: fm.to_vec(),
                },
                Series {
                    label: format!("flutter / {criterion}"),
                    xs: t,
                    ys: fm.iter().map(|x| x / criterion).collect(),
                },
            ],
            shaded: untrusted_intervals(m),
            shaded_label: "transonic bridge (stated uncertainty) or outside the grid".to_string(),
            points: first_violation(m, criterion)
                .map(|(t, mach, margin)| MarkedPoint {
                    x: t,
                    y: mach,
                    label: format!("first violation: t = {t:.3} s, V_F/V = {margin:.3}"),
                })
                .into_iter()
                .collect(),
            ..TimePlot::default()
        }),
        _ => Err("flutter_margin.csv has no mach and flutter_mach columns".to_string()),
    };
    PlannedFigure {
        stem: "flutter_margin".to_string(),
        caption: format!(
            "Flight Mach against the flutter Mach of the clamped fin and the criterion line (V_F/V = {criterion}); rows with a stated uncertainty (transonic bridge) or outside the grid shaded, the first violation of the criterion (margin over 1 + u) marked"
        ),
        plot,
    }
}

/// The figure set for a history. `group_of` classifies a mode name (the part after
/// `eta_`): from the artifact's mode classes when available.
pub fn plan_figures(h: &History, group_of: &dyn Fn(&str) -> ModeGroup) -> Vec<PlannedFigure> {
    let modes = |g: ModeGroup| -> Vec<String> {
        h.channels
            .iter()
            .filter(|c| !c.starts_with("eta_dot_"))
            .filter(|c| c.strip_prefix("eta_").is_some_and(|m| group_of(m) == g))
            .cloned()
            .collect()
    };
    let (flap, twist, bending, other) = (
        modes(ModeGroup::FinFlap),
        modes(ModeGroup::FinTwist),
        modes(ModeGroup::BodyBending),
        modes(ModeGroup::Other),
    );
    let fixed = |v: Vec<String>| -> ColumnSelector { Box::new(move |_| v.clone()) };
    let recipes = vec![
        Recipe {
            stem: "alpha",
            caption: "Angle of attack and sideslip",
            title: "Angle of attack",
            y_label: "angle (deg)",
            columns: exact(&["alpha", "beta"]),
            wanted: "alpha, beta",
        },
        Recipe {
            stem: "fin_flap",
            caption: "Fin flap modal coordinates",
            title: "Fin flap modes",
            y_label: "modal coordinate eta (kg^1/2 m)",
            columns: fixed(flap),
            wanted: "eta_<mode> of fin_flap modes",
        },
        Recipe {
            stem: "fin_twist",
            caption: "Fin twist modal coordinates",
            title: "Fin twist modes",
            y_label: "modal coordinate eta (kg^1/2 m)",
            columns: fixed(twist),
            wanted: "eta_<mode> of fin_twist modes",
        },
        Recipe {
            stem: "body_bending",
            caption: "Body bending modal coordinates",
            title: "Body bending modes",
            y_label: "modal coordinate eta (kg^1/2 m)",
            columns: fixed(bending),
            wanted: "eta_<mode> of body_bending modes",
        },
        Recipe {
            stem: "other_modes",
            caption: "Other modal coordinates",
            title: "Other modes",
            y_label: "modal coordinate eta (kg^1/2 m)",
            columns: fixed(other),
            wanted: "eta_<mode> of modes of class other",
        },
        Recipe {
            stem: "velocity_axial",
            caption: "Axial velocity in body axes",
            title: "Axial velocity",
            y_label: "velocity (m/s)",
            columns: exact(&["v_body_x"]),
            wanted: "v_body_x",
        },
        Recipe {
            stem: "velocity_lateral",
            caption: "Lateral and normal velocities in body axes",
            title: "Lateral velocities",
            y_label: "velocity (m/s)",
            columns: exact(&["v_body_y", "v_body_z"]),
            wanted: "v_body_y, v_body_z",
        },
        Recipe {
            stem: "angular_velocity",
            caption: "Angular velocity in body axes",
            title: "Angular velocity",
            y_label: "angular velocity (rad/s)",
            columns: exact(&["omega_body_x", "omega_body_y", "omega_body_z"]),
            wanted: "omega_body_x, omega_body_y, omega_body_z",
        },
        Recipe {
            stem: "mach",
            caption: "Mach number",
            title: "Mach number",
            y_label: "Mach (-)",
            columns: exact(&["mach"]),
            wanted: "mach",
        },
        Recipe {
            stem: "altitude",
            caption: "Altitude of the nose tip",
            title: "Altitude",
            y_label: "altitude (m)",
            columns: exact(&["altitude"]),
            wanted: "altitude",
        },
        Recipe {
            stem: "speed",
            caption: "Inertial speed of the nose tip",
            title: "Speed",
            y_label: "speed (m/s)",
            columns: exact(&["speed"]),
            wanted: "speed",
        },
        Recipe {
            stem: "acceleration",
            caption: "Magnitude of the inertial acceleration of the nose tip",
            title: "Acceleration",
            y_label: "acceleration (m/s^2)",
            columns: exact(&["acceleration"]),
            wanted: "acceleration",
        },
        Recipe {
            stem: "dynamic_pressure",
            caption: "Dynamic pressure",
            title: "Dynamic pressure",
            y_label: "q (Pa)",
            columns: exact(&["dynamic_pressure"]),
            wanted: "dynamic_pressure",
        },
        Recipe {
            stem: "static_margin",
            caption: "Static margin from the run's coefficient tables (calibres; meaningful while the vehicle flies nose first, before deployment)",
            title: "Static margin",
            y_label: "static margin (cal)",
            columns: exact(&["static_margin"]),
            wanted: "static_margin",
        },
        Recipe {
            stem: "fin_root_stress",
            caption: "Fin root bending stress (5.6)",
            title: "Fin root stress",
            y_label: "stress (Pa)",
            columns: matching(|c| c.starts_with("fin") && c.ends_with("_root_stress")),
            wanted: "fin<i>_root_stress",
        },
        Recipe {
            stem: "body_aero_force",
            caption: "Body aerodynamic forces",
            title: "Body aerodynamic force",
            y_label: "force (N)",
            columns: aero("body", "force"),
            wanted: "columns containing `aero`, `body` and `force` (not written by `flexflight run` yet)",
        },
        Recipe {
            stem: "body_aero_moment",
            caption: "Body aerodynamic moments",
            title: "Body aerodynamic moment",
            y_label: "moment (N m)",
            columns: aero("body", "moment"),
            wanted: "columns containing `aero`, `body` and `moment` (not written by `flexflight run` yet)",
        },
        Recipe {
            stem: "fin_aero_force",
            caption: "Fin aerodynamic forces",
            title: "Fin aerodynamic force",
            y_label: "force (N)",
            columns: aero("fin", "force"),
            wanted: "columns containing `aero`, `fin` and `force` (not written by `flexflight run` yet)",
        },
        Recipe {
            stem: "fin_aero_moment",
            caption: "Fin aerodynamic moments",
            title: "Fin aerodynamic moment",
            y_label: "moment (N m)",
            columns: aero("fin", "moment"),
            wanted: "columns containing `aero`, `fin` and `moment` (not written by `flexflight run` yet)",
        },
        Recipe {
            stem: "attitude",
            caption: "Roll, pitch and yaw (Euler angles of C_BI, eq. 4.4.4)",
            title: "Attitude",
            y_label: "angle (deg)",
            columns: exact(&["roll", "pitch", "yaw"]),
            wanted: "roll, pitch, yaw",
        },
        Recipe {
            stem: "max_deformation",
            caption: "Largest elastic displacement over the FE nodes",
            title: "Maximum deformation",
            y_label: "displacement (m)",
            columns: exact(&["max_deformation"]),
            wanted: "max_deformation",
        },
        Recipe {
            stem: "energy",
            caption: "Kinetic, strain, gravitational and total energy (total conserved without thrust, aerodynamics and damping)",
            title: "Energies",
            y_label: "energy (J)",
            columns: exact(&[
                "energy_kinetic",
                "energy_strain",
                "energy_gravitational",
                "energy_total",
            ]),
            wanted: "energy_kinetic, energy_strain, energy_gravitational, energy_total",
        },
        Recipe {
            stem: "energy_strain",
            caption: "Strain energy of the elastic modes (too small to see beside the others)",
            title: "Strain energy",
            y_label: "energy (J)",
            columns: exact(&["energy_strain"]),
            wanted: "energy_strain",
        },
        Recipe {
            stem: "momentum",
            caption: "Linear momentum in inertial axes",
            title: "Linear momentum",
            y_label: "momentum (kg m/s)",
            columns: exact(&[
                "momentum_inertial_x",
                "momentum_inertial_y",
                "momentum_inertial_z",
            ]),
            wanted: "momentum_inertial_x, _y, _z",
        },
        Recipe {
            stem: "angular_momentum",
            caption: "Angular momentum about the centre of mass, inertial axes",
            title: "Angular momentum",
            y_label: "angular momentum (kg m^2/s)",
            columns: exact(&["h_cm_inertial_x", "h_cm_inertial_y", "h_cm_inertial_z"]),
            wanted: "h_cm_inertial_x, _y, _z",
        },
    ];
    let t = h.time().to_vec();
    recipes
        .into_iter()
        // Modes of class `other` are not part of the thesis' set: no entry when absent.
        .filter(|r| r.stem != "other_modes" || !(r.columns)(h).is_empty())
        .map(|r| {
            let cols = (r.columns)(h);
            let plot = if cols.is_empty() {
                Err(format!("no columns: wanted {}", r.wanted))
            } else {
                Ok(TimePlot {
                    title: r.title.to_string(),
                    x_label: "t (s)".to_string(),
                    y_label: r.y_label.to_string(),
                    series: cols
                        .iter()
                        .filter_map(|c| {
                            Some(Series {
                                label: c.clone(),
                                xs: t.clone(),
                                ys: if UNWRAPPED.contains(&c.as_str()) {
                                    unwrap_degrees(h.column(c)?)
                                } else {
                                    h.column(c)?.to_vec()
                                },
                            })
                        })
                        .collect(),
                    ..TimePlot::default()
                })
            };
            PlannedFigure {
                stem: r.stem.to_string(),
                caption: r.caption.to_string(),
                plot,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator for the property tests (PCG-style LCG).
    fn uniform(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Unwrapping: no jump of more than 180 deg between consecutive points, the same
    /// values modulo 360, and a walk with steps under 180 deg recovered up to one constant
    /// whole number of turns (Euler angles written wrapped to (-180, 180]).
    #[test]
    fn unwrapped_angles_never_jump_and_keep_their_values_modulo_360() {
        let wrap = |a: f64| a - 360.0 * ((a + 180.0) / 360.0).ceil() + 360.0;
        let mut seed = 32;
        for _ in 0..300 {
            let n = 2 + (uniform(&mut seed) * 400.0) as usize;
            let step = 179.0 * uniform(&mut seed);
            let mut a = 2000.0 * uniform(&mut seed) - 1000.0;
            let mut walk = Vec::with_capacity(n);
            for _ in 0..n {
                a += step * (2.0 * uniform(&mut seed) - 1.0);
                walk.push(a);
            }
            let wrapped: Vec<f64> = walk.iter().map(|a| wrap(*a)).collect();
            assert!(
                wrapped
                    .iter()
                    .all(|w| *w > -180.0 - 1e-9 && *w <= 180.0 + 1e-9)
            );
            let u = unwrap_degrees(&wrapped);
            assert!(u.windows(2).all(|w| (w[1] - w[0]).abs() <= 180.0));
            for (w, x) in wrapped.iter().zip(&u) {
                let turns = (x - w) / 360.0;
                assert!((turns - turns.round()).abs() < 1e-9, "{w} -> {x}");
            }
            let offset = u[0] - walk[0];
            assert!((offset / 360.0 - (offset / 360.0).round()).abs() < 1e-9);
            for (x, a) in u.iter().zip(&walk) {
                assert!((x - a - offset).abs() < 1e-6, "{x} {a} {offset}");
            }
        }
        let u = unwrap_degrees(&[170.0, f64::NAN, -170.0]);
        assert!(u[0] == 170.0 && u[1].is_nan() && u[2] == 190.0, "{u:?}");
    }

    /// The ground track's minimum span: 10 m for a vertical flight whose north position is
    /// round-off; 1 % of the range for a long one.
    #[test]
    fn ground_track_spans_at_least_ten_metres_or_a_hundredth_of_the_range() {
        let h = History {
            channels: ["t", "p_inertial_x", "p_inertial_y", "speed"]
                .map(String::from)
                .to_vec(),
            columns: vec![
                vec![0.0, 1.0, 2.0],
                vec![0.0, -2e-12, 2e-11],
                vec![0.0, 0.0, 0.0],
                vec![0.0, 1.0, 0.0],
            ],
        };
        let p = ground_track(&h).plot.unwrap();
        assert_eq!(p.equal_axes_min_span, Some(10.0));
        assert_eq!(ground_track_min_span(&[0.0, 3000.0], &[0.0, 4000.0]), 50.0);
    }

    #[test]
    fn untrusted_rows_and_the_first_violation() {
        let h = History {
            channels: ["t", "mach", "speed_margin", "trusted", "in_grid"]
                .map(String::from)
                .to_vec(),
            columns: vec![
                vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0],
                vec![0.5, 0.95, 1.0, 1.1, 0.8, 0.7],
                vec![2.0, 1.0, 1.05, 1.1, 1.12, 1.3],
                vec![1.0, 0.0, 0.0, 1.0, 1.0, 1.0],
                vec![1.0, 1.0, 1.0, 0.0, 1.0, 1.0],
            ],
        };
        assert_eq!(untrusted_intervals(&h), vec![(0.5, 3.5)]);
        // Rows 1-3 are untrusted; row 4 is the first trusted row below 1.15.
        assert_eq!(first_violation(&h, 1.15), Some((4.0, 0.8, 1.12)));
        assert_eq!(first_violation(&h, 1.1), None);
        let f = flutter_margin(&h, 1.15);
        assert!(f.plot.is_err(), "no flutter_mach column");
    }
    use crate::report::history::parse_history;
    use std::path::Path;

    #[test]
    fn figures_follow_the_columns() {
        let h = parse_history(
            "t,alpha,beta,eta_fin1_flap,eta_fin1_twist,eta_body_bending_y1,eta_dot_fin1_flap,mach\n0,1,0,0,0,0,0,0.8\n1,2,0,1,2,3,4,0.9\n",
            Path::new("h.csv"),
        )
        .unwrap();
        let figs = plan_figures(&h, &ModeGroup::from_name);
        let get = |s: &str| figs.iter().find(|f| f.stem == s).unwrap();
        let alpha = get("alpha").plot.as_ref().unwrap();
        assert_eq!(alpha.series.len(), 2);
        let flap = get("fin_flap").plot.as_ref().unwrap();
        assert_eq!(flap.series.len(), 1, "rates are not coordinates");
        assert_eq!(flap.series[0].label, "eta_fin1_flap");
        assert_eq!(
            get("body_bending").plot.as_ref().unwrap().series[0].ys,
            vec![0.0, 3.0]
        );
        assert!(get("energy").plot.is_err());
        assert!(get("body_aero_force").plot.is_err());
        assert!(
            figs.iter().all(|f| f.stem != "other_modes"),
            "omitted when empty"
        );
    }
}
