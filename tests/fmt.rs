//! The canonical printer on every shipped `.vdl` file: idempotent, faithful to the tree
//! (up to spans), and meaning-preserving (the checked IR is the same); `flexflight fmt`
//! behaviour through the CLI; comments and blank lines survive.

mod common;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;
use flexflight::check::{DiskLoader, check_files};
use flexflight::cli::{Cli, Terminal, run};
use flexflight::diagnostics::{RenderOptions, render};
use flexflight::syntax::ast::SourceTree;
use flexflight::syntax::print::print_tree;
use flexflight::syntax::{FileId, parse_file};

fn parse_ok(text: &str, what: &str) -> SourceTree {
    let (tree, errors) = parse_file(FileId(0), text);
    assert!(errors.is_empty(), "{what} does not parse: {errors:?}");
    tree
}

/// The tree's debug form with every span offset replaced by `_`: two trees that differ only
/// in where things were written compare equal.
fn erase_spans(tree: &SourceTree) -> String {
    let dbg = format!("{tree:#?}");
    let mut out = String::with_capacity(dbg.len());
    for line in dbg.lines() {
        let t = line.trim_start();
        if let Some(key) = ["start: ", "end: "].iter().find(|k| t.starts_with(**k)) {
            let rest = &t[key.len()..];
            if rest
                .trim_end_matches(',')
                .chars()
                .all(|c| c.is_ascii_digit())
            {
                out.push_str(&line[..line.len() - t.len()]);
                out.push_str(key);
                out.push_str("_,\n");
                continue;
            }
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// The first differing line of two texts, with a little context.
fn first_difference(a: &str, b: &str) -> String {
    let (la, lb): (Vec<&str>, Vec<&str>) = (a.lines().collect(), b.lines().collect());
    let k = la
        .iter()
        .zip(&lb)
        .position(|(x, y)| x != y)
        .unwrap_or(la.len().min(lb.len()));
    let lo = k.saturating_sub(12);
    format!(
        "line {}:\n--- original\n{}\n--- reparsed\n{}",
        k + 1,
        la[lo..(k + 3).min(la.len())].join("\n"),
        lb[lo..(k + 3).min(lb.len())].join("\n")
    )
}

#[test]
fn there_are_shipped_files() {
    let files = common::shipped_vdl_files();
    assert!(files.len() >= 4, "found only {files:?}");
}

#[test]
fn printing_is_idempotent_and_keeps_the_tree() {
    for path in common::shipped_vdl_files() {
        let text = std::fs::read_to_string(&path).expect("read");
        let what = path.display().to_string();
        let tree = parse_ok(&text, &what);
        let once = print_tree(&tree);
        let tree2 = parse_ok(&once, &format!("printed {what}"));
        let twice = print_tree(&tree2);
        assert_eq!(once, twice, "printing {what} is not idempotent");
        let (a, b) = (erase_spans(&tree), erase_spans(&tree2));
        assert!(
            a == b,
            "the printed {what} parses to a different tree:\n{}",
            first_difference(&a, &b)
        );
    }
}

#[test]
fn shipped_files_are_formatted() {
    for path in common::shipped_vdl_files() {
        let text = std::fs::read_to_string(&path).expect("read");
        let printed = print_tree(&parse_ok(&text, &path.display().to_string()));
        assert!(
            printed == text,
            "{} is not in canonical form; first difference at line {}",
            path.display(),
            text.lines()
                .zip(printed.lines())
                .position(|(a, b)| a != b)
                .map_or(0, |k| k + 1)
        );
    }
}

/// Copy the shipped tree, formatted, into `dir` (keeping relative imports valid).
fn write_formatted_copy(dir: &Path) -> Vec<PathBuf> {
    let root = common::root();
    let mut out = Vec::new();
    for path in common::shipped_vdl_files() {
        let rel = path.strip_prefix(&root).expect("under root");
        let dest = dir.join(rel);
        std::fs::create_dir_all(dest.parent().expect("parent")).expect("mkdir");
        let text = std::fs::read_to_string(&path).expect("read");
        std::fs::write(&dest, print_tree(&parse_ok(&text, "shipped file"))).expect("write");
        out.push(dest);
    }
    // Data files the vehicle files refer to (FE matrices, ...), unchanged.
    copy_data_files(&root.join("examples"), &dir.join("examples"));
    out
}

fn copy_data_files(from: &Path, to: &Path) {
    let Ok(entries) = std::fs::read_dir(from) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            copy_data_files(&p, &to.join(e.file_name()));
        } else if p.extension().is_none_or(|x| x != "vdl") {
            std::fs::create_dir_all(to).expect("mkdir");
            std::fs::copy(&p, to.join(e.file_name())).expect("copy");
        }
    }
}

fn ir_json(path: &Path, dir: &Path) -> serde_json::Value {
    let checked = check_files(&[path.to_path_buf()], &[], &DiskLoader);
    assert!(
        !checked.has_errors(),
        "{} does not check:\n{}",
        path.display(),
        render(
            &checked.diagnostics,
            &checked.sources,
            RenderOptions::plain(100)
        )
    );
    let mut v = common::program_json(&checked.program);
    common::strip_spans(&mut v);
    common::replace_paths(&mut v, dir, "$ROOT");
    v
}

#[test]
fn formatting_does_not_change_the_checked_ir() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let copies = write_formatted_copy(tmp.path());
    let root = common::root();
    for (orig, copy) in common::shipped_vdl_files().iter().zip(&copies) {
        let a = ir_json(orig, &root);
        let b = ir_json(copy, tmp.path());
        assert!(a == b, "formatting {} changed its meaning", orig.display());
        // Not vacuous: every shipped file declares something.
        let n: usize = ["materials", "vehicles", "scenarios", "sweeps"]
            .iter()
            .map(|k| a[k].as_array().map_or(0, Vec::len))
            .sum();
        assert!(n > 0, "{} checks to an empty program", orig.display());
    }
}

