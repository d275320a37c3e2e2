//! A discovered effect in the contract's words: a name made from what it depends on, its stage
//! and channels, the fitted expression with its coefficients and their units, each feature's
//! inclusion probability, and the evidence.

use super::super::{channel_words, Description, Term};
use super::dictionary::Quantity;
use super::FeatureInfo;
use crate::data::CHANNELS;
use crate::output::{EffectReport, Numbers, ParamDetail};

/// Parameter names of a term's coefficients, in the order of its features.
const COEFFICIENTS: [&str; 3] = ["c1", "c2", "c3"];
const TIME_CONSTANTS: [&str; 3] = ["tau1_s", "tau2_s", "tau3_s"];
const FREQUENCIES: [&str; 3] = ["freq1_hz", "freq2_hz", "freq3_hz"];

/// The recorded quantities the features are functions of, in the contract's order.
fn depends(features: &[FeatureInfo]) -> Vec<Quantity> {
    let mut d: Vec<Quantity> = features
        .iter()
        .flat_map(|f| f.depends.iter().copied())
        .collect();
    d.sort();
    d.dedup();
    d
}

/// The name: what it depends on, in snake case (`load_history_dependence`).
fn name(features: &[FeatureInfo]) -> String {
    let d: Vec<String> = depends(features)
        .iter()
        .map(|q| q.name().to_lowercase())
        .collect();
    if d.is_empty() {
        "constant_term".into()
    } else {
        format!("{}_dependence", d.join("_and_"))
    }
}

fn unit_of(c: usize) -> &'static str {
    if c == 0 {
        "N"
    } else {
        "V"
    }
}

/// A coefficient's unit: the channel's over the feature's.
fn ratio_unit(channel: &str, feature: &str) -> String {
    match feature {
        "1" => channel.to_string(),
        f if f.contains(' ') || f.contains('/') => format!("{channel}/({f})"),
        f => format!("{channel}/{f}"),
    }
}

/// The coefficients of term `t` in its features' own units, with their units.
fn coefficients(t: &Term, features: &[FeatureInfo]) -> Vec<(f64, String)> {
    features
        .iter()
        .zip(&t.beta)
        .map(|(f, b)| (b / f.scale, ratio_unit(unit_of(t.channel), &f.unit)))
        .collect()
}

/// `channel += c1 unit x expr + ...` for a term with its own features.
fn expression(t: &Term, features: &[FeatureInfo]) -> String {
    let parts: Vec<String> = coefficients(t, features)
        .iter()
        .zip(features)
        .map(|((c, u), f)| format!("{} {u} x {}", number(*c), f.expr))
        .collect();
    format!("{} += {}", CHANNELS[t.channel], parts.join(" + "))
}

fn number(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e4) {
        format!("{v:.4e}")
    } else {
        format!("{v:.4}")
    }
}

/// The lead term's description (the report groups a discovered effect's terms by it).
pub(crate) fn describe(t: &Term) -> Description {
    let info = t.info.as_ref().expect("a discovered term has its info");
    let mut params: Vec<(&'static str, f64, String)> = coefficients(t, &info.features)
        .into_iter()
        .zip(COEFFICIENTS)
        .map(|((v, u), n)| (n, v, u))
        .collect();
    // Each feature's time constant or frequency, named by the coefficient it goes with.
    for (i, f) in info.features.iter().enumerate().take(COEFFICIENTS.len()) {
        match f.grid {
            Some((hz, true)) => params.push((FREQUENCIES[i], hz, "Hz".into())),
            Some((tau, false)) => params.push((TIME_CONSTANTS[i], tau, "s".into())),
            None => {}
        }
    }
    Description {
        name: name(&info.features).into(),
        params,
        depends_on: depends(&info.features).iter().map(|q| q.name()).collect(),
        form: expression(t, &info.features),
    }
}

/// The effect of a discovered group's `terms` (load first), with the evidence of the search
/// against the model without it.
pub(crate) fn effect(terms: &[&Term], bic_gain: f64, ratio: f64) -> EffectReport {
    let lead = terms[0];
    let info = lead.info.as_ref().expect("a discovered term has its info");
    let mut forms: Vec<String> = terms
        .iter()
        .filter(|t| !t.info.as_ref().is_some_and(|i| i.propagated))
        .map(|t| expression(t, &t.info.as_ref().expect("info").features))
        .collect();
    let follow: Vec<String> = terms
        .iter()
        .filter(|t| t.info.as_ref().is_some_and(|i| i.propagated))
        .map(|t| format!("{} x {:.2}", CHANNELS[t.channel], t.beta[0]))
        .collect();
    if !follow.is_empty() {
        forms.push(format!(
            "the outputs follow the load's change in proportion to their response per newton ({})",
            follow.join(", ")
        ));
    }
    let form = forms.join("; ");
    let d = describe(lead);
    let mut inclusion = Numbers::default();
    for (f, p) in info.features.iter().zip(&info.inclusion) {
        inclusion.push(&f.expr, *p);
    }
    let channels: Vec<usize> = terms.iter().map(|t| t.channel).collect();
    let on: Vec<&str> = channels.iter().map(|&c| channel_words(c)).collect();
    let evidence = format!(
        "Not in the catalogue, discovered in the residual on {}: {form}. Stage: {}. (Against the model without it: BIC lower by {bic_gain:.0}, held-out misfit {ratio:.1} times smaller.)",
        on.join(", "),
        info.stage_note
    );
    EffectReport {
        name: d.name.into_owned(),
        stage: info.stage,
        channels: channels.iter().map(|&c| CHANNELS[c].to_string()).collect(),
        params: Numbers(d.params.iter().map(|p| (p.0.to_string(), p.1)).collect()),
        param_stderr: Numbers::default(),
        evidence,
        catalogue: false,
        depends_on: Some(d.depends_on.iter().map(|s| s.to_string()).collect()),
        form: Some(form),
        inclusion: Some(inclusion),
        parameters: d
            .params
            .iter()
            .map(|(name, value, unit)| ParamDetail::unbounded(name, *value, None, unit))
            .collect(),
        evidence_values: Some(crate::output::EvidenceValues::with_bic_gain(bic_gain)),
    }
}
