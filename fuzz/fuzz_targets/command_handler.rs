//! The firmware's receive and command path (host build of the firmware library) driven by
//! arbitrary operations: raw bytes, requests with arbitrary bodies under a valid CRC, samples
//! (saturating, lost, failed reads), failing hardware and a stalled link.
//!
//! Properties: no panic; every request the device's accumulator completes gets exactly one reply
//! with its tag and opcode, or is counted as a reply dropped for a stalled link (never a second
//! reply, never a reply to nothing); nothing waits forever once the link drains and a frame
//! boundary passes; every byte the device sends decodes; sample frames count every frame they
//! drop; the info frame's configuration stays within its documented bounds.
#![no_main]

use std::collections::HashMap;

use firmware::ads131m04::{Osr, Pga};
use firmware::device::{Device, DeviceConfig, BoardControl, HardwareError, RX_BYTES};
use firmware::offset::{DriftSettings, NullTiming};
use firmware::stream::RawSample;
use libfuzzer_sys::fuzz_target;
use protocol::{
    Accumulator, FilterConfig, Info, Malformed, Message, Outcome, Reply, CODE_MAX, CODE_MIN,
    MAX_BATCH,
};

/// The ADC clock of `hardware/adc.toml`, as the firmware is built with it.
const CLKIN_HZ: u32 = firmware::params::ADC_CLKIN_HZ;
const DRIFT_LIMIT: i32 = 500;
const DAC_FULL_SCALE: u16 = 4095;

fn config() -> DeviceConfig {
    DeviceConfig {
        chip_serial: 7,
        clkin_hz: CLKIN_HZ,
        vref_mv: 1200,
        pga: [Pga::X1; 4],
        amp_gain: [3000.0, 2000.0, 2000.0],
        excitation_v: 3.3,
        calibration: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        osr: Osr::Osr4096,
        batch: 4,
        filter: FilterConfig::NONE,
        null_timing: NullTiming {
            settle: 1,
            average: 2,
        },
        drift: DriftSettings {
            window: 1000,
            rate: 0.01,
            limit: DRIFT_LIMIT,
        },
        dac_initial: [2048; 3],
        dac_vmid_code: 2048,
        null_at_power_up: false,
    }
}

#[derive(Default)]
struct Hardware {
    fail_dac: bool,
    fail_adc: bool,
}

impl BoardControl for Hardware {
    fn set_trim(&mut self, codes: [u16; 3]) -> Result<(), HardwareError> {
        assert!(
            codes.iter().all(|&c| c <= DAC_FULL_SCALE),
            "DAC code {codes:?}"
        );
        if self.fail_dac {
            return Err(HardwareError::Dac);
        }
        Ok(())
    }
    fn set_osr(&mut self, _osr: Osr) -> Result<(), HardwareError> {
        if self.fail_adc {
            return Err(HardwareError::Adc);
        }
        Ok(())
    }
}

/// A request frame around an arbitrary body after the request type byte, with a valid CRC.
fn request_frame(rest: &[u8]) -> Vec<u8> {
    let mut body = vec![protocol::kind::REQUEST];
    body.extend_from_slice(rest);
    let crc = protocol::CRC.checksum(&body);
    body.extend_from_slice(&crc.to_le_bytes());
    let mut frame = vec![0u8; body.len() + body.len() / 254 + 2];
    let n = cobs::encode(&body, &mut frame);
    frame.truncate(n);
    frame.push(0);
    frame
}

/// The harness: the device, what was asked of it and what it answered.
struct Harness {
    dev: Device,
    hw: Hardware,
    /// A copy of the device's receive accumulator, to know which requests it completed.
    mirror: Accumulator<RX_BYTES>,
    /// Requests (tag, opcode) not yet answered.
    unanswered: HashMap<(u8, u8), u32>,
    out: Accumulator,
    stalled: bool,
    index: u32,
    last_seq: Option<u32>,
}

impl Harness {
    fn new() -> Self {
        let mut h = Self {
            dev: Device::new(config()),
            hw: Hardware::default(),
            mirror: Accumulator::with_capacity(),
            unanswered: HashMap::new(),
            out: Accumulator::new(),
            stalled: false,
            index: 0,
            last_seq: None,
        };
        h.dev
            .power_up(&mut h.hw)
            .expect("the DAC works at power-up");
        h
    }

    fn rx(&mut self, bytes: &[u8]) {
        for outcome in self.mirror.feed(bytes) {
            let key = match outcome {
                Outcome::Message(Message::Request(req)) => (req.tag, req.command.opcode()),
                Outcome::Malformed(Malformed::BadRequest { tag, opcode, .. }) => (tag, opcode),
                _ => continue,
            };
            *self.unanswered.entry(key).or_default() += 1;
        }
        self.dev.on_rx(bytes);
    }

    fn sample(&mut self, codes: [i32; 4], read_error: bool, lost: u32) {
        self.index = self.index.wrapping_add(1 + lost);
        let raw = RawSample {
            index: self.index,
            codes,
            read_error,
        };
        self.dev.on_sample(&raw, &mut self.hw);
    }

