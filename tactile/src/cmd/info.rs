//! `tactile info`: the sensor's identity and configuration.

use super::common::{print_info, PortArg};
use sysexit::ResultExt as _;

/// Print a sensor's info frame (identity, rate, gains, filter, calibration, tare, null state)
/// and the round-trip time of a ping.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub port: PortArg,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let dev = args.port.open()?;
    let info = dev.get_info().coded()?;
    let rtt = dev.ping().coded()?;
    print_info(&dev.port().display().to_string(), &info);
    println!("ping             {:.2} ms", rtt.as_secs_f64() * 1e3);
    Ok(())
}
