//! The user's own simulation as the baseline (`tactile prove --simulation-category`): the lab
//! models the test with another model than ours (another contact law and other output laws:
//! [`lab::LabModel`]) and writes its simulation to a file as a lab would (a static response
//! table, or the test in time at its own rate and time base, some at the bridges' volts, some
//! without moments or without the load); the recording is that model with the gel, gains and
//! offsets the lab did not know, plus concealed catalogue effects drawn as the standard proof
//! draws them. Each recording is diagnosed blind against the lab's simulation, and against our
//! own baseline beside it for comparison.

pub mod lab;
mod score;

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use sim::compression::RodSchedule;
use sim::effects::{Effect, EffectKind};

use crate::categories::OtherFingertip;
use crate::{random_params, Case, Jig, Plan, Score};
use baseline::synth::{rod_at, simulate, Gaussian, SimSpec};
use baseline::{BaselineParams, FingertipResponse, Readout};
use diagnosis::simulation::Simulations;
use diagnosis::{BaselineSource, Options};
use lab::{Form, LabModel, Lumped, RodPath, Written};
pub use score::{table, Figures, PRIMARY_WITHIN};

/// The lab's guess of the gel's modulus, Pa: the recordings' gels are 1.0e5-1.5e5 Pa.
const LAB_MODULUS_PA: f64 = 1.2e5;

/// One recording of the category, the lab's simulation of it and what was hidden.
pub struct SimCase {
    pub case: Case,
    pub simulation: PathBuf,
    pub form: Form,
    pub model: String,
    /// The channels the simulation leaves empty.
    pub lacks: [bool; 4],
    /// The load scale a right calibration finds: the recording's modulus over the lab's.
    pub load_scale: f64,
}

/// A case scored both ways.
pub struct Scored {
    pub against_simulation: Score,
    pub against_ours: Score,
    /// The load scale the diagnosis against the simulation calibrated.
    pub load_scale: Option<f64>,
}

/// Errors of the category: an FE table for the lab's reference, or writing a simulation.
#[derive(Debug, thiserror::Error)]
pub enum CategoryError {
    #[error(transparent)]
    Fe(#[from] baseline::fe_response::FeResponseError),
    #[error("writing {}: {source}", .path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
}

impl Plan {
    /// The category's recordings, their simulations written into `dir` (in parallel, each from
    /// its own seed): the standard proof's effect sets, each once with a table and once with a
    /// simulated test.
    pub fn simulation_cases(&self, dir: &Path) -> Result<Vec<SimCase>, CategoryError> {
        std::fs::create_dir_all(dir).map_err(|source| CategoryError::Write {
            path: dir.to_path_buf(),
            source,
        })?;
        let truths = self.truths();
        let n = truths.len();
        (0..2 * n)
            .into_par_iter()
            .map(|i| self.simulation_case(3000 + i, &truths[i % n], i >= n, dir))
            .collect()
    }

