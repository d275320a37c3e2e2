//! The recording CSV's rows, formatted fast: the contract's writer ([`RecordingWriter`]) writes
//! the metadata and header, and the rows (sixteen thousand a second for a hand, seventeen
//! values each) are formatted here straight into the output buffer with `itoa` for whole
//! numbers and `ryu` for the rest: no allocation per value, and a third of the time of `{}` on
//! an `f64`. A value equal to the one above it in its column (the frame's host time, its
//! temperature, its sequence: ten rows share them) is copied from there, not formatted again.
//! Same layout as the contract writer: comma-separated, a missing value (NaN) empty.

use std::io::Write;

use recording::{Meta, RecordingWriter};

/// Whole numbers below this are written as integers (exactly representable in an `f64`).
const EXACT_INT: f64 = 9_007_199_254_740_992.0;

/// Bytes of rows gathered before they go to the file (a quarter second of one finger).
const BUFFER: usize = 1 << 16;

/// A column's last value and its text, to copy when the next row repeats it.
#[derive(Clone, Copy)]
struct Last {
    bits: u64,
    text: [u8; 24],
    len: u8,
}

pub struct RowWriter {
    out: Box<dyn Write>,
    with_temp: bool,
    buf: Vec<u8>,
    last: Vec<Last>,
    ryu: ryu::Buffer,
    itoa: itoa::Buffer,
}

impl RowWriter {
    /// Write the metadata and header (columns: the required six, `temp_C` if `with_temp`, then
    /// `extra`).
    pub fn new(
        out: Box<dyn Write>,
        meta: &Meta,
        with_temp: bool,
        extra: &[&str],
    ) -> std::io::Result<Self> {
        let mut buf = Vec::with_capacity(2 * BUFFER);
        RecordingWriter::new(&mut buf, meta, with_temp, extra)?.flush()?;
        Ok(Self::on(out, with_temp, buf))
    }

    fn on(out: Box<dyn Write>, with_temp: bool, buf: Vec<u8>) -> Self {
        Self {
            out,
            with_temp,
            buf,
            last: Vec::new(),
            ryu: ryu::Buffer::new(),
            itoa: itoa::Buffer::new(),
        }
    }

    /// Column `i`'s text of `v` at the end of the buffer.
    fn value(&mut self, i: usize, v: f64) {
        if !v.is_finite() {
            return;
        }
        let bits = v.to_bits();
        if let Some(l) = self.last.get(i).filter(|l| l.bits == bits) {
            self.buf.extend_from_slice(&l.text[..usize::from(l.len)]);
            return;
        }
        let text = if v.fract() == 0.0 && v.abs() < EXACT_INT {
            self.itoa.format(v as i64).as_bytes()
        } else {
            self.ryu.format_finite(v).as_bytes()
        };
        self.buf.extend_from_slice(text);
        if self.last.len() <= i {
            let none = Last {
                bits: f64::NAN.to_bits(),
                text: [0; 24],
                len: 0,
            };
            self.last.resize(i + 1, none);
        }
        // Every text of ryu and itoa fits: at most 24 bytes.
        let l = &mut self.last[i];
        l.bits = bits;
        l.len = text.len().min(24) as u8;
        l.text[..usize::from(l.len)].copy_from_slice(&text[..usize::from(l.len)]);
    }

    /// One row: `required` = t_s, rod_mm, load_N, fz_V, mx_V, my_V; `temp_c` only if the file
    /// has that column; `extra` one value per extra column.
    pub fn write_row(
        &mut self,
        required: &[f64; 6],
        temp_c: f64,
        extra: &[f64],
    ) -> std::io::Result<()> {
        let temp = self.with_temp.then_some(temp_c);
        for (i, v) in required.iter().chain(temp.iter()).chain(extra).enumerate() {
            if i > 0 {
                self.buf.push(b',');
            }
            self.value(i, *v);
        }
        self.buf.push(b'\n');
        if self.buf.len() >= BUFFER {
            self.write_out()?;
        }
        Ok(())
    }

    /// Hand the gathered rows to the file (whole rows only).
    fn write_out(&mut self) -> std::io::Result<()> {
        let r = self.out.write_all(&self.buf);
        self.buf.clear();
        r
    }

    pub fn flush(&mut self) -> std::io::Result<()> {
        self.write_out()?;
        self.out.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row reads back as the values written, whatever their form.
    #[test]
    fn values_round_trip() {
        let mut w = RowWriter::on(Box::new(std::io::sink()), true, Vec::new());
        let req = [1.0e-7, f64::NAN, -2.5, 1_764_000_000.123_456_7, 0.0, -3.0];
        // Twice, the second row from the columns' last values.
        w.write_row(&req, 25.5, &[42.0, 1e300]).unwrap();
        w.write_row(&req, 25.5, &[42.0, 1e300]).unwrap();
        let text = String::from_utf8(w.buf.clone()).unwrap();
        let (first, line) = text.split_once('\n').unwrap();
        assert_eq!(format!("{first}\n"), line);
        let back: Vec<f64> = line
            .trim_end()
            .split(',')
            .map(|f| {
                if f.is_empty() {
                    f64::NAN
                } else {
                    f.parse().unwrap()
                }
            })
            .collect();
        assert_eq!(line.split(',').nth(1), Some(""));
        assert_eq!(line.split(',').nth(7), Some("42"));
        for (a, b) in back.iter().zip(req.iter().chain(&[25.5, 42.0, 1e300])) {
            assert!(a == b || (a.is_nan() && b.is_nan()), "{a} vs {b}");
        }
    }
}
