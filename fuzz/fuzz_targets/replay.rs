//! Arbitrary bytes through `tactile replay`'s readers: an MCAP file when the bytes start with
//! the MCAP magic (the seeds do), a raw serial capture otherwise. Property: no panic, and a
//! refusal names the input.
#![no_main]

use std::path::Path;
use std::sync::OnceLock;

use host::logger::replay::replay_bytes;
use host::logger::Setup;
use libfuzzer_sys::fuzz_target;

/// The set-up of `hardware/` (temperature sensor included), loaded once.
fn setup() -> &'static Setup {
    static SETUP: OnceLock<Setup> = OnceLock::new();
    SETUP.get_or_init(|| Setup::from_hardware("fuzz".into()).expect("hardware/ loads"))
}

fuzz_target!(|data: &[u8]| {
    let name = Path::new("fuzz-input");
    if let Err(e) = replay_bytes(data, name, Box::new(std::io::sink()), setup(), None) {
        assert!(e.to_string().starts_with("fuzz-input"), "{e}");
    }
});
