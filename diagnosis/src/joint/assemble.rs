//! The session's OUT.json from its search: the shared effects with their parameters and
//! evidence, what each recording has alone, a sensitivity that follows the contact angle
//! (`angle_dependence`) or that the recordings contradict, and what stays undecided.

use sim::effects::{EffectKind, Stage};

use super::model::Layout;
use super::output::*;
use super::search::OWN_ALWAYS;
use super::{distinct, Members, Outcome};
use crate::data::CHANNELS;
use crate::fit::{physical, Model, N_BASE, SCALE_AT};
use crate::output::{EffectReport, Fit, Heldout, Numbers, Undecided, Verdict};

/// The report of the session's `outcome` with its validation.
pub(crate) fn report(m: &Members, outcome: &Outcome, validation: Validation) -> SessionReport {
    let protocols = Protocols {
        contact_angles_deg: distinct(m.protocols.iter().map(|p| p.contact_angle_deg), 0.0),
        azimuths_deg: distinct(m.protocols.iter().map(|p| p.azimuth_deg), 0.0),
        rod_speeds_mm_per_min: distinct(m.protocols.iter().map(|p| p.rod_speed_mm_per_min), 0.2),
    };
    let mut shared = shared_effects(m, outcome);
    let (angle, contradicted) = scales(m, outcome, &protocols);
    shared.extend(angle);
    let recordings: Vec<RecordingRow> = (0..m.setups.len())
        .map(|r| row(m, outcome, r, !shared.is_empty()))
        .collect();
    let verdict = session_verdict(&recordings, &shared);
    SessionReport {
        format: FORMAT,
        verdict,
        recordings,
        shared,
        validation,
        undecided: undecided(m, &protocols, outcome),
        protocols,
        contradicted,
        candidates: outcome.tried.clone(),
        seconds: 0.0,
    }
}

/// Recording `r`'s model at the session's fit.
fn model_of<'s, 'a>(m: &Members<'s, 'a>, layout: &Layout, full: &[f64], r: usize) -> Model<'s, 'a> {
    Model::new(m.setups[r], &layout.kinds(r), &full[..N_BASE])
}

/// A catalogue effect's report from recording `r`'s fitted vector.
fn effect_report(
    m: &Members,
    outcome: &Outcome,
    r: usize,
    kind: EffectKind,
    evidence: String,
) -> EffectReport {
    let f = &outcome.fitted;
    let full = &f.fit.full[r];
    let model = model_of(m, &f.layout, full, r);
    let at = crate::fit::param_index(&model.kinds, kind, 0).unwrap_or(N_BASE);
    let (mut params, mut stderr) = (Numbers::default(), Numbers::default());
    for (j, name) in kind.param_names().iter().enumerate() {
        let v = physical(&model, full, at + j);
        params.push(name, v);
        let se = f.fit.shared_stderr(at + j).map(|se| {
            if model.specs()[at + j].log {
                se * v
            } else {
                se
            }
        });
        if let Some(se) = se.filter(|s| s.is_finite()) {
            stderr.push(name, se);
        }
    }
    let used: Vec<&str> = (0..4)
        .filter(|&c| m.setups.iter().any(|s| s.used[c]))
        .map(|c| CHANNELS[c])
        .collect();
    EffectReport {
        name: kind.name().into(),
        stage: kind.stage(),
        channels: kind
            .channels()
            .iter()
            .filter(|c| used.contains(c))
            .map(|c| c.to_string())
            .collect(),
        params,
        param_stderr: stderr,
        evidence,
        catalogue: true,
        depends_on: None,
        form: None,
        parameters: Vec::new(),
    }
}

fn shared_effects(m: &Members, outcome: &Outcome) -> Vec<SharedEffect> {
    let n = m.setups.len();
    outcome
        .gains
        .iter()
        .filter(|(k, _)| outcome.fitted.layout.shared.contains(k))
        .map(|&(k, g)| {
            let words = format!(
                "one parameter set for all {n} recordings: {}",
                g.words(&format!("the session without {}", k.name()))
            );
            SharedEffect {
                effect: effect_report(m, outcome, 0, k, words),
                channel_param: None,
                recordings: None,
            }
        })
        .collect()
}

