//! HIL 1: the firmware library (real drivers, offset cut, filters, framing, commands) on a host
//! thread against the emulated sensor chain, paced at the ADC's data rate, streaming through a
//! pseudo-terminal that the host's serial driver opens by path. The standard test's load (45 N
//! at 20 deg, sped up 40x) runs while the host tares, sets a filter and changes the rate; every
//! decoded sample is checked against the chain's noise-free ground truth passed through an f64
//! reference of the filter in force, and every command against the frame it took effect in.
//!
//! Run: `cargo test -p hil --test hil_native -- --nocapture` (prints the figures).

use std::time::{Duration, Instant};

use hil::native::{NativeConfig, NativeSensor};
use hil::reference::{code_to_v, ErrorStats, ReferenceFilter};
use host::device::{Device, Event, Frame, OpenOptions, PortSpec};
use protocol::{FilterConfig, NullState};

const CFG: NativeConfig = NativeConfig {
    peak_load_n: 45.0,
    load_start_s: 3.0,
    speed_factor: 40.0,
    noise_seed: Some(11),
};
const FILTER: FilterConfig = FilterConfig {
    smoother_alpha: 1.0,
    butterworth_order: 2,
    cutoff_hz: 20.0,
};
const FAST_HZ: u32 = 2000;
/// Samples skipped after each filter (re)start: the device primes with a noisy sample, the
/// reference with the truth; the 20 Hz low-pass forgets the difference within ~5 / f_c.
const SETTLE_S: f64 = 0.25;

/// Read events until `done` holds for the frames so far (or panic after `timeout`).
fn pump(dev: &Device, frames: &mut Vec<Frame>, timeout: Duration, done: impl Fn(&[Frame]) -> bool) {
    let deadline = Instant::now() + timeout;
    while !done(frames) {
        assert!(
            Instant::now() < deadline,
            "timed out after {} frames",
            frames.len()
        );
        match dev.events().recv_timeout(Duration::from_millis(50)) {
            Ok(Event::Frame(f)) => frames.push(f),
            Ok(Event::Gap(g)) => panic!("gap in the stream: {g:?}"),
            Ok(Event::Info(_)) | Err(_) => {}
        }
    }
}

fn device_time_s(f: &Frame) -> f64 {
    f.t_device_us as f64 * 1e-6
}

