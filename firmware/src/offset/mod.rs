//! The offset cut, three layers, each visible in the status and info frames:
//! 1. [`autonull`]: analog, the trim DAC ahead of the gain stage (state: Off/Searching/Nulled/Failed);
//! 2. [`tare`]: digital, the mean of N samples at rest subtracted (tare_active, the offsets);
//! 3. [`drift`]: digital, slow bounded tracking while unloaded (drift_tracking, the correction).

pub mod autonull;
pub mod drift;
pub mod tare;

pub use autonull::{AutoNull, NullState, NullStep, NullTiming};
pub use drift::{DriftSettings, DriftTracker};
pub use tare::Tare;

/// Bridge channels the offset cut works on.
pub const CHANNELS: usize = 3;
