//! The fast path for the one message sent thousands of times a second: a sample frame encoded in
//! place, straight into the caller's buffer. Samples are written at their final wire position as
//! they arrive ([`SampleFrameEncoder::push`]); [`SampleFrameEncoder::finish`] writes the header,
//! computes the CRC-32C a word at a time and applies COBS in the same pass, in place: the body
//! already sits one byte into the buffer, where COBS puts it, so encoding only rewrites the zero
//! bytes (and the leading code byte) with distances. No intermediate body, no copy.
//!
//! The bytes are exactly those of [`crate::encode`] (SPEC.md, type 0x01; tests compare it with the
//! field-by-field writer on random frames). COBS here relies on a frame shorter than 254 bytes
//! (one COBS block), which every sample frame is.

use crate::message::{kind, Code, Status, SAMPLE_HEADER_LEN, SAMPLE_LEN};
use crate::{sample_frame_wire_len, EncodeError, CRC_LEN, MAX_BATCH};

/// Largest sample frame on the wire, delimiter included (16 samples: 168 bytes).
pub const SAMPLE_FRAME_MAX_WIRE: usize = sample_frame_wire_len(MAX_BATCH);

/// A buffer that holds one encoded sample frame of up to [`MAX_BATCH`] samples.
pub type SampleFrameBuf = [u8; SAMPLE_FRAME_MAX_WIRE];

const _: () = assert!(
    SAMPLE_FRAME_MAX_WIRE - 1 < 255,
    "COBS in one block needs < 254 bytes"
);

/// Where the body starts in the buffer: after the COBS code byte.
const BODY_AT: usize = 1;
/// Where sample 0 starts in the buffer.
const SAMPLES_AT: usize = BODY_AT + SAMPLE_HEADER_LEN;

/// The sample frame header: everything but the samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SampleHeader {
    pub seq: u32,
    pub t_us: u32,
    pub status: Status,
    pub temp: Code,
}

/// Builds one sample frame in a caller's [`SampleFrameBuf`]. It keeps only the sample count; the
/// caller keeps the buffer (e.g. in its transmit path) and hands it to every call.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SampleFrameEncoder {
    len: u8,
}

impl SampleFrameEncoder {
    pub const fn new() -> Self {
        Self { len: 0 }
    }

