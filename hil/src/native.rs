//! HIL path 1: the firmware library's device core (real ADS131M04 and MCP4728 drivers, offset
//! cut, filters, framing, command handling) runs on a host thread against the emulated sensor
//! chain (`sim::chain`) behind the register-level ADC emulation, paced in real time at the ADC's
//! data rate like the DRDY interrupt; its bytes go out through the master of a pty, and the host
//! opens the slave by path.
//!
//! The thread plays both halves of the firmware: the "interrupt" converts, checks DRDY, reads the
//! ADC through the driver and pushes into the firmware's acquisition queue; the "main loop" drains
//! the queue into the device core, feeds it received bytes and drains its transmit buffer into
//! the pty. When the thread falls behind wall time it catches up conversion by conversion (the
//! sample clock never skips), so device time stays exact while wall time jitters.

use std::cell::RefCell;
use std::io;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use firmware::ads131m04::{Ads131m04 as Driver, Config, Osr, Pga, WordLength};
use firmware::device::{BoardControl, Device, DeviceConfig, HardwareError};
use firmware::mcp4728::{Mcp4728, DEFAULT_ADDRESS};
use firmware::offset::{DriftSettings, NullTiming};
use firmware::stream::{Acquirer, Overruns, RawSample, SampleQueue};
use sim::ads131m04::trim_dac::TrimDac;
use sim::ads131m04::{handles, AdcParams, Ads131m04 as Emu, DrdyHandle, SpiHandle};
use sim::chain::Chain;
use sim::load::ForceSchedule;

use crate::pty::{read_master, write_master, Pty};

/// The emulated sensor under test.
pub type SensorChain = Chain<ForceSchedule>;

/// What the emulated sensor does.
#[derive(Debug, Clone, Copy)]
pub struct NativeConfig {
    /// Peak of the standard test (N); fingertip.toml's is 60 N.
    pub peak_load_n: f64,
    /// Device time at which the rod touches, s.
    pub load_start_s: f64,
    /// Speed-up of the standard test's rod motion (the real test takes a minute).
    pub speed_factor: f64,
    /// Seed of the front end's noise; `None` runs noise-free.
    pub noise_seed: Option<u64>,
}

impl NativeConfig {
    /// The chain this configuration describes (noise as configured), from `hardware/`.
    pub fn chain(&self) -> io::Result<SensorChain> {
        let mut p = hardware::Params::load_default().map_err(io::Error::other)?;
        p.fingertip.test.peak_load_n = self.peak_load_n;
        let test = ForceSchedule::from_params(&p, self.load_start_s, self.speed_factor);
        let chain = Chain::from_params(&p, test).map_err(io::Error::other)?;
        Ok(match self.noise_seed {
            Some(seed) => chain.with_noise(seed),
            None => chain,
        })
    }
}

/// The device configuration for the chain: the front end's gains and the chip model's
/// calibration (ADC-input volts to N, N·m), as a board would hand them to the core.
pub fn device_config(chain: &SensorChain) -> DeviceConfig {
    let gains = chain.front_end.channels.map(|c| c.gain());
    let c = chip::sensitivity::calibration_matrix_after_gains(&chain.chip, gains)
        .unwrap_or([[0.0; 3]; 3]);
    DeviceConfig {
        chip_serial: 0x5EED_0001,
        clkin_hz: chain.front_end.adc.modulator_hz as u32 * 2,
        vref_mv: (chain.front_end.adc.reference_v * 1000.0).round() as u16,
        pga: [Pga::X1; 4],
        amp_gain: gains.map(|g| g as f32),
        excitation_v: chain.chip.excitation_v as f32,
        calibration: c.map(|row| row.map(|x| x as f32)),
        osr: Osr::Osr4096,
        batch: protocol::MAX_BATCH as u8,
        filter: protocol::FilterConfig::NONE,
        // 20 samples per measurement, 14 measurements: 0.28 s at 1 kSPS.
        null_timing: NullTiming {
            settle: 4,
            average: 16,
        },
        drift: DriftSettings {
            window: 2000,
            rate: 1.0e-4,
            limit: 20_000,
        },
        dac_initial: [2048; 3],
        dac_vmid_code: 2048,
        null_at_power_up: true,
    }
}

