//! The one I/O thread of every port opened together ([`super::Device::open_all`]): it waits on
//! all their descriptors at once (`epoll`: registered once, so a wake costs what is ready, not
//! a scan of every tty), reads each as it becomes readable, and serves each port's commands,
//! deadlines and reconnections ([`Io`]).
//!
//! Wakes, not bytes, are what a hand of sensors costs: sixteen threads reading every frame as
//! it came woke about two thousand times a second. While every port streams and no command is
//! waiting, the thread works in rounds instead: a pause drawn from `U(0, 2·coalesce)`, one read
//! of every port that has bytes, then a catch window of `catch` in which each frame is read the
//! moment it arrives. The reads after a pause carry the rest of the pause as delay; the reads in
//! the catch window carry none, and they are what the clock fit's lower envelope rests on
//! ([`crate::clock`]): about a third of each port's frames fall in a window at the defaults
//! (5 ms of every 15), so every port is read on arrival some thirty times a second, for about
//! nine wakes a round in all.
//! The pause is random so that the windows do not lock onto the frame period (a fixed one
//! would catch the frames of one phase only); the rounds depend on no port's frames, which is
//! what lets `hil::hand_clock` simulate each finger on its own.

use std::os::fd::{AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::time::{Duration, Instant};

use super::io::Io;
use super::port::READ_POLL;

pub(super) struct Hub {
    /// The ports by a fixed index (the epoll events name it); `None` once closed.
    ios: Vec<Option<Io>>,
    /// The descriptor (and count of opens) each port has in `epoll`.
    registered: Vec<Option<(RawFd, u64)>>,
    epoll: OwnedFd,
    events: Vec<libc::epoll_event>,
    buf: Vec<u8>,
    coalesce: Duration,
    catch: Duration,
    catch_until: Instant,
    /// State of the pause's draw.
    rand: u64,
}

impl Hub {
    pub(super) fn new(ios: Vec<Io>, coalesce: Duration, catch: Duration) -> std::io::Result<Self> {
        // SAFETY: plain syscall; the result is checked before it is owned.
        let fd = unsafe { libc::epoll_create1(libc::EPOLL_CLOEXEC) };
        if fd < 0 {
            return Err(std::io::Error::last_os_error());
        }
        // SAFETY: a fresh descriptor that nothing else owns.
        let epoll = unsafe { OwnedFd::from_raw_fd(fd) };
        let n = ios.len();
        Ok(Self {
            ios: ios.into_iter().map(Some).collect(),
            registered: vec![None; n],
            epoll,
            events: vec![libc::epoll_event { events: 0, u64: 0 }; n.max(1)],
            buf: vec![0u8; 16 * 1024],
            coalesce,
            catch,
            catch_until: Instant::now(),
            rand: 0x9E37_79B9_7F4A_7C15 ^ u64::from(std::process::id()),
        })
    }

    /// Until every port is closed by its handle or given up. A wake in a catch window that
    /// read a frame goes straight back to waiting: the ports' commands, deadlines and
    /// registrations are looked at once a round (and at every wake outside the rounds), not
    /// at each of the window's wakes.
    pub(super) fn run(mut self) {
        let mut catching = false;
        loop {
            if !catching {
                self.service();
                if self.ios.iter().all(Option::is_none) {
                    return;
                }
                self.register();
            }
            let timeout = self.wait();
            let read = self.poll_and_read(timeout);
            catching = read && Instant::now() < self.catch_until;
        }
    }

    fn live(&self) -> impl Iterator<Item = &Io> {
        self.ios.iter().flatten()
    }

    /// Each port's commands, reconnection and deadlines; a port that is done is closed.
    fn service(&mut self) {
        for slot in &mut self.ios {
            if slot.as_mut().is_some_and(|io| !io.service()) {
                if let Some(io) = slot.take() {
                    io.close();
                }
            }
        }
    }

    /// Keep `epoll` in step with the ports: a reopened port's new descriptor in, a closed
    /// one's out (closing a descriptor removes it; the delete is for a number reused).
    fn register(&mut self) {
        for (i, slot) in self.ios.iter().enumerate() {
            let now = slot.as_ref().and_then(Io::fd);
            if now == self.registered[i] {
                continue;
            }
            if let Some((old, _)) = self.registered[i] {
                self.ctl(libc::EPOLL_CTL_DEL, old, i);
            }
            self.registered[i] = now.filter(|(fd, _)| self.ctl(libc::EPOLL_CTL_ADD, *fd, i));
        }
    }

    /// One `epoll_ctl`; `false` if it failed (a port not registered is read again after its
    /// next reopen, and its silence meanwhile ends in a reconnection).
    fn ctl(&self, op: libc::c_int, fd: RawFd, index: usize) -> bool {
        let mut ev = libc::epoll_event {
            events: libc::EPOLLIN as u32,
            u64: index as u64,
        };
        // SAFETY: a valid epoll descriptor, a descriptor number, an event that outlives the call.
        unsafe { libc::epoll_ctl(self.epoll.as_raw_fd(), op, fd, &mut ev) == 0 }
    }

    /// How long to wait for bytes: in a catch window, its rest; after it, the pause (slept
    /// here), then nothing; while a command waits or nothing streams, up to [`READ_POLL`]
    /// (the handles' commands are looked at between waits). Never past a port's deadline.
    fn wait(&mut self) -> Duration {
        let rounds = !self.coalesce.is_zero()
            && !self.live().any(Io::waiting)
            && self.live().any(Io::streaming);
        let now = Instant::now();
        let timeout = if !rounds {
            READ_POLL
        } else if now < self.catch_until {
            self.catch_until - now
        } else {
            std::thread::sleep(self.pause());
            self.catch_until = Instant::now() + self.catch;
            Duration::ZERO
        };
        let due = self.live().filter_map(Io::due).min();
        due.map_or(timeout, |d| {
            timeout.min(d.saturating_duration_since(Instant::now()))
        })
    }

    /// A draw from `U(0, 2·coalesce)`.
    fn pause(&mut self) -> Duration {
        // xorshift64: a cheap uniform draw; no statistics hang on its quality.
        self.rand ^= self.rand << 13;
        self.rand ^= self.rand >> 7;
        self.rand ^= self.rand << 17;
        let u = (self.rand >> 11) as f64 / (1u64 << 53) as f64;
        self.coalesce.mul_f64(2.0 * u)
    }

    /// Wait up to `timeout` for any open port to be readable, and read each that is; `true`
    /// if one was.
    fn poll_and_read(&mut self, timeout: Duration) -> bool {
        if self.registered.iter().all(Option::is_none) {
            std::thread::sleep(timeout); // every port away: only reconnections to try
            return false;
        }
        // Whole milliseconds, rounded up: a window's last fraction is waited for, not spun on.
        let ms = timeout.as_micros().div_ceil(1000).min(i32::MAX as u128) as i32;
        // SAFETY: a valid epoll descriptor and an event array of the length given.
        let ready = unsafe {
            libc::epoll_wait(
                self.epoll.as_raw_fd(),
                self.events.as_mut_ptr(),
                self.events.len() as i32,
                ms,
            )
        };
        // Fewer than none: interrupted; the next turn looks again.
        let ready = usize::try_from(ready).unwrap_or(0);
        for k in 0..ready {
            let i = self.events[k].u64 as usize;
            // Bytes, a hang-up or an error: the read tells which (and marks a lost port).
            if let Some(io) = self.ios.get_mut(i).and_then(Option::as_mut) {
                io.read_ready(&mut self.buf);
            }
        }
        ready > 0
    }
}
