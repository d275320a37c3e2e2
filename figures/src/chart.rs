//! One line chart: titled axes with SI-scaled units and round ticks, shaded bands, lines, and a
//! legend in its own strip above the data so that it never hides a curve.

use std::ops::Range;

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::number::{si_scale, Scale};
use crate::{register_font, Error, Ticks};

/// Most points drawn per line; longer series are thinned by a stride.
pub const MAX_POINTS: usize = 20_000;
/// Height of the legend strip above the plotting area, px.
const LEGEND_H: u32 = 26;
/// Width of the tick-label area left of the y axis, px.
const Y_LABELS_W: u32 = 72;
// plotters writes SVG font sizes at 0.8 of these: 13 and 14 px on the page.
const FONT: (&str, u32) = ("sans-serif", 16);
const TITLE_FONT: (&str, u32) = ("sans-serif", 17);

/// What an axis shows: a name and its SI unit (`"V"`, `"N"`, `"s"`; `""` when dimensionless).
/// The axis title is `name [unit]` with the unit's prefix chosen for the data.
#[derive(Debug, Clone, PartialEq)]
pub struct Quantity {
    pub name: String,
    pub unit: String,
}

impl Quantity {
    pub fn new(name: &str, unit: &str) -> Quantity {
        Quantity {
            name: name.to_string(),
            unit: unit.to_string(),
        }
    }
}

/// How a series is drawn: a line of `width` px, or dots when `dots`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Style {
    pub colour: RGBColor,
    pub width: u32,
    pub dots: bool,
}

/// The house styles, so that "recording" or "baseline" look the same in every figure.
pub mod styles {
    use super::Style;
    use plotters::style::RGBColor;

    /// Measured data: thin grey, under the models.
    pub const RECORDING: Style = Style {
        colour: RGBColor(120, 120, 120),
        width: 1,
        dots: false,
    };
    /// Measured data under model lines: a wide, light band that a thinner model line drawn
    /// over it leaves visible on both sides, so that where they agree both are still seen.
    pub const RECORDING_UNDER: Style = Style {
        colour: RGBColor(196, 196, 196),
        width: 7,
        dots: false,
    };
    /// The calibrated baseline model.
    pub const BASELINE: Style = Style {
        colour: RGBColor(214, 39, 40),
        width: 2,
        dots: false,
    };
    /// The improved model (baseline plus the effects found).
    pub const IMPROVED: Style = Style {
        colour: RGBColor(31, 119, 180),
        width: 2,
        dots: false,
    };
    /// Shading of a stretch the fit never saw (held-out).
    pub const HELDOUT: RGBColor = RGBColor(150, 150, 150);
    /// Shading of the window where an effect shows.
    pub const WINDOW: RGBColor = RGBColor(255, 160, 0);
    /// Distinct colours for channels plotted side by side (Fz, Mx, My, load).
    pub const CHANNELS: [RGBColor; 4] = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(148, 103, 189),
    ];
}

/// A named series of `(x, y)` points in the quantities' base units; a non-finite value breaks
/// the line instead of being bridged.
#[derive(Debug, Clone)]
pub struct Line {
    pub label: String,
    pub style: Style,
    pub points: Vec<(f64, f64)>,
}

impl Line {
    pub fn new(label: &str, style: Style, points: Vec<(f64, f64)>) -> Line {
        Line {
            label: label.to_string(),
            style,
            points,
        }
    }
}

/// A shaded stretch of the x axis (`from..to` in the x quantity's base unit), named in the
/// legend.
#[derive(Debug, Clone)]
pub struct Band {
    pub from: f64,
    pub to: f64,
    pub colour: RGBColor,
    pub label: String,
}

/// One chart. `x_range` (base units) zooms in; by default the lines' extent is shown.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Shown at the left of the legend strip; may be empty.
    pub title: String,
    pub x: Quantity,
    pub y: Quantity,
    pub x_range: Option<(f64, f64)>,
    pub lines: Vec<Line>,
    pub bands: Vec<Band>,
    /// Draw y = 0 (residuals).
    pub zero_line: bool,
}

