//! The report's figures, drawn with the `figures` crate (the axes `tactile plot` uses too):
//! per channel the recording with both models and the residuals, a zoom on the window where an
//! effect shows, and (the session's page) every channel of a recording stacked.

use figures::{draw_panel, styles, svg_string, Band, Error, Line, Panel, Quantity};

use super::words::channel_unit;
use crate::data::CHANNELS;
use crate::outcome::PlotData;
use crate::terms::TermCurve;

/// Figure width in SVG pixels; the page scales it to its column.
const WIDTH: u32 = 960;
/// Height of one panel, legend strip included.
const PANEL_H: u32 = 270;

fn time() -> Quantity {
    Quantity::new("time", "s")
}

/// What channel `c` measures, for the axis title.
pub fn quantity_name(c: usize) -> &'static str {
    ["load", "Fz bridge", "Mx bridge", "My bridge"][c]
}

fn series(t: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    t.iter().copied().zip(y.iter().copied()).collect()
}

fn minus(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(a, b)| a - b).collect()
}

fn heldout(p: &PlotData) -> Band {
    Band {
        from: p.heldout.0,
        to: p.heldout.1,
        colour: styles::HELDOUT,
        label: "held out (never fitted)".into(),
    }
}

/// What a figure calls its model: the single report's `improved` (baseline plus the effects
/// found), or a session's model of the recording.
pub const IMPROVED: &str = "improved";

/// The two panels of channel `c`: the recording (wide and light, under the models), the model
/// called `model` and, thin and on top, the baseline, so that each stays visible where they
/// agree; then the residuals of both. `x_range` zooms, `extra` adds bands (the evidence
/// window).
fn channel_panels(
    p: &PlotData,
    c: usize,
    x_range: Option<(f64, f64)>,
    extra: &[Band],
    model: &str,
) -> [Panel; 2] {
    let unit = channel_unit(CHANNELS[c]);
    let mut bands = extra.to_vec();
    bands.push(heldout(p));
    let thin = |s: figures::Style| figures::Style { width: 1, ..s };
    let mut top = Panel::new(time(), Quantity::new(quantity_name(c), unit));
    top.x_range = x_range;
    top.bands = bands.clone();
    top.lines = vec![
        Line::new(
            "recording",
            styles::RECORDING_UNDER,
            series(&p.t_s, &p.recorded[c]),
        ),
        Line::new(model, styles::IMPROVED, series(&p.t_s, &p.improved[c])),
        Line::new(
            "baseline",
            thin(styles::BASELINE),
            series(&p.t_s, &p.baseline[c]),
        ),
    ];
    let name = format!("{} residual", quantity_name(c));
    let mut bottom = Panel::new(time(), Quantity::new(&name, unit));
    bottom.x_range = x_range;
    bottom.bands = bands;
    bottom.zero_line = true;
    let before = minus(&p.recorded[c], &p.baseline[c]);
    let after = minus(&p.recorded[c], &p.improved[c]);
    bottom.lines = vec![
        Line::new(
            "residual, baseline",
            thin(styles::BASELINE),
            series(&p.t_s, &before),
        ),
        Line::new(
            &format!("residual, {model}"),
            thin(styles::IMPROVED),
            series(&p.t_s, &after),
        ),
    ];
    [top, bottom]
}

fn two_panels(panels: &[Panel; 2]) -> Result<String, Error> {
    svg_string((WIDTH, 2 * PANEL_H), |root| {
        let areas = root.split_evenly((2, 1));
        draw_panel(&areas[0], &panels[0])?;
        draw_panel(&areas[1], &panels[1])
    })
}

/// Channel `c` over the whole recording.
pub fn channel(p: &PlotData, c: usize) -> Result<String, Error> {
    two_panels(&channel_panels(p, c, None, &[], IMPROVED))
}

/// Channel `c` around `window` (s), the window shaded and named `what`.
pub fn zoom(p: &PlotData, c: usize, window: (f64, f64), what: &str) -> Result<String, Error> {
    let (a, b) = window;
    let len = b - a;
    let (t0, t1) = (p.t_s[0], *p.t_s.last().unwrap_or(&b));
    // Context before the window, and more after it: effects show in how the signal settles.
    let range = (
        (a - (0.25 * len).max(3.0)).max(t0),
        (b + (0.25 * len).max(10.0)).min(t1),
    );
    let band = Band {
        from: a,
        to: b,
        colour: styles::WINDOW,
        label: what.to_string(),
    };
    two_panels(&channel_panels(p, c, Some(range), &[band], IMPROVED))
}

