//! Firmware for QEMU `mps2-an386` (Cortex-M4F). UART0 carries the protocol frames; the ADC is the
//! sim crate's register-level ADS131M04 emulation behind the same `SpiDevice` + DRDY the real
//! driver uses, converting the deterministic stimulus (`sim::ads131m04::stimulus`) that host tests
//! recompute; the trim DAC is the emulated MCP4728 driven by the real MCP4728 driver. SysTick paces
//! the conversions: its interrupt converts, reads the ADC through the driver and queues the sample;
//! the main loop does everything else.
//!
//! Run: `qemu-system-arm -machine mps2-an386 -nographic -kernel <elf> -serial pty` (see
//! scripts/test-firmware.sh); the device waits for a Start request before streaming.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!(
        "this is a thumbv7em-none-eabihf binary for QEMU mps2-an386: build it from firmware/"
    );
    std::process::exit(2);
}

#[cfg(target_os = "none")]
#[path = "../../boards/mps2_an386.rs"]
mod board;

#[cfg(target_os = "none")]
mod target {
    use super::board::{self, Uart0};
    use core::cell::RefCell;
    use cortex_m::peripheral::SYST;
    use cortex_m_rt::{entry, exception};
    use critical_section::Mutex;
    use firmware::ads131m04::{Ads131m04, Config, Osr, WordLength};
    use firmware::device::{Device, Frontend, HardwareError};
    use firmware::mcp4728::{trim_writes, Mcp4728, DEFAULT_ADDRESS};
    use firmware::stream::{Acquirer, Overruns, RawSample, SampleQueue};
    use sim::ads131m04::stimulus::{Stimulus, StimulusParams};
    use sim::ads131m04::trim_dac::TrimDac;
    use sim::ads131m04::{handles, Ads131m04 as Emu, DrdyHandle, SpiHandle};
    use {defmt_rtt as _, panic_probe as _};

    type Chip = RefCell<Emu<Stimulus>>;
    type Adc = Ads131m04<SpiHandle<'static, Stimulus>, DrdyHandle<'static, Stimulus>>;

    /// What the sample-clock interrupt owns.
    struct Acquisition {
        chip: &'static Chip,
        adc: Adc,
        acq: Acquirer<'static>,
        index: u32,
        last: [i32; 4],
    }

    /// The emulated chip is shared between the interrupt and the main loop through `&RefCell`,
    /// which is not `Send`. Single core, and every access happens inside a critical section, so
    /// moving it into the interrupt's mutex is sound.
    struct Shared(Acquisition);
    // SAFETY: see above: one core, accessed only under `critical_section::with`.
    unsafe impl Send for Shared {}

    static ACQUISITION: Mutex<RefCell<Option<Shared>>> = Mutex::new(RefCell::new(None));
    static mut QUEUE: SampleQueue = SampleQueue::new();
    static OVERRUNS: Overruns = Overruns::new();

    #[exception]
    fn SysTick() {
        critical_section::with(|cs| {
            let mut slot = ACQUISITION.borrow_ref_mut(cs);
            let Some(Shared(a)) = slot.as_mut() else {
                return;
            };
            a.chip.borrow_mut().convert();
            let (codes, read_error) = match a.adc.read() {
                Ok(conv) => (conv.codes, false),
                Err(_) => (a.last, true),
            };
            a.last = codes;
            a.acq.push(RawSample {
                index: a.index,
                codes,
                read_error,
            });
            a.index = a.index.wrapping_add(1);
        });
    }

    /// The main loop's hardware: trim DAC on the emulated I2C, ADC rate and the SysTick period.
    struct QemuFrontend {
        dac: Mcp4728<TrimDac<'static, Stimulus>>,
        syst: SYST,
        clkin_hz: u32,
    }

    /// The DAC handle borrows the chip, so its writes run inside critical sections.
    impl Frontend for QemuFrontend {
        fn set_trim(&mut self, codes: [u16; 3]) -> Result<(), HardwareError> {
            critical_section::with(|_| self.dac.multi_write(&trim_writes(codes)))
                .map_err(|_| HardwareError::Dac)
        }

        fn set_osr(&mut self, osr: Osr) -> Result<(), HardwareError> {
            critical_section::with(|cs| {
                let mut slot = ACQUISITION.borrow_ref_mut(cs);
                let Some(Shared(a)) = slot.as_mut() else {
                    return Err(HardwareError::Adc);
                };
                a.adc.set_osr(osr).map_err(|_| HardwareError::Adc)
            })?;
            board::start_sample_clock(
                &mut self.syst,
                board::ticks_per_sample(osr.data_rate_hz(self.clkin_hz)),
            );
            Ok(())
        }
    }

    #[entry]
    fn main() -> ! {
        let cp = cortex_m::Peripherals::take().unwrap();
        let mut uart = Uart0::init();
        let chip: &'static Chip =
            cortex_m::singleton!(: Chip = RefCell::new(Emu::new(Stimulus::new(StimulusParams::QEMU_BOARD)))).unwrap();
        let config = board::device_config();
        let (spi, drdy) = handles(chip);
        let mut adc = Ads131m04::new(spi, drdy);
        let adc_config = Config {
            word_length: WordLength::Bits24,
            osr: config.osr,
            gains: config.pga,
            input_crc: true,
        };
        if let Err(e) = adc.init(&adc_config) {
            defmt::error!("ADC init failed: {}", defmt::Debug2Format(&e));
        }
        // SAFETY: the queue is split once, before the interrupt that uses the producer starts.
        let (producer, mut consumer) = unsafe { (*core::ptr::addr_of_mut!(QUEUE)).split() };
        critical_section::with(|cs| {
            let acq = Acquirer::new(producer, &OVERRUNS);
            ACQUISITION.borrow_ref_mut(cs).replace(Shared(Acquisition {
                chip,
                adc,
                acq,
                index: 0,
                last: [0; 4],
            }));
        });
        let mut fe = QemuFrontend {
            dac: Mcp4728::new(TrimDac(chip), DEFAULT_ADDRESS),
            syst: cp.SYST,
            clkin_hz: config.clkin_hz,
        };
        let mut dev = Device::new(config);
        if dev.power_up(&mut fe).is_err() {
            defmt::error!("trim DAC write failed at power-up");
        }
        let period = board::ticks_per_sample(dev.rate_hz());
        board::start_sample_clock(&mut fe.syst, period);
        loop {
            let mut busy = false;
            while let Some(raw) = consumer.dequeue() {
                dev.on_sample(&raw, &mut fe);
                busy = true;
            }
            dev.note_overruns(OVERRUNS.take());
            let mut rx = [0u8; 32];
            let mut n = 0;
            while n < rx.len() {
                match uart.try_read() {
                    Some(b) => {
                        rx[n] = b;
                        n += 1;
                    }
                    None => break,
                }
            }
            if n > 0 {
                dev.on_rx(&rx[..n]);
                busy = true;
            }
            dev.poll(&mut fe);
            dev.tx().drain(|b| uart.try_write(b));
            if !busy && dev.tx().is_empty() {
                // SysTick wakes us for the next conversion; received bytes wait in the UART
                // until then (at most one sample period).
                cortex_m::asm::wfi();
            }
        }
    }
}
