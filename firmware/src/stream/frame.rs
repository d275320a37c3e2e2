//! The per-sample framing path: samples are written straight into a sample-frame body as they
//! arrive, and a full batch is finished with the CRC-32C and COBS in one pass each.
//!
//! This produces exactly the bytes of `protocol::encode(&Message::Sample(..))` (SPEC.md, type
//! 0x01; host tests compare the two on random frames), but about four times faster: the protocol
//! crate builds a `SampleFrame`, writes it through a bounds-checked cursor, computes the CRC a
//! byte at a time and uses a general COBS routine, which together cost ~260 instructions per sample
//! on the Cortex-M4, more than half the firmware's budget. Here: fixed offsets, CRC-32C sliced by
//! four (4 KiB of tables), and a COBS pass specialised to bodies shorter than 254 bytes that
//! skips zero-free words.

use protocol::{Status, CRC_LEN, MAX_BATCH, MAX_FRAME, SAMPLE_HEADER_LEN, SAMPLE_LEN};

use super::TxBuffer;

/// Largest sample-frame body plus its CRC.
const PAYLOAD_MAX: usize = SAMPLE_HEADER_LEN + MAX_BATCH * SAMPLE_LEN + CRC_LEN;
const _: () = assert!(PAYLOAD_MAX < 254, "the COBS pass assumes one block");

/// CRC-32C (Castagnoli, reflected 0x82F63B78), slicing-by-4 tables.
const CRC_TABLES: [[u32; 256]; 4] = crc_tables();

const fn crc_tables() -> [[u32; 256]; 4] {
    let mut t = [[0u32; 256]; 4];
    let mut i = 0;
    while i < 256 {
        let mut c = i as u32;
        let mut k = 0;
        while k < 8 {
            c = if c & 1 != 0 {
                (c >> 1) ^ 0x82F6_3B78
            } else {
                c >> 1
            };
            k += 1;
        }
        t[0][i] = c;
        i += 1;
    }
    let mut i = 0;
    while i < 256 {
        let mut s = 1;
        while s < 4 {
            let prev = t[s - 1][i];
            t[s][i] = (prev >> 8) ^ t[0][(prev & 0xFF) as usize];
            s += 1;
        }
        i += 1;
    }
    t
}

/// CRC-32C of `bytes` (init and final XOR 0xFFFFFFFF).
#[inline(never)]
pub fn crc32c(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    let mut chunks = bytes.chunks_exact(4);
    for w in &mut chunks {
        crc ^= u32::from_le_bytes([w[0], w[1], w[2], w[3]]);
        crc = CRC_TABLES[3][(crc & 0xFF) as usize]
            ^ CRC_TABLES[2][((crc >> 8) & 0xFF) as usize]
            ^ CRC_TABLES[1][((crc >> 16) & 0xFF) as usize]
            ^ CRC_TABLES[0][(crc >> 24) as usize];
    }
    for &b in chunks.remainder() {
        crc = (crc >> 8) ^ CRC_TABLES[0][((crc ^ u32::from(b)) & 0xFF) as usize];
    }
    !crc
}

/// COBS of `src` (shorter than 254 bytes, so one block) into `dst` (exactly `src.len() + 1`
/// bytes). Four bytes at a time: a word is stored, and its zero bytes (found all at once with a
/// bit trick, then visited lowest first) become code bytes. A leaf function on purpose: inlined
/// into the device core, the loop ran out of registers and spilled to the stack.
#[inline(never)]
fn cobs_short(src: &[u8], dst: &mut [u8]) {
    let dst = &mut dst[..src.len() + 1];
    let mut code_at = 0;
    let mut words = src.chunks_exact(4);
    let mut j = 1;
    for w in &mut words {
        let v = u32::from_le_bytes([w[0], w[1], w[2], w[3]]);
        if v == 0 {
            // Four zeros (a channel at rest after a tare): close the open block, then three
            // one-byte blocks; the fourth zero's slot becomes the open code byte.
            dst[code_at] = (j - code_at) as u8;
            dst[j..j + 3].copy_from_slice(&[1, 1, 1]);
            code_at = j + 3;
            j += 4;
            continue;
        }
        dst[j..j + 4].copy_from_slice(w);
        // 0x80 in exactly the bytes of v that are zero.
        let mut zeros = !(((v & 0x7F7F_7F7F).wrapping_add(0x7F7F_7F7F)) | v | 0x7F7F_7F7F);
        while zeros != 0 {
            let at = j + (zeros.trailing_zeros() / 8) as usize;
            dst[code_at] = (at - code_at) as u8;
            code_at = at;
            zeros &= zeros - 1;
        }
        j += 4;
    }
    for &b in words.remainder() {
        if b == 0 {
            dst[code_at] = (j - code_at) as u8;
            code_at = j;
        } else {
            dst[j] = b;
        }
        j += 1;
    }
    dst[code_at] = (j - code_at) as u8;
}

/// A sample frame being filled.
pub struct FrameBuilder {
    body: [u8; PAYLOAD_MAX],
    len: usize,
    t_us: u32,
    temp: i32,
}

impl Default for FrameBuilder {
    fn default() -> Self {
        Self::new()
    }
}

impl FrameBuilder {
    pub const fn new() -> Self {
        Self {
            body: [0; PAYLOAD_MAX],
            len: 0,
            t_us: 0,
            temp: 0,
        }
    }

    /// Samples in the frame.
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Open the frame: time of its first sample and the temperature channel's code.
    pub fn open(&mut self, t_us: u32, temp: i32) {
        self.len = 0;
        self.t_us = t_us;
        self.temp = temp;
    }

