//! The serial driver: open a sensor by path or USB serial number, stream decoded sample frames
//! (device time unwrapped, host receive time, sequence), send commands with typed results,
//! count every kind of damage, and reconnect after an unplug with the gap marked.
//!
//! One I/O thread owns the ports opened together ([`Device::open_all`]; `hub`): it decodes with
//! [`crate::decode::FastDecoder`], sends each sensor's [`Event`]s into its bounded channel (a reader that cannot keep up loses frames *visibly*,
//! as a [`GapKind::HostQueueFull`], instead of lagging ever further behind), and carries out
//! commands sent to it with their tags, timeouts and retries.

mod convert;
mod error;
mod hub;
mod io;
mod port;
mod track;

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, SystemTime};

use protocol::{Calibration, Command, FilterConfig, Info, SampleFrame};

pub use convert::Scale;
pub use error::DeviceError;
pub use port::{list_ports, open_path, PortEntry, PortSpec, BAUD};
pub use track::{Step, Tracker};

/// How the driver behaves.
#[derive(Debug, Clone)]
pub struct OpenOptions {
    /// Reopen the port after the device disappears (unplug, emulator restart).
    pub reconnect: bool,
    /// Give up (the stream ends with [`DeviceError::Gone`]) after this long without a device.
    pub reconnect_for: Duration,
    /// How long one attempt of a command waits for its reply.
    pub command_timeout: Duration,
    /// Further attempts, with the same tag, after a timeout.
    pub retries: u32,
    /// Events buffered between the I/O thread and the reader.
    pub queue: usize,
    /// Mean pause of the I/O thread while streaming, so that one wake reads several frames
    /// of every port (zero: read every frame as it comes). See [`OpenOptions::catch`].
    pub coalesce: Duration,
    /// After each pause and the read of every port, how long the I/O thread reads each frame
    /// the moment it arrives: those reads are the ones the clock fit ([`crate::clock`]) is
    /// made of, since a frame read after a pause carries the rest of the pause as delay.
    pub catch: Duration,
}

impl Default for OpenOptions {
    fn default() -> Self {
        Self {
            reconnect: true,
            reconnect_for: Duration::from_secs(30),
            command_timeout: Duration::from_millis(300),
            retries: 3,
            queue: 16_384,
            coalesce: Duration::from_millis(10),
            catch: Duration::from_millis(5),
        }
    }
}

/// One sample frame as received.
#[derive(Debug, Clone)]
pub struct Frame {
    /// The sequence number as sent (u32, wraps).
    pub seq: u32,
    /// Device time of the first sample in µs, unwrapped within the connection session.
    pub t_device_us: u64,
    /// When the host read the bytes that completed this frame.
    pub host_time: SystemTime,
    /// Connection session: 0 for the first, +1 after every reconnection or device restart.
    pub session: u32,
    pub frame: SampleFrame,
    /// The encoded frame as it came off the wire (COBS, without the delimiter).
    pub raw: Vec<u8>,
}

/// Why the stream is not continuous at this point.
#[derive(Debug, Clone, PartialEq)]
pub enum GapKind {
    /// Frames are missing by sequence: `lost_on_link` were lost between device and host,
    /// `dropped_by_device` were dropped by the device itself (its `status.dropped`).
    Sequence {
        after_seq: u32,
        missing: u64,
        lost_on_link: u64,
        dropped_by_device: u64,
    },
    /// The port went away; nothing arrives until [`GapKind::Reconnected`].
    Disconnected,
    /// The port is back after `downtime`; `missing` frames by sequence if the device kept
    /// counting through the outage (None if it restarted).
    Reconnected {
        downtime: Duration,
        missing: Option<u64>,
    },
    /// The device's sequence went backwards: it restarted. A new session begins.
    DeviceRestart { last_seq: u32, new_seq: u32 },
    /// The reader fell behind and this many frames were discarded by the host.
    HostQueueFull { frames: u64 },
}

