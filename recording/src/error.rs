//! Why a recording was refused. Every variant names the line (1-based) and, where there is one,
//! the field, so the one-line message is enough to fix the file; [`read`](super::read) wraps
//! them in [`RecordingError::InFile`] so the message names the file too.

use std::fmt;

/// A recording that breaks the layout of `docs/recording-format.md`, or is too big to hold in
/// memory.
#[derive(Debug)]
#[non_exhaustive]
pub enum RecordingError {
    /// The file could not be opened or read.
    Io {
        /// The file.
        path: String,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// Another error, found in the file at `path`.
    InFile {
        /// The file.
        path: String,
        /// The error in it.
        source: Box<RecordingError>,
    },
    /// The file has no header line (it is empty or holds metadata only).
    Empty,
    /// A line is not valid UTF-8.
    NotUtf8 {
        /// 1-based line.
        line: usize,
        /// The column it happened in (data rows).
        field: Option<String>,
        /// The first byte that is not UTF-8.
        byte: u8,
        /// A guess at what the bytes are (UTF-16, Latin-1, binary).
        hint: &'static str,
    },
    /// The last line has no line end: a write cut short (a killed writer) may have shortened
    /// `field`, so the row cannot be trusted.
    Unterminated {
        /// 1-based line.
        line: usize,
        /// The field the line ends in.
        field: String,
    },
    /// A line is longer than any recording line can reasonably be (binary data, no line ends).
    LineTooLong {
        /// 1-based line.
        line: usize,
        /// The reader's limit.
        limit_bytes: usize,
    },
    /// The input is bigger than the readers hold in memory.
    TooLarge {
        /// Bytes read or the file's size.
        bytes: u64,
        /// The reader's limit.
        limit_bytes: u64,
    },
    /// The rows hold more values than the readers hold in memory.
    TooManyValues {
        /// 1-based line where the limit was passed.
        line: usize,
        /// The reader's limit.
        limit: u64,
    },
    /// A required metadata key is absent.
    MissingKey {
        /// The header line, where metadata ended.
        line: usize,
        /// The missing key.
        key: &'static str,
    },
    /// A metadata value that must be a number is not one.
    BadMetaValue {
        /// 1-based line.
        line: usize,
        /// The key.
        key: String,
        /// Its value.
        value: String,
    },
    /// A metadata key is given a second time (any key: which one counts would be a guess).
    DuplicateKey {
        /// 1-based line of the second occurrence.
        line: usize,
        /// 1-based line of the first occurrence.
        first_line: usize,
        /// The key.
        key: String,
    },
    /// A metadata value that must be a positive number (a rate, a radius, a gain, the
    /// excitation) is zero or negative.
    NotPositive {
        /// 1-based line.
        line: usize,
        /// The key.
        key: &'static str,
        /// Its value.
        value: String,
    },
    /// A column that must be measured (`t_s`, `rod_mm`, `load_N`) is empty on every row.
    ColumnEmpty {
        /// The header line.
        line: usize,
        /// The column.
        column: &'static str,
    },
    /// The `format` key names another format or version.
    WrongFormat {
        /// 1-based line.
        line: usize,
        /// The value of `format`.
        value: String,
    },
    /// A required column is absent from the header.
    MissingColumn {
        /// The header line.
        line: usize,
        /// The missing column.
        column: &'static str,
    },
    /// The header names a column twice.
    DuplicateColumn {
        /// The header line.
        line: usize,
        /// The column named twice.
        column: String,
    },
    /// A data row has more or fewer fields than the header.
    FieldCount {
        /// 1-based line.
        line: usize,
        /// Columns in the header.
        expected: usize,
        /// Fields in the row.
        found: usize,
    },
    /// A data field is neither a decimal number nor empty/`nan`/`NaN`.
    NotNumeric {
        /// 1-based line.
        line: usize,
        /// The column.
        column: String,
        /// The field's text.
        value: String,
    },
    /// `t_s` went backwards.
    DecreasingTime {
        /// 1-based line.
        line: usize,
        /// The row's time.
        t_s: f64,
        /// The previous row's time.
        previous_t_s: f64,
    },
}

impl fmt::Display for RecordingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io { path, source } => write!(f, "{path}: {source}"),
            Self::InFile { path, source } => write!(f, "{path}: {source}"),
            Self::TooLarge { .. } => f.write_str(&self.what()),
            _ => {
                write!(f, "line {}", self.line().unwrap_or(1))?;
                if let Some(field) = self.field() {
                    write!(f, ", field `{field}`")?;
                }
                write!(f, ": {}", self.what())
            }
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
    /// The operating system's reason when the file could not be opened or read; `None` when it
    /// was read and refused.
    pub fn io_kind(&self) -> Option<std::io::ErrorKind> {
        match self {
            RecordingError::Io { source, .. } => Some(source.kind()),
            RecordingError::InFile { source, .. } => source.io_kind(),
            _ => None,
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
            | DuplicateKey { line, .. }
            | NotPositive { line, .. }
            | ColumnEmpty { line, .. }
            | WrongFormat { line, .. }
            | MissingColumn { line, .. }
            | DuplicateColumn { line, .. }
            | FieldCount { line, .. }
            | NotNumeric { line, .. }
            | DecreasingTime { line, .. } => Some(*line),
        }
    }

