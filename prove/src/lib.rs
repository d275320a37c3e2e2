//! The proof: recordings with concealed catalogue effects, generated with the simulator and
//! diagnosed blind (the truth only scores the result). [`categories`] varies what a user
//! varies: protocols, another model's baseline, three effects, nuisances.
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

pub mod categories;
pub mod lab;
pub mod real;
pub mod reported;
pub mod sessions;
pub mod simulation;

use std::fmt::Write as _;

use rayon::prelude::*;
use sim::compression::RodSchedule;
use sim::effects::{Effect, EffectKind};

use baseline::fe_response::FeResponseError;
use baseline::synth::{simulate, simulate_path, Gaussian, Noise, SimSpec};
use baseline::{BaselineParams, Drive, FingertipResponse};
use categories::described::{Injection, Truth};
use categories::{Nuisance, OtherFingertip, TestShape};
use diagnosis::output::Report;
use diagnosis::{diagnose, Options};
use recording::Recording;
use reported::ReportedEffect;

/// One generated recording and what is hidden in it.
pub struct Case {
    pub id: usize,
    pub truth: Vec<Effect>,
    pub low_snr: bool,
    pub recording: Recording,
    /// The physics hidden besides the catalogue's, and what a right answer says of it
    /// ([`categories::described`]).
    pub described: Option<Truth>,
    /// Physics nobody named, and what a right answer says of it ([`categories::unnamed`]).
    pub unnamed: Option<categories::unnamed::Truth>,
}

impl Score {
    /// Nothing was hidden in the recording, seen or not: it must be answered
    /// `no_significant_mismatch` with nothing named.
    pub fn effect_free(&self) -> bool {
        self.truth.is_empty() && self.unseen.is_empty()
    }

    /// What the diagnosis answered, for a table: the named effects, then the undecided ones
    /// with a "?" ("" for none).
    pub fn answer(&self, sep: &str) -> String {
        let undecided = self.undecided.iter().map(|e| format!("{e}?"));
        let described = self
            .described()
            .into_iter()
            .map(|e| format!("{e} (described)"));
        let all: Vec<String> = self
            .found
            .iter()
            .cloned()
            .chain(undecided)
            .chain(described)
            .collect();
        all.join(sep)
    }

    /// The names of the terms reported with `"catalogue": false`.
    pub fn described(&self) -> Vec<String> {
        self.effects
            .iter()
            .filter(|e| !e.is_catalogue())
            .map(|e| e.name.clone())
            .collect()
    }
}

/// How one case was scored.
#[derive(Debug, Clone)]
pub struct Score {
    pub id: usize,
    /// The hidden effects the recording can show (what must be found).
    pub truth: Vec<String>,
    /// Hidden effects its sample rate cannot show (a mains line below its Nyquist rate).
    pub unseen: Vec<String>,
    /// The catalogue effects the diagnosis named.
    pub found: Vec<String>,
    /// Every effect reported, as the contract's JSON has it (stage, channels, `catalogue`,
    /// `depends_on`): described terms included.
    pub effects: Vec<ReportedEffect>,
    /// Effects it reported as undecided against a calibration (`Report::undecided`).
    pub undecided: Vec<String>,
    pub correct: bool,
    /// The verdict was `no_significant_mismatch` (what an effect-free recording must get).
    pub quiet: bool,
    pub low_snr: bool,
    /// Relative error of each true effect's primary parameter, where that effect was found.
    pub primary_errors: Vec<(String, f64)>,
    pub heldout_before: f64,
    pub heldout_after: f64,
    pub seconds: f64,
    /// The best-scoring wrong single effect and how much higher its BIC was than the chosen
    /// model's (small = hard to tell apart).
    pub runner_up: Option<(String, f64)>,
}

/// Generator settings.
pub struct Plan {
    pub seed: u64,
    pub sample_rate_hz: f64,
    pub no_effect: usize,
    pub per_effect: usize,
    pub radius_mm: f64,
    /// The project's model parameters (the diagnosis gets them too; the recording carries the
    /// gains and excitation in its metadata).
    pub options: Options,
    pub readout: baseline::Readout,
}

/// Contact angles of the generated recordings, deg.
const JIG_ANGLES_DEG: [f64; 5] = [10.0, 15.0, 17.5, 20.0, 25.0];

