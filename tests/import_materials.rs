//! Issue 34 item 1: the materials rocketeers build with. A design's material name maps to a
//! standard-library material with sourced E and nu (`std/materials.vdl`), its density kept
//! from the design; a name with no sourced material is asked for by name, never defaulted.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use flexflight::import::emit::{MATERIAL_MAP, std_density, std_elastic, std_material_for};

/// OpenRocket's bulk materials and their densities (kg/m^3), as its material database
/// defines them: `core/src/main/java/info/openrocket/core/database/Databases.java`
/// (`BULK_MATERIAL`), openrocket/openrocket at 8fa969d8504c9f8b788966035f5f92df8e30a1af.
const OPENROCKET_BULK: &[(&str, f64)] = &[
    ("Acrylic", 1190.0),
    ("Aluminum", 2700.0),
    ("Balsa", 170.0),
    ("Basswood", 500.0),
    ("Birch", 670.0),
    ("Brass", 8600.0),
    ("Cardboard", 680.0),
    ("Carbon fiber", 1780.0),
    ("Cork", 240.0),
    ("Delrin", 1420.0),
    ("Depron (XPS)", 40.0),
    ("Fiberglass", 1850.0),
    ("Kraft phenolic", 950.0),
    ("Maple", 755.0),
    ("Nylon", 1150.0),
    ("Paper (office)", 820.0),
    ("Pine", 530.0),
    ("Plywood (birch)", 630.0),
    ("Polycarbonate (Lexan)", 1200.0),
    ("Polystyrene", 1050.0),
    ("PVC", 1390.0),
    ("Spruce", 450.0),
    ("Steel", 7850.0),
    ("Styrofoam (generic EPS)", 20.0),
    ("Styrofoam \"Blue foam\" (XPS)", 32.0),
    ("Titanium", 4500.0),
    ("Quantum tubing", 1050.0),
    ("Blue tube", 1300.0),
    ("PLA - 100% infill", 1250.0),
    ("PETG - 100% infill", 1250.0),
    ("ABS - 100% infill", 1050.0),
];

/// Every map target is a material of the embedded standard library with E, nu and rho (the
/// library itself is checked wherever a vehicle imports it, e.g. the import test below).
#[test]
fn every_map_target_is_a_standard_material_with_e_nu_and_rho() {
    for (key, std) in MATERIAL_MAP {
        let (e, nu) = std_elastic(std).unwrap_or_else(|| panic!("{key}: {std} has no E, nu"));
        let rho = std_density(std).unwrap_or_else(|| panic!("{key}: {std} has no rho"));
        assert!(e > 1e9 && e < 5e11, "{std}: E {e}");
        assert!(nu > 0.0 && nu < 0.5, "{std}: nu {nu}");
        assert!(rho > 500.0 && rho < 2e4, "{std}: rho {rho}");
    }
}

/// A property over OpenRocket's whole list: every name that maps, maps to a standard
/// material whose density is within 5 % of OpenRocket's for that name (so a mismapping, such
/// as balsa to birch, 170 against 670 kg/m^3, fails). The names rocketeers use most must map.
#[test]
fn openrocket_names_map_to_materials_of_their_density() {
    let mut mapped = Vec::new();
    for (name, rho_or) in OPENROCKET_BULK {
        if let Some(std) = std_material_for(name) {
            let rho = std_density(std).unwrap();
            let r = rho_or / rho;
            assert!(
                (1.0 / 1.05..=1.05).contains(&r),
                "{name} ({rho_or} kg/m^3) mapped to {std} ({rho} kg/m^3)"
            );
            mapped.push(*name);
        }
    }
    for must in [
        "Aluminum",
        "Fiberglass",
        "Titanium",
        "Polycarbonate (Lexan)",
        "ABS - 100% infill",
        "Steel",
        "Brass",
    ] {
        assert!(mapped.contains(&must), "{must} is not mapped: {mapped:?}");
    }
}

