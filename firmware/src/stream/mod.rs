//! Streaming: acquisition queue, frame batching with drop accounting, transmit buffer.

pub mod queue;

pub use queue::{Acquirer, Drain, Overruns, RawSample, SampleQueue, QUEUE_LEN};
