//! Incremental writer: metadata and header at creation, then one row per call.

use std::io::Write;

use super::{Meta, REQUIRED_COLUMNS, TEMP_COLUMN};

/// Writes a recording row by row. The writer buffers `out` itself (64 KiB, so a `File` needs no
/// `BufWriter`); each row is formatted whole and handed over in one piece, so `out` only ever
/// receives whole lines, and [`flush`](Self::flush) pushes everything out.
pub struct RecordingWriter<W: Write> {
    out: std::io::BufWriter<W>,
    with_temp: bool,
    n_extra: usize,
    line: String,
}

impl<W: Write> RecordingWriter<W> {
    /// Write the metadata and header. Columns: the required six, then `temp_C` if `with_temp`,
    /// then `extra` in order.
    pub fn new(out: W, meta: &Meta, with_temp: bool, extra: &[&str]) -> std::io::Result<Self> {
        let mut out = std::io::BufWriter::with_capacity(1 << 16, out);
        for (k, v) in meta.pairs() {
            writeln!(out, "# {k} = {v}")?;
        }
        let mut header: Vec<&str> = REQUIRED_COLUMNS.to_vec();
        if with_temp {
            header.push(TEMP_COLUMN);
        }
        header.extend_from_slice(extra);
        writeln!(out, "{}", header.join(","))?;
        Ok(Self {
            out,
            with_temp,
            n_extra: extra.len(),
            line: String::with_capacity(128),
        })
    }

    /// Write one row: `required` = t_s, rod_mm, load_N, fz_V, mx_V, my_V; `temp_c` only if the
    /// writer was created with the temperature column; `extra` one value per extra column.
    /// `NaN` is written as an empty field (missing).
    pub fn write_row(
        &mut self,
        required: &[f64; 6],
        temp_c: Option<f64>,
        extra: &[f64],
    ) -> std::io::Result<()> {
        use std::fmt::Write as _;
        assert_eq!(
            extra.len(),
            self.n_extra,
            "extra values must match the extra columns"
        );
        self.line.clear();
        let temp = self.with_temp.then(|| temp_c.unwrap_or(f64::NAN));
        for (i, v) in required.iter().chain(temp.iter()).chain(extra).enumerate() {
            if i > 0 {
                self.line.push(',');
            }
            if v.is_finite() {
                let _ = write!(self.line, "{v}");
            }
        }
        self.line.push('\n');
        self.out.write_all(self.line.as_bytes())
    }

    /// Push buffered rows to the underlying writer.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }
}
