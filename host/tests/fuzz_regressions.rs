//! Inputs the fuzz targets (`fuzz/`) found to crash a reader, kept as tests.

use std::path::Path;

use host::logger::mcap_io::{recover_bytes, MCAP_MAGIC};
use host::logger::replay::replay_bytes;
use host::logger::Setup;

fn replay(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/fuzz")
        .join(name);
    let bytes = std::fs::read(&path).unwrap();
    let setup = Setup::from_hardware("regression".into()).unwrap();
    match replay_bytes(
        &bytes,
        Path::new(name),
        Box::new(std::io::sink()),
        &setup,
        None,
    ) {
        Ok(s) => format!("replayed {} frames", s.frames),
        Err(e) => e.to_string(),
    }
}

/// mcap 0.26 reserved a channel string's declared length (4 GiB) before checking the record
/// held it: an out-of-memory abort on a small machine.
#[test]
fn an_mcap_string_longer_than_its_record_is_refused_without_allocating_it() {
    let e = replay("replay-mcap-4gib-string");
    assert!(e.starts_with("replay-mcap-4gib-string"), "{e}");
}

/// mcap 0.26 added a record length to an offset without checking (`attempt to add with
/// overflow` in `sans_io::linear_reader`).
#[test]
fn an_mcap_record_length_near_u64_max_is_refused_without_overflow() {
    let e = replay("replay-mcap-offset-overflow");
    assert!(e.starts_with("replay-mcap-offset-overflow"), "{e}");
}

/// The same two faults built by hand: a channel whose topic claims 4 GiB, and a record whose
/// length is `u64::MAX`; both stop the recovery with the reason, keeping what came before.
#[test]
fn declared_lengths_are_checked_against_the_bytes_there() {
    let record = |op: u8, body: &[u8]| {
        let mut r = vec![op];
        r.extend((body.len() as u64).to_le_bytes());
        r.extend(body);
        r
    };
    let mut channel = vec![1, 0, 0, 0];
    channel.extend(u32::MAX.to_le_bytes());
    channel.extend(b"/t");
    let file = [MCAP_MAGIC, &record(0x04, &channel)].concat();
    let r = recover_bytes(Path::new("x.mcap"), &file).unwrap();
    assert!(r.messages.is_empty());
    assert!(r.truncated.unwrap().contains("overruns its record"));

    let mut ok_channel = vec![1, 0, 0, 0];
    ok_channel.extend(2u32.to_le_bytes());
    ok_channel.extend(b"/t");
    ok_channel.extend(1u32.to_le_bytes());
    ok_channel.extend(b"e");
    let mut message = vec![1, 0, 0, 0, 0, 0];
    message.extend(5u64.to_le_bytes());
    message.extend(6u64.to_le_bytes());
    message.extend(b"data");
    let mut huge = vec![0x05];
    huge.extend(u64::MAX.to_le_bytes());
    let file = [
        MCAP_MAGIC,
        &record(0x04, &ok_channel),
        &record(0x05, &message),
        &huge,
    ]
    .concat();
    let r = recover_bytes(Path::new("x.mcap"), &file).unwrap();
    assert_eq!(r.messages.len(), 1);
    assert_eq!((&*r.messages[0].topic, r.messages[0].publish_ns), ("/t", 6));
    assert_eq!(r.messages[0].data, b"data");
    assert!(
        r.truncated.unwrap().contains("cut short"),
        "a record cut short"
    );
}
