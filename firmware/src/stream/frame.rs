//! The per-sample framing path: each sample goes straight to its wire position in the frame buffer
//! as it arrives, and a full batch is finished (header, CRC-32C, COBS, delimiter) in place by the
//! protocol crate's [`SampleFrameEncoder`], the single definition of the sample-frame layout. The
//! finished frame is copied whole into the transmit buffer, or dropped whole when it lacks room.

use protocol::{
    SampleFrameBuf, SampleFrameEncoder, SampleHeader, Status, MAX_FRAME, SAMPLE_FRAME_MAX_WIRE,
};

use super::TxBuffer;

/// A sample frame being filled.
pub struct FrameBuilder {
    buf: SampleFrameBuf,
    enc: SampleFrameEncoder,
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
            buf: [0; SAMPLE_FRAME_MAX_WIRE],
            enc: SampleFrameEncoder::new(),
            t_us: 0,
            temp: 0,
        }
    }

    /// Samples in the frame.
    pub fn len(&self) -> usize {
        self.enc.len()
    }

    pub fn is_empty(&self) -> bool {
        self.enc.is_empty()
    }

    /// Open the frame: time of its first sample and the temperature channel's code.
    pub fn open(&mut self, t_us: u32, temp: i32) {
        self.enc = SampleFrameEncoder::new();
        self.t_us = t_us;
        self.temp = temp;
    }

    /// Append one sample (three codes, already clamped to 24 bits). The caller closes the frame
    /// at its batch size, never above [`protocol::MAX_BATCH`]; a sample beyond it is refused
    /// (false).
    #[inline]
    pub fn push(&mut self, ch: [i32; 3]) -> bool {
        self.enc.push(&mut self.buf, ch)
    }

    /// Wire length of the frame as it stands: body, CRC, one COBS byte, delimiter.
    pub fn wire_len(&self) -> usize {
        self.enc.wire_len()
    }

    /// Encode the frame in place; returns the wire length (0 for an empty frame) and empties
    /// the builder.
    fn encode(&mut self, seq: u32, status: &Status) -> usize {
        let header = SampleHeader {
            seq,
            t_us: self.t_us,
            status: *status,
            temp: self.temp,
        };
        self.enc.finish(&mut self.buf, &header)
    }

    /// Finish the frame into `out` (COBS(body ‖ CRC) ‖ 0x00); returns the wire length and
    /// empties the builder. An empty frame encodes to nothing (returns 0).
    pub fn finish(&mut self, seq: u32, status: &Status, out: &mut [u8; MAX_FRAME]) -> usize {
        let n = self.encode(seq, status);
        out[..n].copy_from_slice(&self.buf[..n]);
        n
    }

    /// Finish the frame straight into the transmit buffer; false (frame dropped, builder emptied
    /// all the same) if it is empty or the buffer lacks room for the whole frame.
    pub fn finish_into<const N: usize>(
        &mut self,
        seq: u32,
        status: &Status,
        tx: &mut TxBuffer<N>,
    ) -> bool {
        let n = self.wire_len();
        if self.is_empty() {
            return false;
        }
        let Some(dst) = tx.reserve(n) else {
            self.enc = SampleFrameEncoder::new();
            return false;
        };
        let header = SampleHeader {
            seq,
            t_us: self.t_us,
            status: *status,
            temp: self.temp,
        };
        // The reservation holds exactly the wire length, so this cannot fail.
        let n = self
            .enc
            .finish_into(&mut self.buf, &header, dst)
            .unwrap_or(0);
        tx.commit(n);
        n > 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::{encode_vec, Message, NullState, Sample, SampleFrame, MAX_BATCH};

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
                assert!(builder.push(ch));
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
