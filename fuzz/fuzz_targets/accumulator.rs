//! Arbitrary bytes, in arbitrary chunks, through the protocol accumulator and body decoder.
//! Properties: no panic; anything accepted re-encodes to a frame that decodes to itself.
#![no_main]

use libfuzzer_sys::fuzz_target;
use protocol::{encode_vec, Accumulator, Message, Outcome};

fuzz_target!(|data: &[u8]| {
    let Some((&chunk, bytes)) = data.split_first() else {
        return;
    };
    let mut acc = Accumulator::new();
    for c in bytes.chunks(usize::from(chunk).max(1)) {
        for outcome in acc.feed(c) {
            if let Outcome::Message(msg) = outcome {
                let wire = encode_vec(&msg).expect("an accepted message re-encodes");
                let again: Vec<Outcome> = Accumulator::new().feed(&wire).collect();
                assert_eq!(again, vec![Outcome::Message(msg)]);
            }
        }
    }
    let _ = Message::decode_body(bytes);
});
