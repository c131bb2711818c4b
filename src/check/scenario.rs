//! Checking `scenario` blocks: the vehicle variant, initial conditions, stimuli, run settings.

use crate::diagnostics::Diagnostic;
use crate::syntax::Spanned;
use crate::syntax::ast::{Block, EntryKind, ValueKind};
use crate::syntax::print::value_text;
use crate::units::Dim;

use super::fields::{self as f, Fields};
use super::ir::*;
use super::overrides::{self, is_scenario_path};
use super::{Cx, Decls, OtherKind, SetOverride, patch, vehicle};

pub(crate) fn check_scenario(
    cx: &mut Cx,
    b: &Block,
    decls: &Decls,
    materials: &[Material],
    sets: &[SetOverride],
) -> Option<Scenario> {
    let name = b.name.as_ref()?;
    if super::fixture::is_tunnel_scenario(b) {
        cx.push(
            Diagnostic::error(
                "vdl::fixture::not_flown",
                format!(
                    "scenario `{}` tests a fixture in a wind tunnel: it is not flown",
                    name.name
                ),
            )
            .label(name.span, "a wind-tunnel scenario")
            .with_help("`flexflight analyze flutter FILE --scenario NAME` takes it"),
        );
        return None;
    }
    // Scenario-rooted `--set` paths patch the scenario itself.
    let scenario_sets: Vec<&SetOverride> =
        sets.iter().filter(|s| is_scenario_path(&s.path)).collect();
    let b = &patch(cx, b, &scenario_sets);
    let mut fl = Fields::new(cx, format!("scenario `{}`", name.name), b.header, &b.body);
    let vehicle_v = fl.required(cx, "vehicle", "sphads1");
    let with_b = fl.block("with");
    let launch_b = fl.block("launch");
    let initial_b = if launch_b.is_some() {
        fl.block("initial")
    } else {
        fl.required_block(cx, "initial")
    };
    let stimuli_b = fl.block("stimuli");
    let wind_b = fl.block("wind");
    let parachute_bs = fl.blocks("parachute");
    let motor_scale_b = fl.block("motor_scale");
    let run_b = fl.required_block(cx, "run");
    fl.finish(cx);

    // Resolve the vehicle and build the variant: base AST + `with` + vehicle `--set`.
    let vehicle_block = vehicle_v.and_then(|v| {
        let other = |kind, blocks| OtherKind {
            kind,
            blocks,
            label: None,
            help: None,
        };
        let others = [
            other("material", &decls.materials),
            other("scenario", &decls.scenarios),
            other("sweep", &decls.sweeps),
        ];
        super::reference(cx, v, "vehicle", &decls.vehicles, &others).map(|i| decls.vehicles[i])
    });
    let mut overrides_applied = Vec::new();
    let variant = vehicle_block.and_then(|vb| {
        let mut patched = vb.clone();
        if let Some(wb) = with_b {
            for e in &wb.body.entries {
                match &e.kind {
                    EntryKind::Assign(a) => {
                        if is_scenario_path(&a.path) {
                            cx.push(
                                Diagnostic::error("vdl::override::path", "`with` changes the vehicle; set initial conditions and run settings in their own blocks")
                                    .label(a.path_span(), "a scenario field, not a vehicle field"),
                            );
                            continue;
                        }
                        overrides_applied.push(Override { path: a.path_string(), value: value_text(&a.value), span: e.span });
                        if let Err(d) = overrides::apply(&mut patched.body, &a.path, &a.value) {
                            cx.push(d);
                        }
                    }
                    _ => cx.push(
                        Diagnostic::error("vdl::override::syntax", "a `with` block holds only `path = value` lines")
                            .label(e.span, "not an override"),
                    ),
                }
            }
        }
        for s in sets.iter().filter(|s| !is_scenario_path(&s.path)) {
            let span = s.path.first().map_or(s.value.span, |p| p.span.to(s.value.span));
            overrides_applied.push(Override {
                path: crate::syntax::ast::path_string(&s.path),
                value: value_text(&s.value),
                span,
            });
            if let Err(d) = overrides::apply(&mut patched.body, &s.path, &s.value) {
                cx.push(d);
            }
        }
        vehicle::check_vehicle(cx, &patched, materials)
    });

    let launch = launch_b.map(|lb| check_launch(cx, lb));
    let initial = match (launch_b, &launch, initial_b) {
        (Some(lb), _, Some(ib)) => {
            cx.push(
                Diagnostic::error(
                    "vdl::launch::initial",
                    "a scenario with a `launch` block starts at rest on the rail: it takes no `initial` block",
                )
                .label(ib.header, "remove this block")
                .label(lb.header, "the launch sets the initial state"),
            );
            None
        }
        (Some(_), Some(Some(l)), None) => Some(Initial {
            span: l.span,
            velocity: InitialVelocity::Body(Spanned::new([0.0; 3], l.span)),
            angular_velocity: Spanned::new([0.0; 3], l.span),
            attitude: Attitude::Euler(Spanned::new(
                [0.0, l.elevation.value, l.heading.value],
                l.span,
            )),
            position: InitialPosition::Altitude(l.site_altitude),
        }),
        (Some(_), _, None) => None,
        (None, _, ib) => ib.and_then(|ib| check_initial(cx, ib)),
    };
    let wind = wind_b.map(|wb| check_wind(cx, wb));
    let parachutes: Vec<Option<Parachute>> = parachute_bs
        .iter()
        .map(|pb| check_parachute(cx, pb))
        .collect();
    let stimuli = match stimuli_b {
        Some(sb) => check_stimuli(cx, sb),
        None => Some(Vec::new()),
    };
    let run = run_b.and_then(|rb| check_run(cx, rb));
    let motor_scale = motor_scale_b.map(|mb| {
        let m = check_motor_scale(cx, mb)?;
        if variant.as_ref().is_some_and(|v| v.motor.is_none()) {
            cx.push(
                Diagnostic::error(
                    "vdl::motor_scale::no_motor",
                    "`motor_scale` scales the vehicle's motor, and this vehicle has none",
                )
                .label(mb.header, "no `motor` to scale")
                .with_help("give the vehicle a `motor NAME { ... }` block, or remove this one"),
            );
            return None;
        }
        Some(m)
    });
    Some(Scenario {
        name: Spanned::new(name.name.clone(), name.span),
        span: b.header,
        vehicle: variant?,
        overrides: overrides_applied,
        initial: initial?,
        stimuli: stimuli?,
        run: run?,
        launch: match launch {
            Some(l) => Some(l?),
            None => None,
        },
        wind: match wind {
            Some(w) => Some(w?),
            None => None,
        },
        parachutes: parachutes.into_iter().collect::<Option<Vec<_>>>()?,
        motor_scale: match motor_scale {
            Some(m) => Some(m?),
            None => None,
        },
    })
}

