use super::*;
use sysexit::ExitStatus as _;

/// A fresh folder for one test.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tactile-inputs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn meta(radius_mm: f64, serial: Option<&str>) -> Meta {
    Meta {
        sample_rate_hz: 100.0,
        contact_angle_deg: 0.0,
        azimuth_deg: 0.0,
        fingertip_radius_mm: radius_mm,
        gain_fz: 1.0,
        gain_mx: 1.0,
        gain_my: 1.0,
        excitation_v: 3.3,
        rod_speed_mm_per_min: None,
        source: None,
        other: serial
            .map(|s| vec![(recording::CHIP_SERIAL_KEY.to_string(), s.to_string())])
            .unwrap_or_default(),
    }
}

#[test]
fn a_missing_input_and_an_empty_list_are_refused_before_any_work() {
    let d = scratch("missing");
    std::fs::write(d.join("a.csv"), "x").unwrap();
    let err = expand(&[d.join("a.csv"), d.join("missing.csv")]).unwrap_err();
    assert_eq!(err.exit_code(), sysexit::NO_INPUT, "{err}");
    assert!(err.to_string().contains("missing.csv"), "{err}");
    let err = expand(&[]).unwrap_err();
    assert_eq!(err.exit_code(), sysexit::USAGE);
    assert!(err.to_string().starts_with("no recording given"), "{err}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn folders_expand_to_their_csv_files_sorted() {
    let d = scratch("folders");
    for name in ["b.csv", "a.csv", "notes.txt"] {
        std::fs::write(d.join(name), name).unwrap();
    }
    assert_eq!(
        expand(std::slice::from_ref(&d)).unwrap(),
        [d.join("a.csv"), d.join("b.csv")]
    );
    let empty = d.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let err = expand(&[empty]).unwrap_err();
    assert!(matches!(err, InputError::NoRecordings(_)), "{err}");
    assert_eq!(err.exit_code(), sysexit::NO_INPUT);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn one_recording_twice_is_refused_by_content_naming_both() {
    let d = scratch("twice");
    let a = d.join("a.csv");
    std::fs::write(&a, "one recording\n").unwrap();
    std::fs::write(d.join("b.csv"), "another recording\n").unwrap();
    std::fs::write(d.join("copy.csv"), "one recording\n").unwrap();
    std::os::unix::fs::symlink(&a, d.join("link.csv")).unwrap();
    let dotted = d.join(".").join("a.csv");
    for (second, how) in [
        (a.clone(), "the same file"),
        (dotted, "the same file"),
        (d.join("link.csv"), "the same file"),
        (d.join("copy.csv"), "byte-identical copies"),
    ] {
        let files = [a.clone(), d.join("b.csv"), second.clone()];
        let err = refuse_repeats(&files).unwrap_err();
        assert_eq!(err.exit_code(), sysexit::USAGE, "{err}");
        let line = err.to_string();
        assert_eq!(
            line,
            format!(
                "{} and {} are {how}: each recording is given once",
                a.display(),
                second.display()
            )
        );
    }
    // Two files that share a name in different folders are two recordings.
    let (day1, day2) = (d.join("day1"), d.join("day2"));
    for (dir, text) in [(&day1, "first day\n"), (&day2, "second day\n")] {
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join("rec.csv"), text).unwrap();
    }
    assert!(refuse_repeats(&[day1.join("rec.csv"), day2.join("rec.csv"), a]).is_ok());
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn another_fingertip_or_device_is_refused_naming_file_key_and_both_values() {
    let (a, b, c) = (
        meta(20.0, None),
        meta(12.0, None),
        meta(20.0, Some("00c0ffee")),
    );
    let err = one_sensor([("a.csv", &a), ("b.csv", &b)]).unwrap_err();
    assert_eq!(err.exit_code(), sysexit::DATA);
    assert!(
        err.to_string().starts_with(
            "b.csv: fingertip_radius_mm = 12, but a.csv has fingertip_radius_mm = 20: "
        ),
        "{err}"
    );
    // A serial is judged where the metadata give it: against the first recording that does.
    let other = meta(20.0, Some("0BADF00D"));
    assert!(one_sensor([("a.csv", &a), ("c.csv", &c)]).is_ok());
    let err = one_sensor([("a.csv", &a), ("c.csv", &c), ("d.csv", &other)]).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("d.csv: chip_serial = 0BADF00D, but c.csv has chip_serial = 00c0ffee"),
        "{err}"
    );
    // The same serial in another case, the same radius written otherwise: one sensor.
    let same = meta(20.000, Some(" 00C0FFEE "));
    assert!(one_sensor([("c.csv", &c), ("e.csv", &same)]).is_ok());
}

#[test]
fn another_instrument_or_unit_is_refused_and_a_key_only_one_names_is_not() {
    let with = |pairs: &[(&str, &str)]| {
        let mut m = meta(2.0, None);
        m.other = pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        m
    };
    let cartilage = with(&[("sensor", "Mach-1 MA0561076c, load cell 25kg SN:1886652")]);
    let skin = with(&[("sensor", "eflesh-1"), ("sensor_unit", "uT")]);
    let err = one_sensor([("cartilage.csv", &cartilage), ("skin.csv", &skin)]).unwrap_err();
    assert_eq!(err.exit_code(), sysexit::DATA);
    assert!(
        err.to_string().starts_with(
            "skin.csv: sensor = eflesh-1, but cartilage.csv has sensor = Mach-1 MA0561076c, \
             load cell 25kg SN:1886652"
        ),
        "{err}"
    );
    // The unit alone tells two skins apart.
    let (ut, volts) = (
        with(&[("sensor_unit", "uT")]),
        with(&[("sensor_unit", "V")]),
    );
    let err = one_sensor([("a.csv", &ut), ("b.csv", &volts)]).unwrap_err();
    assert!(
        err.to_string()
            .starts_with("b.csv: sensor_unit = V, but a.csv has sensor_unit = uT"),
        "{err}"
    );
    // Recordings that merely lack a key are not refused for it.
    let bare = with(&[]);
    assert!(one_sensor([("a.csv", &bare), ("b.csv", &skin), ("c.csv", &bare)]).is_ok());
}
