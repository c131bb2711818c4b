//! Checking the `motor NAME { ... }` block of a vehicle and reading thrust curves at check
//! time, so that a corrupt curve is a diagnostic on its own line before anything runs.

use std::path::Path;

use crate::diagnostics::Diagnostic;
use crate::runtime::catalogue::{self, Lookup};
use crate::runtime::thrust::{ThrustCurve, ThrustCurveError};
use crate::syntax::ast::Block;
use crate::syntax::{Span, Spanned};
use crate::units::Dim;

use super::Cx;
use super::fields::{self as f, Fields};
use super::ir::{Motor, Structure};

/// Upper bound on a loaded motor's mean density over its declared cylinder, kg/m³ (solid
/// steel; see `check_motor`).
const MAX_MEAN_DENSITY: f64 = 7850.0;

/// Reads and checks a thrust curve (RASP `.eng` or CSV) named at `named_at`; a reader error
/// is reported on the curve file's line (code `vdl::motor::curve`).
pub(crate) fn read_curve(cx: &mut Cx, path: &Path, named_at: Span) -> Option<ThrustCurve> {
    let bundled = catalogue::bundled_text(path).map(|t| Ok(t.to_string()));
    let text = match bundled.unwrap_or_else(|| cx.loader.read(path)) {
        Ok(t) => t,
        Err(e) => {
            cx.push(
                Diagnostic::error(
                    "vdl::motor::curve",
                    format!("cannot read the thrust curve {}: {e}", path.display()),
                )
                .label(named_at, "named here"),
            );
            return None;
        }
    };
    let is_eng = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("eng"));
    let parsed = if is_eng {
        ThrustCurve::parse_eng(&text, path)
    } else {
        ThrustCurve::parse_csv(&text, path)
    };
    match parsed {
        Ok(c) => Some(c),
        Err(e) => {
            let mut d = Diagnostic::error("vdl::motor::curve", e.to_string());
            if let Some(line) = e.line() {
                if let Some((start, end)) = line_range(&text, line) {
                    let id = match cx.sources.find(path) {
                        Some(id) => id,
                        None => {
                            cx.sources
                                .add(path.to_path_buf(), path.display().to_string(), text)
                        }
                    };
                    d = d.label(Span::new(id, start, end), "here");
                }
            }
            cx.push(d.label(named_at, "thrust curve named here"));
            None
        }
    }
}

/// Resolves a motor `designation` (`"Cesaroni M1670"`) in the bundled catalogue to the
/// virtual path of its curve; not-found (`vdl::motor::designation`, with the nearest curves)
/// and ambiguous (`vdl::motor::ambiguous`, with the candidates) are errors at the string.
fn resolve_designation(
    cx: &mut Cx,
    written: &str,
    span: Span,
) -> Option<Spanned<std::path::PathBuf>> {
    let entries = catalogue::bundled();
    let makers = || {
        let mut m: Vec<&str> = entries
            .iter()
            .filter_map(|e| e.curve.maker.as_deref().map(catalogue::maker_name))
            .collect();
        m.sort_unstable();
        m.dedup();
        m.join(", ")
    };
    let d = match catalogue::parse_designation(written) {
        Ok(d) => d,
        Err(maker) => {
            let msg = if maker.is_empty() {
                "an empty motor designation".to_string()
            } else {
                format!("`{maker}` is not a motor manufacturer of the catalogue")
            };
            cx.push(
                Diagnostic::error("vdl::motor::designation", msg)
                    .label(span, "the designation")
                    .with_help(format!(
                        "write the motor's designation (`M1670`), optionally after its manufacturer ({})",
                        makers()
                    )),
            );
            return None;
        }
    };
    let list = |ks: &[usize]| {
        ks.iter()
            .map(|k| format!("`{}`", entries[*k].describe()))
            .collect::<Vec<_>>()
            .join(", ")
    };
    match catalogue::lookup(
        entries
            .iter()
            .map(|e| (e.curve.name.as_str(), e.curve.maker.as_deref())),
        &d,
    ) {
        Lookup::Found(k) => Some(Spanned::new(catalogue::bundled_path(entries[k].file), span)),
        Lookup::Ambiguous(ks) => {
            cx.push(
                Diagnostic::error(
                    "vdl::motor::ambiguous",
                    format!(
                        "motor `{written}` matches {} curves of the catalogue: {}",
                        ks.len(),
                        list(&ks)
                    ),
                )
                .label(span, "which one?")
                .with_help("write the full designation of one of them"),
            );
            None
        }
        Lookup::NotFound(near) => {
            let nearest = if near.is_empty() {
                String::new()
            } else {
                format!("; the nearest: {}", list(&near))
            };
            cx.push(
                Diagnostic::error(
                    "vdl::motor::designation",
                    format!("motor `{written}` is not in the bundled catalogue{nearest}"),
                )
                .label(span, "not found")
                .with_help(
                    "the catalogue is listed in motors/README.md; for another motor give its RASP `.eng` curve (the manufacturer's or thrustcurve.org's) as `curve = \"FILE.eng\"`",
                ),
            );
            None
        }
    }
}

