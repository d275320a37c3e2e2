//! The messages: what each frame body means. Byte layouts are in `SPEC.md`; each `encode_body`
//! and `decode_body` below follows it field by field.

use crate::wire::{Reader, Short, Writer};
use crate::{Malformed, MAX_BATCH};

/// A 24-bit two's-complement ADS131M04 code, sign-extended into an `i32`.
pub type Code = i32;
/// Smallest 24-bit code.
pub const CODE_MIN: Code = -crate::codes::FULL_SCALE;
/// Largest 24-bit code.
pub const CODE_MAX: Code = crate::codes::FULL_SCALE - 1;

/// Frame type bytes, the first byte of every body.
pub mod kind {
    pub const SAMPLE: u8 = 0x01;
    pub const INFO: u8 = 0x02;
    pub const REPLY: u8 = 0x03;
    pub const REQUEST: u8 = 0x04;
}

/// One simultaneous reading of the three bridge channels (ADC channels 0..=2: Fz, Mx, My).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Sample {
    pub ch: [Code; 3],
}

/// Where the hardware offset null (trim-DAC search) stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NullState {
    /// Never run, or the DAC is at its reset codes.
    #[default]
    Off = 0,
    /// A search is running; samples are not meaningful.
    Searching = 1,
    /// Every channel was brought within its tolerance of mid-scale.
    Nulled = 2,
    /// At least one channel could not be brought within range (offset beyond the trim range).
    Failed = 3,
}

impl NullState {
    fn from_bits(bits: u8) -> Self {
        match bits & 0b11 {
            0 => Self::Off,
            1 => Self::Searching,
            2 => Self::Nulled,
            _ => Self::Failed,
        }
    }
}

/// Per-frame device state: nothing that changes the meaning of the samples is silent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Status {
    /// Bit i set: ADC channel i (0..=3) hit full scale in this frame's samples.
    pub saturated: u8,
    pub null_state: NullState,
    /// A digital tare is being subtracted from the samples.
    pub tare_active: bool,
    /// Slow drift tracking is adjusting the offsets.
    pub drift_tracking: bool,
    /// The acquisition queue overflowed since the last frame: samples were lost before framing.
    pub sample_overrun: bool,
    /// An ADC read failed (SPI CRC or bus error) since the last frame.
    pub adc_error: bool,
    /// Incremented by the device on every accepted configuration change (wraps).
    pub config_epoch: u8,
    /// Whole frames dropped since the previous frame because the link could not keep up.
    pub dropped: u16,
}

/// Size of the encoded [`Status`].
pub const STATUS_LEN: usize = 5;

impl Status {
    /// The five status bytes of a sample frame: saturated, flags, config_epoch, dropped (LE).
    pub fn to_bytes(&self) -> [u8; STATUS_LEN] {
        let flags = (self.null_state as u8)
            | (u8::from(self.tare_active) << 2)
            | (u8::from(self.drift_tracking) << 3)
            | (u8::from(self.sample_overrun) << 4)
            | (u8::from(self.adc_error) << 5);
        let [d0, d1] = self.dropped.to_le_bytes();
        [self.saturated & 0x0F, flags, self.config_epoch, d0, d1]
    }

    fn encode(&self, w: &mut Writer<'_>) -> bool {
        w.bytes(&self.to_bytes())
    }

    fn decode(r: &mut Reader<'_>) -> Result<Self, Malformed> {
        let saturated = r.u8()?;
        let flags = r.u8()?;
        if saturated & 0xF0 != 0 || flags & 0xC0 != 0 {
            return Err(Malformed::ReservedBits);
        }
        Ok(Self {
            saturated,
            null_state: NullState::from_bits(flags),
            tare_active: flags & (1 << 2) != 0,
            drift_tracking: flags & (1 << 3) != 0,
            sample_overrun: flags & (1 << 4) != 0,
            adc_error: flags & (1 << 5) != 0,
            config_epoch: r.u8()?,
            dropped: r.u16()?,
        })
    }
}

