//! Driver, DAC driver and device core against the sim's emulated ADS131M04 and trim DAC with the
//! QEMU board's stimulus: power-up null, tare at rest, then the streamed codes must be the
//! stimulus signal's ideal codes within one code.

#![allow(clippy::needless_range_loop, clippy::explicit_counter_loop)]

use super::*;
use crate::ads131m04::{Ads131m04, Config, WordLength};
use crate::mcp4728::{trim_writes, Mcp4728, DEFAULT_ADDRESS};
use crate::params::EMULATED_ADC;
use core::cell::RefCell;
use protocol::codes::volts_to_code;
use sim::ads131m04::stimulus::{Stimulus, StimulusParams};
use sim::ads131m04::trim_dac::TrimDac;
use sim::ads131m04::{handles, Ads131m04 as Emu, DrdyHandle, SpiHandle};

type Chip = RefCell<Emu<Stimulus>>;

struct Bench<'a> {
    adc: Ads131m04<SpiHandle<'a, Stimulus>, DrdyHandle<'a, Stimulus>>,
    dac: Mcp4728<TrimDac<'a, Stimulus>>,
}

impl BoardControl for Bench<'_> {
    fn set_trim(&mut self, codes: [u16; 3]) -> Result<(), HardwareError> {
        self.dac
            .multi_write(&trim_writes(codes))
            .map_err(|_| HardwareError::Dac)
    }
    fn set_osr(&mut self, osr: Osr) -> Result<(), HardwareError> {
        self.adc.set_osr(osr).map_err(|_| HardwareError::Adc)
    }
}

fn bench(chip: &Chip) -> Bench<'_> {
    let (spi, drdy) = handles(chip);
    let mut adc = Ads131m04::new(spi, drdy);
    let cfg = Config {
        word_length: WordLength::Bits24,
        osr: Osr::Osr4096,
        gains: [crate::ads131m04::Pga::X1; 4],
        input_crc: true,
    };
    adc.init(&cfg).unwrap();
    Bench {
        adc,
        dac: Mcp4728::new(TrimDac(chip), DEFAULT_ADDRESS),
    }
}

/// One conversion: the chip converts, the driver reads it as the DRDY interrupt would.
fn step(chip: &Chip, bench: &mut Bench<'_>, dev: &mut Device) -> u64 {
    chip.borrow_mut().convert();
    let index = chip.borrow().conversions() - 1;
    assert!(bench.adc.data_ready().unwrap());
    let conv = bench.adc.read().unwrap();
    dev.on_sample(
        &RawSample {
            index: index as u32,
            codes: conv.codes,
            read_error: false,
        },
        bench,
    );
    index
}

#[test]
fn null_tare_and_stream_the_stimulus() {
    let chip = RefCell::new(Emu::new(
        Stimulus::new(StimulusParams::QEMU_BOARD),
        EMULATED_ADC,
    ));
    let mut bench = bench(&chip);
    let mut cfg = config();
    cfg.null_at_power_up = true;
    cfg.null_timing = NullTiming {
        settle: 2,
        average: 8,
    };
    let mut dev = Device::new(cfg);
    dev.power_up(&mut bench).unwrap();
    while dev.null_state() == NullState::Searching {
        step(&chip, &mut bench, &mut dev);
    }
    assert_eq!(dev.null_state(), NullState::Nulled);
    // offset / 3e-4 V per code: 0.35 V → +1167, −0.25 V → −833, 0.2 V → +667 codes from mid.
    assert_eq!(&dev.info().dac_codes[..3], &[3215, 1215, 2715]);
    request(&mut dev, 1, Command::Tare { samples: 64 });
    request(&mut dev, 2, Command::Start);
    let rest = StimulusParams::QEMU_BOARD.rest;
    while chip.borrow().conversions() < rest {
        step(&chip, &mut bench, &mut dev);
    }
    drain(&mut dev);
    let reference = Stimulus::new(StimulusParams::QEMU_BOARD);
    let mut f = Vec::new();
    for _ in 0..2000 {
        step(&chip, &mut bench, &mut dev);
        f.extend(frames(&drain(&mut dev)));
    }
    assert!(f.len() >= 499);
    for frame in &f {
        // Conversion index of the frame's first sample from its time stamp (1000 samples/s).
        let mut n = u64::from(frame.t_us / 1000);
        assert!(frame.status.tare_active && frame.status.null_state == NullState::Nulled);
        for s in frame.samples() {
            let truth = reference.signal_v(n);
            for ch in 0..3 {
                let expect = volts_to_code(f64::from(truth[ch]), EMULATED_ADC.vref_v, 1);
                assert!(
                    (s.ch[ch] - expect).abs() <= 1,
                    "n {n} ch {ch}: {} vs {expect}",
                    s.ch[ch]
                );
            }
            n += 1;
        }
    }
    assert!(f.windows(2).all(|w| w[1].seq == w[0].seq + 1));
}
