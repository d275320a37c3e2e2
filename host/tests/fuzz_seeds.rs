//! Writes the seed corpora of the `recording_csv` and `replay` fuzz targets (`fuzz/corpus/`):
//! `cargo test -p host --test fuzz_seeds -- --ignored`. Seeds: logger and replay output,
//! the contract's example and its variants, MCAP files (complete and cut as a killed logger
//! leaves them), raw captures (clean, damaged, truncated).

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::{Duration, UNIX_EPOCH};

use hil::check::scratch;
use hil::emu::{info_for, truth_frame, EmuConfig};
use host::device::{Event, Frame, Gap, GapKind};
use host::logger::mcap_io::McapSink;
use host::logger::{metadata, Recorder, Setup};
use protocol::{encode_vec, Message, Status};

const EXAMPLE: &str = "# format = tactile-recording/1\n# sample_rate_hz = 1000\n# contact_angle_deg = 20\n\
# azimuth_deg = 60\n# fingertip_radius_mm = 20\n# gain_fz = 3000\n# gain_mx = 1000\n# gain_my = 1000\n\
# excitation_V = 3.3\n# rod_speed_mm_per_min = 20\nt_s,rod_mm,load_N,fz_V,mx_V,my_V\n\
0.000,-0.500,0.000,0.0012,-0.0003,0.0001\n0.001,-0.500,0.000,0.0011,-0.0002,0.0000\n";

