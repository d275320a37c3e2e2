//! The transmit buffer between framing and the serial port. Frames enter whole or not at all, so
//! a frame on the wire is never cut short: when the link cannot keep up, the framer drops the
//! whole frame and counts it. The port side takes bytes one at a time without waiting.

use heapless::Deque;

/// Byte FIFO holding complete encoded frames.
pub struct TxBuffer<const N: usize> {
    bytes: Deque<u8, N>,
}

impl<const N: usize> Default for TxBuffer<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> TxBuffer<N> {
    pub const fn new() -> Self {
        Self { bytes: Deque::new() }
    }

    /// Free space in bytes.
    pub fn free(&self) -> usize {
        N - self.bytes.len()
    }

    /// Bytes waiting.
    pub fn len(&self) -> usize {
        self.bytes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }

    /// Append a whole frame if it fits; otherwise append nothing and return false.
    pub fn push_frame(&mut self, frame: &[u8]) -> bool {
        if frame.len() > self.free() {
            return false;
        }
        for &b in frame {
            // Cannot fail: room was checked above.
            let _ = self.bytes.push_back(b);
        }
        true
    }

    /// The next byte to send, without removing it.
    pub fn peek(&self) -> Option<u8> {
        self.bytes.front().copied()
    }

    /// Remove the byte returned by [`Self::peek`].
    pub fn pop(&mut self) -> Option<u8> {
        self.bytes.pop_front()
    }

    /// Hand bytes to `send` until it refuses one (port full) or the buffer is empty; returns the
    /// count sent.
    pub fn drain(&mut self, mut send: impl FnMut(u8) -> bool) -> usize {
        let mut sent = 0;
        while let Some(b) = self.peek() {
            if !send(b) {
                break;
            }
            self.bytes.pop_front();
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
