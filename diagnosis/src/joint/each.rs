//! The session page's last section: each recording, where the models miss it. Per recording its
//! verdict under the session's model and what remains, the held-out stretch and what it covers,
//! the misfits before and after, and one figure of every compared channel: the recording, the
//! baseline calibrated to it alone and the session's model, drawn so that each stays visible,
//! the windows where the baseline misses and where the session's model still misses shaded and
//! named, and the residuals of both (the single report's figure code, [`figs::stacked`]).

use figures::{styles, Band};
use plotters::style::RGBColor;

use super::headline;
use super::headline::{pct, plain};
use super::output::{RecordingRow, Remaining};
use super::SessionDiagnosis;
use crate::data::CHANNELS;
use crate::localise::Mismatch;
use crate::outcome::{Diagnosis, PlotData};
use crate::output::{Report, Verdict};
use crate::report::page::{esc, figure, verdict_label};
use crate::report::{figs, remains};

/// What the session's model is called in the figures.
const MODEL: &str = "session's model";
/// Windows of the baseline's misfit shaded per channel: the largest, at most this many, each
/// holding at least [`BAND_SHARE`] of the baseline's misfit (smaller ones would be noise in
/// the picture).
const BANDS: usize = 2;
const BAND_SHARE: f64 = 0.05;
/// Shading of a window where the session's model still misses (the baseline's is
/// [`styles::WINDOW`], orange).
const STILL_MISSES: RGBColor = RGBColor(148, 103, 189);

/// The section: a paragraph saying how to read the figures, then each recording.
pub(super) fn section(d: &SessionDiagnosis) -> String {
    let mut h = format!(
        "<h2 id=each>Each recording</h2><p>Per recording and compared channel: the recording \
         (wide, light grey), the {MODEL} (blue) and, thin and on top, the baseline calibrated \
         to that recording alone (red), the held-out stretch, which no parameter saw, shaded \
         grey; below, what each model leaves (the residuals), shaded orange where the baseline \
         misses most and purple where the {MODEL} still misses (a recording it does not \
         explain). Series at the fitting rate (block means).</p>"
    );
    for (i, (file, single)) in d.singles.iter().enumerate() {
        h.push_str(&format!("<h3 id=rec-{i}><code>{}</code>", esc(file)));
        let row = d.report.recordings.get(i);
        let plots = d.plots.get(i).and_then(Option::as_ref);
        match (single, row, plots) {
            (Ok(single), Some(row), Some(p)) => h.push_str(&recording(single, row, p)),
            (Err(e), ..) => {
                h.push_str(&format!("</h3><p class=error>Not analysed: {}</p>", esc(e)))
            }
            _ => h.push_str("</h3><p class=error>Not analysed.</p>"),
        }
    }
    h
}

/// One recording: verdict, what remains, the held-out stretch, the misfits, the figure.
fn recording(single: &Diagnosis, row: &RecordingRow, p: &PlotData) -> String {
    let verdict = row.verdict.map_or("", |v| verdict_label(v).1);
    let mut h = format!(" <small>{verdict}</small></h3><p>");
    if let Some(pr) = row.protocol {
        h.push_str(&format!(
            "Contact angle {}°, azimuth {}°, rod speed {} mm/min. ",
            plain(pr.contact_angle_deg),
            plain(pr.azimuth_deg),
            plain(pr.rod_speed_mm_per_min)
        ));
    }
    h.push_str(&esc(&what_remains(row)));
    let (a, b) = p.heldout;
    h.push_str(&format!(
        " Held out: {}–{} s ({}).",
        plain(a),
        plain(b),
        covers(p)
    ));
    if let Some(f) = &row.fit {
        h.push_str(&format!(
            " Misfit (RMS over each channel's range, mean of the compared channels), baseline \
             alone → {MODEL}: {} → {} over the recording, {} → {} held out.",
            pct(f.rmse_before),
            pct(f.rmse_after),
            pct(f.heldout.rmse_before),
            pct(f.heldout.rmse_after)
        ));
    }
    h.push_str("</p>");
    if let Some(rem) = row.remains.as_ref().filter(|r| !r.channels.is_empty()) {
        let items: Vec<String> = rem
            .channels
            .iter()
            .map(|s| format!("<li>{}</li>", esc(s)))
            .collect();
        h.push_str(&format!("<ul class=remains>{}</ul>", items.concat()));
    }
    let bands = bands(&single.report, row.remains.as_ref());
    let caption = format!(
        "{}: every compared channel, the recording with the baseline alone and the {MODEL} \
         (top of each pair), their residuals (bottom).",
        row.file
    );
    h.push_str(&figure(figs::stacked(p, MODEL, &bands), &caption));
    if let Some(rem) = &row.remains {
        h.push_str(&what_is_left(row, rem, p, &bands));
    }
    h
}

