//! The HTML report: one self-contained file (inline SVG, no fonts, scripts or anything fetched)
//! that opens offline and can be mailed. It leads with the verdict in a sentence, then one
//! paragraph per effect with a zoom on the window where it shows, what remains unexplained,
//! every channel's recording against the baseline and improved models with the residuals, the
//! candidates weighed and the baseline's calibration. The figures use the `figures` crate, the
//! same axes as `tactile plot`.
//!
//! [`html()`] builds the page, [`write()`] writes it to a file.

pub(crate) mod figs;
pub(crate) mod page;
pub(crate) mod params;
pub mod remains;
pub(crate) mod words;

use std::path::Path;

use crate::data::CHANNELS;
use crate::outcome::{Diagnosis, PlotData};
use crate::output::Verdict;
use page::{esc, figure};
use remains::Remains;

/// The report of `d` as one HTML document.
pub fn html(d: &Diagnosis) -> String {
    let r = &d.report;
    let remains = remains::analyse(&d.plots);
    let mut h = page::head(r, &words::verdict_sentence(r, &remains));
    h.push_str(&effects(d));
    if matches!(
        r.verdict,
        Verdict::PartiallyExplained | Verdict::Unexplained
    ) {
        h.push_str(&what_remains(d, &remains));
    }
    h.push_str(&channels(&d.plots));
    h.push_str(&page::candidates(r));
    h.push_str("<h2 id=baseline>Baseline calibration</h2><p>The baseline model's own parameters, fitted before any effect was tried.</p>");
    let b = &r.baseline;
    h.push_str(&params::table(&params::rows(
        &b.parameters,
        &b.params,
        None,
    )));
    h.push_str("<p class=facts>Written by <code>tactile diagnose</code>; the numbers are those of \
                its JSON output (<code>tactile-diagnosis/1</code>, docs/diagnosis-format.md).</p></body></html>\n");
    h
}

/// Write [`html`] of `d` to `path` (a file, e.g. `report.html`) whole, creating its folder
/// ([`crate::outputs::write_whole`]).
pub fn write(path: &Path, d: &Diagnosis) -> std::io::Result<()> {
    crate::outputs::write_whole(path, html(d).as_bytes())
}

/// One paragraph, parameter table and zoomed figure per effect.
fn effects(d: &Diagnosis) -> String {
    let r = &d.report;
    let mut h = String::from("<h2 id=effects>Effects found</h2>");
    if r.effects.is_empty() {
        h.push_str("<p>None: no catalogue effect improved both the fit and the held-out misfit enough to be kept.</p>");
    }
    for e in &r.effects {
        let window = words::evidence_window(e, &r.effects, &r.mismatches);
        h.push_str(&format!(
            "<h3>{} <small>({}{})</small></h3><p><b>{}</b></p><p>{} {}</p>",
            esc(&capital(&words::effect_name(&e.name))),
            e.stage.name(),
            if e.catalogue {
                ""
            } else {
                ", not in the catalogue"
            },
            esc(&words::stage_sentence(e)),
            esc(&e.evidence),
            esc(&words::effect_sentences(e, r, window))
        ));
        h.push_str(&evidence_numbers(e));
        let rows = params::rows(&e.parameters, &e.params, Some(&e.param_stderr));
        h.push_str(&params::table(&rows));
        h.push_str(&discovered(d, e));
        let Some(m) = window else { continue };
        let Some(c) = CHANNELS.iter().position(|c| *c == m.channel) else {
            continue;
        };
        let what = format!("where it shows: {}", m.regime);
        let caption = format!(
            "{}, {}–{} s: the window where {} shows (shaded orange), with the signals and residuals around it.",
            figs::quantity_name(c),
            figures::number::significant(m.t_start_s, 3),
            figures::number::significant(m.t_end_s, 3),
            words::effect_name(&e.name)
        );
        h.push_str(&figure(
            figs::zoom(&d.plots, c, (m.t_start_s, m.t_end_s), &what),
            &caption,
        ));
    }
    for u in &r.undecided {
        let names: Vec<String> = u.effects.iter().map(|e| words::effect_name(e)).collect();
        let calibration = match (names.is_empty(), u.calibration.is_empty()) {
            (_, true) => String::new(),
            (true, false) => format!("the calibration ({})", u.calibration.join(", ")),
            (false, false) => format!(" or the calibration ({})", u.calibration.join(", ")),
        };
        h.push_str(&format!(
            "<h3>Undecided: {}{}</h3><p>{}.</p>",
            esc(&names.join(" or ")),
            esc(&calibration),
            esc(&capital(&u.reason))
        ));
    }
    h
}

