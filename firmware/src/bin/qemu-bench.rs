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
//! compiler, so they are approximate (within ~15 instructions). The total A − B is exact up to
//! the few instructions of glue around the chip's calls in B's loop (borrow, call, SPI operation
//! list): the same streaming loop, instruction for instruction, has measured 391.5 to 395.5
//! under different layouts of this file. Each run is its own never-inlined function so that
//! editing one does not move the others' code.
//! For a per-function profile of run A, run QEMU with `-d in_asm,exec,nochain` and weigh each
//! translated block's instruction count by its executions.
#![cfg_attr(target_os = "none", no_std, no_main)]
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

firmware::mps2_an386_binary!();

#[cfg(target_os = "none")]
mod target {
    use core::cell::RefCell;
    use cortex_m::peripheral::syst::SystClkSource;
    use cortex_m::peripheral::SYST;
    use cortex_m_rt::entry;
    use cortex_m_semihosting::hprintln;
    use embedded_hal::spi::SpiDevice;
    use firmware::ads131m04::{crc, Ads131m04, Config, Osr, Pga, WordLength};
    use firmware::board::mps2_an386 as board;
    use firmware::device::{BoardControl, Device, HardwareError};
    use firmware::stream::{RawSample, SampleQueue};
    use protocol::{Command, FilterConfig, Message, Request};
    use sim::ads131m04::stimulus::{Stimulus, StimulusParams};
    use sim::ads131m04::{handles, Ads131m04 as Emu};

    /// Conversions per timed run.
    const N: u32 = 4096;

    struct NoHardware;
    impl BoardControl for NoHardware {
        fn set_trim(&mut self, _codes: [u16; 3]) -> Result<(), HardwareError> {
            Ok(())
        }
        fn set_osr(&mut self, _osr: Osr) -> Result<(), HardwareError> {
            Ok(())
        }
    }

    fn chip() -> RefCell<Emu<Stimulus>> {
        let bench = Stimulus::new(StimulusParams::QEMU_BOARD);
        RefCell::new(Emu::new(bench, board::ADC_PARAMS))
    }