    /// Samples written so far.
    pub fn len(&self) -> usize {
        usize::from(self.len)
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn is_full(&self) -> bool {
        usize::from(self.len) >= MAX_BATCH
    }

    /// Wire length of the frame as it stands (delimiter included).
    pub fn wire_len(&self) -> usize {
        sample_frame_wire_len(self.len())
    }

    /// Write the next sample (three 24-bit codes; the top byte of each is dropped) at its wire
    /// position in `buf`. Returns false, writing nothing, if the frame already holds
    /// [`MAX_BATCH`] samples.
    #[inline]
    pub fn push(&mut self, buf: &mut SampleFrameBuf, ch: [Code; 3]) -> bool {
        if self.is_full() {
            return false;
        }
        let at = SAMPLES_AT + usize::from(self.len) * SAMPLE_LEN;
        // Three overlapping 4-byte stores: each code's fourth byte is overwritten by the next code,
        // the last one by the next sample or the CRC, both written later. Sample 15 ends at
        // byte 163, so the spare byte (164) is inside the buffer.
        let s = &mut buf[at..at + SAMPLE_LEN + 1];
        s[0..4].copy_from_slice(&ch[0].to_le_bytes());
        s[3..7].copy_from_slice(&ch[1].to_le_bytes());
        s[6..10].copy_from_slice(&ch[2].to_le_bytes());
        self.len += 1;
        true
    }

    /// Finish the frame in `buf`: header, CRC-32C, COBS and the 0x00 delimiter. Returns the wire
    /// length, the frame being `buf[..len]`, and empties the encoder for the next frame. An empty
    /// frame is not a valid sample frame: it encodes to nothing and returns 0.
    pub fn finish(&mut self, buf: &mut SampleFrameBuf, header: &SampleHeader) -> usize {
        let n = self.len();
        if n == 0 {
            return 0;
        }
        self.len = 0;
        write_header(buf, header, n as u8);
        let body_len = SAMPLE_HEADER_LEN + n * SAMPLE_LEN;
        crc_and_cobs(buf, body_len)
    }

    /// As [`Self::finish`], but the COBS pass writes the frame into `out` (at least
    /// [`Self::wire_len`] bytes, e.g. a transmit buffer's free space) instead of over `buf`: the
    /// one copy the frame needs anyway on its way out, folded into the encoding. Returns the wire
    /// length (0 for an empty frame), or `BufferTooSmall`; the encoder is emptied either way.
    pub fn finish_into(
        &mut self,
        buf: &mut SampleFrameBuf,
        header: &SampleHeader,
        out: &mut [u8],
    ) -> Result<usize, EncodeError> {
        let n = self.len();
        self.len = 0;
        if n == 0 {
            return Ok(0);
        }
        let wire_len = sample_frame_wire_len(n);
        let out = out.get_mut(..wire_len).ok_or(EncodeError::BufferTooSmall)?;
        write_header(buf, header, n as u8);
        let end = append_crc(buf, SAMPLE_HEADER_LEN + n * SAMPLE_LEN);
        cobs_copy(&buf[..end], out);
        Ok(wire_len)
    }
}

/// The 18 header bytes, SPEC.md order: type, seq, t_us, status (5), temp (i24), n.
#[inline]
fn write_header(buf: &mut SampleFrameBuf, h: &SampleHeader, n: u8) {
    let b = &mut buf[BODY_AT..BODY_AT + SAMPLE_HEADER_LEN];
    b[0] = kind::SAMPLE;
    b[1..5].copy_from_slice(&h.seq.to_le_bytes());
    b[5..9].copy_from_slice(&h.t_us.to_le_bytes());
    b[9..14].copy_from_slice(&h.status.to_bytes());
    b[14..17].copy_from_slice(&h.temp.to_le_bytes()[..3]);
    b[17] = n;
}

/// Bit 7 of each byte of `v` that is zero, nothing else (the classic "has zero byte" trick, exact
/// form: no false positives from borrows).
#[inline(always)]
fn zero_bytes(v: u32) -> u32 {
    !(((v & 0x7F7F_7F7F).wrapping_add(0x7F7F_7F7F)) | v | 0x7F7F_7F7F)
}

/// CRC-32C over the body at `buf[1..1 + body_len]`, appended little-endian, then COBS over body
/// and CRC in place (code byte at `buf[0]`) and the delimiter. Returns the wire length.
#[inline(never)]
fn crc_and_cobs(buf: &mut SampleFrameBuf, body_len: usize) -> usize {
    let end = append_crc(buf, body_len);
    cobs_in_place(buf, end);
    buf[end] = 0;
    end + 1
}

/// CRC-32C of the body at `buf[1..1 + body_len]` written after it; returns the end of the CRC.
#[inline(never)]
fn append_crc(buf: &mut SampleFrameBuf, body_len: usize) -> usize {
    // `min` only tells the compiler the bound (body_len ≤ 162 already), so no index is checked.
    let body_end = (BODY_AT + body_len).min(SAMPLE_FRAME_MAX_WIRE - 1 - CRC_LEN);
    let end = body_end + CRC_LEN;
    let crc = !crate::crc32c::update(!0, &buf[BODY_AT..body_end]);
    buf[body_end..end].copy_from_slice(&crc.to_le_bytes());
    end
}

/// COBS of `src[1..]` (shorter than 254 bytes; `src[0]` is the unused code-byte slot) into `out`
/// (exactly `src.len() + 1` bytes: code byte, data, delimiter). A word at a time: each word is
/// stored whole, then its zero bytes are overwritten with codes; an all-zero word (common in a
/// tared signal at rest) is written in one go.
#[inline(never)]
fn cobs_copy(src: &[u8], out: &mut [u8]) {
    let end = src.len();
    let Some(out) = out.get_mut(..end + 1) else {
        return;
    };
    let mut code_at = 0usize;
    let mut j = BODY_AT;
    while j + 4 <= end {
        let w: [u8; 4] = src[j..j + 4].try_into().unwrap_or([1; 4]);
        let v = u32::from_le_bytes(w);
        if v == 0 {
            // Four zeros (a tared channel at rest): close the open block, three one-byte blocks,
            // and the fourth zero's slot becomes the open code byte.
            out[code_at] = (j - code_at) as u8;
            out[j..j + 4].copy_from_slice(&[1, 1, 1, 0]);
            code_at = j + 3;
            j += 4;
            continue;
        }
        out[j..j + 4].copy_from_slice(&w);
        let mut zeros = zero_bytes(v);
        while zeros != 0 {
            let at = j + (zeros.trailing_zeros() / 8) as usize;
            out[code_at] = (at - code_at) as u8;
            code_at = at;
            zeros &= zeros - 1;
        }
        j += 4;
    }
    while j < end {
        let b = src[j];
        out[j] = b;
        if b == 0 {
            out[code_at] = (j - code_at) as u8;
            code_at = j;
        }
        j += 1;
    }
    out[code_at] = (end - code_at) as u8;
    out[end] = 0;
}

/// COBS of `buf[1..end]` in place, `end` < 255: every zero byte, and the leading code byte
/// `buf[0]`, becomes the distance to the next zero byte (or to `end`). A word at a time: zero-free
/// words, the usual case, cost a load and a test.
#[inline(always)]
fn cobs_in_place(buf: &mut SampleFrameBuf, end: usize) {
    let end = end.min(SAMPLE_FRAME_MAX_WIRE - 1);
    let mut code_at = 0usize;
    let mut j = BODY_AT;
    while j + 4 <= end {
        let v = u32::from_le_bytes([buf[j], buf[j + 1], buf[j + 2], buf[j + 3]]);
        let mut zeros = zero_bytes(v);
        while zeros != 0 {
            let at = j + (zeros.trailing_zeros() / 8) as usize;
            buf[code_at] = (at - code_at) as u8;
            code_at = at;
            zeros &= zeros - 1;
        }
        j += 4;
    }
    while j < end {
        if buf[j] == 0 {
            buf[code_at] = (j - code_at) as u8;
            code_at = j;
        }
        j += 1;
    }
    buf[code_at] = (end - code_at) as u8;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Message, NullState, Sample, SampleFrame, CRC, MAX_FRAME};

