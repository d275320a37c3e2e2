//! `tactile simulate` and `tactile diagnose` end to end through the binary: the contract's command
//! lines, OUT.json's fields, exit codes and one-line errors.

use std::path::PathBuf;
use std::process::Command;

fn tactile() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tactile"))
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tactile-diagnosis-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn simulate_then_diagnose_per_contract() {
    let rec = temp("vh.csv");
    let out = tactile()
        .args([
            "simulate",
            "--contact-angle",
            "20",
            "--azimuth",
            "60",
            "--peak-load",
            "50",
            "--out",
        ])
        .arg(&rec)
        .args([
            "--rate",
            "250",
            "--noise-v",
            "0.002",
            "--noise-load-n",
            "0.02",
        ])
        .args([
            "--effect",
            "viscoelastic_relaxation:tau_s=3,fraction=0.3",
            "--effect",
            "highpass_coupling:tau_s=40",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = temp("vh.json");
    let report = temp("vh-report");
    let out = tactile()
        .arg("diagnose")
        .arg(&rec)
        .arg("--json")
        .arg(&json)
        .arg("--report")
        .arg(&report)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["format"], "tactile-diagnosis/1");
    assert_eq!(v["recording"], rec.display().to_string());
    let verdict = v["verdict"].as_str().unwrap();
    assert!([
        "no_significant_mismatch",
        "explained",
        "partially_explained",
        "unexplained"
    ]
    .contains(&verdict));
    assert!(
        v["baseline"]["params"]["youngs_modulus_Pa"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    for m in v["mismatches"].as_array().unwrap() {
        assert!(["rest", "loading", "hold", "release", "recovery"]
            .contains(&m["regime"].as_str().unwrap()));
        for k in ["channel", "t_start_s", "t_end_s", "rms", "share"] {
            assert!(!m[k].is_null(), "mismatch lacks {k}");
        }
    }
    let names: Vec<&str> = v["effects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    assert!(
        names.contains(&"viscoelastic_relaxation") && names.contains(&"highpass_coupling"),
        "{names:?}"
    );
    let ve = v["effects"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["name"] == "viscoelastic_relaxation")
        .unwrap();
    assert!((ve["params"]["tau_s"].as_f64().unwrap() - 3.0).abs() < 0.6);
    assert!(ve["param_stderr"]["tau_s"].as_f64().unwrap() > 0.0);
    assert!(!ve["evidence"].as_str().unwrap().is_empty());
    let fit = &v["fit"];
    assert!(fit["rmse_after"].as_f64().unwrap() < fit["rmse_before"].as_f64().unwrap());
    let h = &fit["heldout"];
    assert!(h["rmse_after"].as_f64().unwrap() < 0.5 * h["rmse_before"].as_f64().unwrap());
    assert!(h["t_end_s"].as_f64().unwrap() > h["t_start_s"].as_f64().unwrap());
    // `--report DIR` (no .html) still means a folder; the report is one file in it.
    let html = std::fs::read_to_string(report.join("report.html")).unwrap();
    assert!(html.contains("Viscoelastic relaxation") && html.contains("<svg"));
    assert_eq!(
        std::fs::read_dir(&report).unwrap().count(),
        1,
        "one file, nothing loose"
    );
}

#[test]
fn malformed_recording_is_a_one_line_data_error() {
    let rec = temp("bad.csv");
    std::fs::write(
        &rec,
        "# format = tactile-recording/1\nt_s,rod_mm,load_N,fz_V,mx_V,my_V\n0,0,0,0,0,0\n",
    )
    .unwrap();
    let out = tactile()
        .arg("diagnose")
        .arg(&rec)
        .arg("--json")
        .arg(temp("bad.json"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(65));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("line 2") && err.contains("sample_rate_hz"),
        "{err}"
    );
}

#[test]
fn missing_recording_is_no_input() {
    let out = tactile()
        .args(["diagnose", "/nonexistent/rec.csv", "--json"])
        .arg(temp("x.json"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(66));
}

/// The contract's own command lines with nothing added: `simulate` writes the baseline model's
/// own recording, noise-free, so its diagnosis has nothing to report. Its residual is the
/// arithmetic's (about 1e-11 of each range), structured but no mismatch.
#[test]
fn the_baselines_own_noise_free_recording_is_no_mismatch() {
    let rec = temp("own.csv");
    let out = tactile()
        .args(["simulate", "--contact-angle", "10", "--azimuth", "0"])
        .args(["--peak-load", "60", "--rate", "250", "--out"])
        .arg(&rec)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = temp("own.json");
    let out = tactile()
        .arg("diagnose")
        .arg(&rec)
        .arg("--json")
        .arg(&json)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    assert_eq!(v["verdict"], "no_significant_mismatch", "{v}");
    assert!(v["effects"].as_array().unwrap().is_empty(), "{v}");
    // Nothing undecided is an empty list, not an absent field (as in the session's output).
    assert_eq!(v["undecided"], serde_json::json!([]), "{v}");
}
