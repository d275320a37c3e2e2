//! Driver for the TI ADS131M04 four-channel 24-bit simultaneous-sampling delta-sigma ADC, written
//! to the datasheet (SBAS890). Generic over an `embedded_hal::spi::SpiDevice` (SPI mode 1; one
//! transaction = one frame with chip select held low) and the active-low DRDY input.
//!
//! Frame protocol: every frame carries a command word in and a response word out, then the four
//! channel data words and a CRC word. The response to a command arrives in the *next* frame, so a
//! register read is RREG followed by NULL. The output CRC (CRC-16-CCITT) is checked on every frame;
//! with `input_crc` set, the driver also appends a CRC to what it sends and the device refuses
//! commands whose CRC does not match.

pub mod crc;

use ads131m04_regs::{addr, clock, cmd, gain1, id, mode, FRAME_WORDS};
use embedded_hal::digital::InputPin;
use embedded_hal::spi::SpiDevice;

pub use ads131m04_regs::{Osr, Pga, Status, WordLength, CHANNELS};

/// Largest frame in bytes (32-bit words).
const MAX_FRAME_BYTES: usize = FRAME_WORDS * 4;

/// Errors of the driver. The bus errors are kept as the HAL reported them.
#[derive(Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error<S, P> {
    /// The SPI transaction failed.
    Spi(S),
    /// Reading the DRDY pin failed.
    Drdy(P),
    /// The CRC word of a frame from the device does not match the frame's contents.
    Crc { computed: u16, received: u16 },
    /// The ID register does not identify a four-channel ADS131M04.
    WrongId(u16),
    /// The device answered a command with an unexpected response word.
    Response { expected: u16, received: u16 },
    /// The device reports (STATUS.CRC_ERR) that it refused a frame for a bad input CRC.
    InputCrc,
}

/// Settings applied by [`Ads131m04::init`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Config {
    pub word_length: WordLength,
    pub osr: Osr,
    pub gains: [Pga; CHANNELS],
    /// Send a CRC with every frame (MODE.RX_CRC_EN) so the device refuses corrupted commands.
    pub input_crc: bool,
}

/// One conversion: the STATUS word of the frame and the four codes (24-bit scale).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Conversion {
    pub status: Status,
    pub codes: [i32; CHANNELS],
}

/// A frame as received: response word and channel codes.
#[derive(Clone, Copy, Debug)]
struct Frame {
    response: u16,
    codes: [i32; CHANNELS],
}

/// The ADC on its bus.
pub struct Ads131m04<SPI, DRDY> {
    spi: SPI,
    drdy: DRDY,
    word: WordLength,
    input_crc: bool,
    /// The NULL frame to send for a data read, prebuilt for the current word length and CRC mode.
    null_frame: [u8; MAX_FRAME_BYTES],
    /// Receive buffer of the data read, kept rather than zeroed on the stack for every frame.
    rx: [u8; MAX_FRAME_BYTES],
}

type Result<T, SPI, DRDY> = core::result::Result<
    T,
    Error<
        <SPI as embedded_hal::spi::ErrorType>::Error,
        <DRDY as embedded_hal::digital::ErrorType>::Error,
    >,
>;

impl<SPI: SpiDevice, DRDY: InputPin> Ads131m04<SPI, DRDY> {
    /// Take the bus and the DRDY pin. The device is assumed in its reset state (24-bit words, no
    /// input CRC) until [`Self::init`] runs.
    pub fn new(spi: SPI, drdy: DRDY) -> Self {
        let mut dev = Self {
            spi,
            drdy,
            word: WordLength::Bits24,
            input_crc: false,
            null_frame: [0; MAX_FRAME_BYTES],
            rx: [0; MAX_FRAME_BYTES],
        };
        dev.rebuild_null_frame();
        dev
    }

    /// The DRDY pin, e.g. to clear its interrupt flag in the DRDY interrupt.
    pub fn drdy_mut(&mut self) -> &mut DRDY {
        &mut self.drdy
    }

    /// Give the bus and pin back.
    pub fn release(self) -> (SPI, DRDY) {
        (self.spi, self.drdy)
    }

    /// Reset, check the ID, and apply `config`. Returns the ID register.
    pub fn init(&mut self, config: &Config) -> Result<u16, SPI, DRDY> {
        self.reset()?;
        let id_reg = self.read_register(addr::ID)?;
        if id_reg & id::MASK != id::ADS131M04 {
            return Err(Error::WrongId(id_reg));
        }
        // TIMEOUT kept as at reset; RESET written 0 to acknowledge the reset.
        let mode = mode::TIMEOUT
            | (config.word_length.code() << mode::WLENGTH_SHIFT)
            | if config.input_crc { mode::RX_CRC_EN } else { 0 };
        // The new word length and CRC mode apply from the frame after the WREG, which is the one
        // that carries the acknowledgement.
        self.command(cmd::wreg(addr::MODE, 1), &[mode])?;
        self.word = config.word_length;
        self.input_crc = config.input_crc;
        self.rebuild_null_frame();
        self.expect_ack(cmd::wreg_ack(addr::MODE, 1))?;
        self.set_osr(config.osr)?;
        self.set_gains(config.gains)?;
        Ok(id_reg)
    }

