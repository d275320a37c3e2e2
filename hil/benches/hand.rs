//! A whole hand at once: sixteen emulated fingertips at 1 kHz, each on its own pseudo-terminal,
//! into ONE `tactile log -p … -p … --live -o out.csv -d 60` process, as a robot hand's sensors
//! would be logged. The logger is the real `tactile` binary in a process of its own, so what is
//! measured from /proc is its cost alone:
//!
//! - its share of one core: utime + stime of all its threads from /proc/<pid>/stat over the
//!   run, against the wall time of the same run (goal under [`CPU_GOAL`]);
//! - the samples lost: per sensor, what the emulator sent up to the last frame the recording
//!   holds against the data rows in the recording, plus the logger's own counters (its final
//!   status line: lost, dropped, crc, reconnects, host-queue drops) and gap rows;
//! - its resident memory: VmRSS and VmHWM from /proc/<pid>/status.
//!
//! The live view needs a terminal: the logger gets a pty of the bench's size as its controlling
//! terminal, stdin and stdout, and a thread here reads (and discards) what the dashboard draws,
//! as a terminal emulator would. With `TACTILE_HAND_STALL` that reader stops for a while, a
//! terminal that cannot keep up: the logger must drop screen refreshes, never samples, and keep
//! writing its files.
//!
//! The emulators are threads of this process (`hil::emu`, real-time pace, batch 10), started by
//! the logger's start command and stopped by its stop. Their CPU is this process's, reported
//! beside the logger's with the machine's load average, and their pacing is checked: the most
//! frames that fell due at once (1 when on time) and frames dropped by a full transmit queue.
//!
//! First, the simulated hour of issue #29 ([`hil::hand_clock`]): prints `worst misalignment`
//! between any two fingers against the truth, and fails over 1 ms.
//!
//! Run: `scripts/bench-hand.sh [seconds] [sensors]` (builds in release, then runs this).
//! Environment: `TACTILE_BIN` (default: `tactile` next to this binary's `deps/`),
//! `TACTILE_HAND_SECONDS` (60), `TACTILE_HAND_SENSORS` (16), `TACTILE_HAND_TERM` (terminal
//! size `COLSxROWS`, default 200x150: every sensor's panel at full height),
//! `TACTILE_HAND_STALL` (`FROM+SECONDS`: the terminal stops being read from FROM s for
//! SECONDS), `TACTILE_HAND_NICE` (autogroup nice, default -10; root only),
//! `TACTILE_HAND_KEEP=1` (keep the recording's files).

use std::io::{BufRead, BufReader};
use std::os::fd::{AsRawFd, OwnedFd};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitCode, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant, SystemTime};

use hil::check::scratch;
use hil::emu::{EmuConfig, EmuStats, Emulator};
use hil::procfs::{autogroup_nice, cpu_s, loadavg, own_session, rss_kib, thread_cpu_s};
use hil::pty::{read_master, Pty};
use host::logger::per_sensor_path;

/// The logger's share of one core the hand must stay under (issue #29: 5 %, from 10 %).
const CPU_GOAL: f64 = 0.05;
const RATE_HZ: u32 = 1000;
const BATCH: u8 = 10;
/// How often the logger is sampled from /proc.
const PROBE_EVERY: Duration = Duration::from_millis(250);
/// The start-up (opening sixteen ports, the handshakes) is left out of the steady-state share.
const SETTLE_S: f64 = 5.0;

struct Opts {
    seconds: f64,
    sensors: usize,
    cols: u16,
    rows: u16,
    /// The terminal is not read from this many seconds for that many.
    stall: Option<(f64, f64)>,
    nice: i32,
    keep: bool,
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Positional `[seconds] [sensors]` (cargo bench adds `--bench`, skipped), then the environment.
fn opts() -> Opts {
    let pos: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let term = std::env::var("TACTILE_HAND_TERM").unwrap_or_default();
    let (cols, rows) = term
        .split_once('x')
        .and_then(|(c, r)| Some((c.parse().ok()?, r.parse().ok()?)))
        .unwrap_or((200, 150));
    let stall = std::env::var("TACTILE_HAND_STALL").ok().and_then(|v| {
        let (from, len) = v.split_once('+')?;
        Some((from.parse().ok()?, len.parse().ok()?))
    });
    Opts {
        seconds: pos
            .first()
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| env_or("TACTILE_HAND_SECONDS", 60.0)),
        sensors: pos
            .get(1)
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| env_or("TACTILE_HAND_SENSORS", 16)),
        cols,
        rows,
        stall,
        nice: env_or("TACTILE_HAND_NICE", -10),
        keep: env_or("TACTILE_HAND_KEEP", 0) != 0,
    }
}

