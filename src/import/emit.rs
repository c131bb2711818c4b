//! The vehicle file an import writes: materials, the vehicle (generated body with the nose,
//! fin sets (the aft-most unnamed, the others named: `arrange_fin_sets`), the masses the body does not contain, the motor) and a scenario per stored
//! simulation, each with a comment saying where its numbers come from.
//!
//! The generated body is a tube of the first body tube's material and wall with a nose shell
//! of the same wall and the design's transitions and boat tails (`structure::generate`,
//! `check::transition`), one diameter between them. Where the design differs (nose shape,
//! nose or tube material or wall, mass overrides), the difference of mass, true minus
//! generated, is added back as a point or distributed mass at the place that restores the
//! centre of mass: for masses (m_t, x_t) true and (m_g, x_g) generated, Delta m = m_t - m_g at
//! x = (m_t x_t - m_g x_g) / Delta m (first moments add). A negative difference cannot be
//! added: where a part of the body (nose, tube, transition) is lighter in the design than
//! the generated structure there (a mass override below what its wall gives), the generated
//! body's density is lowered by the smallest ratio k = m_t / m_g over those parts, so that
//! every body part's difference m_t - k m_g is positive and restored (its stiffness stays
//! the material's); a fin set's override below its generated mass is still a warning that
//! says by how much the model is heavy there.

use std::f64::consts::PI;
use std::fmt::Write;

use super::catalogue::{self, Entry, Lookup};
use super::shapes::NoseShape;
use super::{Cx, Deploy, Design, GuideKind, MassItem, MotorRef, Options, OrMaterial};
use crate::diagnostics::Diagnostic;

/// Standard-library materials the names rocketeers use map to: (key, standard material).
/// A key matches a design's material name case-insensitively as a whole word or words
/// (`std_material_for`), first key first, so the specific keys (an alloy's number) come
/// before the general ones ("aluminum"). The names are OpenRocket's bulk materials
/// (`core/src/main/java/info/openrocket/core/database/Databases.java`) and the RockSim
/// material lists OpenRocket bundles (`datafiles/rocksim_src/*/MATERIAL.CSV`); a name no
/// key matches is asked for (`--material`), never defaulted. Of the woods only balsa has
/// sourced constants (std/materials.vdl: the Wood Handbook's flat-sawn sheet); basswood,
/// birch, plywood, spruce, pine and maple are asked for.
pub const MATERIAL_MAP: &[(&str, &str)] = &[
    ("7075", "aluminium_7075_t6"),
    ("2024", "aluminium_2024_t3"),
    ("6061", "aluminium_6061_t6"),
    ("2014", "aluminium_2014_t6"),
    ("fiberglass", "fibreglass_g10"),
    ("fibreglass", "fibreglass_g10"),
    ("g10", "fibreglass_g10"),
    ("g-10", "fibreglass_g10"),
    ("fr4", "fibreglass_g10"),
    ("fr-4", "fibreglass_g10"),
    ("carbon fiber", "carbon_fibre_fabric"),
    ("carbon fibre", "carbon_fibre_fabric"),
    ("balsa", "balsa"),
    ("aluminum", "aluminium_6061_t6"),
    ("aluminium", "aluminium_6061_t6"),
    ("titanium", "titanium_6al4v"),
    ("polycarbonate", "polycarbonate"),
    ("lexan", "polycarbonate"),
    ("abs", "abs"),
    ("steel", "steel_1020"),
    ("brass", "brass_c26000"),
];

/// Words that make a name something else than the material a key names: a honeycomb or
/// foam sandwich ("Fiberglass/Honeycomb" in RockSim's lists) is far less stiff than the
/// laminate, and a stainless steel is another alloy than the carbon steel of `steel_1020`;
/// such a name is asked for.
const OTHER_MATERIAL: &[&str] = &["honeycomb", "foam", "core", "stainless"];

/// The standard material a design's material name maps to, if any (`MATERIAL_MAP`).
pub fn std_material_for(name: &str) -> Option<&'static str> {
    let lname = name.to_ascii_lowercase();
    if OTHER_MATERIAL.iter().any(|w| has_word(&lname, w)) {
        return None;
    }
    MATERIAL_MAP
        .iter()
        .find(|(k, _)| has_word(&lname, k))
        .map(|(_, std)| *std)
}

/// Whether `key` occurs in `hay` not joined to a letter or digit on either side ("abs" is
/// in "ABS - 100% infill", not in "Absorbent"; "2024" in "Aluminum 2024").
fn has_word(hay: &str, key: &str) -> bool {
    let mut from = 0;
    while let Some(i) = hay[from..].find(key) {
        let a = from + i;
        let b = a + key.len();
        let before = hay[..a].chars().next_back();
        let after = hay[b..].chars().next();
        let joined = |c: Option<char>| c.is_some_and(char::is_alphanumeric);
        if !joined(before) && !joined(after) {
            return true;
        }
        from = a + key.len().max(1);
    }
    false
}

/// Words naming orthotropic materials (wood, plywood, paper, fibre laminates), for which the
/// diagnostic asking for E and nu says how to choose an isotropic pair on the safe side.
const ORTHOTROPIC: &[&str] = &[
    "wood",
    "plywood",
    "balsa",
    "basswood",
    "birch",
    "spruce",
    "pine",
    "maple",
    "paper",
    "kraft",
    "cardboard",
    "phenolic",
    "carbon",
    "fiber",
    "fibre",
    "blue tube",
    "quantum",
];

fn is_orthotropic(name: &str) -> bool {
    let lname = name.to_ascii_lowercase();
    ORTHOTROPIC.iter().any(|w| has_word(&lname, w))
}

/// Words naming a 3D-printed plastic (OpenRocket's "PLA - 100% infill", "PETG - 100% infill"),
/// whose diagnostic asks for the modulus of printed specimens: a printed part is anisotropic
/// (layer and raster directions, infill) and less stiff than the resin of its filament
/// (std/materials.vdl's header: Polymaker's PolyTerra PLA, 1997 MPa printed X-Y and 1615 MPa
/// Z, against 3.6 GPa for NatureWorks' 4043D resin).
const PRINTED: &[&str] = &["pla", "petg", "infill", "printed"];

/// Words naming nylon, whose diagnostic asks for the conditioned modulus: nylon takes up water
/// from the air and its modulus falls by more than half (DuPont's Zytel 103HSL NC010 PA66:
/// 3100 MPa dry, 1400 MPa conditioned; std/materials.vdl's header).
const NYLON: &[&str] = &["nylon", "polyamide"];

/// The help of the diagnostic asking for a material's E and nu (`resolve_material`): what to
/// give for an orthotropic material, a printed plastic or nylon, each on the safe (less stiff)
/// side for flutter; a data sheet's values for anything else.
fn ask_for_material_help(name: &str) -> String {
    let lname = name.to_ascii_lowercase();
    let any = |words: &[&str]| words.iter().any(|w| has_word(&lname, w));
    let mut help = format!("give them: --material '{name}=E GPa,nu'");
    if is_orthotropic(name) {
        help.push_str(". Wood, plywood, paper and fibre laminates are orthotropic: an isotropic plate's shear modulus E / (2 (1 + nu)), which the flutter margin (NACA TN 4197) rests on, should be no more than the material's in-plane shear modulus; or give the fins' material E2 and G12 in the written file (a lamina: docs/language.md)");
    } else if any(PRINTED) || any(NYLON) {
        if any(PRINTED) {
            help.push_str(". A printed part is anisotropic (layer and raster directions, infill) and less stiff than the resin of its filament: give the modulus of printed specimens in their weakest direction (a maker's printed X-Y or Z value, not the resin's), or the fins' E2 and G12 in the written file (a lamina: docs/language.md)");
        }
        if any(NYLON) {
            help.push_str(". Nylon takes up water from the air and its modulus falls by more than half (DuPont's Zytel 103HSL NC010: 3100 MPa dry, 1400 MPa conditioned, ISO 527): give the conditioned value");
        }
    } else {
        help.push_str(" (e.g. from the supplier's data sheet)");
    }
    help
}

/// The density of a standard-library material, kg/m^3, read from the embedded
/// `std/materials.vdl`.
pub fn std_density(name: &str) -> Option<f64> {
    let body = std_block(name)?;
    body.lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .find_map(|l| l.strip_prefix("rho ="))
        .and_then(|v| v.trim().strip_suffix("kg/m^3"))
        .and_then(|v| v.trim().parse::<f64>().ok())
}

fn std_block(name: &str) -> Option<&'static str> {
    let text = crate::check::STDLIB
        .iter()
        .find(|(p, _)| *p == "std/materials.vdl")?
        .1;
    let start = text.find(&format!("material {name} {{"))?;
    let body = &text[start..];
    Some(&body[..body.find('}')?])
}

