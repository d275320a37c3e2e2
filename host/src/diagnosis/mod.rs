//! Mismatch diagnosis (`shared/contracts/diagnosis-v1.md`): calibrate the baseline model of a
//! compression test to a recording, locate what remains, name the missing physics from the
//! catalogue (`sim::effects`), fit it, and show the fit improve on a held-out stretch.

pub mod baseline;
pub mod data;
pub mod evidence;
pub mod fe_cache;
pub mod fe_response;
pub mod fit;
pub mod interp;
pub mod lm;
pub mod localise;
pub mod mains;
pub mod output;
pub mod pipeline;
pub mod regimes;
pub mod synth;
pub mod temperature;

pub use pipeline::{diagnose, Diagnosis, Options};
pub mod prove;
pub mod report;
