//! The host's fast receive path: the same outcomes as [`protocol::Accumulator`] (the property
//! tests of this module's `tests::equivalence` hold it to that), at memory speed.
//!
//! Why it is faster than the plain pipeline: delimiters are found with `memchr` (SIMD) instead
//! of a byte loop; frames that lie wholly inside the input are COBS-decoded straight from the
//! input into one reused scratch buffer (whole blocks with `copy_from_slice`, never byte by
//! byte); the CRC-32C runs on the SSE4.2 / ARMv8 CRC instruction (`crc32c` crate); sample frames
//! of the exact length are parsed without the generic field cursor. Only a frame that straddles
//! two reads is copied into the carry buffer first.

use protocol::{
    Code, Malformed, Message, NullState, Outcome, Sample, SampleFrame, Status, CRC_LEN, MAX_BATCH,
    MAX_ENCODED, SAMPLE_HEADER_LEN, SAMPLE_LEN,
};

/// One delimited frame as the fast decoder judged it, with its encoded bytes (COBS, without the
/// delimiter) for raw capture.
#[derive(Debug)]
pub struct Judged<'a> {
    pub outcome: Outcome,
    /// The encoded frame as received; empty for an [`Outcome::Overflow`] (its bytes are gone).
    pub raw: &'a [u8],
}

/// A streaming decoder that keeps the bytes of an unfinished frame between calls.
#[derive(Debug, Clone)]
pub struct FastDecoder {
    carry: Vec<u8>,
    overflowed: bool,
    scratch: Box<[u8; MAX_ENCODED]>,
}

impl Default for FastDecoder {
    fn default() -> Self {
        Self::new()
    }
}

impl FastDecoder {
    pub fn new() -> Self {
        Self {
            carry: Vec::with_capacity(MAX_ENCODED),
            overflowed: false,
            scratch: Box::new([0; MAX_ENCODED]),
        }
    }

    /// Forget any partial frame (after reopening a port).
    pub fn reset(&mut self) {
        self.carry.clear();
        self.overflowed = false;
    }

    /// Bytes of the frame currently being collected.
    pub fn pending(&self) -> usize {
        self.carry.len()
    }

