//! `paper-sensor.toml`: the original paper's sensor where it differs from the project's default
//! model: the law of Fz across the inclination that the paper reports, the gel's relaxation and
//! the AC coupling of its offset cut (the reasons are in the file). Only the paper's session and
//! the paper's-sensor scorecard (`tactile observations --session`, `--paper-sensor`) read it; the
//! default model, `tactile simulate` and the diagnosis's baseline never do.

use std::path::Path;

use crate::{ParamError, Reader};

/// The paper's sensor: its angle law of Fz and its time behaviour.
#[derive(Debug, Clone, PartialEq)]
pub struct PaperSensor {
    /// Fz at the peak load over Fz at 0°, per degree of inclination above 0° (linear law).
    pub fz_rise_per_deg: f64,
    /// Share of the gel's modulus that relaxes (a Prony term's g).
    pub relaxation_fraction: f64,
    /// Time constant of that relaxation.
    pub relaxation_tau_s: f64,
    /// Time constant of the offset cut's AC coupling of every output.
    pub ac_coupling_tau_s: f64,
}

impl PaperSensor {
    pub(crate) fn load(file: &Path) -> Result<Self, Vec<ParamError>> {
        let mut r = Reader::open(file).map_err(|e| vec![e])?;
        let sensor = Self {
            fz_rise_per_deg: r.f64("angle_law.fz_rise_per_deg", -0.02..=0.02),
            relaxation_fraction: r.f64("gel.relaxation_fraction", 0.0..=0.95),
            relaxation_tau_s: r.f64("gel.relaxation_tau_s", 1.0e-3..=1.0e4),
            ac_coupling_tau_s: r.f64("offset_cut.ac_coupling_tau_s", 1.0e-3..=1.0e6),
        };
        r.finish()?;
        Ok(sensor)
    }

    /// The paper's Fz at the peak load at `theta_deg` over that at 0°.
    pub fn fz_ratio(&self, theta_deg: f64) -> f64 {
        1.0 + self.fz_rise_per_deg * theta_deg
    }
}
