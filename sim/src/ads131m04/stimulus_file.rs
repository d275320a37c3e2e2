//! A recorded analog input for the emulated ADC: per-conversion volts at the four ADC inputs read
//! from a stimulus file, so a test produced elsewhere (`tactile simulate --adc-stimulus`: a
//! compression test with the sensor's physics and any concealed effects) drives the firmware's
//! real driver, offset cut, filters and framing under QEMU. The QEMU board reads the file through
//! ARM semihosting in blocks; tests read it from memory. Both go through [`RecordSource`].
//!
//! File layout (little-endian, `f32` IEEE-754):
//!
//! | offset | bytes | field |
//! |---|---|---|
//! | 0 | 8 | magic `TACSTIM1` |
//! | 8 | 4 | `u32` header length in bytes ([`HEADER_BYTES`]; records start there) |
//! | 12 | 4 | `f32` sample rate the records were produced at, Hz |
//! | 16 | 4 | `u32` number of records |
//! | 20 | 12 | `f32` x 3 amplifier gains Fz, Mx, My of the sensor that produced them |
//! | 32 | 4 | `f32` bridge excitation, V |
//! | 36 | 16 per record | `f32` x 4 volts at ADC inputs 0..=3 (Fz, Mx, My, temperature sensor) |
//!
//! The bridge channels' records are the signal after the offset cut (what a nulled, tared channel
//! shows); the QEMU bench adds its own raw offsets and trim-DAC response ([`Stimulus::bridge_v`]),
//! so the firmware's auto-null runs exactly as with the triangle stimulus. Channel 3 (the
//! temperature sensor) is taken as recorded.
//!
//! Playback is sequential, one record per conversion, and starts on [`FileStimulus::start`]
//! (the test machine starts its run when the host starts recording). Before that the inputs
//! replay the first block over and over: a file begins with the sensor at rest (at least
//! [`BLOCK_RECORDS`] records), so the power-up auto-null sees the rest with its noise, as it would
//! on the bench. After the last record the inputs hold it and [`FileStimulus::finished`] turns
//! true.

use super::stimulus::Stimulus;
use super::trim_dac::TrimInput;
use super::AnalogInput;
use ads131m04_regs::Osr;

/// First bytes of a stimulus file.
pub const MAGIC: [u8; 8] = *b"TACSTIM1";
/// Header length written by this version.
pub const HEADER_BYTES: usize = 36;
/// Bytes per record: four `f32`.
pub const RECORD_BYTES: usize = 16;
/// Records read per block (2 KiB): one semihosting call every 128 conversions.
pub const BLOCK_RECORDS: usize = 128;

/// What the header says about the records.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Header {
    /// Rate the records were produced at; the board converts at this rate.
    pub sample_rate_hz: f32,
    /// Number of records.
    pub records: u32,
    /// Amplifier gains Fz, Mx, My of the sensor model that produced the volts (reported by the
    /// board in its info frame, so the recording's metadata describes the sensor).
    pub amp_gain: [f32; 3],
    /// Bridge excitation of that sensor model.
    pub excitation_v: f32,
}

/// A header that cannot be used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum HeaderError {
    /// Fewer bytes than a header.
    Short,
    /// The file does not start with [`MAGIC`].
    Magic,
    /// The header length field is below [`HEADER_BYTES`].
    Length,
    /// Sample rate, a gain or the excitation is not a positive finite number.
    Value,
}

