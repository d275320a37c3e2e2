//! Every subcommand's error paths: the exit code, one line on stderr naming the port, file,
//! line or field, and never a panic. Also: complete help, and a broken pipe is a clean exit.
//!
//! Permission denied as root: root ignores file modes, so the `chmod 000` port is opened by a
//! child process running as user `nobody` (uid 65534); when the tests do not run as root the
//! mode alone refuses it.

use std::os::unix::fs::PermissionsExt;
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use hil::check::scratch;
use hil::emu::{EmuConfig, Emulator};
use host::device::{Device, OpenOptions, PortSpec};
use sysexit as exit;

mod common;
use common::{fails, tactile};

const DEVICE_COMMANDS: [&[&str]; 4] = [
    &["info"],
    &["tare"],
    &["config", "--rate", "1000"],
    &["log", "--duration", "1"],
];

fn with_port<'a>(cmd: &[&'a str], port: &'a str) -> Vec<&'a str> {
    let mut v = cmd.to_vec();
    v.extend(["-p", port]);
    v
}

#[test]
fn missing_port_not_a_tty_and_permission_denied() {
    let dir = scratch("cli-ports");
    let dir_s = dir.to_str().unwrap().to_owned();
    let plain = dir.join("plain-file");
    std::fs::write(&plain, b"x").unwrap();
    let plain_s = plain.to_str().unwrap().to_owned();
    for cmd in DEVICE_COMMANDS {
        fails(
            &tactile(&with_port(cmd, "/nonexistent/ttyACM9")),
            exit::NO_INPUT,
            &["/nonexistent/ttyACM9", "no such device"],
        );
        fails(
            &tactile(&with_port(cmd, &dir_s)),
            exit::NO_INPUT,
            &[&dir_s, "directory"],
        );
        fails(
            &tactile(&with_port(cmd, &plain_s)),
            exit::NO_INPUT,
            &[&plain_s, "regular file"],
        );
    }
    fails(
        &tactile(&["info", "-p", "serial:NOPE123"]),
        exit::NO_INPUT,
        &["NOPE123"],
    );

    let emu = Emulator::spawn(EmuConfig::new(dir.join("tactile0"))).unwrap();
    let slave = emu.slave.clone();
    std::fs::set_permissions(&slave, std::fs::Permissions::from_mode(0o000)).unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_tactile"));
    cmd.args(["info", "-p"]).arg(&slave);
    // SAFETY: getuid has no preconditions.
    let root = unsafe { libc::getuid() } == 0;
    if root {
        cmd.uid(65534).gid(65534);
    }
    match cmd.output() {
        Ok(out) => fails(
            &out,
            exit::NO_PERM,
            &[slave.to_str().unwrap(), "permission denied"],
        ),
        // The checkout is not readable by `nobody` (a private home): nothing to test this way.
        Err(e) if root => eprintln!("permission test skipped: cannot run tactile as nobody: {e}"),
        Err(e) => panic!("{e}"),
    }
    std::fs::set_permissions(&slave, std::fs::Permissions::from_mode(0o620)).unwrap();
    drop(emu);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn busy_port_and_device_gone_mid_stream() {
    let dir = scratch("cli-busy");
    let cfg = EmuConfig::new(dir.join("tactile0"));
    let emu = Emulator::spawn(cfg.clone()).unwrap();
    let link = cfg.link.to_str().unwrap().to_owned();
    {
        let held = Device::open(&PortSpec::parse(&link), OpenOptions::default()).unwrap();
        for cmd in DEVICE_COMMANDS {
            fails(
                &tactile(&with_port(cmd, &link)),
                exit::UNAVAILABLE,
                &["busy"],
            );
        }
        drop(held);
    }
    // The device vanishes while `log` records; without reconnection that is an error, after
    // the rows received so far are safely written.
    let csv = dir.join("gone.csv");
    let child = Command::new(env!("CARGO_BIN_EXE_tactile"))
        .args([
            "log",
            "-q",
            "--no-reconnect",
            "--duration",
            "20",
            "-p",
            &link,
            "-o",
        ])
        .arg(&csv)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1200));
    emu.kill();
    let out = child.wait_with_output().unwrap();
    fails(&out, exit::UNAVAILABLE, &[&link, "device gone"]);
    let rec = recording::read(&csv).expect("rows up to the loss are valid");
    assert!(rec.channels.len() > 100);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_serial_device_that_does_not_answer_times_out() {
    let (_master, _slave, path) = hil::emu::silent_pty().unwrap();
    let p = path.to_str().unwrap();
    let out = tactile(&["info", "-p", p, "--timeout", "0.05"]);
    fails(
        &out,
        exit::UNAVAILABLE,
        &[p, "no reply to get info after 4 attempts"],
    );
}