/// A batch of 1..=[`MAX_BATCH`] consecutive samples with their sequence, time and status.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SampleFrame {
    /// Device frame counter, +1 per frame produced (dropped frames included), wraps.
    pub seq: u32,
    /// Device time of the first sample, in microseconds, wraps every 71.6 minutes.
    pub t_us: u32,
    pub status: Status,
    /// ADC channel 3 (temperature sensor next to the chip), once per frame.
    pub temp: Code,
    len: u8,
    samples: [Sample; MAX_BATCH],
}

/// Bytes of a sample frame body before the samples: type, seq, t_us, status, temp, count.
pub const SAMPLE_HEADER_LEN: usize = 1 + 4 + 4 + STATUS_LEN + 3 + 1;
/// Bytes per sample in a sample frame body: three 24-bit codes.
pub const SAMPLE_LEN: usize = 9;

impl SampleFrame {
    /// An empty frame; [`SampleFrame::push`] samples into it before encoding.
    pub fn new(seq: u32, t_us: u32, status: Status, temp: Code) -> Self {
        Self {
            seq,
            t_us,
            status,
            temp,
            len: 0,
            samples: [Sample::default(); MAX_BATCH],
        }
    }

    /// Add a sample; gives it back if the frame already holds [`MAX_BATCH`].
    pub fn push(&mut self, sample: Sample) -> Result<(), Sample> {
        let slot = self.samples.get_mut(usize::from(self.len)).ok_or(sample)?;
        *slot = sample;
        self.len += 1;
        Ok(())
    }

    pub fn samples(&self) -> &[Sample] {
        &self.samples[..usize::from(self.len)]
    }

    pub fn len(&self) -> usize {
        usize::from(self.len)
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn is_full(&self) -> bool {
        usize::from(self.len) == MAX_BATCH
    }

    fn encode(&self, w: &mut Writer<'_>) -> bool {
        let mut ok = w.u8(kind::SAMPLE)
            && w.u32(self.seq)
            && w.u32(self.t_us)
            && self.status.encode(w)
            && w.i24(self.temp)
            && w.u8(self.len);
        for s in self.samples() {
            ok = ok && w.i24(s.ch[0]) && w.i24(s.ch[1]) && w.i24(s.ch[2]);
        }
        ok
    }

    fn decode(r: &mut Reader<'_>) -> Result<Self, Malformed> {
        let seq = r.u32()?;
        let t_us = r.u32()?;
        let status = Status::decode(r)?;
        let temp = r.i24()?;
        let n = r.u8()?;
        if n == 0 || usize::from(n) > MAX_BATCH {
            return Err(Malformed::BadBatch(n));
        }
        let expected = usize::from(n) * SAMPLE_LEN;
        if r.remaining() != expected {
            return Err(Malformed::Length {
                expected: SAMPLE_HEADER_LEN + expected,
            });
        }
        let mut frame = Self::new(seq, t_us, status, temp);
        for _ in 0..n {
            let s = Sample {
                ch: [r.i24()?, r.i24()?, r.i24()?],
            };
            frame.push(s).map_err(|_| Malformed::BadBatch(n))?;
        }
        Ok(frame)
    }
}

/// Digital filter settings, applied per bridge channel after the offset cut: first the
/// recursive smoother, then the Butterworth low-pass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterConfig {
    /// Weight of the new sample in `y = alpha·x + (1 − alpha)·y_prev`; 1.0 turns it off.
    pub smoother_alpha: f32,
    /// Butterworth low-pass order: 0 (off), 2 (one biquad) or 4 (two biquads).
    pub butterworth_order: u8,
    /// Butterworth −3 dB frequency; ignored when the order is 0.
    pub cutoff_hz: f32,
}

impl FilterConfig {
    /// No filtering at all.
    pub const NONE: Self = Self {
        smoother_alpha: 1.0,
        butterworth_order: 0,
        cutoff_hz: 0.0,
    };

