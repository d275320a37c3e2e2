//! Register-level emulation of the TI ADS131M04 (4-channel, 24-bit, simultaneous-sampling
//! delta-sigma ADC) as the firmware sees it: an `embedded_hal::spi::SpiDevice` speaking the
//! datasheet's frame protocol (SBAS890 §8.5) plus an active-low DRDY `InputPin`.
//!
//! What is emulated: command words NULL / RESET / STANDBY / WAKEUP / LOCK / UNLOCK / RREG (one
//! register) / WREG, the one-frame response latency, the STATUS word, word lengths 16/24/32 bits
//! (zero-padded or sign-extended), the output CRC word on every frame and the input CRC check when
//! MODE.RX_CRC_EN is set, the CLOCK register's OSR (data rate) and channel enables, GAIN1's PGA,
//! and DRDY (low from a conversion until its data have been clocked out).
//! Not emulated: multi-register RREG (answered with STATUS), the ANSI CRC type, offset/gain
//! calibration registers (stored, not applied), the global-chop and current-detect modes, DRDY
//! pulse shape and timing; conversions happen when the owner calls [`Ads131m04::convert`].
//! The analog side is an [`AnalogInput`]: volts at the four ADC inputs per conversion index.
//! No noise is added here: noise belongs to the front-end model feeding the input.

pub mod crc;
pub mod regs;
pub mod stimulus;
pub mod stimulus_file;
pub mod trim_dac;

use core::cell::RefCell;
use core::convert::Infallible;

use embedded_hal::digital::{ErrorType as PinErrorType, InputPin};
use embedded_hal::spi::{ErrorType as SpiErrorType, Operation, SpiDevice};

use crc::{crc16_ccitt, CRC_INIT};

/// Internal reference voltage (datasheet: 1.2 V); full scale is ±VREF / gain.
pub const VREF_V: f32 = 1.2;
/// Nominal CLKIN (datasheet typical 8.192 MHz); the modulator runs at CLKIN / 2.
pub const CLKIN_HZ: u32 = 8_192_000;
/// Largest and smallest 24-bit codes.
pub const CODE_MAX: i32 = (1 << 23) - 1;
pub const CODE_MIN: i32 = -(1 << 23);
/// Longest input frame the emulation buffers (a WREG of 20 registers with CRC in 32-bit words).
const MAX_FRAME_BYTES: usize = 96;
/// Words in an output frame: response, four channels, CRC.
const FRAME_WORDS: usize = 6;

/// The analog signal at the ADC's four differential inputs.
pub trait AnalogInput {
    /// Input voltages in volts for the conversion with index `index` (0 for the first one).
    fn sample_v(&mut self, index: u64) -> [f32; 4];
}

/// The ideal conversion: code = round(v · gain / VREF · 2^23), clamped to the 24-bit range.
/// `gain` is the PGA gain (1, 2, 4, …, 128). All arithmetic is plain f32, so the host and the
/// Cortex-M4F compute identical codes for identical inputs.
pub fn ideal_code(v: f32, gain: u8, vref_v: f32) -> i32 {
    let scaled = v * f32::from(gain) / vref_v * 8_388_608.0;
    let rounded = if scaled >= 0.0 {
        scaled + 0.5
    } else {
        scaled - 0.5
    };
    if rounded >= CODE_MAX as f32 {
        CODE_MAX
    } else if rounded <= CODE_MIN as f32 {
        CODE_MIN
    } else {
        rounded as i32
    }
}

/// The emulated chip. Share it through a `RefCell` and hand out [`SpiHandle`] and [`DrdyHandle`]
/// with [`handles`].
pub struct Ads131m04<A> {
    regs: [u16; regs::REG_COUNT],
    input: A,
    codes: [i32; 4],
    /// New conversion not yet clocked out: DRDY is low.
    fresh: bool,
    next_index: u64,
    overruns: u64,
    response: Response,
    standby: bool,
    locked: bool,
    crc_err: bool,
    frames: u64,
    // Frame in progress.
    out: [u8; FRAME_WORDS * 4],
    out_len: usize,
    inp: [u8; MAX_FRAME_BYTES],
    inp_len: usize,
    pos: usize,
    data_end: usize,
}

