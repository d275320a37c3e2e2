//! `tactile import` through the binary: a small Mach-1 export and a semicolon CSV become
//! recordings the reader accepts, with the sensor columns not measured; broken exports are one
//! line naming file, line and field, exit 65. A sensor's log with a reference's (the committed
//! synthetic pair, and the real eFlesh pair where it is present) become one recording.

use std::path::PathBuf;

use sysexit as exit;

mod common;
use common::{fails, tactile};

const MACH1: &str = "<Mach-1 File>\r\n<INFO>\r\nLoad Cell Type:\tSingle-axis\r\n<END INFO>\r\n\
<Find Contact>\r\n<DATA>\r\nTime, s\tPosition (z), mm\tFz, gf\r\n0.00\t-3.0\t0\r\n0.01\t-2.9\t0.1\r\n<END DATA>\r\n\
<Stress Relaxation>\r\n<DATA>\r\nTime, s\tPosition (z), mm\tPosition (x), mm\tFz, gf\r\n\
0.00\t-2.7942\t0\t0.0\r\n0.01\t-2.7900\t0\t1.0\r\n0.02\t-2.7800\t0\t2.0\r\n0.03\t-2.7800\t0\t1.5\r\n<divider>\r\n<END DATA>\r\n";

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("tactile-import-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn s(p: &std::path::Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn mach1_block_imports_and_lists() {
    let d = dir();
    let input = d.join("m.txt");
    std::fs::write(&input, MACH1).unwrap();
    let list = tactile(&["import", s(&input), "--list"]);
    assert!(list.status.success());
    let text = String::from_utf8_lossy(&list.stdout);
    assert!(text.contains("1\tFind Contact\t2 rows"), "{text}");
    assert!(text.contains("2\tStress Relaxation\t4 rows"), "{text}");
    let out = d.join("m.csv");
    let run = tactile(&[
        "import",
        s(&input),
        "--test",
        "stress relaxation",
        "-o",
        s(&out),
        "--radius-mm",
        "0.5",
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let rec = recording::read(&out).unwrap();
    assert_eq!(rec.channels.len(), 4);
    assert_eq!(rec.meta.sample_rate_hz, 100.0);
    assert_eq!(rec.meta.fingertip_radius_mm, 0.5);
    assert!(!rec.measured("fz_V") && rec.measured("load_N"));
    assert!(rec
        .meta
        .source
        .as_deref()
        .unwrap()
        .contains("block 2 (Stress Relaxation)"));
    fails(
        &tactile(&["import", s(&input), "--radius-mm", "2", "-o", s(&out)]),
        exit::DATA,
        &["m.txt:1", "--block"],
    );
}

#[test]
fn csv_imports_with_units_and_sign() {
    let d = dir();
    let input = d.join("c.csv");
    std::fs::write(
        &input,
        "machine X\nTime;Ext;Load\n0;100;0\n10;110;-1\n20;130;-2\n",
    )
    .unwrap();
    let out = d.join("c-rec.csv");
    let run = tactile(&[
        "import",
        s(&input),
        "--format",
        "csv",
        "--skip-rows",
        "1",
        "--time-col",
        "Time",
        "--disp-col",
        "Ext",
        "--force-col",
        "3",
        "--time-unit",
        "ms",
        "--disp-unit",
        "um",
        "--force-unit",
        "kgf",
        "--radius-mm",
        "2",
        "-o",
        s(&out),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let rec = recording::read(&out).unwrap();
    assert_eq!(rec.meta.sample_rate_hz, 100.0);
    assert!((rec.channels.load_n[2] + 2.0 * 9.80665).abs() < 1e-9);
}

#[test]
fn broken_exports_exit_65_naming_line_and_field() {
    let d = dir();
    let out = d.join("never.csv");
    let cases = [
        (
            "trunc.txt",
            MACH1.replace("<divider>\r\n<END DATA>\r\n", ""),
            "trunc.txt:17: field <END DATA>",
        ),
        (
            "nodata.txt",
            MACH1.replace(
                "<Stress Relaxation>\r\n<DATA>\r\n",
                "<Stress Relaxation>\r\n",
            ),
            "nodata.txt:11: field <DATA>",
        ),
        (
            "text.txt",
            MACH1.replace("0.01\t-2.7900", "0.01\tabc"),
            "text.txt:15: field Position (z), mm",
        ),
        (
            "unit.txt",
            MACH1.replace("Fz, gf\r\n0.00\t-2.7942", "Fz, oz\r\n0.00\t-2.7942"),
            "unit.txt:13: field Fz, oz: unknown",
        ),
    ];
    for (name, text, needle) in cases {
        let input = d.join(name);
        std::fs::write(&input, text).unwrap();
        fails(
            &tactile(&[
                "import",
                s(&input),
                "--block",
                "2",
                "--radius-mm",
                "2",
                "-o",
                s(&out),
            ]),
            exit::DATA,
            &[needle],
        );
    }
    let input = d.join("unknown-unit.csv");
    std::fs::write(&input, "t,d,f\n0,0,0\n1,1,1\n").unwrap();
    // A unit the command does not know is a usage error, named with the flag.
    fails(
        &tactile(&[
            "import",
            s(&input),
            "--format",
            "csv",
            "--force-unit",
            "stone",
            "--radius-mm",
            "2",
            "-o",
            s(&out),
        ]),
        exit::USAGE,
        &["--force-unit", "unknown unit \"stone\""],
    );
    assert!(!out.exists());
}

#[test]
fn a_missing_export_names_the_file_and_says_why_once() {
    let out = tactile(&[
        "import",
        "/nonexistent/export.txt",
        "--radius-mm",
        "2",
        "-o",
        "/tmp/never.csv",
    ]);
    fails(&out, exit::NO_INPUT, &["/nonexistent/export.txt"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        err.matches("os error 2").count(),
        1,
        "the cause said twice: {err}"
    );
}

/// An import writes only what it is told or can read: without a radius it writes nothing
/// (the format requires `fingertip_radius_mm`, and a default would pass for a measured one);
/// `--sensor-id` is recorded as `sensor`, by which a session refuses another instrument.
#[test]
fn an_import_says_which_sensor_and_invents_no_radius() {
    let d = dir();
    let input = d.join("plain.csv");
    std::fs::write(
        &input,
        "t,z,f\n0,0,0\n0.1,0.1,0.5\n0.2,0.2,1.0\n0.3,0.3,1.6\n",
    )
    .unwrap();
    let out = d.join("plain-rec.csv");
    fails(
        &tactile(&["import", "--format", "csv", s(&input), "-o", s(&out)]),
        exit::USAGE,
        &["--radius-mm"],
    );
    assert!(!out.exists(), "an import without a radius wrote a file");
    let run = tactile(&[
        "import",
        "--format",
        "csv",
        s(&input),
        "--radius-mm",
        "0.5",
        "--sensor-id",
        "rig-7 cell 123",
        "-o",
        s(&out),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let rec = recording::read(&out).unwrap();
    assert_eq!(rec.meta.fingertip_radius_mm, 0.5);
    assert_eq!(rec.meta.get("sensor"), Some("rig-7 cell 123"));
    assert!(!rec
        .meta
        .source
        .as_deref()
        .unwrap()
        .contains("hardware/ written"));
    // Another instrument's import: one session refuses the pair by name, writing nothing.
    let other = d.join("other-rec.csv");
    let run = tactile(&[
        "import",
        "--format",
        "csv",
        s(&input),
        "--radius-mm",
        "0.5",
        "--sensor-id",
        "skin-2",
        "-o",
        s(&other),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let json = d.join("session.json");
    fails(
        &tactile(&[
            "diagnose",
            "--joint",
            s(&out),
            s(&other),
            "--json",
            s(&json),
        ]),
        exit::DATA,
        &[
            "other-rec.csv: sensor = skin-2",
            "plain-rec.csv has sensor = rig-7 cell 123",
        ],
    );
    assert!(!json.exists());
}