    /// RESET command; the next frame must carry the reset acknowledgement. Word length and input
    /// CRC return to their defaults.
    pub fn reset(&mut self) -> Result<(), SPI, DRDY> {
        self.command(cmd::RESET, &[])?;
        self.word = WordLength::Bits24;
        self.input_crc = false;
        self.rebuild_null_frame();
        self.expect_ack(cmd::RESET_ACK)
    }

    /// Set the oversampling ratio (data rate), all channels enabled, high-resolution mode.
    pub fn set_osr(&mut self, osr: Osr) -> Result<(), SPI, DRDY> {
        let clock =
            clock::ALL_CHANNELS | (osr.code() << clock::OSR_SHIFT) | clock::PWR_HIGH_RESOLUTION;
        self.write_register(addr::CLOCK, clock)
    }

    /// Set the four PGA gains.
    pub fn set_gains(&mut self, gains: [Pga; CHANNELS]) -> Result<(), SPI, DRDY> {
        self.write_register(addr::GAIN1, gain1::encode(gains))
    }

    /// STANDBY: stop converting (low power) until [`Self::wakeup`].
    pub fn standby(&mut self) -> Result<(), SPI, DRDY> {
        self.simple_command(cmd::STANDBY)
    }

    /// WAKEUP from standby.
    pub fn wakeup(&mut self) -> Result<(), SPI, DRDY> {
        self.simple_command(cmd::WAKEUP)
    }

    /// LOCK the register map against writes.
    pub fn lock(&mut self) -> Result<(), SPI, DRDY> {
        self.simple_command(cmd::LOCK)
    }

    /// UNLOCK the register map.
    pub fn unlock(&mut self) -> Result<(), SPI, DRDY> {
        self.simple_command(cmd::UNLOCK)
    }

    /// Read one register (RREG, then NULL to clock out the answer).
    pub fn read_register(&mut self, address: u8) -> Result<u16, SPI, DRDY> {
        self.command(cmd::rreg(address), &[])?;
        let frame = self.command(cmd::NULL, &[])?;
        Ok(frame.response)
    }

    /// Write one register and check the acknowledgement.
    pub fn write_register(&mut self, address: u8, value: u16) -> Result<(), SPI, DRDY> {
        self.command(cmd::wreg(address, 1), &[value])?;
        self.expect_ack(cmd::wreg_ack(address, 1))
    }

    /// Whether DRDY is low (a conversion waits to be read).
    pub fn data_ready(&mut self) -> Result<bool, SPI, DRDY> {
        self.drdy.is_low().map_err(Error::Drdy)
    }

    /// Read the latest conversion with a NULL frame (response = STATUS). Checks the frame CRC and
    /// reports a refused input CRC from the device. Inlined into the caller (the sample-clock
    /// interrupt) for the common 24-bit word: the codes go from the decoder straight to where the
    /// caller keeps them instead of through a returned copy; other word lengths are out of line.
    #[inline(always)]
    pub fn read(&mut self) -> Result<Conversion, SPI, DRDY> {
        // One path per word length, each with its frame length fixed at compile time: no length
        // arithmetic, no slicing checks, and the CRC and decoding unroll and inline.
        let frame = if self.word == WordLength::Bits24 {
            self.read_frame::<3, { FRAME_WORDS * 3 }>()?
        } else {
            self.read_other_word_length()?
        };
        let status = Status(frame.response);
        if status.input_crc_error() {
            return Err(Error::InputCrc);
        }
        Ok(Conversion {
            status,
            codes: frame.codes,
        })
    }

    /// [`Self::read`]'s frame for 16- and 32-bit words.
    #[inline(never)]
    fn read_other_word_length(&mut self) -> Result<Frame, SPI, DRDY> {
        match self.word {
            WordLength::Bits16 => self.read_frame::<2, { FRAME_WORDS * 2 }>(),
            word => {
                let mut rx = [0u8; MAX_FRAME_BYTES];
                self.spi
                    .transfer(&mut rx, &self.null_frame)
                    .map_err(Error::Spi)?;
                parse_words::<4, SPI, DRDY>(&rx, word)
            }
        }
    }

    /// Clock one NULL frame of `N` = 6 words of `WB` bytes and parse it.
    #[inline(always)]
    fn read_frame<const WB: usize, const N: usize>(&mut self) -> Result<Frame, SPI, DRDY> {
        // N ≤ MAX_FRAME_BYTES for every instance, so the compiler drops the range checks.
        let rx = &mut self.rx[..N];
        self.spi
            .transfer(rx, &self.null_frame[..N])
            .map_err(Error::Spi)?;
        parse_words_inline::<WB, SPI, DRDY>(&self.rx[..N], self.word)
    }