/// `motor_scale { impulse (1), burn_time (1) }`: positive factors from 0.5 to 2 (a motor
/// lot scatters by a few per cent; a factor outside this range is a typo, not a motor).
fn check_motor_scale(cx: &mut Cx, b: &Block) -> Option<MotorScale> {
    let mut fl = Fields::new(cx, "the `motor_scale` block", b.header, &b.body);
    let mut factor = |cx: &mut Cx, name: &'static str| match fl.value(name) {
        Some(v) => f::check_range(
            f::number(cx, v),
            cx,
            |x| (0.5..=2.0).contains(&x),
            "a factor from 0.5 to 2",
        ),
        None => Some(Q::new(1.0, b.header)),
    };
    let impulse = factor(cx, "impulse");
    let burn_time = factor(cx, "burn_time");
    fl.finish(cx);
    Some(MotorScale {
        span: b.header,
        impulse: impulse?,
        burn_time: burn_time?,
    })
}

/// `launch { site_altitude, rail_length, elevation, heading }`.
fn check_launch(cx: &mut Cx, b: &Block) -> Option<Launch> {
    let mut fl = Fields::new(cx, "the `launch` block", b.header, &b.body);
    let site = f::check_range(
        fl.required(cx, "site_altitude", "0 m")
            .and_then(|v| f::quantity(cx, v, Dim::LENGTH)),
        cx,
        |h| (-500.0..=86_000.0).contains(&h),
        "a site altitude from -500 m to 86 km (the 1976 standard atmosphere)",
    );
    // The foot of the rail is the launch's only pad contact (runtime/flight.rs: it holds the
    // vehicle at rest until the thrust exceeds the weight's component along the rail). With
    // no rail the vehicle would start free, at rest on the pad, and sink under its weight
    // until the thrust caught up (the 1.6 cm and 347,058 steps): refused here.
    let rail = f::non_negative(
        fl.required(cx, "rail_length", "3 m")
            .and_then(|v| f::quantity(cx, v, Dim::LENGTH)),
        cx,
    );
    let rail = match rail {
        Some(r) if r.value == 0.0 => {
            cx.push(
                Diagnostic::error(
                    "vdl::launch::rail",
                    format!(
                        "a launch needs a rail longer than 0 m (rail_length = {} m): the foot of the rail is what holds the vehicle on the pad until its thrust exceeds its weight",
                        r.value
                    ),
                )
                .label(r.span, "no rail")
                .with_help("give the rail's length (the distance the vehicle travels along it before it flies free), or start the vehicle in flight with an `initial` block instead of `launch`"),
            );
            None
        }
        other => other,
    };
    let elevation = f::check_range(
        fl.required(cx, "elevation", "85 deg")
            .and_then(|v| f::quantity(cx, v, Dim::ANGLE)),
        cx,
        |e| e > 0.0 && e <= std::f64::consts::FRAC_PI_2 + 1e-12,
        "an elevation above the horizon, 0 < elevation <= 90 deg",
    );
    let heading = match fl.value("heading") {
        Some(v) => f::check_range(
            f::quantity(cx, v, Dim::ANGLE),
            cx,
            |h| (-2.0 * std::f64::consts::PI..=2.0 * std::f64::consts::PI).contains(&h),
            "a heading from -360 deg to 360 deg",
        ),
        None => Some(Spanned::new(0.0, b.header)),
    };
    fl.finish(cx);
    Some(Launch {
        span: b.header,
        site_altitude: site?,
        rail_length: rail?,
        elevation: elevation?,
        heading: heading?,
    })
}

