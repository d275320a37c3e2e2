//! A sensor emulator on a pseudo-terminal, for host tests until the HIL work runs the real
//! firmware: it streams sample frames of a deterministic signal (so a test knows the truth of
//! every sample by its sequence number), answers every command of `protocol/SPEC.md` with an
//! ack or a nack, and can be killed, cut mid-frame and restarted on the same stable path, as a
//! USB-serial device node disappears and reappears.
//!
//! The device clock runs from a fixed `epoch`: frame `seq` is due `seq · batch / rate` seconds
//! after it, whether or not the emulator is running, so a restarted emulator continues the
//! sequence and the frames of an outage are genuinely missing, as with a device that kept
//! running while its cable was out. [`Pace::FreeRun`] instead streams a fixed number of frames
//! as fast as the pty takes them (device time still follows the sequence), for studies that
//! need a million frames in less than an hour.
//!
//! [`EmuConfig::clock_ppm`] makes the device's crystal run fast or slow (frames come due by the
//! device's clock, so a fast device sends more of them per true second, each stamped with its
//! own time), and [`EmuConfig::jitter`] holds every sample frame back by a draw of a one-sided
//! link delay: the truth of both is known, so the host's clock estimate can be checked.
//!
//! With [`EmuConfig::faults`] the device's output passes `sim::link::FaultyLink` on its way to
//! the pty, so the host driver reads a damaged stream, and [`EmuStats::injected`] holds the
//! link's exact account of what it did.

use std::collections::VecDeque;
use std::fs::File;
use std::io::{self, Read, Write};
use std::ops::Range;
use std::os::fd::{AsRawFd, OwnedFd};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant, SystemTime};

use protocol::{
    opcode, Accumulator, Command, FilterConfig, Info, Message, NackCode, NullState, Outcome, Reply,
    Request, Sample, SampleFrame, Status,
};
use sim::clock::LinkJitter;
use sim::link::{FaultRates, FaultyLink, Injected};

use crate::pty::relink;

/// How the emulator paces its frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pace {
    /// Frame `seq` is due `seq · batch / rate` s after the epoch, as on a real device.
    RealTime,
    /// Frames 0..`frames` as fast as the pty takes them from the start command on, then
    /// silence (commands are still answered).
    FreeRun { frames: u64 },
}

/// Damage done to the device's output on its way to the pty.
#[derive(Debug, Clone)]
pub struct EmuFaults {
    pub rates: FaultRates,
    pub seed: u64,
    /// Sample frames with these sequence numbers go through the link at `rates`; the others
    /// (and everything after them) pass it clean, so losses at both ends show by sequence.
    /// Everything before the first sample frame bypasses the link: the handshake stays intact.
    pub frames: Range<u64>,
}

/// The emulated device's configuration. The analog values are the emulator's own test values
/// (not hardware parameters): they only need to be self-consistent with its info frame.
#[derive(Debug, Clone)]
pub struct EmuConfig {
    /// The stable path (a symlink re-pointed to each new pty).
    pub link: PathBuf,
    pub rate_hz: u32,
    pub batch: u8,
    /// Origin of the device clock; frame sequence and time are derived from it.
    pub epoch: SystemTime,
    /// Stream without waiting for a start command.
    pub autostart: bool,
    pub chip_serial: u32,
    /// Write half of a frame, then stop, after this long.
    pub cut_mid_frame_after: Option<Duration>,
    pub pace: Pace,
    pub faults: Option<EmuFaults>,
    /// The device crystal's error, ppm (positive: its clock runs fast against true time).
    pub clock_ppm: f64,
    /// Each sample frame is delayed by a draw of this (seeded) delay before the pty sees it.
    pub jitter: Option<(LinkJitter, u64)>,
}

impl EmuConfig {
    pub fn new(link: impl Into<PathBuf>) -> Self {
        Self {
            link: link.into(),
            rate_hz: 1000,
            batch: 10,
            epoch: SystemTime::now(),
            autostart: false,
            chip_serial: 0x7AC7_11E0,
            cut_mid_frame_after: None,
            pace: Pace::RealTime,
            faults: None,
            clock_ppm: 0.0,
            jitter: None,
        }
    }
}

