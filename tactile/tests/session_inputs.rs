//! Inputs and outputs that go wrong around `tactile diagnose --joint` and the batch
//! (`--out-dir`), through the binary (`docs/session-format.md`, "One sensor, one list of
//! files"; `docs/bad-input.md`): every refusal is one line naming what is wrong, with its exit
//! code, before any work and with nothing written.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn tactile() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tactile"))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tactile-inputs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A short recording at `azimuth` (a few seconds of a small press, 50 Hz): quick to diagnose.
fn simulate(out: &Path, azimuth: &str, seed: &str) {
    let o = tactile()
        .args(["simulate", "--contact-angle", "20", "--azimuth", azimuth])
        .args(["--peak-load", "5", "--rate", "50", "--recovery-s", "8"])
        .args([
            "--noise-v",
            "0.002",
            "--noise-load-n",
            "0.02",
            "--seed",
            seed,
        ])
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// `file` with its metadata key `key` set to `value` (added after `format` if absent).
fn set_meta(file: &Path, key: &str, value: &str) {
    let text = std::fs::read_to_string(file).unwrap();
    let prefix = format!("# {key} = ");
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    match lines.iter().position(|l| l.starts_with(&prefix)) {
        Some(i) => lines[i] = format!("{prefix}{value}"),
        None => lines.insert(1, format!("{prefix}{value}")),
    }
    std::fs::write(file, lines.join("\n") + "\n").unwrap();
}

/// The one stderr line of a failed run, after checking its exit code.
fn refused(o: &Output, code: i32) -> String {
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(code), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    err
}

fn run(args: &[&dyn AsRef<std::ffi::OsStr>]) -> Output {
    let mut c = tactile();
    for a in args {
        c.arg(a);
    }
    c.arg("--quiet").output().unwrap()
}

/// Two recordings `a.csv` (azimuth 0) and `b.csv` (azimuth 90) in a fresh folder.
fn two(name: &str) -> (PathBuf, PathBuf, PathBuf) {
    let d = scratch(name);
    let (a, b) = (d.join("a.csv"), d.join("b.csv"));
    simulate(&a, "0", "1");
    simulate(&b, "90", "2");
    (d, a, b)
}

#[test]
fn another_fingertip_or_device_is_refused_by_name_and_nothing_written() {
    let (d, a, b) = two("other-sensor");
    let json = d.join("out.json");
    set_meta(&b, "fingertip_radius_mm", "12");
    let started = Instant::now();
    let o = run(&[&"diagnose", &"--joint", &a, &b, &"--json", &json]);
    let err = refused(&o, 65);
    assert!(
        err.contains(&format!(
            "{}: fingertip_radius_mm = 12, but {} has fingertip_radius_mm = 20",
            b.display(),
            a.display()
        )),
        "{err}"
    );
    assert!(!err.contains("Newton"), "{err}");
    assert!(started.elapsed() < Duration::from_secs(20), "refused late");
    assert!(!json.exists());
    // The same radius, another device's serial.
    set_meta(&b, "fingertip_radius_mm", "20");
    set_meta(&a, "chip_serial", "0000beef");
    set_meta(&b, "chip_serial", "0000cafe");
    let err = refused(
        &run(&[&"diagnose", &"--joint", &a, &b, &"--json", &json]),
        65,
    );
    assert!(
        err.contains("chip_serial = 0000cafe") && err.contains("chip_serial = 0000beef"),
        "{err}"
    );
    assert!(!json.exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn one_recording_twice_is_refused_naming_both() {
    let (d, a, b) = two("twice");
    let json = d.join("out.json");
    let copy = d.join("copy.csv");
    std::fs::copy(&a, &copy).unwrap();
    let link = d.join("link.csv");
    std::os::unix::fs::symlink(&a, &link).unwrap();
    let dotted = d.join(".").join("a.csv");
    for second in [&a, &dotted, &link, &copy] {
        for mode in [["--joint", "--json"], ["--out-dir", "--out-dir"]] {
            let out: &dyn AsRef<std::ffi::OsStr> = if mode[0] == "--joint" { &json } else { &d };
            let args: Vec<&dyn AsRef<std::ffi::OsStr>> = if mode[0] == "--joint" {
                vec![&"diagnose", &"--joint", &a, &b, second, &"--json", out]
            } else {
                vec![&"diagnose", &a, &b, second, &"--out-dir", out]
            };
            let err = refused(&run(&args), 64);
            assert!(
                err.contains(&format!("{} and {}", a.display(), second.display())),
                "{mode:?} {err}"
            );
            assert!(err.contains("each recording is given once"), "{err}");
        }
    }
    assert!(!json.exists() && !d.join("summary.csv").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn missing_inputs_are_no_input_everywhere() {
    let (d, a, _) = two("missing");
    let missing = d.join("missing.csv");
    let json = d.join("out.json");
    for args in [
        vec![
            &"diagnose" as &dyn AsRef<std::ffi::OsStr>,
            &"--joint",
            &missing,
            &"--json",
            &json,
        ],
        vec![&"diagnose", &"--joint", &a, &missing, &"--json", &json],
        vec![&"diagnose", &a, &missing, &"--out-dir", &d],
        vec![&"diagnose", &missing, &"--json", &json],
    ] {
        let err = refused(&run(&args), 66);
        assert!(err.contains("missing.csv"), "{err}");
    }
    assert!(!json.exists() && !d.join("summary.csv").exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn output_paths_are_checked_before_any_work() {
    let (d, a, b) = two("outputs");
    let json = d.join("out.json");
    let under_a_file = a.join("x.html");
    for args in [
        vec![
            &"diagnose" as &dyn AsRef<std::ffi::OsStr>,
            &"--joint",
            &a,
            &b,
            &"--json",
            &json,
            &"--report",
            &under_a_file,
        ],
        vec![
            &"diagnose",
            &a,
            &"--json",
            &json,
            &"--report",
            &under_a_file,
        ],
        vec![&"diagnose", &"--joint", &a, &b, &"--json", &under_a_file],
    ] {
        let started = Instant::now();
        let err = refused(&run(&args), 73);
        assert!(
            err.contains(&format!(
                "{}: cannot be created: {} is a file, not a folder",
                under_a_file.display(),
                a.display()
            )),
            "{err}"
        );
        assert!(started.elapsed() < Duration::from_secs(20), "refused late");
        assert!(!json.exists(), "the JSON was left behind");
    }
    // An output folder that is a file, an output that is an input, one file for both outputs.
    let err = refused(&run(&[&"diagnose", &a, &b, &"--out-dir", &a]), 73);
    assert!(err.contains("is a file"), "{err}");
    let err = refused(&run(&[&"diagnose", &"--joint", &a, &b, &"--json", &b]), 64);
    assert!(err.contains("is one of the recordings read"), "{err}");
    let page = d.join("same.html");
    let err = refused(
        &run(&[&"diagnose", &a, &"--json", &page, &"--report", &page]),
        64,
    );
    assert!(err.contains("are one file"), "{err}");
    assert_eq!(
        std::fs::read_dir(&d).unwrap().count(),
        2,
        "something written"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// Two recordings that share a file name are a normal session, named by their paths as given;
/// `--json` and `--report` create missing folders alike; `contradicted` and `undecided` are
/// there as lists. In the batch the same two are refused, saying why.
#[test]
fn recordings_sharing_a_file_name_are_a_session_named_by_path() {
    let d = scratch("day1-day2");
    let (day1, day2) = (d.join("day1"), d.join("day2"));
    std::fs::create_dir_all(&day1).unwrap();
    std::fs::create_dir_all(&day2).unwrap();
    simulate(&day1.join("rec.csv"), "0", "1");
    simulate(&day2.join("rec.csv"), "90", "2");
    let (r1, r2) = (day1.join("rec.csv"), day2.join("rec.csv"));
    let json = d.join("new-json").join("out.json");
    let page = d.join("new-page").join("session.html");
    let o = run(&[
        &"diagnose",
        &"--joint",
        &r1,
        &r2,
        &"--json",
        &json,
        &"--report",
        &page,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(page.exists());
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let files: Vec<&str> = v["recordings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["file"].as_str().unwrap())
        .collect();
    assert_eq!(
        files,
        [r1.display().to_string(), r2.display().to_string()],
        "{v:#}"
    );
    for key in ["contradicted", "undecided"] {
        assert!(v[key].is_array(), "{key} missing: {v:#}");
    }
    let out_dir = d.join("batch");
    let err = refused(&run(&[&"diagnose", &r1, &r2, &"--out-dir", &out_dir]), 64);
    assert!(
        err.contains("would both be written to rec.json and rec.html"),
        "{err}"
    );
    assert!(!out_dir.exists());
    let _ = std::fs::remove_dir_all(&d);
}
