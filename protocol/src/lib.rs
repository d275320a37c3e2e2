//! The tactile wire format: the single definition of every frame and command exchanged between
//! the sensor firmware, the emulated sensor and the host.
//!
//! A frame on the wire is `COBS(body ‖ CRC-32C(body)) ‖ 0x00`: the zero byte delimits frames, so
//! a receiver that joins mid-stream or loses bytes resynchronises at the next zero. The body's
//! first byte says what it is ([`Message`]). The byte-exact layout is in `SPEC.md` beside this
//! crate; the golden vectors in `tests/golden.rs` pin it down.
//!
//! ```
//! use protocol::{encode, Accumulator, Command, Message, Outcome, Request, MAX_FRAME};
//!
//! let msg = Message::Request(Request { tag: 7, command: Command::Ping { nonce: 42 } });
//! let mut wire = [0u8; MAX_FRAME];
//! let n = encode(&msg, &mut wire).unwrap();
//!
//! let mut acc = Accumulator::new();
//! let got: Vec<Outcome> = acc.feed(&wire[..n]).collect();
//! assert_eq!(got, vec![Outcome::Message(msg)]);
//! ```
#![cfg_attr(not(any(test, feature = "std")), no_std)]
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

mod accumulator;
pub mod codes;
mod crc32c;
mod message;
mod sample_encoder;
mod wire;

use core::fmt;

pub use accumulator::{Accumulator, Outcome, Outcomes};
pub use crc32c::crc32c;
pub use message::*;
pub use sample_encoder::{SampleFrameBuf, SampleFrameEncoder, SampleHeader, SAMPLE_FRAME_MAX_WIRE};

/// Version of this wire format, sent in [`Info::protocol_version`]. See SPEC.md's versioning rule.
pub const PROTOCOL_VERSION: u8 = 1;

/// Most samples one sample frame carries.
pub const MAX_BATCH: usize = 16;

/// Largest body a receiver accepts: room for a full sample frame and for info frames of later
/// protocol versions, which may append fields.
pub const MAX_BODY: usize = 240;

/// Bytes of the CRC-32C trailer.
pub const CRC_LEN: usize = 4;

/// Largest COBS-encoded frame, without its delimiter: the accumulator's default capacity.
pub const MAX_ENCODED: usize = cobs::max_encoding_length(MAX_BODY + CRC_LEN);

/// Largest frame on the wire, delimiter included: size encode buffers with this.
pub const MAX_FRAME: usize = MAX_ENCODED + 1;

/// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78, init and xor-out 0xFFFFFFFF): better
/// Hamming distance than CRC-32/ISO-HDLC at these lengths, and in hardware on x86 and ARMv8.
/// The `crc` crate's catalogue definition, kept as the reference; the encoder and the accumulator
/// use the faster sliced [`crc32c`], which computes the same function.
pub const CRC: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISCSI);

/// Bytes one sample frame of `n` samples (1..=16) occupies on the wire, delimiter included.
/// COBS adds exactly one byte to any payload shorter than 254 bytes, so this does not depend on
/// the sample values.
pub const fn sample_frame_wire_len(n: usize) -> usize {
    SAMPLE_HEADER_LEN + n * SAMPLE_LEN + CRC_LEN + 1 + 1
}

/// Highest sample rate a link of `baud` (8N1: 10 bits per byte) carries without loss when every
/// frame holds `batch` samples.
pub fn max_lossless_rate_hz(baud: u32, batch: usize) -> f64 {
    let bytes_per_s = f64::from(baud) / 10.0;
    bytes_per_s * batch as f64 / sample_frame_wire_len(batch) as f64
}

/// Why a message could not be encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum EncodeError {
    /// The output buffer is shorter than the encoded frame (use [`MAX_FRAME`]).
    BufferTooSmall,
    /// A sample frame with no sample in it.
    EmptyBatch,
}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::BufferTooSmall => f.write_str("output buffer too small for the encoded frame"),
            Self::EmptyBatch => f.write_str("sample frame holds no sample"),
        }
    }
}

impl core::error::Error for EncodeError {}

