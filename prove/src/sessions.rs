//! The session category: sessions of one sensor and gel pressed three times, varying what a
//! lab varies (azimuth, rod speed, contact angle), with physics shared by all recordings,
//! diagnosed jointly and blind (`diagnosis::joint`). Each kind hides what only the session's
//! variation decides: a rotated chip across azimuths; friction, a lag, hysteresis or relaxation
//! across rod speeds; an angle law unlike the model's across contact angles. Null sessions must
//! come back quiet, and a misdeclared moment gain across azimuths must not become crosstalk.
//! Half the sessions' fingertips are another model's family ([`OtherFingertip`]).

use std::fmt::Write as _;

use rayon::prelude::*;
use sim::compression::RodSchedule;
use sim::effects::{Effect, EffectKind};

use super::{peak_output_v, random_params, truth_baseline, Plan};
use crate::categories::OtherFingertip;
use baseline::fe_response::FeResponseError;
use baseline::synth::{simulate, Gaussian, Noise, SimSpec};
use baseline::FingertipResponse;
use diagnosis::joint::output::SessionReport;
use recording::Recording;

/// What a session varies and hides.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SessionKind {
    /// Three azimuths, a rotated chip.
    Crosstalk,
    /// Three azimuths, one moment gain in the metadata 25–40 % off: no crosstalk may be named.
    MisdeclaredGain,
    /// Three rod speeds, each with one rate-dependent effect.
    Friction,
    Lag,
    Hysteresis,
    Relaxation,
    /// Three contact angles, the Fz share growing or shrinking 10–15 % more than the model's.
    AngleLaw,
    /// Any of the three variations, nothing hidden.
    Null,
    /// Three single presses to 60, 80 and 100 % of one load, a hysteresis: each recording is
    /// held out at rest, where a hysteresis shows nothing, so no recording alone can test it.
    OnePress,
}

impl SessionKind {
    /// The category's kinds: what the sessions vary (azimuth, rod speed, contact angle).
    pub const ALL: [SessionKind; 8] = [
        SessionKind::Crosstalk,
        SessionKind::MisdeclaredGain,
        SessionKind::Friction,
        SessionKind::Lag,
        SessionKind::Hysteresis,
        SessionKind::Relaxation,
        SessionKind::AngleLaw,
        SessionKind::Null,
    ];

    /// Studies beyond the category, run only by their `--kind`: their sessions are numbered
    /// after the category's, whose ids (and so recordings) they leave unchanged.
    pub const EXTRA: [SessionKind; 1] = [SessionKind::OnePress];

    /// The kind's key on the command line (`tactile prove --sessions --kind KEY`).
    pub fn key(self) -> &'static str {
        match self {
            SessionKind::Crosstalk => "crosstalk",
            SessionKind::MisdeclaredGain => "misdeclared-gain",
            SessionKind::Friction => "friction",
            SessionKind::Lag => "lag",
            SessionKind::Hysteresis => "hysteresis",
            SessionKind::Relaxation => "relaxation",
            SessionKind::AngleLaw => "angle-law",
            SessionKind::Null => "null",
            SessionKind::OnePress => "one-press",
        }
    }

    /// The kind whose [`Self::key`] is `key`.
    pub fn from_key(key: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .chain(Self::EXTRA)
            .find(|k| k.key() == key)
    }

    pub fn name(self) -> &'static str {
        match self {
            SessionKind::Crosstalk => "crosstalk across azimuths",
            SessionKind::MisdeclaredGain => "misdeclared gain across azimuths",
            SessionKind::Friction => "friction across speeds",
            SessionKind::Lag => "lag across speeds",
            SessionKind::Hysteresis => "hysteresis across speeds",
            SessionKind::Relaxation => "relaxation across speeds",
            SessionKind::AngleLaw => "angle law across contact angles",
            SessionKind::Null => "null session",
            SessionKind::OnePress => "hysteresis, one press each",
        }
    }

    /// The catalogue effect hidden, shared by every recording.
    fn effect(self) -> Option<EffectKind> {
        match self {
            SessionKind::Crosstalk => Some(EffectKind::Crosstalk),
            SessionKind::Friction => Some(EffectKind::ContactFriction),
            SessionKind::Lag => Some(EffectKind::TimeOffset),
            SessionKind::Hysteresis => Some(EffectKind::Hysteresis),
            SessionKind::Relaxation => Some(EffectKind::ViscoelasticRelaxation),
            SessionKind::OnePress => Some(EffectKind::Hysteresis),
            _ => None,
        }
    }
}

