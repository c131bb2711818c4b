//! Checking the `motor NAME { ... }` block of a vehicle and reading thrust curves at check
//! time, so that a corrupt curve is a diagnostic on its own line before anything runs.

use std::path::Path;

use crate::diagnostics::Diagnostic;
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
    let text = match cx.loader.read(path) {
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

/// `motor NAME { curve, position, length, diameter, propellant_mass?, total_mass? }`.
/// The masses default to the RASP header's; a CSV curve (no header) needs both.
pub(crate) fn check_motor(cx: &mut Cx, b: &Block, structure: Option<&Structure>) -> Option<Motor> {
    let name = super::vehicle::block_name(cx, b)?;
    let mut fl = Fields::new(cx, format!("motor `{}`", name.value), b.header, &b.body);
    let curve_path = fl
        .required(cx, "curve", "\"motors/AeroTech_K1000T.eng\"")
        .and_then(|v| {
            let s = f::string(cx, v)?;
            cx.resolve_file(&s, v.span, "thrust curve")
                .map(|p| Spanned::new(p, v.span))
        });
    let position = fl
        .required(cx, "position", "(-2.0, 0, 0) m")
        .and_then(|v| f::vector3(cx, v, Dim::LENGTH));
    let length = fl
        .required(cx, "length", "396 mm")
        .and_then(|v| f::quantity(cx, v, Dim::LENGTH));
    let length = f::positive(length, cx);
    let diameter = fl
        .required(cx, "diameter", "75 mm")
        .and_then(|v| f::quantity(cx, v, Dim::LENGTH));
    let diameter = f::positive(diameter, cx);
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
        header_dimensions(cx, &curve, &curve_path, length, diameter);
    }
    let from_header = |given: Option<Option<Spanned<f64>>>,
                       header: Option<f64>,
                       cx: &mut Cx,
                       what: &str|
     -> Option<Spanned<f64>> {
        match (given, header) {
            (Some(g), _) => g,
            (None, Some(h)) => Some(Spanned::new(h, curve_path.span)),
            (None, None) => {
                cx.push(
                    Diagnostic::error(
                        "vdl::motor::mass",
                        format!("the thrust curve has no header: give the motor's `{what}`"),
                    )
                    .label(curve_path.span, "a CSV curve carries no masses")
                    .label(b.header, format!("add `{what} = ... kg` here")),
                );
                None
            }
        }
    };
    let propellant_mass = from_header(prop, curve.propellant_mass, cx, "propellant_mass");
    let total_mass = from_header(total, curve.total_mass, cx, "total_mass");
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

/// Warns (`vdl::motor::header`) where the motor's `length` or `diameter` contradicts the
/// `.eng` header's: the motor's cylinder sets its mass distribution and so the static margin
/// (the 0.30 m for the M1670's 757 mm moved it by 0.5 calibre).
fn header_dimensions(
    cx: &mut Cx,
    curve: &ThrustCurve,
    curve_path: &Spanned<std::path::PathBuf>,
    length: Option<Spanned<f64>>,
    diameter: Option<Spanned<f64>>,
) {
    for (what, given, header) in [
        ("length", length, curve.length),
        ("diameter", diameter, curve.diameter),
    ] {
        let (Some(g), Some(h)) = (given, header) else {
            continue;
        };
        // (1e-9 m: a value written 1 mm off is within the tolerance despite rounding.)
        if (g.value - h).abs() > HEADER_DIMENSION_TOL + 1e-9 {
            let mm = |x: f64| super::plausible::short(x * 1e3);
            cx.push(
                Diagnostic::warning(
                    "vdl::motor::header",
                    format!(
                        "the motor's {what} ({} mm) differs from its thrust curve's header ({} mm)",
                        mm(g.value),
                        mm(h)
                    ),
                )
                .label(g.span, format!("{what} {} mm", mm(g.value)))
                .label(curve_path.span, format!("the `.eng` header says {} mm", mm(h)))
                .with_help(format!(
                    "the motor's cylinder places its mass, and so the centre of mass and the static margin: write the header's {what}, or `expect_unusual = true` in the motor if the difference is meant"
                )),
            );
        }
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