/// `tactile` built next to this bench (`target/release/tactile`), unless `TACTILE_BIN` says.
fn tactile_bin() -> PathBuf {
    if let Some(p) = std::env::var_os("TACTILE_BIN") {
        return p.into();
    }
    let exe = std::env::current_exe().expect("own path");
    exe.parent()
        .and_then(Path::parent)
        .expect("target dir")
        .join("tactile")
}

/// The logger's terminal: a pty of the given size whose master a thread reads and discards, as
/// a terminal emulator draws; `stall` holds that reader off for a while.
struct Screen {
    slave: OwnedFd,
    bytes: Arc<AtomicU64>,
    stop: Arc<AtomicBool>,
    reader: JoinHandle<()>,
}

impl Screen {
    fn open(cols: u16, rows: u16, stall: Option<(f64, f64)>, t0: Instant) -> std::io::Result<Self> {
        let pty = Pty::open()?;
        let size = libc::winsize {
            ws_row: rows,
            ws_col: cols,
            ws_xpixel: 0,
            ws_ypixel: 0,
        };
        // SAFETY: a valid fd and a winsize that outlives the call.
        if unsafe { libc::ioctl(pty.slave.as_raw_fd(), libc::TIOCSWINSZ, &size) } != 0 {
            return Err(std::io::Error::last_os_error());
        }
        let (bytes, stop) = (
            Arc::new(AtomicU64::new(0)),
            Arc::new(AtomicBool::new(false)),
        );
        let (b, s, master) = (bytes.clone(), stop.clone(), pty.master);
        let reader = std::thread::spawn(move || {
            let mut buf = vec![0u8; 64 * 1024];
            while !s.load(Ordering::Relaxed) {
                let t = t0.elapsed().as_secs_f64();
                if stall.is_some_and(|(from, len)| t >= from && t < from + len) {
                    std::thread::sleep(Duration::from_millis(20));
                    continue;
                }
                let mut fd = libc::pollfd {
                    fd: master.as_raw_fd(),
                    events: libc::POLLIN,
                    revents: 0,
                };
                // SAFETY: one valid pollfd, its count, a timeout in ms.
                unsafe { libc::poll(&mut fd, 1, 50) };
                while let Ok(n @ 1..) = read_master(&master, &mut buf) {
                    b.fetch_add(n as u64, Ordering::Relaxed);
                }
            }
        });
        Ok(Self {
            slave: pty.slave,
            bytes,
            stop,
            reader,
        })
    }

    fn close(self) -> u64 {
        self.stop.store(true, Ordering::Relaxed);
        let _ = self.reader.join();
        self.bytes.load(Ordering::Relaxed)
    }
}

/// Start `tactile log --hand hand.toml --live -o out -d seconds` on the screen's pty, which
/// becomes its controlling terminal (the dashboard asks it for its size and reads its keys).
fn spawn_logger(
    bin: &Path,
    hand: &Path,
    out: &Path,
    seconds: f64,
    screen: &Screen,
) -> std::io::Result<Child> {
    let mut cmd = Command::new(bin);
    cmd.arg("log").arg("--hand").arg(hand);
    cmd.args(["--live", "-o"])
        .arg(out)
        .args(["-d", &seconds.to_string()])
        .env("TERM", "xterm-256color")
        .stdin(Stdio::from(screen.slave.try_clone()?))
        .stdout(Stdio::from(screen.slave.try_clone()?))
        .stderr(Stdio::piped());
    // SAFETY: setsid and ioctl are async-signal-safe and touch no memory of the parent.
    unsafe {
        cmd.pre_exec(|| {
            if libc::setsid() < 0 || libc::ioctl(0, libc::TIOCSCTTY, 0) < 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    cmd.spawn()
}

/// Keep every line the logger writes to stderr (its final status line carries its counters).
fn collect_stderr(child: &mut Child) -> (Arc<Mutex<Vec<String>>>, JoinHandle<()>) {
    let lines = Arc::new(Mutex::new(Vec::new()));
    let keep = lines.clone();
    let stderr = child.stderr.take().expect("piped stderr");
    let t = std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            keep.lock().expect("lines").push(line);
        }
    });
    (lines, t)
}