/// Counters of a finished run.
#[derive(Debug, Clone, Copy, Default)]
pub struct NativeStats {
    pub conversions: u64,
    pub frames_queued: u32,
    pub frames_dropped: u32,
    pub rx_errors: u32,
    /// Largest lag of the pacing thread behind wall time, s.
    pub max_lag_s: f64,
    /// Wall time of the run, s.
    pub wall_s: f64,
}

/// The running sensor: its pty path and the thread.
pub struct NativeSensor {
    pub path: PathBuf,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<io::Result<NativeStats>>>,
}

impl NativeSensor {
    /// Power the sensor up (the auto-null starts at once) on a new pty.
    pub fn spawn(cfg: NativeConfig) -> io::Result<Self> {
        let pty = Pty::open()?;
        let path = pty.path.clone();
        let stop = Arc::new(AtomicBool::new(false));
        let flag = stop.clone();
        let thread = std::thread::Builder::new()
            .name("hil-native-device".into())
            .spawn(move || run(cfg, pty, &flag))?;
        Ok(Self {
            path,
            stop,
            thread: Some(thread),
        })
    }

    /// Stop the device and return its counters.
    pub fn stop(mut self) -> io::Result<NativeStats> {
        self.halt()
            .unwrap_or_else(|| Err(io::Error::other("device thread already stopped")))
    }

    fn halt(&mut self) -> Option<io::Result<NativeStats>> {
        self.stop.store(true, Ordering::Relaxed);
        let t = self.thread.take()?;
        Some(
            t.join()
                .unwrap_or_else(|_| Err(io::Error::other("device thread panicked"))),
        )
    }
}

impl Drop for NativeSensor {
    fn drop(&mut self) {
        let _ = self.halt();
    }
}

type Shared = RefCell<Emu<SensorChain>>;

/// The board: DAC over the emulated I2C, OSR through the real driver.
struct Bench<'a> {
    adc: Driver<SpiHandle<'a, SensorChain>, DrdyHandle<'a, SensorChain>>,
    dac: Mcp4728<TrimDac<'a, SensorChain>>,
}

impl BoardControl for Bench<'_> {
    fn set_trim(&mut self, codes: [u16; 3]) -> Result<(), HardwareError> {
        // Channel D holds the mid-rail reference and is never written (firmware::mcp4728).
        self.dac
            .multi_write(&firmware::mcp4728::trim_writes(codes))
            .map_err(|_| HardwareError::Dac)
    }

    fn set_osr(&mut self, osr: Osr) -> Result<(), HardwareError> {
        self.adc.set_osr(osr).map_err(|_| HardwareError::Adc)
    }
}

