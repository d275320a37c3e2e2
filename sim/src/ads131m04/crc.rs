//! CRC-16-CCITT as the ADS131M04 computes it (MODE.CRC_TYPE = 0): polynomial 0x1021, initial value
//! 0xFFFF, no reflection, no final XOR. Bitwise on purpose: the emulation is a second, independent
//! implementation of the checksum the firmware computes with a table.

/// CRC-16-CCITT of `bytes`, continuing from `crc` (start with [`CRC_INIT`]).
pub fn crc16_ccitt(mut crc: u16, bytes: &[u8]) -> u16 {
    for &byte in bytes {
        crc ^= u16::from(byte) << 8;
        for _ in 0..8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ 0x1021
            } else {
                crc << 1
            };
        }
    }
    crc
}

/// Initial value of the device's CRC register (datasheet: "seed value FFFFh").
pub const CRC_INIT: u16 = 0xFFFF;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_ccitt_false_check_value() {
        // CRC-16/CCITT-FALSE check value for the ASCII string "123456789".
        assert_eq!(crc16_ccitt(CRC_INIT, b"123456789"), 0x29B1);
    }

    #[test]
    fn a_frame_followed_by_its_crc_leaves_zero() {
        let mut frame = [0x05, 0x00, 0x00, 0x12, 0x34, 0x56, 0, 0];
        let crc = crc16_ccitt(CRC_INIT, &frame[..6]);
        frame[6..].copy_from_slice(&crc.to_be_bytes());
        assert_eq!(crc16_ccitt(CRC_INIT, &frame), 0);
    }
}
