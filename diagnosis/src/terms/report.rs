//! The described terms and the calibration's findings as effects of OUT.json: a term seen on
//! several channels (one line on the load cell and the outputs, one relaxation of two outputs)
//! is one effect on all of them, located by where it acts.

use super::sanity::SanityFinding;
use super::{line, Found, Term, TermKind};
use crate::data::CHANNELS;
use crate::output::{EffectReport, EvidenceValues, Numbers, ParamDetail};
use sim::effects::Stage;

/// The effects the search kept, strongest evidence first, each with the indices of its terms
/// in `found.terms` (the lead first).
pub(crate) fn effects(found: &Found) -> Vec<(EffectReport, Vec<usize>)> {
    let mut order: Vec<usize> = (0..found.terms.len())
        .filter(|&i| found.terms[i].kind != TermKind::Recalibration)
        .collect();
    order.sort_by(|&a, &b| found.evidence[b].0.total_cmp(&found.evidence[a].0));
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for i in order {
        match groups.iter_mut().find(|g| {
            // Two of one kind on one channel (two knocks) are two findings.
            same_physics(&found.terms[g[0]], &found.terms[i])
                && g.iter()
                    .all(|&j| found.terms[j].channel != found.terms[i].channel)
        }) {
            Some(g) => g.push(i),
            None => groups.push(vec![i]),
        }
    }
    groups
        .into_iter()
        .map(|mut g| {
            let lead = &found.terms[g[0]];
            if lead.kind == TermKind::Discovered {
                // The discovered effect reads its form and parameters off its first channel.
                g.sort_by_key(|&i| found.terms[i].channel);
                let members: Vec<&Term> = g.iter().map(|&i| &found.terms[i]).collect();
                let (bic_gain, ratio) = found.evidence[g[0]];
                return (super::discover::effect(&members, bic_gain, ratio), g);
            }
            let mut channels: Vec<usize> = g.iter().map(|&i| found.terms[i].channel).collect();
            channels.sort_unstable();
            let stage = stage_of(lead, &channels);
            let (bic_gain, ratio) = found.evidence[g[0]];
            (effect(lead, stage, &channels, bic_gain, ratio), g)
        })
        .collect()
}

/// Two terms are one piece of physics: the same description and, for a line, one frequency
/// (within the periodogram's resolution over a hundred seconds).
fn same_physics(a: &Term, b: &Term) -> bool {
    if let (Some(x), Some(y)) = (&a.info, &b.info) {
        return x.group == y.group;
    }
    a.kind == b.kind
        && a.describe().name == b.describe().name
        && (a.kind != TermKind::Line || (a.shape[0] - b.shape[0]).abs() < 0.01)
}

/// Where a term seen on `channels` acts.
fn stage_of(t: &Term, channels: &[usize]) -> Stage {
    match t.kind {
        TermKind::Line => line::merged_stage(channels),
        TermKind::SpeedPower if channels.contains(&0) => Stage::Material,
        _ => t.stage(),
    }
}

fn effect(t: &Term, stage: Stage, channels: &[usize], bic_gain: f64, ratio: f64) -> EffectReport {
    let d = t.describe();
    let catalogue = t.kind.catalogue_kind().is_some();
    let on: Vec<&str> = channels.iter().map(|&c| super::channel_words(c)).collect();
    let evidence = format!(
        "{} on {}: {}. (Against the model without it: BIC lower by {:.0}, held-out misfit {:.1} times smaller.)",
        if catalogue {
            "A catalogue effect at a stage of its own"
        } else {
            "Not in the catalogue, described"
        },
        on.join(", "),
        d.form,
        bic_gain,
        ratio
    );
    let parameters: Vec<ParamDetail> = d
        .params
        .iter()
        .map(|(name, value, unit)| ParamDetail::unbounded(name, *value, None, unit))
        .collect();
    EffectReport {
        name: d.name.to_string(),
        stage,
        channels: channels.iter().map(|&c| CHANNELS[c].to_string()).collect(),
        params: Numbers(d.params.iter().map(|p| (p.0.to_string(), p.1)).collect()),
        param_stderr: Numbers::default(),
        evidence,
        catalogue,
        depends_on: (!catalogue).then(|| d.depends_on.iter().map(|s| s.to_string()).collect()),
        form: (!catalogue).then_some(d.form),
        inclusion: None,
        parameters,
        evidence_values: Some(EvidenceValues::with_bic_gain(bic_gain)),
    }
}

/// The fast lines, one effect per frequency (within a hundredth of a hertz) on every channel
/// that holds it, located as a slow line is ([`line::merged_stage`]).
pub(crate) fn fast_lines(lines: &[super::FastLine]) -> Vec<EffectReport> {
    let mut groups: Vec<Vec<&super::FastLine>> = Vec::new();
    for l in lines {
        match groups
            .iter_mut()
            .find(|g| (g[0].line.freq_hz - l.line.freq_hz).abs() < 0.01)
        {
            Some(g) => g.push(l),
            None => groups.push(vec![l]),
        }
    }
    groups.iter().map(|g| fast_line_effect(g)).collect()
}

fn fast_line_effect(g: &[&super::FastLine]) -> EffectReport {
    let channels: Vec<usize> = g.iter().map(|l| l.channel).collect();
    let lead = g[0];
    let f = lead.line.freq_hz;
    let unit = if lead.channel == 0 { "N" } else { "V" };
    let amplitude = lead.line.amplitude();
    let form = format!(
        "a sinusoid of {amplitude:.4} {unit} amplitude at {f:.3} Hz (period {:.4} s), faster than the fitting series shows",
        1.0 / f
    );
    let finding = SanityFinding {
        name: "periodic_line",
        stage: line::merged_stage(&channels),
        channels,
        params: vec![
            ("freq_hz", f, "Hz".into()),
            ("amplitude", amplitude, unit.into()),
        ],
        depends_on: vec!["time"],
        evidence: format!(
            "Not in the catalogue, described on {}: {form}.",
            g.iter()
                .map(|l| super::channel_words(l.channel))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        form,
        bic_gain: lead.bic_gain,
        heldout_ratio: lead.heldout_ratio,
    };
    sanity_effect(&finding)
}

/// A finding of the calibration's sanity as an effect the catalogue lacks.
pub(crate) fn sanity_effect(f: &SanityFinding) -> EffectReport {
    EffectReport {
        name: f.name.to_string(),
        stage: f.stage,
        channels: f.channels.iter().map(|&c| CHANNELS[c].to_string()).collect(),
        params: Numbers(f.params.iter().map(|p| (p.0.to_string(), p.1)).collect()),
        param_stderr: Numbers::default(),
        evidence: format!(
            "{} (Against the model without it: BIC lower by {:.0}, held-out misfit {:.1} times smaller.)",
            f.evidence, f.bic_gain, f.heldout_ratio
        ),
        catalogue: false,
        depends_on: Some(f.depends_on.iter().map(|s| s.to_string()).collect()),
        form: Some(f.form.clone()),
        inclusion: None,
        parameters: Vec::new(),
        evidence_values: Some(EvidenceValues::with_bic_gain(f.bic_gain)),
    }
}
