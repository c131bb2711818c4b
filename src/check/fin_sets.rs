//! Further fin sets of a vehicle (`fins NAME { ... }`, issue 34): canards, a second set of
//! fins on the same stage.
//!
//! Each named `fins` block has every field of the unnamed one and is checked by the same
//! code (`check_fins` of `check::vehicle`, passed in). What is checked here is what a second
//! set adds:
//! - the vehicle's structure is generated (`structure { generate { ... } }`): a further set's
//!   mass enters the generated model as a rigid body; an imported FE model carries its own
//!   masses and cannot be told about it (`vdl::fins::placement`);
//! - its root chord lies on the body tube, not on the nose (`vdl::fins::placement`), and not
//!   on a transition (the unnamed set's rule, `transition_check::check_fins_clear`); a root
//!   forward of the nose tip or aft of the tail is `check_fins`' own `vdl::value::range`;
//! - no two sets, the unnamed one included, overlap: their root chords share a station range
//!   and two of their fins stand at the same angle about the body axis, i.e. closer than the
//!   half-thicknesses of the two fins at the body's surface (`vdl::fins::overlap`);
//! - duplicate names are `vdl::duplicate`, reported by `Fields` for any named block.
//!
//! A further set is rigid in the flight: its mass is a rigid body on the nearest body node
//! (`structure::generate`), its aerodynamics part of the built-in estimator's body table
//! (`aero::estimator`, with its cant's roll forcing and its roll damping in the body table's
//! roll columns): no elastic modes, no fin key node, no fin load). Its clamped-fin flutter margin is computed as the unnamed set's is
//! (`ops::flutter::flight_margin_with`). A warning at `check` says so for each set
//! (`vdl::fins::rigid_set`), and says where the aerodynamics come from tables or DATCOM that
//! they must hold the set's contribution themselves.

use crate::diagnostics::Diagnostic;
use crate::syntax::Spanned;
use crate::syntax::ast::Block;

use super::Cx;
use super::ir::{Aero, AeroSource, FinSet, Fins, Structure};

