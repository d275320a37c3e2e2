//! The device core on the host: every command with valid and out-of-range arguments, commands at
//! frame boundaries, the drop counter under a slow link, and the whole chain against the sim's
//! emulated ADC.

use super::*;
use crate::ads131m04::Pga;
use crate::offset::{DriftSettings, NullTiming};
use protocol::{Command, NackCode, NullState, SampleFrame, CRC};

#[derive(Default)]
struct MockBoard {
    trims: Vec<[u16; 3]>,
    osrs: Vec<Osr>,
    fail_dac: bool,
    fail_adc: bool,
}

impl BoardControl for MockBoard {
    fn set_trim(&mut self, codes: [u16; 3]) -> Result<(), HardwareError> {
        if self.fail_dac {
            return Err(HardwareError::Dac);
        }
        self.trims.push(codes);
        Ok(())
    }
    fn set_osr(&mut self, osr: Osr) -> Result<(), HardwareError> {
        if self.fail_adc {
            return Err(HardwareError::Adc);
        }
        self.osrs.push(osr);
        Ok(())
    }
}

pub(super) fn config() -> DeviceConfig {
    DeviceConfig {
        chip_serial: 0x1234_5678,
        clkin_hz: 8_192_000,
        vref_mv: 1200,
        pga: [Pga::X1; 4],
        amp_gain: [3000.0, 2000.0, 2000.0],
        excitation_v: 3.3,
        calibration: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        osr: Osr::Osr4096, // 1000 samples/s
        batch: 4,
        filter: FilterConfig::NONE,
        null_timing: NullTiming {
            settle: 1,
            average: 2,
        },
        drift: DriftSettings {
            window: 1000,
            rate: 0.01,
            limit: 500,
        },
        dac_initial: [2048; 3],
        dac_vmid_code: 2048,
        null_at_power_up: false,
    }
}

fn raw(index: u32, codes: [i32; 4]) -> RawSample {
    RawSample {
        index,
        codes,
        read_error: false,
    }
}

/// Everything in the transmit buffer, decoded.
fn drain(dev: &mut Device) -> Vec<Message> {
    let mut bytes = Vec::new();
    dev.tx().drain(|b| {
        bytes.push(b);
        true
    });
    let mut acc = Accumulator::<{ protocol::MAX_ENCODED }>::new();
    acc.feed(&bytes)
        .map(|o| match o {
            Outcome::Message(m) => m,
            other => panic!("device sent a bad frame: {other:?}"),
        })
        .collect()
}

fn request(dev: &mut Device, tag: u8, command: Command) {
    let wire = protocol::encode_vec(&Message::Request(Request { tag, command })).unwrap();
    dev.on_rx(&wire);
}

fn replies(msgs: &[Message]) -> Vec<Reply> {
    msgs.iter()
        .filter_map(|m| {
            if let Message::Reply(r) = m {
                Some(*r)
            } else {
                None
            }
        })
        .collect()
}

fn frames(msgs: &[Message]) -> Vec<SampleFrame> {
    msgs.iter()
        .filter_map(|m| {
            if let Message::Sample(f) = m {
                Some(f.clone())
            } else {
                None
            }
        })
        .collect()
}

/// Send one command to a stopped device and return its reply.
fn answer(dev: &mut Device, hw: &mut MockBoard, command: Command) -> Reply {
    request(dev, 9, command);
    dev.poll(hw);
    let r = replies(&drain(dev));
    assert_eq!(r.len(), 1, "{command:?}: {r:?}");
    r[0]
}

fn ack(command: &Command) -> Reply {
    Reply::Ack {
        tag: 9,
        opcode: command.opcode(),
    }
}

fn nacked(command: &Command, code: NackCode) -> Reply {
    Reply::Nack {
        tag: 9,
        opcode: command.opcode(),
        code,
    }
}

fn check(dev: &mut Device, hw: &mut MockBoard, command: Command, expected: Result<(), NackCode>) {
    let epoch = dev.config_epoch();
    let got = answer(dev, hw, command);
    match expected {
        Ok(()) => assert_eq!(got, ack(&command), "{command:?}"),
        Err(code) => {
            assert_eq!(got, nacked(&command, code), "{command:?}");
            assert_eq!(
                dev.config_epoch(),
                epoch,
                "a refused command changes nothing: {command:?}"
            );
        }
    }
}

