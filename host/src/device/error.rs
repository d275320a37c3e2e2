//! What can go wrong with a sensor link. Every variant names the port, so the CLI's one-line
//! report says where.

use std::path::PathBuf;

use protocol::NackCode;

/// A failure to open, talk to or keep a sensor.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DeviceError {
    /// Nothing exists at the port path.
    #[error("port {port}: no such device")]
    NotFound { port: PathBuf },
    /// No USB serial port carries the requested serial number.
    #[error("no serial port with USB serial number {serial}")]
    NoSuchSerial { serial: String },
    /// The process may not open the port (group `dialout`? udev rule?).
    #[error("port {port}: permission denied")]
    PermissionDenied { port: PathBuf },
    /// The path exists but is not a terminal device (a directory or a plain file).
    #[error("port {port}: not a serial device ({what})")]
    NotATty { port: PathBuf, what: &'static str },
    /// Another process holds the port (exclusive lock).
    #[error("port {port}: busy (opened exclusively by another process)")]
    Busy { port: PathBuf },
    /// The device went away (unplugged, emulator stopped) and did not come back in time.
    #[error("port {port}: device gone")]
    Gone { port: PathBuf },
    /// The device did not answer a command within its timeout, after every retry.
    #[error("port {port}: no reply to {command} after {attempts} attempts")]
    Timeout {
        port: PathBuf,
        command: &'static str,
        attempts: u32,
    },
    /// The device refused a command.
    #[error("port {port}: {command} refused by the device ({code:?})")]
    Nack {
        port: PathBuf,
        command: &'static str,
        code: NackCode,
    },
    /// The device speaks another protocol version.
    #[error("port {port}: device speaks protocol version {got}, this host speaks {want}")]
    Version { port: PathBuf, got: u8, want: u8 },
    /// Any other operating-system error on the port.
    #[error("port {port}: {source}")]
    Io {
        port: PathBuf,
        source: std::io::Error,
    },
}

impl sysexit::ExitStatus for DeviceError {
    fn exit_code(&self) -> u8 {
        use sysexit as exit;
        match self {
            Self::NotFound { .. } | Self::NoSuchSerial { .. } => exit::NO_INPUT,
            Self::PermissionDenied { .. } => exit::NO_PERM,
            Self::NotATty { .. } => exit::NO_INPUT,
            Self::Busy { .. } | Self::Gone { .. } | Self::Timeout { .. } => exit::UNAVAILABLE,
            Self::Nack { .. } | Self::Version { .. } => exit::PROTOCOL,
            Self::Io { .. } => exit::IO,
        }
    }
}
