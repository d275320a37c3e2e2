//! Streaming: acquisition queue (interrupt → main loop) and the transmit buffer (framing → port).

pub mod queue;
pub mod frame;
pub mod tx;

pub use queue::{Acquirer, Drain, Overruns, RawSample, SampleQueue, QUEUE_LEN};
pub use frame::FrameBuilder;
pub use tx::TxBuffer;