/// The final residual of channel `c` (of the model `p.improved`, called `model`) with its
/// straight-line trend, `bands` shaded besides the held-out stretch.
pub fn remainder(
    p: &PlotData,
    c: usize,
    slope: f64,
    model: &str,
    bands: &[Band],
) -> Result<String, Error> {
    let unit = channel_unit(CHANNELS[c]);
    let after = minus(&p.recorded[c], &p.improved[c]);
    let n = after.len().max(1) as f64;
    let (tm, rm) = (p.t_s.iter().sum::<f64>() / n, after.iter().sum::<f64>() / n);
    let line: Vec<(f64, f64)> = p.t_s.iter().map(|&t| (t, rm + slope * (t - tm))).collect();
    let name = format!("{} residual", quantity_name(c));
    let mut panel = Panel::new(time(), Quantity::new(&name, unit));
    panel.zero_line = true;
    panel.bands = bands.to_vec();
    panel.bands.push(heldout(p));
    panel.lines = vec![
        Line::new(
            &format!("residual, {model}"),
            figures::Style {
                width: 1,
                ..styles::IMPROVED
            },
            series(&p.t_s, &after),
        ),
        Line::new("trend", styles::BASELINE, line),
    ];
    svg_string((WIDTH, PANEL_H), |root| draw_panel(root, &panel))
}

/// Heights of a channel's signal and residual panels in [`stacked`], legend strips included.
const STACKED_H: (u32, u32) = (250, 170);

/// Every compared channel of `p` in one figure, each as [`channel`] draws it with `model` for
/// the improved series' name (the session's page, per recording): the held-out stretch shaded
/// on the signals, `bands[c]` (where the models miss) on channel `c`'s residuals, so that each
/// panel's shading and legend stay few.
pub fn stacked(p: &PlotData, model: &str, bands: &[Vec<Band>; 4]) -> Result<String, Error> {
    let panels: Vec<Panel> = (0..4)
        .filter(|&c| p.used[c])
        .flat_map(|c| {
            let [mut top, mut bottom] = channel_panels(p, c, None, &[], model);
            top.bands = vec![heldout(p)];
            bottom.bands.clone_from(&bands[c]);
            // Right under its channel's panel: the short name fits the short panel.
            bottom.y.name = "residual".into();
            // The baseline's residual wider, under the model's: where they agree both show.
            bottom.lines[0].style.width = 3;
            [top, bottom]
        })
        .collect();
    let pairs = (panels.len() / 2).max(1) as u32;
    let (signal, residual) = STACKED_H;
    // Where each panel ends: signal, residual, signal, ...
    let breaks: Vec<i32> = (0..2 * pairs - 1)
        .scan(0, |y, i| {
            *y += if i % 2 == 0 { signal } else { residual };
            Some(*y as i32)
        })
        .collect();
    svg_string((WIDTH, pairs * (signal + residual)), |root| {
        let areas = root.split_by_breakpoints::<i32, i32, _, _>([], &breaks);
        for (area, panel) in areas.iter().zip(&panels) {
            draw_panel(area, panel)?;
        }
        Ok(())
    })
}

/// A discovered term (`curve`, on its channel) against what it depends on: the load, the rod's
/// travel or another output (`against`, a channel index, or `None` for the travel), as dots, one
/// per block of the fitting series; the held-out stretch's blocks in grey.
pub fn term_against(
    p: &PlotData,
    curve: &TermCurve,
    against: Option<usize>,
) -> Result<String, Error> {
    let (x, quantity) = match against {
        Some(c) => (
            &p.recorded[c],
            Quantity::new(quantity_name(c), channel_unit(CHANNELS[c])),
        ),
        None => (&p.rod_mm, Quantity::new("rod travel", "mm")),
    };
    let unit = channel_unit(CHANNELS[curve.channel]);
    let name = format!("term on {}", quantity_name(curve.channel));
    let mut panel = Panel::new(quantity, Quantity::new(&name, unit));
    panel.zero_line = true;
    let held = |t: f64| (p.heldout.0..=p.heldout.1).contains(&t);
    let points = |keep: bool| -> Vec<(f64, f64)> {
        p.t_s
            .iter()
            .zip(x.iter().zip(&curve.values))
            .filter(|(t, _)| held(**t) == keep)
            .map(|(_, (x, y))| (*x, *y))
            .collect()
    };
    let dots = |s: figures::Style| figures::Style { dots: true, ..s };
    panel.lines = vec![
        Line::new("fitted stretch", dots(styles::IMPROVED), points(false)),
        Line::new("held out", dots(styles::RECORDING), points(true)),
    ];
    svg_string((WIDTH, PANEL_H), |root| draw_panel(root, &panel))
}
