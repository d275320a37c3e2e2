//! `tactile config`: change rate, filter, calibration, drift tracking; run the auto-null.

use host::logger::FileError;
use std::path::PathBuf;
use sysexit::ResultExt as _;

use protocol::FilterConfig;

use super::common::{finite, print_info, PortArg};

/// Change a sensor's configuration; every change is acknowledged by the device (or refused
/// with its reason) and the resulting info frame is printed.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub port: PortArg,
    /// Sample rate in Hz (one of the ADC's rates).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=64_000))]
    pub rate: Option<u32>,
    /// Recursive smoother weight alpha in (0, 1]; 1 turns it off.
    #[arg(long, value_parser = alpha)]
    pub smoother_alpha: Option<f64>,
    /// Butterworth low-pass order: 0 (off), 2 or 4.
    #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(["0", "2", "4"]))]
    pub butterworth_order: Option<String>,
    /// Butterworth cutoff in Hz (below 0.45 × rate).
    #[arg(long, value_parser = finite)]
    pub cutoff_hz: Option<f64>,
    /// Calibration matrix: a file of 3 lines of 3 numbers (V -> N, N·m), row-major.
    #[arg(long, value_name = "FILE")]
    pub calibration: Option<PathBuf>,
    /// Slow drift tracking on or off.
    #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(["on", "off"]))]
    pub drift_tracking: Option<String>,
    /// Run the trim-DAC offset search.
    #[arg(long)]
    pub auto_null: bool,
}

fn alpha(s: &str) -> Result<f64, String> {
    let v = finite(s)?;
    if v > 0.0 && v <= 1.0 {
        Ok(v)
    } else {
        Err(format!("{s} is outside (0, 1]"))
    }
}

/// Read a 3×3 matrix file; errors name the line.
pub fn read_matrix(path: &std::path::Path) -> Result<[[f32; 3]; 3], FileError> {
    let text = std::fs::read_to_string(path).map_err(|e| FileError::Open {
        path: path.into(),
        source: e,
    })?;
    let rows: Vec<(usize, &str)> = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
        .collect();
    let bad = |line, why: String| FileError::Malformed {
        path: path.into(),
        line,
        field: "calibration".into(),
        why,
    };
    if rows.len() != 3 {
        return Err(bad(
            rows.last().map_or(1, |r| r.0),
            format!("{} rows, expected 3", rows.len()),
        ));
    }
    let mut m = [[0f32; 3]; 3];
    for (r, (line, l)) in rows.iter().enumerate() {
        let vals: Vec<&str> = l
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .collect();
        if vals.len() != 3 {
            return Err(bad(*line, format!("{} numbers, expected 3", vals.len())));
        }
        for (c, v) in vals.iter().enumerate() {
            m[r][c] = v
                .parse::<f32>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| bad(*line, format!("not a number: {v:?}")))?;
        }
    }
    Ok(m)
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let calibration = args
        .calibration
        .as_deref()
        .map(read_matrix)
        .transpose()
        .coded()?;
    let dev = args.port.open()?;
    let info = dev.get_info().coded()?;
    if let Some(hz) = args.rate {
        dev.set_rate(hz).coded()?;
    }
    if args.smoother_alpha.is_some() || args.butterworth_order.is_some() || args.cutoff_hz.is_some()
    {
        let f = info.filter;
        let order = args
            .butterworth_order
            .as_deref()
            .map_or(f.butterworth_order, |o| o.parse().unwrap_or(0));
        dev.set_filter(FilterConfig {
            smoother_alpha: args.smoother_alpha.map_or(f.smoother_alpha, |a| a as f32),
            butterworth_order: order,
            cutoff_hz: args.cutoff_hz.map_or(f.cutoff_hz, |c| c as f32),
        })?;
    }
    if let Some(m) = calibration {
        dev.set_calibration(m).coded()?;
    }
    if let Some(d) = args.drift_tracking.as_deref() {
        dev.set_drift_tracking(d == "on").coded()?;
    }
    if args.auto_null {
        dev.auto_null().coded()?;
    }
    print_info(&dev.port().display().to_string(), &dev.get_info().coded()?);
    Ok(())
}
