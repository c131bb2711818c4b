//! Motors by name: the bundled catalogue of published RASP thrust curves (`motors/`, embedded
//! in the binary, provenance per file in `motors/README.md`) and the matching of a designation
//! as rocketeers write it (`M1670`, `Cesaroni M1670`, `CTI M1670-BS`, `aerotech k1000t`).
//!
//! A bundled curve is named in the IR by a virtual path, [`BUNDLED_PREFIX`] + file name
//! (`bundled:motors/Cesaroni_M1670.eng`), which [`ThrustCurve::read`] resolves here rather than
//! on the disk: the vehicle's checked motor then carries its curve like a user's file.
//!
//! # Matching
//!
//! A designation string is split into an optional manufacturer (leading words that name a
//! maker, by full name, common short form or RASP maker code: `Cesaroni`, `Cesaroni
//! Technology`, `CTI`) and the motor's name (the last word). Names are compared upper-cased
//! with every character that is not a letter or digit removed (`M1670-BS`, `m1670bs`), in
//! three tiers; the first tier with any match decides:
//!
//! 1. the whole name (`M1670-BS` = `M1670BS`; `H125W-29mm`);
//! 2. the common part before the curve name's first `-` (`K1000T-P` answers `K1000T`;
//!    `H125W-29mm` and `H125W-38mm` both answer `H125W`, which is then ambiguous);
//! 3. both names' common parts with their trailing propellant letters dropped (`G80T` finds
//!    the RASAero file's `G80`, `I284` finds `I284W`).
//!
//! The manufacturer, where given, must agree with the curve's. Several curves in the deciding
//! tier are ambiguous (the candidates are listed); none is not-found, and the nearest curves
//! are listed: those of the same impulse class, then of the neighbouring classes, by the
//! ratio of average thrust (the number after the class letter).

use std::path::Path;

use super::thrust::ThrustCurve;

/// Prefix of the virtual path naming a bundled curve.
pub const BUNDLED_PREFIX: &str = "bundled:motors/";

/// The bundled curves: (file name, text).
pub const BUNDLED: &[(&str, &str)] = &[
    (
        "AeroTech_G64.eng",
        include_str!("../../motors/AeroTech_G64.eng"),
    ),
    (
        "AeroTech_G80.eng",
        include_str!("../../motors/AeroTech_G80.eng"),
    ),
    (
        "AeroTech_H125W-29mm.eng",
        include_str!("../../motors/AeroTech_H125W-29mm.eng"),
    ),
    (
        "AeroTech_H125W-38mm.eng",
        include_str!("../../motors/AeroTech_H125W-38mm.eng"),
    ),
    (
        "AeroTech_H128W.eng",
        include_str!("../../motors/AeroTech_H128W.eng"),
    ),
    (
        "AeroTech_H238T.eng",
        include_str!("../../motors/AeroTech_H238T.eng"),
    ),
    (
        "AeroTech_I218R.eng",
        include_str!("../../motors/AeroTech_I218R.eng"),
    ),
    (
        "AeroTech_I284W.eng",
        include_str!("../../motors/AeroTech_I284W.eng"),
    ),
    (
        "AeroTech_J350W.eng",
        include_str!("../../motors/AeroTech_J350W.eng"),
    ),
    (
        "AeroTech_J570W.eng",
        include_str!("../../motors/AeroTech_J570W.eng"),
    ),
    (
        "AeroTech_K1000T.eng",
        include_str!("../../motors/AeroTech_K1000T.eng"),
    ),
    (
        "AeroTech_K550W.eng",
        include_str!("../../motors/AeroTech_K550W.eng"),
    ),
    (
        "AeroTech_L1150.eng",
        include_str!("../../motors/AeroTech_L1150.eng"),
    ),
    (
        "AeroTech_M1315W.eng",
        include_str!("../../motors/AeroTech_M1315W.eng"),
    ),
    (
        "Cesaroni_I285.eng",
        include_str!("../../motors/Cesaroni_I285.eng"),
    ),
    (
        "Cesaroni_J285.eng",
        include_str!("../../motors/Cesaroni_J285.eng"),
    ),
    (
        "Cesaroni_K660.eng",
        include_str!("../../motors/Cesaroni_K660.eng"),
    ),
    (
        "Cesaroni_L1115.eng",
        include_str!("../../motors/Cesaroni_L1115.eng"),
    ),
    (
        "Cesaroni_M1400.eng",
        include_str!("../../motors/Cesaroni_M1400.eng"),
    ),
    (
        "Cesaroni_M1670.eng",
        include_str!("../../motors/Cesaroni_M1670.eng"),
    ),
    ("Estes_A8.eng", include_str!("../../motors/Estes_A8.eng")),
    ("Estes_B4.eng", include_str!("../../motors/Estes_B4.eng")),
    ("Estes_C6.eng", include_str!("../../motors/Estes_C6.eng")),
    ("Estes_D12.eng", include_str!("../../motors/Estes_D12.eng")),
];

