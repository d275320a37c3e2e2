//! HIL path 2: the firmware's QEMU board binary (`qemu-mps2-an386`) in `qemu-system-arm -machine
//! mps2-an386`, UART0 on a pty. QEMU 7.2 drops pty output until a reader opens the slave, so QEMU
//! starts halted (`-S`), the host opens the pty, and only then does [`QemuBoard::resume`] send
//! `cont` on the monitor (QEMU's stdin).
//!
//! Two clocks: [`Clock::RealTime`] (no `-icount`): SysTick paces the conversions against the
//! host's clock like the real sample clock, so the host's commands land at realistic device
//! times; QEMU re-arms SysTick after each interrupt, so on a loaded host the delivered rate falls
//! below nominal (device time, counted in conversions, then runs slow against wall time).
//! [`Clock::Virtual`] (`-icount shift=0,sleep=off`): one instruction per virtual ns, idle time
//! skipped: the guest runs as fast as QEMU can execute it, which measures the path's capacity.
//!
//! QEMU is killed when the board is dropped (test failure included), and through
//! `PR_SET_PDEATHSIG` when the thread that started it dies, so no run leaves a stray process.

use std::io::{self, BufRead, BufReader, Write};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

/// The firmware crate's folder.
pub fn firmware_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../firmware")
}

/// Build (or find up to date) the QEMU board's release ELF, as `scripts/test-firmware.sh` does.
pub fn build_elf() -> io::Result<PathBuf> {
    let dir = firmware_dir();
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = Command::new(cargo)
        .current_dir(&dir)
        .args(["build", "--release", "--bin", "qemu-mps2-an386"])
        // The outer `cargo test` exports its own target settings; the firmware has its own.
        .env_remove("CARGO_TARGET_DIR")
        .env_remove("CARGO_BUILD_TARGET")
        .status()?;
    if !status.success() {
        return Err(io::Error::other(format!(
            "building the QEMU firmware failed: {status}"
        )));
    }
    Ok(dir.join("target/thumbv7em-none-eabihf/release/qemu-mps2-an386"))
}

/// The board's trim codes after the power-up null (offset / 3e-4 V per code from mid), for the
/// stimulus of `sim::ads131m04::stimulus::StimulusParams::QEMU_BOARD`.
pub const NULL_CODES: [u16; 3] = [3215, 1215, 2715];

/// The code the board's emulated ADC gives `v` volts at an input: PGA 1, and the reference the
/// board gives the chip (`firmware::params::EMULATED_ADC`, adc.toml's).
pub fn ideal_code(v: f32) -> i32 {
    protocol::codes::volts_to_code(f64::from(v), firmware::params::ADC_VREF_V, 1)
}

/// How QEMU's clock runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Clock {
    /// Virtual time follows the host's clock.
    RealTime,
    /// `-icount shift=0,sleep=off`: deterministic instruction timing, idle periods skipped.
    Virtual,
}

impl Clock {
    /// `TACTILE_HIL_QEMU_CLOCK=virtual` selects [`Clock::Virtual`]; real time otherwise.
    pub fn from_env() -> Self {
        match std::env::var("TACTILE_HIL_QEMU_CLOCK").as_deref() {
            Ok("virtual") => Self::Virtual,
            _ => Self::RealTime,
        }
    }
}

/// A halted or running QEMU with the firmware.
pub struct QemuBoard {
    child: Child,
    monitor: ChildStdin,
    /// UART0's pty.
    pub pty: PathBuf,
}

impl QemuBoard {
    /// Start QEMU halted with `elf` and UART0 on a new pty; returns once QEMU has named the pty.
    pub fn spawn(elf: &Path, clock: Clock) -> io::Result<Self> {
        let mut cmd = Command::new("qemu-system-arm");
        cmd.args([
            "-machine",
            "mps2-an386",
            "-cpu",
            "cortex-m4",
            "-nographic",
            "-S",
        ]);
        if clock == Clock::Virtual {
            cmd.args(["-icount", "shift=0,sleep=off"]);
        }
        cmd.args(["-serial", "pty", "-monitor", "stdio"])
            .arg("-kernel")
            .arg(elf)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        // SAFETY: prctl is async-signal-safe; nothing else runs between fork and exec.
        unsafe {
            cmd.pre_exec(|| {
                libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL);
                Ok(())
            });
        }
        let mut child = cmd.spawn()?;
        let monitor = child
            .stdin
            .take()
            .ok_or_else(|| io::Error::other("no stdin"))?;
        let (tx, rx) = mpsc::channel::<PathBuf>();
        // QEMU names the pty on stderr ("char device redirected to /dev/pts/N (label serial0)");
        // the monitor talks on stdout. Both are drained for the life of the process.
        for stream in [
            child
                .stdout
                .take()
                .map(|s| Box::new(s) as Box<dyn io::Read + Send>),
            child
                .stderr
                .take()
                .map(|s| Box::new(s) as Box<dyn io::Read + Send>),
        ]
        .into_iter()
        .flatten()
        {
            let tx = tx.clone();
            std::thread::spawn(move || {
                for line in BufReader::new(stream).lines().map_while(Result::ok) {
                    if let Some(at) = line.find("/dev/pts/") {
                        let path: String = line[at..]
                            .chars()
                            .take_while(|c| !c.is_whitespace())
                            .collect();
                        let _ = tx.send(PathBuf::from(path));
                    }
                }
            });
        }
        let mut board = Self {
            child,
            monitor,
            pty: PathBuf::new(),
        };
        board.pty = rx
            .recv_timeout(Duration::from_secs(20))
            .map_err(|_| io::Error::other("QEMU did not name its pty"))?;
        Ok(board)
    }

    /// Let the halted CPU run (call once the host has the pty open).
    pub fn resume(&mut self) -> io::Result<()> {
        self.monitor.write_all(b"cont\n")?;
        self.monitor.flush()
    }

    /// QEMU's process id (for checks that it is gone).
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// SIGKILL QEMU, as a crash or a pulled power lead would stop the board, and reap it.
    pub fn kill(mut self) -> io::Result<()> {
        self.child.kill()?;
        self.child.wait().map(|_| ())
    }

    /// Quit QEMU through the monitor, and kill it if it has not gone within a second.
    pub fn shutdown(mut self) -> io::Result<()> {
        self.halt()
    }

    fn halt(&mut self) -> io::Result<()> {
        let _ = self.monitor.write_all(b"quit\n");
        let _ = self.monitor.flush();
        for _ in 0..20 {
            if self.child.try_wait()?.is_some() {
                return Ok(());
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let _ = self.child.kill();
        self.child.wait().map(|_| ())
    }
}

impl Drop for QemuBoard {
    fn drop(&mut self) {
        let _ = self.halt();
    }
}
