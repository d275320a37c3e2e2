//! `tactile`: parse the raw arguments into a validated command, run it, map errors to exit codes.
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = match tactile::cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) => return tactile::cli::report_usage(&err),
    };
    match cli.command.run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => tactile::cli::report(&err),
    }
}
