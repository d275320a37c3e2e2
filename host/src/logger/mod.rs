//! Recording: the contract CSV (written by [`recording::RecordingWriter`]) and the MCAP file, fed by the driver's [`Event`](crate::device::Event)s (live) or by
//! re-decoded raw frames (replay), with one code path for both.
//!
//! Crash safety: rows are formatted whole and buffered; [`Recorder::maybe_flush`] writes the
//! buffer out every [`FLUSH_EVERY`] (well under the one second allowed), so a `kill -9` loses at
//! most that much. The CSV only ever receives whole lines. The MCAP writer closes its chunk at
//! every flush, so a killed logger leaves a file whose complete chunks [`mcap_io::recover`]
//! reads without the summary section it never wrote.

pub mod cdr;
pub mod mcap_io;
mod recorder;
pub mod reference;
pub mod replay;
mod rows;

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use protocol::Info;

use mcap_io::{McapSink, SensorChannels};
pub use recorder::Recorder;
use recording::Meta;

/// The MCAP file shared by every sensor of one `log` run, with this sensor's channels.
pub type SharedMcap = (Rc<RefCell<McapSink>>, SensorChannels);

/// How often buffered rows and MCAP chunks reach the file.
pub const FLUSH_EVERY: Duration = Duration::from_millis(250);

