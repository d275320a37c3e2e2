//! The HTML report: plain SVG written by hand (no plotting dependency): recording vs baseline vs
//! improved model per channel, residual before/after, the localisation timeline, the parameter
//! table with uncertainties and one sentence per effect.

use std::fmt::Write as _;
use std::path::Path;

use super::data::CHANNELS;
use super::output::Report;
use super::pipeline::{Diagnosis, PlotData};
use super::regimes::Regime;

const W: f64 = 900.0;
const H: f64 = 220.0;
const PAD: f64 = 45.0;

/// Write `index.html` and one SVG per plot into `dir`.
pub fn write(dir: &Path, d: &Diagnosis) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let mut html = summary_html(&d.report);
    html.push_str("<h2>Localisation timeline</h2>");
    std::fs::write(dir.join("timeline.svg"), timeline_svg(d))?;
    html.push_str("<img src=timeline.svg>");
    html.push_str("<h2>Channels</h2>");
    let p = &d.plots;
    for c in (0..4).filter(|&c| p.used[c]) {
        let (fit, residual) = channel_svgs(p, c);
        std::fs::write(dir.join(format!("{}.svg", CHANNELS[c])), &fit)?;
        std::fs::write(dir.join(format!("{}_residual.svg", CHANNELS[c])), &residual)?;
        let _ = write!(
            html,
            "<h3>{0}</h3><img src={0}.svg><br><img src={0}_residual.svg>",
            CHANNELS[c]
        );
    }
    html.push_str("<p>Shaded: the held-out stretch, never fitted. Series shown at the fitting rate (block means).</p>");
    std::fs::write(dir.join("index.html"), html)
}

/// The report's head: verdict and RMSEs, each effect with its parameters, the baseline's
/// calibration.
fn summary_html(r: &Report) -> String {
    let mut html = String::new();
    let _ = write!(
        html,
        "<!doctype html><meta charset=utf-8><title>tactile diagnose: {}</title>\
         <style>body{{font-family:sans-serif;max-width:960px;margin:auto}}td,th{{padding:2px 8px;text-align:right}}</style>\
         <h1>Diagnosis of {}</h1><p>Verdict: <b>{:?}</b>. RMSE (mean of RMS / range) {:.4} -> {:.4}; held-out stretch {:.1}-{:.1} s: {:.4} -> {:.4}.</p>",
        esc(&r.recording), esc(&r.recording), r.verdict, r.fit.rmse_before, r.fit.rmse_after,
        r.fit.heldout.t_start_s, r.fit.heldout.t_end_s, r.fit.heldout.rmse_before, r.fit.heldout.rmse_after
    );
    html.push_str("<h2>Effects found</h2>");
    if r.effects.is_empty() {
        html.push_str("<p>None.</p>");
    }
    for e in &r.effects {
        let _ = write!(html, "<h3>{}</h3><p>{}</p><table><tr><th>parameter</th><th>value</th><th>std. error</th></tr>", e.name, esc(&e.evidence));
        for (k, v) in &e.params.0 {
            let se = e
                .param_stderr
                .get(k)
                .map_or("-".to_string(), |s| format!("{s:.3e}"));
            let _ = write!(html, "<tr><td>{k}</td><td>{v:.4e}</td><td>{se}</td></tr>");
        }
        html.push_str("</table>");
    }
    html.push_str("<h2>Baseline calibration</h2><table>");
    for (k, v) in &r.baseline.params.0 {
        let _ = write!(html, "<tr><td>{k}</td><td>{v:.4e}</td></tr>");
    }
    html.push_str("</table>");
    html
}