    fn encode(&self, w: &mut Writer<'_>) -> bool {
        w.f32(self.smoother_alpha) && w.u8(self.butterworth_order) && w.f32(self.cutoff_hz)
    }

    fn decode(r: &mut Reader<'_>) -> Result<Self, Short> {
        Ok(Self {
            smoother_alpha: r.f32()?,
            butterworth_order: r.u8()?,
            cutoff_hz: r.f32()?,
        })
    }

    fn is_finite(&self) -> bool {
        self.smoother_alpha.is_finite() && self.cutoff_hz.is_finite()
    }
}

/// Row-major 3x3 matrix from bridge volts at the ADC input (Fz, Mx, My channels) to
/// (Fz in N, Mx in N·m, My in N·m).
pub type Calibration = [[f32; 3]; 3];

fn encode_matrix(m: &Calibration, w: &mut Writer<'_>) -> bool {
    m.iter().flatten().all(|v| w.f32(*v))
}

fn decode_matrix(r: &mut Reader<'_>) -> Result<Calibration, Short> {
    let mut m = [[0.0; 3]; 3];
    for v in m.iter_mut().flatten() {
        *v = r.f32()?;
    }
    Ok(m)
}

/// The device's identity and full configuration: enough to turn codes into volts and loads.
#[derive(Debug, Clone, PartialEq)]
pub struct Info {
    /// [`crate::PROTOCOL_VERSION`] of the firmware that sent it.
    pub protocol_version: u8,
    /// Firmware major, minor, patch.
    pub fw_version: [u8; 3],
    pub chip_serial: u32,
    pub sample_rate_hz: u32,
    /// Samples per sample frame.
    pub batch: u8,
    /// ADC programmable gain per channel (1, 2, 4, …, 128).
    pub pga_gain: [u8; 4],
    /// ADC reference in millivolts; full scale is ±vref/pga.
    pub vref_mv: u16,
    /// Voltage gain of the amplifier ahead of the ADC, per bridge channel.
    pub amp_gain: [f32; 3],
    /// Bridge excitation in volts.
    pub excitation_v: f32,
    pub filter: FilterConfig,
    pub calibration: Calibration,
    /// Trim-DAC codes (MCP4728 channels A..D) found by the last auto-null.
    pub dac_codes: [u16; 4],
    /// Digital tare subtracted from each bridge channel, in codes.
    pub tare: [i32; 3],
    /// Offset currently removed by drift tracking, in codes.
    pub drift: [i32; 3],
    pub null_state: NullState,
    pub drift_tracking: bool,
    pub streaming: bool,
    pub config_epoch: u8,
}

/// Bytes of an info body as this version writes it.
pub const INFO_LEN: usize =
    1 + 1 + 3 + 4 + 4 + 1 + 4 + 2 + 12 + 4 + 9 + 36 + 8 + 12 + 12 + 1 + 1 + 1;

impl Info {
    fn encode(&self, w: &mut Writer<'_>) -> bool {
        let flags = u8::from(self.drift_tracking) | (u8::from(self.streaming) << 1);
        w.u8(kind::INFO)
            && w.u8(self.protocol_version)
            && w.bytes(&self.fw_version)
            && w.u32(self.chip_serial)
            && w.u32(self.sample_rate_hz)
            && w.u8(self.batch)
            && w.bytes(&self.pga_gain)
            && w.u16(self.vref_mv)
            && self.amp_gain.iter().all(|g| w.f32(*g))
            && w.f32(self.excitation_v)
            && self.filter.encode(w)
            && encode_matrix(&self.calibration, w)
            && self.dac_codes.iter().all(|c| w.u16(*c))
            && self.tare.iter().all(|t| w.i32(*t))
            && self.drift.iter().all(|d| w.i32(*d))
            && w.u8(self.null_state as u8)
            && w.u8(flags)
            && w.u8(self.config_epoch)
    }

