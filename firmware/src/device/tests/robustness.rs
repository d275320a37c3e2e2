//! Garbage, truncated, over-long and out-of-range arguments for every command, bursts of
//! requests, and the status flags for saturation and overruns: every request gets exactly one
//! reply with a code, nothing panics and nothing is left waiting.

use super::*;
use protocol::opcode;

/// Arguments of a valid request for each opcode that takes any.
fn valid_args() -> Vec<(u8, Vec<u8>)> {
    let filter = [&1.0f32.to_le_bytes()[..], &[2], &50.0f32.to_le_bytes()].concat();
    let identity: Vec<u8> = [1.0f32, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    vec![
        (opcode::SET_RATE, 2000u32.to_le_bytes().to_vec()),
        (opcode::SET_FILTER, filter),
        (opcode::TARE, 8u16.to_le_bytes().to_vec()),
        (opcode::SET_CALIBRATION, identity),
        (opcode::PING, 5u32.to_le_bytes().to_vec()),
        (opcode::SET_DRIFT_TRACKING, vec![1]),
        (opcode::SET_BATCH, vec![2]),
    ]
}

const NO_ARGS: [u8; 5] = [
    opcode::START,
    opcode::STOP,
    opcode::CLEAR_TARE,
    opcode::AUTO_NULL,
    opcode::GET_INFO,
];

/// Send one raw request body (after the type byte) and return the single reply to it.
fn raw_answer(dev: &mut Device, hw: &mut MockBoard, tag: u8, rest: &[u8]) -> Reply {
    let body = [&[protocol::kind::REQUEST, tag][..], rest].concat();
    dev.on_rx(&raw_request(&body));
    dev.poll(hw);
    let r = replies(&drain(dev));
    assert_eq!(r.len(), 1, "{rest:?}: {r:?}");
    r[0]
}

fn malformed(tag: u8, opcode: u8) -> Reply {
    Reply::Nack {
        tag,
        opcode,
        code: NackCode::Malformed,
    }
}

#[test]
fn truncated_and_over_long_arguments_are_nacked_malformed() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    let epoch = dev.config_epoch();
    for (op, args) in valid_args() {
        for cut in 0..args.len() {
            let rest = [&[op][..], &args[..cut]].concat();
            assert_eq!(
                raw_answer(&mut dev, &mut hw, cut as u8, &rest),
                malformed(cut as u8, op),
                "opcode {op:#04x} cut to {cut} bytes"
            );
        }
        let long = [&[op][..], &args, &[0]].concat();
        assert_eq!(
            raw_answer(&mut dev, &mut hw, 99, &long),
            malformed(99, op),
            "opcode {op:#04x} with a byte too many"
        );
    }
    for op in NO_ARGS {
        assert_eq!(raw_answer(&mut dev, &mut hw, 7, &[op, 0]), malformed(7, op));
    }
    assert_eq!(
        dev.config_epoch(),
        epoch,
        "no refused request changed anything"
    );
    assert!(!dev.streaming());
}

#[test]
fn non_finite_and_non_boolean_arguments_are_out_of_range() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    let out_of_range = |opcode| Reply::Nack {
        tag: 1,
        opcode,
        code: NackCode::OutOfRange,
    };
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let filters = [
            [&bad.to_le_bytes()[..], &[2], &50.0f32.to_le_bytes()].concat(),
            [&1.0f32.to_le_bytes()[..], &[2], &bad.to_le_bytes()].concat(),
        ];
        for args in filters {
            let rest = [&[opcode::SET_FILTER][..], &args].concat();
            assert_eq!(
                raw_answer(&mut dev, &mut hw, 1, &rest),
                out_of_range(opcode::SET_FILTER)
            );
        }
        let mut matrix = [0u8; 36];
        matrix[16..20].copy_from_slice(&bad.to_le_bytes());
        let rest = [&[opcode::SET_CALIBRATION][..], &matrix].concat();
        assert_eq!(
            raw_answer(&mut dev, &mut hw, 1, &rest),
            out_of_range(opcode::SET_CALIBRATION)
        );
    }
    for b in [2u8, 0x80, 0xFF] {
        assert_eq!(
            raw_answer(&mut dev, &mut hw, 1, &[opcode::SET_DRIFT_TRACKING, b]),
            out_of_range(opcode::SET_DRIFT_TRACKING)
        );
    }
    assert!(!dev.info().drift_tracking);
}

