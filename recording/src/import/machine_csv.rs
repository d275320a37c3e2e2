//! A generic test machine's CSV: a time, a displacement and a force column chosen by name or
//! by 1-based index, each with its unit; the delimiter given or detected, a header or none,
//! lines to skip ahead of it, `#` lines ignored ([`super::table`]). The same reader reads the
//! reference log of a pair ([`super::pair`]).

use super::table::{Table, TableOptions};
use super::units::Unit;
use crate::machine::{MachineExport, MachineExportError};

pub use super::table::{detect_delimiter, ColumnRef};
pub use super::units::{unit, FORCE_UNITS, LENGTH_UNITS, TIME_UNITS};

/// How to read the CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvOptions {
    /// The time column.
    pub time: ColumnRef,
    /// The displacement column.
    pub displacement: ColumnRef,
    /// The force column.
    pub force: ColumnRef,
    /// Unit of the time column (one of [`TIME_UNITS`]).
    pub time_unit: Unit,
    /// Unit of the displacement column (one of [`LENGTH_UNITS`]).
    pub length_unit: Unit,
    /// Unit of the force column (one of [`FORCE_UNITS`]).
    pub force_unit: Unit,
    /// The displacement decreases as the indenter presses in (a robot's z above the sample).
    pub press_down: bool,
    /// The force reads negative in compression.
    pub compression_negative: bool,
    /// The displacement reading, in its own unit, at first contact: `rod_mm` is 0 there;
    /// `None`: the first reading.
    pub contact_at: Option<f64>,
    /// The force column's marker for "no reading" (e.g. `-1` from a scale with nothing new).
    pub missing: Option<f64>,
    /// Lines, header and delimiter.
    pub table: TableOptions,
}

/// A machine's log on its own clock: time in s (not shifted), rod travel in mm from the
/// contact reading, pressing in positive, and force in N (`NaN` where there was no reading).
#[derive(Debug, Clone, PartialEq)]
pub struct MachineLog {
    /// Time, s, on the log's own clock, non-decreasing.
    pub t_s: Vec<f64>,
    /// Rod travel, mm, pressing in positive, 0 at the contact reading.
    pub rod_mm: Vec<f64>,
    /// Compressive force, N.
    pub load_n: Vec<f64>,
}

/// Read the columns of a CSV already in memory; `path` names it in errors.
pub fn read_log(
    text: &str,
    path: &str,
    opt: &CsvOptions,
) -> Result<MachineLog, MachineExportError> {
    let table = Table::parse(text, path, &opt.table)?;
    let t_s = table.times(table.column(&opt.time)?, opt.time_unit.factor)?;
    let raw = table.values(table.column(&opt.displacement)?, 1.0, None)?;
    let force = table.values(
        table.column(&opt.force)?,
        opt.force_unit.factor,
        opt.missing,
    )?;
    let contact = match opt.contact_at {
        Some(c) => c,
        None => raw.iter().copied().find(|v| v.is_finite()).unwrap_or(0.0),
    };
    let sign = |negative: bool| if negative { -1.0 } else { 1.0 };
    let into = sign(opt.press_down) * opt.length_unit.factor;
    Ok(MachineLog {
        t_s,
        rod_mm: raw.iter().map(|d| into * (d - contact)).collect(),
        load_n: force
            .iter()
            .map(|f| sign(opt.compression_negative) * f)
            .collect(),
    })
}

/// Parse a CSV already in memory; `path` names it in errors. Time starts at zero, and the
/// displacement at the contact reading (by default its first value).
pub fn parse(
    text: &str,
    path: &str,
    opt: &CsvOptions,
) -> Result<MachineExport, MachineExportError> {
    let log = read_log(text, path, opt)?;
    if log.t_s.len() < 2 {
        return Err(super::bad(path, 1, "(rows)", "fewer than two rows"));
    }
    let t0 = log.t_s[0];
    Ok(MachineExport {
        t_s: log.t_s.iter().map(|t| t - t0).collect(),
        rod_mm: log.rod_mm,
        load_n: log.load_n,
    })
}