impl<A: AnalogInput> Ads131m04<A> {
    /// A chip just out of power-on reset, converting `input`.
    pub fn new(input: A) -> Self {
        let mut chip = Self {
            regs: [0; regs::REG_COUNT],
            input,
            codes: [0; 4],
            fresh: false,
            next_index: 0,
            overruns: 0,
            response: Response::Word(regs::RESET_RESPONSE),
            standby: false,
            locked: false,
            crc_err: false,
            frames: 0,
            out: [0; FRAME_WORDS * 4],
            out_len: 0,
            inp: [0; MAX_FRAME_BYTES],
            inp_len: 0,
            pos: 0,
            data_end: 0,
        };
        chip.reset();
        chip
    }

    fn reset(&mut self) {
        self.regs = [0; regs::REG_COUNT];
        for (addr, value) in regs::RESET_VALUES {
            self.regs[usize::from(addr)] = value;
        }
        self.standby = false;
        self.locked = false;
        self.crc_err = false;
        self.response = Response::Word(regs::RESET_RESPONSE);
    }

    /// One conversion period has elapsed: convert the input and pull DRDY low. A conversion that
    /// was never read is overwritten and counted in [`Self::overruns`]. Nothing happens in standby.
    #[allow(clippy::needless_range_loop)] // channel index selects gain bits, enable bit and code
    pub fn convert(&mut self) {
        if self.standby {
            return;
        }
        let volts = self.input.sample_v(self.next_index);
        let gain1 = self.regs[usize::from(regs::GAIN1)];
        let enabled = self.regs[usize::from(regs::CLOCK)] >> regs::CLOCK_CH_EN_SHIFT;
        for ch in 0..4 {
            let gain = 1u8 << ((gain1 >> (4 * ch)) & 0b111);
            self.codes[ch] = if enabled & (1 << ch) != 0 {
                ideal_code(volts[ch], gain, VREF_V)
            } else {
                0
            };
        }
        if self.fresh {
            self.overruns += 1;
        }
        self.fresh = true;
        self.next_index += 1;
    }

    /// Output data rate in samples per second at the nominal CLKIN: CLKIN / 2 / OSR.
    pub fn data_rate_hz(&self) -> f32 {
        let code =
            (self.regs[usize::from(regs::CLOCK)] & regs::CLOCK_OSR_MASK) >> regs::CLOCK_OSR_SHIFT;
        (CLKIN_HZ / 2) as f32 / regs::OSR[usize::from(code)] as f32
    }

    /// The current value of a register (test and HIL visibility; the firmware uses RREG).
    pub fn register(&self, addr: u8) -> u16 {
        if addr == regs::STATUS {
            self.status()
        } else {
            self.regs[usize::from(addr & 0x3F)]
        }
    }

    /// Codes of the latest conversion.
    pub fn codes(&self) -> [i32; 4] {
        self.codes
    }

    /// Index the next conversion will have (= conversions done so far).
    pub fn conversions(&self) -> u64 {
        self.next_index
    }

    /// Conversions overwritten before the host read them.
    pub fn overruns(&self) -> u64 {
        self.overruns
    }

    /// SPI frames seen (chip-select assertions).
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// The analog input, e.g. to change a stimulus parameter or feed a trim correction.
    pub fn input_mut(&mut self) -> &mut A {
        &mut self.input
    }

    /// DRDY pin level: low while a conversion waits to be read.
    pub fn drdy_is_low(&self) -> bool {
        self.fresh
    }

    fn word_bytes(&self) -> usize {
        match (self.regs[usize::from(regs::MODE)] & regs::MODE_WLENGTH_MASK)
            >> regs::MODE_WLENGTH_SHIFT
        {
            0 => 2,
            1 => 3,
            _ => 4,
        }
    }