    /// The field (column or metadata key) the error is in, if it names one.
    fn field(&self) -> Option<&str> {
        use RecordingError::*;
        match self {
            NotUtf8 { field, .. } => field.as_deref(),
            Unterminated { field, .. } => Some(field),
            BadMetaValue { key, .. } | DuplicateKey { key, .. } => Some(key),
            NotPositive { key, .. } => Some(key),
            ColumnEmpty { column, .. } => Some(column),
            WrongFormat { .. } => Some("format"),
            DuplicateColumn { column, .. } | NotNumeric { column, .. } => Some(column),
            DecreasingTime { .. } => Some("t_s"),
            _ => None,
        }
    }

    /// What is wrong, after the line and field.
    fn what(&self) -> String {
        use RecordingError::*;
        match self {
            Io { source, .. } => source.to_string(),
            InFile { source, .. } => source.to_string(),
            Empty => "empty recording: no header line".into(),
            NotUtf8 { byte, hint, .. } => {
                format!("not UTF-8 text (byte 0x{byte:02x}); {hint}; the format is UTF-8")
            }
            Unterminated { .. } => "last line has no line end, so it may have been cut short \
                mid-write (killed writer?); refused rather than read a shortened value (delete \
                the line to read the rest)"
                .into(),
            LineTooLong { limit_bytes, .. } => {
                format!("longer than {limit_bytes} bytes without a line end: not a recording")
            }
            TooLarge { bytes, limit_bytes } => format!(
                "{bytes} bytes is over the {limit_bytes}-byte limit of the recording reader (it \
                 holds the recording in memory): split the recording"
            ),
            TooManyValues { limit, .. } => format!(
                "more than {limit} values, the limit of the recording reader (it holds the \
                 recording in memory): split the recording"
            ),
            MissingKey { key, .. } => {
                format!("required metadata key `{key}` missing before the header")
            }
            BadMetaValue { value, .. } | NotNumeric { value, .. } => {
                format!("`{value}` is not a number")
            }
            DuplicateKey { first_line, .. } => {
                format!("metadata key given twice (first on line {first_line})")
            }
            NotPositive { value, .. } => format!("`{value}` is not a positive number"),
            ColumnEmpty { .. } => {
                "empty on every row: a required measured column (time, rod or load) has no value"
                    .into()
            }
            WrongFormat { value, .. } => format!("`{value}` is not `{}`", super::FORMAT),
            MissingColumn { column, .. } => {
                format!("required column `{column}` missing from the header")
            }
            DuplicateColumn { .. } => "column named twice".into(),
            FieldCount {
                expected, found, ..
            } => format!("{found} fields, the header has {expected}"),
            DecreasingTime {
                t_s, previous_t_s, ..
            } => format!("{t_s} is before the previous row's {previous_t_s}"),
        }
    }
}

/// A file that could not be read is a missing or forbidden input; one that was read and
/// refused is bad data.
impl sysexit::ExitStatus for RecordingError {
    fn exit_code(&self) -> u8 {
        self.io_kind().map_or(sysexit::DATA, sysexit::of_input)
    }
}
