//! The session's plot of one parameter across the recordings (plotters, SVG into a string for
//! inline use). One entry point, [`parameter_svg`], so that it can later share its axes code with
//! the single-recording report.

use plotters::prelude::*;

/// A parameter's value and its standard error where there is one.
pub type Point = (f64, Option<f64>);

const SIZE: (u32, u32) = (900, 260);

/// An inline `<svg>` of `points[i]` against recording `i` (x ticks named by `labels[i]`), value
/// ± standard error as an error bar; a recording without the parameter has no point.
pub fn parameter_svg(
    labels: &[String],
    points: &[Option<Point>],
    y_title: &str,
) -> Result<String, String> {
    let mut svg = String::new();
    draw(&mut svg, labels, points, y_title).map_err(|e| e.to_string())?;
    Ok(svg)
}

type DrawResult = Result<(), Box<dyn std::error::Error>>;

fn draw(
    svg: &mut String,
    labels: &[String],
    points: &[Option<Point>],
    y_title: &str,
) -> DrawResult {
    let root = SVGBackend::with_string(svg, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let n = labels.len() as i32;
    let shown: Vec<(i32, f64, f64, f64)> = points
        .iter()
        .enumerate()
        .filter_map(|(i, p)| {
            let (v, se) = (*p)?;
            let se = se.filter(|s| s.is_finite()).unwrap_or(0.0);
            v.is_finite().then_some((i as i32, v, v - se, v + se))
        })
        .collect();
    let mut chart = ChartBuilder::on(&root)
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(90)
        .build_cartesian_2d(-1..n, y_range(&shown))?;
    let name = |x: &i32| {
        usize::try_from(*x)
            .ok()
            .and_then(|i| labels.get(i))
            .cloned()
            .unwrap_or_default()
    };
    chart
        .configure_mesh()
        .x_labels(labels.len() + 2)
        .x_label_formatter(&name)
        .x_desc("recording")
        .y_desc(y_title)
        .draw()?;
    let color = BLUE;
    chart.draw_series(LineSeries::new(
        shown.iter().map(|&(i, v, _, _)| (i, v)),
        color.mix(0.4),
    ))?;
    chart.draw_series(
        shown
            .iter()
            .map(|&(i, v, lo, hi)| ErrorBar::new_vertical(i, lo, v, hi, color.filled(), 8)),
    )?;
    chart.draw_series(
        shown
            .iter()
            .map(|&(i, v, _, _)| Circle::new((i, v), 3, color.filled())),
    )?;
    root.present()?;
    Ok(())
}

/// The value range with error bars, padded; a flat or empty series gets a visible span.
fn y_range(shown: &[(i32, f64, f64, f64)]) -> std::ops::Range<f64> {
    let lo = shown.iter().map(|p| p.2).fold(f64::INFINITY, f64::min);
    let hi = shown.iter().map(|p| p.3).fold(f64::NEG_INFINITY, f64::max);
    if !lo.is_finite() || !hi.is_finite() {
        return 0.0..1.0;
    }
    let pad = ((hi - lo) * 0.1)
        .max(hi.abs().max(lo.abs()) * 0.05)
        .max(1e-12);
    (lo - pad)..(hi + pad)
}
