//! Firmware for QEMU `mps2-an386` (Cortex-M4F). UART0 carries the protocol frames; the ADC is the
//! sim crate's register-level ADS131M04 emulation behind the same `SpiDevice` + DRDY the real
//! driver uses; the trim DAC is the emulated MCP4728 driven by the real MCP4728 driver. SysTick
//! paces the conversions: its interrupt converts, reads the ADC through the driver and queues the
//! sample; the main loop does everything else.
//!
//! What the emulated ADC converts:
//! - by default the deterministic triangle stimulus (`sim::ads131m04::stimulus`) that host tests
//!   recompute;
//! - with a stimulus file named on the semihosting command line, the recorded volts of that file
//!   (`sim::ads131m04::stimulus_file`, e.g. a compression test from `tactile simulate
//!   --adc-stimulus`), read from the host through ARM semihosting in 2 KiB blocks. The board then
//!   converts at the file's rate and reports the file's amplifier gains and excitation in its info
//!   frame; the playback starts when the host starts the stream (until then the inputs hold the
//!   first record, the sensor at rest, which the power-up auto-null sees) and the sample clock
//!   stops after the last record (the test is over).
//!
//! Run: `qemu-system-arm -machine mps2-an386 -nographic -kernel <elf> -serial pty` (see
//! scripts/test-firmware.sh), plus `-semihosting-config enable=on,target=native,arg=<elf>,arg=<file>`
//! for a stimulus file (scripts/demo-chain.sh); the device waits for a Start request before
//! streaming. Without `-semihosting-config` the semihosting probe at start-up traps (a BKPT with
//! no debugger is a HardFault on M-profile), the handler below makes the call return -1, and the
//! board falls back to the triangles.
#![cfg_attr(target_os = "none", no_std, no_main)]
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

firmware::mps2_an386_binary!();

#[cfg(target_os = "none")]
mod semihost {
    //! The host side of the stimulus file: the semihosting calls, and the HardFault handler that
    //! turns a semihosting call into a failed one (-1) when QEMU runs without semihosting.
    use cortex_m_semihosting::syscall;
    use sim::ads131m04::stimulus_file::RecordSource;

    // The handler: if the faulting instruction is the semihosting BKPT (0xBEAB, escalated to
    // HardFault because no debugger is attached), step over it with r0 = -1; any other fault goes
    // to cortex-m-rt's default handler. Written in assembly because it must return to the
    // stacked frame, which a Rust `HardFault` handler (`-> !`) cannot.
    core::arch::global_asm!(
        ".section .text.HardFault,\"ax\",%progbits",
        ".global HardFault",
        ".type HardFault,%function",
        ".thumb_func",
        "HardFault:",
        "  tst lr, #4",
        "  ite eq",
        "  mrseq r0, msp",
        "  mrsne r0, psp",
        "  ldr r1, [r0, #24]", // stacked PC
        "  ldrh r2, [r1]",
        "  movw r3, #0xbeab", // bkpt 0xab
        "  cmp r2, r3",
        "  bne 1f",
        "  adds r1, r1, #2",
        "  str r1, [r0, #24]",
        "  mvn r1, #0",
        "  str r1, [r0]",     // stacked r0: the call's result
        "  movw r2, #0xed2c", // HFSR, write one to clear
        "  movt r2, #0xe000",
        "  ldr r3, [r2]",
        "  str r3, [r2]",
        "  bx lr",
        "1:",
        "  b HardFault_",
    );

    /// The semihosting command line (`arg=` values of `-semihosting-config`, space-separated), or
    /// `None` without semihosting.
    pub fn command_line(buf: &mut [u8]) -> Option<&[u8]> {
        let mut block = [buf.as_mut_ptr() as usize, buf.len()];
        // SAFETY: SYS_GET_CMDLINE writes at most block[1] bytes into buf and the length into
        // block[1]; both outlive the call.
        let r = unsafe {
            cortex_m_semihosting::syscall1(
                cortex_m_semihosting::nr::GET_CMDLINE,
                block.as_mut_ptr() as usize,
            )
        };
        (r == 0 && block[1] <= buf.len()).then(|| &buf[..block[1]])
    }

    /// A host file opened read-only in binary mode.
    pub struct HostFile {
        handle: usize,
    }

    impl HostFile {
        pub fn open(path: &[u8]) -> Option<Self> {
            let mut name = [0u8; 128];
            if path.len() >= name.len() {
                return None;
            }
            name[..path.len()].copy_from_slice(path);
            // SAFETY: `name` is NUL-terminated and outlives the call; mode 1 = "rb".
            let handle = unsafe { syscall!(OPEN, name.as_ptr(), 1, path.len()) };
            (handle as isize >= 0).then_some(Self { handle })
        }
    }