/// A recording the session's model does not explain: the residual of the channel where it
/// misses most, on its own scale (beside the baseline's, a misfit of a few hundred µV is a flat
/// line), with its trend and the windows shaded.
fn what_is_left(
    row: &RecordingRow,
    rem: &Remaining,
    p: &PlotData,
    bands: &[Vec<Band>; 4],
) -> String {
    let analysed = remains::analyse(p);
    let channel = rem
        .windows
        .first()
        .and_then(|m| CHANNELS.iter().position(|c| *c == m.channel))
        .or_else(|| analysed.first().map(|r| r.channel));
    let Some(c) = channel else {
        return String::new();
    };
    let slope = analysed
        .iter()
        .find(|r| r.channel == c)
        .map_or(0.0, |r| r.trend.slope);
    let still: Vec<Band> = bands[c]
        .iter()
        .filter(|b| b.colour == STILL_MISSES)
        .cloned()
        .collect();
    let caption = format!(
        "{}: what the {MODEL} leaves on {} (the channel where it misses most), with its \
         straight-line trend; purple: the windows where it still misses.",
        row.file,
        figs::quantity_name(c)
    );
    figure(figs::remainder(p, c, slope, MODEL, &still), &caption)
}

/// The recording's verdict in a sentence: noise left, or where and how the model still misses.
fn what_remains(row: &RecordingRow) -> String {
    match (row.verdict, &row.remains) {
        (Some(Verdict::NoSignificantMismatch), _) => {
            "The baseline alone explains it: what it leaves is noise.".to_string()
        }
        (Some(Verdict::Explained), _) => {
            format!("What the {MODEL} leaves is noise.")
        }
        (_, Some(rem)) if !rem.windows.is_empty() => {
            let at: Vec<String> = rem.windows.iter().map(headline::window).collect();
            format!(
                "The {MODEL} still misses {}: {}.",
                headline::list(&at),
                rem.character
            )
        }
        (_, Some(rem)) => format!("What the {MODEL} leaves is not noise: {}.", rem.character),
        _ => String::new(),
    }
}

/// Which regimes the held-out stretch covers, and what that means for its test: a rest or a
/// recovery carries no load, so a held-out stretch there cannot test what acts with the load
/// (a sensitivity, an angle law).
fn covers(p: &PlotData) -> String {
    let (a, b) = p.heldout;
    let mut names: Vec<&str> = Vec::new();
    for s in &p.segments {
        let (Some(&t0), Some(&t1)) = (p.t_s.get(s.start), p.t_s.get(s.end.saturating_sub(1)))
        else {
            continue;
        };
        let overlap = t1.min(b) - t0.max(a);
        let name = s.regime.name();
        if overlap > 0.05 * (b - a) && !names.contains(&name) {
            names.push(name);
        }
    }
    let list: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    let unloaded = !names.is_empty() && names.iter().all(|n| matches!(*n, "rest" | "recovery"));
    if unloaded {
        format!(
            "{}: the rod off the load, so it tests how the sensor settles, not what acts \
             under load (a sensitivity, an angle law)",
            headline::list(&list)
        )
    } else if list.is_empty() {
        "no regime found".to_string()
    } else {
        headline::list(&list)
    }
}

/// Per channel the bands to shade: the largest windows where the baseline misses, and where
/// the session's model still misses.
fn bands(single: &Report, remains: Option<&Remaining>) -> [Vec<Band>; 4] {
    let band = |m: &Mismatch, colour: RGBColor, who: &str| Band {
        from: m.t_start_s,
        to: m.t_end_s,
        colour,
        label: format!("{who} misses"),
    };
    std::array::from_fn(|c| {
        let on = |m: &&Mismatch| m.channel == CHANNELS[c];
        // A baseline its recording's own diagnosis found quiet misses nowhere: its windows
        // are shares of noise.
        let missed = single.verdict != Verdict::NoSignificantMismatch;
        let mut v: Vec<Band> = single
            .mismatches
            .iter()
            .filter(|_| missed)
            .filter(on)
            .filter(|m| m.share >= BAND_SHARE)
            .take(BANDS)
            .map(|m| band(m, styles::WINDOW, "baseline"))
            .collect();
        if let Some(rem) = remains {
            v.extend(
                rem.windows
                    .iter()
                    .filter(on)
                    .map(|m| band(m, STILL_MISSES, "model")),
            );
        }
        v
    })
}
