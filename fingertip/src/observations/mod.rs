//! The paper's seven observations of the real sensor, tested one by one against the model: a
//! scorecard with, per observation, the paper's statement, the quantities that test it, the
//! model's values, agree or disagree, and the physics responsible.
//!
//! The criteria and their reasons are in `fingertip/OBSERVATIONS.md`; [`criteria`] holds them
//! as constants. The model is the FE fingertip of a [`Config`] through the standard test
//! ([`runs`]); the chip's loads stand for its outputs (its bridges are linear in them, so
//! ratios, exponents, times and signs carry over). An optional `output_filter` applies
//! electronics to each output's time series (e.g. the AC coupling of the offset cut, an
//! operator of the `sim` catalogue): the caller passes it in, so this crate does not depend on
//! `sim` (whose tests depend on this crate) and the FE stays free of the signal chain.

pub mod causes;
pub mod criteria;
pub mod energy;
pub mod measures;
pub mod runs;
mod scorecard;

pub use runs::{FeSchedule, TestSeries};
pub use scorecard::score;

use crate::{Config, CurvePoint};

/// Electronics applied to one output's time series `(t_s, values)` in place.
pub type OutputFilter = dyn Fn(&[f64], &mut [f64]) + Sync;

/// What is scored: a fingertip model, the test, the inclinations of the sweep.
pub struct Setup<'a> {
    /// The model at the paper's inclined test (theta_p = 20°, phi = 60°).
    pub config: Config,
    pub test: FeSchedule,
    /// Inclinations of the sweep, degrees, ascending from 0 (the reference) to the largest
    /// (observation 6); the test's inclination is run as part of the standard test.
    pub sweep_deg: Vec<f64>,
    /// A name for the model variant.
    pub label: String,
    /// Electronics on each output (None: the chip's loads as they are).
    pub output_filter: Option<&'a OutputFilter>,
}

/// Inclinations of the scorecard's sweep, degrees: the reference, the chapter's steps up to its
/// largest angle (observation 6).
pub const SWEEP_DEG: [f64; 4] = [0.0, 10.0, 20.0, 30.0];

impl<'a> Setup<'a> {
    /// `config` through the standard test of `hardware/fingertip.toml` and the sweep
    /// [`SWEEP_DEG`]: the one place the scorecard's test is read from the hardware files.
    pub fn from_hardware(
        config: Config,
        hw: &hardware::Fingertip,
        label: &str,
        output_filter: Option<&'a OutputFilter>,
    ) -> Self {
        Setup {
            config,
            test: FeSchedule {
                peak_load_n: hw.test.peak_load_n,
                hold_s: hw.test.hold_s,
                return_speed_mm_per_s: hw.test.return_speed_mm_per_min / 60.0,
                recovery_s: hw.test.recovery_s,
            },
            sweep_deg: SWEEP_DEG.to_vec(),
            label: label.into(),
            output_filter,
        }
    }
}

/// One quantity that tests an observation.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Check {
    /// What is measured, with its unit.
    pub quantity: String,
    /// The model's value.
    pub value: f64,
    /// The criterion for agreement, in words with its threshold.
    pub criterion: String,
    pub agree: bool,
}

/// One observation of the paper against the model.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Row {
    /// The observation's number in the paper's list (1..=7).
    pub number: u8,
    /// The paper's statement.
    pub statement: String,
    pub checks: Vec<Check>,
    /// Every check agrees.
    pub agree: bool,
    /// The physics in the model that produces (or fails to produce) the observation.
    pub physics: String,
}

/// The scorecard and the series it was computed from (for plots).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Scorecard {
    pub label: String,
    pub rows: Vec<Row>,
    /// (theta_p in degrees, outputs at the peak load) for each inclination of the sweep.
    pub sweep: Vec<(f64, CurvePoint)>,
    /// The whole standard test at the test's inclination (outputs after `output_filter`).
    pub series: TestSeries,
    /// Azimuth of the tilt plane, degrees.
    pub azimuth_deg: f64,
}

impl Scorecard {
    /// Rows that disagree.
    pub fn disagreements(&self) -> Vec<u8> {
        self.rows
            .iter()
            .filter(|r| !r.agree)
            .map(|r| r.number)
            .collect()
    }
}

/// Moment about the tilt-plane normal (sin phi, -cos phi): the moment the tilt produces, N·m.
pub fn tilt_moment_nm(p: &CurvePoint, phi_deg: f64) -> f64 {
    let phi = phi_deg.to_radians();
    p.mx_nm * phi.sin() - p.my_nm * phi.cos()
}

/// Moment about the tilt direction (cos phi, sin phi): crosstalk of the tilt, N·m.
pub fn cross_moment_nm(p: &CurvePoint, phi_deg: f64) -> f64 {
    let phi = phi_deg.to_radians();
    p.mx_nm * phi.cos() + p.my_nm * phi.sin()
}
