//! ADS131M04 register addresses, command words and field encodings (datasheet SBAS890 §8.5.1.9
//! "Commands" and §8.6 "Register Map").

/// Register addresses.
pub mod addr {
    pub const ID: u8 = 0x00;
    pub const STATUS: u8 = 0x01;
    pub const MODE: u8 = 0x02;
    pub const CLOCK: u8 = 0x03;
    pub const GAIN1: u8 = 0x04;
}

/// Command words (16 bits, MSB-aligned in the first word of the frame).
pub mod cmd {
    pub const NULL: u16 = 0x0000;
    pub const RESET: u16 = 0x0011;
    pub const STANDBY: u16 = 0x0022;
    pub const WAKEUP: u16 = 0x0033;
    pub const LOCK: u16 = 0x0555;
    pub const UNLOCK: u16 = 0x0655;
    /// 101a_aaaa_annn_nnnn: read n + 1 registers from address a.
    pub const RREG: u16 = 0xA000;
    /// 011a_aaaa_annn_nnnn: write n + 1 registers from address a.
    pub const WREG: u16 = 0x6000;
    /// Response to WREG: 010a_aaaa_ammm_mmmm.
    pub const WREG_ACK: u16 = 0x4000;
    /// Response to RESET on a 4-channel device: 0xFF20 | channel count.
    pub const RESET_ACK: u16 = 0xFF24;

    /// RREG of one register.
    pub const fn rreg(addr: u8) -> u16 {
        RREG | ((addr as u16 & 0x3F) << 7)
    }
    /// WREG of `count` (1..=4) registers starting at `addr`.
    pub const fn wreg(addr: u8, count: u8) -> u16 {
        WREG | ((addr as u16 & 0x3F) << 7) | ((count as u16 - 1) & 0x7F)
    }
    /// The acknowledgement the device sends for `wreg(addr, count)`.
    pub const fn wreg_ack(addr: u8, count: u8) -> u16 {
        WREG_ACK | ((addr as u16 & 0x3F) << 7) | ((count as u16 - 1) & 0x7F)
    }
}

/// ID register: bits 11:8 are the channel count; the high nibble reads 0b0010 for the family.
pub const ID_MASK: u16 = 0xFF00;
pub const ID_ADS131M04: u16 = 0x2400;

/// MODE register: reset value 0x0510 keeps the SPI timeout (bit 4); we set WLENGTH (9:8) and
/// RX_CRC_EN (12) and clear the RESET flag (10) by writing 0 to it.
pub const MODE_TIMEOUT: u16 = 1 << 4;
pub const MODE_RX_CRC_EN: u16 = 1 << 12;
pub const MODE_WLENGTH_SHIFT: u16 = 8;

/// CLOCK register: all four channels enabled (11:8), OSR (4:2), power mode high resolution (1:0).
pub const CLOCK_ALL_CHANNELS: u16 = 0x0F00;
pub const CLOCK_OSR_SHIFT: u16 = 2;
pub const CLOCK_PWR_HIGH_RESOLUTION: u16 = 0b10;

/// Word length of the SPI frame (MODE.WLENGTH).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum WordLength {
    /// 16-bit words: data truncated to the 16 MSBs.
    Bits16 = 0,
    /// 24-bit words (reset default).
    Bits24 = 1,
    /// 32-bit words, data MSB-aligned with a zero LSB byte.
    Bits32ZeroPad = 2,
    /// 32-bit words, data sign-extended into the MSB byte.
    Bits32SignExtend = 3,
}

impl WordLength {
    /// Bytes per word on the wire.
    pub const fn bytes(self) -> usize {
        match self {
            Self::Bits16 => 2,
            Self::Bits24 => 3,
            Self::Bits32ZeroPad | Self::Bits32SignExtend => 4,
        }
    }

    /// A 24-bit code from one data word, sign-extended to i32. 16-bit data keep the 24-bit scale
    /// (the 8 LSBs read as zero).
    #[inline]
    pub fn decode(self, w: &[u8]) -> i32 {
        match self {
            Self::Bits16 => i32::from(i16::from_be_bytes([w[0], w[1]])) << 8,
            Self::Bits24 | Self::Bits32ZeroPad => i32::from_be_bytes([w[0], w[1], w[2], 0]) >> 8,
            Self::Bits32SignExtend => i32::from_be_bytes([w[0], w[1], w[2], w[3]]),
        }
    }
}

/// Oversampling ratio (CLOCK.OSR). Data rate = f_CLKIN / 2 / OSR (4 kSPS at OSR 1024, 8.192 MHz).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Osr {
    Osr128 = 0,
    Osr256 = 1,
    Osr512 = 2,
    Osr1024 = 3,
    Osr2048 = 4,
    Osr4096 = 5,
    Osr8192 = 6,
    /// Code 7 is 16256, not 16384.
    Osr16256 = 7,
}

impl Osr {
    pub const ALL: [Osr; 8] = [
        Self::Osr128,
        Self::Osr256,
        Self::Osr512,
        Self::Osr1024,
        Self::Osr2048,
        Self::Osr4096,
        Self::Osr8192,
        Self::Osr16256,
    ];

