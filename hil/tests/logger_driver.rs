//! The host driver against the `tactile-emu` process: SIGKILL the emulator process mid-stream
//! (often mid-frame), start a new one on the same path, and check through the library API that
//! the driver reconnects by itself, marks the outage, resumes streaming, keeps its counters,
//! and that every frame it delivers is the emulator's truth.

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use hil::check::scratch;
use hil::emu::truth_frame;
use host::device::{Device, Event, GapKind, OpenOptions, PortSpec};

fn emulator(link: &std::path::Path, epoch_s: f64) -> Child {
    let child = Command::new(env!("CARGO_BIN_EXE_tactile-emu"))
        .arg("--link")
        .arg(link)
        .args([
            "--rate",
            "1000",
            "--batch",
            "10",
            "--epoch-unix",
            &epoch_s.to_string(),
        ])
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    // Wait for the link to point at the new pty.
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_secs(5) {
        if std::fs::metadata(link).is_ok() {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child
}

#[test]
fn the_driver_survives_a_killed_emulator_process() {
    let dir = scratch("driver");
    let link = dir.join("tactile0");
    let epoch_s = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap()
        .as_secs_f64();
    let mut emu = emulator(&link, epoch_s);
    let dev = Device::open(&PortSpec::Path(link.clone()), OpenOptions::default()).unwrap();
    let info = dev.get_info().unwrap();
    assert_eq!(info.sample_rate_hz, 1000);
    dev.start().unwrap();

    let mut frames = 0u64;
    let mut gaps = Vec::new();
    let mut after_reconnect = 0u64;
    let t0 = Instant::now();
    let mut killed = false;
    let mut restarted = false;
    while t0.elapsed() < Duration::from_secs(4) {
        if !killed && t0.elapsed() > Duration::from_millis(1200) {
            emu.kill().unwrap(); // SIGKILL: may cut a frame in half
            emu.wait().unwrap();
            std::fs::remove_file(&link).ok(); // the device node disappears with the device
            killed = true;
        }
        if killed && !restarted && t0.elapsed() > Duration::from_millis(1800) {
            emu = emulator(&link, epoch_s);
            restarted = true;
        }
        match dev.events().recv_timeout(Duration::from_millis(50)) {
            Ok(Event::Frame(f)) => {
                let truth = truth_frame(f.seq, info.batch, info.sample_rate_hz, f.frame.status);
                assert_eq!(
                    f.frame, truth,
                    "frame {} differs from the emulator's truth",
                    f.seq
                );
                frames += 1;
                if gaps
                    .iter()
                    .any(|g| matches!(g, GapKind::Reconnected { .. }))
                {
                    after_reconnect += 1;
                }
            }
            Ok(Event::Gap(g)) => gaps.push(g.kind),
            Ok(Event::Info(_)) | Err(_) => {}
        }
    }
    emu.kill().ok();
    emu.wait().ok();
    assert!(frames > 150, "{frames} frames");
    assert!(
        matches!(gaps.first(), Some(GapKind::Disconnected)),
        "{gaps:?}"
    );
    let missing = gaps.iter().find_map(|g| match g {
        GapKind::Reconnected { missing, .. } => Some(*missing),
        _ => None,
    });
    let missing = missing
        .expect("reconnection marked")
        .expect("sequence continued");
    assert!((30..300).contains(&missing), "missing {missing}");
    assert!(
        after_reconnect > 50,
        "streaming did not resume: {after_reconnect} frames"
    );
    let c = dev.counters();
    assert_eq!(c.reconnects, 1);
    assert_eq!(c.duplicates, 0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Several ports on the one I/O thread (`Device::open_all`): a missing port is its own error
/// and leaves the others open; when one emulator vanishes (no reconnection asked) its stream
/// ends as gone while the other keeps streaming.
#[test]
fn one_thread_serves_several_ports_and_loses_one_alone() {
    let dir = scratch("driver-all");
    let (a, b) = (dir.join("tactile-a"), dir.join("tactile-b"));
    let epoch_s = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap()
        .as_secs_f64();
    let mut emu_a = emulator(&a, epoch_s);
    let mut emu_b = emulator(&b, epoch_s);
    let opts = OpenOptions {
        reconnect: false,
        ..OpenOptions::default()
    };
    let specs = [a, dir.join("missing"), b].map(PortSpec::Path);
    let mut opened = Device::open_all(&specs, opts).into_iter();
    let dev_a = opened.next().unwrap().unwrap();
    let missing = opened.next().unwrap();
    assert!(
        matches!(missing, Err(host::device::DeviceError::NotFound { .. })),
        "{:?}",
        missing.err()
    );
    let dev_b = opened.next().unwrap().unwrap();
    dev_a.start().unwrap();
    dev_b.start().unwrap();
    let count = |dev: &Device, for_: Duration| {
        let t0 = Instant::now();
        let mut frames = 0;
        while t0.elapsed() < for_ {
            match dev.events().recv_timeout(Duration::from_millis(50)) {
                Ok(Event::Frame(_)) => frames += 1,
                Ok(_) | Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => break,
            }
        }
        frames
    };
    assert!(count(&dev_a, Duration::from_millis(500)) > 20);
    assert!(count(&dev_b, Duration::from_millis(500)) > 20);
    emu_a.kill().unwrap();
    emu_a.wait().unwrap();
    // A's stream ends (its events channel disconnects once the thread lets go of the port).
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_secs(5) && dev_a.gone_error().is_none() {
        let _ = dev_a.events().recv_timeout(Duration::from_millis(50));
    }
    assert!(dev_a.gone_error().is_some(), "port A should be gone");
    assert!(
        count(&dev_b, Duration::from_millis(500)) > 20,
        "B kept streaming"
    );
    dev_b.close();
    dev_a.close();
    emu_b.kill().unwrap();
    emu_b.wait().unwrap();
}
