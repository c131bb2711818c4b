//! The `flexflight` binary: parses arguments, decides how the terminal draws reports (the
//! graphical miette handler lives only here), and hands over to `flexflight::cli`.

use std::io::IsTerminal;
use std::process::ExitCode;

use clap::Parser;
use flexflight::cli::{self, Cli, Terminal};
use flexflight::diagnostics::RenderOptions;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let stderr = std::io::stderr();
    let color = stderr.is_terminal() && std::env::var_os("NO_COLOR").is_none();
    let width = std::env::var("COLUMNS")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(100);
    let term = Terminal {
        render: RenderOptions {
            width,
            color,
            unicode: true,
        },
    };
    cli::run(cli, term)
}
