//! `tactile log --hand` against two pty emulators whose crystals are off by ±300 ppm behind a
//! jittered link: one CSV per finger named by finger, one MCAP with a topic per finger, each
//! finger's clock rate estimated (metadata `clock_ppm`), and the two fingers' `t_s` of the same
//! true instant in agreement. A few seconds of real time: the hour is simulated in
//! `hil::hand_clock` and `scripts/bench-hand.sh`.

use std::process::Command;
use std::time::{SystemTime, UNIX_EPOCH};

use hil::check::scratch;
use hil::emu::{EmuConfig, Emulator};
use sim::clock::LinkJitter;

const PPM: [f64; 2] = [300.0, -300.0];

fn meta(rec: &recording::Recording, key: &str) -> f64 {
    let v = rec
        .meta
        .other
        .iter()
        .find(|(k, _)| k == key)
        .unwrap_or_else(|| panic!("no {key}"));
    v.1.trim()
        .parse()
        .unwrap_or_else(|_| panic!("{key} = {}", v.1))
}

/// Each data row's `t_s` minus the true time (since the recording's start) its sample was taken.
fn time_errors(rec: &recording::Recording, cfg: &EmuConfig, ppm: f64) -> Vec<(f64, f64)> {
    let start = meta(rec, "start_unix_s");
    let epoch = cfg.epoch.duration_since(UNIX_EPOCH).unwrap().as_secs_f64();
    let seq = rec.column("seq").unwrap();
    let gap = rec.column("gap").unwrap();
    let mut out = Vec::new();
    let mut k = 0;
    for i in 0..rec.channels.len() {
        if gap[i] != 0.0 {
            continue;
        }
        k = if i > 0 && seq[i - 1] == seq[i] {
            k + 1
        } else {
            0
        };
        let n = seq[i] * f64::from(cfg.batch) + f64::from(k);
        let true_s = epoch + n / f64::from(cfg.rate_hz) / (1.0 + ppm * 1e-6) - start;
        out.push((true_s, rec.channels.t_s[i] - true_s));
    }
    out
}

#[test]
fn a_hand_file_logs_each_finger_on_one_time_base() {
    let dir = scratch("hand");
    let epoch = SystemTime::now();
    let mut emus = Vec::new();
    let mut cfgs = Vec::new();
    for (i, ppm) in PPM.iter().enumerate() {
        let mut cfg = EmuConfig::new(dir.join(format!("tip{i}")));
        cfg.epoch = epoch;
        cfg.clock_ppm = *ppm;
        cfg.jitter = Some((LinkJitter::USB_BUSY, 7 + i as u64));
        emus.push(Emulator::spawn(cfg.clone()).unwrap());
        cfgs.push(cfg);
    }
    let hand = dir.join("hand.toml");
    let toml = format!(
        "# two fingers\n[fingers]\nthumb = \"{}\"\nindex = \"{}\"\n",
        cfgs[0].link.display(),
        cfgs[1].link.display()
    );
    std::fs::write(&hand, toml).unwrap();
    let st = Command::new(env!("CARGO_BIN_EXE_tactile"))
        .args(["log", "-q", "--hand"])
        .arg(&hand)
        .arg("-o")
        .arg(dir.join("rec.csv"))
        .args(["--duration", "8"])
        .status()
        .unwrap();
    assert!(st.success());
    drop(emus);
    let mut errors = Vec::new();
    for (i, name) in ["thumb", "index"].iter().enumerate() {
        let rec = recording::read(&dir.join(format!("rec-{name}.csv"))).unwrap();
        let ppm = meta(&rec, "clock_ppm");
        // Eight seconds through a pty, jittered, at the emulators' 2 ms tick: within 150 ppm.
        assert!(
            (ppm - PPM[i]).abs() < 150.0,
            "{name}: {ppm} ppm, truth {}",
            PPM[i]
        );
        assert!(meta(&rec, "clock_uncertainty_us") < 2000.0);
        errors.push(time_errors(&rec, &cfgs[i], PPM[i]));
    }
    // The same true instant (to a frame) in both fingers: their time errors must agree. The
    // pty and the emulators' 2 ms tick add their own delays; the bound is two milliseconds here.
    let worst = errors[0]
        .iter()
        .filter_map(|(t, e)| {
            let j = errors[1].partition_point(|(u, _)| u < t);
            let (u, f) = errors[1].get(j)?;
            ((u - t).abs() < 0.01).then(|| (e - f).abs())
        })
        .fold(0.0, f64::max);
    assert!(worst < 2e-3, "fingers misaligned by {worst} s");
    let bytes = std::fs::read(dir.join("rec.mcap")).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let topics: Vec<&str> = summary
        .channels
        .values()
        .map(|c| c.topic.as_str())
        .collect();
    for t in ["/tactile/thumb/sample", "/tactile/index/sample"] {
        assert!(topics.contains(&t), "{topics:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A malformed hand file or a finger whose port is missing: one line naming the file, the line
/// and the field (or the finger), a non-zero exit, and no file created.
#[test]
fn a_bad_hand_file_is_one_clear_error() {
    let dir = scratch("hand-bad");
    let cases = [
        (
            "[fingers]\nthumb = \"/dev/null\"\nring = 3\n",
            65,
            ":3: field fingers.ring: expected a port",
        ),
        (
            "[fingers]\nthumb = \"/nonexistent/tip\"\n",
            66,
            ": finger thumb: port /nonexistent/tip",
        ),
    ];
    for (text, code, says) in cases {
        let hand = dir.join("hand.toml");
        std::fs::write(&hand, text).unwrap();
        let o = Command::new(env!("CARGO_BIN_EXE_tactile"))
            .args(["log", "-q", "--hand"])
            .arg(&hand)
            .arg("-o")
            .arg(dir.join("rec.csv"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(code), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains("hand.toml") && err.contains(says), "{err}");
        assert!(!dir.join("rec-thumb.csv").exists() && !dir.join("rec.mcap").exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}
