//! The simulated standard compression test with the options of `tactile simulate`: the nominal
//! baseline at a modulus, the lab's temperature of `hardware/sim.toml`, the caller's loads,
//! catalogue effects, noise, gains and smoother. One implementation for the command line and
//! the Python package (`tactile.simulate`), so both write the same recording for the same
//! options.

use chip::from_hardware::FromHardwareError;
use recording::Recording;
use sim::compression::RodSchedule;
use sim::effects::Effect;

use crate::fe_response::{FeResponseError, FeSource};
use crate::model::{smoother_tau_s, BaselineParams, Readout};
use crate::response::FingertipResponse;
use crate::synth::{simulate_to_peaks, Noise, SimSpec};
use recording::SMOOTHER_KEY;

/// The options of `tactile simulate` that shape the recording (the command's output files are
/// its own). Optional values default to `hardware/`.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulateOptions {
    /// Inclination theta_p of the load axis from the fingertip axis, deg.
    pub contact_angle_deg: f64,
    /// Azimuth phi of the tilt plane from the chip's x axis, deg.
    pub azimuth_deg: f64,
    /// Load at which the rod stops and holds, N: the recorded load's peak, whatever the
    /// effects on the load ([`crate::synth::rod_history_to_peaks`]).
    pub peak_load_n: f64,
    /// Sample rate, Hz [default: `fingertip.toml` test.sample_rate_hz].
    pub rate_hz: Option<f64>,
    /// The rod's speed while it loads, mm/min [default: `fingertip.toml`
    /// test.rod_speed_mm_per_min].
    pub rod_speed_mm_per_min: Option<f64>,
    /// Rest after each return, s [default: `fingertip.toml` test.recovery_s]. With further
    /// cycles it sets the length of a long recording (the batch benchmark's 300 s).
    pub recovery_s: Option<f64>,
    /// Gel Young's modulus, Pa [default: `fingertip.toml`].
    pub modulus_pa: Option<f64>,
    /// Further compression cycles at these peak loads, N.
    pub then_peak_loads_n: Vec<f64>,
    /// White noise on each output, V (standard deviation).
    pub noise_v: f64,
    /// White noise on the load cell, N.
    pub noise_load_n: f64,
    /// Noise seed.
    pub seed: u64,
    /// Catalogue effects as `name:param=value,...` ([`Effect::from_spec`]).
    pub effects: Vec<String>,
    /// Amplifier gains Fz, Mx, My [default: `frontend.toml`'s amplifier chain].
    pub gain: Option<[f64; 3]>,
    /// The firmware's first-order smoother's alpha [default: off].
    pub smoother_alpha: Option<f64>,
    /// A sinusoidal swing of the ambient temperature: amplitude (degC) and period (s).
    pub ambient_swing: Option<(f64, f64)>,
    /// Bridge excitation, V [default: `chip.toml`].
    pub excitation_v: Option<f64>,
}

impl SimulateOptions {
    /// The command's defaults for the given angles and peak load: no noise, seed 1, no
    /// effects, every optional value from `hardware/`.
    pub fn new(contact_angle_deg: f64, azimuth_deg: f64, peak_load_n: f64) -> Self {
        Self {
            contact_angle_deg,
            azimuth_deg,
            peak_load_n,
            rate_hz: None,
            rod_speed_mm_per_min: None,
            recovery_s: None,
            modulus_pa: None,
            then_peak_loads_n: Vec::new(),
            noise_v: 0.0,
            noise_load_n: 0.0,
            seed: 1,
            effects: Vec::new(),
            gain: None,
            smoother_alpha: None,
            ambient_swing: None,
            excitation_v: None,
        }
    }