/// Channel `c`'s plots: recording, baseline and improved model; the residual before and after.
fn channel_svgs(p: &PlotData, c: usize) -> (String, String) {
    let fit = series_svg(
        &p.t_s,
        &[
            (&p.recorded[c], "#888", "recording"),
            (&p.baseline[c], "#d33", "baseline"),
            (&p.improved[c], "#36c", "improved"),
        ],
        CHANNELS[c],
        p.heldout,
    );
    let minus = |model: &[f64]| -> Vec<f64> {
        p.recorded[c]
            .iter()
            .zip(model)
            .map(|(a, b)| a - b)
            .collect()
    };
    let (rb, ri) = (minus(&p.baseline[c]), minus(&p.improved[c]));
    let residual = series_svg(
        &p.t_s,
        &[
            (&rb, "#d33", "residual before"),
            (&ri, "#36c", "residual after"),
        ],
        &format!("{} residual", CHANNELS[c]),
        p.heldout,
    );
    (fit, residual)
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Line plot of several series sharing the time axis, the held-out stretch shaded.
fn series_svg(
    t: &[f64],
    series: &[(&Vec<f64>, &str, &str)],
    title: &str,
    heldout: (f64, f64),
) -> String {
    let (t0, t1) = (t[0], *t.last().unwrap_or(&1.0));
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (y, _, _) in series {
        for &v in y.iter() {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if hi <= lo {
        hi = lo + 1.0;
    }
    let x = |v: f64| PAD + (v - t0) / (t1 - t0).max(1e-9) * (W - 2.0 * PAD);
    let y = |v: f64| H - PAD + (lo - v) / (hi - lo) * (H - 2.0 * PAD);
    let mut s =
        format!("<svg xmlns='http://www.w3.org/2000/svg' width='{W}' height='{H}' font-size='11'>");
    let _ = write!(
        s,
        "<rect x='{:.1}' y='{PAD}' width='{:.1}' height='{:.1}' fill='#eee'/>",
        x(heldout.0),
        x(heldout.1) - x(heldout.0),
        H - 2.0 * PAD
    );
    let _ = write!(s, "<text x='{PAD}' y='15'>{}</text>", esc(title));
    for (i, (ys, colour, label)) in series.iter().enumerate() {
        let step = (ys.len() / 2000).max(1);
        let pts: Vec<String> = (0..ys.len())
            .step_by(step)
            .map(|k| format!("{:.1},{:.1}", x(t[k]), y(ys[k])))
            .collect();
        let _ = write!(
            s,
            "<polyline fill='none' stroke='{colour}' stroke-width='1' points='{}'/>",
            pts.join(" ")
        );
        let _ = write!(
            s,
            "<text x='{:.0}' y='15' fill='{colour}'>{label}</text>",
            W - 330.0 + 110.0 * i as f64
        );
    }
    let _ = write!(
        s,
        "<text x='2' y='{:.0}'>{hi:.3e}</text><text x='2' y='{:.0}'>{lo:.3e}</text>",
        PAD,
        H - PAD
    );
    let _ = write!(s, "<text x='{PAD}' y='{:.0}'>{t0:.0} s</text><text x='{:.0}' y='{:.0}'>{t1:.0} s</text></svg>", H - 20.0, W - PAD - 30.0, H - 20.0);
    s
}

/// Regimes as coloured bands and each mismatch window as a bar whose height is its share.
fn timeline_svg(d: &Diagnosis) -> String {
    let p = &d.plots;
    let (t0, t1) = (p.t_s[0], *p.t_s.last().unwrap_or(&1.0));
    let x = |v: f64| PAD + (v - t0) / (t1 - t0).max(1e-9) * (W - 2.0 * PAD);
    let mut s =
        format!("<svg xmlns='http://www.w3.org/2000/svg' width='{W}' height='{H}' font-size='11'>");
    for seg in &p.segments {
        let colour = match seg.regime {
            Regime::Rest => "#ddd",
            Regime::Loading => "#fdd",
            Regime::Hold => "#fda",
            Regime::Release => "#dfd",
            Regime::Recovery => "#ddf",
        };
        let (a, b) = (p.t_s[seg.start], p.t_s[(seg.end).min(p.t_s.len() - 1)]);
        let _ = write!(s, "<rect x='{:.1}' y='20' width='{:.1}' height='20' fill='{colour}'><title>{}</title></rect>", x(a), (x(b) - x(a)).max(0.5), seg.regime.name());
    }
    let _ = write!(s, "<text x='{PAD}' y='15'>regimes (rest grey, loading red, hold orange, release green, recovery blue); bars: share of the baseline misfit per channel and window (tallest = largest share)</text>");
    let max_share = d
        .report
        .mismatches
        .iter()
        .map(|m| m.share)
        .fold(1e-12, f64::max);
    for m in &d.report.mismatches {
        let row = CHANNELS.iter().position(|c| *c == m.channel).unwrap_or(0) as f64;
        let top = 60.0 + row * 38.0;
        let h = 34.0 * (m.share / max_share).min(1.0);
        let _ = write!(s, "<rect x='{:.1}' y='{:.1}' width='{:.1}' height='{h:.1}' fill='#c33'><title>{} {} {:.0} %</title></rect>", x(m.t_start_s), top + 34.0 - h, (x(m.t_end_s) - x(m.t_start_s)).max(1.0), m.channel, m.regime, 100.0 * m.share);
    }
    for (i, c) in CHANNELS.iter().enumerate() {
        let _ = write!(
            s,
            "<text x='2' y='{:.0}'>{c}</text>",
            60.0 + i as f64 * 38.0 + 30.0
        );
    }
    s.push_str("</svg>");
    s
}
