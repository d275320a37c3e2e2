//! `tactile diagnose A.csv B.csv ... --out-dir DIR` (and a folder instead of files) through the
//! binary: every recording's OUT.json and report, `summary.csv` and `summary.html`, one stderr
//! line and exit 65 for a corrupt file among good ones, exit 0 when all are good, OUT.json the
//! same as the single-recording command's.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const GOOD: usize = 20;

fn tactile() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tactile"))
}

fn fresh_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tactile-session-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Recording `i`: 100 Hz, one short cycle; every third hides a relaxation whose tau drifts,
/// every fourth an AC coupling.
fn simulate(i: usize, out: &Path) -> std::process::Child {
    let mut cmd = tactile();
    cmd.args(["simulate", "--contact-angle", "20", "--azimuth", "60"])
        .args(["--rate", "100", "--recovery-s", "15", "--seed"])
        .arg((i + 1).to_string())
        .args([
            "--noise-v",
            "0.002",
            "--noise-load-n",
            "0.02",
            "--peak-load",
        ])
        .arg(format!("{}", 40 + i))
        .arg("--out")
        .arg(out);
    if i % 3 == 0 {
        let tau = 2.0 + 0.1 * i as f64;
        cmd.arg("--effect")
            .arg(format!("viscoelastic_relaxation:tau_s={tau},fraction=0.3"));
    }
    if i % 4 == 1 {
        cmd.args(["--effect", "highpass_coupling:tau_s=30"]);
    }
    cmd.spawn().unwrap()
}

/// `GOOD` recordings `rec-00.csv`... in `dir`, simulated side by side.
fn recordings(dir: &Path) -> Vec<PathBuf> {
    let paths: Vec<PathBuf> = (0..GOOD)
        .map(|i| dir.join(format!("rec-{i:02}.csv")))
        .collect();
    let children: Vec<_> = paths
        .iter()
        .enumerate()
        .map(|(i, p)| simulate(i, p))
        .collect();
    for mut child in children {
        assert!(child.wait().unwrap().success());
    }
    paths
}

/// The records of an RFC 4180 text (quoted fields may hold commas, quotes and line ends).
fn parse_csv(text: &str) -> Vec<Vec<String>> {
    let (mut rows, mut row, mut field) = (Vec::new(), Vec::new(), String::new());
    let (mut quoted, mut chars) = (false, text.chars().peekable());
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => quoted = true,
            (false, ',') => row.push(std::mem::take(&mut field)),
            (false, '\r') => {}
            (false, '\n') => {
                row.push(std::mem::take(&mut field));
                rows.push(std::mem::take(&mut row));
            }
            (false, c) => field.push(c),
        }
    }
    rows
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The summary's rows as maps from its header.
fn summary(dir: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let rows = parse_csv(&std::fs::read_to_string(dir.join("summary.csv")).unwrap());
    let header = &rows[0];
    rows[1..]
        .iter()
        .map(|r| {
            assert_eq!(r.len(), header.len(), "{r:?}");
            header.iter().cloned().zip(r.iter().cloned()).collect()
        })
        .collect()
}

#[test]
fn a_session_with_a_corrupt_file_analyses_the_rest_and_exits_65() {
    let dir = fresh_dir("in");
    let paths = recordings(&dir);
    // A copy of a good recording cut a few bytes into a row: a torn last line.
    let text = std::fs::read(&paths[0]).unwrap();
    let row_start = 1 + text[..text.len() / 2]
        .iter()
        .rposition(|&b| b == b'\n')
        .unwrap();
    std::fs::write(dir.join("bad.csv"), &text[..row_start + 4]).unwrap();
    let out_dir = fresh_dir("out");
    let out = tactile()
        .arg("diagnose")
        .arg(&dir)
        .arg("--out-dir")
        .arg(&out_dir)
        .output()
        .unwrap();
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(65), "{err}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(
        lines[0].contains("bad.csv") && lines[0].contains("line "),
        "{err}"
    );
    for p in &paths {
        let stem = p.file_stem().unwrap().to_str().unwrap();
        let json = std::fs::read_to_string(out_dir.join(format!("{stem}.json"))).unwrap();
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(v["format"], "tactile-diagnosis/1");
        assert_eq!(v["recording"], p.display().to_string());
        assert!(out_dir.join(format!("{stem}.html")).exists());
    }
    assert!(!out_dir.join("bad.json").exists());
    let rows = summary(&out_dir);
    assert_eq!(rows.len(), GOOD + 1);
    // The folder's files in sorted order: bad.csv first.
    assert!(rows[0]["file"].ends_with("bad.csv") && rows[0]["status"] == "error");
    assert!(rows[0]["error"].contains("bad.csv") && rows[0]["error"].contains("line "));
    for (row, p) in rows[1..].iter().zip(&paths) {
        assert_eq!(row["file"], p.display().to_string());
        assert_eq!(row["status"], "ok", "{row:?}");
        assert!(row["error"].is_empty() && row["youngs_modulus_Pa"].parse::<f64>().unwrap() > 0.0);
    }
    let relaxed = rows
        .iter()
        .filter(|r| r["effects"].contains("viscoelastic_relaxation"))
        .count();
    assert!(
        relaxed >= 3,
        "relaxation found in only {relaxed} recordings"
    );
    let html = std::fs::read_to_string(out_dir.join("summary.html")).unwrap();
    let params = rows[0].keys().filter(|k| k.ends_with("_stderr")).count();
    assert!(params >= 1);
    // The baseline's modulus and each effect parameter.
    assert_eq!(html.matches("<svg").count(), 1 + params);
    assert!(html.contains("tau_s [s]") && html.contains("bad.csv"));
    std::fs::remove_dir_all(&dir).unwrap();
    std::fs::remove_dir_all(&out_dir).unwrap();
}

#[test]
fn a_session_of_good_files_exits_0_with_the_single_commands_json() {
    let dir = fresh_dir("good");
    let paths: Vec<PathBuf> = (0..2)
        .map(|i| {
            let p = dir.join(format!("good-{i}.csv"));
            assert!(simulate(i, &p).wait().unwrap().success());
            p
        })
        .collect();
    let out_dir = dir.join("out");
    let out = tactile()
        .arg("diagnose")
        .args(&paths)
        .arg("--out-dir")
        .arg(&out_dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stderr(&out).is_empty(), "{}", stderr(&out));
    assert_eq!(summary(&out_dir).len(), 2);
    let single = dir.join("single.json");
    let out = tactile()
        .arg("diagnose")
        .arg(&paths[1])
        .arg("--json")
        .arg(&single)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    let read = |p: &Path| -> serde_json::Value {
        let mut v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
        // Wall time differs from run to run.
        v.as_object_mut().unwrap().remove("seconds");
        v
    };
    assert_eq!(read(&single), read(&out_dir.join("good-1.json")));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn several_recordings_without_out_dir_are_a_usage_error() {
    let out = tactile()
        .args(["diagnose", "a.csv", "b.csv", "--json", "x.json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(64), "{}", stderr(&out));
    assert!(stderr(&out).contains("--out-dir"), "{}", stderr(&out));
}