/// Checks the named `fins` blocks `blocks` with `check_fins` and what a further set adds
/// (module doc). `primary` is the unnamed set, if it checked. `None` when any set failed
/// (each failure reported).
pub(super) fn check_fin_sets(
    cx: &mut Cx,
    blocks: &[&Block],
    primary: Option<&Fins>,
    structure: Option<&Structure>,
    aero: Option<&Aero>,
    mut check_fins: impl FnMut(&mut Cx, &Block) -> Option<Fins>,
) -> Option<Vec<FinSet>> {
    let mut sets = Vec::with_capacity(blocks.len());
    let mut ok = true;
    for b in blocks {
        let Some(name) = &b.name else { continue };
        let Some(fins) = check_fins(cx, b) else {
            ok = false;
            continue;
        };
        match structure {
            Some(Structure::Generate(g)) => {
                let (_, fore) = fins.root_stations();
                let nose = g.body.nose_length.value;
                if -fore < nose - 1e-12 * nose {
                    cx.push(
                        Diagnostic::error(
                            "vdl::fins::placement",
                            format!(
                                "fin set `{}` has its root chord on the nose: its leading edge is {:.4} m aft of the tip, the nose is {:.4} m long",
                                name.name,
                                -fore,
                                nose
                            ),
                        )
                        .label(fins.root_trailing_edge_x.span, "root trailing edge station")
                        .label(g.body.nose_length.span, "the nose")
                        .with_help("fins sit on the body tube: move the set aft so its root leading edge is behind the nose's base"),
                    );
                    ok = false;
                    continue;
                }
                if !super::transition_check::check_fins_clear(cx, &g.body, &fins) {
                    ok = false;
                    continue;
                }
            }
            Some(Structure::Files(f)) => {
                cx.push(
                    Diagnostic::error(
                        "vdl::fins::placement",
                        format!(
                            "fin set `{}` needs a generated structure: a further set's mass enters the generated model as a rigid body, and an imported FE model holds its own masses",
                            name.name
                        ),
                    )
                    .label(b.header, "a further fin set")
                    .label(f.span, "the structure is read from files")
                    .with_help("put the set's mass into the FE model and its aerodynamics into the coefficient tables, and remove this block"),
                );
                ok = false;
                continue;
            }
            None => {}
        }
        let mut d = Diagnostic::warning(
            "vdl::fins::rigid_set",
            format!(
                "fin set `{}` is rigid in the flight: its mass is a rigid body on the body, its aerodynamics are part of the body's coefficients; it has no elastic modes and no fin loads (its clamped-fin flutter margin is computed)",
                name.name
            ),
        )
        .label(b.header, "a further, rigid fin set");
        let tabulated = matches!(
            aero.map(|a| &a.source),
            Some(AeroSource::Tables { .. }) | Some(AeroSource::Datcom { .. })
        );
        if fins.cant.value != 0.0 && tabulated {
            d = d.label(
                fins.cant.span,
                "this cant rolls the vehicle only through the body table's roll columns `cl_0, cl_p`",
            );
        }
        d = match aero.map(|a| &a.source) {
            Some(AeroSource::Tables { .. }) | Some(AeroSource::Datcom { .. }) => d.with_help(
                "the aerodynamics come from tables: their body coefficients must include this set (the built-in estimator adds it itself)",
            ),
            _ => d.with_help(
                "the unnamed `fins` block is the vehicle's flexible, meshed set: make the set whose flexibility matters that one",
            ),
        };
        cx.push(d);
        sets.push(FinSet {
            name: Spanned::new(name.name.clone(), name.span),
            fins,
        });
    }
    if !ok {
        return None;
    }
    // Overlaps: every pair among the unnamed set and the named ones.
    let all: Vec<(&str, &Fins)> = primary
        .map(|p| ("fins", p))
        .into_iter()
        .chain(sets.iter().map(|s| (s.name.value.as_str(), &s.fins)))
        .collect();
    let radius = |f: &Fins| match structure {
        Some(Structure::Generate(g)) => g.body.radius_under(f),
        _ => 0.5,
    };
    for (i, (na, a)) in all.iter().enumerate() {
        for (nb, b) in &all[i + 1..] {
            if let Some((ka, kb)) = overlap(a, radius(a), b, radius(b)) {
                let name = |n: &str| {
                    if n == "fins" {
                        "the `fins` block".to_string()
                    } else {
                        format!("fin set `{n}`")
                    }
                };
                cx.push(
                    Diagnostic::error(
                        "vdl::fins::overlap",
                        format!(
                            "{} and {} overlap: their root chords share body stations and fin {} of one stands where fin {} of the other does ({:.3} deg and {:.3} deg)",
                            name(na),
                            name(nb),
                            ka + 1,
                            kb + 1,
                            a.angles[ka].value.to_degrees(),
                            b.angles[kb].value.to_degrees(),
                        ),
                    )
                    .label(b.root_trailing_edge_x.span, "this set's root")
                    .label(a.root_trailing_edge_x.span, "the other set's root")
                    .with_help("move one set along the body so the root chords do not share stations, or turn it with `angles = [...]`"),
                );
                ok = false;
            }
        }
    }
    ok.then_some(sets)
}

/// Do fin sets `a` and `b` (body radii `ra`, `rb` under their roots) overlap? Their root
/// chords share an open station range, and a fin of each stands at the same angle: the
/// angular distance between them, reduced to [0, pi], below the sum of the two fins' half
/// thicknesses over the body radius (the angles their roots subtend). The indices of the
/// first such pair of fins.
pub fn overlap(a: &Fins, ra: f64, b: &Fins, rb: f64) -> Option<(usize, usize)> {
    let ((a_aft, a_fore), (b_aft, b_fore)) = (a.root_stations(), b.root_stations());
    if a_fore <= b_aft || b_fore <= a_aft {
        return None;
    }
    let r = ra.min(rb).max(f64::MIN_POSITIVE);
    let width = 0.5 * (a.thickness.value + b.thickness.value) / r;
    let two_pi = 2.0 * std::f64::consts::PI;
    for (i, da) in a.angles.iter().enumerate() {
        for (j, db) in b.angles.iter().enumerate() {
            let d = (da.value - db.value).rem_euclid(two_pi);
            if d.min(two_pi - d) < width {
                return Some((i, j));
            }
        }
    }
    None
}
