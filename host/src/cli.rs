//! Top-level argument tree, and how an error ends the process: one line on stderr and the exit
//! code of [`crate::exit`].

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::cmd;
use crate::exit;

/// Firmware and host toolkit for the MEMS force/moment sensor in a soft fingertip.
#[derive(Debug, Parser)]
#[command(name = "tactile", version, about, long_about = None, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// List serial ports with their USB serial numbers.
    List(cmd::list::Args),
    /// Print a sensor's device info / configuration frame.
    Info(cmd::info::Args),
    /// Record one or several sensors to the recording CSV and an MCAP file.
    Log(cmd::log::Args),
    /// Digital tare: average samples at rest and subtract them on the device.
    Tare(cmd::tare::Args),
    /// Change a sensor's sample rate, filter or calibration.
    Config(cmd::config::Args),
    /// Re-decode a raw capture or MCAP file to the recording CSV.
    Replay(cmd::replay::Args),
    /// Plot a recording to PNG and SVG.
    Plot(cmd::plot::Args),
    /// Print the chip's sensitivities, crosstalk and strength for the geometry in hardware/.
    Chip(cmd::chip::Args),
    /// Run the soft-fingertip finite-element model of a rod compression.
    Fe(cmd::fe::Args),
    /// The paper's seven observations against the fingertip model: a scorecard.
    Observations(cmd::observations::Args),
    /// Write the baseline model's recording of the standard compression test.
    Simulate(cmd::simulate::Args),
    /// Locate where a recording and the simulation disagree and name the missing physics.
    Diagnose(cmd::diagnose::Args),
    /// Generate recordings with concealed effects, diagnose them blind and score the result.
    Prove(cmd::prove::Args),
    /// Convert a test machine's export (Mach-1 text, generic CSV) to a recording.
    Import(cmd::import::Args),
}

/// Print `err` as one line on stderr and choose the exit code. A broken pipe is success:
/// `tactile replay x.mcap | head` must not fail.
pub fn report(err: &anyhow::Error) -> ExitCode {
    if is_broken_pipe(err) {
        return ExitCode::SUCCESS;
    }
    if let Some(done) = err.downcast_ref::<exit::Reported>() {
        return ExitCode::from(done.code);
    }
    let line = err
        .chain()
        .map(|e| e.to_string())
        .collect::<Vec<_>>()
        .join(": ");
    eprintln!("tactile: error: {line}");
    ExitCode::from(exit_code(err))
}

/// Print a clap outcome: `--help` and `--version` go to stdout with success; a bad flag or value
/// goes to stderr with [`exit::USAGE`], like every other error of ours, not clap's own 2.
pub fn report_usage(err: &clap::Error) -> ExitCode {
    if !err.use_stderr() {
        // Printing help into a closed pipe is not an error either.
        let _ = err.print();
        return ExitCode::SUCCESS;
    }
    // One line, like every other error: clap's own first line names the flag and the value.
    let text = err.render().to_string();
    let line = text
        .lines()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("invalid arguments");
    let line = line.trim_start_matches("error: ");
    eprintln!("tactile: error: {line} (see --help)");
    ExitCode::from(exit::USAGE)
}

fn is_broken_pipe(err: &anyhow::Error) -> bool {
    err.chain().any(|e| {
        e.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

fn exit_code(err: &anyhow::Error) -> u8 {
    for cause in err.chain() {
        if let Some(code) = crate::cmd::exit_code_of(cause) {
            return code;
        }
        if let Some(io) = cause.downcast_ref::<std::io::Error>() {
            return match io.kind() {
                std::io::ErrorKind::NotFound => exit::NO_INPUT,
                std::io::ErrorKind::PermissionDenied => exit::NO_PERM,
                _ => exit::IO,
            };
        }
    }
    1
}