/// What a session varies from recording to recording.
#[derive(Debug, Clone, Copy)]
enum Vary {
    Azimuth,
    Speed,
    Angle,
    /// One press per recording, to these shares of the session's peak load.
    Peak,
}

impl Vary {
    /// Test `step` of a session at (contact angle, azimuth) with presses `peaks_n`: its
    /// (contact angle, azimuth, rod speed in mm/min) and its presses.
    fn test(
        self,
        step: usize,
        (angle, azimuth): (f64, f64),
        peaks_n: [f64; 2],
    ) -> ((f64, f64, f64), Vec<f64>) {
        let (mut a, mut az, mut speed) = (angle, azimuth, 20.0);
        let mut peaks = peaks_n.to_vec();
        match self {
            Vary::Azimuth => az = AZIMUTHS_DEG[step],
            Vary::Speed => speed = SPEEDS_MM_PER_MIN[step],
            Vary::Angle => a = ANGLES_DEG[step],
            Vary::Peak => peaks = vec![peaks_n[0] * PEAK_SHARES[step]],
        }
        ((a, az, speed), peaks)
    }
}

/// A generated session and its truth.
pub struct SessionCase {
    pub id: usize,
    pub kind: SessionKind,
    pub other_family: bool,
    /// The catalogue effect shared by every recording.
    pub truth: Option<Effect>,
    /// The true Fz sensitivity ratio (largest over smallest angle) against the model's.
    pub angle_ratio: Option<f64>,
    pub recordings: Vec<(String, Recording)>,
    /// Each recording as it would be without noise: the floor under its held-out misfit.
    pub noiseless: Vec<Recording>,
}

const AZIMUTHS_DEG: [f64; 3] = [0.0, 45.0, 90.0];
const SPEEDS_MM_PER_MIN: [f64; 3] = [10.0, 30.0, 90.0];
const ANGLES_DEG: [f64; 3] = [0.0, 15.0, 30.0];
const PEAK_SHARES: [f64; 3] = [0.6, 0.8, 1.0];

impl Plan {
    /// `per_kind` sessions of every kind (of `only`, when given), each from its own seed: a
    /// session's id, and so its recordings, do not depend on `only`.
    pub fn sessions(
        &self,
        per_kind: usize,
        only: Option<SessionKind>,
    ) -> Result<Vec<SessionCase>, FeResponseError> {
        let round = |kinds: &[SessionKind]| {
            (0..per_kind)
                .flat_map(|_| kinds.to_vec())
                .collect::<Vec<SessionKind>>()
        };
        let specs: Vec<(usize, SessionKind)> =
            [round(&SessionKind::ALL), round(&SessionKind::EXTRA)]
                .concat()
                .into_iter()
                .enumerate()
                .filter(|&(_, k)| match only {
                    Some(o) => o == k,
                    None => SessionKind::ALL.contains(&k),
                })
                .collect();
        specs
            .into_par_iter()
            .map(|(id, kind)| self.session(id, kind))
            .collect()
    }