    /// The standard test of `fingertip.toml`, at [`SimulateOptions::rate_hz`] if given.
    pub fn compression_test(&self, tip: &hardware::Fingertip) -> RodSchedule {
        RodSchedule {
            sample_rate_hz: self.rate_hz.unwrap_or(tip.test.sample_rate_hz),
            speed_mm_per_min: self
                .rod_speed_mm_per_min
                .unwrap_or(tip.test.rod_speed_mm_per_min),
            hold_s: tip.test.hold_s,
            return_speed_mm_per_min: tip.test.return_speed_mm_per_min,
            recovery_s: self.recovery_s.unwrap_or(tip.test.recovery_s),
            ..Default::default()
        }
    }

    /// The values a command line cannot check alone. The messages name the command's flags,
    /// whose names the Python keywords share.
    pub fn check(&self) -> Result<(), SimulateError> {
        if !positive(self.peak_load_n) {
            return Err(SimulateError::PeakLoad);
        }
        if self
            .rod_speed_mm_per_min
            .is_some_and(|v| !(positive(v) && v.is_finite()))
        {
            return Err(SimulateError::RodSpeed);
        }
        if let Some(recovery_s) = self.recovery_s {
            if !(recovery_s.is_finite() && recovery_s >= 0.0) {
                return Err(SimulateError::Recovery);
            }
        }
        if let Some((_, period_s)) = self.ambient_swing {
            if !positive(period_s) {
                return Err(SimulateError::SwingPeriod);
            }
        }
        if let Some(alpha) = self.smoother_alpha {
            if !(positive(alpha) && alpha < 1.0) {
                return Err(SimulateError::SmootherAlpha);
            }
        }
        Ok(())
    }
}

/// Whether `x` is a positive number (`NaN` is not).
fn positive(x: f64) -> bool {
    x > 0.0
}

