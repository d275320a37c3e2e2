//! Golden byte vectors: the exact wire bytes of one message of every frame and command type.
//! A layout change makes these fail; that is the point. After a deliberate change, bump
//! PROTOCOL_VERSION, update SPEC.md, and regenerate with
//! `cargo run -p protocol --example dump_golden --features std`.

mod common;

use common::golden_messages;
use protocol::{encode_vec, Accumulator, Message, Outcome, CRC};

/// Hex digits to bytes; spaces only group fields for the reader.
fn hex(s: &str) -> Vec<u8> {
    let digits: Vec<u8> = s.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    digits
        .chunks(2)
        .map(|d| u8::from_str_radix(std::str::from_utf8(d).unwrap(), 16).unwrap())
        .collect()
}

const GOLDEN: &[(&str, &str)] = &[
    ("sample", "09 01 04 03 02 01 40 42 0f 0b 05 16 03 02 01 fe ff ff 02 01 01 07 ff ff ff ff ff 7f 01 05 80 56 34 12 01 01 05 28 89 51 aa 00"),
    ("info", "03 02 01 09 01 02 ef be ad de e8 03 01 08 10 01 02 04 80 b0 04 04 80 3b 45 01 03 7a 44 01 07 7a 44 33 33 53 40 01 04 80 3e 04 01 03 48 42 01 03 80 3f 01 01 01 01 01 01 01 01 01 01 01 01 01 01 02 40 01 01 01 01 01 01 01 01 01 01 01 01 01 01 02 bf 06 08 e8 03 b8 0b 01 06 f6 ff ff ff 14 01 01 06 e2 ff ff ff 01 01 01 06 fe ff ff ff 03 01 01 08 02 01 09 15 a6 7b bd 00"),
    ("request_start", "08 04 01 01 14 1c 73 1f 00"),
    ("request_stop", "08 04 02 02 79 47 c4 38 00"),
    ("request_set_rate", "06 04 03 03 40 1f 01 05 53 ac f4 f5 00"),
    ("request_set_filter", "04 04 04 04 01 04 80 3f 02 01 07 c8 42 5f 23 ae 84 00"),
    ("request_tare", "0a 04 05 05 f4 01 0b a9 b4 c0 00"),
    ("request_clear_tare", "08 04 06 06 ba b1 d4 b1 00"),
    ("request_auto_null", "08 04 07 07 ce aa 1d 50 00"),
    ("request_get_info", "08 04 08 08 17 9c 77 e9 00"),
    ("request_set_calibration", "04 04 09 09 01 03 80 3f 01 01 01 01 01 01 01 01 01 01 01 01 01 03 80 3f 01 01 01 01 01 01 01 01 01 01 01 01 01 07 80 3f c0 c7 e8 8f 00"),
    ("request_ping", "0c 04 0a 0a 0d f0 fe ca 08 f8 b8 85 00"),
    ("request_set_drift_tracking", "09 04 0b 0b 01 a0 6c a2 ba 00"),
    ("request_set_batch", "09 04 0c 0c 08 40 1a 8d cc 00"),
    ("reply_ack", "04 03 05 05 05 31 0d f2 4c 00"),
    ("reply_nack", "0a 03 06 03 01 03 43 7f d8 23 00"),
    ("reply_pong", "0d 03 07 0a 02 0d f0 fe ca 4f d9 88 14 00"),
];

#[test]
fn every_message_encodes_to_its_golden_bytes() {
    let messages = golden_messages::all();
    assert_eq!(messages.len(), GOLDEN.len(), "a golden vector per message");
    for ((name, msg), (gname, gbytes)) in messages.iter().zip(GOLDEN) {
        assert_eq!(name, gname);
        assert_eq!(encode_vec(msg).unwrap(), hex(gbytes), "{name}");
    }
}

#[test]
fn every_golden_vector_decodes_to_its_message() {
    for ((name, msg), (_, gbytes)) in golden_messages::all().iter().zip(GOLDEN) {
        let mut acc = Accumulator::new();
        let got: Vec<Outcome> = acc.feed(&hex(gbytes)).collect();
        assert_eq!(got, vec![Outcome::Message(msg.clone())], "{name}");
    }
}

/// Plain reference COBS (Cheshire & Baker), written from the paper's description, to check the
/// wire bytes independently of the `cobs` crate.
fn reference_cobs(data: &[u8]) -> Vec<u8> {
    let mut out = vec![0];
    let mut code_at = 0;
    for &b in data {
        if b == 0 {
            out[code_at] = (out.len() - code_at) as u8;
            code_at = out.len();
            out.push(0);
        } else {
            out.push(b);
            if out.len() - code_at == 0xFF {
                out[code_at] = 0xFF;
                code_at = out.len();
                out.push(0);
            }
        }
    }
    out[code_at] = (out.len() - code_at) as u8;
    out.push(0);
    out
}

/// Body bytes written out field by field from SPEC.md, then framed by the reference COBS.
#[test]
fn hand_written_bodies_match_the_spec() {
    let bodies: &[(&str, &str)] = &[
        // type | seq 0x01020304 | t_us 1e6 | sat 0b0101 | flags nulled+tare+overrun | epoch 3 |
        // dropped 258 | temp -2 | n=2 | [1,-1,max] | [min,0x123456,0]
        (
            "sample",
            "01 04030201 40420f00 05 16 03 0201 feffff 02 010000 ffffff ffff7f 000080 563412 000000",
        ),
        ("request_ping", "04 0a 0a 0df0feca"),
        ("request_set_rate", "04 03 03 401f0000"),
        ("reply_ack", "03 05 05 00"),
        ("reply_nack", "03 06 03 01 03"),
        ("reply_pong", "03 07 0a 02 0df0feca"),
    ];
    for (name, body_hex) in bodies {
        let mut body = hex(body_hex);
        let crc = CRC.checksum(&body);
        body.extend_from_slice(&crc.to_le_bytes());
        let golden = GOLDEN.iter().find(|(n, _)| n == name).unwrap().1;
        assert_eq!(reference_cobs(&body), hex(golden), "{name}");
    }
}

#[test]
fn crc_is_crc32c() {
    // The standard check value of CRC-32C over "123456789".
    assert_eq!(CRC.checksum(b"123456789"), 0xE306_9283);
}

#[test]
fn info_from_a_later_version_with_appended_fields_still_decodes() {
    let Message::Info(info) = golden_messages::info() else {
        unreachable!()
    };
    let mut body = vec![0u8; 240];
    let n = Message::Info(info.clone()).encode_body(&mut body).unwrap();
    body.truncate(n);
    body.extend_from_slice(&[0xAA, 0xBB]);
    assert_eq!(Message::decode_body(&body), Ok(Message::Info(info)));
}
