//! The page around the figures: head and style (no fonts, scripts or anything fetched: the file
//! opens offline and can be mailed), escaping, figure wrappers and the candidate table.

use figures::number::{fixed, significant};

use super::words::{candidate_reason, effect_name};
use crate::output::{Report, Verdict};

/// The pages' style sheet (the session's page uses it too).
pub(crate) const STYLE: &str = "\
body{font-family:system-ui,-apple-system,'Segoe UI',Roboto,sans-serif;max-width:1000px;\
margin:0 auto;padding:12px 20px 40px;color:#222;line-height:1.45}\
h1{font-size:1.45em;margin:.3em 0}h2{margin-top:1.6em;border-bottom:1px solid #ddd}\
.verdict{font-size:1.2em;font-weight:600;background:#f3f6fa;border-left:6px solid #1f77b4;\
padding:10px 14px;margin:10px 0}\
.verdict.partially_explained{border-color:#e69500}.verdict.unexplained{border-color:#d62728}\
.verdict.explained,.verdict.no_significant_mismatch{border-color:#2ca02c}\
.facts{color:#555;margin:4px 0}figure{margin:10px 0 18px}\
figure svg{width:100%;height:auto;display:block}figcaption{color:#555;font-size:.9em}\
table{border-collapse:collapse;margin:8px 0 14px}\
td,th{padding:3px 10px;border-bottom:1px solid #e3e3e3;text-align:left;vertical-align:top}\
th{background:#f5f5f5}.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}\
tr.at-bound td{background:#fff3cd}tr.chosen td{background:#eaf5ea;font-weight:600}\
.error{color:#b00}code{font-size:.95em}";

/// `&`, `<` and `>` as entities: recording names and reasons are data, not markup.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The verdict as the contract spells it (`partially_explained`) and in words.
pub fn verdict_label(v: Verdict) -> (&'static str, &'static str) {
    match v {
        Verdict::NoSignificantMismatch => ("no_significant_mismatch", "no significant mismatch"),
        Verdict::Explained => ("explained", "explained"),
        Verdict::PartiallyExplained => ("partially_explained", "partially explained"),
        Verdict::Unexplained => ("unexplained", "unexplained"),
    }
}

/// Doctype, title, style and the heading with the verdict sentence first, where a reader
/// looks.
pub fn head(r: &Report, sentence: &str) -> String {
    let (class, words) = verdict_label(r.verdict);
    let h = &r.fit.heldout;
    let pct = |v: f64| format!("{} %", significant(100.0 * v, 2));
    format!(
        "<!doctype html><html lang=en><meta charset=utf-8>\
         <meta name=viewport content='width=device-width,initial-scale=1'>\
         <title>Diagnosis of {name}</title><style>{STYLE}</style><body>\
         <h1>Diagnosis of <code>{name}</code></h1>\
         <p id=verdict class='verdict {class}'>{sentence}</p>\
         <p class=facts>Verdict <b>{words}</b>. Misfit (RMS over each channel's range, mean of \
         the compared channels): {} before, {} after; on the held-out stretch {}–{} s, which no \
         parameter saw: {} before, {} after. Diagnosed in {} s.</p>{simulation}",
        pct(r.fit.rmse_before),
        pct(r.fit.rmse_after),
        significant(h.t_start_s, 3),
        significant(h.t_end_s, 3),
        pct(h.rmse_before),
        pct(h.rmse_after),
        significant(r.seconds, 2),
        name = esc(&r.recording),
        sentence = esc(sentence),
        simulation = simulation(r),
    )
}

/// Whose simulation the baseline was, where it was the user's (`baseline.simulation`).
fn simulation(r: &Report) -> String {
    let Some(s) = &r.baseline.simulation else {
        return String::new();
    };
    let not: Vec<String> = s
        .not_compared
        .iter()
        .map(|(c, why)| format!("<code>{}</code> ({})", esc(c), esc(why)))
        .collect();
    let not = if not.is_empty() {
        String::new()
    } else {
        format!(" Not compared: {}.", not.join(", "))
    };
    let source = s
        .metadata
        .iter()
        .find(|(k, _)| k == "source")
        .map_or(String::new(), |(_, v)| format!(" ({})", esc(v)));
    format!(
        "<p class=facts id=simulation>Baseline: the simulation <code>{file}</code>{source}, \
         {form}, in place of our fingertip FE and chip, calibrated by a load scale, the output \
         scales and offsets; {aligned}. Its outputs were given at {at}.{not}</p>",
        file = esc(&s.file),
        form = s.form.replace('_', " "),
        aligned = esc(&s.aligned),
        at = esc(&s.outputs_at),
    )
}

/// An inline SVG figure with its caption, or the reason it is missing.
pub fn figure(svg: Result<String, figures::Error>, caption: &str) -> String {
    match svg {
        Ok(svg) => format!(
            "<figure>{svg}<figcaption>{}</figcaption></figure>",
            esc(caption)
        ),
        Err(e) => format!(
            "<p class=error>Figure not drawn ({}): {}</p>",
            esc(caption),
            esc(&e.to_string())
        ),
    }
}

/// A candidate's effects in words; an effect listed twice is its two-term form (the pipeline's
/// two-time-scale relaxation).
fn model_name(effects: &[String]) -> String {
    if effects.is_empty() {
        return "baseline only".to_string();
    }
    let mut names: Vec<String> = Vec::new();
    for (i, e) in effects.iter().enumerate() {
        if effects[..i].contains(e) {
            continue;
        }
        let twice = effects[i + 1..].contains(e);
        let name = effect_name(e);
        names.push(if twice {
            format!("{name} (two terms)")
        } else {
            name
        });
    }
    names.join(" + ")
}

/// Every model weighed, best BIC first, with why it was kept or rejected.
pub fn candidates(r: &Report) -> String {
    let chosen = r.candidates.iter().find(|c| c.accepted);
    let mut order: Vec<_> = r.candidates.iter().collect();
    order.sort_by(|a, b| a.bic.total_cmp(&b.bic));
    let mut h = String::from(
        "<h2 id=candidates>Candidates weighed</h2><p>Each model was fitted to the recording outside the \
         held-out stretch; BIC weighs fit against parameters (lower is better), the held-out \
         misfit (χ², noise units) is on data no parameter saw.</p><table class=candidates>\
         <tr><th>model</th><th>BIC</th><th>held-out χ²</th><th>why</th></tr>",
    );
    for c in order {
        let name = model_name(&c.effects);
        let class = if c.accepted { " class=chosen" } else { "" };
        h.push_str(&format!(
            "<tr{class}><td>{}</td><td class=num>{}</td><td class=num>{}</td><td>{}</td></tr>",
            esc(&name),
            fixed(c.bic, 0),
            significant(c.heldout_chi2, 3),
            esc(&candidate_reason(c, chosen))
        ));
    }
    h.push_str("</table>");
    h
}