/// Why a simulation could not run.
#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    /// An effect that is not `name:param=value,...` of the catalogue.
    #[error("--effect: {0}")]
    Effect(String),
    /// A peak load that is not positive.
    #[error("--peak-load must be positive")]
    PeakLoad,
    /// A rod speed that is not a positive number.
    #[error("--rod-speed must be positive (mm/min)")]
    RodSpeed,
    /// A rest after the return that is negative or not a number.
    #[error("--recovery-s must be zero or positive")]
    Recovery,
    /// An ambient swing whose period is not positive.
    #[error("--ambient-swing: the period must be positive")]
    SwingPeriod,
    /// A smoother alpha outside (0, 1).
    #[error("--smoother-alpha must lie in (0, 1)")]
    SmootherAlpha,
    /// The chip or front end of `hardware/` cannot be built.
    #[error(transparent)]
    Hardware(#[from] FromHardwareError),
    /// The fingertip's FE response for the angles failed.
    #[error(transparent)]
    Fingertip(#[from] FeResponseError),
}

/// Options out of range and a hardware description that makes no sensor are bad input.
impl sysexit::ExitStatus for SimulateError {
    fn exit_code(&self) -> u8 {
        match self {
            SimulateError::Hardware(_) => sysexit::DATA,
            _ => sysexit::USAGE,
        }
    }
}

/// The recording of the standard test with `opt`, through the same forward model as the
/// emulated sensor ([`simulate_to_peaks`]: each cycle stops where the recorded load reaches
/// its peak); a smoother is named in the metadata ([`SMOOTHER_KEY`]).
pub fn simulate_standard_test(
    opt: &SimulateOptions,
    params: &hardware::Params,
) -> Result<Recording, SimulateError> {
    simulate_standard_test_with(opt, params, |_| {})
}

/// [`simulate_standard_test`] of a sensor whose baseline departs from the nominal one as
/// `adjust` says (e.g. another Fz sensitivity: the paper's angle law of Fz in the paper's
/// session, `tactile observations --session`). The recording's metadata stay the true test's.
pub fn simulate_standard_test_with(
    opt: &SimulateOptions,
    params: &hardware::Params,
    adjust: impl FnOnce(&mut BaselineParams),
) -> Result<Recording, SimulateError> {
    let effects = opt
        .effects
        .iter()
        .map(|s| Effect::from_spec(s).map_err(SimulateError::Effect))
        .collect::<Result<Vec<_>, _>>()?;
    opt.check()?;
    let test = opt.compression_test(&params.fingertip);
    let readout = readout(opt, params, test.sample_rate_hz)?;
    let fingertip = FeSource::from_hardware(params)?.response(
        params.fingertip.radius_mm,
        opt.contact_angle_deg,
        opt.azimuth_deg,
    )?;
    let mut spec = spec(opt, params, &fingertip, readout, test, effects);
    adjust(&mut spec.baseline);
    let mut rec = simulate_to_peaks(&spec);
    if let Some(alpha) = opt.smoother_alpha {
        rec.meta
            .other
            .push((SMOOTHER_KEY.to_string(), alpha.to_string()));
    }
    Ok(rec)
}

/// The emulated sensor's front end, with the options' gains, excitation and smoother.
fn readout(
    opt: &SimulateOptions,
    params: &hardware::Params,
    sample_rate_hz: f64,
) -> Result<Readout, FromHardwareError> {
    let nominal = Readout::from_hardware(params)?;
    let gain = opt.gain.unwrap_or(nominal.signal.gain);
    let excitation_v = opt.excitation_v.unwrap_or(nominal.signal.excitation_v);
    let mut readout = Readout::from_chip(params, gain, excitation_v)?;
    readout.smoother_tau_s = opt
        .smoother_alpha
        .and_then(|alpha| smoother_tau_s(alpha, sample_rate_hz));
    Ok(readout)
}

/// The simulation: the nominal baseline at the given modulus, the lab's temperature of
/// `sim.toml`, the options' loads, effects and noise.
fn spec<'a>(
    opt: &SimulateOptions,
    params: &hardware::Params,
    fingertip: &'a dyn FingertipResponse,
    readout: Readout,
    test: RodSchedule,
    effects: Vec<Effect>,
) -> SimSpec<'a> {
    let tip = &params.fingertip;
    let names: Vec<&str> = effects.iter().map(|e| e.kind().name()).collect();
    SimSpec {
        fingertip,
        readout,
        baseline: BaselineParams::nominal(opt.modulus_pa.unwrap_or(tip.youngs_modulus_pa)),
        contact_angle_deg: opt.contact_angle_deg,
        azimuth_deg: opt.azimuth_deg,
        radius_mm: tip.radius_mm,
        test,
        peak_loads_n: std::iter::once(opt.peak_load_n)
            .chain(opt.then_peak_loads_n.iter().copied())
            .collect(),
        source: format!(
            "tactile simulate (FE baseline); effects: [{}]",
            names.join(" ")
        ),
        effects,
        noise: Noise {
            load_n: opt.noise_load_n,
            volts: [opt.noise_v; 3],
            temp_c: 0.0,
        },
        seed: opt.seed,
        ambient_c: params.sim.ambient_c,
        warm_up_rise_c: params.sim.warmup_rise_c,
        ambient_swing: opt.ambient_swing,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_outside_their_range_are_refused_naming_the_flag() {
        let ok = SimulateOptions::new(10.0, 0.0, 2.0);
        assert!(ok.check().is_ok());
        let cases = [
            (SimulateOptions::new(10.0, 0.0, 0.0), "--peak-load"),
            (
                SimulateOptions {
                    rod_speed_mm_per_min: Some(0.0),
                    ..ok.clone()
                },
                "--rod-speed",
            ),
            (
                SimulateOptions {
                    ambient_swing: Some((1.0, 0.0)),
                    ..ok.clone()
                },
                "--ambient-swing",
            ),
            (
                SimulateOptions {
                    smoother_alpha: Some(1.0),
                    ..ok.clone()
                },
                "--smoother-alpha",
            ),
        ];
        for (opt, flag) in cases {
            let message = opt.check().unwrap_err().to_string();
            assert!(message.starts_with(flag), "{message}");
        }
    }
}
