//! The session's verdict in words: OUT.json's `summary` and the page's headline, one text so
//! that the two never say different things. From the report alone: which file failed and why,
//! what acts on the session (shared effects, angle laws, recordings' own effects), where the
//! session's model leaves noise and where not (each recording left unexplained named with the
//! windows where the model still misses and its residual's character), and how the shared
//! physics predicts recordings it never saw.

use figures::number::{measurement, significant};

use super::output::{Change, LeaveOneOut, RecordingRow, SessionReport, SharedEffect, Validation};
use crate::localise::Mismatch;
use crate::output::Verdict;
use crate::report::page::verdict_label;
use crate::report::{capital, words};

/// The summary of `r`: a failed file first, then the verdict and what it rests on.
pub(super) fn sentence(r: &SessionReport) -> String {
    let mut parts: Vec<String> = failed(&r.recordings).into_iter().collect();
    parts.push(verdict(r));
    if r.verdict != Verdict::NoSignificantMismatch {
        if r.shares_nothing() {
            parts.push(NOTHING_TRANSFERS.to_string());
        }
        parts.push(full_stop(&capital(&validation(&r.validation))));
    }
    parts.join(" ")
}

/// What the summary and the page say where the session's model shares no effect: the
/// leave-one-out then tests no shared physics, and is not evidence of transfer.
pub(super) const NOTHING_TRANSFERS: &str = "Nothing transfers: these tests share no physics the \
     others can predict (no effect is shared; each recording keeps its own calibration and \
     effects).";

/// How the shared physics predicts the recordings it never saw, in words: how many held-out
/// stretches fit better than with their own baseline, the same within the held-out test's
/// margin, or worse ([`Change`]); the second half of the verdict sentence.
fn validation(v: &Validation) -> String {
    let rows = &v.leave_one_out;
    if rows.is_empty() {
        return "no recording could be left out to validate it".to_string();
    }
    let count = |c: Change| rows.iter().filter(|r| r.change == c).count();
    let (better, same, worse) = (
        count(Change::Better),
        count(Change::NoChange),
        count(Change::Worse),
    );
    let n = rows.len();
    let mut rest: Vec<String> = Vec::new();
    if same > 0 {
        rest.push(format!(
            "{same} {} the same within {} noise",
            if same == 1 { "fits" } else { "fit" },
            if same == 1 { "its" } else { "their" }
        ));
    }
    if worse > 0 {
        rest.push(format!("{worse} worse"));
    }
    let head = match better {
        0 => "no held-out stretch fits better than with its own baseline".to_string(),
        b if b == n && n > 1 => {
            format!("all {n} held-out stretches fit better than with their own baseline")
        }
        b => format!(
            "{b} of {n} held-out stretches {} better than with {} own baseline",
            if b == 1 { "fits" } else { "fit" },
            if b == 1 { "its" } else { "their" }
        ),
    };
    let tail = match (better, rest.is_empty()) {
        (_, true) => String::new(),
        (0, false) => format!(": {}", list(&rest)),
        _ => format!(", {}", list(&rest)),
    };
    let mean = |f: fn(&LeaveOneOut) -> f64| rows.iter().map(f).sum::<f64>() / n as f64;
    format!(
        "predicted from the other recordings alone, {head}{tail} (mean {} → {} of the range)",
        pct(mean(|r| r.rmse_before)),
        pct(mean(|r| r.rmse_after))
    )
}

/// "1 of 4 files could not be analysed (why): …", or nothing when every file was.
pub(super) fn failed(rows: &[RecordingRow]) -> Option<String> {
    let errors: Vec<String> = rows
        .iter()
        .filter_map(|x| {
            let e = x.error.as_deref()?;
            // The reason names the file as given (its path); say which row it is if not.
            Some(if e.contains(x.file.as_str()) {
                e.to_string()
            } else {
                format!("{}: {e}", x.file)
            })
        })
        .collect();
    if errors.is_empty() {
        return None;
    }
    let (n, k) = (rows.len(), errors.len());
    let files = if n == 1 { "file" } else { "files" };
    Some(format!(
        "{k} of {n} {files} could not be analysed ({}); the session is diagnosed from the other {}.",
        errors.join("; "),
        n - k
    ))
}

/// "Session explained: …; what the session's model leaves is noise in every recording."
fn verdict(r: &SessionReport) -> String {
    let analysed: Vec<&RecordingRow> = r.recordings.iter().filter(|x| x.error.is_none()).collect();
    let n = analysed.len();
    if n == 0 {
        return "No recording could be analysed.".to_string();
    }
    if r.verdict == Verdict::NoSignificantMismatch {
        return format!(
            "Session: no significant mismatch. The baseline model explains all {n} analysed \
             recordings: nothing is shared or missing, what remains is noise."
        );
    }
    let (_, label) = verdict_label(r.verdict);
    let what = found(r, n);
    let noise = |x: &&RecordingRow| {
        matches!(
            x.verdict,
            Some(Verdict::Explained | Verdict::NoSignificantMismatch)
        )
    };
    let (quiet, left): (Vec<&RecordingRow>, Vec<&RecordingRow>) =
        analysed.iter().partition(|x| noise(x));
    // One recording left: where and how in full; several: each with its largest window, the
    // rest in its row.
    let left: Vec<String> = match left.as_slice() {
        [one] => vec![left_in(one)],
        many => many.iter().map(|x| briefly(x)).collect(),
    };
    match r.verdict {
        // Rows that disagree with the verdict (a report put together by hand): no list.
        Verdict::PartiallyExplained | Verdict::Unexplained if left.is_empty() => {
            format!("Session {label}: {what}.")
        }
        Verdict::Explained => format!(
            "Session explained: {what}; what the session's model leaves is noise in {}.",
            if n == 1 {
                "the recording"
            } else {
                "every recording"
            }
        ),
        Verdict::PartiallyExplained if !quiet.is_empty() => {
            let quiet: Vec<String> = quiet.iter().map(|x| x.file.clone()).collect();
            format!(
                "Session {label}: {what}. What the session's model leaves is noise in {} but not \
                 in {}.",
                list(&quiet),
                list(&left)
            )
        }
        _ => format!(
            "Session {label}: {what}; what the session's model leaves is not noise in {}.",
            list(&left)
        ),
    }
}