#[test]
fn malformed_files_name_the_line_and_field() {
    let dir = scratch("cli-files");
    let p = |n: &str| dir.join(n);
    let s = |q: &Path| q.to_str().unwrap().to_owned();
    let head = "# format = tactile-recording/1\n# sample_rate_hz = 1000\n# contact_angle_deg = 0\n# azimuth_deg = 0\n# fingertip_radius_mm = 20\n# gain_fz = 1\n# gain_mx = 1\n# gain_my = 1\n# excitation_V = 3.3\nt_s,rod_mm,load_N,fz_V,mx_V,my_V\n";
    std::fs::write(
        p("bad-number.csv"),
        format!("{head}0,,,1,2,3\n0.001,,,1,oops,3\n"),
    )
    .unwrap();
    std::fs::write(p("no-key.csv"), head.replace("# gain_mx = 1\n", "")).unwrap();
    std::fs::write(
        p("back-in-time.csv"),
        format!("{head}1,,,1,2,3\n0.5,,,1,2,3\n"),
    )
    .unwrap();
    std::fs::write(p("empty.csv"), "").unwrap();
    std::fs::write(p("binary.csv"), [0xffu8, 0xfe, 0, 1, 2, 0x80]).unwrap();
    std::fs::write(p("truncated.csv"), format!("{head}0,,,1,2")).unwrap();
    fails(
        &tactile(&["plot", &s(&p("bad-number.csv"))]),
        exit::DATA,
        &["bad-number.csv: line 12", "mx_V"],
    );
    fails(
        &tactile(&["plot", &s(&p("no-key.csv"))]),
        exit::DATA,
        &["no-key.csv", "gain_mx"],
    );
    fails(
        &tactile(&["plot", &s(&p("back-in-time.csv"))]),
        exit::DATA,
        &["back-in-time.csv: line 12", "t_s"],
    );
    fails(
        &tactile(&["plot", &s(&p("empty.csv"))]),
        exit::DATA,
        &["empty.csv: line 1", "header"],
    );
    fails(
        &tactile(&["plot", &s(&p("binary.csv"))]),
        exit::DATA,
        &["binary.csv: line 1", "UTF-8"],
    );
    fails(
        &tactile(&["plot", &s(&p("truncated.csv"))]),
        exit::DATA,
        &["truncated.csv: line 11", "mx_V", "no line end"],
    );
    fails(
        &tactile(&["plot", &s(&p("missing.csv"))]),
        exit::NO_INPUT,
        &["missing.csv"],
    );
    std::fs::write(
        p("garbage.bin"),
        (0..5000u32)
            .map(|i| (i * 7 % 251) as u8 + 1)
            .collect::<Vec<u8>>(),
    )
    .unwrap();
    fails(
        &tactile(&["replay", &s(&p("garbage.bin"))]),
        exit::DATA,
        &["garbage.bin"],
    );
    let mut fake_mcap = b"\x89MCAP0\r\n".to_vec();
    fake_mcap.extend([1, 2, 3]);
    std::fs::write(p("broken.mcap"), fake_mcap).unwrap();
    fails(
        &tactile(&["replay", &s(&p("broken.mcap"))]),
        exit::DATA,
        &["broken.mcap"],
    );
    std::fs::write(p("cal.txt"), "1 0 0\n0 1 x\n0 0 1\n").unwrap();
    fails(
        &tactile(&[
            "config",
            "-p",
            "/nonexistent/tty",
            "--calibration",
            &s(&p("cal.txt")),
        ]),
        exit::DATA,
        &["cal.txt:2", "calibration"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_flags_and_out_of_range_numbers_are_usage_errors() {
    for args in [
        &["log", "--bogus"][..],
        &["log", "-p", "/dev/null", "--duration", "-1"],
        &["log", "-p", "/dev/null", "--duration", "nan"],
        &["tare", "-p", "/dev/null", "--samples", "0"],
        &["tare", "-p", "/dev/null", "--samples", "70000"],
        &["config", "-p", "/dev/null", "--smoother-alpha", "2"],
        &["config", "-p", "/dev/null", "--butterworth-order", "3"],
        &["config", "-p", "/dev/null", "--rate", "0"],
        &["info", "-p", "/dev/null", "--timeout", "0"],
        &["plot", "x.csv", "--format", "gif"],
        &["log"],
    ] {
        let out = tactile(args);
        // Usage errors exit with EX_USAGE (64) and name the offending flag or value.
        fails(&out, 64, &[]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("error:"), "{args:?}: {err}");
    }
}

#[test]
fn help_is_complete_for_every_subcommand() {
    let top = tactile(&["--help"]);
    assert!(top.status.success());
    let text = String::from_utf8_lossy(&top.stdout);
    for sub in [
        "list", "info", "log", "tare", "config", "replay", "plot", "simulate", "diagnose",
    ] {
        assert!(text.contains(sub), "{sub} missing from --help");
        let h = tactile(&[sub, "--help"]);
        assert!(h.status.success(), "{sub} --help failed");
        assert!(
            String::from_utf8_lossy(&h.stdout).contains("Usage:"),
            "{sub}"
        );
    }
    let log = String::from_utf8_lossy(&tactile(&["log", "--help"]).stdout).into_owned();
    for flag in [
        "--port",
        "--out",
        "--mcap",
        "--duration",
        "--reference",
        "--align",
        "--live",
        "--no-reconnect",
    ] {
        assert!(log.contains(flag), "log --help lacks {flag}");
    }
}

#[test]
fn a_broken_pipe_is_a_clean_exit() {
    let dir = scratch("cli-pipe");
    let cfg = EmuConfig::new(dir.join("tactile0"));
    let emu = Emulator::spawn(cfg.clone()).unwrap();
    let csv = dir.join("r.csv");
    let st = Command::new(env!("CARGO_BIN_EXE_tactile"))
        .args(["log", "-q", "--duration", "1.5", "-p"])
        .arg(&cfg.link)
        .arg("-o")
        .arg(&csv)
        .status()
        .unwrap();
    assert!(st.success());
    drop(emu);
    // `tactile replay r.mcap | head -1`
    let mut child = Command::new(env!("CARGO_BIN_EXE_tactile"))
        .arg("replay")
        .arg(dir.join("r.mcap"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 16];
    use std::io::Read;
    child
        .stdout
        .as_mut()
        .unwrap()
        .read_exact(&mut first)
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "exit {:?}: {err}", out.status);
    assert!(!err.contains("error") && !err.contains("panicked"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
