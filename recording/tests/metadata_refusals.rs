//! The refusals of `docs/recording-format.md`, "What is refused" and "Quantities not measured":
//! each names the line and the key or column, and a sensor column empty on every row is read as
//! not measured rather than refused.

use recording::{Recording, RecordingError};

const META: &str = "# format = tactile-recording/1\n# sample_rate_hz = 1000\n# contact_angle_deg = 20\n\
# azimuth_deg = 60\n# fingertip_radius_mm = 20\n# gain_fz = 3000\n# gain_mx = 1000\n# gain_my = 1000\n\
# excitation_V = 3.3\n";
const HEADER: &str = "t_s,rod_mm,load_N,fz_V,mx_V,my_V\n";
const ROWS: &str = "0,0,0,0,0,0\n0.001,0.1,0.2,0.3,0.4,0.5\n";

fn err(text: &str) -> String {
    match Recording::parse(text) {
        Ok(_) => panic!("accepted a broken file:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// The metadata with `key`'s line replaced by `line`.
fn with(key: &str, line: &str) -> String {
    let meta: String = META
        .lines()
        .map(|l| {
            if l.starts_with(&format!("# {key} =")) {
                format!("{line}\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    format!("{meta}{HEADER}{ROWS}")
}

#[test]
fn each_positive_key_refuses_zero_negative_and_non_numbers() {
    let keys = [
        ("sample_rate_hz", 2),
        ("fingertip_radius_mm", 5),
        ("gain_fz", 6),
        ("gain_mx", 7),
        ("gain_my", 8),
        ("excitation_V", 9),
    ];
    for (key, line) in keys {
        for bad in ["0", "-1000", "-0.0", "nan", "inf", "fast"] {
            let e = err(&with(key, &format!("# {key} = {bad}")));
            assert!(
                e.starts_with(&format!("line {line}, field `{key}`: `{bad}` is not a")),
                "{key} = {bad}: {e}"
            );
        }
    }
}

#[test]
fn sample_rate_minus_1000_is_refused_with_its_line() {
    assert_eq!(
        err(&with("sample_rate_hz", "# sample_rate_hz = -1000")),
        "line 2, field `sample_rate_hz`: `-1000` is not a positive number"
    );
}

#[test]
fn angles_may_be_zero_or_negative() {
    let text = with("contact_angle_deg", "# contact_angle_deg = 0")
        .replace("# azimuth_deg = 60", "# azimuth_deg = -30");
    let r = Recording::parse(&text).unwrap();
    assert_eq!(r.meta.azimuth_deg, -30.0);
}

#[test]
fn a_key_given_twice_names_both_lines() {
    let e = err(&format!("{META}# gain_fz = 3000\n{HEADER}{ROWS}"));
    assert_eq!(
        e,
        "line 10, field `gain_fz`: metadata key given twice (first on line 6)"
    );
    let e = err(&format!(
        "{META}# operator = A\n# operator = B\n{HEADER}{ROWS}"
    ));
    assert!(e.starts_with("line 11, field `operator`"), "{e}");
    assert!(e.contains("first on line 10"), "{e}");
}

#[test]
fn each_required_key_missing_is_named() {
    for key in [
        "format",
        "sample_rate_hz",
        "contact_angle_deg",
        "azimuth_deg",
        "fingertip_radius_mm",
        "gain_fz",
        "gain_mx",
        "gain_my",
        "excitation_V",
    ] {
        let meta: String = META
            .lines()
            .filter(|l| !l.starts_with(&format!("# {key} =")))
            .map(|l| format!("{l}\n"))
            .collect();
        let e = err(&format!("{meta}{HEADER}{ROWS}"));
        assert!(e.contains(&format!("`{key}` missing")), "{key}: {e}");
        assert!(e.starts_with("line 9"), "{key}: the header line: {e}");
    }
}

#[test]
fn existing_refusals_still_hold() {
    let e = err(&format!("{META}{HEADER}0,0,0,0,0,0\n0.001,0,x,0,0,0\n"));
    assert_eq!(e, "line 12, field `load_N`: `x` is not a number");
    let e = err(&format!("{META}{HEADER}1,0,0,0,0,0\n0.5,0,0,0,0,0\n"));
    assert!(e.starts_with("line 12, field `t_s`"), "{e}");
}

#[test]
fn sensor_columns_empty_on_every_row_are_not_measured() {
    let r = Recording::parse(&format!(
        "{META}{HEADER}0,0,0,,,\n0.01,0.1,0.2,,,\n0.02,,0.3,,,\n"
    ))
    .unwrap();
    for name in ["fz_V", "mx_V", "my_V", "temp_C"] {
        assert!(!r.measured(name), "{name}");
    }
    for name in ["t_s", "rod_mm", "load_N"] {
        assert!(r.measured(name), "{name}");
    }
    assert_eq!(
        r.channels.measured(),
        [true, true, true, false, false, false]
    );
    let kept = r.without_gaps();
    assert_eq!(kept.channels.t_s, vec![0.0, 0.01], "the rod gap is dropped");
    assert!(kept.channels.fz_v.iter().all(|v| v.is_nan()));
}

#[test]
fn a_sensor_column_measured_on_one_row_is_measured() {
    let r = Recording::parse(&format!("{META}{HEADER}0,0,0,,,\n0.01,0.1,0.2,1e-3,,\n")).unwrap();
    assert!(r.measured("fz_V"));
    assert_eq!(r.without_gaps().channels.len(), 1, "row 1 is a gap in fz_V");
}

#[test]
fn time_rod_or_load_empty_on_every_row_is_refused_naming_it() {
    let cases = [
        ("t_s", ",0,0,1,1,1\n,0.1,0.2,1,1,1\n"),
        ("rod_mm", "0,,0,,,\n0.01,nan,0.2,,,\n"),
        ("load_N", "0,0,,,,\n0.01,0.1,NaN,,,\n"),
    ];
    for (column, rows) in cases {
        let e = err(&format!("{META}{HEADER}{rows}"));
        assert!(
            e.starts_with(&format!("line 10, field `{column}`: empty on every row")),
            "{column}: {e}"
        );
    }
}

#[test]
fn a_sensor_only_log_without_rod_and_load_is_read() {
    let r = Recording::parse(&format!("{META}{HEADER}0,,,1,2,3\n0.01,,,1,2,3\n")).unwrap();
    assert!(!r.measured("rod_mm") && r.measured("fz_V"));
    assert_eq!(
        r.without_gaps().channels.len(),
        0,
        "rod and load always count for gaps"
    );
}

#[test]
fn errors_from_a_file_name_the_file() {
    let dir = std::env::temp_dir().join(format!("recording-meta-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("twice.csv");
    std::fs::write(
        &path,
        format!("{META}# sample_rate_hz = 10\n{HEADER}{ROWS}"),
    )
    .unwrap();
    let e: RecordingError = recording::read(&path).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("twice.csv: line 10, field `sample_rate_hz`"),
        "{msg}"
    );
    assert_eq!(e.line(), Some(10));
    let _ = std::fs::remove_dir_all(&dir);
}
