//! Streaming reader: one pass over the lines, no whole-file buffer.

use std::io::BufRead;
use std::path::Path;

use super::meta::parse_number;
use super::{Channels, Column, Meta, Recording, RecordingError, REQUIRED_COLUMNS, TEMP_COLUMN};

/// Read and validate the recording at `path`.
pub fn read(path: &Path) -> Result<Recording, RecordingError> {
    let io = |source| RecordingError::Io {
        path: path.display().to_string(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    read_from(std::io::BufReader::with_capacity(1 << 16, file))
}

/// Where each header column goes.
#[derive(Clone, Copy)]
enum Slot {
    Required(usize),
    Temp,
    Extra(usize),
}

/// Read and validate a recording from any buffered source.
pub fn read_from<R: BufRead>(mut input: R) -> Result<Recording, RecordingError> {
    let mut buf = Vec::with_capacity(256);
    let mut line_no = 0usize;
    let mut pairs = Vec::new();
    // Metadata and comments up to the header.
    let header = loop {
        let Some(line) = next_line(&mut input, &mut buf, &mut line_no)? else {
            return Err(RecordingError::Empty);
        };
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        if let Some(comment) = line.strip_prefix('#') {
            if let Some((k, v)) = comment.split_once('=') {
                pairs.push((line_no, k.trim().to_string(), v.trim().to_string()));
            }
            continue;
        }
        break line.to_string();
    };
    let header_line = line_no;
    let meta = Meta::from_pairs(pairs, header_line)?;
    let (names, slots) = parse_header(&header, header_line)?;
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
    let mut previous_t = f64::NEG_INFINITY;
    let mut row = [f64::NAN; 6];
    while let Some(line) = next_line(&mut input, &mut buf, &mut line_no)? {
        let line = line.trim_end_matches(['\r', '\n']);
        if line.trim().is_empty() {
            continue;
        }
        let mut found = 0;
        for (i, field) in line.split(',').enumerate() {
            found += 1;
            let Some(&slot) = slots.get(i) else { continue };
            let value = parse_field(field).ok_or_else(|| RecordingError::NotNumeric {
                line: line_no,
                column: names[i].clone(),
                value: field.to_string(),
            })?;
            match slot {
                Slot::Required(k) => row[k] = value,
                Slot::Temp => {
                    if let Some(t) = rec.temp_c.as_mut() {
                        t.push(value);
                    }
                }
                Slot::Extra(k) => rec.extra[k].values.push(value),
            }
        }
        if found != slots.len() {
            return Err(RecordingError::FieldCount {
                line: line_no,
                expected: slots.len(),
                found,
            });
        }
        let t = row[0];
        if t < previous_t {
            return Err(RecordingError::DecreasingTime {
                line: line_no,
                t_s: t,
                previous_t_s: previous_t,
            });
        }
        if !t.is_nan() {
            previous_t = t;
        }
        push_row(&mut rec.channels, &row);
    }
    Ok(rec)
}

fn push_row(c: &mut Channels, row: &[f64; 6]) {
    c.t_s.push(row[0]);
    c.rod_mm.push(row[1]);
    c.load_n.push(row[2]);
    c.fz_v.push(row[3]);
    c.mx_v.push(row[4]);
    c.my_v.push(row[5]);
}

/// The next line as UTF-8 (without the line end), or `None` at the end of the input.
fn next_line<'b, R: BufRead>(
    input: &mut R,
    buf: &'b mut Vec<u8>,
    line_no: &mut usize,
) -> Result<Option<&'b str>, RecordingError> {
    buf.clear();
    let n = input
        .read_until(b'\n', buf)
        .map_err(|source| RecordingError::Io {
            path: "<input>".into(),
            source,
        })?;
    if n == 0 {
        return Ok(None);
    }
    *line_no += 1;
    let mut bytes = &buf[..];
    if *line_no == 1 {
        bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    }
    while let Some(rest) = bytes
        .strip_suffix(b"\n")
        .or_else(|| bytes.strip_suffix(b"\r"))
    {
        bytes = rest;
    }
    std::str::from_utf8(bytes)
        .map(Some)
        .map_err(|_| RecordingError::NotUtf8 { line: *line_no })
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
    if f.is_empty() || f.eq_ignore_ascii_case("nan") {
        return Some(f64::NAN);
    }
    parse_number(f)
}