/// The sample with global index `n` (frame `seq` holds `n = seq·batch + k`): three sines of
/// different frequencies and amplitudes so that channel mix-ups show.
pub fn truth_sample(n: u64, rate_hz: u32) -> Sample {
    let t = n as f64 / f64::from(rate_hz);
    let tau = std::f64::consts::TAU;
    Sample {
        ch: [
            (2.0e6 * (tau * 0.5 * t).sin()).round() as i32 + 100_000,
            (1.0e6 * (tau * 1.3 * t).sin()).round() as i32,
            (5.0e5 * (tau * 0.7 * t).cos()).round() as i32,
        ],
    }
}

/// The temperature code sent with frame `seq`.
pub fn truth_temp(seq: u32) -> i32 {
    1_000_000 + (seq % 1000) as i32
}

/// Device time of frame `seq` (µs since the epoch, wrapping like the real u32 counter).
pub fn frame_time_us(seq: u64, batch: u8, rate_hz: u32) -> u32 {
    (seq * u64::from(batch) * 1_000_000 / u64::from(rate_hz)) as u32
}

/// The complete frame `seq` as the emulator sends it (status aside).
pub fn truth_frame(seq: u32, batch: u8, rate_hz: u32, status: Status) -> SampleFrame {
    let mut f = SampleFrame::new(
        seq,
        frame_time_us(u64::from(seq), batch, rate_hz),
        status,
        truth_temp(seq),
    );
    for k in 0..u64::from(batch) {
        let _ = f.push(truth_sample(u64::from(seq) * u64::from(batch) + k, rate_hz));
    }
    f
}

/// What the emulator did, for tests.
#[derive(Debug, Default)]
pub struct EmuStats {
    pub frames_sent: AtomicU64,
    /// Sequence of the last frame written completely, +1 (0: none yet).
    pub last_seq_plus_one: AtomicU64,
    /// Sequence of the first sample frame queued, +1 (0: none yet): with the last, the range a
    /// recording of the whole stream must hold.
    pub first_seq_plus_one: AtomicU64,
    /// Frames the device dropped because its transmit queue was full (real-time pace).
    pub frames_dropped: AtomicU64,
    /// Most frames that fell due in one pass of the device loop: 1 when the emulator keeps its
    /// pace, k when its thread was held off the CPU for about k frame periods.
    pub max_burst: AtomicU64,
    pub requests: AtomicU64,
    /// The fault-injecting link's account (all zero without faults).
    pub injected: Mutex<Injected>,
}

impl EmuStats {
    /// A snapshot of the link's account.
    pub fn injected(&self) -> Injected {
        self.injected
            .lock()
            .map_or_else(|p| *p.into_inner(), |i| *i)
    }
}

/// A running emulator.
pub struct Emulator {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<io::Result<()>>>,
    pub slave: PathBuf,
    pub stats: Arc<EmuStats>,
}

impl Emulator {
    /// Open a pty, point `cfg.link` at it and start answering.
    pub fn spawn(cfg: EmuConfig) -> io::Result<Self> {
        let (master, slave_fd, slave) = open_pty()?;
        relink(&cfg.link, &slave)?;
        let stop = Arc::new(AtomicBool::new(false));
        let stats = Arc::new(EmuStats::default());
        let (s2, st2) = (stop.clone(), stats.clone());
        let thread = std::thread::Builder::new()
            .name("tactile-emu".into())
            .spawn(move || {
                let _keep_slave_open = slave_fd;
                Device::new(cfg, File::from(master), st2).run(&s2)
            })?;
        Ok(Self {
            stop,
            thread: Some(thread),
            slave,
            stats,
        })
    }

    /// Stop abruptly and close the pty (the host sees the device vanish).
    pub fn kill(mut self) {
        self.halt();
    }

    /// Wait until the emulator stops by itself (after a cut mid-frame).
    pub fn wait(mut self) -> io::Result<()> {
        self.thread
            .take()
            .map_or(Ok(()), |t| t.join().unwrap_or(Ok(())))
    }

    fn halt(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        self.halt();
    }
}

/// A pty whose other end nobody answers: a serial device that is not a tactile sensor. Keep
/// both fds for as long as the device should exist.
pub fn silent_pty() -> io::Result<(OwnedFd, OwnedFd, PathBuf)> {
    open_pty()
}

/// A raw, close-on-exec pty pair: the same one the HIL tests use.
fn open_pty() -> io::Result<(OwnedFd, OwnedFd, PathBuf)> {
    let pty = crate::pty::Pty::open()?;
    Ok((pty.master, pty.slave, pty.path))
}

