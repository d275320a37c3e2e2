//! The receiving side: a fixed-size accumulator that collects bytes up to each 0x00 delimiter,
//! checks and decodes the frame, and resynchronises at the next delimiter after anything bad.

use crate::{crc32c, Malformed, Message, CRC_LEN, MAX_ENCODED};

/// What one delimited frame turned out to be. Nothing here is a panic: bad bytes are outcomes.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// A frame that passed the CRC and decoded.
    Message(Message),
    /// The CRC did not match: corrupted in transit (or bytes lost or inserted).
    CrcError,
    /// More than the accumulator's capacity arrived without a delimiter; discarded up to the
    /// next delimiter.
    Overflow,
    /// The CRC matched but the body is not a valid message.
    Malformed(Malformed),
}

/// Collects encoded bytes between delimiters in a buffer of `N` bytes, no allocation.
#[derive(Debug, Clone)]
pub struct Accumulator<const N: usize = MAX_ENCODED> {
    buf: [u8; N],
    len: usize,
    overflowed: bool,
}

impl Default for Accumulator<MAX_ENCODED> {
    fn default() -> Self {
        Self::new()
    }
}

impl Accumulator<MAX_ENCODED> {
    /// An empty accumulator sized for the largest frame of the protocol. Anything received
    /// before the first delimiter is treated like any other frame (it will normally fail its
    /// CRC and be reported).
    pub const fn new() -> Self {
        Self::with_capacity()
    }
}

impl<const N: usize> Accumulator<N> {
    /// An empty accumulator holding at most `N` encoded bytes per frame: a device that only
    /// receives short requests can use a small one.
    pub const fn with_capacity() -> Self {
        Self {
            buf: [0; N],
            len: 0,
            overflowed: false,
        }
    }

    /// Forget any partial frame (e.g. after reopening the port).
    pub fn reset(&mut self) {
        self.len = 0;
        self.overflowed = false;
    }

    /// Bytes of the frame currently being collected.
    pub fn pending(&self) -> usize {
        self.len
    }

    /// Feed received bytes; iterate to get one [`Outcome`] per completed frame. Bytes after the
    /// last delimiter stay in the accumulator for the next call. Dropping the iterator early
    /// discards the unread rest of `input`.
    pub fn feed<'a, 'b>(&'a mut self, input: &'b [u8]) -> Outcomes<'a, 'b, N> {
        Outcomes { acc: self, input }
    }

    fn absorb(&mut self, chunk: &[u8]) {
        if self.overflowed {
            return;
        }
        match self.buf.get_mut(self.len..self.len + chunk.len()) {
            Some(dst) => {
                dst.copy_from_slice(chunk);
                self.len += chunk.len();
            }
            None => {
                self.overflowed = true;
                self.len = 0;
            }
        }
    }

    /// A delimiter arrived: judge what was collected. `None` for an empty frame (idle line).
    fn finish(&mut self) -> Option<Outcome> {
        let len = core::mem::take(&mut self.len);
        if core::mem::take(&mut self.overflowed) {
            return Some(Outcome::Overflow);
        }
        if len == 0 {
            return None;
        }
        Some(judge(&mut self.buf[..len]))
    }
}

/// Decode one delimited COBS frame in place, check its CRC, parse its body.
fn judge(frame: &mut [u8]) -> Outcome {
    let decoded = match cobs::decode_in_place(frame) {
        Ok(n) => n,
        Err(_) => return Outcome::Malformed(Malformed::Cobs),
    };
    let Some(body_len) = decoded.checked_sub(CRC_LEN).filter(|n| *n > 0) else {
        return Outcome::Malformed(Malformed::Short);
    };
    let (body, crc) = frame[..decoded].split_at(body_len);
    let mut crc_bytes = [0u8; CRC_LEN];
    crc_bytes.copy_from_slice(crc);
    if crc32c(body) != u32::from_le_bytes(crc_bytes) {
        return Outcome::CrcError;
    }
    match Message::decode_body(body) {
        Ok(msg) => Outcome::Message(msg),
        Err(m) => Outcome::Malformed(m),
    }
}

/// Iterator over the outcomes of one [`Accumulator::feed`] call.
pub struct Outcomes<'a, 'b, const N: usize> {
    acc: &'a mut Accumulator<N>,
    input: &'b [u8],
}

impl<const N: usize> Iterator for Outcomes<'_, '_, N> {
    type Item = Outcome;

    fn next(&mut self) -> Option<Outcome> {
        while !self.input.is_empty() {
            let Some(end) = self.input.iter().position(|b| *b == 0) else {
                self.acc.absorb(self.input);
                self.input = &[];
                return None;
            };
            self.acc.absorb(&self.input[..end]);
            self.input = &self.input[end + 1..];
            if let Some(outcome) = self.acc.finish() {
                return Some(outcome);
            }
        }
        None
    }
}
