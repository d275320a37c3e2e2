//! The report in sentences: the verdict, one paragraph per effect (what physics, where it
//! shows, how much misfit it removes), what remains, and why each candidate was kept or not.

use figures::number::{measurement, significant};

use super::remains::{Finding, Remains};
use crate::data::CHANNELS;
use crate::localise::Mismatch;
use crate::output::{CandidateReport, EffectReport, Report, Stage, Verdict};

/// A channel as a reader names it.
pub fn channel_name(channel: &str) -> &'static str {
    match channel {
        "load_N" => "the load cell",
        "fz_V" => "Fz",
        "mx_V" => "Mx",
        "my_V" => "My",
        _ => "a channel",
    }
}

/// The unit of a channel's values.
pub fn channel_unit(channel: &str) -> &'static str {
    if channel == "load_N" {
        "N"
    } else {
        "V"
    }
}

/// `viscoelastic_relaxation` -> `viscoelastic relaxation`.
pub fn effect_name(name: &str) -> String {
    name.replace('_', " ")
}

fn count(n: usize) -> String {
    const WORDS: [&str; 6] = ["no", "one", "two", "three", "four", "five"];
    WORDS.get(n).map_or(n.to_string(), |w| w.to_string())
}

/// Where in the chain an effect acts, on which channels, and for a described term its form and
/// what it is a function of, in one sentence.
pub fn stage_sentence(e: &EffectReport) -> String {
    let stage = match e.stage {
        Stage::Material => "the material (between the rod's travel and the load)",
        Stage::Transducer => "the transducer (between the load and the outputs)",
        Stage::Electronics => "the electronics (after the transduction)",
    };
    let on: Vec<&str> = e.channels.iter().map(|c| channel_name(c)).collect();
    let mut s = format!("Acts at {stage}, on {}.", list(&on));
    if !e.catalogue {
        let of = match e.depends_on.as_deref() {
            Some([]) | None => "a constant".to_string(),
            Some(d) => format!("a function of {}", d.join(", ")),
        };
        s.push_str(&format!(
            " Not in the catalogue: described as {} ({of}).",
            e.form.as_deref().unwrap_or("a term of its own")
        ));
    }
    s
}

/// "a, b and c".
fn list(items: &[&str]) -> String {
    match items.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => items.concat(),
    }
}

/// RMSE relative to the range, as a percentage.
fn pct(v: f64) -> String {
    format!("{} %", significant(100.0 * v, 2))
}

/// The verdict in one plain sentence.
pub fn verdict_sentence(r: &Report, remains: &[Remains]) -> String {
    let n = r.effects.len();
    let names: Vec<String> = r.effects.iter().map(|e| effect_name(&e.name)).collect();
    let h = &r.fit.heldout;
    let heldout = format!(
        "the misfit on the held-out stretch falls from {} to {} of the range",
        pct(h.rmse_before),
        pct(h.rmse_after)
    );
    let (effects, explain) = if n == 1 {
        ("effect", "explains")
    } else {
        ("effects", "explain")
    };
    match r.verdict {
        Verdict::NoSignificantMismatch => "The baseline model explains this recording: what it leaves is indistinguishable from noise, so no missing physics was needed.".to_string(),
        Verdict::Explained => format!(
            "The baseline misses physics; {} {effects} ({}) {explain} it: {heldout}, and what remains is noise.",
            count(n), names.join(" and ")
        ),
        Verdict::PartiallyExplained => format!(
            "The baseline misses physics; {} {effects} ({}) {explain} most of it ({heldout}), but {} remains.",
            count(n), names.join(" and "), remainder_phrase(remains)
        ),
        Verdict::Unexplained => format!(
            "The baseline misses physics that no catalogue effect explains: {} remains in the residual.",
            remainder_phrase(remains)
        ),
    }
}

