//! `tactile-emu`: run the pty sensor emulator so people and the demo can point `tactile` at it.
//!
//! ```text
//! tactile-emu --link /tmp/tactile0 [--rate 1000] [--batch 10] [--autostart]
//!             [--epoch-unix SECONDS] [--cut-after SECONDS] [--run-for SECONDS]
//!             [--free-run FRAMES] [--fault-rate PER_FRAME] [--fault-seed N]
//!             [--ppm PPM] [--jitter-seed N]
//! ```
//! Prints the pty path and the link, then runs until killed (or `--run-for` / `--cut-after`).
//! `--free-run` streams that many frames as fast as the pty takes them; `--fault-rate` passes
//! the frames (all but 16 at each end) through `sim::link::FaultyLink` with every fault at that
//! rate, and prints the link's account at the end of `--run-for`. `--ppm` sets the crystal's
//! error; `--jitter-seed` delays each frame by a draw of a busy USB link's delay
//! (`sim::clock::LinkJitter::USB_BUSY`).
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

use std::process::ExitCode;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use hil::emu::{EmuConfig, EmuFaults, Emulator, Pace};
use sim::link::FaultRates;

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tactile-emu: error: {e}");
            ExitCode::from(64)
        }
    }
}

fn value<T: std::str::FromStr>(
    args: &mut impl Iterator<Item = String>,
    flag: &str,
) -> Result<T, String> {
    let v = args.next().ok_or_else(|| format!("{flag} needs a value"))?;
    v.parse().map_err(|_| format!("{flag}: cannot read {v:?}"))
}

/// The configuration's values a device could have.
fn check(cfg: &EmuConfig) -> Result<(), String> {
    if !cfg.clock_ppm.is_finite() || cfg.clock_ppm.abs() >= 1e5 {
        return Err(format!("--ppm: {} is not a crystal error", cfg.clock_ppm));
    }
    if cfg.rate_hz == 0 || !(1..=16).contains(&cfg.batch) {
        return Err("--rate must be > 0 and --batch in 1..=16".into());
    }
    Ok(())
}

fn run() -> Result<(), String> {
    let mut cfg = EmuConfig::new("/tmp/tactile0");
    let mut run_for = None;
    let (mut fault_rate, mut fault_seed) = (None, 1u64);
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--link" => cfg.link = value::<String>(&mut args, &a)?.into(),
            "--rate" => cfg.rate_hz = value(&mut args, &a)?,
            "--batch" => cfg.batch = value(&mut args, &a)?,
            "--autostart" => cfg.autostart = true,
            "--epoch-unix" => {
                cfg.epoch = UNIX_EPOCH + Duration::from_secs_f64(value(&mut args, &a)?)
            }
            "--cut-after" => {
                cfg.cut_mid_frame_after = Some(Duration::from_secs_f64(value(&mut args, &a)?))
            }
            "--run-for" => run_for = Some(Duration::from_secs_f64(value(&mut args, &a)?)),
            "--free-run" => {
                cfg.pace = Pace::FreeRun {
                    frames: value(&mut args, &a)?,
                }
            }
            "--fault-rate" => fault_rate = Some(value::<f64>(&mut args, &a)?),
            "--fault-seed" => fault_seed = value(&mut args, &a)?,
            "--ppm" => cfg.clock_ppm = value(&mut args, &a)?,
            "--jitter-seed" => {
                cfg.jitter = Some((sim::clock::LinkJitter::USB_BUSY, value(&mut args, &a)?))
            }
            "-h" | "--help" => {
                println!("usage: tactile-emu --link PATH [--rate HZ] [--batch N] [--autostart] [--epoch-unix S] [--cut-after S] [--run-for S] [--free-run FRAMES] [--fault-rate R] [--fault-seed N] [--ppm PPM] [--jitter-seed N]");
                return Ok(());
            }
            other => return Err(format!("unknown argument {other:?}")),
        }
    }
    check(&cfg)?;
    if let Some(rate) = fault_rate {
        if !(0.0..=1.0).contains(&rate) {
            return Err(format!(
                "--fault-rate: {rate} is not a probability in 0..=1"
            ));
        }
        let end = match cfg.pace {
            Pace::FreeRun { frames } => frames.saturating_sub(16),
            Pace::RealTime => u64::MAX,
        };
        cfg.faults = Some(EmuFaults {
            rates: FaultRates::uniform(rate, Duration::from_millis(20)),
            seed: fault_seed,
            frames: 16..end,
        });
    }
    let since = SystemTime::now()
        .duration_since(cfg.epoch)
        .unwrap_or_default();
    let cut = cfg.cut_mid_frame_after;
    let link = cfg.link.clone();
    let emu = Emulator::spawn(cfg).map_err(|e| format!("{}: {e}", link.display()))?;
    println!(
        "{} -> {} (device clock at {:.3} s)",
        link.display(),
        emu.slave.display(),
        since.as_secs_f64()
    );
    if cut.is_some() {
        return emu.wait().map_err(|e| e.to_string());
    }
    match run_for {
        Some(d) => std::thread::sleep(d),
        None => loop {
            std::thread::sleep(Duration::from_secs(3600));
        },
    }
    if fault_rate.is_some() {
        println!("injected: {:?}", emu.stats.injected());
    }
    emu.kill();
    Ok(())
}
