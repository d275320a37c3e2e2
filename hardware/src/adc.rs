//! `adc.toml`: the ADS131M04's configuration (clock, OSR, PGA, reference, word length, CRC) and
//! the datasheet values the models rely on (input impedance, noise table).

use std::path::Path;

use crate::{ParamError, Reader};

/// The OSR settings of the ADS131M04, in the order of the datasheet's noise table columns.
pub const NOISE_TABLE_OSR: [u32; 9] = [16384, 8192, 4096, 2048, 1024, 512, 256, 128, 64];
/// PGA gains that have a noise table in `adc.toml`.
pub const NOISE_TABLE_GAINS: [u32; 4] = [1, 2, 4, 8];

/// The CRC the ADS131M04 appends to every SPI word frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Crc {
    /// CRC-16-CCITT, polynomial 0x1021 (CRC_TYPE = 0).
    Ccitt,
    /// CRC-16-ANSI, polynomial 0x8005 (CRC_TYPE = 1).
    Ansi,
    /// No CRC checking of input frames (output CRC words are still sent).
    Off,
}

/// The ADC and how it is configured.
#[derive(Debug, Clone, PartialEq)]
pub struct Adc {
    pub part: String,
    pub clkin_hz: f64,
    /// Oversampling ratio; `fDATA = clkin_hz / 2 / osr` (high-resolution mode).
    pub osr: u32,
    /// Internal reference voltage: full scale is `+-reference_v / pga_gain`.
    pub reference_v: f64,
    /// PGA gain of channels 0..3.
    pub pga_gain: [u32; 4],
    /// Differential input impedance at the PGA gains in use.
    pub input_impedance_ohm: f64,
    /// SPI word length.
    pub word_bits: u32,
    pub crc: Crc,
    /// Input-referred noise, `[gain index][osr index]`, indices as in [`NOISE_TABLE_GAINS`] and
    /// [`NOISE_TABLE_OSR`].
    pub noise_uvrms: [[f64; 9]; 4],
}

impl Adc {
    pub(crate) fn load(file: &Path) -> Result<Self, Vec<ParamError>> {
        let mut r = Reader::open(file).map_err(|e| vec![e])?;
        let adc = Self::read(&mut r);
        adc.check(&mut r);
        r.finish()?;
        Ok(adc)
    }

    fn read(r: &mut Reader) -> Self {
        let gains: [f64; 4] = r.f64_array("channels.pga_gain", 1.0..=128.0);
        let crc = match r.choice("interface.crc", &["ccitt", "ansi", "off"]) {
            "ansi" => Crc::Ansi,
            "off" => Crc::Off,
            _ => Crc::Ccitt,
        };
        Self {
            part: r.string("part"),
            clkin_hz: r.f64("clock.clkin_hz", 0.3e6..=8.4e6),
            osr: r.int("clock.osr", 64..=16384) as u32,
            reference_v: r.f64("reference.internal_v", 1.0..=1.4),
            // A fractional gain becomes 0, which the gain rule in `check` rejects.
            pga_gain: gains.map(|g| if g.fract() == 0.0 { g as u32 } else { 0 }),
            input_impedance_ohm: r.f64("channels.input_impedance_ohm", 1.0e3..=1.0e12),
            word_bits: r.int("interface.word_bits", 16..=32) as u32,
            crc,
            noise_uvrms: [
                r.f64_array("noise.gain1_uvrms", 0.01..=1000.0),
                r.f64_array("noise.gain2_uvrms", 0.01..=1000.0),
                r.f64_array("noise.gain4_uvrms", 0.01..=1000.0),
                r.f64_array("noise.gain8_uvrms", 0.01..=1000.0),
            ],
        }
    }

    /// Rules across keys; each has its own test in `tests/adc_rules.rs`.
    fn check(&self, r: &mut Reader) {
        if !NOISE_TABLE_OSR.contains(&self.osr) {
            r.reject(
                "clock.osr",
                "must be one of 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384",
            );
        }
        if ![16, 24, 32].contains(&self.word_bits) {
            r.reject("interface.word_bits", "must be 16, 24 or 32");
        }
        if self.pga_gain.iter().any(|g| !NOISE_TABLE_GAINS.contains(g)) {
            r.reject(
                "channels.pga_gain",
                "each gain must be 1, 2, 4 or 8 (the gains with a noise table)",
            );
        }
        for (g, row) in self.noise_uvrms.iter().enumerate() {
            // Averaging over a longer window can only lower the noise.
            if row.windows(2).any(|w| w[0] > w[1]) {
                let key = format!("noise.gain{}_uvrms", NOISE_TABLE_GAINS[g]);
                r.reject(
                    &key,
                    "must rise from OSR 16384 to OSR 64 (less averaging, more noise)",
                );
            }
        }
    }

    /// Output data rate in high-resolution mode.
    pub fn data_rate_hz(&self) -> f64 {
        self.modulator_hz() / f64::from(self.osr)
    }

    /// Modulator sampling frequency, `fMOD = fCLKIN / 2`.
    pub fn modulator_hz(&self) -> f64 {
        self.clkin_hz / 2.0
    }

    /// The datasheet's input-referred noise for `channel` at the configured OSR, in volts rms.
    pub fn noise_rms_v(&self, channel: usize) -> f64 {
        let g = NOISE_TABLE_GAINS
            .iter()
            .position(|g| *g == self.pga_gain[channel])
            .unwrap_or(0);
        let o = NOISE_TABLE_OSR
            .iter()
            .position(|o| *o == self.osr)
            .unwrap_or(0);
        self.noise_uvrms[g][o] * 1.0e-6
    }
}