/// Output scales fitted per recording: `angle_dependence` where they follow the contact angle
/// (or, at one angle, the azimuth) and the recordings at one angle agree; else a contradiction.
fn scales(
    m: &Members,
    outcome: &Outcome,
    protocols: &Protocols,
) -> (Vec<SharedEffect>, Vec<Contradiction>) {
    let f = &outcome.fitted;
    let (mut found, mut contradicted) = (Vec::new(), Vec::new());
    for &c in &f.layout.own_scales {
        let channel = CHANNELS[c + 1];
        let values: Vec<(usize, f64)> = (0..m.setups.len())
            .filter(|&r| m.setups[r].used[c + 1])
            .map(|r| (r, f.fit.full[r][SCALE_AT + c]))
            .collect();
        let by_angle = protocols.contact_angles_deg.len() > 1;
        let by_azimuth = !by_angle && protocols.azimuths_deg.len() > 1;
        let axis = |r: usize| {
            if by_angle {
                m.protocols[r].contact_angle_deg
            } else {
                m.protocols[r].azimuth_deg
            }
        };
        let law = (by_angle || by_azimuth)
            .then(|| follows_axis(&values, &axis))
            .flatten();
        match law {
            Some(ratio) => found.push(angle_dependence(channel, ratio, by_angle, &values, m)),
            None => contradicted.push(Contradiction {
                parameter: format!("scale_{}", channel.trim_end_matches("_V")),
                values: values.iter().map(|&(r, v)| (m.files[r].clone(), v)).collect(),
                evidence: format!(
                    "no single sensitivity of {channel} fits every recording (per recording passes both tests), and the difference does not follow the tests' contact angle or azimuth: the sensor or its mounting changed between tests"
                ),
            }),
        }
    }
    (found, contradicted)
}

/// The scale at the axis's largest value over that at its smallest (means of the recordings
/// there), where the recordings at one axis value agree better than across axis values.
fn follows_axis(values: &[(usize, f64)], axis: &dyn Fn(usize) -> f64) -> Option<f64> {
    let levels = distinct(values.iter().map(|&(r, _)| axis(r)), 0.0);
    if levels.len() < 2 {
        return None;
    }
    let at = |level: f64| -> Vec<f64> {
        values
            .iter()
            .filter(|&&(r, _)| (axis(r) - level).abs() <= 0.5)
            .map(|&(_, v)| v)
            .collect()
    };
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let means: Vec<f64> = levels.iter().map(|&l| mean(&at(l))).collect();
    let across = means.iter().cloned().fold(f64::MIN, f64::max)
        - means.iter().cloned().fold(f64::MAX, f64::min);
    let within = levels
        .iter()
        .map(|&l| {
            let v = at(l);
            v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
        })
        .fold(0.0, f64::max);
    let (lo, hi) = (means[0], means[means.len() - 1]);
    (within < 0.5 * across && lo > 0.0).then(|| hi / lo)
}

fn angle_dependence(
    channel: &str,
    ratio: f64,
    by_angle: bool,
    values: &[(usize, f64)],
    m: &Members,
) -> SharedEffect {
    let axis = if by_angle { "contact angle" } else { "azimuth" };
    let list: Vec<String> = values
        .iter()
        .map(|&(r, v)| {
            let p = m.protocols[r];
            let at = if by_angle {
                p.contact_angle_deg
            } else {
                p.azimuth_deg
            };
            format!("{at:.0}°: {v:.3}")
        })
        .collect();
    let mut params = Numbers::default();
    params.push("ratio", ratio);
    SharedEffect {
        effect: EffectReport {
            name: "angle_dependence".into(),
            stage: Stage::Transducer,
            channels: vec![channel.to_string()],
            params,
            param_stderr: Numbers::default(),
            evidence: format!(
                "one sensitivity of {channel} fits each test alone but none fits all: relative to the model's angle law it changes with the {axis} ({}), so the share of the load reaching the output follows another law than the model's",
                list.join(", ")
            ),
            catalogue: true,
            depends_on: None,
            form: None,
            parameters: Vec::new(),
        },
        channel_param: Some(channel.to_string()),
        recordings: None,
    }
}

