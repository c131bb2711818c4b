//! Motors by name for the importer: the `.eng` files of a user's `--motor-dir` directories,
//! searched first, then the bundled catalogue of published RASP thrust curves
//! ([`crate::runtime::catalogue`], the `motors/` folder with provenance per file in
//! `motors/README.md`). Designations match as `motor { designation = ... }` does at `check`
//! (the tiers of [`crate::runtime::catalogue`]): a designation as OpenRocket stores it (`C6`,
//! `G80T`, `K1000T`) against each curve's RASP name (`C6`, `G80`, `K1000T-P`), the
//! manufacturer, where given, agreeing (RASP maker codes `ES`, `AT`, `CTI`, ... expanded).

use std::path::{Path, PathBuf};

use crate::runtime::catalogue as bundled;
use crate::runtime::thrust::ThrustCurve;

pub use crate::runtime::catalogue::{BUNDLED, maker_name, name_matches};

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
    /// `Maker NAME` as `motor { designation = ... }` takes it (an exact match of a bundled
    /// curve).
    pub fn designation(&self) -> String {
        let maker = self.curve.maker.as_deref().map(maker_name).unwrap_or("");
        format!("{maker} {}", self.curve.name).trim().to_string()
    }

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

/// Finds `designation` (of `manufacturer`, if known): in the user's files first (a user's
/// file shadows a bundled curve of the same name), then in the bundled curves; the nearest
/// of a not-found designation come from the whole catalogue.
pub fn lookup(catalogue: &[Entry], designation: &str, manufacturer: Option<&str>) -> Lookup {
    let d = bundled::Designation {
        manufacturer: manufacturer.map(str::to_string),
        name: designation.to_string(),
    };
    let search = |user: bool| {
        let part: Vec<&Entry> = catalogue
            .iter()
            .filter(|e| e.origin.is_user() == user)
            .collect();
        let found = bundled::lookup(
            part.iter()
                .map(|e| (e.curve.name.as_str(), e.curve.maker.as_deref())),
            &d,
        );
        (part, found)
    };
    for user in [true, false] {
        let (part, found) = search(user);
        match found {
            bundled::Lookup::Found(k) => return Lookup::Found(Box::new(part[k].clone())),
            bundled::Lookup::Ambiguous(v) => {
                return Lookup::Ambiguous(v.into_iter().map(|k| part[k].clone()).collect());
            }
            bundled::Lookup::NotFound(_) => {}
        }
    }
    match bundled::lookup(
        catalogue
            .iter()
            .map(|e| (e.curve.name.as_str(), e.curve.maker.as_deref())),
        &d,
    ) {
        bundled::Lookup::NotFound(near) => {
            Lookup::NotFound(near.into_iter().map(|k| catalogue[k].clone()).collect())
        }
        _ => Lookup::NotFound(Vec::new()),
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