/// `wind { speed, direction [, reference_height, exponent] }` or `wind { profile = [...] }`.
fn check_wind(cx: &mut Cx, b: &Block) -> Option<Wind> {
    let mut fl = Fields::new(cx, "the `wind` block", b.header, &b.body);
    let profile_v = fl.value("profile");
    let speed_v = fl.value("speed");
    let direction_v = fl.value("direction");
    let href_v = fl.value("reference_height");
    let exp_v = fl.value("exponent");
    fl.finish(cx);
    let speed_of = |cx: &mut Cx, v: &crate::syntax::ast::Value| {
        f::non_negative(f::quantity(cx, v, Dim::VELOCITY), cx)
    };
    let profile = match profile_v {
        Some(p) => {
            if let Some(extra) = speed_v.or(direction_v).or(href_v).or(exp_v) {
                cx.push(
                    Diagnostic::error(
                        "vdl::wind::profile",
                        "a wind `profile` table gives speed and direction at each height; it takes no other field",
                    )
                    .label(extra.span, "remove this field")
                    .label(p.span, "the table"),
                );
                return None;
            }
            let ValueKind::List(items) = &p.kind else {
                cx.push(
                    Diagnostic::error(
                        "vdl::type::mismatch",
                        format!(
                            "expected a list of `at(height, speed, direction)`, found {}",
                            p.describe()
                        ),
                    )
                    .label(p.span, "not a list"),
                );
                return None;
            };
            let mut points: Vec<WindPoint> = Vec::new();
            let mut ok = true;
            for item in items {
                let ValueKind::Call { name, args } = &item.kind else {
                    cx.push(
                        Diagnostic::error(
                            "vdl::type::mismatch",
                            format!(
                                "expected `at(height, speed, direction)`, found {}",
                                item.describe()
                            ),
                        )
                        .label(item.span, "not a table row"),
                    );
                    ok = false;
                    continue;
                };
                if name.name != "at" || args.len() != 3 {
                    cx.push(
                        Diagnostic::error(
                            "vdl::type::mismatch",
                            "a wind table row is `at(height, speed, direction)`",
                        )
                        .label(item.span, "write `at(100 m, 5 m/s, 270 deg)`"),
                    );
                    ok = false;
                    continue;
                }
                let h = f::quantity(cx, &args[0].value, Dim::LENGTH);
                let v = speed_of(cx, &args[1].value);
                let d = f::quantity(cx, &args[2].value, Dim::ANGLE);
                let (Some(h), Some(v), Some(d)) = (h, v, d) else {
                    ok = false;
                    continue;
                };
                if let Some(prev) = points.last() {
                    if h.value <= prev.height {
                        cx.push(
                            Diagnostic::error(
                                "vdl::wind::profile",
                                "wind table heights must increase strictly",
                            )
                            .label(h.span, "not above the previous height")
                            .label(prev.span, "previous row"),
                        );
                        ok = false;
                        continue;
                    }
                }
                points.push(WindPoint {
                    span: item.span,
                    height: h.value,
                    speed: v.value,
                    direction: d.value,
                });
            }
            if points.is_empty() && ok {
                cx.push(
                    Diagnostic::error("vdl::wind::profile", "a wind table needs at least one row")
                        .label(p.span, "empty"),
                );
                ok = false;
            }
            if points.len() > crate::runtime::stimuli::MAX_WIND_ROWS {
                cx.push(
                    Diagnostic::error(
                        "vdl::wind::profile",
                        format!(
                            "a wind table holds at most {} rows, this one has {}",
                            crate::runtime::stimuli::MAX_WIND_ROWS,
                            points.len()
                        ),
                    )
                    .label(p.span, "too many rows"),
                );
                ok = false;
            }
            if !ok {
                return None;
            }
            WindProfile::Table(points)
        }
        None => {
            let speed = match speed_v {
                Some(v) => speed_of(cx, v),
                None => {
                    cx.push(
                        Diagnostic::error(
                            "vdl::field::missing",
                            "the `wind` block needs a `speed` (or a `profile` table)",
                        )
                        .label(b.header, "`speed` is missing here")
                        .with_help("add a line such as `speed = 5 m/s`"),
                    );
                    None
                }
            };
            let direction = match direction_v {
                Some(v) => f::quantity(cx, v, Dim::ANGLE),
                None => {
                    cx.push(
                        Diagnostic::error("vdl::field::missing", "the `wind` block needs a `direction` (where the wind blows from, clockwise from north)")
                            .label(b.header, "`direction` is missing here")
                            .with_help("add a line such as `direction = 270 deg`"),
                    );
                    None
                }
            };
            match (href_v, exp_v) {
                (None, None) => WindProfile::Constant {
                    speed: speed?,
                    direction: direction?,
                },
                (Some(h), e) => {
                    let h = f::positive(f::quantity(cx, h, Dim::LENGTH), cx);
                    let e = match e {
                        Some(e) => f::check_range(
                            f::number(cx, e),
                            cx,
                            |x| (0.0..=1.0).contains(&x),
                            "a power-law exponent from 0 to 1",
                        ),
                        None => Some(Spanned::new(1.0 / 7.0, b.header)),
                    };
                    WindProfile::PowerLaw {
                        speed: speed?,
                        direction: direction?,
                        reference_height: h?,
                        exponent: e?,
                    }
                }
                (None, Some(e)) => {
                    cx.push(
                        Diagnostic::error(
                            "vdl::field::missing",
                            "a power-law wind needs the `reference_height` its `speed` is given at",
                        )
                        .label(e.span, "exponent without a reference height")
                        .with_help("add a line such as `reference_height = 10 m`"),
                    );
                    return None;
                }
            }
        }
    };
    Some(Wind {
        span: b.header,
        profile,
    })
}

