//! The device subcommands doing their work against the emulator: info, tare, config (accepted
//! and refused), and a slow reader that loses frames visibly instead of lagging.

use std::process::{Command, Output};
use std::time::Duration;

use hil::check::scratch;
use hil::emu::{EmuConfig, Emulator};
use host::device::{Device, Event, GapKind, OpenOptions, PortSpec};
use sysexit as exit;

fn tactile(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tactile"))
        .args(args)
        .output()
        .unwrap()
}

fn stdout(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn info_tare_and_config_against_the_emulator() {
    let dir = scratch("commands");
    let cfg = EmuConfig::new(dir.join("tactile0"));
    let _emu = Emulator::spawn(cfg.clone()).unwrap();
    let p = cfg.link.to_str().unwrap();
    let info = stdout(&tactile(&["info", "-p", p]));
    assert!(
        info.contains("chip serial      7ac711e0") && info.contains("1000 Hz"),
        "{info}"
    );
    let tare = stdout(&tactile(&["tare", "-p", p, "--samples", "50"]));
    assert!(tare.contains("config epoch 1"), "{tare}");
    let cfg_out = stdout(&tactile(&[
        "config",
        "-p",
        p,
        "--rate",
        "500",
        "--smoother-alpha",
        "0.5",
    ]));
    assert!(
        cfg_out.contains("500 Hz") && cfg_out.contains("smoother alpha 0.5"),
        "{cfg_out}"
    );
    // The device refuses a rate its ADC cannot run: the nack's reason reaches the user.
    let o = tactile(&["config", "-p", p, "--rate", "123"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(exit::PROTOCOL.into()), "{err}");
    assert!(
        err.contains("set rate refused by the device (OutOfRange)") && err.contains(p),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_slow_reader_loses_frames_visibly() {
    let dir = scratch("slow");
    let cfg = EmuConfig::new(dir.join("tactile0"));
    let _emu = Emulator::spawn(cfg.clone()).unwrap();
    let opts = OpenOptions {
        queue: 8,
        ..OpenOptions::default()
    };
    let dev = Device::open(&PortSpec::Path(cfg.link.clone()), opts).unwrap();
    dev.start().unwrap();
    std::thread::sleep(Duration::from_millis(800));
    let mut lost = None;
    while let Ok(ev) = dev.events().recv_timeout(Duration::from_millis(200)) {
        if let Event::Gap(g) = ev {
            if let GapKind::HostQueueFull { frames } = g.kind {
                lost = Some(frames);
                break;
            }
        }
    }
    let lost = lost.expect("the discarded frames are reported as a gap");
    assert!(lost > 30, "{lost}");
    assert_eq!(dev.counters().host_queue_drops, lost);
    let _ = std::fs::remove_dir_all(&dir);
}
