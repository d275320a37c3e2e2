//! The I/O thread: owns the port, decodes, tracks sequence and time, runs commands with tags,
//! timeouts and retries, and reconnects.

use std::io::{Read, Write};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant, SystemTime};

use protocol::{opcode, Command, Message, Outcome, Reply, Request, SampleFrame};
use serialport::TTYPort;

use super::track::{Step, Tracker};
use super::{
    command_name, Answer, Control, DeviceError, Event, Frame, Gap, GapKind, OpenOptions, PortSpec,
    Shared,
};
use crate::decode::{FastDecoder, Judged};

/// A request waiting for its reply.
struct Inflight {
    tag: u8,
    command: Command,
    wire: Vec<u8>,
    deadline: Instant,
    attempts: u32,
    /// `None` for the driver's own requests (the handshake after a reconnection).
    reply: Option<mpsc::Sender<Result<Answer, DeviceError>>>,
    /// A get info was acked; it completes when the info frame arrives.
    acked: bool,
}

pub(super) struct Io {
    spec: PortSpec,
    path: PathBuf,
    link: Option<TTYPort>,
    opts: OpenOptions,
    shared: Arc<Shared>,
    events: mpsc::SyncSender<Event>,
    control: mpsc::Receiver<Control>,
    inflight: Vec<Inflight>,
    next_tag: u8,
    streaming: bool,
    track: Tracker,
    /// The last sequence seen before a disconnection, to count frames lost across it.
    seq_before_outage: Option<u32>,
    lost_since: Option<(Instant, SystemTime)>,
    damaged: bool,
    queue_drops_pending: u64,
    shutdown: bool,
    /// State of the draw in [`Io::coalesce`].
    rand: u64,
}

fn add(c: &AtomicU64, n: u64) {
    c.fetch_add(n, Ordering::Relaxed);
}

impl Io {
    pub(super) fn new(
        spec: PortSpec,
        path: PathBuf,
        tty: TTYPort,
        opts: OpenOptions,
        shared: Arc<Shared>,
        events: mpsc::SyncSender<Event>,
        control: mpsc::Receiver<Control>,
    ) -> Self {
        shared.connected.store(true, Ordering::Relaxed);
        let mut io = Self {
            spec,
            path,
            link: Some(tty),
            opts,
            shared,
            events,
            control,
            inflight: Vec::new(),
            next_tag: 1,
            streaming: false,
            track: Tracker::default(),
            seq_before_outage: None,
            lost_since: None,
            damaged: false,
            queue_drops_pending: 0,
            shutdown: false,
            rand: 0x9E37_79B9_7F4A_7C15 ^ u64::from(std::process::id()),
        };
        // A lone delimiter ends whatever the device's receiver holds, so our first request is clean.
        io.write(&[0]);
        io
    }

    pub(super) fn run(mut self) {
        let mut decoder = FastDecoder::new();
        let mut buf = vec![0u8; 16 * 1024];
        while !self.shutdown {
            self.poll_control();
            if self.link.is_none() {
                if !self.reconnect(&mut decoder) {
                    break;
                }
                continue;
            }
            let read = self.link.as_mut().map(|l| l.read(&mut buf));
            match read {
                Some(Ok(0)) => self.lost(),
                Some(Ok(n)) => {
                    add(&self.shared.counters.bytes, n as u64);
                    let now = SystemTime::now();
                    decoder.feed(&buf[..n], |j| self.on_frame(j, now));
                    self.coalesce();
                }
                Some(Err(e)) if is_transient(&e) => {}
                Some(Err(_)) | None => self.lost(),
            }
            self.check_deadlines();
        }
        // Best effort: leave the device quiet when the handle is closed.
        if self.link.is_some() && self.streaming {
            let _ = self.send_raw(Command::Stop, 0);
        }
    }

    /// While streaming with no command waiting, let frames gather before the next read, so one
    /// wake takes several frames instead of one each. The pause is drawn uniformly from
    /// `0..2·coalesce`: a fixed one would lock to the frame period, and the frames read just
    /// after they arrived (the clock fit's minimum-delay points, [`crate::clock`]) would be those of one
    /// phase only; a random one reads some frame soon after its arrival in every second.
    fn coalesce(&mut self) {
        if !self.streaming || !self.inflight.is_empty() || self.opts.coalesce.is_zero() {
            return;
        }
        // xorshift64: a cheap uniform draw; no statistics hang on its quality.
        self.rand ^= self.rand << 13;
        self.rand ^= self.rand >> 7;
        self.rand ^= self.rand << 17;
        let u = (self.rand >> 11) as f64 / (1u64 << 53) as f64;
        std::thread::sleep(self.opts.coalesce.mul_f64(2.0 * u));
    }