/// The text of a bundled curve named by its virtual path (`bundled:motors/FILE`), if it is one.
pub fn bundled_text(path: &Path) -> Option<&'static str> {
    let file = path.to_str()?.strip_prefix(BUNDLED_PREFIX)?;
    BUNDLED.iter().find(|(f, _)| *f == file).map(|(_, t)| *t)
}

/// The virtual path of a bundled file.
pub fn bundled_path(file: &str) -> std::path::PathBuf {
    std::path::PathBuf::from(format!("{BUNDLED_PREFIX}{file}"))
}

/// Full manufacturer names for RASP maker codes (thrustcurve.org's abbreviations) and the
/// forms OpenRocket and rocketeers write.
pub fn maker_name(code: &str) -> &str {
    match norm(code).as_str() {
        "ES" | "ESTES" => "Estes",
        "AT" | "AEROTECH" | "AEROTECHRCS" | "RCS" => "AeroTech",
        "CTI" | "CESARONI" | "CESARONITECHNOLOGY" | "CESARONITECHNOLOGYINC" | "PRO" => "Cesaroni",
        "AP" | "APOGEE" => "Apogee",
        "QU" | "QUEST" => "Quest",
        "KL" | "KLIMA" => "Klima",
        "LOKI" | "LOKIRESEARCH" => "Loki",
        "HT" | "HYPERTEK" => "Hypertek",
        "AMW" | "ANIMALMOTORWORKS" => "Animal Motor Works",
        _ => code,
    }
}

/// Upper-cased, letters and digits only.
pub fn norm(s: &str) -> String {
    s.chars()
        .filter(|c| c.is_alphanumeric())
        .flat_map(char::to_uppercase)
        .collect()
}

/// The common part of a curve name (before its first `-`), normalised.
fn common(name: &str) -> String {
    norm(name.split('-').next().unwrap_or(name))
}

/// A normalised common part without its trailing propellant letters (`G80T` -> `G80`).
fn stripped(common: &str) -> &str {
    let s = common.trim_end_matches(|c: char| c.is_ascii_alphabetic());
    if s.len() >= 2 { s } else { common }
}

/// The matching tier (1, 2, 3) at which a curve name answers a designation, if any.
pub fn match_tier(rasp: &str, designation: &str) -> Option<u8> {
    if norm(rasp) == norm(designation) {
        return Some(1);
    }
    let (r, d) = (common(rasp), common(designation));
    if r == d || r == norm(designation) {
        return Some(2);
    }
    (stripped(&r) == stripped(&d) && d.len() >= 2).then_some(3)
}

/// Whether a RASP curve name matches a designation at any tier.
pub fn name_matches(rasp: &str, designation: &str) -> bool {
    match_tier(rasp, designation).is_some()
}

/// Whether `manufacturer` (any written form) is the curve's maker (a RASP code).
pub fn maker_matches(curve_maker: Option<&str>, manufacturer: Option<&str>) -> bool {
    match (manufacturer, curve_maker) {
        (Some(m), Some(e)) => {
            // OpenRocket writes `Cesaroni Technology`, RASP `CTI`: a prefix suffices.
            let (m, e) = (norm(maker_name(m)), norm(maker_name(e)));
            m.starts_with(&e) || e.starts_with(&m)
        }
        _ => true,
    }
}