    /// The field-by-field path: `Message::encode_body`, the `crc` crate, the `cobs` crate.
    fn reference(frame: &SampleFrame) -> Vec<u8> {
        let mut body = vec![0u8; 256];
        let n = Message::Sample(frame.clone())
            .encode_body(&mut body)
            .unwrap();
        body.truncate(n);
        body.extend_from_slice(&CRC.checksum(&body).to_le_bytes());
        let mut out = vec![0u8; MAX_FRAME];
        let k = cobs::encode(&body, &mut out);
        out.truncate(k);
        out.push(0);
        out
    }

    fn xorshift(state: &mut u32) -> u32 {
        *state ^= *state << 13;
        *state ^= *state >> 17;
        *state ^= *state << 5;
        *state
    }

    #[test]
    fn bytes_equal_the_field_by_field_encoder_on_random_frames() {
        let mut state = 0x1234_5678u32;
        let mut enc = SampleFrameEncoder::new();
        let mut buf = [0xA5u8; SAMPLE_FRAME_MAX_WIRE];
        for round in 0..3000usize {
            let mut next = || xorshift(&mut state);
            // Zero bytes everywhere now and then, so COBS sees single zeros and runs of them.
            let zero_every = [0, 2, 3, 5, 11][round % 5];
            let code = |x: u32| {
                if round % 13 == 0 || (zero_every != 0 && x % zero_every == 0) {
                    0
                } else {
                    ((x as i32) << 8) >> 8 & !(0xFF << (8 * (x % 4)))
                }
            };
            let status = Status {
                saturated: (next() & 0x0F) as u8,
                null_state: [
                    NullState::Off,
                    NullState::Searching,
                    NullState::Nulled,
                    NullState::Failed,
                ][round % 4],
                tare_active: next() & 1 == 1,
                drift_tracking: next() & 1 == 1,
                sample_overrun: next() & 1 == 1,
                adc_error: next() & 1 == 1,
                config_epoch: next() as u8,
                dropped: if round % 3 == 0 { 0 } else { next() as u16 },
            };
            let header = SampleHeader {
                seq: next(),
                t_us: if round % 7 == 0 { 0 } else { next() },
                status,
                temp: code(next()),
            };
            let n = 1 + round % MAX_BATCH;
            let mut frame = SampleFrame::new(header.seq, header.t_us, status, header.temp);
            for _ in 0..n {
                let ch = [code(next()), code(next()), code(next())];
                frame.push(Sample { ch }).unwrap();
                assert!(enc.push(&mut buf, ch));
            }
            assert_eq!(enc.wire_len(), sample_frame_wire_len(n));
            let expected = reference(&frame);
            if round % 2 == 0 {
                let len = enc.finish(&mut buf, &header);
                assert_eq!(&buf[..len], &expected[..], "round {round}");
            } else {
                let mut out = [0x5Au8; MAX_FRAME];
                let len = enc.finish_into(&mut buf, &header, &mut out[..]).unwrap();
                assert_eq!(&out[..len], &expected[..], "round {round}");
            }
            assert!(enc.is_empty());
        }
    }

    #[test]
    fn full_frame_refuses_a_sample_and_empty_frame_encodes_to_nothing() {
        let mut enc = SampleFrameEncoder::new();
        let mut buf = [0u8; SAMPLE_FRAME_MAX_WIRE];
        let header = SampleHeader {
            seq: 1,
            t_us: 2,
            status: Status::default(),
            temp: 3,
        };
        assert_eq!(enc.finish(&mut buf, &header), 0);
        for _ in 0..MAX_BATCH {
            assert!(enc.push(&mut buf, [-1, 0, 1]));
        }
        assert!(!enc.push(&mut buf, [7, 7, 7]));
        assert_eq!(enc.finish(&mut buf, &header), SAMPLE_FRAME_MAX_WIRE);
        assert_eq!(buf[SAMPLE_FRAME_MAX_WIRE - 1], 0);
        assert!(buf[..SAMPLE_FRAME_MAX_WIRE - 1].iter().all(|b| *b != 0));
    }
}
