//! The SPI word (section 8.5, "SPI Communication Words"): every word of a frame has the length
//! MODE.WLENGTH sets; 16-bit command, response and CRC words are MSB-aligned in it, and a 24-bit
//! conversion code is laid out as this type says.

use crate::mode;

/// Word length of the SPI frame, MODE.WLENGTH.
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
    #[inline]
    pub const fn bytes(self) -> usize {
        match self {
            Self::Bits16 => 2,
            Self::Bits24 => 3,
            Self::Bits32ZeroPad | Self::Bits32SignExtend => 4,
        }
    }

    /// The 2-bit field value.
    pub const fn code(self) -> u16 {
        self as u16
    }

    /// The setting of a field value (bits above the field ignored).
    pub const fn from_code(code: u16) -> Self {
        match code & 0b11 {
            0 => Self::Bits16,
            1 => Self::Bits24,
            2 => Self::Bits32ZeroPad,
            _ => Self::Bits32SignExtend,
        }
    }

    /// The setting held in a MODE (or STATUS) register value.
    pub const fn from_mode(mode: u16) -> Self {
        Self::from_code((mode & mode::WLENGTH_MASK) >> mode::WLENGTH_SHIFT)
    }

    /// A 24-bit code from one data word (at least [`Self::bytes`] long), sign-extended to i32.
    /// 16-bit data keep the 24-bit scale (the 8 LSBs read as zero).
    #[inline]
    pub fn decode(self, w: &[u8]) -> i32 {
        match self {
            Self::Bits16 => i32::from(i16::from_be_bytes([w[0], w[1]])) << 8,
            Self::Bits24 | Self::Bits32ZeroPad => i32::from_be_bytes([w[0], w[1], w[2], 0]) >> 8,
            Self::Bits32SignExtend => i32::from_be_bytes([w[0], w[1], w[2], w[3]]),
        }
    }

    /// The data word (its first [`Self::bytes`] bytes of `w`) of a 24-bit code, as the device
    /// sends it.
    #[inline]
    pub fn encode(self, code: i32, w: &mut [u8]) {
        let be = code.to_be_bytes(); // [sign, bits 23..16, 15..8, 7..0]
        match self {
            Self::Bits16 => w[..2].copy_from_slice(&be[1..3]),
            Self::Bits24 => w[..3].copy_from_slice(&be[1..4]),
            Self::Bits32ZeroPad => {
                w[..3].copy_from_slice(&be[1..4]);
                w[3] = 0;
            }
            Self::Bits32SignExtend => w[..4].copy_from_slice(&be),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol::{CODE_MAX, CODE_MIN};

    const ALL: [WordLength; 4] = [
        WordLength::Bits16,
        WordLength::Bits24,
        WordLength::Bits32ZeroPad,
        WordLength::Bits32SignExtend,
    ];

    #[test]
    fn decoding_matches_the_datasheet_layouts() {
        assert_eq!(WordLength::Bits24.decode(&[0xFF, 0xFF, 0xFE]), -2);
        assert_eq!(WordLength::Bits32ZeroPad.decode(&[0x80, 0, 0, 0]), CODE_MIN);
        assert_eq!(
            WordLength::Bits32SignExtend.decode(&[0xFF, 0xC0, 0, 0]),
            -(1 << 22)
        );
        assert_eq!(WordLength::Bits16.decode(&[0x40, 0x00]), 1 << 22);
    }

    #[test]
    fn codes_round_trip_through_every_word_length_up_to_full_scale() {
        for word in ALL {
            for code in [CODE_MIN, CODE_MIN + 1, -256, -1, 0, 1, 255, 256, CODE_MAX] {
                let mut w = [0xAA; 4];
                word.encode(code, &mut w);
                // 16-bit words carry the top 16 of the 24 bits.
                let kept = if word == WordLength::Bits16 {
                    code & !0xFF
                } else {
                    code
                };
                assert_eq!(word.decode(&w[..word.bytes()]), kept, "{word:?} {code}");
            }
        }
    }

    #[test]
    fn the_field_round_trips_through_mode() {
        for word in ALL {
            assert_eq!(WordLength::from_code(word.code()), word);
            let m =
                (mode::RESET_VALUE & !mode::WLENGTH_MASK) | (word.code() << mode::WLENGTH_SHIFT);
            assert_eq!(WordLength::from_mode(m), word);
        }
        assert_eq!(WordLength::from_mode(mode::RESET_VALUE), WordLength::Bits24);
    }
}
