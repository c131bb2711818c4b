//! RockSim designs (`.rkt`, `<RockSimDocument>`) read into the same [`Design`] as OpenRocket's,
//! so that the vehicle file is written by the same emitter with the same diagnostics.
//!
//! The format as OpenRocket's RockSim importer reads it (core/src/main/java/info/openrocket/
//! core/file/rocksim/, `RockSimCommonConstants`, `importt/*Handler.java`, commit 8fa969d8;
//! checked against the RockSim files of its test resources):
//!
//! - units: lengths in mm (`ROCKSIM_TO_OPENROCKET_LENGTH = 1000`), masses in g
//!   (`ROCKSIM_TO_OPENROCKET_MASS = 1000`), bulk densities in kg/m^3 (factor 1);
//! - the single stage's parts are `DesignInformation/RocketDesign/Stage3Parts` in order, fore
//!   to aft (`Stage2Parts`, `Stage1Parts`: boosters); a part's children are in its
//!   `AttachedParts`;
//! - `NoseCone`: `Len`, `BaseDia`, `WallThickness`, `ConstructionType` (0 solid, 1 hollow),
//!   `ShapeCode` (0 conical, 1 ogive, 2 parabolic, which OpenRocket maps to its ellipsoid, 3
//!   elliptical, 4 power series, 5 parabolic series, 6 Haack; `RockSimNoseConeCode`),
//!   `ShapeParameter`, `ShoulderLen`, `ShoulderOD`; `Transition`: `FrontDia`, `RearDia`, `Len`
//!   and the nose's shape and construction fields; `BodyTube`: `OD`, `ID`, `Len`,
//!   `IsMotorMount`, `EngineOverhang`;
//! - every part: `Name`, `Material`, `Density`, and a mass and centre-of-mass override,
//!   `KnownMass` (g) and `KnownCG` (mm from the part's fore end), both in force when
//!   `UseKnownCG` is 1 (`BaseHandler`);
//! - attached parts are placed by `Xb` (mm) and `LocationMode`: 0 from the parent's fore end,
//!   1 from the nose tip, 2 from the parent's aft end (`RockSimLocationMode`,
//!   `PositionDependentHandler`: offset -Xb from the bottom);
//! - `FinSet` and `CustomFinSet`: `FinCount`, `ShapeCode` (0 trapezoidal, 1 elliptical, 2
//!   custom: the planform, whichever the element), `RootChord`, `TipChord`, `SemiSpan`,
//!   `SweepDistance` (leading edge), `PointList` (custom: [`point_list`]), `Thickness`,
//!   `TipShapeCode` (0 square, 1 rounded, 2 airfoil), `CantAngle`, `RadialAngle` (radians,
//!   OpenRocket's base rotation; `FinSetHandler`);
//! - the motor: `SimulationList/Simulation/Stage3Engines/EngineSet` (`EngineCode`,
//!   `EngineMfg`, `EngineOverhang`) of each stored simulation.

use roxmltree::Node;

use super::shapes::NoseShape;
use super::{
    Cx, Deploy, Design, FinSet, FinShape, ImpTransition, MassItem, MotorRef, Mount, Nose,
    OrMaterial, Recovery, Tube, child, text_of,
};
use crate::diagnostics::Diagnostic;

const MM: f64 = 1e-3;

/// A tube marked `IsMotorMount`: its name, aft end (m from the tip), `EngineOverhang`, inner
/// diameter and length (m), and its element.
struct RsMount {
    name: String,
    aft: f64,
    overhang: f64,
    bore: f64,
    length: f64,
    at: crate::syntax::Span,
}
const G: f64 = 1e-3;