/// The two-effect cases: viscoelastic relaxation with AC coupling (the paper's observations)
/// twice, and three pairs with distinct signatures.
const PAIRS: [(EffectKind, EffectKind); 5] = [
    (
        EffectKind::ViscoelasticRelaxation,
        EffectKind::HighpassCoupling,
    ),
    (
        EffectKind::ViscoelasticRelaxation,
        EffectKind::HighpassCoupling,
    ),
    (EffectKind::ThermalDrift, EffectKind::MainsInterference),
    (EffectKind::Hysteresis, EffectKind::Crosstalk),
    (EffectKind::Stiffening, EffectKind::TimeOffset),
];

impl Plan {
    /// Which effects each case hides.
    pub fn truths(&self) -> Vec<Vec<EffectKind>> {
        let mut t: Vec<Vec<EffectKind>> = (0..self.no_effect).map(|_| Vec::new()).collect();
        for _ in 0..self.per_effect {
            t.extend(EffectKind::ALL.iter().map(|&k| vec![k]));
        }
        t.extend(PAIRS.iter().map(|&(a, b)| vec![a, b]));
        t
    }

    /// Generate every case (in parallel, each from its own seed).
    pub fn generate(&self) -> Result<Vec<Case>, FeResponseError> {
        self.truths()
            .into_par_iter()
            .enumerate()
            .map(|(id, kinds)| self.case(id, &kinds))
            .collect()
    }

    fn case(&self, id: usize, kinds: &[EffectKind]) -> Result<Case, FeResponseError> {
        self.build(id, &CaseSpec::new(kinds))
    }

    /// The ambient's swing (amplitude °C, period s) where the case needs one, drawn after the
    /// truth (in the standard proof's order).
    fn ambient_swing(
        &self,
        id: usize,
        cs: &CaseSpec,
        u: &mut impl FnMut(f64, f64) -> f64,
    ) -> Option<(f64, f64)> {
        // Every other drift follows an ambient that also swings: the regression on temp_C.
        let mut ambient_swing = (cs.kinds.contains(&EffectKind::ThermalDrift) && id % 2 == 0)
            .then(|| (u(0.5, 1.0), u(30.0, 90.0)));
        if cs.nuisance == Some(Nuisance::TemperatureIgnored) {
            ambient_swing = Some((u(1.0, 2.0), u(40.0, 90.0)));
        }
        if let Some(swing) = cs
            .injection
            .and_then(|i| i.ambient_swing(self.seed ^ id as u64))
        {
            ambient_swing = Some(swing);
        }
        if let Some(swing) = cs
            .unnamed
            .and_then(|h| h.ambient_swing(self.seed ^ id as u64))
        {
            ambient_swing = Some(swing);
        }
        ambient_swing
    }

    /// One case: the jig and the truth drawn from the case's seed (in the standard proof's
    /// order, so its recordings do not change), then what the category varies.
    fn build(&self, id: usize, cs: &CaseSpec) -> Result<Case, FeResponseError> {
        let mut g = Gaussian::new(
            self.seed
                .wrapping_mul(0x2545_F491_4F6C_DD1D)
                .wrapping_add(id as u64 * 7919 + 1),
        );
        let mut u = |a: f64, b: f64| a + (b - a) * g.uniform();
        let jig = Jig::draw(id, &mut u);
        let fe =
            self.options
                .fe
                .response(self.radius_mm, jig.contact_angle_deg, jig.azimuth_deg)?;
        let baseline = truth_baseline(jig.modulus_pa, &mut u);
        // A rail must clip in both cycles to be seen in the held-out one.
        let second_peak_output = peak_output_v(&fe, &self.readout, &baseline, jig.second_peak_n);
        let truth: Vec<Effect> = cs
            .kinds
            .iter()
            .map(|&k| k.with_params(&random_params(k, &mut u, second_peak_output)))
            .collect();
        let ambient_swing = self.ambient_swing(id, cs, &mut u);
        let other = cs.other_family.map(|linear_outputs| OtherFingertip {
            fe: &fe,
            exponent: u(1.5, 2.3),
            d_ref_mm: sim::compression::rod_at_load(
                |d| fe.unit_response(d).force_n * jig.modulus_pa,
                jig.peak_n,
                60.0,
            ),
            linear_outputs,
        });
        let fingertip: &dyn FingertipResponse = match &other {
            Some(o) => o,
            None => &fe,
        };
        let spec = SimSpec {
            fingertip,
            readout: self.readout,
            baseline,
            contact_angle_deg: jig.contact_angle_deg,
            azimuth_deg: jig.azimuth_deg,
            radius_mm: self.radius_mm,
            test: RodSchedule {
                sample_rate_hz: cs
                    .sample_rate_hz
                    .or(cs.protocol.sample_rate_hz())
                    .unwrap_or(self.sample_rate_hz),
                recovery_s: 45.0,
                ..Default::default()
            },
            peak_loads_n: vec![jig.peak_n, jig.second_peak_n],
            effects: truth.clone(),
            noise: jig.noise,
            seed: self.seed ^ (id as u64) << 20,
            ambient_c: 24.0,
            warm_up_rise_c: 6.0,
            ambient_swing,
            source: "tactile prove".into(),
        };
        let (recording, hidden) = record(&spec, cs, &jig);
        let (described, unnamed) = match hidden {
            Hidden::Nothing => (None, None),
            Hidden::Described(t) => (Some(t), None),
            Hidden::Unnamed(t) => (None, Some(t)),
        };
        Ok(Case {
            id,
            truth,
            low_snr: jig.low_snr,
            recording,
            described,
            unnamed,
        })
    }
}