#[test]
fn set_rate_accepts_adc_rates_only() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    check(&mut dev, &mut hw, Command::SetRate { hz: 4000 }, Ok(()));
    assert_eq!(
        (dev.rate_hz(), hw.osrs.as_slice()),
        (4000, &[Osr::Osr1024][..])
    );
    check(
        &mut dev,
        &mut hw,
        Command::SetRate { hz: 1234 },
        Err(NackCode::OutOfRange),
    );
    check(
        &mut dev,
        &mut hw,
        Command::SetRate { hz: 0 },
        Err(NackCode::OutOfRange),
    );
    check(
        &mut dev,
        &mut hw,
        Command::SetRate { hz: 64_000 },
        Err(NackCode::OutOfRange),
    );
    // A low-pass at 200 Hz is fine at 4 kHz but not at 250 Hz (≥ 0.45·rate).
    let filter = FilterConfig {
        smoother_alpha: 1.0,
        butterworth_order: 2,
        cutoff_hz: 200.0,
    };
    check(&mut dev, &mut hw, Command::SetFilter(filter), Ok(()));
    check(
        &mut dev,
        &mut hw,
        Command::SetRate { hz: 250 },
        Err(NackCode::OutOfRange),
    );
    hw.fail_adc = true;
    check(
        &mut dev,
        &mut hw,
        Command::SetRate { hz: 1000 },
        Err(NackCode::Hardware),
    );
    assert_eq!(dev.rate_hz(), 4000);
}

#[test]
fn set_filter_checks_every_field() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    let f = |alpha, order, cutoff| {
        Command::SetFilter(FilterConfig {
            smoother_alpha: alpha,
            butterworth_order: order,
            cutoff_hz: cutoff,
        })
    };
    check(&mut dev, &mut hw, f(0.2, 4, 50.0), Ok(()));
    assert_eq!(
        dev.info().filter,
        FilterConfig {
            smoother_alpha: 0.2,
            butterworth_order: 4,
            cutoff_hz: 50.0
        }
    );
    check(&mut dev, &mut hw, f(0.0, 0, 0.0), Err(NackCode::OutOfRange));
    check(&mut dev, &mut hw, f(1.5, 0, 0.0), Err(NackCode::OutOfRange));
    check(
        &mut dev,
        &mut hw,
        f(1.0, 3, 50.0),
        Err(NackCode::OutOfRange),
    );
    check(
        &mut dev,
        &mut hw,
        f(1.0, 2, 450.0),
        Err(NackCode::OutOfRange),
    );
    check(&mut dev, &mut hw, f(1.0, 2, 0.0), Err(NackCode::OutOfRange));
    check(&mut dev, &mut hw, f(1.0, 2, 0.5), Err(NackCode::OutOfRange));
    assert_eq!(
        dev.info().filter.cutoff_hz,
        50.0,
        "refused settings leave the filter alone"
    );
}

#[test]
fn tare_averages_then_subtracts_and_is_reported() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    check(
        &mut dev,
        &mut hw,
        Command::Tare { samples: 0 },
        Err(NackCode::OutOfRange),
    );
    check(&mut dev, &mut hw, Command::Tare { samples: 4 }, Ok(()));
    check(
        &mut dev,
        &mut hw,
        Command::Tare { samples: 4 },
        Err(NackCode::Busy),
    );
    let epoch = dev.config_epoch();
    for i in 0..4 {
        dev.on_sample(&raw(i, [1000, -2000, 30, 5]), &mut hw);
    }
    assert_eq!(dev.config_epoch(), epoch.wrapping_add(1));
    assert_eq!(dev.info().tare, [1000, -2000, 30]);
    check(&mut dev, &mut hw, Command::Start, Ok(()));
    for i in 4..8 {
        dev.on_sample(&raw(i, [1010, -2000, 30, 5]), &mut hw);
    }
    let f = frames(&drain(&mut dev));
    assert_eq!(f.len(), 1);
    assert!(f[0].status.tare_active);
    assert!(f[0].samples().iter().all(|s| s.ch == [10, 0, 0]));
    check(&mut dev, &mut hw, Command::ClearTare, Ok(()));
    assert_eq!(dev.info().tare, [0, 0, 0]);
}

#[test]
fn auto_null_runs_reports_and_refuses_overlap() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    check(&mut dev, &mut hw, Command::AutoNull, Ok(()));
    assert_eq!(dev.null_state(), NullState::Searching);
    check(&mut dev, &mut hw, Command::AutoNull, Err(NackCode::Busy));
    check(
        &mut dev,
        &mut hw,
        Command::Tare { samples: 3 },
        Err(NackCode::Busy),
    );
    // A front end whose output is offset − 1000·(code − 2048), searched to the end.
    let offset = [500_000, -700_000, 0];
    let mut i = 0;
    while dev.null_state() == NullState::Searching {
        let dac = *hw.trims.last().unwrap();
        let codes = core::array::from_fn(|ch| {
            if ch < 3 {
                offset[ch] - 1000 * (i32::from(dac[ch]) - 2048)
            } else {
                0
            }
        });
        dev.on_sample(&raw(i as u32, codes), &mut hw);
        i += 1;
        assert!(i < 1000);
    }
    assert_eq!(dev.null_state(), NullState::Nulled);
    assert_eq!(&dev.info().dac_codes[..3], &[2548, 1348, 2048]);
    let mut failing = MockBoard {
        fail_dac: true,
        ..Default::default()
    };
    check(
        &mut dev,
        &mut failing,
        Command::AutoNull,
        Err(NackCode::Hardware),
    );
    assert_eq!(dev.null_state(), NullState::Failed);
}