/// `parachute NAME { cd_area, trigger = apogee | altitude(h) | time(t), lag }`.
fn check_parachute(cx: &mut Cx, b: &Block) -> Option<Parachute> {
    let name = match &b.name {
        Some(n) => Some(Spanned::new(n.name.clone(), n.span)),
        None => {
            cx.push(
                Diagnostic::error("vdl::name::missing", "a `parachute` needs a name")
                    .label(b.header, "write `parachute NAME {`"),
            );
            None
        }
    };
    let mut fl = Fields::new(cx, "a `parachute`", b.header, &b.body);
    let cd_area = f::positive(
        fl.required(cx, "cd_area", "1.5 m^2")
            .and_then(|v| f::quantity(cx, v, Dim::AREA)),
        cx,
    );
    let trigger = fl.required(cx, "trigger", "apogee").and_then(|v| {
        let t = match &v.kind {
            ValueKind::Name(id) if id.name == "apogee" => Some(Trigger::Apogee),
            ValueKind::Call { name, args } if name.name == "altitude" && args.len() == 1 => {
                f::non_negative(f::quantity(cx, &args[0].value, Dim::LENGTH), cx)
                    .map(|h| Trigger::Altitude(h.value))
            }
            ValueKind::Call { name, args } if name.name == "time" && args.len() == 1 => {
                f::non_negative(f::quantity(cx, &args[0].value, Dim::TIME), cx)
                    .map(|t| Trigger::Time(t.value))
            }
            _ => {
                cx.push(
                    Diagnostic::error("vdl::type::mismatch", format!("expected a parachute trigger, found {}", v.describe()))
                        .label(v.span, "not a trigger")
                        .with_help("write `apogee`, `altitude(300 m)` (on descent, above the ground) or `time(12 s)`"),
                );
                None
            }
        };
        t.map(|t| Spanned::new(t, v.span))
    });
    let lag = match fl.value("lag") {
        Some(v) => f::non_negative(f::quantity(cx, v, Dim::TIME), cx),
        None => Some(Spanned::new(0.0, b.header)),
    };
    fl.finish(cx);
    Some(Parachute {
        name: name?,
        cd_area: cd_area?,
        trigger: trigger?,
        lag: lag?,
    })
}