/// The truth of what a case hides besides the catalogue's effects.
enum Hidden {
    Nothing,
    Described(Truth),
    Unnamed(categories::unnamed::Truth),
}

/// Simulate `spec` along the case's protocol, then add its nuisance; or simulate the physics it
/// hides besides the catalogue's, with its truth.
fn record(spec: &SimSpec, cs: &CaseSpec, jig: &Jig) -> (Recording, Hidden) {
    let waypoints = cs.protocol.waypoints(spec, [jig.peak_n, jig.second_peak_n]);
    let history = || match &waypoints {
        Some(w) => sim::compression::RodHistory::from_waypoints(spec.test.sample_rate_hz, w),
        None => {
            let turns: Vec<f64> = spec
                .peak_loads_n
                .iter()
                .map(|&l| baseline::synth::rod_at(spec, l))
                .collect();
            spec.test.rod_history(&turns)
        }
    };
    if let Some(injection) = &cs.injection {
        let (recording, truth) = injection.record(spec, history());
        return (recording, Hidden::Described(truth));
    }
    if let Some(hidden) = &cs.unnamed {
        let (recording, truth) = hidden.record(spec, history());
        return (recording, Hidden::Unnamed(truth));
    }
    let mut recording = match waypoints {
        Some(w) => simulate_path(
            spec,
            sim::compression::RodHistory::from_waypoints(spec.test.sample_rate_hz, &w),
        ),
        None => simulate(spec),
    };
    if let Some(n) = cs.nuisance {
        // Their own streams, so the simulation's noise is the same with and without them.
        let mut h = Gaussian::new(spec.seed ^ 0x05EE_D0FA);
        let mut z = Gaussian::new(spec.seed ^ 0x0C01_00E5);
        let mut u = |a: f64, b: f64| a + (b - a) * h.uniform();
        n.apply(&mut recording, &mut u, &mut || z.normal(), &jig.noise);
    }
    (recording, Hidden::Nothing)
}

/// What one case hides, and what its category varies beyond the standard proof.
#[derive(Debug, Clone)]
pub struct CaseSpec {
    pub kinds: Vec<EffectKind>,
    pub protocol: TestShape,
    /// Another model's fingertip: `Some(linear_outputs)`.
    pub other_family: Option<bool>,
    pub nuisance: Option<Nuisance>,
    /// Physics beyond the catalogue's effects, or a catalogue entry at another stage.
    pub injection: Option<Injection>,
    /// Physics nobody named ([`categories::unnamed`]), or a null recording of that group.
    pub unnamed: Option<categories::unnamed::Hidden>,
    /// Its own sample rate, over the protocol's and the plan's.
    pub sample_rate_hz: Option<f64>,
}

impl CaseSpec {
    /// The standard proof's case hiding `kinds`.
    pub fn new(kinds: &[EffectKind]) -> Self {
        CaseSpec {
            kinds: kinds.to_vec(),
            protocol: TestShape::Standard,
            other_family: None,
            nuisance: None,
            injection: None,
            unnamed: None,
            sample_rate_hz: None,
        }
    }
}

/// The jig's settings and the measurement's noise of one case.
struct Jig {
    contact_angle_deg: f64,
    azimuth_deg: f64,
    peak_n: f64,
    second_peak_n: f64,
    modulus_pa: f64,
    low_snr: bool,
    noise: Noise,
}

