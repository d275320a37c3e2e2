//! Command words and the responses they earn (section 8.5, "Commands"). A command is 16 bits,
//! MSB-aligned in the first word of a frame; its response arrives in the first word of the
//! *next* frame.

/// No operation; the response is the STATUS register.
pub const NULL: u16 = 0x0000;
/// Reset the device; answered with [`RESET_ACK`].
pub const RESET: u16 = 0x0011;
/// Stop converting (low power) until [`WAKEUP`]; echoed.
pub const STANDBY: u16 = 0x0022;
/// Leave standby; echoed.
pub const WAKEUP: u16 = 0x0033;
/// Lock the register map against writes; echoed.
pub const LOCK: u16 = 0x0555;
/// Unlock the register map; echoed.
pub const UNLOCK: u16 = 0x0655;
/// RREG opcode, `101a_aaaa_annn_nnnn`: read n + 1 registers from address a.
pub const RREG: u16 = 0xA000;
/// WREG opcode, `011a_aaaa_annn_nnnn`: write n + 1 registers from address a.
pub const WREG: u16 = 0x6000;
/// The opcode bits of RREG and WREG.
pub const OPCODE_MASK: u16 = 0xE000;
/// Response to WREG, `010a_aaaa_ammm_mmmm`: the address and count of the write.
pub const WREG_ACK: u16 = 0x4000;
/// Response to RESET of a four-channel device: `0xFF20 | channel count`.
pub const RESET_ACK: u16 = 0xFF20 | super::CHANNELS as u16;

/// Shift of the 6-bit address field in RREG, WREG and the WREG acknowledgement.
const ADDRESS_SHIFT: u16 = 7;
/// Mask of the 7-bit `count - 1` field.
const COUNT_MASK: u16 = 0x7F;

/// The address and count fields of RREG, WREG and the WREG acknowledgement.
const fn fields(address: u8, count: u8) -> u16 {
    ((address as u16 & super::addr::MASK as u16) << ADDRESS_SHIFT)
        | ((count as u16).wrapping_sub(1) & COUNT_MASK)
}

/// RREG of one register.
#[inline]
pub const fn rreg(address: u8) -> u16 {
    RREG | fields(address, 1)
}

/// WREG of `count` (1..=4 in one frame) registers starting at `address`.
#[inline]
pub const fn wreg(address: u8, count: u8) -> u16 {
    WREG | fields(address, count)
}

/// The acknowledgement the device sends for `wreg(address, count)`.
#[inline]
pub const fn wreg_ack(address: u8, count: u8) -> u16 {
    WREG_ACK | fields(address, count)
}

/// The register address a RREG or WREG word names.
#[inline]
pub const fn address(word: u16) -> u8 {
    ((word >> ADDRESS_SHIFT) as u8) & super::addr::MASK
}

/// The number of registers a RREG or WREG word names (its field holds the count minus one).
#[inline]
pub const fn count(word: u16) -> usize {
    (word & COUNT_MASK) as usize + 1
}

/// Whether `word` is a RREG.
#[inline]
pub const fn is_rreg(word: u16) -> bool {
    word & OPCODE_MASK == RREG
}

/// Whether `word` is a WREG.
#[inline]
pub const fn is_wreg(word: u16) -> bool {
    word & OPCODE_MASK == WREG
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::addr;

    #[test]
    fn command_words_match_the_datasheet_bit_patterns() {
        assert_eq!(rreg(addr::ID), 0b1010_0000_0000_0000);
        assert_eq!(rreg(addr::CLOCK), 0b1010_0001_1000_0000);
        assert_eq!(wreg(addr::GAIN1, 1), 0b0110_0010_0000_0000);
        assert_eq!(wreg_ack(addr::MODE, 2), 0b0100_0001_0000_0001);
        assert_eq!(RESET_ACK, 0xFF24);
    }

    #[test]
    fn address_and_count_round_trip_through_every_register_word() {
        for a in 0..addr::COUNT as u8 {
            for n in 1..=4 {
                for word in [wreg(a, n), wreg_ack(a, n)] {
                    assert_eq!((address(word), count(word)), (a, usize::from(n)));
                }
                assert!(is_wreg(wreg(a, n)) && !is_rreg(wreg(a, n)));
            }
            assert_eq!((address(rreg(a)), count(rreg(a))), (a, 1));
            assert!(is_rreg(rreg(a)) && !is_wreg(rreg(a)));
        }
    }

    #[test]
    fn the_fixed_commands_are_neither_rreg_nor_wreg() {
        for word in [NULL, RESET, STANDBY, WAKEUP, LOCK, UNLOCK] {
            assert!(!is_rreg(word) && !is_wreg(word), "{word:#06x}");
        }
    }
}