fn check_initial(cx: &mut Cx, b: &Block) -> Option<Initial> {
    let mut fl = Fields::new(cx, "the `initial` block", b.header, &b.body);
    let vel = fl.value("velocity");
    let mach = fl.value("mach");
    let velocity = match (vel, mach) {
        (Some(v), None) => f::vector3(cx, v, Dim::VELOCITY).map(InitialVelocity::Body),
        (None, Some(m)) => f::check_range(
            f::number(cx, m),
            cx,
            |x| (0.0..=10.0).contains(&x),
            "0 <= Mach <= 10",
        )
        .map(InitialVelocity::Mach),
        (Some(_), Some(m)) => {
            cx.push(
                Diagnostic::error(
                    "vdl::initial::velocity",
                    "give either `velocity` or `mach`, not both",
                )
                .label(m.span, "second speed"),
            );
            None
        }
        (None, None) => {
            fl.required(cx, "velocity", "(200, 0, 0) m/s");
            None
        }
    };
    let angular_velocity = match fl.value("angular_velocity") {
        Some(v) => f::vector3(cx, v, Dim::ANGULAR_VELOCITY),
        None => Some(Spanned::new([0.0; 3], b.header)),
    };
    let attitude = match fl.value("attitude") {
        None => Some(Attitude::Euler(Spanned::new([0.0; 3], b.header))),
        Some(v) => match &v.kind {
            ValueKind::Call { name, args } if name.name == "euler" && args.len() == 3 => {
                let a: Option<Vec<f64>> = args
                    .iter()
                    .map(|a| f::quantity(cx, &a.value, Dim::ANGLE).map(|q| q.value))
                    .collect();
                a.map(|a| Attitude::Euler(Spanned::new([a[0], a[1], a[2]], v.span)))
            }
            ValueKind::Call { name, args } if name.name == "quaternion" && args.len() == 4 => {
                let q: Option<Vec<f64>> = args
                    .iter()
                    .map(|a| f::number(cx, &a.value).map(|q| q.value))
                    .collect();
                q.and_then(|q| {
                    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
                    if (n - 1.0).abs() > 1e-6 {
                        cx.push(
                            Diagnostic::error(
                                "vdl::value::range",
                                format!("a quaternion must have unit norm (this one has {n:.6})"),
                            )
                            .label(v.span, "not normalised"),
                        );
                        return None;
                    }
                    Some(Attitude::Quaternion(Spanned::new(
                        [q[0] / n, q[1] / n, q[2] / n, q[3] / n],
                        v.span,
                    )))
                })
            }
            _ => {
                cx.push(
                    Diagnostic::error("vdl::type::mismatch", format!("expected an attitude, found {}", v.describe()))
                        .label(v.span, "not an attitude")
                        .with_help("write `euler(ROLL deg, PITCH deg, YAW deg)` or `quaternion(q0, q1, q2, q3)`"),
                );
                None
            }
        },
    };
    let alt = fl.value("altitude");
    let pos = fl.value("position");
    let position = match (alt, pos) {
        (Some(v), None) => f::check_range(
            f::quantity(cx, v, Dim::LENGTH),
            cx,
            |h| (-500.0..=86_000.0).contains(&h),
            "an altitude from -500 m to 86 km (the 1976 standard atmosphere)",
        )
        .map(InitialPosition::Altitude),
        (None, Some(v)) => f::vector3(cx, v, Dim::LENGTH).map(InitialPosition::Inertial),
        (Some(_), Some(p)) => {
            cx.push(
                Diagnostic::error(
                    "vdl::initial::position",
                    "give either `altitude` or `position`, not both",
                )
                .label(p.span, "second position"),
            );
            None
        }
        (None, None) => {
            fl.required(cx, "altitude", "5 km");
            None
        }
    };
    fl.finish(cx);
    Some(Initial {
        span: b.header,
        velocity: velocity?,
        angular_velocity: angular_velocity?,
        attitude: attitude?,
        position: position?,
    })
}

