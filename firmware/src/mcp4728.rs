//! Driver for the Microchip MCP4728 quad 12-bit DAC over embedded-hal I2C (datasheet DS22187E
//! §5.6 "Write Commands", §5.7 "Read Command"). The firmware uses it as the four-channel trim
//! source of the offset cut: it writes the input registers only (fast write / multi-write), never
//! the EEPROM, so the power-up codes stay whatever was last stored deliberately.

use embedded_hal::i2c::I2c;

/// Factory address 0b110_0000 (A2..A0 = 0).
pub const DEFAULT_ADDRESS: u8 = 0x60;
/// Largest 12-bit code.
pub const CODE_MAX: u16 = 4095;
/// Internal reference (datasheet: 2.048 V), used when `Vref::Internal`.
pub const INTERNAL_VREF_MV: u16 = 2048;

/// Reference of one channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Vref {
    /// VDD as reference (gain ignored by the device).
    Vdd,
    /// Internal 2.048 V reference.
    Internal,
}

/// Output gain of one channel (internal reference only).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Gain {
    X1,
    X2,
}

/// Errors of the driver.
#[derive(Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error<E> {
    /// The I2C transaction failed (NACK, arbitration loss, bus fault …) as the HAL reported it.
    I2c(E),
    /// A code above 4095 was requested; nothing was sent.
    CodeOutOfRange(u16),
    /// A channel index above 3 was requested; nothing was sent.
    ChannelOutOfRange(u8),
}

/// One channel's input-register settings for a multi-write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChannelWrite {
    pub channel: u8,
    pub code: u16,
    pub vref: Vref,
    pub gain: Gain,
}

/// What a read returns for one channel's DAC input register.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChannelState {
    pub code: u16,
    pub vref: Vref,
    pub gain: Gain,
    /// Power-down bits PD1:PD0 (0 = normal operation).
    pub power_down: u8,
    /// EEPROM write in progress (RDY/BSY low).
    pub busy: bool,
}

/// The DAC on its bus.
pub struct Mcp4728<I2C> {
    i2c: I2C,
    address: u8,
}

impl<I2C: I2c> Mcp4728<I2C> {
    /// Take the bus; `address` is the 7-bit address (see [`DEFAULT_ADDRESS`]).
    pub fn new(i2c: I2C, address: u8) -> Self {
        Self { i2c, address }
    }

    /// Give the bus back.
    pub fn release(self) -> I2C {
        self.i2c
    }

    /// Fast write (C2:C1 = 00): all four input registers, power-down bits 00, in one 8-byte
    /// transaction. Reference and gain stay as they are. Outputs update at the ACK (UDAC/LDAC low).
    pub fn fast_write(&mut self, codes: [u16; 4]) -> Result<(), Error<I2C::Error>> {
        let mut buf = [0u8; 8];
        for (i, &code) in codes.iter().enumerate() {
            check_code(code)?;
            buf[2 * i] = (code >> 8) as u8; // 0 0 PD1 PD0 D11..D8
            buf[2 * i + 1] = code as u8;
        }
        self.i2c.write(self.address, &buf).map_err(Error::I2c)
    }

    /// Multi-write (0b01000, UDAC = 0): up to four channels with reference and gain, one
    /// transaction, three bytes per channel.
    pub fn multi_write(&mut self, writes: &[ChannelWrite]) -> Result<(), Error<I2C::Error>> {
        let mut buf = [0u8; 12];
        for (i, w) in writes.iter().take(4).enumerate() {
            check_code(w.code)?;
            if w.channel > 3 {
                return Err(Error::ChannelOutOfRange(w.channel));
            }
            buf[3 * i] = 0b0100_0000 | (w.channel << 1);
            let vref = if w.vref == Vref::Internal { 0x80 } else { 0 };
            let gain = if w.gain == Gain::X2 { 0x10 } else { 0 };
            buf[3 * i + 1] = vref | gain | (w.code >> 8) as u8;
            buf[3 * i + 2] = w.code as u8;
        }
        self.i2c
            .write(self.address, &buf[..3 * writes.len().min(4)])
            .map_err(Error::I2c)
    }

