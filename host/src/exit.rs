//! Exit codes, after BSD sysexits, so scripts can tell a bad file from a missing port. Error
//! types of the host library say which one they deserve ([`ExitStatus`]); errors of the other
//! crates are mapped in [`crate::cmd::exit_code_of`].

/// Internal error: a bug or a state the program did not expect.
pub const SOFTWARE: u8 = 70;
/// Bad command-line arguments.
pub const USAGE: u8 = 64;
/// An input file or device answer that breaks its format.
pub const DATA: u8 = 65;
/// An input file or port that is not there.
pub const NO_INPUT: u8 = 66;
/// A device that is busy, gone or silent.
pub const UNAVAILABLE: u8 = 69;
/// Any other I/O error.
pub const IO: u8 = 74;
/// An output file could not be created or written.
pub const CANT_CREATE: u8 = 73;
/// Permission denied on a file or port.
pub const NO_PERM: u8 = 77;
/// The device answered but refused or spoke another protocol version.
pub const PROTOCOL: u8 = 76;

/// Something that knows which exit code it deserves. Error types of the library implement
/// this; [`crate::cli::report`] finds the first one in an `anyhow` chain.
pub trait ExitStatus {
    /// The sysexits code the process ends with.
    fn exit_code(&self) -> u8;
}

/// The code for an input that could not be opened or read for reason `kind`.
pub fn of_input(kind: std::io::ErrorKind) -> u8 {
    match kind {
        std::io::ErrorKind::NotFound => NO_INPUT,
        std::io::ErrorKind::PermissionDenied => NO_PERM,
        _ => IO,
    }
}

/// An error the command has already told the user about, line by line (a session's bad
/// recordings); [`crate::cli::report`] only ends the process with `code`.
#[derive(Debug, thiserror::Error)]
#[error("{what}")]
pub struct Reported {
    /// The sysexits code the process ends with.
    pub code: u8,
    /// What happened, in one line, for a caller that prints it anyway.
    pub what: String,
}
