//! The calibration's setup: everything the fits of one recording share (the drive on the
//! decimated series, the front end its metadata describes, the stretches, the channels worth
//! comparing), from the baseline's response to the recorded rod path ([`Fingertip`]).
use std::sync::Arc;

use baseline::fe_response::AngleBlend;
use baseline::{Drive, Readout, UnitResponse};
use recording::Meta;
use sim::forward::SignalPath;

use crate::data::Data;
use crate::fit::Setup;
use crate::options::Options;
use crate::simulation;
use crate::stretches::Stretches;

/// The baseline's response to the recorded rod path.
#[derive(Clone)]
pub(crate) enum Fingertip {
    /// Our FE tables at the recording's contact angle and azimuth.
    Fe(Box<AngleBlend>),
    /// The user's simulation at each full-rate sample of the recording (load scale 1).
    Simulated(Arc<Vec<UnitResponse>>),
}

/// Everything the fits of one recording share: the drive on the decimated series, the front end
/// of the recording's metadata, the stretches and the channels worth comparing.
pub(crate) fn calibration_setup<'a>(
    data: &'a Data,
    meta: &Meta,
    fingertip: &Fingertip,
    stretches: &Stretches,
    opt: &Options,
) -> Setup<'a> {
    let fit_t = &data.fit.t_s;
    let heldout_mask = stretches.mask(fit_t);
    let thermal = match (&data.fit.temp_c, &data.full.temp_c) {
        (Some(fit), Some(full)) => crate::temperature::fit(fit_t, fit, full),
        _ => None,
    };
    let (t, rod) = (fit_t.clone(), &data.fit.rod_mm);
    let (drive, fit_bounds) = match fingertip {
        Fingertip::Fe(fe) => (
            Drive::over_blocks(fe.as_ref(), t, rod, &data.full.rod_mm, &data.bounds),
            opt.fit_bounds.clone(),
        ),
        Fingertip::Simulated(units) => (
            Drive::over_blocks_of_samples(t, rod, units, &data.bounds),
            simulation::calibration_bounds(&opt.fit_bounds, data.compared(0)),
        ),
    };
    Setup {
        data,
        drive: drive.with_temperature(thermal.and(data.fit.temp_c.clone())),
        user_simulation: matches!(fingertip, Fingertip::Simulated(_)),
        readout: readout(meta, opt),
        contact_angle_deg: meta.contact_angle_deg,
        fit_mask: heldout_mask.iter().map(|h| !h).collect(),
        heldout_mask,
        used: std::array::from_fn(|c| data.compared(c)),
        discover: true,
        thermal,
        fit_bounds,
        initial: Default::default(),
        scale_reference: Default::default(),
        sensor_unit: meta.get("sensor_unit").unwrap_or("V").to_string(),
    }
}

/// The front end the recording describes: the chip's sensitivities with the metadata's gains,
/// excitation and firmware smoother.
fn readout(meta: &Meta, opt: &Options) -> Readout {
    Readout {
        signal: SignalPath {
            sensitivity_per_v: opt.sensitivity_per_v,
            gain: [meta.gain_fz, meta.gain_mx, meta.gain_my],
            excitation_v: meta.excitation_v,
        },
        smoother_tau_s: meta
            .other
            .iter()
            .find(|(k, _)| k == recording::SMOOTHER_KEY)
            .and_then(|(_, v)| v.trim().parse::<f64>().ok())
            .and_then(|alpha| baseline::smoother_tau_s(alpha, meta.sample_rate_hz)),
    }
}

/// The calibration's setups of one diagnosis: on the recording as read (`whole`: its
/// localisation, full-rate evaluation and description), and on the data the catalogue is
/// fitted on where that differs (`fitted`: without readings held, a frozen channel's samples
/// or what the discovery step found).
pub(crate) struct Setups<'a> {
    pub whole: Setup<'a>,
    pub fitted: Option<Setup<'a>>,
}

impl Setups<'_> {
    /// The setup the catalogue's candidates are fitted with.
    pub fn for_selection(&self) -> &Setup<'_> {
        self.fitted.as_ref().unwrap_or(&self.whole)
    }
}