    fn status(&self) -> u16 {
        let mode = self.regs[usize::from(regs::MODE)];
        let enabled = (self.regs[usize::from(regs::CLOCK)] >> regs::CLOCK_CH_EN_SHIFT) & 0xF;
        let mut status =
            mode & (regs::STATUS_RESET | regs::MODE_WLENGTH_MASK | regs::STATUS_CRC_TYPE);
        if self.locked {
            status |= regs::STATUS_LOCK;
        }
        if self.crc_err {
            status |= regs::STATUS_CRC_ERR;
        }
        if self.fresh {
            status |= enabled;
        }
        status
    }

    /// Chip select asserted: lay out the output frame (response, 4 data words, CRC).
    fn begin_frame(&mut self) {
        let wb = self.word_bytes();
        let wlength = (self.regs[usize::from(regs::MODE)] & regs::MODE_WLENGTH_MASK)
            >> regs::MODE_WLENGTH_SHIFT;
        self.out = [0; FRAME_WORDS * 4];
        let response = match self.response {
            Response::Word(word) => word,
            Response::Status => {
                // STATUS reflects the moment the frame starts; CRC_ERR clears once reported.
                let status = self.status();
                self.crc_err = false;
                status
            }
        };
        self.out[..2].copy_from_slice(&response.to_be_bytes());
        for (ch, &code) in self.codes.iter().enumerate() {
            let word = &mut self.out[(ch + 1) * wb..(ch + 2) * wb];
            let be = code.to_be_bytes(); // [sign, b23..16, b15..8, b7..0]
            match wlength {
                0 => word.copy_from_slice(&be[1..3]),
                1 => word.copy_from_slice(&be[1..4]),
                2 => word[..3].copy_from_slice(&be[1..4]),
                _ => word.copy_from_slice(&be),
            }
        }
        let crc_at = 5 * wb;
        let crc = crc16_ccitt(CRC_INIT, &self.out[..crc_at]);
        self.out[crc_at..crc_at + 2].copy_from_slice(&crc.to_be_bytes());
        self.out_len = FRAME_WORDS * wb;
        self.data_end = 5 * wb;
        self.inp_len = 0;
        self.pos = 0;
    }

    /// One byte clocked in on MOSI; returns the byte clocked out on MISO.
    fn shift(&mut self, mosi: u8) -> u8 {
        let miso = if self.pos < self.out_len {
            self.out[self.pos]
        } else {
            0
        };
        if self.inp_len < MAX_FRAME_BYTES {
            self.inp[self.inp_len] = mosi;
            self.inp_len += 1;
        }
        self.pos += 1;
        if self.pos == self.data_end {
            self.fresh = false;
        }
        miso
    }

    /// Chip select released: execute the command of the frame; its response goes out next frame.
    fn end_frame(&mut self) {
        self.frames += 1;
        let wb = self.word_bytes();
        if self.inp_len < wb {
            return; // too short to carry a command: ignored, response unchanged
        }
        let word = |i: usize, inp: &[u8]| u16::from_be_bytes([inp[i * wb], inp[i * wb + 1]]);
        let command = word(0, &self.inp);
        let is_wreg = command & regs::OPCODE_MASK == regs::CMD_WREG;
        let data_words = if is_wreg {
            usize::from(command & 0x7F) + 1
        } else {
            0
        };
        let mode = self.regs[usize::from(regs::MODE)];
        if mode & regs::MODE_RX_CRC_EN != 0 {
            let crc_word = 1 + data_words;
            if (crc_word + 1) * wb > self.inp_len {
                self.reject_input();
                return;
            }
            let expected = crc16_ccitt(CRC_INIT, &self.inp[..crc_word * wb]);
            if word(crc_word, &self.inp) != expected {
                self.reject_input();
                return;
            }
        }
        if (1 + data_words) * wb > self.inp_len {
            self.reject_input();
            return;
        }
        self.execute(command, wb);
    }

    /// Input CRC mismatch or truncated frame: the command is not executed, CRC_ERR is set.
    fn reject_input(&mut self) {
        self.crc_err = true;
        self.response = Response::Status;
    }

