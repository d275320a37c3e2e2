//! The trim DAC of the stimulus bench, an MCP4728 reduced to what the firmware's offset cut uses:
//! fast write (all four input registers) and multi-write (per channel, reference and gain bits
//! ignored) over `embedded_hal::i2c::I2c`, at the factory address 0x60. The codes land in the
//! emulated ADC's analog input ([`TrimInput`]), so an auto-null search sees its own DAC writes.
//! Not emulated: reads, EEPROM writes, VREF/gain/power-down commands (acknowledged, no effect),
//! general calls, LDAC/UDAC timing (outputs update at once).

use core::cell::RefCell;

use embedded_hal::i2c::{ErrorKind, ErrorType, I2c, NoAcknowledgeSource, Operation};

use super::stimulus::Stimulus;
use super::{Ads131m04, AnalogInput};

/// Address the emulated DAC answers.
pub const ADDRESS: u8 = 0x60;

/// An analog input that a trim DAC can move.
pub trait TrimInput {
    /// DAC channel `channel` (0..=3) now outputs `code` (0..=4095).
    fn set_trim(&mut self, channel: usize, code: u16);
}

impl TrimInput for Stimulus {
    fn set_trim(&mut self, channel: usize, code: u16) {
        self.trim_codes[channel] = code;
    }
}

/// The DAC's I2C side, wired into a shared emulated ADC's input.
pub struct TrimDac<'a, A>(pub &'a RefCell<Ads131m04<A>>);

impl<A> ErrorType for TrimDac<'_, A> {
    type Error = ErrorKind;
}

impl<A: AnalogInput + TrimInput> I2c for TrimDac<'_, A> {
    fn transaction(
        &mut self,
        address: u8,
        operations: &mut [Operation<'_>],
    ) -> Result<(), ErrorKind> {
        if address != ADDRESS {
            return Err(ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address));
        }
        for op in operations {
            match op {
                Operation::Write(bytes) => self.write_command(bytes),
                Operation::Read(buf) => buf.fill(0),
            }
        }
        Ok(())
    }
}

impl<A: AnalogInput + TrimInput> TrimDac<'_, A> {
    fn write_command(&mut self, bytes: &[u8]) {
        let Some(&first) = bytes.first() else { return };
        let mut chip = self.0.borrow_mut();
        let input = chip.input_mut();
        if first & 0xC0 == 0 {
            // Fast write: two bytes per channel, 0 0 PD1 PD0 D11..D8 | D7..D0.
            for (ch, pair) in bytes.chunks_exact(2).take(4).enumerate() {
                input.set_trim(ch, (u16::from(pair[0] & 0x0F) << 8) | u16::from(pair[1]));
            }
        } else if first & 0xF8 == 0x40 {
            // Multi-write: 0100 0 DAC1 DAC0 UDAC | VREF PD1 PD0 Gx D11..D8 | D7..D0.
            for triple in bytes.chunks_exact(3) {
                let ch = usize::from((triple[0] >> 1) & 0b11);
                input.set_trim(
                    ch,
                    (u16::from(triple[1] & 0x0F) << 8) | u16::from(triple[2]),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ads131m04::stimulus::StimulusParams;
    use crate::ads131m04::DATASHEET_PARAMS;

    #[test]
    fn fast_and_multi_write_move_the_trim() {
        let bench = Stimulus::new(StimulusParams::QEMU_BOARD);
        let chip = RefCell::new(Ads131m04::new(bench, DATASHEET_PARAMS));
        let mut dac = TrimDac(&chip);
        dac.write(ADDRESS, &[0x0F, 0xFF, 0x08, 0x00, 0x00, 0x01, 0x00, 0x00])
            .unwrap();
        assert_eq!(chip.borrow_mut().input_mut().trim_codes, [4095, 2048, 1, 0]);
        dac.write(ADDRESS, &[0x42, 0x87, 0xD0]).unwrap();
        assert_eq!(chip.borrow_mut().input_mut().trim_codes[1], 0x7D0);
        assert!(dac.write(0x61, &[0, 0]).is_err());
    }
}