    /// Later protocol versions may append fields; a longer body is read up to what this
    /// version knows (see the versioning rule in SPEC.md).
    fn decode(r: &mut Reader<'_>) -> Result<Self, Malformed> {
        let protocol_version = r.u8()?;
        let fw_version = [r.u8()?, r.u8()?, r.u8()?];
        let chip_serial = r.u32()?;
        let sample_rate_hz = r.u32()?;
        let batch = r.u8()?;
        let pga_gain = [r.u8()?, r.u8()?, r.u8()?, r.u8()?];
        let vref_mv = r.u16()?;
        let amp_gain = [r.f32()?, r.f32()?, r.f32()?];
        let excitation_v = r.f32()?;
        let filter = FilterConfig::decode(r)?;
        let calibration = decode_matrix(r)?;
        let dac_codes = [r.u16()?, r.u16()?, r.u16()?, r.u16()?];
        let tare = [r.i32()?, r.i32()?, r.i32()?];
        let drift = [r.i32()?, r.i32()?, r.i32()?];
        let null_byte = r.u8()?;
        let flags = r.u8()?;
        let config_epoch = r.u8()?;
        if null_byte > 3 || flags & 0xFC != 0 {
            return Err(Malformed::ReservedBits);
        }
        Ok(Self {
            protocol_version,
            fw_version,
            chip_serial,
            sample_rate_hz,
            batch,
            pga_gain,
            vref_mv,
            amp_gain,
            excitation_v,
            filter,
            calibration,
            dac_codes,
            tare,
            drift,
            null_state: NullState::from_bits(null_byte),
            drift_tracking: flags & 1 != 0,
            streaming: flags & 2 != 0,
            config_epoch,
        })
    }
}

/// What the host asks the device to do. The device applies it at the next frame boundary and
/// answers with a [`Reply`] carrying the request's tag.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Command {
    /// Begin streaming sample frames.
    Start,
    /// Stop streaming (the current frame is finished first).
    Stop,
    /// Set the sample rate in Hz (the device refuses rates its ADC cannot run).
    SetRate { hz: u32 },
    /// Replace the filter settings.
    SetFilter(FilterConfig),
    /// Average this many samples at rest and subtract the mean from then on.
    Tare { samples: u16 },
    /// Stop subtracting the digital tare.
    ClearTare,
    /// Run the trim-DAC search that brings each amplified output near mid-scale.
    AutoNull,
    /// Send an [`Info`] frame.
    GetInfo,
    /// Store a new calibration matrix.
    SetCalibration(Calibration),
    /// Answer with a pong carrying `nonce`: a liveness and round-trip check.
    Ping { nonce: u32 },
    /// Turn the slow, bounded drift tracking on or off.
    SetDriftTracking { enabled: bool },
    /// Samples per frame, 1..=16.
    SetBatch { samples: u8 },
}

/// Opcode bytes of the commands.
pub mod opcode {
    pub const START: u8 = 0x01;
    pub const STOP: u8 = 0x02;
    pub const SET_RATE: u8 = 0x03;
    pub const SET_FILTER: u8 = 0x04;
    pub const TARE: u8 = 0x05;
    pub const CLEAR_TARE: u8 = 0x06;
    pub const AUTO_NULL: u8 = 0x07;
    pub const GET_INFO: u8 = 0x08;
    pub const SET_CALIBRATION: u8 = 0x09;
    pub const PING: u8 = 0x0A;
    pub const SET_DRIFT_TRACKING: u8 = 0x0B;
    pub const SET_BATCH: u8 = 0x0C;
}

impl Command {
    /// This command's opcode byte.
    pub fn opcode(&self) -> u8 {
        match self {
            Self::Start => opcode::START,
            Self::Stop => opcode::STOP,
            Self::SetRate { .. } => opcode::SET_RATE,
            Self::SetFilter(_) => opcode::SET_FILTER,
            Self::Tare { .. } => opcode::TARE,
            Self::ClearTare => opcode::CLEAR_TARE,
            Self::AutoNull => opcode::AUTO_NULL,
            Self::GetInfo => opcode::GET_INFO,
            Self::SetCalibration(_) => opcode::SET_CALIBRATION,
            Self::Ping { .. } => opcode::PING,
            Self::SetDriftTracking { .. } => opcode::SET_DRIFT_TRACKING,
            Self::SetBatch { .. } => opcode::SET_BATCH,
        }
    }

