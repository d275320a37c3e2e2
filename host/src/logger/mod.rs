//! Recording: the contract CSV and the MCAP file, fed by the driver's [`Event`]s (live) or by
//! re-decoded raw frames (replay), with one code path for both.
//!
//! Crash safety: rows are formatted whole and buffered; [`Recorder::maybe_flush`] writes the
//! buffer out every [`FLUSH_EVERY`] (well under the one second allowed), so a `kill -9` loses at
//! most that much. The CSV only ever receives whole lines. The MCAP writer closes its chunk at
//! every flush, so a killed logger leaves a file whose complete chunks [`mcap_io::recover`]
//! reads without the summary section it never wrote.

pub mod csv;
pub mod mcap_io;
pub mod reference;
pub mod replay;

use std::cell::RefCell;
use std::fmt::Write as _;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use protocol::Info;

use crate::device::{Event, Frame, Gap, GapKind, Scale};
use csv::{CsvSink, REQUIRED_COLUMNS};
use mcap_io::{McapSink, SensorChannels};

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
    /// The file breaks its format at this line and field.
    #[error("{}:{line}: field {field}: {why}", .path.display())]
    Malformed {
        path: PathBuf,
        line: usize,
        field: String,
        why: String,
    },
    /// Writing an output failed.
    #[error("{}: {source}", .path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
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

    pub fn exit_code(&self) -> u8 {
        use crate::cli::exit;
        match self {
            Self::Open { source, .. } => match source.kind() {
                std::io::ErrorKind::NotFound => exit::NO_INPUT,
                std::io::ErrorKind::PermissionDenied => exit::NO_PERM,
                _ => exit::NO_INPUT,
            },
            Self::Malformed { .. } | Self::Capture { .. } => exit::DATA,
            Self::Write { .. } => exit::CANT_CREATE,
        }
    }
}

/// Columns written after the contract's: both timestamps, the sequence, the gap marks, the
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
}

impl Setup {
    /// The set-up of the standard compression test in `hardware/fingertip.toml`.
    pub fn from_hardware(source: String) -> Result<Self, hardware::LoadError> {
        let p = hardware::Params::load_default()?;
        Ok(Self {
            contact_angle_deg: p.fingertip.test.contact_angle_deg,
            azimuth_deg: p.fingertip.test.azimuth_deg,
            fingertip_radius_mm: p.fingertip.radius_mm,
            rod_speed_mm_per_min: Some(p.fingertip.test.rod_speed_mm_per_min),
            source,
        })
    }
}

/// The contract's metadata lines for a device described by `info`.
pub fn metadata(info: &Info, setup: &Setup, start: SystemTime) -> Vec<(String, String)> {
    let mut m: Vec<(String, String)> = vec![
        ("format".into(), csv::FORMAT.into()),
        ("sample_rate_hz".into(), info.sample_rate_hz.to_string()),
        (
            "contact_angle_deg".into(),
            setup.contact_angle_deg.to_string(),
        ),
        ("azimuth_deg".into(), setup.azimuth_deg.to_string()),
        (
            "fingertip_radius_mm".into(),
            setup.fingertip_radius_mm.to_string(),
        ),
        ("gain_fz".into(), info.amp_gain[0].to_string()),
        ("gain_mx".into(), info.amp_gain[1].to_string()),
        ("gain_my".into(), info.amp_gain[2].to_string()),
        ("excitation_V".into(), info.excitation_v.to_string()),
    ];
    if let Some(v) = setup.rod_speed_mm_per_min {
        m.push(("rod_speed_mm_per_min".into(), v.to_string()));
    }
    m.push(("source".into(), setup.source.clone()));
    m.push(("chip_serial".into(), format!("{:08x}", info.chip_serial)));
    let fw = info.fw_version;
    m.push(("firmware".into(), format!("{}.{}.{}", fw[0], fw[1], fw[2])));
    m.push(("start_unix_s".into(), unix_s(start).to_string()));
    m
}