fn corpus(target: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fuzz/corpus")
        .join(target);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn setup() -> Setup {
    Setup::from_hardware("fuzz seed".into()).unwrap()
}

/// `n` frames of the emulator's truth, sequence numbers from 1, as the driver delivers them.
fn frames(cfg: &EmuConfig, n: u32) -> Vec<Frame> {
    (1..=n)
        .map(|seq| {
            let frame = truth_frame(seq, cfg.batch, cfg.rate_hz, Status::default());
            let mut raw = encode_vec(&Message::Sample(frame.clone())).unwrap();
            raw.pop();
            Frame {
                seq,
                t_device_us: u64::from(frame.t_us),
                host_time: UNIX_EPOCH
                    + Duration::from_secs(1_800_000_000)
                    + Duration::from_micros(u64::from(frame.t_us)),
                session: 0,
                frame,
                raw,
            }
        })
        .collect()
}

/// A logger run over `frames` with a gap in the middle: the CSV and the MCAP bytes.
fn logged(dir: &Path, cfg: &EmuConfig, frames: &[Frame]) -> (Vec<u8>, Vec<u8>) {
    let info = info_for(cfg);
    let (csv, mcap) = (dir.join("r.csv"), dir.join("r.mcap"));
    let start = frames[0].host_time;
    let sink = Rc::new(RefCell::new(McapSink::create(&mcap).unwrap()));
    let ch = sink
        .borrow_mut()
        .add_sensor("seed", &metadata(&info, &setup(), start).pairs())
        .unwrap();
    let mut rec = Recorder::create(&csv, &info, &setup(), start)
        .unwrap()
        .with_mcap((sink.clone(), ch));
    rec.on_event(&Event::Info(info.clone())).unwrap();
    for (i, f) in frames.iter().enumerate() {
        if i == frames.len() / 2 {
            let gap = GapKind::Reconnected {
                downtime: Duration::from_millis(30),
                missing: Some(0),
            };
            rec.on_event(&Event::Gap(Gap {
                kind: gap,
                host_time: f.host_time,
                session: 0,
            }))
            .unwrap();
        }
        rec.on_event(&Event::Frame(f.clone())).unwrap();
        rec.flush().unwrap(); // one chunk per frame: cut points between and inside chunks
    }
    rec.detach_mcap();
    drop(rec);
    Rc::try_unwrap(sink)
        .ok()
        .unwrap()
        .into_inner()
        .finish()
        .unwrap();
    (std::fs::read(csv).unwrap(), std::fs::read(mcap).unwrap())
}

fn raw_capture(cfg: &EmuConfig, frames: &[Frame]) -> Vec<u8> {
    let mut bytes = encode_vec(&Message::Info(info_for(cfg))).unwrap();
    for f in frames {
        bytes.extend(&f.raw);
        bytes.push(0);
    }
    bytes
}

#[test]
#[ignore = "writes the fuzz seed corpora: cargo test -p host --test fuzz_seeds -- --ignored"]
fn write_seed_corpora() {
    let dir = scratch("seeds");
    let mut cfg = EmuConfig::new(dir.join("unused"));
    cfg.batch = 4;
    let fr = frames(&cfg, 6);
    let (csv, mcap) = logged(&dir, &cfg, &fr);
    let csv_text = String::from_utf8(csv.clone()).unwrap();

    let rc = corpus("recording_csv");
    let mut seeds: Vec<(String, Vec<u8>)> = vec![
        ("example".into(), EXAMPLE.into()),
        ("example-crlf".into(), EXAMPLE.replace('\n', "\r\n").into()),
        ("example-bom".into(), format!("\u{feff}{EXAMPLE}").into()),
        (
            "example-gaps".into(),
            format!("{EXAMPLE}0.002,,nan,NaN,,\n0.003,1,2,3,4,5\n").into(),
        ),
        (
            "example-temp-extra".into(),
            EXAMPLE
                .replace("my_V\n", "my_V,temp_C,seq\n")
                .replace("0.0001\n", "0.0001,25.5,1\n")
                .replace("0.0000\n", "0.0000,,2\n")
                .into(),
        ),
        (
            "example-decreasing".into(),
            format!("{EXAMPLE}0.0005,0,0,0,0,0\n").into(),
        ),
        (
            "example-latin1".into(),
            [EXAMPLE.as_bytes(), b"# operator = Jos\xe9\n"].concat(),
        ),
        (
            "example-utf16".into(),
            [
                &b"\xff\xfe"[..],
                &EXAMPLE
                    .encode_utf16()
                    .flat_map(u16::to_le_bytes)
                    .collect::<Vec<u8>>(),
            ]
            .concat(),
        ),
        ("logger".into(), csv.clone()),
        ("empty".into(), Vec::new()),
        (
            "meta-only".into(),
            EXAMPLE
                .lines()
                .take(10)
                .collect::<Vec<_>>()
                .join("\n")
                .into(),
        ),
    ];
    for cut in [EXAMPLE.len() - 1, EXAMPLE.len() - 7, EXAMPLE.len() / 2, 40] {
        seeds.push((
            format!("example-cut{cut}"),
            EXAMPLE.as_bytes()[..cut].to_vec(),
        ));
    }
    for cut in [
        csv.len() - 1,
        csv.len() - 20,
        csv_text.find("t_s,").unwrap() + 30,
    ] {
        seeds.push((format!("logger-cut{cut}"), csv[..cut].to_vec()));
    }
    for (name, bytes) in &seeds {
        std::fs::write(rc.join(name), bytes).unwrap();
    }

    let rp = corpus("replay");
    let raw = raw_capture(&cfg, &fr);
    let mut damaged = raw.clone();
    let mid = damaged.len() / 2;
    damaged[mid] ^= 0x10;
    damaged.splice(mid / 2..mid / 2, [7u8; 40]);
    let mut seeds: Vec<(String, Vec<u8>)> = vec![
        ("mcap".into(), mcap.clone()),
        ("raw".into(), raw.clone()),
        ("raw-damaged".into(), damaged),
        (
            "raw-no-info".into(),
            raw_capture(&cfg, &fr)[raw.len() - fr[0].raw.len() * 2 - 2..].to_vec(),
        ),
    ];
    for k in 1..=8 {
        let cut = mcap.len() * k / 9;
        seeds.push((format!("mcap-cut{cut}"), mcap[..cut].to_vec()));
    }
    for cut in [raw.len() - 3, raw.len() / 3] {
        seeds.push((format!("raw-cut{cut}"), raw[..cut].to_vec()));
    }
    for (name, bytes) in &seeds {
        std::fs::write(rp.join(name), bytes).unwrap();
    }
    eprintln!(
        "seeds: csv {} bytes, mcap {} bytes, raw {} bytes",
        csv.len(),
        mcap.len(),
        raw.len()
    );
    let _ = std::fs::remove_dir_all(&dir);
}
