//! The one forward model of the signal: chip loads (Fz, Mx, My) -> beam stresses ->
//! piezoresistor ΔR/R -> bridge outputs (the `chip` crate's model, as its sensitivity matrix)
//! -> amplifier gains -> volts at the ADC inputs after the offset cut.
//!
//! `tactile simulate`, the proof's generator and the diagnosis's baseline compute their volts
//! with [`SignalPath::volts`]; the emulated sensor ([`crate::chain`]) feeds
//! [`SignalPath::bridge_v`] into its circuit, which adds the operating point (the arms' mismatch,
//! the trim DAC, the amplifiers' offsets and rails), then noise and the ADC. Inside the rails
//! both give the same volts up to rounding.
//!
//! Linear in the load, as the diagnosis's baseline is: the stresses are linear in the load and
//! the bridges are taken at their zero-load slope. The divider's own curvature (a relative error
//! of about ΔR/R / 2, below 0.1 % at the standard test's peak) is the catalogue's
//! `bridge_nonlinearity` effect where a recording shows it.

use chip::{sensitivity_matrix, ChipParams, Matrix3};

use crate::frontend::{FrontEnd, CHANNELS};

/// Chip loads to the volts at the ADC inputs of the three bridge channels (Fz, Mx, My).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SignalPath {
    /// Bridge output per volt of excitation per unit load: rows are the bridges [Fz, Mx, My],
    /// columns the loads [Fz (N), Mx (N·m), My (N·m)].
    pub sensitivity_per_v: Matrix3,
    /// Small-signal voltage gain from each bridge's terminals to its ADC input.
    pub gain: [f64; CHANNELS],
    /// Bridge excitation, V.
    pub excitation_v: f64,
}

impl SignalPath {
    /// The chip's sensitivity matrix (its beams, piezoresistors and bridges) per volt of its own
    /// excitation, with the amplifier `gain`s and bridge `excitation_v` given (a recording's
    /// metadata, say).
    pub fn from_chip(chip: &ChipParams, gain: [f64; CHANNELS], excitation_v: f64) -> Self {
        let s = sensitivity_matrix(chip);
        Self {
            sensitivity_per_v: s.map(|row| row.map(|v| v / chip.excitation_v)),
            gain,
            excitation_v,
        }
    }

    /// The chip behind `front_end`'s amplifier chains: their DC gains, the chip's excitation.
    pub fn from_front_end(chip: &ChipParams, front_end: &FrontEnd) -> Self {
        let gain = core::array::from_fn(|i| front_end.channels[i].gain());
        Self::from_chip(chip, gain, chip.excitation_v)
    }

    /// The bridges' outputs at their terminals for chip loads `load` (Fz in N, Mx and My in
    /// N·m).
    pub fn bridge_v(&self, load: [f64; 3]) -> [f64; CHANNELS] {
        core::array::from_fn(|b| self.excitation_v * self.per_volt(b, load))
    }

    /// The volts at the ADC inputs for chip loads `load` (Fz in N, Mx and My in N·m).
    pub fn volts(&self, load: [f64; 3]) -> [f64; CHANNELS] {
        core::array::from_fn(|b| self.gain[b] * self.excitation_v * self.per_volt(b, load))
    }

    /// The chip loads (Fz in N, Mx and My in N·m) that give `volts` at the ADC inputs: the
    /// inverse of [`Self::volts`]. A model that gives volts rather than loads (a user's
    /// simulation) is read back to the loads the mechanical effects act on; `None` where the
    /// path is singular (a zero gain or excitation, a degenerate chip).
    pub fn chip_loads(&self, volts: [f64; CHANNELS]) -> Option<[f64; 3]> {
        let inv = chip::sensitivity::inverse(&self.sensitivity_per_v)?;
        let per_volt: [f64; CHANNELS] =
            core::array::from_fn(|b| volts[b] / (self.gain[b] * self.excitation_v));
        if per_volt.iter().any(|v| !v.is_finite()) {
            return None;
        }
        Some(core::array::from_fn(|k| {
            inv[k][0] * per_volt[0] + inv[k][1] * per_volt[1] + inv[k][2] * per_volt[2]
        }))
    }

    /// Bridge `b`'s output per volt of excitation.
    fn per_volt(&self, b: usize, load: [f64; 3]) -> f64 {
        let s = &self.sensitivity_per_v[b];
        s[0] * load[0] + s[1] * load[1] + s[2] * load[2]
    }
}

#[cfg(feature = "std")]
impl SignalPath {
    /// Everything from `hardware/`: the chip and its excitation of `chip.toml`, the amplifier
    /// chains of `frontend.toml`.
    pub fn from_params(
        p: &hardware::Params,
    ) -> Result<Self, chip::from_hardware::FromHardwareError> {
        let chip = ChipParams::try_from(&p.chip)?;
        Ok(Self::from_front_end(&chip, &FrontEnd::from_params(p)))
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;

    /// Small loads: the linear path and the chip's exact bridges through the same gains agree
    /// to the divider's curvature, ΔR/R / 2.
    #[test]
    fn agrees_with_the_exact_bridges_at_small_loads() {
        let p = hardware::Params::load_default().unwrap();
        let chip = ChipParams::try_from(&p.chip).unwrap();
        let path = SignalPath::from_params(&p).unwrap();
        let load = chip::Load::new(1.0e-3, 2.0e-7, -1.0e-7);
        let exact = chip::bridge_outputs_v(&chip, load);
        let linear = path.bridge_v(load.to_array());
        for (e, l) in exact.iter().zip(linear) {
            assert!((e - l).abs() < 1e-3 * e.abs(), "{e} vs {l}");
        }
        let volts = path.volts(load.to_array());
        for i in 0..CHANNELS {
            assert!((volts[i] - path.gain[i] * linear[i]).abs() < 1e-15 * volts[i].abs().max(1.0));
        }
    }

    /// Volts read back to chip loads give the loads again.
    #[test]
    fn chip_loads_invert_the_volts() {
        let p = hardware::Params::load_default().unwrap();
        let path = SignalPath::from_params(&p).unwrap();
        let load = [1.5, 2.0e-4, -3.0e-4];
        let back = path.chip_loads(path.volts(load)).unwrap();
        for (a, b) in load.iter().zip(back) {
            assert!((a - b).abs() < 1e-9 * a.abs(), "{a} vs {b}");
        }
        let dead = SignalPath {
            gain: [0.0, 1.0, 1.0],
            ..path
        };
        assert!(dead.chip_loads([1.0; 3]).is_none());
    }
}
