//! OUT.json of `docs/diagnosis-format.md`, field for field, plus extra fields (`localisation`,
//! `candidates`, `seconds`) that the contract welcomes.

use serde::ser::{Serialize, SerializeMap, Serializer};
use serde::Serialize as DeriveSerialize;

use super::localise::{ChannelLocalisation, Mismatch};
pub use crate::simulation::SimulationReport;
pub use sim::effects::Stage;

/// A stage as the contract spells it.
fn stage_name<S: Serializer>(stage: &Stage, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(stage.name())
}

/// The contract's format tag.
pub const FORMAT: &str = "tactile-diagnosis/1";

/// Named numbers that keep their order in JSON (primary parameter first).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Numbers(pub Vec<(String, f64)>);

impl Numbers {
    pub fn get(&self, key: &str) -> Option<f64> {
        self.0.iter().find(|(k, _)| k == key).map(|(_, v)| *v)
    }

    pub fn push(&mut self, key: &str, value: f64) {
        self.0.push((key.to_string(), value));
    }
}

impl Serialize for Numbers {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            // JSON has no NaN: a value that could not be computed is null.
            if v.is_finite() {
                map.serialize_entry(k, v)?;
            } else {
                map.serialize_entry(k, &Option::<f64>::None)?;
            }
        }
        map.end()
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, DeriveSerialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    NoSignificantMismatch,
    Explained,
    PartiallyExplained,
    Unexplained,
}

#[derive(Debug, Clone, DeriveSerialize)]
pub struct Baseline {
    pub params: Numbers,
    pub rmse: Numbers,
    /// Extra: every calibrated parameter with its unit, bounds and bound flag.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub parameters: Vec<ParamDetail>,
    /// The user's simulation the baseline was (the 2026-11-27 amendment); absent for our own
    /// fingertip FE and chip.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub simulation: Option<SimulationReport>,
    /// Extra: the unit the outputs hold, as the recording's metadata `sensor_unit` states it
    /// (absent: volts). Only the fitted scales and the values in that unit depend on it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensor_unit: Option<String>,
}