fn frame(cx: &mut Cx, fl: &mut Fields) -> Option<Frame> {
    match fl.value("frame") {
        Some(v) => f::keyword(
            cx,
            v,
            &[("body", Frame::Body), ("inertial", Frame::Inertial)],
        ),
        None => Some(Frame::Body),
    }
}

fn check_stimuli(cx: &mut Cx, b: &Block) -> Option<Vec<Stimulus>> {
    let mut fl = Fields::new(cx, "the `stimuli` block", b.header, &b.body);
    let gusts = fl.blocks("gust");
    let cosines = fl.blocks("one_minus_cosine");
    let sines = fl.blocks("sine");
    let turbs = fl.blocks("turbulence");
    fl.finish(cx);
    let mut out = Vec::new();
    let mut ok = true;
    let named = |cx: &mut Cx, sb: &Block| match &sb.name {
        Some(n) => Some(Spanned::new(n.name.clone(), n.span)),
        None => {
            cx.push(
                Diagnostic::error(
                    "vdl::name::missing",
                    format!("a `{}` needs a name", sb.kind.name),
                )
                .label(sb.header, format!("write `{} NAME {{`", sb.kind.name)),
            );
            None
        }
    };
    let time = |cx: &mut Cx, fl: &mut Fields, n: &'static str, ex: &str| {
        f::non_negative(
            fl.required(cx, n, ex)
                .and_then(|v| f::quantity(cx, v, Dim::TIME)),
            cx,
        )
    };
    for (blocks, cosine) in [(&gusts, false), (&cosines, true)] {
        for sb in blocks.iter() {
            let name = named(cx, sb);
            let mut fl = Fields::new(
                cx,
                format!(
                    "gust `{}`",
                    sb.name.as_ref().map_or("", |n| n.name.as_str())
                ),
                sb.header,
                &sb.body,
            );
            let start = time(cx, &mut fl, "start", "1 s");
            let duration = f::positive(
                fl.required(cx, "duration", "0.1 s")
                    .and_then(|v| f::quantity(cx, v, Dim::TIME)),
                cx,
            );
            let velocity = fl
                .required(cx, "velocity", "(0, 0, 5) m/s")
                .and_then(|v| f::vector3(cx, v, Dim::VELOCITY));
            let fr = frame(cx, &mut fl);
            fl.finish(cx);
            match (name, start, duration, velocity, fr) {
                (Some(name), Some(start), Some(duration), Some(velocity), Some(frame)) => {
                    out.push(Stimulus {
                        name,
                        kind: if cosine {
                            StimulusKind::OneMinusCosine {
                                start,
                                duration,
                                velocity,
                                frame,
                            }
                        } else {
                            StimulusKind::Gust {
                                start,
                                duration,
                                velocity,
                                frame,
                            }
                        },
                    })
                }
                _ => ok = false,
            }
        }
    }
    for sb in &sines {
        let name = named(cx, sb);
        let mut fl = Fields::new(cx, "a `sine` stimulus", sb.header, &sb.body);
        let start = time(cx, &mut fl, "start", "1 s");
        let duration = f::positive(
            fl.required(cx, "duration", "2 s")
                .and_then(|v| f::quantity(cx, v, Dim::TIME)),
            cx,
        );
        let amplitude = fl
            .required(cx, "amplitude", "(0, 0, 2) m/s")
            .and_then(|v| f::vector3(cx, v, Dim::VELOCITY));
        let frequency = f::positive(
            fl.required(cx, "frequency", "2 Hz")
                .and_then(|v| f::quantity(cx, v, Dim::FREQUENCY)),
            cx,
        );
        let fr = frame(cx, &mut fl);
        fl.finish(cx);
        match (name, start, duration, amplitude, frequency, fr) {
            (
                Some(name),
                Some(start),
                Some(duration),
                Some(amplitude),
                Some(frequency),
                Some(frame),
            ) => out.push(Stimulus {
                name,
                kind: StimulusKind::Sine {
                    start,
                    duration,
                    amplitude,
                    frequency,
                    frame,
                },
            }),
            _ => ok = false,
        }
    }
    for sb in &turbs {
        let name = named(cx, sb);
        let mut fl = Fields::new(cx, "a `turbulence` stimulus", sb.header, &sb.body);
        let model = fl.required(cx, "model", "dryden").and_then(|v| {
            f::keyword(
                cx,
                v,
                &[
                    ("dryden", TurbulenceModel::Dryden),
                    ("von_karman", TurbulenceModel::VonKarman),
                ],
            )
            .map(|m| Spanned::new(m, v.span))
        });
        let intensity = f::positive(
            fl.required(cx, "intensity", "1 m/s")
                .and_then(|v| f::quantity(cx, v, Dim::VELOCITY)),
            cx,
        );
        let scale = f::positive(
            fl.required(cx, "scale_length", "533 m")
                .and_then(|v| f::quantity(cx, v, Dim::LENGTH)),
            cx,
        );
        let seed = fl
            .required(cx, "seed", "1")
            .and_then(|v| f::integer(cx, v).map(|s| Spanned::new(s, v.span)));
        let start = time(cx, &mut fl, "start", "0 s");
        let duration = f::positive(
            fl.required(cx, "duration", "10 s")
                .and_then(|v| f::quantity(cx, v, Dim::TIME)),
            cx,
        );
        fl.finish(cx);
        match (name, model, intensity, scale, seed, start, duration) {
            (
                Some(name),
                Some(model),
                Some(intensity),
                Some(scale_length),
                Some(seed),
                Some(start),
                Some(duration),
            ) => out.push(Stimulus {
                name,
                kind: StimulusKind::Turbulence {
                    model,
                    intensity,
                    scale_length,
                    seed,
                    start,
                    duration,
                },
            }),
            _ => ok = false,
        }
    }
    ok.then_some(out)
}

