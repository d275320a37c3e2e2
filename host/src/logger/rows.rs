//! The recording CSV's rows, formatted fast: the contract's writer ([`RecordingWriter`]) writes
//! the metadata and header, and the rows (sixteen thousand a second for a hand, seventeen
//! values each) are formatted here straight into the output buffer: no allocation per value.
//! A column with a resolution ([`RowWriter::set_decimals`]: the times to the µs, the ADC's
//! outputs to a tenth of a code) is written with that many decimals from an integer (`itoa`),
//! not with the 17 significant digits of the `f64`, which the data do not hold; any other column
//! with `itoa` for whole numbers and `ryu` (the shortest form that reads back as the same
//! `f64`) for the rest. A value equal to the one above it in its column (the frame's host
//! time, its temperature, its sequence: ten rows share them) is copied from there, not
//! formatted again. Same layout as the contract writer: comma-separated, a missing value (NaN)
//! empty.

use std::io::Write;

use recording::{Meta, RecordingWriter};

/// Whole numbers below this are written as integers (exactly representable in an `f64`).
const EXACT_INT: f64 = 9_007_199_254_740_992.0;

/// Bytes of rows gathered before they go to the file (a quarter second of one finger).
const BUFFER: usize = 1 << 16;

/// Most decimals a column is written with: `10^d` and the scaled value stay exact integers.
pub const MAX_DECIMALS: u8 = 15;

/// `10^d` for every `d` up to [`MAX_DECIMALS`] (exact as an `f64` too).
const POW10: [u64; MAX_DECIMALS as usize + 1] = {
    let mut p = [1u64; MAX_DECIMALS as usize + 1];
    let mut i = 1;
    while i < p.len() {
        p[i] = p[i - 1] * 10;
        i += 1;
    }
    p
};

/// Scaled values at or above this are written in the shortest form instead (an `i64` holds
/// them, and an `f64` below 2^53 is an exact integer).
const FIXED_LIMIT: f64 = 9.0e15;

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
    /// Per column, in row order: `Some(d)` writes `d` decimals, `None` the shortest form.
    decimals: Vec<Option<u8>>,
    ryu: ryu::Buffer,
    itoa: itoa::Buffer,
}

/// Decimals that write a value of resolution `step` (one code of the ADC, say) to a tenth of
/// a step: enough to tell every step from its neighbours, no more. `None` for a step that is
/// not a positive finite number (no resolution known: the shortest form).
pub fn decimals_for(step: f64) -> Option<u8> {
    if !(step.is_finite() && step > 0.0) {
        return None;
    }
    let d = (-step.log10()).ceil() + 1.0;
    Some(d.clamp(0.0, f64::from(MAX_DECIMALS)) as u8)
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
            decimals: Vec::new(),
            ryu: ryu::Buffer::new(),
            itoa: itoa::Buffer::new(),
        }
    }

    /// The decimals of each column, in row order (`required`, `temp_C` if the file has it,
    /// the extra columns); a column not named, or `None`, is written in its shortest form.
    pub fn set_decimals(&mut self, decimals: &[Option<u8>]) {
        self.decimals = decimals
            .iter()
            .map(|d| d.map(|d| d.min(MAX_DECIMALS)))
            .collect();
        // The texts kept for copying were written with the old decimals.
        self.last.clear();
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
        let at = self.buf.len();
        match self.decimals.get(i).copied().flatten() {
            Some(d) if fixed(&mut self.buf, &mut self.itoa, v, d) => {}
            _ if v.fract() == 0.0 && v.abs() < EXACT_INT => {
                self.buf
                    .extend_from_slice(self.itoa.format(v as i64).as_bytes());
            }
            _ => self
                .buf
                .extend_from_slice(self.ryu.format_finite(v).as_bytes()),
        }
        self.remember(i, bits, at);
    }

    /// Keep column `i`'s text (the buffer from `at`) for the next row to copy.
    fn remember(&mut self, i: usize, bits: u64, at: usize) {
        let text = &self.buf[at..];
        if self.last.len() <= i {
            let none = Last {
                bits: f64::NAN.to_bits(),
                text: [0; 24],
                len: 0,
            };
            self.last.resize(i + 1, none);
        }
        let l = &mut self.last[i];
        // Every text of ryu and itoa fits in 24 bytes, and a fixed one (under 2^53 scaled, at
        // most 15 decimals) in 19; a longer one is not kept.
        if text.len() > l.text.len() {
            l.bits = f64::NAN.to_bits();
            return;
        }
        l.bits = bits;
        l.len = text.len() as u8;
        l.text[..text.len()].copy_from_slice(text);
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

/// `v` with `d` decimals appended to `buf`, rounded half away from zero; `false` (nothing
/// written) when `v·10^d` is too large for an exact integer.
fn fixed(buf: &mut Vec<u8>, itoa: &mut itoa::Buffer, v: f64, d: u8) -> bool {
    let unit = POW10[usize::from(d)];
    let scaled = v * unit as f64;
    if scaled.abs() >= FIXED_LIMIT {
        return false;
    }
    // `as` truncates toward zero; the half added first makes it round.
    let m = (scaled + 0.5f64.copysign(scaled)) as i64;
    if m < 0 {
        buf.push(b'-');
    }
    let (whole, frac) = (m.unsigned_abs() / unit, m.unsigned_abs() % unit);
    buf.extend_from_slice(itoa.format(whole).as_bytes());
    if d > 0 {
        buf.push(b'.');
        let digits = itoa.format(frac).as_bytes();
        buf.resize(buf.len() + usize::from(d) - digits.len(), b'0');
        buf.extend_from_slice(digits);
    }
    true
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

    /// A column with decimals reads back within half its last digit, rounded half away from
    /// zero, with no more digits than asked for; a value too large for them is written whole.
    #[test]
    fn fixed_decimals_round_trip_to_their_last_digit() {
        let mut w = RowWriter::on(Box::new(std::io::sink()), false, Vec::new());
        w.set_decimals(&[Some(6), Some(8), Some(0), Some(3), Some(15), Some(2)]);
        let req = [1_764_000_000.123_456_7, -0.123_456_786, 2.5, -0.000_4, 0.1, 1e300];
        w.write_row(&req, f64::NAN, &[]).unwrap();
        let text = String::from_utf8(w.buf.clone()).unwrap();
        let fields: Vec<&str> = text.trim_end().split(',').collect();
        assert_eq!(
            fields[..5],
            ["1764000000.123457", "-0.12345679", "3", "0.000", "0.100000000000000"]
        );
        assert_eq!(fields[5].parse::<f64>().unwrap(), 1e300);
    }

    /// A tenth of a step: one code of a 24-bit ADC over ±1.2 V (0.14 µV) is 8 decimals.
    #[test]
    fn decimals_resolve_a_tenth_of_a_step() {
        assert_eq!(decimals_for(1.2 / 8_388_608.0), Some(8));
        assert_eq!(decimals_for(3e-6), Some(7));
        assert_eq!(decimals_for(0.0), None);
        assert_eq!(decimals_for(f64::NAN), None);
    }
}