    /// One case: the jig, the lab's model and the truth from the case's seed.
    fn simulation_case(
        &self,
        id: usize,
        kinds: &[EffectKind],
        series: bool,
        dir: &Path,
    ) -> Result<SimCase, CategoryError> {
        let mut g = Gaussian::new(
            self.seed
                .wrapping_mul(0x9E37_79B9_7F4A_7C15)
                .wrapping_add(id as u64 * 7919 + 3),
        );
        let mut u = |a: f64, b: f64| a + (b - a) * g.uniform();
        let jig = Jig::draw(id, &mut u);
        let fe =
            self.options
                .fe
                .response(self.radius_mm, jig.contact_angle_deg, jig.azimuth_deg)?;
        let d_ref_mm = sim::compression::rod_at_load(
            |d| fe.unit_response(d).force_n * jig.modulus_pa,
            jig.peak_n,
            60.0,
        );
        let model = draw_model(&fe, d_ref_mm, id, &mut u);
        let truth_base = truth_baseline(jig.modulus_pa, &mut u);
        let second_peak = crate::peak_output_v(
            model.response(),
            &self.readout,
            &truth_base,
            jig.second_peak_n,
        );
        let truth: Vec<Effect> = kinds
            .iter()
            .map(|&k| k.with_params(&random_params(k, &mut u, second_peak)))
            .collect();
        let swing = (kinds.contains(&EffectKind::ThermalDrift) && id % 2 == 0)
            .then(|| (u(0.5, 1.0), u(30.0, 90.0)));
        let spec = SimSpec {
            effects: truth.clone(),
            seed: self.seed ^ (id as u64) << 20,
            ambient_swing: swing,
            ..self.recording_spec(model.response(), truth_base, &jig)
        };
        let recording = simulate(&spec);
        let form = draw_form(series, &mut u);
        let lacks = draw_lacks(id, kinds);
        let file = dir.join(format!("sim-{id:04}.csv"));
        self.write_simulation(id, (&spec, &model, &jig), (form, lacks), &file)?;
        Ok(SimCase {
            case: Case {
                id,
                truth,
                low_snr: jig.low_snr,
                recording,
                described: None,
                unnamed: None,
            },
            simulation: file,
            form,
            model: model.name(),
            lacks,
            load_scale: jig.modulus_pa / LAB_MODULUS_PA,
        })
    }

    /// The lab's simulation of case `id` (its `spec`, the lab's `model` on the `jig`) to `file`,
    /// in `form`, without the outputs it `lacks`.
    fn write_simulation(
        &self,
        id: usize,
        (spec, model, jig): (&SimSpec, &LabModel, &Jig),
        (form, lacks): (Form, [bool; 4]),
        file: &Path,
    ) -> Result<(), CategoryError> {
        let path = RodPath {
            schedule: spec.test.clone(),
            turns_mm: spec.peak_loads_n.iter().map(|&l| rod_at(spec, l)).collect(),
        };
        let written = Written {
            model: model.response(),
            nominal: BaselineParams::nominal(LAB_MODULUS_PA),
            readout: lab_front_end(id, &self.readout),
            lacks,
            contact_angle_deg: jig.contact_angle_deg,
            azimuth_deg: jig.azimuth_deg,
            radius_mm: self.radius_mm,
            source: format!("the lab's {} model", model.name()),
        };
        written
            .write(form, &path, file)
            .map_err(|source| CategoryError::Write {
                path: file.to_path_buf(),
                source,
            })
    }

    /// Every case diagnosed blind against its simulation and against our own baseline.
    pub fn run_simulation_cases(&self, cases: &[SimCase]) -> Vec<Scored> {
        cases
            .par_iter()
            .map(|c| {
                let name = format!("prove-{:04}.csv", c.case.id);
                let opt = Options {
                    baseline: BaselineSource::Simulation(Simulations::one(&c.simulation)),
                    ..self.options.clone()
                };
                let sim = diagnosis::diagnose(&c.case.recording, &name, &opt).map(|d| d.report);
                let load_scale = sim
                    .as_ref()
                    .ok()
                    .and_then(|r| r.baseline.params.get("load_scale"));
                let ours =
                    diagnosis::diagnose(&c.case.recording, &name, &self.options).map(|d| d.report);
                crate::keep_answer(&name, "-simulation", sim.as_ref().ok());
                crate::keep_answer(&name, "-ours", ours.as_ref().ok());
                Scored {
                    against_simulation: crate::score(&c.case, sim.ok()),
                    against_ours: crate::score(&c.case, ours.ok()),
                    load_scale,
                }
            })
            .collect()
    }
}

impl Plan {
    /// The recording's settings for `jig` with `fingertip` and the truth's calibration `base`:
    /// the standard test at the plan's rate, no effect yet.
    fn recording_spec<'a>(
        &self,
        fingertip: &'a dyn FingertipResponse,
        base: BaselineParams,
        jig: &Jig,
    ) -> SimSpec<'a> {
        SimSpec {
            fingertip,
            readout: self.readout,
            baseline: base,
            contact_angle_deg: jig.contact_angle_deg,
            azimuth_deg: jig.azimuth_deg,
            radius_mm: self.radius_mm,
            test: RodSchedule {
                sample_rate_hz: self.sample_rate_hz,
                recovery_s: 45.0,
                ..Default::default()
            },
            peak_loads_n: vec![jig.peak_n, jig.second_peak_n],
            effects: Vec::new(),
            noise: jig.noise,
            seed: 0,
            ambient_c: 24.0,
            warm_up_rise_c: 6.0,
            ambient_swing: None,
            source: "tactile prove --simulation-category".into(),
        }
    }
}

