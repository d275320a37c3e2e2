//! The session page's evidence: the leave-one-out validation as a table and a bar chart
//! (plotters into an inline SVG, as the batch summary's plots; the `figures` crate draws lines
//! only), and the session models tried.

use figures::number::{fixed, significant};
use figures::{styles, svg_string, Error};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::headline::pct;
use super::output::{Change, LeaveOneOut, SessionCandidate, Validation};
use crate::report::page::{esc, figure};
use crate::report::words::effect_name;

/// The bar chart's size in SVG pixels; the page scales it to its column.
const SIZE: (u32, u32) = (960, 320);
/// The single report's figure fonts (plotters writes them at 0.8: 13 and 14 px on the page).
const FONT: (&str, u32) = ("sans-serif", 16);
const TITLE_FONT: (&str, u32) = ("sans-serif", 17);

/// The leave-one-out section: what it does, its table and its bar chart.
/// `shares_nothing`: the session's model shares no effect, and the validation is then no
/// evidence of transfer.
pub(super) fn section(v: &Validation, shares_nothing: bool) -> String {
    let what = if shares_nothing {
        format!(
            "{} The validation below tests only the baseline's calibration shared across the \
             tests; it is no evidence that anything found transfers.",
            super::headline::NOTHING_TRANSFERS
        )
    } else {
        "This is the evidence that the physics found transfers to a test it never saw.".into()
    };
    let mut h = format!(
        "<h2 id=validation>Leave-one-out validation</h2><p>For each recording, the session's \
         shared physics fitted to the other recordings alone; then, with those parameters \
         fixed, only the recording's own calibration fitted to its fitting stretch, and its \
         held-out stretch predicted. Before: the baseline calibrated to that recording alone, \
         on the same stretch. {} A change counts only beyond the held-out test's own margin \
         (twice the noise of the two misfits' difference, and half a percent of the \
         misfit).</p>",
        esc(&what)
    );
    let rows = &v.leave_one_out;
    if rows.is_empty() {
        let note = v
            .note
            .as_deref()
            .unwrap_or("no recording could be left out");
        h.push_str(&format!("<p>{}</p>", esc(note)));
        return h;
    }
    h.push_str(
        "<table class=validation><tr><th>recording left out</th><th>own baseline</th>\
         <th>shared physics of the others</th><th>change</th><th>beyond the noise</th></tr>",
    );
    for r in rows {
        let change = 100.0 * (r.rmse_after / r.rmse_before - 1.0);
        let (class, word) = match r.change {
            Change::Better => ("better", "better"),
            Change::NoChange => ("same", "no change"),
            Change::Worse => ("worse", "worse"),
        };
        h.push_str(&format!(
            "<tr><td><code>{}</code></td><td class=num>{}</td><td class=num>{}</td>\
             <td class=num>{} %</td><td class={class}>{word}</td></tr>",
            esc(&r.file),
            pct(r.rmse_before),
            pct(r.rmse_after),
            signed(change)
        ));
    }
    h.push_str("</table>");
    let caption = "Held-out RMSE of each recording left out (RMS over each channel's range, mean \
                   of the compared channels): its own baseline (red) and the shared physics \
                   fitted to the others (blue). Lower is better.";
    h.push_str(&figure(bars(rows), caption));
    h
}

/// `+1.2` or `−3.4`: a change with its sign.
fn signed(v: f64) -> String {
    if !v.is_finite() {
        return "–".to_string();
    }
    let s = significant(v.abs(), 2);
    if v < 0.0 {
        format!("−{s}")
    } else {
        format!("+{s}")
    }
}

/// The bar chart of `rows`: per recording its held-out RMSE before and after, in % of range.
pub(super) fn bars(rows: &[LeaveOneOut]) -> Result<String, Error> {
    svg_string(SIZE, |root| draw_bars(root, rows))
}

fn draw_err(e: impl std::fmt::Display) -> Error {
    Error::Draw(e.to_string())
}

