//! One test per rule of `docs/recording-format.md`: what is accepted, and what is refused with the line
//! and the field named.

use recording::{Recording, RecordingError};

const META: &str = "# format = tactile-recording/1\n# sample_rate_hz = 1000\n# contact_angle_deg = 20\n\
# azimuth_deg = 60\n# fingertip_radius_mm = 20\n# gain_fz = 3000\n# gain_mx = 1000\n# gain_my = 1000\n\
# excitation_V = 3.3\n# rod_speed_mm_per_min = 20\n";
const HEADER: &str = "t_s,rod_mm,load_N,fz_V,mx_V,my_V\n";

fn parse(text: &str) -> Result<Recording, RecordingError> {
    Recording::parse(text)
}

fn ok(text: &str) -> Recording {
    parse(text).unwrap_or_else(|e| panic!("refused a valid file: {e}"))
}

fn err(text: &str) -> String {
    match parse(text) {
        Ok(_) => panic!("accepted a broken file"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn contract_example_reads_with_typed_metadata() {
    let r = ok(&format!("{META}{HEADER}0.000,-0.500,0.000,0.0012,-0.0003,0.0001\n0.001,-0.500,0.000,0.0011,-0.0002,0.0000\n"));
    assert_eq!(r.channels.len(), 2);
    assert_eq!(r.meta.sample_rate_hz, 1000.0);
    assert_eq!(r.meta.contact_angle_deg, 20.0);
    assert_eq!(r.meta.excitation_v, 3.3);
    assert_eq!(r.meta.rod_speed_mm_per_min, Some(20.0));
    assert_eq!(r.channels.fz_v[0], 0.0012);
    assert_eq!(r.channels.rod_mm[1], -0.5);
}

#[test]
fn spaces_around_equals_are_optional_and_unknown_keys_are_kept() {
    let meta = META
        .replace("# gain_fz = 3000", "#gain_fz=3000")
        .replace("# azimuth_deg = 60", "#   azimuth_deg=   60");
    let r = ok(&format!(
        "{meta}# operator = A. N. Other\n# jig = 20 deg, mount B\n{HEADER}0,0,0,0,0,0\n"
    ));
    assert_eq!(r.meta.gain_fz, 3000.0);
    assert_eq!(r.meta.azimuth_deg, 60.0);
    assert_eq!(
        r.meta.other,
        vec![
            ("operator".to_string(), "A. N. Other".to_string()),
            ("jig".into(), "20 deg, mount B".into())
        ]
    );
}

#[test]
fn comment_lines_without_equals_are_ignored() {
    let r = ok(&format!(
        "# recorded on the lab rig\n{META}# plain note\n{HEADER}0,0,0,0,0,0\n"
    ));
    assert_eq!(r.channels.len(), 1);
    assert!(r.meta.other.is_empty());
}

#[test]
fn crlf_line_ends_are_accepted() {
    let text = format!("{META}{HEADER}0,1,2,3,4,5\n0.001,1,2,3,4,5\n").replace('\n', "\r\n");
    let r = ok(&text);
    assert_eq!(r.channels.my_v, vec![5.0, 5.0]);
}

#[test]
fn empty_nan_and_nan_fields_are_missing_and_make_gaps() {
    let r = ok(&format!("{META}{HEADER}0,0,0,0,0,0\n0.001,,0,0,0,0\n0.002,0,nan,0,0,0\n0.003,0,0,NaN,0,0\n0.004,0,0,0,0,0\n"));
    assert_eq!(r.channels.len(), 5);
    assert!(
        r.channels.rod_mm[1].is_nan()
            && r.channels.load_n[2].is_nan()
            && r.channels.fz_v[3].is_nan()
    );
    assert_eq!(r.without_gaps().channels.t_s, vec![0.0, 0.004]);
}

#[test]
fn exponent_and_signed_numbers_parse() {
    let r = ok(&format!("{META}{HEADER}0,-2e-3,1.5,+3,1E2,-0.25\n"));
    assert_eq!(r.channels.rod_mm[0], -2e-3);
    assert_eq!(r.channels.mx_v[0], 100.0);
}

#[test]
fn extra_columns_and_temperature_are_carried_in_any_order() {
    let r = ok(&format!(
        "{META}my_V,seq,t_s,temp_C,rod_mm,load_N,fz_V,mx_V\n5,7,0,25.5,1,2,3,4\n"
    ));
    assert_eq!(r.channels.my_v, vec![5.0]);
    assert_eq!(r.channels.t_s, vec![0.0]);
    assert_eq!(r.temp_c, Some(vec![25.5]));
    assert_eq!(r.extra.len(), 1);
    assert_eq!(r.extra[0].name, "seq");
    assert_eq!(r.extra[0].values, vec![7.0]);
}

#[test]
fn read_with_columns_names_the_columns_in_the_files_order() {
    let path = std::env::temp_dir().join(format!("recording-columns-{}.csv", std::process::id()));
    let header = "my_V,seq,t_s,temp_C,rod_mm,load_N,fz_V,mx_V";
    std::fs::write(&path, format!("{META}{header}\n5,7,0,25.5,1,2,3,4\n")).unwrap();
    let read = recording::read_with_columns(&path);
    std::fs::remove_file(&path).unwrap();
    let (r, columns) = read.unwrap();
    assert_eq!(columns.join(","), header);
    for (name, value) in columns
        .iter()
        .zip([5.0, 7.0, 0.0, 25.5, 1.0, 2.0, 3.0, 4.0])
    {
        assert_eq!(r.column(name), Some(&[value][..]), "{name}");
    }
}

#[test]
fn writer_round_trips_everything() {
    let r = ok(&format!("{META}# source = unit test\n# custom = x\n{HEADER_T}0,-0.5,0,0.0012,-0.0003,1e-5,25,9\n0.001,,0,0,0,0,,10\n",
        HEADER_T = "t_s,rod_mm,load_N,fz_V,mx_V,my_V,temp_C,seq\n"));
    let mut out = Vec::new();
    r.write_to(&mut out).unwrap();
    let back = Recording::parse(std::str::from_utf8(&out).unwrap()).unwrap();
    assert_eq!(back.meta, r.meta);
    assert_eq!(back.extra, r.extra);
    assert_eq!(back.channels.fz_v, r.channels.fz_v);
    assert!(back.channels.rod_mm[1].is_nan());
    assert_eq!(back.temp_c.as_ref().unwrap()[0], 25.0);
}

#[test]
fn missing_required_key_is_refused_naming_it() {
    for key in [
        "sample_rate_hz",
        "contact_angle_deg",
        "azimuth_deg",
        "fingertip_radius_mm",
        "gain_fz",
        "gain_mx",
        "gain_my",
        "excitation_V",
        "format",
    ] {
        let meta: String = META
            .lines()
            .filter(|l| !l.starts_with(&format!("# {key} =")))
            .map(|l| format!("{l}\n"))
            .collect();
        let e = err(&format!("{meta}{HEADER}0,0,0,0,0,0\n"));
        assert!(
            e.contains(&format!("`{key}`")) && e.contains("line "),
            "{key}: {e}"
        );
    }
}

#[test]
fn non_numeric_metadata_value_is_refused() {
    let e = err(&format!(
        "{}{HEADER}0,0,0,0,0,0\n",
        META.replace("# gain_mx = 1000", "# gain_mx = high")
    ));
    assert_eq!(e, "line 7, field `gain_mx`: `high` is not a number");
}

#[test]
fn wrong_format_value_is_refused() {
    let e = err(&format!(
        "{}{HEADER}0,0,0,0,0,0\n",
        META.replace("tactile-recording/1", "tactile-recording/2")
    ));
    assert!(e.starts_with("line 1, field `format`"), "{e}");
}

#[test]
fn missing_required_column_is_refused_naming_it() {
    let e = err(&format!("{META}t_s,rod_mm,load_N,fz_V,my_V\n0,0,0,0,0\n"));
    assert_eq!(e, "line 11: required column `mx_V` missing from the header");
}

#[test]
fn non_numeric_field_is_refused_naming_line_and_column() {
    let e = err(&format!("{META}{HEADER}0,0,0,0,0,0\n0.001,0,0,abc,0,0\n"));
    assert_eq!(e, "line 13, field `fz_V`: `abc` is not a number");
}

#[test]
fn decreasing_time_is_refused() {
    let e = err(&format!("{META}{HEADER}0.002,0,0,0,0,0\n0.001,0,0,0,0,0\n"));
    assert!(e.starts_with("line 13, field `t_s`"), "{e}");
}

#[test]
fn equal_times_are_allowed() {
    ok(&format!("{META}{HEADER}0.001,0,0,0,0,0\n0.001,0,0,0,0,0\n"));
}

#[test]
fn wrong_field_count_is_refused() {
    let e = err(&format!("{META}{HEADER}0,0,0,0,0\n"));
    assert_eq!(e, "line 12: 5 fields, the header has 6");
    let e = err(&format!("{META}{HEADER}0,0,0,0,0,0,0\n"));
    assert_eq!(e, "line 12: 7 fields, the header has 6");
}

#[test]
fn bad_utf8_is_refused_naming_the_line_and_field() {
    let mut bytes = format!("{META}{HEADER}0,0,0,0,0,0\n").into_bytes();
    bytes.extend_from_slice(b"0.001,0,0,\xff\xfe,0,0\n");
    let e = recording::read_from(&bytes[..]).unwrap_err().to_string();
    assert_eq!(
        e,
        "line 13, field `fz_V`: not UTF-8 text (byte 0xff); Latin-1/Windows-1252 text or binary \
         data; the format is UTF-8"
    );
}

#[test]
fn utf16_is_refused_as_utf16() {
    let bytes: Vec<u8> = [0xFF, 0xFE]
        .into_iter()
        .chain(
            format!("{META}{HEADER}")
                .encode_utf16()
                .flat_map(u16::to_le_bytes),
        )
        .collect();
    let e = recording::read_from(&bytes[..]).unwrap_err().to_string();
    assert!(
        e.starts_with("line 1: not UTF-8 text (byte 0xff); UTF-16 text"),
        "{e}"
    );
}

/// The contract's lines end with `\n` or `\r\n`; a last row without one may have been cut
/// mid-number by a killed writer, so it is refused (not dropped, not read): naming the line
/// and the field it stops in.
#[test]
fn a_last_line_without_line_end_is_refused() {
    let e = err(&format!("{META}{HEADER}0,0,0,0.0012,0,0\n0.001,0,0,0.00"));
    assert_eq!(
        e,
        "line 13, field `fz_V`: last line has no line end, so it may have been cut short \
         mid-write (killed writer?); refused rather than read a shortened value (delete the \
         line to read the rest)"
    );
    // A complete-looking row is refused all the same: its last value may be shortened.
    let e = err(&format!("{META}{HEADER}0,0,0,0.0012,0,0.25"));
    assert!(
        e.starts_with("line 12, field `my_V`: last line has no line end"),
        "{e}"
    );
    let e = err(&format!("{META}{}", HEADER.trim_end()));
    assert!(
        e.starts_with("line 11, field `header`: last line has no line end"),
        "{e}"
    );
    // `\r\n` ends and trailing blank lines without an end are fine.
    ok(&format!("{META}{HEADER}0,0,0,0,0,0\r\n  "));
}

#[test]
fn input_over_the_byte_limit_is_refused() {
    use recording::{read_from_with, Limits};
    let text = format!("{META}{HEADER}0,0,0,0,0,0\n0.001,0,0,0,0,0\n");
    let limits = Limits {
        max_bytes: text.len() as u64 - 1,
        ..Limits::DEFAULT
    };
    let e = read_from_with(text.as_bytes(), limits).unwrap_err();
    assert!(
        e.to_string()
            .contains(&format!("is over the {}-byte limit", text.len() - 1)),
        "{e}"
    );
    let exact = Limits {
        max_bytes: text.len() as u64,
        ..Limits::DEFAULT
    };
    assert_eq!(
        read_from_with(text.as_bytes(), exact)
            .unwrap()
            .channels
            .len(),
        2
    );
}

#[test]
fn a_file_over_the_byte_limit_is_refused_before_reading_naming_it() {
    use recording::{read_with, Limits};
    let dir = std::env::temp_dir().join(format!("rec-limit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("big.csv");
    std::fs::write(&path, format!("{META}{HEADER}0,0,0,0,0,0\n")).unwrap();
    let e = read_with(
        &path,
        Limits {
            max_bytes: 100,
            ..Limits::DEFAULT
        },
    )
    .unwrap_err();
    let msg = e.to_string();
    assert!(msg.starts_with(&format!("{}: ", path.display())), "{msg}");
    assert!(msg.contains("over the 100-byte limit"), "{msg}");
    assert_eq!(e.io_kind(), None, "read, then refused");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn too_many_values_and_overlong_lines_are_refused() {
    use recording::{read_from_with, Limits};
    let text = format!("{META}{HEADER}0,0,0,0,0,0\n0.001,0,0,0,0,0\n");
    let few = Limits {
        max_values: 11,
        ..Limits::DEFAULT
    };
    let e = read_from_with(text.as_bytes(), few)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("line 13: more than 11 values"), "{e}");
    let short = Limits {
        max_line_bytes: 30,
        ..Limits::DEFAULT
    };
    let e = read_from_with(text.as_bytes(), short)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("line 11: longer than 30 bytes"), "{e}");
}

#[test]
fn columns_and_untyped_keys_are_found_by_name() {
    let r = ok(&format!(
        "{META}# firmware_smoother_alpha = 0.25\nt_s,rod_mm,load_N,fz_V,mx_V,my_V,temp_C,seq\n0,1,2,3,4,5,25,7\n"
    ));
    assert_eq!(r.meta.get("firmware_smoother_alpha"), Some("0.25"));
    assert_eq!(r.meta.get("nope"), None);
    assert_eq!(r.column("load_N"), Some(&[2.0][..]));
    assert_eq!(r.column("temp_C"), Some(&[25.0][..]));
    assert_eq!(r.column("seq"), Some(&[7.0][..]));
    assert_eq!(r.column("nope"), None);
}

#[test]
fn empty_file_is_refused() {
    assert_eq!(err(""), "line 1: empty recording: no header line");
    assert_eq!(err(META), "line 1: empty recording: no header line");
}

#[test]
fn a_missing_file_is_an_io_error_and_a_broken_one_is_not() {
    let e = recording::read(std::path::Path::new("/nonexistent/rec.csv")).unwrap_err();
    assert_eq!(e.io_kind(), Some(std::io::ErrorKind::NotFound));
    assert_eq!(parse("").unwrap_err().io_kind(), None);
}

#[test]
fn writer_streams_rows_and_flushes_on_demand() {
    let r = ok(&format!("{META}{HEADER}"));
    let mut buf = Vec::new();
    {
        let mut w = recording::RecordingWriter::new(&mut buf, &r.meta, false, &[]).unwrap();
        for i in 0..1000 {
            w.write_row(&[i as f64 * 1e-3, 0.1, 0.2, 0.3, f64::NAN, 0.5], None, &[])
                .unwrap();
        }
        w.flush().unwrap();
    }
    let back = Recording::parse(std::str::from_utf8(&buf).unwrap()).unwrap();
    assert_eq!(back.channels.len(), 1000);
    assert!(back.channels.mx_v[3].is_nan());
}
