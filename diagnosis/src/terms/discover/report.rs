//! A discovered effect in the contract's words: a name made from what it depends on, its stage
//! and channels, the fitted expression with its coefficients and their units, each feature's
//! inclusion probability, and the evidence.

use super::super::{channel_words, Description, Term};
use super::dictionary::Quantity;
use super::FeatureInfo;
use crate::data::CHANNELS;
use crate::output::{EffectReport, Numbers, ParamDetail};
use sim::effects::Stage;

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

/// The name: what the term is, in at most four words of snake case (the contract's amendment
/// of 2026-11-28), from where it acts and the kind of its features; `depends_on` carries the
/// dependence. Where several kinds mix, the one that says most of the physics leads: a memory
/// of the load, a periodic error (a ringing after a change), a settling after a change, a lag
/// that grows with time (a rate times time), an error with the rate, a drift in time, with the
/// temperature, with another output, a static nonlinearity. The place: the material, the load
/// cell, the sensing element, an output (its level, where the term scales with it).
fn name(channel: usize, stage: Stage, features: &[FeatureInfo]) -> String {
    let d = depends(features);
    let has = |q: Quantity| d.contains(&q);
    let own_level = d.contains(&Quantity::Channel(channel));
    let rate = has(Quantity::RodSpeed) || has(Quantity::LoadRate);
    let ringing = features.iter().any(|f| matches!(f.grid, Some((_, true))));
    let product_with_time = features
        .iter()
        .any(|f| f.depends.contains(&Quantity::Time) && f.depends.len() > 1);
    let what = if has(Quantity::LoadHistory) {
        "memory"
    } else if ringing {
        "periodic_error"
    } else if has(Quantity::TimeSinceChange) {
        "settling"
    } else if product_with_time && rate {
        "lag_growing"
    } else if rate {
        "rate_error"
    } else if has(Quantity::Time) {
        "drift"
    } else if has(Quantity::TempC) {
        "temperature_error"
    } else if d
        .iter()
        .any(|q| matches!(q, Quantity::Channel(c) if *c != channel))
    {
        "crosstalk"
    } else if has(Quantity::RodMm) || has(Quantity::LoadN) || own_level {
        "nonlinearity"
    } else {
        return "constant_offset".into();
    };
    let place = match (channel, stage) {
        (0, Stage::Material) => "material",
        (0, _) => "load_cell",
        (_, Stage::Material) => "material",
        (_, Stage::Transducer) => "sensing_element",
        _ if own_level && what != "nonlinearity" => "output_level",
        _ => "output",
    };
    format!("{place}_{what}")
}

/// Each symbol of the dictionary's forms (`dictionary.rs`) and what it stands for, in the
/// order a reader meets them.
const SYMBOLS: [(&str, &str); 13] = [
    ("h_", "h_τ(L) is the load through a first-order memory of time constant τ (dh/dt = (L - h)/τ), so L - h_τ(L) is what the load has not yet followed"),
    ("(-dt", "dt is the time since the last change of regime (a start, stop or reversal of the rod)"),
    ("t", "t is the time from the start of the record"),
    ("dL/dt", "dL/dt is the load's rate"),
    ("dL/dx", "dL/dx is the load's local stiffness against the rod's travel"),
    ("max past x", "max past x is the deepest travel reached so far"),
    ("sgn(v)", "sgn(v) is the direction of the rod's motion"),
    ("|v|", "|v| is the rod's speed without its sign"),
    ("v", "v is the rod's speed"),
    ("x", "x is the rod's travel from first contact"),
    ("L", "L is the recorded load"),
    ("(T - T0)", "T - T0 is the temperature's change from the start"),
    ("_V", "a channel name (fz_V, mx_V, my_V) stands for that output's recorded value"),
];

/// What each symbol of the features' expressions `exprs` stands for, one sentence (a
/// one-letter symbol where it stands alone: `x` is no multiplication sign there).
fn glossary(exprs: &str) -> String {
    let tokens: Vec<&str> = exprs
        .split(|c: char| c.is_whitespace() || "()^,/+-*;".contains(c))
        .collect();
    let words: Vec<&str> = SYMBOLS
        .iter()
        .filter(|(symbol, _)| {
            if symbol.len() == 1 {
                tokens.contains(symbol)
            } else {
                exprs.contains(symbol)
            }
        })
        .map(|(_, meaning)| *meaning)
        .collect();
    if words.is_empty() {
        String::new()
    } else {
        format!(" Where {}.", words.join("; "))
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
        name: name(t.channel, info.stage, &info.features).into(),
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
        "Not in the catalogue, discovered in the residual on {}: {form}.{} Stage: {}. (Against the model without it: BIC lower by {bic_gain:.0}, held-out misfit {ratio:.1} times smaller.)",
        on.join(", "),
        glossary(
            &terms
                .iter()
                .filter_map(|t| t.info.as_ref())
                .flat_map(|i| i.features.iter().map(|f| f.expr.as_str()))
                .collect::<Vec<_>>()
                .join(" ; ")
        ),
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
