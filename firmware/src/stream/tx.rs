//! The transmit buffer between framing and the serial port. Frames enter whole or not at all, so
//! a frame on the wire is never cut short: when the link cannot keep up, the framer drops the
//! whole frame and counts it. The port side takes bytes one at a time without waiting.

/// Byte ring holding complete encoded frames. `N` must be a power of two (index masking keeps
/// the per-byte cost of the port side to a load, a store and an add).
pub struct TxBuffer<const N: usize> {
    buf: [u8; N],
    /// Free-running read and write counters; `write - read` bytes are queued.
    read: usize,
    write: usize,
}

impl<const N: usize> Default for TxBuffer<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> TxBuffer<N> {
    const MASK: usize = {
        assert!(N.is_power_of_two(), "TxBuffer size must be a power of two");
        N - 1
    };

    pub const fn new() -> Self {
        Self { buf: [0; N], read: 0, write: 0 }
    }

    /// Bytes waiting.
    pub fn len(&self) -> usize {
        self.write.wrapping_sub(self.read)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Free space in bytes.
    pub fn free(&self) -> usize {
        N - self.len()
    }

    /// Append a whole frame if it fits; otherwise append nothing and return false.
    pub fn push_frame(&mut self, frame: &[u8]) -> bool {
        if frame.len() > self.free() {
            return false;
        }
        let start = self.write & Self::MASK;
        let first = frame.len().min(N - start);
        self.buf[start..start + first].copy_from_slice(&frame[..first]);
        self.buf[..frame.len() - first].copy_from_slice(&frame[first..]);
        self.write = self.write.wrapping_add(frame.len());
        true
    }

    /// The next byte to send, without removing it.
    pub fn peek(&self) -> Option<u8> {
        (!self.is_empty()).then(|| self.buf[self.read & Self::MASK])
    }

    /// Remove and return the next byte.
    pub fn pop(&mut self) -> Option<u8> {
        let b = self.peek()?;
        self.read = self.read.wrapping_add(1);
        Some(b)
    }

    /// Hand bytes to `send` until it refuses one (port full) or the buffer is empty; returns the
    /// count sent.
    pub fn drain(&mut self, mut send: impl FnMut(u8) -> bool) -> usize {
        let mut sent = 0;
        while self.read != self.write {
            if !send(self.buf[self.read & Self::MASK]) {
                break;
            }
            self.read = self.read.wrapping_add(1);
            sent += 1;
        }
        sent
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_go_in_whole_or_not_at_all() {
        let mut tx = TxBuffer::<8>::new();
        tx.push_frame(&[9, 9, 9, 0]);
        tx.drain(|_| true); // start off zero: the frames below wrap around the end
        assert!(tx.push_frame(&[1, 2, 3, 0]));
        assert!(!tx.push_frame(&[4, 5, 6, 7, 0]));
        assert_eq!(tx.len(), 4);
        let mut out = Vec::new();
        let mut budget = 2;
        tx.drain(|b| {
            if budget == 0 {
                return false;
            }
            budget -= 1;
            out.push(b);
            true
        });
        assert_eq!(out, [1, 2]);
        assert!(tx.push_frame(&[4, 5, 6, 7, 0]) || tx.free() < 5);
        tx.drain(|b| {
            out.push(b);
            true
        });
        assert_eq!(out, [1, 2, 3, 0, 4, 5, 6, 7, 0]);
    }
}
