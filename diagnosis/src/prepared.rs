//! One recording read and ready to fit ([`Prepared`]): its data, stretches and the baseline's
//! response. A single diagnosis (`crate::pipeline`) and each member of a joint one
//! (`crate::joint`) set up their fits from it alike.
use std::sync::Arc;

use baseline::{Drive, Outputs};
use recording::{Meta, Recording};

use crate::calibration::{calibration_setup, Fingertip, Setups};
use crate::data::{Data, DataError};
use crate::fit::Setup;
use crate::misfit::contract_rmse;
use crate::options::{BaselineSource, Options};
use crate::preconditions::{moment_direction, Features};
use crate::simulation::{self, Samples, SimulationError, SimulationReport};
use crate::stretches::Stretches;

/// One recording read and ready to fit: its data, stretches and fingertip. A single diagnosis
/// and each member of a joint one (`crate::joint`) set up their fits from it alike.
#[derive(Clone)]
pub(crate) struct Prepared {
    pub(crate) data: Data,
    pub(crate) stretches: Stretches,
    pub(crate) fingertip: Fingertip,
    /// The user's simulation behind the baseline, where it is one (OUT.json's
    /// `baseline.simulation`).
    pub(crate) simulation: Option<SimulationReport>,
    pub(crate) meta: Meta,
    /// The data without its readings held (`Data::without_held`), if it has any: worked out
    /// once, for every diagnosis of the recording.
    pub(crate) held: Option<Data>,
    /// Channels found frozen, each with the time it froze, s.
    pub(crate) frozen: Vec<(usize, f64)>,
    /// What an earlier diagnosis discovered, which the catalogue is fitted without.
    pub(crate) discovered: Option<crate::terms::AtStage>,
    /// No discovery step ([`Setup::discover`]).
    pub(crate) without_discovery: bool,
}

/// The contract's held-out RMSE of `prediction`'s channels as the model of `rec` (the same
/// samples). With `prediction` the recording without its noise it is the least any model can
/// reach on that stretch: the floor under a held-out ratio. `None` when the two differ in
/// length.
pub fn heldout_rmse_of(
    rec: &Recording,
    prediction: &Recording,
    opt: &Options,
) -> Result<Option<f64>, DataError> {
    let p = prepare(rec, "", opt)?;
    let c = &prediction.channels;
    if c.len() != p.data.full.t_s.len() {
        return Ok(None);
    }
    let o = Outputs {
        load_n: c.load_n.clone(),
        volts: [c.fz_v.clone(), c.mx_v.clone(), c.my_v.clone()],
    };
    Ok(Some(p.rmse(&o).1))
}

/// Read `rec` (called `name` in the outputs) and look up its baseline's response: the FE's at
/// its contact angle and azimuth, or its simulation's (`opt.baseline`).
pub(crate) fn prepare(rec: &Recording, name: &str, opt: &Options) -> Result<Prepared, DataError> {
    let mut data = Data::new(rec)?;
    let meta = rec.meta.clone();
    let (fingertip, simulation) = match &opt.baseline {
        BaselineSource::Fe => {
            let fe = opt.fe.response(
                meta.fingertip_radius_mm,
                meta.contact_angle_deg,
                meta.azimuth_deg,
            )?;
            (Fingertip::Fe(Box::new(fe)), None)
        }
        BaselineSource::Simulation(sims) => {
            let path = sims
                .for_recording(name)
                .ok_or_else(|| SimulationError::Unpaired(name.to_string()))?;
            let at = Samples {
                t_s: &data.full.t_s,
                rod_mm: &data.full.rod_mm,
            };
            let loaded =
                simulation::load(path, rec, at, opt.sensitivity_per_v, sims.accepts_scale())?;
            data = data.unmodelled(loaded.lacks);
            (
                Fingertip::Simulated(Arc::new(loaded.units)),
                Some(loaded.report),
            )
        }
    };
    let stretches = Stretches::detect(&data);
    Ok(Prepared {
        held: data.without_held(),
        data,
        stretches,
        fingertip,
        simulation,
        meta,
        frozen: Vec::new(),
        discovered: None,
        without_discovery: false,
    })
}

