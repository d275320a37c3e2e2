//! The recording format `tactile-recording/1` (specified in `docs/recording-format.md`): a CSV with
//! `# key = value` metadata, one header line and numeric rows; and the test machine's export
//! (time, rod travel, load) that the logger merges into a recording ([`machine`]).
//!
//! [`read`] / [`Recording::parse`] refuse a file that breaks the layout with a
//! [`RecordingError`] naming the line and the field (and the file, for [`read`]), and a file too
//! big to hold in memory ([`Limits`]); [`RecordingWriter`] writes rows incrementally (the
//! logger, `tactile simulate`, `replay` and the reference merge use it).
//!
//! A last line without its line end is refused ([`RecordingError::Unterminated`]): the format
//! makes every line end with `\n` or `\r\n`, and a row cut short by a killed writer can still
//! parse (`0.0012` cut to `0.00`), so reading it would silently alter the data.
#![warn(missing_docs)]
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

mod error;
mod meta;
mod reader;
mod writer;

pub use error::RecordingError;
pub use meta::{Meta, CHIP_SERIAL_KEY, NUMBER_KEYS, SENSOR_KEY, SENSOR_UNIT_KEY, SMOOTHER_KEY};
pub use reader::{read, read_from, read_from_with, read_with, read_with_columns, Limits};
pub use writer::RecordingWriter;

pub mod import;
pub mod machine;

/// The value of the `format` key this module reads and writes.
pub const FORMAT: &str = "tactile-recording/1";

/// The required columns, in the order the writer emits them.
pub const REQUIRED_COLUMNS: [&str; 6] = ["t_s", "rod_mm", "load_N", "fz_V", "mx_V", "my_V"];
/// The optional temperature column.
pub const TEMP_COLUMN: &str = "temp_C";

/// One channel that is not required by the contract, carried along by name.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// The column's name in the header.
    pub name: String,
    /// One value per row; a missing value is `NaN`.
    pub values: Vec<f64>,
}

/// The required channels, one value per row; a missing value is `NaN`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Channels {
    /// Time since the start of the recording, s (`t_s`).
    pub t_s: Vec<f64>,
    /// Rod travel from first contact, mm (`rod_mm`).
    pub rod_mm: Vec<f64>,
    /// Force along the rod axis from the reference load cell, N (`load_N`).
    pub load_n: Vec<f64>,
    /// Fz channel at the ADC input, V (`fz_V`).
    pub fz_v: Vec<f64>,
    /// Mx channel at the ADC input, V (`mx_V`).
    pub mx_v: Vec<f64>,
    /// My channel at the ADC input, V (`my_V`).
    pub my_v: Vec<f64>,
}

impl Channels {
    /// Number of rows (gaps included).
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// The four compared signals by contract name, in the order load, fz, mx, my.
    pub fn signals(&self) -> [(&'static str, &[f64]); 4] {
        [
            ("load_N", &self.load_n),
            ("fz_V", &self.fz_v),
            ("mx_V", &self.mx_v),
            ("my_V", &self.my_v),
        ]
    }

    /// The six required columns by contract name, in the contract's order.
    pub fn required(&self) -> [(&'static str, &[f64]); 6] {
        [
            ("t_s", &self.t_s),
            ("rod_mm", &self.rod_mm),
            ("load_N", &self.load_n),
            ("fz_V", &self.fz_v),
            ("mx_V", &self.mx_v),
            ("my_V", &self.my_v),
        ]
    }

    /// Whether row `i` is a gap (a required value missing). Counts every required column; use
    /// [`Channels::is_gap_in`] with [`Channels::measured`] to ignore columns not measured.
    pub fn is_gap(&self, i: usize) -> bool {
        self.required().iter().any(|(_, c)| c[i].is_nan())
    }

    /// Which required columns were measured, in the order of [`Channels::required`]: a column
    /// empty on every row was not measured (`docs/recording-format.md`, "Quantities not
    /// measured"). With no rows, every column counts as measured.
    pub fn measured(&self) -> [bool; 6] {
        let empty = self.is_empty();
        self.required()
            .map(|(_, c)| empty || c.iter().any(|v| !v.is_nan()))
    }

    /// Whether row `i` is a gap in one of the columns `measured` marks (see
    /// [`Channels::measured`]).
    pub fn is_gap_in(&self, i: usize, measured: &[bool; 6]) -> bool {
        self.required()
            .iter()
            .zip(measured)
            .any(|((_, c), &m)| m && c[i].is_nan())
    }
}

/// A whole recording in memory.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// The metadata block.
    pub meta: Meta,
    /// The required columns.
    pub channels: Channels,
    /// `temp_C`, when the file has that column.
    pub temp_c: Option<Vec<f64>>,
    /// Every other column, in file order.
    pub extra: Vec<Column>,
}

impl Recording {
    /// A recording with no rows yet.
    pub fn new(meta: Meta) -> Self {
        Self {
            meta,
            channels: Channels::default(),
            temp_c: None,
            extra: Vec::new(),
        }
    }

