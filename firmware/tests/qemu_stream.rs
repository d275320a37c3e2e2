//! The QEMU board binary, end to end at the byte level: QEMU `mps2-an386` runs the release ELF
//! with UART0 on stdio; the test sends requests, decodes the frames, and checks them against the
//! stimulus recomputed here. Needs `qemu-system-arm` and the thumb ELF, so it is ignored by default
//! and run by `scripts/test-firmware.sh` (which builds the ELF first).

#![allow(clippy::needless_range_loop)]

use std::io::{Read, Write};
use std::process::{Command as Process, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use firmware::params::ADC_VREF_V;
use protocol::codes::volts_to_code;
use protocol::{
    encode_vec, Accumulator, Command, Message, NullState, Outcome, Reply, Request, SampleFrame,
};
use sim::ads131m04::stimulus::{Stimulus, StimulusParams};

/// The code the QEMU board's emulated chip (reference `adc.toml`'s, PGA 1) gives `v` volts.
fn ideal_code(v: f32) -> i32 {
    volts_to_code(f64::from(v), ADC_VREF_V, 1)
}

const ELF: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/target/thumbv7em-none-eabihf/release/qemu-mps2-an386"
);

fn send(stdin: &mut impl Write, tag: u8, command: Command) {
    stdin
        .write_all(&encode_vec(&Message::Request(Request { tag, command })).unwrap())
        .unwrap();
    stdin.flush().unwrap();
}

#[test]
#[ignore = "needs qemu-system-arm and the thumb release ELF: run by scripts/test-firmware.sh"]
fn qemu_board_streams_the_stimulus_and_obeys_commands() {
    let mut qemu = Process::new("qemu-system-arm")
        .args([
            "-machine",
            "mps2-an386",
            "-cpu",
            "cortex-m4",
            "-display",
            "none",
            "-monitor",
            "none",
        ])
        .args([
            "-serial",
            "stdio",
            "-icount",
            "shift=0,sleep=off",
            "-kernel",
            ELF,
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("start qemu-system-arm");
    let mut stdin = qemu.stdin.take().unwrap();
    let mut stdout = qemu.stdout.take().unwrap();
    let (tx, rx) = mpsc::channel::<Vec<u8>>();
    std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n) = stdout.read(&mut buf) {
            if n == 0 || tx.send(buf[..n].to_vec()).is_err() {
                break;
            }
        }
    });
    let mut acc = Accumulator::new();
    let mut frames: Vec<SampleFrame> = Vec::new();
    let mut replies: Vec<Reply> = Vec::new();
    let mut collect = |until: &dyn Fn(&[SampleFrame], &[Reply]) -> bool,
                       frames: &mut Vec<SampleFrame>,
                       replies: &mut Vec<Reply>| {
        let deadline = Instant::now() + Duration::from_secs(60);
        while !until(frames, replies) {
            assert!(
                Instant::now() < deadline,
                "timed out: {} frames, replies {replies:?}",
                frames.len()
            );
            let Ok(bytes) = rx.recv_timeout(Duration::from_millis(200)) else {
                continue;
            };
            for outcome in acc.feed(&bytes) {
                match outcome {
                    Outcome::Message(Message::Sample(f)) => frames.push(f),
                    Outcome::Message(Message::Reply(r)) => replies.push(r),
                    Outcome::Message(_) => {}
                    other => panic!("bad frame from the device: {other:?}"),
                }
            }
        }
    };
    send(&mut stdin, 1, Command::Ping { nonce: 0xC0FFEE });
    send(&mut stdin, 2, Command::Start);
    collect(&|f, _| f.len() >= 200, &mut frames, &mut replies);
    assert_eq!(
        replies[..2],
        [
            Reply::Pong {
                tag: 1,
                nonce: 0xC0FFEE
            },
            Reply::Ack {
                tag: 2,
                opcode: protocol::opcode::START
            }
        ]
    );
    // Null at power-up against the stimulus, then raw (untared) codes of the nulled channels.
    let nulled: Vec<&SampleFrame> = frames
        .iter()
        .filter(|f| f.status.null_state == NullState::Nulled)
        .collect();
    assert!(
        nulled.len() > 100,
        "the power-up null must finish within the rest period"
    );
    assert!(
        frames
            .windows(2)
            .all(|w| w[1].seq == w[0].seq.wrapping_add(1)),
        "no frame lost on stdio"
    );
    let stim = Stimulus::new(StimulusParams::QEMU_BOARD);
    // Residual after nulling: offset − 3e-4·(code − 2048) with the codes found by the search
    // (host test `null_tare_and_stream_the_stimulus`: 3215, 1215, 2715).
    let mut trimmed = Stimulus::new(StimulusParams::QEMU_BOARD);
    trimmed.trim_codes = [3215, 1215, 2715, 2048];
    let mut checked = 0;
    for f in nulled.iter().skip(1) {
        let n0 = u64::from(f.t_us / 1000);
        for (k, s) in f.samples().iter().enumerate() {
            let v = trimmed.volts(n0 + k as u64);
            for ch in 0..3 {
                assert_eq!(
                    s.ch[ch],
                    ideal_code(v[ch]),
                    "sample {} ch {ch}",
                    n0 + k as u64
                );
            }
            checked += 1;
        }
        assert_eq!(f.temp, ideal_code(stim.volts(n0)[3]));
    }
    assert!(checked > 1000);
    // Tare at rest and a filter change: acked, and visible from a later frame's epoch on.
    let epoch = frames.last().unwrap().status.config_epoch;
    send(&mut stdin, 3, Command::Tare { samples: 32 });
    send(&mut stdin, 4, Command::SetRate { hz: 1234 });
    collect(
        &|f, r| r.len() >= 4 && f.last().is_some_and(|f| f.status.tare_active),
        &mut frames,
        &mut replies,
    );
    assert_eq!(
        replies[2],
        Reply::Ack {
            tag: 3,
            opcode: protocol::opcode::TARE
        }
    );
    assert_eq!(
        replies[3],
        Reply::Nack {
            tag: 4,
            opcode: protocol::opcode::SET_RATE,
            code: protocol::NackCode::OutOfRange
        }
    );
    assert_eq!(
        frames.last().unwrap().status.config_epoch,
        epoch.wrapping_add(1)
    );
    // A valid rate change: acked, and the frames after it are 16 samples at 2 kSPS = 8 ms apart.
    let epoch = frames.last().unwrap().status.config_epoch;
    send(&mut stdin, 5, Command::SetRate { hz: 2000 });
    let after = move |f: &SampleFrame| f.status.config_epoch == epoch.wrapping_add(1);
    collect(
        &|f, r| r.len() >= 5 && f.iter().filter(|x| after(x)).count() >= 3,
        &mut frames,
        &mut replies,
    );
    assert_eq!(
        replies[4],
        Reply::Ack {
            tag: 5,
            opcode: protocol::opcode::SET_RATE
        }
    );
    let fast: Vec<&SampleFrame> = frames.iter().filter(|x| after(x)).collect();
    assert_eq!(fast[2].t_us - fast[1].t_us, 8000);
    assert!(frames
        .windows(2)
        .all(|w| w[1].seq == w[0].seq.wrapping_add(1)));
    let _ = qemu.kill();
    let _ = qemu.wait();
}
