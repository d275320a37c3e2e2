//! `tactile-emu`: run the pty sensor emulator so people and the demo can point `tactile` at it.
//!
//! ```text
//! tactile-emu --link /tmp/tactile0 [--rate 1000] [--batch 10] [--autostart]
//!             [--epoch-unix SECONDS] [--cut-after SECONDS] [--run-for SECONDS]
//! ```
//! Prints the pty path and the link, then runs until killed (or `--run-for` / `--cut-after`).

use std::process::ExitCode;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use tests::emu::{EmuConfig, Emulator};

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

fn run() -> Result<(), String> {
    let mut cfg = EmuConfig::new("/tmp/tactile0");
    let mut run_for = None;
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
            "-h" | "--help" => {
                println!("usage: tactile-emu --link PATH [--rate HZ] [--batch N] [--autostart] [--epoch-unix S] [--cut-after S] [--run-for S]");
                return Ok(());
            }
            other => return Err(format!("unknown argument {other:?}")),
        }
    }
    if cfg.rate_hz == 0 || !(1..=16).contains(&cfg.batch) {
        return Err("--rate must be > 0 and --batch in 1..=16".into());
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
    emu.kill();
    Ok(())
}