    fn encode_args(&self, w: &mut Writer<'_>) -> bool {
        match self {
            Self::Start | Self::Stop | Self::ClearTare | Self::AutoNull | Self::GetInfo => true,
            Self::SetRate { hz } => w.u32(*hz),
            Self::SetFilter(f) => f.encode(w),
            Self::Tare { samples } => w.u16(*samples),
            Self::SetCalibration(m) => encode_matrix(m, w),
            Self::Ping { nonce } => w.u32(*nonce),
            Self::SetDriftTracking { enabled } => w.u8(u8::from(*enabled)),
            Self::SetBatch { samples } => w.u8(*samples),
        }
    }

    /// Decode the arguments of `op`. Values are only checked for being representable here
    /// (finite floats, booleans 0/1); the device checks its own ranges.
    fn decode_args(op: u8, r: &mut Reader<'_>) -> Result<Self, NackCode> {
        let short = |_: Short| NackCode::Malformed;
        let cmd = match op {
            opcode::START => Self::Start,
            opcode::STOP => Self::Stop,
            opcode::SET_RATE => Self::SetRate {
                hz: r.u32().map_err(short)?,
            },
            opcode::SET_FILTER => {
                let f = FilterConfig::decode(r).map_err(short)?;
                if !f.is_finite() {
                    return Err(NackCode::OutOfRange);
                }
                Self::SetFilter(f)
            }
            opcode::TARE => Self::Tare {
                samples: r.u16().map_err(short)?,
            },
            opcode::CLEAR_TARE => Self::ClearTare,
            opcode::AUTO_NULL => Self::AutoNull,
            opcode::GET_INFO => Self::GetInfo,
            opcode::SET_CALIBRATION => {
                let m = decode_matrix(r).map_err(short)?;
                if !m.iter().flatten().all(|v| v.is_finite()) {
                    return Err(NackCode::OutOfRange);
                }
                Self::SetCalibration(m)
            }
            opcode::PING => Self::Ping {
                nonce: r.u32().map_err(short)?,
            },
            opcode::SET_DRIFT_TRACKING => match r.u8().map_err(short)? {
                0 => Self::SetDriftTracking { enabled: false },
                1 => Self::SetDriftTracking { enabled: true },
                _ => return Err(NackCode::OutOfRange),
            },
            opcode::SET_BATCH => Self::SetBatch {
                samples: r.u8().map_err(short)?,
            },
            _ => return Err(NackCode::UnknownCommand),
        };
        if r.remaining() != 0 {
            return Err(NackCode::Malformed);
        }
        Ok(cmd)
    }
}

/// A command with the tag the host chose to match its reply.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Request {
    pub tag: u8,
    pub command: Command,
}

impl Request {
    fn encode(&self, w: &mut Writer<'_>) -> bool {
        w.u8(kind::REQUEST)
            && w.u8(self.tag)
            && w.u8(self.command.opcode())
            && self.command.encode_args(w)
    }

    fn decode(r: &mut Reader<'_>) -> Result<Self, Malformed> {
        let tag = r.u8()?;
        let opcode = r.u8()?;
        match Command::decode_args(opcode, r) {
            Ok(command) => Ok(Self { tag, command }),
            Err(code) => Err(Malformed::BadRequest { tag, opcode, code }),
        }
    }
}

/// Why the device refused a request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum NackCode {
    /// The arguments were truncated, too long or not decodable.
    Malformed,
    /// The opcode is not one this firmware knows.
    UnknownCommand,
    /// An argument is outside the range the device accepts.
    OutOfRange,
    /// Not possible in the current state (e.g. tare while not streaming).
    InvalidState,
    /// The device is busy with an earlier request (e.g. an auto-null search).
    Busy,
    /// The hardware failed while carrying it out (ADC or DAC error).
    Hardware,
    /// A code from a newer firmware that this version does not know.
    Other(u8),
}

