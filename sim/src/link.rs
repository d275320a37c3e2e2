//! A fault-injecting link between the device and the host: bit flips, dropped and duplicated
//! bytes, inserted garbage, truncated frames and stalls, each at its own rate. It keeps an exact
//! account of what it did — frames delivered intact, frames lost, junk frames the receiver must
//! reject — so a test can demand that the host's counters equal the injected ones.
//!
//! The link sees the device's byte stream, splits it at the 0x00 delimiters (the device's
//! output is clean COBS), and damages frame by frame. The account is taken from what was really
//! emitted, not from what was intended: a delimited unit of output counts as a delivered frame
//! exactly when its bytes are those of a frame sent (damage can cancel out, e.g. a duplicated
//! byte removed again by a truncation), and as junk otherwise.

use std::collections::HashMap;
use std::time::Duration;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// How often each fault happens.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaultRates {
    /// Per frame: one random bit of one random byte (delimiter included) flipped.
    pub bit_flip: f64,
    /// Per frame: one random byte removed.
    pub drop_byte: f64,
    /// Per frame: one random byte sent twice.
    pub duplicate_byte: f64,
    /// Per frame: 1–32 bytes of garbage sent before it (half of the bursts end in 0x00, as a
    /// glitch on an idle line does; the others run into the frame).
    pub garbage: f64,
    /// Per frame: the frame cut short (half of the time its delimiter goes with it, merging it
    /// with the next frame, as a cable pulled mid-frame does).
    pub truncate: f64,
    /// Per frame: the link stalls for [`FaultRates::stall_for`] after it.
    pub stall: f64,
    pub stall_for: Duration,
}

impl FaultRates {
    /// A clean link.
    pub const NONE: Self = Self {
        bit_flip: 0.0,
        drop_byte: 0.0,
        duplicate_byte: 0.0,
        garbage: 0.0,
        truncate: 0.0,
        stall: 0.0,
        stall_for: Duration::ZERO,
    };

    /// Every fault at the same per-frame `rate`.
    pub fn uniform(rate: f64, stall_for: Duration) -> Self {
        Self {
            bit_flip: rate,
            drop_byte: rate,
            duplicate_byte: rate,
            garbage: rate,
            truncate: rate,
            stall: rate,
            stall_for,
        }
    }
}

/// What the link did, counted by kind of fault and by effect on the frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Injected {
    /// Frames the device sent through the link.
    pub frames_in: u64,
    /// Frames that reached the output unchanged and delimited: the receiver must accept each.
    pub frames_delivered: u64,
    /// Frames that did not arrive intact: the receiver must not accept any of them.
    pub frames_lost: u64,
    /// Non-empty delimited units of output that are not an intact frame: the receiver must
    /// reject each one (CRC error, malformed or overflow).
    pub junk_units: u64,
    /// Delivered frames that follow one or more junk units since the previous delivered frame:
    /// the points where a receiver that resynchronises within one frame returns to good data.
    pub recoveries: u64,
    pub bit_flips: u64,
    pub bytes_dropped: u64,
    pub bytes_duplicated: u64,
    pub garbage_bursts: u64,
    pub truncations: u64,
    pub stalls: u64,
}

/// The faulty link. Feed it the device's bytes with [`FaultyLink::transmit`].
pub struct FaultyLink {
    rates: FaultRates,
    rng: ChaCha8Rng,
    partial: Vec<u8>,
    frame_index: u64,
    /// Output unit being assembled (bytes since the last 0x00 emitted).
    unit: Vec<u8>,
    /// Content of the frames that may still be in flight, by index: a unit equal to one of them
    /// is a delivered frame.
    in_flight: HashMap<u64, Vec<u8>>,
    /// Junk units emitted since the last delivered frame.
    junk_since_delivery: bool,
    counted: Injected,
}

impl FaultyLink {
    pub fn new(rates: FaultRates, seed: u64) -> Self {
        Self {
            rates,
            rng: ChaCha8Rng::seed_from_u64(seed),
            partial: Vec::new(),
            frame_index: 0,
            unit: Vec::new(),
            in_flight: HashMap::new(),
            junk_since_delivery: false,
            counted: Injected::default(),
        }
    }

