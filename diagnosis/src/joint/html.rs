//! The session's page: one self-contained HTML file (inline SVG and CSS, no script, nothing
//! fetched, no link) in the single report's style. From the top: the session's verdict in
//! words (OUT.json's `summary`: what is explained, what is not and where, a file that failed),
//! the recordings, the shared effects, the sensitivities that follow the contact angle or that
//! the recordings contradict, the leave-one-out validation ([`super::validation`]), what stays
//! undecided, the session models tried, and per recording where the models miss it
//! ([`super::each`]).

use std::path::Path;

use figures::number::significant;

use super::output::SessionReport;
use super::SessionDiagnosis;
use super::{each, headline, tables, validation};
use crate::report::page::{esc, verdict_label, STYLE};
use crate::report::{capital, words};

/// The session page's own style on top of the single report's: a failed file turns the
/// verdict's border red, and the validation's words are coloured by their outcome.
const SESSION_STYLE: &str = ".verdict.failed{border-color:#d62728}\
.verdict .failure{display:block;color:#b00;margin-bottom:6px}\
td.better{color:#2a7a2a}td.worse{color:#b00}td.same{color:#555}\
.remains{color:#8a4b00}h3 small{font-weight:normal;color:#555}";

/// The session's page as one HTML document.
pub fn report_html(d: &SessionDiagnosis) -> String {
    let r = &d.report;
    let mut h = head(r);
    h.push_str(&tables::recordings(r));
    h.push_str(&tables::shared(r));
    h.push_str(&sensitivities(r));
    h.push_str(&validation::section(&r.validation, r.shares_nothing()));
    h.push_str(&undecided(r));
    h.push_str(&validation::candidates(&r.candidates));
    h.push_str(&each::section(d));
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

/// Doctype, title, style and the heading with the verdict first: OUT.json's `summary`, a failed
/// file's line set apart in red above the rest.
fn head(r: &SessionReport) -> String {
    let (class, words) = verdict_label(r.verdict);
    let n = r.recordings.len();
    let analysed = r.recordings.iter().filter(|x| x.error.is_none()).count();
    // Each distinct value, or where there are many their range: never one value for several.
    let values = |v: &[f64]| match v {
        [first, .., last] if v.len() > 4 => {
            format!("{}–{}", headline::plain(*first), headline::plain(*last))
        }
        _ => {
            let v: Vec<String> = v.iter().map(|x| headline::plain(*x)).collect();
            v.join(", ")
        }
    };
    let p = &r.protocols;
    let summary = if r.summary.is_empty() {
        headline::sentence(r)
    } else {
        r.summary.clone()
    };
    let failed = analysed < n;
    // The failure leads the summary (`headline::sentence`): set apart.
    let failure = headline::failed(&r.recordings);
    let text = match failure.and_then(|f| Some((summary.strip_prefix(&f)?, f))) {
        Some((rest, f)) => format!("<span class=failure>{}</span>{}", esc(&f), esc(rest)),
        None => esc(&summary),
    };
    let class = if failed {
        format!("{class} failed")
    } else {
        class.to_string()
    };
    format!(
        "<!doctype html><html lang=en><meta charset=utf-8>\
         <meta name=viewport content='width=device-width,initial-scale=1'>\
         <title>Joint diagnosis of a session of {n} recordings</title>\
         <style>{STYLE}{SESSION_STYLE}</style><body>\
         <h1>Joint diagnosis of a session of {n} recordings</h1>\
         <p id=verdict class='verdict {class}'>{text}</p>\
         <p class=facts>Verdict <b>{words}</b>. {analysed} of {n} recordings analysed, one model \
         of the sensor and the gel for all of them. Contact angles {}°; azimuths {}°; rod \
         speeds {} mm/min. Diagnosed in {} s.</p>",
        values(&p.contact_angles_deg),
        values(&p.azimuths_deg),
        values(&p.rod_speeds_mm_per_min),
        significant(r.seconds, 2),
    )
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
                headline::axis(r),
                significant(ratio, 3),
                esc(&headline::full_stop(&capital(&e.evidence)))
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
            capital(&headline::list(&values)),
            esc(&headline::full_stop(&c.evidence))
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
            esc(&headline::full_stop(&u.reason))
        ));
    }
    h.push_str("</ul>");
    h
}
