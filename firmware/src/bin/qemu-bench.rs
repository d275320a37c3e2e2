//! Instructions per sample of the firmware's own work, under QEMU `mps2-an386` with
//! `-icount shift=0` (one instruction = 1 ns of virtual time; SysTick on the 25 MHz core clock
//! advances once per 40 instructions). Run by scripts/bench-firmware.sh.
//!
//! Three runs of N conversions on identical emulated chips, timed with SysTick as a free-running
//! down-counter:
//!   B  the emulated chip alone: convert, and clock one 18-byte NULL frame (with input CRC) out of
//!      it through its SpiDevice (the chip's own work, excluded);
//!   C  B's work through the real driver: frame, SPI transfer, CRC-16 check, decode;
//!   A  C plus the firmware's streaming path: queue push and pop, offset cut (tare and drift
//!      tracking on), 3 channels × two Butterworth biquads, batching, protocol encoding with
//!      CRC-32C and COBS into the transmit buffer, and draining it (to a sink, not the UART).
//!   Q  C plus the queue push and pop;
//!   E  Q plus the device core with streaming off and no filter: offset cut and bookkeeping;
//!   D  E with the two biquads on: D − E is the filters' share, A − D the framing's.
//! Firmware instructions per sample = (A − B) / N; C − B is the driver's share. The other shares
//! are differences between separately compiled loops, each scheduled differently by the
//! compiler, so they are approximate (within ~15 instructions); the total A − B is exact.
//! For a per-function profile of run A, run QEMU with `-d in_asm,exec,nochain` and weigh each
//! translated block's instruction count by its executions.
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
    use super::board;
    use core::cell::RefCell;
    use cortex_m::peripheral::syst::SystClkSource;
    use cortex_m::peripheral::SYST;
    use cortex_m_rt::entry;
    use cortex_m_semihosting::{debug, hprintln};
    use embedded_hal::spi::SpiDevice;
    use firmware::ads131m04::{crc, Ads131m04, Config, Osr, WordLength};
    use firmware::device::{Device, Frontend, HardwareError};
    use firmware::stream::{RawSample, SampleQueue};
    use protocol::{Command, FilterConfig, Message, Request};
    use sim::ads131m04::stimulus::{Stimulus, StimulusParams};
    use sim::ads131m04::{handles, Ads131m04 as Emu};

    #[defmt::global_logger]
    struct NoLogger;
    unsafe impl defmt::Logger for NoLogger {
        fn acquire() {}
        unsafe fn flush() {}
        unsafe fn release() {}
        unsafe fn write(_bytes: &[u8]) {}
    }

    #[panic_handler]
    fn panic(info: &core::panic::PanicInfo) -> ! {
        hprintln!("panic: {}", info);
        debug::exit(debug::EXIT_FAILURE);
        loop {
            cortex_m::asm::wfi();
        }
    }

    /// Conversions per timed run.
    const N: u32 = 4096;

    struct NoHardware;
    impl Frontend for NoHardware {
        fn set_trim(&mut self, _codes: [u16; 3]) -> Result<(), HardwareError> {
            Ok(())
        }
        fn set_osr(&mut self, _osr: Osr) -> Result<(), HardwareError> {
            Ok(())
        }
    }

    fn chip() -> RefCell<Emu<Stimulus>> {
        RefCell::new(Emu::new(Stimulus::new(StimulusParams::QEMU_BOARD)))
    }

    const ADC_CONFIG: Config = Config {
        word_length: WordLength::Bits24,
        osr: Osr::Osr4096,
        gains: [firmware::ads131m04::Pga::X1; 4],
        input_crc: true,
    };

    /// SysTick ticks spent in `f` (counter runs down from 2^24 − 1; runs stay far below a wrap).
    fn ticks(syst: &mut SYST, f: impl FnOnce()) -> u32 {
        syst.disable_interrupt();
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(0x00FF_FFFF);
        syst.clear_current();
        syst.enable_counter();
        let start = SYST::get_current();
        f();
        let end = SYST::get_current();
        syst.disable_counter();
        start.wrapping_sub(end) & 0x00FF_FFFF
    }

    fn request(dev: &mut Device, command: Command) {
        let mut wire = [0u8; protocol::MAX_FRAME];
        let n =
            protocol::encode(&Message::Request(Request { tag: 0, command }), &mut wire).unwrap();
        dev.on_rx(&wire[..n]);
    }

    /// What a device-core run switches on.
    #[derive(Clone, Copy)]
    struct Path {
        drift: bool,
        biquads: bool,
        streaming: bool,
    }

    /// Runs A, D and E: N conversions through driver, queue and device core; returns (ticks, wire
    /// bytes, frames dropped).
    fn streaming_run(syst: &mut SYST, path: Path) -> (u32, usize, u32) {
        let chip_a = chip();
        let (spi_a, drdy_a) = handles(&chip_a);
        let mut adc_a = Ads131m04::new(spi_a, drdy_a);
        adc_a.init(&ADC_CONFIG).unwrap();
        let mut config = board::device_config();
        config.null_at_power_up = false;
        let mut dev = Device::new(config);
        let mut hw = NoHardware;
        let mut queue = SampleQueue::new();
        let (mut producer, mut consumer) = queue.split();
        request(
            &mut dev,
            Command::SetFilter(FilterConfig {
                smoother_alpha: 1.0,
                butterworth_order: if path.biquads { 4 } else { 0 },
                cutoff_hz: 50.0,
            }),
        );
        request(&mut dev, Command::Tare { samples: 32 });
        request(
            &mut dev,
            Command::SetDriftTracking {
                enabled: path.drift,
            },
        );
        if path.streaming {
            request(&mut dev, Command::Start);
        }
        let mut index = 0u32;
        let mut sent = 0usize;
        let mut run = |count: u32, dev: &mut Device, sent: &mut usize| {
            for _ in 0..count {
                chip_a.borrow_mut().convert();
                let conv = adc_a.read().unwrap();
                let _ = producer.enqueue(RawSample {
                    index,
                    codes: conv.codes,
                    read_error: false,
                });
                index = index.wrapping_add(1);
                while let Some(raw) = consumer.dequeue() {
                    dev.on_sample(&raw, &mut hw);
                }
                *sent += dev.tx().drain(|_| true);
            }
        };
        run(64, &mut dev, &mut sent); // warm-up: commands applied, tare done
        let before = sent;
        let t = ticks(syst, || run(N, &mut dev, &mut sent));
        (t, sent - before, dev.counters().frames_dropped)
    }

    #[entry]
    fn main() -> ! {
        let mut cp = cortex_m::Peripherals::take().unwrap();
        let per_tick = board::INSTRUCTIONS_PER_TICK;

        // B: the emulated chip alone.
        let chip_b = chip();
        let (mut spi_b, drdy_b) = handles(&chip_b);
        let mut adc_b = Ads131m04::new(handles(&chip_b).0, drdy_b);
        adc_b.init(&ADC_CONFIG).unwrap();
        let mut null_frame = [0u8; 18];
        let c = crc::crc16(crc::SEED, &null_frame[..3]);
        null_frame[3..5].copy_from_slice(&c.to_be_bytes());
        let mut rx = [0u8; 18];
        let t_b = ticks(&mut cp.SYST, || {
            for _ in 0..N {
                chip_b.borrow_mut().convert();
                spi_b.transfer(&mut rx, &null_frame).unwrap();
            }
        });

        // C: through the driver.
        let chip_c = chip();
        let (spi_c, drdy_c) = handles(&chip_c);
        let mut adc_c = Ads131m04::new(spi_c, drdy_c);
        adc_c.init(&ADC_CONFIG).unwrap();
        let mut sum = 0i32;
        let t_c = ticks(&mut cp.SYST, || {
            for _ in 0..N {
                chip_c.borrow_mut().convert();
                sum = sum.wrapping_add(adc_c.read().unwrap().codes[0]);
            }
        });

        // Q: the driver and the acquisition queue.
        let chip_q = chip();
        let (spi_q, drdy_q) = handles(&chip_q);
        let mut adc_q = Ads131m04::new(spi_q, drdy_q);
        adc_q.init(&ADC_CONFIG).unwrap();
        let mut queue = SampleQueue::new();
        let (mut producer, mut consumer) = queue.split();
        let t_q = ticks(&mut cp.SYST, || {
            for index in 0..N {
                chip_q.borrow_mut().convert();
                let conv = adc_q.read().unwrap();
                let _ = producer.enqueue(RawSample {
                    index,
                    codes: conv.codes,
                    read_error: false,
                });
                while let Some(raw) = consumer.dequeue() {
                    sum = sum.wrapping_add(raw.codes[1]);
                }
            }
        });

        // A: the whole streaming path, with the default offset cut (tare) and with drift tracking;
        // E and D: the device core without framing, without and with the filters.
        let full = Path {
            drift: false,
            biquads: true,
            streaming: true,
        };
        let (t_a, bytes, dropped) = streaming_run(&mut cp.SYST, full);
        let (t_drift, _, _) = streaming_run(
            &mut cp.SYST,
            Path {
                drift: true,
                ..full
            },
        );
        let (t_d, _, _) = streaming_run(
            &mut cp.SYST,
            Path {
                streaming: false,
                ..full
            },
        );
        let (t_e, _, _) = streaming_run(
            &mut cp.SYST,
            Path {
                streaming: false,
                biquads: false,
                ..full
            },
        );

        let per_sample = |t: u32| (t as f32) * per_tick as f32 / N as f32;
        let firmware = per_sample(t_a) - per_sample(t_b);
        let driver = per_sample(t_c) - per_sample(t_b);
        hprintln!(
            "conversions per run: {} ({} wire bytes, {} frames dropped, checksum {})",
            N,
            bytes,
            dropped,
            sum
        );
        hprintln!(
            "emulated chip alone (excluded): {} instructions/sample",
            per_sample(t_b)
        );
        hprintln!(
            "driver read + SPI CRC check: {} instructions/sample",
            driver
        );
        hprintln!(
            "queue, offset cut, 2 biquads x 3 ch, framing, CRC-32C, COBS: {} instructions/sample",
            firmware - driver
        );
        hprintln!(
            "  of which queue push + pop: {}; offset cut and device bookkeeping: {}; \
             2 biquads x 3 ch: {}; framing, CRC-32C, COBS: {}",
            per_sample(t_q) - per_sample(t_c),
            per_sample(t_e) - per_sample(t_q),
            per_sample(t_d) - per_sample(t_e),
            per_sample(t_a) - per_sample(t_d)
        );
        hprintln!(
            "with drift tracking on (off by default): {} instructions/sample",
            per_sample(t_drift) - per_sample(t_b)
        );
        hprintln!(
            "firmware instructions/sample: {} (goal 400, ratio {})",
            firmware,
            firmware / 400.0
        );
        debug::exit(debug::EXIT_SUCCESS);
        loop {
            cortex_m::asm::wfi();
        }
    }
}