/// A file that cannot be read or written, or does not hold what it should.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FileError {
    /// The file could not be opened or read.
    #[error("{}: {source}", .path.display())]
    Open {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A recording CSV that the format's reader refused (names file, line and field).
    #[error(transparent)]
    Recording(#[from] recording::RecordingError),
    /// A test machine's export that its reader refused (names file, line and field).
    #[error(transparent)]
    Machine(#[from] recording::machine::MachineExportError),
    /// The file breaks its format at this line and field.
    #[error("{}:{line}: field {field}: {why}", .path.display())]
    Malformed {
        path: PathBuf,
        line: usize,
        field: String,
        why: String,
    },
    /// The file's syntax breaks at this line, where no field is defined (a TOML line without
    /// a key).
    #[error("{}:{line}: {why}", .path.display())]
    Syntax {
        path: PathBuf,
        line: usize,
        why: String,
    },
    /// Writing an output failed.
    #[error("{}: {source}", .path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    /// An input bigger than the reader holds in memory.
    #[error("{}: {bytes} bytes is over the {limit_bytes}-byte limit of this reader ({why})", .path.display())]
    TooLarge {
        path: PathBuf,
        bytes: u64,
        limit_bytes: u64,
        why: &'static str,
    },
    /// An MCAP or raw capture that cannot be read at all.
    #[error("{}: {why}", .path.display())]
    Capture { path: PathBuf, why: String },
}

impl FileError {
    pub(crate) fn open(path: &Path, source: std::io::Error) -> Self {
        Self::Open {
            path: path.to_path_buf(),
            source,
        }
    }

    pub(crate) fn write(path: &Path, source: std::io::Error) -> Self {
        Self::Write {
            path: path.to_path_buf(),
            source,
        }
    }
}

impl sysexit::ExitStatus for FileError {
    fn exit_code(&self) -> u8 {
        use sysexit as exit;
        match self {
            Self::Open { source, .. } => match source.kind() {
                std::io::ErrorKind::NotFound => exit::NO_INPUT,
                std::io::ErrorKind::PermissionDenied => exit::NO_PERM,
                _ => exit::NO_INPUT,
            },
            Self::Recording(e) => e.io_kind().map_or(exit::DATA, exit::of_input),
            // An export that cannot be opened is a missing input, whatever the reason.
            Self::Machine(e) => match e.io_kind() {
                Some(std::io::ErrorKind::PermissionDenied) => exit::NO_PERM,
                Some(_) => exit::NO_INPUT,
                None => exit::DATA,
            },
            Self::Malformed { .. }
            | Self::Syntax { .. }
            | Self::Capture { .. }
            | Self::TooLarge { .. } => exit::DATA,
            Self::Write { .. } => exit::CANT_CREATE,
        }
    }
}

/// Columns written after the contract's (and `temp_C`): both timestamps, the sequence, the gap marks, the
/// loads through the calibration matrix and the raw temperature code.
pub const EXTRA_COLUMNS: [&str; 11] = [
    "seq",
    "t_device_s",
    "t_host_s",
    "session",
    "gap",
    "missing",
    "fz_N",
    "mx_Nm",
    "my_Nm",
    "temp_code",
    "saturated",
];

/// `gap` column codes.
pub mod gap_code {
    pub const NONE: f64 = 0.0;
    pub const SEQUENCE: f64 = 1.0;
    pub const DISCONNECTED: f64 = 2.0;
    pub const RECONNECTED: f64 = 3.0;
    pub const DEVICE_RESTART: f64 = 4.0;
    pub const HOST_QUEUE: f64 = 5.0;
}

/// What the contract's metadata says about the test set-up, besides what the device reports.
#[derive(Debug, Clone)]
pub struct Setup {
    pub contact_angle_deg: f64,
    pub azimuth_deg: f64,
    pub fingertip_radius_mm: f64,
    pub rod_speed_mm_per_min: Option<f64>,
    pub source: String,
    /// The temperature sensor on ADC channel 3, to write `temp_C`; `None`: no `temp_C` column.
    pub temp_sensor: Option<sim::frontend::TempSensor>,
    /// Time the rows by the device's own stamps, from the first frame's receipt, instead of
    /// mapping its clock onto the host's: for a device whose clock does not run in real time
    /// (an emulator on a virtual clock, which runs a test's minutes in seconds).
    pub device_clock: bool,
}

impl Setup {
    /// The set-up of the standard compression test in `hardware/fingertip.toml`, and the
    /// board's temperature sensor of `hardware/frontend.toml`.
    pub fn from_hardware(source: String) -> Result<Self, hardware::LoadError> {
        let p = hardware::Params::load_default()?;
        Ok(Self {
            contact_angle_deg: p.fingertip.test.contact_angle_deg,
            azimuth_deg: p.fingertip.test.azimuth_deg,
            fingertip_radius_mm: p.fingertip.radius_mm,
            rod_speed_mm_per_min: Some(p.fingertip.test.rod_speed_mm_per_min),
            source,
            temp_sensor: Some(sim::frontend::FrontEnd::from_params(&p).temperature),
            device_clock: false,
        })
    }
}

/// The value an `f32` of the info frame was set to: its shortest decimal form (`3.3`, not
/// `3.299999952316284`), which is what the device was configured with.
fn decimal(v: f32) -> f64 {
    v.to_string().parse().unwrap_or(f64::from(v))
}

/// The recording's metadata for a device described by `info`: every key of the contract, then
/// this project's own (chip serial, firmware, start time, the firmware filter the diagnosis
/// needs to model the smoother).
pub fn metadata(info: &Info, setup: &Setup, start: SystemTime) -> Meta {
    let fw = info.fw_version;
    let f = info.filter;
    let other = [
        (
            recording::CHIP_SERIAL_KEY,
            format!("{:08x}", info.chip_serial),
        ),
        ("firmware", format!("{}.{}.{}", fw[0], fw[1], fw[2])),
        ("start_unix_s", unix_s(start).to_string()),
        (
            recording::SMOOTHER_KEY,
            decimal(f.smoother_alpha).to_string(),
        ),
        (
            "firmware_butterworth_order",
            f.butterworth_order.to_string(),
        ),
        ("firmware_cutoff_hz", decimal(f.cutoff_hz).to_string()),
        (
            clock_key::TIME_BASE,
            clock_key::time_base(setup.device_clock).to_string(),
        ),
        (clock_key::PPM, PENDING.to_string()),
        (clock_key::UNCERTAINTY, PENDING.to_string()),
        (clock_key::RESTARTS, PENDING.to_string()),
    ];
    Meta {
        sample_rate_hz: f64::from(info.sample_rate_hz),
        contact_angle_deg: setup.contact_angle_deg,
        azimuth_deg: setup.azimuth_deg,
        fingertip_radius_mm: setup.fingertip_radius_mm,
        gain_fz: decimal(info.amp_gain[0]),
        gain_mx: decimal(info.amp_gain[1]),
        gain_my: decimal(info.amp_gain[2]),
        excitation_v: decimal(info.excitation_v),
        rod_speed_mm_per_min: setup.rod_speed_mm_per_min,
        source: Some(setup.source.clone()),
        other: other.map(|(k, v)| (k.to_string(), v)).to_vec(),
    }
}

/// Placeholder of a metadata value only known at the end of the run: padded so that the final
/// value overwrites it in place (the rows after it are already written).
pub const PENDING: &str = "pending                 ";

/// This project's metadata keys for the time base (the format keeps unknown keys).
pub mod clock_key {
    use crate::clock::DeviceClock;

    pub const TIME_BASE: &str = "time_base";
    pub const TIME_BASE_VALUE: &str = "host clock; device stamps mapped by a lower-envelope fit";
    /// With `Setup::device_clock`: the clock fit is still reported, not applied.
    pub const DEVICE_TIME_BASE_VALUE: &str =
        "device clock; its stamps from the first frame's receipt (tactile log --device-clock)";
    /// The device clock's rate error against the host's, ppm, at the end of the run.
    pub const PPM: &str = "clock_ppm";
    /// The alignment's uncertainty, µs (median height of minimum-delay points above the fit).
    pub const UNCERTAINTY: &str = "clock_uncertainty_us";
    /// Sessions whose device clock restarted (placed on the time base by the fitted rate).
    pub const RESTARTS: &str = "clock_restarts";

    /// [`TIME_BASE`]'s value: the device's clock (`tactile log --device-clock`) or the host's.
    pub fn time_base(device_clock: bool) -> &'static str {
        if device_clock {
            DEVICE_TIME_BASE_VALUE
        } else {
            TIME_BASE_VALUE
        }
    }

    /// The MCAP record `clock <label>` at the end of the run: the time base the rows are on,
    /// then the clock's final values ([`pairs`]).
    pub fn record(c: &DeviceClock, device_clock: bool) -> Vec<(String, String)> {
        let mut r = vec![(TIME_BASE.to_string(), time_base(device_clock).to_string())];
        r.extend(pairs(c));
        r
    }

    /// The clock's final values under these keys.
    pub fn pairs(c: &DeviceClock) -> Vec<(String, String)> {
        vec![
            (PPM.into(), format!("{:.3}", c.ppm())),
            (
                UNCERTAINTY.into(),
                format!("{:.1}", c.uncertainty_s() * 1e6),
            ),
            (RESTARTS.into(), c.restarts.to_string()),
        ]
    }
}

pub fn unix_s(t: SystemTime) -> f64 {
    t.duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// The path a CSV for sensor `label` goes to when several sensors are logged at once.
pub fn per_sensor_path(base: &Path, label: &str, several: bool) -> PathBuf {
    if !several {
        return base.to_path_buf();
    }
    let clean: String = label
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    let stem = base
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    base.with_file_name(format!("{stem}-{}.csv", clean.trim_matches('_')))
}