fn draw_bars(root: &DrawingArea<SVGBackend<'_>, Shift>, rows: &[LeaveOneOut]) -> Result<(), Error> {
    let last = u32::try_from(rows.len()).unwrap_or(1).max(1) - 1;
    let top = rows
        .iter()
        .flat_map(|r| [r.rmse_before, r.rmse_after])
        .filter(|v| v.is_finite())
        .fold(0.0, f64::max);
    // Room above the bars for the legend.
    let y_max = (100.0 * top * 1.35).max(1e-9);
    let mut chart = ChartBuilder::on(root)
        .margin_left(10)
        .margin_right(18)
        .margin_top(10)
        .x_label_area_size(44)
        .y_label_area_size(72)
        .build_cartesian_2d((0..last).into_segmented(), 0.0..y_max)
        .map_err(draw_err)?;
    let name = |v: &SegmentValue<u32>| match v {
        SegmentValue::CenterOf(i) => rows
            .get(*i as usize)
            .map_or(String::new(), |r| r.file.clone()),
        _ => String::new(),
    };
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(rows.len() + 1)
        .x_label_formatter(&name)
        .y_label_formatter(&|v| significant(*v, 2))
        .x_desc("recording left out")
        .y_desc("held-out RMSE [% of range]")
        .bold_line_style(RGBColor(228, 228, 228))
        .light_line_style(TRANSPARENT)
        .label_style(FONT)
        .axis_desc_style(TITLE_FONT)
        .draw()
        .map_err(draw_err)?;
    let sides = [
        ("own baseline", styles::BASELINE.colour, true),
        (
            "shared physics of the others",
            styles::IMPROVED.colour,
            false,
        ),
    ];
    for (label, colour, left) in sides {
        let value = |r: &LeaveOneOut| if left { r.rmse_before } else { r.rmse_after };
        let bar = |(i, r): (usize, &LeaveOneOut)| {
            let i = i as u32;
            let (a, b) = if left {
                (SegmentValue::Exact(i), SegmentValue::CenterOf(i))
            } else {
                (SegmentValue::CenterOf(i), SegmentValue::Exact(i + 1))
            };
            let mut rect = Rectangle::new([(a, 0.0), (b, 100.0 * value(r))], colour.filled());
            let (l, r) = if left { (14, 1) } else { (1, 14) };
            rect.set_margin(0, 0, l, r);
            rect
        };
        chart
            .draw_series(rows.iter().enumerate().map(bar))
            .map_err(draw_err)?
            .label(label)
            .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 22, y + 6)], colour.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font(FONT)
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(200, 200, 200))
        .draw()
        .map_err(draw_err)
}

/// Every session model tried, in the order of the search, the accepted one highlighted;
/// collapsed, since it is the record rather than the finding.
pub(super) fn candidates(tried: &[SessionCandidate]) -> String {
    let names = |v: &[String]| {
        if v.is_empty() {
            "–".to_string()
        } else {
            let v: Vec<String> = v.iter().map(|e| effect_name(e)).collect();
            esc(&v.join(", "))
        }
    };
    let mut h = format!(
        "<h2 id=candidates>Session models tried</h2><details><summary>{} models, in the order \
         the search tried them (the accepted ones highlighted). BIC weighs fit against \
         parameters (lower is better); the held-out misfit (χ², noise units) is on data no \
         parameter saw.</summary><table class=candidates><tr><th>shared</th>\
         <th>per recording</th><th>scales per recording</th><th>BIC</th><th>held-out χ²</th>\
         <th>why</th></tr>",
        tried.len()
    );
    for c in tried {
        let class = if c.accepted { " class=chosen" } else { "" };
        h.push_str(&format!(
            "<tr{class}><td>{}</td><td>{}</td><td>{}</td><td class=num>{}</td>\
             <td class=num>{}</td><td>{}</td></tr>",
            names(&c.shared),
            names(&c.per_recording),
            names(&c.per_recording_scales),
            fixed(c.bic, 0),
            significant(c.heldout_chi2, 3),
            esc(&c.reason)
        ));
    }
    h.push_str("</table></details>");
    h
}