/// Byte range of 1-based line `line` (without its line break).
fn line_range(text: &str, line: usize) -> Option<(usize, usize)> {
    let mut start = 0;
    for (k, l) in text.split_inclusive('\n').enumerate() {
        if k + 1 == line {
            let t = l.trim_end_matches(['\n', '\r']);
            return Some((start, start + t.len().max(1).min(l.len())));
        }
        start += l.len();
    }
    None
}

/// `motor NAME { curve | designation, position, length?, diameter?, propellant_mass?,
/// total_mass? }`. The dimensions and masses default to the RASP header's; a CSV curve (no
/// header) needs all four. A `designation` is resolved in the bundled catalogue
/// ([`crate::runtime::catalogue`]) and names its curve by the catalogue's virtual path.
pub(crate) fn check_motor(cx: &mut Cx, b: &Block, structure: Option<&Structure>) -> Option<Motor> {
    let name = super::vehicle::block_name(cx, b)?;
    let mut fl = Fields::new(cx, format!("motor `{}`", name.value), b.header, &b.body);
    let curve_v = fl.value("curve");
    let designation_v = fl.value("designation");
    let curve_path = match (curve_v, designation_v) {
        (Some(c), Some(d)) => {
            cx.push(
                Diagnostic::error(
                    "vdl::motor::source",
                    "a motor takes its thrust curve from a `curve` file or a catalogue `designation`, not both",
                )
                .label(c.span, "a curve file")
                .label(d.span, "a designation")
                .with_help("remove one of them"),
            );
            None
        }
        (None, None) => {
            cx.push(
                Diagnostic::error(
                    "vdl::motor::source",
                    format!("motor `{}` has no thrust curve", name.value),
                )
                .label(b.header, "this motor")
                .with_help(
                    "name a motor of the bundled catalogue (`designation = \"Cesaroni M1670\"`) or a curve file (`curve = \"motors/AeroTech_K1000T.eng\"`)",
                ),
            );
            None
        }
        (Some(c), None) => f::string(cx, c).and_then(|s| {
            cx.resolve_file(&s, c.span, "thrust curve")
                .map(|p| Spanned::new(p, c.span))
        }),
        (None, Some(d)) => f::string(cx, d).and_then(|s| resolve_designation(cx, &s, d.span)),
    };
    let position = fl
        .required(cx, "position", "(-2.0, 0, 0) m")
        .and_then(|v| f::vector3(cx, v, Dim::LENGTH));
    let length = fl
        .value("length")
        .map(|v| f::positive(f::quantity(cx, v, Dim::LENGTH), cx));
    let diameter = fl
        .value("diameter")
        .map(|v| f::positive(f::quantity(cx, v, Dim::LENGTH), cx));
    let prop = fl
        .value("propellant_mass")
        .map(|v| f::positive(f::quantity(cx, v, Dim::MASS), cx));
    let total = fl
        .value("total_mass")
        .map(|v| f::positive(f::quantity(cx, v, Dim::MASS), cx));
    let expect_unusual = fl
        .value("expect_unusual")
        .and_then(|v| f::boolean(cx, v))
        .unwrap_or(false);
    fl.finish(cx);
    let curve_path = curve_path?;
    let curve = read_curve(cx, &curve_path.value, curve_path.span)?;
    if !expect_unusual {
        header_values(
            cx,
            &curve,
            &curve_path,
            [
                ("length", length.flatten(), curve.length),
                ("diameter", diameter.flatten(), curve.diameter),
                ("propellant_mass", prop.flatten(), curve.propellant_mass),
                ("total_mass", total.flatten(), curve.total_mass),
            ],
        );
    }
    let from_header = |given: Option<Option<Spanned<f64>>>,
                       header: Option<f64>,
                       cx: &mut Cx,
                       what: &str,
                       unit: &str|
     -> Option<Spanned<f64>> {
        let code = if unit == "kg" {
            "vdl::motor::mass"
        } else {
            "vdl::field::missing"
        };
        match (given, header) {
            (Some(g), _) => g,
            (None, Some(h)) => Some(Spanned::new(h, curve_path.span)),
            (None, None) => {
                cx.push(
                    Diagnostic::error(
                        code,
                        format!("the thrust curve has no header: give the motor's `{what}`"),
                    )
                    .label(
                        curve_path.span,
                        "a CSV curve carries no dimensions or masses",
                    )
                    .label(b.header, format!("add `{what} = ... {unit}` here")),
                );
                None
            }
        }
    };
    let length = from_header(length, curve.length, cx, "length", "mm");
    let diameter = from_header(diameter, curve.diameter, cx, "diameter", "mm");
    let propellant_mass = from_header(prop, curve.propellant_mass, cx, "propellant_mass", "kg");
    let total_mass = from_header(total, curve.total_mass, cx, "total_mass", "kg");
    let (position, length, diameter) = (position?, length?, diameter?);
    let (propellant_mass, total_mass) = (propellant_mass?, total_mass?);
    let mut ok = true;
    if propellant_mass.value > total_mass.value {
        cx.push(
            Diagnostic::error(
                "vdl::motor::mass",
                format!(
                    "the propellant ({} kg) is heavier than the loaded motor ({} kg)",
                    propellant_mass.value, total_mass.value
                ),
            )
            .label(propellant_mass.span, "propellant mass")
            .label(total_mass.span, "total mass (casing + propellant)"),
        );
        ok = false;
    }
    // A motor heavier than the vehicle. The motor is a component of the vehicle here (its
    // casing and grain are added to the structure), so the lift-off vehicle always outweighs
    // it, and a rail launch whose thrust cannot lift the whole vehicle is `plan::no_liftoff`.
    // What remains to catch at `check` is a motor heavier than any motor of its size can be
    // (a unit slip, `2575 kg` for `2575 g`, or a wrong header): the loaded motor fills at most
    // its declared cylinder, `V = π D² L / 4`, so its mean density `m_total / V` cannot exceed
    // that of the densest material it is built of. Solid-motor casings are steel, aluminium or
    // composite, the propellant and liners lighter still: the bound is solid steel,
    // 7850 kg/m³ (EN 1991-1-1, Annex A, Table A.4: steel 77.0-78.5 kN/m³). Real motors sit far
    // below it (the AeroTech K1000T: 2.575 kg in 75 mm x 396 mm, 1472 kg/m³; the Cesaroni
    // M1670: 5.231 kg in 75 mm x 757 mm, 1564 kg/m³), so the bound leaves real motors a
    // factor of 5 and flags any mass slip larger than that (a unit slip is a factor 1000).
    let volume = std::f64::consts::PI * diameter.value * diameter.value * length.value / 4.0;
    let mean_density = total_mass.value / volume;
    if mean_density > MAX_MEAN_DENSITY {
        cx.push(
            Diagnostic::error(
                "vdl::motor::heavy",
                format!(
                    "the loaded motor ({} kg) is heavier than a solid steel cylinder of its size ({:.3} kg): its mean density would be {:.0} kg/m^3",
                    total_mass.value,
                    MAX_MEAN_DENSITY * volume,
                    mean_density
                ),
            )
            .label(total_mass.span, "total mass (casing + propellant)")
            .label(length.span, "motor length")
            .label(diameter.span, "motor diameter")
            .with_help("check the mass unit (kg or g) or the `.eng` header's masses"),
        );
        ok = false;
    }
    if curve.total_impulse() <= 0.0 {
        cx.push(
            Diagnostic::error(
                "vdl::motor::curve",
                "the thrust curve delivers no impulse: the propellant could never burn",
            )
            .label(curve_path.span, "a curve with zero thrust throughout"),
        );
        ok = false;
    }
    let p = position.value;
    if p[1] != 0.0 || p[2] != 0.0 {
        cx.push(
            Diagnostic::error(
                "vdl::motor::geometry",
                "the motor must sit on the body axis (y = z = 0)",
            )
            .label(position.span, "off the axis"),
        );
        ok = false;
    }
    if let Some(Structure::Generate(g)) = structure {
        let (l_body, d_body) = (g.body.length.value, g.body.diameter.value);
        let (aft, fore) = (p[0], p[0] + length.value);
        if aft < -l_body * (1.0 + 1e-12) || fore > 0.0 {
            cx.push(
                Diagnostic::error(
                    "vdl::motor::geometry",
                    format!(
                        "the motor (x from {aft} m to {fore} m) does not fit inside the body (0 to -{l_body} m)"
                    ),
                )
                .label(position.span, "aft end of the motor")
                .label(length.span, "its length, forward from the aft end"),
            );
            ok = false;
        }
        // The narrowest section over the motor's length (transitions are monotone: their ends
        // and the motor's ends are the candidates).
        let mut d_body = d_body;
        if !g.body.transitions.is_empty() {
            let mut xs = vec![aft, fore.min(0.0)];
            for t in g.body.transition_geoms() {
                xs.extend(
                    [-t.start, -t.end()]
                        .into_iter()
                        .filter(|x| *x <= fore && *x >= aft),
                );
            }
            d_body = xs
                .iter()
                .map(|&x| 2.0 * g.body.radius_at(x))
                .fold(f64::INFINITY, f64::min);
        }
        let inner = d_body - 2.0 * g.body.wall.value;
        if diameter.value > inner * (1.0 + 1e-12) {
            cx.push(
                Diagnostic::error(
                    "vdl::motor::geometry",
                    format!(
                        "the motor ({} mm) is wider than the body's bore ({} mm)",
                        diameter.value * 1e3,
                        inner * 1e3
                    ),
                )
                .label(diameter.span, "motor diameter")
                .label(g.body.diameter.span, "body outer diameter"),
            );
            ok = false;
        }
    } else if p[0] > 0.0 || p[0] + length.value > 0.0 {
        cx.push(
            Diagnostic::error(
                "vdl::motor::geometry",
                "the motor reaches ahead of the nose (x > 0)",
            )
            .label(position.span, "aft end of the motor")
            .label(length.span, "its length, forward from the aft end"),
        );
        ok = false;
    }
    ok.then_some(Motor {
        name,
        header: b.header,
        curve: curve_path,
        position,
        length,
        diameter,
        propellant_mass,
        total_mass,
    })
}

