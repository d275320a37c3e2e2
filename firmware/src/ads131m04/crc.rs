//! CRC-16-CCITT of the ADS131M04's SPI frames: polynomial 0x1021, seed 0xFFFF, MSB first, no final
//! XOR (datasheet SBAS890 §8.5.1.10, MODE.CRC_TYPE = 0). Table-driven: the check runs on every
//! frame, 15 bytes in 24-bit mode, so it costs a few instructions per byte instead of ~40.

/// The device's CRC seed.
pub const SEED: u16 = 0xFFFF;
const POLY: u16 = 0x1021;

/// One table entry per value of the top byte of the running CRC.
const TABLE: [u16; 256] = build_table();

const fn build_table() -> [u16; 256] {
    let mut table = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let mut crc = (i as u16) << 8;
        let mut bit = 0;
        while bit < 8 {
            crc = if crc & 0x8000 != 0 { (crc << 1) ^ POLY } else { crc << 1 };
            bit += 1;
        }
        table[i] = crc;
        i += 1;
    }
    table
}

/// CRC of `bytes` starting from `crc`.
#[inline]
pub fn crc16(mut crc: u16, bytes: &[u8]) -> u16 {
    for &byte in bytes {
        crc = (crc << 8) ^ TABLE[usize::from((crc >> 8) as u8 ^ byte)];
    }
    crc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_value_of_crc16_ccitt_false() {
        assert_eq!(crc16(SEED, b"123456789"), 0x29B1);
    }

    #[test]
    fn table_matches_the_bitwise_definition() {
        let bitwise = |bytes: &[u8]| {
            let mut crc = SEED;
            for &b in bytes {
                crc ^= u16::from(b) << 8;
                for _ in 0..8 {
                    crc = if crc & 0x8000 != 0 { (crc << 1) ^ POLY } else { crc << 1 };
                }
            }
            crc
        };
        let data: [u8; 18] = core::array::from_fn(|i| (i as u8).wrapping_mul(37).wrapping_add(11));
        assert_eq!(crc16(SEED, &data), bitwise(&data));
    }
}
