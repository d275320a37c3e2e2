//! NUCLEO-F411RE wiring (see hardware/board-pins.md) and the device configuration of the real
//! front end.
//!
//! The front-end values below (amplifier gains, excitation, PGA, clock) are the board's defaults
//! until the hardware crate exposes the front-end parameters to the firmware build; each is listed
//! with its source in hardware/board-pins.md for the hardware helper to fold in.

use firmware::ads131m04::{Osr, Pga};
use firmware::device::DeviceConfig;
use firmware::offset::{DriftSettings, NullTiming};

/// USART2 (ST-LINK virtual COM port) baud rate.
pub const BAUD: u32 = 921_600;
/// SPI1 clock to the ADS131M04 (datasheet maximum 25 MHz; 12.5 MHz = APB2 100 MHz / 8).
pub const SPI_HZ: u32 = 12_500_000;
/// I2C1 clock to the MCP4728 (fast mode).
pub const I2C_HZ: u32 = 400_000;
/// Core clock from the ST-LINK's 8 MHz MCO (HSE bypass) through the PLL.
pub const SYSCLK_HZ: u32 = 100_000_000;
pub const HSE_HZ: u32 = 8_000_000;

pub fn device_config() -> DeviceConfig {
    DeviceConfig {
        chip_serial: 0,
        // 8.192 MHz crystal oscillator on the ADC board (ADS131M04 nominal CLKIN).
        clkin_hz: 8_192_000,
        // ADS131M04 internal reference.
        vref_mv: 1200,
        pga: [Pga::X1; 4],
        // Sensor facts: about 3000 for Fz, lower for the more sensitive moment bridges.
        amp_gain: [3000.0, 2000.0, 2000.0],
        excitation_v: 3.3,
        // Uncalibrated until the host sends a calibration (set calibration command).
        calibration: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        osr: Osr::Osr4096, // 1000 samples/s
        batch: protocol::MAX_BATCH as u8,
        filter: protocol::FilterConfig::NONE,
        // Settle 8 samples (8 ms at 1 kSPS: the amplifier's RC filter), average 32.
        null_timing: NullTiming { settle: 8, average: 32 },
        drift: DriftSettings { window: 2000, rate: 1.0e-4, limit: 20_000 },
        dac_initial: [2048; 4],
        null_at_power_up: true,
    }
}
