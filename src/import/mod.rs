//! `flexflight import`: an OpenRocket design (`.ork`: plain XML, gzip or ZIP) or a RockSim
//! design (`.rkt`, [`rocksim`]) becomes a commented vehicle file with a scenario per stored
//! simulation.
//!
//! Pipeline: [`container::decode`] -> XML (roxmltree, byte ranges kept so that every
//! diagnostic points at its element's line and column) -> [`Design`] (the components the
//! vehicle language can say, in metres from the nose tip) -> text ([`emit`]).
//!
//! What the language cannot say is a diagnostic naming the component: an error where the
//! flight would be a different rocket (a second stage, a step in diameter without a transition,
//! an assembly mass override, a material without stiffness, a motor
//! not in the catalogue), a warning where the rocket is kept and one property is approximated
//! (a nose shape other than a cone generated as a cone with its exact mass restored, a
//! component's surface finish other than the vehicle's). Launch lugs and rail buttons become
//! `launch_lug` and `rail_button` blocks (their drag; their masses stay among the masses).
//! Nothing is written on an error.
//!
//! Masses: OpenRocket stores densities and dimensions and computes masses; so does this
//! importer, with OpenRocket's formulas (component classes under
//! core/src/main/java/info/openrocket/core/rocketcomponent/, read at commit 8fa969d8): tubes
//! and rings pi (r_o^2 - r_i^2) L rho, parachutes canopy area pi d^2/4 times the surface
//! density plus line count x line length x line density, shock cords length x line density.
//! A mass override replaces the component's own mass (and a CG override its centre), and the
//! comment says so.

pub mod catalogue;
pub mod container;
pub mod emit;
mod rocksim;
pub mod shapes;

use std::path::{Path, PathBuf};

use roxmltree::Node;

use crate::diagnostics::Diagnostic;
use crate::syntax::{FileId, SourceMap, Span};

use shapes::NoseShape;

/// Import options.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Directories searched for `.eng` thrust curves before the bundled catalogue.
    pub motor_dirs: Vec<PathBuf>,
    /// Elastic constants for materials the standard library does not map.
    pub materials: Vec<GivenMaterial>,
    /// `--motor DESIGNATION`: the motor to fly, resolved in the catalogue as `motor {
    /// designation }` is; it supplies the motor of a design that stores none and replaces
    /// the design's own (a warning), and must fit the motor mount (`emit::named_motor`).
    pub motor: Option<String>,
}

/// `--material 'NAME=E,nu'`: the stiffness of an OpenRocket material, by its name.
#[derive(Clone, Debug, PartialEq)]
pub struct GivenMaterial {
    pub name: String,
    /// Young's modulus, Pa.
    pub e: f64,
    pub nu: f64,
}

impl GivenMaterial {
    /// Parses `NAME=E,nu` with E in GPa or MPa (`Cardboard=2.5 GPa,0.3`).
    pub fn parse(s: &str) -> Result<GivenMaterial, String> {
        let (name, rest) = s
            .rsplit_once('=')
            .ok_or_else(|| format!("`{s}`: expected NAME=E,nu (e.g. 'Cardboard=2.5 GPa,0.3')"))?;
        let (e, nu) = rest
            .split_once(',')
            .ok_or_else(|| format!("`{s}`: expected NAME=E,nu (e.g. 'Cardboard=2.5 GPa,0.3')"))?;
        let e = e.trim();
        let (num, scale) = if let Some(v) = e.strip_suffix("GPa") {
            (v, 1e9)
        } else if let Some(v) = e.strip_suffix("MPa") {
            (v, 1e6)
        } else {
            return Err(format!("`{e}`: give E with its unit, GPa or MPa"));
        };
        let e: f64 = num
            .trim()
            .parse()
            .map_err(|_| format!("`{num}` is not a number"))?;
        let nu: f64 = nu
            .trim()
            .parse()
            .map_err(|_| format!("`{nu}` is not a number"))?;
        if !(e.is_finite() && e > 0.0 && nu > 0.0 && nu < 0.5) {
            return Err(format!("`{s}`: need E > 0 and 0 < nu < 0.5"));
        }
        Ok(GivenMaterial {
            name: name.trim().to_string(),
            e: e * scale,
            nu,
        })
    }
}

/// A successful import.
#[derive(Debug)]
pub struct Imported {
    /// The vehicle file's text.
    pub vdl: String,
    /// Thrust curves to write beside it: (file name, text).
    pub motors: Vec<(String, String)>,
    /// Warnings (approximations), also written as comments in the file.
    pub warnings: Vec<Diagnostic>,
}

/// Reads `path` and builds the vehicle file. The design text is added to `sources` so that
/// the diagnostics render with their line and column.
pub fn import_design(
    path: &Path,
    opts: &Options,
    sources: &mut SourceMap,
) -> Result<Imported, Vec<Diagnostic>> {
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) => {
            return Err(vec![
                Diagnostic::error(
                    "import::read",
                    format!("cannot read {}: {e}", path.display()),
                )
                .with_help("give the path of an OpenRocket .ork file"),
            ]);
        }
    };
    let (xml, entry) = match container::decode(&bytes) {
        Ok(x) => x,
        Err(e) => {
            let id = sources.add(path.to_path_buf(), path.display().to_string(), "");
            return Err(vec![
                Diagnostic::error("import::container", format!("{}: {}", path.display(), e.0))
                    .label(Span::new(id, 0, 0), "in this file"),
            ]);
        }
    };
    let name = match &entry {
        Some(e) => format!("{} ({e})", path.display()),
        None => path.display().to_string(),
    };
    let file = sources.add(path.to_path_buf(), name, xml.as_str());
    let doc = match roxmltree::Document::parse(&xml) {
        Ok(d) => d,
        Err(e) => {
            // A file cut short: roxmltree reports the root as never closed, at 1:1; name the
            // innermost element the file ends inside, at its start tag, and the end.
            let open = open_at_end(&xml);
            if let (true, Some(&(name, at))) = (
                matches!(
                    e,
                    roxmltree::Error::UnexpectedEndOfStream | roxmltree::Error::UnclosedRootNode
                ),
                open.last(),
            ) {
                let path: Vec<&str> = open.iter().map(|(n, _)| *n).collect();
                let end = xml.len();
                return Err(vec![
                    Diagnostic::error(
                        "import::xml",
                        format!(
                            "the design ends inside `<{name}>` ({}): the file is cut short",
                            path.join(" > ")
                        ),
                    )
                    .label(
                        Span::new(file, at, at + name.len() + 1),
                        "opened here, never closed",
                    )
                    .label(Span::new(file, end, end), "the file ends here")
                    .with_help("the file may be truncated: save or download it again"),
                ]);
            }
            let pos = e.pos();
            let off = offset_of(&xml, pos.row as usize, pos.col as usize);
            return Err(vec![
                Diagnostic::error(
                    "import::xml",
                    format!("the design is not well-formed XML: {e}"),
                )
                .label(Span::new(file, off, off), "here")
                .with_help("the file may be truncated or corrupt"),
            ]);
        }
    };
    let mut cx = Cx {
        file,
        text: &xml,
        diags: Vec::new(),
    };
    let design = read_design(&mut cx, &doc, path);
    if cx.diags.iter().any(Diagnostic::is_error) {
        return Err(cx.diags);
    }
    let Some(mut design) = design else {
        return Err(cx.diags);
    };
    let catalogue = catalogue::load(&opts.motor_dirs);
    if let Some(m) = &opts.motor {
        if !emit::named_motor(&mut cx, &mut design, m, &catalogue) {
            return Err(cx.diags);
        }
    }
    let out = emit::emit(&mut cx, &design, opts, &catalogue);
    if cx.diags.iter().any(Diagnostic::is_error) {
        return Err(cx.diags);
    }
    let (vdl, motors) = out.ok_or_else(|| cx.diags.clone())?;
    Ok(Imported {
        vdl,
        motors,
        warnings: cx.diags,
    })
}

/// The elements still open where `xml` ends, outermost first, each with the byte offset of
/// its start tag's `<`: a scan of the tags alone (comments, CDATA sections, processing
/// instructions and declarations skipped; an end tag closes the innermost open element, a
/// tag cut short by the end of the file is not counted), for the diagnostic of a file cut
/// short, whose well-formedness error roxmltree reports at the root.
fn open_at_end(xml: &str) -> Vec<(&str, usize)> {
    let b = xml.as_bytes();
    let mut open: Vec<(&str, usize)> = Vec::new();
    let mut i = 0;
    while let Some(k) = xml[i..].find('<') {
        let at = i + k;
        let rest = &xml[at..];
        let skip = [
            ("<!--", "-->"),
            ("<![CDATA[", "]]>"),
            ("<?", "?>"),
            ("<!", ">"),
        ]
        .iter()
        .find(|(o, _)| rest.starts_with(o));
        if let Some((o, c)) = skip {
            match rest[o.len()..].find(c) {
                Some(e) => i = at + o.len() + e + c.len(),
                None => break,
            }
            continue;
        }
        // The tag's end, outside quoted attribute values.
        let mut j = at + 1;
        let mut quote = None;
        while j < b.len() {
            match (quote, b[j]) {
                (None, b'"' | b'\'') => quote = Some(b[j]),
                (Some(q), c) if c == q => quote = None,
                (None, b'>') => break,
                _ => {}
            }
            j += 1;
        }
        if j >= b.len() {
            break;
        }
        let tag = &xml[at + 1..j];
        if let Some(name) = tag.strip_prefix('/') {
            let name = name.trim();
            if let Some(p) = open.iter().rposition(|(n, _)| *n == name) {
                open.truncate(p);
            }
        } else if !tag.ends_with('/') {
            let end = tag
                .find(|c: char| c.is_whitespace() || c == '/')
                .unwrap_or(tag.len());
            open.push((&tag[..end], at));
        }
        i = j + 1;
    }
    open
}

