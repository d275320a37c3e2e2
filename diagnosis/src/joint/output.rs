//! OUT.json of a joint diagnosis, `tactile-session-diagnosis/1` (`docs/session-format.md`),
//! field for field, plus extra fields the contract welcomes (`protocols`, `contradicted`,
//! `candidates`, `seconds`).

use serde::Serialize;

use crate::localise::Mismatch;
use crate::output::{EffectReport, Fit, Undecided, Verdict};

/// The contract's format tag.
pub const FORMAT: &str = "tactile-session-diagnosis/1";

#[derive(Debug, Clone, Serialize)]
pub struct SessionReport {
    pub format: &'static str,
    pub verdict: Verdict,
    /// Extra: the verdict in words, as the page's headline says it: what is explained, what is
    /// not and where, and which file failed.
    pub summary: String,
    pub recordings: Vec<RecordingRow>,
    pub shared: Vec<SharedEffect>,
    pub validation: Validation,
    pub undecided: Vec<Undecided>,
    /// Extra: what the session's protocols vary, which decides what it can separate.
    pub protocols: Protocols,
    /// Extra: shared parameters the recordings contradict, in words; always present, `[]` when
    /// there is nothing (the contract's amendment of 2026-11-27).
    pub contradicted: Vec<Contradiction>,
    /// Extra: every session model tried, for the record.
    pub candidates: Vec<SessionCandidate>,
    pub seconds: f64,
}

/// One input file: its own effects and held-out fit, or why it could not be analysed.
#[derive(Debug, Clone, Serialize)]
pub struct RecordingRow {
    pub file: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub verdict: Option<Verdict>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub effects: Option<Vec<EffectReport>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fit: Option<Fit>,
    /// Extra: its contact angle, azimuth and rod speed, as its metadata gives them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub protocol: Option<Protocol>,
    /// Extra: where and how the session's model still misses this recording, when its verdict
    /// is `partially_explained` or `unexplained`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub remains: Option<Remaining>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// What the session's model leaves in a recording it does not explain.
#[derive(Debug, Clone, Serialize)]
pub struct Remaining {
    /// The regime windows holding the largest shares of the model's residual, worst first, in
    /// the form of `tactile-diagnosis/1`'s `mismatches`.
    pub windows: Vec<Mismatch>,
    /// The residual's character in a phrase ("a slow drift on Fz"; "structured misfit, largest
    /// on Fz" where no single trend, period or dependence stands out).
    pub character: String,
    /// Each channel's residual in a sentence where it shows a trend, a period, or a part that
    /// follows the load or its rate.
    pub channels: Vec<String>,
}

/// An effect with one parameter set for several recordings.
#[derive(Debug, Clone)]
pub struct SharedEffect {
    pub effect: EffectReport,
    /// A parameter that names an output (`angle_dependence`'s `channel`), first in `params`.
    pub channel_param: Option<String>,
    /// The files it acts on; absent: all.
    pub recordings: Option<Vec<String>>,
}

/// The effect's fields, `channel_param` first among its `params`, then `recordings`.
impl Serialize for SharedEffect {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::Error;
        #[derive(Serialize)]
        struct Plain<'e> {
            #[serde(flatten)]
            effect: &'e EffectReport,
            #[serde(skip_serializing_if = "Option::is_none")]
            recordings: &'e Option<Vec<String>>,
        }
        if self.channel_param.is_none() {
            let plain = Plain {
                effect: &self.effect,
                recordings: &self.recordings,
            };
            return plain.serialize(s);
        }
        let mut v = serde_json::to_value(&self.effect).map_err(S::Error::custom)?;
        if let (Some(ch), Some(params)) = (&self.channel_param, v.get_mut("params")) {
            let mut with = serde_json::Map::new();
            with.insert("channel".into(), ch.clone().into());
            if let Some(p) = params.as_object() {
                with.extend(p.clone());
            }
            *params = with.into();
        }
        if let (Some(files), Some(obj)) = (&self.recordings, v.as_object_mut()) {
            obj.insert("recordings".into(), files.clone().into());
        }
        v.serialize(s)
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct Validation {
    pub leave_one_out: Vec<LeaveOneOut>,
    /// Extra: why there is no leave-one-out row (fewer than two recordings), in words.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// One recording predicted from the shared physics of the others.
#[derive(Debug, Clone, Serialize)]
pub struct LeaveOneOut {
    pub file: String,
    pub rmse_before: f64,
    pub rmse_after: f64,
    /// Extra: whether the prediction beats the recording's own baseline on that stretch by the
    /// held-out test's own margin (its noise, and half a percent of the misfit).
    pub change: Change,
}

/// A held-out misfit against the baseline's, by the held-out test's margin.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Change {
    Better,
    /// Within the margin: no change.
    NoChange,
    Worse,
}

#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Protocol {
    pub contact_angle_deg: f64,
    pub azimuth_deg: f64,
    /// The rod's speed while it moves, mm/min (the metadata's, else measured).
    pub rod_speed_mm_per_min: f64,
}

/// The distinct values the session's recordings take.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Protocols {
    pub contact_angles_deg: Vec<f64>,
    pub azimuths_deg: Vec<f64>,
    pub rod_speeds_mm_per_min: Vec<f64>,
}

/// A parameter that one value cannot serve for the whole session.
#[derive(Debug, Clone, Serialize)]
pub struct Contradiction {
    pub parameter: String,
    /// Its value in each recording, in input order of the analysed ones.
    pub values: Vec<(String, f64)>,
    pub evidence: String,
}

/// A session model tried.
#[derive(Debug, Clone, Serialize)]
pub struct SessionCandidate {
    pub shared: Vec<String>,
    /// Effects fitted per recording (besides each recording's own drift and saturation).
    pub per_recording: Vec<String>,
    /// Output scales fitted per recording.
    pub per_recording_scales: Vec<String>,
    pub bic: f64,
    pub heldout_chi2: f64,
    pub accepted: bool,
    #[serde(skip_serializing_if = "String::is_empty")]
    pub reason: String,
}

/// The session-only catalogue entry's name.
pub const ANGLE_DEPENDENCE: &str = "angle_dependence";

impl SessionReport {
    /// The shared effects proper: not the angle laws.
    pub fn effects_shared(&self) -> impl Iterator<Item = &SharedEffect> {
        self.shared
            .iter()
            .filter(|s| s.effect.name != ANGLE_DEPENDENCE)
    }

    /// Whether the session's model shares no effect (nor an angle law): then nothing of what
    /// was found transfers between its tests (`session-v1.md`, "What transfers").
    pub fn shares_nothing(&self) -> bool {
        self.shared.is_empty()
    }

    /// The `angle_dependence` entries.
    pub fn angle_laws(&self) -> impl Iterator<Item = &SharedEffect> {
        self.shared
            .iter()
            .filter(|s| s.effect.name == ANGLE_DEPENDENCE)
    }
}
