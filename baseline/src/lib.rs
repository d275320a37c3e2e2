//! The baseline model of a compression test: what the sensor in its fingertip records when
//! nothing but the modelled physics acts. The diagnosis calibrates it to a recording; `tactile
//! simulate` writes its own recording of the standard test; the proof's generators add
//! concealed effects to it.
//!
//! The steps: the fingertip's response to rod travel ([`response`]), from the FE model's tables
//! ([`fe_response`], [`response_table`], cached beside the FE by `fingertip::cache`), read at a
//! load ([`map_by_load`]); the rod's drive and the outputs through the one forward model of the
//! signal ([`model`]: `sim::forward`); a whole recording with noise and effects ([`synth`]); the
//! standard test of `hardware/` ([`standard_test`]).
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

pub mod fe_response;
pub mod interp;
pub mod map_by_load;
pub mod model;
pub mod response;
pub mod response_table;
pub mod standard_test;
pub mod synth;

pub use model::{evaluate, smoother_tau_s, BaselineParams, Drive, Outputs, Readout};
pub use response::{FingertipResponse, UnitResponse};
pub use response_table::ResponseTable;