fn offset_of(text: &str, row: usize, col: usize) -> usize {
    let mut off = 0;
    for (i, line) in text.split_inclusive('\n').enumerate() {
        if i + 1 == row {
            let c = line
                .char_indices()
                .nth(col.saturating_sub(1))
                .map_or(line.len(), |(b, _)| b);
            return (off + c).min(text.len());
        }
        off += line.len();
    }
    text.len()
}

pub(crate) struct Cx<'a> {
    file: FileId,
    text: &'a str,
    pub(crate) diags: Vec<Diagnostic>,
}

impl Cx<'_> {
    /// The span of an element's start tag.
    pub(crate) fn span(&self, n: Node) -> Span {
        let r = n.range();
        let end = self.text[r.start..r.end]
            .find('>')
            .map_or(r.end, |i| r.start + i + 1);
        Span::new(self.file, r.start, end)
    }

    pub(crate) fn error(&mut self, code: &'static str, n: Node, msg: String, label: &str) {
        let d = Diagnostic::error(code, msg).label(self.span(n), label);
        self.diags.push(d);
    }

    pub(crate) fn warn(&mut self, n: Node, msg: String) {
        let d = Diagnostic::warning("import::approximation", msg).label(self.span(n), "here");
        self.diags.push(d);
    }
}

/// A step in diameter where a body tube starts (at radius `tube.radius`) behind a part that
/// ends at radius `r_prev`, which the generated body cannot have (its radius changes only
/// along a transition): bridged when the tube is long enough, else `false` (the caller's
/// `import::diameter` error).
///
/// - A step of at most [`STEP_ABSORBED`] of the diameter (a nose shoulder 0.1 mm under its
///   tube's bore, as RockSim and OpenRocket designs often have) is taken as no step: the
///   tube keeps the radius ahead, its mass is restored as any tube's is; a warning.
/// - A larger step becomes a conical shoulder (or reducer) 45 degrees to the axis, of length
///   `|Δr|` taken from the front of the tube (which is shortened by as much): Barrowman's
///   normal force of a shoulder depends on its two areas only, not on its length (Barrowman
///   1967, eq. 3-66; `aero::estimator`), so the step's normal force and centre of pressure are
///   kept to within the shoulder's length; its pressure drag is the estimator's of a 45-degree
///   shoulder, not of a blunt step (OpenRocket computes a step as a zero-length transition); a
///   warning says so. A tube shorter than four times the step is not bridged.
pub(crate) fn bridge_step(
    cx: &mut Cx,
    n: Node,
    tube: &mut Tube,
    r_prev: f64,
    ahead: &str,
    transitions: &mut Vec<ImpTransition>,
) -> bool {
    let dr = tube.radius - r_prev;
    if dr.abs() <= 1e-6 {
        return true;
    }
    if dr.abs() <= STEP_ABSORBED * 2.0 * tube.radius.max(r_prev) {
        cx.warn(
            n,
            format!(
                "body tube `{}` starts at diameter {:.3} mm, the {ahead} ends at {:.3} mm: a step of {:.3} mm, taken as none (the generated tube has the diameter ahead; its mass is kept)",
                tube.name,
                2e3 * tube.radius,
                2e3 * r_prev,
                2e3 * dr.abs()
            ),
        );
        tube.radius = r_prev;
        return true;
    }
    let len = dr.abs();
    if tube.length < 4.0 * len {
        return false;
    }
    cx.warn(
        n,
        format!(
            "body tube `{}` starts at diameter {:.3} mm, the {ahead} ends at {:.3} mm: the step is generated as a 45-degree conical {} of {:.1} mm at the tube's front (its normal force is the step's; its pressure drag that of a 45-degree {}, not of a blunt step)",
            tube.name,
            2e3 * tube.radius,
            2e3 * r_prev,
            if dr > 0.0 { "shoulder" } else { "reducer" },
            1e3 * len,
            if dr > 0.0 { "shoulder" } else { "reducer" },
        ),
    );
    transitions.push(ImpTransition {
        name: format!("step ahead of {}", tube.name),
        top: tube.top,
        length: len,
        r_fore: r_prev,
        r_aft: tube.radius,
        thickness: tube.thickness,
        filled: false,
        shape: NoseShape::Conical,
        clipped: false,
        material: tube.material.clone(),
        override_mass: None,
        override_cg: None,
        at: cx.span(n),
    });
    tube.top += len;
    tube.length -= len;
    true
}

/// A step in diameter at most this fraction of the diameter is taken as none
/// ([`bridge_step`]).
pub const STEP_ABSORBED: f64 = 0.01;

/// A material as OpenRocket stores it: a name and a density (bulk kg/m^3, surface kg/m^2,
/// line kg/m).
#[derive(Clone, Debug, PartialEq)]
pub struct OrMaterial {
    pub name: String,
    pub density: f64,
    /// Where it is first used (for the diagnostic asking for its stiffness).
    pub at: Span,
}

/// A mass the generated structure does not contain: point or distributed along [s0, s1]
/// (metres aft of the nose tip).
#[derive(Clone, Debug)]
pub struct MassItem {
    pub name: String,
    pub mass: f64,
    pub s0: f64,
    pub s1: f64,
    /// Why it is there (component kind, override, correction), for the comment.
    pub note: String,
}

#[derive(Clone, Debug)]
pub struct Nose {
    pub name: String,
    pub shape: NoseShape,
    pub length: f64,
    pub radius: f64,
    pub thickness: f64,
    pub filled: bool,
    pub material: OrMaterial,
    pub override_mass: Option<f64>,
    pub override_cg: Option<f64>,
}

#[derive(Clone, Debug)]
pub struct Tube {
    pub name: String,
    pub top: f64,
    pub length: f64,
    pub radius: f64,
    pub thickness: f64,
    pub material: OrMaterial,
    pub override_mass: Option<f64>,
}

/// A transition or boat tail (issue 34): fore end `top` m aft of the tip, radii resolved
/// (`auto` from the neighbours, as OpenRocket does).
#[derive(Clone, Debug)]
pub struct ImpTransition {
    pub name: String,
    pub top: f64,
    pub length: f64,
    pub r_fore: f64,
    pub r_aft: f64,
    pub thickness: f64,
    pub filled: bool,
    pub shape: NoseShape,
    /// OpenRocket's "clipped" profile (the nose profile cut at the smaller radius).
    pub clipped: bool,
    pub material: OrMaterial,
    pub override_mass: Option<f64>,
    pub override_cg: Option<f64>,
    pub at: Span,
}

#[derive(Clone, Debug)]
pub struct FinSet {
    pub name: String,
    pub count: u32,
    pub root: f64,
    pub tip: f64,
    pub span: f64,
    /// Leading-edge sweep distance, m.
    pub sweep: f64,
    pub thickness: f64,
    /// The language's `cross_section` keyword.
    pub cross_section: &'static str,
    /// Degrees.
    pub cant: f64,
    /// Leading edge of the root, metres aft of the tip.
    pub root_le: f64,
    pub material: OrMaterial,
    pub override_mass: Option<f64>,
    /// The planform (issue 34): OpenRocket's trapezoidal, elliptical or freeform fin set.
    pub outline: FinShape,
    /// Root fillets: radius (m) and material (`<filletradius>`, `<filletmaterial>`).
    pub fillet: Option<(f64, OrMaterial)>,
    /// The angle of each fin about the axis, degrees (`count` of them): OpenRocket's
    /// `<angleoffset>` plus 360 i/count; sets merged by [`arrange_fin_sets`] list their fins'.
    pub angles: Vec<f64>,
}

/// A fin set's planform as OpenRocket stores it.
#[derive(Clone, Debug, PartialEq)]
pub enum FinShape {
    Trapezoidal,
    /// `ellipticalfinset`: the half ellipse on `root` of height `span` (`tip` and `sweep` 0).
    Elliptical,
    /// `freeformfinset`: the `<finpoints>` (x aft of the root leading edge, y outward), m.
    Freeform(Vec<(f64, f64)>),
}

/// The design's fin sets of one stage as the language's (issue 34): sets that differ only in
/// their angles (a rocketeer's way to cant or place each fin of one set on its own, as
/// OpenRocket's "Simulation scripting" example does with three one-fin sets) are merged into
/// one set listing its fins' angles; the **aft-most** set (its root trailing edge furthest aft;
/// on a tie the larger planform area times count) becomes the unnamed `fins` block, the
/// vehicle's flexible, meshed set, and the others named further sets, fore to aft. The aft-most,
/// not the largest: it is the stabilising set whose flexibility and flutter a rocketeer asks
/// about, while forward sets are canards (rigid in the flight, `check::fin_sets`). `None` for
/// no set. Each merge is said in `notes`.
pub(crate) fn arrange_fin_sets(
    sets: Vec<FinSet>,
    notes: &mut Vec<String>,
) -> Option<(FinSet, Vec<FinSet>)> {
    let same = |a: &FinSet, b: &FinSet| {
        a.root == b.root
            && a.tip == b.tip
            && a.span == b.span
            && a.sweep == b.sweep
            && a.thickness == b.thickness
            && a.cross_section == b.cross_section
            && a.cant == b.cant
            && a.root_le == b.root_le
            && a.material.name == b.material.name
            && a.material.density == b.material.density
            && a.outline == b.outline
            && a.override_mass.is_none()
            && b.override_mass.is_none()
    };
    let mut merged: Vec<FinSet> = Vec::new();
    for s in sets {
        match merged.iter_mut().find(|m| same(m, &s)) {
            Some(m) => {
                notes.push(format!(
                    "fin set `{}` is fin set `{}` at other angles: merged into one set of their {} fins",
                    s.name,
                    m.name,
                    m.count + s.count
                ));
                m.count += s.count;
                m.angles.extend(s.angles);
                m.angles.sort_by(f64::total_cmp);
            }
            None => merged.push(s),
        }
    }
    let key = |f: &FinSet| (f.root_le + f.root, f64::from(f.count) * f.area());
    let primary = (0..merged.len()).max_by(|&i, &j| {
        let (a, b) = (key(&merged[i]), key(&merged[j]));
        a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1))
    })?;
    let p = merged.remove(primary);
    merged.sort_by(|a, b| a.root_le.total_cmp(&b.root_le));
    Some((p, merged))
}

