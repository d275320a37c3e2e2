//! Mismatch diagnosis (`shared/contracts/diagnosis-v1.md`): calibrate the baseline model of a
//! compression test to a recording, locate what remains, name the missing physics from the
//! catalogue (`sim::effects`), fit it, and show the fit improve on a held-out stretch.

pub mod baseline;
pub mod standin;
pub mod synth;