    /// Write VREF select bits (0b100x_ABCD; 1 = internal) for all channels.
    pub fn set_vref(&mut self, vref: [Vref; 4]) -> Result<(), Error<I2C::Error>> {
        let bits = vref
            .iter()
            .fold(0u8, |acc, v| (acc << 1) | u8::from(*v == Vref::Internal));
        self.i2c
            .write(self.address, &[0b1000_0000 | bits])
            .map_err(Error::I2c)
    }

    /// Write gain select bits (0b110x_ABCD; 1 = ×2) for all channels.
    pub fn set_gain(&mut self, gain: [Gain; 4]) -> Result<(), Error<I2C::Error>> {
        let bits = gain
            .iter()
            .fold(0u8, |acc, g| (acc << 1) | u8::from(*g == Gain::X2));
        self.i2c
            .write(self.address, &[0b1100_0000 | bits])
            .map_err(Error::I2c)
    }

    /// Read the four DAC input registers (the device sends input register and EEPROM, 6 bytes per
    /// channel; the EEPROM half is skipped).
    pub fn read(&mut self) -> Result<[ChannelState; 4], Error<I2C::Error>> {
        let mut buf = [0u8; 24];
        self.i2c.read(self.address, &mut buf).map_err(Error::I2c)?;
        Ok(core::array::from_fn(|ch| {
            let b = &buf[6 * ch..6 * ch + 3];
            ChannelState {
                code: (u16::from(b[1] & 0x0F) << 8) | u16::from(b[2]),
                vref: if b[1] & 0x80 != 0 {
                    Vref::Internal
                } else {
                    Vref::Vdd
                },
                gain: if b[1] & 0x10 != 0 { Gain::X2 } else { Gain::X1 },
                power_down: (b[1] >> 5) & 0b11,
                busy: b[0] & 0x80 == 0,
            }
        }))
    }
}

/// Multi-write entries for the three bridge trims on channels A..=C, VDD reference, gain 1
/// (hardware/frontend.toml, `[trim]`: "VDD reference: 12 bits over 0 .. analog_v"). Channel D is
/// left alone: it holds the mid-rail reference.
pub fn trim_writes(codes: [u16; 3]) -> [ChannelWrite; 3] {
    core::array::from_fn(|ch| ChannelWrite {
        channel: ch as u8,
        code: codes[ch],
        vref: Vref::Vdd,
        gain: Gain::X1,
    })
}

fn check_code<E>(code: u16) -> Result<(), Error<E>> {
    if code > CODE_MAX {
        Err(Error::CodeOutOfRange(code))
    } else {
        Ok(())
    }
}

/// Output voltage in millivolts of `code` for a reference of `vref_mv` and gain (datasheet eq. 4-1).
pub fn output_mv(code: u16, vref_mv: u16, gain: Gain) -> f32 {
    let g = if gain == Gain::X2 { 2.0 } else { 1.0 };
    f32::from(vref_mv) * f32::from(code) / 4096.0 * g
}

#[cfg(test)]
mod tests {
    use super::*;
    use embedded_hal::i2c::ErrorKind;
    use embedded_hal_mock::eh1::i2c::{Mock, Transaction as Tx};

    #[test]
    fn fast_write_packs_four_channels_in_eight_bytes() {
        let mut i2c = Mock::new(&[Tx::write(
            0x60,
            vec![0x0F, 0xFF, 0x08, 0x00, 0x00, 0x01, 0x0A, 0xBC],
        )]);
        let mut dac = Mcp4728::new(i2c.clone(), DEFAULT_ADDRESS);
        dac.fast_write([4095, 2048, 1, 0xABC]).unwrap();
        i2c.done();
    }