    /// Change the rates from the next frame on (a test switches the faults on after a clean
    /// start and off for a clean end, so that losses at both ends show by sequence).
    pub fn set_rates(&mut self, rates: FaultRates) {
        self.rates = rates;
    }

    /// The account so far. Frames still in flight inside the link are not counted yet.
    pub fn injected(&self) -> Injected {
        let mut c = self.counted;
        c.frames_lost = c.frames_in - c.frames_delivered;
        c
    }

    /// Pass `bytes` from the device; damaged output is appended to `out`. Returns how long the
    /// link should stall before sending more (a proxy sleeps that long; a test may ignore it).
    pub fn transmit(&mut self, bytes: &[u8], out: &mut Vec<u8>) -> Duration {
        let mut stall = Duration::ZERO;
        for &b in bytes {
            if b != 0 {
                self.partial.push(b);
                continue;
            }
            let content = std::mem::take(&mut self.partial);
            if content.is_empty() {
                // An idle delimiter from the device: passes through, belongs to no frame.
                self.emit(out, &[0]);
                continue;
            }
            stall += self.frame(&content, out);
        }
        stall
    }

    fn frame(&mut self, content: &[u8], out: &mut Vec<u8>) -> Duration {
        let index = self.frame_index;
        self.frame_index += 1;
        self.counted.frames_in += 1;
        // A frame can only arrive within the next output unit or two; eight is ample.
        self.in_flight.retain(|i, _| i + 8 > index);
        self.in_flight.insert(index, content.to_vec());
        let mut bytes: Vec<u8> = content.iter().copied().chain([0u8]).collect();
        self.damage(&mut bytes);
        self.emit(out, &bytes);
        if self.rng.random_bool(self.rates.stall) {
            self.counted.stalls += 1;
            return self.rates.stall_for;
        }
        Duration::ZERO
    }

    fn damage(&mut self, bytes: &mut Vec<u8>) {
        let r = self.rates;
        if self.rng.random_bool(r.garbage) {
            self.counted.garbage_bursts += 1;
            let n = self.rng.random_range(1..=32);
            let mut burst: Vec<u8> = (0..n).map(|_| self.rng.random_range(1..=255u8)).collect();
            if self.rng.random_bool(0.5) {
                burst.push(0);
            }
            bytes.splice(0..0, burst);
        }
        if self.rng.random_bool(r.bit_flip) {
            self.counted.bit_flips += 1;
            let at = self.rng.random_range(0..bytes.len());
            bytes[at] ^= 1 << self.rng.random_range(0..8);
        }
        if self.rng.random_bool(r.drop_byte) && bytes.len() > 1 {
            self.counted.bytes_dropped += 1;
            let at = self.rng.random_range(0..bytes.len());
            bytes.remove(at);
        }
        if self.rng.random_bool(r.duplicate_byte) {
            self.counted.bytes_duplicated += 1;
            let at = self.rng.random_range(0..bytes.len());
            // A duplicated delimiter is an empty frame, harmless; a duplicated content byte
            // breaks the frame.
            bytes.insert(at + 1, bytes[at]);
        }
        if self.rng.random_bool(r.truncate) && bytes.len() > 2 {
            self.counted.truncations += 1;
            let keep = self.rng.random_range(1..bytes.len() - 1);
            let keep_delimiter = self.rng.random_bool(0.5);
            bytes.truncate(keep);
            if keep_delimiter {
                bytes.push(0);
            }
        }
    }

    /// Append to `out`, classifying each delimited output unit as a delivered frame or junk.
    fn emit(&mut self, out: &mut Vec<u8>, bytes: &[u8]) {
        out.extend_from_slice(bytes);
        for &b in bytes {
            if b != 0 {
                self.unit.push(b);
                continue;
            }
            if !self.unit.is_empty() {
                let delivered = self
                    .in_flight
                    .iter()
                    .find(|(_, c)| **c == self.unit)
                    .map(|(i, _)| *i);
                match delivered {
                    Some(i) => {
                        // Delivered once; a copy of it later would be junk.
                        self.in_flight.remove(&i);
                        self.counted.frames_delivered += 1;
                        if std::mem::take(&mut self.junk_since_delivery) {
                            self.counted.recoveries += 1;
                        }
                    }
                    None => {
                        self.counted.junk_units += 1;
                        self.junk_since_delivery = true;
                    }
                }
            }
            self.unit.clear();
        }
    }
}
