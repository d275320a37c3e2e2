//! Streaming reader: one pass over the lines, no whole-file buffer, and [`Limits`] on what it
//! holds in memory so a huge or binary file is refused instead of exhausting memory.

use std::io::{BufRead, Read};
use std::path::Path;

use super::meta::parse_number;
use super::{Channels, Column, Meta, Recording, RecordingError, REQUIRED_COLUMNS, TEMP_COLUMN};

/// How much the reader accepts. The recording is held in memory as `f64` columns, so both the
/// input and the values kept are bounded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Largest input, in bytes.
    pub max_bytes: u64,
    /// Most values (rows times columns) kept.
    pub max_values: u64,
    /// Longest line, in bytes.
    pub max_line_bytes: usize,
}

impl Limits {
    /// 1 GiB of text, 2^27 values (1 GiB of `f64`), 1 MiB lines: an hour at 1 kHz of the
    /// logger's 18 columns is ~0.6 GB of text and 65 M values.
    pub const DEFAULT: Limits = Limits {
        max_bytes: 1 << 30,
        max_values: 1 << 27,
        max_line_bytes: 1 << 20,
    };
}

/// Read and validate the recording at `path`; errors name the file.
pub fn read(path: &Path) -> Result<Recording, RecordingError> {
    read_with(path, Limits::DEFAULT)
}

/// [`read`] with other limits. A regular file over `max_bytes` is refused before reading.
pub fn read_with(path: &Path, limits: Limits) -> Result<Recording, RecordingError> {
    read_path(path, limits).map(|(rec, _)| rec)
}

/// [`read`], and the header's column names in the file's order: [`Recording`] holds the
/// columns in the contract's order, and a table shown to people (the Python package's
/// DataFrame) keeps the file's.
pub fn read_with_columns(path: &Path) -> Result<(Recording, Vec<String>), RecordingError> {
    read_path(path, Limits::DEFAULT)
}

/// [`read_with`], with the header's column names.
fn read_path(path: &Path, limits: Limits) -> Result<(Recording, Vec<String>), RecordingError> {
    let name = path.display().to_string();
    let io = |source| RecordingError::Io {
        path: name.clone(),
        source,
    };
    let in_file = |e: RecordingError| match e {
        RecordingError::Io { source, .. } => io(source),
        e => RecordingError::InFile {
            path: name.clone(),
            source: Box::new(e),
        },
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let bytes = file.metadata().map_err(io)?.len();
    if bytes > limits.max_bytes {
        return Err(in_file(RecordingError::TooLarge {
            bytes,
            limit_bytes: limits.max_bytes,
        }));
    }
    read_source(std::io::BufReader::with_capacity(1 << 16, file), limits).map_err(in_file)
}

/// Where each header column goes.
#[derive(Clone, Copy)]
enum Slot {
    Required(usize),
    Temp,
    Extra(usize),
}

/// Read and validate a recording from any buffered source, with [`Limits::DEFAULT`].
pub fn read_from<R: BufRead>(input: R) -> Result<Recording, RecordingError> {
    read_from_with(input, Limits::DEFAULT)
}

/// One line of the input.
struct Line<'b> {
    no: usize,
    bytes: &'b [u8],
    /// Whether it ended with `\n` (a torn last line does not).
    terminated: bool,
}

/// Lines of the input, counting bytes against the limits.
struct Lines<R> {
    input: R,
    buf: Vec<u8>,
    no: usize,
    total: u64,
    limits: Limits,
}

impl<R: BufRead> Lines<R> {
    /// The next line without its line end, or `None` at the end of the input.
    fn next(&mut self) -> Result<Option<Line<'_>>, RecordingError> {
        self.buf.clear();
        let cap = self.limits.max_line_bytes as u64 + 1;
        let n = (&mut self.input)
            .take(cap)
            .read_until(b'\n', &mut self.buf)
            .map_err(|source| RecordingError::Io {
                path: "<input>".into(),
                source,
            })?;
        if n == 0 {
            return Ok(None);
        }
        self.no += 1;
        self.total += n as u64;
        if self.total > self.limits.max_bytes {
            return Err(RecordingError::TooLarge {
                bytes: self.total,
                limit_bytes: self.limits.max_bytes,
            });
        }
        let terminated = self.buf.last() == Some(&b'\n');
        if !terminated && n as u64 == cap {
            return Err(RecordingError::LineTooLong {
                line: self.no,
                limit_bytes: self.limits.max_line_bytes,
            });
        }
        let mut bytes = &self.buf[..];
        if self.no == 1 {
            bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        }
        let bytes = bytes.strip_suffix(b"\n").unwrap_or(bytes);
        let bytes = bytes.strip_suffix(b"\r").unwrap_or(bytes);
        Ok(Some(Line {
            no: self.no,
            bytes,
            terminated,
        }))
    }
}

