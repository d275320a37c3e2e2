//! One port's side of the I/O thread ([`super::hub`]): owns the port, decodes, tracks sequence
//! and time, runs commands with tags, timeouts and retries, and reconnects. It never blocks:
//! the hub reads it when its descriptor has bytes and calls it back for its deadlines.

use std::io::Write;
use std::os::fd::AsRawFd;
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

/// The I/O thread's ends of one handle's channels.
pub(super) struct Ends {
    pub events: mpsc::SyncSender<Event>,
    pub control: mpsc::Receiver<Control>,
    /// Dropped when the port is closed.
    pub closed: mpsc::Sender<()>,
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
    /// `None` only while it is feeding (it calls back into this `Io`).
    decoder: Option<FastDecoder>,
    /// When the next reconnection attempt is due, while the port is away.
    retry_at: Instant,
    /// Dropped with this `Io`, when the port is closed: [`super::Device`] waits for it.
    _closed: mpsc::Sender<()>,
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
        ends: Ends,
    ) -> Self {
        let Ends {
            events,
            control,
            closed,
        } = ends;
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
            decoder: Some(FastDecoder::new()),
            retry_at: Instant::now(),
            _closed: closed,
        };
        // A lone delimiter ends whatever the device's receiver holds, so our first request is clean.
        io.write(&[0]);
        io
    }

    /// The port's descriptor while it is open, with the count of opens (a reopened port may
    /// get the number of the descriptor it had).
    pub(super) fn fd(&self) -> Option<(std::os::fd::RawFd, u64)> {
        let opens = self.shared.counters.reconnects.load(Ordering::Relaxed);
        self.link.as_ref().map(|l| (l.as_raw_fd(), opens))
    }

    /// A command waits for its reply: the port's bytes should be read as they come.
    pub(super) fn waiting(&self) -> bool {
        !self.inflight.is_empty()
    }

    pub(super) fn streaming(&self) -> bool {
        self.streaming && self.link.is_some()
    }

    /// The earliest instant this port needs the thread: a command's deadline, or the next
    /// reconnection attempt.
    pub(super) fn due(&self) -> Option<Instant> {
        let deadline = self.inflight.iter().map(|f| f.deadline).min();
        let retry = self.link.is_none().then_some(self.retry_at);
        deadline.into_iter().chain(retry).min()
    }

    /// Commands from the handle, a reconnection attempt if one is due, expired deadlines;
    /// `false` once this port is done (closed by its handle, or given up).
    pub(super) fn service(&mut self) -> bool {
        self.poll_control();
        if !self.shutdown && self.link.is_none() && Instant::now() >= self.retry_at {
            self.reconnect();
        }
        self.check_deadlines();
        !self.shutdown
    }

    /// Read what the port holds (the hub saw it readable, so this does not block) and handle
    /// every completed frame, stamped with the time of this read.
    pub(super) fn read_ready(&mut self, buf: &mut [u8]) {
        let Some((fd, _)) = self.fd() else {
            return;
        };
        // SAFETY: `fd` is this port's open descriptor and `buf` is writable for its length.
        let n = unsafe { libc::read(fd, buf.as_mut_ptr().cast(), buf.len()) };
        let now = SystemTime::now();
        match n {
            0 => self.lost(),
            n if n > 0 => {
                let n = n as usize;
                add(&self.shared.counters.bytes, n as u64);
                if let Some(mut decoder) = self.decoder.take() {
                    decoder.feed(&buf[..n], |j| self.on_frame(j, now));
                    self.decoder = Some(decoder);
                }
            }
            _ if is_transient(&std::io::Error::last_os_error()) => {}
            _ => self.lost(),
        }
    }

    /// Leave the device quiet (best effort) as the handle closes.
    pub(super) fn close(mut self) {
        if self.link.is_some() && self.streaming {
            let _ = self.send_raw(Command::Stop, 0);
        }
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
        // The first attempt after a pause: a device that vanishes takes a moment to come back.
        self.retry_at = Instant::now() + RETRY_EVERY;
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

    /// One reconnection attempt; gives up (the stream ends) after `reconnect_for`.
    fn reconnect(&mut self) {
        let since = self.lost_since.map_or_else(Instant::now, |(i, _)| i);
        if !self.opts.reconnect || since.elapsed() > self.opts.reconnect_for {
            self.shared.gone.store(true, Ordering::Relaxed);
            self.shutdown = true;
            return;
        }
        self.retry_at = Instant::now() + RETRY_EVERY;
        let Ok(path) = self.spec.resolve() else {
            return;
        };
        let Ok(tty) = super::port::open_path(&path) else {
            return;
        };
        self.path = path;
        self.link = Some(tty);
        if let Some(d) = self.decoder.as_mut() {
            d.reset();
        }
        self.track.new_session();
        self.damaged = false;
        add(&self.shared.counters.reconnects, 1);
        self.shared.connected.store(true, Ordering::Relaxed);
        self.write(&[0]);
        self.submit(Command::GetInfo, None);
        if self.streaming {
            self.submit(Command::Start, None);
        }
    }
}

/// Pause between reconnection attempts.
const RETRY_EVERY: Duration = Duration::from_millis(100);

fn is_transient(e: &std::io::Error) -> bool {
    matches!(
        e.kind(),
        std::io::ErrorKind::TimedOut
            | std::io::ErrorKind::WouldBlock
            | std::io::ErrorKind::Interrupted
    )
}