impl Panel {
    pub fn new(x: Quantity, y: Quantity) -> Panel {
        Panel {
            title: String::new(),
            x,
            y,
            x_range: None,
            lines: Vec::new(),
            bands: Vec::new(),
            zero_line: false,
        }
    }

    /// The x extent: `x_range`, else the finite x of every line.
    fn x_extent(&self) -> (f64, f64) {
        self.x_range
            .unwrap_or_else(|| extent(self.lines.iter().flat_map(|l| l.points.iter().map(|p| p.0))))
    }

    /// The y extent of the points inside `x0..=x1`, 4 % padded; zero included for residuals.
    fn y_extent(&self, (x0, x1): (f64, f64)) -> (f64, f64) {
        let ys = self
            .lines
            .iter()
            .flat_map(|l| l.points.iter())
            .filter(|p| p.0 >= x0 && p.0 <= x1)
            .map(|p| p.1)
            .chain(self.zero_line.then_some(0.0));
        let (lo, hi) = extent(ys);
        let pad = 0.04 * (hi - lo);
        (lo - pad, hi + pad)
    }
}

/// Smallest and largest finite value, or (NaN, NaN) when there is none.
fn extent(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if lo.is_finite() {
        (lo, hi)
    } else {
        (f64::NAN, f64::NAN)
    }
}

/// Split `points` into runs without non-finite values, thinned to at most `max_points` in all.
pub fn segments(points: &[(f64, f64)], max_points: usize) -> Vec<Vec<(f64, f64)>> {
    let stride = points.len().div_ceil(max_points.max(1)).max(1);
    let mut out = vec![Vec::new()];
    for &(x, y) in points.iter().step_by(stride) {
        if x.is_finite() && y.is_finite() {
            if let Some(last) = out.last_mut() {
                last.push((x, y));
            }
        } else if out.last().is_some_and(|s| !s.is_empty()) {
            out.push(Vec::new());
        }
    }
    out.retain(|s| !s.is_empty());
    out
}

fn draw_err(e: impl std::fmt::Display) -> Error {
    Error::Draw(e.to_string())
}

/// Draw `panel` filling `area`: legend strip on top, then the chart.
pub fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
) -> Result<(), Error> {
    let (sx, sy, xt, yt) = axes(panel, area.dim_in_pixel());
    let (top, body) = area.split_vertically(LEGEND_H);
    let mut chart = ChartBuilder::on(&body)
        .margin_left(10)
        .margin_right(18)
        .margin_top(6)
        .x_label_area_size(44)
        .y_label_area_size(Y_LABELS_W)
        .build_cartesian_2d(TickAxis::new(&xt), TickAxis::new(&yt))
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .x_desc(sx.title(&panel.x.name))
        .y_desc(sy.title(&panel.y.name))
        .x_label_formatter(&|v| xt.label(*v))
        .y_label_formatter(&|v| yt.label(*v))
        .bold_line_style(RGBColor(228, 228, 228))
        .light_line_style(TRANSPARENT)
        .label_style(FONT)
        .axis_desc_style(TITLE_FONT)
        .draw()
        .map_err(draw_err)?;
    // A band outside the shown range would be a legend entry for nothing.
    let shown = |b: &&Band| b.to * sx.factor > xt.lo && b.from * sx.factor < xt.hi;
    let bands: Vec<&Band> = panel.bands.iter().filter(shown).collect();
    for b in &bands {
        let (a, z) = (
            (b.from * sx.factor).max(xt.lo),
            (b.to * sx.factor).min(xt.hi),
        );
        let fill = b.colour.mix(0.18).filled();
        chart
            .draw_series([Rectangle::new([(a, yt.lo), (z, yt.hi)], fill)])
            .map_err(draw_err)?;
    }
    if panel.zero_line && yt.lo < 0.0 && yt.hi > 0.0 {
        let axis = BLACK.mix(0.5).stroke_width(1);
        chart
            .draw_series(LineSeries::new([(xt.lo, 0.0), (xt.hi, 0.0)], axis))
            .map_err(draw_err)?;
    }
    for line in &panel.lines {
        draw_line(&mut chart, line, (&sx, &sy), (xt.lo, xt.hi))?;
    }
    legend(&top, panel, &bands)
}

