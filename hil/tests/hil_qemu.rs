//! HIL 2: the firmware's QEMU board binary in `qemu-system-arm -machine mps2-an386`, UART0 on a
//! pty; the host's serial driver and recorder (the code path of `tactile log`) read it live, send
//! commands and write a recording-v1 CSV. The board converts the deterministic stimulus of
//! `sim::ads131m04::stimulus` through the register-level ADC emulation and the real driver, so
//! every decoded code is recomputed here from its conversion index: sample count, sequence
//! continuity, values (raw, tared, filtered) and the frames where tare, filter and rate took
//! effect are all checked. QEMU is always killed at the end (see `hil::qemu`).
//!
//! Needs `qemu-system-arm` (scripts/setup.sh installs it) and builds the thumb ELF if missing.
//! Run: `cargo test -p hil --test hil_qemu -- --nocapture` (prints the figures); with
//! `TACTILE_HIL_QEMU_CLOCK=virtual` QEMU runs as fast as it can (`-icount shift=0,sleep=off`),
//! which measures the path's capacity instead of the real-time rate.

use std::time::{Duration, Instant, SystemTime};

use hil::pty::hold_open;
use hil::qemu::{build_elf, ideal_code, Clock, QemuBoard, NULL_CODES};
use hil::reference::ReferenceFilter;
use host::device::{Device, Event, Frame, OpenOptions, PortSpec};
use host::logger::{Recorder, Setup};
use protocol::{FilterConfig, NullState};
use sim::ads131m04::stimulus::{Stimulus, StimulusParams};

const FILTER: FilterConfig = FilterConfig {
    smoother_alpha: 1.0,
    butterworth_order: 4,
    cutoff_hz: 50.0,
};
const FAST_HZ: u32 = 2000;
/// Largest difference between the device's f32 filter and the f64 reference on the noise-free
/// stimulus, in codes (1 code = 143 nV). f32 carries 24 bits: on signals of up to 2.5e6 codes each
/// operation rounds by up to ~0.15 codes, and a 4th-order cascade at f_c / f_s = 0.025 (poles
/// at radius ~0.85) accumulates some tens of them; measured 8 codes (printed). 50 codes = 7 uV,
/// 6e-6 of full scale; a wrong coefficient or a section in the wrong order misses by thousands.
const FILTER_TOLERANCE_CODES: f64 = 50.0;

fn pump(
    dev: &Device,
    rec: &mut Recorder,
    frames: &mut Vec<Frame>,
    done: impl Fn(&[Frame]) -> bool,
) {
    let deadline = Instant::now() + Duration::from_secs(30);
    while !done(frames) {
        assert!(
            Instant::now() < deadline,
            "timed out after {} frames",
            frames.len()
        );
        match dev.events().recv_timeout(Duration::from_millis(50)) {
            Ok(ev) => {
                rec.on_event(&ev).expect("recording");
                match ev {
                    Event::Frame(f) => frames.push(f),
                    Event::Gap(g) => panic!("gap in the stream: {g:?}"),
                    Event::Info(_) => {}
                }
            }
            Err(_) => continue,
        }
    }
}

/// Frames per second of host receive time over `frames` (the rate the link really carries).
fn steady_frames_per_s(frames: &[Frame]) -> f64 {
    let span = frames
        .last()
        .unwrap()
        .host_time
        .duration_since(frames[0].host_time)
        .unwrap_or_default();
    (frames.len() - 1) as f64 / span.as_secs_f64()
}

