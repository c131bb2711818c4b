//! The README against the code (issue 9, defect 10): the files `run` writes against the
//! README's "Run outputs". (The field table is checked in `tests/readme_fields.rs`, the
//! diagnostic codes in `tests/diagnostics.rs`.)

use std::path::{Path, PathBuf};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn readme() -> String {
    std::fs::read_to_string(repo("docs/outputs.md")).unwrap()
}

/// Every file and directory `run` writes into `--out`, relative, directories with a `/`.
fn written(dir: &Path, prefix: &str, out: &mut Vec<String>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let e = e.unwrap();
        let name = format!("{prefix}{}", e.file_name().to_string_lossy());
        if e.path().is_dir() {
            out.push(format!("{name}/"));
            written(&e.path(), &format!("{name}/"), out);
        } else {
            out.push(name);
        }
    }
}

#[test]
fn every_file_run_writes_is_in_the_readme() {
    let out = tempfile::tempdir().unwrap();
    let cache = Path::new(env!("CARGO_TARGET_TMPDIR")).join("docs-cache");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_flexflight"))
        .arg("run")
        .arg(repo("examples/thesis/section_6_5.vdl"))
        .args([
            "--scenario",
            "subsonic_t06",
            "--set",
            "run.stop_time=0.002 s",
        ])
        .arg("--out")
        .arg(out.path())
        .arg("--cache-dir")
        .arg(&cache)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut files = Vec::new();
    written(out.path(), "", &mut files);
    assert!(files.len() >= 4, "{files:?}");
    let text = readme();
    let start = text.find("## Run outputs").unwrap();
    let end = start + 1 + text[start + 1..].find("\n## ").unwrap();
    let section = &text[start..end];
    let missing: Vec<&String> = files
        .iter()
        .filter(|f| !section.contains(&format!("`{f}`")))
        .collect();
    assert!(
        missing.is_empty(),
        "`run` writes {missing:?}, which the README's \"Run outputs\" does not name"
    );
}

fn validation() -> String {
    std::fs::read_to_string(repo("docs/validation.md")).unwrap()
}

/// The line of `docs/validation.md` that contains `key` (the first one).
fn validation_line(key: &str) -> String {
    validation()
        .lines()
        .find(|l| l.contains(key))
        .unwrap_or_else(|| panic!("no line with `{key}` in docs/validation.md"))
        .to_string()
}

/// Issue 38, item 2: the flutter speeds of the clamped 0.875 mm SPHADS-1 fin quoted in
/// `docs/validation.md` are today's binary's (to the digits printed), and the Göthert error
/// term `4 k M² / β²` quoted for that flutter point is computed from the solver's own `k`
/// and Mach.
#[test]
fn validation_flutter_figures_are_todays() {
    let run = |aero: &str| -> serde_json::Value {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("fl");
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_flexflight"))
            .args(["analyze", "flutter"])
            .arg(repo("examples/thesis/section_6_5.vdl"))
            .args(["--scenario", "subsonic_t06", "--clamped", "--modes", "4"])
            .args(["--aero", aero, "--set", "fins.thickness=0.875 mm", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_str(&std::fs::read_to_string(out.join("flutter.json")).unwrap()).unwrap()
    };
    for (aero, key) in [
        ("unsteady", "| clamped fin, unsteady panels"),
        ("doublet-lattice", "| clamped fin, doublet lattice"),
        ("quasi-steady", "| clamped fin, quasi-steady panels"),
    ] {
        let j = run(aero);
        let f = &j["flutter"][0];
        let (v, hz) = (
            f["speed_m_s"].as_f64().unwrap(),
            f["frequency_hz"].as_f64().unwrap(),
        );
        let row = validation_line(key);
        assert!(
            row.contains(&format!("{v:.1} m/s, {hz:.1} Hz")),
            "{aero}: {v:.2} m/s, {hz:.2} Hz against\n{row}"
        );
        if aero == "unsteady" {
            let k = f["reduced_frequency"].as_f64().unwrap();
            let m = j["mach"].as_f64().unwrap();
            let term = 4.0 * k * m * m / (1.0 - m * m);
            let text = validation().replace('\n', " ");
            let want = format!(
                "relative order 4kM²/β², {term:.2} at the SPHADS-1 flutter point with the solver's own k = {k:.3}"
            );
            assert!(text.contains(&want), "missing: {want}");
        }
    }
}