fn f32_at(b: &[u8], at: usize) -> f32 {
    f32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

impl Header {
    /// The header's bytes.
    pub fn to_bytes(&self) -> [u8; HEADER_BYTES] {
        let mut b = [0u8; HEADER_BYTES];
        b[..8].copy_from_slice(&MAGIC);
        b[8..12].copy_from_slice(&(HEADER_BYTES as u32).to_le_bytes());
        b[12..16].copy_from_slice(&self.sample_rate_hz.to_le_bytes());
        b[16..20].copy_from_slice(&self.records.to_le_bytes());
        for (i, g) in self.amp_gain.iter().enumerate() {
            b[20 + 4 * i..24 + 4 * i].copy_from_slice(&g.to_le_bytes());
        }
        b[32..36].copy_from_slice(&self.excitation_v.to_le_bytes());
        b
    }

    /// Parse the first bytes of a file; returns the header and where the records start.
    pub fn parse(b: &[u8]) -> Result<(Self, usize), HeaderError> {
        if b.len() < HEADER_BYTES {
            return Err(HeaderError::Short);
        }
        if b[..8] != MAGIC {
            return Err(HeaderError::Magic);
        }
        let length = u32_at(b, 8) as usize;
        if length < HEADER_BYTES {
            return Err(HeaderError::Length);
        }
        let h = Self {
            sample_rate_hz: f32_at(b, 12),
            records: u32_at(b, 16),
            amp_gain: core::array::from_fn(|i| f32_at(b, 20 + 4 * i)),
            excitation_v: f32_at(b, 32),
        };
        let positive = |v: f32| v.is_finite() && v > 0.0;
        if !(positive(h.sample_rate_hz)
            && h.amp_gain.iter().all(|g| positive(*g))
            && positive(h.excitation_v))
        {
            return Err(HeaderError::Value);
        }
        Ok((h, length))
    }
}

/// Whether the emulated ADC, clocked at `clkin_hz`, converts at exactly `rate_hz` (CLKIN / 2 /
/// OSR for one of its OSRs, a whole number of samples per second as the firmware's rate setting
/// needs): a stimulus file plays one record per conversion, so it must be produced at such a rate.
pub fn is_data_rate(rate_hz: f64, clkin_hz: u32) -> bool {
    let half_clkin_hz = clkin_hz / 2;
    Osr::ALL.iter().any(|osr| {
        half_clkin_hz % osr.ratio() == 0 && f64::from(osr.data_rate_hz(clkin_hz)) == rate_hz
    })
}

/// One record's bytes.
pub fn record_bytes(volts: [f32; 4]) -> [u8; RECORD_BYTES] {
    let mut b = [0u8; RECORD_BYTES];
    for (i, v) in volts.iter().enumerate() {
        b[4 * i..4 * i + 4].copy_from_slice(&v.to_le_bytes());
    }
    b
}

/// Where the records come from, positioned at the first record.
pub trait RecordSource {
    /// Read up to `buf.len()` bytes from the current position; 0 at the end (or on an error:
    /// the test is then over).
    fn read(&mut self, buf: &mut [u8]) -> usize;
}

/// Records held in memory (tests, host-side replays).
pub struct SliceSource<'a> {
    bytes: &'a [u8],
}

impl<'a> SliceSource<'a> {
    /// `bytes` = the records, header already removed.
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes }
    }
}

impl RecordSource for SliceSource<'_> {
    fn read(&mut self, buf: &mut [u8]) -> usize {
        let n = buf.len().min(self.bytes.len());
        buf[..n].copy_from_slice(&self.bytes[..n]);
        self.bytes = &self.bytes[n..];
        n
    }
}

/// The QEMU bench (raw offsets, trim DAC) with a recorded signal in place of the triangles.
pub struct FileStimulus<S> {
    /// Offsets and trim codes of the bench; its triangle signal is not used.
    pub bench: Stimulus,
    pub header: Header,
    source: S,
    block: [u8; BLOCK_RECORDS * RECORD_BYTES],
    /// Bytes of `block` holding records, and the next one to play.
    len: usize,
    pos: usize,
    /// The record on the inputs now.
    current: [f32; 4],
    played: u32,
    started: bool,
    /// Conversions before the start (they cycle through the first block).
    idle: usize,
}