/// Whether `words` names a manufacturer the catalogue knows.
fn is_maker(words: &str) -> bool {
    maker_name(words) != words
        || BUNDLED
            .iter()
            .any(|(f, _)| f.split('_').next().is_some_and(|m| norm(m) == norm(words)))
}

/// A designation string split into manufacturer and motor name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Designation {
    pub manufacturer: Option<String>,
    pub name: String,
}

/// Splits `Cesaroni Technology M1670` into (`Cesaroni Technology`, `M1670`). Leading words
/// that do not name a known maker are an error carrying them.
pub fn parse_designation(s: &str) -> Result<Designation, String> {
    let words: Vec<&str> = s.split_whitespace().collect();
    match words.as_slice() {
        [] => Err(String::new()),
        [one] => Ok(Designation {
            manufacturer: None,
            name: (*one).to_string(),
        }),
        [lead @ .., last] => {
            let maker = lead.join(" ");
            if is_maker(&maker) {
                Ok(Designation {
                    manufacturer: Some(maker),
                    name: (*last).to_string(),
                })
            } else {
                Err(maker)
            }
        }
    }
}

/// One bundled curve.
#[derive(Clone, Debug)]
pub struct Entry {
    pub file: &'static str,
    pub curve: ThrustCurve,
}

impl Entry {
    /// `Cesaroni M1670-BS` for candidate lists.
    pub fn describe(&self) -> String {
        let maker = self.curve.maker.as_deref().map(maker_name).unwrap_or("?");
        format!("{maker} {}", self.curve.name)
    }
}

/// The bundled catalogue, parsed (every bundled file parses: a unit test keeps it so).
pub fn bundled() -> Vec<Entry> {
    BUNDLED
        .iter()
        .filter_map(|(file, text)| {
            ThrustCurve::parse_eng(text, &bundled_path(file))
                .ok()
                .map(|curve| Entry { file, curve })
        })
        .collect()
}

/// The outcome of a look-up, as indices into the catalogue searched.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Lookup {
    Found(usize),
    /// Several curves match in the deciding tier.
    Ambiguous(Vec<usize>),
    /// None matches; the nearest (module doc), at most [`NEAREST`].
    NotFound(Vec<usize>),
}

/// How many nearest curves a not-found look-up lists.
pub const NEAREST: usize = 5;

/// Finds `d` among curves given as (name, maker code) (module doc).
pub fn lookup<'a>(
    curves: impl Iterator<Item = (&'a str, Option<&'a str>)> + Clone,
    d: &Designation,
) -> Lookup {
    let mut best: Option<u8> = None;
    let mut hits = Vec::new();
    for (k, (name, maker)) in curves.clone().enumerate() {
        if !maker_matches(maker, d.manufacturer.as_deref()) {
            continue;
        }
        let Some(t) = match_tier(name, &d.name) else {
            continue;
        };
        match best {
            Some(b) if t > b => {}
            Some(b) if t == b => hits.push(k),
            _ => {
                best = Some(t);
                hits = vec![k];
            }
        }
    }
    match hits.len() {
        1 => Lookup::Found(hits[0]),
        0 => Lookup::NotFound(nearest(curves, d)),
        _ => Lookup::Ambiguous(hits),
    }
}

/// Impulse class letter (A = 0, ...) and average thrust of a designation (`M1670` -> (12,
/// 1670)), if it has that form.
fn class_and_thrust(name: &str) -> Option<(u32, f64)> {
    let n = common(name);
    let mut chars = n.chars();
    let letter = chars.next().filter(|c| c.is_ascii_uppercase())?;
    let digits: String = chars.take_while(|c| c.is_ascii_digit()).collect();
    let thrust: f64 = digits.parse().ok()?;
    Some((u32::from(letter) - u32::from('A'), thrust.max(1.0)))
}