/// One look at the logger from /proc.
#[derive(Debug, Clone, Copy)]
struct Probe {
    t_s: f64,
    cpu_s: f64,
    rss_kib: u64,
    hwm_kib: u64,
}

/// What the watch over the run saw.
struct Watch {
    probes: Vec<Probe>,
    status: ExitStatus,
    /// Thread name, CPU s, thread count: the last look before the logger exited.
    threads: Vec<(String, f64, usize)>,
    /// Longest time the first sensor's CSV did not grow after its first data.
    longest_csv_stall_s: f64,
    /// The emulators' process (this one) CPU s over the run.
    bench_cpu_s: f64,
}

/// Sample the logger every [`PROBE_EVERY`] until it exits; a line every ten seconds.
fn watch(
    child: &mut Child,
    t0: Instant,
    deadline_s: f64,
    csv: &Path,
    screen_bytes: &AtomicU64,
) -> Watch {
    let pid = child.id();
    let bench_cpu0 = cpu_s(std::process::id()).unwrap_or(0.0);
    let (mut probes, mut threads) = (Vec::new(), Vec::new());
    let (mut csv_len, mut csv_changed, mut longest) = (0u64, None::<f64>, 0.0f64);
    let mut next_line = 10.0;
    let status = loop {
        if let Some(st) = child.try_wait().expect("wait for the logger") {
            break st;
        }
        let t_s = t0.elapsed().as_secs_f64();
        if let (Some(cpu), Some((rss, hwm))) = (cpu_s(pid), rss_kib(pid)) {
            probes.push(Probe {
                t_s,
                cpu_s: cpu,
                rss_kib: rss,
                hwm_kib: hwm,
            });
            // Before the deadline: once it passes, threads end one by one.
            if t_s < deadline_s {
                threads = thread_cpu_s(pid);
            }
        }
        let len = std::fs::metadata(csv).map_or(0, |m| m.len());
        if len != csv_len {
            if let Some(c) = csv_changed.filter(|_| csv_len > 0) {
                longest = longest.max(t_s - c);
            }
            (csv_len, csv_changed) = (len, Some(t_s));
        }
        if t_s >= next_line {
            next_line += 10.0;
            progress_line(&probes, t_s, screen_bytes.load(Ordering::Relaxed));
        }
        std::thread::sleep(PROBE_EVERY);
    };
    Watch {
        probes,
        status,
        threads,
        longest_csv_stall_s: longest,
        bench_cpu_s: cpu_s(std::process::id()).unwrap_or(0.0) - bench_cpu0,
    }
}

/// The logger's CPU share over the last ten seconds, its RSS, the load, the screen's output.
fn progress_line(probes: &[Probe], t_s: f64, screen_bytes: u64) {
    let Some(last) = probes.last() else {
        return;
    };
    let back = probes
        .iter()
        .rev()
        .find(|p| last.t_s - p.t_s >= 10.0)
        .unwrap_or(&probes[0]);
    let share = (last.cpu_s - back.cpu_s) / (last.t_s - back.t_s).max(1e-9);
    eprintln!(
        "hand {t_s:5.0} s: logger {:5.2} % of a core (last {:.0} s), RSS {:.1} MiB, load {}, \
         screen {:.0} kB",
        100.0 * share,
        last.t_s - back.t_s,
        last.rss_kib as f64 / 1024.0,
        loadavg(),
        screen_bytes as f64 / 1e3
    );
}

/// What one sensor's recording holds.
#[derive(Debug, Default, Clone)]
struct Tally {
    rows: u64,
    frames: u64,
    gap_rows: u64,
    first_seq: Option<u64>,
    last_seq: Option<u64>,
    /// Sequence breaks between consecutive data frames.
    breaks: u64,
    bytes: u64,
}