    /// The ratio itself.
    pub const fn ratio(self) -> u32 {
        match self {
            Self::Osr16256 => 16256,
            other => 128 << (other as u32),
        }
    }

    /// Output data rate for a clock input of `clkin_hz`, rounded down to whole samples/s.
    pub const fn data_rate_hz(self, clkin_hz: u32) -> u32 {
        clkin_hz / 2 / self.ratio()
    }

    /// The OSR giving exactly `rate_hz` at `clkin_hz`, if any. The product is checked: a rate
    /// from the host whose product wraps must not alias a real rate (found by fuzzing).
    pub fn for_rate(rate_hz: u32, clkin_hz: u32) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|osr| rate_hz.checked_mul(osr.ratio()) == Some(clkin_hz / 2))
    }
}

/// Programmable gain of one channel (GAIN1.PGAGAINn): 1, 2, 4, …, 128.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Pga(u8);

impl Pga {
    pub const X1: Pga = Pga(0);

    /// The PGA setting for a gain of `gain`, if the device has it.
    pub const fn from_gain(gain: u8) -> Option<Self> {
        if gain.is_power_of_two() {
            Some(Pga(gain.trailing_zeros() as u8))
        } else {
            None
        }
    }

    /// The gain (1..=128).
    pub const fn gain(self) -> u8 {
        1 << self.0
    }

    /// The 3-bit field value.
    pub const fn code(self) -> u16 {
        self.0 as u16
    }
}

/// The GAIN1 register value for four channel gains.
pub fn gain1(gains: [Pga; 4]) -> u16 {
    gains
        .iter()
        .enumerate()
        .fold(0, |acc, (ch, g)| acc | (g.code() << (4 * ch)))
}

/// The STATUS word (response to NULL).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status(pub u16);

impl Status {
    /// Register map locked (LOCK command).
    pub const fn locked(self) -> bool {
        self.0 & (1 << 15) != 0
    }
    /// Resynchronisation fault.
    pub const fn resync(self) -> bool {
        self.0 & (1 << 14) != 0
    }
    /// Register-map CRC changed.
    pub const fn regmap_crc_fault(self) -> bool {
        self.0 & (1 << 13) != 0
    }
    /// The device rejected the previous frame's input CRC.
    pub const fn input_crc_error(self) -> bool {
        self.0 & (1 << 12) != 0
    }
    /// A reset occurred and has not been acknowledged by clearing MODE.RESET.
    pub const fn reset(self) -> bool {
        self.0 & (1 << 10) != 0
    }
    /// Word length field.
    pub const fn word_length_code(self) -> u16 {
        (self.0 >> 8) & 0b11
    }
    /// New data on channel `ch` (0..=3).
    pub const fn drdy(self, ch: usize) -> bool {
        self.0 & (1 << ch) != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn command_words_match_the_datasheet_bit_patterns() {
        assert_eq!(cmd::rreg(addr::ID), 0b1010_0000_0000_0000);
        assert_eq!(cmd::rreg(addr::CLOCK), 0b1010_0001_1000_0000);
        assert_eq!(cmd::wreg(addr::GAIN1, 1), 0b0110_0010_0000_0000);
        assert_eq!(cmd::wreg_ack(addr::MODE, 2), 0b0100_0001_0000_0001);
    }

    #[test]
    fn osr_rates_at_8_192_mhz() {
        assert_eq!(Osr::Osr128.data_rate_hz(8_192_000), 32_000);
        assert_eq!(Osr::Osr1024.data_rate_hz(8_192_000), 4_000);
        assert_eq!(Osr::Osr16256.data_rate_hz(8_192_000), 251);
        assert_eq!(Osr::for_rate(1000, 8_192_000), Some(Osr::Osr4096));
        assert_eq!(Osr::for_rate(1001, 8_192_000), None);
        // 32 kSPS plus 2^25: × 128 wraps to exactly clkin/2 in 32-bit arithmetic.
        assert_eq!(Osr::for_rate(32_000 + (1 << 25), 8_192_000), None);
    }

    #[test]
    fn gains_and_word_decoding() {
        assert_eq!(Pga::from_gain(32).map(Pga::code), Some(5));
        assert_eq!(Pga::from_gain(3), None);
        let g = [
            Pga::X1,
            Pga::from_gain(2).unwrap(),
            Pga::from_gain(4).unwrap(),
            Pga::from_gain(128).unwrap(),
        ];
        assert_eq!(gain1(g), 0x7210);
        assert_eq!(WordLength::Bits24.decode(&[0xFF, 0xFF, 0xFE]), -2);
        assert_eq!(
            WordLength::Bits32ZeroPad.decode(&[0x80, 0, 0, 0]),
            -(1 << 23)
        );
        assert_eq!(
            WordLength::Bits32SignExtend.decode(&[0xFF, 0xC0, 0, 0]),
            -(1 << 22)
        );
        assert_eq!(WordLength::Bits16.decode(&[0x40, 0x00]), 1 << 22);
    }
}
