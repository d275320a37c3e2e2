//! One sensor's recording CSV (and its share of the MCAP file), fed by the driver's events.

use std::fmt::Write as _;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::time::{Instant, SystemTime};

use protocol::Info;

use super::{gap_code, metadata, unix_s, FileError, Setup, SharedMcap, EXTRA_COLUMNS, FLUSH_EVERY};
use crate::device::{Event, Frame, Gap, GapKind, Scale};
use recording::RecordingWriter;

/// Writes one sensor's CSV. Times: within a connection session `t_s` follows the device clock
/// (no host jitter); each session is anchored to the host clock at its first frame, and `t_s`
/// never decreases.
pub struct Recorder {
    path: PathBuf,
    csv: RecordingWriter<Box<dyn std::io::Write>>,
    scale: Scale,
    temp_sensor: Option<sim::frontend::TempSensor>,
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

/// Index of each extra column in [`EXTRA_COLUMNS`].
mod col {
    pub const SEQ: usize = 0;
    pub const T_DEVICE: usize = 1;
    pub const T_HOST: usize = 2;
    pub const SESSION: usize = 3;
    pub const GAP: usize = 4;
    pub const MISSING: usize = 5;
    pub const LOADS: usize = 6;
    pub const TEMP_CODE: usize = 9;
    pub const SATURATED: usize = 10;
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
        let meta = metadata(info, setup, start);
        let with_temp = setup.temp_sensor.is_some();
        let mut csv = RecordingWriter::new(out, &meta, with_temp, &EXTRA_COLUMNS)
            .map_err(|e| FileError::write(path, e))?;
        csv.flush().map_err(|e| FileError::write(path, e))?;
        Ok(Self {
            path: path.to_path_buf(),
            csv,
            scale: Scale::from_info(info),
            temp_sensor: setup.temp_sensor,
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

    /// Temperature next to the chip from the frame's ADC channel 3 code, if the sensor is known.
    fn temp_c(&self, code: i32) -> f64 {
        self.temp_sensor.map_or(f64::NAN, |s| {
            s.temperature_c(f64::from(code) * self.scale.temp_volts_per_code)
        })
    }

    fn write_row(
        &mut self,
        required: &[f64; 6],
        temp_c: f64,
        extra: &[f64],
    ) -> Result<(), FileError> {
        self.csv
            .write_row(required, Some(temp_c), extra)
            .map_err(|e| FileError::write(&self.path, e))
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
        let temp_c = self.temp_c(f.frame.temp);
        let mut extra = [f64::NAN; EXTRA_COLUMNS.len()];
        extra[col::SEQ] = f64::from(f.seq);
        extra[col::T_HOST] = t_host;
        extra[col::SESSION] = f64::from(f.session);
        extra[col::GAP] = gap_code::NONE;
        extra[col::MISSING] = 0.0;
        extra[col::TEMP_CODE] = f64::from(f.frame.temp);
        extra[col::SATURATED] = f64::from(f.frame.status.saturated);
        for (k, s) in f.frame.samples().iter().enumerate() {
            let t_dev_s = t_dev0_s + k as f64 / self.rate_hz;
            let t_s = (anchor + t_dev_s).max(self.last_t_s);
            self.last_t_s = t_s;
            let v = self.scale.adc_volts(s);
            let l = self.scale.loads(s);
            extra[col::T_DEVICE] = t_dev_s;
            extra[col::LOADS..col::LOADS + 3].copy_from_slice(&l);
            self.write_row(&[t_s, f64::NAN, f64::NAN, v[0], v[1], v[2]], temp_c, &extra)?;
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
        let mut extra = [f64::NAN; EXTRA_COLUMNS.len()];
        extra[col::T_HOST] = unix_s(g.host_time);
        extra[col::SESSION] = f64::from(g.session);
        extra[col::GAP] = code;
        extra[col::MISSING] = missing.unwrap_or(f64::NAN);
        let nan = f64::NAN;
        self.write_row(&[t_s, nan, nan, nan, nan, nan], nan, &extra)?;
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