    fn poll_control(&mut self) {
        loop {
            match self.control.try_recv() {
                Ok(c) => self.submit(c.command, Some(c.reply)),
                Err(mpsc::TryRecvError::Empty) => return,
                Err(mpsc::TryRecvError::Disconnected) => {
                    self.shutdown = true;
                    return;
                }
            }
        }
    }

    fn submit(
        &mut self,
        command: Command,
        reply: Option<mpsc::Sender<Result<Answer, DeviceError>>>,
    ) {
        if self.link.is_none() {
            if let Some(r) = reply {
                let _ = r.send(Err(DeviceError::Gone {
                    port: self.path.clone(),
                }));
            }
            return;
        }
        let tag = self.next_tag;
        self.next_tag = self.next_tag.wrapping_add(1).max(1);
        let wire = match protocol::encode_vec(&Message::Request(Request { tag, command })) {
            Ok(w) => w,
            Err(_) => return, // every request fits a frame; nothing to send otherwise
        };
        self.write(&wire);
        let deadline = Instant::now() + self.opts.command_timeout;
        self.inflight.push(Inflight {
            tag,
            command,
            wire,
            deadline,
            attempts: 1,
            reply,
            acked: false,
        });
    }

    fn send_raw(&mut self, command: Command, tag: u8) -> Option<()> {
        let wire = protocol::encode_vec(&Message::Request(Request { tag, command })).ok()?;
        self.link.as_mut()?.write_all(&wire).ok()
    }

    fn write(&mut self, bytes: &[u8]) {
        let ok = self
            .link
            .as_mut()
            .is_some_and(|l| l.write_all(bytes).and_then(|_| l.flush()).is_ok());
        if !ok && self.link.is_some() {
            self.lost();
        }
    }

    fn check_deadlines(&mut self) {
        let now = Instant::now();
        let mut resend = Vec::new();
        let mut i = 0;
        while i < self.inflight.len() {
            let f = &mut self.inflight[i];
            if f.deadline > now {
                i += 1;
                continue;
            }
            if f.attempts <= self.opts.retries {
                f.attempts += 1;
                f.deadline = now + self.opts.command_timeout;
                resend.push(f.wire.clone());
                i += 1;
            } else {
                let f = self.inflight.remove(i);
                let err = DeviceError::Timeout {
                    port: self.path.clone(),
                    command: command_name(&f.command),
                    attempts: f.attempts,
                };
                if let Some(r) = f.reply {
                    let _ = r.send(Err(err));
                }
            }
        }
        for w in resend {
            self.write(&w);
        }
    }

    fn complete(&mut self, tag: u8, result: Result<Answer, DeviceError>) {
        let Some(i) = self.inflight.iter().position(|f| f.tag == tag) else {
            return;
        };
        let f = self.inflight.remove(i);
        if result.is_ok() {
            match f.command {
                Command::Start => self.streaming = true,
                Command::Stop => self.streaming = false,
                _ => {}
            }
        }
        if let Some(r) = f.reply {
            let _ = r.send(result);
        }
    }

    fn on_frame(&mut self, j: Judged<'_>, now: SystemTime) {
        let shared = self.shared.clone();
        let c = &shared.counters;
        match j.outcome {
            Outcome::Message(msg) => {
                if std::mem::take(&mut self.damaged) {
                    add(&c.resyncs, 1);
                }
                match msg {
                    Message::Sample(f) => self.on_sample(f, j.raw, now),
                    Message::Info(info) => self.on_info(info),
                    Message::Reply(r) => self.on_reply(r),
                    Message::Request(_) => {} // our own echo on a loopback link: not for us
                }
            }
            Outcome::CrcError => {
                add(&c.crc_errors, 1);
                self.damaged = true;
            }
            Outcome::Overflow => {
                add(&c.overflows, 1);
                self.damaged = true;
            }
            Outcome::Malformed(_) => {
                add(&c.malformed, 1);
                self.damaged = true;
            }
        }
    }

    fn on_info(&mut self, info: protocol::Info) {
        if let Ok(mut slot) = self.shared.info.lock() {
            *slot = Some(info.clone());
        }
        // The info frame answers the oldest acked (or, if the ack was lost, any) get info.
        let pending = self.inflight.iter().position(|f| f.acked).or_else(|| {
            self.inflight
                .iter()
                .position(|f| matches!(f.command, Command::GetInfo))
        });
        if let Some(i) = pending {
            let tag = self.inflight[i].tag;
            self.complete(tag, Ok(Answer::Info(info.clone())));
        }
        self.emit(Event::Info(info));
    }

