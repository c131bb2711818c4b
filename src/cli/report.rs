//! `flexflight report DIR`: draw a run's or a map's report ([`crate::ops::report`]) and say
//! what was written.

use crate::ops::report::{ReportArgs, build_report};

use super::{EXIT_DIAGNOSTICS, EXIT_OK, EXIT_USAGE, Terminal};

/// `flexflight report DIR`.
pub fn cmd_report(args: &ReportArgs, _term: Terminal) -> u8 {
    let done = match build_report(args) {
        Ok(d) => d,
        Err(crate::ops::OpsError::Coded {
            code,
            message,
            input,
        }) => {
            eprintln!("error[{code}]: {message}");
            return if input { EXIT_DIAGNOSTICS } else { EXIT_USAGE };
        }
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_USAGE;
        }
    };
    for r in &done.removed {
        eprintln!("removed stale {}", r.display());
    }
    for w in &done.warnings {
        eprintln!("warning: {w}");
    }
    eprintln!(
        "{} figure(s) drawn, {} skipped ({} files) -> {}",
        done.drawn,
        done.skipped,
        done.files,
        done.index.display()
    );
    EXIT_OK
}