#[test]
fn hil_qemu_firmware_under_qemu_streams_to_the_host_logger() {
    let elf = build_elf().expect("build the QEMU firmware");
    let mut board = QemuBoard::spawn(&elf, Clock::from_env()).expect("start qemu-system-arm");
    let keeper = hold_open(&board.pty).expect("open UART0's pty");
    board.resume().unwrap();
    let opts = OpenOptions {
        reconnect: false,
        ..OpenOptions::default()
    };
    let dev =
        Device::open(&PortSpec::Path(board.pty.clone()), opts).expect("open UART0's pty by path");
    drop(keeper);
    let info0 = dev.info().expect("info at open");
    let out = std::env::temp_dir().join(format!("hil_qemu_{}.csv", std::process::id()));
    let setup =
        Setup::from_hardware("hil_qemu: firmware under QEMU mps2-an386, stimulus bench".into())
            .unwrap();
    let mut rec =
        Recorder::create(&out, &info0, &setup, SystemTime::now()).expect("recording file");
    rec.on_event(&Event::Info(info0.clone())).unwrap();

    let wall = Instant::now();
    let mut frames = Vec::new();
    dev.start().unwrap();
    pump(&dev, &mut rec, &mut frames, |f| {
        f.last()
            .is_some_and(|f| f.frame.status.null_state == NullState::Nulled)
    });
    dev.tare(64).unwrap();
    pump(&dev, &mut rec, &mut frames, |f| {
        f.last().is_some_and(|f| f.frame.status.tare_active)
    });
    let rest_s = StimulusParams::QEMU_BOARD.rest as f64 / 1000.0;
    assert!(
        (frames.last().unwrap().t_device_us as f64) * 1e-6 < rest_s,
        "tare must finish at rest"
    );
    // Into the waves, then a filter, then the rate.
    pump(&dev, &mut rec, &mut frames, |f| {
        f.last()
            .is_some_and(|f| f.t_device_us as f64 * 1e-6 > rest_s + 0.6)
    });
    dev.set_filter(FILTER).unwrap();
    let epoch_filter = frames
        .last()
        .unwrap()
        .frame
        .status
        .config_epoch
        .wrapping_add(1);
    pump(&dev, &mut rec, &mut frames, |f| {
        f.last()
            .is_some_and(|f| f.frame.status.config_epoch == epoch_filter)
    });
    pump(&dev, &mut rec, &mut frames, |f| {
        f.len() > 10 && f[f.len() - 10].frame.status.config_epoch == epoch_filter
    });
    dev.set_rate(FAST_HZ).unwrap();
    let info = dev.get_info().unwrap();
    rec.on_event(&Event::Info(info.clone())).unwrap();
    let epoch_rate = info.config_epoch;
    pump(&dev, &mut rec, &mut frames, |f| {
        f.iter()
            .filter(|f| f.frame.status.config_epoch == epoch_rate)
            .count()
            > 100
    });
    let streamed_s = wall.elapsed().as_secs_f64();
    let steady_fps = steady_frames_per_s(&frames[frames.len() - 100..]);
    let counters = dev.counters();
    dev.close();
    rec.flush().unwrap();
    let pid = board.pid();
    board.shutdown().expect("stop QEMU");
    assert!(
        !std::path::Path::new(&format!("/proc/{pid}")).exists(),
        "QEMU must be gone"
    );

    // Sequence continuity and the driver's counters.
    assert!(
        frames
            .windows(2)
            .all(|w| w[1].seq == w[0].seq.wrapping_add(1)),
        "sequence gap"
    );
    assert_eq!(
        (
            counters.lost_on_link,
            counters.dropped_by_device,
            counters.crc_errors
        ),
        (0, 0, 0)
    );
    assert_eq!(&info.dac_codes[..3], &NULL_CODES);
    assert_eq!((info.sample_rate_hz, info.filter), (FAST_HZ, FILTER));

    // Values, by conversion index: frames are continuous, so the index of every sample follows
    // from the first streamed frame's time stamp (1000 samples/s before the rate change).
    let stim = Stimulus::new(StimulusParams::QEMU_BOARD);
    let mut trimmed = Stimulus::new(StimulusParams::QEMU_BOARD);
    trimmed.trim_codes = [NULL_CODES[0], NULL_CODES[1], NULL_CODES[2], 2048];
    let mut index = u64::from(frames[0].frame.t_us / 1000);
    let (mut exact, mut filtered, mut worst_filter) = (0u64, 0u64, 0.0f64);
    let mut refs: Option<(u8, [ReferenceFilter; 3])> = None;
    let mut k_rate = None;
    for (k, f) in frames.iter().enumerate() {
        let st = f.frame.status;
        // The null and the tare finish in the middle of a frame: that frame mixes both states.
        let transition = k > 0 && {
            let prev = frames[k - 1].frame.status;
            prev.null_state != st.null_state || prev.tare_active != st.tare_active
        };
        if transition {
            index += f.frame.len() as u64;
            continue;
        }
        if st.config_epoch == epoch_rate && k_rate.is_none() {
            k_rate = Some(k);
        }
        assert_eq!(
            f.frame.temp,
            ideal_code(stim.volts(index)[3]),
            "temperature at {index}"
        );
        for s in f.frame.samples() {
            let truth = if st.tare_active {
                stim.signal_v(index)
            } else {
                trimmed.volts(index)
            };
            let ideal: [i32; 3] = core::array::from_fn(|ch| ideal_code(truth[ch]));
            if st.null_state == NullState::Nulled
                && st.config_epoch < epoch_filter
                && !st.tare_active
            {
                // Nulled, untared, unfiltered: the codes of the trimmed stimulus exactly.
                assert_eq!(s.ch, ideal, "raw sample {index}");
                exact += 1;
            } else if st.tare_active && st.config_epoch < epoch_filter {
                // Tared at rest: the signal alone, within the tare's rounding.
                for (ch, (got, want)) in s.ch.iter().zip(ideal).enumerate() {
                    assert!((got - want).abs() <= 1, "tared sample {index} ch {ch}");
                }
                exact += 1;
            } else if st.config_epoch >= epoch_filter {
                let rate = if st.config_epoch == epoch_rate {
                    f64::from(FAST_HZ)
                } else {
                    1000.0
                };
                if refs.as_ref().is_none_or(|(e, _)| *e != st.config_epoch) {
                    refs = Some((
                        st.config_epoch,
                        core::array::from_fn(|_| ReferenceFilter::new(&FILTER, rate)),
                    ));
                }
                let (_, r) = refs.as_mut().unwrap();
                for ch in 0..3 {
                    let expect = r[ch].step(f64::from(ideal[ch]));
                    let e = (f64::from(s.ch[ch]) - expect).abs();
                    worst_filter = worst_filter.max(e);
                    assert!(
                        e < FILTER_TOLERANCE_CODES,
                        "filtered sample {index} ch {ch}: {} vs {expect}",
                        s.ch[ch]
                    );
                }
                filtered += 1;
            }
            index += 1;
        }
    }
    // The rate took effect at a frame boundary (16 old periods, then 15 old + 1 new, then 16 new).
    let k = k_rate.expect("frames at the new rate");
    let dt = |i: usize| frames[i].t_device_us as i64 - frames[i - 1].t_device_us as i64;
    assert_eq!((dt(k - 1), dt(k), dt(k + 1)), (16_000, 15_500, 8_000));
    let samples: u64 = frames.iter().map(|f| f.frame.len() as u64).sum();
    assert!(
        exact > 500 && filtered > 1000,
        "{exact} exact, {filtered} filtered samples"
    );

    // The recording: the contract's CSV with one row per sample.
    let recording = recording::read(&out).expect("recording-v1 CSV reads back");
    let fz = &recording.channels.fz_v;
    assert_eq!(fz.len() as u64, samples, "one row per sample");
    assert!(recording.meta.get("firmware_smoother_alpha").is_some());
    let _ = std::fs::remove_file(&out);
    let _ = std::fs::remove_file(out.with_extension("mcap"));
    eprintln!(
        "hil_qemu: {} frames, {samples} samples in {streamed_s:.2} s wall: {:.0} frames/s, {:.0} samples/s; \
         {exact} samples exact, {filtered} filtered within {worst_filter:.1} codes of the f64 reference; \
         steady state at {FAST_HZ} Hz: {steady_fps:.1} frames/s ({:?} clock)",
        frames.len(),
        frames.len() as f64 / streamed_s,
        samples as f64 / streamed_s,
        Clock::from_env(),
    );
}