impl Jig {
    /// Drawn from the case's uniform deviates `u(a, b)`, in a fixed order.
    fn draw(id: usize, u: &mut impl FnMut(f64, f64) -> f64) -> Self {
        // Inclinations in equal steps (one between grid tables, so the blend is exercised) and
        // two azimuths, the paper's 60 deg and 30 deg.
        let contact_angle_deg = JIG_ANGLES_DEG
            [(u(0.0, 1.0) * JIG_ANGLES_DEG.len() as f64) as usize % JIG_ANGLES_DEG.len()];
        let azimuth_deg = if u(0.0, 1.0) < 0.5 { 30.0 } else { 60.0 };
        let peak_n = u(40.0, 70.0);
        let second_peak_n = peak_n * u(0.5, 0.8);
        // Stiffer than nominal or nominal: the FE tables reach 75 N at the nominal modulus.
        let modulus_pa = u(1.0e5, 1.5e5);
        let low_snr = id % 4 == 3;
        let volts_noise = if low_snr {
            u(8e-3, 12e-3)
        } else {
            u(1e-3, 3e-3)
        };
        Self {
            contact_angle_deg,
            azimuth_deg,
            peak_n,
            second_peak_n,
            modulus_pa,
            low_snr,
            noise: Noise {
                load_n: if low_snr { 0.1 } else { 0.02 },
                volts: [volts_noise; 3],
                temp_c: 0.02,
            },
        }
    }
}

/// The truth's baseline: the drawn modulus, and the deviations from the nominal model
/// (exponent, sensitivities, output shapes, azimuth, offsets) a real sensor has and the diagnosis
/// calibrates: well inside `hardware/fit-bounds.toml`'s bounds. The two moment chains are
/// identical, their gains equal within 1 %.
fn truth_baseline(modulus_pa: f64, u: &mut impl FnMut(f64, f64) -> f64) -> BaselineParams {
    let moment = u(0.85, 1.15);
    BaselineParams {
        youngs_modulus_pa: modulus_pa,
        exponent_shift: u(-0.1, 0.1),
        exponent_curvature: u(-0.05, 0.05),
        scale: [
            u(0.85, 1.15),
            moment * u(0.995, 1.005),
            moment * u(0.995, 1.005),
        ],
        force_warp: [0.0; 3],
        force_law_blend: 0.0,
        map_load_share: 0.0,
        map_load_level: 0.0,
        map_blend: [u(0.0, 0.3), u(0.0, 0.3), u(0.0, 0.3)],
        azimuth_shift_deg: u(-1.5, 1.5),
        offset: [
            u(-0.05, 0.05),
            u(-0.02, 0.02),
            u(-0.02, 0.02),
            u(-0.02, 0.02),
        ],
    }
}