/// The info frame the emulator sends for `cfg` (at power-up, before any command).
pub fn info_for(cfg: &EmuConfig) -> Info {
    Info {
        protocol_version: protocol::PROTOCOL_VERSION,
        fw_version: [0, 1, 0],
        chip_serial: cfg.chip_serial,
        sample_rate_hz: cfg.rate_hz,
        batch: cfg.batch,
        pga_gain: [1, 1, 1, 1],
        vref_mv: 1200,
        amp_gain: [3000.0, 1000.0, 1000.0],
        excitation_v: 3.3,
        filter: FilterConfig::NONE,
        calibration: [[100.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]],
        dac_codes: [2048; 4],
        tare: [0; 3],
        drift: [0; 3],
        null_state: NullState::Off,
        drift_tracking: false,
        streaming: cfg.autostart,
        config_epoch: 0,
    }
}

/// Largest backlog of unsent bytes before the emulated device drops whole frames, like a
/// firmware TX queue that the link cannot drain.
const TX_QUEUE_BYTES: usize = 16 * 1024;

/// In [`Pace::FreeRun`], new frames are made while fewer bytes than this wait to be written.
const FREE_RUN_QUEUE_BYTES: usize = 16 * 1024;

struct Device {
    cfg: EmuConfig,
    port: File,
    stats: Arc<EmuStats>,
    info: Info,
    streaming: bool,
    next_seq: Option<u64>,
    dropped: u16,
    tx: Vec<u8>,
    acc: Accumulator,
    /// The fault-injecting link, from the first sample frame on.
    link: Option<FaultyLink>,
    /// Bytes written to the pty so far.
    written: u64,
    /// Stalls the link asked for: (after this many bytes written, for this long).
    stalls: VecDeque<(u64, Duration)>,
    quiet_until: Option<Instant>,
    /// Sample frames on their way through the jittered link: (when the pty gets it, bytes).
    in_flight: VecDeque<(SystemTime, Vec<u8>)>,
    jitter_rng: rand_chacha::ChaCha8Rng,
}

impl Device {
    fn new(cfg: EmuConfig, port: File, stats: Arc<EmuStats>) -> Self {
        let info = info_for(&cfg);
        let cfg_seed = cfg.jitter.map_or(0, |(_, seed)| seed);
        let streaming = cfg.autostart;
        Self {
            cfg,
            port,
            stats,
            info,
            streaming,
            next_seq: None,
            dropped: 0,
            tx: Vec::new(),
            acc: Accumulator::new(),
            link: None,
            written: 0,
            stalls: VecDeque::new(),
            quiet_until: None,
            in_flight: VecDeque::new(),
            jitter_rng: sim::clock::rng(cfg_seed),
        }
    }

    fn run(mut self, stop: &AtomicBool) -> io::Result<()> {
        let started = Instant::now();
        self.queue(&[0]);
        let mut buf = [0u8; 1024];
        while !stop.load(Ordering::Relaxed) {
            match self.port.read(&mut buf) {
                Ok(n) => self.on_bytes(&buf[..n]),
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {}
                // EIO: no slave open right now; keep the clock running.
                Err(_) => {}
            }
            if let Some(after) = self.cfg.cut_mid_frame_after {
                if started.elapsed() >= after {
                    return self.cut_mid_frame();
                }
            }
            self.produce();
            self.arrive();
            self.drain();
            self.wait();
        }
        Ok(())
    }

    /// Real time: a 2 ms tick. Free run: until the pty takes more (or 1 ms).
    fn wait(&self) {
        let free_run = matches!(self.cfg.pace, Pace::FreeRun { .. });
        if !free_run {
            std::thread::sleep(Duration::from_millis(2));
        } else if self.tx.is_empty() || self.quiet_until.is_some() {
            std::thread::sleep(Duration::from_micros(200));
        } else {
            let mut fd = libc::pollfd {
                fd: self.port.as_raw_fd(),
                events: libc::POLLOUT,
                revents: 0,
            };
            // SAFETY: one valid pollfd, its count, a timeout in ms.
            unsafe { libc::poll(&mut fd, 1, 1) };
        }
    }

    /// Write every complete queued byte, then half of one more frame, and stop.
    fn cut_mid_frame(&mut self) -> io::Result<()> {
        while !self.tx.is_empty() {
            self.drain();
            std::thread::sleep(Duration::from_millis(1));
        }
        let seq = self.due_seq();
        let f = truth_frame(seq as u32, self.cfg.batch, self.cfg.rate_hz, self.status());
        let wire = protocol::encode_vec(&Message::Sample(f)).map_err(io::Error::other)?;
        self.port.write_all(&wire[..wire.len() / 2])
    }

