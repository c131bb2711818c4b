//! `flexflight import DESIGN.ork -o ROCKET.vdl [--motor-dir DIR] [--material 'NAME=E,nu']
//! [--motor DESIGNATION]`:
//! a thin shell over [`crate::import::import_design`]. Nothing is written unless the import
//! succeeds; then the vehicle file and the thrust curves it names (beside it).

use std::path::{Path, PathBuf};

use super::{EXIT_DIAGNOSTICS, EXIT_OK, EXIT_USAGE, Format, Terminal, emit};
use crate::import::{GivenMaterial, Options, import_design};
use crate::syntax::SourceMap;

pub fn cmd_import(
    design: &Path,
    out: &Path,
    motor_dirs: &[PathBuf],
    materials: &[String],
    motor: Option<&str>,
    format: Format,
    term: Terminal,
) -> u8 {
    let mut given = Vec::new();
    for m in materials {
        match GivenMaterial::parse(m) {
            Ok(g) => given.push(g),
            Err(e) => {
                eprintln!("error: --material {e}");
                return EXIT_USAGE;
            }
        }
    }
    let opts = Options {
        motor_dirs: motor_dirs.to_vec(),
        materials: given,
        motor: motor.map(str::to_string),
    };
    let mut sources = SourceMap::new();
    match import_design(design, &opts, &mut sources) {
        Err(diags) => {
            emit(&diags, &sources, format, term);
            EXIT_DIAGNOSTICS
        }
        Ok(imp) => {
            // The vehicle file and its thrust curves all or none
            // ([`crate::ops::files::write_all_atomic`]): a failed write leaves nothing.
            let dir = out.parent().unwrap_or(Path::new(""));
            let mut files = vec![(out.to_path_buf(), imp.vdl.as_str())];
            for (name, text) in &imp.motors {
                files.push((dir.join(name), text.as_str()));
            }
            let dirs: Vec<&Path> = if dir.as_os_str().is_empty() {
                Vec::new()
            } else {
                vec![dir]
            };
            if let Err(e) = crate::ops::files::write_all_atomic(&dirs, &files) {
                eprintln!("error: cannot write {}: {e}", out.display());
                return EXIT_USAGE;
            }
            emit(&imp.warnings, &sources, format, term);
            if format == Format::Human {
                eprintln!(
                    "ok: wrote {} and {} thrust curve(s), {} warning(s)",
                    out.display(),
                    imp.motors.len(),
                    imp.warnings.len()
                );
            }
            EXIT_OK
        }
    }
}