/// The largest output magnitude of the noise-free baseline at `peak` (to place a rail).
fn peak_output_v(
    fingertip: &dyn FingertipResponse,
    readout: &baseline::Readout,
    base: &BaselineParams,
    peak: f64,
) -> f64 {
    let e = base.youngs_modulus_pa;
    let rod = sim::compression::rod_at_load(|d| fingertip.unit_response(d).force_n * e, peak, 60.0);
    let drive = Drive::new(fingertip, vec![0.0], &[rod]);
    let v = readout.scaled_volts(drive.unit(0).chip.map(|c| c * e), base);
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Physical ranges of each effect's parameters, catalogue order.
fn random_params(
    kind: EffectKind,
    u: &mut impl FnMut(f64, f64) -> f64,
    peak_output_v: f64,
) -> Vec<f64> {
    let sign = |u: &mut dyn FnMut(f64, f64) -> f64| if u(0.0, 1.0) < 0.5 { -1.0 } else { 1.0 };
    use EffectKind::*;
    match kind {
        ViscoelasticRelaxation => vec![u(1.0, 15.0), u(0.1, 0.4)],
        Hysteresis => vec![u(0.02, 0.08)],
        HighpassCoupling => vec![u(10.0, 100.0)],
        ThermalDrift => vec![sign(u) * u(0.02, 0.1), u(20.0, 100.0)],
        // |p - 1| from 1.5 times the calibration's Fz threshold (0.1) up.
        Stiffening => vec![u(1.15, 1.5)],
        Crosstalk => vec![sign(u) * u(5.0, 15.0)],
        AmplifierSaturation => vec![peak_output_v * u(0.6, 0.9)],
        TimeOffset => vec![sign(u) * u(0.03, 0.2)],
        MainsInterference => vec![
            if u(0.0, 1.0) < 0.5 { 50.0 } else { 60.0 } + u(-0.1, 0.1),
            u(3e-3, 15e-3),
        ],
        // Beyond what the calibration's map blend absorbs (`hardware/fit-bounds.toml`:
        // 0.1 on Fz, the documented threshold of the static-shape effects): 1.5 to 3 times it.
        BridgeNonlinearity => vec![sign(u) * u(0.15, 0.3)],
        ContactFriction => vec![u(0.04, 0.12)],
    }
}

/// Diagnose every case blind and score it.
pub fn run(cases: &[Case], opt: &Options) -> Vec<Score> {
    cases
        .par_iter()
        .map(|case| {
            let name = format!("prove-{:02}.csv", case.id);
            let d = diagnose(&case.recording, &name, opt).map(|d| d.report);
            keep_answer(&name, "", d.as_ref().ok());
            score(case, d.ok())
        })
        .collect()
}

/// The environment variable naming a folder into which every answer a proof makes is written
/// (`<recording>.json`, `suffix` added to the stem), for `check-claims` and the scan test.
pub const ANSWERS_ENV: &str = "TACTILE_PROVE_ANSWERS";

/// Writes `report` as `name`'s answer into the folder [`ANSWERS_ENV`] names, if it names one.
/// Best effort: a proof's score does not depend on it.
pub fn keep_answer(name: &str, suffix: &str, report: Option<&Report>) {
    let (Some(dir), Some(r)) = (std::env::var_os(ANSWERS_ENV), report) else {
        return;
    };
    let stem = name.strip_suffix(".csv").unwrap_or(name);
    let path = std::path::Path::new(&dir).join(format!("{stem}{suffix}.json"));
    let _ = std::fs::create_dir_all(&dir);
    if let Ok(text) = serde_json::to_string_pretty(r) {
        let _ = std::fs::write(path, text);
    }
}

fn score(case: &Case, report: Option<Report>) -> Score {
    // What the recording can show is what is asked for: a mains line sampled below its
    // Nyquist rate has aliased into a slow wave (listed as `unseen`, not required).
    let visible = |e: &&Effect| {
        e.kind() != sim::effects::EffectKind::MainsInterference
            || diagnosis::mains_visible(case.recording.meta.sample_rate_hz)
    };
    let name = |e: &Effect| e.kind().name().to_string();
    let truth: Vec<String> = case.truth.iter().filter(visible).map(name).collect();
    let unseen: Vec<String> = case
        .truth
        .iter()
        .filter(|e| !visible(e))
        .map(name)
        .collect();
    let Some(r) = report else {
        return Score::failed(case, truth, unseen);
    };
    // Read through the contract's keys: a described term (`"catalogue": false`) is no
    // catalogue name.
    let effects = ReportedEffect::all(&serde_json::to_value(&r).unwrap_or_default());
    let named: Vec<String> = effects
        .iter()
        .filter(|e| e.is_catalogue())
        .map(|e| e.name.clone())
        .collect();
    // A true effect the recording cannot tell from a calibration, reported as such
    // (`Report::undecided`), is answered as well as the data allow; shown with a "?".
    let undecided: Vec<&String> = r
        .undecided
        .iter()
        .flat_map(|u| &u.effects)
        .filter(|e| !named.contains(e))
        .collect();
    let mut a = truth.clone();
    let mut b = named.clone();
    b.extend(
        undecided
            .iter()
            .filter(|e| truth.contains(e))
            .map(|e| e.to_string()),
    );
    let found = named;
    let undecided: Vec<String> = undecided.into_iter().cloned().collect();
    a.sort();
    b.sort();
    let primary_errors = primary_errors(&case.truth, &r);
    let chosen_bic = r
        .candidates
        .iter()
        .find(|c| c.accepted)
        .map_or(f64::NAN, |c| c.bic);
    let runner_up = r
        .candidates
        .iter()
        .filter(|c| c.effects.len() == 1 && !truth.contains(&c.effects[0]))
        .min_by(|a, b| a.bic.total_cmp(&b.bic))
        .map(|c| (c.effects[0].clone(), c.bic - chosen_bic));
    Score {
        runner_up,
        id: case.id,
        truth,
        unseen,
        found,
        effects,
        undecided,
        correct: a == b,
        quiet: r.verdict == diagnosis::output::Verdict::NoSignificantMismatch,
        low_snr: case.low_snr,
        primary_errors,
        heldout_before: r.fit.heldout.rmse_before,
        heldout_after: r.fit.heldout.rmse_after,
        seconds: r.seconds,
    }
}

impl Score {
    /// A case whose diagnosis failed: nothing found, nothing measured.
    fn failed(case: &Case, truth: Vec<String>, unseen: Vec<String>) -> Self {
        Score {
            id: case.id,
            truth,
            unseen,
            found: vec!["<error>".into()],
            effects: Vec::new(),
            undecided: Vec::new(),
            correct: false,
            quiet: false,
            low_snr: case.low_snr,
            primary_errors: Vec::new(),
            heldout_before: f64::NAN,
            heldout_after: f64::NAN,
            seconds: f64::NAN,
            runner_up: None,
        }
    }
}

/// Relative error of each true effect's primary parameter, where the diagnosis found that
/// effect.
fn primary_errors(truth: &[Effect], r: &Report) -> Vec<(String, f64)> {
    truth
        .iter()
        .filter_map(|e| {
            let kind = e.kind();
            let primary = kind.param_names()[0];
            let est = r
                .effects
                .iter()
                .find(|x| x.name == kind.name())?
                .params
                .get(primary)?;
            let truth = e.params()[0];
            Some((kind.name().to_string(), ((est - truth) / truth).abs()))
        })
        .collect()
}

/// The acceptance figures of the proof.
#[derive(Debug, Clone)]
pub struct Summary {
    pub cases: usize,
    pub correct_share: f64,
    pub false_alarms: usize,
    pub no_effect_cases: usize,
    /// Effect-free recordings whose verdict was not `no_significant_mismatch` (no effect named,
    /// but the residual left structured: `unexplained`).
    pub not_quiet: usize,
    pub primary_within_20: f64,
    pub primary_cases: usize,
    pub heldout_ratio_mean: f64,
    pub mean_seconds: f64,
}

impl Summary {
    pub fn of(scores: &[Score]) -> Self {
        let n = scores.len().max(1) as f64;
        let none: Vec<&Score> = scores.iter().filter(|s| s.effect_free()).collect();
        // Primary parameter: every true effect counts; a missed effect counts as outside 20 %.
        let mut primary = Vec::new();
        for s in scores {
            for t in &s.truth {
                let e = s
                    .primary_errors
                    .iter()
                    .find(|(k, _)| k == t)
                    .map_or(f64::INFINITY, |(_, e)| *e);
                primary.push(e);
            }
        }
        // After/before compares the named model with the calibrated baseline; where every true
        // effect was answered as a calibration's equivalent (undecided), the baseline already
        // holds it and there is no model after to compare.
        let absorbed = |s: &Score| s.truth.iter().all(|t| s.undecided.contains(t));
        let with: Vec<f64> = scores
            .iter()
            .filter(|s| !s.truth.is_empty() && !absorbed(s))
            .map(|s| s.heldout_after / s.heldout_before)
            .collect();
        Self {
            cases: scores.len(),
            correct_share: scores.iter().filter(|s| s.correct).count() as f64 / n,
            // A described term is a finding too: on an effect-free recording, a false alarm.
            false_alarms: none
                .iter()
                .filter(|s| !s.found.is_empty() || !s.described().is_empty())
                .count(),
            no_effect_cases: none.len(),
            not_quiet: none.iter().filter(|s| !s.quiet).count(),
            primary_within_20: primary.iter().filter(|&&e| e <= 0.2).count() as f64
                / primary.len().max(1) as f64,
            primary_cases: primary.len(),
            heldout_ratio_mean: with.iter().sum::<f64>() / with.len().max(1) as f64,
            mean_seconds: scores.iter().map(|s| s.seconds).sum::<f64>() / n,
        }
    }

    pub fn passes(&self) -> bool {
        self.correct_share >= 0.9
            && self.false_alarms == 0
            && self.primary_within_20 >= 0.8
            && self.heldout_ratio_mean <= 0.5
    }
}

/// Score table as markdown.
pub fn markdown(scores: &[Score], s: &Summary) -> String {
    let mut out = String::from("| case | hidden | found | right | low SNR | primary error | held-out RMSE before | after | s | best wrong single (BIC above chosen) |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for x in scores {
        let errs: Vec<String> = x
            .primary_errors
            .iter()
            .map(|(k, e)| format!("{k}: {:.1} %", 100.0 * e))
            .collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {:.4} | {:.4} | {:.2} | {} |",
            x.id,
            if x.truth.is_empty() {
                "-".into()
            } else {
                x.truth.join(" + ")
            },
            if x.found.is_empty() && x.undecided.is_empty() {
                "-".into()
            } else {
                x.answer(" + ")
            },
            if x.correct { "yes" } else { "**no**" },
            if x.low_snr { "yes" } else { "" },
            errs.join(", "),
            x.heldout_before,
            x.heldout_after,
            x.seconds,
            x.runner_up
                .as_ref()
                .map_or(String::new(), |(k, d)| format!("{k} (+{d:.0})"))
        );
    }
    let _ = writeln!(
        out,
        "\n**{} recordings: effect set right in {:.0} % (need >= 90 %); false alarms on no-effect recordings: {} of {} (need 0); primary parameter within 20 %: {:.0} % of {} (need >= 80 %); mean held-out RMSE after/before where an effect is present: {:.3} (need <= 0.5); mean diagnosis time {:.2} s. {}**",
        s.cases, 100.0 * s.correct_share, s.false_alarms, s.no_effect_cases, 100.0 * s.primary_within_20, s.primary_cases,
        s.heldout_ratio_mean, s.mean_seconds, if s.passes() { "PASS" } else { "FAIL" }
    );
    out
}

