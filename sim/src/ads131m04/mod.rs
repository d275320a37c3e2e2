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

pub mod stimulus;
pub mod stimulus_file;
pub mod trim_dac;

use core::cell::RefCell;
use core::convert::Infallible;

use ads131m04_regs::crc::{crc16_bitwise, SEED};
use ads131m04_regs::{addr, clock, cmd, gain1, mode, status, Osr, WordLength, FRAME_WORDS};
use embedded_hal::digital::{ErrorType as PinErrorType, InputPin};
use embedded_hal::spi::{ErrorType as SpiErrorType, Operation, SpiDevice};

/// Longest input frame the emulation buffers (a WREG of 20 registers with CRC in 32-bit words).
const MAX_FRAME_BYTES: usize = 96;

/// What the chip takes from its board: reference and clock (`hardware/adc.toml`,
/// `reference.internal_v` and `clock.clkin_hz`, read by the `hardware` crate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdcParams {
    /// Reference voltage: full scale is ±`vref_v` / PGA gain.
    pub vref_v: f64,
    /// CLKIN frequency; the modulator runs at half of it (high-resolution mode).
    pub clkin_hz: u32,
}

#[cfg(feature = "std")]
impl AdcParams {
    /// The reference and clock of `adc.toml`.
    pub fn from_hardware(adc: &hardware::Adc) -> Self {
        Self {
            vref_v: adc.reference_v,
            clkin_hz: adc.clkin_hz.round() as u32,
        }
    }
}

/// The analog signal at the ADC's four differential inputs.
pub trait AnalogInput {
    /// Input voltages in volts for the conversion with index `index` (0 for the first one).
    fn sample_v(&mut self, index: u64) -> [f32; 4];
}