/// Units and ticks of both axes for a panel of `(w, h)` pixels: about one x tick per 110 px
/// and one y tick per 50 px.
fn axes(panel: &Panel, (w, h): (u32, u32)) -> (Scale, Scale, Ticks, Ticks) {
    let (x0, x1) = panel.x_extent();
    let (y0, y1) = panel.y_extent((x0, x1));
    let sx = si_scale(x0.abs().max(x1.abs()), &panel.x.unit);
    let sy = si_scale(y0.abs().max(y1.abs()), &panel.y.unit);
    let x_ticks = (w / 110).max(3) as usize;
    let xt = Ticks::new(x0 * sx.factor, x1 * sx.factor, x_ticks, false);
    let yt = Ticks::new(
        y0 * sy.factor,
        y1 * sy.factor,
        (h / 50).max(3) as usize,
        true,
    );
    (sx, sy, xt, yt)
}

/// A linear axis whose grid lines and labels sit exactly on [`Ticks::values`] (plotters' own
/// choice of key points would not match the decimals of our labels).
struct TickAxis {
    inner: RangedCoordf64,
    ticks: Vec<f64>,
}

impl TickAxis {
    fn new(t: &Ticks) -> TickAxis {
        TickAxis {
            inner: (t.lo..t.hi).into(),
            ticks: t.values(),
        }
    }
}

impl Ranged for TickAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        // Grid lines only at the labelled ticks: no unlabelled light lines.
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.ticks.clone()
        }
    }

    fn range(&self) -> Range<f64> {
        self.inner.range()
    }
}

type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<TickAxis, TickAxis>>;

/// One series, scaled to the axes' units and clipped to the shown x range.
fn draw_line<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    line: &Line,
    (sx, sy): (&Scale, &Scale),
    (lo, hi): (f64, f64),
) -> Result<(), Error> {
    let scaled: Vec<(f64, f64)> = line
        .points
        .iter()
        .map(|&(x, y)| (x * sx.factor, y * sy.factor))
        .filter(|p| p.0 >= lo && p.0 <= hi)
        .collect();
    let s = line.style;
    for seg in segments(&scaled, MAX_POINTS) {
        if s.dots {
            let dots = seg
                .into_iter()
                .map(|p| Circle::new(p, 1, s.colour.filled()));
            chart.draw_series(dots).map_err(draw_err)?;
        } else {
            let stroke = s.colour.stroke_width(s.width);
            chart
                .draw_series(LineSeries::new(seg, stroke))
                .map_err(draw_err)?;
        }
    }
    Ok(())
}

/// The title, then one swatch and label per band and line, left to right in the strip. A band
/// without a label, or with one an earlier band has, is shaded but not named again.
fn legend<DB: DrawingBackend>(
    top: &DrawingArea<DB, Shift>,
    panel: &Panel,
    bands: &[&Band],
) -> Result<(), Error> {
    let font: TextStyle = FONT.into();
    let width = |s: &str| {
        top.estimate_text_size(s, &font)
            .map_or(7 * s.chars().count() as i32, |(w, _)| w as i32)
    };
    let mid = LEGEND_H as i32 / 2 + 2;
    let text = |s: &str, x: i32| {
        Text::new(
            s.to_string(),
            (x, mid),
            FONT.into_font()
                .color(&BLACK)
                .pos(plotters::style::text_anchor::Pos::new(
                    plotters::style::text_anchor::HPos::Left,
                    plotters::style::text_anchor::VPos::Center,
                )),
        )
    };
    let mut x = 10;
    if !panel.title.is_empty() {
        top.draw(&text(&panel.title, x)).map_err(draw_err)?;
        x += width(&panel.title) + 24;
    }
    for (i, b) in bands.iter().enumerate() {
        if b.label.is_empty() || bands[..i].iter().any(|o| o.label == b.label) {
            continue;
        }
        let swatch = Rectangle::new(
            [(x, mid - 6), (x + 22, mid + 6)],
            b.colour.mix(0.3).filled(),
        );
        top.draw(&swatch).map_err(draw_err)?;
        top.draw(&text(&b.label, x + 28)).map_err(draw_err)?;
        x += 28 + width(&b.label) + 18;
    }
    for l in &panel.lines {
        let stroke = l.style.colour.stroke_width(l.style.width.max(2));
        let swatch = PathElement::new(vec![(x, mid), (x + 22, mid)], stroke);
        top.draw(&swatch).map_err(draw_err)?;
        top.draw(&text(&l.label, x + 28)).map_err(draw_err)?;
        x += 28 + width(&l.label) + 18;
    }
    Ok(())
}

