//! The recording CSV of `shared/contracts/recording-v1.md`: a small writer (kept separate so
//! the lead can switch it onto the shared `host::recording` writer at merge) and a strict
//! reader used by `plot`, `--reference` and the tests to check files against the contract.

use std::io::Write;
use std::path::{Path, PathBuf};

use super::FileError;

/// `format` value of the contract.
pub const FORMAT: &str = "tactile-recording/1";
/// Required metadata keys, in the contract's order.
pub const REQUIRED_KEYS: [&str; 9] = [
    "format",
    "sample_rate_hz",
    "contact_angle_deg",
    "azimuth_deg",
    "fingertip_radius_mm",
    "gain_fz",
    "gain_mx",
    "gain_my",
    "excitation_V",
];
/// Required columns, in the contract's order.
pub const REQUIRED_COLUMNS: [&str; 6] = ["t_s", "rod_mm", "load_N", "fz_V", "mx_V", "my_V"];

/// Writes metadata, header and rows. Each row is formatted whole into memory first, so the
/// file only ever receives complete lines (see [`super::Recorder`] for the flush policy).
#[derive(Debug)]
pub struct CsvSink<W: Write> {
    out: W,
    columns: usize,
    line: String,
}

impl<W: Write> CsvSink<W> {
    /// Write the metadata (`# key = value`) and the header; `columns` must start with
    /// [`REQUIRED_COLUMNS`].
    pub fn new(mut out: W, meta: &[(String, String)], columns: &[&str]) -> std::io::Result<Self> {
        for (k, v) in meta {
            writeln!(out, "# {k} = {v}")?;
        }
        writeln!(out, "{}", columns.join(","))?;
        Ok(Self {
            out,
            columns: columns.len(),
            line: String::with_capacity(256),
        })
    }

    /// One row; `None` is a missing value (an empty field). Extra values beyond the header are
    /// a programmer error.
    pub fn row(&mut self, values: &[Option<f64>]) -> std::io::Result<()> {
        use std::fmt::Write as _;
        assert!(values.len() <= self.columns, "row wider than the header");
        self.line.clear();
        for i in 0..self.columns {
            if i > 0 {
                self.line.push(',');
            }
            if let Some(Some(v)) = values.get(i) {
                if v.is_finite() {
                    let _ = write!(self.line, "{v}");
                }
            }
        }
        self.line.push('\n');
        self.out.write_all(self.line.as_bytes())
    }

    pub fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }

    pub fn get_mut(&mut self) -> &mut W {
        &mut self.out
    }
}

/// A recording read back: metadata, column names and rows (missing values as NaN).
#[derive(Debug, Clone)]
pub struct Recording {
    pub meta: Vec<(String, String)>,
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Recording {
    pub fn meta(&self, key: &str) -> Option<&str> {
        self.meta
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    pub fn column(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c == name)
    }

    /// The values of one column (NaN where missing).
    pub fn values(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.column(name)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }
}

fn malformed(path: &Path, line: usize, field: &str, why: impl Into<String>) -> FileError {
    FileError::Malformed {
        path: path.to_path_buf(),
        line,
        field: field.to_owned(),
        why: why.into(),
    }
}

/// Read a recording with every rule of the contract: required keys and columns, numeric fields
/// (empty, `nan`, `NaN` missing), non-decreasing `t_s`. A final line without its `\n` is an
/// unfinished write of a killed logger and is refused like any broken row.
pub fn read_recording(path: &Path) -> Result<Recording, FileError> {
    let bytes = std::fs::read(path).map_err(|e| FileError::open(path, e))?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        let line = bytes[..e.valid_up_to()]
            .iter()
            .filter(|b| **b == b'\n')
            .count()
            + 1;
        malformed(path, line, "(text)", "not UTF-8")
    })?;
    parse_recording(path, text)
}

