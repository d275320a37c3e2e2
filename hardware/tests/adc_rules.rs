//! One test per cross-key rule of adc.toml, and the derived clock figures.

mod common;
use common::{folder_with, rule_broken};

const FILE: &str = "adc.toml";

#[test]
fn shipped_configuration_gives_1_ksps_and_the_table_noise() {
    let adc = hardware::Params::load_default().unwrap().adc;
    assert!((adc.modulator_hz() - 4.096e6).abs() < 1e-3);
    assert!((adc.data_rate_hz() - 1000.0).abs() < 1e-9);
    // ADS131M04-Q1 Table 7-1, gain 1, 1 kSPS.
    assert!((adc.noise_rms_v(0) - 3.38e-6).abs() < 1e-12);
    assert_eq!(adc.crc, hardware::Crc::Ccitt);
}

#[test]
fn osr_not_offered_by_the_chip_is_refused() {
    let dir = folder_with(FILE, "osr = 4096", "osr = 4000");
    rule_broken(&dir, FILE, "clock.osr");
}

#[test]
fn word_length_not_offered_by_the_chip_is_refused() {
    let dir = folder_with(FILE, "word_bits = 24", "word_bits = 20");
    rule_broken(&dir, FILE, "interface.word_bits");
}

#[test]
fn pga_gain_without_a_noise_table_is_refused() {
    let dir = folder_with(FILE, "pga_gain = [1, 1, 1, 1]", "pga_gain = [1, 16, 1, 1]");
    rule_broken(&dir, FILE, "channels.pga_gain");
}

#[test]
fn fractional_pga_gain_is_refused() {
    let dir = folder_with(FILE, "pga_gain = [1, 1, 1, 1]", "pga_gain = [1, 1.5, 1, 1]");
    rule_broken(&dir, FILE, "channels.pga_gain");
}

#[test]
fn noise_table_falling_with_less_averaging_is_refused() {
    let dir = folder_with(FILE, "[1.90, 2.39, 3.38,", "[1.90, 2.39, 2.00,");
    rule_broken(&dir, FILE, "noise.gain1_uvrms");
}
