//! Register-level behaviour against hand-built frames (datasheet SBAS890 §8.5).

use super::stimulus::{Stimulus, StimulusParams};
use super::*;
use protocol::codes::volts_to_code;

struct Constant([f32; 4]);
impl AnalogInput for Constant {
    fn sample_v(&mut self, _index: u64) -> [f32; 4] {
        self.0
    }
}

/// Clock one frame of `words` 16-bit command/data words (MSB-aligned in `wb`-byte words, padded
/// to six words) and return the output bytes.
fn frame<A: AnalogInput>(chip: &RefCell<Ads131m04<A>>, words: &[u16], wb: usize) -> [u8; 24] {
    let mut tx = [0u8; 24];
    for (i, w) in words.iter().enumerate() {
        tx[i * wb..i * wb + 2].copy_from_slice(&w.to_be_bytes());
    }
    let mut rx = [0u8; 24];
    let (mut spi, _) = handles(chip);
    spi.transfer(&mut rx[..6 * wb], &tx[..6 * wb]).unwrap();
    rx
}

/// A chip converting `input`, with the datasheet's reference and clock.
fn chip<A: AnalogInput>(input: A) -> RefCell<Ads131m04<A>> {
    RefCell::new(Ads131m04::new(input, DATASHEET_PARAMS))
}

fn word(rx: &[u8], i: usize, wb: usize) -> u16 {
    u16::from_be_bytes([rx[i * wb], rx[i * wb + 1]])
}

#[test]
fn first_frame_after_power_up_answers_reset_then_status() {
    let chip = chip(Constant([0.0; 4]));
    let rx = frame(&chip, &[cmd::NULL], 3);
    assert_eq!(word(&rx, 0, 3), 0xFF24);
    let rx = frame(&chip, &[cmd::NULL], 3);
    // RESET bit, WLENGTH = 01 (24 bit), no DRDY bits: 0x0500.
    assert_eq!(word(&rx, 0, 3), 0x0500);
}

#[test]
fn status_shows_drdy_and_data_words_carry_codes() {
    let chip = chip(Constant([0.6, -0.3, 0.0, 1.5]));
    frame(&chip, &[cmd::NULL], 3);
    chip.borrow_mut().convert();
    assert!(chip.borrow().drdy_is_low());
    let rx = frame(&chip, &[cmd::NULL], 3);
    assert_eq!(word(&rx, 0, 3), 0x050F);
    assert_eq!(&rx[3..6], &[0x40, 0x00, 0x00]);
    assert_eq!(&rx[6..9], &[0xE0, 0x00, 0x00]);
    assert_eq!(&rx[12..15], &[0x7F, 0xFF, 0xFF]);
    assert_eq!(crc16_bitwise(SEED, &rx[..18]), 0, "frame CRC");
    assert!(
        !chip.borrow().drdy_is_low(),
        "reading the data releases DRDY"
    );
}

#[test]
fn rreg_answers_in_the_next_frame_and_wreg_is_acknowledged() {
    let chip = chip(Constant([0.0; 4]));
    frame(&chip, &[cmd::RREG], 3); // RREG ID (address 0, one register)
    let rx = frame(&chip, &[cmd::NULL], 3);
    assert_eq!(word(&rx, 0, 3), 0x2400);
    // WREG CLOCK = 0x0F02 (OSR 128 -> 32 kSPS).
    let wreg = cmd::WREG | (u16::from(addr::CLOCK) << 7);
    frame(&chip, &[wreg, 0x0F02], 3);
    let rx = frame(&chip, &[cmd::NULL], 3);
    assert_eq!(word(&rx, 0, 3), 0x4000 | (u16::from(addr::CLOCK) << 7));
    assert_eq!(chip.borrow().register(addr::CLOCK), 0x0F02);
    assert_eq!(chip.borrow().data_rate_hz(), 32_000.0);
}

