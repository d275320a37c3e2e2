//! Arguments and helpers shared by the device subcommands.

use std::time::Duration;
use sysexit::ResultExt as _;

use host::device::{Device, OpenOptions, PortSpec};

/// `--port`: a device path or `serial:<USB serial number>`.
#[derive(Debug, Clone, clap::Args)]
pub struct PortArg {
    /// Serial port: a device path (/dev/ttyACM0, a pty, a udev symlink) or
    /// `serial:<USB serial number>` (see `tactile list`).
    #[arg(long, short = 'p', value_name = "PORT")]
    pub port: String,
    /// Seconds to wait for each reply before retrying (3 retries).
    #[arg(long, default_value_t = 0.3, value_name = "SECONDS", value_parser = positive_seconds)]
    pub timeout: f64,
}

impl PortArg {
    /// Open the sensor without reconnection: a one-shot command should fail, not wait.
    pub fn open(&self) -> anyhow::Result<Device> {
        let opts = OpenOptions {
            reconnect: false,
            command_timeout: Duration::from_secs_f64(self.timeout),
            ..OpenOptions::default()
        };
        Ok(Device::open(&PortSpec::parse(&self.port), opts).coded()?)
    }
}

/// A strictly positive, finite number of seconds (at most a day).
pub fn positive_seconds(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("{s:?} is not a number"))?;
    if v.is_finite() && v > 0.0 && v <= 86_400.0 {
        Ok(v)
    } else {
        Err(format!("{s} is out of range (0, 86400] s"))
    }
}

/// A finite number.
pub fn finite(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("{s:?} is not a number"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{s} is not finite"))
    }
}

/// Print a device's info frame.
pub fn print_info(port: &str, info: &protocol::Info) {
    let fw = info.fw_version;
    println!("port             {port}");
    println!("chip serial      {:08x}", info.chip_serial);
    println!(
        "firmware         {}.{}.{} (protocol {})",
        fw[0], fw[1], fw[2], info.protocol_version
    );
    println!(
        "sample rate      {} Hz, {} samples/frame",
        info.sample_rate_hz, info.batch
    );
    println!(
        "PGA gain         {:?}, vref {} mV",
        info.pga_gain, info.vref_mv
    );
    println!(
        "amplifier gain   Fz {} Mx {} My {}",
        info.amp_gain[0], info.amp_gain[1], info.amp_gain[2]
    );
    println!("excitation       {} V", info.excitation_v);
    let f = info.filter;
    println!(
        "filter           smoother alpha {}, Butterworth order {} at {} Hz",
        f.smoother_alpha, f.butterworth_order, f.cutoff_hz
    );
    for (i, row) in info.calibration.iter().enumerate() {
        let name = ["Fz [N]  ", "Mx [N·m]", "My [N·m]"][i];
        println!(
            "calibration {name} = {:>12} {:>12} {:>12} · V",
            row[0], row[1], row[2]
        );
    }
    println!("trim DAC         {:?}", info.dac_codes);
    println!("tare (codes)     {:?}", info.tare);
    println!(
        "drift (codes)    {:?}, tracking {}",
        info.drift,
        if info.drift_tracking { "on" } else { "off" }
    );
    println!("null state       {:?}", info.null_state);
    println!("streaming        {}", info.streaming);
    println!("config epoch     {}", info.config_epoch);
}