const MESSY: &str = "# Header comment.\n\n\nmaterial   m{\n  E=70 GPa   # Young\n\n  # density next\n  nu = 0.3;rho = 2700 kg/m^3\n  # trailing comment\n}\n";

#[test]
fn comments_and_blank_lines_survive() {
    let tree = parse_ok(MESSY, "messy");
    let printed = print_tree(&tree);
    for needle in [
        "# Header comment.",
        "# Young",
        "# density next",
        "# trailing comment",
    ] {
        assert!(printed.contains(needle), "lost `{needle}`:\n{printed}");
    }
    // The blank line between the header and the block, and the one before the commented
    // group, are kept (collapsed to one); no blank line is invented elsewhere.
    assert!(
        printed.contains("# Header comment.\n\nmaterial m {"),
        "{printed}"
    );
    assert!(
        printed.contains("# Young\n\n  # density next\n"),
        "{printed}"
    );
    assert!(!printed.contains("\n\n\n"), "{printed}");
    // The entries separated by `;` end up on their own lines.
    assert!(
        printed.contains("  nu = 0.3\n  rho = 2700 kg/m^3\n"),
        "{printed}"
    );
    assert_eq!(print_tree(&parse_ok(&printed, "printed messy")), printed);
}

fn fmt_cli(args: &[&str]) -> ExitCode {
    let mut argv = vec!["flexflight", "fmt"];
    argv.extend_from_slice(args);
    let cli = Cli::try_parse_from(argv).expect("command line");
    run(
        cli,
        Terminal {
            render: RenderOptions::plain(80),
        },
    )
}

fn code(c: ExitCode) -> String {
    format!("{c:?}")
}

#[test]
fn fmt_check_through_the_cli() {
    let ok = || code(ExitCode::from(0));
    let diags = || code(ExitCode::from(1));
    let tmp = tempfile::tempdir().expect("tempdir");
    let messy = tmp.path().join("messy.vdl");
    std::fs::write(&messy, MESSY).expect("write");
    let m = messy.to_str().expect("utf-8 path");

    // --check reports the unformatted file and does not touch it.
    assert_eq!(code(fmt_cli(&["--check", m])), diags());
    assert_eq!(std::fs::read_to_string(&messy).expect("read"), MESSY);

    // fmt rewrites it to the printer's output; then --check passes.
    assert_eq!(code(fmt_cli(&[m])), ok());
    let formatted = std::fs::read_to_string(&messy).expect("read");
    assert_eq!(formatted, print_tree(&parse_ok(MESSY, "messy")));
    assert_eq!(code(fmt_cli(&["--check", m])), ok());

    // A file with a syntax error is reported and never rewritten.
    let broken = tmp.path().join("broken.vdl");
    let broken_text = "material m {\n  E = 70 GPa\n";
    std::fs::write(&broken, broken_text).expect("write");
    let b = broken.to_str().expect("utf-8 path");
    assert_eq!(code(fmt_cli(&[b])), diags());
    assert_eq!(std::fs::read_to_string(&broken).expect("read"), broken_text);

    // The shipped files pass `fmt --check`.
    let shipped: Vec<String> = common::shipped_vdl_files()
        .iter()
        .map(|p| p.display().to_string())
        .collect();
    let mut args = vec!["--check"];
    args.extend(shipped.iter().map(String::as_str));
    assert_eq!(code(fmt_cli(&args)), ok());
}
