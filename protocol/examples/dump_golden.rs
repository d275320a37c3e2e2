//! Print the wire bytes of the golden messages, for pasting into tests/golden.rs after a
//! deliberate layout change (bump PROTOCOL_VERSION and update SPEC.md at the same time).
//! Run: `cargo run -p protocol --example dump_golden --features std`
#[path = "../tests/common/golden_messages.rs"]
mod golden_messages;

fn main() {
    for (name, msg) in golden_messages::all() {
        let wire = protocol::encode_vec(&msg).expect("golden messages encode");
        let hex: Vec<String> = wire.iter().map(|b| format!("{b:02x}")).collect();
        println!("{name}: {}", hex.join(" "));
    }
}