/// Extra: one fitted parameter in full. The contract's `params` and `param_stderr` carry the
/// value and its standard error; this adds the unit, the bounds the fit was allowed and whether
/// it ended on one, which a reader needs before taking the value as a finding.
#[derive(Debug, Clone, DeriveSerialize)]
pub struct ParamDetail {
    pub name: String,
    pub value: f64,
    /// Standard error; `null` when the fit could not resolve it.
    pub stderr: Option<f64>,
    /// A 95 % interval where one was computed instead of (or beside) a standard error.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ci_low: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ci_high: Option<f64>,
    pub unit: String,
    pub lower: f64,
    pub upper: f64,
    /// The value sits on `lower` or `upper`: the data did not resolve it inside the bounds.
    pub at_bound: bool,
    /// Why the value is a bound, or what else limits it, in words.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

impl ParamDetail {
    /// A parameter fitted without bounds (a described term's amplitude or time constant).
    pub fn unbounded(name: &str, value: f64, stderr: Option<f64>, unit: &str) -> Self {
        ParamDetail {
            name: name.to_string(),
            value,
            stderr,
            ci_low: None,
            ci_high: None,
            unit: unit.to_string(),
            lower: f64::NEG_INFINITY,
            upper: f64::INFINITY,
            at_bound: false,
            note: None,
        }
    }
}

/// One effect found: a catalogue entry, or a term the catalogue lacks, described
/// (`catalogue: false`, with `depends_on` and `form`).
#[derive(Debug, Clone, DeriveSerialize)]
pub struct EffectReport {
    pub name: String,
    /// Where in the chain it acts: `material`, `transducer` or `electronics`.
    #[serde(serialize_with = "stage_name")]
    pub stage: Stage,
    pub channels: Vec<String>,
    pub params: Numbers,
    pub param_stderr: Numbers,
    pub evidence: String,
    /// A catalogue entry (`true`) or a described term (`false`).
    pub catalogue: bool,
    /// A described term's recorded quantities (`time`, `rod_mm`, `rod_speed`, `load_N`,
    /// `load_rate`, `temp_C`, an output channel); empty for a constant.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub depends_on: Option<Vec<String>>,
    /// A described term's fitted expression, in words and symbols.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub form: Option<String>,
    /// A discovered term's features (as its `form` writes them), each with the share of
    /// bootstrap resamples whose selection kept it (0-1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub inclusion: Option<Numbers>,
    /// Extra: `params` with units, bounds and bound flags.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub parameters: Vec<ParamDetail>,
    /// The numbers behind `evidence` (the 2026-11-28 amendment), set by the certification
    /// step (`crate::certify`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub evidence_values: Option<EvidenceValues>,
}

/// The evidence of one effect as numbers: the criterion and the held-out stretch against the
/// model without it, and the held-out test's p-value (`docs/diagnosis-format.md`).
#[derive(Debug, Clone, Copy, PartialEq, DeriveSerialize)]
pub struct EvidenceValues {
    /// BIC of the model without the effect minus the model with it (`null`: not computed).
    pub bic_gain: f64,
    /// The contract's RMSE on the held-out stretch without the effect and with it.
    pub heldout_rmse_without: f64,
    pub heldout_rmse_with: f64,
    /// One-sided p-value of the held-out block test (`crate::certify`), before the
    /// false-discovery control over the answer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p_value: Option<f64>,
    /// Extension: the Benjamini–Hochberg adjusted p-value over everything the answer tested.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub q_value: Option<f64>,
}

impl EvidenceValues {
    /// The criterion's gain alone, before the held-out test is made.
    pub fn with_bic_gain(bic_gain: f64) -> Self {
        EvidenceValues {
            bic_gain,
            heldout_rmse_without: f64::NAN,
            heldout_rmse_with: f64::NAN,
            p_value: None,
            q_value: None,
        }
    }
}

impl EffectReport {
    /// Whether the discovery step found it (it alone carries `inclusion`): a session holds it
    /// as the recording's own, at its stage.
    pub fn is_discovered(&self) -> bool {
        self.inclusion.is_some()
    }
}

#[derive(Debug, Clone, DeriveSerialize)]
pub struct Heldout {
    pub t_start_s: f64,
    pub t_end_s: f64,
    pub rmse_before: f64,
    pub rmse_after: f64,
}

#[derive(Debug, Clone, DeriveSerialize)]
pub struct Fit {
    pub rmse_before: f64,
    pub rmse_after: f64,
    pub heldout: Heldout,
}

/// One candidate model tried, for the record.
#[derive(Debug, Clone, DeriveSerialize)]
pub struct CandidateReport {
    pub effects: Vec<String>,
    pub bic: f64,
    pub aicc: f64,
    /// Weighted sum of squares on the held-out stretch (noise units).
    pub heldout_chi2: f64,
    /// Weighted sum of squares on the fitting stretch (noise units): the fit's cost.
    pub fit_chi2: f64,
    /// The model it was started from (its effects), when it adds one effect to a fitted model;
    /// its `fit_chi2` is never above that model's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub extends: Option<Vec<String>>,
    pub accepted: bool,
    /// Why the candidate was kept or rejected, in words.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub reason: String,
}

#[derive(Debug, Clone, DeriveSerialize)]
pub struct Localisation {
    pub channels: Vec<ChannelLocalisation>,
    /// Spectral lines in the baseline residual: (frequency, mean amplitude in V, prominence).
    pub lines: Vec<(f64, f64, f64)>,
}

/// Effects the recording cannot tell from a calibration: the data show the deviation, but the
/// same misfit is a baseline parameter's (extra field; see `crate::undecided`).
#[derive(Debug, Clone, DeriveSerialize)]
pub struct Undecided {
    /// The catalogue effects it could be.
    pub effects: Vec<String>,
    /// The calibration parameters that produce the same output.
    pub calibration: Vec<String>,
    /// The deviation, in the effect's and the calibration's terms.
    pub params: Numbers,
    /// Why the recording cannot decide, and what would, in words.
    pub reason: String,
}

#[derive(Debug, Clone, DeriveSerialize)]
pub struct Report {
    pub format: &'static str,
    pub recording: String,
    pub verdict: Verdict,
    pub baseline: Baseline,
    pub mismatches: Vec<Mismatch>,
    pub effects: Vec<EffectReport>,
    /// What the recording shows but cannot attribute (extra field); always present, `[]`
    /// when there is nothing, as in the session's output.
    pub undecided: Vec<Undecided>,
    pub fit: Fit,
    pub localisation: Localisation,
    pub candidates: Vec<CandidateReport>,
    pub seconds: f64,
}
