//! The public Mach-1 examples, read from their zip beside the checkout (never copied in), and
//! a block imported as `tactile import FILE --block N` writes it. Shared by the tests that use
//! them (`#[path]`-included; not a test target of its own).

use std::io::Read;

use recording::import::mach1;
use recording::Recording;

const ZIP: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/real-data/mach1/examples.zip"
);

/// The blocks of `name` in the examples zip; fails loudly if the data is absent.
pub fn blocks(name: &str) -> Vec<mach1::Block> {
    let file = std::fs::File::open(ZIP).unwrap_or_else(|e| {
        panic!("{ZIP}: {e}: the Mach-1 examples must sit in shared/real-data/mach1/ beside the checkout")
    });
    let mut zip = zip::ZipArchive::new(file).expect("examples.zip is a zip archive");
    let mut raw = Vec::new();
    zip.by_name(name)
        .unwrap_or_else(|e| panic!("{name} in {ZIP}: {e}"))
        .read_to_end(&mut raw)
        .expect("read");
    let text: String = raw.iter().map(|&b| char::from(b)).collect();
    mach1::parse(&text, name).unwrap_or_else(|e| panic!("{e}"))
}

/// `block` of `name` as a recording, as `tactile import` and `tactile prove --mach1` write it.
pub fn recording(block: &mach1::Block, name: &str) -> Recording {
    let hw = hardware::Params::load_default().expect("hardware");
    let readout = baseline::Readout::from_hardware(&hw).expect("front end");
    let meta = recording::import::ImportMeta {
        fingertip_radius_mm: hw.fingertip.radius_mm,
        gain: readout.signal.gain,
        excitation_v: readout.signal.excitation_v,
        source: format!("Mach-1 export {name}, block {}", block.index),
    };
    recording::import::to_recording(&block.to_export(), &meta, name)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The first block of `name` that `pick` chooses, as a recording.
#[allow(dead_code)] // Not every including test picks by predicate.
pub fn import(name: &str, pick: impl Fn(&mach1::Block) -> bool) -> Recording {
    let blocks = blocks(name);
    let block = blocks.iter().find(|b| pick(b)).expect("the block");
    recording(block, name)
}
