//! The fault-injecting link inside the pty HIL path: the emulator (`hil::emu`, free-running)
//! sends its frames through `sim::link::FaultyLink` (bit flips, dropped, duplicated and garbage
//! bytes, truncations, stalls longer than the host's read timeout) into a pty; the host
//! library's serial driver (`host::device`, the code `tactile log` runs) opens the pty by path
//! and decodes. Checks over 100,000 frames (a million with `--ignored`):
//! - no corrupted frame accepted: every delivered sample equals the emulator's deterministic
//!   truth for its sequence, sequences strictly increase;
//! - resynchronisation within one frame: every frame the link delivered intact is decoded, and
//!   the driver's resync count equals the link's recoveries (good frames right after junk);
//! - the host's counters equal the injected counts exactly: CRC errors + malformed + overflows =
//!   junk units, frames lost by sequence = frames the link lost, frames = frames delivered.
//!
//! Run: `cargo test -p hil --test hil_faults -- --nocapture` (prints injected vs detected);
//! the million: `cargo test --release -p hil --test hil_faults -- --ignored --nocapture`.

use std::time::{Duration, Instant};

use hil::check::scratch;
use hil::emu::{truth_frame, EmuConfig, EmuFaults, Emulator, Pace};
use host::device::{Counters, Device, Event, GapKind, OpenOptions, PortSpec};
use protocol::Status;
use sim::link::{FaultRates, Injected};

/// Frames at each end that pass the link clean: a loss before the first accepted frame or after
/// the last one would not show by sequence.
const CLEAN_ENDS: u64 = 16;

/// What the host saw, besides its counters.
#[derive(Debug, Default)]
struct Seen {
    accepted: u64,
    samples: u64,
    /// Frames missing by sequence, summed over the gap events.
    missing_by_gaps: u64,
    wall_s: f64,
}

/// Every fault at `rate` per frame; stalls at 1e-3 (each costs wall time) and 20 ms long, twice
/// the driver's read timeout, so a frame is left half-read across an idle read.
fn rates(rate: f64) -> FaultRates {
    FaultRates {
        stall: 1e-3,
        stall_for: Duration::from_millis(20),
        ..FaultRates::uniform(rate, Duration::ZERO)
    }
}

fn run(frames: u64, rate: f64, seed: u64) -> (Injected, Counters, Seen) {
    let dir = scratch("faults");
    let mut cfg = EmuConfig::new(dir.join("tactile0"));
    cfg.pace = Pace::FreeRun { frames };
    cfg.faults = Some(EmuFaults {
        rates: rates(rate),
        seed,
        frames: CLEAN_ENDS..frames - CLEAN_ENDS,
    });
    let (batch, rate_hz) = (cfg.batch, cfg.rate_hz);
    let link = cfg.link.clone();
    let emu = Emulator::spawn(cfg).expect("start the emulator");
    let opts = OpenOptions {
        reconnect: false,
        ..OpenOptions::default()
    };
    let dev = Device::open(&PortSpec::Path(link), opts).expect("open the pty by path");
    dev.start().expect("start");
    let t0 = Instant::now();
    let mut seen = Seen::default();
    let mut next_seq = 0u32;
    let deadline = Duration::from_secs(60 + frames / 5_000);
    while u64::from(next_seq) < frames {
        assert!(
            t0.elapsed() < deadline,
            "stuck at frame {next_seq}: {:?}",
            dev.counters()
        );
        match dev.events().recv_timeout(Duration::from_millis(200)) {
            Ok(Event::Frame(f)) => {
                assert!(f.seq >= next_seq, "frame {} after {}", f.seq, next_seq);
                let truth = truth_frame(f.seq, batch, rate_hz, Status::default());
                assert_eq!(f.frame, truth, "frame {} accepted but not as sent", f.seq);
                next_seq = f.seq + 1;
                seen.accepted += 1;
                seen.samples += f.frame.len() as u64;
            }
            Ok(Event::Gap(g)) => match g.kind {
                GapKind::Sequence {
                    missing,
                    dropped_by_device: 0,
                    ..
                } => seen.missing_by_gaps += missing,
                other => panic!("unexpected gap {other:?}"),
            },
            Ok(Event::Info(_)) | Err(_) => {}
        }
    }
    seen.wall_s = t0.elapsed().as_secs_f64();
    let counters = dev.counters();
    let injected = emu.stats.injected();
    dev.close();
    emu.kill();
    let _ = std::fs::remove_dir_all(&dir);
    (injected, counters, seen)
}

fn check(frames: u64, rate: f64, seed: u64) {
    let (inj, c, seen) = run(frames, rate, seed);
    let rejected = c.crc_errors + c.malformed + c.overflows;
    let kinds = [
        inj.bit_flips,
        inj.bytes_dropped,
        inj.bytes_duplicated,
        inj.garbage_bursts,
        inj.truncations,
        inj.stalls,
    ];
    println!(
        "hil_faults: {frames} frames through the pty at fault rate {rate}/frame in {:.1} s \
         ({:.0} frames/s)\n  injected [bit flips, bytes dropped, bytes duplicated, garbage \
         bursts, truncations, stalls]: {kinds:?}\n  link account: {} delivered, {} lost, \
         {} junk units, {} recoveries\n  host driver: {} frames, {} lost by sequence, {} rejected \
         ({} CRC, {} malformed, {} overflow), {} resyncs, {} duplicates",
        seen.wall_s,
        frames as f64 / seen.wall_s,
        inj.frames_delivered,
        inj.frames_lost,
        inj.junk_units,
        inj.recoveries,
        c.frames,
        c.lost_on_link,
        rejected,
        c.crc_errors,
        c.malformed,
        c.overflows,
        c.resyncs,
        c.duplicates,
    );
    assert_eq!(inj.frames_in, frames, "the link saw every frame");
    assert_eq!(
        seen.accepted, inj.frames_delivered,
        "every intact frame decoded"
    );
    assert_eq!(c.frames, inj.frames_delivered);
    assert_eq!(
        c.lost_on_link, inj.frames_lost,
        "lost frames counted as injected"
    );
    assert_eq!(
        seen.missing_by_gaps, inj.frames_lost,
        "every loss marked as a gap"
    );
    assert_eq!(
        rejected, inj.junk_units,
        "every damaged unit rejected and counted"
    );
    assert_eq!(
        c.resyncs, inj.recoveries,
        "back on the first intact frame after damage"
    );
    assert_eq!(
        (c.duplicates, c.dropped_by_device, c.host_queue_drops),
        (0, 0, 0)
    );
    assert_eq!(seen.samples, c.samples);
    // Every kind of fault happened.
    assert!(kinds.iter().all(|&n| n > 0), "{inj:?}");
}

#[test]
fn hil_faults_hundred_thousand_frames_through_a_faulty_pty() {
    check(100_000, 0.01, 7);
    // A link this bad merges frames into runs longer than any frame (overflows).
    check(20_000, 0.2, 9);
}

#[test]
#[ignore = "a million frames through the pty; run with --release --ignored"]
fn hil_faults_a_million_frames_through_a_faulty_pty() {
    check(1_000_000, 0.01, 8);
}
