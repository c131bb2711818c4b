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
