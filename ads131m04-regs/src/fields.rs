//! The fields of the STATUS, MODE, CLOCK and GAIN1 registers (section 8.6) and their encodings.

/// MODE register (address 0x02).
pub mod mode {
    /// Reset value: 24-bit words, CRC-CCITT, RESET flag set, SPI timeout on.
    pub const RESET_VALUE: u16 = 0x0510;
    /// RX_CRC_EN: the device checks a CRC on the frames it receives.
    pub const RX_CRC_EN: u16 = 1 << 12;
    /// CRC_TYPE: 0 = CRC-16-CCITT, 1 = ANSI CRC-16.
    pub const CRC_TYPE: u16 = 1 << 11;
    /// RESET: a reset happened; cleared by writing 0.
    pub const RESET: u16 = 1 << 10;
    /// Shift of WLENGTH (bits 9:8), see [`crate::WordLength`].
    pub const WLENGTH_SHIFT: u16 = 8;
    /// Mask of WLENGTH.
    pub const WLENGTH_MASK: u16 = 0b11 << WLENGTH_SHIFT;
    /// TIMEOUT: the SPI interface resets after 2^14 idle CLKIN periods mid-frame.
    pub const TIMEOUT: u16 = 1 << 4;
}

/// STATUS register (address 0x01), the response to NULL. Its bits 11:8 mirror MODE's CRC_TYPE,
/// RESET and WLENGTH at the same positions.
pub mod status {
    /// LOCK: the register map is locked.
    pub const LOCK: u16 = 1 << 15;
    /// F_RESYNC: the device resynchronised its conversions.
    pub const F_RESYNC: u16 = 1 << 14;
    /// REG_MAP: the register-map CRC changed.
    pub const REG_MAP: u16 = 1 << 13;
    /// CRC_ERR: the previous frame's input CRC did not match; its command was not executed.
    pub const CRC_ERR: u16 = 1 << 12;
    /// CRC_TYPE, as in MODE.
    pub const CRC_TYPE: u16 = super::mode::CRC_TYPE;
    /// RESET, as in MODE.
    pub const RESET: u16 = super::mode::RESET;
    /// WLENGTH, as in MODE.
    pub const WLENGTH_MASK: u16 = super::mode::WLENGTH_MASK;
    /// DRDY3..DRDY0: new data on channel 3..0.
    pub const DRDY_MASK: u16 = 0x000F;
}

/// CLOCK register (address 0x03).
pub mod clock {
    /// Reset value: all channels on, OSR 1024, high-resolution mode.
    pub const RESET_VALUE: u16 = 0x0F0E;
    /// Shift of CH3_EN..CH0_EN (bits 11:8).
    pub const CH_EN_SHIFT: u16 = 8;
    /// All four channel enables.
    pub const ALL_CHANNELS: u16 = 0xF << CH_EN_SHIFT;
    /// Shift of OSR (bits 4:2), see [`crate::Osr`].
    pub const OSR_SHIFT: u16 = 2;
    /// Mask of OSR.
    pub const OSR_MASK: u16 = 0b111 << OSR_SHIFT;
    /// PWR (bits 1:0) = high-resolution mode: the modulator runs at f_CLKIN / 2.
    pub const PWR_HIGH_RESOLUTION: u16 = 0b10;
}

/// GAIN1 register (address 0x04): PGAGAINn in bits 4n+2..4n, see [`crate::Pga`].
pub mod gain1 {
    use crate::{Pga, CHANNELS};

    /// Bits between the fields of neighbouring channels.
    const FIELD_BITS: usize = 4;

    /// The register value for four channel gains.
    pub fn encode(gains: [Pga; CHANNELS]) -> u16 {
        gains
            .iter()
            .enumerate()
            .fold(0, |acc, (ch, g)| acc | (g.code() << (FIELD_BITS * ch)))
    }

    /// The four channel gains of a register value.
    pub fn decode(value: u16) -> [Pga; CHANNELS] {
        core::array::from_fn(|ch| Pga::from_code(value >> (FIELD_BITS * ch)))
    }
}

/// Oversampling ratio, CLOCK.OSR. Data rate = f_CLKIN / 2 / OSR in high-resolution mode (1 kSPS
/// at OSR 4096 and 8.192 MHz).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Osr {
    /// OSR 128.
    Osr128 = 0,
    /// OSR 256.
    Osr256 = 1,
    /// OSR 512.
    Osr512 = 2,
    /// OSR 1024 (reset default).
    Osr1024 = 3,
    /// OSR 2048.
    Osr2048 = 4,
    /// OSR 4096.
    Osr4096 = 5,
    /// OSR 8192.
    Osr8192 = 6,
    /// Code 7 is 16256, not 16384.
    Osr16256 = 7,
}