    /// Feed received bytes; `sink` gets one [`Judged`] per completed frame, in order.
    pub fn feed(&mut self, mut input: &[u8], mut sink: impl FnMut(Judged<'_>)) {
        // Finish the frame begun in an earlier call, if any.
        if !self.carry.is_empty() || self.overflowed {
            let Some(end) = memchr::memchr(0, input) else {
                self.absorb(input);
                return;
            };
            self.absorb(&input[..end]);
            input = &input[end + 1..];
            let carry = std::mem::take(&mut self.carry);
            if std::mem::take(&mut self.overflowed) {
                sink(Judged {
                    outcome: Outcome::Overflow,
                    raw: &[],
                });
            } else if !carry.is_empty() {
                let outcome = judge(&carry, &mut self.scratch);
                sink(Judged {
                    outcome,
                    raw: &carry,
                });
            }
            self.carry = carry;
            self.carry.clear();
        }
        let mut frames = memchr::memchr_iter(0, input);
        let mut start = 0;
        for end in frames.by_ref() {
            let frame = &input[start..end];
            start = end + 1;
            if frame.is_empty() {
                continue;
            }
            let outcome = if frame.len() > MAX_ENCODED {
                Outcome::Overflow
            } else {
                judge(frame, &mut self.scratch)
            };
            let raw = if matches!(outcome, Outcome::Overflow) {
                &[][..]
            } else {
                frame
            };
            sink(Judged { outcome, raw });
        }
        self.absorb(&input[start..]);
    }

    fn absorb(&mut self, chunk: &[u8]) {
        if self.overflowed || chunk.is_empty() {
            return;
        }
        if self.carry.len() + chunk.len() > MAX_ENCODED {
            self.overflowed = true;
            self.carry.clear();
        } else {
            self.carry.extend_from_slice(chunk);
        }
    }
}

/// COBS-decode `src` (no zero inside) into `dst`, block by block; the same acceptance rule as
/// `cobs::decode_in_place` (a block may end exactly at the frame's end, not past it).
#[inline]
fn cobs_decode(src: &[u8], dst: &mut [u8; MAX_ENCODED]) -> Option<usize> {
    let end = src.len();
    let (mut si, mut di) = (0usize, 0usize);
    while si < end {
        let code = usize::from(src[si]);
        if si + code > end && code != 1 {
            return None;
        }
        let n = code - 1;
        dst.get_mut(di..di + n)?
            .copy_from_slice(&src[si + 1..si + code]);
        si += code;
        di += n;
        if code != 0xFF && si < end {
            *dst.get_mut(di)? = 0;
            di += 1;
        }
    }
    Some(di)
}

/// Judge one delimited, non-empty frame of at most [`MAX_ENCODED`] bytes.
#[inline]
fn judge(frame: &[u8], scratch: &mut [u8; MAX_ENCODED]) -> Outcome {
    let Some(decoded) = cobs_decode(frame, scratch) else {
        return Outcome::Malformed(Malformed::Cobs);
    };
    let Some(body_len) = decoded.checked_sub(CRC_LEN).filter(|n| *n > 0) else {
        return Outcome::Malformed(Malformed::Short);
    };
    let (body, crc) = scratch[..decoded].split_at(body_len);
    let expected = u32::from_le_bytes([crc[0], crc[1], crc[2], crc[3]]);
    if crc32c::crc32c(body) != expected {
        return Outcome::CrcError;
    }
    if let Some(frame) = parse_sample_frame(body) {
        return Outcome::Message(Message::Sample(frame));
    }
    match Message::decode_body(body) {
        Ok(msg) => Outcome::Message(msg),
        Err(m) => Outcome::Malformed(m),
    }
}

#[inline(always)]
fn i24(b: &[u8]) -> Code {
    i32::from_le_bytes([b[0], b[1], b[2], 0]) << 8 >> 8
}

/// The common case, a well-formed sample frame, read with fixed offsets. Anything unusual
/// returns `None` and goes to the protocol crate's parser, which names the fault.
#[inline]
fn parse_sample_frame(body: &[u8]) -> Option<SampleFrame> {
    if body.len() < SAMPLE_HEADER_LEN || body[0] != protocol::kind::SAMPLE {
        return None;
    }
    let n = usize::from(body[17]);
    if n == 0 || n > MAX_BATCH || body.len() != SAMPLE_HEADER_LEN + n * SAMPLE_LEN {
        return None;
    }
    let (saturated, flags) = (body[9], body[10]);
    if saturated & 0xF0 != 0 || flags & 0xC0 != 0 {
        return None;
    }
    let status = Status {
        saturated,
        null_state: match flags & 0b11 {
            0 => NullState::Off,
            1 => NullState::Searching,
            2 => NullState::Nulled,
            _ => NullState::Failed,
        },
        tare_active: flags & (1 << 2) != 0,
        drift_tracking: flags & (1 << 3) != 0,
        sample_overrun: flags & (1 << 4) != 0,
        adc_error: flags & (1 << 5) != 0,
        config_epoch: body[11],
        dropped: u16::from_le_bytes([body[12], body[13]]),
    };
    let seq = u32::from_le_bytes([body[1], body[2], body[3], body[4]]);
    let t_us = u32::from_le_bytes([body[5], body[6], body[7], body[8]]);
    let mut frame = SampleFrame::new(seq, t_us, status, i24(&body[14..17]));
    for s in body[SAMPLE_HEADER_LEN..].chunks_exact(SAMPLE_LEN) {
        // Cannot overflow: n <= MAX_BATCH was checked above.
        let _ = frame.push(Sample {
            ch: [i24(&s[0..3]), i24(&s[3..6]), i24(&s[6..9])],
        });
    }
    Some(frame)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outcomes(bytes: &[u8], split: usize) -> Vec<Outcome> {
        let mut d = FastDecoder::new();
        let mut out = Vec::new();
        let (a, b) = bytes.split_at(split.min(bytes.len()));
        d.feed(a, |j| out.push(j.outcome));
        d.feed(b, |j| out.push(j.outcome));
        out
    }

    #[test]
    fn decodes_a_sample_frame_split_anywhere() {
        let mut f = SampleFrame::new(7, 1000, Status::default(), -5);
        for k in 0..16 {
            f.push(Sample {
                ch: [k, -k, 1 << 22],
            })
            .unwrap();
        }
        let wire = protocol::encode_vec(&Message::Sample(f.clone())).unwrap();
        for split in 0..wire.len() {
            assert_eq!(
                outcomes(&wire, split),
                vec![Outcome::Message(Message::Sample(f.clone()))]
            );
        }
    }

    #[test]
    fn crc_error_overflow_and_cobs_faults_are_outcomes() {
        let wire =
            protocol::encode_vec(&Message::Reply(protocol::Reply::Ack { tag: 1, opcode: 2 }))
                .unwrap();
        let mut bad = wire.clone();
        bad[2] ^= 0x10;
        assert_eq!(outcomes(&bad, 3), vec![Outcome::CrcError]);
        let long = vec![1u8; MAX_ENCODED + 1];
        let mut stream = long.clone();
        stream.push(0);
        assert_eq!(outcomes(&stream, 100), vec![Outcome::Overflow]);
        assert_eq!(
            outcomes(&[9, 1, 0], 1),
            vec![Outcome::Malformed(Malformed::Cobs)]
        );
    }

    mod equivalence {
        //! The fast path must judge every stream exactly as `protocol::Accumulator` does:
        //! random valid traffic, damaged with flips, drops, insertions, truncations and
        //! garbage, fed in random pieces.
        use super::super::*;
        use proptest::prelude::*;
        use protocol::{Accumulator, Reply};
        use rand::{Rng, SeedableRng};
        use rand_chacha::ChaCha8Rng;

        fn code(rng: &mut impl Rng) -> Code {
            rng.random_range(protocol::CODE_MIN..=protocol::CODE_MAX)
        }

        fn message(rng: &mut impl Rng) -> Message {
            if rng.random_bool(0.8) {
                let status = Status {
                    saturated: rng.random_range(0..16),
                    null_state: NullState::Nulled,
                    tare_active: rng.random(),
                    drift_tracking: rng.random(),
                    sample_overrun: rng.random(),
                    adc_error: rng.random(),
                    config_epoch: rng.random(),
                    dropped: rng.random(),
                };
                let mut f = SampleFrame::new(rng.random(), rng.random(), status, code(rng));
                for _ in 0..rng.random_range(1..=MAX_BATCH) {
                    let _ = f.push(Sample {
                        ch: [code(rng), code(rng), code(rng)],
                    });
                }
                Message::Sample(f)
            } else {
                Message::Reply(Reply::Pong {
                    tag: rng.random(),
                    nonce: rng.random(),
                })
            }
        }

        /// A stream of frames with damage of every kind at random places.
        pub(crate) fn damaged_stream(seed: u64, frames: usize) -> Vec<u8> {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut out = Vec::new();
            for _ in 0..frames {
                let mut w = protocol::encode_vec(&message(&mut rng)).unwrap();
                match rng.random_range(0..12) {
                    0 => {
                        let i = rng.random_range(0..w.len());
                        w[i] ^= 1 << rng.random_range(0..8);
                    }
                    1 => {
                        let i = rng.random_range(0..w.len());
                        w.remove(i);
                    }
                    2 => {
                        let i = rng.random_range(0..w.len());
                        w.insert(i, rng.random());
                    }
                    3 => w.truncate(rng.random_range(0..w.len())),
                    4 => {
                        w.extend((0..rng.random_range(0..400)).map(|_| rng.random_range(1..=255u8)))
                    }
                    5 => w.extend((0..rng.random_range(0..40)).map(|_| rng.random::<u8>())),
                    _ => {}
                }
                out.extend(w);
            }
            out
        }

        fn reference(stream: &[u8], cuts: &[usize]) -> Vec<Outcome> {
            let mut acc = Accumulator::new();
            let mut out = Vec::new();
            let mut prev = 0;
            for &c in cuts.iter().chain(std::iter::once(&stream.len())) {
                out.extend(acc.feed(&stream[prev..c]));
                prev = c;
            }
            out
        }

        fn fast(stream: &[u8], cuts: &[usize]) -> Vec<Outcome> {
            let mut d = FastDecoder::new();
            let mut out = Vec::new();
            let mut prev = 0;
            for &c in cuts.iter().chain(std::iter::once(&stream.len())) {
                d.feed(&stream[prev..c], |j| out.push(j.outcome));
                prev = c;
            }
            out
        }

        proptest! {
            #![proptest_config(ProptestConfig::with_cases(256))]
            #[test]
            fn same_outcomes_as_the_accumulator(seed in any::<u64>(), frames in 1usize..60, cut_seed in any::<u64>()) {
                let stream = damaged_stream(seed, frames);
                let mut rng = ChaCha8Rng::seed_from_u64(cut_seed);
                let mut cuts: Vec<usize> = (0..rng.random_range(0..8)).map(|_| rng.random_range(0..=stream.len())).collect();
                cuts.sort_unstable();
                prop_assert_eq!(fast(&stream, &cuts), reference(&stream, &cuts));
            }

            #[test]
            fn same_outcomes_on_pure_garbage(bytes in proptest::collection::vec(any::<u8>(), 0..2000), cut in 0usize..2000) {
                let cuts = [cut.min(bytes.len())];
                prop_assert_eq!(fast(&bytes, &cuts), reference(&bytes, &cuts));
            }
        }
    }
}