impl FinSet {
    /// The default angles of `count` fins from OpenRocket's `<angleoffset>`, degrees.
    pub fn default_angles(count: u32, offset: f64) -> Vec<f64> {
        (0..count)
            .map(|i| offset + 360.0 * f64::from(i) / f64::from(count.max(1)))
            .collect()
    }

    /// Planform area of one fin, m².
    pub fn area(&self) -> f64 {
        match &self.outline {
            FinShape::Trapezoidal => 0.5 * (self.root + self.tip) * self.span,
            FinShape::Elliptical => 0.25 * std::f64::consts::PI * self.root * self.span,
            FinShape::Freeform(p) => {
                let mut a = 0.0;
                for k in 0..p.len() {
                    let (u, v) = (p[k], p[(k + 1) % p.len()]);
                    a += u.0 * v.1 - v.0 * u.1;
                }
                0.5 * a.abs()
            }
        }
    }
}

#[derive(Clone, Debug)]
pub struct MotorRef {
    pub config: String,
    pub designation: String,
    pub manufacturer: Option<String>,
    /// Ejection delay, s (`None`: plugged).
    pub delay: Option<f64>,
    pub length: Option<f64>,
    pub diameter: Option<f64>,
    pub at: Span,
}

#[derive(Clone, Debug)]
pub struct Mount {
    pub name: String,
    /// Aft end of the mount tube, metres aft of the tip.
    pub aft: f64,
    pub overhang: f64,
    pub motors: Vec<MotorRef>,
    /// The mount tube's inner diameter and length, m (where the design gives them): what a
    /// motor named at import must fit (`emit::named_motor`).
    pub bore: Option<f64>,
    pub length: Option<f64>,
    /// The mount's element.
    pub at: Span,
}

#[derive(Clone, Debug)]
pub enum Deploy {
    Apogee,
    /// Altitude on the way down, m.
    Altitude(f64),
    /// At the motor's ejection charge (burnout + delay).
    Ejection,
    Never,
}

#[derive(Clone, Debug)]
pub struct Recovery {
    pub name: String,
    pub cd: f64,
    pub cd_auto: bool,
    pub area: f64,
    pub deploy: Deploy,
    pub delay: f64,
}

#[derive(Clone, Debug)]
pub struct Simulation {
    pub name: String,
    pub config: Option<String>,
    pub rod_length: f64,
    pub rod_angle: f64,
    pub rod_direction: f64,
    pub wind_speed: f64,
    pub wind_turbulence: f64,
    /// Radians, as OpenRocket stores it.
    pub wind_direction: f64,
    pub into_wind: bool,
    pub site_altitude: f64,
    pub max_time: f64,
    pub apogee: Option<f64>,
    pub max_velocity: Option<f64>,
    pub time_to_apogee: Option<f64>,
    pub status: String,
}

/// Everything the importer read, in metres from the nose tip.
#[derive(Clone, Debug)]
pub struct Design {
    pub file: PathBuf,
    pub name: String,
    pub designer: Option<String>,
    pub version: String,
    pub creator: Option<String>,
    pub nose: Nose,
    pub tubes: Vec<Tube>,
    /// Transitions and boat tails, fore to aft.
    pub transitions: Vec<ImpTransition>,
    /// The flexible, meshed fin set (the aft-most: [`arrange_fin_sets`]).
    pub fins: FinSet,
    /// Further fin sets on the same stage (canards, ...), fore to aft: named `fins` blocks.
    pub more_fins: Vec<FinSet>,
    pub masses: Vec<MassItem>,
    pub mount: Option<Mount>,
    pub recovery: Vec<Recovery>,
    pub simulations: Vec<Simulation>,
    pub default_config: Option<String>,
    pub configs: Vec<String>,
    /// Notes for the file's header comment.
    pub notes: Vec<String>,
    /// The surface finish of the built-in drag model ([`choose_finish`]).
    pub finish: Finish,
    /// Launch lugs and rail buttons (their drag; their masses are among `masses`).
    pub guides: Vec<Guide>,
}

/// A launch lug or rail button of the design, in metres from the nose tip.
#[derive(Clone, Debug, PartialEq)]
pub struct Guide {
    pub name: String,
    pub kind: GuideKind,
}

#[derive(Clone, Debug, PartialEq)]
pub enum GuideKind {
    /// Fore end, length, outer and inner diameter.
    Lug {
        top: f64,
        length: f64,
        outer_diameter: f64,
        inner_diameter: f64,
    },
    /// Centre, outer diameter, total height, the notch's diameter and height.
    Button {
        centre: f64,
        outer_diameter: f64,
        height: f64,
        inner_diameter: f64,
        inner_height: f64,
    },
}

/// The vehicle's surface finish (`aero { finish }`): a name of
/// `aero::estimator::FINISHES`, and what the design said, for the comment.
#[derive(Clone, Debug, PartialEq)]
pub struct Finish {
    pub name: &'static str,
    pub roughness: f64,
    pub said: String,
}

