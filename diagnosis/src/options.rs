//! The knobs of a diagnosis and where its baseline comes from: what every step reads and none
//! changes.
use std::sync::Arc;

use baseline::fe_response::FeSource;
use baseline::Readout;

pub use crate::select::Progress;
use crate::simulation::Simulations;

/// Where the baseline model comes from: the one place it is chosen.
#[derive(Debug, Clone, Default)]
pub enum BaselineSource {
    /// Our fingertip's FE tables and our chip ([`Options::fe`]).
    #[default]
    Fe,
    /// The user's own simulation of each recording (`docs/simulation-format.md`), calibrated
    /// with a load scale, the three output scales and four offsets.
    Simulation(Simulations),
}

/// Knobs of a run and the project's model parameters the recording does not carry.
#[derive(Clone)]
pub struct Options {
    /// Our FE model or the user's simulation.
    pub baseline: BaselineSource,
    /// The fingertip FE and the chip behind the baseline's response tables.
    pub fe: FeSource,
    /// The chip's bridge output per volt of excitation per unit load (the `chip` crate).
    pub sensitivity_per_v: [[f64; 3]; 3],
    /// How far the baseline may be calibrated (`hardware/fit-bounds.toml`).
    pub fit_bounds: hardware::FitBounds,
    /// Called as the candidate models are fitted (a progress bar, say).
    pub progress: Option<Arc<Progress>>,
}

impl std::fmt::Debug for Options {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Options")
            .field("baseline", &self.baseline)
            .field("fe", &self.fe)
            .field("sensitivity_per_v", &self.sensitivity_per_v)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

impl Options {
    /// The project's fingertip, chip and pillar from `hardware/`, no progress reports.
    pub fn from_hardware(
        hw: &hardware::Params,
    ) -> Result<Self, chip::from_hardware::FromHardwareError> {
        let fe = Readout::from_chip(hw, [1.0; 3], hw.chip.excitation_v)?;
        Ok(Self {
            baseline: BaselineSource::Fe,
            fe: FeSource::from_hardware(hw)?,
            sensitivity_per_v: fe.signal.sensitivity_per_v,
            fit_bounds: hw.fit_bounds.clone(),
            progress: None,
        })
    }
}
