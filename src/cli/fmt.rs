//! `flexflight fmt`: canonical formatting, written atomically, never on a file with syntax
//! errors (nothing the user had is lost).

use std::path::PathBuf;

use crate::check::{Cx, DiskLoader};
use crate::syntax::print::print_tree;
use crate::syntax::{SourceMap, parse_file};

use crate::ops::files::write_atomic;

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
