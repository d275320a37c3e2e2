//! The transmit buffer between framing and the serial port. Frames enter whole or not at all, so
//! a frame on the wire is never cut short: when the link cannot keep up, the framer drops the
//! whole frame and counts it. The port side takes bytes one at a time without waiting.

/// Byte FIFO holding complete encoded frames, linear rather than circular: the framer encodes
/// straight into the free space ([`Self::reserve`]), so a frame needs contiguous room. When the
/// buffer runs empty both indices return to 0 (the usual case when the link keeps up); otherwise a
/// frame that does not fit at the end moves the unsent bytes to the front first.
pub struct TxBuffer<const N: usize> {
    buf: [u8; N],
    /// Next byte to send; bytes `read..write` are queued.
    read: usize,
    write: usize,
}

impl<const N: usize> Default for TxBuffer<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> TxBuffer<N> {
    pub const fn new() -> Self {
        Self {
            buf: [0; N],
            read: 0,
            write: 0,
        }
    }

    /// Bytes waiting.
    pub fn len(&self) -> usize {
        self.write - self.read
    }

    pub fn is_empty(&self) -> bool {
        self.read == self.write
    }

    /// Free space in bytes.
    pub fn free(&self) -> usize {
        N - self.len()
    }

    /// `len` contiguous bytes to write a frame into, if the buffer has that much room; the frame
    /// becomes visible to the port only at [`Self::commit`].
    pub fn reserve(&mut self, len: usize) -> Option<&mut [u8]> {
        if len > self.free() {
            return None;
        }
        if self.write + len > N {
            self.buf.copy_within(self.read..self.write, 0);
            self.write -= self.read;
            self.read = 0;
        }
        Some(&mut self.buf[self.write..self.write + len])
    }

    /// Publish `len` bytes written into the last reservation.
    pub fn commit(&mut self, len: usize) {
        debug_assert!(self.write + len <= N, "commit beyond the reservation");
        self.write += len;
    }

    /// Append a whole frame if it fits; otherwise append nothing and return false.
    pub fn push_frame(&mut self, frame: &[u8]) -> bool {
        match self.reserve(frame.len()) {
            Some(dst) => {
                dst.copy_from_slice(frame);
                self.commit(frame.len());
                true
            }
            None => false,
        }
    }

    /// The next byte to send, without removing it.
    pub fn peek(&self) -> Option<u8> {
        (!self.is_empty()).then(|| self.buf[self.read])
    }

    /// Remove and return the next byte.
    pub fn pop(&mut self) -> Option<u8> {
        let b = self.peek()?;
        self.read += 1;
        if self.read == self.write {
            self.read = 0;
            self.write = 0;
        }
        Some(b)
    }

    /// Hand bytes to `send` until it refuses one (port full) or the buffer is empty; returns the
    /// count sent.
    #[inline]
    pub fn drain(&mut self, mut send: impl FnMut(u8) -> bool) -> usize {
        // The main loop calls this after every sample; most of the time nothing waits.
        if self.is_empty() {
            return 0;
        }
        let start = self.read;
        for &b in &self.buf[self.read..self.write] {
            if !send(b) {
                break;
            }
            self.read += 1;
        }
        let sent = self.read - start;
        if self.read == self.write {
            self.read = 0;
            self.write = 0;
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
        tx.drain(|b| b == 9); // leave the delimiter queued: the buffer must compact below
        assert!(tx.push_frame(&[1, 2, 3, 0]));
        assert!(!tx.push_frame(&[4, 5, 6, 7, 0]));
        assert_eq!(tx.len(), 5);
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
        assert_eq!(out, [0, 1]);
        assert!(tx.push_frame(&[4, 5, 6, 7, 0]), "compaction makes room");
        tx.drain(|b| {
            out.push(b);
            true
        });
        assert_eq!(out, [0, 1, 2, 3, 0, 4, 5, 6, 7, 0]);
        assert!(tx.is_empty() && tx.free() == 8);
    }
}