/// "a slow drift on Fz", or a generic phrase when nothing single stands out.
pub(crate) fn remainder_phrase(remains: &[Remains]) -> String {
    let first = remains.iter().find_map(|r| r.findings().first().cloned());
    let Some(f) = first else {
        return match remains.first() {
            Some(r) => format!(
                "structured misfit, largest on {}",
                channel_name(CHANNELS[r.channel])
            ),
            None => "structured misfit".to_string(),
        };
    };
    // Every channel showing the same kind of structure, worst first: "on My, Mx and Fz".
    let same = |g: &Finding| std::mem::discriminant(g) == std::mem::discriminant(&f);
    let names: Vec<&str> = remains
        .iter()
        .filter(|r| r.findings().iter().any(same))
        .map(|r| channel_name(CHANNELS[r.channel]))
        .collect();
    let on = match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => names.concat(),
    };
    match f {
        Finding::Drift(_) => format!("a slow drift on {on}"),
        Finding::Periodic(p) => format!(
            "a periodic component on {on} (period {})",
            period(p.freq_hz)
        ),
        Finding::FollowsLoad(_) => format!("a load-dependent error on {on}"),
        Finding::FollowsRate(_) => format!("a rate-dependent error on {on}"),
    }
}

fn period(f_hz: f64) -> String {
    measurement(1.0 / f_hz, None, "s")
}

/// Regimes where an effect shows first, by the physics of the catalogue entry.
fn preferred_regimes(effect: &str) -> &'static [&'static str] {
    match effect {
        "viscoelastic_relaxation" => &["hold", "release", "recovery"],
        "hysteresis" => &["release", "loading", "hold"],
        "highpass_coupling" => &["hold", "recovery", "rest"],
        "thermal_drift" => &["rest", "recovery"],
        "time_offset" | "contact_friction" => &["release", "loading"],
        "stiffening" | "bridge_nonlinearity" | "amplifier_saturation" | "crosstalk" => {
            &["hold", "loading"]
        }
        _ => &[],
    }
}

/// The window of the baseline's misfit where `e` shows: on one of its channels, in the first of
/// its regimes that has a window, the largest there; else its channels' largest window. A
/// channel another of the `effects` found frozen or dead is left out where `e` has others: its
/// misfit there is the freeze's (a relaxation had been shown where Fz stood still).
pub fn evidence_window<'a>(
    e: &EffectReport,
    effects: &[EffectReport],
    mismatches: &'a [Mismatch],
) -> Option<&'a Mismatch> {
    let frozen = |c: &String| {
        effects.iter().any(|o| {
            o.name != e.name
                && matches!(
                    o.name.as_str(),
                    "stuck_channel" | "dead_channel" | "dead_sensor"
                )
                && o.channels.contains(c)
        })
    };
    let live: Vec<&String> = e.channels.iter().filter(|c| !frozen(c)).collect();
    let channels: Vec<&String> = if live.is_empty() {
        e.channels.iter().collect()
    } else {
        live
    };
    let on_channels = |m: &&Mismatch| channels.iter().any(|c| *c == m.channel);
    let largest = |regime: Option<&str>| {
        mismatches
            .iter()
            .filter(on_channels)
            .filter(|m| regime.is_none_or(|r| m.regime == r))
            .max_by(|a, b| a.share.total_cmp(&b.share))
    };
    preferred_regimes(&e.name)
        .iter()
        .find_map(|r| largest(Some(r)))
        .or_else(|| largest(None))
}

fn heldout_chi2(candidates: &[CandidateReport], effects: &[&str]) -> Option<f64> {
    let mut want: Vec<&str> = effects.to_vec();
    want.sort_unstable();
    candidates
        .iter()
        .find(|c| {
            let mut have: Vec<&str> = c.effects.iter().map(String::as_str).collect();
            have.sort_unstable();
            have == want
        })
        .map(|c| c.heldout_chi2)
}

