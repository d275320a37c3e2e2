//! HIL 2 survives the board dying: the firmware under QEMU streams to the host's driver and
//! recorder (the code path of `tactile log`) through a stable symlink to UART0's pty; mid-stream
//! qemu-system-arm is SIGKILLed (often mid-frame), the device node disappears, and a new QEMU
//! boots the firmware on a new pty that the symlink is re-pointed to, as udev re-points
//! `/dev/serial/by-id/...` when a board comes back. Checks: the driver reconnects by itself
//! (through the path, to the new pty) and restarts the stream; the outage is marked (a
//! disconnected row, then a reconnected row with the missing count unknown because the device
//! restarted, sessions 0 then 1); the CSV reads back with the contract's reader, one row per
//! received sample, no sample twice; every settled sample equals the stimulus's code.
//!
//! Run: `cargo test -p hil --test hil_qemu_restart -- --nocapture`.

use std::os::fd::OwnedFd;
use std::path::Path;
use std::time::{Duration, Instant, SystemTime};

use hil::check::scratch;
use hil::pty::{hold_open, relink};
use hil::qemu::{build_elf, ideal_code, Clock, QemuBoard, NULL_CODES};
use host::device::{Counters, Device, Event, Frame, GapKind, OpenOptions, PortSpec, Scale};
use host::logger::{gap_code, Recorder, Setup};
use protocol::NullState;
use sim::ads131m04::stimulus::{Stimulus, StimulusParams};

/// Settled frames wanted from each boot before moving on.
const SETTLED_FRAMES: usize = 40;

/// Start QEMU with the firmware, let it run with a reader on its pty, and point `link` at it.
fn boot(elf: &Path, link: &Path) -> (QemuBoard, OwnedFd) {
    let mut board = QemuBoard::spawn(elf, Clock::RealTime).expect("start qemu-system-arm");
    let keeper = hold_open(&board.pty).expect("open UART0's pty");
    board.resume().expect("cont");
    relink(link, &board.pty).expect("point the stable path at the new pty");
    (board, keeper)
}

/// What the host received, in order.
#[derive(Default)]
struct Log {
    frames: Vec<Frame>,
    gaps: Vec<GapKind>,
}

impl Log {
    /// Frames of `session` after its power-up null finished.
    fn settled(&self, session: u32) -> usize {
        self.frames
            .iter()
            .filter(|f| f.session == session && f.frame.status.null_state == NullState::Nulled)
            .count()
    }
}

/// Move events into the recorder and the log until `done` (or 20 s).
fn pump(dev: &Device, rec: &mut Recorder, log: &mut Log, done: impl Fn(&Log) -> bool) {
    let t0 = Instant::now();
    while !done(log) {
        assert!(
            t0.elapsed() < Duration::from_secs(20),
            "timed out: {} frames, gaps {:?}, {:?}",
            log.frames.len(),
            log.gaps,
            dev.counters()
        );
        if let Ok(ev) = dev.events().recv_timeout(Duration::from_millis(20)) {
            rec.on_event(&ev).expect("recording");
            match ev {
                Event::Frame(f) => log.frames.push(f),
                Event::Gap(g) => log.gaps.push(g.kind),
                Event::Info(_) => {}
            }
        }
    }
}

/// Every sample of a settled frame (nulled, and not the frame in which the null finished) equals
/// the trimmed stimulus's code at its conversion index (t_us counts 1000 µs conversions from
/// the board's boot). Returns the number of samples checked.
fn check_values(frames: &[Frame]) -> u64 {
    let mut trimmed = Stimulus::new(StimulusParams::QEMU_BOARD);
    trimmed.trim_codes = [NULL_CODES[0], NULL_CODES[1], NULL_CODES[2], 2048];
    let mut checked = 0;
    for w in frames.windows(2) {
        let (prev, f) = (&w[0], &w[1]);
        let settled = f.frame.status.null_state == NullState::Nulled
            && prev.frame.status.null_state == NullState::Nulled
            && prev.session == f.session;
        if !settled {
            continue;
        }
        let first = u64::from(f.frame.t_us / 1000);
        for (k, s) in f.frame.samples().iter().enumerate() {
            let v = trimmed.volts(first + k as u64);
            let ideal: [i32; 3] = core::array::from_fn(|ch| ideal_code(v[ch]));
            assert_eq!(
                s.ch, ideal,
                "session {} frame {} sample {k}",
                f.session, f.seq
            );
            checked += 1;
        }
    }
    checked
}

