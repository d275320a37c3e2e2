//! Why a recording was refused. Every variant names the line (1-based) and, where there is one,
//! the field, so the one-line message is enough to fix the file; [`read`](super::read) wraps
//! them in [`RecordingError::InFile`] so the message names the file too.

use std::fmt;

/// A recording that breaks the layout of `recording-v1.md`, or is too big to hold in memory.
#[derive(Debug)]
#[non_exhaustive]
pub enum RecordingError {
    /// The file could not be opened or read.
    Io {
        path: String,
        source: std::io::Error,
    },
    /// Another error, found in the file at `path`.
    InFile {
        path: String,
        source: Box<RecordingError>,
    },
    /// The file has no header line (it is empty or holds metadata only).
    Empty,
    /// A line is not valid UTF-8; `field` is the column it happened in (data rows), `hint` a
    /// guess at what the bytes are (UTF-16, Latin-1, binary).
    NotUtf8 {
        line: usize,
        field: Option<String>,
        byte: u8,
        hint: &'static str,
    },
    /// The last line has no line end: a write cut short (a killed writer) may have shortened
    /// `field`, so the row cannot be trusted.
    Unterminated { line: usize, field: String },
    /// A line is longer than any recording line can reasonably be (binary data, no line ends).
    LineTooLong { line: usize, limit_bytes: usize },
    /// The input is bigger than the readers hold in memory.
    TooLarge { bytes: u64, limit_bytes: u64 },
    /// The rows hold more values than the readers hold in memory.
    TooManyValues { line: usize, limit: u64 },
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
            InFile { path, source } => write!(f, "{path}: {source}"),
            Empty => write!(f, "line 1: empty recording: no header line"),
            NotUtf8 {
                line,
                field,
                byte,
                hint,
            } => {
                write!(f, "line {line}")?;
                if let Some(field) = field {
                    write!(f, ", field `{field}`")?;
                }
                write!(
                    f,
                    ": not UTF-8 text (byte 0x{byte:02x}); {hint}; the format is UTF-8"
                )
            }
            Unterminated { line, field } => write!(
                f,
                "line {line}, field `{field}`: last line has no line end, so it may have been cut \
                 short mid-write (killed writer?); refused rather than read a shortened value \
                 (delete the line to read the rest)"
            ),
            LineTooLong { line, limit_bytes } => write!(
                f,
                "line {line}: longer than {limit_bytes} bytes without a line end: not a recording"
            ),
            TooLarge { bytes, limit_bytes } => write!(
                f,
                "{bytes} bytes is over the {limit_bytes}-byte limit of the recording reader \
                 (it holds the recording in memory): split the recording"
            ),
            TooManyValues { line, limit } => write!(
                f,
                "line {line}: more than {limit} values, the limit of the recording reader \
                 (it holds the recording in memory): split the recording"
            ),
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
            RecordingError::Io { source, .. } => match source.kind() {
                std::io::ErrorKind::NotFound => exit::NO_INPUT,
                std::io::ErrorKind::PermissionDenied => exit::NO_PERM,
                _ => exit::IO,
            },
            RecordingError::InFile { source, .. } => source.exit_code(),
            _ => exit::DATA,
        }
    }

    /// The 1-based line the error is on, if it is about one.
    pub fn line(&self) -> Option<usize> {
        use RecordingError::*;
        match self {
            InFile { source, .. } => source.line(),
            Io { .. } | TooLarge { .. } => None,
            Empty => Some(1),
            NotUtf8 { line, .. }
            | Unterminated { line, .. }
            | LineTooLong { line, .. }
            | TooManyValues { line, .. }
            | MissingKey { line, .. }
            | BadMetaValue { line, .. }
            | WrongFormat { line, .. }
            | MissingColumn { line, .. }
            | DuplicateColumn { line, .. }
            | FieldCount { line, .. }
            | NotNumeric { line, .. }
            | DecreasingTime { line, .. } => Some(*line),
        }
    }
}