/// The emulated chip. Share it through a `RefCell` and hand out [`SpiHandle`] and [`DrdyHandle`]
/// with [`handles`].
pub struct Ads131m04<A> {
    regs: [u16; addr::COUNT],
    params: AdcParams,
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
    /// A chip just out of power-on reset, converting `input` with the reference and clock of
    /// `params`.
    pub fn new(input: A, params: AdcParams) -> Self {
        let mut chip = Self {
            regs: [0; addr::COUNT],
            params,
            input,
            codes: [0; 4],
            fresh: false,
            next_index: 0,
            overruns: 0,
            response: Response::Word(cmd::RESET_ACK),
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
        self.regs = [0; addr::COUNT];
        for (address, value) in ads131m04_regs::RESET_VALUES {
            self.regs[usize::from(address)] = value;
        }
        self.standby = false;
        self.locked = false;
        self.crc_err = false;
        self.response = Response::Word(cmd::RESET_ACK);
    }

    /// One conversion period has elapsed: convert the input and pull DRDY low. A conversion that
    /// was never read is overwritten and counted in [`Self::overruns`]. Nothing happens in standby.
    pub fn convert(&mut self) {
        if self.standby {
            return;
        }
        let volts = self.input.sample_v(self.next_index);
        let gains = gain1::decode(self.regs[usize::from(addr::GAIN1)]);
        let enabled = self.regs[usize::from(addr::CLOCK)] >> clock::CH_EN_SHIFT;
        for (ch, code) in self.codes.iter_mut().enumerate() {
            *code = if enabled & (1 << ch) != 0 {
                let gain = u32::from(gains[ch].gain());
                protocol::codes::volts_to_code(f64::from(volts[ch]), self.params.vref_v, gain)
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

    /// Output data rate in samples per second: CLKIN / 2 / OSR.
    pub fn data_rate_hz(&self) -> f32 {
        let osr = Osr::from_clock(self.regs[usize::from(addr::CLOCK)]);
        (self.params.clkin_hz / 2) as f32 / osr.ratio() as f32
    }

    /// The reference and clock the chip runs from.
    pub fn params(&self) -> AdcParams {
        self.params
    }

    /// The current value of a register (test and HIL visibility; the firmware uses RREG).
    pub fn register(&self, address: u8) -> u16 {
        if address == addr::STATUS {
            self.status()
        } else {
            self.regs[usize::from(address & addr::MASK)]
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

    fn word_length(&self) -> WordLength {
        WordLength::from_mode(self.regs[usize::from(addr::MODE)])
    }

    fn status(&self) -> u16 {
        let mode = self.regs[usize::from(addr::MODE)];
        let enabled =
            (self.regs[usize::from(addr::CLOCK)] >> clock::CH_EN_SHIFT) & status::DRDY_MASK;
        // STATUS mirrors MODE's RESET, WLENGTH and CRC_TYPE bits at the same positions.
        let mut word = mode & (status::RESET | status::WLENGTH_MASK | status::CRC_TYPE);
        if self.locked {
            word |= status::LOCK;
        }
        if self.crc_err {
            word |= status::CRC_ERR;
        }
        if self.fresh {
            word |= enabled;
        }
        word
    }

    /// Chip select asserted: lay out the output frame (response, 4 data words, CRC).
    fn begin_frame(&mut self) {
        let word_length = self.word_length();
        let wb = word_length.bytes();
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
            word_length.encode(code, &mut self.out[(ch + 1) * wb..(ch + 2) * wb]);
        }
        let crc_at = (FRAME_WORDS - 1) * wb;
        let crc = crc16_bitwise(SEED, &self.out[..crc_at]);
        self.out[crc_at..crc_at + 2].copy_from_slice(&crc.to_be_bytes());
        self.out_len = FRAME_WORDS * wb;
        self.data_end = crc_at;
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
        let wb = self.word_length().bytes();
        if self.inp_len < wb {
            return; // too short to carry a command: ignored, response unchanged
        }
        let word = |i: usize, inp: &[u8]| u16::from_be_bytes([inp[i * wb], inp[i * wb + 1]]);
        let command = word(0, &self.inp);
        let data_words = if cmd::is_wreg(command) {
            cmd::count(command)
        } else {
            0
        };
        if self.regs[usize::from(addr::MODE)] & mode::RX_CRC_EN != 0 {
            let crc_word = 1 + data_words;
            if (crc_word + 1) * wb > self.inp_len {
                self.reject_input();
                return;
            }
            let expected = crc16_bitwise(SEED, &self.inp[..crc_word * wb]);
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
        let allowed_when_locked =
            command == cmd::NULL || command == cmd::UNLOCK || cmd::is_rreg(command);
        if self.locked && !allowed_when_locked {
            self.response = Response::Status;
            return;
        }
        let word = match command {
            cmd::RESET => {
                self.reset();
                return;
            }
            cmd::STANDBY => {
                self.standby = true;
                command
            }
            cmd::WAKEUP => {
                self.standby = false;
                command
            }
            cmd::LOCK => {
                self.locked = true;
                command
            }
            cmd::UNLOCK => {
                self.locked = false;
                command
            }
            c if cmd::is_rreg(c) && cmd::count(c) == 1 => self.register(cmd::address(c)),
            c if cmd::is_wreg(c) => {
                self.write_registers(c, wb);
                cmd::WREG_ACK | (c & !cmd::OPCODE_MASK)
            }
            _ => {
                self.response = Response::Status;
                return;
            }
        };
        self.response = Response::Word(word);
    }

    /// The data words of a WREG frame into the registers they address; writes to read-only
    /// addresses are ignored.
    fn write_registers(&mut self, command: u16, wb: usize) {
        let first = cmd::address(command);
        for i in 0..cmd::count(command) {
            let reg = first.wrapping_add(i as u8);
            let at = (1 + i) * wb;
            let value = u16::from_be_bytes([self.inp[at], self.inp[at + 1]]);
            if ads131m04_regs::WRITABLE.contains(&reg) {
                self.regs[usize::from(reg)] = value;
            }
        }
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

/// The datasheet's typical reference and clock (internal 1.2 V, 8.192 MHz), for tests that check
/// codes and rates against the datasheet's numbers.
#[cfg(test)]
pub(crate) const DATASHEET_PARAMS: AdcParams = AdcParams {
    vref_v: 1.2,
    clkin_hz: 8_192_000,
};

#[cfg(test)]
mod tests;