/// Where `e` shows and how much held-out misfit it removes, from the candidates weighed.
pub fn effect_sentences(e: &EffectReport, r: &Report, window: Option<&Mismatch>) -> String {
    let mut s = String::new();
    if let Some(m) = window {
        s.push_str(&format!(
            "It shows most on {} during the {} at {}–{} s, where the baseline left {} of its misfit (RMS {}).",
            channel_name(m.channel),
            m.regime,
            significant(m.t_start_s, 3),
            significant(m.t_end_s, 3),
            pct(m.share),
            measurement(m.rms, None, channel_unit(m.channel)),
        ));
    }
    let chosen: Vec<&str> = r
        .candidates
        .iter()
        .find(|c| c.accepted)
        .map(|c| c.effects.iter().map(String::as_str).collect())
        .unwrap_or_else(|| r.effects.iter().map(|e| e.name.as_str()).collect());
    let without: Vec<&str> = {
        let mut v = chosen.clone();
        if let Some(i) = v.iter().position(|n| *n == e.name) {
            v.remove(i);
        }
        v
    };
    let cands = &r.candidates;
    if let (Some(none), Some(alone)) = (heldout_chi2(cands, &[]), heldout_chi2(cands, &[&e.name])) {
        if none > 0.0 {
            s.push_str(&format!(
                " On its own it removes {} of the baseline's held-out misfit (χ² {} → {}).",
                pct(1.0 - alone / none),
                significant(none, 3),
                significant(alone, 3)
            ));
        }
    }
    if without.len() < chosen.len() && !without.is_empty() {
        if let (Some(with), Some(wo)) =
            (heldout_chi2(cands, &chosen), heldout_chi2(cands, &without))
        {
            if with > 0.0 {
                s.push_str(&format!(
                    " Leaving it out of the final model would multiply the held-out misfit by {}.",
                    significant(wo / with, 3)
                ));
            }
        }
    }
    s.trim_start().to_string()
}

/// One channel's remaining structure in words, or `None` when nothing passes its threshold.
pub fn remains_sentence(r: &Remains) -> Option<String> {
    let ch = CHANNELS[r.channel];
    let unit = channel_unit(ch);
    let parts: Vec<String> = r
        .findings()
        .iter()
        .map(|f| match f {
            Finding::Drift(t) => format!(
                "a slow drift of {} over the recording ({}/s, t = {})",
                measurement(t.change, None, unit),
                measurement(t.slope, None, unit),
                significant(t.t_stat, 2)
            ),
            Finding::Periodic(p) => format!(
                "a periodic component of period {} and amplitude {} ({} of the residual's variance)",
                period(p.freq_hz),
                measurement(p.amplitude, None, unit),
                pct(p.share)
            ),
            Finding::FollowsLoad(c) => format!("a part that follows the load (r = {})", significant(*c, 2)),
            Finding::FollowsRate(c) => format!(
                "a part that follows the loading rate (r = {})",
                significant(*c, 2)
            ),
        })
        .collect();
    if parts.is_empty() {
        return None;
    }
    let mut s = format!(
        "{} (RMS {}, {} of its range): {}.",
        capitalised(channel_name(ch)),
        measurement(r.rms, None, unit),
        pct(r.relative),
        parts.join("; ")
    );
    if let Some(m) = &r.worst {
        s.push_str(&format!(
            " Most of it sits in the {} at {}–{} s.",
            m.regime,
            significant(m.t_start_s, 3),
            significant(m.t_end_s, 3)
        ));
    }
    Some(s)
}

fn capitalised(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map_or(String::new(), |f| f.to_uppercase().chain(c).collect())
}