/// Score table as CSV.
pub fn csv(scores: &[Score]) -> String {
    let mut out = String::from("case,hidden,found,correct,low_snr,primary_errors,heldout_rmse_before,heldout_rmse_after,seconds\n");
    for x in scores {
        let errs: Vec<String> = x
            .primary_errors
            .iter()
            .map(|(k, e)| format!("{k}={e:.4}"))
            .collect();
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{}",
            x.id,
            x.truth.join("+"),
            x.answer("+"),
            x.correct,
            x.low_snr,
            errs.join(" "),
            x.heldout_before,
            x.heldout_after,
            x.seconds
        );
    }
    out
}

/// Summary plot: held-out RMSE before (grey) and after (blue) per case, log scale, red marks
/// where the effect set was wrong.
pub fn summary_svg(scores: &[Score]) -> String {
    let (w, h, pad) = (900.0, 300.0, 40.0);
    let vals: Vec<f64> = scores
        .iter()
        .flat_map(|s| [s.heldout_before, s.heldout_after])
        .filter(|v| *v > 0.0 && v.is_finite())
        .collect();
    let lo = vals
        .iter()
        .cloned()
        .fold(f64::INFINITY, f64::min)
        .log10()
        .floor();
    let hi = vals
        .iter()
        .cloned()
        .fold(f64::NEG_INFINITY, f64::max)
        .log10()
        .ceil()
        .max(lo + 1.0);
    let y = |v: f64| h - pad - (v.max(1e-300).log10() - lo) / (hi - lo) * (h - 2.0 * pad);
    let bw = (w - 2.0 * pad) / scores.len().max(1) as f64;
    let mut s = format!("<svg xmlns='http://www.w3.org/2000/svg' width='{w}' height='{h}' font-size='10'><text x='{pad}' y='15'>held-out RMSE per case (grey: baseline, blue: with the effects found; red dot: wrong effect set), log scale 1e{lo}..1e{hi}</text>");
    for (i, sc) in scores.iter().enumerate() {
        let x = pad + i as f64 * bw;
        let _ = write!(s, "<rect x='{:.1}' y='{:.1}' width='{:.1}' height='{:.1}' fill='#aaa'><title>{}: {}</title></rect>", x, y(sc.heldout_before), bw * 0.45, h - pad - y(sc.heldout_before), sc.id, sc.truth.join("+"));
        let _ = write!(
            s,
            "<rect x='{:.1}' y='{:.1}' width='{:.1}' height='{:.1}' fill='#36c'/>",
            x + bw * 0.45,
            y(sc.heldout_after),
            bw * 0.45,
            h - pad - y(sc.heldout_after)
        );
        if !sc.correct {
            let _ = write!(
                s,
                "<circle cx='{:.1}' cy='{:.1}' r='3' fill='red'/>",
                x + bw * 0.45,
                h - pad + 10.0
            );
        }
    }
    s.push_str("</svg>");
    s
}
