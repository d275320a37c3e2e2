//! Firmware for the NUCLEO-F411RE (STM32F411RE, Cortex-M4F, run at 96 MHz). The ADS131M04 on SPI1
//! signals each conversion on DRDY (EXTI, falling edge); the interrupt reads it through the driver
//! and queues the sample. The main loop runs the device core and writes frames to USART2, the
//! ST-LINK virtual COM port. The MCP4728 trim DAC sits on I2C1. Pins and rates:
//! hardware/board.toml (checked against the code at compile time, see src/board/nucleo_f411re.rs).
//! defmt logs over RTT (`cargo run --release --bin nucleo-f411re`).
//!
//! The independent watchdog (IWDG, timeout in src/board/nucleo_f411re.rs) starts before the ADC
//! and DAC are set up and is fed once per main-loop pass, only when the pass made progress: it
//! ran to its end and, if samples were waiting, handed at least one to the device core. A hung
//! bus, interrupt or loop therefore resets the board. After a watchdog reset the firmware says so
//! over defmt (RCC_CSR.IWDGRSTF); the protocol has no field for a reset cause, so the host sees
//! it only as a new power-up (a fresh info frame, sequence numbers from 0).
#![cfg_attr(target_os = "none", no_std, no_main)]
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

firmware::nucleo_f411re_binary!();

#[cfg(target_os = "none")]
mod target {
    use core::cell::RefCell;
    use cortex_m_rt::entry;
    use critical_section::Mutex;
    use embedded_hal::spi::MODE_1;
    use embedded_hal_bus::spi::ExclusiveDevice;
    use embedded_hal_nb::serial::{Read, Write};
    use firmware::ads131m04::{Ads131m04, Config, Osr};
    use firmware::board::nucleo_f411re as board;
    use firmware::device::{BoardControl, Device, DeviceConfig, HardwareError};
    use firmware::mcp4728::{trim_writes, Mcp4728};
    use firmware::params;
    use firmware::stream::{Acquirer, Drain, Overruns, SampleQueue, Sampler};
    use stm32f4xx_hal::gpio::{Edge, Input, Output, PinState, PB6, PC7};
    use stm32f4xx_hal::i2c::{DutyCycle, I2c, Mode as I2cMode};
    use stm32f4xx_hal::pac::{self, interrupt, I2C1, SPI1, USART2};
    use stm32f4xx_hal::prelude::*;
    use stm32f4xx_hal::rcc::Config as RccConfig;
    use stm32f4xx_hal::serial::config::Config as SerialConfig;
    use stm32f4xx_hal::serial::{Rx, Tx};
    use stm32f4xx_hal::spi::Spi;

    type AdcSpi = ExclusiveDevice<Spi<SPI1>, PB6<Output>, embedded_hal_bus::spi::NoDelay>;
    type Adc = Ads131m04<AdcSpi, PC7<Input>>;
    type AdcSampler = Sampler<'static, AdcSpi, PC7<Input>>;

    static SAMPLER: Mutex<RefCell<Option<AdcSampler>>> = Mutex::new(RefCell::new(None));
    static mut QUEUE: SampleQueue = SampleQueue::new();
    static OVERRUNS: Overruns = Overruns::new();

    /// DRDY fell: a conversion is ready. Read it (CRC checked) and queue it; never wait.
    #[interrupt]
    fn EXTI9_5() {
        critical_section::with(|cs| {
            let mut slot = SAMPLER.borrow_ref_mut(cs);
            let Some(sampler) = slot.as_mut() else {
                return;
            };
            sampler.adc_mut().drdy_mut().clear_interrupt_pending_bit();
            sampler.on_conversion();
        });
    }

    struct NucleoBoard {
        dac: Mcp4728<I2c<I2C1>>,
    }

    impl BoardControl for NucleoBoard {
        fn set_trim(&mut self, codes: [u16; 3]) -> Result<(), HardwareError> {
            self.dac
                .multi_write(&trim_writes(codes))
                .map_err(|_| HardwareError::Dac)
        }