fn check_run(cx: &mut Cx, b: &Block) -> Option<RunSettings> {
    let mut fl = Fields::new(cx, "the `run` block", b.header, &b.body);
    let stop = f::positive(
        fl.required(cx, "stop_time", "10 s")
            .and_then(|v| f::quantity(cx, v, Dim::TIME)),
        cx,
    );
    let integrator = match fl.value("integrator") {
        Some(v) => f::keyword(cx, v, &Integrator::NAMES).map(|i| Spanned::new(i, v.span)),
        None => Some(Spanned::new(Integrator::Dopri5, b.header)),
    };
    let tol = |cx: &mut Cx, fl: &mut Fields, n: &'static str, default: f64| match fl.value(n) {
        Some(v) => f::check_range(
            f::number(cx, v),
            cx,
            |x| x > 0.0 && x < 1.0,
            "a tolerance between 0 and 1",
        ),
        None => Some(Spanned::new(default, b.header)),
    };
    let rtol = tol(cx, &mut fl, "rtol", 1e-6);
    let atol = tol(cx, &mut fl, "atol", 1e-9);
    let dt = |cx: &mut Cx, fl: &mut Fields, n: &'static str, default: f64| match fl.value(n) {
        Some(v) => f::positive(f::quantity(cx, v, Dim::TIME), cx),
        None => Some(Spanned::new(default, b.header)),
    };
    let step = dt(cx, &mut fl, "step", 1e-4);
    let min_step = dt(cx, &mut fl, "min_step", 1e-12);
    let output = dt(cx, &mut fl, "output_interval", 1e-3);
    let ground = fl
        .value("stop_on_ground")
        .and_then(|v| f::boolean(cx, v))
        .unwrap_or(true);
    let max_alpha = fl.value("max_alpha").map(|v| {
        f::check_range(
            f::quantity(cx, v, Dim::ANGLE),
            cx,
            |x| x > 0.0 && x <= std::f64::consts::PI,
            "0 < alpha <= 180 deg",
        )
    });
    let model_limits = fl
        .value("model_limits")
        .and_then(|v| f::boolean(cx, v))
        .unwrap_or(true);
    let max_def = fl
        .value("max_deformation")
        .map(|v| f::positive(f::quantity(cx, v, Dim::LENGTH), cx));
    fl.finish(cx);
    let max_alpha = match max_alpha {
        Some(q) => Some(q?),
        None => None,
    };
    let max_deformation = match max_def {
        Some(q) => Some(q?),
        None => None,
    };
    if let (Some(o), Some(s)) = (&output, &stop) {
        if o.value > s.value {
            cx.push(
                Diagnostic::error(
                    "vdl::value::range",
                    "the output interval is longer than the run",
                )
                .label(o.span, "output interval")
                .label(s.span, "stop time"),
            );
            return None;
        }
    }
    if let (Some(o), Some(s)) = (&output, &stop) {
        if let Some(d) = history_size(o, s) {
            cx.push(d);
            return None;
        }
    }
    Some(RunSettings {
        span: b.header,
        stop_time: stop?,
        integrator: integrator?,
        rtol: rtol?,
        atol: atol?,
        step: step?,
        min_step: min_step?,
        output_interval: output?,
        stop_on_ground: ground,
        max_alpha,
        max_deformation,
        model_limits,
    })
}

