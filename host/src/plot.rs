//! Plots of a recording (plotters): the bridge outputs against time, and against the reference
//! load when the recording has one; PNG and SVG. Gaps (missing values) break the lines instead
//! of being bridged.

use std::ops::Range;
use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use recording::Recording;

/// Output formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Png,
    Svg,
}

/// Why a plot could not be drawn.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlotError {
    /// The drawing backend failed (file not writable, font missing).
    #[error("{}: {why}", .path.display())]
    Draw { path: PathBuf, why: String },
    /// PNG text needs a TrueType font and none was found.
    #[error("no TrueType font found for PNG labels (set TACTILE_FONT to a .ttf file, or use --format svg)")]
    NoFont,
}

const CHANNELS: [(&str, &str); 3] = [
    ("fz_V", "Fz bridge [V]"),
    ("mx_V", "Mx bridge [V]"),
    ("my_V", "My bridge [V]"),
];
const SIZE: (u32, u32) = (1200, 900);
/// Most points drawn per line; longer series are thinned by a stride.
const MAX_POINTS: usize = 20_000;

/// Make plotters' `sans-serif` resolve to a system TrueType font (PNG only; SVG leaves text to
/// the viewer).
fn register_font() -> Result<(), PlotError> {
    static DONE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *DONE.get_or_init(|| {
        let mut candidates: Vec<PathBuf> = std::env::var_os("TACTILE_FONT")
            .map(PathBuf::from)
            .into_iter()
            .collect();
        candidates.extend(
            [
                "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
                "/usr/share/fonts/TTF/DejaVuSans.ttf",
                "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
                "/System/Library/Fonts/Supplemental/Arial.ttf",
            ]
            .map(PathBuf::from),
        );
        candidates
            .iter()
            .find_map(|p| std::fs::read(p).ok())
            .is_some_and(|bytes| {
                let leaked: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                plotters::style::register_font("sans-serif", FontStyle::Normal, leaked).is_ok()
            })
    });
    if ok {
        Ok(())
    } else {
        Err(PlotError::NoFont)
    }
}

/// Split `(x, y)` into runs without missing values, thinned to at most [`MAX_POINTS`].
fn segments(x: &[f64], y: &[f64]) -> Vec<Vec<(f64, f64)>> {
    let stride = (x.len() / MAX_POINTS).max(1);
    let mut out = vec![Vec::new()];
    for i in (0..x.len().min(y.len())).step_by(stride) {
        if x[i].is_finite() && y[i].is_finite() {
            if let Some(last) = out.last_mut() {
                last.push((x[i], y[i]));
            }
        } else if out.last().is_some_and(|s| !s.is_empty()) {
            out.push(Vec::new());
        }
    }
    out.retain(|s| !s.is_empty());
    out
}

fn range(v: impl Iterator<Item = f64>) -> Range<f64> {
    let (lo, hi) = v
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return 0.0..1.0;
    }
    let pad = ((hi - lo) * 0.05).max(1e-9);
    (lo - pad)..(hi + pad)
}

fn panels<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    rec: &Recording,
    x_col: &str,
    x_desc: &str,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let x = rec.column(x_col).unwrap_or_default();
    let areas = root.split_evenly((3, 1));
    let colors = [BLUE, RED, GREEN];
    for ((col, desc), (area, color)) in CHANNELS.iter().zip(areas.iter().zip(colors)) {
        let y = rec.column(col).unwrap_or_default();
        let mut chart = ChartBuilder::on(area)
            .margin(8)
            .x_label_area_size(35)
            .y_label_area_size(80)
            .build_cartesian_2d(range(x.iter().copied()), range(y.iter().copied()))
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc(*desc)
            .draw()
            .map_err(|e| e.to_string())?;
        for seg in segments(x, y) {
            if x_col == "t_s" {
                chart
                    .draw_series(LineSeries::new(seg, &color))
                    .map_err(|e| e.to_string())?;
            } else {
                chart
                    .draw_series(seg.into_iter().map(|p| Circle::new(p, 1, color.filled())))
                    .map_err(|e| e.to_string())?;
            }
        }
    }
    root.present().map_err(|e| e.to_string())
}

fn draw_one(
    path: &Path,
    format: Format,
    rec: &Recording,
    x_col: &str,
    x_desc: &str,
) -> Result<(), PlotError> {
    let res = match format {
        Format::Png => {
            register_font()?;
            panels(
                &BitMapBackend::new(path, SIZE).into_drawing_area(),
                rec,
                x_col,
                x_desc,
            )
        }
        Format::Svg => panels(
            &SVGBackend::new(path, SIZE).into_drawing_area(),
            rec,
            x_col,
            x_desc,
        ),
    };
    res.map_err(|why| PlotError::Draw {
        path: path.to_path_buf(),
        why,
    })
}

/// Draw `<prefix>-time.<ext>` and, when the recording has reference loads, `<prefix>-load.<ext>`;
/// returns the files written.
pub fn plot(rec: &Recording, prefix: &Path, formats: &[Format]) -> Result<Vec<PathBuf>, PlotError> {
    let has_load = rec.channels.load_n.iter().any(|x| x.is_finite());
    let mut written = Vec::new();
    for &format in formats {
        let ext = if format == Format::Png { "png" } else { "svg" };
        let stem = prefix
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let time = prefix.with_file_name(format!("{stem}-time.{ext}"));
        draw_one(&time, format, rec, "t_s", "t [s]")?;
        written.push(time);
        if has_load {
            let load = prefix.with_file_name(format!("{stem}-load.{ext}"));
            draw_one(&load, format, rec, "load_N", "reference load [N]")?;
            written.push(load);
        }
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaps_split_the_line_and_thin_long_series() {
        let x = [0.0, 1.0, f64::NAN, 3.0, 4.0];
        let y = [1.0, 2.0, 3.0, f64::NAN, 5.0];
        assert_eq!(
            segments(&x, &y),
            vec![vec![(0.0, 1.0), (1.0, 2.0)], vec![(4.0, 5.0)]]
        );
        let long: Vec<f64> = (0..100_000).map(f64::from).collect();
        assert!(segments(&long, &long)[0].len() <= MAX_POINTS);
    }
}
