//! `board.toml`: the NUCLEO-F411RE pin map of the front-end board (SPI to the ADC, DRDY, I2C to
//! the trim DAC, the ST-LINK virtual COM port, the ADC clock).

use std::path::Path;

use crate::{ParamError, Reader};

/// Pins that can carry each function on the STM32F411RE (DS10314 Table 9, LQFP64 pins only).
const ALTERNATES: &[(&str, &[&str])] = &[
    ("spi.sck", &["PA5", "PB3"]),
    ("spi.miso", &["PA6", "PB4"]),
    ("spi.mosi", &["PA7", "PB5"]),
    ("i2c.scl", &["PB6", "PB8"]),
    ("i2c.sda", &["PB7", "PB9"]),
    // USART2 reaches the ST-LINK VCP only on PA2/PA3 (UM1724).
    ("uart.tx", &["PA2"]),
    ("uart.rx", &["PA3"]),
    ("clock.mco_pin", &["PA8", "PC9"]),
];

/// Where the ADS131M04's CLKIN comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ClockSource {
    /// A crystal oscillator on the front-end board.
    Oscillator,
    /// The MCU's MCO output.
    Mco,
}

/// The board's pin map; pins are names like `PA5`.
#[derive(Debug, Clone, PartialEq)]
pub struct Board {
    pub board: String,
    pub spi_sck: String,
    pub spi_miso: String,
    pub spi_mosi: String,
    pub spi_cs: String,
    pub spi_clock_hz: f64,
    pub adc_drdy: String,
    pub adc_sync_reset: String,
    pub i2c_scl: String,
    pub i2c_sda: String,
    pub i2c_clock_hz: f64,
    /// 7-bit I2C address of the MCP4728.
    pub dac_address: u8,
    pub dac_ldac: String,
    pub uart_tx: String,
    pub uart_rx: String,
    pub uart_baud: u32,
    pub clock_source: ClockSource,
    pub mco_pin: String,
    /// Part number of the analog rail's regulator.
    pub analog_regulator: String,
    /// Nucleo supply pin feeding that regulator.
    pub analog_from: String,
    /// Nucleo supply pin feeding the ADC's digital side.
    pub digital_from: String,
}

impl Board {
    pub(crate) fn load(file: &Path) -> Result<Self, Vec<ParamError>> {
        let mut r = Reader::open(file).map_err(|e| vec![e])?;
        let board = Self::read(&mut r);
        board.check(&mut r);
        r.finish()?;
        Ok(board)
    }

    fn read(r: &mut Reader) -> Self {
        r.choice("spi.peripheral", &["SPI1"]);
        r.choice("i2c.peripheral", &["I2C1"]);
        r.choice("uart.peripheral", &["USART2"]);
        Self {
            board: r.choice("board", &["NUCLEO-F411RE"]).to_string(),
            spi_sck: r.string("spi.sck"),
            spi_miso: r.string("spi.miso"),
            spi_mosi: r.string("spi.mosi"),
            spi_cs: r.string("spi.cs"),
            // The ADS131M04 allows SCLK up to 25 MHz.
            spi_clock_hz: r.f64("spi.clock_hz", 1.0e5..=25.0e6),
            adc_drdy: r.string("adc.drdy"),
            adc_sync_reset: r.string("adc.sync_reset"),
            i2c_scl: r.string("i2c.scl"),
            i2c_sda: r.string("i2c.sda"),
            // MCP4728: standard, fast and high-speed (3.4 MHz) modes.
            i2c_clock_hz: r.f64("i2c.clock_hz", 1.0e4..=3.4e6),
            // MCP4728 addresses are 0b1100_A2A1A0.
            dac_address: r.int("i2c.dac_address", 0x60..=0x67) as u8,
            dac_ldac: r.string("i2c.dac_ldac"),
            uart_tx: r.string("uart.tx"),
            uart_rx: r.string("uart.rx"),
            uart_baud: r.int("uart.baud", 1200..=2_000_000) as u32,
            clock_source: match r.choice("clock.source", &["oscillator", "mco"]) {
                "mco" => ClockSource::Mco,
                _ => ClockSource::Oscillator,
            },
            mco_pin: r.string("clock.mco_pin"),
            analog_regulator: r.string("power.analog_regulator"),
            analog_from: r.choice("power.analog_from", &["5V", "3V3"]).to_string(),
            digital_from: r.choice("power.digital_from", &["3V3", "5V"]).to_string(),
        }
    }

    /// Every pin with its key, in file order.
    pub fn pins(&self) -> Vec<(&'static str, &str)> {
        vec![
            ("spi.sck", &self.spi_sck),
            ("spi.miso", &self.spi_miso),
            ("spi.mosi", &self.spi_mosi),
            ("spi.cs", &self.spi_cs),
            ("adc.drdy", &self.adc_drdy),
            ("adc.sync_reset", &self.adc_sync_reset),
            ("i2c.scl", &self.i2c_scl),
            ("i2c.sda", &self.i2c_sda),
            ("i2c.dac_ldac", &self.dac_ldac),
            ("uart.tx", &self.uart_tx),
            ("uart.rx", &self.uart_rx),
            ("clock.mco_pin", &self.mco_pin),
        ]
    }

    /// Rules across keys; each has its own test in `tests/board_rules.rs`.
    fn check(&self, r: &mut Reader) {
        // The ADS131M04's DVDD/IOVDD must match the MCU's 3.3 V logic levels.
        if self.digital_from != "3V3" {
            r.reject(
                "power.digital_from",
                "must be \"3V3\": the ADC's I/O talks to 3.3 V MCU pins",
            );
        }
        let pins = self.pins();
        for (i, (key, pin)) in pins.iter().enumerate() {
            if !is_lqfp64_gpio(pin) {
                r.reject(
                    key,
                    format!(
                        "`{pin}` is not a pin of the LQFP64 STM32F411RE (PA0..PC15, PD2, PH0, PH1)"
                    ),
                );
                continue;
            }
            if let Some((_, allowed)) = ALTERNATES.iter().find(|(k, _)| k == key) {
                if !allowed.contains(pin) {
                    r.reject(
                        key,
                        format!(
                            "`{pin}` cannot carry this function; use one of {}",
                            allowed.join(", ")
                        ),
                    );
                }
            }
            if let Some((other, _)) = pins[..i].iter().find(|(_, p)| p == pin) {
                r.reject(key, format!("`{pin}` is already used by `{other}`"));
            }
        }
    }
}

/// `PA0`..`PA15`, `PB0`..`PB15`, `PC0`..`PC15`, `PD2`, `PH0`, `PH1`.
fn is_lqfp64_gpio(pin: &str) -> bool {
    let Some(rest) = pin.strip_prefix('P') else {
        return false;
    };
    let mut chars = rest.chars();
    let Some(port) = chars.next() else {
        return false;
    };
    let Ok(n) = chars.as_str().parse::<u8>() else {
        return false;
    };
    if chars.as_str().starts_with('0') && n != 0 {
        return false;
    }
    match port {
        'A' | 'B' | 'C' => n <= 15,
        'D' => n == 2,
        'H' => n <= 1,
        _ => false,
    }
}
