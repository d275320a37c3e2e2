//! `tactile diagnose` refuses bad metadata and unusable columns before any diagnosis: exit 65
//! (bad data), one stderr line naming the file, the line and the key or column.

use std::path::PathBuf;

use sysexit as exit;

mod common;
use common::{fails, tactile};

const HEAD: &str =
    "# format = tactile-recording/1\n# sample_rate_hz = 1000\n# contact_angle_deg = 0\n\
# azimuth_deg = 0\n# fingertip_radius_mm = 20\n# gain_fz = 1100\n# gain_mx = 110\n# gain_my = 110\n\
# excitation_V = 3.3\n";
const COLUMNS: &str = "t_s,rod_mm,load_N,fz_V,mx_V,my_V\n";
const ROWS: &str = "0,0,0,0,0,0\n0.001,0.01,0.02,0,0,0\n";

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("tactile-bad-meta-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn diagnose_fails(name: &str, text: &str, needles: &[&str]) {
    let d = dir();
    let rec = d.join(name);
    std::fs::write(&rec, text).unwrap();
    let json = d.join(format!("{name}.json"));
    let out = tactile(&[
        "diagnose",
        rec.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]);
    fails(&out, exit::DATA, needles);
    assert!(!json.exists(), "{name}: no verdict is written");
}

#[test]
fn bad_metadata_exits_65_naming_file_line_and_key() {
    let cases = [
        (
            "rate-negative.csv",
            "# sample_rate_hz = 1000",
            "# sample_rate_hz = -1000",
            "line 2, field `sample_rate_hz`",
        ),
        (
            "rate-zero.csv",
            "# sample_rate_hz = 1000",
            "# sample_rate_hz = 0",
            "line 2, field `sample_rate_hz`",
        ),
        (
            "gain-zero.csv",
            "# gain_fz = 1100",
            "# gain_fz = 0",
            "line 6, field `gain_fz`",
        ),
        (
            "twice.csv",
            "# gain_my = 110",
            "# gain_my = 110\n# gain_my = 120",
            "line 9, field `gain_my`",
        ),
    ];
    for (name, from, to, needle) in cases {
        let text = format!("{}{COLUMNS}{ROWS}", HEAD.replace(from, to));
        diagnose_fails(name, &text, &[&format!("{name}: {needle}")]);
    }
}

#[test]
fn a_load_column_empty_on_every_row_exits_65() {
    let text = format!("{HEAD}{COLUMNS}0,0,,,,\n0.001,0.01,,,,\n");
    diagnose_fails(
        "no-load.csv",
        &text,
        &["no-load.csv: line 10, field `load_N`", "empty on every row"],
    );
}