fn nearest<'a>(
    curves: impl Iterator<Item = (&'a str, Option<&'a str>)>,
    d: &Designation,
) -> Vec<usize> {
    let Some((class, thrust)) = class_and_thrust(&d.name) else {
        return Vec::new();
    };
    let mut scored: Vec<(u32, f64, usize)> = curves
        .enumerate()
        .filter(|(_, (_, maker))| maker_matches(*maker, d.manufacturer.as_deref()))
        .filter_map(|(k, (name, _))| {
            let (c, t) = class_and_thrust(name)?;
            Some((c.abs_diff(class), (t / thrust).ln().abs(), k))
        })
        .filter(|(dc, _, _)| *dc <= 1)
        .collect();
    scored.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
    scored
        .into_iter()
        .take(NEAREST)
        .map(|(_, _, k)| k)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn find(s: &str) -> Lookup {
        let c = bundled();
        let d = parse_designation(s).unwrap();
        lookup(
            c.iter()
                .map(|e| (e.curve.name.as_str(), e.curve.maker.as_deref())),
            &d,
        )
    }

    fn file_of(l: &Lookup) -> &'static str {
        let c = bundled();
        match l {
            Lookup::Found(k) => c[*k].file,
            other => panic!("not found: {other:?}"),
        }
    }

    #[test]
    fn every_bundled_curve_parses_with_a_full_header() {
        let c = bundled();
        assert_eq!(c.len(), BUNDLED.len());
        for e in &c {
            assert!(
                e.curve.length.is_some() && e.curve.diameter.is_some(),
                "{}",
                e.file
            );
            assert!(
                e.curve.total_mass.is_some() && e.curve.maker.is_some(),
                "{}",
                e.file
            );
            assert!(e.curve.total_impulse() > 0.0, "{}", e.file);
            assert_eq!(
                bundled_text(&bundled_path(e.file)).map(str::len),
                Some(BUNDLED.iter().find(|(f, _)| *f == e.file).unwrap().1.len())
            );
        }
    }

    #[test]
    fn designations_are_case_and_punctuation_insensitive() {
        for s in [
            "M1670",
            "Cesaroni M1670",
            "CTI M1670",
            "cti m1670",
            "Cesaroni Technology M1670-BS",
            "CTI M1670BS",
            "m-1670",
        ] {
            assert_eq!(file_of(&find(s)), "Cesaroni_M1670.eng", "{s}");
        }
        assert_eq!(file_of(&find("AeroTech K1000T")), "AeroTech_K1000T.eng");
        assert_eq!(file_of(&find("AT G80T")), "AeroTech_G80.eng");
        assert_eq!(file_of(&find("Aerotech I284")), "AeroTech_I284W.eng");
        assert_eq!(file_of(&find("H125W-38mm")), "AeroTech_H125W-38mm.eng");
    }

    #[test]
    fn a_name_two_curves_share_is_ambiguous() {
        match find("AeroTech H125W") {
            Lookup::Ambiguous(v) => {
                let c = bundled();
                let mut files: Vec<_> = v.iter().map(|k| c[*k].file).collect();
                files.sort_unstable();
                assert_eq!(
                    files,
                    ["AeroTech_H125W-29mm.eng", "AeroTech_H125W-38mm.eng"]
                );
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn another_makers_motor_is_not_found_and_the_nearest_are_listed() {
        // CTI makes no K1000T in the catalogue: AeroTech's is not offered as a match.
        match find("CTI K1000T") {
            Lookup::NotFound(near) => {
                let c = bundled();
                assert!(!near.is_empty());
                for k in &near {
                    assert_eq!(c[*k].curve.maker.as_deref(), Some("CTI"));
                }
                // Cesaroni's K660 is the nearest K.
                assert_eq!(c[near[0]].file, "Cesaroni_K660.eng");
            }
            other => panic!("{other:?}"),
        }
        match find("M1600") {
            Lookup::NotFound(near) => {
                let c = bundled();
                let names: Vec<_> = near.iter().map(|k| c[*k].curve.name.as_str()).collect();
                // Same class first, by thrust ratio: 1670, 1400, 1315.
                assert_eq!(&names[..3], ["M1670-BS", "M1400", "M1315W"]);
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn an_unknown_manufacturer_is_reported() {
        assert_eq!(parse_designation("Acme M1670"), Err("Acme".to_string()));
        assert!(parse_designation("Cesaroni Technology M1670").is_ok());
    }
}