    /// Frames due by now: the device's clock reads `(1 + ppm·1e-6)·t` at true time `t`.
    fn due_seq(&self) -> u64 {
        let elapsed = SystemTime::now()
            .duration_since(self.cfg.epoch)
            .unwrap_or_default();
        let device_s = elapsed.as_secs_f64() * (1.0 + self.cfg.clock_ppm * 1e-6);
        (device_s / self.frame_s()) as u64
    }

    fn frame_s(&self) -> f64 {
        f64::from(self.cfg.batch) / f64::from(self.cfg.rate_hz)
    }

    /// Frames whose link delay has passed go to the pty, in order (a serial link is FIFO).
    fn arrive(&mut self) {
        let now = SystemTime::now();
        while self.in_flight.front().is_some_and(|(at, _)| *at <= now) {
            if let Some((_, bytes)) = self.in_flight.pop_front() {
                self.queue(&bytes);
            }
        }
    }

    fn status(&self) -> Status {
        Status {
            config_epoch: self.info.config_epoch,
            dropped: self.dropped,
            ..Status::default()
        }
    }

    fn produce(&mut self) {
        if let Pace::FreeRun { frames } = self.cfg.pace {
            let mut next = self.next_seq.unwrap_or(0);
            while self.streaming && next < frames && self.tx.len() < FREE_RUN_QUEUE_BYTES {
                self.send_frame(next);
                next += 1;
            }
            self.next_seq = Some(next);
            return;
        }
        let due = self.due_seq();
        let mut next = self.next_seq.unwrap_or(due);
        if !self.streaming {
            self.next_seq = Some(due);
            return;
        }
        self.stats
            .max_burst
            .fetch_max(due.saturating_sub(next), Ordering::Relaxed);
        while next < due {
            if self.tx.len() > TX_QUEUE_BYTES {
                self.dropped = self.dropped.saturating_add(1);
                self.stats.frames_dropped.fetch_add(1, Ordering::Relaxed);
            } else {
                self.send_frame(next);
                self.dropped = 0;
            }
            next += 1;
        }
        self.next_seq = Some(next);
    }

    /// Queue sample frame `seq`, through the faulty link if there is one.
    fn send_frame(&mut self, seq: u64) {
        if let Some(faults) = &self.cfg.faults {
            let rates = if faults.frames.contains(&seq) {
                faults.rates
            } else {
                FaultRates::NONE
            };
            let seed = faults.seed;
            self.link
                .get_or_insert_with(|| FaultyLink::new(rates, seed))
                .set_rates(rates);
        }
        let f = truth_frame(seq as u32, self.cfg.batch, self.cfg.rate_hz, self.status());
        if let Ok(w) = protocol::encode_vec(&Message::Sample(f)) {
            match self.cfg.jitter {
                Some((j, _)) if self.cfg.pace == Pace::RealTime => {
                    // Sent when the device's clock reached the frame's end, delayed by the link.
                    let device_s = (seq + 1) as f64 * self.frame_s();
                    let true_s = device_s / (1.0 + self.cfg.clock_ppm * 1e-6);
                    let at = self.cfg.epoch
                        + Duration::from_secs_f64(true_s + j.draw(&mut self.jitter_rng));
                    let at = self.in_flight.back().map_or(at, |(last, _)| at.max(*last));
                    self.in_flight.push_back((at, w));
                }
                _ => self.queue(&w),
            }
        }
        self.stats.frames_sent.fetch_add(1, Ordering::Relaxed);
        let _ = self.stats.first_seq_plus_one.compare_exchange(
            0,
            seq + 1,
            Ordering::Relaxed,
            Ordering::Relaxed,
        );
        self.stats
            .last_seq_plus_one
            .store(seq + 1, Ordering::Relaxed);
    }

    /// Write what the pty takes, up to the next stall of the link; nothing while stalled.
    fn drain(&mut self) {
        if self.quiet_until.is_some_and(|t| Instant::now() < t) {
            return;
        }
        self.quiet_until = None;
        while !self.tx.is_empty() {
            let limit = self
                .stalls
                .front()
                .map_or(self.tx.len(), |(at, _)| (at - self.written) as usize);
            if limit == 0 {
                let (_, stall) = self.stalls.pop_front().unwrap_or_default();
                self.quiet_until = Some(Instant::now() + stall);
                return;
            }
            match self.port.write(&self.tx[..limit]) {
                Ok(0) | Err(_) => return,
                Ok(n) => {
                    self.tx.drain(..n);
                    self.written += n as u64;
                }
            }
        }
    }

