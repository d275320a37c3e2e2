//! `sim.toml`: the emulated sensor's own parameters: the pillar that carries the gel's traction
//! onto the chip, and the warm-up of the temperature next to the chip.

use std::path::Path;

use crate::{ParamError, Reader};

/// Parameters only the emulation needs.
#[derive(Debug, Clone, PartialEq)]
pub struct Sim {
    /// Diameter of the pillar on the chip's central block.
    pub pillar_diameter_um: f64,
    /// Air temperature around the fingertip.
    pub ambient_c: f64,
    /// Final temperature rise near the chip from the electronics' own dissipation.
    pub warmup_rise_c: f64,
    /// Time constant of that rise from power-up.
    pub warmup_tau_s: f64,
}

impl Sim {
    pub(crate) fn load(file: &Path) -> Result<Self, Vec<ParamError>> {
        let mut r = Reader::open(file).map_err(|e| vec![e])?;
        let sim = Self {
            pillar_diameter_um: r.f64("pillar.diameter_um", 1.0..=2000.0),
            ambient_c: r.f64("temperature.ambient_c", -40.0..=85.0),
            warmup_rise_c: r.f64("temperature.warmup_rise_c", 0.0..=50.0),
            warmup_tau_s: r.f64("temperature.warmup_tau_s", 1.0e-3..=1.0e5),
        };
        r.finish()?;
        Ok(sim)
    }
}