/// A gap in the stream, marked where it happened.
#[derive(Debug, Clone, PartialEq)]
pub struct Gap {
    pub kind: GapKind,
    pub host_time: SystemTime,
    pub session: u32,
}

/// What the stream carries.
#[derive(Debug, Clone)]
pub enum Event {
    Frame(Frame),
    Gap(Gap),
    /// A new info frame (after get info, or after a reconnection).
    Info(Info),
}

/// Running totals, shared with the I/O thread.
#[derive(Debug, Default)]
pub(crate) struct AtomicCounters {
    frames: AtomicU64,
    samples: AtomicU64,
    bytes: AtomicU64,
    crc_errors: AtomicU64,
    overflows: AtomicU64,
    malformed: AtomicU64,
    resyncs: AtomicU64,
    lost_on_link: AtomicU64,
    dropped_by_device: AtomicU64,
    duplicates: AtomicU64,
    reconnects: AtomicU64,
    host_queue_drops: AtomicU64,
}

/// A snapshot of the counters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    pub frames: u64,
    pub samples: u64,
    pub bytes: u64,
    /// Frames whose CRC did not match.
    pub crc_errors: u64,
    /// Runs of bytes longer than any frame, discarded up to the next delimiter.
    pub overflows: u64,
    /// Frames that passed the CRC but did not parse.
    pub malformed: u64,
    /// Returns to good frames after damage.
    pub resyncs: u64,
    /// Frames missing by sequence that the device did not report as dropped.
    pub lost_on_link: u64,
    /// Frames the device reported dropped (`status.dropped`).
    pub dropped_by_device: u64,
    /// Frames received twice (same sequence), discarded.
    pub duplicates: u64,
    pub reconnects: u64,
    /// Frames the host discarded because the reader fell behind.
    pub host_queue_drops: u64,
}

impl AtomicCounters {
    fn snapshot(&self) -> Counters {
        let g = |a: &AtomicU64| a.load(Ordering::Relaxed);
        Counters {
            frames: g(&self.frames),
            samples: g(&self.samples),
            bytes: g(&self.bytes),
            crc_errors: g(&self.crc_errors),
            overflows: g(&self.overflows),
            malformed: g(&self.malformed),
            resyncs: g(&self.resyncs),
            lost_on_link: g(&self.lost_on_link),
            dropped_by_device: g(&self.dropped_by_device),
            duplicates: g(&self.duplicates),
            reconnects: g(&self.reconnects),
            host_queue_drops: g(&self.host_queue_drops),
        }
    }
}

/// State the I/O thread shares with the handle.
#[derive(Debug, Default)]
pub(crate) struct Shared {
    counters: AtomicCounters,
    info: Mutex<Option<Info>>,
    connected: AtomicBool,
    gone: AtomicBool,
}

/// What a successful command returned.
#[derive(Debug, Clone, PartialEq)]
pub enum Answer {
    Ack,
    Pong { nonce: u32 },
    Info(Info),
}

pub(crate) struct Control {
    command: Command,
    reply: mpsc::Sender<Result<Answer, DeviceError>>,
}

/// An open sensor.
pub struct Device {
    spec: PortSpec,
    port: std::path::PathBuf,
    shared: Arc<Shared>,
    control: Option<mpsc::Sender<Control>>,
    events: mpsc::Receiver<Event>,
    /// Ends (disconnects) when the I/O thread has closed this sensor's port.
    closed: Option<mpsc::Receiver<()>>,
    opts: OpenOptions,
}

impl Device {
    /// Open the sensor and read its info frame. Does not start streaming.
    pub fn open(spec: &PortSpec, opts: OpenOptions) -> Result<Self, DeviceError> {
        let mut all = Self::open_all(std::slice::from_ref(spec), opts);
        all.pop().unwrap_or_else(|| {
            Err(DeviceError::Gone {
                port: spec.label().into(),
            })
        })
    }