#[test]
fn word_length_32_sign_extended_and_16_bit() {
    let chip = chip(Constant([-0.6, 0.0, 0.0, 0.0]));
    let wreg = cmd::WREG | (u16::from(addr::MODE) << 7);
    frame(&chip, &[wreg, 0x0310], 3); // WLENGTH = 11
    chip.borrow_mut().convert();
    let rx = frame(&chip, &[cmd::NULL], 4);
    assert_eq!(&rx[4..8], &(-(1i32 << 22)).to_be_bytes());
    assert_eq!(crc16_bitwise(SEED, &rx[..24]), 0);
    frame(&chip, &[wreg, 0x0010], 4); // WLENGTH = 00
    chip.borrow_mut().convert();
    let rx = frame(&chip, &[cmd::NULL], 2);
    assert_eq!(&rx[2..4], &[0xC0, 0x00]);
    assert_eq!(crc16_bitwise(SEED, &rx[..12]), 0);
}

#[test]
fn input_crc_mismatch_refuses_the_command_and_flags_crc_err() {
    let chip = chip(Constant([0.0; 4]));
    let wreg_mode = cmd::WREG | (u16::from(addr::MODE) << 7);
    frame(&chip, &[wreg_mode, 0x1510], 3); // RX_CRC_EN on (no CRC needed yet)
    let wreg_gain = cmd::WREG | (u16::from(addr::GAIN1) << 7);
    frame(&chip, &[wreg_gain, 0x0007, 0xBEEF], 3); // wrong CRC
    let rx = frame(&chip, &[cmd::NULL, 0xBEEF], 3);
    assert_ne!(word(&rx, 0, 3) & status::CRC_ERR, 0);
    assert_eq!(chip.borrow().register(addr::GAIN1), 0);
    let crc = crc16_bitwise(SEED, &[0x60 | 0x02, 0x00, 0x00, 0x00, 0x07, 0x00]);
    let wreg_gain = cmd::WREG | (u16::from(addr::GAIN1) << 7);
    frame(&chip, &[wreg_gain, 0x0007, crc], 3);
    assert_eq!(chip.borrow().register(addr::GAIN1), 0x0007);
}

#[test]
fn lock_refuses_writes_until_unlock_and_standby_stops_conversions() {
    let chip = chip(Constant([0.1; 4]));
    frame(&chip, &[cmd::LOCK], 3);
    frame(
        &chip,
        &[cmd::WREG | (u16::from(addr::GAIN1) << 7), 0x0001],
        3,
    );
    assert_eq!(chip.borrow().register(addr::GAIN1), 0);
    frame(&chip, &[cmd::UNLOCK], 3);
    frame(&chip, &[cmd::STANDBY], 3);
    chip.borrow_mut().convert();
    assert_eq!(chip.borrow().conversions(), 0);
    frame(&chip, &[cmd::WAKEUP], 3);
    chip.borrow_mut().convert();
    assert_eq!(chip.borrow().conversions(), 1);
}

#[test]
fn reset_command_restores_defaults() {
    let chip = chip(Constant([0.0; 4]));
    frame(
        &chip,
        &[cmd::WREG | (u16::from(addr::GAIN1) << 7), 0x0003],
        3,
    );
    frame(&chip, &[cmd::RESET], 3);
    let rx = frame(&chip, &[cmd::NULL], 3);
    assert_eq!(word(&rx, 0, 3), 0xFF24);
    assert_eq!(chip.borrow().register(addr::GAIN1), 0);
}

#[test]
fn stimulus_codes_are_recomputable_from_the_index() {
    let chip = chip(Stimulus::new(StimulusParams::QEMU_BOARD));
    let reference = Stimulus::new(StimulusParams::QEMU_BOARD);
    let vref_v = DATASHEET_PARAMS.vref_v;
    for n in 0..50u64 {
        chip.borrow_mut().convert();
        let expect: [i32; 4] =
            core::array::from_fn(|ch| volts_to_code(f64::from(reference.volts(n)[ch]), vref_v, 1));
        assert_eq!(chip.borrow().codes(), expect, "conversion {n}");
    }
}
