//! The sample clock's work, the same on every board (the DRDY interrupt on the NUCLEO, SysTick
//! under QEMU): read one conversion through the driver and queue it, never waiting. A failed read
//! (bus error, CRC mismatch) queues the last good codes flagged as a read error, so the index
//! sequence stays whole and the device core can count the failure.

use embedded_hal::digital::InputPin;
use embedded_hal::spi::SpiDevice;

use super::{Acquirer, RawSample};
use crate::ads131m04::{Ads131m04, CHANNELS};

/// The ADC, the queue's producing end and the conversion counter the interrupt owns.
pub struct Sampler<'a, SPI, DRDY> {
    adc: Ads131m04<SPI, DRDY>,
    acq: Acquirer<'a>,
    index: u32,
    last: [i32; CHANNELS],
}

impl<'a, SPI: SpiDevice, DRDY: InputPin> Sampler<'a, SPI, DRDY> {
    /// Sample `adc` (initialised) into `acq`, counting conversions from 0.
    pub fn new(adc: Ads131m04<SPI, DRDY>, acq: Acquirer<'a>) -> Self {
        Self {
            adc,
            acq,
            index: 0,
            last: [0; CHANNELS],
        }
    }

    /// The driver, e.g. to change the rate or clear the DRDY pin's interrupt flag.
    pub fn adc_mut(&mut self) -> &mut Ads131m04<SPI, DRDY> {
        &mut self.adc
    }

    /// One conversion is ready: read it and queue it.
    #[inline]
    pub fn on_conversion(&mut self) {
        let (codes, read_error) = match self.adc.read() {
            Ok(conv) => (conv.codes, false),
            Err(_) => (self.last, true),
        };
        self.last = codes;
        self.acq.push(RawSample {
            index: self.index,
            codes,
            read_error,
        });
        self.index = self.index.wrapping_add(1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ads131m04::{Config, Osr, Pga, WordLength};
    use crate::params::EMULATED_ADC;
    use crate::stream::{Overruns, SampleQueue};
    use core::cell::{Cell, RefCell};
    use embedded_hal::spi::{ErrorType, Operation};
    use sim::ads131m04::stimulus::{Stimulus, StimulusParams};
    use sim::ads131m04::{handles, Ads131m04 as Emu};

    /// An SPI device that flips a bit of what it reads while `corrupt` is set.
    struct Flaky<'a, S> {
        inner: S,
        corrupt: &'a Cell<bool>,
    }

    impl<S: SpiDevice> ErrorType for Flaky<'_, S> {
        type Error = S::Error;
    }

    impl<S: SpiDevice> SpiDevice for Flaky<'_, S> {
        fn transaction(&mut self, ops: &mut [Operation<'_, u8>]) -> Result<(), S::Error> {
            self.inner.transaction(ops)?;
            if let (true, Some(Operation::Transfer(read, _))) =
                (self.corrupt.get(), ops.first_mut())
            {
                read[4] ^= 1;
            }
            Ok(())
        }
    }

    #[test]
    fn queues_every_conversion_and_repeats_the_last_codes_when_a_read_fails() {
        let bench = Stimulus::new(StimulusParams::QEMU_BOARD);
        let chip = RefCell::new(Emu::new(bench, EMULATED_ADC));
        let corrupt = Cell::new(false);
        let (spi, drdy) = handles(&chip);
        let mut adc = Ads131m04::new(
            Flaky {
                inner: spi,
                corrupt: &corrupt,
            },
            drdy,
        );
        let config = Config {
            word_length: WordLength::Bits24,
            osr: Osr::Osr4096,
            gains: [Pga::X1; CHANNELS],
            input_crc: true,
        };
        adc.init(&config).unwrap();
        let mut queue = SampleQueue::new();
        let overruns = Overruns::new();
        let (producer, mut consumer) = queue.split();
        let mut sampler = Sampler::new(adc, Acquirer::new(producer, &overruns));
        let mut sample = |corrupted: bool| {
            corrupt.set(corrupted);
            chip.borrow_mut().convert();
            sampler.on_conversion();
            (consumer.dequeue().unwrap(), chip.borrow().codes())
        };
        let (good, codes) = sample(false);
        assert_eq!((good.index, good.codes, good.read_error), (0, codes, false));
        let (bad, _) = sample(true);
        assert_eq!((bad.index, bad.codes, bad.read_error), (1, codes, true));
        let (next, codes) = sample(false);
        assert_eq!((next.index, next.codes, next.read_error), (2, codes, false));
        assert_eq!(overruns.take(), 0);
    }
}
