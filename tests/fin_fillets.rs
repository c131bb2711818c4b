//! Issue 34: fin root fillets (`fins { fillet_radius; fillet_density }`, `check::ir::Fillet`):
//! the cross-section against a numerical integration of the region it stands for, the mass it
//! adds to the generated structure on the root chord, bad input refused at `check` with file,
//! line and column, and OpenRocket's `<filletradius>` imported.

#![allow(clippy::unwrap_used)]

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::Command;

use flexflight::check::ir::{Fillet, Structure};
use flexflight::check::{DiskLoader, check_files};
use flexflight::structure::compile::generator_spec;
use flexflight::structure::generate::{generate, rigid_body_projection};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// The region a fillet fills, integrated numerically from its definition, written out here
/// independently of `Fillet::section_area`: in the section plane, the fin along `z = 0,
/// y > 0`, the points with `0 < z < r` outside the body's circle (radius `R` about the
/// origin) and outside the fillet's circle (radius `r`, tangent to the fin and to the body:
/// centre at height `r`, distance `R + r` from the origin), between the fin's root and the
/// fillet's tangent point on the fin, and below the line through the origin and the fillet's
/// centre, on which the circles touch. Column by column in `y` (midpoint rule): a column's
/// filled height runs from the body's surface (or the fin) up to the lower arc of the
/// fillet's circle, or to its top `r` before the circle begins.
fn numerical_area(big_r: f64, r: f64, columns: usize) -> f64 {
    let yc = ((big_r + r).powi(2) - r * r).sqrt();
    let y0 = (big_r * big_r - r * r).max(0.0).sqrt();
    let h = (yc - y0) / columns as f64;
    let mut area = 0.0;
    for k in 0..columns {
        let y = y0 + (k as f64 + 0.5) * h;
        // Below the fillet's arc: z < r - sqrt(r^2 - (y - yc)^2) where the circle spans y.
        let dy = y - yc;
        let arc = if dy.abs() < r {
            r - (r * r - dy * dy).sqrt()
        } else {
            r
        };
        // Below the line from the body's axis to the fillet's centre: the two circles touch
        // on it, and beyond it the gap between them is open air.
        let top = arc.min(r * y / yc);
        // Above the body: z > sqrt(R^2 - y^2) where the body spans y.
        let bottom = if y < big_r {
            (big_r * big_r - y * y).sqrt()
        } else {
            0.0
        };
        area += (top - bottom).max(0.0) * h;
    }
    area
}

/// The closed form (`Fillet::section_area`, derived in its doc) is the region's area, over
/// bodies from 10 mm to 1 m and fillets from 1 to 30 mm, within the midpoint rule's error;
/// its limits: a flat body (R >> r) gives `r^2 (1 - pi/4)`, and the area scales as `r^2`
/// there.
#[test]
fn the_fillet_section_is_the_region_between_fin_body_and_arc() {
    for big_r in [0.01, 0.0245, 0.049, 0.1, 1.0] {
        for r in [0.001, 0.003, 0.01, 0.03] {
            let closed = Fillet::section_area(big_r, r);
            let numeric = numerical_area(big_r, r, 400_000);
            assert!(
                (closed / numeric - 1.0).abs() < 2e-7,
                "R = {big_r}, r = {r}: closed {closed:e}, numeric {numeric:e}"
            );
            assert!(closed > 0.0 && closed < r * r * (1.0 - std::f64::consts::FRAC_PI_4));
        }
    }
    let flat =
        Fillet::section_area(1e4, 0.01) / (0.01f64.powi(2) * (1.0 - std::f64::consts::FRAC_PI_4));
    assert!((flat - 1.0).abs() < 1e-5, "{flat}");
}

/// `hpr_k1000` with 10 mm epoxy fillets (1150 kg/m^3): the generated structure is heavier by
/// two fillets a fin along the 0.25 m root chord (the numerically integrated section), and
/// the added mass sits at the root chord's middle (first moment about the origin). The old
/// code refuses `fillet_radius` as an unknown field.
#[test]
fn a_fillet_adds_its_mass_on_the_root_chord() {
    let file = repo("examples/hpr_k1000/hpr_k1000.vdl");
    let vehicle = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let checked = check_files(std::slice::from_ref(&file), &sets, &DiskLoader);
        assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
        checked.program.vehicles[0].clone()
    };
    let projection = |v: &flexflight::check::ir::Vehicle| {
        let Structure::Generate(g) = &v.structure else {
            panic!("a generated structure")
        };
        rigid_body_projection(&generate(&generator_spec(v, g)).unwrap())
    };
    let bare = projection(&vehicle(&[]));
    let with = projection(&vehicle(&[
        "fins.fillet_radius=10 mm",
        "fins.fillet_density=1150 kg/m^3",
    ]));
    let (count, root, r_body) = (3.0, 0.25, 0.049);
    let expected = count * 2.0 * numerical_area(r_body, 0.010, 400_000) * root * 1150.0;
    let added = with[0][0] - bare[0][0];
    assert!(
        (added / expected - 1.0).abs() < 2e-7,
        "added {added} kg, expected {expected} kg"
    );
    // First moment m x (x of the root chord's middle: the trailing edge at -1.9 m).
    let moment = with[1][5] - bare[1][5];
    let x_mid = -1.9 + root / 2.0;
    assert!(
        (moment.abs() / (expected * x_mid.abs()) - 1.0).abs() < 2e-7,
        "first moment {moment}, expected magnitude {}",
        expected * x_mid.abs()
    );
}