/// Read a recording CSV: data rows, gap rows, frames by sequence and breaks in it.
fn tally(path: &Path) -> std::io::Result<Tally> {
    let f = BufReader::with_capacity(1 << 20, std::fs::File::open(path)?);
    let mut t = Tally::default();
    let mut cols: Option<(usize, usize)> = None;
    for line in f.lines() {
        let line = line?;
        t.bytes += line.len() as u64 + 1;
        if line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split(',').collect();
        let Some((seq_c, gap_c)) = cols else {
            let at = |name: &str| fields.iter().position(|c| *c == name);
            cols = at("seq").zip(at("gap"));
            continue;
        };
        if fields[gap_c].parse::<f64>().unwrap_or(0.0) != 0.0 {
            t.gap_rows += 1;
            continue;
        }
        t.rows += 1;
        let seq: u64 = fields[seq_c].parse().unwrap_or(u64::MAX);
        if t.last_seq != Some(seq) {
            if t.last_seq.is_some_and(|l| seq != l + 1) {
                t.breaks += 1;
            }
            t.frames += 1;
            t.first_seq.get_or_insert(seq);
            t.last_seq = Some(seq);
        }
    }
    Ok(t)
}

/// The logger's counters for each sensor, from its final status line
/// (` | label: … lost A dropped B crc C reconnects D queue E`), summed over the sensors.
fn logger_counters(lines: &[String]) -> Option<[u64; 5]> {
    let line = lines.iter().rev().find(|l| l.contains(" S/s, "))?;
    let keys = ["lost", "dropped", "crc", "reconnects", "queue"];
    let mut sum = [0u64; 5];
    for part in line.split(" | ").skip(1) {
        for (k, key) in keys.iter().enumerate() {
            let at = part.find(&format!(" {key} "))? + key.len() + 2;
            let n: u64 = part[at..]
                .split(|c: char| !c.is_ascii_digit())
                .next()?
                .parse()
                .ok()?;
            sum[k] += n;
        }
    }
    Some(sum)
}

/// One sensor's account: what its emulator sent against what its recording holds.
#[derive(Debug, Default, Clone, Copy)]
struct Account {
    sent: u64,
    recorded: u64,
    /// Samples sent up to the last recorded frame and missing from the recording.
    lost: u64,
    /// Samples sent after the last recorded frame: on their way when the logger's time was up.
    after_end: u64,
    emu_dropped: u64,
    max_burst: u64,
}

fn account(stats: &EmuStats, t: &Tally) -> Account {
    let batch = u64::from(BATCH);
    let sent_frames = stats.frames_sent.load(Ordering::Relaxed);
    let last_sent = stats
        .last_seq_plus_one
        .load(Ordering::Relaxed)
        .checked_sub(1);
    let after_end = match (last_sent, t.last_seq) {
        (Some(s), Some(r)) => s.saturating_sub(r),
        (_, None) => sent_frames,
        (None, Some(_)) => 0,
    };
    let due = sent_frames.saturating_sub(after_end);
    Account {
        sent: sent_frames * batch,
        recorded: t.rows,
        lost: due.saturating_sub(t.frames) * batch,
        after_end: after_end * batch,
        emu_dropped: stats.frames_dropped.load(Ordering::Relaxed),
        max_burst: stats.max_burst.load(Ordering::Relaxed),
    }
}

/// Finger `i`'s name in the hand file.
fn finger(i: usize) -> String {
    format!("tip{:02}", i + 1)
}

/// Finger `i`'s crystal error: the sixteen spread over ±100 ppm.
fn crystal_ppm(i: usize, sensors: usize) -> f64 {
    -100.0 + 200.0 * i as f64 / (sensors.max(2) - 1) as f64
}

/// The hand file naming each finger's stable link.
fn write_hand(dir: &Path, links: &[PathBuf]) -> PathBuf {
    let mut toml = String::from("[fingers]\n");
    for (i, l) in links.iter().enumerate() {
        toml.push_str(&format!("{} = \"{}\"\n", finger(i), l.display()));
    }
    let path = dir.join("hand.toml");
    std::fs::write(&path, toml).expect("write the hand file");
    path
}