    fn on_reply(&mut self, r: Reply) {
        match r {
            Reply::Ack { tag, opcode: op } if op == opcode::GET_INFO => {
                if let Some(f) = self.inflight.iter_mut().find(|f| f.tag == tag) {
                    f.acked = true;
                }
            }
            Reply::Ack { tag, .. } => self.complete(tag, Ok(Answer::Ack)),
            Reply::Pong { tag, nonce } => self.complete(tag, Ok(Answer::Pong { nonce })),
            Reply::Nack { tag, code, .. } => {
                let command = self
                    .inflight
                    .iter()
                    .find(|f| f.tag == tag)
                    .map_or("command", |f| command_name(&f.command));
                let err = DeviceError::Nack {
                    port: self.path.clone(),
                    command,
                    code,
                };
                self.complete(tag, Err(err));
            }
        }
    }

    fn on_sample(&mut self, f: SampleFrame, raw: &[u8], now: SystemTime) {
        let shared = self.shared.clone();
        let c = &shared.counters;
        add(&c.dropped_by_device, u64::from(f.status.dropped));
        let Step::Keep {
            gap,
            t_device_us,
            session,
        } = self.track.step(f.seq, f.t_us, f.status.dropped)
        else {
            add(&c.duplicates, 1);
            return;
        };
        if let Some(GapKind::Sequence { lost_on_link, .. }) = &gap {
            add(&c.lost_on_link, *lost_on_link);
        }
        let mut gap = gap;
        if let Some((since, _)) = self.lost_since.take() {
            let missing = self.seq_before_outage.take().and_then(|before| {
                let d = f.seq.wrapping_sub(before);
                (d != 0 && d < 1 << 31).then(|| u64::from(d - 1))
            });
            gap = Some(GapKind::Reconnected {
                downtime: since.elapsed(),
                missing,
            });
        }
        if let Some(kind) = gap {
            self.emit(Event::Gap(Gap {
                kind,
                host_time: now,
                session,
            }));
        }
        if self.queue_drops_pending > 0 {
            // Report the loss as soon as there is room for the report; until then keep counting.
            let kind = GapKind::HostQueueFull {
                frames: self.queue_drops_pending,
            };
            if self
                .events
                .try_send(Event::Gap(Gap {
                    kind,
                    host_time: now,
                    session,
                }))
                .is_ok()
            {
                self.queue_drops_pending = 0;
            }
        }
        add(&c.frames, 1);
        add(&c.samples, f.len() as u64);
        let ev = Event::Frame(Frame {
            seq: f.seq,
            t_device_us,
            host_time: now,
            session,
            frame: f,
            raw: raw.to_vec(),
        });
        if let Err(mpsc::TrySendError::Full(_)) = self.events.try_send(ev) {
            add(&self.shared.counters.host_queue_drops, 1);
            self.queue_drops_pending += 1;
        }
    }

    fn emit(&mut self, ev: Event) {
        if self.events.try_send(ev).is_err() {
            add(&self.shared.counters.host_queue_drops, 1);
        }
    }

    /// The port failed: mark the gap, fail waiting commands, and start reconnecting.
    fn lost(&mut self) {
        self.link = None;
        self.shared.connected.store(false, Ordering::Relaxed);
        let now = SystemTime::now();
        self.lost_since = Some((Instant::now(), now));
        self.seq_before_outage = self.track.last_seq().or(self.seq_before_outage);
        self.emit(Event::Gap(Gap {
            kind: GapKind::Disconnected,
            host_time: now,
            session: self.track.session(),
        }));
        for f in self.inflight.drain(..) {
            if let Some(r) = f.reply {
                let _ = r.send(Err(DeviceError::Gone {
                    port: self.path.clone(),
                }));
            }
        }
    }

    /// One reconnection attempt; `false` when it is time to give up.
    fn reconnect(&mut self, decoder: &mut FastDecoder) -> bool {
        let since = self.lost_since.map_or_else(Instant::now, |(i, _)| i);
        if !self.opts.reconnect || since.elapsed() > self.opts.reconnect_for {
            self.shared.gone.store(true, Ordering::Relaxed);
            return false;
        }
        std::thread::sleep(Duration::from_millis(100));
        let Ok(path) = self.spec.resolve() else {
            return true;
        };
        let Ok(tty) = super::port::open_path(&path) else {
            return true;
        };
        self.path = path;
        self.link = Some(tty);
        decoder.reset();
        self.track.new_session();
        self.damaged = false;
        add(&self.shared.counters.reconnects, 1);
        self.shared.connected.store(true, Ordering::Relaxed);
        self.write(&[0]);
        self.submit(Command::GetInfo, None);
        if self.streaming {
            self.submit(Command::Start, None);
        }
        true
    }
}

fn is_transient(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        std::io::ErrorKind::TimedOut
            | std::io::ErrorKind::WouldBlock
            | std::io::ErrorKind::Interrupted
    )
}
