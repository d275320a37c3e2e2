//! `tactile log` killed with SIGKILL: the CSV holds whole rows up to the last flush (at most
//! a second before the kill), every one true to the emulator, and the MCAP file, which never
//! got its summary, is recovered up to its last complete chunk and replays to the same data.

use std::path::Path;
use std::process::Command;
use std::time::{Duration, SystemTime};

use hil::check::{replay, scratch, verify_file};
use hil::emu::{EmuConfig, Emulator};
use host::logger::mcap_io::recover;
use host::logger::unix_s;

#[test]
fn a_killed_logger_leaves_readable_files_up_to_the_last_second() {
    let dir = scratch("kill9");
    let cfg = EmuConfig::new(dir.join("tactile0"));
    let _emu = Emulator::spawn(cfg.clone()).unwrap();
    let csv = dir.join("rec.csv");
    let mut child = Command::new(env!("CARGO_BIN_EXE_tactile"))
        .args(["log", "-q", "-p"])
        .arg(&cfg.link)
        .arg("-o")
        .arg(&csv)
        .args(["--duration", "60"])
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(2500));
    child.kill().unwrap(); // SIGKILL
    let killed_at = unix_s(SystemTime::now());
    child.wait().unwrap();

    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        text.ends_with('\n'),
        "torn last row: {:?}",
        text.lines().last()
    );
    let (rec, v) = verify_file(&csv, &cfg).expect("every row complete and valid");
    let t_host = rec.column("t_host_s").unwrap();
    let last = t_host
        .iter()
        .copied()
        .filter(|t| t.is_finite())
        .fold(f64::NAN, f64::max);
    assert!(
        killed_at - last <= 1.0,
        "the CSV ends {:.3} s before the kill",
        killed_at - last
    );
    assert!(v.samples > 500);

    let mcap = dir.join("rec.mcap");
    let r = recover(&mcap).unwrap();
    assert!(!r.messages.is_empty());
    let last_mcap_ns = r.messages.iter().map(|m| m.publish_ns).max().unwrap();
    assert!(
        killed_at - last_mcap_ns as f64 * 1e-9 <= 1.0,
        "MCAP ends too early"
    );
    let out = dir.join("replayed.csv");
    replay(Path::new(env!("CARGO_BIN_EXE_tactile")), &mcap, &out);
    let (_, v2) = verify_file(&out, &cfg).unwrap();
    assert_eq!(v2.first_seq, v.first_seq);
    assert!(
        v2.samples + 1000 >= v.samples,
        "MCAP recovered {} samples, CSV has {}",
        v2.samples,
        v.samples
    );
    let _ = std::fs::remove_dir_all(&dir);
}