/// Encode `msg` as one complete frame (COBS of body and CRC, then the 0x00 delimiter) into
/// `out`; returns the number of bytes written.
pub fn encode(msg: &Message, out: &mut [u8]) -> Result<usize, EncodeError> {
    if let Message::Sample(frame) = msg {
        return encode_sample(frame, out);
    }
    let mut body = [0u8; MAX_BODY + CRC_LEN];
    let n = match msg.encode_body(&mut body[..MAX_BODY]) {
        Some(n) => n,
        None if matches!(msg, Message::Sample(f) if f.is_empty()) => {
            return Err(EncodeError::EmptyBatch)
        }
        // Every message of this version fits MAX_BODY; the constants say so.
        None => unreachable!("message larger than MAX_BODY"),
    };
    let crc = crc32c(&body[..n]);
    body[n..n + CRC_LEN].copy_from_slice(&crc.to_le_bytes());
    let k = cobs::try_encode(&body[..n + CRC_LEN], out).map_err(|_| EncodeError::BufferTooSmall)?;
    *out.get_mut(k).ok_or(EncodeError::BufferTooSmall)? = 0;
    Ok(k + 1)
}

/// A sample frame through the in-place [`SampleFrameEncoder`], the path the firmware uses.
fn encode_sample(frame: &SampleFrame, out: &mut [u8]) -> Result<usize, EncodeError> {
    if frame.is_empty() {
        return Err(EncodeError::EmptyBatch);
    }
    let mut buf = [0u8; SAMPLE_FRAME_MAX_WIRE];
    let mut enc = SampleFrameEncoder::new();
    for s in frame.samples() {
        enc.push(&mut buf, s.ch);
    }
    let header = SampleHeader {
        seq: frame.seq,
        t_us: frame.t_us,
        status: frame.status,
        temp: frame.temp,
    };
    enc.finish_into(&mut buf, &header, out)
}

/// Encode into a new `Vec` (host side).
#[cfg(any(test, feature = "std"))]
pub fn encode_vec(msg: &Message) -> Result<Vec<u8>, EncodeError> {
    let mut out = vec![0u8; MAX_FRAME];
    let n = encode(msg, &mut out)?;
    out.truncate(n);
    Ok(out)
}

/// Why a frame whose CRC matched still could not be read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Malformed {
    /// The frame decoded to nothing.
    Empty,
    /// The COBS encoding is broken (a length byte points past the frame).
    Cobs,
    /// Shorter than a type byte and a CRC.
    Short,
    /// The first body byte is not a known message type.
    UnknownType(u8),
    /// A field ends past the body.
    Truncated,
    /// The body has the wrong length for its type; `expected` is the right length.
    Length { expected: usize },
    /// A sample frame claims 0 or more than [`MAX_BATCH`] samples.
    BadBatch(u8),
    /// Reserved bits or an undefined enumeration value are set.
    ReservedBits,
    /// A request that the device must refuse: it carries the tag and opcode to answer.
    BadRequest { tag: u8, opcode: u8, code: NackCode },
}

impl From<wire::Short> for Malformed {
    fn from(_: wire::Short) -> Self {
        Self::Truncated
    }
}

impl fmt::Display for Malformed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Empty => f.write_str("empty frame"),
            Self::Cobs => f.write_str("broken COBS encoding"),
            Self::Short => f.write_str("frame shorter than type byte and CRC"),
            Self::UnknownType(t) => write!(f, "unknown message type 0x{t:02x}"),
            Self::Truncated => f.write_str("a field runs past the end of the body"),
            Self::Length { expected } => write!(f, "wrong body length, expected {expected} bytes"),
            Self::BadBatch(n) => write!(f, "sample count {n} outside 1..={MAX_BATCH}"),
            Self::ReservedBits => f.write_str("reserved bits or undefined value set"),
            Self::BadRequest { tag, opcode, code } => {
                write!(
                    f,
                    "request tag {tag} opcode 0x{opcode:02x} refused: {code:?}"
                )
            }
        }
    }
}

impl core::error::Error for Malformed {}