#[test]
fn get_info_acks_then_sends_the_info_frame() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    request(&mut dev, 3, Command::GetInfo);
    dev.poll(&mut hw);
    let msgs = drain(&mut dev);
    assert_eq!(msgs.len(), 2);
    assert_eq!(
        msgs[0],
        Message::Reply(Reply::Ack {
            tag: 3,
            opcode: protocol::opcode::GET_INFO
        })
    );
    let Message::Info(info) = &msgs[1] else {
        panic!("{msgs:?}")
    };
    assert_eq!(
        (info.sample_rate_hz, info.batch, info.chip_serial),
        (1000, 4, 0x1234_5678)
    );
    assert_eq!(info.pga_gain, [1; 4]);
    assert_eq!(info.protocol_version, protocol::PROTOCOL_VERSION);
}

#[test]
fn calibration_ping_drift_batch_start_stop() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    let m = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]];
    check(&mut dev, &mut hw, Command::SetCalibration(m), Ok(()));
    assert_eq!(dev.info().calibration, m);
    assert_eq!(
        answer(&mut dev, &mut hw, Command::Ping { nonce: 77 }),
        Reply::Pong { tag: 9, nonce: 77 }
    );
    check(
        &mut dev,
        &mut hw,
        Command::SetDriftTracking { enabled: true },
        Ok(()),
    );
    assert!(dev.info().drift_tracking);
    check(
        &mut dev,
        &mut hw,
        Command::SetBatch { samples: 0 },
        Err(NackCode::OutOfRange),
    );
    check(
        &mut dev,
        &mut hw,
        Command::SetBatch { samples: 17 },
        Err(NackCode::OutOfRange),
    );
    check(&mut dev, &mut hw, Command::SetBatch { samples: 16 }, Ok(()));
    check(&mut dev, &mut hw, Command::Start, Ok(()));
    assert!(dev.streaming());
    check(&mut dev, &mut hw, Command::Stop, Ok(()));
    assert!(!dev.streaming());
}

/// A request frame with an arbitrary body (valid CRC and COBS).
fn raw_request(body: &[u8]) -> Vec<u8> {
    let mut payload = body.to_vec();
    payload.extend_from_slice(&CRC.checksum(body).to_le_bytes());
    let mut out = vec![0u8; payload.len() + 4];
    let n = cobs::encode(&payload, &mut out);
    out.truncate(n);
    out.push(0);
    out
}

#[test]
fn malformed_and_unknown_requests_are_nacked_with_their_tag() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    dev.on_rx(&raw_request(&[0x04, 21, protocol::opcode::SET_RATE, 1, 2])); // u32 cut short
    dev.on_rx(&raw_request(&[0x04, 22, 0x7F])); // no such opcode
    dev.on_rx(&raw_request(&[
        0x04,
        23,
        protocol::opcode::SET_DRIFT_TRACKING,
        2,
    ])); // not a bool
    dev.poll(&mut hw);
    let r = replies(&drain(&mut dev));
    assert_eq!(
        r,
        [
            Reply::Nack {
                tag: 21,
                opcode: protocol::opcode::SET_RATE,
                code: NackCode::Malformed
            },
            Reply::Nack {
                tag: 22,
                opcode: 0x7F,
                code: NackCode::UnknownCommand
            },
            Reply::Nack {
                tag: 23,
                opcode: protocol::opcode::SET_DRIFT_TRACKING,
                code: NackCode::OutOfRange
            },
        ]
    );
    dev.on_rx(&[0x55, 0x13, 0x00]); // garbage: not answered, counted
    assert_eq!(dev.counters().rx_errors, 1);
}

#[test]
fn commands_take_effect_at_the_next_frame_boundary() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    check(&mut dev, &mut hw, Command::Start, Ok(()));
    let epoch = dev.config_epoch();
    dev.on_sample(&raw(0, [1; 4]), &mut hw);
    request(&mut dev, 5, Command::SetBatch { samples: 2 });
    dev.poll(&mut hw); // a frame is open: nothing applied yet
    assert!(replies(&drain(&mut dev)).is_empty());
    for i in 1..4 {
        dev.on_sample(&raw(i, [1; 4]), &mut hw);
    }
    let msgs = drain(&mut dev);
    // The old frame (4 samples, old epoch) comes first, then the ack.
    let Message::Sample(first) = &msgs[0] else {
        panic!("{msgs:?}")
    };
    assert_eq!((first.len(), first.status.config_epoch), (4, epoch));
    assert_eq!(
        msgs[1],
        Message::Reply(Reply::Ack {
            tag: 5,
            opcode: protocol::opcode::SET_BATCH
        })
    );
    for i in 4..6 {
        dev.on_sample(&raw(i, [1; 4]), &mut hw);
    }
    let f = frames(&drain(&mut dev));
    assert_eq!(
        (f[0].len(), f[0].status.config_epoch, f[0].seq),
        (2, epoch.wrapping_add(1), 1)
    );
}

