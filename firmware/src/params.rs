//! The boards' parameters from `hardware/*.toml`, as constants: `build.rs` loads the files through
//! the `hardware` crate (the one loader) and writes them out; each constant's doc line names the
//! file and key it comes from. Both boards take the ADC's clock and reference from here (the QEMU
//! board's emulated chip included); the NUCLEO board takes the rest.

include!(concat!(env!("OUT_DIR"), "/hardware_params.rs"));

/// The emulated ADS131M04's reference and clock, those of the real board's chip: what the QEMU
/// board and the host tests give the sim's register-level chip.
#[cfg(any(test, target_os = "none"))]
pub const EMULATED_ADC: sim::ads131m04::AdcParams = sim::ads131m04::AdcParams {
    vref_v: ADC_VREF_V,
    clkin_hz: ADC_CLKIN_HZ,
};
