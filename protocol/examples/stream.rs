//! A device-like stream of sample frames with an info frame and a reply, damaged the way a loose
//! connector damages it, decoded by the accumulator. Shows what the host sees.
//! Run: `cargo run -p protocol --example stream --features std`

use protocol::*;

fn frame(seq: u32) -> Message {
    let mut f = SampleFrame::new(seq, seq * 16_000, Status::default(), 12_345);
    for k in 0..MAX_BATCH as i32 {
        let t = (seq as i32 * 16 + k) as f64 / 1000.0;
        let fz = (2.0e6 * (t * 3.0).sin()) as i32;
        f.push(Sample {
            ch: [fz, fz / 3, -fz / 5],
        })
        .unwrap();
    }
    Message::Sample(f)
}

fn main() {
    let mut wire = vec![0u8]; // a session starts with a lone delimiter
    wire.extend(encode_vec(&Message::Reply(Reply::Pong { tag: 1, nonce: 7 })).unwrap());
    for seq in 0..8 {
        let mut bytes = encode_vec(&frame(seq)).unwrap();
        match seq {
            2 => bytes[40] ^= 0x10,               // a bit flip
            4 => bytes.truncate(bytes.len() / 2), // a cable pulled mid-frame: merges with frame 5
            6 => wire.extend([0x13, 0x37, 0xFF]), // garbage before the frame
            _ => {}
        }
        wire.extend(bytes);
    }
    println!("{} bytes on the wire; decoding:", wire.len());
    let mut acc = Accumulator::new();
    for outcome in acc.feed(&wire) {
        match outcome {
            Outcome::Message(Message::Sample(f)) => println!(
                "  sample frame seq {:>2}  t {:>7} us  {} samples  first Fz code {:>8}",
                f.seq,
                f.t_us,
                f.len(),
                f.samples()[0].ch[0]
            ),
            Outcome::Message(other) => println!("  {other:?}"),
            bad => println!("  rejected: {bad:?}"),
        }
    }
}