    /// Append one sample (three codes, already clamped to 24 bits). The caller closes the frame
    /// at its batch size, never above [`MAX_BATCH`].
    #[inline]
    pub fn push(&mut self, ch: [i32; 3]) {
        let at = SAMPLE_HEADER_LEN + self.len * SAMPLE_LEN;
        let s = &mut self.body[at..at + SAMPLE_LEN];
        s[..3].copy_from_slice(&ch[0].to_le_bytes()[..3]);
        s[3..6].copy_from_slice(&ch[1].to_le_bytes()[..3]);
        s[6..9].copy_from_slice(&ch[2].to_le_bytes()[..3]);
        self.len += 1;
    }

    /// Wire length of the frame as it stands: body, CRC, one COBS byte, delimiter.
    pub fn wire_len(&self) -> usize {
        SAMPLE_HEADER_LEN + self.len * SAMPLE_LEN + CRC_LEN + 2
    }

    /// Finish the frame into `out` (COBS(body ‖ CRC) ‖ 0x00); returns the wire length and
    /// empties the builder. An empty frame encodes to nothing (returns 0).
    pub fn finish(&mut self, seq: u32, status: &Status, out: &mut [u8; MAX_FRAME]) -> usize {
        if self.len == 0 {
            return 0;
        }
        let n = self.wire_len();
        self.encode(seq, status, &mut out[..n]);
        n
    }

    /// Finish the frame straight into the transmit buffer; false (frame dropped, builder emptied
    /// all the same) if the buffer lacks room for the whole frame.
    pub fn finish_into<const N: usize>(
        &mut self,
        seq: u32,
        status: &Status,
        tx: &mut TxBuffer<N>,
    ) -> bool {
        let n = self.wire_len();
        if self.len == 0 {
            return false;
        }
        let Some(dst) = tx.reserve(n) else {
            self.len = 0;
            return false;
        };
        self.encode(seq, status, dst);
        tx.commit(n);
        true
    }

    /// Header, CRC, COBS and delimiter into `dst` (exactly the wire length).
    fn encode(&mut self, seq: u32, status: &Status, dst: &mut [u8]) {
        let h = &mut self.body[..SAMPLE_HEADER_LEN];
        h[0] = protocol::kind::SAMPLE;
        h[1..5].copy_from_slice(&seq.to_le_bytes());
        h[5..9].copy_from_slice(&self.t_us.to_le_bytes());
        h[9] = status.saturated & 0x0F;
        h[10] = (status.null_state as u8)
            | (u8::from(status.tare_active) << 2)
            | (u8::from(status.drift_tracking) << 3)
            | (u8::from(status.sample_overrun) << 4)
            | (u8::from(status.adc_error) << 5);
        h[11] = status.config_epoch;
        h[12..14].copy_from_slice(&status.dropped.to_le_bytes());
        h[14..17].copy_from_slice(&self.temp.to_le_bytes()[..3]);
        h[17] = self.len as u8;
        let body_len = SAMPLE_HEADER_LEN + self.len * SAMPLE_LEN;
        let crc = crc32c(&self.body[..body_len]);
        self.body[body_len..body_len + CRC_LEN].copy_from_slice(&crc.to_le_bytes());
        let payload = body_len + CRC_LEN;
        cobs_short(&self.body[..payload], &mut dst[..payload + 1]);
        dst[payload + 1] = 0;
        self.len = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::{encode_vec, Message, NullState, Sample, SampleFrame};

    #[test]
    fn crc32c_check_value() {
        assert_eq!(crc32c(b"123456789"), 0xE306_9283);
        for len in 0..40 {
            let data: Vec<u8> = (0..len).map(|i| (i * 37 + 5) as u8).collect();
            assert_eq!(crc32c(&data), protocol::CRC.checksum(&data), "len {len}");
        }
    }

    #[test]
    fn bytes_equal_the_protocol_encoder() {
        let mut state = 0x1234_5678u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state
        };
        let mut builder = FrameBuilder::new();
        let mut wire = [0u8; MAX_FRAME];
        for round in 0..500 {
            let n = 1 + (next() as usize % MAX_BATCH);
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
                // Zero bytes in every field now and then, so COBS sees runs of them.
                dropped: if round % 3 == 0 { 0 } else { next() as u16 },
            };
            let code = |x: u32| {
                // Every fifth code zero, every eleventh frame all zeros (runs of zero words).
                if x % 5 == 0 || round % 11 == 0 {
                    0
                } else {
                    ((x as i32) << 8) >> 8
                }
            };
            let (seq, t_us, temp) = (
                next(),
                if round % 7 == 0 { 0 } else { next() },
                code(next()),
            );
            let mut reference = SampleFrame::new(seq, t_us, status, temp);
            builder.open(t_us, temp);
            for _ in 0..n {
                let ch = [code(next()), code(next()), code(next())];
                reference.push(Sample { ch }).unwrap();
                builder.push(ch);
            }
            let expected = encode_vec(&Message::Sample(reference)).unwrap();
            if round % 2 == 0 {
                let len = builder.finish(seq, &status, &mut wire);
                assert_eq!(&wire[..len], &expected[..], "round {round}");
            } else {
                let mut tx = TxBuffer::<256>::new();
                assert!(builder.finish_into(seq, &status, &mut tx));
                let mut got = Vec::new();
                tx.drain(|b| {
                    got.push(b);
                    true
                });
                assert_eq!(got, expected, "round {round}");
            }
        }
    }
}
