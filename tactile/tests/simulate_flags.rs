//! `tactile simulate`'s flags as a user writes them, and the help texts: `--peak-load` is the
//! recorded load's peak whatever the effects on the load, `--rod-speed` sets the protocol's
//! speed, `--gain` takes the comma form its help shows, `--effect` lists the catalogue; `tactile
//! --help` says what the tool does, `diagnose --help` the batch and the joint modes.

use std::path::PathBuf;
use std::process::{Command, Output};

fn tactile(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tactile"))
        .args(args)
        .output()
        .unwrap()
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tactile-simflags-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// `simulate` of a short test at 100 Hz with `more` flags into `name`, read back.
fn simulate(name: &str, more: &[&str]) -> recording::Recording {
    let out = temp(name);
    let path = out.to_str().unwrap();
    let base = [
        "simulate",
        "--contact-angle",
        "20",
        "--azimuth",
        "30",
        "--rate",
        "100",
        "--recovery-s",
        "5",
        "--out",
        path,
    ];
    let o = tactile(&[&base[..], more].concat());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    recording::read(&out).unwrap()
}

fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
}

#[test]
fn the_peak_load_is_the_recorded_loads_peak_with_a_relaxation() {
    let relaxation = "viscoelastic_relaxation:tau_s=4,fraction=0.3";
    let rec = simulate(
        "relaxed.csv",
        &["--peak-load", "40", "--effect", relaxation],
    );
    let peak = max(&rec.channels.load_n);
    assert!(
        (peak - 40.0).abs() < 1e-3,
        "recorded peak {peak} N, asked 40 N"
    );
    // Two cycles, the second smaller: each stops at its own peak.
    let rec = simulate(
        "relaxed-twice.csv",
        &[
            "--peak-load",
            "40",
            "--then-peak-load",
            "25",
            "--effect",
            relaxation,
            "--effect",
            "hysteresis:width=0.1",
        ],
    );
    // The cycles split where the rod is back at its start after the first press.
    let (rod, load) = (&rec.channels.rod_mm, &rec.channels.load_n);
    let pressed = rod.iter().position(|&r| r > 0.0).unwrap();
    let back = pressed + rod[pressed..].iter().position(|&r| r <= rod[0]).unwrap();
    let (first, second) = (max(&load[..back]), max(&load[back..]));
    assert!((first - 40.0).abs() < 1e-3, "first cycle's peak {first} N");
    assert!(
        (second - 25.0).abs() < 1e-3,
        "second cycle's peak {second} N"
    );
}

#[test]
fn rod_speed_and_gains_are_set_as_written() {
    let rec = simulate(
        "fast.csv",
        &[
            "--peak-load",
            "10",
            "--rod-speed",
            "60",
            "--gain",
            "2000,200,200",
        ],
    );
    assert_eq!(rec.meta.rod_speed_mm_per_min, Some(60.0));
    assert_eq!(
        [rec.meta.gain_fz, rec.meta.gain_mx, rec.meta.gain_my],
        [2000.0, 200.0, 200.0]
    );
    // The rod moves at 60 mm/min while it loads: 1 mm a second.
    let (t, rod) = (&rec.channels.t_s, &rec.channels.rod_mm);
    let i = rod.iter().position(|&r| r > 1.0).unwrap();
    let speed = (rod[i + 10] - rod[i]) / (t[i + 10] - t[i]) * 60.0;
    assert!((speed - 60.0).abs() < 1e-6, "{speed} mm/min");
    // The three values as three words still work; a wrong count is a usage error naming the
    // flag and its form.
    let spaced = simulate(
        "spaced.csv",
        &["--peak-load", "10", "--gain", "2000", "200", "200"],
    );
    assert_eq!(spaced.meta.gain_fz, 2000.0);
    let o = tactile(&[
        "simulate",
        "--contact-angle",
        "0",
        "--azimuth",
        "0",
        "--peak-load",
        "2",
        "--gain",
        "1,2",
        "--out",
        "/nonexistent/never.csv",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(64), "{err}");
    assert!(
        err.contains("--gain takes 3 numbers, FZ,MX,MY (got 2)"),
        "{err}"
    );
    for bad in ["0", "-5", "nan"] {
        let o = tactile(&[
            "simulate",
            "--contact-angle",
            "0",
            "--azimuth",
            "0",
            "--peak-load",
            "2",
            "--rod-speed",
            bad,
            "--out",
            "/nonexistent/never.csv",
        ]);
        assert_eq!(
            o.status.code(),
            Some(64),
            "{bad}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

const EFFECTS: [&str; 11] = [
    "viscoelastic_relaxation",
    "hysteresis",
    "highpass_coupling",
    "thermal_drift",
    "stiffening",
    "crosstalk",
    "amplifier_saturation",
    "time_offset",
    "mains_interference",
    "bridge_nonlinearity",
    "contact_friction",
];

#[test]
fn an_unknown_effect_is_answered_with_the_catalogue_and_the_help_lists_it() {
    let o = tactile(&[
        "simulate",
        "--contact-angle",
        "0",
        "--azimuth",
        "0",
        "--peak-load",
        "2",
        "--effect",
        "foo",
        "--out",
        "/nonexistent/never.csv",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(64), "{err}");
    assert!(err.contains("unknown effect `foo`"), "{err}");
    let help = String::from_utf8_lossy(&tactile(&["simulate", "--help"]).stdout).into_owned();
    for name in EFFECTS {
        assert!(err.contains(name), "{name} not in: {err}");
        assert!(help.contains(name), "{name} not in simulate --help");
    }
    assert!(
        help.contains("--rod-speed") && help.contains("FZ,MX,MY"),
        "{help}"
    );
}

#[test]
fn the_help_says_what_the_tool_and_diagnose_do() {
    let top = String::from_utf8_lossy(&tactile(&["--help"]).stdout).into_owned();
    assert!(
        top.starts_with("Record, simulate and diagnose a soft fingertip's force/moment sensor"),
        "{top}"
    );
    assert!(!top.contains("argument parsing"), "{top}");
    for command in ["list", "log", "simulate", "diagnose", "prove", "import"] {
        assert!(top.contains(&format!("  {command} ")), "{command}: {top}");
    }
    let diagnose = String::from_utf8_lossy(&tactile(&["diagnose", "--help"]).stdout).into_owned();
    assert!(
        !diagnose.contains("More than one needs --out-dir"),
        "{diagnose}"
    );
    for says in [
        "Batch",
        "--joint",
        "one session",
        "--out-dir DIR diagnoses each alone",
    ] {
        assert!(diagnose.contains(says), "{says}: {diagnose}");
    }
}
