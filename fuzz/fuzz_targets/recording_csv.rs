//! Arbitrary bytes through the recording reader (`recording`, `docs/recording-format.md`), with
//! small limits so the limit paths are reached too. Properties: no panic; every refusal but a size limit names
//! its line; anything accepted writes back to a file that reads back to the same text.
#![no_main]

use libfuzzer_sys::fuzz_target;
use recording::{read_from_with, Limits, Recording};

const LIMITS: Limits = Limits {
    max_bytes: 1 << 16,
    max_values: 4096,
    max_line_bytes: 1024,
};

fn write(rec: &Recording) -> Vec<u8> {
    let mut out = Vec::new();
    rec.write_to(&mut out).expect("writing to memory");
    out
}

fuzz_target!(|data: &[u8]| {
    match read_from_with(data, LIMITS) {
        Ok(rec) => {
            let text = write(&rec);
            let back = read_from_with(&text[..], Limits::DEFAULT)
                .unwrap_or_else(|e| panic!("the writer's output is refused: {e}"));
            assert_eq!(back.channels.len(), rec.channels.len());
            assert_eq!(write(&back), text, "write-read-write changes the file");
        }
        Err(e) => {
            let msg = e.to_string();
            if let Some(line) = e.line() {
                assert!(msg.starts_with(&format!("line {line}")), "{msg}");
            } else {
                assert!(msg.contains("limit"), "neither a line nor a limit: {msg}");
            }
        }
    }
});
