//! The session's page: one self-contained HTML file (inline SVG and CSS, no script, nothing
//! fetched, no link) in the single report's style. From the top: the session's verdict in a
//! sentence, the recordings, the shared effects, the sensitivities that follow the contact
//! angle or that the recordings contradict, the leave-one-out validation ([`super::validation`]),
//! what stays undecided, the session models tried, and per recording a small figure of its
//! channels.

use std::path::Path;

use figures::number::significant;

use super::output::{SessionReport, SharedEffect};
use super::SessionDiagnosis;
use super::{tables, validation};
use crate::output::Verdict;
use crate::report::page::{esc, figure, verdict_label, STYLE};
use crate::report::{capital, figs, words};

/// The session's page as one HTML document.
pub fn report_html(d: &SessionDiagnosis) -> String {
    let r = &d.report;
    let mut h = head(r);
    h.push_str(&tables::recordings(r));
    h.push_str(&tables::shared(r));
    h.push_str(&sensitivities(r));
    h.push_str(&validation::section(&r.validation));
    h.push_str(&undecided(r));
    h.push_str(&validation::candidates(&r.candidates));
    h.push_str(&each_recording(d));
    h.push_str(
        "<p class=facts>Written by <code>tactile diagnose --joint</code>; the numbers are those \
         of its JSON output (<code>tactile-session-diagnosis/1</code>).</p></body></html>\n",
    );
    h
}

/// Write [`report_html`] of `d` to `path` (a file, e.g. `session.html`) whole, creating its
/// folder ([`crate::outputs::write_whole`]).
pub fn write_report(path: &Path, d: &SessionDiagnosis) -> std::io::Result<()> {
    crate::outputs::write_whole(path, report_html(d).as_bytes())
}

/// "a, b and c".
fn list(items: &[String]) -> String {
    match items.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => items.concat(),
    }
}

/// `s` ending in a full stop (evidence and reasons come with or without one).
fn full_stop(s: &str) -> String {
    let s = s.trim_end();
    if s.ends_with(['.', '!', '?']) {
        s.to_string()
    } else {
        format!("{s}.")
    }
}

/// Doctype, title, style and the heading with the verdict sentence first.
fn head(r: &SessionReport) -> String {
    let (class, words) = verdict_label(r.verdict);
    let n = r.recordings.len();
    let analysed = r.recordings.iter().filter(|x| x.error.is_none()).count();
    let values = |v: &[f64]| {
        let v: Vec<String> = v.iter().map(|x| tables::plain(*x)).collect();
        v.join(", ")
    };
    let p = &r.protocols;
    format!(
        "<!doctype html><html lang=en><meta charset=utf-8>\
         <meta name=viewport content='width=device-width,initial-scale=1'>\
         <title>Joint diagnosis of a session of {n} recordings</title><style>{STYLE}</style><body>\
         <h1>Joint diagnosis of a session of {n} recordings</h1>\
         <p id=verdict class='verdict {class}'>{}</p>\
         <p class=facts>Verdict <b>{words}</b>. {analysed} of {n} recordings analysed, one model \
         of the sensor and the gel for all of them. Contact angles {}°; azimuths {}°; rod \
         speeds {} mm/min. Diagnosed in {} s.</p>",
        esc(&verdict_sentence(r)),
        values(&p.contact_angles_deg),
        values(&p.azimuths_deg),
        values(&p.rod_speeds_mm_per_min),
        significant(r.seconds, 2),
    )
}

/// The session's verdict in one sentence: what is shared, what follows the angle, what
/// belongs to single recordings, and how the shared physics predicts recordings it never saw.
pub(super) fn verdict_sentence(r: &SessionReport) -> String {
    let n = r.recordings.iter().filter(|x| x.error.is_none()).count();
    if r.verdict == Verdict::NoSignificantMismatch {
        return format!(
            "The baseline model explains all {n} analysed recordings: nothing is shared or \
             missing, what remains is noise."
        );
    }
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
    let what = if found.is_empty() {
        "no effect was found".to_string()
    } else {
        list(&found)
    };
    let (_, verdict) = verdict_label(r.verdict);
    format!(
        "Session {verdict}: {what}; {}.",
        validation::sentence(&r.validation)
    )
}

