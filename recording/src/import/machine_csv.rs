//! A generic test machine's CSV: a time, a displacement and a force column chosen by name or
//! by 1-based index, each with its unit; comma, semicolon or tab separated (detected from the
//! header); header rows to skip ahead of the column header; `#` lines ignored.

use std::str::FromStr;

use super::{bad, number};
use crate::machine::{MachineExport, MachineExportError};

/// A column chosen by its header name (without case) or by its 1-based index.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ColumnRef {
    /// The header's name for it.
    Name(String),
    /// 1-based position in the row.
    Index(usize),
}

impl FromStr for ColumnRef {
    type Err = std::convert::Infallible;
    /// Digits are an index, anything else a name.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Ok(match s.trim().parse::<usize>() {
            Ok(i) => ColumnRef::Index(i),
            Err(_) => ColumnRef::Name(s.trim().to_string()),
        })
    }
}

/// A unit: its name and the factor to the recording's unit (s, mm or N).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unit {
    /// The unit's name, e.g. `gf`.
    pub name: &'static str,
    /// Recording units per one of this unit.
    pub factor: f64,
}

/// Time units, to s.
pub const TIME_UNITS: [Unit; 3] = [
    Unit {
        name: "s",
        factor: 1.0,
    },
    Unit {
        name: "ms",
        factor: 1e-3,
    },
    Unit {
        name: "min",
        factor: 60.0,
    },
];
/// Length units, to mm.
pub const LENGTH_UNITS: [Unit; 3] = [
    Unit {
        name: "mm",
        factor: 1.0,
    },
    Unit {
        name: "um",
        factor: 1e-3,
    },
    Unit {
        name: "m",
        factor: 1e3,
    },
];
/// Force units, to N.
pub const FORCE_UNITS: [Unit; 5] = [
    Unit {
        name: "N",
        factor: 1.0,
    },
    Unit {
        name: "gf",
        factor: 9.80665e-3,
    },
    Unit {
        name: "kgf",
        factor: 9.80665,
    },
    Unit {
        name: "lbf",
        factor: 4.448_221_615_260_5,
    },
    Unit {
        name: "kN",
        factor: 1e3,
    },
];

/// The unit called `name` among `units`, if any.
pub fn unit(units: &[Unit], name: &str) -> Option<Unit> {
    units.iter().copied().find(|u| u.name == name.trim())
}

/// How to read the CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvOptions {
    /// The time column.
    pub time: ColumnRef,
    /// The displacement column.
    pub displacement: ColumnRef,
    /// The force column.
    pub force: ColumnRef,
    /// Unit of the time column (a name of [`TIME_UNITS`]).
    pub time_unit: String,
    /// Unit of the displacement column (a name of [`LENGTH_UNITS`]).
    pub length_unit: String,
    /// Unit of the force column (a name of [`FORCE_UNITS`]).
    pub force_unit: String,
    /// Multiply displacement and force by -1 (a machine that reads compression as negative).
    pub invert: bool,
    /// Lines to skip before the column header.
    pub skip_rows: usize,
}

/// The delimiter of a header line: the most frequent of tab, semicolon and comma.
pub fn detect_delimiter(header: &str) -> char {
    ['\t', ';', ',']
        .into_iter()
        .max_by_key(|d| header.matches(*d).count())
        .unwrap_or(',')
}

/// Parse a CSV already in memory; `path` names it in errors. Time starts at zero, displacement
/// at its first value.
pub fn parse(
    text: &str,
    path: &str,
    opt: &CsvOptions,
) -> Result<MachineExport, MachineExportError> {
    let mut lines = text
        .lines()
        .enumerate()
        .skip(opt.skip_rows)
        .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
        .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
    let (hline, header) = lines
        .next()
        .ok_or_else(|| bad(path, opt.skip_rows + 1, "(header)", "no header line"))?;
    let delimiter = detect_delimiter(header);
    let names: Vec<String> = header
        .split(delimiter)
        .map(|s| s.trim().to_string())
        .collect();
    let pick =
        |c: &ColumnRef, units: &[Unit], u: &str| -> Result<(usize, f64), MachineExportError> {
            let k = column(&names, c)
                .ok_or_else(|| bad(path, hline, &format!("{c:?}"), "no such column"))?;
            let unit = unit(units, u).ok_or_else(|| {
                let known: Vec<&str> = units.iter().map(|u| u.name).collect();
                bad(
                    path,
                    hline,
                    &names[k],
                    format!("unknown unit {u:?} (known: {known:?})"),
                )
            })?;
            Ok((k, unit.factor))
        };
    let sign = if opt.invert { -1.0 } else { 1.0 };
    let cols = [
        pick(&opt.time, &TIME_UNITS, &opt.time_unit)?,
        pick(&opt.displacement, &LENGTH_UNITS, &opt.length_unit)?,
        pick(&opt.force, &FORCE_UNITS, &opt.force_unit)?,
    ];
    let mut raw = [Vec::new(), Vec::new(), Vec::new()];
    for (no, line) in lines {
        let fields: Vec<&str> = line.split(delimiter).collect();
        for ((k, factor), out) in cols.iter().zip(raw.iter_mut()) {
            let text = fields.get(*k).copied().unwrap_or("");
            out.push(number(path, no, &names[*k], text)? * factor);
        }
        let t = &raw[0];
        if t.len() > 1 && t[t.len() - 1] < t[t.len() - 2] {
            return Err(bad(path, no, &names[cols[0].0], "time decreases"));
        }
    }
    if raw[0].len() < 2 {
        return Err(bad(path, hline, "(rows)", "fewer than two rows"));
    }
    let [t, d, f] = raw;
    Ok(MachineExport {
        t_s: t.iter().map(|v| v - t[0]).collect(),
        rod_mm: d.iter().map(|v| sign * (v - d[0])).collect(),
        load_n: f.iter().map(|v| sign * v).collect(),
    })
}

/// The 0-based position of column `c` in `names`.
fn column(names: &[String], c: &ColumnRef) -> Option<usize> {
    match c {
        ColumnRef::Index(i) => (*i >= 1 && *i <= names.len()).then(|| i - 1),
        ColumnRef::Name(n) => names.iter().position(|h| h.eq_ignore_ascii_case(n)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts(time: &str, disp: &str, force: &str) -> CsvOptions {
        CsvOptions {
            time: time.parse().unwrap(),
            displacement: disp.parse().unwrap(),
            force: force.parse().unwrap(),
            time_unit: "ms".into(),
            length_unit: "um".into(),
            force_unit: "gf".into(),
            invert: false,
            skip_rows: 2,
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
        o.invert = true;
        assert!(parse(SEMI, "m.csv", &o).unwrap().load_n[1] < 0.0);
    }

    #[test]
    fn bad_input_names_the_line_and_field() {
        let mut unknown = opts("1", "2", "3");
        unknown.force_unit = "stone".into();
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
                ":3: field Index(9): no such column",
            ),
            (
                SEMI.to_string(),
                unknown,
                ":3: field Load: unknown unit \"stone\"",
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