impl Osr {
    /// Every setting, in code order.
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

    /// The 3-bit field value.
    pub const fn code(self) -> u16 {
        self as u16
    }

    /// The setting of a field value (bits above the field ignored).
    pub const fn from_code(code: u16) -> Self {
        Self::ALL[(code & 0b111) as usize]
    }

    /// The setting held in a CLOCK register value.
    pub const fn from_clock(clock: u16) -> Self {
        Self::from_code((clock & clock::OSR_MASK) >> clock::OSR_SHIFT)
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

/// Programmable gain of one channel, GAIN1.PGAGAINn: 1, 2, 4, …, 128.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Pga(u8);

impl Pga {
    /// Gain 1 (reset default).
    pub const X1: Pga = Pga(0);

    /// The PGA setting for a gain of `gain`, if the device has it.
    pub const fn from_gain(gain: u8) -> Option<Self> {
        if gain.is_power_of_two() {
            Some(Pga(gain.trailing_zeros() as u8))
        } else {
            None
        }
    }

    /// The setting of a 3-bit field value (bits above the field ignored).
    pub const fn from_code(code: u16) -> Self {
        Pga((code & 0b111) as u8)
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

/// A STATUS word (the response to NULL), decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status(pub u16);

impl Status {
    /// Register map locked (LOCK command).
    #[inline]
    pub const fn locked(self) -> bool {
        self.0 & status::LOCK != 0
    }
    /// Resynchronisation fault.
    #[inline]
    pub const fn resync(self) -> bool {
        self.0 & status::F_RESYNC != 0
    }
    /// Register-map CRC changed.
    #[inline]
    pub const fn regmap_crc_fault(self) -> bool {
        self.0 & status::REG_MAP != 0
    }
    /// The device rejected the previous frame's input CRC.
    #[inline]
    pub const fn input_crc_error(self) -> bool {
        self.0 & status::CRC_ERR != 0
    }
    /// A reset occurred and has not been acknowledged by clearing MODE.RESET.
    #[inline]
    pub const fn reset(self) -> bool {
        self.0 & status::RESET != 0
    }
    /// Word length field.
    #[inline]
    pub const fn word_length_code(self) -> u16 {
        (self.0 & status::WLENGTH_MASK) >> mode::WLENGTH_SHIFT
    }
    /// New data on channel `ch` (0..=3).
    #[inline]
    pub const fn drdy(self, ch: usize) -> bool {
        self.0 & (1 << ch) != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn osr_round_trips_through_its_field_and_the_clock_register() {
        for osr in Osr::ALL {
            assert_eq!(Osr::from_code(osr.code()), osr);
            let clock =
                clock::ALL_CHANNELS | (osr.code() << clock::OSR_SHIFT) | clock::PWR_HIGH_RESOLUTION;
            assert_eq!(Osr::from_clock(clock), osr);
        }
        assert_eq!(Osr::from_clock(clock::RESET_VALUE), Osr::Osr1024);
    }

    #[test]
    fn gains_round_trip_through_gain1() {
        assert_eq!(Pga::from_gain(32).map(Pga::code), Some(5));
        assert_eq!(Pga::from_gain(3), None);
        let g = [
            Pga::X1,
            Pga::from_gain(2).unwrap(),
            Pga::from_gain(4).unwrap(),
            Pga::from_gain(128).unwrap(),
        ];
        assert_eq!(gain1::encode(g), 0x7210);
        assert_eq!(gain1::decode(0x7210), g);
        for code in 0..8 {
            let pga = Pga::from_code(code);
            assert_eq!(Pga::from_gain(pga.gain()), Some(pga));
            assert_eq!(gain1::decode(gain1::encode([pga; 4])), [pga; 4]);
        }
    }

    #[test]
    fn status_bits_decode_to_their_flags() {
        let s = Status(status::LOCK | status::CRC_ERR | status::RESET | (1 << 8) | 0b0101);
        assert!(s.locked() && s.input_crc_error() && s.reset());
        assert!(!s.resync() && !s.regmap_crc_fault());
        assert_eq!(s.word_length_code(), 1);
        assert!(s.drdy(0) && !s.drdy(1) && s.drdy(2) && !s.drdy(3));
    }
}
