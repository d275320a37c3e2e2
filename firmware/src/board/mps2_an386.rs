//! QEMU `mps2-an386` (Cortex-M4F), shared by the QEMU binaries: the CMSDK APB UART0 that carries
//! the frames, the SysTick sample clock, the emulated ADC's parameters, the device configuration,
//! exit and panic reporting over semihosting.
//!
//! QEMU 7.2 facts this relies on: BAUDDIV must be ≥ 16 or the UART stays silent; DATA must be read
//! once right after enabling RX or host input arrives about a second late; SysTick runs on the
//! 25 MHz core clock, so under `-icount shift=0` (1 ns per instruction) one tick is 40 instructions.

use core::ptr::{read_volatile, write_volatile};

use cortex_m_semihosting::{debug, hprintln};
use sim::ads131m04::AdcParams;

use crate::ads131m04::{Osr, Pga};
use crate::device::DeviceConfig;
use crate::offset::{DriftSettings, NullTiming};
use crate::params;

/// Core clock of the machine (QEMU's `mps2-an386` SYSCLK).
pub const SYSCLK_HZ: u32 = 25_000_000;
/// Instructions per SysTick tick under `-icount shift=0` (1 GHz virtual instruction clock).
pub const INSTRUCTIONS_PER_TICK: u32 = 1_000_000_000 / SYSCLK_HZ;

/// CMSDK APB UART0.
pub struct Uart0;

const UART0_BASE: usize = 0x4000_4000;
const DATA: usize = UART0_BASE;
const STATE: usize = UART0_BASE + 0x04;
const CTRL: usize = UART0_BASE + 0x08;
const BAUDDIV: usize = UART0_BASE + 0x10;
const STATE_TX_FULL: u32 = 1 << 0;
const STATE_RX_FULL: u32 = 1 << 1;
const CTRL_TX_EN: u32 = 1 << 0;
const CTRL_RX_EN: u32 = 1 << 1;

impl Uart0 {
    /// Enable TX and RX. The only instance: the registers are memory-mapped and owned by it.
    pub fn init() -> Self {
        // SAFETY: fixed MMIO addresses of UART0 on this machine; nothing else touches them.
        unsafe {
            write_volatile(BAUDDIV as *mut u32, 16);
            write_volatile(CTRL as *mut u32, CTRL_TX_EN | CTRL_RX_EN);
            let _ = read_volatile(DATA as *const u32);
        }
        Uart0
    }

    /// Put one byte in the transmitter if it has room.
    #[inline]
    pub fn try_write(&mut self, byte: u8) -> bool {
        // SAFETY: UART0 MMIO, owned by `self`.
        unsafe {
            if read_volatile(STATE as *const u32) & STATE_TX_FULL != 0 {
                return false;
            }
            write_volatile(DATA as *mut u32, u32::from(byte));
        }
        true
    }

    /// One received byte, if any.
    #[inline]
    pub fn try_read(&mut self) -> Option<u8> {
        // SAFETY: UART0 MMIO, owned by `self`.
        unsafe {
            if read_volatile(STATE as *const u32) & STATE_RX_FULL != 0 {
                Some(read_volatile(DATA as *const u32) as u8)
            } else {
                None
            }
        }
    }

    /// Up to `buf.len()` received bytes into `buf`; returns how many.
    pub fn read_available(&mut self, buf: &mut [u8]) -> usize {
        let mut n = 0;
        while n < buf.len() {
            match self.try_read() {
                Some(b) => {
                    buf[n] = b;
                    n += 1;
                }
                None => break,
            }
        }
        n
    }
}

/// Start SysTick on the core clock with an interrupt every `period_ticks` ticks.
pub fn start_sample_clock(syst: &mut cortex_m::peripheral::SYST, period_ticks: u32) {
    use cortex_m::peripheral::syst::SystClkSource;
    syst.disable_counter();
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(period_ticks - 1);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
}

/// SysTick ticks per sample at `rate_hz`.
pub const fn ticks_per_sample(rate_hz: u32) -> u32 {
    SYSCLK_HZ / rate_hz
}

/// The emulated ADS131M04's reference and clock: those of the real board's chip.
pub const ADC_PARAMS: AdcParams = params::EMULATED_ADC;

/// The device configuration of the QEMU board. The "sensor" here is the sim crate's stimulus
/// bench: volts at the ADC inputs are the signal, so the amplifier gain and calibration are unity
/// and loads read as ADC-input volts. Clock and reference are the emulated chip's, [`ADC_PARAMS`].
pub fn device_config() -> DeviceConfig {
    DeviceConfig {
        chip_serial: 0,
        clkin_hz: ADC_PARAMS.clkin_hz,
        vref_mv: params::ADC_VREF_MV,
        pga: [Pga::X1; 4],
        amp_gain: [1.0; 3],
        excitation_v: 1.0,
        calibration: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        osr: Osr::Osr4096, // 1000 samples/s at 8.192 MHz
        batch: protocol::MAX_BATCH as u8,
        filter: protocol::FilterConfig::NONE,
        // 20 samples per measurement, 14 measurements: the power-up null takes 0.28 s, inside the
        // stimulus's rest period (2000 samples).
        null_timing: NullTiming {
            settle: 4,
            average: 16,
        },
        drift: DriftSettings {
            window: 2000,
            rate: 1.0e-4,
            limit: 20_000,
        },
        dac_initial: [sim::ads131m04::stimulus::TRIM_MID_CODE; 3],
        dac_vmid_code: sim::ads131m04::stimulus::TRIM_MID_CODE,
        null_at_power_up: true,
    }
}

/// End the QEMU run with a success or failure exit code (semihosting SYS_EXIT). Without
/// semihosting the call returns and the core sleeps.
pub fn exit(success: bool) -> ! {
    debug::exit(if success {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    loop {
        cortex_m::asm::wfi();
    }
}

/// The panic handler's body: the message over semihosting, then a failed exit, so a test run
/// ends at once with the reason instead of waiting for its timeout.
pub fn on_panic(info: &core::panic::PanicInfo) -> ! {
    hprintln!("panic: {}", info);
    exit(false)
}