/// The emulated hand: one emulator per fingertip behind a stable link in `dir`. Their device
/// clocks are spread over one frame period, as independent sensors' clocks would be, their
/// crystals over ±100 ppm, and each link is jittered as a busy USB bus would.
fn start_hand(dir: &Path, sensors: usize) -> (Vec<Emulator>, Vec<PathBuf>) {
    let frame = Duration::from_secs_f64(f64::from(BATCH) / f64::from(RATE_HZ));
    let now = SystemTime::now();
    let mut emus = Vec::new();
    let mut links = Vec::new();
    for i in 0..sensors {
        let link = dir.join(format!("tip{:02}", i + 1));
        let mut cfg = EmuConfig::new(&link);
        cfg.rate_hz = RATE_HZ;
        cfg.batch = BATCH;
        cfg.epoch = now - frame.mul_f64(i as f64 / sensors as f64);
        cfg.chip_serial = 0x7AC7_1100 + i as u32;
        cfg.clock_ppm = crystal_ppm(i, sensors);
        cfg.jitter = Some((sim::clock::LinkJitter::USB_BUSY, 100 + i as u64));
        emus.push(Emulator::spawn(cfg).expect("start an emulator"));
        links.push(link);
    }
    (emus, links)
}

/// The simulated hour (`hil::hand_clock`): sixteen crystals within ±100 ppm, a jittered link,
/// a device restart and a link loss at half time, through the logger's time mapping on a
/// virtual clock; `true` when any two fingers stayed within [`ALIGN_GOAL_S`] at every point.
fn simulated_hour() -> bool {
    let sim = hil::hand_clock::HandSim::hour();
    let t0 = Instant::now();
    let r = hil::hand_clock::simulate(&sim);
    let j = sim.jitter;
    println!(
        "simulated hour: {} fingers x {:.0} s on a virtual clock ({:.1} s of wall time), crystals \
         within ±{:.0} ppm, link delay {:.0} µs + U(0, {:.0} µs) + Exp({:.0} µs), {:.0} % held up \
         to {:.0} ms, one reader in rounds (pause U(0, {:.0} ms), catch window {:.1} ms); finger 1 restarts and finger 2 loses its link \
         at {:.0} s for {:.0} s; {} frames compared",
        sim.fingers,
        sim.seconds,
        t0.elapsed().as_secs_f64(),
        sim.max_ppm,
        j.floor_s * 1e6,
        j.usb_frame_s * 1e6,
        j.sched_mean_s * 1e6,
        j.outlier_prob * 100.0,
        j.outlier_max_s * 1e3,
        2e3 * sim.coalesce_s,
        1e3 * sim.catch_s,
        sim.reconnect_at_s,
        sim.outage_s,
        r.frames
    );
    println!(
        "worst misalignment: {:.0} µs (at {:.2} s; goal < {:.0} µs); reconnects: time step {:+.1} µs \
         (device restarted), {:+.1} µs (clock kept running); worst rate error {:.2} ppm",
        r.worst_s * 1e6,
        r.worst_at_s,
        ALIGN_GOAL_S * 1e6,
        r.reconnect_steps_s[0] * 1e6,
        r.reconnect_steps_s[1] * 1e6,
        r.worst_ppm_error
    );
    r.worst_s < ALIGN_GOAL_S && r.reconnect_steps_s.iter().all(|s| s.abs() < ALIGN_GOAL_S)
}

/// Any two fingers must agree within this at every point of the simulated hour.
const ALIGN_GOAL_S: f64 = 1e-3;

