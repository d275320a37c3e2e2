//! Round-trip properties: whatever is encoded decodes to itself, alone or back to back, fed in
//! any chunking; and any bytes at all decode without a panic.

mod common;

use common::random;
use proptest::prelude::*;
use protocol::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn decode_all(bytes: &[u8], chunk: usize) -> Vec<Outcome> {
    let mut acc = Accumulator::new();
    bytes
        .chunks(chunk.max(1))
        .flat_map(|c| acc.feed(c).collect::<Vec<_>>())
        .collect()
}

proptest! {
    #[test]
    fn any_message_round_trips(seed in any::<u64>()) {
        let msg = random::message(&mut ChaCha8Rng::seed_from_u64(seed));
        let wire = encode_vec(&msg).unwrap();
        prop_assert!(wire.len() <= MAX_FRAME);
        prop_assert_eq!(wire.iter().filter(|b| **b == 0).count(), 1, "only the delimiter is zero");
        prop_assert_eq!(decode_all(&wire, wire.len()), vec![Outcome::Message(msg)]);
    }

    #[test]
    fn a_stream_round_trips_in_any_chunking(seed in any::<u64>(), n in 1usize..20, chunk in 1usize..300) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let msgs: Vec<Message> = (0..n).map(|_| random::message(&mut rng)).collect();
        let wire: Vec<u8> = msgs.iter().flat_map(|m| encode_vec(m).unwrap()).collect();
        let expected: Vec<Outcome> = msgs.into_iter().map(Outcome::Message).collect();
        prop_assert_eq!(decode_all(&wire, chunk), expected);
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..2000), chunk in 1usize..64) {
        let _ = decode_all(&bytes, chunk);
        let _ = Message::decode_body(&bytes);
    }
}

#[test]
fn a_sample_frame_holds_one_to_sixteen_samples() {
    let mut f = SampleFrame::new(0, 0, Status::default(), 0);
    assert_eq!(
        encode_vec(&Message::Sample(f.clone())),
        Err(EncodeError::EmptyBatch)
    );
    for i in 0..MAX_BATCH {
        f.push(Sample { ch: [i as i32; 3] }).unwrap();
    }
    assert!(f.is_full());
    assert!(f.push(Sample::default()).is_err());
    assert_eq!(
        encode_vec(&Message::Sample(f)).unwrap().len(),
        sample_frame_wire_len(MAX_BATCH)
    );
}

#[test]
fn encode_refuses_a_short_buffer() {
    let msg = common::golden_messages::sample_frame();
    let mut out = [0u8; 10];
    assert_eq!(encode(&msg, &mut out), Err(EncodeError::BufferTooSmall));
}

#[test]
fn a_bad_request_carries_tag_and_opcode_for_the_nack() {
    let cases: &[(&[u8], NackCode)] = &[
        (&[0x04, 9, 0x7F], NackCode::UnknownCommand),
        (&[0x04, 9, opcode::SET_RATE, 1, 2], NackCode::Malformed),
        (&[0x04, 9, opcode::START, 0], NackCode::Malformed),
        (
            &[0x04, 9, opcode::SET_DRIFT_TRACKING, 2],
            NackCode::OutOfRange,
        ),
    ];
    for (body, code) in cases {
        let opcode = body[2];
        assert_eq!(
            Message::decode_body(body),
            Err(Malformed::BadRequest {
                tag: 9,
                opcode,
                code: *code
            }),
            "{body:02x?}"
        );
    }
    let mut nan_filter = vec![0x04, 9, opcode::SET_FILTER];
    nan_filter.extend_from_slice(&f32::NAN.to_le_bytes());
    nan_filter.push(2);
    nan_filter.extend_from_slice(&10.0f32.to_le_bytes());
    assert_eq!(
        Message::decode_body(&nan_filter),
        Err(Malformed::BadRequest {
            tag: 9,
            opcode: opcode::SET_FILTER,
            code: NackCode::OutOfRange
        })
    );
}

#[test]
fn an_overlong_frame_is_an_overflow_and_the_next_frame_decodes() {
    let msg = common::golden_messages::sample_frame();
    let mut wire = vec![0x55; MAX_ENCODED + 10];
    wire.push(0);
    wire.extend(encode_vec(&msg).unwrap());
    assert_eq!(
        decode_all(&wire, 7),
        vec![Outcome::Overflow, Outcome::Message(msg)]
    );
}

/// The acceptance figure: 921,600 baud 8N1 carries at least 8,500 samples/s in full frames.
#[test]
fn full_batches_carry_at_least_8500_samples_per_second_at_921600_baud() {
    let frame = {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut f = SampleFrame::new(1, 2, Status::default(), 3);
        while !f.is_full() {
            f.push(random::sample_frame(&mut rng).samples()[0]).unwrap();
        }
        f
    };
    let bytes = encode_vec(&Message::Sample(frame)).unwrap().len();
    assert_eq!(bytes, 168, "SPEC.md states 168 bytes per full frame");
    let rate = 921_600.0 / 10.0 * MAX_BATCH as f64 / bytes as f64;
    println!(
        "{bytes} bytes per 16 samples = {:.3} bytes/sample; max lossless rate {rate:.0} samples/s",
        bytes as f64 / 16.0
    );
    assert!(rate >= 8500.0, "{rate}");
    assert!((max_lossless_rate_hz(921_600, MAX_BATCH) - rate).abs() < 1e-9);
}
