//! Plots of what a recording holds, each channel in its own unit: the sensor outputs (volts, or
//! the `sensor_unit` of a foreign sensor) against time, and against the reference load when the
//! recording has one; for a test of the material alone (a machine's export), the rod and the
//! load against time and the load against the rod. PNG and SVG. The axes, number format and legend are the `figures`
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

const SIZE: (u32, u32) = (1200, 900);

/// One channel to draw: its column, what its axis shows (name and unit) and the legend's name.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    pub column: &'static str,
    pub axis: Quantity,
    pub short: &'static str,
}

/// The sensor outputs the recording measured, each in its own unit: volts (`Fz bridge [V]`),
/// or the `sensor_unit` its metadata state for a foreign sensor (`Fz output [µT]`). A column
/// empty on every row was not measured and gets no panel.
pub fn outputs(rec: &Recording) -> Vec<Channel> {
    let given = rec
        .meta
        .get(recording::SENSOR_UNIT_KEY)
        .map_or("V", str::trim);
    // `uT` is how a keyboard writes µT.
    let unit = match given.strip_prefix('u') {
        Some(rest) if !rest.is_empty() => format!("µ{rest}"),
        _ if given.is_empty() => "V".to_string(),
        _ => given.to_string(),
    };
    let what = if unit == "V" { "bridge" } else { "output" };
    [("fz_V", "Fz"), ("mx_V", "Mx"), ("my_V", "My")]
        .into_iter()
        .filter(|(col, _)| measured(rec, col))
        .map(|(column, short)| Channel {
            column,
            axis: Quantity::new(&format!("{short} {what}"), &unit),
            short,
        })
        .collect()
}

fn measured(rec: &Recording, col: &str) -> bool {
    rec.column(col)
        .is_some_and(|v| v.iter().any(|x| x.is_finite()))
}

fn rod() -> Channel {
    Channel {
        column: "rod_mm",
        axis: Quantity::new("rod travel", "mm"),
        short: "rod",
    }
}

fn load() -> Channel {
    Channel {
        column: "load_N",
        axis: Quantity::new("reference load", "N"),
        short: "load",
    }
}

/// One panel per channel of `ys` against `x` (the figures crate's axes, as in the diagnosis
/// report); dots when `x` is not time, since a load sweep goes back and forth.
fn panels<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    rec: &Recording,
    x: &Channel,
    ys: &[Channel],
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let xs = rec.column(x.column).unwrap_or_default();
    let areas = root.split_evenly((ys.len().max(1), 1));
    for (i, (y, area)) in ys.iter().zip(areas.iter()).enumerate() {
        let values = rec.column(y.column).unwrap_or_default();
        let style = Style {
            colour: styles::CHANNELS[i % styles::CHANNELS.len()],
            width: 1,
            dots: x.column != "t_s",
        };
        let mut panel = Panel::new(x.axis.clone(), y.axis.clone());
        let points = xs.iter().zip(values).map(|(&a, &b)| (a, b)).collect();
        panel.lines.push(Line::new(y.short, style, points));
        draw_panel(area, &panel).map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())
}

fn draw_one(
    path: &Path,
    format: Format,
    rec: &Recording,
    (x, ys): (&Channel, &[Channel]),
) -> Result<(), PlotError> {
    register_font().map_err(|_| PlotError::NoFont)?;
    let res = match format {
        Format::Png => panels(
            &BitMapBackend::new(path, SIZE).into_drawing_area(),
            rec,
            x,
            ys,
        ),
        Format::Svg => panels(&SVGBackend::new(path, SIZE).into_drawing_area(), rec, x, ys),
    };
    res.map_err(|why| PlotError::Draw {
        path: path.to_path_buf(),
        why,
    })
}

/// The figures of what `rec` holds, each as (file suffix, x, ys): the sensor outputs against
/// time and, with reference loads, against the load; for a test of the material alone (no
/// output measured), the rod and the load against time and the load against the rod.
pub fn figures(rec: &Recording) -> Vec<(&'static str, Channel, Vec<Channel>)> {
    let time = Channel {
        column: "t_s",
        axis: Quantity::new("time", "s"),
        short: "time",
    };
    let outputs = outputs(rec);
    let (has_rod, has_load) = (measured(rec, "rod_mm"), measured(rec, "load_N"));
    let mut out = Vec::new();
    if outputs.is_empty() {
        let both: Vec<Channel> = [(has_rod, rod()), (has_load, load())]
            .into_iter()
            .filter_map(|(m, c)| m.then_some(c))
            .collect();
        out.push(("time", time, both));
        if has_rod && has_load {
            out.push(("load", rod(), vec![load()]));
        }
    } else {
        out.push(("time", time, outputs.clone()));
        if has_load {
            out.push(("load", load(), outputs));
        }
    }
    out
}

/// Draw `<prefix>-time.<ext>` and, when the recording has reference loads, `<prefix>-load.<ext>`
/// ([`figures`]); returns the files written.
pub fn plot(rec: &Recording, prefix: &Path, formats: &[Format]) -> Result<Vec<PathBuf>, PlotError> {
    let mut written = Vec::new();
    let stem = prefix
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    for &format in formats {
        let ext = if format == Format::Png { "png" } else { "svg" };
        for (suffix, x, ys) in figures(rec) {
            let path = prefix.with_file_name(format!("{stem}-{suffix}.{ext}"));
            draw_one(&path, format, rec, (&x, &ys))?;
            written.push(path);
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
    fn a_machine_test_is_drawn_as_rod_and_load_and_a_skin_in_its_own_unit() {
        let dir = std::env::temp_dir().join(format!("tactile-plot-m-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut machine = recording();
        let c = &mut machine.channels;
        for v in [&mut c.fz_v, &mut c.mx_v, &mut c.my_v] {
            v.iter_mut().for_each(|x| *x = f64::NAN);
        }
        let written = plot(&machine, &dir.join("m"), &[Format::Svg]).unwrap();
        assert_eq!(written.len(), 2, "time, and load against rod");
        let time = std::fs::read_to_string(&written[0]).unwrap();
        assert!(time.contains("rod travel [mm]") && time.contains("reference load [N]"));
        assert!(!time.contains("bridge"), "an empty sensor panel was drawn");
        let load = std::fs::read_to_string(&written[1]).unwrap();
        assert!(load.contains("rod travel [mm]") && load.contains("reference load [N]"));
        // A magnetic skin logged in µT, Fz only.
        let mut skin = recording();
        skin.meta.other.push(("sensor_unit".into(), "uT".into()));
        let c = &mut skin.channels;
        c.fz_v.iter_mut().for_each(|x| *x *= 1e6);
        for v in [&mut c.mx_v, &mut c.my_v] {
            v.iter_mut().for_each(|x| *x = f64::NAN);
        }
        let written = plot(&skin, &dir.join("s"), &[Format::Svg]).unwrap();
        let time = std::fs::read_to_string(&written[0]).unwrap();
        assert!(time.contains("Fz output [µT]"), "the skin's unit");
        assert!(!time.contains("Mx") && !time.contains("[kV]") && !time.contains("kµT"));
        std::fs::remove_dir_all(&dir).unwrap();
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
