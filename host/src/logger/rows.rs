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

/// Scaled values at or above this are written in the shortest form instead: below it an `f64`
/// is an integer to within a unit (the Unix time in µs, 1.8e15, to a quarter), and the whole
/// part keeps to 16 digits.
const FIXED_LIMIT: f64 = 9.0e15;

/// Bytes of a value's text at most: `ryu`'s longest form; a fixed one (under 2^53 scaled, at
/// most 15 decimals, a sign and a point) takes 18.
const TEXT: usize = 24;

/// The digit pairs `00` to `99`: two digits per division.
const PAIRS: [u8; 200] = {
    let mut p = [0u8; 200];
    let mut i = 0;
    while i < 100 {
        p[2 * i] = b'0' + (i / 10) as u8;
        p[2 * i + 1] = b'0' + (i % 10) as u8;
        i += 1;
    }
    p
};

/// A column's last value, and its text while the column repeats, to copy when the next row
/// repeats it.
#[derive(Clone, Copy)]
struct Last {
    bits: u64,
    text: [u8; TEXT],
    /// The length of `text`; `None` when it is not kept.
    kept: Option<u8>,
}

impl Last {
    /// No value yet (a NaN's bits: a missing value is never written, so never matched).
    const NONE: Self = Self {
        bits: 0x7ff8_0000_0000_0000,
        text: [0; TEXT],
        kept: None,
    };
}

pub struct RowWriter {
    out: Box<dyn Write>,
    with_temp: bool,
    buf: Vec<u8>,
    /// The row being assembled, with room for every column's text at its longest: each
    /// value is written into a whole [`TEXT`]-byte slot (a copy of fixed size), and the row
    /// goes to `buf` in one copy.
    row: Vec<u8>,
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
            row: Vec::new(),
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

    /// One row: `required` = t_s, rod_mm, load_N, fz_V, mx_V, my_V; `temp_c` only if the file
    /// has that column; `extra` one value per extra column.
    pub fn write_row(
        &mut self,
        required: &[f64; 6],
        temp_c: f64,
        extra: &[f64],
    ) -> std::io::Result<()> {
        let temp = self.with_temp.then_some(temp_c);
        let n = required.len() + temp.iter().len() + extra.len();
        // Each column's slot and comma, and the newline.
        self.row.resize(self.row.len().max((n + 1) * (TEXT + 1)), 0);
        self.last.resize(self.last.len().max(n), Last::NONE);
        let mut at = 0;
        for (i, v) in required.iter().chain(temp.iter()).chain(extra).enumerate() {
            if i > 0 {
                self.row[at] = b',';
                at += 1;
            }
            at += self.value(i, *v, at);
        }
        self.row[at] = b'\n';
        self.buf.extend_from_slice(&self.row[..=at]);
        if self.buf.len() >= BUFFER {
            self.write_out()?;
        }
        Ok(())
    }