/// The most output rows a run may ask for (`stop_time / output_interval + 1`).
///
/// Every row is kept in memory while the run lasts (`RunOutput::rows`, one `f64` per
/// column) and written to `history.csv` as text (the shortest round-trip form, at most 24
/// characters and a separator per value, cli/floatfmt.rs). A run writes at least the 24
/// rigid and 25 invariant channels ([`crate::plan::RIGID_CHANNELS`],
/// [`crate::plan::INVARIANT_CHANNELS`]), so 2,000,000 rows hold at least 0.78 GB of numbers
/// and up to 2.45 GB of text: flexflight's bound for one run on a workstation. The longest
/// example flight (600 s at 10 ms) writes 60,001 rows; a 1000 s flight at 1 ms, 1,000,001.
pub const MAX_OUTPUT_ROWS: f64 = 2_000_000.0;

/// Bytes of text a value of `history.csv` may take (24 characters and a separator).
const TEXT_BYTES_PER_VALUE: f64 = 25.0;

/// The error for an output interval that asks for more than [`MAX_OUTPUT_ROWS`] rows, with
/// the rows and the memory it implies.
fn history_size(output: &Q, stop: &Q) -> Option<crate::diagnostics::Diagnostic> {
    // Rows at 0, dt, 2 dt, ... up to the stop time (a ratio within 1e-9 of a whole number,
    // as 2 s / 1 us in floating point, counts as that number).
    let rows = (stop.value / output.value + 1e-9).floor() + 1.0;
    if rows <= MAX_OUTPUT_ROWS {
        return None;
    }
    let columns =
        (crate::plan::RIGID_CHANNELS.len() + crate::plan::INVARIANT_CHANNELS.len()) as f64;
    let numbers = rows * columns * 8.0;
    let text = rows * columns * TEXT_BYTES_PER_VALUE;
    Some(
        Diagnostic::error(
            "vdl::run::output_rows",
            format!(
                "output_interval = {} s over stop_time = {} s asks for {rows:.0} rows: with at least {columns:.0} columns that is at least {:.2} GB of numbers in memory and up to {:.2} GB of history.csv text; the limit is {MAX_OUTPUT_ROWS:.0} rows",
                output.value,
                stop.value,
                numbers / 1e9,
                text / 1e9
            ),
        )
        .label(output.span, "output interval")
        .label(stop.span, "stop time")
        .with_help(format!(
            "write a longer output interval: at least {} s for this stop time",
            stop.value / (MAX_OUTPUT_ROWS - 1.0)
        )),
    )
}