impl<S: RecordSource> FileStimulus<S> {
    /// Load the first block, which the inputs cycle through until [`Self::start`]. `None` if the
    /// file holds no record.
    pub fn new(bench: Stimulus, header: Header, source: S) -> Option<Self> {
        let mut s = Self {
            bench,
            header,
            source,
            block: [0; BLOCK_RECORDS * RECORD_BYTES],
            len: 0,
            pos: 0,
            current: [0.0; 4],
            played: 0,
            started: false,
            idle: 0,
        };
        s.current = s.next_record()?;
        s.played = 0;
        // The first record is played again as sample 0 once the run starts.
        s.pos = 0;
        Some(s)
    }

    /// The `k`-th record of the block in memory (before the start: the file's first block).
    fn block_record(&self, k: usize) -> [f32; 4] {
        let b = &self.block[k * RECORD_BYTES..(k + 1) * RECORD_BYTES];
        core::array::from_fn(|i| f32_at(b, 4 * i))
    }

    /// Start the playback with the next conversion.
    pub fn start(&mut self) {
        self.started = true;
    }

    pub fn started(&self) -> bool {
        self.started
    }

    /// Every record has been played.
    pub fn finished(&self) -> bool {
        self.played >= self.header.records
    }

    /// Records played since the start.
    pub fn played(&self) -> u32 {
        self.played
    }

    fn next_record(&mut self) -> Option<[f32; 4]> {
        if self.pos + RECORD_BYTES > self.len {
            let n = self.source.read(&mut self.block);
            self.len = n - n % RECORD_BYTES;
            self.pos = 0;
            if self.len == 0 {
                return None;
            }
        }
        let record = self.block_record(self.pos / RECORD_BYTES);
        self.pos += RECORD_BYTES;
        self.played += 1;
        Some(record)
    }

    /// Volts at the ADC inputs for the record on the inputs now.
    pub fn volts(&self) -> [f32; 4] {
        let mut v = self.current;
        for (ch, v) in v.iter_mut().take(3).enumerate() {
            *v = self.bench.bridge_v(ch, *v);
        }
        v
    }
}

impl<S: RecordSource> AnalogInput for FileStimulus<S> {
    /// The conversion index is not used: playback is sequential from [`Self::start`].
    fn sample_v(&mut self, _index: u64) -> [f32; 4] {
        if !self.started {
            self.current = self.block_record(self.idle % (self.len / RECORD_BYTES));
            self.idle += 1;
        } else if !self.finished() {
            match self.next_record() {
                Some(r) => self.current = r,
                // A file shorter than its header says: the test ends here.
                None => self.played = self.header.records,
            }
        }
        self.volts()
    }
}

impl<S> TrimInput for FileStimulus<S> {
    fn set_trim(&mut self, channel: usize, code: u16) {
        self.bench.set_trim(channel, code);
    }
}

