//! The boards' parameters from `hardware/*.toml`, as constants: `build.rs` loads the files through
//! the `hardware` crate (the one loader) and writes them out; each constant's doc line names the
//! file and key it comes from.

include!(concat!(env!("OUT_DIR"), "/hardware_params.rs"));