    /// Open several sensors, served by one I/O thread (a hand: one wake reads every port), and
    /// read each one's info frame. One result per spec, in order; a sensor that fails leaves
    /// the others open.
    pub fn open_all(specs: &[PortSpec], opts: OpenOptions) -> Vec<Result<Self, DeviceError>> {
        let mut ios = Vec::new();
        let mut opened: Vec<Result<Self, DeviceError>> = Vec::new();
        for spec in specs {
            let tty = spec.resolve().and_then(|p| Ok((port::open_path(&p)?, p)));
            opened.push(tty.map(|(tty, path)| {
                let shared = Arc::new(Shared::default());
                let (ctl_tx, ctl_rx) = mpsc::channel();
                let (ev_tx, ev_rx) = mpsc::sync_channel(opts.queue.max(1));
                let (closed_tx, closed_rx) = mpsc::channel();
                ios.push(io::Io::new(
                    spec.clone(),
                    path.clone(),
                    tty,
                    opts.clone(),
                    shared.clone(),
                    io::Ends {
                        events: ev_tx,
                        control: ctl_rx,
                        closed: closed_tx,
                    },
                ));
                Self {
                    spec: spec.clone(),
                    port: path,
                    shared,
                    control: Some(ctl_tx),
                    events: ev_rx,
                    closed: Some(closed_rx),
                    opts: opts.clone(),
                }
            }));
        }
        if !ios.is_empty() {
            let spawned = hub::Hub::new(ios, opts.coalesce, opts.catch).and_then(|hub| {
                std::thread::Builder::new()
                    .name("tactile-io".into())
                    .spawn(move || hub.run())
            });
            if let Err(e) = spawned {
                return opened
                    .into_iter()
                    .map(|d| {
                        d.and_then(|d| {
                            Err(DeviceError::Io {
                                port: d.port.clone(),
                                source: std::io::Error::new(e.kind(), e.to_string()),
                            })
                        })
                    })
                    .collect();
            }
        }
        opened
            .into_iter()
            .map(|d| d.and_then(Self::handshake))
            .collect()
    }

    /// Read the info frame and check the protocol version.
    fn handshake(self) -> Result<Self, DeviceError> {
        let info = self.get_info()?;
        if info.protocol_version != protocol::PROTOCOL_VERSION {
            return Err(DeviceError::Version {
                port: self.port.clone(),
                got: info.protocol_version,
                want: protocol::PROTOCOL_VERSION,
            });
        }
        Ok(self)
    }

    pub fn spec(&self) -> &PortSpec {
        &self.spec
    }

    /// The device path in use.
    pub fn port(&self) -> &std::path::Path {
        &self.port
    }

    /// The latest info frame.
    pub fn info(&self) -> Option<Info> {
        self.shared.info.lock().ok().and_then(|i| i.clone())
    }

    pub fn counters(&self) -> Counters {
        self.shared.counters.snapshot()
    }

    pub fn is_connected(&self) -> bool {
        self.shared.connected.load(Ordering::Relaxed)
    }

    /// The channel-based stream; it ends when the device is gone for good (or closed).
    pub fn events(&self) -> &mpsc::Receiver<Event> {
        &self.events
    }

