//! Plots of a recording: the bridge outputs against time, and against the reference load when
//! the recording has one; PNG and SVG. The axes, number format and legend are the `figures`
//! crate's, shared with the diagnosis report. Gaps (missing values) break the lines instead of
//! being bridged.

use std::path::{Path, PathBuf};

use figures::{draw_panel, register_font, styles, Line, Panel, Quantity, Style};
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
    /// Labels are laid out with a TrueType font and none was found.
    #[error("no TrueType font found for the labels (set TACTILE_FONT to a .ttf file)")]
    NoFont,
}

/// Column, what the axis shows, its unit and the legend's name.
const CHANNELS: [(&str, &str, &str, &str); 3] = [
    ("fz_V", "Fz bridge", "V", "Fz"),
    ("mx_V", "Mx bridge", "V", "Mx"),
    ("my_V", "My bridge", "V", "My"),
];
const SIZE: (u32, u32) = (1200, 900);

/// One panel per bridge output against `x` (the figures crate's axes, as in the diagnosis
/// report); dots when `x` is not time, since a load sweep goes back and forth.
fn panels<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    rec: &Recording,
    x_col: &str,
    x: &Quantity,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let xs = rec.column(x_col).unwrap_or_default();
    let areas = root.split_evenly((3, 1));
    for (i, ((col, name, unit, short), area)) in CHANNELS.iter().zip(areas.iter()).enumerate() {
        let ys = rec.column(col).unwrap_or_default();
        let style = Style {
            colour: styles::CHANNELS[i],
            width: 1,
            dots: x_col != "t_s",
        };
        let mut panel = Panel::new(x.clone(), Quantity::new(name, unit));
        let points = xs.iter().zip(ys).map(|(&a, &b)| (a, b)).collect();
        panel.lines.push(Line::new(short, style, points));
        draw_panel(area, &panel).map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())
}

fn draw_one(
    path: &Path,
    format: Format,
    rec: &Recording,
    x_col: &str,
    x: &Quantity,
) -> Result<(), PlotError> {
    register_font().map_err(|_| PlotError::NoFont)?;
    let res = match format {
        Format::Png => panels(
            &BitMapBackend::new(path, SIZE).into_drawing_area(),
            rec,
            x_col,
            x,
        ),
        Format::Svg => panels(
            &SVGBackend::new(path, SIZE).into_drawing_area(),
            rec,
            x_col,
            x,
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
        draw_one(&time, format, rec, "t_s", &Quantity::new("time", "s"))?;
        written.push(time);
        if has_load {
            let load = prefix.with_file_name(format!("{stem}-load.{ext}"));
            let load_axis = Quantity::new("reference load", "N");
            draw_one(&load, format, rec, "load_N", &load_axis)?;
            written.push(load);
        }
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn recording() -> Recording {
        let mut rec = Recording::new(recording::Meta {
            sample_rate_hz: 100.0,
            contact_angle_deg: 20.0,
            azimuth_deg: 60.0,
            fingertip_radius_mm: 20.0,
            gain_fz: 100.0,
            gain_mx: 100.0,
            gain_my: 100.0,
            excitation_v: 3.3,
            rod_speed_mm_per_min: None,
            source: None,
            other: Vec::new(),
        });
        let c = &mut rec.channels;
        for k in 0..500 {
            let t = f64::from(k) * 0.01;
            c.t_s.push(t);
            c.rod_mm.push(t);
            c.load_n.push(if k == 250 { f64::NAN } else { 10.0 * t });
            c.fz_v.push(0.004 * t);
            c.mx_v.push(-0.002 * t);
            c.my_v.push(0.5 + 0.1 * t);
        }
        rec
    }

    #[test]
    fn svg_plots_carry_the_shared_axes() {
        let dir = std::env::temp_dir().join(format!("tactile-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let written = plot(&recording(), &dir.join("r"), &[Format::Svg]).unwrap();
        assert_eq!(written.len(), 2, "time and load plots");
        let time = std::fs::read_to_string(&written[0]).unwrap();
        // Small voltages in mV, larger in V, a titled time axis, no exponent form, a legend per panel.
        for needle in [
            "time [s]",
            "Fz bridge [mV]",
            "Mx bridge [mV]",
            "My bridge [V]",
            ">\nFz\n<",
        ] {
            assert!(time.contains(needle), "{needle} missing");
        }
        let load = std::fs::read_to_string(&written[1]).unwrap();
        assert!(load.contains("reference load [N]"));
        assert!(load.contains("<circle"), "a load sweep is drawn as dots");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
