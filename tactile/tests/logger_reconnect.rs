//! `tactile log` against the pty emulator: the emulator is killed mid-stream and restarted on
//! the same path; the logger must reconnect, mark the outage, and lose or duplicate nothing
//! that the gap row does not account for. The CSV is re-read by the contract reader and
//! checked sample by sample against the emulator's truth; the MCAP replays to the same rows.

use std::path::Path;
use std::process::Command;
use std::time::{Duration, SystemTime};

use hil::check::{replay, scratch, verify_file};
use hil::emu::{EmuConfig, Emulator};
use host::logger::gap_code;
use host::logger::mcap_io::recover;

#[test]
fn reconnects_after_the_emulator_dies_and_marks_the_gap() {
    let dir = scratch("reconnect");
    let mut cfg = EmuConfig::new(dir.join("tactile0"));
    cfg.epoch = SystemTime::now();
    let emu = Emulator::spawn(cfg.clone()).unwrap();
    let csv = dir.join("rec.csv");
    let mut child = Command::new(env!("CARGO_BIN_EXE_tactile"))
        .args(["log", "-q", "-p"])
        .arg(&cfg.link)
        .arg("-o")
        .arg(&csv)
        .args(["--duration", "4", "--reconnect-for", "10"])
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    let sent_before = emu
        .stats
        .frames_sent
        .load(std::sync::atomic::Ordering::Relaxed);
    emu.kill();
    std::thread::sleep(Duration::from_millis(700));
    let emu2 = Emulator::spawn(cfg.clone()).unwrap();
    let status = child.wait().unwrap();
    drop(emu2);
    assert!(status.success(), "tactile log failed: {status}");
    assert!(
        sent_before > 50,
        "emulator streamed only {sent_before} frames before the kill"
    );

    let (_, v) = verify_file(&csv, &cfg).expect("the CSV follows the contract");
    let codes: Vec<u32> = v.gaps.iter().map(|g| g.0).collect();
    assert!(
        codes.contains(&(gap_code::DISCONNECTED as u32)),
        "no disconnection marked: {:?}",
        v.gaps
    );
    let reconnected = v
        .gaps
        .iter()
        .find(|g| g.0 == gap_code::RECONNECTED as u32)
        .expect("reconnection marked");
    // The device clock ran on during the 0.7 s outage: about 70 frames of 10 ms are missing.
    let missing = reconnected
        .1
        .expect("the restarted device continued its sequence");
    assert!((40..400).contains(&missing), "missing {missing}");
    assert!(v.samples > 2000, "only {} samples", v.samples);

    // The MCAP file was finished properly and replays to exactly the same data rows.
    let mcap = dir.join("rec.mcap");
    let r = recover(&mcap).unwrap();
    assert!(r.truncated.is_none(), "{:?}", r.truncated);
    // What Foxglove needs: a summary with chunk indexes, ros2msg schemas declared in the file,
    // CDR messages. Every sample is decoded with the `mcap` crate through its declared schema.
    let bytes = std::fs::read(&mcap).unwrap();
    let summary = mcap::Summary::read(&bytes)
        .unwrap()
        .expect("a summary section");
    assert!(!summary.chunk_indexes.is_empty());
    assert_eq!(summary.channels.len(), 3);
    for schema in summary.schemas.values() {
        assert_eq!(schema.encoding, "ros2msg");
    }
    assert_eq!(decoded_samples(&bytes) as usize, v.samples);
    let out = dir.join("replayed.csv");
    replay(Path::new(env!("CARGO_BIN_EXE_tactile")), &mcap, &out);
    let (_, v2) = verify_file(&out, &cfg).unwrap();
    assert_eq!(
        (v2.samples, v2.first_seq, v2.last_seq),
        (v.samples, v.first_seq, v.last_seq)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Decode every CDR message of an MCAP file through the schema its channel declares (the schema
/// text parsed, not offsets known in advance); the number of samples (one message per frame,
/// an array element per sample), whose times must be the recording's origin plus their `t_s`
/// (a message is logged at its first sample's).
fn decoded_samples(bytes: &[u8]) -> u64 {
    use host::logger::cdr::{decode, parse_schema};
    let (mut samples, mut origin) = (0u64, None::<f64>);
    for m in mcap::MessageStream::new(bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.message_encoding != "cdr" {
            continue;
        }
        let schema = m.channel.schema.as_ref().expect("a declared schema");
        let fields = parse_schema(std::str::from_utf8(&schema.data).unwrap()).unwrap();
        let v = decode(&fields, &m.data).unwrap();
        assert_eq!(v.len(), fields.len());
        if !m.channel.topic.ends_with("/sample") {
            continue;
        }
        let get = |name: &str| v.iter().find(|(n, _)| n == name).unwrap().1.nums();
        let t_s = get("t_s");
        for name in [
            "t_device_s",
            "fz_v",
            "mx_v",
            "my_v",
            "fz_n",
            "mx_nm",
            "my_nm",
        ] {
            let x = get(name);
            assert_eq!(x.len(), t_s.len(), "{name}: one element per sample");
            assert!(x.iter().all(|x| x.is_finite()), "{name}");
        }
        assert!(get("t_host_s")[0] > 1e9, "a Unix time");
        assert!(t_s.windows(2).all(|w| w[0] <= w[1]), "t_s never decreases");
        samples += t_s.len() as u64;
        let o = m.log_time as f64 * 1e-9 - t_s[0];
        let o0 = *origin.get_or_insert(o);
        assert!((o - o0).abs() < 1e-5, "log time off t_s by {} s", o - o0);
    }
    samples
}