        fn set_osr(&mut self, osr: Osr) -> Result<(), HardwareError> {
            critical_section::with(|cs| {
                let mut slot = SAMPLER.borrow_ref_mut(cs);
                let Some(sampler) = slot.as_mut() else {
                    return Err(HardwareError::Adc);
                };
                sampler
                    .adc_mut()
                    .set_osr(osr)
                    .map_err(|_| HardwareError::Adc)
            })
        }
    }

    /// Whether the last reset came from the independent watchdog; clears the reset flags so the
    /// next reset reports its own cause.
    fn take_watchdog_reset(rcc: &pac::RCC) -> bool {
        // The PAC names RCC_CSR bit 29 (IWDGRSTF in RM0383) `wdgrstf`.
        let by_watchdog = rcc.csr().read().wdgrstf().bit_is_set();
        rcc.csr().modify(|_, w| w.rmvf().set_bit());
        by_watchdog
    }

    /// Start the IWDG with the board's prescaler and reload; it cannot be stopped again. It
    /// halts while a debugger halts the core.
    fn start_watchdog(iwdg: &pac::IWDG, dbgmcu: &pac::DBGMCU) {
        const KR_ACCESS: u16 = 0x5555;
        const KR_START: u16 = 0xCCCC;
        dbgmcu.apb1_fz().modify(|_, w| w.dbg_iwdg_stop().set_bit());
        iwdg.kr().write(|w| unsafe { w.key().bits(KR_START) });
        iwdg.kr().write(|w| unsafe { w.key().bits(KR_ACCESS) });
        iwdg.pr()
            .write(|w| unsafe { w.pr().bits(board::WATCHDOG.prescaler) });
        iwdg.rlr().write(|w| w.rl().set(board::WATCHDOG.reload));
        // The new values reach the LSI domain a few LSI cycles later.
        while iwdg.sr().read().bits() != 0 {}
        feed_watchdog(iwdg);
    }

    fn feed_watchdog(iwdg: &pac::IWDG) {
        const KR_RELOAD: u16 = 0xAAAA;
        iwdg.kr().write(|w| unsafe { w.key().bits(KR_RELOAD) });
    }

    /// The driver on SPI1, initialised for `config`; logs the ID or the failure.
    fn adc(spi: AdcSpi, drdy: PC7<Input>, config: &DeviceConfig) -> Adc {
        let mut adc = Ads131m04::new(spi, drdy);
        let adc_config = Config {
            word_length: board::word_length(),
            osr: config.osr,
            gains: config.pga,
            input_crc: params::ADC_INPUT_CRC,
        };
        match adc.init(&adc_config) {
            Ok(id) => defmt::info!("ADS131M04 ID {=u16:#06x}", id),
            Err(e) => defmt::error!("ADS131M04 init failed: {}", defmt::Debug2Format(&e)),
        }
        adc
    }

