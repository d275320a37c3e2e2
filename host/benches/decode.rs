//! Decode throughput: the host's fast path (`host::decode::FastDecoder`: memchr, block-wise
//! COBS without an extra copy, hardware CRC-32C, fixed-offset sample parsing) against the plain
//! pipeline a first implementation would write with the same crates the protocol uses (split on
//! 0, `cobs::decode_vec`, `crc::Crc<u32>` CRC-32C with its default table, `Message::decode_body`),
//! on the same bytes, in the same run. Run: `cargo bench -p host --bench decode`.

use std::hint::black_box;
use std::time::{Duration, Instant};

use host::decode::FastDecoder;
use protocol::{Message, NullState, Outcome, Sample, SampleFrame, Status, CRC_LEN};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Full sample frames (16 samples, 168 bytes) of random codes: about 16.8 MB.
fn stream(frames: usize) -> Vec<u8> {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut out = Vec::with_capacity(frames * 168);
    for seq in 0..frames as u32 {
        let status = Status { null_state: NullState::Nulled, config_epoch: 3, ..Status::default() };
        let mut f = SampleFrame::new(seq, seq.wrapping_mul(16_000), status, rng.random_range(-(1 << 23)..(1 << 23)));
        for _ in 0..16 {
            let ch = [0; 3].map(|_: i32| rng.random_range(-(1 << 23)..(1 << 23)));
            let _ = f.push(Sample { ch });
        }
        out.extend(protocol::encode_vec(&Message::Sample(f)).expect("encodable"));
    }
    out
}

/// Samples found by the host path; reads the stream in 64 KiB pieces like the driver.
fn fast(bytes: &[u8]) -> u64 {
    let mut d = FastDecoder::new();
    let mut samples = 0u64;
    for chunk in bytes.chunks(64 * 1024) {
        d.feed(chunk, |j| {
            if let Outcome::Message(Message::Sample(f)) = j.outcome {
                samples += f.len() as u64;
            }
        });
    }
    samples
}

/// Samples found by the plain pipeline.
fn plain(bytes: &[u8]) -> u64 {
    let crc = crc::Crc::<u32>::new(&crc::CRC_32_ISCSI);
    let mut samples = 0u64;
    for frame in bytes.split(|b| *b == 0).filter(|f| !f.is_empty()) {
        let Ok(decoded) = cobs::decode_vec(frame) else { continue };
        if decoded.len() <= CRC_LEN {
            continue;
        }
        let (body, tail) = decoded.split_at(decoded.len() - CRC_LEN);
        if crc.checksum(body) != u32::from_le_bytes([tail[0], tail[1], tail[2], tail[3]]) {
            continue;
        }
        if let Ok(Message::Sample(f)) = Message::decode_body(body) {
            samples += f.len() as u64;
        }
    }
    samples
}

/// Best of several timed runs (the machine is shared), in GB/s.
fn throughput(bytes: &[u8], f: fn(&[u8]) -> u64) -> (f64, u64) {
    let mut best = Duration::MAX;
    let mut samples = 0;
    let t_end = Instant::now() + Duration::from_secs(3);
    let mut runs = 0;
    while runs < 5 || (Instant::now() < t_end && runs < 50) {
        let t = Instant::now();
        samples = black_box(f(black_box(bytes)));
        best = best.min(t.elapsed());
        runs += 1;
    }
    (bytes.len() as f64 / best.as_secs_f64() / 1e9, samples)
}

fn main() {
    // `cargo bench` passes --bench; `cargo test --benches` runs this once quickly.
    let quick = !std::env::args().any(|a| a == "--bench");
    let bytes = stream(if quick { 2_000 } else { 100_000 });
    let (gbs_fast, n_fast) = throughput(&bytes, fast);
    let (gbs_plain, n_plain) = throughput(&bytes, plain);
    assert_eq!(n_fast, n_plain, "both paths must decode the same samples");
    println!("decode benchmark: {} MB of 168-byte sample frames, {} samples", bytes.len() / 1_000_000, n_fast);
    println!("host fast path (memchr + block COBS + crc32c + fixed parse): {gbs_fast:.3} GB/s");
    println!("plain cobs + crc pipeline (split, cobs::decode_vec, crc Table<1>, decode_body): {gbs_plain:.3} GB/s");
    println!("ratio: {:.2}x (goal: >= 1 GB/s and >= 2x)", gbs_fast / gbs_plain);
}
