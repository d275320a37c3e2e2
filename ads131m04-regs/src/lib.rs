//! The TI ADS131M04's register map, command words, field encodings and SPI frame facts: the one
//! description of the chip that the firmware's driver (`firmware::ads131m04`) and the sim's
//! register-level emulation (`sim::ads131m04`) both program against, so the two cannot disagree
//! about a bit.
//!
//! Source: TI datasheet SBAS890, section 8.5 "Programming" (SPI frames and words, commands,
//! CRC) and section 8.6 "Register Map" (one table per register; the register names below are
//! the datasheet's). Only what the driver or the emulation uses is here.
//!
//! ```
//! use ads131m04_regs::{addr, cmd, Osr};
//!
//! let word = cmd::wreg(addr::CLOCK, 1);
//! assert_eq!((cmd::address(word), cmd::count(word)), (addr::CLOCK, 1));
//! assert_eq!(Osr::Osr4096.data_rate_hz(8_192_000), 1000);
//! ```
#![no_std]
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

pub mod cmd;
pub mod crc;
mod fields;
mod word;

pub use fields::{clock, gain1, mode, status, Osr, Pga, Status};
pub use word::WordLength;

/// Input channels of the ADS131M04.
pub const CHANNELS: usize = 4;

/// Words in a frame of the four-channel device (section 8.5, "SPI Communication Frames"): the
/// command word in and the response word out, one data word per channel, the CRC word.
pub const FRAME_WORDS: usize = 2 + CHANNELS;

/// Register addresses (section 8.6, "Register Map"). The address field of RREG and WREG is 6
/// bits wide.
pub mod addr {
    /// ID: channel count and revision (read-only).
    pub const ID: u8 = 0x00;
    /// STATUS: flags and the data-ready bits (read-only; also the response to NULL).
    pub const STATUS: u8 = 0x01;
    /// MODE: word length, CRC settings, reset flag, SPI timeout, DRDY format.
    pub const MODE: u8 = 0x02;
    /// CLOCK: channel enables, oversampling ratio, power mode.
    pub const CLOCK: u8 = 0x03;
    /// GAIN1: the PGA gain of each channel.
    pub const GAIN1: u8 = 0x04;
    /// CFG: global chop and current detection.
    pub const CFG: u8 = 0x06;
    /// CHn_GCAL_MSB, the gain-calibration register of channel n (reset 0x8000, gain 1.0). Each
    /// channel has a block of five registers from CH0_CFG (0x09): CFG, OCAL_MSB, OCAL_LSB,
    /// GCAL_MSB, GCAL_LSB.
    pub const CH_GCAL_MSB: [u8; super::CHANNELS] = [0x0C, 0x11, 0x16, 0x1B];
    /// CH3_GCAL_LSB, the last register of the channel blocks.
    pub const CH3_GCAL_LSB: u8 = 0x1C;
    /// REGMAP_CRC: the register map's CRC (read-only).
    pub const REGMAP_CRC: u8 = 0x3E;
    /// Number of addresses the 6-bit address field spans.
    pub const COUNT: usize = 64;
    /// Mask of the 6-bit address field.
    pub const MASK: u8 = 0x3F;
}

/// ID register (section 8.6): bits 15:12 read 0b0010 for the family, bits 11:8 are the channel
/// count, the low byte is reserved.
pub mod id {
    /// The bits that identify the part (family and channel count).
    pub const MASK: u16 = 0xFF00;
    /// Family and channel count of the four-channel ADS131M04.
    pub const ADS131M04: u16 = 0x2400;
}

/// Reset values of the registers that do not reset to 0 (section 8.6): ID, MODE, CLOCK, CFG and
/// the four gain-calibration registers.
pub const RESET_VALUES: [(u8, u16); 8] = [
    (addr::ID, id::ADS131M04),
    (addr::MODE, mode::RESET_VALUE),
    (addr::CLOCK, clock::RESET_VALUE),
    (addr::CFG, 0x0600),
    (addr::CH_GCAL_MSB[0], 0x8000),
    (addr::CH_GCAL_MSB[1], 0x8000),
    (addr::CH_GCAL_MSB[2], 0x8000),
    (addr::CH_GCAL_MSB[3], 0x8000),
];

/// The registers a WREG may change: MODE through CH3_GCAL_LSB (ID and STATUS are read-only, the
/// addresses above the channel blocks are reserved or read-only).
pub const WRITABLE: core::ops::RangeInclusive<u8> = addr::MODE..=addr::CH3_GCAL_LSB;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channel_blocks_are_five_registers_from_ch0_cfg() {
        for (ch, &gcal) in addr::CH_GCAL_MSB.iter().enumerate() {
            assert_eq!(gcal, 0x09 + 5 * ch as u8 + 3);
        }
        assert_eq!(addr::CH3_GCAL_LSB, addr::CH_GCAL_MSB[3] + 1);
    }

    #[test]
    fn reset_values_sit_at_valid_addresses() {
        for (address, _) in RESET_VALUES {
            assert!(usize::from(address) < addr::COUNT);
            assert_eq!(address & addr::MASK, address);
        }
        assert!(!WRITABLE.contains(&addr::ID) && !WRITABLE.contains(&addr::STATUS));
    }
}