    const ADC_CONFIG: Config = Config {
        word_length: WordLength::Bits24,
        osr: Osr::Osr4096,
        gains: [Pga::X1; 4],
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

    /// A device core configured for `path`, tare requested.
    fn device(path: Path) -> Device {
        let mut config = board::device_config();
        config.null_at_power_up = false;
        let mut dev = Device::new(config);
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
        dev
    }

    /// Runs A, D and E: N conversions through driver, queue and device core; returns (ticks, wire
    /// bytes, frames dropped).
    #[inline(never)]
    fn streaming_run(syst: &mut SYST, path: Path) -> (u32, usize, u32) {
        let chip_a = chip();
        let (spi_a, drdy_a) = handles(&chip_a);
        let mut adc_a = Ads131m04::new(spi_a, drdy_a);
        adc_a.init(&ADC_CONFIG).unwrap();
        let mut dev = device(path);
        let mut hw = NoHardware;
        let mut queue = SampleQueue::new();
        let (mut producer, mut consumer) = queue.split();
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

    /// Run B: the emulated chip alone, converting and clocking out one NULL frame (with input CRC)
    /// through its SpiDevice.
    #[inline(never)]
    fn chip_run(syst: &mut SYST) -> u32 {
        let chip_b = chip();
        let (mut spi_b, drdy_b) = handles(&chip_b);
        let mut adc_b = Ads131m04::new(handles(&chip_b).0, drdy_b);
        adc_b.init(&ADC_CONFIG).unwrap();
        let mut null_frame = [0u8; 18];
        let c = crc::crc16(crc::SEED, &null_frame[..3]);
        null_frame[3..5].copy_from_slice(&c.to_be_bytes());
        let mut rx = [0u8; 18];
        ticks(syst, || {
            for _ in 0..N {
                chip_b.borrow_mut().convert();
                spi_b.transfer(&mut rx, &null_frame).unwrap();
            }
        })
    }

    /// Run C: B's work through the driver; adds the first channel's codes to `sum`.
    #[inline(never)]
    fn driver_run(syst: &mut SYST, sum: &mut i32) -> u32 {
        let chip_c = chip();
        let (spi_c, drdy_c) = handles(&chip_c);
        let mut adc_c = Ads131m04::new(spi_c, drdy_c);
        adc_c.init(&ADC_CONFIG).unwrap();
        ticks(syst, || {
            for _ in 0..N {
                chip_c.borrow_mut().convert();
                *sum = sum.wrapping_add(adc_c.read().unwrap().codes[0]);
            }
        })
    }

    /// Run Q: C plus the acquisition queue; adds the second channel's codes to `sum`.
    #[inline(never)]
    fn queue_run(syst: &mut SYST, sum: &mut i32) -> u32 {
        let chip_q = chip();
        let (spi_q, drdy_q) = handles(&chip_q);
        let mut adc_q = Ads131m04::new(spi_q, drdy_q);
        adc_q.init(&ADC_CONFIG).unwrap();
        let mut queue = SampleQueue::new();
        let (mut producer, mut consumer) = queue.split();
        ticks(syst, || {
            for index in 0..N {
                chip_q.borrow_mut().convert();
                let conv = adc_q.read().unwrap();
                let _ = producer.enqueue(RawSample {
                    index,
                    codes: conv.codes,
                    read_error: false,
                });
                while let Some(raw) = consumer.dequeue() {
                    *sum = sum.wrapping_add(raw.codes[1]);
                }
            }
        })
    }

    /// Ticks of every run.
    struct Runs {
        b: u32,
        c: u32,
        q: u32,
        a: u32,
        drift: u32,
        d: u32,
        e: u32,
    }

    fn report(runs: &Runs, bytes: usize, dropped: u32, sum: i32) {
        let per_sample = |t: u32| (t as f32) * board::INSTRUCTIONS_PER_TICK as f32 / N as f32;
        let firmware = per_sample(runs.a) - per_sample(runs.b);
        let driver = per_sample(runs.c) - per_sample(runs.b);
        hprintln!(
            "conversions per run: {} ({} wire bytes, {} frames dropped, checksum {})",
            N,
            bytes,
            dropped,
            sum
        );
        hprintln!(
            "emulated chip alone (excluded): {} instructions/sample",
            per_sample(runs.b)
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
            per_sample(runs.q) - per_sample(runs.c),
            per_sample(runs.e) - per_sample(runs.q),
            per_sample(runs.d) - per_sample(runs.e),
            per_sample(runs.a) - per_sample(runs.d)
        );
        hprintln!(
            "with drift tracking on (off by default): {} instructions/sample",
            per_sample(runs.drift) - per_sample(runs.b)
        );
        hprintln!(
            "firmware instructions/sample: {} (goal 400, ratio {})",
            firmware,
            firmware / 400.0
        );
    }

    #[entry]
    fn main() -> ! {
        let mut cp = cortex_m::Peripherals::take().unwrap();
        let syst = &mut cp.SYST;
        let mut sum = 0i32;
        let b = chip_run(syst);
        let c = driver_run(syst, &mut sum);
        let q = queue_run(syst, &mut sum);
        // A: the whole streaming path, with the default offset cut (tare) and with drift tracking;
        // E and D: the device core without framing, without and with the filters.
        let full = Path {
            drift: false,
            biquads: true,
            streaming: true,
        };
        let (a, bytes, dropped) = streaming_run(syst, full);
        let with_drift = Path {
            drift: true,
            ..full
        };
        let no_framing = Path {
            streaming: false,
            ..full
        };
        let no_filters = Path {
            biquads: false,
            ..no_framing
        };
        let runs = Runs {
            b,
            c,
            q,
            a,
            drift: streaming_run(syst, with_drift).0,
            d: streaming_run(syst, no_framing).0,
            e: streaming_run(syst, no_filters).0,
        };
        report(&runs, bytes, dropped, sum);
        board::exit(true)
    }
}