    fn session(&self, id: usize, kind: SessionKind) -> Result<SessionCase, FeResponseError> {
        let mut g = Gaussian::new(
            self.seed
                .wrapping_mul(0x9E37_79B9_7F4A_7C15)
                .wrapping_add(id as u64 * 104_729 + 17),
        );
        let mut u = |a: f64, b: f64| a + (b - a) * g.uniform();
        let vary = match kind {
            SessionKind::Crosstalk | SessionKind::MisdeclaredGain => Vary::Azimuth,
            SessionKind::AngleLaw => Vary::Angle,
            SessionKind::Null => [Vary::Azimuth, Vary::Speed, Vary::Angle][id % 3],
            SessionKind::OnePress => Vary::Peak,
            _ => Vary::Speed,
        };
        let angle = [10.0, 15.0, 20.0][(u(0.0, 3.0) as usize).min(2)];
        let azimuth = if u(0.0, 1.0) < 0.5 { 30.0 } else { 60.0 };
        let peak_n = u(30.0, 50.0);
        let second_n = peak_n * u(0.5, 0.8);
        let mut base = truth_baseline(u(1.0e5, 1.5e5), &mut u);
        let other_family = id % 2 == 1;
        let exponent = u(1.5, 2.3);
        let noise = Noise {
            load_n: 0.02,
            volts: [u(1e-3, 3e-3); 3],
            temp_c: 0.02,
        };
        let fe0 = self.options.fe.response(self.radius_mm, angle, azimuth)?;
        let peak_v = peak_output_v(&fe0, &self.readout, &base, second_n);
        let truth = kind
            .effect()
            .map(|k| k.with_params(&random_params(k, &mut u, peak_v)));
        let angle_ratio = (kind == SessionKind::AngleLaw).then(|| {
            if u(0.0, 1.0) < 0.5 {
                u(1.10, 1.15)
            } else {
                u(0.85, 0.9)
            }
        });
        let misdeclared = (kind == SessionKind::MisdeclaredGain)
            .then(|| (if u(0.0, 1.0) < 0.5 { 1 } else { 2 }, u(1.25, 1.4)));
        let fz_scale = base.scale[0];
        let mut recordings = Vec::new();
        let mut noiseless = Vec::new();
        for (i, step) in [0usize, 1, 2].into_iter().enumerate() {
            let ((a, az, speed), peaks_n) = vary.test(step, (angle, azimuth), [peak_n, second_n]);
            // The jig is set anew for every test, within its mounting accuracy.
            base.azimuth_shift_deg = u(-1.5, 1.5);
            if let Some(ratio) = angle_ratio {
                let at = (a - ANGLES_DEG[0]) / (ANGLES_DEG[2] - ANGLES_DEG[0]);
                base.scale[0] = fz_scale * (1.0 + (ratio - 1.0) * at);
            }
            let sensor = Sensor {
                base,
                exponent,
                other_family,
                reference_n: peak_n,
                peaks_n,
                truth: truth.iter().cloned().collect(),
                noise,
            };
            let seed = self.seed ^ ((id * 8 + i) as u64) << 20;
            noiseless.push(self.test(&sensor, (a, az, speed), seed, true)?);
            let mut rec = self.test(&sensor, (a, az, speed), seed, false)?;
            rec.meta.rod_speed_mm_per_min = Some(speed);
            if let Some((channel, factor)) = misdeclared {
                *[&mut rec.meta.gain_mx, &mut rec.meta.gain_my][channel - 1] *= factor;
            }
            recordings.push((format!("s{id:02}-{i}.csv"), rec));
        }
        Ok(SessionCase {
            id,
            kind,
            other_family,
            truth,
            angle_ratio,
            recordings,
            noiseless,
        })
    }
}

/// What a session's recordings share: the sensor, the gel and the physics hidden in them.
struct Sensor {
    base: baseline::BaselineParams,
    exponent: f64,
    other_family: bool,
    /// The load at which another model's force law meets the FE's (the session's peak).
    reference_n: f64,
    /// The test's presses.
    peaks_n: Vec<f64>,
    truth: Vec<Effect>,
    noise: Noise,
}

impl Plan {
    /// One test of `sensor` at (contact angle, azimuth, rod speed in mm/min), `quiet`: without
    /// its noise (the same seed draws the same everything else).
    fn test(
        &self,
        sensor: &Sensor,
        (a, az, speed): (f64, f64, f64),
        seed: u64,
        quiet: bool,
    ) -> Result<Recording, FeResponseError> {
        let base = sensor.base;
        let fe = self.options.fe.response(self.radius_mm, a, az)?;
        let other = OtherFingertip {
            fe: &fe,
            exponent: sensor.exponent,
            d_ref_mm: sim::compression::rod_at_load(
                |d| fe.unit_response(d).force_n * base.youngs_modulus_pa,
                sensor.reference_n,
                60.0,
            ),
            linear_outputs: false,
        };
        let fingertip: &dyn FingertipResponse = if sensor.other_family { &other } else { &fe };
        let spec = SimSpec {
            fingertip,
            readout: self.readout,
            baseline: base,
            contact_angle_deg: a,
            azimuth_deg: az,
            radius_mm: self.radius_mm,
            test: RodSchedule {
                sample_rate_hz: self.sample_rate_hz,
                recovery_s: 45.0,
                speed_mm_per_min: speed,
                ..Default::default()
            },
            peak_loads_n: sensor.peaks_n.clone(),
            effects: sensor.truth.clone(),
            noise: if quiet {
                Noise {
                    load_n: 0.0,
                    volts: [0.0; 3],
                    temp_c: 0.0,
                }
            } else {
                sensor.noise
            },
            seed,
            ambient_c: 24.0,
            warm_up_rise_c: 6.0,
            ambient_swing: None,
            source: "tactile prove (session)".into(),
        };
        Ok(simulate(&spec))
    }
}

