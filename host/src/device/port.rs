//! Finding and opening a serial port: by path or by USB serial number, exclusively.

use std::path::{Path, PathBuf};
use std::time::Duration;

use serialport::{SerialPort, SerialPortType, TTYPort};

use super::DeviceError;

/// Which sensor to open.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PortSpec {
    /// A device path (`/dev/ttyACM0`, a pty, a stable symlink from udev).
    Path(PathBuf),
    /// The USB serial number of the adapter, looked up among the system's ports.
    Serial(String),
}

impl PortSpec {
    /// `serial:ABC123` selects by USB serial number; anything else is a path.
    pub fn parse(s: &str) -> Self {
        match s.strip_prefix("serial:") {
            Some(sn) => Self::Serial(sn.to_owned()),
            None => Self::Path(PathBuf::from(s)),
        }
    }

    /// The path to open now (a serial number is looked up again on every call, so a replugged
    /// adapter that came back under another ttyACM name is found).
    pub fn resolve(&self) -> Result<PathBuf, DeviceError> {
        match self {
            Self::Path(p) => Ok(p.clone()),
            Self::Serial(sn) => list_ports()
                .into_iter()
                .find(|p| p.serial_number.as_deref() == Some(sn.as_str()))
                .map(|p| PathBuf::from(p.path))
                .ok_or_else(|| DeviceError::NoSuchSerial { serial: sn.clone() }),
        }
    }

    /// A short name for messages and file names.
    pub fn label(&self) -> String {
        match self {
            Self::Path(p) => p.display().to_string(),
            Self::Serial(sn) => format!("serial:{sn}"),
        }
    }
}

/// One port the system knows, for `tactile list`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PortEntry {
    pub path: String,
    pub serial_number: Option<String>,
    pub description: String,
}

/// Every serial port the system enumerates (USB ones with vendor, product and serial number).
pub fn list_ports() -> Vec<PortEntry> {
    let ports = serialport::available_ports().unwrap_or_default();
    ports
        .into_iter()
        .map(|p| match p.port_type {
            SerialPortType::UsbPort(u) => PortEntry {
                path: p.port_name,
                serial_number: u.serial_number,
                description: format!(
                    "USB {:04x}:{:04x} {} {}",
                    u.vid,
                    u.pid,
                    u.manufacturer.unwrap_or_default(),
                    u.product.unwrap_or_default()
                ),
            },
            SerialPortType::PciPort => PortEntry {
                path: p.port_name,
                serial_number: None,
                description: "PCI".into(),
            },
            SerialPortType::BluetoothPort => PortEntry {
                path: p.port_name,
                serial_number: None,
                description: "Bluetooth".into(),
            },
            SerialPortType::Unknown => PortEntry {
                path: p.port_name,
                serial_number: None,
                description: "other".into(),
            },
        })
        .collect()
}

/// Link speed used for real USB-serial adapters (SPEC.md's budget is computed for it); a pty or
/// a USB CDC device ignores it.
pub const BAUD: u32 = 921_600;

/// How long one blocking read waits before the I/O loop looks at commands and deadlines.
pub const READ_POLL: Duration = Duration::from_millis(10);

/// Open `path` exclusively (TIOCEXCL and an exclusive `flock`, which also holds against root),
/// naming the precise reason when it fails.
pub fn open_path(path: &Path) -> Result<TTYPort, DeviceError> {
    let port = path.to_path_buf();
    let meta = std::fs::metadata(path).map_err(|e| classify_io(&port, e))?;
    if meta.is_dir() {
        return Err(DeviceError::NotATty {
            port,
            what: "a directory",
        });
    }
    if meta.is_file() {
        return Err(DeviceError::NotATty {
            port,
            what: "a regular file",
        });
    }
    let builder = serialport::new(path.to_string_lossy(), BAUD).timeout(READ_POLL);
    let tty = TTYPort::open(&builder).map_err(|e| classify_serial(&port, e))?;
    let _ = tty.clear(serialport::ClearBuffer::All);
    Ok(tty)
}

fn classify_io(port: &Path, e: std::io::Error) -> DeviceError {
    let port = port.to_path_buf();
    match e.kind() {
        std::io::ErrorKind::NotFound => DeviceError::NotFound { port },
        std::io::ErrorKind::PermissionDenied => DeviceError::PermissionDenied { port },
        _ => DeviceError::Io { port, source: e },
    }
}

fn classify_serial(port: &Path, e: serialport::Error) -> DeviceError {
    let port = port.to_path_buf();
    match e.kind() {
        serialport::ErrorKind::NoDevice => DeviceError::Busy { port },
        serialport::ErrorKind::Io(kind) => {
            classify_io(&port, std::io::Error::new(kind, e.description))
        }
        _ if e.description.contains("Inappropriate ioctl") => DeviceError::NotATty {
            port,
            what: "not a terminal",
        },
        _ => DeviceError::Io {
            port,
            source: std::io::Error::other(e.description),
        },
    }
}
