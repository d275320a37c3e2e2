//! Two sensors logged at once, a test machine's export merged by cross-correlation, and the
//! plots drawn from the merged recording.

use std::process::Command;

use hil::check::scratch;
use hil::emu::{EmuConfig, Emulator};
use host::logger::reference::interpolate;
use recording::read as read_recording;

fn tactile(args: &[&std::ffi::OsStr]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_tactile"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn two_sensors_then_reference_merge_then_plots() {
    let dir = scratch("multi");
    let (a, b) = (
        EmuConfig::new(dir.join("ttyA")),
        EmuConfig::new(dir.join("ttyB")),
    );
    let _ea = Emulator::spawn(a.clone()).unwrap();
    let _eb = Emulator::spawn(b.clone()).unwrap();
    let out = dir.join("rec.csv");
    let o = tactile(&[
        "log".as_ref(),
        "-q".as_ref(),
        "-d".as_ref(),
        "1.5".as_ref(),
        "-p".as_ref(),
        a.link.as_os_str(),
        "-p".as_ref(),
        b.link.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv_a = dir.join(format!(
        "rec-{}.csv",
        dir.join("ttyA")
            .to_string_lossy()
            .replace(|c: char| !c.is_ascii_alphanumeric(), "_")
            .trim_matches('_')
    ));
    let rec_a = read_recording(&csv_a).expect("one CSV per sensor");
    assert!(rec_a.channels.len() > 1000);
    // One MCAP, two sensors: replay needs to be told which.
    let mcap = dir.join("rec.mcap");
    let o = tactile(&["replay".as_ref(), mcap.as_os_str()]);
    assert_eq!(o.status.code(), Some(65));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--sensor"));

    // A machine export that lags the sensor by 0.3 s: load = 0.9·Fz + 1 N, rod = 0.01·t.
    let t = rec_a.column("t_s").unwrap();
    let fz = rec_a.column("fz_N").unwrap();
    let mut machine = String::from("time_s,position_mm,force_N\n");
    let mut tm = -0.5;
    while tm < 3.0 {
        if let Some(f) = interpolate(t, fz, tm - 0.3) {
            machine.push_str(&format!("{tm:.3},{:.5},{:.6}\n", 0.01 * tm, 0.9 * f + 1.0));
        }
        tm += 0.005;
    }
    let machine_csv = dir.join("machine.csv");
    std::fs::write(&machine_csv, machine).unwrap();
    let merged = dir.join("merged.csv");
    let o = tactile(&[
        "replay".as_ref(),
        mcap.as_os_str(),
        "--sensor".as_ref(),
        "ttyA".as_ref(),
        "-o".as_ref(),
        merged.as_os_str(),
        "--reference".as_ref(),
        machine_csv.as_os_str(),
        "--xcorr-max-lag-s".as_ref(),
        "0.8".as_ref(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m = read_recording(&merged).unwrap();
    let reference = m
        .meta
        .get("reference")
        .expect("merge noted in the metadata");
    let offset: f64 = reference
        .split("offset ")
        .nth(1)
        .and_then(|s| s.trim_end_matches(" s)").parse().ok())
        .unwrap();
    // Replay starts its clock at the first frame, the live log at its start: the machine's
    // 0.3 s lag is seen through that difference.
    let expected = 0.3 + t[0] - m.channels.t_s[0];
    assert!(
        (offset - expected).abs() < 0.011,
        "offset {offset}, expected {expected}"
    );
    let (load, fz) = (&m.channels.load_n, m.column("fz_N").unwrap());
    let worst = load
        .iter()
        .zip(fz)
        .filter(|(l, _)| l.is_finite())
        .map(|(l, f)| (l - (0.9 * f + 1.0)).abs())
        .fold(0.0, f64::max);
    assert!(
        worst < 0.5,
        "merged load off by {worst} N ({})",
        merged.display()
    );

    let prefix = dir.join("plot");
    let o = tactile(&[
        "plot".as_ref(),
        merged.as_os_str(),
        "-o".as_ref(),
        prefix.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for name in [
        "plot-time.png",
        "plot-time.svg",
        "plot-load.png",
        "plot-load.svg",
    ] {
        let bytes = std::fs::read(dir.join(name)).unwrap_or_else(|_| panic!("{name} not written"));
        assert!(bytes.len() > 1000, "{name} too small");
        if name.ends_with(".png") {
            assert_eq!(&bytes[..4], b"\x89PNG");
        } else {
            assert!(String::from_utf8_lossy(&bytes).contains("<svg"));
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
