//! Register map, command words and bit fields of the ADS131M04 (TI datasheet SBAS890, sections
//! 8.5 "Programming" and 8.6 "Register Map"), as the emulation needs them.

/// Register addresses.
pub const ID: u8 = 0x00;
pub const STATUS: u8 = 0x01;
pub const MODE: u8 = 0x02;
pub const CLOCK: u8 = 0x03;
pub const GAIN1: u8 = 0x04;
pub const CFG: u8 = 0x06;
pub const REGMAP_CRC: u8 = 0x3E;
/// Number of register addresses (6-bit address field).
pub const REG_COUNT: usize = 64;

/// ID register value: bits 11:8 CHANCNT = 4; the low byte is reserved (reads 0 here).
pub const ID_VALUE: u16 = 0x2400;

/// Reset values of the registers that do not reset to 0: ID, MODE, CLOCK, CFG and the four
/// CHn_GCAL_MSB registers (0x8000 = gain calibration 1.0).
pub const RESET_VALUES: [(u8, u16); 8] = [
    (ID, ID_VALUE),
    (MODE, 0x0510),
    (CLOCK, 0x0F0E),
    (CFG, 0x0600),
    (0x0C, 0x8000),
    (0x11, 0x8000),
    (0x16, 0x8000),
    (0x1B, 0x8000),
];
/// Registers the host may write (WREG to others is ignored): MODE..=CH3_GCAL_LSB.
pub const WRITABLE: core::ops::RangeInclusive<u8> = MODE..=0x1D;

/// Command words (16 bits, MSB-aligned in the first word of a frame).
pub const CMD_NULL: u16 = 0x0000;
pub const CMD_RESET: u16 = 0x0011;
pub const CMD_STANDBY: u16 = 0x0022;
pub const CMD_WAKEUP: u16 = 0x0033;
pub const CMD_LOCK: u16 = 0x0555;
pub const CMD_UNLOCK: u16 = 0x0655;
/// RREG: 101a_aaaa_annn_nnnn; WREG: 011a_aaaa_annn_nnnn (n = registers - 1).
pub const CMD_RREG: u16 = 0xA000;
pub const CMD_WREG: u16 = 0x6000;
/// Mask of the opcode bits of RREG / WREG.
pub const OPCODE_MASK: u16 = 0xE000;
/// Response to RESET: 0xFF20 | channel count.
pub const RESET_RESPONSE: u16 = 0xFF24;
/// Response to WREG: 010a_aaaa_ammm_mmmm.
pub const WREG_RESPONSE: u16 = 0x4000;

/// STATUS bits.
pub const STATUS_LOCK: u16 = 1 << 15;
pub const STATUS_CRC_ERR: u16 = 1 << 12;
pub const STATUS_CRC_TYPE: u16 = 1 << 11;
pub const STATUS_RESET: u16 = 1 << 10;

/// MODE bits.
pub const MODE_RX_CRC_EN: u16 = 1 << 12;
pub const MODE_CRC_TYPE: u16 = 1 << 11;
pub const MODE_RESET: u16 = 1 << 10;
pub const MODE_WLENGTH_SHIFT: u16 = 8;
pub const MODE_WLENGTH_MASK: u16 = 0b11 << 8;

/// CLOCK fields: channel enables (11:8), OSR (4:2).
pub const CLOCK_CH_EN_SHIFT: u16 = 8;
pub const CLOCK_OSR_SHIFT: u16 = 2;
pub const CLOCK_OSR_MASK: u16 = 0b111 << 2;

/// Oversampling ratio per CLOCK.OSR code (code 7 is 16256, not 16384).
pub const OSR: [u32; 8] = [128, 256, 512, 1024, 2048, 4096, 8192, 16256];