fn main() -> ExitCode {
    let aligned = simulated_hour();
    let o = opts();
    let bin = tactile_bin();
    if !bin.exists() {
        eprintln!(
            "{}: build it first (scripts/bench-hand.sh does)",
            bin.display()
        );
        return ExitCode::from(2);
    }
    let session = own_session(o.nice);
    let dir = scratch("hand");
    let out = dir.join("hand.csv");
    let (emus, links) = start_hand(&dir, o.sensors);
    let hand = write_hand(&dir, &links);
    let csvs: Vec<PathBuf> = (0..links.len())
        .map(|i| per_sensor_path(&out, &finger(i), true))
        .collect();
    let load_start = loadavg();
    let t0 = Instant::now();
    let screen = Screen::open(o.cols, o.rows, o.stall, t0).expect("a pty for the dashboard");
    let mut child = spawn_logger(&bin, &hand, &out, o.seconds, &screen).expect("start tactile");
    let logger_session = autogroup_nice(Some(child.id()), o.nice);
    let (lines, stderr) = collect_stderr(&mut child);
    let w = watch(&mut child, t0, o.seconds, &csvs[0], &screen.bytes);
    let wall_s = t0.elapsed().as_secs_f64();
    let load_end = loadavg();
    let screen_bytes = screen.close();
    let _ = stderr.join();
    let stats: Vec<Arc<EmuStats>> = emus.iter().map(|e| e.stats.clone()).collect();
    drop(emus);
    let lines = lines.lock().expect("lines").clone();
    let accounts: Vec<(Account, Tally)> = csvs
        .iter()
        .zip(&stats)
        .map(|(p, s)| {
            let t = tally(p).unwrap_or_default();
            (account(s, &t), t)
        })
        .collect();
    let ok = report(&Report {
        o: &o,
        w: &w,
        wall_s,
        accounts: &accounts,
        lines: &lines,
        screen_bytes,
        loads: [&load_start, &load_end],
        sessions: [&session, &logger_session],
        mcap_bytes: std::fs::metadata(out.with_extension("mcap")).map_or(0, |m| m.len()),
    });
    if o.keep {
        eprintln!("files kept in {}", dir.display());
    } else {
        let _ = std::fs::remove_dir_all(&dir);
    }
    if ok && aligned {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

struct Report<'a> {
    o: &'a Opts,
    w: &'a Watch,
    wall_s: f64,
    accounts: &'a [(Account, Tally)],
    lines: &'a [String],
    screen_bytes: u64,
    loads: [&'a str; 2],
    sessions: [&'a str; 2],
    mcap_bytes: u64,
}

/// The logger's CPU share of one core between two probes.
fn share(a: &Probe, b: &Probe) -> f64 {
    (b.cpu_s - a.cpu_s) / (b.t_s - a.t_s).max(1e-9)
}

/// Print the figures; `true` when the logger met both goals (no loss, CPU under the goal).
fn report(r: &Report<'_>) -> bool {
    let o = r.o;
    for l in r.lines.iter().filter(|l| !l.contains(" S/s, ")) {
        eprintln!("tactile log: {l}");
    }
    println!(
        "hand: {} sensors x {RATE_HZ} Hz (batch {BATCH}) -> one `tactile log --live` on a \
         {}x{} pty, -d {} s; logger exit {}; wall {:.1} s",
        o.sensors, o.cols, o.rows, o.seconds, r.w.status, r.wall_s
    );
    let cpu_ok = report_cpu(r);
    let loss_ok = report_loss(r);
    report_memory(r);
    report_clocks(r);
    println!(
        "machine: 2-core x86_64 here ({} CPUs online); load average {} at the start, {} at the \
         end; emulators (this process) {:.1} % of a core; bench session {}, logger session {}",
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        r.loads[0],
        r.loads[1],
        100.0 * r.w.bench_cpu_s / r.wall_s,
        r.sessions[0],
        r.sessions[1]
    );
    println!(
        "verdict: CPU {} (goal < {:.0} % of a core), loss {} (goal 0)",
        if cpu_ok { "met" } else { "MISSED" },
        100.0 * CPU_GOAL,
        if loss_ok { "met" } else { "MISSED" }
    );
    cpu_ok && loss_ok && r.w.status.success()
}

fn report_cpu(r: &Report<'_>) -> bool {
    let (Some(first), Some(last)) = (r.w.probes.first(), r.w.probes.last()) else {
        println!("logger CPU: no sample (the logger exited at once)");
        return false;
    };
    let all = share(first, last);
    let settled =
        r.w.probes
            .iter()
            .find(|p| p.t_s >= SETTLE_S)
            .unwrap_or(first);
    let steady = share(settled, last);
    println!(
        "logger CPU: {:.2} % of one core over {:.1} s ({:.2} s user+system) = {:.2} x the {:.0} % \
         goal; from {:.0} s on: {:.2} % = {:.2} x",
        100.0 * all,
        last.t_s - first.t_s,
        last.cpu_s - first.cpu_s,
        all / CPU_GOAL,
        100.0 * CPU_GOAL,
        settled.t_s,
        100.0 * steady,
        steady / CPU_GOAL
    );
    let threads: Vec<String> =
        r.w.threads
            .iter()
            .map(|(n, s, k)| format!("{n:?} x{k}: {s:.2} s"))
            .collect();
    println!("logger threads (CPU s by name): {}", threads.join(", "));
    all < CPU_GOAL
}

fn report_loss(r: &Report<'_>) -> bool {
    let mut sum = Account::default();
    let (mut gap_rows, mut breaks) = (0, 0);
    for (a, t) in r.accounts {
        sum.sent += a.sent;
        sum.recorded += a.recorded;
        sum.lost += a.lost;
        sum.after_end += a.after_end;
        sum.emu_dropped += a.emu_dropped;
        sum.max_burst = sum.max_burst.max(a.max_burst);
        gap_rows += t.gap_rows;
        breaks += t.breaks;
    }
    let per: Vec<String> = r
        .accounts
        .iter()
        .map(|(a, _)| format!("{}/{}/{}", a.sent, a.recorded, a.lost))
        .collect();
    println!(
        "samples: sent {}, recorded {}, lost {} (sent before the last recorded frame and not in \
         the recording); {} more were sent after it, while the logger stopped; recording: {} \
         gap rows, {} sequence breaks",
        sum.sent, sum.recorded, sum.lost, sum.after_end, gap_rows, breaks
    );
    println!("per sensor sent/recorded/lost: {}", per.join(" "));
    let counters = logger_counters(r.lines);
    match counters {
        Some([lost, dropped, crc, reconnects, queue]) => println!(
            "logger's counters (all sensors): lost {lost}, dropped {dropped}, crc {crc}, \
             reconnects {reconnects}, host-queue drops {queue}"
        ),
        None => println!("logger's counters: no final status line"),
    }
    println!(
        "emulators' pacing: {} frames dropped by a full transmit queue, most frames due at once {}",
        sum.emu_dropped, sum.max_burst
    );
    let clean = counters.is_some_and(|c| c.iter().all(|&n| n == 0));
    sum.lost == 0 && gap_rows == 0 && breaks == 0 && sum.recorded > 0 && clean
}

/// Each finger's clock estimate in the logger's final status line
/// (` | tipNN: … clock +x.x ppm [(settling)] ±u µs, …`) against its emulator's crystal.
fn report_clocks(r: &Report<'_>) {
    let Some(line) = r.lines.iter().rev().find(|l| l.contains(" S/s, ")) else {
        return;
    };
    let (mut worst, mut unc, mut n) = (0.0f64, 0.0f64, 0);
    for (i, part) in line.split(" | ").skip(1).enumerate() {
        let Some(at) = part.find("clock ") else {
            continue;
        };
        let mut words = part[at + 6..].split_whitespace();
        let ppm: Option<f64> = words.next().and_then(|w| w.parse().ok());
        // `ppm`, `(settling)` while the rate settles, then the alignment's `±u`.
        let u: Option<f64> = words
            .find(|w| w.starts_with('±'))
            .and_then(|w| w.trim_start_matches('±').parse().ok());
        if let (Some(ppm), Some(u)) = (ppm, u) {
            worst = worst.max((ppm - crystal_ppm(i, r.o.sensors)).abs());
            unc = unc.max(u);
            n += 1;
        }
    }
    println!(
        "clock estimates (the logger's final status line): {n} fingers, crystals -100 … +100 ppm; \
         worst |estimated - true| {worst:.2} ppm; alignment uncertainty up to {unc:.0} µs"
    );
}

fn report_memory(r: &Report<'_>) {
    let p = &r.w.probes;
    let at = |t: f64| p.iter().find(|q| q.t_s >= t).or(p.last());
    let (Some(early), Some(last)) = (at(SETTLE_S), p.last()) else {
        return;
    };
    let mib = |k: u64| k as f64 / 1024.0;
    let csv_mb: u64 = r.accounts.iter().map(|(_, t)| t.bytes).sum();
    println!(
        "logger memory: VmRSS {:.1} MiB at {:.0} s, {:.1} MiB at the end; VmHWM {:.1} MiB; files: \
         CSV {:.0} MB in {} files, MCAP {:.0} MB; the CSVs went at most {:.2} s without growing",
        mib(early.rss_kib),
        early.t_s,
        mib(last.rss_kib),
        mib(last.hwm_kib),
        csv_mb as f64 / 1e6,
        r.accounts.len(),
        r.mcap_bytes as f64 / 1e6,
        r.w.longest_csv_stall_s
    );
    println!(
        "live view: {:.0} kB drawn ({:.1} kB/s)",
        r.screen_bytes as f64 / 1e3,
        r.screen_bytes as f64 / 1e3 / r.wall_s
    );
}