/// An effect's evidence as numbers (`evidence_values`): the criterion, the held-out misfit
/// without and with it, the held-out test's p-value and its value after the false-discovery
/// control.
fn evidence_numbers(e: &crate::output::EffectReport) -> String {
    let Some(v) = e.evidence_values else {
        return String::new();
    };
    let s = |x: f64| figures::number::significant(x, 3);
    let mut parts = vec![format!("BIC lower by {}", s(v.bic_gain))];
    if v.heldout_rmse_with.is_finite() {
        parts.push(format!(
            "held-out RMSE {} without it, {} with it",
            s(v.heldout_rmse_without),
            s(v.heldout_rmse_with)
        ));
    }
    if let (Some(p), Some(q)) = (v.p_value, v.q_value) {
        parts.push(format!(
            "held-out test p = {}, {} after the false-discovery control (passes at 0.05)",
            s(p),
            s(q)
        ));
    }
    format!(
        "<p class=evidence>Evidence: {}.</p>",
        esc(&parts.join("; "))
    )
}

/// `s` with its first letter in upper case.
/// A discovered term's inclusion (the share of bootstrap resamples that kept each feature) and
/// its figure against what it depends on most directly: the load (its level, rate or memory),
/// the rod's travel or speed, or another output; a term of time alone is seen in its window.
fn discovered(d: &Diagnosis, e: &crate::output::EffectReport) -> String {
    let Some(inclusion) = e.inclusion.as_ref() else {
        return String::new();
    };
    let mut h =
        String::from("<p>How often a bootstrap resample of the recording kept each feature: ");
    let shares: Vec<String> = inclusion
        .0
        .iter()
        .map(|(f, p)| format!("<code>{}</code> {:.0} %", esc(f), 100.0 * p))
        .collect();
    h.push_str(&shares.join(", "));
    h.push_str(".</p>");
    let depends = e.depends_on.as_deref().unwrap_or_default();
    let has = |q: &str| depends.iter().any(|d| d == q);
    let against = if has("load_N") || has("load_rate") || has("load_history") {
        Some(Some(0))
    } else if has("rod_mm") || has("rod_speed") {
        Some(None)
    } else {
        (1..4).find(|&c| has(CHANNELS[c])).map(Some)
    };
    let curve = d.plots.terms.iter().find(|t| t.name == e.name);
    if let (Some(against), Some(curve)) = (against, curve) {
        let x = against.map_or("the rod's travel", figs::quantity_name);
        let caption = format!(
            "The term on {} against {x}, one dot per block (held-out blocks grey): the shape \
             of the dependence the data chose.",
            figs::quantity_name(curve.channel)
        );
        h.push_str(&figure(
            figs::term_against(&d.plots, curve, against),
            &caption,
        ));
    }
    h
}

pub(crate) fn capital(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map_or(String::new(), |f| f.to_uppercase().chain(c).collect())
}

/// Where the final residual is still structured, and how.
fn what_remains(d: &Diagnosis, remains: &[Remains]) -> String {
    let p = &d.plots;
    let mut h = String::from("<h2 id=remains>What remains</h2><p>The residual of the improved model is not noise. Per channel, worst first:</p><ul>");
    let sentences: Vec<(usize, String)> = remains
        .iter()
        .enumerate()
        .filter_map(|(i, r)| words::remains_sentence(r).map(|s| (i, s)))
        .collect();
    for (_, s) in &sentences {
        h.push_str(&format!("<li>{}</li>", esc(s)));
    }
    // Spectral lines are found on the full-rate residual, which the plots' block means hide.
    let mains_named = d
        .report
        .effects
        .iter()
        .any(|e| e.name == "mains_interference");
    let lines = if mains_named {
        &[][..]
    } else {
        &d.report.localisation.lines[..]
    };
    for (f, amplitude, _) in lines {
        h.push_str(&format!(
            "<li>A spectral line at {} with amplitude {} in the full-rate residual, not modelled.</li>",
            figures::number::measurement(*f, None, "Hz"),
            figures::number::measurement(*amplitude, None, "V")
        ));
    }
    if sentences.is_empty() && lines.is_empty() {
        h.push_str("<li>No single trend, periodic component or correlation with the load or its rate stands out; the structure is in the residual plots below.</li>");
    }
    h.push_str("</ul>");
    if let Some(&(i, _)) = sentences.first() {
        let r = &remains[i];
        let caption = format!(
            "{} residual of the improved model with its straight-line trend.",
            figs::quantity_name(r.channel)
        );
        h.push_str(&figure(
            figs::remainder(p, r.channel, r.trend.slope, figs::IMPROVED, &[]),
            &caption,
        ));
    }
    h
}

/// Every compared channel over the whole recording.
fn channels(p: &PlotData) -> String {
    let mut h = String::from("<h2 id=channels>Channels</h2><p>Grey band: the held-out stretch, which no parameter saw. Series at the fitting rate (block means).</p>");
    for c in (0..4).filter(|&c| p.used[c]) {
        let caption = format!(
            "{}: recording, baseline and improved model (top); residuals before and after (bottom).",
            figs::quantity_name(c)
        );
        h.push_str(&figure(figs::channel(p, c), &caption));
    }
    h
}