/// Why a candidate was kept or rejected: the pipeline's `reason` when it gave one, else from
/// its scores against the chosen model.
pub fn candidate_reason(c: &CandidateReport, chosen: Option<&CandidateReport>) -> String {
    if !c.reason.is_empty() {
        return c.reason.clone();
    }
    if c.accepted {
        return "chosen: the lowest BIC among models whose every effect lowers both BIC and the held-out misfit".to_string();
    }
    let Some(best) = chosen else {
        return "rejected: no effect in it earned its place".to_string();
    };
    if c.effects.is_empty() {
        return "the baseline alone: the reference every effect is weighed against".to_string();
    }
    if c.bic > best.bic {
        format!(
            "rejected: BIC {} above the chosen model, held-out misfit {}× the chosen model's",
            significant(c.bic - best.bic, 3),
            significant(c.heldout_chi2 / best.heldout_chi2.max(1e-300), 3)
        )
    } else {
        "rejected: lower BIC, but one of its effects did not lower the held-out misfit enough against the model without it".to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn effect(name: &str, channels: &[&str]) -> EffectReport {
        EffectReport {
            name: name.into(),
            stage: sim::effects::Stage::Material,
            channels: channels.iter().map(|c| c.to_string()).collect(),
            params: Default::default(),
            param_stderr: Default::default(),
            evidence: String::new(),
            catalogue: true,
            depends_on: None,
            form: None,
            inclusion: None,
            parameters: Vec::new(),
            evidence_values: None,
        }
    }

    fn window(channel: &'static str, share: f64) -> Mismatch {
        Mismatch {
            channel,
            t_start_s: 10.0,
            t_end_s: 12.0,
            regime: "hold",
            rms: 0.1,
            share,
        }
    }

    /// A relaxation on the load and Fz beside a freeze of Fz is shown where the load misfits,
    /// not in the frozen Fz's larger window; the freeze itself on Fz.
    #[test]
    fn an_effect_is_not_shown_on_a_channel_another_found_frozen() {
        let relax = effect("viscoelastic_relaxation", &["load_N", "fz_V"]);
        let stuck = effect("stuck_channel", &["fz_V"]);
        let all = [relax.clone(), stuck.clone()];
        let windows = [window("fz_V", 0.6), window("load_N", 0.2)];
        let shown = |e: &EffectReport| evidence_window(e, &all, &windows).map(|m| m.channel);
        assert_eq!(shown(&relax), Some("load_N"));
        assert_eq!(shown(&stuck), Some("fz_V"));
        assert_eq!(
            evidence_window(&relax, std::slice::from_ref(&relax), &windows).map(|m| m.channel),
            Some("fz_V")
        );
    }

    fn candidate(effects: &[&str], bic: f64, chi2: f64, accepted: bool) -> CandidateReport {
        CandidateReport {
            effects: effects.iter().map(|s| s.to_string()).collect(),
            bic,
            aicc: bic,
            heldout_chi2: chi2,
            accepted,
            reason: String::new(),
            fit_chi2: chi2,
            extends: None,
        }
    }

    #[test]
    fn reasons_follow_the_scores_unless_the_pipeline_gave_one() {
        let best = candidate(&["viscoelastic_relaxation"], 100.0, 2000.0, true);
        let worse = candidate(&["hysteresis"], 350.0, 8000.0, false);
        let why = candidate_reason(&worse, Some(&best));
        assert_eq!(
            why,
            "rejected: BIC 250 above the chosen model, held-out misfit 4.00× the chosen model's"
        );
        assert!(candidate_reason(&best, Some(&best)).starts_with("chosen"));
        let mut given = worse.clone();
        given.reason = "held-out misfit not lower".into();
        assert_eq!(
            candidate_reason(&given, Some(&best)),
            "held-out misfit not lower"
        );
    }

    fn drifting(channel: usize, change: f64) -> Remains {
        Remains {
            channel,
            rms: 0.009,
            relative: 0.02,
            trend: super::super::remains::Trend {
                slope: change / 180.0,
                t_stat: 5.0,
                change,
            },
            peak: None,
            corr_load: 0.0,
            corr_rate: 0.0,
            worst: None,
        }
    }

    #[test]
    fn the_remainder_names_every_channel_with_the_same_structure() {
        let r = [drifting(3, 0.026), drifting(1, 0.024), drifting(2, 0.001)];
        assert_eq!(remainder_phrase(&r), "a slow drift on My and Fz");
        assert_eq!(
            remainder_phrase(&r[2..]),
            "structured misfit, largest on Mx"
        );
        let s = remains_sentence(&r[0]).unwrap();
        assert!(
            s.starts_with("My (RMS 9.00 mV, 2.0 % of its range): a slow drift of 26.0 mV"),
            "{s}"
        );
    }
}