/// The CSV holds exactly the received samples in order, with the two gap rows between the
/// sessions, and reads back with the contract's reader.
fn check_recording(path: &Path, log: &Log, scale: &Scale) {
    let rec = recording::read(path).expect("the recording reads back with the contract's reader");
    let col = |n: &str| rec.column(n).unwrap_or_else(|| panic!("column {n}"));
    let (seq, session, gap, missing) = (col("seq"), col("session"), col("gap"), col("missing"));
    let volts = [col("fz_V"), col("mx_V"), col("my_V")];
    let mut samples = log.frames.iter().flat_map(|f| {
        f.frame
            .samples()
            .iter()
            .map(move |s| (f.session, f.seq, s.ch))
            .collect::<Vec<_>>()
    });
    let mut gaps = Vec::new();
    for i in 0..rec.channels.len() {
        if gap[i] != gap_code::NONE {
            assert!(volts[0][i].is_nan(), "row {i}: a gap row carries no value");
            gaps.push((gap[i], missing[i].is_nan(), session[i] as u32));
            continue;
        }
        let (s, q, codes) = samples.next().expect("no more rows than samples");
        assert_eq!((session[i] as u32, seq[i] as u32), (s, q), "row {i}");
        for ch in 0..3 {
            let code = (volts[ch][i] / scale.volts_per_code[ch]).round() as i32;
            assert_eq!(code, codes[ch], "row {i} channel {ch}");
        }
    }
    assert!(samples.next().is_none(), "every sample has its row");
    assert_eq!(
        gaps,
        [
            (gap_code::DISCONNECTED, true, 0),
            (gap_code::RECONNECTED, true, 1)
        ],
        "the outage marked once: disconnected, then reconnected with an unknown loss"
    );
}

#[test]
fn hil_qemu_restart_the_host_follows_a_killed_and_rebooted_board() {
    let elf = build_elf().expect("build the QEMU firmware");
    let dir = scratch("qemu-restart");
    let link = dir.join("uart0");
    let (board, keeper) = boot(&elf, &link);
    let opts = OpenOptions {
        reconnect_for: Duration::from_secs(15),
        ..OpenOptions::default()
    };
    let dev = Device::open(&PortSpec::Path(link.clone()), opts).expect("open the stable path");
    let info = dev.info().expect("info at open");
    let out = dir.join("restart.csv");
    let setup = Setup::from_hardware("hil_qemu_restart: QEMU killed and rebooted".into()).unwrap();
    let mut rec = Recorder::create(&out, &info, &setup, SystemTime::now()).expect("recording");
    let mut log = Log::default();
    let wall = Instant::now();
    dev.start().unwrap();
    pump(&dev, &mut rec, &mut log, |l| l.settled(0) >= SETTLED_FRAMES);

    // The board dies mid-stream and its device node goes with it.
    let (pid1, t_kill) = (board.pid(), Instant::now());
    board.kill().expect("SIGKILL qemu-system-arm");
    drop(keeper);
    std::fs::remove_file(&link).expect("the device node disappears");
    pump(&dev, &mut rec, &mut log, |l| !l.gaps.is_empty());
    std::thread::sleep(Duration::from_millis(300));
    let (board, keeper) = boot(&elf, &link);
    pump(&dev, &mut rec, &mut log, |l| l.settled(1) >= SETTLED_FRAMES);
    let outage_s = t_kill.elapsed().as_secs_f64();
    let counters = dev.counters();
    dev.close();
    rec.flush().unwrap();
    drop(keeper);
    let pid2 = board.pid();
    board.shutdown().expect("stop QEMU");
    for pid in [pid1, pid2] {
        assert!(
            !Path::new(&format!("/proc/{pid}")).exists(),
            "QEMU {pid} must be gone"
        );
    }

    assert_eq!(
        counters,
        Counters {
            reconnects: 1,
            ..clean(counters)
        },
        "one reconnection, nothing damaged, lost or twice"
    );
    assert!(
        matches!(
            log.gaps.as_slice(),
            [
                GapKind::Disconnected,
                GapKind::Reconnected { missing: None, .. }
            ]
        ),
        "{:?}",
        log.gaps
    );
    for session in 0..2 {
        let seqs: Vec<u32> = log
            .frames
            .iter()
            .filter(|f| f.session == session)
            .map(|f| f.seq)
            .collect();
        // At least the settled frames the pump waited for: on a loaded machine the host may
        // reattach after the reboot's null has finished, and every frame it sees is settled.
        assert!(
            seqs.len() >= SETTLED_FRAMES,
            "session {session}: {} frames",
            seqs.len()
        );
        assert!(
            seqs.windows(2).all(|w| w[1] == w[0].wrapping_add(1)),
            "session {session}: sequence not continuous"
        );
    }
    let checked = check_values(&log.frames);
    let scale = Scale::from_info(&info);
    check_recording(&out, &log, &scale);
    let sessions: Vec<u32> = log.frames.iter().map(|f| f.session).collect();
    eprintln!(
        "hil_qemu_restart: {} frames ({} before the kill, {} after the reboot) in {:.1} s wall, \
         {checked} settled samples equal to the stimulus; kill -> settled stream again in \
         {outage_s:.1} s; gaps {:?}",
        log.frames.len(),
        sessions.iter().filter(|&&s| s == 0).count(),
        sessions.iter().filter(|&&s| s == 1).count(),
        wall.elapsed().as_secs_f64(),
        log.gaps,
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `c` with every damage and loss counter at zero (the totals kept).
fn clean(c: Counters) -> Counters {
    Counters {
        frames: c.frames,
        samples: c.samples,
        bytes: c.bytes,
        ..Counters::default()
    }
}
