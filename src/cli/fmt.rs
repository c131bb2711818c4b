//! `flexflight fmt`: canonical formatting, written atomically, never on a file with syntax
//! errors (nothing the user had is lost).

use std::path::{Path, PathBuf};

use crate::check::{Cx, DiskLoader};
use crate::syntax::print::print_tree;
use crate::syntax::{SourceMap, parse_file};

use super::{EXIT_DIAGNOSTICS, EXIT_OK, EXIT_USAGE, Format, Terminal, emit};

pub fn cmd_fmt(files: &[PathBuf], check: bool, format: Format, term: Terminal) -> u8 {
    let mut worst = EXIT_OK;
    for path in files {
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("error: cannot read `{}`: {e}", path.display());
                worst = worst.max(EXIT_USAGE);
                continue;
            }
        };
        let mut sources = SourceMap::new();
        let id = sources.add(path.clone(), path.display().to_string(), text.as_str());
        let (tree, errors) = parse_file(id, &text);
        if !errors.is_empty() {
            let mut cx = Cx {
                sources,
                diags: Vec::new(),
                loader: &DiskLoader,
            };
            crate::check::push_parse_errors_pub(&mut cx, errors);
            emit(&cx.diags, &cx.sources, format, term);
            worst = worst.max(EXIT_DIAGNOSTICS);
            continue;
        }
        let formatted = print_tree(&tree);
        if formatted == text {
            continue;
        }
        if check {
            eprintln!("{} is not formatted", path.display());
            worst = worst.max(EXIT_DIAGNOSTICS);
        } else if let Err(e) = write_atomic(path, &formatted) {
            eprintln!("error: cannot write `{}`: {e}", path.display());
            worst = worst.max(EXIT_USAGE);
        } else {
            eprintln!("formatted {}", path.display());
        }
    }
    worst
}

/// Write a set of files all or nothing, as far as a file system allows: every file's text
/// goes to a temporary file beside it first; only when all of them are written are they
/// renamed onto their paths (a rename within a directory does not fail for want of space).
/// If a temporary file cannot be written, or a rename fails, the temporary files are removed
/// and the directories this call created (`dirs`, the ones that did not exist) are removed
/// again when empty, so a failed run leaves nothing behind and overwrites nothing it had
/// not renamed yet.
pub fn write_all_atomic(dirs: &[&Path], files: &[(PathBuf, &str)]) -> std::io::Result<()> {
    let mut created = Vec::new();
    let undo_dirs = |created: &[PathBuf]| {
        for d in created.iter().rev() {
            let _ = std::fs::remove_dir(d);
        }
    };
    for d in dirs {
        if !d.exists() {
            // Each missing ancestor too, outermost first, so that the undo removes them all.
            let mut missing: Vec<PathBuf> = d
                .ancestors()
                .take_while(|a| !a.as_os_str().is_empty() && !a.exists())
                .map(Path::to_path_buf)
                .collect();
            missing.reverse();
            if let Err(e) = std::fs::create_dir_all(d) {
                undo_dirs(&created);
                return Err(e);
            }
            created.extend(missing);
        }
    }
    let temps: Vec<PathBuf> = files.iter().map(|(p, _)| temp_path(p, "tmp")).collect();
    let cleanup = |temps: &[PathBuf]| {
        for t in temps {
            let _ = std::fs::remove_file(t);
        }
        undo_dirs(&created);
    };
    for ((path, text), tmp) in files.iter().zip(&temps) {
        if let Err(e) = std::fs::write(tmp, text) {
            cleanup(&temps);
            return Err(e);
        }
        if let Ok(meta) = std::fs::metadata(path) {
            let _ = std::fs::set_permissions(tmp, meta.permissions());
        }
    }
    // The one rename failure that can be seen coming: a directory in the way of a file.
    if let Some((path, _)) = files.iter().find(|(p, _)| p.is_dir()) {
        cleanup(&temps);
        return Err(std::io::Error::new(
            std::io::ErrorKind::IsADirectory,
            format!("`{}` is a directory", path.display()),
        ));
    }
    for ((path, _), tmp) in files.iter().zip(&temps) {
        if let Err(e) = std::fs::rename(tmp, path) {
            cleanup(&temps);
            return Err(e);
        }
    }
    Ok(())
}

/// The temporary file beside `path`: `.NAME.TAG.PID` in the same directory (so that the
/// rename stays within one file system).
fn temp_path(path: &Path, tag: &str) -> PathBuf {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    dir.join(format!(".{name}.{tag}.{}", std::process::id()))
}

/// Write through a temporary file in the same directory, then rename over the original.
pub fn write_atomic(path: &Path, text: &str) -> std::io::Result<()> {
    let tmp = temp_path(path, "fmt");
    std::fs::write(&tmp, text)?;
    if let Ok(meta) = std::fs::metadata(path) {
        let _ = std::fs::set_permissions(&tmp, meta.permissions());
    }
    std::fs::rename(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}
