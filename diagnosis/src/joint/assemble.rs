//! The session's OUT.json from its search: the shared effects with their parameters and
//! evidence, what each recording has alone, a sensitivity that follows the contact angle
//! (`angle_dependence`) or that the recordings contradict, and what stays undecided.

use sim::effects::{EffectKind, Stage};

use super::model::Layout;
use super::output::*;
use super::search::OWN_ALWAYS;
use super::seen::{self, Seen};
use super::{distinct, distinct_kinds, verdict, Members, Outcome};
use crate::data::CHANNELS;
use crate::fit::{physical, Model, N_BASE, SCALE_AT};
use crate::outcome::PlotData;
use crate::output::{EffectReport, Fit, Heldout, Numbers, Undecided, Verdict};

/// The report of the session's `outcome` with its validation, and each recording's series as
/// the session's model sees it ([`Seen::plots`]).
pub(crate) fn report(
    m: &Members,
    outcome: &Outcome,
    validation: Validation,
) -> (SessionReport, Vec<PlotData>) {
    let protocols = Protocols {
        contact_angles_deg: distinct(m.protocols.iter().map(|p| p.contact_angle_deg), 0.0),
        azimuths_deg: distinct(m.protocols.iter().map(|p| p.azimuth_deg), 0.0),
        rod_speeds_mm_per_min: distinct(m.protocols.iter().map(|p| p.rod_speed_mm_per_min), 0.0),
    };
    let mut shared = shared_effects(m, outcome);
    let (rotation, turned) = rotation(m, outcome, &protocols);
    shared.extend(rotation);
    let (angle, contradicted) = scales(m, outcome, &protocols);
    shared.extend(angle);
    let (recordings, plots): (Vec<RecordingRow>, Vec<PlotData>) = (0..m.setups.len())
        .map(|r| {
            // The terms beyond the catalogue that the recording keeps are not in the session's
            // fit: on their channels its model is its own diagnosis's.
            let terms_hold = described_still_needed(m, outcome, r);
            let own_terms = if terms_hold {
                seen::term_channels(&m.diags[r].report.effects)
            } else {
                Vec::new()
            };
            let seen = seen::seen(m, &outcome.fitted, r, &own_terms);
            let on = |s: &SharedEffect| {
                s.recordings
                    .as_ref()
                    .is_none_or(|f| f.contains(&m.files[r]))
            };
            let flags = RowFlags {
                shared_on_it: shared.iter().any(on),
                turned: turned.contains(&r),
                terms_hold,
            };
            (row(m, outcome, r, flags, &seen), seen.plots)
        })
        .unzip();
    let verdict = verdict::session(&recordings);
    let report = SessionReport {
        format: FORMAT,
        verdict,
        summary: String::new(),
        recordings,
        shared,
        validation,
        undecided: undecided(m, &protocols, outcome),
        protocols,
        contradicted,
        candidates: outcome.tried.clone(),
        seconds: 0.0,
    };
    (report, plots)
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
    // Each term of the kind (a relaxation's two Prony terms): its values and standard errors.
    let mut terms: Vec<Vec<(f64, Option<f64>)>> = (0..)
        .map_while(|nth| crate::fit::nth_param_index(&model.kinds, kind, nth, 0))
        .map(|at| {
            (0..kind.param_names().len())
                .map(|j| {
                    let v = physical(&model, full, at + j);
                    let se = f.fit.shared_stderr(at + j).map(|se| {
                        if model.specs()[at + j].log {
                            se * v
                        } else {
                            se
                        }
                    });
                    (v, se.filter(|s| s.is_finite()))
                })
                .collect()
        })
        .collect();
    // The larger share leads, as in a single recording's report.
    if let Some(share) = kind.param_names().iter().position(|&n| n == "fraction") {
        terms.sort_by(|a, b| b[share].0.total_cmp(&a[share].0));
    }
    let (mut params, mut stderr) = (Numbers::default(), Numbers::default());
    for (nth, term) in terms.iter().enumerate() {
        for (name, &(v, se)) in kind.param_names().iter().zip(term) {
            let name = match nth {
                0 => name.to_string(),
                _ => crate::evidence::second_term_name(name),
            };
            params.push(&name, v);
            if let Some(se) = se {
                stderr.push(&name, se);
            }
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
        inclusion: None,
        parameters: Vec::new(),
        evidence_values: None,
    }
}

fn shared_effects(m: &Members, outcome: &Outcome) -> Vec<SharedEffect> {
    let n = m.setups.len();
    outcome
        .gains
        .iter()
        .filter(|(k, _)| outcome.fitted.layout.shared.contains(k))
        .enumerate()
        .filter(|&(i, (k, _))| !outcome.gains[..i].iter().any(|(x, _)| x == k))
        .map(|(_, kg)| kg)
        .map(|&(k, g)| {
            let words = format!(
                "one parameter set for all {n} recordings: {}",
                g.words(&format!(
                    "the session without {}",
                    crate::report::words::effect_name(k.name())
                ))
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
        let tolerance = m.setups[0].fit_bounds.angle_law_tolerance;
        if !beyond_tolerance(f, &values, SCALE_AT + c, tolerance) {
            // Within the model's own angle law's accuracy: no finding.
            continue;
        }
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
            inclusion: None,
            parameters: Vec::new(),
            evidence_values: None,
        },
        channel_param: Some(channel.to_string()),
        recordings: None,
    }
}

/// What decides a recording's row besides its fit.
#[derive(Clone, Copy)]
struct RowFlags {
    /// A shared effect (or an angle law) acts on it.
    shared_on_it: bool,
    /// Its moment vector is turned beyond the jig's tolerance, unlike the session's others.
    turned: bool,
    /// It keeps the terms beyond the catalogue its own diagnosis described.
    terms_hold: bool,
}

/// Recording `r`'s row: its own effects (those found alone that belong to one test, and shared
/// effects the session fits per recording), its fit with the session's model, its verdict from
/// what that model leaves in it ([`verdict::recording`]) and, where it is not explained, what
/// remains.
fn row(m: &Members, outcome: &Outcome, r: usize, flags: RowFlags, seen: &Seen) -> RecordingRow {
    let single = &m.diags[r].report;
    let f = &outcome.fitted;
    let RowFlags {
        shared_on_it,
        turned,
        terms_hold,
    } = flags;
    // A sign the session turned back is this test's finding, whatever the model fits after.
    let flipped = m.flipped.get(r).is_some_and(|f| !f.is_empty());
    let mut effects: Vec<EffectReport> = single
        .effects
        .iter()
        .filter(|e| {
            e.catalogue || terms_hold || e.is_discovered() || (flipped && e.name == "inverted_sign")
        })
        .filter(|e| {
            !e.catalogue
                || EffectKind::from_name(&e.name)
                    .is_none_or(|k| !outcome.decided.contains(&k) || e.stage != k.stage())
        })
        .cloned()
        .collect();
    if turned {
        let words = "the moment vector turned beyond the jig's mounting tolerance in this test, unlike the session's other tests".to_string();
        effects.push(effect_report(m, outcome, r, EffectKind::Crosstalk, words));
    }
    let own_shared = distinct_kinds(
        f.layout.own[r]
            .iter()
            .copied()
            .filter(|k| !OWN_ALWAYS.contains(k) && *k != EffectKind::Crosstalk),
    );
    for k in own_shared {
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
    let named = !effects.is_empty() || shared_on_it;
    let lowered = held < single.fit.heldout.rmse_before;
    let verdict = verdict::recording(named, seen.white, lowered);
    let remains = matches!(verdict, Verdict::PartiallyExplained | Verdict::Unexplained)
        .then(|| seen::remaining(&seen.plots));
    RecordingRow {
        file: m.files[r].clone(),
        verdict: Some(verdict),
        effects: Some(effects),
        fit: Some(fit),
        protocol: Some(m.protocols[r]),
        remains,
        error: None,
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
            // What a recording's held-out stretch could not test, the session's search tested
            // across its recordings (`search::Search::across`).
            let searched = |e: &String| {
                EffectKind::from_name(e).is_some_and(|k| !turn && outcome.decided.contains(&k))
            };
            if !u.effects.is_empty() && u.calibration.is_empty() && u.effects.iter().all(searched) {
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
    // Against a user's simulation a scale calibrates the simulation's outputs, not the gains.
    if m.setups.iter().any(|s| s.user_simulation) {
        return None;
    }
    let f = &outcome.fitted;
    let details: Vec<crate::output::ParamDetail> = (0..3)
        .filter(|c| !f.layout.own_scales.contains(c))
        .filter(|&c| m.setups.iter().any(|s| s.used[c + 1]))
        .map(|c| {
            let r = (0..m.setups.len())
                .find(|&r| m.setups[r].used[c + 1])
                .unwrap_or(0);
            let i = SCALE_AT + c;
            crate::output::ParamDetail::unbounded(
                &format!("scale_{}", ["fz", "mx", "my"][c]),
                f.fit.full[r][i],
                f.fit.shared_stderr(i),
                "",
            )
        })
        .collect();
    crate::terms::sanity::gains_off(&details)
}

/// The turn of the moment vector each recording was fitted with, deg (where both moments are
/// measured).
fn turns(m: &Members, outcome: &Outcome) -> Vec<(usize, f64)> {
    let f = &outcome.fitted;
    (0..m.setups.len())
        .filter_map(|r| {
            let kinds = f.layout.kinds(r);
            let at = crate::fit::param_index(&kinds, EffectKind::Crosstalk, 0)?;
            Some((r, f.fit.full[r][at]))
        })
        .collect()
}

/// A chip rotated on its mount: every recording's turn beyond the jig's mounting tolerance
/// (`hardware/fit-bounds.toml`), the same way, the turns agreeing within it. Else the
/// recordings whose own turn exceeds the tolerance (a jig set off in that test). A turn is
/// only read where it is told from the moment gains: across azimuths, or where a recording's
/// protocol alone allows it.
fn rotation(
    m: &Members,
    outcome: &Outcome,
    protocols: &Protocols,
) -> (Option<SharedEffect>, Vec<usize>) {
    let t = turns(m, outcome);
    let tol = m.setups[0].fit_bounds.jig_azimuth_tolerance_deg;
    let told = protocols.azimuths_deg.len() > 1
        || t.iter().any(|&(r, _)| {
            let s = m.setups[r];
            m.prepared[r]
                .features(s)
                .allows(EffectKind::Crosstalk)
                .is_ok()
        });
    if t.is_empty() || !told {
        return (None, Vec::new());
    }
    let n = t.len() as f64;
    let mean = t.iter().map(|x| x.1).sum::<f64>() / n;
    let sd = (t.iter().map(|x| (x.1 - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt();
    let agree = t.iter().all(|x| (x.1 - mean).abs() <= tol);
    if mean.abs() > tol && agree {
        let mut params = Numbers::default();
        params.push("angle_deg", mean);
        let mut stderr = Numbers::default();
        if t.len() > 1 {
            stderr.push("angle_deg", sd / n.sqrt());
        }
        let list: Vec<String> = t
            .iter()
            .map(|&(r, a)| format!("{}: {a:.1}°", m.files[r]))
            .collect();
        let mut effect = effect_report(m, outcome, t[0].0, EffectKind::Crosstalk, String::new());
        effect.params = params;
        effect.param_stderr = stderr;
        effect.evidence = format!(
            "the moment vector is turned the same way in every test ({}), beyond the jig's {tol:.0}° mounting tolerance and within it of one another: the chip is rotated on its mount; one turn with the session's shared moment gains fits every azimuth",
            list.join(", ")
        );
        let shared = SharedEffect {
            effect,
            channel_param: None,
            recordings: None,
        };
        return (Some(shared), Vec::new());
    }
    let beyond = t.iter().filter(|x| x.1.abs() > tol).map(|x| x.0).collect();
    (None, beyond)
}

/// Whether the terms recording `r`'s own diagnosis described beyond the catalogue still earn
/// their parameters against the session's model, on the channels they act on: the recording's
/// own model with them fits those channels' fitting stretch better than the session's by the
/// criterion (BIC, margin [`MIN_BIC_GAIN`](crate::candidate::MIN_BIC_GAIN)). A term that stood
/// in for what the session decides (a sign read wrong where one recording cannot tell a turned
/// moment from its scales) is then dropped. On the terms' channels alone, so a misfit of the
/// shared model elsewhere does not keep them.
fn described_still_needed(m: &Members, outcome: &Outcome, r: usize) -> bool {
    let d = m.diags[r];
    // A discovered term is held in the session's fit itself (`Diagnosis::at_stage`).
    let terms: Vec<&EffectReport> = d
        .report
        .effects
        .iter()
        .filter(|e| !e.catalogue && !e.is_discovered())
        .collect();
    let k: usize = terms.iter().map(|e| e.params.0.len().max(1)).sum();
    let s = m.setups[r];
    let channels: Vec<usize> = (0..4)
        .filter(|&c| s.used[c])
        .filter(|&c| {
            terms
                .iter()
                .any(|e| e.channels.iter().any(|n| n == CHANNELS[c]))
        })
        .collect();
    if k == 0 || channels.is_empty() {
        return k > 0;
    }
    let f = &outcome.fitted;
    let session = model_of(m, &f.layout, &f.fit.full[r], r).outputs(&f.fit.full[r], &s.drive);
    let p = &d.plots;
    let (mut chi2_own, mut chi2_session, mut n) = (0.0, 0.0, 0usize);
    for &c in &channels {
        for (i, _) in s.fit_mask.iter().enumerate().filter(|x| *x.1) {
            let w = s.data.weight(c, i);
            chi2_own += ((p.recorded[c][i] - p.improved[c][i]) * w).powi(2);
            chi2_session += ((s.data.fit.y[c][i] - session.channel(c)[i]) * w).powi(2);
            n += 1;
        }
    }
    let n = n as f64;
    n * (chi2_session / chi2_own.max(1e-300)).ln() - k as f64 * n.ln()
        > crate::candidate::MIN_BIC_GAIN
}

/// Whether two recordings' scales (index `i`) differ by more than `tolerance` (relative) plus
/// twice their combined standard error: a scale barely determined (an output that carries
/// little at one azimuth) is no evidence of an angle law.
fn beyond_tolerance(
    f: &super::search::Fitted,
    values: &[(usize, f64)],
    i: usize,
    tolerance: f64,
) -> bool {
    let rel_se = |r: usize, v: f64| {
        f.fit
            .own_stderr(r, i)
            .map_or(f64::INFINITY, |se| se / v.abs())
    };
    values.iter().any(|&(a, va)| {
        values.iter().any(|&(b, vb)| {
            let spread = (va / vb).ln().abs();
            let se = rel_se(a, va).hypot(rel_se(b, vb));
            va > 0.0 && vb > 0.0 && spread > (1.0 + tolerance).ln() + 2.0 * se
        })
    })
}
