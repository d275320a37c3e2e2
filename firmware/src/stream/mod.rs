//! Streaming: the sample clock's read (ADC → queue), the acquisition queue (interrupt → main
//! loop) and the transmit buffer (framing → port).

pub mod frame;
pub mod queue;
pub mod sampler;
pub mod tx;

pub use frame::FrameBuilder;
pub use queue::{Acquirer, Drain, Overruns, Producer, RawSample, SampleQueue, QUEUE_LEN};
pub use sampler::Sampler;
pub use tx::TxBuffer;