#[test]
fn slow_link_drops_whole_frames_and_counts_them_in_the_next_frame() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    check(&mut dev, &mut hw, Command::SetBatch { samples: 16 }, Ok(()));
    check(&mut dev, &mut hw, Command::Start, Ok(()));
    // The link carries 4 bytes per sample; a full frame needs 10.5: about 60 % must be dropped.
    let mut wire = Vec::new();
    for i in 0..16_000u32 {
        dev.on_sample(&raw(i, [i as i32, 0, 0, 0]), &mut hw);
        let mut budget = 4;
        dev.tx().drain(|b| {
            if budget == 0 {
                return false;
            }
            budget -= 1;
            wire.push(b);
            true
        });
    }
    // The link catches up after acquisition stops: everything queued arrives.
    dev.tx().drain(|b| {
        wire.push(b);
        true
    });
    let mut acc = Accumulator::<{ protocol::MAX_ENCODED }>::new();
    let mut received = Vec::new();
    for outcome in acc.feed(&wire) {
        match outcome {
            Outcome::Message(Message::Sample(f)) => received.push(f),
            other => panic!("a frame on the wire was damaged: {other:?}"),
        }
    }
    let c = dev.counters();
    assert!(c.frames_dropped > 400, "{c:?}");
    assert_eq!(c.frames_queued as usize, received.len());
    assert_eq!((c.frames_queued + c.frames_dropped) as usize, 16_000 / 16);
    // Every gap in seq is announced by the next frame's dropped count.
    for pair in received.windows(2) {
        let gap = pair[1].seq.wrapping_sub(pair[0].seq) - 1;
        assert_eq!(
            u32::from(pair[1].status.dropped),
            gap,
            "seq {} -> {}",
            pair[0].seq,
            pair[1].seq
        );
    }
    // Samples inside a delivered frame are consecutive (frames are never cut or merged).
    for f in &received {
        let first = f.samples()[0].ch[0];
        assert!(f
            .samples()
            .iter()
            .enumerate()
            .all(|(k, s)| s.ch[0] == first + k as i32));
    }
    // Every drop is announced, except those after the last frame that got through.
    let announced: u32 = received.iter().map(|f| u32::from(f.status.dropped)).sum();
    let last_seq = received.last().unwrap().seq;
    assert_eq!(announced + (999 - last_seq), c.frames_dropped);
}

#[test]
fn saturation_overrun_and_adc_error_flags() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    check(&mut dev, &mut hw, Command::Start, Ok(()));
    dev.on_sample(&raw(0, [CODE_MAX, 0, 0, CODE_MIN]), &mut hw);
    dev.on_sample(&raw(3, [0; 4]), &mut hw); // two conversions lost
    dev.on_sample(
        &RawSample {
            index: 4,
            codes: [0; 4],
            read_error: true,
        },
        &mut hw,
    );
    dev.on_sample(&raw(5, [0; 4]), &mut hw);
    dev.on_sample(&raw(6, [0; 4]), &mut hw);
    dev.on_sample(&raw(7, [0; 4]), &mut hw);
    dev.on_sample(&raw(8, [0; 4]), &mut hw);
    dev.on_sample(&raw(9, [0; 4]), &mut hw);
    let f = frames(&drain(&mut dev));
    assert_eq!(f[0].status.saturated, 0b1001);
    assert!(f[0].status.sample_overrun && f[0].status.adc_error);
    assert_eq!(f[0].t_us, 0);
    assert_eq!(
        f[1].t_us, 6000,
        "time follows the conversion index through the gap"
    );
    assert_eq!(
        f[1].status,
        Status {
            config_epoch: f[0].status.config_epoch,
            ..Status::default()
        }
    );
}

#[test]
fn a_repeated_index_still_advances_time_by_one_period() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    check(&mut dev, &mut hw, Command::SetBatch { samples: 1 }, Ok(()));
    check(&mut dev, &mut hw, Command::Start, Ok(()));
    for index in [10, 11, 11, 12] {
        dev.on_sample(&raw(index, [0; 4]), &mut hw);
    }
    let period_us = 1_000_000 / dev.rate_hz();
    let t: Vec<u32> = frames(&drain(&mut dev)).iter().map(|f| f.t_us).collect();
    assert_eq!(t, [0, period_us, 2 * period_us, 3 * period_us]);
}

mod against_emulation;
mod robustness;
