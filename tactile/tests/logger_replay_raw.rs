//! `tactile replay` of a raw serial capture: the info frame gives the scale, damaged bytes are
//! counted and skipped, a lost frame becomes a gap row, and every sample is the encoded truth.

use std::process::Command;

use hil::check::{scratch, verify};
use hil::emu::{info_for, truth_frame, EmuConfig};
use host::device::Scale;
use protocol::{Message, Status};
use recording::read as read_recording;

/// Index of the last byte of an encoded frame that is data, not a COBS length byte, and that
/// a flip of bit 2 does not turn into a delimiter.
fn data_byte(wire: &[u8]) -> usize {
    let mut codes = Vec::new();
    let mut p = 0;
    while p < wire.len() - 1 {
        codes.push(p);
        p += usize::from(wire[p]);
    }
    (1..wire.len() - 1)
        .rev()
        .find(|i| !codes.contains(i) && wire[*i] != 0x04)
        .unwrap()
}

#[test]
fn a_raw_capture_with_damage_replays_to_a_valid_recording() {
    let dir = scratch("raw");
    let cfg = EmuConfig::new(dir.join("unused"));
    let info = info_for(&cfg);
    let mut bytes = vec![0x13, 0x37, 0x00]; // line noise before the first delimiter
    bytes.extend(protocol::encode_vec(&Message::Info(info.clone())).unwrap());
    for seq in 100..400u32 {
        let mut wire = protocol::encode_vec(&Message::Sample(truth_frame(
            seq,
            cfg.batch,
            cfg.rate_hz,
            Status::default(),
        )))
        .unwrap();
        match seq {
            150 => continue,                 // lost on the link
            200 => wire[10] ^= 0x04,         // a bit flip: CRC error, frame lost
            250 => bytes.extend([7u8; 300]), // garbage run: overflow, then the next frame resyncs
            300 => {
                // A flipped data bit (not a COBS length byte): the CRC catches it.
                let i = data_byte(&wire);
                wire[i] ^= 0x04;
            }
            _ => {}
        }
        bytes.extend(wire);
    }
    let cap = dir.join("capture.bin");
    std::fs::write(&cap, &bytes).unwrap();
    let out = dir.join("r.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_tactile"))
        .arg("replay")
        .arg(&cap)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    // The line noise and the flip at frame 200 (it lands on a COBS length byte) are malformed
    // frames, the data flip at frame 300 a CRC error, the garbage run an overflow.
    assert!(
        err.contains("1 CRC errors, 2 malformed, 1 overflows") && err.contains("4 gaps"),
        "{err}"
    );
    let rec = read_recording(&out).unwrap();
    let scale = Scale::from_info(&info);
    let v = verify(
        &rec,
        usize::from(cfg.batch),
        cfg.rate_hz,
        scale.volts_per_code[0],
    )
    .unwrap();
    assert_eq!((v.first_seq, v.last_seq), (100, 399));
    // 300 frames sent, 4 lost (150 dropped, 200 and 300 corrupted, 250 swallowed by garbage).
    assert_eq!(v.frames, 296);
    assert_eq!(v.gaps, vec![(1, Some(1)); 4]);
    let _ = std::fs::remove_dir_all(&dir);
}
