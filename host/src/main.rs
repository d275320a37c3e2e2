//! `tactile`: parse the raw arguments into a validated command, run it, map errors to exit codes.

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = match host::cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) => return host::cli::report_usage(&err),
    };
    match host::cmd::run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => host::cli::report(&err),
    }
}