/// (E, nu) of a standard-library material, read from the embedded `std/materials.vdl`.
pub fn std_elastic(name: &str) -> Option<(f64, f64)> {
    let body = std_block(name)?;
    let mut e = None;
    let mut nu = None;
    for line in body.lines() {
        let l = line.split('#').next().unwrap_or("").trim();
        if let Some(v) = l.strip_prefix("E =") {
            e = gpa(v);
        } else if let Some(v) = l.strip_prefix("nu =") {
            nu = v.trim().parse::<f64>().ok();
        }
    }
    Some((e?, nu?))
}

/// (E2, G12) of a standard-library material that is an orthotropic lamina (docs/language.md,
/// `material`), read from the embedded `std/materials.vdl`; `None` for an isotropic one.
pub fn std_lamina(name: &str) -> Option<(f64, f64)> {
    let body = std_block(name)?;
    let mut e2 = None;
    let mut g12 = None;
    for line in body.lines() {
        let l = line.split('#').next().unwrap_or("").trim();
        if let Some(v) = l.strip_prefix("E2 =") {
            e2 = gpa(v);
        } else if let Some(v) = l.strip_prefix("G12 =") {
            g12 = gpa(v);
        }
    }
    Some((e2?, g12?))
}

/// A modulus as the written file gives it: in GPa from 1 GPa up, else in MPa, with at most 4
/// decimals either way, so that a wood's cross-grain or shear modulus (balsa's E2 56.1 MPa,
/// G12 138.38 MPa) is written as std/materials.vdl has it rather than rounded to 0.1 MPa.
fn modulus(x: f64) -> String {
    if x >= 1e9 {
        format!("{} GPa", f(x / 1e9, 4))
    } else {
        format!("{} MPa", f(x / 1e6, 4))
    }
}

/// A modulus written `X GPa` or `X MPa`, in Pa.
fn gpa(v: &str) -> Option<f64> {
    let v = v.trim();
    if let Some(g) = v.strip_suffix("GPa") {
        g.trim().parse::<f64>().ok().map(|x| x * 1e9)
    } else if let Some(m) = v.strip_suffix("MPa") {
        m.trim().parse::<f64>().ok().map(|x| x * 1e6)
    } else {
        None
    }
}

/// A VDL identifier from an OpenRocket name.
pub fn ident(s: &str) -> String {
    let mut out = String::new();
    for ch in s.chars() {
        if ch.is_ascii_alphanumeric() {
            out.push(ch.to_ascii_lowercase());
        } else if !out.ends_with('_') {
            out.push('_');
        }
    }
    let out = out.trim_matches('_').to_string();
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        format!("c_{out}")
    } else {
        out
    }
}

