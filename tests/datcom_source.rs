//! `aero { source = datcom("for006.dat") }` (issue 34, item 5): a vehicle flies on Missile
//! DATCOM output; bad files and contradicting reference quantities are diagnostics at
//! `check` with the DATCOM file's line; the aero cache key follows the file's bytes.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn data(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/datcom")
        .join(p)
}

const DAT: &str = "ogive_two_fin_sets_for006.dat";

/// The test vehicle and its DATCOM file copied into `dir`, the vehicle text edited by `edit`
/// and the DATCOM text by `edit_dat`.
fn setup(
    dir: &Path,
    edit: impl Fn(String) -> String,
    edit_dat: impl Fn(String) -> String,
) -> PathBuf {
    let vdl = std::fs::read_to_string(data("ogive_missile.vdl")).unwrap();
    let dat = std::fs::read_to_string(data(DAT)).unwrap();
    std::fs::write(dir.join(DAT), edit_dat(dat)).unwrap();
    let file = dir.join("ogive_missile.vdl");
    std::fs::write(&file, edit(vdl)).unwrap();
    file
}

fn flexflight(args: &[&str], file: &Path) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_flexflight"));
    c.arg(args[0]).arg(file).args(&args[1..]);
    c.output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `check` fails with code `vdl::aero::datcom` and every `needles` in the report.
fn refused(file: &Path, needles: &[&str]) {
    let o = flexflight(&["check"], file);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    // The report wraps its message at a width that depends on the file's path (the temporary
    // directory): compare with the gutter and line breaks folded into single spaces.
    let flat = e
        .replace('│', " ")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    for n in ["vdl::aero::datcom"].iter().chain(needles) {
        assert!(e.contains(n) || flat.contains(n), "`{n}` not in:\n{e}");
    }
}

#[test]
fn a_vehicle_flies_on_datcom_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .arg("run")
        .arg(data("ogive_missile.vdl"))
        .args(["--scenario", "gust", "--out"])
        .arg(&out)
        .arg("--cache-dir")
        .arg(dir.path().join("cache"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["stop_reason"], "completed", "{}", s["stop_detail"]);
}

#[test]
fn a_reference_area_that_contradicts_the_file_is_refused_at_check() {
    let dir = tempfile::tempdir().unwrap();
    let file = setup(
        dir.path(),
        |v| {
            v.replace(
                "out_of_range = clamp",
                "out_of_range = clamp\n    reference_area = 1.1 m^2",
            )
        },
        |d| d,
    );
    // Labelled at the page of the file that gives SREF (line 687) and at the vehicle's value.
    refused(
        &file,
        &[
            "reference area",
            "ogive_two_fin_sets_for006.dat:687",
            "ogive_missile.vdl:",
        ],
    );
}

#[test]
fn two_fin_sets_without_a_choice_are_refused_at_check() {
    let dir = tempfile::tempdir().unwrap();
    let file = setup(dir.path(), |v| v.replace(", fin_set = 2)", ")"), |d| d);
    refused(&file, &["fin_set = N"]);
}

#[test]
fn a_truncated_file_is_refused_at_check_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let file = setup(
        dir.path(),
        |v| v,
        |d| d.lines().take(703).map(|l| format!("{l}\n")).collect(),
    );
    refused(&file, &["END OF JOB", "ogive_two_fin_sets_for006.dat:703"]);
}

#[test]
fn a_missing_file_is_refused_at_check() {
    let dir = tempfile::tempdir().unwrap();
    let file = setup(
        dir.path(),
        |v| v.replace("\"ogive_two_fin_sets_for006.dat\"", "\"nope.dat\""),
        |d| d,
    );
    let o = flexflight(&["check"], &file);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("nope.dat"), "{}", stderr(&o));
}

#[test]
fn the_aero_key_follows_the_datcom_file() {
    let key = |dir: &Path| {
        let checked = flexflight::check::check_scenario_files(
            &[dir.join("ogive_missile.vdl")],
            &[],
            "gust",
            &flexflight::check::DiskLoader,
        );
        assert!(!checked.has_errors(), "{:?}", checked.diagnostics);
        let sc = checked.program.scenario("gust").unwrap().clone();
        let structural = flexflight::ops::compile::cache_key(&sc.vehicle).unwrap();
        flexflight::ops::compile::aero_cache_key(&sc.vehicle, &structural).unwrap()
    };
    // One directory, the file edited in place: the vehicle text and every path the same.
    let dir = tempfile::tempdir().unwrap();
    setup(dir.path(), |v| v, |d| d);
    let before = key(dir.path());
    assert_eq!(before, key(dir.path()), "the key is deterministic");
    let dat = dir.path().join(DAT);
    let d = std::fs::read_to_string(&dat).unwrap();
    // One coefficient of the complete configuration (CN at 4 deg, page 22).
    let e = d.replacen("          4.00     1.154 ", "          4.00     1.155 ", 1);
    assert_ne!(e, d);
    std::fs::write(&dat, e).unwrap();
    assert_ne!(
        before,
        key(dir.path()),
        "editing the DATCOM file must change the aero key"
    );
}

/// A `fins` block that fails its own checks is reported once: no DATCOM follow-on error
/// saying the vehicle has no fins.
#[test]
fn a_bad_fins_block_gives_no_datcom_follow_on_error() {
    let dir = tempfile::tempdir().unwrap();
    let file = setup(dir.path(), |v| v.replace("count = 4", "count = 0"), |d| d);
    let o = flexflight(&["check"], &file);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("count"), "{e}");
    assert!(!e.contains("vdl::aero::datcom"), "{e}");
}
