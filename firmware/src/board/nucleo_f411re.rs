//! NUCLEO-F411RE: clocks, the watchdog setting, and the device configuration of the real front end
//! from the board's parameters ([`crate::params`], from `hardware/*.toml`). The pins the binary
//! wires are checked against `hardware/board.toml` at compile time ([`PIN_CHECKS`]), so the two
//! cannot drift apart. The peripherals themselves are set up in `src/bin/nucleo-f411re.rs`: the
//! HAL and its interrupt table must not reach the QEMU binaries, which link this library too.

use crate::ads131m04::{Osr, Pga, WordLength};
use crate::device::DeviceConfig;
use crate::iwdg::IwdgSetting;
use crate::offset::{DriftSettings, NullTiming};
use crate::params::{
    ADC_CLKIN_HZ, ADC_OSR, ADC_PGA_GAIN, ADC_VREF_MV, ADC_WORD_BITS, AMP_GAIN, DAC_TRIM_MID_CODE,
    DAC_VMID_CODE, EXCITATION_V, PINS,
};

/// HSE input: the ST-LINK's 8 MHz MCO (HSE bypass).
pub const HSE_HZ: u32 = 8_000_000;
/// Core clock through the PLL: 96 MHz makes APB2 / 8 the 12 MHz SPI clock of board.toml exactly.
pub const SYSCLK_HZ: u32 = 96_000_000;

/// The IWDG's clock, the LSI RC oscillator: 32 kHz typical, 17..=47 kHz over process, voltage
/// and temperature (STM32F411xC/E datasheet DS10314, table "LSI oscillator characteristics").
pub const LSI_HZ: u32 = 32_000;
/// Watchdog timeout at the typical LSI: far above the longest legitimate main-loop pass (a DAC
/// write of the auto-null over 400 kHz I2C, ~0.1 ms; a full queue of 63 samples, ~1 ms) and short
/// enough that a hung loop costs well under a second of data. With the LSI's spread the real
/// timeout lies between 170 and 471 ms (the `iwdg` tests work it out).
pub const WATCHDOG_TIMEOUT_MS: u32 = 250;
/// Prescaler and reload for [`WATCHDOG_TIMEOUT_MS`]: divider 4, reload 1999 (checked at compile
/// time: the timeout must be representable).
pub const WATCHDOG: IwdgSetting = match IwdgSetting::for_timeout(WATCHDOG_TIMEOUT_MS, LSI_HZ) {
    Some(s) => s,
    None => panic!("watchdog timeout out of the IWDG's range"),
};

/// The pins `src/bin/nucleo-f411re.rs` uses, by board.toml key.
const WIRED: [(&str, &str); 11] = [
    ("spi.sck", "PA5"),
    ("spi.miso", "PA6"),
    ("spi.mosi", "PA7"),
    ("spi.cs", "PB6"),
    ("adc.drdy", "PC7"),
    ("adc.sync_reset", "PA9"),
    ("i2c.scl", "PB8"),
    ("i2c.sda", "PB9"),
    ("i2c.dac_ldac", "PB10"),
    ("uart.tx", "PA2"),
    ("uart.rx", "PA3"),
];

const fn str_eq(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// Every wired pin equals board.toml's pin for its key (compile-time).
pub const PIN_CHECKS: () = {
    let mut i = 0;
    while i < WIRED.len() {
        let mut found = false;
        let mut k = 0;
        while k < PINS.len() {
            if str_eq(PINS[k].0, WIRED[i].0) {
                assert!(
                    str_eq(PINS[k].1, WIRED[i].1),
                    "a pin in nucleo-f411re.rs differs from hardware/board.toml"
                );
                found = true;
            }
            k += 1;
        }
        assert!(
            found,
            "a pin key of nucleo-f411re.rs is missing from hardware/board.toml"
        );
        i += 1;
    }
};

/// The ADC word length of adc.toml.
pub const fn word_length() -> WordLength {
    match ADC_WORD_BITS {
        16 => WordLength::Bits16,
        32 => WordLength::Bits32SignExtend,
        _ => WordLength::Bits24,
    }
}

/// The device configuration of the real front end, from `hardware/*.toml`.
pub fn device_config() -> DeviceConfig {
    let osr = Osr::ALL
        .into_iter()
        .find(|o| o.ratio() == ADC_OSR)
        .unwrap_or(Osr::Osr4096);
    let pga = ADC_PGA_GAIN.map(|g| Pga::from_gain(g).unwrap_or(Pga::X1));
    DeviceConfig {
        chip_serial: 0,
        clkin_hz: ADC_CLKIN_HZ,
        vref_mv: ADC_VREF_MV,
        pga,
        amp_gain: AMP_GAIN,
        excitation_v: EXCITATION_V,
        // Uncalibrated until the host sends a calibration (set calibration command).
        calibration: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        osr,
        batch: protocol::MAX_BATCH as u8,
        filter: protocol::FilterConfig::NONE,
        // Firmware timing choices (not hardware values): settle 8 samples after each DAC step
        // (8 ms at 1 kSPS, many anti-alias time constants), average 32 samples per measurement.
        null_timing: NullTiming {
            settle: 8,
            average: 32,
        },
        // Drift tracking (off at power-up): unloaded = within 2000 codes of zero, time constant
        // 10^4 samples, at most 20,000 codes of correction.
        drift: DriftSettings {
            window: 2000,
            rate: 1.0e-4,
            limit: 20_000,
        },
        dac_initial: [DAC_TRIM_MID_CODE; 3],
        dac_vmid_code: DAC_VMID_CODE,
        null_at_power_up: true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_wired_pins_are_board_toml_s() {
        // Evaluated at compile time: a differing pin fails the host build too, not only the
        // thumb build of the binary.
        let () = PIN_CHECKS;
    }

    #[test]
    fn the_device_configuration_is_adc_toml_s() {
        let config = device_config();
        assert_eq!(config.osr.ratio(), ADC_OSR);
        assert_eq!(config.pga.map(Pga::gain), ADC_PGA_GAIN);
        assert_eq!(
            (config.clkin_hz, config.vref_mv),
            (ADC_CLKIN_HZ, ADC_VREF_MV)
        );
        assert_eq!(word_length().bytes() * 8, ADC_WORD_BITS as usize);
    }
}