/// Write a stimulus file.
#[cfg(feature = "std")]
pub fn write(
    mut out: impl std::io::Write,
    sample_rate_hz: f32,
    amp_gain: [f32; 3],
    excitation_v: f32,
    records: &[[f32; 4]],
) -> std::io::Result<()> {
    let header = Header {
        sample_rate_hz,
        records: u32::try_from(records.len())
            .map_err(|_| std::io::Error::other("more than 2^32 records"))?,
        amp_gain,
        excitation_v,
    };
    out.write_all(&header.to_bytes())?;
    for r in records {
        out.write_all(&record_bytes(*r))?;
    }
    out.flush()
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::super::stimulus::{StimulusParams, TRIM_MID_CODE};
    use super::*;

    fn file(records: &[[f32; 4]]) -> Vec<u8> {
        let mut b = Vec::new();
        write(&mut b, 500.0, [3000.0, 1000.0, 1000.0], 3.3, records).unwrap();
        b
    }

    fn ramp(n: usize) -> Vec<[f32; 4]> {
        (0..n)
            .map(|i| [i as f32 * 1e-3, -(i as f32) * 1e-3, 0.5, 0.75])
            .collect()
    }

    #[test]
    fn data_rates_are_clkin_over_twice_the_osr() {
        let rate = |hz| is_data_rate(hz, super::super::DATASHEET_PARAMS.clkin_hz);
        assert!(rate(500.0) && rate(1000.0) && rate(32_000.0));
        // 4.096 MHz / 16256 = 251.97 Hz: not a whole rate; 300 Hz: no OSR.
        assert!(!rate(4_096_000.0 / 16_256.0) && !rate(300.0));
    }

    #[test]
    fn header_round_trips_and_rejects_garbage() {
        let b = file(&ramp(3));
        let (h, at) = Header::parse(&b).unwrap();
        assert_eq!(at, HEADER_BYTES);
        assert_eq!(h.records, 3);
        assert_eq!(h.sample_rate_hz, 500.0);
        assert_eq!(h.amp_gain, [3000.0, 1000.0, 1000.0]);
        assert_eq!(b.len(), HEADER_BYTES + 3 * RECORD_BYTES);
        assert_eq!(Header::parse(&b[..10]), Err(HeaderError::Short));
        let mut bad = b.clone();
        bad[0] = b'X';
        assert_eq!(Header::parse(&bad), Err(HeaderError::Magic));
        let mut bad = b.clone();
        bad[12..16].copy_from_slice(&f32::NAN.to_le_bytes());
        assert_eq!(Header::parse(&bad), Err(HeaderError::Value));
    }

    /// Cycles through the first block until started, then one record per conversion across
    /// block boundaries, then holds the last one.
    #[test]
    fn plays_records_in_order_after_start() {
        let n = BLOCK_RECORDS * 2 + 7;
        let records = ramp(n);
        let b = file(&records);
        let (h, at) = Header::parse(&b).unwrap();
        let params = StimulusParams {
            offset_v: [0.0; 4],
            ..StimulusParams::QEMU_BOARD
        };
        let mut s =
            FileStimulus::new(Stimulus::new(params), h, SliceSource::new(&b[at..])).unwrap();
        for i in 0..BLOCK_RECORDS + 5 {
            assert_eq!(s.sample_v(0), records[i % BLOCK_RECORDS]);
        }
        s.start();
        for (i, r) in records.iter().enumerate() {
            assert!(!s.finished());
            assert_eq!(s.sample_v(i as u64), *r, "record {i}");
        }
        assert!(s.finished());
        assert_eq!(s.sample_v(0), records[n - 1]);
        assert_eq!(s.played() as usize, n);
    }

    /// The bench's raw offset and the trim DAC act on the bridge channels as with the triangles.
    #[test]
    fn bench_offset_and_trim_apply_to_the_bridges_only() {
        let records = ramp(2);
        let b = file(&records);
        let (h, at) = Header::parse(&b).unwrap();
        let bench = Stimulus::new(StimulusParams::QEMU_BOARD);
        let mut s = FileStimulus::new(bench, h, SliceSource::new(&b[at..])).unwrap();
        s.set_trim(0, TRIM_MID_CODE + 1000);
        let v = s.sample_v(0);
        let p = StimulusParams::QEMU_BOARD;
        assert!((v[0] - (p.offset_v[0] + records[0][0] - 0.3)).abs() < 1e-6);
        assert_eq!(v[1], p.offset_v[1] + records[0][1]);
        assert_eq!(v[3], records[0][3]);
    }

    #[test]
    fn a_short_file_ends_the_test_early() {
        let b = file(&ramp(10));
        let (h, at) = Header::parse(&b).unwrap();
        let mut s = FileStimulus::new(
            Stimulus::new(StimulusParams::QEMU_BOARD),
            h,
            SliceSource::new(&b[at..at + 4 * RECORD_BYTES + 3]),
        )
        .unwrap();
        s.start();
        for _ in 0..4 {
            s.sample_v(0);
        }
        assert!(!s.finished());
        s.sample_v(0);
        assert!(s.finished());
        assert!(FileStimulus::new(
            Stimulus::new(StimulusParams::QEMU_BOARD),
            h,
            SliceSource::new(&[])
        )
        .is_none());
    }
}
