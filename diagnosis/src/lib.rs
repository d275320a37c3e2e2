//! Mismatch diagnosis (its output and catalogue: `docs/diagnosis-format.md`): calibrate the
//! baseline model of a compression test (crate `baseline`) to a recording (`recording`), locate
//! what remains, name the missing physics from the catalogue (`sim::effects`), fit it, and show
//! the fit improve on a held-out stretch. A library: no command line; `tactile diagnose` is a
//! thin command over [`diagnose`], and the proof (crate `prove`) scores it.
//!
//! The public API: [`diagnose`] with its [`Options`] gives a [`Diagnosis`]; [`output`] is its
//! JSON (`tactile-diagnosis/1`), [`report::write`] its HTML page, [`session`] a batch of
//! recordings with their summary, [`joint`] a session diagnosed jointly; [`inputs`] and
//! [`outputs`] check the files a run reads and writes before any work.
//!
//! The private modules, each importing only those before it: `stats` (tests and estimators)
//! -> `data` (read, decimate; `noise`, `quantisation`) -> `regimes` -> `preconditions` -> `fit`
//! (calibrate; `specs`, `lm`, `temperature`) -> `candidate` -> `params` -> `select` (the
//! effects' selection) -> `localise`, `mains` -> `evidence` -> `terms` (the library beyond the
//! catalogue) -> the types the steps share (`options`, `stretches`, `calibration`, `misfit`,
//! `prepared`, `outcome`) -> `steps` (one module per step) -> `pipeline` (the steps in order,
//! holding none of them) -> [`output`] and [`report`].
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

mod calibration;
mod candidate;
mod certify;
mod data;
mod evidence;
mod fit;
pub mod inputs;
pub mod joint;
mod lm;
mod localise;
mod mains;
mod misfit;
mod noise;
mod options;
mod outcome;
pub mod output;
pub mod outputs;
mod params;
mod pipeline;
mod preconditions;
mod prepared;
mod quantisation;
mod regimes;
pub mod report;
mod scale_check;
mod select;
pub mod session;
pub mod simulation;
mod specs;
mod static_shape;
mod stats;
mod steps;
mod stretches;
mod temperature;
mod terms;
mod undecided;

pub use data::DataError;
pub use fit::model_evaluations;
pub use options::{BaselineSource, Options, Progress};
pub use outcome::Diagnosis;
pub use pipeline::{diagnose, diagnose_owned};
pub use preconditions::mains_visible;
pub use prepared::heldout_rmse_of;
