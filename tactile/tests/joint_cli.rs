//! `tactile diagnose --joint` end to end through the binary (`docs/session-format.md`): a
//! rotated chip that one recording at an axis-aligned azimuth cannot tell from its moment gains
//! is found, shared, across three azimuths; a bad file is a row with its error and exit 65, the
//! others still diagnosed; nothing analysable is a one-line error and no OUT.json (a missing
//! input, refused before any work: `session_inputs.rs`).

use std::path::{Path, PathBuf};
use std::process::Command;

fn tactile() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tactile"))
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tactile-joint-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn simulate(out: &Path, azimuth: &str, seed: &str) {
    let o = tactile()
        .args(["simulate", "--contact-angle", "20", "--azimuth", azimuth])
        .args(["--peak-load", "40", "--rate", "200", "--recovery-s", "30"])
        .args([
            "--noise-v",
            "0.002",
            "--noise-load-n",
            "0.02",
            "--seed",
            seed,
        ])
        .args(["--effect", "crosstalk:angle_deg=8"])
        .arg("--out")
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn session(name: &str) -> PathBuf {
    let d = dir(name);
    for (az, seed) in [("0", "1"), ("45", "2"), ("90", "3")] {
        simulate(&d.join(format!("az{az}.csv")), az, seed);
    }
    d
}

/// `tactile diagnose --joint DIR --json JSON`.
fn joint(dir: &Path, json: &Path) -> std::process::Output {
    tactile()
        .args(["diagnose", "--joint", "--quiet"])
        .arg(dir)
        .arg("--json")
        .arg(json)
        .output()
        .unwrap()
}

fn read(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_rotated_chip_is_shared_across_azimuths_and_validated_left_out() {
    let d = session("rotated");
    let json = d.join("out.json");
    let o = joint(&d, &json);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v = read(&json);
    assert_eq!(v["format"], "tactile-session-diagnosis/1");
    let rows = v["recordings"].as_array().unwrap();
    let files: Vec<&str> = rows.iter().map(|r| r["file"].as_str().unwrap()).collect();
    assert_eq!(files, ["az0.csv", "az45.csv", "az90.csv"]);
    let shared = v["shared"].as_array().unwrap();
    let names: Vec<&str> = shared.iter().map(|s| s["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["crosstalk"], "{v:#}");
    let angle = shared[0]["params"]["angle_deg"].as_f64().unwrap();
    assert!((angle - 8.0).abs() < 1.6, "crosstalk {angle} deg, truth 8");
    // Named once, in `shared`, never again under a recording.
    for r in rows {
        assert!(r["effects"]
            .as_array()
            .unwrap()
            .iter()
            .all(|e| e["name"] != "crosstalk"));
        assert!(r["fit"]["heldout"]["rmse_after"]
            .as_f64()
            .unwrap()
            .is_finite());
    }
    let loo = v["validation"]["leave_one_out"].as_array().unwrap();
    assert_eq!(loo.len(), 3);
    let ratio: f64 = loo
        .iter()
        .map(|l| l["rmse_after"].as_f64().unwrap() / l["rmse_before"].as_f64().unwrap())
        .sum::<f64>()
        / 3.0;
    assert!(ratio < 1.0, "leave-one-out after/before {ratio}");
    // Two azimuths decide what one could not: no turn of the moment scales is left open.
    let undecided = v["undecided"].as_array().unwrap();
    assert!(undecided
        .iter()
        .all(|u| !u["effects"].to_string().contains("crosstalk")));
}

#[test]
fn a_bad_file_is_its_row_and_the_session_goes_on() {
    let d = session("bad");
    std::fs::write(d.join("broken.csv"), "t_s,rod_mm\n0,zero\n").unwrap();
    let json = d.join("out.json");
    let o = joint(&d, &json);
    assert_eq!(
        o.status.code(),
        Some(65),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("broken.csv"), "{stderr}");
    let v = read(&json);
    let rows = v["recordings"].as_array().unwrap();
    assert_eq!(rows.len(), 4);
    let broken = rows.iter().find(|r| r["file"] == "broken.csv").unwrap();
    assert!(broken["error"].as_str().unwrap().contains("broken.csv"));
    assert!(broken.get("verdict").is_none());
    assert_eq!(
        rows.iter().filter(|r| r.get("verdict").is_some()).count(),
        3
    );
}

#[test]
fn nothing_analysable_is_an_error_without_output() {
    let d = dir("none");
    std::fs::write(d.join("a.csv"), "nonsense\n").unwrap();
    std::fs::write(d.join("b.csv"), "t_s,rod_mm\n").unwrap();
    let json = d.join("out.json");
    let o = tactile()
        .args(["diagnose", "--joint", "--quiet"])
        .arg(d.join("a.csv"))
        .arg(d.join("b.csv"))
        .arg("--json")
        .arg(&json)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(65));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("a.csv") && stderr.contains("b.csv"),
        "{stderr}"
    );
    assert!(!json.exists());
    let o = tactile()
        .args(["diagnose", "--joint"])
        .arg(d.join("a.csv"))
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(64),
        "--joint without --json is a usage error"
    );
}