#[cfg(test)]
mod tests {
    use super::super::units::parse as unit_of;
    use super::*;

    fn opts(time: &str, disp: &str, force: &str) -> CsvOptions {
        CsvOptions {
            time: time.parse().unwrap(),
            displacement: disp.parse().unwrap(),
            force: force.parse().unwrap(),
            time_unit: unit_of(&TIME_UNITS, "ms").unwrap(),
            length_unit: unit_of(&LENGTH_UNITS, "um").unwrap(),
            force_unit: unit_of(&FORCE_UNITS, "gf").unwrap(),
            press_down: false,
            compression_negative: false,
            contact_at: None,
            missing: None,
            table: TableOptions {
                skip_rows: 2,
                ..Default::default()
            },
        }
    }

    const SEMI: &str = "Instron 5944\nsample B\nTime;Ext;Load\n0;100;0\n10;110;1000\n20;130;2000\n";

    #[test]
    fn units_delimiter_skip_and_names_or_indices() {
        for o in [opts("Time", "ext", "LOAD"), opts("1", "2", "3")] {
            let e = parse(SEMI, "m.csv", &o).unwrap();
            assert_eq!(e.t_s, vec![0.0, 0.01, 0.02]);
            assert!((e.rod_mm[2] - 0.03).abs() < 1e-12);
            assert!((e.load_n[1] - 9.80665).abs() < 1e-9);
        }
        let tab = SEMI.replace(';', "\t");
        assert_eq!(parse(&tab, "m.csv", &opts("1", "2", "3")).unwrap().len(), 3);
        let mut o = opts("1", "2", "3");
        o.press_down = true;
        o.compression_negative = true;
        let e = parse(SEMI, "m.csv", &o).unwrap();
        assert!(e.load_n[1] < 0.0 && e.rod_mm[1] < 0.0);
    }

    /// A robot's z over the sample with a scale that marks "nothing new" with -1, no header.
    #[test]
    fn headerless_press_down_contact_and_missing_marker() {
        let mut o = opts("1", "4", "5");
        o.table.skip_rows = 0;
        o.time_unit = unit_of(&TIME_UNITS, "s").unwrap();
        o.length_unit = unit_of(&LENGTH_UNITS, "mm").unwrap();
        o.force_unit = unit_of(&FORCE_UNITS, "g").unwrap();
        o.press_down = true;
        o.contact_at = Some(287.5);
        o.missing = Some(-1.0);
        let text =
            "100.0,315,-100,288.0,0.0\n100.1,315,-100,287.0,-1\n100.2,315,-100,286.5,102.0\n";
        let log = read_log(text, "states.csv", &o).unwrap();
        assert_eq!(log.t_s, vec![100.0, 100.1, 100.2]);
        assert_eq!(log.rod_mm, vec![-0.5, 0.5, 1.0]);
        assert!(log.load_n[1].is_nan());
        assert!((log.load_n[2] - 1.000_278_3).abs() < 1e-6);
    }

    #[test]
    fn bad_input_names_the_line_and_field() {
        let cases = [
            (
                SEMI.replace("10;110", "10;x"),
                opts("1", "2", "3"),
                ":5: field Ext: not a number",
            ),
            (
                SEMI.replace("20;130", "5;130"),
                opts("1", "2", "3"),
                ":6: field Time: time decreases",
            ),
            (
                SEMI.to_string(),
                opts("1", "2", "9"),
                ":3: field column 9: no such column",
            ),
            (
                SEMI.to_string(),
                opts("1", "2", "Force"),
                ":3: field Force: no such column (columns: Time, Ext, Load)",
            ),
            (
                "a\nb\n".to_string(),
                opts("1", "2", "3"),
                ":3: field (header)",
            ),
        ];
        for (text, o, want) in cases {
            let e = parse(&text, "m.csv", &o).unwrap_err().to_string();
            assert!(e.contains(want), "{want}: {e}");
        }
    }
}