    /// Hand the ADC and the queue's producing end to the DRDY interrupt (still masked); returns
    /// the main loop's end.
    fn start_acquisition(adc: Adc) -> Drain<'static> {
        // SAFETY: the queue is split once, before the DRDY interrupt is unmasked.
        let (producer, consumer) = unsafe { (*core::ptr::addr_of_mut!(QUEUE)).split() };
        critical_section::with(|cs| {
            let sampler = Sampler::new(adc, Acquirer::new(producer, &OVERRUNS));
            SAMPLER.borrow_ref_mut(cs).replace(sampler);
        });
        consumer
    }

    #[entry]
    fn main() -> ! {
        let () = board::PIN_CHECKS;
        let mut dp = pac::Peripherals::take().unwrap();
        if take_watchdog_reset(&dp.RCC) {
            defmt::warn!("reset by the independent watchdog: the main loop had stopped");
        }
        start_watchdog(&dp.IWDG, &dp.DBGMCU);
        let mut rcc = dp.RCC.freeze(
            RccConfig::hse(board::HSE_HZ.Hz())
                .bypass_hse_oscillator()
                .sysclk(board::SYSCLK_HZ.Hz()),
        );
        let gpioa = dp.GPIOA.split(&mut rcc);
        let gpiob = dp.GPIOB.split(&mut rcc);
        let gpioc = dp.GPIOC.split(&mut rcc);
        // ADC SYNC/RESET held high (the driver resets with the RESET command); DAC LDAC held
        // low so its outputs follow each write.
        let _sync_reset = gpioa.pa9.into_push_pull_output_in_state(PinState::High);
        let _ldac = gpiob.pb10.into_push_pull_output_in_state(PinState::Low);
        let mut syscfg = dp.SYSCFG.constrain(&mut rcc);
        let serial_config = SerialConfig::default().baudrate(params::UART_BAUD.bps());
        let serial = dp
            .USART2
            .serial::<u8>((gpioa.pa2, gpioa.pa3), serial_config, &mut rcc);
        let (tx, rx) = serial.unwrap().split();
        let pins = (Some(gpioa.pa5), Some(gpioa.pa6), Some(gpioa.pa7));
        let spi = dp.SPI1.spi(pins, MODE_1, params::SPI_HZ.Hz(), &mut rcc);
        let cs = gpiob.pb6.into_push_pull_output_in_state(PinState::High);
        let mut drdy = gpioc.pc7.into_pull_up_input();
        drdy.make_interrupt_source(&mut syscfg);
        drdy.trigger_on_edge(&mut dp.EXTI, Edge::Falling);
        drdy.enable_interrupt(&mut dp.EXTI);
        let i2c_mode = I2cMode::fast(params::I2C_HZ.Hz(), DutyCycle::Ratio2to1);
        let i2c = I2c::new(dp.I2C1, (gpiob.pb8, gpiob.pb9), i2c_mode, &mut rcc);

        let config = board::device_config();
        let spi = ExclusiveDevice::new_no_delay(spi, cs).unwrap();
        let consumer = start_acquisition(adc(spi, drdy, &config));
        let mut fe = NucleoBoard {
            dac: Mcp4728::new(i2c, params::DAC_ADDRESS),
        };
        let mut dev = Device::new(config);
        if dev.power_up(&mut fe).is_err() {
            defmt::error!("MCP4728 did not acknowledge the power-up write");
        }
        // SAFETY: the handler and everything it touches are initialised above.
        unsafe { cortex_m::peripheral::NVIC::unmask(pac::Interrupt::EXTI9_5) };
        defmt::info!("streaming core up at {=u32} samples/s", dev.rate_hz());
        run(&mut dev, &mut fe, consumer, (tx, rx), &dp.IWDG)
    }

    /// The main loop: samples to the device core, requests from USART2, frames back out; the
    /// watchdog fed once per pass that made progress. No WFI: USART2 has a one-byte receive
    /// register and no receive interrupt is used, so the loop must keep polling or a burst of
    /// request bytes would overrun it.
    fn run(
        dev: &mut Device,
        fe: &mut NucleoBoard,
        mut consumer: Drain<'static>,
        (mut tx, mut rx): (Tx<USART2>, Rx<USART2>),
        iwdg: &pac::IWDG,
    ) -> ! {
        loop {
            let waiting = !consumer.is_empty();
            let mut handled = 0u32;
            while let Some(raw) = consumer.dequeue() {
                dev.on_sample(&raw, fe);
                handled += 1;
            }
            dev.note_overruns(OVERRUNS.take());
            let mut buf = [0u8; 32];
            let mut n = 0;
            while n < buf.len() {
                match rx.read() {
                    Ok(b) => {
                        buf[n] = b;
                        n += 1;
                    }
                    Err(nb::Error::WouldBlock) => break,
                    // Overrun or framing error: the accumulator resynchronises at the next 0x00.
                    Err(nb::Error::Other(_)) => break,
                }
            }
            if n > 0 {
                dev.on_rx(&buf[..n]);
            }
            dev.poll(fe);
            dev.tx().drain(|b| tx.write(b).is_ok());
            if !waiting || handled > 0 {
                feed_watchdog(iwdg);
            }
        }
    }
}