    /// A blocking iterator over events; ends when the device is gone for good.
    pub fn iter(&self) -> mpsc::Iter<'_, Event> {
        self.events.iter()
    }

    /// Why the stream ended, if it did.
    pub fn gone_error(&self) -> Option<DeviceError> {
        self.shared
            .gone
            .load(Ordering::Relaxed)
            .then(|| DeviceError::Gone {
                port: self.port.clone(),
            })
    }

    /// Send `command` and wait for its outcome (timeouts and retries as in [`OpenOptions`]).
    pub fn command(&self, command: Command) -> Result<Answer, DeviceError> {
        let gone = || DeviceError::Gone {
            port: self.port.clone(),
        };
        let (tx, rx) = mpsc::channel();
        let ctl = self.control.as_ref().ok_or_else(gone)?;
        ctl.send(Control { command, reply: tx })
            .map_err(|_| gone())?;
        let attempts = self.opts.retries + 1;
        // The I/O thread answers every request; this bound only guards against its death.
        let bound = self.opts.command_timeout * attempts + Duration::from_secs(2);
        rx.recv_timeout(bound).unwrap_or_else(|_| Err(gone()))
    }

    fn ack(&self, command: Command) -> Result<(), DeviceError> {
        self.command(command).map(|_| ())
    }

    pub fn get_info(&self) -> Result<Info, DeviceError> {
        match self.command(Command::GetInfo)? {
            Answer::Info(i) => Ok(i),
            _ => Err(DeviceError::Timeout {
                port: self.port.clone(),
                command: "get info",
                attempts: 1,
            }),
        }
    }

    pub fn start(&self) -> Result<(), DeviceError> {
        self.ack(Command::Start)
    }
    pub fn stop(&self) -> Result<(), DeviceError> {
        self.ack(Command::Stop)
    }
    pub fn set_rate(&self, hz: u32) -> Result<(), DeviceError> {
        self.ack(Command::SetRate { hz })
    }
    pub fn set_filter(&self, filter: FilterConfig) -> Result<(), DeviceError> {
        self.ack(Command::SetFilter(filter))
    }
    pub fn tare(&self, samples: u16) -> Result<(), DeviceError> {
        self.ack(Command::Tare { samples })
    }
    pub fn clear_tare(&self) -> Result<(), DeviceError> {
        self.ack(Command::ClearTare)
    }
    pub fn auto_null(&self) -> Result<(), DeviceError> {
        self.ack(Command::AutoNull)
    }
    pub fn set_calibration(&self, c: Calibration) -> Result<(), DeviceError> {
        self.ack(Command::SetCalibration(c))
    }
    pub fn set_batch(&self, samples: u8) -> Result<(), DeviceError> {
        self.ack(Command::SetBatch { samples })
    }
    pub fn set_drift_tracking(&self, enabled: bool) -> Result<(), DeviceError> {
        self.ack(Command::SetDriftTracking { enabled })
    }

    /// Round-trip time of a ping.
    pub fn ping(&self) -> Result<Duration, DeviceError> {
        let t0 = std::time::Instant::now();
        let nonce = t0.elapsed().subsec_nanos() ^ 0x5a5a_a5a5;
        match self.command(Command::Ping { nonce })? {
            Answer::Pong { nonce: n } if n == nonce => Ok(t0.elapsed()),
            _ => Err(DeviceError::Timeout {
                port: self.port.clone(),
                command: "ping",
                attempts: 1,
            }),
        }
    }

    /// Stop streaming (best effort) and close the port.
    pub fn close(mut self) {
        let _ = self.stop();
        self.shutdown();
    }

    /// Drop the command channel (the I/O thread closes the port when it sees that) and wait
    /// until the port is closed, so that it can be opened again at once.
    fn shutdown(&mut self) {
        self.control = None;
        if let Some(closed) = self.closed.take() {
            let _ = closed.recv();
        }
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        self.shutdown();
    }
}

/// The name of a command for messages.
pub(crate) fn command_name(c: &Command) -> &'static str {
    match c {
        Command::Start => "start",
        Command::Stop => "stop",
        Command::SetRate { .. } => "set rate",
        Command::SetFilter(_) => "set filter",
        Command::Tare { .. } => "tare",
        Command::ClearTare => "clear tare",
        Command::AutoNull => "auto-null",
        Command::GetInfo => "get info",
        Command::SetCalibration(_) => "set calibration",
        Command::Ping { .. } => "ping",
        Command::SetDriftTracking { .. } => "set drift tracking",
        Command::SetBatch { .. } => "set batch",
        _ => "command",
    }
}