    impl RecordSource for HostFile {
        fn read(&mut self, buf: &mut [u8]) -> usize {
            // SAFETY: SYS_READ writes at most buf.len() bytes into buf; returns the bytes NOT read.
            let left = unsafe { syscall!(READ, self.handle, buf.as_mut_ptr(), buf.len()) };
            buf.len().saturating_sub(left)
        }
    }
}

#[cfg(target_os = "none")]
mod target {
    use core::cell::RefCell;
    use cortex_m::peripheral::SYST;
    use cortex_m_rt::{entry, exception};
    use critical_section::Mutex;
    use firmware::ads131m04::{Ads131m04, Config, Osr, WordLength};
    use firmware::board::mps2_an386::{self as board, Uart0};
    use firmware::device::{BoardControl, Device, DeviceConfig, HardwareError};
    use firmware::mcp4728::{trim_writes, Mcp4728, DEFAULT_ADDRESS};
    use firmware::stream::{Acquirer, Drain, Overruns, SampleQueue, Sampler};
    use sim::ads131m04::stimulus::{Stimulus, StimulusParams};
    use sim::ads131m04::stimulus_file::{FileStimulus, Header, RecordSource, HEADER_BYTES};
    use sim::ads131m04::trim_dac::{TrimDac, TrimInput};
    use sim::ads131m04::{handles, Ads131m04 as Emu, AnalogInput, DrdyHandle, SpiHandle};

    use super::semihost::{self, HostFile};

    /// What the emulated ADC converts: the triangles, or a stimulus file from the host.
    // One instance, in a static singleton, and no heap to box the file's 2 KiB block into.
    #[allow(clippy::large_enum_variant)]
    enum BoardInput {
        Triangle(Stimulus),
        File(FileStimulus<HostFile>),
    }

    impl AnalogInput for BoardInput {
        fn sample_v(&mut self, index: u64) -> [f32; 4] {
            match self {
                Self::Triangle(s) => s.sample_v(index),
                Self::File(f) => f.sample_v(index),
            }
        }
    }

    impl TrimInput for BoardInput {
        fn set_trim(&mut self, channel: usize, code: u16) {
            match self {
                Self::Triangle(s) => s.set_trim(channel, code),
                Self::File(f) => f.set_trim(channel, code),
            }
        }
    }

    impl BoardInput {
        /// The stimulus file named by the second word of the semihosting command line (the first
        /// is the program), or the triangles.
        fn from_host() -> Self {
            let bench = Stimulus::new(StimulusParams::QEMU_BOARD);
            let mut line = [0u8; 160];
            let path = semihost::command_line(&mut line)
                .and_then(|l| l.split(|b| *b == b' ').filter(|w| !w.is_empty()).nth(1));
            let Some(path) = path else {
                return Self::Triangle(bench);
            };
            let Some(mut file) = HostFile::open(path) else {
                defmt::error!("stimulus file cannot be opened");
                return Self::Triangle(bench);
            };
            match read_header(&mut file) {
                Some(header) => match FileStimulus::new(bench.clone(), header, file) {
                    Some(f) => Self::File(f),
                    None => Self::Triangle(bench),
                },
                None => Self::Triangle(bench),
            }
        }

        fn file(&mut self) -> Option<&mut FileStimulus<HostFile>> {
            match self {
                Self::File(f) => Some(f),
                Self::Triangle(_) => None,
            }
        }
    }

    /// The stimulus file's header, leaving the file at its first record: records start right
    /// after this version's header, and a longer header (a later version's) is skipped.
    fn read_header(file: &mut HostFile) -> Option<Header> {
        let mut head = [0u8; HEADER_BYTES];
        let parsed = (file.read(&mut head) == HEADER_BYTES)
            .then(|| Header::parse(&head).ok())
            .flatten();
        let Some((header, length)) = parsed else {
            defmt::error!("stimulus file: bad header");
            return None;
        };
        let mut skip = [0u8; 16];
        let mut left = length - HEADER_BYTES;
        while left > 0 {
            let n = file.read(&mut skip[..left.min(16)]);
            if n == 0 {
                return None;
            }
            left -= n;
        }
        Some(header)
    }

    type Chip = RefCell<Emu<BoardInput>>;
    type Adc = Ads131m04<SpiHandle<'static, BoardInput>, DrdyHandle<'static, BoardInput>>;