/// [`read_recording`] on text already in memory.
pub fn parse_recording(path: &Path, text: &str) -> Result<Recording, FileError> {
    // A byte-order mark from a spreadsheet export is not part of the first line.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut meta = Vec::new();
    let mut lines = text
        .split_inclusive('\n')
        .enumerate()
        .map(|(i, l)| (i + 1, l));
    let mut header = None;
    for (n, line) in lines.by_ref() {
        let l = line.trim_end_matches(['\n', '\r']);
        if let Some(c) = l.strip_prefix('#') {
            if let Some((k, v)) = c.split_once('=') {
                meta.push((k.trim().to_owned(), v.trim().to_owned()));
            }
            continue;
        }
        if l.trim().is_empty() {
            continue;
        }
        header = Some((n, l));
        break;
    }
    let Some((hline, header)) = header else {
        return Err(malformed(path, 1, "(header)", "no header line"));
    };
    for key in REQUIRED_KEYS {
        if !meta.iter().any(|(k, _)| k == key) {
            return Err(malformed(path, hline, key, "required metadata key missing"));
        }
    }
    let format = meta
        .iter()
        .find(|(k, _)| k == "format")
        .map(|(_, v)| v.as_str());
    if format != Some(FORMAT) {
        return Err(malformed(
            path,
            hline,
            "format",
            format!("expected {FORMAT}"),
        ));
    }
    let columns: Vec<String> = header.split(',').map(|c| c.trim().to_owned()).collect();
    for col in REQUIRED_COLUMNS {
        if !columns.iter().any(|c| c == col) {
            return Err(malformed(path, hline, col, "required column missing"));
        }
    }
    let t_col = columns.iter().position(|c| c == "t_s").unwrap_or(0);
    let mut rows = Vec::new();
    let mut last_t = f64::NEG_INFINITY;
    for (n, line) in lines {
        if !line.ends_with('\n') {
            return Err(malformed(
                path,
                n,
                "(row)",
                "unfinished last line (no line end)",
            ));
        }
        let l = line.trim_end_matches(['\n', '\r']);
        if l.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = l.split(',').collect();
        if fields.len() != columns.len() {
            let why = format!("{} fields, the header has {}", fields.len(), columns.len());
            return Err(malformed(path, n, "(row)", why));
        }
        let mut row = Vec::with_capacity(fields.len());
        for (f, col) in fields.iter().zip(&columns) {
            row.push(
                parse_field(f)
                    .ok_or_else(|| malformed(path, n, col, format!("not a number: {f:?}")))?,
            );
        }
        let t = row[t_col];
        if t < last_t {
            return Err(malformed(
                path,
                n,
                "t_s",
                format!("decreases from {last_t} to {t}"),
            ));
        }
        if !t.is_nan() {
            last_t = t;
        }
        rows.push(row);
    }
    Ok(Recording {
        meta,
        columns,
        rows,
    })
}

fn parse_field(f: &str) -> Option<f64> {
    let f = f.trim();
    match f {
        "" | "nan" | "NaN" => Some(f64::NAN),
        _ => f.parse::<f64>().ok().filter(|v| v.is_finite()),
    }
}

/// The path a CSV for sensor `label` goes to when several sensors are logged at once.
pub fn per_sensor_path(base: &Path, label: &str, several: bool) -> PathBuf {
    if !several {
        return base.to_path_buf();
    }
    let clean: String = label
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    let stem = base
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    base.with_file_name(format!("{stem}-{}.csv", clean.trim_matches('_')))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn meta() -> Vec<(String, String)> {
        let v = [
            FORMAT, "1000", "20", "60", "20", "3000", "1000", "1000", "3.3",
        ];
        REQUIRED_KEYS
            .iter()
            .zip(v)
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    }

    #[test]
    fn writes_what_the_contract_reader_reads() {
        let mut out = Vec::new();
        let mut cols = REQUIRED_COLUMNS.to_vec();
        cols.push("seq");
        let mut w = CsvSink::new(&mut out, &meta(), &cols).unwrap();
        w.row(&[
            Some(0.0),
            None,
            None,
            Some(1.5e-3),
            Some(-2e-3),
            Some(0.0),
            Some(7.0),
        ])
        .unwrap();
        w.row(&[Some(0.001)]).unwrap();
        let text = String::from_utf8(out).unwrap();
        let r = parse_recording(Path::new("x.csv"), &text).unwrap();
        assert_eq!(r.rows.len(), 2);
        assert_eq!(r.rows[0][3], 1.5e-3);
        assert!(r.rows[0][1].is_nan() && r.rows[1][6].is_nan());
        assert_eq!(r.meta("gain_fz"), Some("3000"));
    }

    #[test]
    fn a_byte_order_mark_is_not_part_of_the_first_key() {
        let mut out = Vec::new();
        let mut w = CsvSink::new(&mut out, &meta(), &REQUIRED_COLUMNS).unwrap();
        w.row(&[Some(0.0)]).unwrap();
        let text = format!("\u{feff}{}", String::from_utf8(out).unwrap());
        let r = parse_recording(Path::new("bom.csv"), &text).unwrap();
        assert_eq!(r.meta("format"), Some(FORMAT));
    }

    #[test]
    fn refuses_contract_violations_naming_line_and_field() {
        let head = "# format = tactile-recording/1\n# sample_rate_hz = 1\n# contact_angle_deg = 0\n# azimuth_deg = 0\n# fingertip_radius_mm = 20\n# gain_fz = 1\n# gain_mx = 1\n# gain_my = 1\n# excitation_V = 3\nt_s,rod_mm,load_N,fz_V,mx_V,my_V\n";
        let err = |t: &str| {
            parse_recording(Path::new("r.csv"), t)
                .unwrap_err()
                .to_string()
        };
        assert!(err(&format!("{head}0,1,2,3,x,5\n")).contains("r.csv:11: field mx_V"));
        assert!(
            err(&format!("{head}1,,,,,\n0,,,,,\n")).contains("line 12")
                || err(&format!("{head}1,,,,,\n0,,,,,\n")).contains(":12: field t_s")
        );
        assert!(err(&format!("{head}0,1,2")).contains("unfinished"));
        assert!(err(&head.replace("# gain_my = 1\n", "")).contains("gain_my"));
        assert!(err(&head.replace(",my_V", "")).contains("my_V"));
    }
}