fn run(cfg: NativeConfig, pty: Pty, stop: &AtomicBool) -> io::Result<NativeStats> {
    let chain = cfg.chain()?;
    let dev_cfg = device_config(&chain);
    // The emulated chip runs from the reference and clock the device reports (adc.toml's).
    let adc_params = AdcParams {
        vref_v: chain.front_end.adc.reference_v,
        clkin_hz: dev_cfg.clkin_hz,
    };
    let emu: Shared = RefCell::new(Emu::new(chain, adc_params));
    let mut bench = bench(&emu, &dev_cfg)?;
    let mut queue = SampleQueue::new();
    let overruns = Overruns::new();
    let (producer, mut consumer) = queue.split();
    let mut acq = Acquirer::new(producer, &overruns);
    let mut dev = Device::new(dev_cfg);
    dev.power_up(&mut bench)
        .map_err(|e| io::Error::other(format!("power-up: {e:?}")))?;

    let start = Instant::now();
    let mut rate_hz = emu.borrow().data_rate_hz();
    let mut next_s = 0.0_f64;
    let mut stats = NativeStats::default();
    let mut staging: Vec<u8> = Vec::with_capacity(8192);
    let mut rx = [0u8; 512];
    while !stop.load(Ordering::Relaxed) {
        let now_s = start.elapsed().as_secs_f64();
        stats.max_lag_s = stats.max_lag_s.max(now_s - next_s);
        // Conversions due by now (more than one when the thread fell behind), each followed by a
        // main-loop pass as on the board; at least one pass when none is due, for commands.
        loop {
            let due = next_s <= now_s;
            if due {
                acq.push(interrupt(&emu, &mut bench));
                next_s += 1.0 / f64::from(rate_hz);
            }
            while let Some(raw) = consumer.dequeue() {
                dev.on_sample(&raw, &mut bench);
            }
            dev.note_overruns(overruns.take());
            let n = read_master(&pty.master, &mut rx)?;
            if n > 0 {
                dev.on_rx(&rx[..n]);
            }
            dev.poll(&mut bench);
            follow_rate(&emu, &mut rate_hz, &mut next_s);
            dev.tx().drain(|b| {
                let room = staging.len() < staging.capacity();
                if room {
                    staging.push(b);
                }
                room
            });
            let written = write_master(&pty.master, &staging)?;
            staging.drain(..written);
            if !due || next_s > now_s {
                break;
            }
        }
        let wait = next_s - start.elapsed().as_secs_f64();
        if wait > 0.0 {
            std::thread::sleep(Duration::from_secs_f64(wait.min(0.002)));
        }
    }
    let c = dev.counters();
    stats.conversions = emu.borrow().conversions();
    stats.frames_queued = c.frames_queued;
    stats.frames_dropped = c.frames_dropped;
    stats.rx_errors = c.rx_errors;
    stats.wall_s = start.elapsed().as_secs_f64();
    drop(pty);
    Ok(stats)
}

/// The board's drivers on the emulated chip, the ADC initialised for `dev_cfg`.
fn bench<'a>(emu: &'a Shared, dev_cfg: &DeviceConfig) -> io::Result<Bench<'a>> {
    let (spi, drdy) = handles(emu);
    let mut adc = Driver::new(spi, drdy);
    let adc_cfg = Config {
        word_length: WordLength::Bits24,
        osr: dev_cfg.osr,
        gains: dev_cfg.pga,
        input_crc: true,
    };
    adc.init(&adc_cfg)
        .map_err(|e| io::Error::other(format!("ADC init: {e:?}")))?;
    Ok(Bench {
        adc,
        dac: Mcp4728::new(TrimDac(emu), DEFAULT_ADDRESS),
    })
}

/// The DRDY interrupt: a conversion is ready; read it through the driver.
fn interrupt(emu: &Shared, bench: &mut Bench<'_>) -> RawSample {
    emu.borrow_mut().convert();
    let index = (emu.borrow().conversions() - 1) as u32;
    match bench
        .adc
        .data_ready()
        .map(|ready| ready.then(|| bench.adc.read()))
    {
        Ok(Some(Ok(conv))) => RawSample {
            index,
            codes: conv.codes,
            read_error: false,
        },
        // DRDY high after a conversion, or a failed read: flagged in the next frame's status.
        _ => RawSample {
            index,
            codes: [0; 4],
            read_error: true,
        },
    }
}

/// After a rate command the ADC converts at a new rate: the chain's clock and the pacing follow
/// from the last conversion on, as the device's time stamps do.
fn follow_rate(emu: &Shared, rate_hz: &mut f32, next_s: &mut f64) {
    let now = emu.borrow().data_rate_hz();
    if now == *rate_hz {
        return;
    }
    let mut e = emu.borrow_mut();
    let last = e.conversions().saturating_sub(1);
    e.input_mut().retime(last, 1.0 / f64::from(now));
    *next_s += 1.0 / f64::from(now) - 1.0 / f64::from(*rate_hz);
    *rate_hz = now;
}