    fn queue(&mut self, bytes: &[u8]) {
        let Some(link) = self.link.as_mut() else {
            self.tx.extend_from_slice(bytes);
            return;
        };
        let stall = link.transmit(bytes, &mut self.tx);
        if stall > Duration::ZERO {
            self.stalls
                .push_back((self.written + self.tx.len() as u64, stall));
        }
        if let Ok(mut i) = self.stats.injected.lock() {
            *i = link.injected();
        }
    }

    fn send(&mut self, msg: &Message) {
        if let Ok(w) = protocol::encode_vec(msg) {
            self.queue(&w);
        }
    }

    fn on_bytes(&mut self, bytes: &[u8]) {
        let outcomes: Vec<Outcome> = self.acc.feed(bytes).collect();
        for o in outcomes {
            match o {
                Outcome::Message(Message::Request(r)) => self.on_request(r),
                Outcome::Malformed(protocol::Malformed::BadRequest { tag, opcode, code }) => {
                    self.send(&Message::Reply(Reply::Nack { tag, opcode, code }));
                }
                // A frame that fails its CRC is not answered (SPEC.md): the host retries.
                _ => {}
            }
        }
    }

    fn on_request(&mut self, r: Request) {
        self.stats.requests.fetch_add(1, Ordering::Relaxed);
        let op = r.command.opcode();
        let tag = r.tag;
        match self.execute(r.command) {
            Ok(()) if op == opcode::PING => {
                if let Command::Ping { nonce } = r.command {
                    self.send(&Message::Reply(Reply::Pong { tag, nonce }));
                }
            }
            Ok(()) => {
                self.send(&Message::Reply(Reply::Ack { tag, opcode: op }));
                if op == opcode::GET_INFO {
                    let info = Message::Info(self.info.clone());
                    self.send(&info);
                }
            }
            Err(code) => self.send(&Message::Reply(Reply::Nack {
                tag,
                opcode: op,
                code,
            })),
        }
    }

    /// Apply a command with the device rules of SPEC.md.
    fn execute(&mut self, c: Command) -> Result<(), NackCode> {
        let changed = match c {
            Command::Start => {
                self.streaming = true;
                false
            }
            Command::Stop => {
                self.streaming = false;
                false
            }
            Command::SetRate { hz } => {
                if ![250, 500, 1000, 2000, 4000, 8000].contains(&hz) {
                    return Err(NackCode::OutOfRange);
                }
                self.cfg.rate_hz = hz;
                self.info.sample_rate_hz = hz;
                true
            }
            Command::SetFilter(f) => {
                let alpha_ok = f.smoother_alpha > 0.0 && f.smoother_alpha <= 1.0;
                let order_ok = matches!(f.butterworth_order, 0 | 2 | 4);
                let cutoff_ok = f.butterworth_order == 0
                    || (f.cutoff_hz > 0.0 && f.cutoff_hz < 0.45 * self.cfg.rate_hz as f32);
                if !(alpha_ok && order_ok && cutoff_ok) {
                    return Err(NackCode::OutOfRange);
                }
                self.info.filter = f;
                true
            }
            Command::Tare { samples } => {
                if samples == 0 {
                    return Err(NackCode::OutOfRange);
                }
                if !self.streaming {
                    return Err(NackCode::InvalidState);
                }
                true
            }
            Command::ClearTare | Command::AutoNull => true,
            Command::GetInfo | Command::Ping { .. } => false,
            Command::SetCalibration(m) => {
                self.info.calibration = m;
                true
            }
            Command::SetDriftTracking { enabled } => {
                self.info.drift_tracking = enabled;
                true
            }
            Command::SetBatch { samples } => {
                if !(1..=16).contains(&samples) {
                    return Err(NackCode::OutOfRange);
                }
                // The frame clock is defined by the batch; keep it fixed in this emulator.
                return Err(NackCode::InvalidState);
            }
            _ => return Err(NackCode::UnknownCommand),
        };
        if changed {
            self.info.config_epoch = self.info.config_epoch.wrapping_add(1);
        }
        self.info.streaming = self.streaming;
        Ok(())
    }
}
