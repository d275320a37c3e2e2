//! The CRC of the SPI frames (section 8.5, "Communication Cyclic Redundancy Check (CRC)"): with
//! MODE.CRC_TYPE = 0 it is CRC-16-CCITT, polynomial 0x1021, seed 0xFFFF, MSB first, no
//! reflection, no final XOR. The device appends it to every output frame over the words before
//! it; with MODE.RX_CRC_EN the host appends one to its frames too.
//!
//! [`crc16_bitwise`] is the definition, bit by bit. The firmware runs a table-driven version on
//! every frame and checks it against this one; the emulation uses this one directly.

/// The generator polynomial (x^16 + x^12 + x^5 + 1).
pub const POLY: u16 = 0x1021;
/// The seed: the CRC register's value before the first byte.
pub const SEED: u16 = 0xFFFF;

/// CRC of `bytes`, continuing from `crc` (start with [`SEED`]).
pub fn crc16_bitwise(mut crc: u16, bytes: &[u8]) -> u16 {
    for &byte in bytes {
        crc ^= u16::from(byte) << 8;
        for _ in 0..8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ POLY
            } else {
                crc << 1
            };
        }
    }
    crc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_ccitt_false_check_value() {
        // CRC-16/CCITT-FALSE check value for the ASCII string "123456789".
        assert_eq!(crc16_bitwise(SEED, b"123456789"), 0x29B1);
    }

    #[test]
    fn a_frame_followed_by_its_crc_leaves_zero() {
        let mut frame = [0x05, 0x00, 0x00, 0x12, 0x34, 0x56, 0, 0];
        let crc = crc16_bitwise(SEED, &frame[..6]);
        frame[6..].copy_from_slice(&crc.to_be_bytes());
        assert_eq!(crc16_bitwise(SEED, &frame), 0);
    }
}
