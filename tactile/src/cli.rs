//! Top-level argument tree, and how an error ends the process: one line on stderr and the exit
//! code its error chose ([`sysexit`]).

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::cmd;

/// Record, simulate and diagnose a soft fingertip's force/moment sensor: a MEMS chip measuring
/// Fz, Mx and My at the base of a 40 mm gel hemisphere. Talk to sensors over USB serial (list,
/// info, tare, config); record one sensor or a whole hand to CSV and MCAP (log), re-decode a
/// capture (replay), plot a recording (plot), convert a test machine's export (import); model
/// the chip and the fingertip (chip, fe, observations) and simulate a compression test
/// (simulate); and where a recording and the model disagree, find where and name the missing
/// physics, for one recording, a batch or a session of one sensor diagnosed jointly (diagnose);
/// prove scores that diagnosis on recordings with concealed effects. `tactile COMMAND --help`
/// describes each; an error is one line naming the file, line or port, with a sysexits code.
#[derive(Debug, Parser)]
#[command(name = "tactile", version, long_about = None, propagate_version = true)]
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
    /// Write the baseline model's recording of the standard compression test, with effects.
    Simulate(cmd::simulate::Args),
    /// Locate where recordings and the model disagree and name the missing physics: one
    /// recording, a batch (--out-dir) or a session diagnosed jointly (--joint).
    Diagnose(cmd::diagnose::Args),
    /// Generate recordings with concealed effects, diagnose them blind and score the result.
    Prove(cmd::prove::Args),
    /// Convert a test machine's export (Mach-1 text, generic CSV), or a sensor's log with a
    /// reference's log, to a recording.
    Import(cmd::import::Args),
}

impl Command {
    /// Run the subcommand.
    pub fn run(self) -> anyhow::Result<()> {
        match self {
            Self::List(a) => cmd::list::run(a),
            Self::Info(a) => cmd::info::run(a),
            Self::Log(a) => cmd::log::run(a),
            Self::Tare(a) => cmd::tare::run(a),
            Self::Config(a) => cmd::config::run(a),
            Self::Replay(a) => cmd::replay::run(a),
            Self::Plot(a) => cmd::plot::run(a),
            Self::Chip(a) => cmd::chip::run(a),
            Self::Fe(a) => cmd::fe::run(a),
            Self::Observations(a) => cmd::observations::run(a),
            Self::Simulate(a) => cmd::simulate::run(a),
            Self::Diagnose(a) => cmd::diagnose::run(a),
            Self::Prove(a) => cmd::prove::run(a),
            Self::Import(a) => cmd::import::run(a),
        }
    }
}

/// Print `err` as one line on stderr and choose the exit code. A broken pipe is success:
/// `tactile replay x.mcap | head` must not fail. An error the command already told the user
/// about line by line ([`sysexit::Reported`]) only sets the code.
pub fn report(err: &anyhow::Error) -> ExitCode {
    if is_broken_pipe(err) {
        return ExitCode::SUCCESS;
    }
    let code = sysexit::code_of(err.chain()).unwrap_or(1);
    if err.downcast_ref::<sysexit::Reported>().is_none() {
        eprintln!("tactile: error: {}", sysexit::one_line(err.chain()));
    }
    ExitCode::from(code)
}

/// Print a clap outcome: `--help` and `--version` go to stdout with success; a bad flag or value
/// goes to stderr with [`sysexit::USAGE`], like every other error of ours, not clap's own 2.
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
    ExitCode::from(sysexit::USAGE)
}

fn is_broken_pipe(err: &anyhow::Error) -> bool {
    err.chain().any(|e| {
        e.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}