#[test]
fn hil_native_firmware_library_against_the_emulated_sensor_over_a_pty() {
    let sensor = NativeSensor::spawn(CFG).expect("start the emulated sensor");
    let opts = OpenOptions {
        reconnect: false,
        ..OpenOptions::default()
    };
    let dev =
        Device::open(&PortSpec::Path(sensor.path.clone()), opts).expect("open the pty by path");
    let wall = Instant::now();
    let mut frames = Vec::new();
    dev.start().unwrap();
    let t = Duration::from_secs(20);
    pump(&dev, &mut frames, t, |f| {
        f.last()
            .is_some_and(|f| f.frame.status.null_state == NullState::Nulled)
    });
    dev.tare(256).unwrap();
    pump(&dev, &mut frames, t, |f| {
        f.last().is_some_and(|f| f.frame.status.tare_active)
    });
    dev.set_filter(FILTER).unwrap();
    let epoch_tared = frames.last().unwrap().frame.status.config_epoch;
    pump(&dev, &mut frames, t, |f| {
        f.last()
            .is_some_and(|f| f.frame.status.config_epoch != epoch_tared)
    });
    let epoch_filter = frames.last().unwrap().frame.status.config_epoch;
    assert_eq!(epoch_filter, epoch_tared.wrapping_add(1));
    assert!(
        device_time_s(frames.last().unwrap()) < CFG.load_start_s,
        "commands must land before the load"
    );
    // Mid-ramp: double the rate.
    pump(&dev, &mut frames, t, |f| {
        f.last()
            .is_some_and(|f| device_time_s(f) > CFG.load_start_s + 0.5)
    });
    dev.set_rate(FAST_HZ).unwrap();
    let info = dev.get_info().unwrap();
    let end_s = {
        let chain = CFG.chain().unwrap();
        chain.history.end_s() + 0.5
    };
    pump(&dev, &mut frames, t, |f| {
        f.last().is_some_and(|f| device_time_s(f) > end_s)
    });
    let streamed_s = wall.elapsed().as_secs_f64();
    let tail = &frames[frames.len() - 100..];
    let span = tail
        .last()
        .unwrap()
        .host_time
        .duration_since(tail[0].host_time)
        .unwrap_or_default();
    let steady_fps = 99.0 / span.as_secs_f64();
    let counters = dev.counters();
    dev.close();
    let stats = sensor.stop().expect("device thread");

    // Sequence: continuous, nothing dropped by the device or lost on the pty.
    assert!(
        frames
            .windows(2)
            .all(|w| w[1].seq == w[0].seq.wrapping_add(1)),
        "sequence gap"
    );
    assert_eq!(
        (
            stats.frames_dropped,
            counters.lost_on_link,
            counters.crc_errors
        ),
        (0, 0, 0)
    );
    assert_eq!(info.sample_rate_hz, FAST_HZ);
    assert_eq!(info.filter, FILTER);

    // The rate took effect at a frame boundary: the first frame of its epoch starts one new period
    // after the old frame's last sample, and spacings are 16 old periods before, 16 new after.
    let epoch_rate = info.config_epoch;
    let k = frames
        .iter()
        .position(|f| f.frame.status.config_epoch == epoch_rate)
        .expect("rate epoch seen");
    let dt = |i: usize| frames[i].t_device_us as i64 - frames[i - 1].t_device_us as i64;
    assert_eq!(dt(k - 1), 16_000);
    assert_eq!(dt(k), 15 * 1000 + 500, "first frame at the new rate");
    assert_eq!(dt(k + 1), 16 * 500);
    // The filter took effect at a frame boundary: the last unfiltered frame shows the raw noise,
    // the first filtered one is already smooth (every sample of it filtered).
    let kf = frames
        .iter()
        .position(|f| f.frame.status.config_epoch == epoch_filter)
        .unwrap();
    // Spread about the straight line through the frame: the noise, without the load's slope
    // (on a loaded machine the command can land on the steep part of the sped-up ramp).
    let spread = |f: &Frame| {
        let y: Vec<f64> = f
            .frame
            .samples()
            .iter()
            .map(|s| f64::from(s.ch[0]))
            .collect();
        let (n, x_mean) = (y.len() as f64, (y.len() as f64 - 1.0) / 2.0);
        let y_mean = y.iter().sum::<f64>() / n;
        let dx = |i: usize| i as f64 - x_mean;
        let sxy: f64 = y
            .iter()
            .enumerate()
            .map(|(i, v)| dx(i) * (v - y_mean))
            .sum();
        let sxx: f64 = (0..y.len()).map(|i| dx(i) * dx(i)).sum();
        let residual = |(i, v): (usize, &f64)| v - y_mean - sxy / sxx * dx(i);
        let r: Vec<f64> = y.iter().enumerate().map(residual).collect();
        r.iter().cloned().fold(f64::MIN, f64::max) - r.iter().cloned().fold(f64::MAX, f64::min)
    };
    assert!(
        spread(&frames[kf - 1]) > 4.0 * spread(&frames[kf]),
        "{} vs {}",
        spread(&frames[kf - 1]),
        spread(&frames[kf])
    );

    // Values: every sample from the filter's start on against the truth through the reference.
    let mut truth_chain = NativeConfig {
        noise_seed: None,
        ..CFG
    }
    .chain()
    .unwrap();
    truth_chain.dac_codes = [0, 1, 2].map(|i| u32::from(info.dac_codes[i]));
    let sigma = truth_chain.noise_rms_v();
    let gain = ReferenceFilter::noise_gain(&FILTER, 1000.0)
        .max(ReferenceFilter::noise_gain(&FILTER, 2000.0));
    let mut filters: Option<(u8, [ReferenceFilter; 3])> = None;
    let mut stats_ch = [ErrorStats::default(); 3];
    let mut peak = [0.0f64; 3];
    let mut restart_s = 0.0;
    for f in frames.iter().skip(kf) {
        let epoch = f.frame.status.config_epoch;
        let rate = if epoch == epoch_rate {
            f64::from(FAST_HZ)
        } else {
            1000.0
        };
        if filters.as_ref().is_none_or(|(e, _)| *e != epoch) {
            filters = Some((
                epoch,
                core::array::from_fn(|_| ReferenceFilter::new(&FILTER, rate)),
            ));
            restart_s = device_time_s(f);
        }
        let (_, refs) = filters.as_mut().unwrap();
        for (j, s) in f.frame.samples().iter().enumerate() {
            let t_s = device_time_s(f) + j as f64 / rate;
            let truth = truth_chain.truth_v(t_s);
            for ch in 0..3 {
                let expect = refs[ch].step(truth[ch]);
                peak[ch] = peak[ch].max(truth[ch].abs());
                if t_s - restart_s > SETTLE_S {
                    stats_ch[ch].add(code_to_v(&info, ch, s.ch[ch]) - expect);
                }
            }
        }
    }
    let samples: u64 = frames.iter().map(|f| f.frame.len() as u64).sum();
    eprintln!(
        "hil_native: {} frames, {samples} samples in {streamed_s:.2} s wall: {:.0} frames/s, {:.0} samples/s; \
         pacing lag max {:.1} ms; steady state at {FAST_HZ} Hz: {steady_fps:.1} frames/s",
        frames.len(),
        frames.len() as f64 / streamed_s,
        samples as f64 / streamed_s,
        stats.max_lag_s * 1e3
    );
    for (ch, name) in ["Fz", "Mx", "My"].iter().enumerate() {
        // 6 sigma of the filtered noise, plus the tare's own noise (256 raw samples averaged).
        let tol = 6.0 * sigma[ch] * gain + 6.0 * sigma[ch] / 256f64.sqrt();
        let s = stats_ch[ch];
        eprintln!(
            "  {name}: peak {:.3} V, error rms {:.1} uV, max {:.1} uV (tolerance {:.1} uV, {:.3} % of peak), {} samples",
            peak[ch],
            s.rms() * 1e6,
            s.max_abs * 1e6,
            tol * 1e6,
            100.0 * tol / peak[ch],
            s.n
        );
        assert!(s.n > 2000, "{name}: {} samples compared", s.n);
        assert!(
            s.max_abs < tol,
            "{name}: max error {} V > {tol} V",
            s.max_abs
        );
        // The load must move the channel well clear of the tolerance, so the comparison above
        // resolves the signal to 1 % (an absolute floor would track the front end's gains).
        assert!(
            tol < 0.01 * peak[ch],
            "{name}: peak {} V is not 100x the tolerance {tol} V",
            peak[ch]
        );
    }
}