/// What acts on the session, in words: its shared effects, its angle laws, and how many
/// recordings have effects of their own.
fn found(r: &SessionReport, n: usize) -> String {
    let mut found: Vec<String> = r
        .effects_shared()
        .map(|s| format!("{} {}", words::effect_name(&s.effect.name), acts_on(s, n)))
        .collect();
    found.extend(r.angle_laws().map(|s| {
        let ch = s
            .effect
            .channels
            .first()
            .map_or("", |c| words::channel_name(c));
        format!(
            "the sensitivity of {ch} follows the {} unlike the model",
            axis(r)
        )
    }));
    let own = r
        .recordings
        .iter()
        .filter(|x| x.effects.as_ref().is_some_and(|e| !e.is_empty()))
        .count();
    if own > 0 {
        let s = if own == 1 {
            "recording has effects of its own"
        } else {
            "recordings have effects of their own"
        };
        found.push(format!("{own} {s}"));
    }
    if found.is_empty() {
        "no effect was found".to_string()
    } else {
        list(&found)
    }
}

/// A recording the session's model does not explain, with what remains in it: "c.csv, where it
/// still misses Fz during the hold at 30–42 s (RMS 1.2 mV, 55 % of what it leaves); its
/// residual shows a slow drift on Fz". The largest window (the row and the page list the
/// others); the residual's character where it has one.
fn left_in(x: &RecordingRow) -> String {
    let Some(rem) = &x.remains else {
        return x.file.clone();
    };
    let character = (!rem.channels.is_empty()).then_some(rem.character.as_str());
    match (rem.windows.first(), character) {
        (None, _) => format!("{} ({})", x.file, rem.character),
        (Some(w), None) => format!("{}, where it still misses {}", x.file, window(w)),
        (Some(w), Some(c)) => format!(
            "{}, where it still misses {}; its residual shows {c}",
            x.file,
            window(w)
        ),
    }
}

/// "c.csv (Fz during the hold at 30–42 s)": a recording left unexplained among several.
fn briefly(x: &RecordingRow) -> String {
    match x.remains.as_ref().and_then(|r| r.windows.first()) {
        Some(m) => format!(
            "{} ({} during the {} at {}–{} s)",
            x.file,
            words::channel_name(m.channel),
            m.regime,
            plain(m.t_start_s),
            plain(m.t_end_s)
        ),
        None => x.file.clone(),
    }
}

/// "Fz during the hold at 30–42 s (RMS 1.2 mV, 55 % of what it leaves)".
pub(super) fn window(m: &Mismatch) -> String {
    format!(
        "{} during the {} at {}–{} s (RMS {}, {} % of what it leaves)",
        words::channel_name(m.channel),
        m.regime,
        plain(m.t_start_s),
        plain(m.t_end_s),
        measurement(m.rms, None, words::channel_unit(m.channel)),
        significant(100.0 * m.share, 2)
    )
}

/// "shared by all 3 recordings", or by the ones it names.
pub(super) fn acts_on(s: &SharedEffect, n: usize) -> String {
    match &s.recordings {
        None => format!("is shared by all {n} recordings"),
        Some(files) => format!("is shared by {}", list(files)),
    }
}

/// What the angle laws follow: the contact angle when the session has several, else the
/// azimuth (as the search decides).
pub(super) fn axis(r: &SessionReport) -> &'static str {
    if r.protocols.contact_angles_deg.len() > 1 {
        "contact angle"
    } else {
        "azimuth"
    }
}

/// "a, b and c".
pub(super) fn list(items: &[String]) -> String {
    match items.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => items.concat(),
    }
}

/// `s` ending in a full stop (evidence and reasons come with or without one).
pub(super) fn full_stop(s: &str) -> String {
    let s = s.trim_end();
    if s.ends_with(['.', '!', '?']) {
        s.to_string()
    } else {
        format!("{s}.")
    }
}

/// A protocol's value as a lab writes it: `20`, `22.5`, `0.25` (three significant digits at
/// most, no trailing zeros).
pub(super) fn plain(v: f64) -> String {
    let s = significant(v, 3);
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A relative RMSE as a percentage of the range.
pub(super) fn pct(v: f64) -> String {
    format!("{} %", significant(100.0 * v, 2))
}
