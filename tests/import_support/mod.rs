//! Helpers shared by the import tests (`tests/import.rs`, `tests/import_examples.rs`).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The `flexflight` binary under test.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flexflight"))
}

/// A file of `tests/import_designs/`.
pub fn design(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/import_designs")
        .join(name)
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The terminal report with its line breaks and gutters folded (messages wrap at a width).
pub fn flat(e: &str) -> String {
    e.split_whitespace()
        .filter(|w| *w != "│")
        .collect::<Vec<_>>()
        .join(" ")
}