    #[test]
    fn multi_write_sets_reference_and_gain_per_channel() {
        let expected = vec![0x40, 0x87, 0xD0, 0x46, 0x10, 0x01];
        let mut i2c = Mock::new(&[Tx::write(0x61, expected)]);
        let mut dac = Mcp4728::new(i2c.clone(), 0x61);
        dac.multi_write(&[
            ChannelWrite {
                channel: 0,
                code: 0x7D0,
                vref: Vref::Internal,
                gain: Gain::X1,
            },
            ChannelWrite {
                channel: 3,
                code: 0x001,
                vref: Vref::Vdd,
                gain: Gain::X2,
            },
        ])
        .unwrap();
        i2c.done();
    }

    #[test]
    fn vref_and_gain_select_commands() {
        let mut i2c = Mock::new(&[
            Tx::write(0x60, vec![0b1000_1111]),
            Tx::write(0x60, vec![0b1100_1010]),
        ]);
        let mut dac = Mcp4728::new(i2c.clone(), DEFAULT_ADDRESS);
        dac.set_vref([Vref::Internal; 4]).unwrap();
        dac.set_gain([Gain::X2, Gain::X1, Gain::X2, Gain::X1])
            .unwrap();
        i2c.done();
    }

    #[test]
    fn read_decodes_the_input_registers() {
        let mut bytes = vec![0u8; 24];
        bytes[..3].copy_from_slice(&[0x80, 0x98, 0x00]); // ready, internal ref, gain 2, code 0x800
        bytes[6..9].copy_from_slice(&[0x00, 0x2F, 0xFF]); // busy, VDD ref, PD = 01, code 0xFFF
        let mut i2c = Mock::new(&[Tx::read(0x60, bytes)]);
        let mut dac = Mcp4728::new(i2c.clone(), DEFAULT_ADDRESS);
        let s = dac.read().unwrap();
        assert_eq!(
            s[0],
            ChannelState {
                code: 0x800,
                vref: Vref::Internal,
                gain: Gain::X2,
                power_down: 0,
                busy: false
            }
        );
        assert_eq!(
            s[1],
            ChannelState {
                code: 0xFFF,
                vref: Vref::Vdd,
                gain: Gain::X1,
                power_down: 1,
                busy: true
            }
        );
        i2c.done();
    }

    #[test]
    fn out_of_range_code_and_channel_send_nothing() {
        let mut i2c = Mock::new(&[]);
        let mut dac = Mcp4728::new(i2c.clone(), DEFAULT_ADDRESS);
        assert_eq!(
            dac.fast_write([0, 4096, 0, 0]),
            Err(Error::CodeOutOfRange(4096))
        );
        let w = ChannelWrite {
            channel: 4,
            code: 1,
            vref: Vref::Vdd,
            gain: Gain::X1,
        };
        assert_eq!(dac.multi_write(&[w]), Err(Error::ChannelOutOfRange(4)));
        i2c.done();
    }

    #[test]
    fn bus_errors_are_kept() {
        let mut i2c = Mock::new(&[
            Tx::write(0x60, vec![0; 8]).with_error(ErrorKind::NoAcknowledge(
                embedded_hal::i2c::NoAcknowledgeSource::Address,
            )),
            Tx::read(0x60, vec![0; 24]).with_error(ErrorKind::Bus),
        ]);
        let mut dac = Mcp4728::new(i2c.clone(), DEFAULT_ADDRESS);
        assert_eq!(
            dac.fast_write([0; 4]),
            Err(Error::I2c(ErrorKind::NoAcknowledge(
                embedded_hal::i2c::NoAcknowledgeSource::Address
            )))
        );
        assert_eq!(dac.read(), Err(Error::I2c(ErrorKind::Bus)));
        i2c.done();
    }

    #[test]
    fn output_voltage_equation() {
        assert_eq!(output_mv(2048, 2048, Gain::X1), 1024.0);
        assert_eq!(output_mv(4095, 2048, Gain::X2), 4095.0);
    }
}