/// `draw` on a white `size` canvas, returned as an SVG document (for inlining into HTML: it
/// carries its own `viewBox`, so CSS may scale it).
pub fn svg_string<F>(size: (u32, u32), draw: F) -> Result<String, Error>
where
    F: FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), Error>,
{
    register_font()?;
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, size).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        draw(&root)?;
        root.present().map_err(draw_err)?;
    }
    Ok(buf)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaps_split_the_line_and_long_series_are_thinned() {
        let p = [
            (0.0, 1.0),
            (1.0, 2.0),
            (f64::NAN, 3.0),
            (3.0, f64::NAN),
            (4.0, 5.0),
        ];
        assert_eq!(
            segments(&p, 100),
            vec![vec![(0.0, 1.0), (1.0, 2.0)], vec![(4.0, 5.0)]]
        );
        let long: Vec<(f64, f64)> = (0..100_000).map(|i| (f64::from(i), 0.0)).collect();
        assert!(segments(&long, MAX_POINTS)[0].len() <= MAX_POINTS);
    }

    #[test]
    fn a_panel_has_titled_axes_round_ticks_and_its_legend() {
        let svg = svg_string((700, 260), |area| {
            let mut p = Panel::new(Quantity::new("time", "s"), Quantity::new("Fz bridge", "V"));
            p.title = "Fz".into();
            let pts = (0..=180).map(|i| (f64::from(i), -0.013 + 0.0003 * f64::from(i)));
            p.lines
                .push(Line::new("recording", styles::RECORDING, pts.collect()));
            p.bands.push(Band {
                from: 90.0,
                to: 180.0,
                colour: styles::HELDOUT,
                label: "held out".into(),
            });
            draw_panel(area, &p)
        })
        .unwrap();
        let texts: Vec<&str> = svg
            .split("<text")
            .skip(1)
            .filter_map(|t| Some(t.split('>').nth(1)?.split('<').next()?.trim()))
            .collect();
        for needle in ["time [s]", "Fz bridge [mV]", "held out", "recording", "150"] {
            assert!(texts.contains(&needle), "{needle} missing from {texts:?}");
        }
        assert!(
            texts.contains(&"\u{2212}20"),
            "negative mV ticks with a minus sign"
        );
        let exponent = |t: &&str| t.contains(|c: char| c.is_ascii_digit()) && t.contains('e');
        assert!(!texts.iter().any(exponent), "exponent form in {texts:?}");
    }

    #[test]
    fn a_band_label_is_named_once_in_the_legend() {
        let svg = svg_string((700, 260), |area| {
            let mut p = Panel::new(Quantity::new("time", "s"), Quantity::new("residual", "V"));
            let pts = (0..=100).map(|i| (f64::from(i), 0.0));
            p.lines
                .push(Line::new("residual", styles::IMPROVED, pts.collect()));
            let band = |from: f64, label: &str| Band {
                from,
                to: from + 10.0,
                colour: styles::WINDOW,
                label: label.into(),
            };
            p.bands = vec![band(10.0, "misses"), band(50.0, "misses"), band(80.0, "")];
            draw_panel(area, &p)
        })
        .unwrap();
        assert_eq!(
            svg.matches(">misses<").count() + svg.matches(">\nmisses\n<").count(),
            1
        );
        // All three shaded, two swatches (the line's and the named band's) in the strip.
        let shaded = svg.matches("opacity=\"0.18\"").count();
        assert_eq!(shaded, 3, "{svg}");
        assert_eq!(svg.matches("opacity=\"0.3\"").count(), 1);
    }
}