impl<'b> Line<'b> {
    /// The line as UTF-8; `columns` (the header, once known) lets the error name the field.
    fn text(&self, columns: &[String]) -> Result<&'b str, RecordingError> {
        std::str::from_utf8(self.bytes).map_err(|e| {
            let at = e.valid_up_to();
            let commas = self.bytes[..at].iter().filter(|&&b| b == b',').count();
            RecordingError::NotUtf8 {
                line: self.no,
                field: columns.get(commas).cloned(),
                byte: self.bytes[at],
                hint: encoding_hint(self.bytes, self.no),
            }
        })
    }
}

/// A guess at what non-UTF-8 bytes are, for the error message.
fn encoding_hint(bytes: &[u8], line: usize) -> &'static str {
    if line == 1 && (bytes.starts_with(b"\xFF\xFE") || bytes.starts_with(b"\xFE\xFF")) {
        "UTF-16 text (byte-order mark)"
    } else if bytes.contains(&0) {
        "NUL bytes: binary data or UTF-16 text"
    } else {
        "Latin-1/Windows-1252 text or binary data"
    }
}

/// [`read_from`] with other limits.
pub fn read_from_with<R: BufRead>(input: R, limits: Limits) -> Result<Recording, RecordingError> {
    read_source(input, limits).map(|(rec, _)| rec)
}

/// [`read_from_with`], and the header's column names in the file's order.
fn read_source<R: BufRead>(
    input: R,
    limits: Limits,
) -> Result<(Recording, Vec<String>), RecordingError> {
    let mut lines = Lines {
        input,
        buf: Vec::with_capacity(256),
        no: 0,
        total: 0,
        limits,
    };
    let head = read_head(&mut lines)?;
    let meta = Meta::from_pairs(head.pairs, head.line)?;
    let (names, slots) = parse_header(&head.header, head.line)?;
    let mut rec = Recording::new(meta);
    if slots.iter().any(|s| matches!(s, Slot::Temp)) {
        rec.temp_c = Some(Vec::new());
    }
    rec.extra = slots
        .iter()
        .zip(&names)
        .filter(|(s, _)| matches!(s, Slot::Extra(_)))
        .map(|(_, n)| Column {
            name: n.clone(),
            values: Vec::new(),
        })
        .collect();
    read_rows(&mut lines, &names, &slots, &mut rec)?;
    refuse_empty_columns(&rec, head.line)?;
    Ok((rec, names))
}

/// Refuse a recording with rows whose `t_s` is empty on every row, or whose `rod_mm` or
/// `load_N` is: except in a sensor-only log (the logger without a reference machine writes rod
/// and load empty), which still has a measured sensor column to read.
fn refuse_empty_columns(rec: &Recording, header_line: usize) -> Result<(), RecordingError> {
    if rec.channels.is_empty() {
        return Ok(());
    }
    let measured = rec.channels.measured();
    let sensor_measured = measured[3..].iter().any(|&m| m);
    for (k, (column, values)) in rec.channels.required().into_iter().take(3).enumerate() {
        if (k == 0 || !sensor_measured) && values.iter().all(|v| v.is_nan()) {
            return Err(RecordingError::ColumnEmpty {
                line: header_line,
                column,
            });
        }
    }
    Ok(())
}

/// What comes before the data rows.
struct Head {
    /// Metadata as `(line, key, value)`.
    pairs: Vec<(usize, String, String)>,
    /// The header line's text and its number.
    header: String,
    line: usize,
}

/// Metadata and comments up to the header, and the header.
fn read_head<R: BufRead>(lines: &mut Lines<R>) -> Result<Head, RecordingError> {
    let mut pairs = Vec::new();
    loop {
        let Some(line) = lines.next()? else {
            return Err(RecordingError::Empty);
        };
        let text = line.text(&[])?.trim();
        if text.is_empty() {
            continue;
        }
        if let Some(comment) = text.strip_prefix('#') {
            if let Some((k, v)) = comment.split_once('=') {
                pairs.push((line.no, k.trim().to_string(), v.trim().to_string()));
            }
            continue;
        }
        if !line.terminated {
            return Err(RecordingError::Unterminated {
                line: line.no,
                field: "header".into(),
            });
        }
        return Ok(Head {
            pairs,
            header: text.to_string(),
            line: line.no,
        });
    }
}