    /// The values of column `name` (required, `temp_C` or extra), if the recording has it.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        if let Some((_, v)) = self
            .channels
            .required()
            .into_iter()
            .find(|(n, _)| *n == name)
        {
            return Some(v);
        }
        if name == TEMP_COLUMN {
            return self.temp_c.as_deref();
        }
        self.extra
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.values.as_slice())
    }

    /// Whether column `name` is in the recording and has a value on at least one row; a
    /// required sensor column empty on every row was not measured.
    pub fn measured(&self, name: &str) -> bool {
        self.column(name)
            .is_some_and(|v| v.is_empty() || v.iter().any(|x| !x.is_nan()))
    }

    /// Parse a recording from text already in memory.
    pub fn parse(text: &str) -> Result<Self, RecordingError> {
        read_from(text.as_bytes())
    }

    /// The same recording without its gap rows (rows with a missing time, rod or load, or a
    /// missing value in a measured sensor column); a sensor column not measured stays empty.
    pub fn without_gaps(&self) -> Recording {
        let measured = self.gap_columns();
        let keep: Vec<usize> = (0..self.channels.len())
            .filter(|&i| !self.channels.is_gap_in(i, &measured))
            .collect();
        self.rows(&keep)
    }

    /// Whether any row is a gap as [`Recording::without_gaps`] drops it: a recording without
    /// one need not be copied (an hour at 1 kHz is 210 MB of columns).
    pub fn has_gaps(&self) -> bool {
        let measured = self.gap_columns();
        (0..self.channels.len()).any(|i| self.channels.is_gap_in(i, &measured))
    }

    /// The required columns whose missing values make a gap: time, rod and load always, a
    /// sensor column where it was measured.
    fn gap_columns(&self) -> [bool; 6] {
        let mut measured = self.channels.measured();
        // Only a sensor column may be "not measured"; time, rod and load always count.
        measured[..3].fill(true);
        measured
    }

    /// The same recording with only the rows `keep` (indices, in the order given), in every
    /// column: the required ones, `temp_C` and the extra ones.
    pub fn rows(&self, keep: &[usize]) -> Recording {
        let pick = |v: &Vec<f64>| keep.iter().map(|&i| v[i]).collect::<Vec<f64>>();
        let c = &self.channels;
        Recording {
            meta: self.meta.clone(),
            channels: Channels {
                t_s: pick(&c.t_s),
                rod_mm: pick(&c.rod_mm),
                load_n: pick(&c.load_n),
                fz_v: pick(&c.fz_v),
                mx_v: pick(&c.mx_v),
                my_v: pick(&c.my_v),
            },
            temp_c: self.temp_c.as_ref().map(pick),
            extra: self
                .extra
                .iter()
                .map(|c| Column {
                    name: c.name.clone(),
                    values: pick(&c.values),
                })
                .collect(),
        }
    }

    /// Write the whole recording to `out` in the contract's layout.
    pub fn write_to<W: std::io::Write>(&self, out: W) -> std::io::Result<()> {
        let names: Vec<&str> = self.extra.iter().map(|c| c.name.as_str()).collect();
        let mut w = RecordingWriter::new(out, &self.meta, self.temp_c.is_some(), &names)?;
        let c = &self.channels;
        let mut extra = vec![0.0; self.extra.len()];
        for i in 0..c.len() {
            for (e, col) in extra.iter_mut().zip(&self.extra) {
                *e = col.values[i];
            }
            let row = [
                c.t_s[i],
                c.rod_mm[i],
                c.load_n[i],
                c.fz_v[i],
                c.mx_v[i],
                c.my_v[i],
            ];
            w.write_row(&row, self.temp_c.as_ref().map(|t| t[i]), &extra)?;
        }
        w.flush()
    }
}