fn comment_safe(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

/// Number with at most `d` decimals, trailing zeros dropped.
fn f(x: f64, d: usize) -> String {
    let s = format!("{x:.d$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" { "0".into() } else { s }
}

fn mm(x: f64) -> String {
    format!("{} mm", f(x * 1e3, 4))
}

#[derive(Clone)]
struct MatOut {
    ident: String,
    block: String,
    /// Whether the written material is an orthotropic lamina (`E2`, `G12`): a fin set of it
    /// is written with its `grain`.
    lamina: bool,
}

/// What a design's material is used for: the vehicle's body (an isotropic beam, which refuses
/// an orthotropic material: `vdl::material::orthotropic`) or a fin set (a plate that takes a
/// lamina).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    Body,
    Fins,
}

/// Whether a design's material, used for a fin set, is written as a lamina: it maps to an
/// orthotropic standard material and no `--material` gives it as isotropic.
fn fins_take_lamina(m: &OrMaterial, opts: &Options) -> bool {
    let given = opts
        .materials
        .iter()
        .any(|g| g.name.eq_ignore_ascii_case(m.name.trim()));
    !given && std_material_for(&m.name).is_some_and(|s| std_lamina(s).is_some())
}

/// A design's density further than this factor from the standard material's it is mapped to
/// is warned about (`resolve_material`): OpenRocket's own database densities of the mapped
/// names are within 1.02 of the standard materials' but for "Carbon fiber", 1.11 (its 1780
/// kg/m^3 is the fibre's own density, std/materials.vdl's `carbon_fibre_fabric` the
/// laminate's 1600; tests/import_materials.rs), while a foam or a partial infill is several
/// times lighter.
const DENSITY_FACTOR: f64 = 1.5;

/// The material block written for a design's material `m` in its `role`, or `None` after an
/// error diagnostic (no known stiffness). A name mapped to an isotropic standard material is
/// written with its E and nu whatever the role. A name mapped to a lamina is written for a
/// fin set as the lamina (E, E2, G12, nu: identifier `NAME_ork`); for the body, an isotropic
/// beam, as the isotropic equivalent E = min(E, E2) with nu = nu_12 (identifier
/// `NAME_body_ork`): the lower in-plane modulus, so that the body's bending stiffness is not
/// overstated in either direction of the tube's cloth (for fibreglass_g10 this is the old
/// isotropic pair, 21 GPa and 0.136). The beam's shear modulus E / (2 (1 + nu)) then exceeds
/// G12 (9.2 against 4 GPa for G-10): it enters only the beam's shear deformation and torsion,
/// small next to its bending for a slender body, and the comment written says so.
fn resolve_material(cx: &mut Cx, m: &OrMaterial, opts: &Options, role: Role) -> Option<MatOut> {
    let given = opts
        .materials
        .iter()
        .find(|g| g.name.eq_ignore_ascii_case(m.name.trim()));
    let mut lamina = None;
    let (e, nu, source) = if let Some(g) = given {
        (
            g.e,
            g.nu,
            "E and nu given on the command line (--material)".to_string(),
        )
    } else if let Some(std) = std_material_for(&m.name) {
        let (e, nu) = std_elastic(std)?;
        let rho = std_density(std)?;
        let ratio = m.density / rho;
        if !(1.0 / DENSITY_FACTOR..=DENSITY_FACTOR).contains(&ratio) {
            cx.diags.push(
                Diagnostic::warning(
                    "import::material::density",
                    format!(
                        "material `{}` ({} kg/m^3) is taken as `{std}` ({} kg/m^3 in std/materials.vdl) for its E and nu, but its density is {:.2} times that",
                        m.name,
                        f(m.density, 4),
                        f(rho, 4),
                        ratio
                    ),
                )
                .label(m.at, "used here")
                .with_help(format!(
                    "a foam, a core, a partial infill or another material is less stiff than the solid `{std}`: if so, give --material '{}=E GPa,nu'",
                    m.name
                )),
            );
        }
        match (std_lamina(std), role) {
            (None, _) => (
                e,
                nu,
                format!(
                    "E and nu of `{std}` ({} kg/m^3) in std/materials.vdl (see its sources there)",
                    f(rho, 4)
                ),
            ),
            (Some((e2, g12)), Role::Fins) => {
                lamina = Some((e2, g12));
                (
                    e,
                    nu,
                    format!(
                        "the orthotropic lamina `{std}` ({} kg/m^3) in std/materials.vdl (E along its 1-direction, E2 across, G12 the in-plane shear modulus, nu = nu_12; see its sources there)",
                        f(rho, 4)
                    ),
                )
            }
            (Some((e2, _)), Role::Body) => (
                e.min(e2),
                nu,
                format!(
                    "the body, an isotropic beam, cannot take the orthotropic lamina `{std}` ({} kg/m^3) in std/materials.vdl, so this is its isotropic equivalent: the lower in-plane modulus min(E, E2) with nu_12. The beam's shear modulus E / (2 (1 + nu)) exceeds the lamina's G12, which matters only for the body's shear deformation and torsion",
                    f(rho, 4)
                ),
            ),
        }
    } else {
        cx.diags.push(
            Diagnostic::error(
                "import::material",
                format!(
                    "material `{}` ({} kg/m^3) has no known stiffness: flutter depends on E and nu, so they are not guessed",
                    m.name, m.density
                ),
            )
            .label(m.at, "used here")
            .with_help(ask_for_material_help(&m.name)),
        );
        return None;
    };
    let body_equivalent = role == Role::Body
        && given.is_none()
        && lamina.is_none()
        && std_material_for(&m.name).is_some_and(|s| std_lamina(s).is_some());
    let id = if body_equivalent {
        format!("{}_body_ork", ident(&m.name))
    } else {
        format!("{}_ork", ident(&m.name))
    };
    let mut block = String::new();
    let _ = writeln!(
        block,
        "# The design's material `{}`: density {} kg/m^3 from the design; {source}.",
        comment_safe(&m.name),
        f(m.density, 4)
    );
    // A body's isotropic equivalent of a wood lamina is its cross-grain modulus (balsa's
    // 56.1 MPa), below the range of structural solids the checker warns outside of as a likely
    // unit slip (`check::plausible::E_RANGE`): it is meant, and the block says so.
    let unusual = body_equivalent && e < crate::check::plausible::E_RANGE.0;
    if unusual {
        let _ = writeln!(
            block,
            "# Its E is the lamina's cross-grain modulus, below the range of structural solids (0.1 GPa) on purpose, not a unit slip: expect_unusual."
        );
    }
    let _ = writeln!(block, "material {id} {{");
    let _ = writeln!(block, "  E = {}", modulus(e));
    if let Some((e2, g12)) = lamina {
        let _ = writeln!(block, "  E2 = {}", modulus(e2));
        let _ = writeln!(block, "  G12 = {}", modulus(g12));
    }
    let _ = writeln!(block, "  nu = {}", f(nu, 4));
    let _ = writeln!(block, "  rho = {} kg/m^3", f(m.density, 4));
    if unusual {
        let _ = writeln!(block, "  expect_unusual = true");
    }
    let _ = writeln!(block, "}}");
    Some(MatOut {
        ident: id,
        block,
        lamina: lamina.is_some(),
    })
}

/// Diametral clearance a motor named at import may exceed its mount's bore by: 0.5 mm, the
/// design's dimensions being in tenths of a millimetre at best and a motor case's nominal
/// diameter (29, 38, 54 mm ...) the bore of its mount tube.
pub const MOUNT_CLEARANCE: f64 = 0.5e-3;

/// `--motor DESIGNATION` (issue 34): the motor resolved in the catalogue (`--motor-dir` first,
/// then the bundled curves) as `motor { designation }` is, with its exact / ambiguous /
/// not-found diagnostics ([`resolve_motor`]), becomes the design's one motor configuration,
/// `import`, flown by every scenario. A design that stores motors has them replaced (a
/// warning at each, and the header says so); one without a motor mount has no place for it
/// (`import::motor::mount`). The motor must fit the mount: a case wider than the mount's
/// bore by more than [`MOUNT_CLEARANCE`] is `import::motor::fit`; a case longer than the
/// mount sticks out of its aft end by the difference, an overhang (as OpenRocket's
/// `<overhang>`, which the design's own, if larger, keeps), said in a warning. Returns
/// `false` on an error.
pub(crate) fn named_motor(cx: &mut Cx, d: &mut Design, given: &str, cat: &[Entry]) -> bool {
    use crate::runtime::catalogue::parse_designation;
    let Some(mount) = d.mount.as_mut() else {
        cx.diags.push(
            Diagnostic::error(
                "import::motor::mount",
                format!("--motor `{given}`: the design has no motor mount to put it in"),
            )
            .with_help(
                "mark the tube that holds the motor as a motor mount in OpenRocket or RockSim",
            ),
        );
        return false;
    };
    let des = match parse_designation(given) {
        Ok(des) => des,
        Err(lead) => {
            cx.diags.push(
                Diagnostic::error(
                    "import::motor::not_found",
                    format!("--motor `{given}`: `{lead}` is not a motor maker of the catalogue"),
                )
                .label(mount.at, "the motor mount")
                .with_help(
                    "give the maker and the motor, e.g. 'AeroTech K1000T', or the motor alone",
                ),
            );
            return false;
        }
    };
    let r = MotorRef {
        config: "import".into(),
        designation: des.name.clone(),
        manufacturer: des.manufacturer.clone(),
        delay: None,
        length: None,
        diameter: None,
        at: mount.at,
    };
    let Some(e) = resolve_motor(cx, &r, cat) else {
        return false;
    };
    let (dia, len) = (e.curve.diameter, e.curve.length);
    if let (Some(dm), Some(bore)) = (dia, mount.bore) {
        if dm > bore + MOUNT_CLEARANCE {
            cx.diags.push(
                Diagnostic::error(
                    "import::motor::fit",
                    format!(
                        "--motor `{given}`: the {} motor ({} diameter) does not fit motor mount `{}` (bore {})",
                        e.designation(),
                        mm(dm),
                        mount.name,
                        mm(bore)
                    ),
                )
                .label(mount.at, "the motor mount")
                .with_help("name a motor of the mount's diameter or less"),
            );
            return false;
        }
    }
    if let (Some(lm), Some(lt)) = (len, mount.length) {
        if lm - lt > mount.overhang + 1e-9 {
            cx.diags.push(
                Diagnostic::warning(
                    "import::motor::overhang",
                    format!(
                        "--motor `{given}`: the {} motor is {} long, motor mount `{}` {}: it overhangs the mount's aft end by {}",
                        e.designation(),
                        mm(lm),
                        mount.name,
                        mm(lt),
                        mm(lm - lt)
                    ),
                )
                .label(mount.at, "the motor mount"),
            );
            mount.overhang = lm - lt;
        }
    }
    for old in &mount.motors {
        cx.diags.push(
            Diagnostic::warning(
                "import::motor::replaced",
                format!(
                    "the design's motor {} {} (configuration `{}`) is replaced by --motor `{given}`",
                    old.manufacturer.as_deref().unwrap_or(""),
                    old.designation,
                    old.config
                ),
            )
            .label(old.at, "replaced"),
        );
    }
    let replaced: Vec<String> = mount
        .motors
        .iter()
        .map(|m| {
            format!(
                "{} {}",
                m.manufacturer.as_deref().unwrap_or(""),
                m.designation
            )
            .trim()
            .to_string()
        })
        .collect();
    d.notes.push(if replaced.is_empty() {
        format!(
            "the motor, {} ({}), is named at import (--motor `{given}`): the design stores none",
            e.designation(),
            e.describe()
        )
    } else {
        format!(
            "the motor, {} ({}), is named at import (--motor `{given}`): it replaces the design's {}; the stored results below are for the design's motors",
            e.designation(),
            e.describe(),
            replaced.join(", ")
        )
    });
    mount.motors = vec![r];
    d.configs = vec!["import".into()];
    d.default_config = Some("import".into());
    for s in &mut d.simulations {
        s.config = Some("import".into());
    }
    true
}

fn resolve_motor(cx: &mut Cx, r: &MotorRef, cat: &[Entry]) -> Option<Entry> {
    match catalogue::lookup(cat, &r.designation, r.manufacturer.as_deref()) {
        Lookup::Found(e) => {
            if let (Some(l), Some(hl)) = (r.length, e.curve.length) {
                if (l - hl).abs() > 0.002 {
                    cx.diags.push(
                        Diagnostic::warning(
                            "import::motor::dimensions",
                            format!(
                                "motor {}: the design says {} long, the curve's header {}; the header is used",
                                r.designation,
                                mm(l),
                                mm(hl)
                            ),
                        )
                        .label(r.at, "here"),
                    );
                }
            }
            Some(*e)
        }
        Lookup::Ambiguous(v) => {
            cx.diags.push(
                Diagnostic::error(
                    "import::motor::ambiguous",
                    format!(
                        "motor {} {} matches {} thrust curves: {}",
                        r.manufacturer.as_deref().unwrap_or(""),
                        r.designation,
                        v.len(),
                        v.iter().map(Entry::describe).collect::<Vec<_>>().join("; ")
                    ),
                )
                .label(r.at, "this motor")
                .with_help("keep one of them in the --motor-dir directory"),
            );
            None
        }
        Lookup::NotFound(near) => {
            let list = if near.is_empty() {
                "none of its impulse class either".to_string()
            } else {
                format!(
                    "of its impulse class: {}",
                    near.iter()
                        .map(Entry::describe)
                        .collect::<Vec<_>>()
                        .join("; ")
                )
            };
            cx.diags.push(
                Diagnostic::error(
                    "import::motor::not_found",
                    format!(
                        "motor {} {} is not in the catalogue ({list})",
                        r.manufacturer.as_deref().unwrap_or(""),
                        r.designation
                    ),
                )
                .label(r.at, "this motor")
                .with_help(
                    "put its RASP .eng thrust curve (e.g. from the manufacturer or thrustcurve.org) in a directory and pass --motor-dir DIR",
                ),
            );
            None
        }
    }
}

/// One `fins` block (`name`: a further set's) of the importer's set `fins`, with its
/// material's identifier when it is not the body's, and its angles when they are not the
/// language's default 360 (i - 1)/n.
fn write_fin_set(
    o: &mut String,
    fins: &super::FinSet,
    name: Option<&str>,
    material: Option<&MatOut>,
    body_length: f64,
) {
    // A trapezoid without a tip chord (a triangle: RockSim and OpenRocket allow it) is the
    // freeform outline of its three corners: the generated trapezoid's shell mesh needs a tip
    // chord, the freeform mesh ends in a point.
    let pointed;
    let fins = if matches!(fins.outline, super::FinShape::Trapezoidal) && fins.tip <= 0.0 {
        pointed = super::FinSet {
            outline: super::FinShape::Freeform(vec![
                (0.0, 0.0),
                (fins.sweep, fins.span),
                (fins.root, 0.0),
            ]),
            ..fins.clone()
        };
        &pointed
    } else {
        fins
    };
    match &fins.outline {
        super::FinShape::Trapezoidal => {
            let _ = writeln!(
                o,
                "  # `{}`: {} trapezoidal fins, leading-edge sweep {} over the span.",
                comment_safe(&fins.name),
                fins.count,
                mm(fins.sweep)
            );
        }
        super::FinShape::Elliptical => {
            let _ = writeln!(
                o,
                "  # `{}`: {} elliptical fins (the half ellipse on the root chord).",
                comment_safe(&fins.name),
                fins.count
            );
        }
        super::FinShape::Freeform(p) => {
            let _ = writeln!(
                o,
                "  # `{}`: {} freeform fins, the outline of {} points (x aft of the root leading edge, y outward).",
                comment_safe(&fins.name),
                fins.count,
                p.len()
            );
        }
    }
    match name {
        Some(n) => {
            let _ = writeln!(o, "  fins {n} {{");
        }
        None => {
            let _ = writeln!(o, "  fins {{");
        }
    }
    let _ = writeln!(o, "    count = {}", fins.count);
    match &fins.outline {
        super::FinShape::Trapezoidal => {
            let _ = writeln!(o, "    span = {}", mm(fins.span));
            let _ = writeln!(o, "    root_chord = {}", mm(fins.root));
            let _ = writeln!(o, "    tip_chord = {}", mm(fins.tip));
            let _ = writeln!(
                o,
                "    leading_edge_sweep = {} deg",
                f(fins.sweep.atan2(fins.span).to_degrees(), 4)
            );
        }
        super::FinShape::Elliptical => {
            let _ = writeln!(o, "    planform = elliptical");
            let _ = writeln!(o, "    span = {}", mm(fins.span));
            let _ = writeln!(o, "    root_chord = {}", mm(fins.root));
        }
        super::FinShape::Freeform(p) => {
            let _ = writeln!(o, "    planform = freeform");
            let pts: Vec<String> = p
                .iter()
                .map(|&(x, y)| format!("({}, {}) mm", f(x * 1e3, 4), f(y * 1e3, 4)))
                .collect();
            let _ = writeln!(o, "    points = [{}]", pts.join(", "));
        }
    }
    let _ = writeln!(o, "    thickness = {}", mm(fins.thickness));
    let _ = writeln!(o, "    cross_section = {}", fins.cross_section);
    let _ = writeln!(o, "    cant = {} deg", f(fins.cant, 4));
    // At most the body's length (a fin ending at the tail), in the body length's precision
    // (0.1 um), so that rounding cannot put it behind the tail.
    let _ = writeln!(
        o,
        "    root_trailing_edge = {} m",
        f(-(fins.root_le + fins.root).min(body_length), 7)
    );
    let default = super::FinSet::default_angles(fins.count, 0.0);
    if fins.angles.len() == fins.count as usize
        && fins
            .angles
            .iter()
            .zip(&default)
            .any(|(a, b)| (a - b).abs() > 1e-9)
    {
        let list: Vec<String> = fins
            .angles
            .iter()
            .map(|a| format!("{} deg", f(*a, 4)))
            .collect();
        let _ = writeln!(o, "    angles = [{}]", list.join(", "));
    }
    if let Some(m) = material {
        let _ = writeln!(o, "    material = {}", m.ident);
        if m.lamina {
            // OpenRocket and RockSim record no grain or cloth direction.
            let _ = writeln!(
                o,
                "    # The design records no grain or cloth direction: chordwise (the lamina's 1-direction, its E, along the root chord) is assumed. For a fin cut from solid wood with its grain spanwise the margin is lower: set `grain = spanwise` if so."
            );
            let _ = writeln!(o, "    grain = chordwise");
        }
    }
    if let Some((rf, m)) = &fins.fillet {
        let _ = writeln!(
            o,
            "    # Root fillets of `{}` ({} kg/m^3 in the design): their mass only, as OpenRocket counts them.",
            comment_safe(&m.name),
            f(m.density, 6)
        );
        let _ = writeln!(o, "    fillet_radius = {}", mm(*rf));
        let _ = writeln!(o, "    fillet_density = {} kg/m^3", f(m.density, 6));
    }
    let _ = writeln!(o, "  }}");
}

/// The vehicle file and the thrust curves it names; `None` after an error diagnostic.
pub(crate) fn emit(
    cx: &mut Cx,
    d: &Design,
    opts: &Options,
    cat: &[Entry],
) -> Option<(String, Vec<(String, String)>)> {
    let tube0 = &d.tubes[0];
    let body_mat = resolve_material(cx, &tube0.material, opts, Role::Body);
    // Each fin set's material, when not the body's (the unnamed set first, then the others);
    // a lamina is the fins' own material even when the body's is the same (the body takes
    // its isotropic equivalent: `resolve_material`).
    let fin_mats: Vec<Option<MatOut>> = std::iter::once(&d.fins)
        .chain(&d.more_fins)
        .map(|fs| {
            if fs.material.name == tube0.material.name
                && fs.material.density == tube0.material.density
                && !fins_take_lamina(&fs.material, opts)
            {
                None
            } else {
                resolve_material(cx, &fs.material, opts, Role::Fins)
            }
        })
        .collect();
    let fin_mat = fin_mats[0].clone();
    // Motors of every configuration a scenario flies.
    let mount = d.mount.as_ref();
    let mut motor_for = Vec::new(); // (config, entry, ref)
    if let Some(m) = mount {
        for r in &m.motors {
            if let Some(e) = resolve_motor(cx, r, cat) {
                motor_for.push((r.config.clone(), e, r.clone()));
            }
        }
        if m.motors.is_empty() {
            cx.diags.push(
                Diagnostic::warning(
                    "import::motor::unnamed",
                    format!(
                        "motor mount `{}` holds no motor in the design: the vehicle has none and no scenario is written",
                        m.name
                    ),
                )
                .label(m.at, "the motor mount")
                .with_help("name one with --motor DESIGNATION (e.g. --motor 'Estes D12')"),
            );
        }
    } else {
        cx.diags.push(
            Diagnostic::error(
                "import::motor::none",
                "the design has no motor: nothing to fly",
            )
            .with_help("add a motor mount with a motor in OpenRocket (then `--motor DESIGNATION` can name one)"),
        );
    }
    if cx.diags.iter().any(Diagnostic::is_error) {
        return None;
    }
    let body_mat = body_mat?;
    let rho_b = tube0.material.density;
    let t_b = tube0.thickness;
    // The nose's base: the body's diameter ahead of the first transition.
    let r = d.nose.radius;
    let length = d.length();
    let ln = d.nose.length;
    let mut masses: Vec<MassItem> = d.masses.clone();
    let mut notes: Vec<String> = d.notes.clone();
    // The parts whose true mass the generated structure does not have (restored below).
    let mut parts: Vec<Part> = Vec::new();

    // Nose: true shape and material against the generated cone (module doc).
    {
        let n = &d.nose;
        let (mut mt, mut xt) = n
            .shape
            .shell_mass(r, ln, n.thickness, n.material.density, n.filled);
        if let Some(om) = n.override_mass {
            mt = om;
            notes.push(format!(
                "nose `{}`: mass overridden in the design ({om} kg)",
                n.name
            ));
        }
        if let Some(cg) = n.override_cg {
            xt = cg;
            notes.push(format!(
                "nose `{}`: CG overridden in the design ({cg} m from the tip)",
                n.name
            ));
        }
        // The generated nose: the design's profile where the language has it, else a cone.
        let generated = if n.shape.to_language().is_some() {
            n.shape
        } else {
            NoseShape::Conical
        };
        let (mg, xg) = generated.shell_mass(r, ln, t_b, rho_b, false);
        parts.push(Part {
            name: format!("{} (shape and material)", n.name),
            mt,
            xt,
            mg,
            xg,
            range: (0.0, ln),
            body: true,
            spread: false,
        });
        if n.shape.to_language().is_none() {
            cx.diags.push(Diagnostic::warning(
                "import::approximation",
                format!(
                    "nose `{}` is a {} nose, which the language cannot say: the structure and the built-in aerodynamics take a cone of the same length ({}); its mass and centre of mass are restored",
                    n.name,
                    n.shape.describe(),
                    mm(ln)
                ),
            ));
        }
    }
    // Tubes of another material, wall or an overridden mass.
    for t in &d.tubes {
        let r = t.radius;
        let area = |w: f64| PI * (r * r - (r - w).max(0.0).powi(2));
        let mg = rho_b * area(t_b) * t.length;
        let mt = t
            .override_mass
            .unwrap_or(t.material.density * area(t.thickness) * t.length);
        let xc = t.top + t.length / 2.0;
        // Every tube is a part: with the body's density lowered (below) a tube the generated
        // wall matched is light and gets its difference back.
        parts.push(Part {
            name: format!("{} (material, wall or override)", t.name),
            mt,
            xt: xc,
            mg,
            xg: xc,
            range: (t.top, t.top + t.length),
            body: true,
            spread: true,
        });
        if t.material.name != tube0.material.name || (t.thickness - t_b).abs() > 1e-9 {
            cx.diags.push(Diagnostic::warning(
                "import::approximation",
                format!(
                    "body tube `{}` ({}, wall {}) is generated in `{}`'s material and wall ({}); its mass is restored, its stiffness is the generated one",
                    t.name, t.material.name, mm(t.thickness), tube0.name, mm(t_b)
                ),
            ));
        }
    }
    // Transitions (issue 34): generated in the body's material and wall with the design's
    // profile (a cone where the language has none); the difference of mass restored.
    let mut generated_transitions = Vec::new();
    for t in &d.transitions {
        if t.length <= 0.0 {
            cx.diags.push(
                Diagnostic::error(
                    "import::diameter",
                    format!(
                        "transition `{}` has no length: a step in diameter cannot be represented",
                        t.name
                    ),
                )
                .label(t.at, "this transition"),
            );
            continue;
        }
        let lang = t.shape.to_language();
        let g = crate::check::transition::TransitionGeom {
            start: t.top,
            length: t.length,
            r_fore: t.r_fore,
            r_aft: t.r_aft,
            shape: lang.unwrap_or(crate::check::ir::NoseShape::Conical),
        };
        // True: the design's own profile (OpenRocket's, on the smaller radius), wall, density.
        let true_radius = |s: f64| {
            let (lo, hi) = (t.r_fore.min(t.r_aft), t.r_fore.max(t.r_aft));
            let u = (s - t.top).clamp(0.0, t.length);
            let u = if t.r_aft < t.r_fore { t.length - u } else { u };
            lo + t.shape.radius(u, hi - lo, t.length)
        };
        let shell = |radius: &dyn Fn(f64) -> f64, w: f64, rho: f64, filled: bool| {
            let (mut m, mut mx) = (0.0, 0.0);
            for (s, wq) in g.rule(g.start, g.end(), 64) {
                let ro = radius(s);
                let ri = if filled { 0.0 } else { (ro - w).max(0.0) };
                let a = rho * PI * (ro * ro - ri * ri);
                m += wq * a;
                mx += wq * a * s;
            }
            (
                m,
                if m > 0.0 {
                    mx / m
                } else {
                    g.start + 0.5 * g.length
                },
            )
        };
        let (mut mt, mut xt) = shell(&true_radius, t.thickness, t.material.density, t.filled);
        if let Some(om) = t.override_mass {
            mt = om;
            notes.push(format!(
                "transition `{}`: mass overridden in the design ({om} kg)",
                t.name
            ));
        }
        if let Some(cg) = t.override_cg {
            xt = t.top + cg;
            notes.push(format!(
                "transition `{}`: CG overridden in the design ({cg} m from its fore end)",
                t.name
            ));
        }
        let (mg, xg) = shell(&|s| g.radius(s), t_b, rho_b, false);
        parts.push(Part {
            name: format!("{} (shape, material and wall)", t.name),
            mt,
            xt,
            mg,
            xg,
            range: (t.top, t.top + t.length),
            body: true,
            spread: false,
        });
        if lang.is_none() {
            cx.diags.push(Diagnostic::warning(
                "import::approximation",
                format!(
                    "transition `{}` is {}, which the language cannot say: the structure and the built-in aerodynamics take a frustum; its mass and centre of mass are restored",
                    t.name,
                    t.shape.describe()
                ),
            ));
        } else if t.clipped && !matches!(lang, Some(crate::check::ir::NoseShape::Conical)) {
            cx.diags.push(Diagnostic::warning(
                "import::approximation",
                format!(
                    "transition `{}` is a clipped {} profile: it is generated unclipped (the nose profile offset onto the smaller radius, `check::transition`)",
                    t.name,
                    t.shape.describe()
                ),
            ));
        }
        if (t.r_fore - t.r_aft).abs() <= 1e-6 {
            // Equal radii: the tube continues; the shell's mass is restored above.
            continue;
        }
        generated_transitions.push((t, g));
    }
    // Fin mass overrides (every set's).
    let fins = &d.fins;
    for fs in std::iter::once(fins).chain(&d.more_fins) {
        if let Some(om) = fs.override_mass {
            let area = fs.area();
            // OpenRocket's fin set mass includes its fillets; so does the generated one.
            let mg = f64::from(fs.count) * area * fs.thickness * fs.material.density
                + fs.fillet.as_ref().map_or(0.0, |(rf, m)| {
                    2.0 * f64::from(fs.count)
                        * crate::check::ir::Fillet::section_area(r, *rf)
                        * fs.root
                        * m.density
                });
            let xc = fs.root_le + fs.root / 2.0;
            parts.push(Part {
                name: format!("{} (override)", fs.name),
                mt: om,
                xt: xc,
                mg,
                xg: xc,
                range: (fs.root_le, fs.root_le + fs.root),
                body: false,
                spread: false,
            });
        }
    }
    // The generated body's density (module doc): the design's first tube's, lowered where a
    // part of the body (nose, tube, transition) is lighter in the design than the generated
    // structure there (a mass override below what its wall gives: a negative mass cannot be
    // added), to the lightest such part's ratio k = m_true / m_generated; the difference of
    // every body part is then m_true - k m_generated >= 0 and is restored as a mass. The
    // stiffness (E, nu) is the material's; only the beam's and shell's mass per length fall.
    // A part of no mass cannot be kept so (a body of no density is no structure): it keeps
    // the warning.
    let k = parts
        .iter()
        .filter(|p| p.body && p.mg > 0.0 && p.mt > 0.0)
        .map(|p| p.mt / p.mg)
        .fold(1.0, f64::min);
    // Written to 1e-9 kg/m^3, and the masses restored at the density as written.
    let rho_g: f64 = f(k * rho_b, 9)
        .parse()
        .ok()
        .filter(|r: &f64| *r > 0.0)
        .unwrap_or(rho_b);
    let k = rho_g / rho_b;
    if k < 1.0 {
        notes.push(format!(
            "the generated body's density is {} kg/m^3, {} of the design's {} kg/m^3, so that the part lightest against it (a mass override, or a lighter material) keeps its mass; every other part's difference is restored as a mass",
            f(rho_g, 4),
            f(k, 6),
            f(rho_b, 4)
        ));
    }
    for p in &parts {
        let scale = if p.body { k } else { 1.0 };
        add_difference(cx, &mut masses, p, scale, &mut notes);
    }

    let mut aft = mount.map_or(length, |m| m.aft + m.overhang);
    if aft > length + 1e-9 {
        // The motor must lie inside the generated body (`vdl::motor::geometry`): a motor that
        // overhangs the body's aft end is moved forward to it.
        cx.diags.push(Diagnostic::warning(
            "import::approximation",
            format!(
                "the motor overhangs the body's aft end by {}: it is placed with its nozzle at the aft end (the generated body must contain it)",
                mm(aft - length)
            ),
        ));
        aft = length;
    }
    // Masses reaching beyond the generated body (an inner tube or a fin can overhanging the
    // aft end) are moved inside it: `distributed_mass` and `point_mass` stations lie on it.
    for m in &mut masses {
        let (a, b) = (m.s0.clamp(0.0, length), m.s1.clamp(0.0, length));
        if (a - m.s0).abs() > 1e-9 || (b - m.s1).abs() > 1e-9 {
            cx.diags.push(Diagnostic::warning(
                "import::approximation",
                format!(
                    "`{}` reaches {} beyond the body: its mass is placed inside the generated body",
                    m.name,
                    mm((m.s1 - length).max(-m.s0).max(0.0))
                ),
            ));
            m.note.push_str("; moved inside the generated body");
            (m.s0, m.s1) = (a, b);
        }
    }
    // Dry centre of mass (for the coefficient reference point and the key node).
    let (mut m_sum, mut mx_sum) = (0.0, 0.0);
    let (mg, xg) = NoseShape::Conical.shell_mass(r, ln, t_b, rho_g, false);
    m_sum += mg;
    mx_sum += mg * xg;
    // The tube's sections and the transitions (their mean radius, enough for a reference point).
    let mut from = ln;
    let mut rs = r;
    let mut sections: Vec<(f64, f64, f64)> = Vec::new();
    for (_, g) in &generated_transitions {
        sections.push((rs, from, g.start));
        sections.push((0.5 * (g.r_fore + g.r_aft), g.start, g.end()));
        (from, rs) = (g.end(), g.r_aft);
    }
    sections.push((rs, from, length));
    for (rr, a, b) in sections {
        let mb = rho_g * PI * (rr * rr - (rr - t_b).max(0.0).powi(2)) * (b - a);
        m_sum += mb;
        mx_sum += mb * (a + b) / 2.0;
    }
    for fs in std::iter::once(fins).chain(&d.more_fins) {
        let mf = f64::from(fs.count) * fs.area() * fs.thickness * fs.material.density;
        m_sum += mf;
        mx_sum += mf * (fs.root_le + fs.root / 2.0);
    }
    for m in &masses {
        m_sum += m.mass;
        mx_sum += m.mass * (m.s0 + m.s1) / 2.0;
    }
    let cg = if m_sum > 0.0 {
        mx_sum / m_sum
    } else {
        length / 2.0
    };

    let mut o = String::new();
    let vname = ident(&d.name);
    let _ = writeln!(
        o,
        "# {} — imported by `flexflight import` from {}.",
        comment_safe(&d.name),
        d.file.display()
    );
    if let Some(who) = &d.designer {
        let _ = writeln!(o, "# Designed by {}.", comment_safe(who));
    }
    for n in &notes {
        let _ = writeln!(o, "# {}", comment_safe(n));
    }
    let _ = writeln!(o, "#");
    let _ = writeln!(
        o,
        "# The body is generated: the tubes and transitions in the first body tube's material and wall with a"
    );
    let _ = writeln!(
        o,
        "# nose shell of the design's profile; the masses below are the components it does not contain (and"
    );
    let _ = writeln!(
        o,
        "# the differences of mass where the design differs from it), computed from the"
    );
    let _ = writeln!(
        o,
        "# design's dimensions and densities as OpenRocket does. Not imported: appearance,"
    );
    let _ = writeln!(o, "# decals.");
    for w in cx.diags.iter().filter(|w| !w.is_error()) {
        let _ = writeln!(o, "# Approximation: {}", comment_safe(&w.message));
    }
    let _ = writeln!(o);
    let _ = writeln!(o, "import \"std/materials.vdl\"");
    let _ = writeln!(o);
    // With the body's density lowered, a fin set of the body's material keeps the design's
    // density under the material's own name.
    let (body_mat, fin_mats, fin_mat) = if k < 1.0 {
        let fms: Vec<Option<MatOut>> = fin_mats
            .into_iter()
            .map(|m| m.or_else(|| Some(body_mat.clone())))
            .collect();
        let first = fms[0].clone();
        (with_density(&body_mat, rho_g, k), fms, first)
    } else {
        (body_mat, fin_mats, fin_mat)
    };
    o.push_str(&body_mat.block);
    let _ = writeln!(o);
    // The fin sets' materials, each once.
    let mut written = vec![body_mat.ident.clone()];
    for fm in fin_mats.iter().flatten() {
        if !written.contains(&fm.ident) {
            o.push_str(&fm.block);
            let _ = writeln!(o);
            written.push(fm.ident.clone());
        }
    }
    let elements = ((length / (2.0 * r)).round() as i64).clamp(10, 40);
    let _ = writeln!(o, "vehicle {vname} {{");
    let _ = writeln!(o, "  material = {}", body_mat.ident);
    let _ = writeln!(o, "  origin = node(1)");
    let _ = writeln!(o);
    let _ = writeln!(o, "  structure {{");
    let _ = writeln!(o, "    generate {{");
    let _ = writeln!(
        o,
        "      # `{}` and {} body tube(s) ({}).",
        comment_safe(&d.nose.name),
        d.tubes.len(),
        d.tubes
            .iter()
            .map(|t| comment_safe(&t.name))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(o, "      body {{");
    let _ = writeln!(o, "        length = {}", mm(length));
    let _ = writeln!(o, "        diameter = {}", mm(2.0 * r));
    let _ = writeln!(o, "        wall = {}", mm(t_b));
    match d.nose.shape.to_language() {
        Some(shape) => {
            let _ = writeln!(o, "        nose_length = {}", mm(ln));
            let _ = writeln!(
                o,
                "        nose_shape = {} # {} in the design",
                shape.source_text(),
                d.nose.shape.describe()
            );
        }
        None => {
            let _ = writeln!(
                o,
                "        nose_length = {} # {} in the design: taken as a cone",
                mm(ln),
                d.nose.shape.describe()
            );
        }
    }
    let _ = writeln!(o, "        elements = {elements}");
    let _ = writeln!(o, "        theory = euler_bernoulli");
    for (t, g) in &generated_transitions {
        let _ = writeln!(o);
        let _ = writeln!(
            o,
            "        # `{}`: {} {} (the design's {}, wall {}).",
            comment_safe(&t.name),
            if g.narrows() {
                "a boat tail or reducer,"
            } else {
                "a widening transition,"
            },
            t.shape.describe(),
            comment_safe(&t.material.name),
            mm(t.thickness)
        );
        let _ = writeln!(o, "        transition {{");
        let _ = writeln!(o, "          fore_station = {} m", f(-g.start, 7));
        let _ = writeln!(o, "          length = {}", mm(g.length));
        let _ = writeln!(o, "          fore_diameter = {}", mm(2.0 * g.r_fore));
        let _ = writeln!(o, "          aft_diameter = {}", mm(2.0 * g.r_aft));
        if !g.shape.is_conical() {
            let _ = writeln!(o, "          shape = {}", g.shape.source_text());
        }
        let _ = writeln!(o, "        }}");
    }
    for g in &d.guides {
        match g.kind {
            GuideKind::Lug {
                top,
                length,
                outer_diameter,
                inner_diameter,
            } => {
                let _ = writeln!(
                    o,
                    "        # launch lug `{}`: its drag; its mass is among the masses below",
                    comment_safe(&g.name)
                );
                let _ = writeln!(o, "        launch_lug {{");
                let _ = writeln!(o, "          station = {} m", f(-top, 7));
                let _ = writeln!(o, "          length = {}", mm(length));
                let _ = writeln!(o, "          outer_diameter = {}", mm(outer_diameter));
                let _ = writeln!(o, "          inner_diameter = {}", mm(inner_diameter));
                let _ = writeln!(o, "          mass = 0 kg");
                let _ = writeln!(o, "        }}");
            }
            GuideKind::Button {
                centre,
                outer_diameter,
                height,
                inner_diameter,
                inner_height,
            } => {
                let _ = writeln!(
                    o,
                    "        # rail button `{}`: its drag; its mass (if the design overrides it) is among the masses below",
                    comment_safe(&g.name)
                );
                let _ = writeln!(o, "        rail_button {{");
                let _ = writeln!(o, "          station = {} m", f(-centre, 7));
                let _ = writeln!(o, "          outer_diameter = {}", mm(outer_diameter));
                let _ = writeln!(o, "          height = {}", mm(height));
                if inner_height > 0.0 {
                    let _ = writeln!(o, "          inner_diameter = {}", mm(inner_diameter));
                    let _ = writeln!(o, "          inner_height = {}", mm(inner_height));
                }
                let _ = writeln!(o, "          mass = 0 kg");
                let _ = writeln!(o, "        }}");
            }
        }
    }
    let _ = writeln!(o, "      }}");
    let _ = writeln!(o);
    let _ = writeln!(o, "      fin_mesh {{");
    let _ = writeln!(o, "        span_elements = 4");
    let _ = writeln!(o, "        chord_elements = 6");
    let _ = writeln!(o, "      }}");
    let mut used = std::collections::BTreeSet::new();
    for m in &masses {
        if m.mass <= 0.0 {
            let _ = writeln!(o);
            let _ = writeln!(
                o,
                "      # `{}` ({}): no mass.",
                comment_safe(&m.name),
                comment_safe(&m.note)
            );
            continue;
        }
        let mut id = ident(&m.name);
        let base = id.clone();
        let mut k = 2;
        while !used.insert(id.clone()) {
            id = format!("{base}_{k}");
            k += 1;
        }
        let _ = writeln!(o);
        let _ = writeln!(
            o,
            "      # `{}`: {}.",
            comment_safe(&m.name),
            comment_safe(&m.note)
        );
        if m.s1 - m.s0 > 1e-4 {
            let _ = writeln!(o, "      distributed_mass {id} {{");
            let _ = writeln!(o, "        from = {} m", f(-m.s0, 7));
            let _ = writeln!(o, "        to = {} m", f(-m.s1, 7));
            let _ = writeln!(o, "        mass = {} kg", f(m.mass, 6));
        } else {
            let _ = writeln!(o, "      point_mass {id} {{");
            let _ = writeln!(o, "        position = ({}, 0, 0) m", f(-m.s0, 7));
            let _ = writeln!(o, "        mass = {} kg", f(m.mass, 6));
        }
        let _ = writeln!(o, "      }}");
    }
    let _ = writeln!(o, "    }}");
    let _ = writeln!(o, "  }}");
    let _ = writeln!(o);
    write_fin_set(&mut o, fins, None, fin_mat.as_ref(), length);
    // Further sets (canards, ...): named blocks, rigid in the flight (`check::fin_sets`).
    let mut names: Vec<String> = vec!["fins".into()];
    for (fs, fm) in d.more_fins.iter().zip(&fin_mats[1..]) {
        let mut name = ident(&fs.name);
        while names.contains(&name) {
            name.push('_');
        }
        names.push(name.clone());
        let _ = writeln!(o);
        let _ = writeln!(
            o,
            "  # A further fin set: rigid in the flight (its mass a rigid body, its aerodynamics in the"
        );
        let _ = writeln!(
            o,
            "  # body's coefficients; no modes or fin loads; its clamped-fin flutter margin: docs/language.md)."
        );
        write_fin_set(&mut o, fs, Some(&name), fm.as_ref(), length);
    }
    // The vehicle flies the default configuration's motor (else the first).
    let default = d
        .default_config
        .as_ref()
        .and_then(|c| motor_for.iter().find(|(k, _, _)| k == c))
        .or(motor_for.first());
    let mut files: Vec<(String, String)> = Vec::new();
    // Every motor in the bundled catalogue: named by designation (`check` finds the curve and
    // takes the header's dimensions and masses); else every curve is written beside the file,
    // so that a scenario's `motor.curve` override can swap it.
    let by_name = motor_for
        .iter()
        .all(|(_, e, _)| e.origin == super::catalogue::Origin::Bundled);
    if let Some((_, e, rf)) = default {
        let _ = writeln!(o);
        let _ = writeln!(
            o,
            "  # {} {} of the default configuration ({}): its nozzle exit {} aft of the mount's end.",
            rf.manufacturer.as_deref().unwrap_or(""),
            rf.designation,
            e.describe(),
            mm(mount.map_or(0.0, |m| m.overhang))
        );
        let _ = writeln!(o, "  motor {} {{", ident(&rf.designation));
        if by_name {
            let _ = writeln!(o, "    designation = \"{}\"", e.designation());
            let _ = writeln!(o, "    position = ({}, 0, 0) m", f(-aft, 7));
        } else {
            let _ = writeln!(o, "    curve = \"{}\"", e.file);
            let _ = writeln!(o, "    position = ({}, 0, 0) m", f(-aft, 7));
            let _ = writeln!(
                o,
                "    length = {}",
                mm(e.curve.length.or(rf.length).unwrap_or(0.07))
            );
            let _ = writeln!(
                o,
                "    diameter = {}",
                mm(e.curve.diameter.or(rf.diameter).unwrap_or(0.018))
            );
        }
        let _ = writeln!(o, "  }}");
    }
    if !by_name {
        for (_, e, _) in &motor_for {
            if !files.iter().any(|(n, _)| n == &e.file) {
                files.push((e.file.clone(), e.text.clone()));
            }
        }
    }
    let _ = writeln!(o);
    let _ = writeln!(o, "  key_nodes {{");
    let _ = writeln!(
        o,
        "    body = nearest(({}, 0, 0) m) # the estimated dry centre of mass",
        f(-cg, 4)
    );
    let _ = writeln!(o, "    nozzle = nearest(({}, 0, 0) m)", f(-length, 7));
    let _ = writeln!(o, "    fins = fin_point(span = 0.5, chord = 0.25)");
    let _ = writeln!(o, "  }}");
    let _ = writeln!(o);
    let _ = writeln!(o, "  modes {{");
    let _ = writeln!(o, "    body_bending = 2");
    let _ = writeln!(o, "    fin_flap = per_fin");
    let _ = writeln!(o, "    fin_twist = per_fin");
    let _ = writeln!(o, "    fixity = origin");
    let _ = writeln!(
        o,
        "    damping = 0.02 # assumption: 2 % of critical; the design says nothing"
    );
    let _ = writeln!(o, "  }}");
    let _ = writeln!(o);
    let _ = writeln!(o, "  aero {{");
    let _ = writeln!(o, "    source = builtin");
    let _ = writeln!(
        o,
        "    finish = {} # {} um; the design: {}",
        d.finish.name,
        d.finish.roughness * 1e6,
        comment_safe(&d.finish.said)
    );
    let r_max = generated_transitions
        .iter()
        .fold(r, |m, (_, g)| m.max(g.r_fore).max(g.r_aft));
    let _ = writeln!(
        o,
        "    reference_length = {} # the largest diameter",
        mm(2.0 * r_max)
    );
    let _ = writeln!(
        o,
        "    reference_point = ({}, 0, 0) m # the estimated dry centre of mass",
        f(-cg, 4)
    );
    let _ = writeln!(o, "  }}");
    let _ = writeln!(o);
    let _ = writeln!(o, "  forces {{");
    let _ = writeln!(o, "    gravity {{");
    let _ = writeln!(o, "      altitude_correction = true");
    let _ = writeln!(o, "    }}");
    let _ = writeln!(o);
    let _ = writeln!(o, "    body_aero {{");
    let _ = writeln!(o, "      rate_terms = true");
    let _ = writeln!(o, "    }}");
    let _ = writeln!(o);
    let _ = writeln!(o, "    fin_aero {{");
    let _ = writeln!(o, "      distribution = theory");
    let _ = writeln!(o, "      leeward_reduction = true");
    let _ = writeln!(o, "    }}");
    let _ = writeln!(o, "  }}");
    let _ = writeln!(o, "}}");

    // Scenarios.
    let mut snames = std::collections::BTreeSet::new();
    let sims: Vec<super::Simulation> = if d.simulations.is_empty() {
        vec![super::Simulation {
            name: "flight".into(),
            config: d.default_config.clone(),
            rod_length: 1.0,
            rod_angle: 0.0,
            rod_direction: 90.0,
            wind_speed: 0.0,
            wind_turbulence: 0.0,
            wind_direction: 0.0,
            into_wind: false,
            site_altitude: 0.0,
            max_time: 1200.0,
            apogee: None,
            max_velocity: None,
            time_to_apogee: None,
            status: String::new(),
        }]
    } else {
        d.simulations.clone()
    };
    for s in &sims {
        let mut id = ident(&s.name);
        let base = id.clone();
        let mut k = 2;
        while !snames.insert(id.clone()) || id == vname {
            id = format!("{base}_{k}");
            k += 1;
        }
        let motor = s
            .config
            .as_ref()
            .and_then(|c| motor_for.iter().find(|(k, _, _)| k == c))
            .or(default);
        let Some((_, e, rf)) = motor else { continue };
        let _ = writeln!(o);
        let _ = writeln!(
            o,
            "# OpenRocket simulation `{}` ({}), {} {}.",
            comment_safe(&s.name),
            if s.status.is_empty() {
                "no status"
            } else {
                &s.status
            },
            rf.manufacturer.as_deref().unwrap_or(""),
            rf.designation
        );
        if let (Some(a), Some(v), Some(t)) = (s.apogee, s.max_velocity, s.time_to_apogee) {
            let _ = writeln!(
                o,
                "# OpenRocket's stored result: apogee {a} m, max velocity {v} m/s, time to apogee {t} s."
            );
        }
        if s.into_wind {
            let _ = writeln!(
                o,
                "# OpenRocket launched into the wind (`launchintowind`); here the rail points as the file says."
            );
        }
        if s.wind_turbulence > 0.0 {
            let _ = writeln!(
                o,
                "# The wind's turbulence intensity ({} %) is not imported: a steady wind.",
                f(100.0 * s.wind_turbulence, 2)
            );
        }
        let _ = writeln!(o, "scenario {id} {{");
        let _ = writeln!(o, "  vehicle = {vname}");
        let same = default.is_some_and(|(_, de, _)| de.file == e.file);
        if !same && by_name {
            let _ = writeln!(o, "  with {{");
            let _ = writeln!(o, "    motor.designation = \"{}\"", e.designation());
            let _ = writeln!(o, "  }}");
        } else if !same {
            let _ = writeln!(o, "  with {{");
            let _ = writeln!(o, "    motor.curve = \"{}\"", e.file);
            let _ = writeln!(
                o,
                "    motor.length = {}",
                mm(e.curve.length.or(rf.length).unwrap_or(0.07))
            );
            let _ = writeln!(
                o,
                "    motor.diameter = {}",
                mm(e.curve.diameter.or(rf.diameter).unwrap_or(0.018))
            );
            let _ = writeln!(o, "  }}");
        }
        let _ = writeln!(o);
        let _ = writeln!(o, "  launch {{");
        let _ = writeln!(o, "    site_altitude = {} m", f(s.site_altitude, 3));
        let _ = writeln!(o, "    rail_length = {} m", f(s.rod_length, 4));
        let _ = writeln!(o, "    elevation = {} deg", f(90.0 - s.rod_angle, 4));
        let _ = writeln!(
            o,
            "    heading = {} deg",
            f(s.rod_direction.rem_euclid(360.0), 4)
        );
        let _ = writeln!(o, "  }}");
        if s.wind_speed > 0.0 {
            let _ = writeln!(o);
            let _ = writeln!(
                o,
                "  # OpenRocket's average wind; its direction as the file stores it ({} rad).",
                f(s.wind_direction, 6)
            );
            let _ = writeln!(o, "  wind {{");
            let _ = writeln!(o, "    speed = {} m/s", f(s.wind_speed, 4));
            let _ = writeln!(
                o,
                "    direction = {} deg",
                f(s.wind_direction.to_degrees().rem_euclid(360.0), 3)
            );
            let _ = writeln!(o, "  }}");
        }
        for rcv in &d.recovery {
            let trigger = match rcv.deploy {
                Deploy::Apogee => "apogee".to_string(),
                Deploy::Altitude(h) => format!("altitude({} m)", f(h, 3)),
                Deploy::Ejection => match rf.delay {
                    Some(delay) => format!("time({} s)", f(e.curve.burn_time() + delay, 4)),
                    None => {
                        cx.diags.push(Diagnostic::warning(
                            "import::approximation",
                            format!("parachute `{}` opens at the ejection charge of {}, which is plugged: it never opens in scenario `{id}`", rcv.name, rf.designation),
                        ));
                        continue;
                    }
                },
                Deploy::Never => continue,
            };
            let _ = writeln!(o);
            let why = match rcv.deploy {
                Deploy::Ejection => format!(
                    "at the ejection charge: burnout {} s + delay {} s",
                    f(e.curve.burn_time(), 4),
                    f(rf.delay.unwrap_or(0.0), 3)
                ),
                _ => "as the design says".into(),
            };
            let _ = writeln!(
                o,
                "  # `{}`: CD {}{} x {} m^2; opens {why}.",
                comment_safe(&rcv.name),
                f(rcv.cd, 4),
                if rcv.cd_auto {
                    " (OpenRocket's automatic value)"
                } else {
                    ""
                },
                f(rcv.area, 6)
            );
            let _ = writeln!(o, "  parachute {} {{", ident(&rcv.name));
            let _ = writeln!(o, "    cd_area = {} m^2", f(rcv.cd * rcv.area, 6));
            let _ = writeln!(o, "    trigger = {trigger}");
            if rcv.delay > 0.0 {
                let _ = writeln!(o, "    lag = {} s", f(rcv.delay, 4));
            }
            let _ = writeln!(o, "  }}");
        }
        let _ = writeln!(o);
        let _ = writeln!(o, "  run {{");
        let _ = writeln!(
            o,
            "    stop_time = {} s # OpenRocket's maximum simulation time",
            f(s.max_time, 3)
        );
        let _ = writeln!(o, "  }}");
        let _ = writeln!(o, "}}");
    }
    Some((o, files))
}

/// A part of the design whose mass the generated structure does not have exactly: its true
/// mass and centre, the generated ones (at the design's density), the span it lies over,
/// and whether it is of the generated body (its generated mass scales with the body's
/// density).
struct Part {
    name: String,
    mt: f64,
    xt: f64,
    mg: f64,
    xg: f64,
    range: (f64, f64),
    body: bool,
    /// A uniform part (a tube): its difference is restored spread over `range`, as the part
    /// is, not at a point.
    spread: bool,
}

/// The body's material block written with density `rho` (k times the design's), under its
/// own name (a fin set of the same material keeps the design's density).
fn with_density(m: &MatOut, rho: f64, k: f64) -> MatOut {
    let ident = format!("{}_generated", m.ident);
    let mut block = String::new();
    for line in m.block.lines() {
        if line.starts_with("material ") {
            let _ = writeln!(
                block,
                "# The generated body's density: {} of the design's, so that the parts lighter in the design than the generated structure keep their mass (the other parts' masses are restored below).",
                f(k, 6)
            );
            let _ = writeln!(block, "material {ident} {{");
        } else if line.trim_start().starts_with("rho = ") {
            let _ = writeln!(block, "  rho = {} kg/m^3", f(rho, 9));
        } else {
            let _ = writeln!(block, "{line}");
        }
    }
    MatOut {
        ident,
        block,
        lamina: m.lamina,
    }
}

/// Restores part `p`'s difference of mass, true minus generated (its generated mass times
/// `scale`: the body's density ratio, or 1), at the place that restores its first moment; a
/// negative difference is a warning.
fn add_difference(
    cx: &mut Cx,
    masses: &mut Vec<MassItem>,
    p: &Part,
    scale: f64,
    notes: &mut Vec<String>,
) {
    let (name, mt, xt, xg, range) = (&p.name, p.mt, p.xt, p.xg, p.range);
    let mg = scale * p.mg;
    let dm = mt - mg;
    if dm.abs() < 1e-7 {
        return;
    }
    if dm < 0.0 {
        cx.diags.push(Diagnostic::warning(
            "import::approximation",
            format!(
                "`{name}`: the generated structure is {} g heavier than the design here ({} g against {} g); a negative mass cannot be added",
                f(-dm * 1e3, 3),
                f(mg * 1e3, 3),
                f(mt * 1e3, 3)
            ),
        ));
        return;
    }
    let x = ((mt * xt - mg * xg) / dm).clamp(range.0, range.1);
    notes.push(format!(
        "`{name}`: {} g added at {} m (true {} g at {} m, generated {} g at {} m)",
        f(dm * 1e3, 3),
        f(x, 4),
        f(mt * 1e3, 3),
        f(xt, 4),
        f(mg * 1e3, 3),
        f(xg, 4)
    ));
    // A uniform part's difference is uniform too: spread over the part (its centre is x).
    let (s0, s1) = if p.spread { range } else { (x, x) };
    masses.push(MassItem {
        name: name.to_string(),
        mass: dm,
        s0,
        s1,
        note: "mass difference, true minus generated (restores mass and centre of mass)".into(),
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_are_valid_vdl_names() {
        assert_eq!(ident("Nose cone"), "nose_cone");
        assert_eq!(
            ident("Elliptical 12-Gore 42\" Parachute"),
            "elliptical_12_gore_42_parachute"
        );
        assert_eq!(ident("3D fins"), "c_3d_fins");
        assert_eq!(ident("---"), "c_");
    }

    /// The help asking for a material says what to give by the kind the name names, as whole
    /// words: "Plastic" is no "pla", "Polyamide 6" is nylon, a printed nylon gets both notes.
    #[test]
    fn the_help_asking_for_a_material_follows_its_kind() {
        let printed = "printed specimens";
        let wet = "conditioned value";
        let generic = "e.g. from the supplier's data sheet";
        let h = ask_for_material_help("PLA - 100% infill");
        assert!(
            h.contains(printed) && !h.contains(wet) && !h.contains(generic),
            "{h}"
        );
        let h = ask_for_material_help("Polyamide 6");
        assert!(h.contains(wet) && !h.contains(printed), "{h}");
        let h = ask_for_material_help("Nylon (printed)");
        assert!(h.contains(wet) && h.contains(printed), "{h}");
        let h = ask_for_material_help("Kraft phenolic");
        assert!(h.contains("orthotropic") && !h.contains(printed), "{h}");
        for generic_name in ["Plastic (generic)", "PVC", "Explained"] {
            let h = ask_for_material_help(generic_name);
            assert!(
                h.contains(generic) && !h.contains(printed),
                "{generic_name}: {h}"
            );
        }
        assert!(
            ask_for_material_help("PETG - 100% infill")
                .starts_with("give them: --material 'PETG - 100% infill=E GPa,nu'. ")
        );
    }

    #[test]
    fn the_std_map_reads_the_embedded_library() {
        for (_, std) in MATERIAL_MAP {
            let (e, nu) = std_elastic(std).unwrap_or_else(|| panic!("{std} in std/materials.vdl"));
            assert!(e > 1e9 && nu > 0.0 && nu < 0.5);
        }
    }
}
