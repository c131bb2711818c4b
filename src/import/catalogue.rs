//! Motors by name: the bundled catalogue of published RASP thrust curves (`motors/`, with
//! provenance per file in `motors/README.md`) and the `.eng` files of a user's directory.
//!
//! A designation as OpenRocket stores it (`C6`, `G80T`, `K1000T`) is matched against each
//! curve's RASP name (`C6`, `G80`, `K1000T-P`): equal after upper-casing, or equal to the
//! name's common part (before a `-`), or equal once the designation's trailing propellant
//! letters are dropped (`G80T` -> `G80`, the RASAero files' naming). The manufacturer, where
//! given, must agree (RASP maker codes `ES`, `AT`, `CTI`, ... are expanded).

use std::path::{Path, PathBuf};

use crate::runtime::thrust::ThrustCurve;

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
        "AeroTech_K1000T.eng",
        include_str!("../../motors/AeroTech_K1000T.eng"),
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

/// One curve of the catalogue.
#[derive(Clone, Debug)]
pub struct Entry {
    /// File name (written beside the imported vehicle).
    pub file: String,
    /// Where it came from: `bundled` or the user's file.
    pub origin: Origin,
    pub text: String,
    pub curve: ThrustCurve,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Origin {
    Bundled,
    File(PathBuf),
}

impl Entry {
    /// `Maker NAME (file)` for candidate lists.
    pub fn describe(&self) -> String {
        let maker = self.curve.maker.as_deref().map(maker_name).unwrap_or("?");
        let at = match &self.origin {
            Origin::Bundled => format!("bundled {}", self.file),
            Origin::File(p) => p.display().to_string(),
        };
        format!("{maker} {} ({at})", self.curve.name)
    }
}

/// The outcome of a look-up.
#[derive(Debug)]
pub enum Lookup {
    Found(Box<Entry>),
    /// Several curves match; the user chooses with `--motor-dir`.
    Ambiguous(Vec<Entry>),
    /// None matches; the closest by impulse class are listed.
    NotFound(Vec<Entry>),
}

/// Full manufacturer names for RASP maker codes (thrustcurve.org's abbreviations).
pub fn maker_name(code: &str) -> &str {
    match code.trim().to_ascii_uppercase().as_str() {
        "ES" | "ESTES" => "Estes",
        "AT" | "AEROTECH" => "AeroTech",
        "CTI" | "CESARONI" => "Cesaroni",
        "AP" | "APOGEE" => "Apogee",
        "QU" | "QUEST" => "Quest",
        "KL" | "KLIMA" => "Klima",
        "LOKI" => "Loki",
        "HT" | "HYPERTEK" => "Hypertek",
        _ => code,
    }
}

fn norm(s: &str) -> String {
    s.chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_uppercase)
        .collect()
}

/// Whether a RASP curve name matches a designation (module doc).
pub fn name_matches(rasp: &str, designation: &str) -> bool {
    let (r, d) = (norm(rasp), norm(designation));
    if r == d {
        return true;
    }
    let common = r.split('-').next().unwrap_or(&r).to_string();
    if common == d {
        return true;
    }
    let d_common = d.split('-').next().unwrap_or(&d).to_string();
    if common == d_common {
        return true;
    }
    // `G80T` -> `G80`: drop trailing letters after the average-thrust digits.
    let stripped = d_common.trim_end_matches(|c: char| c.is_ascii_alphabetic());
    stripped.len() >= 2 && stripped != d_common && common == stripped
}

fn maker_matches(entry: &ThrustCurve, manufacturer: Option<&str>) -> bool {
    match (manufacturer, entry.maker.as_deref()) {
        (Some(m), Some(e)) => {
            // OpenRocket writes `Cesaroni Technology`, RASP `CTI`: a prefix suffices.
            let (m, e) = (norm(maker_name(m)), norm(maker_name(e)));
            m.starts_with(&e) || e.starts_with(&m)
        }
        _ => true,
    }
}