/// A fillet needs its radius and its density (never a silent default), positive; a
/// structure read from files holds its own masses: each a diagnostic at `check` with the
/// file, line and column of the field, exit 1.
#[test]
fn bad_fillets_are_refused_at_check() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo("examples/hpr_k1000/hpr_k1000.vdl")).unwrap();
    let cases: &[(&str, &str, &str)] = &[
        (
            "    fillet_radius = 6 mm\n",
            "vdl::fins::fillet",
            "`fillet_radius` without the other half",
        ),
        (
            "    fillet_density = 1150 kg/m^3\n",
            "vdl::fins::fillet",
            "`fillet_density` without the other half",
        ),
        (
            "    fillet_radius = -6 mm\n    fillet_density = 1150 kg/m^3\n",
            "vdl::value::range",
            "",
        ),
        (
            "    fillet_radius = 6 mm\n    fillet_density = 1150 kg/m^3\n",
            "",
            "",
        ),
    ];
    for (lines, code, message) in cases {
        let edited = text.replacen(
            "    material = aluminium_6061_t6\n  }",
            &format!("    material = aluminium_6061_t6\n{lines}  }}"),
            1,
        );
        assert_ne!(edited, text);
        let path = dir.path().join("fillet.vdl");
        std::fs::write(&path, &edited).unwrap();
        for motor in ["AeroTech_K1000T.eng", "Cesaroni_M1670.eng"] {
            std::fs::copy(
                repo("examples/hpr_k1000").join(motor),
                dir.path().join(motor),
            )
            .unwrap();
        }
        let out = bin()
            .arg("check")
            .arg(&path)
            .env("NO_COLOR", "1")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr).to_string();
        if code.is_empty() {
            assert!(out.status.success(), "{lines}: {err}");
            continue;
        }
        assert_eq!(out.status.code(), Some(1), "{lines}: {err}");
        assert!(
            err.contains(code) && err.contains(message),
            "{lines}: {err}"
        );
        // The field's line in the edited file.
        let line = edited.lines().position(|l| l.contains("fillet_")).unwrap() + 1;
        assert!(
            err.contains(&format!("fillet.vdl:{line}:")),
            "{lines}: no fillet.vdl:{line}: in {err}"
        );
    }
}

/// OpenRocket's `<filletradius>` and `<filletmaterial>`: Bella Lui's fin set with 5 mm epoxy
/// fillets (the design's own fillet radius is 0, edited here) imports with the fillet, its
/// material named and its density from the design, and the vehicle checks. The old code
/// warned "the root fillet is not represented" and dropped it.
#[test]
fn an_openrocket_fillet_is_imported() {
    let dir = tempfile::tempdir().unwrap();
    let mut xml = String::new();
    flate2::read::GzDecoder::new(
        std::fs::File::open(repo("tests/import_designs/epfl_bella_lui_2020.ork")).unwrap(),
    )
    .read_to_string(&mut xml)
    .unwrap();
    let edited = xml
        .replacen(
            "<filletradius>0.0</filletradius>",
            "<filletradius>0.005</filletradius>",
            1,
        )
        .replacen(
            "<filletmaterial type=\"bulk\" density=\"680.0\">Cardboard</filletmaterial>",
            "<filletmaterial type=\"bulk\" density=\"1150.0\">Epoxy</filletmaterial>",
            1,
        );
    assert_ne!(edited, xml);
    let design = dir.path().join("bella_fillets.ork");
    std::fs::write(&design, edited).unwrap();
    let out = dir.path().join("bella.vdl");
    let o = bin()
        .arg("import")
        .arg(&design)
        .arg("-o")
        .arg(&out)
        .args(["--motor-dir"])
        .arg(repo("tests/import_designs/motors"))
        // Test input, not a reference value: the design gives only the density.
        .args(["--material", "Carbon fiber=70 GPa,0.3"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("fillet"), "{err}");
    let text = std::fs::read_to_string(&out).unwrap();
    for needle in [
        "fillet_radius = 5 mm",
        "fillet_density = 1150 kg/m^3",
        "Root fillets of `Epoxy`",
    ] {
        assert!(text.contains(needle), "{needle}: {text}");
    }
    let c = bin().arg("check").arg(&out).output().unwrap();
    assert!(c.status.success(), "{}", String::from_utf8_lossy(&c.stderr));
}