/// The data rows after the header, each checked whole before it is kept in `rec`.
fn read_rows<R: BufRead>(
    lines: &mut Lines<R>,
    names: &[String],
    slots: &[Slot],
    rec: &mut Recording,
) -> Result<(), RecordingError> {
    let max_values = lines.limits.max_values;
    let mut previous_t = f64::NEG_INFINITY;
    let mut values = 0u64;
    while let Some(line) = lines.next()? {
        let text = line.text(names)?;
        if text.trim().is_empty() {
            continue;
        }
        if !line.terminated {
            let reached = text.split(',').count().min(names.len()) - 1;
            return Err(RecordingError::Unterminated {
                line: line.no,
                field: names[reached].clone(),
            });
        }
        values += slots.len() as u64;
        if values > max_values {
            return Err(RecordingError::TooManyValues {
                line: line.no,
                limit: max_values,
            });
        }
        let row = parse_row(text, line.no, names, slots)?;
        let t = row.required[0];
        if t < previous_t {
            return Err(RecordingError::DecreasingTime {
                line: line.no,
                t_s: t,
                previous_t_s: previous_t,
            });
        }
        if !t.is_nan() {
            previous_t = t;
        }
        row.push_into(rec);
    }
    Ok(())
}

/// One parsed data row.
struct Row {
    required: [f64; 6],
    temp: f64,
    extra: Vec<f64>,
}

impl Row {
    fn push_into(self, rec: &mut Recording) {
        let c: &mut Channels = &mut rec.channels;
        let r = self.required;
        c.t_s.push(r[0]);
        c.rod_mm.push(r[1]);
        c.load_n.push(r[2]);
        c.fz_v.push(r[3]);
        c.mx_v.push(r[4]);
        c.my_v.push(r[5]);
        if let Some(t) = rec.temp_c.as_mut() {
            t.push(self.temp);
        }
        for (col, v) in rec.extra.iter_mut().zip(self.extra) {
            col.values.push(v);
        }
    }
}

/// Split and parse a data row; the whole row is checked before any of it is kept.
fn parse_row(
    text: &str,
    line: usize,
    names: &[String],
    slots: &[Slot],
) -> Result<Row, RecordingError> {
    let found = text.split(',').count();
    if found != slots.len() {
        return Err(RecordingError::FieldCount {
            line,
            expected: slots.len(),
            found,
        });
    }
    let n_extra = slots.iter().filter(|s| matches!(s, Slot::Extra(_))).count();
    let mut row = Row {
        required: [f64::NAN; 6],
        temp: f64::NAN,
        extra: vec![f64::NAN; n_extra],
    };
    for ((field, slot), name) in text.split(',').zip(slots).zip(names) {
        let value = parse_field(field).ok_or_else(|| RecordingError::NotNumeric {
            line,
            column: name.clone(),
            value: field.to_string(),
        })?;
        match *slot {
            Slot::Required(k) => row.required[k] = value,
            Slot::Temp => row.temp = value,
            Slot::Extra(k) => row.extra[k] = value,
        }
    }
    Ok(row)
}

fn parse_header(header: &str, line: usize) -> Result<(Vec<String>, Vec<Slot>), RecordingError> {
    let names: Vec<String> = header.split(',').map(|s| s.trim().to_string()).collect();
    for (i, n) in names.iter().enumerate() {
        if names[..i].contains(n) {
            return Err(RecordingError::DuplicateColumn {
                line,
                column: n.clone(),
            });
        }
    }
    for column in REQUIRED_COLUMNS {
        if !names.iter().any(|n| n == column) {
            return Err(RecordingError::MissingColumn { line, column });
        }
    }
    let mut extra = 0;
    let slots = names
        .iter()
        .map(|n| {
            if let Some(k) = REQUIRED_COLUMNS.iter().position(|c| c == n) {
                Slot::Required(k)
            } else if n == TEMP_COLUMN {
                Slot::Temp
            } else {
                extra += 1;
                Slot::Extra(extra - 1)
            }
        })
        .collect();
    Ok((names, slots))
}

/// A data field: a finite decimal number, or `NaN` for missing (empty, `nan`, `NaN`).
fn parse_field(field: &str) -> Option<f64> {
    let f = field.trim();
    if f.is_empty() || f == "nan" || f == "NaN" {
        return Some(f64::NAN);
    }
    parse_number(f)
}