/// How far a motor's `length` or `diameter` may differ from the RASP header's before
/// `check` questions it, m. The header gives both in whole millimetres (RASP format: "diameter
/// and length in mm"), so a value written to the millimetre is within 0.5 mm of it; 1 mm
/// leaves room for a value written in inches.
pub const HEADER_DIMENSION_TOL: f64 = 1e-3;

/// A motor field checked against the header: (name, the value written, the header's).
type HeaderValue<'a> = (&'a str, Option<Spanned<f64>>, Option<f64>);

/// How far a motor's `propellant_mass` or `total_mass` may differ from the RASP header's
/// before `check` questions it, relative. RASP headers give the masses in kg to three or more
/// significant figures (the M1670's 3.101 and 5.231 kg, the C6's 0.0108 kg), so the header's
/// value rewritten to three significant figures (in g or kg) is within 0.5 % of it.
pub const HEADER_MASS_REL_TOL: f64 = 5e-3;

/// Warns (`vdl::motor::header`) where the motor's `length`, `diameter`, `propellant_mass` or
/// `total_mass` contradicts the `.eng` header's: the motor's cylinder and masses set its mass
/// distribution and so the static margin (the 0.30 m for the M1670's 757 mm moved it
/// by 0.5 calibre), and the propellant mass the exhaust velocity.
fn header_values(
    cx: &mut Cx,
    curve: &ThrustCurve,
    curve_path: &Spanned<std::path::PathBuf>,
    given: [HeaderValue; 4],
) {
    let is_catalogue = crate::runtime::catalogue::bundled_text(&curve_path.value).is_some();
    let source = if is_catalogue {
        format!("the catalogue's `{}` header", curve.name)
    } else {
        "the `.eng` header".to_string()
    };
    for (what, given, header) in given {
        let (Some(g), Some(h)) = (given, header) else {
            continue;
        };
        let is_mass = what.ends_with("mass");
        // (1e-9 m: a value written 1 mm off is within the tolerance despite rounding.)
        let off = if is_mass {
            (g.value - h).abs() > HEADER_MASS_REL_TOL * h
        } else {
            (g.value - h).abs() > HEADER_DIMENSION_TOL + 1e-9
        };
        if !off {
            continue;
        }
        let show = |x: f64| {
            if is_mass {
                format!("{} kg", super::plausible::short(x))
            } else {
                format!("{} mm", super::plausible::short(x * 1e3))
            }
        };
        cx.push(
            Diagnostic::warning(
                "vdl::motor::header",
                format!(
                    "the motor's {what} ({}) differs from its thrust curve's header ({})",
                    show(g.value),
                    show(h)
                ),
            )
            .label(g.span, format!("{what} {}", show(g.value)))
            .label(curve_path.span, format!("{source} says {}", show(h)))
            .with_help(format!(
                "the motor's cylinder and masses place its mass, and so the centre of mass and the static margin: leave `{what}` out to use the header's, or write `expect_unusual = true` in the motor if the difference is meant"
            )),
        );
    }
}

impl ThrustCurveError {
    /// The 1-based line of the curve file the error is on, if it has one.
    pub fn line(&self) -> Option<usize> {
        match self {
            ThrustCurveError::MissingField { line, .. }
            | ThrustCurveError::ExtraField { line, .. }
            | ThrustCurveError::NotFinite { line, .. }
            | ThrustCurveError::NegativeThrust { line, .. }
            | ThrustCurveError::NegativeTime { line, .. }
            | ThrustCurveError::TimeNotIncreasing { line, .. }
            | ThrustCurveError::NonPositive { line, .. }
            | ThrustCurveError::PropellantExceedsTotal { line, .. }
            | ThrustCurveError::BadHeader { line, .. } => Some(*line),
            ThrustCurveError::Io { .. } | ThrustCurveError::EmptyCurve { .. } => None,
        }
    }
}
