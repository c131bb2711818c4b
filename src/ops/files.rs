//! Output files written whole or not at all: a failed operation leaves nothing behind and
//! overwrites nothing the user had.

use std::path::{Path, PathBuf};

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