/// The lab's model, by turns of either family: a power law (outputs linear in the load or on
/// the FE's map) or the lumped law, agreeing with our FE at `d_ref_mm`.
fn draw_model<'a>(
    fe: &'a baseline::fe_response::AngleBlend,
    d_ref_mm: f64,
    id: usize,
    u: &mut impl FnMut(f64, f64) -> f64,
) -> LabModel<'a> {
    if id % 2 == 0 {
        LabModel::PowerLaw(OtherFingertip {
            fe,
            exponent: u(1.5, 2.3),
            d_ref_mm,
            linear_outputs: u(0.0, 1.0) < 0.5,
        })
    } else {
        LabModel::Lumped(Lumped {
            reference: fe.unit_response(d_ref_mm),
            d_ref_mm,
            linear_share: u(0.2, 0.6),
            arm_growth: u(0.1, 0.5),
        })
    }
}

/// The truth's calibration against the lab's model: what a lab cannot know, and only that (the
/// gel's modulus, each output's sensitivity, the offsets); its shape is the lab's model's. The
/// two moment chains are identical, their gains equal within 1 %.
fn truth_baseline(modulus_pa: f64, u: &mut impl FnMut(f64, f64) -> f64) -> BaselineParams {
    let moment = u(0.85, 1.15);
    BaselineParams {
        scale: [
            u(0.85, 1.15),
            moment * u(0.995, 1.005),
            moment * u(0.995, 1.005),
        ],
        offset: [
            u(-0.05, 0.05),
            u(-0.02, 0.02),
            u(-0.02, 0.02),
            u(-0.02, 0.02),
        ],
        ..BaselineParams::nominal(modulus_pa)
    }
}

/// A table with rows 0.05-0.2 mm apart, or the test at 100 Hz to 2 kHz, from contact or
/// shifted by seconds.
fn draw_form(series: bool, u: &mut impl FnMut(f64, f64) -> f64) -> Form {
    const STEPS_MM: [f64; 3] = [0.05, 0.1, 0.2];
    const RATES_HZ: [f64; 4] = [100.0, 250.0, 400.0, 2000.0];
    let pick = |x: f64, n: usize| ((x * n as f64) as usize).min(n - 1);
    if !series {
        return Form::Table {
            step_mm: STEPS_MM[pick(u(0.0, 1.0), STEPS_MM.len())],
        };
    }
    Form::Series {
        rate_hz: RATES_HZ[pick(u(0.0, 1.0), RATES_HZ.len())],
        from_contact: u(0.0, 1.0) < 0.5,
        shift_s: u(1.0, 10.0),
    }
}

/// Every fifth simulation models no moments (where no hidden effect acts on them alone), every
/// seventh no load (where every hidden effect shows on an output).
fn draw_lacks(id: usize, kinds: &[EffectKind]) -> [bool; 4] {
    use EffectKind::*;
    let on_moments = kinds
        .iter()
        .any(|k| matches!(k, Crosstalk | ContactFriction));
    let on_load_only = kinds.iter().any(|k| matches!(k, Stiffening));
    let no_moments = id % 5 == 0 && !on_moments;
    let no_load = id % 7 == 0 && !on_load_only && !no_moments;
    [no_load, false, no_moments, no_moments]
}

/// The lab's front end: every third simulation gives the bridges' own volts (gain 1), the others
/// the recording's gains.
fn lab_front_end(id: usize, ours: &Readout) -> Readout {
    let mut r = *ours;
    if id % 3 == 0 {
        r.signal.gain = [1.0; 3];
    }
    r
}