/// The catalogue: the user's directories first (`.eng` files, one motor each), then the
/// bundled curves. A user file that cannot be read is skipped here and reported by `check`
/// if it is ever named.
pub fn load(dirs: &[PathBuf]) -> Vec<Entry> {
    let mut out = Vec::new();
    for dir in dirs {
        let Ok(rd) = std::fs::read_dir(dir) else {
            continue;
        };
        let mut files: Vec<PathBuf> = rd
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("eng")))
            .collect();
        files.sort();
        for p in files {
            let Ok(text) = std::fs::read_to_string(&p) else {
                continue;
            };
            if let Ok(curve) = ThrustCurve::parse_eng(&text, &p) {
                out.push(Entry {
                    file: p
                        .file_name()
                        .map(|f| f.to_string_lossy().into_owned())
                        .unwrap_or_default(),
                    origin: Origin::File(p.clone()),
                    text,
                    curve,
                });
            }
        }
    }
    for (file, text) in BUNDLED {
        if let Ok(curve) = ThrustCurve::parse_eng(text, Path::new(file)) {
            out.push(Entry {
                file: (*file).to_string(),
                origin: Origin::Bundled,
                text: (*text).to_string(),
                curve,
            });
        }
    }
    out
}

/// Finds `designation` (of `manufacturer`, if known). A user's file shadows a bundled curve of
/// the same name and maker, so only ties within one origin are ambiguous.
pub fn lookup(catalogue: &[Entry], designation: &str, manufacturer: Option<&str>) -> Lookup {
    let hits: Vec<&Entry> = catalogue
        .iter()
        .filter(|e| {
            name_matches(&e.curve.name, designation) && maker_matches(&e.curve, manufacturer)
        })
        .collect();
    match hits.as_slice() {
        [] => {
            let class = norm(designation).chars().next();
            let near = catalogue
                .iter()
                .filter(|e| norm(&e.curve.name).chars().next() == class)
                .cloned()
                .collect();
            Lookup::NotFound(near)
        }
        [one] => Lookup::Found(Box::new((*one).clone())),
        [first, ..] => {
            let same_origin: Vec<Entry> = hits
                .iter()
                .filter(|e| e.origin.is_user() == first.origin.is_user())
                .map(|e| (*e).clone())
                .collect();
            if same_origin.len() == 1 {
                Lookup::Found(Box::new(same_origin[0].clone()))
            } else {
                Lookup::Ambiguous(same_origin)
            }
        }
    }
}

impl Origin {
    fn is_user(&self) -> bool {
        matches!(self, Origin::File(_))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn designations_match_rasp_names() {
        assert!(name_matches("C6", "C6"));
        assert!(name_matches("G80", "G80T"));
        assert!(name_matches("K1000T-P", "K1000T"));
        assert!(name_matches("M1670-BS", "m1670"));
        assert!(!name_matches("C6", "C5"));
        assert!(!name_matches("G80", "G8"));
        assert!(!name_matches("B4", "B"));
    }

    #[test]
    fn the_bundled_catalogue_parses_and_resolves() {
        let c = load(&[]);
        assert_eq!(c.len(), BUNDLED.len(), "every bundled curve parses");
        match lookup(&c, "C6", Some("Estes")) {
            Lookup::Found(e) => assert_eq!(e.file, "Estes_C6.eng"),
            other => panic!("{other:?}"),
        }
        match lookup(&c, "M1670", Some("Cesaroni Technology")) {
            Lookup::Found(e) => assert_eq!(e.file, "Cesaroni_M1670.eng"),
            other => panic!("{other:?}"),
        }
        match lookup(&c, "C6", Some("AeroTech")) {
            Lookup::NotFound(_) => {}
            other => panic!("another maker's C6 is not a match: {other:?}"),
        }
        match lookup(&c, "M1670", None) {
            Lookup::Found(e) => assert_eq!(e.file, "Cesaroni_M1670.eng"),
            other => panic!("{other:?}"),
        }
        match lookup(&c, "C7", Some("Estes")) {
            Lookup::NotFound(near) => {
                assert!(
                    near.iter().any(|e| e.curve.name == "C6"),
                    "lists the C class"
                )
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn two_user_curves_of_one_name_are_ambiguous() {
        let dir = tempfile::tempdir().unwrap();
        let eng = "C6 18 70 0 0.0108 0.0231 ES\n0.1 10\n1.0 0\n;\n";
        std::fs::write(dir.path().join("a.eng"), eng).unwrap();
        std::fs::write(dir.path().join("b.eng"), eng).unwrap();
        let c = load(&[dir.path().to_path_buf()]);
        match lookup(&c, "C6", Some("Estes")) {
            Lookup::Ambiguous(v) => assert_eq!(v.len(), 2),
            other => panic!("{other:?}"),
        }
    }
}