/// Recording `r`'s row: its own effects (those found alone that belong to one test, and shared
/// effects the session fits per recording), its fit with the session's model, its verdict.
fn row(m: &Members, outcome: &Outcome, r: usize, any_shared: bool) -> RecordingRow {
    let single = &m.diags[r].report;
    let f = &outcome.fitted;
    let mut effects: Vec<EffectReport> = single
        .effects
        .iter()
        .filter(|e| {
            !e.catalogue
                || EffectKind::from_name(&e.name).is_none_or(|k| OWN_ALWAYS.contains(&k))
                || e.channels.iter().any(|c| c == "load_N")
        })
        .cloned()
        .collect();
    for &k in f.layout.own[r].iter().filter(|k| !OWN_ALWAYS.contains(k)) {
        let words = format!(
            "{} acts on this recording with its own parameters: one set for the session fails the criterion or the held-out test",
            k.name()
        );
        effects.push(effect_report(m, outcome, r, k, words));
    }
    let full = &f.fit.full[r];
    let setup = m.setups[r];
    let model = model_of(m, &f.layout, full, r);
    let (all, held) = m.prepared[r].rmse(&model.outputs(full, &m.prepared[r].full_drive(setup)));
    let heldout = m.prepared[r].heldout();
    let fit = Fit {
        rmse_before: single.fit.rmse_before,
        rmse_after: all,
        heldout: Heldout {
            t_start_s: heldout.0,
            t_end_s: heldout.1,
            rmse_before: single.fit.heldout.rmse_before,
            rmse_after: held,
        },
    };
    let found = !effects.is_empty() || any_shared;
    let verdict = match single.verdict {
        _ if !found => single.verdict,
        Verdict::NoSignificantMismatch | Verdict::Explained => Verdict::Explained,
        _ if held < single.fit.heldout.rmse_before => Verdict::PartiallyExplained,
        _ => Verdict::Unexplained,
    };
    RecordingRow {
        file: m.files[r].clone(),
        verdict: Some(verdict),
        effects: Some(effects),
        fit: Some(fit),
        protocol: Some(m.protocols[r]),
        error: None,
    }
}

/// The session's verdict from its recordings': quiet when every recording is and nothing is
/// shared; explained when every recording is explained or quiet; unexplained when none is
/// explained at all.
fn session_verdict(rows: &[RecordingRow], shared: &[SharedEffect]) -> Verdict {
    let verdicts: Vec<Verdict> = rows.iter().filter_map(|r| r.verdict).collect();
    let all = |f: &dyn Fn(Verdict) -> bool| verdicts.iter().all(|&v| f(v));
    if shared.is_empty() && all(&|v| v == Verdict::NoSignificantMismatch) {
        Verdict::NoSignificantMismatch
    } else if all(&|v| matches!(v, Verdict::Explained | Verdict::NoSignificantMismatch)) {
        Verdict::Explained
    } else if all(&|v| matches!(v, Verdict::Unexplained | Verdict::NoSignificantMismatch)) {
        Verdict::Unexplained
    } else {
        Verdict::PartiallyExplained
    }
}

/// What the recordings left undecided and the session cannot decide either, once each: a
/// turn of the moment scales is decided by two azimuths (the session's search tried a rotated
/// chip against the shared gains), the rest says which test would decide it. Gains off the
/// metadata are the session's shared scales', not each recording's.
fn undecided(m: &Members, protocols: &Protocols, outcome: &Outcome) -> Vec<Undecided> {
    let layout = &outcome.fitted.layout;
    let azimuths = protocols.azimuths_deg.len() > 1;
    let mut out: Vec<Undecided> = shared_gains_off(m, outcome).into_iter().collect();
    for d in &m.diags {
        for u in &d.report.undecided {
            if u.effects.is_empty() && u.calibration.iter().all(|c| c.starts_with("scale_")) {
                continue;
            }
            let turn = u.effects.iter().any(|e| e == EffectKind::Crosstalk.name());
            if turn && (azimuths || layout.shared.contains(&EffectKind::Crosstalk)) {
                continue;
            }
            if out
                .iter()
                .any(|o| o.effects == u.effects && o.calibration == u.calibration)
            {
                continue;
            }
            let mut u = u.clone();
            if turn {
                u.reason.push_str("; every recording of this session has one azimuth: a test at another azimuth (45° away) would separate a rotated chip from the moment gains");
            }
            out.push(u);
        }
    }
    out
}

/// The session's shared output scales off the metadata's gains beyond what amplifiers and a
/// chip's spread allow ([`crate::terms::sanity::gains_off`]).
fn shared_gains_off(m: &Members, outcome: &Outcome) -> Option<Undecided> {
    let f = &outcome.fitted;
    let details: Vec<crate::output::ParamDetail> = (0..3)
        .filter(|c| !f.layout.own_scales.contains(c))
        .filter(|&c| m.setups.iter().any(|s| s.used[c + 1]))
        .map(|c| {
            let r = (0..m.setups.len())
                .find(|&r| m.setups[r].used[c + 1])
                .unwrap_or(0);
            let i = SCALE_AT + c;
            crate::output::ParamDetail {
                name: format!("scale_{}", ["fz", "mx", "my"][c]),
                value: f.fit.full[r][i],
                stderr: f.fit.shared_stderr(i),
                unit: String::new(),
                lower: f64::NEG_INFINITY,
                upper: f64::INFINITY,
                at_bound: false,
                note: None,
            }
        })
        .collect();
    crate::terms::sanity::gains_off(&details)
}
