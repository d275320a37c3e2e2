//! `tactile replay`: re-decode a capture to the recording CSV.

use std::path::PathBuf;

use anyhow::Context;
use sysexit::ResultExt as _;

use super::common::finite;
use host::logger::reference::{merge_file, Align};
use host::logger::replay::replay;
use host::logger::Setup;

/// Re-decode an MCAP file written by `tactile log` (also one whose logger was killed: its
/// complete chunks are recovered) or a raw byte capture of the serial line, through the same
/// decoder as live logging, into the recording CSV. Writes to stdout unless --out is given.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The capture: .mcap, or raw serial bytes (e.g. saved with `cat /dev/ttyACM0 > x.bin`).
    pub input: PathBuf,
    /// Output CSV (default: stdout).
    #[arg(long, short = 'o')]
    pub out: Option<PathBuf>,
    /// With several sensors in one MCAP: the one whose topic contains this text.
    #[arg(long)]
    pub sensor: Option<String>,
    /// Contact angle theta_p in degrees (default: hardware/fingertip.toml).
    #[arg(long, value_parser = finite)]
    pub contact_angle_deg: Option<f64>,
    /// Azimuth phi in degrees (default: hardware/fingertip.toml).
    #[arg(long, value_parser = finite)]
    pub azimuth_deg: Option<f64>,
    /// A test machine's export to merge into rod_mm and load_N (needs --out).
    #[arg(long, requires = "out")]
    pub reference: Option<PathBuf>,
    /// Align the reference by cross-correlation within this many seconds (default: timestamps).
    #[arg(long, value_parser = finite)]
    pub xcorr_max_lag_s: Option<f64>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let mut setup = Setup::from_hardware(format!("tactile replay {}", args.input.display()))
        .coded()
        .context("hardware parameters")?;
    if let Some(a) = args.contact_angle_deg {
        setup.contact_angle_deg = a;
    }
    if let Some(a) = args.azimuth_deg {
        setup.azimuth_deg = a;
    }
    let s = replay(
        &args.input,
        args.out.as_deref(),
        &setup,
        args.sensor.as_deref(),
    )
    .coded()?;
    eprintln!(
        "{}: {} frames, {} rows, {} gaps, {} CRC errors, {} malformed, {} overflows{}",
        args.input.display(),
        s.frames,
        s.rows,
        s.gaps,
        s.crc_errors,
        s.malformed,
        s.overflows,
        s.truncated
            .map(|t| format!("; file ends early (writer killed?): {t}"))
            .unwrap_or_default()
    );
    if let (Some(reference), Some(out)) = (&args.reference, &args.out) {
        let align = match args.xcorr_max_lag_s {
            Some(l) => Align::Xcorr { max_lag_s: l.abs() },
            None => Align::Time { offset_s: 0.0 },
        };
        merge_file(out, reference, align).coded()?;
    }
    Ok(())
}