    /// Column `i`'s text of `v` in the row at `at` (nothing for a missing value); its length.
    fn value(&mut self, i: usize, v: f64, at: usize) -> usize {
        if !v.is_finite() {
            return 0;
        }
        let bits = v.to_bits();
        let slot: &mut [u8; TEXT] = (&mut self.row[at..at + TEXT])
            .try_into()
            .expect("a slot of TEXT bytes");
        let last = &mut self.last[i];
        let repeat = last.bits == bits;
        if let (true, Some(len)) = (repeat, last.kept) {
            *slot = last.text;
            return usize::from(len);
        }
        let len = match self.decimals.get(i).copied().flatten() {
            Some(d) => fixed(slot, v, d),
            None => None,
        }
        .unwrap_or_else(|| shortest(slot, v, &mut self.ryu, &mut self.itoa));
        // The text is kept once the column repeats (a frame's host time, sequence and
        // temperature are the same in its ten rows), not for a column that changes every row
        // (the times, the outputs): reading back the bytes just written costs a stall.
        last.bits = bits;
        last.kept = repeat.then(|| {
            last.text = *slot;
            len as u8
        });
        len
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

/// `v` in `slot` with `d` decimals, rounded half away from zero; its length, or `None`
/// (nothing written) when `v·10^d` is too large for an exact integer.
fn fixed(slot: &mut [u8; TEXT], v: f64, d: u8) -> Option<usize> {
    let d = usize::from(d);
    let scaled = v * POW10[d] as f64;
    if scaled.is_nan() || scaled.abs() >= FIXED_LIMIT {
        return None;
    }
    // `as` truncates toward zero; the half added first makes it round.
    let m = (scaled + 0.5f64.copysign(scaled)) as i64;
    let mut u = m.unsigned_abs();
    let sign = usize::from(m < 0);
    // At least one digit before the point: `0.05`, not `.05`.
    let n = (u.checked_ilog10().map_or(1, |l| l as usize + 1)).max(d + 1);
    let len = sign + n + usize::from(d > 0);
    // The sign first; without one the digits overwrite it.
    slot[0] = b'-';
    // Digits from the last, by constant divisors (no division by 10^d).
    let mut end = len;
    if d > 0 {
        let point = len - 1 - d;
        u = digits(&mut slot[point + 1..end], u);
        slot[point] = b'.';
        end = point;
    }
    digits(&mut slot[sign..end], u);
    Some(len)
}

/// The last `out.len()` decimal digits of `u` (zero-padded), two at a time; what is left of
/// `u` above them.
fn digits(out: &mut [u8], mut u: u64) -> u64 {
    let mut end = out.len();
    while end >= 2 {
        let r = (u % 100) as usize * 2;
        u /= 100;
        out[end - 2..end].copy_from_slice(&PAIRS[r..r + 2]);
        end -= 2;
    }
    if end == 1 {
        out[0] = b'0' + (u % 10) as u8;
        u /= 10;
    }
    u
}

/// `v` in `slot` in its shortest form: a whole number by `itoa`, any other by `ryu` (the
/// shortest text that reads back as the same `f64`); its length.
fn shortest(
    slot: &mut [u8; TEXT],
    v: f64,
    ryu: &mut ryu::Buffer,
    itoa: &mut itoa::Buffer,
) -> usize {
    let text = if v.fract() == 0.0 && v.abs() < EXACT_INT {
        itoa.format(v as i64).as_bytes()
    } else {
        ryu.format_finite(v).as_bytes()
    };
    // Every text of ryu and itoa fits in TEXT bytes.
    let len = text.len().min(TEXT);
    slot[..len].copy_from_slice(&text[..len]);
    len
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row reads back as the values written, whatever their form.
    #[test]
    fn values_round_trip() {
        let mut w = RowWriter::on(Box::new(std::io::sink()), true, Vec::new());
        let req = [1.0e-7, f64::NAN, -2.5, 1_764_000_000.123_456_7, 0.0, -3.0];
        // Three times: the second row keeps the repeated texts, the third copies them.
        for _ in 0..3 {
            w.write_row(&req, 25.5, &[42.0, 1e300]).unwrap();
        }
        let text = String::from_utf8(w.buf.clone()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!((lines[0], lines[1]), (lines[2], lines[2]));
        let line = lines[2];
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
        let req = [
            1_764_000_000.123_456_7,
            -0.123_456_786,
            2.5,
            -0.000_4,
            0.1,
            1e300,
        ];
        w.write_row(&req, f64::NAN, &[]).unwrap();
        let text = String::from_utf8(w.buf.clone()).unwrap();
        let fields: Vec<&str> = text.trim_end().split(',').collect();
        assert_eq!(
            fields[..5],
            [
                "1764000000.123457",
                "-0.12345679",
                "3",
                "0.000",
                "0.100000000000000"
            ]
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

    /// Over many magnitudes and decimals: exactly `d` decimals, and the value read back
    /// within half a unit of the last digit (plus the rounding of `v·10^d` to an `f64`, up to
    /// a unit near 2^53); the same text as the standard formatter away from a tie.
    #[test]
    fn fixed_reads_back_within_half_its_last_digit() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut slot = [0u8; TEXT];
        for _ in 0..20_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let d = (x % 13) as u8;
            let unit = 10f64.powi(i32::from(d));
            let v = ((x >> 11) as f64 / (1u64 << 53) as f64 - 0.5)
                * 10f64.powi((x >> 8) as i32 % 14 - 7);
            let Some(len) = fixed(&mut slot, v, d) else {
                assert!(v.abs() * unit >= FIXED_LIMIT, "{v}");
                continue;
            };
            let ours = std::str::from_utf8(&slot[..len]).unwrap();
            let decimals = ours.split_once('.').map_or(0, |(_, f)| f.len());
            assert_eq!(decimals, usize::from(d), "{ours}");
            let err = (ours.parse::<f64>().unwrap() - v).abs() * unit;
            let product_ulp = (v.abs() * unit).max(1.0) * f64::EPSILON;
            assert!(err <= 0.5 + 2.0 * product_ulp + 1e-9, "{v} as {ours}");
            if ((v.abs() * unit).fract() - 0.5).abs() > 1e-3 && v.abs() * unit < 1e14 {
                let std = format!("{v:.*}", usize::from(d));
                // Ours has no sign on a value that rounds to zero.
                let zero = !std.bytes().any(|b| (b'1'..=b'9').contains(&b));
                let std = if zero {
                    std.trim_start_matches('-')
                } else {
                    &std
                };
                assert_eq!(ours, std, "{v}");
            }
        }
    }
}