/// A number element in RockSim's units times `scale`; `None` when absent, an error when it
/// does not parse.
fn val(cx: &mut Cx, n: Node, name: &str, scale: f64) -> Result<Option<f64>, ()> {
    let Some(c) = child(n, name) else {
        return Ok(None);
    };
    let t = c.text().unwrap_or("").trim();
    if t.is_empty() {
        return Ok(None);
    }
    match t.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(Some(v * scale)),
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

fn req(cx: &mut Cx, n: Node, name: &str, scale: f64, what: &str) -> Option<f64> {
    match val(cx, n, name, scale) {
        Ok(Some(v)) => Some(v),
        Ok(None) => {
            cx.error(
                "import::value",
                n,
                format!("{what} has no `<{name}>`"),
                "in this part",
            );
            None
        }
        Err(()) => None,
    }
}

fn name_of(n: Node) -> String {
    text_of(n, "Name")
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .unwrap_or_else(|| n.tag_name().name().to_string())
}

fn material(cx: &mut Cx, n: Node) -> OrMaterial {
    let density = val(cx, n, "Density", 1.0).ok().flatten().unwrap_or(0.0);
    let at = cx.span(child(n, "Material").unwrap_or(n));
    OrMaterial {
        name: text_of(n, "Material").unwrap_or("").to_string(),
        density: density.max(0.0),
        at,
    }
}

/// The mass and centre-of-mass override (`UseKnownCG` = 1): (kg, m from the fore end).
fn known(cx: &mut Cx, n: Node) -> Option<(f64, f64)> {
    if text_of(n, "UseKnownCG") != Some("1") {
        return None;
    }
    let m = val(cx, n, "KnownMass", G).ok().flatten()?;
    let cg = val(cx, n, "KnownCG", MM).ok().flatten().unwrap_or(0.0);
    Some((m, cg))
}

fn shape(cx: &mut Cx, n: Node, what: &str) -> Option<NoseShape> {
    let code = text_of(n, "ShapeCode").unwrap_or("0");
    let k = val(cx, n, "ShapeParameter", 1.0)
        .ok()
        .flatten()
        .unwrap_or(0.0);
    Some(match code {
        "0" => NoseShape::Conical,
        "1" => NoseShape::Ogive(1.0),
        // RockSim's parabolic most resembles OpenRocket's ellipsoid (`RockSimNoseConeCode`).
        "2" | "3" => NoseShape::Ellipsoid,
        "4" => NoseShape::Power(k.clamp(0.0, 1.0)),
        "5" => NoseShape::Parabolic(k.clamp(0.0, 1.0)),
        "6" => NoseShape::Haack(k.clamp(0.0, 2.0)),
        _ => {
            cx.error(
                "import::value",
                n,
                format!("{what}: unknown RockSim shape code `{code}`"),
                "unknown shape",
            );
            return None;
        }
    })
}

/// A custom fin set's `<PointList>`: `x,y|x,y|...` in mm, x aft of the root's leading edge, y
/// outward (read as OpenRocket's `FinSetHandler.toCoordinates` does: a repeated `0,0`, which
/// RockSim sometimes writes, is dropped; a list ending at `0,0`, as RockSim writes it from the
/// root's trailing edge round to its leading edge, is reversed). In metres. A missing or empty
/// list, or an entry that is not two numbers, is an `import::value` error at the element
/// (where OpenRocket warns and skips the entry: a fin outline missing a point is another fin).
fn point_list(cx: &mut Cx, c: Node, what: &str) -> Option<Vec<(f64, f64)>> {
    let Some(pl) = child(c, "PointList") else {
        cx.error(
            "import::value",
            c,
            format!("{what}: a custom fin set (ShapeCode 2) without `<PointList>`"),
            "custom fin set",
        );
        return None;
    };
    let text = pl.text().unwrap_or("").trim();
    let mut pts: Vec<(f64, f64)> = Vec::new();
    for (k, entry) in text.split('|').enumerate() {
        let entry = entry.trim();
        if entry.is_empty() {
            continue; // RockSim ends the list with `|`
        }
        let xy: Vec<Option<f64>> = entry
            .split(',')
            .map(|v| v.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect();
        let (x, y) = match xy.as_slice() {
            [Some(x), Some(y)] => (x * MM, y * MM),
            _ => {
                cx.error(
                    "import::value",
                    pl,
                    format!(
                        "{what}: entry {} of the fin's point list, `{entry}`, is not a pair of numbers `x,y` (mm)",
                        k + 1
                    ),
                    "malformed point list",
                );
                return None;
            }
        };
        if pts.last() == Some(&(0.0, 0.0)) && (x, y) == (0.0, 0.0) {
            continue;
        }
        pts.push((x, y));
    }
    if pts.is_empty() {
        cx.error(
            "import::value",
            pl,
            format!("{what}: the fin's point list is empty"),
            "empty point list",
        );
        return None;
    }
    if pts.last() == Some(&(0.0, 0.0)) {
        pts.reverse();
    }
    Some(pts)
}

/// Where an attached part of length `own` starts, m aft of the tip, in a parent spanning
/// [top, top + len] (module doc).
fn place(cx: &mut Cx, n: Node, top: f64, len: f64, own: f64) -> f64 {
    let xb = val(cx, n, "Xb", MM).ok().flatten().unwrap_or(0.0);
    match text_of(n, "LocationMode") {
        Some("1") => xb,
        Some("2") => top + len - own - xb,
        _ => top + xb,
    }
}

/// Read a RockSim document (module doc).
pub(super) fn read(cx: &mut Cx, root: Node, path: &std::path::Path) -> Option<Design> {
    let version = text_of(root, "FileVersion").unwrap_or("?").to_string();
    let Some(rd) = child(root, "DesignInformation").and_then(|d| child(d, "RocketDesign")) else {
        cx.error(
            "import::format",
            root,
            "the RockSim document has no `<DesignInformation><RocketDesign>`".into(),
            "here",
        );
        return None;
    };
    let name = text_of(rd, "Name").unwrap_or("rocket").to_string();
    let designer = text_of(rd, "Designer")
        .filter(|s| !s.is_empty())
        .map(str::to_string);
    for booster in ["Stage2Parts", "Stage1Parts"] {
        if let Some(b) = child(rd, booster) {
            if b.children().any(|c| c.is_element()) {
                cx.error(
                    "import::multistage",
                    b,
                    format!("the design has a booster stage (`{booster}`): flexflight flies single-stage vehicles for now"),
                    "booster stage",
                );
                return None;
            }
        }
    }
    let Some(parts) = child(rd, "Stage3Parts") else {
        cx.error(
            "import::format",
            rd,
            "the design has no `<Stage3Parts>`".into(),
            "here",
        );
        return None;
    };
    let mut nose: Option<Nose> = None;
    let mut tubes: Vec<Tube> = Vec::new();
    let mut transitions: Vec<ImpTransition> = Vec::new();
    let mut masses: Vec<MassItem> = Vec::new();
    let mut fins: Vec<(FinSet, Node)> = Vec::new();
    let mut mounts: Vec<RsMount> = Vec::new();
    let mut recovery: Vec<Recovery> = Vec::new();
    let mut guides: Vec<super::Guide> = Vec::new();
    let mut s = 0.0;
    let mut r_prev: Option<f64> = None;
    let mut ahead = String::new();
    for (i, c) in parts.children().filter(Node::is_element).enumerate() {
        let tag = c.tag_name().name();
        let nm = name_of(c);
        let (top, len, r_fore) = match tag {
            "NoseCone" if i == 0 => {
                let what = format!("nose cone `{nm}`");
                let len = req(cx, c, "Len", MM, &what);
                let dia = req(cx, c, "BaseDia", MM, &what);
                let wall = val(cx, c, "WallThickness", MM)
                    .ok()
                    .flatten()
                    .unwrap_or(0.0);
                let filled = text_of(c, "ConstructionType") == Some("0");
                let sh = shape(cx, c, &what);
                let mat = material(cx, c);
                let kn = known(cx, c);
                let (Some(len), Some(dia), Some(sh)) = (len, dia, sh) else {
                    continue;
                };
                let sl = val(cx, c, "ShoulderLen", MM).ok().flatten().unwrap_or(0.0);
                let sd = val(cx, c, "ShoulderOD", MM).ok().flatten().unwrap_or(0.0);
                if sl > 0.0 && sd > 0.0 {
                    let ro = 0.5 * sd;
                    let ri = if filled { 0.0 } else { (ro - wall).max(0.0) };
                    masses.push(MassItem {
                        name: format!("{nm} shoulder"),
                        mass: std::f64::consts::PI * (ro * ro - ri * ri) * sl * mat.density,
                        s0: len,
                        s1: len + sl,
                        note: "nose-cone shoulder, a tube of the nose's material inside the body"
                            .into(),
                    });
                }
                nose = Some(Nose {
                    name: nm.clone(),
                    shape: sh,
                    length: len,
                    radius: 0.5 * dia,
                    thickness: wall,
                    filled,
                    material: mat,
                    override_mass: kn.map(|k| k.0),
                    override_cg: kn.map(|k| k.1),
                });
                r_prev = Some(0.5 * dia);
                ahead = format!("nose cone `{nm}`");
                (0.0, len, None)
            }
            "BodyTube" => {
                let what = format!("body tube `{nm}`");
                let len = req(cx, c, "Len", MM, &what);
                let od = req(cx, c, "OD", MM, &what);
                let id = req(cx, c, "ID", MM, &what);
                let mat = material(cx, c);
                let kn = known(cx, c);
                let (Some(len), Some(od), Some(id)) = (len, od, id) else {
                    continue;
                };
                if text_of(c, "IsMotorMount") == Some("1") {
                    let oh = val(cx, c, "EngineOverhang", MM)
                        .ok()
                        .flatten()
                        .unwrap_or(0.0);
                    mounts.push(RsMount {
                        name: nm.clone(),
                        aft: s + len,
                        overhang: oh,
                        bore: id,
                        length: len,
                        at: cx.span(c),
                    });
                }
                if kn.is_some_and(|k| k.1 > 0.0) {
                    cx.warn(c, format!("{what}: its CG override is not representable (the tube is generated uniform); its mass is kept"));
                }
                tubes.push(Tube {
                    name: nm.clone(),
                    top: s,
                    length: len,
                    radius: 0.5 * od,
                    thickness: 0.5 * (od - id),
                    material: mat,
                    override_mass: kn.map(|k| k.0),
                });
                (s, len, Some((0.5 * od, format!("body tube `{nm}`"))))
            }
            "Transition" => {
                let what = format!("transition `{nm}`");
                let len = req(cx, c, "Len", MM, &what);
                let fd = req(cx, c, "FrontDia", MM, &what);
                let ad = req(cx, c, "RearDia", MM, &what);
                let wall = val(cx, c, "WallThickness", MM)
                    .ok()
                    .flatten()
                    .unwrap_or(0.0);
                let filled = text_of(c, "ConstructionType") == Some("0");
                let sh = shape(cx, c, &what);
                let mat = material(cx, c);
                let kn = known(cx, c);
                let (Some(len), Some(fd), Some(ad), Some(sh)) = (len, fd, ad, sh) else {
                    continue;
                };
                transitions.push(ImpTransition {
                    name: nm.clone(),
                    top: s,
                    length: len,
                    r_fore: 0.5 * fd,
                    r_aft: 0.5 * ad,
                    thickness: wall,
                    filled,
                    shape: sh,
                    clipped: false,
                    material: mat,
                    override_mass: kn.map(|k| k.0),
                    override_cg: kn.map(|k| k.1),
                    at: cx.span(c),
                });
                (s, len, Some((0.5 * fd, format!("transition `{nm}`"))))
            }
            "NoseCone" => {
                cx.error(
                    "import::unsupported",
                    c,
                    format!("nose cone `{nm}` is not the first part: a second nose cannot be represented"),
                    "not first",
                );
                continue;
            }
            "SubAssembly" | "ExternalPod" => {
                cx.error(
                    "import::unsupported",
                    c,
                    format!("`{nm}` ({tag}) cannot be represented: sub-assemblies and pods are not in the language"),
                    "not representable",
                );
                continue;
            }
            _ => {
                cx.error(
                    "import::component",
                    c,
                    format!("unknown part `<{tag}>` (`{nm}`) on the stage"),
                    "unknown part",
                );
                continue;
            }
        };
        // Each part starts at the radius the section ahead ends at.
        if let (Some((r, what)), Some(rp)) = (&r_fore, r_prev) {
            let bridged = tag == "BodyTube"
                && tubes
                    .last_mut()
                    .is_some_and(|t| super::bridge_step(cx, c, t, rp, &ahead, &mut transitions));
            if !bridged && (r - rp).abs() > 1e-6 {
                cx.error(
                    "import::diameter",
                    c,
                    format!(
                        "{what} starts at diameter {:.3} mm, the {ahead} ends at {:.3} mm: a step in diameter without a transition cannot be represented",
                        2e3 * r,
                        2e3 * rp
                    ),
                    "another diameter",
                );
            }
        }
        if let Some((_, what)) = &r_fore {
            r_prev = Some(match tag {
                "Transition" => transitions.last().map_or(0.0, |t| t.r_aft),
                _ => tubes.last().map_or(0.0, |t| t.radius),
            });
            ahead = what.clone();
        }
        if let Some(ap) = child(c, "AttachedParts") {
            attached(
                cx,
                ap,
                top,
                len,
                &nm,
                &mut masses,
                &mut fins,
                &mut mounts,
                &mut recovery,
                &mut guides,
            );
        }
        s = top + len;
    }
    // The sets as the language's (`arrange_fin_sets`: the aft-most is the flexible set).
    let mut fin_notes = Vec::new();
    let fin = super::arrange_fin_sets(fins.into_iter().map(|f| f.0).collect(), &mut fin_notes);
    if fin.is_none() {
        cx.error(
            "import::unsupported",
            parts,
            "the design has no fin set: flexflight's vehicles have one".into(),
            "this stage",
        );
    }
    if cx.diags.iter().any(Diagnostic::is_error) {
        return None;
    }
    let Some(nose) = nose else {
        cx.error(
            "import::unsupported",
            parts,
            "the design has no nose cone as its first part: the generated body starts with a nose"
                .into(),
            "this stage",
        );
        return None;
    };
    if tubes.is_empty() {
        cx.error(
            "import::unsupported",
            parts,
            "the design has no body tube".into(),
            "this stage",
        );
        return None;
    }
    // The motors of the stored simulations (one configuration each).
    let mut motors = Vec::new();
    let mut configs = Vec::new();
    if let Some(list) = child(root, "SimulationList") {
        for (k, sim) in list
            .children()
            .filter(|c| c.has_tag_name("Simulation"))
            .enumerate()
        {
            let Some(set) = child(sim, "Stage3Engines").and_then(|e| child(e, "EngineSet")) else {
                continue;
            };
            let Some(code) = text_of(set, "EngineCode").filter(|s| !s.is_empty()) else {
                continue;
            };
            let config = format!("rocksim-{}", k + 1);
            configs.push(config.clone());
            motors.push(MotorRef {
                config,
                designation: code.to_string(),
                manufacturer: text_of(set, "EngineMfg")
                    .filter(|s| !s.is_empty())
                    .map(str::to_string),
                delay: None,
                length: None,
                diameter: None,
                at: cx.span(set),
            });
        }
    }
    let mount = match mounts.as_slice() {
        [] => None,
        [m] => Some(Mount {
            name: m.name.clone(),
            aft: m.aft,
            overhang: m.overhang,
            motors,
            bore: (m.bore > 0.0).then_some(m.bore),
            length: (m.length > 0.0).then_some(m.length),
            at: m.at,
        }),
        _ => {
            cx.error(
                "import::unsupported",
                parts,
                format!(
                    "the design has {} motor mounts ({}): one motor is represented",
                    mounts.len(),
                    mounts
                        .iter()
                        .map(|m| m.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                "this stage",
            );
            None
        }
    };
    let mut notes = vec![format!(
        "RockSim file version {version}: lengths in mm, masses in g; RockSim's stored simulation results and launch conditions are not read (a default scenario is written)"
    )];
    notes.extend(fin_notes);
    let found = finishes(cx, parts);
    let finish = super::choose_finish(cx, &found, &mut notes);
    if cx.diags.iter().any(Diagnostic::is_error) {
        return None;
    }
    // The steps bridged by `bridge_step` come after the design's own transitions.
    transitions.sort_by(|a, b| a.top.total_cmp(&b.top));
    Some(Design {
        file: path.to_path_buf(),
        name,
        designer,
        version: version.clone(),
        creator: Some("RockSim".into()),
        nose,
        tubes,
        transitions,
        fins: fin.as_ref()?.0.clone(),
        more_fins: fin?.1,
        masses,
        mount,
        recovery,
        simulations: Vec::new(),
        default_config: configs.first().cloned(),
        configs,
        notes,
        finish,
        guides,
    })
}

/// The `<FinishCode>` of each part, as OpenRocket's RockSim reader maps them
/// (`RockSimFinishCode`: 0 polished -> OpenRocket's POLISHED, 2 um; 1 gloss -> SMOOTH,
/// 20 um; 2 matt -> NORMAL, 60 um; 3 unfinished -> UNFINISHED, 150 um). OpenRocket takes
/// any other code as matt; we say so in a warning.
fn finishes<'a, 'i>(
    cx: &mut Cx,
    parts: Node<'a, 'i>,
) -> Vec<(String, Node<'a, 'i>, &'static str, String)> {
    let mut found = Vec::new();
    for f in parts.descendants().filter(|n| n.has_tag_name("FinishCode")) {
        let Some(comp) = f.parent_element() else {
            continue;
        };
        let text = f.text().unwrap_or("").trim().to_string();
        let (name, said) = match text.as_str() {
            "0" => ("sheet_metal", "polished (FinishCode 0)"),
            "1" => ("smooth_paint", "gloss (FinishCode 1)"),
            "2" => ("regular_paint", "matt (FinishCode 2)"),
            "3" => ("unfinished", "unfinished (FinishCode 3)"),
            _ => {
                cx.warn(
                    f,
                    format!("`{}`: unknown RockSim FinishCode `{text}`, taken as matt (regular paint, 60 um) as OpenRocket does", name_of(comp)),
                );
                ("regular_paint", "matt (an unknown FinishCode)")
            }
        };
        found.push((name_of(comp), f, name, said.to_string()));
    }
    found
}

/// The parts attached to a body part spanning [top, top + len] (module doc): fin sets, inner
/// tubes (a motor mount), and masses (mass objects, rings, launch lugs, recovery devices).
#[allow(clippy::too_many_arguments)]
fn attached<'a, 'i>(
    cx: &mut Cx,
    ap: Node<'a, 'i>,
    top: f64,
    len: f64,
    parent: &str,
    masses: &mut Vec<MassItem>,
    fins: &mut Vec<(FinSet, Node<'a, 'i>)>,
    mounts: &mut Vec<RsMount>,
    recovery: &mut Vec<Recovery>,
    guides: &mut Vec<super::Guide>,
) {
    use std::f64::consts::PI;
    for c in ap.children().filter(Node::is_element) {
        let tag = c.tag_name().name();
        let nm = name_of(c);
        let what = format!("{tag} `{nm}` (in `{parent}`)");
        let mat = material(cx, c);
        let kn = known(cx, c);
        let own = val(cx, c, "Len", MM).ok().flatten().unwrap_or(0.0);
        let at = place(cx, c, top, len, own);
        let mut mass_item = |mass: f64, note: &str| {
            let (mass, s0, s1, note) = match kn {
                Some((m, cg)) => (
                    m,
                    at + cg,
                    at + cg,
                    format!("{note}; mass and CG given in the design"),
                ),
                None => (mass, at, at + own, note.to_string()),
            };
            masses.push(MassItem {
                name: nm.clone(),
                mass,
                s0,
                s1,
                note,
            });
        };
        match tag {
            "FinSet" | "CustomFinSet" => {
                // The planform is `ShapeCode`'s (0 trapezoidal, 1 elliptical, 2 custom), not
                // the element's name (OpenRocket's `FinSetHandler.asOpenRocket`).
                let count = val(cx, c, "FinCount", 1.0).ok().flatten().unwrap_or(0.0);
                let thickness = req(cx, c, "Thickness", MM, &what);
                let code = text_of(c, "ShapeCode")
                    .unwrap_or(if tag == "CustomFinSet" { "2" } else { "0" })
                    .to_string();
                let (root, tip, span, sweep, outline) = match code.as_str() {
                    "0" => (
                        req(cx, c, "RootChord", MM, &what),
                        req(cx, c, "TipChord", MM, &what),
                        req(cx, c, "SemiSpan", MM, &what),
                        val(cx, c, "SweepDistance", MM).ok().flatten().or(Some(0.0)),
                        FinShape::Trapezoidal,
                    ),
                    "1" => (
                        req(cx, c, "RootChord", MM, &what),
                        Some(0.0),
                        req(cx, c, "SemiSpan", MM, &what),
                        Some(0.0),
                        FinShape::Elliptical,
                    ),
                    "2" => {
                        let outline = point_list(cx, c, &what).and_then(|p| {
                            let at = child(c, "PointList").unwrap_or(c);
                            super::checked_outline(cx, at, p, &what)
                        });
                        match outline {
                            Some((pts, root, span)) => (
                                Some(root),
                                Some(0.0),
                                Some(span),
                                Some(0.0),
                                FinShape::Freeform(pts),
                            ),
                            None => continue,
                        }
                    }
                    _ => {
                        cx.error(
                            "import::value",
                            c,
                            format!("{what}: unknown RockSim fin shape code `{code}` (0 trapezoidal, 1 elliptical, 2 custom)"),
                            "unknown shape",
                        );
                        continue;
                    }
                };
                let (Some(root), Some(tip), Some(span), Some(sweep), Some(thickness)) =
                    (root, tip, span, sweep, thickness)
                else {
                    continue;
                };
                let root_le = place(cx, c, top, len, root);
                let cant = val(cx, c, "CantAngle", 1.0).ok().flatten().unwrap_or(0.0);
                // `RadialAngle` (radians) turns the set about the axis (OpenRocket's base
                // rotation, `setBaseRotation`); its fins evenly from it.
                let turn = val(cx, c, "RadialAngle", 1.0)
                    .ok()
                    .flatten()
                    .unwrap_or(0.0)
                    .to_degrees();
                let count = count.max(0.0) as u32;
                fins.push((
                    FinSet {
                        name: nm.clone(),
                        count,
                        angles: FinSet::default_angles(count, turn),
                        root,
                        tip,
                        span,
                        sweep,
                        thickness,
                        cross_section: match text_of(c, "TipShapeCode") {
                            Some("1") => "rounded",
                            Some("2") => "airfoil",
                            _ => "square",
                        },
                        cant: cant.to_degrees(),
                        root_le,
                        material: mat,
                        override_mass: kn.map(|k| k.0),
                        outline,
                        // RockSim's fillets are not read (OpenRocket's RockSim reader does
                        // not read them either: no element to follow).
                        fillet: None,
                    },
                    c,
                ));
            }
            "BodyTube" => {
                // An inner tube: a motor mount or a tube of mass.
                let od = val(cx, c, "OD", MM).ok().flatten().unwrap_or(0.0);
                let id = val(cx, c, "ID", MM).ok().flatten().unwrap_or(0.0);
                if text_of(c, "IsMotorMount") == Some("1") {
                    let oh = val(cx, c, "EngineOverhang", MM)
                        .ok()
                        .flatten()
                        .unwrap_or(0.0);
                    mounts.push(RsMount {
                        name: nm.clone(),
                        aft: at + own,
                        overhang: oh,
                        bore: id,
                        length: own,
                        at: cx.span(c),
                    });
                }
                let m = PI / 4.0 * (od * od - id * id) * own * mat.density;
                mass_item(m, "inner tube");
            }
            "Ring" => {
                let od = val(cx, c, "OD", MM).ok().flatten().unwrap_or(0.0);
                let id = val(cx, c, "ID", MM).ok().flatten().unwrap_or(0.0);
                let m = PI / 4.0 * (od * od - id * id) * own * mat.density;
                mass_item(m, "ring (centring ring, coupler or bulkhead)");
            }
            "MassObject" => {
                let m = val(cx, c, "KnownMass", G).ok().flatten().unwrap_or(0.0);
                mass_item(m, "mass object");
            }
            "LaunchLug" => {
                let od = val(cx, c, "OD", MM).ok().flatten().unwrap_or(0.0);
                let id = val(cx, c, "ID", MM).ok().flatten().unwrap_or(0.0);
                let m = PI / 4.0 * (od * od - id * id) * own * mat.density;
                mass_item(m, "launch lug (off-axis mass placed on the axis)");
                if !(od > 0.0 && id >= 0.0 && id < od && own > 0.0) {
                    cx.error(
                        "import::value",
                        c,
                        format!("{what}: a launch lug needs 0 <= ID < OD and a length"),
                        "launch lug",
                    );
                }
                guides.push(super::Guide {
                    name: nm.clone(),
                    kind: super::GuideKind::Lug {
                        top: at,
                        length: own,
                        outer_diameter: od,
                        inner_diameter: id,
                    },
                });
            }
            "Parachute" | "Streamer" => {
                let cd = val(cx, c, "DragCoefficient", 1.0)
                    .ok()
                    .flatten()
                    .unwrap_or(0.0);
                let area = if tag == "Parachute" {
                    let d = val(cx, c, "Dia", MM).ok().flatten().unwrap_or(0.0);
                    PI * d * d / 4.0
                } else {
                    own * val(cx, c, "Width", MM).ok().flatten().unwrap_or(0.0)
                };
                let m = kn.map_or(0.0, |k| k.0);
                mass_item(m, "recovery device (mass as given)");
                cx.warn(c, format!("{what}: RockSim keeps its deployment in the simulation settings, which are not read: it opens at apogee"));
                recovery.push(Recovery {
                    name: nm.clone(),
                    cd,
                    cd_auto: false,
                    area,
                    // RockSim keeps deployment in its simulation settings, not read: apogee.
                    deploy: Deploy::Apogee,
                    delay: 0.0,
                });
            }
            "SubAssembly" | "TubeFinSet" | "RingTail" | "ExternalPod" => {
                cx.error(
                    "import::unsupported",
                    c,
                    format!("{what} cannot be represented ({tag})"),
                    "not representable",
                );
            }
            _ => {
                cx.warn(c, format!("{what}: an unknown attached part, ignored"));
            }
        }
    }
}