/// One session's score.
pub struct SessionScore {
    pub id: usize,
    pub kind: SessionKind,
    pub right: bool,
    pub recordings_right: usize,
    pub recordings: usize,
    /// Relative error of the primary parameter (the angle ratio's deviation from 1 for an
    /// angle law), where the right effect was found.
    pub param_error: Option<f64>,
    /// Mean leave-one-out held-out RMSE after over before, where physics is hidden.
    pub loo_ratio: Option<f64>,
    /// The same mean with the noiseless recording as the prediction: the least that ratio can
    /// be on this data.
    pub loo_floor: Option<f64>,
    pub named: Vec<String>,
    pub seconds: f64,
    pub report: Option<SessionReport>,
}

/// Diagnose every session jointly and blind, and score it.
pub fn run(cases: &[SessionCase], opt: &diagnosis::Options) -> Vec<SessionScore> {
    cases
        .iter()
        .map(|c| {
            let started = std::time::Instant::now();
            let inputs = c
                .recordings
                .iter()
                .map(|(n, r)| (n.clone(), Ok(r.clone())))
                .collect();
            let report = diagnosis::joint::diagnose_recordings(inputs, opt)
                .ok()
                .map(|d| d.report);
            score(c, report, started.elapsed().as_secs_f64(), opt)
        })
        .collect()
}

/// The names a right answer gives: the hidden effect, `angle_dependence` for an angle law,
/// nothing for a null session or a misdeclared gain.
fn expected(c: &SessionCase) -> Vec<String> {
    match (&c.truth, c.angle_ratio) {
        (Some(e), _) => vec![e.kind().name().to_string()],
        (None, Some(_)) => vec!["angle_dependence".into()],
        (None, None) => Vec::new(),
    }
}

/// The effects session `r` names on the recording `file`: its shared effects that act there
/// and the recording's own, sorted, each once.
fn named_on(r: &SessionReport, file: &str) -> Vec<String> {
    let mut names: Vec<String> = r
        .shared
        .iter()
        .filter(|s| {
            s.recordings
                .as_ref()
                .is_none_or(|f| f.iter().any(|x| x == file))
        })
        .map(|s| s.effect.name.clone())
        .collect();
    let row = r.recordings.iter().find(|x| x.file == file);
    names.extend(
        row.into_iter()
            .flat_map(|x| x.effects.iter().flatten())
            .map(|e| e.name.clone()),
    );
    names.sort();
    names.dedup();
    names
}

fn score(
    c: &SessionCase,
    report: Option<SessionReport>,
    seconds: f64,
    opt: &diagnosis::Options,
) -> SessionScore {
    let want = expected(c);
    let Some(r) = report else {
        return SessionScore {
            id: c.id,
            kind: c.kind,
            right: false,
            recordings_right: 0,
            recordings: c.recordings.len(),
            param_error: None,
            loo_ratio: None,
            loo_floor: None,
            named: vec!["<error>".into()],
            seconds,
            report: None,
        };
    };
    let on = |file: &str| named_on(&r, file);
    let rows_right = r
        .recordings
        .iter()
        .filter(|x| x.error.is_none() && on(&x.file) == want)
        .count();
    let mut named: Vec<String> = r.recordings.iter().flat_map(|x| on(&x.file)).collect();
    named.sort();
    named.dedup();
    let fz_right = r
        .shared
        .iter()
        .filter(|s| s.effect.name == "angle_dependence")
        .all(|s| s.channel_param.as_deref() == Some("fz_V"));
    let right = named == want && fz_right;
    let param_error = param_error(c, &r);
    let loo_ratio = (!want.is_empty()).then(|| {
        let v: Vec<f64> = r
            .validation
            .leave_one_out
            .iter()
            .map(|l| l.rmse_after / l.rmse_before.max(1e-300))
            .collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    });
    let loo_floor = loo_ratio.and_then(|_| loo_floor(c, &r, opt));
    SessionScore {
        id: c.id,
        kind: c.kind,
        right,
        recordings_right: rows_right,
        recordings: c.recordings.len(),
        param_error,
        loo_ratio,
        loo_floor,
        named,
        seconds,
        report: Some(r),
    }
}