/// The vehicle's finish from the finishes its components store (`found`: the component's
/// name, the finish's element, the finish's name in `aero::estimator::FINISHES` and the
/// design's own word for it): the one most components carry (the first of a tie, in design
/// order), with a warning naming each component whose finish differs (flexflight has one
/// surface finish per vehicle); OpenRocket's default, regular paint, with a note when the
/// design stores none.
pub(crate) fn choose_finish(
    cx: &mut Cx,
    found: &[(String, Node, &'static str, String)],
    notes: &mut Vec<String>,
) -> Finish {
    use crate::aero::estimator::FINISHES;
    let roughness = |name: &str| FINISHES.iter().find(|f| f.0 == name).map_or(0.0, |f| f.2);
    let mut best: Option<(&'static str, usize)> = None;
    for (_, _, name, _) in found {
        let n = found.iter().filter(|f| f.2 == *name).count();
        if best.is_none_or(|(_, m)| n > m) {
            best = Some((name, n));
        }
    }
    let Some((name, count)) = best else {
        notes.push(
            "the design stores no surface finish: OpenRocket's default, regular paint (60 um)"
                .into(),
        );
        return Finish {
            name: "regular_paint",
            roughness: crate::aero::estimator::DEFAULT_ROUGHNESS,
            said: "none stored: OpenRocket's default".into(),
        };
    };
    let said = found
        .iter()
        .find(|f| f.2 == name)
        .map(|f| f.3.clone())
        .unwrap_or_default();
    for (comp, fin_node, other, other_said) in found {
        if *other != name {
            cx.warn(
                *fin_node,
                format!(
                    "`{comp}`: its surface finish `{other_said}` ({} um) is taken as the vehicle's `{said}` ({} um): flexflight has one finish per vehicle",
                    roughness(other) * 1e6,
                    roughness(name) * 1e6
                ),
            );
        }
    }
    Finish {
        name,
        roughness: roughness(name),
        said: format!("{said} on {count} of {} components", found.len()),
    }
}

/// The `<finish>` elements of an OpenRocket stage's components (lower-case names of
/// OpenRocket's `ExternalComponent.Finish`, as its `ExternalComponentSaver` writes them); an
/// unknown one is an error at its element.
fn ork_finishes<'a, 'i>(
    cx: &mut Cx,
    stage: Node<'a, 'i>,
) -> Vec<(String, Node<'a, 'i>, &'static str, String)> {
    let mut found = Vec::new();
    for f in stage.descendants().filter(|n| n.has_tag_name("finish")) {
        let Some(comp) = f.parent_element() else {
            continue;
        };
        let text = f.text().unwrap_or("").trim().to_string();
        match crate::aero::estimator::FINISHES
            .iter()
            .find(|x| x.1.eq_ignore_ascii_case(&text))
        {
            Some(x) => found.push((comp_name(comp), f, x.0, text)),
            None => cx.error(
                "import::value",
                f,
                format!("`{}`: unknown surface finish `{text}`", comp_name(comp)),
                "unknown finish",
            ),
        }
    }
    found
}

impl Design {
    pub fn length(&self) -> f64 {
        let tubes = self
            .tubes
            .last()
            .map_or(self.nose.length, |t| t.top + t.length);
        self.transitions
            .last()
            .map_or(tubes, |t| tubes.max(t.top + t.length))
    }
}

fn child<'a, 'i>(n: Node<'a, 'i>, name: &str) -> Option<Node<'a, 'i>> {
    n.children().find(|c| c.has_tag_name(name))
}

fn text_of<'a>(n: Node<'a, '_>, name: &str) -> Option<&'a str> {
    child(n, name).and_then(|c| c.text()).map(str::trim)
}

/// A number field; `auto X` reads X; `auto` alone is `Ok(None)` as a missing field is.
fn num(cx: &mut Cx, n: Node, name: &str) -> Result<Option<f64>, ()> {
    let Some(c) = child(n, name) else {
        return Ok(None);
    };
    let t = c.text().unwrap_or("").trim();
    let t = t.strip_prefix("auto").map_or(t, str::trim);
    if t.is_empty() {
        return Ok(None);
    }
    match t.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(Some(v)),
        _ => {
            cx.error(
                "import::value",
                c,
                format!("`<{name}>` holds `{t}`, not a number"),
                "not a number",
            );
            Err(())
        }
    }
}

fn req(cx: &mut Cx, n: Node, name: &str, what: &str) -> Option<f64> {
    match num(cx, n, name) {
        Ok(Some(v)) => Some(v),
        Ok(None) => {
            cx.error(
                "import::value",
                n,
                format!("{what} has no `<{name}>`"),
                "in this component",
            );
            None
        }
        Err(()) => None,
    }
}

fn comp_name(n: Node) -> String {
    text_of(n, "name")
        .map(str::to_string)
        .unwrap_or_else(|| n.tag_name().name().to_string())
}

fn material(cx: &mut Cx, n: Node, tag: &str) -> Option<OrMaterial> {
    let m = child(n, tag)?;
    let density = m
        .attribute("density")
        .and_then(|d| d.trim().parse::<f64>().ok());
    let Some(density) = density.filter(|d| d.is_finite() && *d >= 0.0) else {
        cx.error(
            "import::value",
            m,
            format!("the material of `{}` has no valid density", comp_name(n)),
            "no density",
        );
        return None;
    };
    Some(OrMaterial {
        name: m.text().unwrap_or("").trim().to_string(),
        density,
        at: cx.span(m),
    })
}

/// Placement of a child of length `own` in a parent spanning [top, top + len]: OpenRocket's
/// `<axialoffset method=...>` (or the older `<position type=...>`).
fn place(n: Node, top: f64, len: f64, own: f64) -> f64 {
    let (method, off) = match child(n, "axialoffset").or_else(|| child(n, "position")) {
        Some(p) => (
            p.attribute("method")
                .or_else(|| p.attribute("type"))
                .unwrap_or("top")
                .to_string(),
            p.text()
                .and_then(|t| t.trim().parse::<f64>().ok())
                .unwrap_or(0.0),
        ),
        None => ("top".to_string(), 0.0),
    };
    match method.as_str() {
        "middle" => top + (len - own) / 2.0 + off,
        "bottom" => top + len - own + off,
        "absolute" => off,
        _ => top + off,
    }
}

/// A mass override (own mass only). An override of the subcomponents' mass is an assembly
/// override the generated structure cannot take: an error.
fn override_mass(cx: &mut Cx, n: Node) -> Option<f64> {
    let m = num(cx, n, "overridemass").ok().flatten()?;
    if text_of(n, "overridesubcomponentsmass") == Some("true") {
        cx.error(
            "import::override",
            n,
            format!(
                "`{}` overrides the mass of itself and its subcomponents ({m} kg): an assembly mass cannot be spread over the generated structure",
                comp_name(n)
            ),
            "assembly override",
        );
        return None;
    }
    Some(m)
}

struct Parent {
    top: f64,
    length: f64,
    inner_radius: f64,
}

struct Reader {
    guides: Vec<Guide>,
    masses: Vec<MassItem>,
    fins: Vec<FinSet>,
    mounts: Vec<Mount>,
    recovery: Vec<Recovery>,
}

fn read_design(cx: &mut Cx, doc: &roxmltree::Document, path: &Path) -> Option<Design> {
    let root = doc.root_element();
    if root.has_tag_name("RockSimDocument") {
        return rocksim::read(cx, root, path);
    }
    if !root.has_tag_name("openrocket") {
        cx.error(
            "import::format",
            root,
            format!(
                "not an OpenRocket design: the root element is `<{}>`, expected `<openrocket>`",
                root.tag_name().name()
            ),
            "root element",
        );
        return None;
    }
    let version = root.attribute("version").unwrap_or("?").to_string();
    let creator = root.attribute("creator").map(str::to_string);
    let Some(rocket) = child(root, "rocket") else {
        cx.error(
            "import::format",
            root,
            "the design has no `<rocket>`".into(),
            "here",
        );
        return None;
    };
    let name = text_of(rocket, "name").unwrap_or("rocket").to_string();
    let designer = text_of(rocket, "designer").map(str::to_string);
    let configs: Vec<String> = rocket
        .children()
        .filter(|c| c.has_tag_name("motorconfiguration"))
        .filter_map(|c| c.attribute("configid").map(str::to_string))
        .collect();
    let default_config = rocket
        .children()
        .filter(|c| c.has_tag_name("motorconfiguration"))
        .find(|c| c.attribute("default") == Some("true"))
        .and_then(|c| c.attribute("configid").map(str::to_string));
    let Some(subs) = child(rocket, "subcomponents") else {
        cx.error(
            "import::format",
            rocket,
            "the rocket has no components".into(),
            "here",
        );
        return None;
    };
    let stages: Vec<Node> = subs.children().filter(Node::is_element).collect();
    for s in &stages {
        if !s.has_tag_name("stage") {
            cx.error(
                "import::component",
                *s,
                format!(
                    "unknown component `<{}>` at the rocket's top level",
                    s.tag_name().name()
                ),
                "expected `<stage>`",
            );
        }
    }
    if stages.len() > 1 {
        let names: Vec<String> = stages.iter().map(|s| comp_name(*s)).collect();
        let mut d = Diagnostic::error(
            "import::multistage",
            format!(
                "the design has {} stages ({}): flexflight flies single-stage vehicles for now",
                stages.len(),
                names.join(", ")
            ),
        );
        for s in &stages {
            d = d.label(cx.span(*s), format!("stage `{}`", comp_name(*s)));
        }
        cx.diags.push(d.with_help(
            "remove the boosters in OpenRocket and import the sustainer alone, or model each stage as its own vehicle",
        ));
        return None;
    }
    let stage = *stages.first()?;
    for n in [rocket, stage] {
        if child(n, "overridemass").is_some() {
            cx.error(
                "import::override",
                n,
                format!("`{}` overrides the mass of the whole stage: an assembly mass cannot be spread over the generated structure", comp_name(n)),
                "stage mass override",
            );
        }
    }
    let ext: Vec<Node> = child(stage, "subcomponents")
        .map(|s| s.children().filter(Node::is_element).collect())
        .unwrap_or_default();
    let mut rd = Reader {
        guides: Vec::new(),
        masses: Vec::new(),
        fins: Vec::new(),
        mounts: Vec::new(),
        recovery: Vec::new(),
    };
    let mut notes = Vec::new();
    let mut nose: Option<Nose> = None;
    let mut tubes: Vec<Tube> = Vec::new();
    let mut transitions: Vec<ImpTransition> = Vec::new();
    // The body's components in order: (is a tube, index, node).
    let mut order: Vec<(bool, usize, Node)> = Vec::new();
    let mut s = 0.0;
    for (i, c) in ext.iter().enumerate() {
        let tag = c.tag_name().name();
        match tag {
            "nosecone" if i == 0 => {
                let nm = comp_name(*c);
                let what = format!("nose cone `{nm}`");
                let length = req(cx, *c, "length", &what);
                // `<thickness>filled</thickness>`: a solid nose (OpenRocket's `filled`).
                let solid = text_of(*c, "thickness") == Some("filled");
                let thickness = if solid {
                    Some(0.0)
                } else {
                    req(cx, *c, "thickness", &what)
                };
                let shape_s = text_of(*c, "shape").unwrap_or("conical");
                let k = num(cx, *c, "shapeparameter").ok().flatten().unwrap_or(1.0);
                let shape = NoseShape::from_ork(shape_s, k);
                if shape.is_none() {
                    cx.error(
                        "import::value",
                        *c,
                        format!("{what}: unknown shape `{shape_s}`"),
                        "unknown shape",
                    );
                }
                let radius = num(cx, *c, "aftradius").ok().flatten();
                let mat = material(cx, *c, "material");
                let filled = solid || text_of(*c, "filled") == Some("true");
                if text_of(*c, "isflipped") == Some("true") {
                    cx.error(
                        "import::unsupported",
                        *c,
                        format!("{what} is flipped (a tail cone): only a forward nose can be represented"),
                        "flipped",
                    );
                }
                let om = override_mass(cx, *c);
                let ocg = num(cx, *c, "overridecg").ok().flatten();
                if let (Some(length), Some(thickness), Some(shape), Some(mat)) =
                    (length, thickness, shape, mat)
                {
                    // `auto` without a value: the next tube's radius, resolved below.
                    nose = Some(Nose {
                        name: nm,
                        shape,
                        length,
                        radius: radius.unwrap_or(f64::NAN),
                        thickness,
                        filled,
                        material: mat,
                        override_mass: om,
                        override_cg: ocg,
                    });
                    // Shoulder: a tube (and cap) inside the first body tube.
                    let sl = num(cx, *c, "aftshoulderlength").ok().flatten().unwrap_or(0.0);
                    let sr = num(cx, *c, "aftshoulderradius").ok().flatten().unwrap_or(0.0);
                    let st = num(cx, *c, "aftshoulderthickness").ok().flatten().unwrap_or(0.0);
                    if sl > 0.0 && sr > 0.0 && st > 0.0 {
                        let rho = nose.as_ref().map_or(0.0, |n| n.material.density);
                        let ri = (sr - st).max(0.0);
                        let mut m = std::f64::consts::PI * (sr * sr - ri * ri) * sl * rho;
                        if text_of(*c, "aftshouldercapped") == Some("true") {
                            m += std::f64::consts::PI * ri * ri * st * rho;
                        }
                        rd.masses.push(MassItem {
                            name: format!("{} shoulder", nose.as_ref().map_or("", |n| &n.name)),
                            mass: m,
                            s0: length,
                            s1: length + sl,
                            note: "nose-cone shoulder, a tube of the nose's material inside the body".into(),
                        });
                    }
                    let nm2 = nose.as_ref().map(|n| n.name.clone()).unwrap_or_default();
                    if let Some(subs) = child(*c, "subcomponents") {
                        let p = Parent {
                            top: 0.0,
                            length,
                            inner_radius: radius.unwrap_or(0.0) - thickness,
                        };
                        read_internal(cx, &mut rd, subs, &p, &nm2);
                    }
                    s = length;
                }
            }
            "bodytube" => {
                let nm = comp_name(*c);
                let what = format!("body tube `{nm}`");
                let length = req(cx, *c, "length", &what);
                let thickness = req(cx, *c, "thickness", &what);
                let radius = num(cx, *c, "radius").ok().flatten();
                let mat = material(cx, *c, "material");
                let om = override_mass(cx, *c);
                if child(*c, "overridecg").is_some() {
                    cx.warn(*c, format!("{what}: its CG override is not representable (the tube is generated uniform); its mass is kept"));
                }
                if let (Some(length), Some(thickness), Some(mat)) = (length, thickness, mat) {
                    let radius = radius.unwrap_or(f64::NAN);
                    if let Some(subs) = child(*c, "subcomponents") {
                        let p = Parent {
                            top: s,
                            length,
                            inner_radius: radius - thickness,
                        };
                        read_internal(cx, &mut rd, subs, &p, &nm);
                    }
                    if let Some(mm) = child(*c, "motormount") {
                        let bore = 2.0 * (radius - thickness);
                        read_mount(cx, &mut rd, mm, &nm, s + length, (bore, length));
                    }
                    tubes.push(Tube {
                        name: nm,
                        top: s,
                        length,
                        radius,
                        thickness,
                        material: mat,
                        override_mass: om,
                    });
                    order.push((true, tubes.len() - 1, *c));
                    s += length;
                }
            }
            "nosecone" => cx.error(
                "import::unsupported",
                *c,
                format!("nose cone `{}` is not the first component: a second nose cannot be represented", comp_name(*c)),
                "not first",
            ),
            "transition" => {
                let nm = comp_name(*c);
                let what = format!("transition `{nm}`");
                let length = req(cx, *c, "length", &what);
                let solid = text_of(*c, "thickness") == Some("filled");
                let thickness = if solid {
                    Some(0.0)
                } else {
                    req(cx, *c, "thickness", &what)
                };
                let shape_s = text_of(*c, "shape").unwrap_or("conical");
                let k = num(cx, *c, "shapeparameter").ok().flatten().unwrap_or(1.0);
                let shape = NoseShape::from_ork(shape_s, k);
                if shape.is_none() {
                    cx.error(
                        "import::value",
                        *c,
                        format!("{what}: unknown shape `{shape_s}`"),
                        "unknown shape",
                    );
                }
                // `auto` (with or without OpenRocket's value after it): the neighbour's radius,
                // resolved below.
                let auto = |tag: &str| text_of(*c, tag).is_some_and(|t| t.starts_with("auto"));
                let r_fore = num(cx, *c, "foreradius").ok().flatten();
                let r_aft = num(cx, *c, "aftradius").ok().flatten();
                let mat = material(cx, *c, "material");
                let om = override_mass(cx, *c);
                let ocg = num(cx, *c, "overridecg").ok().flatten();
                if child(*c, "overridecd").is_some() {
                    cx.warn(*c, format!("{what}: its drag override is not representable (the built-in drag is computed); ignored"));
                }
                let filled = solid || text_of(*c, "filled") == Some("true");
                if let (Some(length), Some(thickness), Some(shape), Some(mat)) =
                    (length, thickness, shape, mat)
                {
                    for (end, s0) in [("fore", s), ("aft", s + length)] {
                        let sl = num(cx, *c, &format!("{end}shoulderlength")).ok().flatten().unwrap_or(0.0);
                        let sr = num(cx, *c, &format!("{end}shoulderradius")).ok().flatten().unwrap_or(0.0);
                        let st = num(cx, *c, &format!("{end}shoulderthickness")).ok().flatten().unwrap_or(0.0);
                        if sl > 0.0 && sr > 0.0 && st > 0.0 {
                            let ri = (sr - st).max(0.0);
                            let mut m = std::f64::consts::PI * (sr * sr - ri * ri) * sl * mat.density;
                            if text_of(*c, &format!("{end}shouldercapped")) == Some("true") {
                                m += std::f64::consts::PI * ri * ri * st * mat.density;
                            }
                            let (a, b) = if end == "fore" { (s0 - sl, s0) } else { (s0, s0 + sl) };
                            rd.masses.push(MassItem {
                                name: format!("{nm} {end} shoulder"),
                                mass: m,
                                s0: a,
                                s1: b,
                                note: "transition shoulder, a tube of the transition's material inside the body".into(),
                            });
                        }
                    }
                    if let Some(subs) = child(*c, "subcomponents") {
                        let p = Parent {
                            top: s,
                            length,
                            inner_radius: r_fore.unwrap_or(0.0).min(r_aft.unwrap_or(0.0)) - thickness,
                        };
                        read_internal(cx, &mut rd, subs, &p, &nm);
                    }
                    transitions.push(ImpTransition {
                        name: nm,
                        top: s,
                        length,
                        r_fore: if auto("foreradius") && r_fore.is_none() { f64::NAN } else { r_fore.unwrap_or(f64::NAN) },
                        r_aft: if auto("aftradius") && r_aft.is_none() { f64::NAN } else { r_aft.unwrap_or(f64::NAN) },
                        thickness,
                        filled,
                        shape,
                        clipped: text_of(*c, "shapeclipped") == Some("true"),
                        material: mat,
                        override_mass: om,
                        override_cg: ocg,
                        at: cx.span(*c),
                    });
                    order.push((false, transitions.len() - 1, *c));
                    s += length;
                }
            }
            "podset" | "parallelstage" | "boosterset" => cx.error(
                "import::unsupported",
                *c,
                format!("`{}` ({tag}) cannot be represented: pods and parallel boosters are not in the language", comp_name(*c)),
                "not representable",
            ),
            _ => cx.error(
                "import::component",
                *c,
                format!("unknown component `<{tag}>` (`{}`) on the stage", comp_name(*c)),
                "unknown component",
            ),
        }
    }
    if cx.diags.iter().any(Diagnostic::is_error) {
        return None;
    }
    let Some(mut nose) = nose else {
        cx.error(
            "import::unsupported",
            stage,
            "the design has no nose cone as its first component: the generated body starts with a nose".into(),
            "this stage",
        );
        return None;
    };
    if tubes.is_empty() {
        cx.error(
            "import::unsupported",
            stage,
            "the design has no body tube".into(),
            "this stage",
        );
        return None;
    }
    // Radii: `auto` resolves to the neighbour (a tube's and a transition's fore radius to the
    // section ahead, a transition's aft radius to the component behind, the nose's to the
    // first component); each component must start at the radius of the section ahead of it
    // (a step without a transition cannot be represented).
    let fores: Vec<Option<f64>> = order
        .iter()
        .map(|&(is_tube, i, _)| {
            let r = if is_tube {
                tubes[i].radius
            } else {
                transitions[i].r_fore
            };
            r.is_finite().then_some(r)
        })
        .collect();
    let explicit_fore = |k: usize| -> Option<f64> { fores.get(k).copied().flatten() };
    let r0 = if nose.radius.is_finite() {
        Some(nose.radius)
    } else {
        explicit_fore(0).or_else(|| tubes.iter().map(|t| t.radius).find(|r| r.is_finite()))
    };
    let Some(r0) = r0 else {
        cx.error(
            "import::value",
            stage,
            "no component gives the body radius".into(),
            "here",
        );
        return None;
    };
    nose.radius = r0;
    let mut r_cur = r0;
    let mut ahead = format!("nose `{}`", nose.name);
    for (k, &(is_tube, i, n)) in order.iter().enumerate() {
        let next = explicit_fore(k + 1);
        let (fore, name) = if is_tube {
            let t = &mut tubes[i];
            if !t.radius.is_finite() {
                t.radius = r_cur;
            }
            (t.radius, format!("body tube `{}`", t.name))
        } else {
            let t = &mut transitions[i];
            if !t.r_fore.is_finite() {
                t.r_fore = r_cur;
            }
            if !t.r_aft.is_finite() {
                t.r_aft = next.unwrap_or(t.r_fore);
            }
            (t.r_fore, format!("transition `{}`", t.name))
        };
        let bridged = is_tube && bridge_step(cx, n, &mut tubes[i], r_cur, &ahead, &mut transitions);
        if !bridged && (fore - r_cur).abs() > 1e-6 {
            cx.error(
                "import::diameter",
                n,
                format!(
                    "{name} starts at radius {:.4} mm, the {ahead} ends at {:.4} mm: a step in diameter without a transition cannot be represented",
                    fore * 1e3,
                    r_cur * 1e3,
                ),
                "another diameter",
            );
        }
        r_cur = if is_tube {
            tubes[i].radius
        } else {
            transitions[i].r_aft
        };
        ahead = name;
    }
    let fins = arrange_fin_sets(std::mem::take(&mut rd.fins), &mut notes);
    if fins.is_none() {
        cx.error(
            "import::unsupported",
            stage,
            "the design has no trapezoidal fin set: flexflight's vehicles have one".into(),
            "this stage",
        );
    }
    // Mounts without a motor are kept for `--motor` only where they are the design's one
    // mount: the mount with the motor is the one flown (as before mounts without motors were
    // kept), several mounts without a motor name no place for one.
    if rd.mounts.iter().any(|m| !m.motors.is_empty()) {
        rd.mounts.retain(|m| !m.motors.is_empty());
    } else if rd.mounts.len() > 1 {
        rd.mounts.clear();
    }
    if rd.mounts.len() > 1 {
        cx.error(
            "import::unsupported",
            stage,
            format!(
                "the design has {} motor mounts ({}): one motor is represented",
                rd.mounts.len(),
                rd.mounts
                    .iter()
                    .map(|m| m.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            "this stage",
        );
    }
    let sims = read_simulations(cx, root);
    let found = ork_finishes(cx, stage);
    let finish = choose_finish(cx, &found, &mut notes);
    if cx.diags.iter().any(Diagnostic::is_error) {
        return None;
    }
    notes.push(format!(
        "OpenRocket file format {version}{}",
        creator
            .as_deref()
            .map(|c| format!(", written by {c}"))
            .unwrap_or_default()
    ));
    // The steps bridged by `bridge_step` come after the design's own transitions.
    transitions.sort_by(|a, b| a.top.total_cmp(&b.top));
    Some(Design {
        file: path.to_path_buf(),
        name,
        designer,
        version,
        creator,
        nose,
        tubes,
        transitions,
        fins: fins.as_ref()?.0.clone(),
        more_fins: fins?.1,
        masses: rd.masses,
        mount: rd.mounts.pop(),
        recovery: rd.recovery,
        simulations: sims,
        default_config,
        configs,
        notes,
        finish,
        guides: rd.guides,
    })
}

/// A motor mount (`<motormount>` of the tube `name` ending at `aft`, of inner diameter `bore`
/// and length `length`): kept even without a motor, which `--motor` may then supply.
fn read_mount(
    cx: &mut Cx,
    rd: &mut Reader,
    mm: Node,
    name: &str,
    aft: f64,
    (bore, length): (f64, f64),
) {
    let overhang = num(cx, mm, "overhang").ok().flatten().unwrap_or(0.0);
    let mut motors = Vec::new();
    for m in mm.children().filter(|c| c.has_tag_name("motor")) {
        let Some(designation) = text_of(m, "designation") else {
            cx.error(
                "import::value",
                m,
                "a motor without `<designation>`".into(),
                "here",
            );
            continue;
        };
        motors.push(MotorRef {
            config: m.attribute("configid").unwrap_or("").to_string(),
            designation: designation.to_string(),
            manufacturer: text_of(m, "manufacturer").map(str::to_string),
            // `none`: a plugged motor (no ejection charge).
            delay: if text_of(m, "delay") == Some("none") {
                None
            } else {
                num(cx, m, "delay").ok().flatten()
            },
            length: num(cx, m, "length").ok().flatten(),
            diameter: num(cx, m, "diameter").ok().flatten(),
            at: cx.span(m),
        });
    }
    rd.mounts.push(Mount {
        name: name.to_string(),
        aft,
        overhang,
        motors,
        bore: (bore.is_finite() && bore > 0.0).then_some(bore),
        length: (length.is_finite() && length > 0.0).then_some(length),
        at: cx.span(mm),
    });
}

fn read_internal(cx: &mut Cx, rd: &mut Reader, subs: Node, p: &Parent, parent_name: &str) {
    use std::f64::consts::PI;
    // The largest inner-tube outer radius among the siblings: an `auto` centring ring's hole.
    let mut tube_r = 0.0f64;
    for c in subs.children().filter(|c| c.has_tag_name("innertube")) {
        if let Ok(Some(r)) = num(cx, c, "outerradius") {
            tube_r = tube_r.max(r);
        }
    }
    for c in subs.children().filter(Node::is_element) {
        let tag = c.tag_name().name();
        let nm = comp_name(c);
        let what = format!("{tag} `{nm}` (in `{parent_name}`)");
        let push = |cx: &mut Cx, rd: &mut Reader, mass: f64, len: f64, note: &str| {
            let top = place(c, p.top, p.length, len);
            let om = override_mass(cx, c);
            let (mass, note) = match om {
                Some(m) => (m, format!("{note}; mass overridden in the design ({m} kg)")),
                None => (mass, note.to_string()),
            };
            let (s0, s1) = match num(cx, c, "overridecg").ok().flatten() {
                Some(cg) => (top + cg, top + cg),
                None => (top, top + len),
            };
            let note = if child(c, "overridecg").is_some() {
                format!("{note}; CG overridden in the design")
            } else {
                note
            };
            rd.masses.push(MassItem {
                name: nm.clone(),
                mass,
                s0,
                s1,
                note,
            });
            top
        };
        match tag {
            "masscomponent" => {
                let m = req(cx, c, "mass", &what).unwrap_or(0.0);
                let len = num(cx, c, "packedlength")
                    .ok()
                    .flatten()
                    .or_else(|| num(cx, c, "length").ok().flatten())
                    .unwrap_or(0.0);
                push(cx, rd, m, len, "mass component");
            }
            "parachute" => {
                let d = req(cx, c, "diameter", &what).unwrap_or(0.0);
                let area = PI * d * d / 4.0;
                let mat = material(cx, c, "material").map_or(0.0, |m| m.density);
                let lc = num(cx, c, "linecount").ok().flatten().unwrap_or(0.0);
                let ll = num(cx, c, "linelength").ok().flatten().unwrap_or(0.0);
                let lm = material(cx, c, "linematerial").map_or(0.0, |m| m.density);
                let m = area * mat + lc * ll * lm;
                let len = num(cx, c, "packedlength").ok().flatten().unwrap_or(0.0);
                push(cx, rd, m, len, "parachute (canopy and lines)");
                let cd_text = text_of(c, "cd").unwrap_or("auto");
                let cd_auto = cd_text.starts_with("auto");
                // OpenRocket's automatic parachute CD is Parachute.DEFAULT_CD = 0.8.
                let cd = if cd_auto {
                    0.8
                } else {
                    num(cx, c, "cd").ok().flatten().unwrap_or(0.8)
                };
                let deploy = match text_of(c, "deployevent").unwrap_or("ejection") {
                    "apogee" => Deploy::Apogee,
                    "altitude" => Deploy::Altitude(
                        num(cx, c, "deployaltitude").ok().flatten().unwrap_or(200.0),
                    ),
                    "ejection" => Deploy::Ejection,
                    "never" => Deploy::Never,
                    other => {
                        cx.error(
                            "import::unsupported",
                            c,
                            format!("{what}: deployment event `{other}` cannot be represented (apogee, altitude or the motor's ejection can)"),
                            "deployment",
                        );
                        Deploy::Never
                    }
                };
                rd.recovery.push(Recovery {
                    name: nm.clone(),
                    cd,
                    cd_auto,
                    area,
                    deploy,
                    delay: num(cx, c, "deploydelay").ok().flatten().unwrap_or(0.0),
                });
            }
            "streamer" => {
                let l = num(cx, c, "striplength").ok().flatten().unwrap_or(0.0);
                let w = num(cx, c, "stripwidth").ok().flatten().unwrap_or(0.0);
                let mat = material(cx, c, "material").map_or(0.0, |m| m.density);
                let len = num(cx, c, "packedlength").ok().flatten().unwrap_or(0.0);
                push(cx, rd, l * w * mat, len, "streamer");
                cx.warn(c, format!("{what}: a streamer's drag is not represented (scenarios take parachutes); its mass is kept"));
            }
            "shockcord" => {
                let l = num(cx, c, "cordlength").ok().flatten().unwrap_or(0.0);
                let mat = material(cx, c, "material").map_or(0.0, |m| m.density);
                let len = num(cx, c, "packedlength").ok().flatten().unwrap_or(0.0);
                push(cx, rd, l * mat, len, "shock cord");
            }
            "innertube" | "tubecoupler" => {
                let len = req(cx, c, "length", &what).unwrap_or(0.0);
                let ro = num(cx, c, "outerradius")
                    .ok()
                    .flatten()
                    .unwrap_or(p.inner_radius);
                let t = req(cx, c, "thickness", &what).unwrap_or(0.0);
                let rho = material(cx, c, "material").map_or(0.0, |m| m.density);
                let ri = (ro - t).max(0.0);
                let m = PI * (ro * ro - ri * ri) * len * rho;
                if tag == "innertube" {
                    if let Some(cl) = text_of(c, "clusterconfiguration") {
                        if cl != "single" {
                            cx.error(
                                "import::unsupported",
                                c,
                                format!("{what}: a motor cluster (`{cl}`) cannot be represented: one motor on the axis can"),
                                "cluster",
                            );
                        }
                    }
                }
                let top = push(cx, rd, m, len, tag);
                if let Some(mm) = child(c, "motormount") {
                    read_mount(cx, rd, mm, &nm, top + len, (2.0 * ri, len));
                }
                if let Some(s) = child(c, "subcomponents") {
                    let q = Parent {
                        top,
                        length: len,
                        inner_radius: ri,
                    };
                    read_internal(cx, rd, s, &q, &nm);
                }
            }
            "centeringring" | "bulkhead" | "engineblock" => {
                let len = req(cx, c, "length", &what).unwrap_or(0.0);
                let ro = num(cx, c, "outerradius")
                    .ok()
                    .flatten()
                    .unwrap_or(p.inner_radius);
                let ri = match tag {
                    "bulkhead" => 0.0,
                    "engineblock" => {
                        let t = num(cx, c, "thickness").ok().flatten().unwrap_or(ro);
                        (ro - t).max(0.0)
                    }
                    _ => num(cx, c, "innerradius").ok().flatten().unwrap_or(tube_r),
                };
                let rho = material(cx, c, "material").map_or(0.0, |m| m.density);
                let n = num(cx, c, "instancecount")
                    .ok()
                    .flatten()
                    .unwrap_or(1.0)
                    .max(1.0);
                if n > 1.0 {
                    cx.warn(c, format!("{what}: {n} instances are placed as one mass of all of them at the first one's place"));
                }
                let m = n * PI * (ro * ro - ri * ri).max(0.0) * len * rho;
                push(cx, rd, m, len, tag);
            }
            "launchlug" => {
                let len = req(cx, c, "length", &what).unwrap_or(0.0);
                let r = req(cx, c, "radius", &what).unwrap_or(0.0);
                let t = num(cx, c, "thickness").ok().flatten().unwrap_or(0.0);
                let rho = material(cx, c, "material").map_or(0.0, |m| m.density);
                let ri = (r - t).max(0.0);
                let n = num(cx, c, "instancecount")
                    .ok()
                    .flatten()
                    .unwrap_or(1.0)
                    .max(1.0);
                let top = push(
                    cx,
                    rd,
                    n * PI * (r * r - ri * ri) * len * rho,
                    len,
                    "launch lug (off-axis mass placed on the axis)",
                );
                let sep = num(cx, c, "instanceseparation")
                    .ok()
                    .flatten()
                    .unwrap_or(0.0);
                for i in 0..n as usize {
                    rd.guides.push(Guide {
                        name: nm.clone(),
                        kind: GuideKind::Lug {
                            top: top + i as f64 * sep,
                            length: len,
                            outer_diameter: 2.0 * r,
                            inner_diameter: 2.0 * ri,
                        },
                    });
                }
            }
            "railbutton" => {
                let od = req(cx, c, "outerdiameter", &what).unwrap_or(0.0);
                let id = num(cx, c, "innerdiameter").ok().flatten().unwrap_or(0.0);
                let h = req(cx, c, "height", &what).unwrap_or(0.0);
                let base = num(cx, c, "baseheight").ok().flatten().unwrap_or(0.0);
                let flange = num(cx, c, "flangeheight").ok().flatten().unwrap_or(0.0);
                let n = num(cx, c, "instancecount")
                    .ok()
                    .flatten()
                    .unwrap_or(1.0)
                    .max(1.0);
                let sep = num(cx, c, "instanceseparation")
                    .ok()
                    .flatten()
                    .unwrap_or(0.0);
                let has = child(c, "overridemass").is_some();
                push(cx, rd, 0.0, 0.0, "rail button");
                // OpenRocket's rail button is `outerdiameter` long along the body.
                let top = place(c, p.top, p.length, od);
                if !has {
                    cx.warn(c, format!("{what}: a rail button's mass is not represented (give its mass as an override in OpenRocket to keep it); its drag is"));
                }
                let inner_height = (h - base - flange).max(0.0);
                let notch = id > 0.0 && id < od && inner_height > 0.0 && inner_height < h;
                for i in 0..n as usize {
                    rd.guides.push(Guide {
                        name: nm.clone(),
                        kind: GuideKind::Button {
                            centre: top + 0.5 * od + i as f64 * sep,
                            outer_diameter: od,
                            height: h,
                            inner_diameter: if notch { id } else { 0.0 },
                            inner_height: if notch { inner_height } else { 0.0 },
                        },
                    });
                }
            }
            "trapezoidfinset" | "ellipticalfinset" | "freeformfinset" => {
                // The planform: OpenRocket's trapezoid, its half ellipse on the root chord, or
                // its polygon of `<finpoints>` (checked as the language checks a freeform fin).
                let (root, tip, span, sweep, outline) = match tag {
                    "trapezoidfinset" => (
                        req(cx, c, "rootchord", &what),
                        req(cx, c, "tipchord", &what),
                        req(cx, c, "height", &what),
                        num(cx, c, "sweeplength").ok().flatten().unwrap_or(0.0),
                        FinShape::Trapezoidal,
                    ),
                    "ellipticalfinset" => (
                        req(cx, c, "rootchord", &what),
                        Some(0.0),
                        req(cx, c, "height", &what),
                        0.0,
                        FinShape::Elliptical,
                    ),
                    _ => match freeform_fin(cx, c, &what) {
                        Some((pts, root, span)) => {
                            (Some(root), Some(0.0), Some(span), 0.0, FinShape::Freeform(pts))
                        }
                        None => continue,
                    },
                };
                let thick = req(cx, c, "thickness", &what);
                let count = num(cx, c, "fincount")
                    .ok()
                    .flatten()
                    .or_else(|| num(cx, c, "instancecount").ok().flatten());
                let cant = num(cx, c, "cant").ok().flatten().unwrap_or(0.0);
                let mat = material(cx, c, "material");
                // OpenRocket's `square`, `rounded` and `airfoil` are the language's
                // `cross_section` (its fin drag); the mesh stays a flat plate of the thickness.
                let cross_section = match text_of(c, "crosssection") {
                    None | Some("square") => "square",
                    Some("rounded") => "rounded",
                    Some("airfoil") => "airfoil",
                    Some(x) => {
                        cx.warn(
                            c,
                            format!(
                                "{what}: its unknown `{x}` cross-section is flown as square edges"
                            ),
                        );
                        "square"
                    }
                };
                // Root fillets: their radius and material (only its density is used).
                let fillet = match num(cx, c, "filletradius").ok().flatten() {
                    Some(r) if r > 0.0 => material(cx, c, "filletmaterial").map(|m| (r, m)),
                    _ => None,
                };
                let tab_h = num(cx, c, "tabheight").ok().flatten().unwrap_or(0.0);
                let tab_l = num(cx, c, "tablength").ok().flatten().unwrap_or(0.0);
                let om = override_mass(cx, c);
                // The fin tab (inside the body): no structure, but its mass is the fin set's
                // as OpenRocket counts it (`FinSet.calculateCM`: tab area x thickness x
                // density per fin), kept as a mass over the tab's length unless the fin set's
                // mass is overridden.
                let tab = (tab_h > 0.0 && tab_l > 0.0).then_some((tab_h, tab_l));
                if tab.is_some() && om.is_some() {
                    cx.warn(
                        c,
                        format!("{what}: the fin tab (inside the body) is not represented (its mass is in the design's override)"),
                    );
                }
                if let (Some(root), Some(tip), Some(span), Some(thick), Some(mat)) =
                    (root, tip, span, thick, mat)
                {
                    let Some(count) = count else {
                        cx.error(
                            "import::value",
                            c,
                            format!("{what} has no `<fincount>`"),
                            "here",
                        );
                        continue;
                    };
                    let le = place(c, p.top, p.length, root);
                    let count = count.round().max(1.0) as u32;
                    if let (Some((h, l)), None) = (tab, om) {
                        let front = tab_front(c, l, root);
                        let m = f64::from(count) * h * l * thick * mat.density;
                        cx.warn(
                            c,
                            format!(
                                "{what}: the fin tab (inside the body) is not represented as structure; its mass ({:.1} g) is kept",
                                1e3 * m
                            ),
                        );
                        rd.masses.push(MassItem {
                            name: format!("{nm} tabs"),
                            mass: m,
                            s0: le + front,
                            s1: le + front + l,
                            note: format!(
                                "fin tabs of `{nm}` ({count} x {:.2} x {:.2} mm, inside the body)",
                                1e3 * l,
                                1e3 * h
                            ),
                        });
                    }
                    let offset = num(cx, c, "angleoffset").ok().flatten().unwrap_or(0.0);
                    rd.fins.push(FinSet {
                        name: nm.clone(),
                        count,
                        angles: FinSet::default_angles(count, offset),
                        root,
                        tip,
                        span,
                        sweep,
                        thickness: thick,
                        cross_section,
                        cant,
                        root_le: le,
                        material: mat,
                        override_mass: om,
                        outline,
                        fillet,
                    });
                }
            }
            "tubefinset" => cx.error(
                "import::unsupported",
                c,
                format!(
                    "{what}: tube fins cannot be represented yet (trapezoidal, elliptical and freeform fins can)"
                ),
                "not representable",
            ),
            "podset" | "parallelstage" | "boosterset" | "transition" | "bodytube" | "nosecone" => {
                cx.error(
                    "import::unsupported",
                    c,
                    format!("{what} cannot be represented inside another component"),
                    "not representable",
                )
            }
            _ => cx.error(
                "import::component",
                c,
                format!("unknown component `<{tag}>` (`{nm}`) in `{parent_name}`"),
                "unknown component",
            ),
        }
    }
}

/// The fin tab's front edge behind the root chord's leading edge, m: `<tabposition>` is an
/// offset from the root's front (`front`/`top`), centre (`center`/`middle`) or end
/// (`end`/`bottom`), as OpenRocket's `FinTabPositionSetter` and `AxialMethod.getAsPosition`
/// read it (the tab's front, centre or end respectively).
fn tab_front(c: Node, tab_length: f64, root: f64) -> f64 {
    let Some(t) = c.children().find(|x| x.has_tag_name("tabposition")) else {
        return 0.5 * (root - tab_length);
    };
    let off = t
        .text()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .unwrap_or(0.0);
    let rel = t.attribute("relativeto").unwrap_or("center");
    if rel.contains("front") || rel == "top" {
        off
    } else if rel.contains("end") || rel == "bottom" {
        off + root - tab_length
    } else {
        off + 0.5 * (root - tab_length)
    }
}

/// A `freeformfinset`'s `<finpoints>`: the points, root chord and span, or a diagnostic at
/// the element (a self-crossing outline names its two edges; one the language's freeform fin
/// cannot be, `check::fin_outline::freeform`, says why).
/// A freeform fin's points (m), root chord and span.
pub(crate) type Freeform = (Vec<(f64, f64)>, f64, f64);

fn freeform_fin(cx: &mut Cx, c: Node, what: &str) -> Option<Freeform> {
    let pts: Vec<(f64, f64)> = child(c, "finpoints")
        .map(|fp| {
            fp.children()
                .filter(|q| q.has_tag_name("point"))
                .filter_map(|q| {
                    Some((
                        q.attribute("x")?.trim().parse().ok()?,
                        q.attribute("y")?.trim().parse().ok()?,
                    ))
                })
                .collect()
        })
        .unwrap_or_default();
    checked_outline(cx, c, pts, what)
}

/// A freeform outline `pts` (m, x aft of the root leading edge, y outward) checked as the
/// language checks a freeform fin: the points, root chord and span, or a diagnostic at `c`
/// (a self-crossing outline, `import::fin::crossing`, names its two edges; one the language's
/// freeform fin cannot be, `check::fin_outline::freeform`, says why). Shared by OpenRocket's
/// `<finpoints>` and RockSim's `<PointList>` ([`rocksim`]).
pub(crate) fn checked_outline(
    cx: &mut Cx,
    c: Node,
    pts: Vec<(f64, f64)>,
    what: &str,
) -> Option<Freeform> {
    use crate::check::fin_outline::{OutlineError, freeform};
    if let Some((i, j)) = self_crossing(&pts) {
        cx.error(
            "import::fin::crossing",
            c,
            format!(
                "{what}: the fin outline crosses itself (edges {i} and {j} of {})",
                pts.len()
            ),
            "self-crossing outline",
        );
        return None;
    }
    let xy: Vec<[f64; 2]> = pts.iter().map(|&(x, y)| [x, y]).collect();
    match freeform(&xy) {
        Ok((_, root, span)) => Some((pts, root, span)),
        Err(e) => {
            // A point by its number from the root's leading edge and its coordinates (a
            // RockSim list is numbered after its reversal: the coordinates find it).
            let at = |k: usize| {
                pts.get(k).map_or(format!("{}", k + 1), |q| {
                    format!("{} ({:.2}, {:.2}) mm", k + 1, 1e3 * q.0, 1e3 * q.1)
                })
            };
            let why = match e {
                OutlineError::TooFew => "it has fewer than three points".to_string(),
                OutlineError::RootNotOnBody(k) => {
                    format!(
                        "point {} is an end of the root edge but not on the body (y != 0)",
                        at(k)
                    )
                }
                OutlineError::BelowRoot(k) => {
                    format!("point {} lies on the body between the root points", at(k))
                }
                OutlineError::NotSingleValued(k) => format!(
                    "it is not single-valued in chord per span station (it turns back in span at point {})",
                    at(k)
                ),
                OutlineError::Crosses(k) => {
                    format!(
                        "its leading edge meets its trailing edge at point {}",
                        at(k)
                    )
                }
                OutlineError::RootChord => "its root chord is zero".to_string(),
            };
            let code = if matches!(e, OutlineError::Crosses(_)) {
                "import::fin::crossing"
            } else {
                "import::unsupported"
            };
            cx.error(
                code,
                c,
                format!("{what}: this freeform fin cannot be represented: {why}"),
                "freeform fin",
            );
            None
        }
    }
}

/// The first pair of non-adjacent edges of the closed polygon `pts` that intersect.
pub fn self_crossing(pts: &[(f64, f64)]) -> Option<(usize, usize)> {
    let n = pts.len();
    if n < 4 {
        return None;
    }
    let cross = |a: (f64, f64), b: (f64, f64), c: (f64, f64)| {
        (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
    };
    for i in 0..n {
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue; // adjacent through the closing edge
            }
            let (c, d) = (pts[j], pts[(j + 1) % n]);
            let (d1, d2) = (cross(a, b, c), cross(a, b, d));
            let (d3, d4) = (cross(c, d, a), cross(c, d, b));
            if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
                return Some((i + 1, j + 1));
            }
        }
    }
    None
}

fn read_simulations(cx: &mut Cx, root: Node) -> Vec<Simulation> {
    let Some(sims) = child(root, "simulations") else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for s in sims.children().filter(|c| c.has_tag_name("simulation")) {
        let Some(c) = child(s, "conditions") else {
            continue;
        };
        let g = |cx: &mut Cx, name: &str, d: f64| num(cx, c, name).ok().flatten().unwrap_or(d);
        let fd = child(s, "flightdata");
        let fa = |k: &str| {
            fd.and_then(|f| f.attribute(k))
                .and_then(|v| v.parse::<f64>().ok())
        };
        // A simulation extension (OpenRocket's listeners: roll control, air-start, scripts)
        // changes the flight it stores; flexflight has no extensions, so the scenario flies
        // the design without it and the stored result is not its reference.
        let name = text_of(s, "name").unwrap_or("simulation");
        for x in s.children().filter(|x| x.has_tag_name("extension")) {
            let id = x.attribute("extensionid").unwrap_or("?");
            let short = id.rsplit('.').next().unwrap_or(id);
            cx.warn(
                x,
                format!(
                    "simulation `{name}`: its extension `{short}` ({id}) is not imported: the scenario flies without it, so OpenRocket's stored result (with it) is not its reference"
                ),
            );
        }
        let wind_dir = match num(cx, c, "winddirection").ok().flatten() {
            Some(d) => d,
            None => child(c, "wind")
                .and_then(|w| text_of(w, "direction"))
                .and_then(|t| t.parse().ok())
                .unwrap_or(0.0),
        };
        out.push(Simulation {
            name: name.to_string(),
            config: text_of(c, "configid").map(str::to_string),
            rod_length: g(cx, "launchrodlength", 1.0),
            rod_angle: g(cx, "launchrodangle", 0.0),
            rod_direction: g(cx, "launchroddirection", 90.0),
            wind_speed: g(cx, "windaverage", 0.0),
            wind_turbulence: g(cx, "windturbulence", 0.0),
            wind_direction: wind_dir,
            into_wind: text_of(c, "launchintowind") == Some("true"),
            site_altitude: g(cx, "launchaltitude", 0.0),
            max_time: g(cx, "maxtime", 1200.0),
            apogee: fa("maxaltitude"),
            max_velocity: fa("maxvelocity"),
            time_to_apogee: fa("timetoapogee"),
            status: s.attribute("status").unwrap_or("").to_string(),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn given_materials_parse_and_refuse_nonsense() {
        let m = GivenMaterial::parse("Plywood (birch)=12.4 GPa,0.3").unwrap();
        assert_eq!(m.name, "Plywood (birch)");
        assert!((m.e - 12.4e9).abs() < 1.0);
        assert!(
            GivenMaterial::parse("Cardboard=3,0.3").is_err(),
            "unit required"
        );
        assert!(GivenMaterial::parse("Cardboard=3 GPa,0.6").is_err());
        assert!(GivenMaterial::parse("Cardboard").is_err());
    }

    /// OpenRocket's three tab references (`FinTabPositionSetter`: `front`/`center`/`end`, or
    /// the newer `top`/`middle`/`bottom`): a 60 mm tab on a 100 mm root, offset 5 mm.
    #[test]
    fn a_fin_tabs_front_edge_is_read_from_each_reference() {
        let front = |rel: &str| {
            let xml = format!(
                "<trapezoidfinset><tabposition relativeto=\"{rel}\">0.005</tabposition></trapezoidfinset>"
            );
            let doc = roxmltree::Document::parse(&xml).unwrap();
            tab_front(doc.root_element(), 0.06, 0.1)
        };
        for (rel, want) in [
            ("front", 0.005),
            ("top", 0.005),
            ("center", 0.025),
            ("middle", 0.025),
            ("end", 0.045),
            ("bottom", 0.045),
        ] {
            assert!((front(rel) - want).abs() < 1e-12, "{rel}: {}", front(rel));
        }
        let doc = roxmltree::Document::parse("<trapezoidfinset/>").unwrap();
        assert!((tab_front(doc.root_element(), 0.06, 0.1) - 0.02).abs() < 1e-12);
    }

    #[test]
    fn a_bow_tie_outline_crosses_itself_and_a_trapezoid_does_not() {
        let trap = [(0.0, 0.0), (0.02, 0.05), (0.06, 0.05), (0.08, 0.0)];
        assert_eq!(self_crossing(&trap), None);
        let bow = [(0.0, 0.0), (0.08, 0.05), (0.08, 0.0), (0.0, 0.05)];
        assert!(self_crossing(&bow).is_some());
    }
}
