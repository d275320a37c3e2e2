//! The acquisition queue: the sample-clock interrupt (DRDY on the board, SysTick under QEMU) reads
//! the ADC and pushes a [`RawSample`]; the main loop pops. Single producer, single consumer,
//! lock-free (heapless SPSC). The interrupt never waits: when the queue is full the sample is
//! dropped and counted, and the main loop reports the count.

use core::sync::atomic::{AtomicU32, Ordering};

use heapless::spsc::{Consumer, Producer, Queue};

/// One conversion as the interrupt saw it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RawSample {
    /// Conversion counter kept by the interrupt (wraps); a gap means a conversion was lost.
    pub index: u32,
    /// The four ADC codes (channels 0–2 bridges, 3 temperature).
    pub codes: [i32; 4],
    /// The ADC read failed (bus error, CRC mismatch): `codes` repeat the last good values.
    pub read_error: bool,
}

/// Queue slots: 64 − 1 samples, 4 ms of buffering at 16 kSPS, > 60 ms at 1 kSPS.
pub const QUEUE_LEN: usize = 64;

/// The queue itself; place it in a `static` and [`Queue::split`] it.
pub type SampleQueue = Queue<RawSample, QUEUE_LEN>;

/// Count of samples the interrupt had to drop because the queue was full.
#[derive(Default)]
pub struct Overruns(AtomicU32);

impl Overruns {
    pub const fn new() -> Self {
        Self(AtomicU32::new(0))
    }

    /// Take the count accumulated since the last call.
    pub fn take(&self) -> u32 {
        self.0.swap(0, Ordering::Relaxed)
    }
}

/// The interrupt's end of the queue.
pub struct Acquirer<'a> {
    producer: Producer<'a, RawSample>,
    overruns: &'a Overruns,
}

impl<'a> Acquirer<'a> {
    pub fn new(producer: Producer<'a, RawSample>, overruns: &'a Overruns) -> Self {
        Self { producer, overruns }
    }

    /// Push without waiting; a full queue drops the sample and counts it.
    #[inline]
    pub fn push(&mut self, sample: RawSample) -> bool {
        match self.producer.enqueue(sample) {
            Ok(()) => true,
            Err(_) => {
                // Single core: a load/store pair is enough, but fetch_add keeps it obviously right.
                self.overruns.0.fetch_add(1, Ordering::Relaxed);
                false
            }
        }
    }
}

/// The main loop's end of the queue.
pub type Drain<'a> = Consumer<'a, RawSample>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_queue_drops_and_counts_without_blocking() {
        let mut queue = SampleQueue::new();
        let overruns = Overruns::new();
        let (producer, mut consumer) = queue.split();
        let mut acq = Acquirer::new(producer, &overruns);
        let sample = |index| RawSample {
            index,
            codes: [0; 4],
            read_error: false,
        };
        for i in 0..(QUEUE_LEN as u32 + 9) {
            acq.push(sample(i));
        }
        assert_eq!(overruns.take(), 10);
        assert_eq!(overruns.take(), 0);
        let first = consumer.dequeue().unwrap();
        assert_eq!(first.index, 0);
        assert_eq!(consumer.len(), QUEUE_LEN - 2);
    }
}
