//! A million damaged streams through the accumulator: no panic, no corrupted frame accepted,
//! and every frame that arrives intact after damage is decoded (resync within one frame).
//!
//! Each stream is a run of valid frames with one kind of damage applied: bit flips, dropped
//! bytes, duplicated bytes, inserted garbage, a truncated frame, or pure garbage. A frame counts
//! as intact when its own bytes and the delimiter in front of it arrive unchanged; those must all
//! be decoded, and nothing else may be accepted except an unchanged original.

mod common;

use common::random;
use protocol::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const STREAMS: usize = 1_000_000;
const FRAMES_PER_STREAM: usize = 3;

#[derive(Clone, Copy, Debug)]
enum Damage {
    None,
    BitFlips,
    DropBytes,
    DuplicateBytes,
    InsertGarbage,
    Truncate,
    PureGarbage,
}

const KINDS: [Damage; 7] = [
    Damage::None,
    Damage::BitFlips,
    Damage::DropBytes,
    Damage::DuplicateBytes,
    Damage::InsertGarbage,
    Damage::Truncate,
    Damage::PureGarbage,
];

/// The stream's bytes, each tagged with the frame it belongs to (delimiters belong to the frame
/// they end) and whether it was altered.
struct Stream {
    bytes: Vec<u8>,
    owner: Vec<Option<usize>>,
    altered: Vec<bool>,
}

fn build(rng: &mut ChaCha8Rng, msgs: &[Message]) -> Stream {
    // A leading delimiter, as after an idle line: the first frame is then resynchronised too.
    let mut s = Stream {
        bytes: vec![0],
        owner: vec![None],
        altered: vec![false],
    };
    for (i, m) in msgs.iter().enumerate() {
        for b in encode_vec(m).unwrap() {
            s.bytes.push(b);
            s.owner.push(Some(i));
            s.altered.push(false);
        }
    }
    let _ = rng;
    s
}

fn damage(rng: &mut ChaCha8Rng, s: &mut Stream, kind: Damage) {
    let len = s.bytes.len();
    match kind {
        Damage::None => {}
        Damage::BitFlips => {
            for _ in 0..rng.random_range(1..=3) {
                let at = rng.random_range(1..len);
                s.bytes[at] ^= 1 << rng.random_range(0..8);
                s.altered[at] = true;
            }
        }
        Damage::DropBytes => {
            for _ in 0..rng.random_range(1..=3) {
                let at = rng.random_range(1..s.bytes.len());
                mark_neighbours(s, at);
                s.bytes.remove(at);
                s.owner.remove(at);
                s.altered.remove(at);
            }
        }
        Damage::DuplicateBytes => {
            let at = rng.random_range(1..len);
            let b = s.bytes[at];
            s.altered[at] = true;
            s.bytes.insert(at, b);
            s.owner.insert(at, s.owner[at]);
            s.altered.insert(at, true);
        }
        Damage::InsertGarbage => {
            let at = rng.random_range(1..len);
            let n = rng.random_range(1..40);
            mark_neighbours(s, at);
            for _ in 0..n {
                s.bytes.insert(at, rng.random());
                s.owner.insert(at, None);
                s.altered.insert(at, true);
            }
        }
        Damage::Truncate => {
            // Cut the tail of one frame, its delimiter included: a unplugged cable mid-frame.
            let frame = rng.random_range(0..FRAMES_PER_STREAM);
            let idx: Vec<usize> = (0..len).filter(|&i| s.owner[i] == Some(frame)).collect();
            let keep = rng.random_range(0..idx.len());
            let (from, to) = (idx[keep], idx[idx.len() - 1]);
            if from > 0 {
                s.altered[from - 1] = true;
            }
            s.bytes.drain(from..=to);
            s.owner.drain(from..=to);
            s.altered.drain(from..=to);
        }
        Damage::PureGarbage => {
            let n = rng.random_range(1..600);
            s.bytes = (0..n).map(|_| rng.random()).collect();
            s.owner = vec![None; n];
            s.altered = vec![true; n];
        }
    }
}

/// Removing or inserting at `at` alters the frames on both sides of the gap.
fn mark_neighbours(s: &mut Stream, at: usize) {
    s.altered[at] = true;
    if at > 0 {
        s.altered[at - 1] = true;
    }
}

/// Frames that arrive with every byte unaltered and an unaltered delimiter right before them.
fn intact_frames(s: &Stream) -> Vec<usize> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < s.bytes.len() {
        let Some(f) = s.owner[i] else {
            i += 1;
            continue;
        };
        let start = i;
        while i < s.bytes.len() && s.owner[i] == Some(f) {
            i += 1;
        }
        let whole = s.bytes[i - 1] == 0 && !s.altered[start..i].iter().any(|a| *a);
        let led_in = start > 0 && s.bytes[start - 1] == 0 && !s.altered[start - 1];
        if whole && led_in {
            out.push(f);
        }
    }
    out
}

#[derive(Default, Debug)]
struct Counts {
    frames_sent: u64,
    frames_intact: u64,
    accepted: u64,
    crc_errors: u64,
    malformed: u64,
    overflows: u64,
}

#[test]
fn a_million_damaged_streams() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x07AC_711E);
    let mut counts = Counts::default();
    let mut acc = Accumulator::new();
    for n in 0..STREAMS {
        let msgs: Vec<Message> = (0..FRAMES_PER_STREAM)
            .map(|_| random::message(&mut rng))
            .collect();
        let mut s = build(&mut rng, &msgs);
        let kind = KINDS[n % KINDS.len()];
        damage(&mut rng, &mut s, kind);
        let expected = intact_frames(&s);

        acc.reset();
        let chunk = rng.random_range(1..=64);
        let mut accepted = Vec::new();
        for c in s.bytes.chunks(chunk) {
            for o in acc.feed(c) {
                match o {
                    Outcome::Message(m) => accepted.push(m),
                    Outcome::CrcError => counts.crc_errors += 1,
                    Outcome::Malformed(_) => counts.malformed += 1,
                    Outcome::Overflow => counts.overflows += 1,
                }
            }
        }
        // No false accept: what was accepted is a subsequence of what was sent, in order.
        let mut sent = msgs.iter();
        for m in &accepted {
            assert!(
                sent.any(|s| s == m),
                "stream {n} ({kind:?}): accepted a message that was not sent: {m:?}"
            );
        }
        // Resync within one frame: every intact frame is decoded.
        for f in &expected {
            assert!(
                accepted.contains(&msgs[*f]),
                "stream {n} ({kind:?}): intact frame {f} lost"
            );
        }
        counts.frames_sent += FRAMES_PER_STREAM as u64;
        counts.frames_intact += expected.len() as u64;
        counts.accepted += accepted.len() as u64;
    }
    println!("robustness: {STREAMS} streams, {counts:?}");
    assert!(counts.crc_errors > 0 && counts.malformed > 0 && counts.overflows > 0);
}