#[test]
fn every_out_of_range_extreme_is_refused() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    // 32 kSPS + 2^25: the OSR product wraps to exactly clkin/2 in u32 (found by fuzzing).
    for hz in [0, 1, u32::MAX, 32_000 + (1 << 25), 64_000] {
        check(
            &mut dev,
            &mut hw,
            Command::SetRate { hz },
            Err(NackCode::OutOfRange),
        );
    }
    for cutoff_hz in [f32::MIN_POSITIVE, -50.0, f32::MAX] {
        let filter = FilterConfig {
            smoother_alpha: 1.0,
            butterworth_order: 4,
            cutoff_hz,
        };
        check(
            &mut dev,
            &mut hw,
            Command::SetFilter(filter),
            Err(NackCode::OutOfRange),
        );
    }
    for order in [1, 3, 5, 255] {
        let filter = FilterConfig {
            smoother_alpha: 1.0,
            butterworth_order: order,
            cutoff_hz: 50.0,
        };
        check(
            &mut dev,
            &mut hw,
            Command::SetFilter(filter),
            Err(NackCode::OutOfRange),
        );
    }
    for samples in [0, 17, 255] {
        check(
            &mut dev,
            &mut hw,
            Command::SetBatch { samples },
            Err(NackCode::OutOfRange),
        );
    }
    assert_eq!(dev.rate_hz(), 1000);
    assert_eq!(dev.info().batch, 4);
}

#[test]
fn a_burst_of_requests_in_one_read_gets_one_reply_each() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    let burst: Vec<u8> = (0..20u8)
        .flat_map(|tag| {
            let req = Request {
                tag,
                command: Command::Ping {
                    nonce: u32::from(tag),
                },
            };
            protocol::encode_vec(&Message::Request(req)).unwrap()
        })
        .collect();
    dev.on_rx(&burst);
    dev.poll(&mut hw);
    let mut r = replies(&drain(&mut dev));
    r.sort_by_key(|reply| match *reply {
        Reply::Pong { tag, .. } | Reply::Ack { tag, .. } | Reply::Nack { tag, .. } => tag,
    });
    assert_eq!(r.len(), 20, "{r:?}");
    for (tag, reply) in (0..20u8).zip(&r) {
        let expected = if usize::from(tag) < PENDING_REQUESTS {
            Reply::Pong {
                tag,
                nonce: u32::from(tag),
            }
        } else {
            Reply::Nack {
                tag,
                opcode: opcode::PING,
                code: NackCode::Busy,
            }
        };
        assert_eq!(*reply, expected);
    }
    assert_eq!(dev.counters().replies_dropped, 0);
}

#[test]
fn a_stalled_link_drops_and_counts_replies_beyond_the_queue() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    check(&mut dev, &mut hw, Command::SetBatch { samples: 16 }, Ok(()));
    check(&mut dev, &mut hw, Command::Start, Ok(()));
    // Fill the transmit buffer with sample frames nobody drains.
    for i in 0..200 {
        dev.on_sample(&raw(i, [0; 4]), &mut hw);
    }
    let busy = |tag| {
        protocol::encode_vec(&Message::Request(Request {
            tag,
            command: Command::Ping { nonce: 0 },
        }))
        .unwrap()
    };
    // Four requests wait for the frame boundary; the busy nacks beyond what the reply queue and
    // the transmit buffer's last bytes hold are dropped and counted.
    let sent = 4 + PENDING_REPLIES as u8 + 8;
    for tag in 0..sent {
        dev.on_rx(&busy(tag));
    }
    let dropped = dev.counters().replies_dropped;
    assert!(dropped > 0);
    let mut r = Vec::new();
    for i in 200..216 {
        dev.on_sample(&raw(i, [0; 4]), &mut hw);
        r.extend(replies(&drain(&mut dev)));
    }
    dev.poll(&mut hw);
    r.extend(replies(&drain(&mut dev)));
    assert_eq!(r.len() as u32 + dropped, u32::from(sent), "{r:?}");
    let pongs = r.iter().filter(|x| matches!(x, Reply::Pong { .. })).count();
    assert_eq!(pongs, PENDING_REQUESTS, "the waiting requests are answered");
    assert_eq!(dev.counters().replies_dropped, dropped);
}

#[test]
fn queue_overruns_are_flagged_in_the_next_frame() {
    let (mut dev, mut hw) = (Device::new(config()), MockBoard::default());
    check(&mut dev, &mut hw, Command::SetBatch { samples: 1 }, Ok(()));
    check(&mut dev, &mut hw, Command::Start, Ok(()));
    dev.note_overruns(0);
    dev.on_sample(&raw(0, [0; 4]), &mut hw);
    dev.note_overruns(2);
    dev.on_sample(&raw(1, [0; 4]), &mut hw);
    dev.on_sample(&raw(2, [0; 4]), &mut hw);
    let f = frames(&drain(&mut dev));
    let overrun: Vec<bool> = f.iter().map(|f| f.status.sample_overrun).collect();
    assert_eq!(overrun, [false, true, false], "flagged once, then cleared");
}