    fn execute(&mut self, command: u16, wb: usize) {
        let addr = ((command >> 7) & 0x3F) as u8;
        let count = usize::from(command & 0x7F) + 1;
        let allowed_when_locked = command == regs::CMD_NULL
            || command == regs::CMD_UNLOCK
            || command & regs::OPCODE_MASK == regs::CMD_RREG;
        if self.locked && !allowed_when_locked {
            self.response = Response::Status;
            return;
        }
        if command == regs::CMD_RESET {
            self.reset();
            return;
        }
        let word = match command {
            regs::CMD_STANDBY => {
                self.standby = true;
                command
            }
            regs::CMD_WAKEUP => {
                self.standby = false;
                command
            }
            regs::CMD_LOCK => {
                self.locked = true;
                command
            }
            regs::CMD_UNLOCK => {
                self.locked = false;
                command
            }
            c if c & regs::OPCODE_MASK == regs::CMD_RREG && count == 1 => self.register(addr),
            c if c & regs::OPCODE_MASK == regs::CMD_WREG => {
                for i in 0..count {
                    let reg = addr.wrapping_add(i as u8);
                    let at = (1 + i) * wb;
                    let value = u16::from_be_bytes([self.inp[at], self.inp[at + 1]]);
                    if regs::WRITABLE.contains(&reg) {
                        self.regs[usize::from(reg)] = value;
                    }
                }
                regs::WREG_RESPONSE | (command & 0x1FFF)
            }
            _ => {
                self.response = Response::Status;
                return;
            }
        };
        self.response = Response::Word(word);
    }
}

/// What the next frame's first word carries.
#[derive(Clone, Copy)]
enum Response {
    /// The STATUS register as of the frame start (after NULL, unknown or refused commands).
    Status,
    /// A fixed word: a command echo, register contents, or the WREG / RESET acknowledgement.
    Word(u16),
}

/// The SPI side of a shared chip.
pub struct SpiHandle<'a, A>(&'a RefCell<Ads131m04<A>>);
/// The DRDY pin of a shared chip (active low).
pub struct DrdyHandle<'a, A>(&'a RefCell<Ads131m04<A>>);

/// SPI device and DRDY pin for one shared chip.
pub fn handles<A: AnalogInput>(
    chip: &RefCell<Ads131m04<A>>,
) -> (SpiHandle<'_, A>, DrdyHandle<'_, A>) {
    (SpiHandle(chip), DrdyHandle(chip))
}

impl<A> SpiErrorType for SpiHandle<'_, A> {
    type Error = Infallible;
}

impl<A: AnalogInput> SpiDevice for SpiHandle<'_, A> {
    /// One transaction is one frame: chip select low for all operations.
    fn transaction(&mut self, operations: &mut [Operation<'_, u8>]) -> Result<(), Infallible> {
        let mut chip = self.0.borrow_mut();
        chip.begin_frame();
        for op in operations.iter_mut() {
            match op {
                Operation::Read(buf) => buf.iter_mut().for_each(|b| *b = chip.shift(0)),
                Operation::Write(buf) => buf.iter().for_each(|&b| {
                    chip.shift(b);
                }),
                Operation::Transfer(read, write) => {
                    for i in 0..read.len().max(write.len()) {
                        let miso = chip.shift(write.get(i).copied().unwrap_or(0));
                        if let Some(r) = read.get_mut(i) {
                            *r = miso;
                        }
                    }
                }
                Operation::TransferInPlace(buf) => buf.iter_mut().for_each(|b| *b = chip.shift(*b)),
                Operation::DelayNs(_) => {}
            }
        }
        chip.end_frame();
        Ok(())
    }
}

impl<A> PinErrorType for DrdyHandle<'_, A> {
    type Error = Infallible;
}

impl<A: AnalogInput> InputPin for DrdyHandle<'_, A> {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        Ok(!self.0.borrow().drdy_is_low())
    }

    fn is_low(&mut self) -> Result<bool, Infallible> {
        Ok(self.0.borrow().drdy_is_low())
    }
}

#[cfg(test)]
mod tests;