/// Names are matched as words: an alloy's number picks the alloy, a sandwich or foam of a
/// mapped material is not the solid material, and a key inside another word does not match.
#[test]
fn names_match_as_words_and_sandwiches_are_not_solids() {
    assert_eq!(std_material_for("Aluminum 7075"), Some("aluminium_7075_t6"));
    assert_eq!(std_material_for("Aluminum 2024"), Some("aluminium_2024_t3"));
    assert_eq!(std_material_for("Aluminum (Al)"), Some("aluminium_6061_t6"));
    assert_eq!(
        std_material_for("G10 Fiberglass (LOC)"),
        Some("fibreglass_g10")
    );
    assert_eq!(std_material_for("Lexan"), Some("polycarbonate"));
    assert_eq!(std_material_for(".125 in Fiberglass/Honeycomb"), None);
    assert_eq!(std_material_for("Absorbent paper"), None);
    assert_eq!(std_material_for("Stainless steel"), None);
    assert_eq!(std_material_for("Steel"), Some("steel_1020"));
    assert_eq!(std_material_for("Carbon fiber"), None);
    assert_eq!(std_material_for("Plywood (birch)"), None);
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The simple model rocket (tests/import_designs/) as plain XML, with its fin set's material
/// and every other bulk Cardboard replaced.
fn simple_rocket_with(dir: &Path, fins: &str, rest: &str) -> PathBuf {
    let f = std::fs::File::open(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/import_designs/simple_model_rocket.ork"),
    )
    .unwrap();
    let mut z = zip::ZipArchive::new(f).unwrap();
    let mut xml = String::new();
    std::io::Read::read_to_string(&mut z.by_name("rocket.ork").unwrap(), &mut xml).unwrap();
    let cardboard =
        "<material type=\"bulk\" density=\"680.0\" group=\"PaperProducts\">Cardboard</material>";
    let a = xml.find("<trapezoidfinset>").unwrap();
    let b = xml.find("</trapezoidfinset>").unwrap();
    let fin_part = xml[a..b].replacen(cardboard, fins, 1);
    assert_ne!(fin_part, xml[a..b], "the fin set has a Cardboard material");
    let xml = format!(
        "{}{}{}",
        xml[..a].replace(cardboard, rest),
        fin_part,
        xml[b..].replace(cardboard, rest)
    );
    let p = dir.join("rocket.ork");
    std::fs::write(&p, xml).unwrap();
    p
}

/// A design in mapped materials imports without `--material`: the fins get the standard
/// polycarbonate's E and nu and the design's density, the body 7075-T6's; the file checks.
#[test]
fn a_design_in_mapped_materials_imports_without_being_told_their_stiffness() {
    let dir = tempfile::tempdir().unwrap();
    let p = simple_rocket_with(
        dir.path(),
        "<material type=\"bulk\" density=\"1200.0\" group=\"Plastics\">Polycarbonate (Lexan)</material>",
        "<material type=\"bulk\" density=\"2810.0\" group=\"Metals\">Aluminum 7075-T6</material>",
    );
    let nose = std::fs::read_to_string(&p).unwrap().replace(
        "<material type=\"bulk\" density=\"1050.0\" group=\"Plastics\">Polystyrene</material>",
        "<material type=\"bulk\" density=\"1050.0\" group=\"Plastics\">ABS - 100% infill</material>",
    );
    std::fs::write(&p, nose).unwrap();
    let out = dir.path().join("rocket.vdl");
    let o = bin()
        .arg("import")
        .arg(&p)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("import::material"), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains(
            "material polycarbonate_lexan_ork {\n  E = 2.379 GPa\n  nu = 0.38\n  rho = 1200 kg/m^3\n}"
        ),
        "{text}"
    );
    assert!(
        text.contains("E and nu of `polycarbonate` (1200 kg/m^3) in std/materials.vdl"),
        "{text}"
    );
    assert!(
        text.contains(
            "material aluminum_7075_t6_ork {\n  E = 71.7 GPa\n  nu = 0.33\n  rho = 2810 kg/m^3\n}"
        ),
        "{text}"
    );
    assert!(
        text.contains("material = polycarbonate_lexan_ork"),
        "{text}"
    );
    assert!(text.contains("material = aluminum_7075_t6_ork"), "{text}");
    let c = bin().arg("check").arg(&out).output().unwrap();
    assert!(c.status.success(), "check: {}\n{text}", stderr(&c));
}

/// A name without a sourced material is asked for by name, a sandwich of a mapped material
/// too (it mapped to the solid laminate before), and nothing is written.
#[test]
fn unmapped_names_are_asked_for_by_name() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["Plywood (birch)", ".125 in Fiberglass/Honeycomb"] {
        let p = simple_rocket_with(
            dir.path(),
            &format!("<material type=\"bulk\" density=\"630.0\" group=\"Woods\">{name}</material>"),
            "<material type=\"bulk\" density=\"2700.0\" group=\"Metals\">Aluminum</material>",
        );
        let out = dir.path().join("out.vdl");
        let o = bin()
            .args(["import"])
            .arg(&p)
            .arg("-o")
            .arg(&out)
            .args(["--material", "Polystyrene=3 GPa,0.35"])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(1), "{name}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains("import::material") && e.contains(name),
            "{name}: {e}"
        );
        assert!(e.contains(&format!("--material '{name}=")), "{name}: {e}");
        // Plywood is orthotropic: the help says how to choose an isotropic pair.
        assert_eq!(
            e.contains("orthotropic"),
            name.starts_with("Plywood"),
            "{name}: {e}"
        );
        assert!(!out.exists());
    }
}

/// A mapped name whose density is far from the standard material's is warned about (a foam
/// or partial infill is less stiff than the solid), and the import still goes through.
#[test]
fn a_mapped_name_of_another_density_is_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let p = simple_rocket_with(
        dir.path(),
        "<material type=\"bulk\" density=\"400.0\" group=\"Plastics\">ABS - 30% infill</material>",
        "<material type=\"bulk\" density=\"2700.0\" group=\"Metals\">Aluminum</material>",
    );
    let out = dir.path().join("out.vdl");
    let o = bin()
        .arg("import")
        .arg(&p)
        .arg("-o")
        .arg(&out)
        .args(["--material", "Polystyrene=3 GPa,0.35"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("import::material::density") && e.contains("ABS - 30% infill"),
        "{e}"
    );
}
