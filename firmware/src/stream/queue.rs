//! The acquisition queue: the sample-clock interrupt (DRDY on the board, SysTick under QEMU) reads
//! the ADC and pushes a [`RawSample`]; the main loop pops. Single producer, single consumer,
//! lock-free. The interrupt never waits: when the queue is full the sample is dropped and counted,
//! and the main loop reports the count.
//!
//! A ring of its own rather than `heapless::spsc`, whose split halves take the capacity at run
//! time (a division per push and per pop): here the capacity is a power of two known at compile
//! time, so an index wraps with one AND.
//!
//! Ordering: on the single-core Cortex-M targets the producer is an interrupt on the same core as
//! the consumer, and a core observes its own memory accesses in program order, so a compiler
//! fence is all the publication needs (no `dmb`); elsewhere (host tests, threads) the indices are
//! real acquire/release atomics.

use core::cell::UnsafeCell;
use core::sync::atomic::{AtomicU32, AtomicUsize, Ordering};

/// Load an index the other end publishes (acquire).
#[inline(always)]
fn load_acquire(index: &AtomicUsize) -> usize {
    #[cfg(all(target_arch = "arm", target_os = "none"))]
    {
        let v = index.load(Ordering::Relaxed);
        core::sync::atomic::compiler_fence(Ordering::Acquire);
        v
    }
    #[cfg(not(all(target_arch = "arm", target_os = "none")))]
    index.load(Ordering::Acquire)
}

/// Publish an index to the other end (release).
#[inline(always)]
fn store_release(index: &AtomicUsize, v: usize) {
    #[cfg(all(target_arch = "arm", target_os = "none"))]
    {
        core::sync::atomic::compiler_fence(Ordering::Release);
        index.store(v, Ordering::Relaxed);
    }
    #[cfg(not(all(target_arch = "arm", target_os = "none")))]
    index.store(v, Ordering::Release);
}

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
const _: () = assert!(QUEUE_LEN.is_power_of_two(), "indices wrap with a mask");
const MASK: usize = QUEUE_LEN - 1;

const EMPTY: RawSample = RawSample {
    index: 0,
    codes: [0; 4],
    read_error: false,
};

/// The queue itself; place it in a `static` and [`SampleQueue::split`] it. Holds up to
/// `QUEUE_LEN − 1` samples (one slot stays free to tell full from empty).
pub struct SampleQueue {
    slots: [UnsafeCell<RawSample>; QUEUE_LEN],
    /// Next slot to read; written only by the consumer.
    head: AtomicUsize,
    /// Next slot to write; written only by the producer.
    tail: AtomicUsize,
}

// SAFETY: the producer writes only the slot at `tail` and then publishes it (Release); the
// consumer reads only slots below the `tail` it loaded (Acquire) and then frees them by moving
// `head` (Release), which the producer loads (Acquire) before reusing a slot (on the single-core
// target, program order plus compiler fences give the same guarantee). `split` hands out exactly
// one of each end.
unsafe impl Sync for SampleQueue {}

impl Default for SampleQueue {
    fn default() -> Self {
        Self::new()
    }
}

impl SampleQueue {
    pub const fn new() -> Self {
        Self {
            slots: [const { UnsafeCell::new(EMPTY) }; QUEUE_LEN],
            head: AtomicUsize::new(0),
            tail: AtomicUsize::new(0),
        }
    }

    /// The two ends: the `&mut` borrow guarantees there is only one of each.
    pub fn split(&mut self) -> (Producer<'_>, Drain<'_>) {
        (Producer { queue: self }, Drain { queue: self })
    }
}

/// The producing end (the interrupt's).
pub struct Producer<'a> {
    queue: &'a SampleQueue,
}

impl Producer<'_> {
    /// Append `sample`, or give it back if the queue is full.
    #[inline]
    pub fn enqueue(&mut self, sample: RawSample) -> Result<(), RawSample> {
        let q = self.queue;
        let tail = q.tail.load(Ordering::Relaxed);
        let next = (tail + 1) & MASK;
        if next == load_acquire(&q.head) {
            return Err(sample);
        }
        // SAFETY: slot `tail` is not visible to the consumer until the store below (see Sync).
        unsafe { *q.slots[tail & MASK].get() = sample };
        store_release(&q.tail, next);
        Ok(())
    }
}

/// The main loop's end of the queue.
pub struct Drain<'a> {
    queue: &'a SampleQueue,
}

impl Drain<'_> {
    /// The oldest sample, if any.
    #[inline]
    pub fn dequeue(&mut self) -> Option<RawSample> {
        let q = self.queue;
        let head = q.head.load(Ordering::Relaxed);
        if head == load_acquire(&q.tail) {
            return None;
        }
        // SAFETY: slot `head` was published by the producer and is not reused before the store
        // below frees it (see Sync).
        let sample = unsafe { *q.slots[head & MASK].get() };
        store_release(&q.head, (head + 1) & MASK);
        Some(sample)
    }

    /// Samples waiting.
    pub fn len(&self) -> usize {
        let q = self.queue;
        q.tail
            .load(Ordering::Acquire)
            .wrapping_sub(q.head.load(Ordering::Relaxed))
            & MASK
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

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
    producer: Producer<'a>,
    overruns: &'a Overruns,
}

impl<'a> Acquirer<'a> {
    pub fn new(producer: Producer<'a>, overruns: &'a Overruns) -> Self {
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
        let rest: Vec<u32> = core::iter::from_fn(|| consumer.dequeue().map(|s| s.index)).collect();
        assert_eq!(rest, (1..QUEUE_LEN as u32 - 1).collect::<Vec<_>>());
        assert!(consumer.is_empty());
        // The freed slots take new samples, across the wrap.
        for i in 100..140 {
            assert!(acq.push(sample(i)));
        }
        let rest: Vec<u32> = core::iter::from_fn(|| consumer.dequeue().map(|s| s.index)).collect();
        assert_eq!(rest, (100..140).collect::<Vec<_>>());
    }
}