impl Prepared {
    /// The recording as a session's member: without the catalogue effects its own diagnosis
    /// found at a stage other than the catalogue's (`at`), which a session's model, with each
    /// effect at its own stage only, is not fitted to; and with the channels `flips` read with
    /// their sign turned back (`inverted_sign`: a wire). The range, the stretches and the free
    /// offsets stay the recording's.
    pub fn for_session(&mut self, at: Option<&crate::terms::AtStage>, flips: &[usize]) {
        let parts = at.map(|a| [&a.full, &a.decimated]);
        for (k, series) in [&mut self.data.full, &mut self.data.fit]
            .into_iter()
            .enumerate()
        {
            for c in 0..4 {
                if let Some(parts) = parts {
                    let part = &parts[k][c];
                    series.y[c].iter_mut().zip(part).for_each(|(y, p)| *y -= p);
                }
                if flips.contains(&c) {
                    series.y[c].iter_mut().for_each(|y| *y = -*y);
                }
            }
        }
        self.held = self.data.without_held();
    }

    /// The calibration setup of this recording's fits.
    pub fn setup(&self, opt: &Options) -> Setup<'_> {
        self.setup_on(&self.data, opt)
    }

    /// The calibration's setups of one diagnosis: on the recording, and on `fitted` (the data
    /// the catalogue is fitted on, [`Prepared::fitted_data`]) where it differs.
    pub(crate) fn setups<'a>(&'a self, fitted: Option<&'a Data>, opt: &Options) -> Setups<'a> {
        Setups {
            whole: self.setup(opt),
            fitted: fitted.map(|d| self.setup_on(d, opt)),
        }
    }

    /// The calibration setup on `data` (this recording's, or it without a frozen channel).
    pub(crate) fn setup_on<'a>(&self, data: &'a Data, opt: &Options) -> Setup<'a> {
        Setup {
            discover: !self.without_discovery,
            ..calibration_setup(data, &self.meta, &self.fingertip, &self.stretches, opt)
        }
    }

    /// The data the catalogue is fitted on where it is not the recording as read: without the
    /// readings held and what a frozen channel read after it froze, and without what the
    /// discovery step found (held as found, so that the calibration is not bent towards it; the
    /// terms are then found again on the whole recording).
    pub(crate) fn fitted_data(&self) -> Option<Data> {
        let base = self.without_frozen().or_else(|| self.held.clone());
        match &self.discovered {
            Some(parts) => Some(parts.taken_from(base.as_ref().unwrap_or(&self.data))),
            None => base,
        }
    }

    /// The data without the readings held (`Data::without_held`) and without what the frozen
    /// channels read after they froze; `None` where none froze.
    pub(crate) fn without_frozen(&self) -> Option<Data> {
        if self.frozen.is_empty() {
            return None;
        }
        let start = self.held.as_ref().unwrap_or(&self.data).clone();
        Some(
            self.frozen
                .iter()
                .fold(start, |d, &(c, t)| d.frozen_from(c, t)),
        )
    }

    /// The drive at the full rate, for the contract's RMSEs.
    pub fn full_drive(&self, setup: &Setup) -> Drive {
        let data = &self.data;
        let (t, rod) = (data.full.t_s.clone(), &data.full.rod_mm);
        let drive = match &self.fingertip {
            Fingertip::Fe(fe) => Drive::new(fe.as_ref(), t, rod),
            Fingertip::Simulated(units) => Drive::of_samples(t, rod, units.to_vec()),
        };
        drive.with_temperature(setup.thermal.and(data.full.temp_c.clone()))
    }

    /// What the recording's protocol shows, for the effects' preconditions.
    pub fn features(&self, setup: &Setup) -> Features {
        let phi = moment_direction(&setup.drive);
        Features::of(
            &self.data,
            &self.stretches.segments,
            setup.used,
            setup.thermal.is_some(),
        )
        .with_moment_direction(phi, setup.fit_bounds.jig_azimuth_tolerance_deg)
    }

    /// The held-out stretch (start, end), s.
    pub fn heldout(&self) -> (f64, f64) {
        self.stretches.heldout
    }

    /// The contract's RMSEs of `o` (full rate): the whole recording, the held-out stretch.
    pub fn rmse(&self, o: &Outputs) -> (f64, f64) {
        let mask = self.stretches.mask(&self.data.full.t_s);
        let all = vec![true; mask.len()];
        (
            contract_rmse(&self.data, o, &all),
            contract_rmse(&self.data, o, &mask),
        )
    }
}