/// The mean over the recordings of the noiseless recording's held-out RMSE over the baseline's
/// (`rmse_before`): what a perfect model's leave-one-out ratio would be.
fn loo_floor(c: &SessionCase, r: &SessionReport, opt: &diagnosis::Options) -> Option<f64> {
    let v: Vec<f64> = c
        .recordings
        .iter()
        .zip(&c.noiseless)
        .filter_map(|((file, rec), quiet)| {
            let l = r
                .validation
                .leave_one_out
                .iter()
                .find(|l| &l.file == file)?;
            let floor = diagnosis::heldout_rmse_of(rec, quiet, opt).ok()??;
            Some(floor / l.rmse_before.max(1e-300))
        })
        .collect();
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

fn param_error(c: &SessionCase, r: &SessionReport) -> Option<f64> {
    if let Some(truth) = c.angle_ratio {
        let found = r
            .shared
            .iter()
            .find(|s| {
                s.effect.name == "angle_dependence" && s.channel_param.as_deref() == Some("fz_V")
            })?
            .effect
            .params
            .get("ratio")?;
        return Some(((found - 1.0) - (truth - 1.0)).abs() / (truth - 1.0).abs());
    }
    let e = c.truth.as_ref()?;
    let primary = e.kind().param_names()[0];
    let found = r
        .shared
        .iter()
        .find(|s| s.effect.name == e.kind().name())?
        .effect
        .params
        .get(primary)?;
    Some(((found - e.params()[0]) / e.params()[0]).abs())
}

/// Per kind and in total: sessions right, recordings right, primary parameters within 20 %,
/// the mean leave-one-out ratio where physics is hidden, and the time per session.
pub fn table(scores: &[SessionScore]) -> String {
    let mut out = String::from(
        "| kind | sessions right | recordings right | params within 20 % | leave-one-out after/before | its noise floor | s per session |\n|---|---|---|---|---|---|---|\n",
    );
    let mut groups: Vec<(String, Vec<&SessionScore>)> = SessionKind::ALL
        .iter()
        .chain(&SessionKind::EXTRA)
        .map(|k| {
            (
                k.name().to_string(),
                scores.iter().filter(|s| s.kind == *k).collect(),
            )
        })
        .filter(|(_, v): &(String, Vec<&SessionScore>)| !v.is_empty())
        .collect();
    groups.push(("**all**".into(), scores.iter().collect()));
    for (name, v) in groups {
        let right = v.iter().filter(|s| s.right).count();
        let recs: usize = v.iter().map(|s| s.recordings_right).sum();
        let recs_all: usize = v.iter().map(|s| s.recordings).sum();
        let params: Vec<f64> = v.iter().filter_map(|s| s.param_error).collect();
        let within = params.iter().filter(|&&e| e <= 0.2).count();
        let loo: Vec<f64> = v.iter().filter_map(|s| s.loo_ratio).collect();
        let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len().max(1) as f64;
        let floor: Vec<f64> = v.iter().filter_map(|s| s.loo_floor).collect();
        let shown = |x: &[f64]| {
            if x.is_empty() {
                "–".to_string()
            } else {
                format!("{:.3}", mean(x))
            }
        };
        let secs = v.iter().map(|s| s.seconds).sum::<f64>() / v.len() as f64;
        let _ = writeln!(
            out,
            "| {name} | {right}/{} | {recs}/{recs_all} | {} | {} | {} | {secs:.0} |",
            v.len(),
            if params.is_empty() {
                "–".to_string()
            } else {
                format!("{within}/{}", params.len())
            },
            shown(&loo),
            shown(&floor),
        );
    }
    out
}

/// One line per session: kind, family, what was named, the figures.
pub fn details(scores: &[SessionScore], cases: &[SessionCase]) -> String {
    let mut out = String::from(
        "| id | kind | family | truth | named | right | recordings | param error | LOO | floor |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (s, c) in scores.iter().zip(cases) {
        let truth = match (&c.truth, c.angle_ratio) {
            (Some(e), _) => format!("{} {:.3}", e.kind().name(), e.params()[0]),
            (None, Some(r)) => format!("angle_dependence fz_V {r:.3}"),
            (None, None) => "–".into(),
        };
        let _ = writeln!(
            out,
            "| {} | {} | {} | {truth} | {} | {} | {}/{} | {} | {} | {} |",
            s.id,
            s.kind.name(),
            if c.other_family { "other" } else { "own" },
            s.named.join(", "),
            if s.right { "yes" } else { "**no**" },
            s.recordings_right,
            s.recordings,
            s.param_error.map_or("–".into(), |e| format!("{e:.2}")),
            s.loo_ratio.map_or("–".into(), |e| format!("{e:.4}")),
            s.loo_floor.map_or("–".into(), |e| format!("{e:.4}")),
        );
    }
    out
}