    /// Drain the transmit buffer (unless stalled) and check everything in it.
    fn link(&mut self) {
        self.dev.poll(&mut self.hw);
        if self.stalled {
            return;
        }
        let mut bytes = Vec::new();
        self.dev.tx().drain(|b| {
            bytes.push(b);
            true
        });
        let outcomes: Vec<Outcome> = self.out.feed(&bytes).collect();
        for outcome in outcomes {
            let Outcome::Message(msg) = outcome else {
                panic!("the device sent a bad frame: {outcome:?}");
            };
            match msg {
                Message::Reply(reply) => self.answered(reply),
                Message::Info(info) => check_info(&info),
                Message::Sample(frame) => {
                    if let Some(last) = self.last_seq {
                        let expected = last
                            .wrapping_add(1)
                            .wrapping_add(u32::from(frame.status.dropped));
                        // `dropped` saturates at u16::MAX; below that it is exact.
                        if frame.status.dropped < u16::MAX {
                            assert_eq!(frame.seq, expected, "a dropped frame went uncounted");
                        }
                    }
                    self.last_seq = Some(frame.seq);
                    assert!((1..=MAX_BATCH).contains(&frame.len()));
                    for s in frame.samples() {
                        assert!(s.ch.iter().all(|c| (CODE_MIN..=CODE_MAX).contains(c)));
                    }
                }
                Message::Request(req) => panic!("the device sent a request: {req:?}"),
            }
        }
    }

    fn answered(&mut self, reply: Reply) {
        let key = match reply {
            Reply::Ack { tag, opcode } | Reply::Nack { tag, opcode, .. } => (tag, opcode),
            Reply::Pong { tag, .. } => (tag, protocol::opcode::PING),
        };
        let n = self
            .unanswered
            .get_mut(&key)
            .unwrap_or_else(|| panic!("a reply to nothing: {reply:?}"));
        *n -= 1;
        if *n == 0 {
            self.unanswered.remove(&key);
        }
    }

    /// Unstall the link and pass a frame boundary: every request must now be answered.
    fn settle(&mut self) {
        self.stalled = false;
        self.hw = Hardware::default();
        self.link();
        // A frame holds at most MAX_BATCH samples: after that many a boundary has passed.
        for _ in 0..=MAX_BATCH {
            self.sample([0; 4], false, 0);
            self.link();
        }
        let open: u32 = self.unanswered.values().sum();
        assert_eq!(
            open,
            self.dev.counters().replies_dropped,
            "requests left without a reply (and not counted as dropped): {:?}",
            self.unanswered
        );
    }
}

/// The documented bounds of the device's configuration (device::command).
fn check_info(info: &Info) {
    assert!(
        (1..=MAX_BATCH as u8).contains(&info.batch),
        "batch {}",
        info.batch
    );
    assert!(
        Osr::for_rate(info.sample_rate_hz, CLKIN_HZ).is_some(),
        "rate {}",
        info.sample_rate_hz
    );
    let f = info.filter;
    assert!(f.smoother_alpha > 0.0 && f.smoother_alpha <= 1.0, "{f:?}");
    assert!(matches!(f.butterworth_order, 0 | 2 | 4), "{f:?}");
    if f.butterworth_order > 0 {
        let rate = info.sample_rate_hz as f32;
        assert!(
            f.cutoff_hz >= 1e-3 * rate && f.cutoff_hz < 0.45 * rate,
            "{f:?} at {rate}"
        );
    }
    assert!(info.calibration.iter().flatten().all(|v| v.is_finite()));
    assert!(info.dac_codes.iter().all(|&c| c <= DAC_FULL_SCALE));
    assert!(
        info.drift.iter().all(|d| d.abs() <= DRIFT_LIMIT),
        "{:?}",
        info.drift
    );
}

/// The next `n` bytes of `rest` (fewer at the end).
fn take<'a>(rest: &mut &'a [u8], n: usize) -> &'a [u8] {
    let (a, b) = rest.split_at(n.min(rest.len()));
    *rest = b;
    a
}

/// A channel code from one byte: spread over the full scale, the extremes saturate.
fn code(b: u8) -> i32 {
    match b {
        0x7F => CODE_MAX,
        0x80 => CODE_MIN,
        _ => i32::from(b as i8) << 16,
    }
}

fuzz_target!(|data: &[u8]| {
    let mut h = Harness::new();
    let mut rest = data;
    while let Some((&op, tail)) = rest.split_first() {
        rest = tail;
        match op % 4 {
            0 => {
                let n = usize::from(op >> 2);
                let bytes = take(&mut rest, n).to_vec();
                h.rx(&bytes);
            }
            1 => {
                let n = usize::from(op >> 2);
                let frame = request_frame(take(&mut rest, n));
                // Delivered whole or in two pieces, as a UART read would split it.
                let cut = usize::from(op >> 5).min(frame.len());
                h.rx(&frame[..cut]);
                h.rx(&frame[cut..]);
            }
            2 => {
                let b = take(&mut rest, 4);
                let codes: [i32; 4] =
                    core::array::from_fn(|i| code(b.get(i).copied().unwrap_or(0)));
                for _ in 0..(op >> 4) + 1 {
                    h.sample(codes, op & 0x04 != 0, u32::from(op & 0x08 != 0));
                }
            }
            _ => {
                h.hw.fail_dac = op & 0x04 != 0;
                h.hw.fail_adc = op & 0x08 != 0;
                h.stalled = op & 0x10 != 0;
            }
        }
        h.link();
    }
    h.settle();
});
