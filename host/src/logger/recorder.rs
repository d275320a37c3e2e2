//! One sensor's recording CSV (and its share of the MCAP file), fed by the driver's events.

use std::fs::File;
use std::io::{Read as _, Seek as _, Write as _};
use std::path::{Path, PathBuf};
use std::time::{Instant, SystemTime};

use protocol::Info;

use super::cdr::CdrWriter;
use super::rows::{decimals_for, RowWriter};
use super::{
    clock_key, gap_code, metadata, unix_s, FileError, Setup, SharedMcap, EXTRA_COLUMNS,
    FLUSH_EVERY, PENDING,
};
use crate::clock::DeviceClock;
use crate::device::{Event, Frame, Gap, GapKind, Scale};

/// Writes one sensor's CSV. Times: `t_s` is the device's stamp mapped onto the host time base
/// by the device clock's running fit ([`DeviceClock`]): no host jitter, no drift between
/// sensors, and one origin (`start`) for every sensor of a run. The first frames of each
/// session are held back until the session's offset is settled, then written; `t_s` never
/// decreases.
pub struct Recorder {
    path: PathBuf,
    csv: RowWriter,
    /// The CSV is a file whose clock metadata can be filled in at the end.
    patchable: bool,
    scale: Scale,
    temp_sensor: Option<sim::frontend::TempSensor>,
    rate_hz: f64,
    start: SystemTime,
    clock: DeviceClock,
    held: Vec<Frame>,
    /// With `Setup::device_clock`: rows are timed by the device's stamps, and this is the first
    /// frame's (device time, host time) that places them.
    device_clock: bool,
    device_origin: Option<(f64, f64)>,
    last_t_s: f64,
    last_flush: Instant,
    mcap: Option<SharedMcap>,
    cdr: CdrWriter,
    /// The frame being written, per sample, in the arrays of [`super::cdr::SAMPLE_SCHEMA`]: `t_s`,
    /// `t_device_s`, the three volts and the three loads.
    columns: [Vec<f64>; 8],
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

/// Times are written to the µs: the device stamps its frames in µs, and the time base is good
/// to a few hundred (docs/hand.md).
const TIME_DECIMALS: Option<u8> = Some(6);

/// Decimals of each column in row order (the required six, `temp_C` if there is a sensor,
/// [`EXTRA_COLUMNS`]): the times to the µs; the ADC's outputs, the loads and the temperature
/// to a tenth of what one code of the ADC moves them by (the finest channel's, for a load),
/// which tells every code from its neighbours; whole numbers as they are.
fn decimals(scale: &Scale, temp_sensor: Option<sim::frontend::TempSensor>) -> Vec<Option<u8>> {
    let volts = scale.volts_per_code.map(decimals_for);
    // The least a load moves by: one code of the channel that weighs least in its row.
    let loads = scale.calibration.map(|row| {
        let steps = row
            .iter()
            .zip(scale.volts_per_code)
            .map(|(c, v)| (c * v).abs());
        decimals_for(steps.filter(|s| *s > 0.0).fold(f64::INFINITY, f64::min))
    });
    let mut d = vec![TIME_DECIMALS, None, None, volts[0], volts[1], volts[2]];
    if let Some(t) = temp_sensor {
        d.push(decimals_for(
            scale.temp_volts_per_code / t.slope_v_per_c.abs(),
        ));
    }
    let mut extra = [None; EXTRA_COLUMNS.len()];
    extra[col::T_DEVICE] = TIME_DECIMALS;
    extra[col::T_HOST] = TIME_DECIMALS;
    extra[col::LOADS..col::LOADS + 3].copy_from_slice(&loads);
    d.extend(extra);
    d
}

impl Recorder {
    pub fn create(
        path: &Path,
        info: &Info,
        setup: &Setup,
        start: SystemTime,
    ) -> Result<Self, FileError> {
        let file = File::create(path).map_err(|e| FileError::write(path, e))?;
        let mut r = Self::create_on(Box::new(file), path, info, setup, start)?;
        r.patchable = true;
        Ok(r)
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
        let mut csv = RowWriter::new(out, &meta, with_temp, &EXTRA_COLUMNS)
            .map_err(|e| FileError::write(path, e))?;
        csv.flush().map_err(|e| FileError::write(path, e))?;
        let scale = Scale::from_info(info);
        csv.set_decimals(&decimals(&scale, setup.temp_sensor));
        Ok(Self {
            path: path.to_path_buf(),
            csv,
            patchable: false,
            scale,
            temp_sensor: setup.temp_sensor,
            rate_hz: f64::from(info.sample_rate_hz.max(1)),
            start,
            clock: DeviceClock::new(),
            held: Vec::new(),
            device_clock: setup.device_clock,
            device_origin: None,
            // The first sample may precede the origin (replay puts it at the first frame's
            // receipt, after the sample was taken): t_s is then slightly negative, not clamped.
            last_t_s: f64::NEG_INFINITY,
            last_flush: Instant::now(),
            mcap: None,
            cdr: CdrWriter::default(),
            columns: Default::default(),
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

    /// This device's clock against the host's.
    pub fn clock(&self) -> &DeviceClock {
        &self.clock
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
                self.csv
                    .set_decimals(&decimals(&self.scale, self.temp_sensor));
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
            .write_row(required, temp_c, extra)
            .map_err(|e| FileError::write(&self.path, e))
    }

    fn on_frame(&mut self, f: &Frame) -> Result<(), FileError> {
        // Held frames of an unsettled session are written with what is known before the next
        // session moves the clock's axis.
        if self.held.first().is_some_and(|h| h.session != f.session) {
            self.release()?;
        }
        let t_dev0_s = f.t_device_us as f64 * 1e-6;
        let host_s = self.host_s(f.host_time);
        self.clock.observe(f.session, t_dev0_s, host_s);
        if !self.clock.settled() {
            self.held.push(f.clone());
            return Ok(());
        }
        self.release()?;
        self.write_frame(f)?;
        self.maybe_flush()
    }

    /// Write the frames held while their session settled.
    fn release(&mut self) -> Result<(), FileError> {
        for f in std::mem::take(&mut self.held) {
            self.write_frame(&f)?;
        }
        Ok(())
    }

    /// The frame's rows, its raw bytes and its samples to the files, on the time base.
    fn write_frame(&mut self, f: &Frame) -> Result<(), FileError> {
        let t_dev0_s = f.t_device_us as f64 * 1e-6;
        let host_s = self.host_s(f.host_time);
        let t_host = unix_s(f.host_time);
        let start = unix_s(self.start);
        let origin = *self.device_origin.get_or_insert((t_dev0_s, host_s));
        let device_clock = self.device_clock;
        let base = |c: &DeviceClock, t_dev: f64| {
            if device_clock {
                origin.1 + (t_dev - origin.0)
            } else {
                c.host_s(t_dev).unwrap_or(host_s)
            }
        };
        if let Some((m, ch)) = &self.mcap {
            let t = ns(start + base(&self.clock, t_dev0_s));
            m.borrow_mut().write(ch.raw, t, ns(t_host), &f.raw)?;
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
        self.columns.iter_mut().for_each(Vec::clear);
        for (k, s) in f.frame.samples().iter().enumerate() {
            let t_dev_s = t_dev0_s + k as f64 / self.rate_hz;
            let t_s = base(&self.clock, t_dev_s).max(self.last_t_s);
            self.last_t_s = t_s;
            let v = self.scale.adc_volts(s);
            let l = self.scale.loads(s);
            extra[col::T_DEVICE] = t_dev_s;
            extra[col::LOADS..col::LOADS + 3].copy_from_slice(&l);
            self.write_row(&[t_s, f64::NAN, f64::NAN, v[0], v[1], v[2]], temp_c, &extra)?;
            self.rows += 1;
            let values = [t_s, t_dev_s, v[0], v[1], v[2], l[0], l[1], l[2]];
            for (c, x) in self.columns.iter_mut().zip(values) {
                c.push(x);
            }
        }
        self.write_samples(f, t_host)
    }

    /// The frame's samples as one MCAP message (schema [`super::cdr::SAMPLE_SCHEMA`]), logged at
    /// its first sample's time.
    fn write_samples(&mut self, f: &Frame, t_host: f64) -> Result<(), FileError> {
        let (Some((m, ch)), Some(t_s)) = (&self.mcap, self.columns[0].first()) else {
            return Ok(());
        };
        let log = ns(unix_s(self.start) + t_s);
        self.cdr
            .begin()
            .f64(t_host)
            .u32(f.seq)
            .u32(f.session)
            .i32(f.frame.temp)
            .u8(f.frame.status.saturated);
        for c in &self.columns {
            self.cdr.f64s(c);
        }
        m.borrow_mut()
            .write(ch.sample, log, ns(t_host), &self.cdr.buf)
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
        self.release()?;
        // On the device's clock a gap has no device stamp: it is marked where the rows stopped.
        let t_s = if self.device_clock && self.last_t_s.is_finite() {
            self.last_t_s
        } else {
            self.host_s(g.host_time).max(self.last_t_s)
        };
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
            let missing = missing.map_or(-1, |m| m as i64);
            self.cdr
                .begin()
                .f64(t_s)
                .string(kind)
                .i64(missing)
                .u32(g.session);
            let t = ns(unix_s(self.start) + t_s);
            m.borrow_mut()
                .write(ch.gap, t, ns(unix_s(g.host_time)), &self.cdr.buf)?;
        }
        // A gap is exactly what a later reader must not miss: write it out now.
        self.flush()
    }

    /// Write the buffered rows out if [`FLUSH_EVERY`] has passed; the shared MCAP file closes
    /// its chunk on its own schedule (one chunk per interval for all sensors together).
    pub fn maybe_flush(&mut self) -> Result<(), FileError> {
        if self.last_flush.elapsed() < FLUSH_EVERY {
            return Ok(());
        }
        self.last_flush = Instant::now();
        self.csv
            .flush()
            .map_err(|e| FileError::write(&self.path, e))?;
        if let Some((m, _)) = &self.mcap {
            m.borrow_mut().flush_due()?;
        }
        Ok(())
    }

    /// Write everything out, frames held while their session settled included.
    pub fn flush(&mut self) -> Result<(), FileError> {
        self.release()?;
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

impl Recorder {
    /// The end of the run: flush, and fill in the clock's metadata (the estimate as it stands
    /// now) in the CSV header and as an MCAP metadata record `clock <label>` (with the time
    /// base the rows are on, which the CSV's header already gives).
    pub fn finish(&mut self, label: &str) -> Result<(), FileError> {
        self.flush()?;
        let pairs = clock_key::pairs(&self.clock);
        if self.patchable {
            patch_header(&self.path, &pairs).map_err(|e| FileError::write(&self.path, e))?;
        }
        if let Some((m, _)) = &self.mcap {
            let record = clock_key::record(&self.clock, self.device_clock);
            m.borrow_mut()
                .metadata(&format!("clock {label}"), &record)?;
        }
        Ok(())
    }
}

/// Overwrite the [`PENDING`] values of `pairs`' keys in the metadata at the head of `path`,
/// within their padding (a value too long for it is left pending rather than break the file).
fn patch_header(path: &Path, pairs: &[(String, String)]) -> std::io::Result<()> {
    let mut f = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(path)?;
    let mut head = vec![0u8; 16 * 1024];
    let n = f.read(&mut head)?;
    let head = String::from_utf8_lossy(&head[..n]).into_owned();
    for (k, v) in pairs {
        let key = format!("# {k} = ");
        let Some(at) = head.find(&key) else {
            continue;
        };
        if v.len() > PENDING.len() {
            continue;
        }
        f.seek(std::io::SeekFrom::Start((at + key.len()) as u64))?;
        f.write_all(format!("{v:<width$}", width = PENDING.len()).as_bytes())?;
    }
    f.flush()
}