    fn simple_command(&mut self, command: u16) -> Result<(), SPI, DRDY> {
        self.command(command, &[])?;
        self.expect_ack(command)
    }

    /// Send a NULL frame and require `expected` as its response word.
    fn expect_ack(&mut self, expected: u16) -> Result<(), SPI, DRDY> {
        let frame = self.command(cmd::NULL, &[])?;
        if frame.response == expected {
            Ok(())
        } else if Status(frame.response).input_crc_error() {
            Err(Error::InputCrc)
        } else {
            Err(Error::Response {
                expected,
                received: frame.response,
            })
        }
    }

    /// One frame: `command`, up to four data words, the input CRC when enabled, zero padding.
    fn command(&mut self, command: u16, data: &[u16]) -> Result<Frame, SPI, DRDY> {
        debug_assert!(
            data.len() <= CHANNELS,
            "at most four data words fit a frame"
        );
        let wb = self.word.bytes();
        let n = FRAME_WORDS * wb;
        let mut tx = [0u8; MAX_FRAME_BYTES];
        tx[..2].copy_from_slice(&command.to_be_bytes());
        for (i, word) in data.iter().enumerate() {
            tx[(i + 1) * wb..(i + 1) * wb + 2].copy_from_slice(&word.to_be_bytes());
        }
        if self.input_crc {
            let at = (1 + data.len()) * wb;
            let crc = crc::crc16(crc::SEED, &tx[..at]);
            tx[at..at + 2].copy_from_slice(&crc.to_be_bytes());
        }
        let mut rx = [0u8; MAX_FRAME_BYTES];
        self.spi
            .transfer(&mut rx[..n], &tx[..n])
            .map_err(Error::Spi)?;
        self.parse(&rx[..n])
    }

    /// Check the CRC word and decode response and data words.
    #[inline]
    fn parse(&self, rx: &[u8]) -> Result<Frame, SPI, DRDY> {
        match self.word {
            // The common case, with the frame length known at compile time: the CRC and the
            // decoding unroll completely.
            WordLength::Bits24 => parse_words::<3, SPI, DRDY>(rx, WordLength::Bits24),
            WordLength::Bits16 => parse_words::<2, SPI, DRDY>(rx, WordLength::Bits16),
            word => parse_words::<4, SPI, DRDY>(rx, word),
        }
    }

    fn rebuild_null_frame(&mut self) {
        self.null_frame = [0; MAX_FRAME_BYTES];
        if self.input_crc {
            let wb = self.word.bytes();
            let crc = crc::crc16(crc::SEED, &self.null_frame[..wb]);
            self.null_frame[wb..wb + 2].copy_from_slice(&crc.to_be_bytes());
        }
    }
}

/// Check the CRC word of a frame of `WB`-byte words and decode its response and data words.
#[inline]
fn parse_words<const WB: usize, SPI: SpiDevice, DRDY: InputPin>(
    rx: &[u8],
    word: WordLength,
) -> Result<Frame, SPI, DRDY> {
    parse_words_inline::<WB, SPI, DRDY>(rx, word)
}

/// [`parse_words`], always inlined: the data read's copy.
#[inline(always)]
fn parse_words_inline<const WB: usize, SPI: SpiDevice, DRDY: InputPin>(
    rx: &[u8],
    word: WordLength,
) -> Result<Frame, SPI, DRDY> {
    let Some(frame) = rx.get(..FRAME_WORDS * WB) else {
        // Shorter than a frame: cannot happen (the caller clocks whole frames); report it as a
        // CRC failure rather than panic.
        return Err(Error::Crc {
            computed: 0,
            received: 0,
        });
    };
    let computed = crc::crc16(crc::SEED, &frame[..5 * WB]);
    let received = u16::from_be_bytes([frame[5 * WB], frame[5 * WB + 1]]);
    if computed != received {
        return Err(Error::Crc { computed, received });
    }
    let response = u16::from_be_bytes([frame[0], frame[1]]);
    let codes = if WB == 3 {
        // The word length is known here: a 24-bit code is the top three bytes of a big-endian
        // 32-bit load (the fourth byte, from the next word, is shifted out), the same value as
        // `WordLength::Bits24.decode` without the run-time match.
        let code = |at: usize| {
            i32::from_be_bytes([frame[at], frame[at + 1], frame[at + 2], frame[at + 3]]) >> 8
        };
        [code(WB), code(2 * WB), code(3 * WB), code(4 * WB)]
    } else {
        core::array::from_fn(|ch| word.decode(&frame[(ch + 1) * WB..(ch + 2) * WB]))
    };
    Ok(Frame { response, codes })
}

#[cfg(test)]
mod tests;
