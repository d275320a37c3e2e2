//! What Linux's /proc says about a process under test: its CPU time (per thread, too), its
//! resident memory, the machine's load, and the scheduler group it runs in. The soak and the
//! hand benchmark measure the real `tactile` binary from outside with these, so that what they
//! report is the logger's own cost and nothing of the harness's.

use std::path::Path;

/// VmRSS and VmHWM (peak RSS) of `pid` in KiB.
pub fn rss_kib(pid: u32) -> Option<(u64, u64)> {
    let s = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let field = |name: &str| -> Option<u64> {
        let line = s.lines().find(|l| l.starts_with(name))?;
        line.split_whitespace().nth(1)?.parse().ok()
    };
    Some((field("VmRSS:")?, field("VmHWM:")?))
}

/// Clock ticks per second of the times in /proc/*/stat.
fn ticks_per_s() -> f64 {
    // SAFETY: sysconf only reads a configuration value.
    let t = unsafe { libc::sysconf(libc::_SC_CLK_TCK) };
    if t > 0 {
        t as f64
    } else {
        100.0
    }
}

/// The command name and user + system CPU seconds of a `stat` file (a process's or a thread's).
fn stat_cpu(path: &Path) -> Option<(String, f64)> {
    let s = std::fs::read_to_string(path).ok()?;
    // The name is in parentheses and may itself hold spaces or parentheses: cut at the last one.
    let open = s.find('(')?;
    let close = s.rfind(')')?;
    let name = s.get(open + 1..close)?.to_owned();
    let rest: Vec<&str> = s.get(close + 1..)?.split_whitespace().collect();
    // Fields 14 (utime) and 15 (stime) of proc(5); `rest` starts at field 3.
    let utime: u64 = rest.get(11)?.parse().ok()?;
    let stime: u64 = rest.get(12)?.parse().ok()?;
    Some((name, (utime + stime) as f64 / ticks_per_s()))
}

/// User + system CPU seconds used so far by every thread of `pid` together.
pub fn cpu_s(pid: u32) -> Option<f64> {
    stat_cpu(Path::new(&format!("/proc/{pid}/stat"))).map(|(_, s)| s)
}

/// CPU seconds of each live thread of `pid`, summed per thread name (sorted by name).
pub fn thread_cpu_s(pid: u32) -> Vec<(String, f64, usize)> {
    let mut by_name: std::collections::BTreeMap<String, (f64, usize)> = Default::default();
    let Ok(tasks) = std::fs::read_dir(format!("/proc/{pid}/task")) else {
        return Vec::new();
    };
    for task in tasks.flatten() {
        if let Some((name, s)) = stat_cpu(&task.path().join("stat")) {
            let e = by_name.entry(name).or_default();
            e.0 += s;
            e.1 += 1;
        }
    }
    by_name.into_iter().map(|(n, (s, k))| (n, s, k)).collect()
}

/// The 1, 5 and 15 minute load averages.
pub fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_default()
}

/// Give the scheduler autogroup of `pid`'s session the nice value `nice` (root only; a no-op
/// elsewhere) and return the line in effect (`/autogroup-N nice K`), or why it is unknown.
///
/// On a machine shared with other sessions' compilers the autogroups share the CPU between
/// sessions first, and a thread's own nice only orders it within its session: a paced emulator
/// or a logger is then held off the CPU for seconds. A session of its own at negative nice
/// runs them when their data is due, as on a machine set up for acquisition.
pub fn autogroup_nice(pid: Option<u32>, nice: i32) -> String {
    let path = pid.map_or_else(
        || "/proc/self/autogroup".to_owned(),
        |p| format!("/proc/{p}/autogroup"),
    );
    let _ = std::fs::write(&path, nice.to_string());
    std::fs::read_to_string(&path).map_or_else(
        |e| format!("autogroup unknown: {e}"),
        |s| s.trim().to_owned(),
    )
}

/// Move this process into a session of its own (the children it starts later join it) and give
/// that session's autogroup `nice`; see [`autogroup_nice`].
pub fn own_session(nice: i32) -> String {
    // SAFETY: setsid has no memory effects; it fails harmlessly if we lead a process group.
    unsafe { libc::setsid() };
    autogroup_nice(None, nice)
}
