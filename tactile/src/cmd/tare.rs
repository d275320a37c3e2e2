//! `tactile tare`: explicit digital tare (the device never tares by itself).

use std::time::Duration;
use sysexit::ResultExt as _;

use super::common::PortArg;

/// Average samples at rest and subtract their mean from then on (on the device); or clear it.
/// Streaming is started for the averaging if it was off, and stopped again afterwards.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub port: PortArg,
    /// Samples to average (1..=65535).
    #[arg(long, default_value_t = 1000, value_parser = clap::value_parser!(u16).range(1..))]
    pub samples: u16,
    /// Stop subtracting the tare instead.
    #[arg(long)]
    pub clear: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let dev = args.port.open()?;
    if args.clear {
        dev.clear_tare().coded()?;
    } else {
        let info = dev.get_info().coded()?;
        let was_streaming = info.streaming;
        if !was_streaming {
            dev.start().coded()?;
        }
        dev.tare(args.samples).coded()?;
        // The device averages the next `samples` samples before the tare applies.
        let wait_s = f64::from(args.samples) / f64::from(info.sample_rate_hz.max(1));
        std::thread::sleep(Duration::from_secs_f64(wait_s.min(70.0)));
        if !was_streaming {
            dev.stop().coded()?;
        }
    }
    let info = dev.get_info().coded()?;
    println!(
        "{}: tare {:?} codes (config epoch {})",
        dev.port().display(),
        info.tare,
        info.config_epoch
    );
    Ok(())
}