    /// What the sample-clock interrupt owns: the emulated chip it converts and the sampler that
    /// reads it.
    struct Acquisition {
        chip: &'static Chip,
        sampler: Sampler<'static, SpiHandle<'static, BoardInput>, DrdyHandle<'static, BoardInput>>,
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
            // After a stimulus file's last record the test is over: no more conversions.
            if a.chip
                .borrow_mut()
                .input_mut()
                .file()
                .is_some_and(|f| f.finished())
            {
                return;
            }
            a.chip.borrow_mut().convert();
            a.sampler.on_conversion();
        });
    }

    /// The main loop's hardware: trim DAC on the emulated I2C, ADC rate and the SysTick period.
    struct QemuBoard {
        dac: Mcp4728<TrimDac<'static, BoardInput>>,
        syst: SYST,
        clkin_hz: u32,
    }

    /// The DAC handle borrows the chip, so its writes run inside critical sections.
    impl BoardControl for QemuBoard {
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
                a.sampler
                    .adc_mut()
                    .set_osr(osr)
                    .map_err(|_| HardwareError::Adc)
            })?;
            board::start_sample_clock(
                &mut self.syst,
                board::ticks_per_sample(osr.data_rate_hz(self.clkin_hz)),
            );
            Ok(())
        }
    }

    /// Start a stimulus file's playback (the triangles run from power-up).
    fn start_playback(chip: &'static Chip) {
        critical_section::with(|_| {
            if let Some(f) = chip.borrow_mut().input_mut().file() {
                f.start();
            }
        });
    }

    /// The device configuration for `input`: a stimulus file describes the sensor, its rate, and
    /// the gains and excitation the host needs to read the volts as that sensor's.
    fn device_config(input: &BoardInput) -> DeviceConfig {
        let mut config = board::device_config();
        if let BoardInput::File(f) = input {
            let rate_hz = f.header.sample_rate_hz as u32;
            match Osr::for_rate(rate_hz, config.clkin_hz) {
                Some(osr) => config.osr = osr,
                None => defmt::error!("stimulus rate {} Hz is not an ADC rate", rate_hz),
            }
            config.amp_gain = f.header.amp_gain;
            config.excitation_v = f.header.excitation_v;
        }
        config
    }

    /// The driver on the emulated chip, initialised for `config`.
    fn adc(chip: &'static Chip, config: &DeviceConfig) -> Adc {
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
        adc
    }

    /// Hand the ADC and the queue's producing end to the sample-clock interrupt; returns the
    /// main loop's end.
    fn start_acquisition(chip: &'static Chip, adc: Adc) -> Drain<'static> {
        // SAFETY: the queue is split once, before the interrupt that uses the producer starts.
        let (producer, consumer) = unsafe { (*core::ptr::addr_of_mut!(QUEUE)).split() };
        critical_section::with(|cs| {
            let sampler = Sampler::new(adc, Acquirer::new(producer, &OVERRUNS));
            ACQUISITION
                .borrow_ref_mut(cs)
                .replace(Shared(Acquisition { chip, sampler }));
        });
        consumer
    }

    #[entry]
    fn main() -> ! {
        let cp = cortex_m::Peripherals::take().unwrap();
        let uart = Uart0::init();
        let input = BoardInput::from_host();
        let config = device_config(&input);
        let chip: &'static Chip =
            cortex_m::singleton!(: Chip = RefCell::new(Emu::new(input, board::ADC_PARAMS)))
                .unwrap();
        let consumer = start_acquisition(chip, adc(chip, &config));
        let mut fe = QemuBoard {
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
        run(chip, dev, fe, consumer, uart)
    }

    /// The main loop: samples to the device core, requests from the UART, frames back out.
    fn run(
        chip: &'static Chip,
        mut dev: Device,
        mut fe: QemuBoard,
        mut consumer: Drain<'static>,
        mut uart: Uart0,
    ) -> ! {
        let mut playing = false;
        loop {
            let mut busy = false;
            while let Some(raw) = consumer.dequeue() {
                dev.on_sample(&raw, &mut fe);
                busy = true;
            }
            dev.note_overruns(OVERRUNS.take());
            let mut rx = [0u8; 32];
            let n = uart.read_available(&mut rx);
            if n > 0 {
                dev.on_rx(&rx[..n]);
                busy = true;
            }
            dev.poll(&mut fe);
            if !playing && dev.streaming() {
                start_playback(chip);
                playing = true;
            }
            dev.tx().drain(|b| uart.try_write(b));
            if !busy && dev.tx().is_empty() {
                // SysTick wakes us for the next conversion; received bytes wait in the UART
                // until then (at most one sample period).
                cortex_m::asm::wfi();
            }
        }
    }
}
