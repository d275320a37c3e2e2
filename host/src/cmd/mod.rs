//! One module per subcommand: its `Args` (clap) and `run`.

pub mod chip;
pub mod common;
pub mod config;
pub mod diagnose;
pub mod fe;
pub mod import;
pub mod info;
pub mod list;
pub mod log;
pub mod observations;
pub mod plot;
pub mod prove;
pub mod replay;
pub mod simulate;
pub mod tare;

use crate::cli::Command;
use crate::exit::{self, ExitStatus};

pub fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::List(a) => list::run(a),
        Command::Info(a) => info::run(a),
        Command::Log(a) => log::run(a),
        Command::Tare(a) => tare::run(a),
        Command::Config(a) => config::run(a),
        Command::Replay(a) => replay::run(a),
        Command::Plot(a) => plot::run(a),
        Command::Chip(a) => chip::run(a),
        Command::Fe(a) => fe::run(a),
        Command::Observations(a) => observations::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Diagnose(a) => diagnose::run(a),
        Command::Prove(a) => prove::run(a),
        Command::Import(a) => import::run(a),
    }
}

/// The exit code a library error asks for, if `cause` is one of ours. Each module that owns an
/// error type adds its downcast here.
pub fn exit_code_of(cause: &(dyn std::error::Error + 'static)) -> Option<u8> {
    if let Some(e) = cause.downcast_ref::<recording::RecordingError>() {
        return Some(e.io_kind().map_or(exit::DATA, exit::of_input));
    }
    if let Some(e) = cause.downcast_ref::<recording::machine::MachineExportError>() {
        return Some(e.io_kind().map_or(exit::DATA, exit::of_input));
    }
    // The library's wrappers forward the message of the error they hold, so the chain skips it.
    if let Some(diagnosis::chip_report::ChipReportError::Params(_)) = cause.downcast_ref() {
        return Some(exit::DATA);
    }
    if let Some(diagnosis::standard_test::SimulateError::Hardware(_)) = cause.downcast_ref() {
        return Some(exit::DATA);
    }
    if cause.is::<diagnosis::data::DataError>()
        || cause.is::<::chip::from_hardware::FromHardwareError>()
        || cause.is::<hardware::LoadError>()
        || cause.is::<crate::calibration::CalibrationError>()
    {
        return Some(exit::DATA);
    }
    if let Some(e) = cause.downcast_ref::<crate::device::DeviceError>() {
        return Some(e.exit_code());
    }
    if let Some(e) = cause.downcast_ref::<crate::logger::FileError>() {
        return Some(e.exit_code());
    }
    if let Some(e) = cause.downcast_ref::<diagnose::UsageError>() {
        return Some(e.exit_code());
    }
    if let Some(e) = cause.downcast_ref::<diagnosis::session::SessionError>() {
        return Some(session_exit_code(e));
    }
    if let Some(e) = cause.downcast_ref::<fe::FeError>() {
        return Some(e.exit_code());
    }
    if let Some(e) = cause.downcast_ref::<fingertip::Error>() {
        return Some(match e {
            fingertip::Error::InvalidConfig { .. } | fingertip::Error::PeakNotReached { .. } => {
                exit::DATA
            }
            fingertip::Error::Io(_) => exit::IO,
            _ => exit::SOFTWARE,
        });
    }
    None
}

fn session_exit_code(e: &diagnosis::session::SessionError) -> u8 {
    use diagnosis::session::SessionError as E;
    match e {
        E::ListDir { source, .. } => exit::of_input(source.kind()),
        E::NoRecordings(_) => exit::NO_INPUT,
        E::SameStem { .. } => exit::USAGE,
        E::Write { .. } => exit::CANT_CREATE,
        _ => exit::SOFTWARE,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_recording_is_no_input_and_a_broken_one_is_data() {
        let missing = recording::read(std::path::Path::new("/nonexistent/rec.csv")).unwrap_err();
        assert_eq!(exit_code_of(&missing), Some(exit::NO_INPUT));
        let broken = recording::Recording::parse("").unwrap_err();
        assert_eq!(exit_code_of(&broken), Some(exit::DATA));
        let export = recording::machine::parse("t_s\n").unwrap_err();
        assert_eq!(exit_code_of(&export), Some(exit::DATA));
    }
}
