//! `tactile`: parse the raw arguments into a validated command, run it, map errors to exit codes.

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = host::cli::Cli::parse();
    match host::cmd::run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => host::cli::report(&err),
    }
}