/// "shared by all 3 recordings", or by the ones it names.
fn acts_on(s: &SharedEffect, n: usize) -> String {
    match &s.recordings {
        None => format!("is shared by all {n} recordings"),
        Some(files) => format!("is shared by {}", list(files)),
    }
}

/// What the angle laws follow: the contact angle when the session has several, else the
/// azimuth (as the search decides).
fn axis(r: &SessionReport) -> &'static str {
    if r.protocols.contact_angles_deg.len() > 1 {
        "contact angle"
    } else {
        "azimuth"
    }
}

/// The outputs' sensitivities across the tests: angle laws and contradictions, in words.
fn sensitivities(r: &SessionReport) -> String {
    let mut h = String::from("<h2 id=sensitivities>Sensitivities across the tests</h2>");
    let mut items: Vec<String> = r
        .angle_laws()
        .map(|s| {
            let e = &s.effect;
            let ch = e.channels.first().map_or("", |c| words::channel_name(c));
            let ratio = e.params.get("ratio").unwrap_or(f64::NAN);
            format!(
                "<li><b>Angle dependence of {ch}.</b> The share of the rod's load that reaches \
                 {ch} changes with the {} otherwise than the model's angle law: its measured \
                 sensitivity at the largest {0} over that at the smallest, divided by the \
                 model's same ratio, is {}. {}</li>",
                axis(r),
                significant(ratio, 3),
                esc(&full_stop(&capital(&e.evidence)))
            )
        })
        .collect();
    items.extend(r.contradicted.iter().map(|c| {
        let values: Vec<String> = c
            .values
            .iter()
            .map(|(f, v)| format!("{} in {}", significant(*v, 3), esc(f)))
            .collect();
        format!(
            "<li><b>Contradicted: <code>{}</code>.</b> {}: {}</li>",
            esc(&c.parameter),
            capital(&list(&values)),
            esc(&full_stop(&c.evidence))
        )
    }));
    if items.is_empty() {
        h.push_str("<p>Each output's sensitivity is one value for the whole session: nothing follows the contact angle or azimuth otherwise than the model says, and no recording contradicts the others.</p>");
    } else {
        h.push_str(&format!("<ul>{}</ul>", items.concat()));
    }
    h
}

/// What the session cannot decide, and why.
fn undecided(r: &SessionReport) -> String {
    let mut h = String::from("<h2 id=undecided>Undecided</h2>");
    if r.undecided.is_empty() {
        h.push_str("<p>Nothing: every deviation the recordings show is attributed.</p>");
        return h;
    }
    h.push_str("<ul>");
    for u in &r.undecided {
        let names: Vec<String> = u.effects.iter().map(|e| words::effect_name(e)).collect();
        h.push_str(&format!(
            "<li><b>{} or the calibration ({})</b>: {}</li>",
            esc(&capital(&names.join(" or "))),
            esc(&u.calibration.join(", ")),
            esc(&full_stop(&u.reason))
        ));
    }
    h.push_str("</ul>");
    h
}

/// Per recording, a small figure of its compared channels from its own diagnosis.
fn each_recording(d: &SessionDiagnosis) -> String {
    let mut h = String::from(
        "<h2 id=each>Each recording</h2><p>Per recording, every compared channel: the recording \
         (grey) and the improved model of its own diagnosis (blue), fitted to that recording \
         alone; the grey band is its held-out stretch, which no parameter saw.</p>",
    );
    for (file, single) in &d.singles {
        h.push_str(&format!("<h3><code>{}</code></h3>", esc(file)));
        match single {
            Ok(s) => {
                let caption = format!(
                    "{file}: recorded and improved series of each compared channel, at the \
                     fitting rate (block means)."
                );
                h.push_str(&figure(figs::overview(&s.plots), &caption));
            }
            Err(e) => h.push_str(&format!("<p class=error>Not analysed: {}</p>", esc(e))),
        }
    }
    h
}
