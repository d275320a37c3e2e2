//! The fault-injecting link against the protocol's decoder: over 100,000 frames (the long run is
//! `cargo test -p sim --release --test link_faults -- --ignored`, a million frames), every
//! corrupted frame is rejected and counted, none is accepted, every intact frame is decoded
//! (resync within one frame), and the decoder's counts equal the link's injected counts.

use std::time::Duration;

use protocol::{
    encode_vec, Accumulator, Message, Outcome, Sample, SampleFrame, Status, CODE_MAX, CODE_MIN,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use sim::link::{FaultRates, FaultyLink, Injected};

fn frame(seq: u32, rng: &mut ChaCha8Rng) -> Message {
    let mut f = SampleFrame::new(seq, seq.wrapping_mul(16_000), Status::default(), 100);
    for _ in 0..rng.random_range(1..=16) {
        let mut ch = [0; 3];
        for v in &mut ch {
            *v = rng.random_range(CODE_MIN..=CODE_MAX);
        }
        f.push(Sample { ch }).unwrap();
    }
    Message::Sample(f)
}

#[derive(Debug, Default)]
struct Received {
    accepted: u64,
    rejected: u64,
    lost_by_seq: u64,
    /// Accepted frames that came right after one or more rejected units.
    resyncs: u64,
}

fn run(frames: u32, rates: FaultRates, seed: u64) -> (Injected, Received) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut link = FaultyLink::new(rates, seed ^ 0x5EED);
    let mut acc = Accumulator::new();
    let mut got = Received::default();
    let mut sent: Vec<Message> = Vec::new();
    let mut next_seq = 0u32;
    let mut damaged = false;
    let mut wire = vec![0u8];
    let mut out = Vec::new();
    for seq in 0..frames {
        let msg = frame(seq, &mut rng);
        wire.extend(encode_vec(&msg).unwrap());
        sent.push(msg);
        if wire.len() < 4096 && seq + 1 < frames {
            continue;
        }
        out.clear();
        let _stall = link.transmit(&wire, &mut out);
        wire.clear();
        for chunk in out.chunks(rng.random_range(1..512)) {
            for outcome in acc.feed(chunk) {
                match outcome {
                    Outcome::Message(Message::Sample(f)) => {
                        let original = &sent[f.seq as usize];
                        assert_eq!(
                            &Message::Sample(f.clone()),
                            original,
                            "accepted a corrupted frame"
                        );
                        assert!(f.seq >= next_seq, "frame {} out of order or twice", f.seq);
                        got.lost_by_seq += u64::from(f.seq - next_seq);
                        next_seq = f.seq + 1;
                        got.accepted += 1;
                        got.resyncs += u64::from(std::mem::take(&mut damaged));
                    }
                    Outcome::Message(other) => panic!("accepted a message never sent: {other:?}"),
                    Outcome::CrcError | Outcome::Malformed(_) | Outcome::Overflow => {
                        got.rejected += 1;
                        damaged = true;
                    }
                }
            }
        }
    }
    // Frames lost after the last accepted one.
    got.lost_by_seq += u64::from(frames - next_seq);
    (link.injected(), got)
}

fn check(frames: u32, rate: f64, seed: u64) {
    let (injected, got) = run(
        frames,
        FaultRates::uniform(rate, Duration::from_millis(5)),
        seed,
    );
    println!(
        "link faults, {frames} frames at rate {rate}: injected {injected:?}; received {got:?}"
    );
    assert_eq!(injected.frames_in, u64::from(frames));
    assert_eq!(
        got.accepted, injected.frames_delivered,
        "every intact frame decoded"
    );
    assert_eq!(
        got.lost_by_seq, injected.frames_lost,
        "lost frames as injected"
    );
    assert_eq!(
        got.rejected, injected.junk_units,
        "every junk unit rejected and counted"
    );
    assert_eq!(
        got.resyncs, injected.recoveries,
        "back on good frames where the link is"
    );
    assert!(injected.frames_lost > 0 && injected.junk_units > 0);
}

#[test]
fn hundred_thousand_frames_through_a_faulty_link() {
    check(100_000, 0.01, 1);
    check(20_000, 0.2, 2);
}

#[test]
fn a_clean_link_delivers_everything() {
    let (injected, got) = run(5_000, FaultRates::NONE, 3);
    assert_eq!(injected.frames_delivered, 5_000);
    assert_eq!(
        (got.accepted, got.rejected, got.lost_by_seq, got.resyncs),
        (5_000, 0, 0, 0)
    );
}

#[test]
#[ignore = "a million frames; run with --release --ignored"]
fn a_million_frames_through_a_faulty_link() {
    check(1_000_000, 0.01, 4);
}