impl NackCode {
    pub fn to_byte(self) -> u8 {
        match self {
            Self::Malformed => 1,
            Self::UnknownCommand => 2,
            Self::OutOfRange => 3,
            Self::InvalidState => 4,
            Self::Busy => 5,
            Self::Hardware => 6,
            Self::Other(b) => b,
        }
    }

    pub fn from_byte(b: u8) -> Self {
        match b {
            1 => Self::Malformed,
            2 => Self::UnknownCommand,
            3 => Self::OutOfRange,
            4 => Self::InvalidState,
            5 => Self::Busy,
            6 => Self::Hardware,
            other => Self::Other(other),
        }
    }
}

/// The device's answer to a [`Request`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reply {
    /// Accepted; it takes effect at the next frame boundary.
    Ack { tag: u8, opcode: u8 },
    /// Refused, with the reason; nothing changed.
    Nack { tag: u8, opcode: u8, code: NackCode },
    /// Answer to [`Command::Ping`].
    Pong { tag: u8, nonce: u32 },
}

impl Reply {
    fn encode(&self, w: &mut Writer<'_>) -> bool {
        w.u8(kind::REPLY)
            && match *self {
                Self::Ack { tag, opcode } => w.u8(tag) && w.u8(opcode) && w.u8(0),
                Self::Nack { tag, opcode, code } => {
                    w.u8(tag) && w.u8(opcode) && w.u8(1) && w.u8(code.to_byte())
                }
                Self::Pong { tag, nonce } => {
                    w.u8(tag) && w.u8(opcode::PING) && w.u8(2) && w.u32(nonce)
                }
            }
    }

    fn decode(r: &mut Reader<'_>) -> Result<Self, Malformed> {
        let tag = r.u8()?;
        let opcode = r.u8()?;
        let reply = match r.u8()? {
            0 => Self::Ack { tag, opcode },
            1 => Self::Nack {
                tag,
                opcode,
                code: NackCode::from_byte(r.u8()?),
            },
            2 if opcode == opcode::PING => Self::Pong {
                tag,
                nonce: r.u32()?,
            },
            _ => return Err(Malformed::ReservedBits),
        };
        Ok(reply)
    }
}

/// Everything that travels on the link, in either direction.
#[derive(Debug, Clone, PartialEq)]
pub enum Message {
    Sample(SampleFrame),
    Info(Info),
    Reply(Reply),
    Request(Request),
}

impl Message {
    /// Serialise the body (no CRC, no COBS) into `buf`; `None` if it does not fit or the
    /// message is not encodable (a sample frame with no sample).
    pub fn encode_body(&self, buf: &mut [u8]) -> Option<usize> {
        let mut w = Writer::new(buf);
        let ok = match self {
            Self::Sample(f) => !f.is_empty() && f.encode(&mut w),
            Self::Info(i) => i.encode(&mut w),
            Self::Reply(r) => r.encode(&mut w),
            Self::Request(q) => q.encode(&mut w),
        };
        ok.then(|| w.len())
    }

    /// Parse a body (CRC already checked and stripped).
    pub fn decode_body(body: &[u8]) -> Result<Self, Malformed> {
        let mut r = Reader::new(body);
        let kind = r.u8().map_err(|_| Malformed::Empty)?;
        let msg = match kind {
            kind::SAMPLE => Self::Sample(SampleFrame::decode(&mut r)?),
            kind::INFO => Self::Info(Info::decode(&mut r)?),
            kind::REPLY => {
                let reply = Reply::decode(&mut r)?;
                if r.remaining() != 0 {
                    return Err(Malformed::Length {
                        expected: body.len() - r.remaining(),
                    });
                }
                Self::Reply(reply)
            }
            kind::REQUEST => Self::Request(Request::decode(&mut r)?),
            other => return Err(Malformed::UnknownType(other)),
        };
        Ok(msg)
    }
}
