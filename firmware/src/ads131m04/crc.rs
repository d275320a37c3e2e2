//! CRC-16-CCITT of the ADS131M04's SPI frames: polynomial 0x1021, seed 0xFFFF, MSB first, no final
//! XOR (datasheet SBAS890 §8.5.1.10, MODE.CRC_TYPE = 0). Table-driven, two bytes per step: the
//! check runs on every frame, 15 bytes in 24-bit mode, so it costs a few instructions per byte
//! instead of ~40 bitwise.

/// The device's CRC seed.
pub const SEED: u16 = 0xFFFF;
const POLY: u16 = 0x1021;

/// One table entry per value of the top byte of the running CRC.
const TABLE: [u16; 256] = build_table();
/// TABLE advanced by one more zero byte: the contribution of the first of two bytes, so two
/// bytes take two lookups and no dependent shift in between (slicing by two, 512 bytes more).
const TABLE2: [u16; 256] = build_table2();

const fn build_table2() -> [u16; 256] {
    let mut t = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let c = TABLE[i];
        t[i] = (c << 8) ^ TABLE[(c >> 8) as usize];
        i += 1;
    }
    t
}

const fn build_table() -> [u16; 256] {
    let mut table = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let mut crc = (i as u16) << 8;
        let mut bit = 0;
        while bit < 8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ POLY
            } else {
                crc << 1
            };
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
    let mut pairs = bytes.chunks_exact(2);
    for p in &mut pairs {
        let x = crc ^ u16::from_be_bytes([p[0], p[1]]);
        crc = TABLE2[usize::from(x >> 8)] ^ TABLE[usize::from(x & 0xFF)];
    }
    for &byte in pairs.remainder() {
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
                    crc = if crc & 0x8000 != 0 {
                        (crc << 1) ^ POLY
                    } else {
                        crc << 1
                    };
                }
            }
            crc
        };
        let data: [u8; 19] = core::array::from_fn(|i| (i as u8).wrapping_mul(37).wrapping_add(11));
        for len in 0..=data.len() {
            assert_eq!(
                crc16(SEED, &data[..len]),
                bitwise(&data[..len]),
                "len {len}"
            );
        }
    }
}
