//! Settings the board hands the device core at power-up. The board fills them from its own
//! parameters; the core never invents a hardware value.

use crate::ads131m04::{Osr, Pga};
use crate::offset::{DriftSettings, NullTiming};
use protocol::{Calibration, FilterConfig};

/// Power-up configuration of the device core.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeviceConfig {
    /// Serial number of the sensing chip, reported in the info frame.
    pub chip_serial: u32,
    /// ADS131M04 clock input, Hz (data rate = clkin / 2 / OSR).
    pub clkin_hz: u32,
    /// ADC reference, mV.
    pub vref_mv: u16,
    /// PGA gain per ADC channel.
    pub pga: [Pga; 4],
    /// Voltage gain of the amplifier ahead of ADC channels 0..=2.
    pub amp_gain: [f32; 3],
    /// Bridge excitation, V.
    pub excitation_v: f32,
    /// Volts at the ADC input → (Fz N, Mx N·m, My N·m).
    pub calibration: Calibration,
    /// Oversampling ratio at power-up.
    pub osr: Osr,
    /// Samples per frame at power-up (1..=16).
    pub batch: u8,
    /// Filters at power-up.
    pub filter: FilterConfig,
    /// Auto-null measurement timing.
    pub null_timing: NullTiming,
    /// Drift tracker settings (tracking itself starts off).
    pub drift: DriftSettings,
    /// Trim-DAC codes (channels A..=C) written at power-up, before any search.
    pub dac_initial: [u16; 3],
    /// DAC channel D's code, the analog mid-rail reference (set in the DAC's EEPROM, never
    /// written by the firmware); reported in the info frame.
    pub dac_vmid_code: u16,
    /// Run the auto-null search at power-up.
    pub null_at_power_up: bool,
}

/// Firmware version from the crate version.
pub const FW_VERSION: [u8; 3] = [
    parse_u8(env!("CARGO_PKG_VERSION_MAJOR")),
    parse_u8(env!("CARGO_PKG_VERSION_MINOR")),
    parse_u8(env!("CARGO_PKG_VERSION_PATCH")),
];

const fn parse_u8(s: &str) -> u8 {
    let bytes = s.as_bytes();
    let mut value: u32 = 0;
    let mut i = 0;
    while i < bytes.len() {
        value = value * 10 + (bytes[i] - b'0') as u32;
        i += 1;
    }
    assert!(value <= 255, "version component above 255");
    value as u8
}