pub fn unix_s(t: SystemTime) -> f64 {
    t.duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// Writes one sensor's CSV. Times: within a connection session `t_s` follows the device clock
/// (no host jitter); each session is anchored to the host clock at its first frame, and `t_s`
/// never decreases.
pub struct Recorder {
    path: PathBuf,
    csv: CsvSink<BufWriter<Box<dyn std::io::Write>>>,
    scale: Scale,
    rate_hz: f64,
    start: SystemTime,
    anchor: Option<(u32, f64)>,
    last_t_s: f64,
    last_flush: Instant,
    mcap: Option<SharedMcap>,
    json: String,
    pub rows: u64,
}

fn ns(unix_s: f64) -> u64 {
    (unix_s.max(0.0) * 1e9) as u64
}

impl Recorder {
    pub fn create(
        path: &Path,
        info: &Info,
        setup: &Setup,
        start: SystemTime,
    ) -> Result<Self, FileError> {
        let file = File::create(path).map_err(|e| FileError::write(path, e))?;
        Self::create_on(Box::new(file), path, info, setup, start)
    }

    /// Write to `out` (e.g. stdout); `path` names it in messages.
    pub fn create_on(
        out: Box<dyn std::io::Write>,
        path: &Path,
        info: &Info,
        setup: &Setup,
        start: SystemTime,
    ) -> Result<Self, FileError> {
        let file = out;
        let mut columns = REQUIRED_COLUMNS.to_vec();
        columns.extend(EXTRA_COLUMNS);
        let out = BufWriter::with_capacity(1 << 20, file);
        let mut csv = CsvSink::new(out, &metadata(info, setup, start), &columns)
            .map_err(|e| FileError::write(path, e))?;
        csv.flush().map_err(|e| FileError::write(path, e))?;
        Ok(Self {
            path: path.to_path_buf(),
            csv,
            scale: Scale::from_info(info),
            rate_hz: f64::from(info.sample_rate_hz.max(1)),
            start,
            anchor: None,
            last_t_s: 0.0,
            last_flush: Instant::now(),
            mcap: None,
            json: String::new(),
            rows: 0,
        })
    }

    /// Let go of the MCAP writer (so the caller can finish it).
    pub fn detach_mcap(&mut self) {
        self.mcap = None;
    }

    /// Also write raw frames, decoded samples and gaps to `mcap`.
    pub fn with_mcap(mut self, mcap: SharedMcap) -> Self {
        self.mcap = Some(mcap);
        self
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn on_event(&mut self, ev: &Event) -> Result<(), FileError> {
        match ev {
            Event::Frame(f) => self.on_frame(f),
            Event::Gap(g) => self.on_gap(g),
            Event::Info(i) => {
                if let Some((m, ch)) = &self.mcap {
                    if let Ok(raw) = protocol::encode_vec(&protocol::Message::Info(i.clone())) {
                        let t = ns(unix_s(SystemTime::now()));
                        m.borrow_mut().write(ch.raw, t, t, &raw[..raw.len() - 1])?;
                    }
                }
                self.scale = Scale::from_info(i);
                self.rate_hz = f64::from(i.sample_rate_hz.max(1));
                Ok(())
            }
        }
    }

    fn host_s(&self, t: SystemTime) -> f64 {
        unix_s(t) - unix_s(self.start)
    }

    fn on_frame(&mut self, f: &Frame) -> Result<(), FileError> {
        let t_dev0_s = f.t_device_us as f64 * 1e-6;
        let anchor = match self.anchor {
            Some((session, a)) if session == f.session => a,
            _ => {
                let a = self.host_s(f.host_time) - t_dev0_s;
                self.anchor = Some((f.session, a));
                a
            }
        };
        let t_host = unix_s(f.host_time);
        let start = unix_s(self.start);
        if let Some((m, ch)) = &self.mcap {
            m.borrow_mut()
                .write(ch.raw, ns(start + anchor + t_dev0_s), ns(t_host), &f.raw)?;
        }
        for (k, s) in f.frame.samples().iter().enumerate() {
            let t_dev_s = t_dev0_s + k as f64 / self.rate_hz;
            let t_s = (anchor + t_dev_s).max(self.last_t_s);
            self.last_t_s = t_s;
            let v = self.scale.adc_volts(s);
            let l = self.scale.loads(s);
            let row = [
                Some(t_s),
                None,
                None,
                Some(v[0]),
                Some(v[1]),
                Some(v[2]),
                Some(f64::from(f.seq)),
                Some(t_dev_s),
                Some(t_host),
                Some(f64::from(f.session)),
                Some(gap_code::NONE),
                Some(0.0),
                Some(l[0]),
                Some(l[1]),
                Some(l[2]),
                Some(f64::from(f.frame.temp)),
                Some(f64::from(f.frame.status.saturated)),
            ];
            self.csv
                .row(&row)
                .map_err(|e| FileError::write(&self.path, e))?;
            self.rows += 1;
            if let Some((m, ch)) = &self.mcap {
                self.json.clear();
                let _ = write!(
                    self.json,
                    r#"{{"t_s":{t_s},"t_device_s":{t_dev_s},"t_host_s":{t_host},"seq":{},"session":{},"fz_V":{},"mx_V":{},"my_V":{},"fz_N":{},"mx_Nm":{},"my_Nm":{},"temp_code":{},"saturated":{}}}"#,
                    f.seq,
                    f.session,
                    v[0],
                    v[1],
                    v[2],
                    l[0],
                    l[1],
                    l[2],
                    f.frame.temp,
                    f.frame.status.saturated
                );
                m.borrow_mut().write(
                    ch.sample,
                    ns(start + t_s),
                    ns(t_host),
                    self.json.as_bytes(),
                )?;
            }
        }
        self.maybe_flush()
    }

    /// A gap is a row with the time and the gap columns only: every required value is missing,
    /// which the contract reads as a gap.
    fn on_gap(&mut self, g: &Gap) -> Result<(), FileError> {
        let (code, missing) = match &g.kind {
            GapKind::Sequence { missing, .. } => (gap_code::SEQUENCE, Some(*missing as f64)),
            GapKind::Disconnected => (gap_code::DISCONNECTED, None),
            GapKind::Reconnected { missing, .. } => {
                (gap_code::RECONNECTED, missing.map(|m| m as f64))
            }
            GapKind::DeviceRestart { .. } => (gap_code::DEVICE_RESTART, None),
            GapKind::HostQueueFull { frames } => (gap_code::HOST_QUEUE, Some(*frames as f64)),
        };
        let t_s = self.host_s(g.host_time).max(self.last_t_s);
        self.last_t_s = t_s;
        let mut row = [None; 17];
        row[0] = Some(t_s);
        row[8] = Some(unix_s(g.host_time));
        row[9] = Some(f64::from(g.session));
        row[10] = Some(code);
        row[11] = missing;
        self.csv
            .row(&row)
            .map_err(|e| FileError::write(&self.path, e))?;
        if let Some((m, ch)) = &self.mcap {
            let kind = match &g.kind {
                GapKind::Sequence { .. } => "sequence",
                GapKind::Disconnected => "disconnected",
                GapKind::Reconnected { .. } => "reconnected",
                GapKind::DeviceRestart { .. } => "device_restart",
                GapKind::HostQueueFull { .. } => "host_queue_full",
            };
            let json = format!(
                r#"{{"t_s":{t_s},"kind":"{kind}","missing":{},"session":{}}}"#,
                missing.unwrap_or(-1.0),
                g.session
            );
            let t = ns(unix_s(self.start) + t_s);
            m.borrow_mut()
                .write(ch.gap, t, ns(unix_s(g.host_time)), json.as_bytes())?;
        }
        // A gap is exactly what a later reader must not miss: write it out now.
        self.flush()
    }

    pub fn maybe_flush(&mut self) -> Result<(), FileError> {
        if self.last_flush.elapsed() >= FLUSH_EVERY {
            self.flush()?;
        }
        Ok(())
    }

    pub fn flush(&mut self) -> Result<(), FileError> {
        self.last_flush = Instant::now();
        self.csv
            .flush()
            .map_err(|e| FileError::write(&self.path, e))?;
        if let Some((m, _)) = &self.mcap {
            m.borrow_mut().flush()?;
        }
        Ok(())
    }
}
