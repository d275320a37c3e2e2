//! Streaming: acquisition queue (interrupt → main loop) and the transmit buffer (framing → port).

pub mod frame;
pub mod queue;
pub mod tx;

pub use frame::FrameBuilder;
pub use queue::{Acquirer, Drain, Overruns, Producer, RawSample, SampleQueue, QUEUE_LEN};
pub use tx::TxBuffer;
