//! Mismatch diagnosis (its output and catalogue: `docs/diagnosis-format.md`): calibrate the
//! baseline model of a compression test to a recording (`recording`), locate what remains, name
//! the missing physics from the catalogue (`sim::effects`), fit it, and show the fit improve on
//! a held-out stretch. A library: no command line and no serial code; `tactile diagnose`,
//! `simulate` and `prove` are thin commands over [`diagnose`], [`synth::simulate`] and
//! [`prove`].
//!
//! The steps are modules: [`data`] (read and decimate) -> [`regimes`] -> [`baseline`] and
//! [`fit`] (calibrate) -> [`pipeline`] (candidates, selection, full-rate evaluation, verdict) ->
//! [`localise`], [`mains`] -> [`output`] (OUT.json) and [`report`] (HTML).

pub mod baseline;
pub mod candidate;
pub mod data;
pub mod evidence;
pub mod fe_cache;
pub mod fe_response;
pub mod fit;
pub mod interp;
pub mod lm;
pub mod localise;
pub mod mains;
pub mod map_by_load;
pub mod noise;
pub mod output;
pub mod params;
pub mod pipeline;
pub mod preconditions;
pub mod quantisation;
pub mod regimes;
pub mod response_table;
pub mod select;
pub mod specs;
pub mod standard_test;
pub mod static_shape;
pub mod synth;
pub mod temperature;
pub mod undecided;

pub mod prove;
pub mod report;
pub mod session;

pub use pipeline::{diagnose, Diagnosis, Options, Progress};
