//! Why a recording was refused. Every variant names the line (1-based) and, where there is one,
//! the field, so the one-line message is enough to fix the file.

use std::fmt;

/// A recording that breaks the layout of `recording-v1.md`.
#[derive(Debug)]
#[non_exhaustive]
pub enum RecordingError {
    /// The file could not be opened or read.
    Io {
        path: String,
        source: std::io::Error,
    },
    /// The file has no header line (it is empty or holds metadata only).
    Empty,
    /// A line is not valid UTF-8.
    NotUtf8 { line: usize },
    /// A required metadata key is absent; `line` is the header line where metadata ended.
    MissingKey { line: usize, key: &'static str },
    /// A metadata value that must be a number is not one.
    BadMetaValue {
        line: usize,
        key: String,
        value: String,
    },
    /// The `format` key names another format or version.
    WrongFormat { line: usize, value: String },
    /// A required column is absent from the header.
    MissingColumn { line: usize, column: &'static str },
    /// The header names a column twice.
    DuplicateColumn { line: usize, column: String },
    /// A data row has more or fewer fields than the header.
    FieldCount {
        line: usize,
        expected: usize,
        found: usize,
    },
    /// A data field is neither a decimal number nor empty/`nan`/`NaN`.
    NotNumeric {
        line: usize,
        column: String,
        value: String,
    },
    /// `t_s` went backwards.
    DecreasingTime {
        line: usize,
        t_s: f64,
        previous_t_s: f64,
    },
}

impl fmt::Display for RecordingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use RecordingError::*;
        match self {
            Io { path, source } => write!(f, "{path}: {source}"),
            Empty => write!(f, "line 1: empty recording: no header line"),
            NotUtf8 { line } => write!(f, "line {line}: not valid UTF-8"),
            MissingKey { line, key } => {
                write!(
                    f,
                    "line {line}: required metadata key `{key}` missing before the header"
                )
            }
            BadMetaValue { line, key, value } => {
                write!(f, "line {line}, field `{key}`: `{value}` is not a number")
            }
            WrongFormat { line, value } => write!(
                f,
                "line {line}, field `format`: `{value}` is not `{}`",
                super::FORMAT
            ),
            MissingColumn { line, column } => {
                write!(
                    f,
                    "line {line}: required column `{column}` missing from the header"
                )
            }
            DuplicateColumn { line, column } => {
                write!(f, "line {line}, field `{column}`: column named twice")
            }
            FieldCount {
                line,
                expected,
                found,
            } => {
                write!(f, "line {line}: {found} fields, the header has {expected}")
            }
            NotNumeric {
                line,
                column,
                value,
            } => {
                write!(
                    f,
                    "line {line}, field `{column}`: `{value}` is not a number"
                )
            }
            DecreasingTime {
                line,
                t_s,
                previous_t_s,
            } => write!(
                f,
                "line {line}, field `t_s`: {t_s} is before the previous row's {previous_t_s}"
            ),
        }
    }
}

impl std::error::Error for RecordingError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            RecordingError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl RecordingError {
    /// sysexits code: a file that is not there is `NO_INPUT`, a broken file `DATA`.
    pub fn exit_code(&self) -> u8 {
        use crate::cli::exit;
        match self {
            RecordingError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => {
                exit::NO_INPUT
            }
            RecordingError::Io { .. } => exit::IO,
            _ => exit::DATA,
        }
    }
}
