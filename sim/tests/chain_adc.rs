//! The chain as the emulated ADS131M04's analog input and the emulated trim DAC's target: the
//! register-level chip converts exactly the chain's volts, DAC writes over I2C move the chain's
//! offset cut, and the noise has the budgeted size.

use std::cell::RefCell;

use embedded_hal::i2c::I2c;
use protocol::codes::volts_to_code;
use sim::ads131m04::trim_dac::{TrimDac, ADDRESS};
use sim::ads131m04::{AdcParams, Ads131m04};
use sim::chain::Chain;
use sim::load::ForceSchedule;

fn chain() -> Chain<ForceSchedule> {
    let p = hardware::Params::load_default().unwrap();
    Chain::from_params(&p, ForceSchedule::from_params(&p, 0.5, 20.0)).unwrap()
}

/// The chain, and the emulated chip converting it with `adc.toml`'s reference and clock.
fn emulated() -> (RefCell<Ads131m04<Chain<ForceSchedule>>>, AdcParams) {
    let adc = AdcParams::from_hardware(&hardware::Params::load_default().unwrap().adc);
    (RefCell::new(Ads131m04::new(chain(), adc)), adc)
}

#[test]
fn emulated_adc_converts_the_chain_volts() {
    let (emu, adc) = emulated();
    {
        let mut e = emu.borrow_mut();
        let codes = e.input_mut().front_end.null_codes();
        e.input_mut().dac_codes = codes;
    }
    for n in 0..3000u64 {
        emu.borrow_mut().convert();
        if n % 97 != 0 {
            continue;
        }
        let mut e = emu.borrow_mut();
        let codes = e.codes();
        let c = e.input_mut();
        let v = c.clean_v(c.clock.time_s(n));
        // The chip sees the chain's volts as f32, its analog input's type.
        let expect: [i32; 4] =
            core::array::from_fn(|ch| volts_to_code(f64::from(v[ch] as f32), adc.vref_v, 1));
        assert_eq!(codes, expect, "conversion {n}");
    }
}

#[test]
fn trim_dac_writes_move_the_offset_cut() {
    let (emu, _) = emulated();
    let mut dac = TrimDac(&emu);
    // Fast write: Fz at 3000, Mx at 1000, My at 2048, VMID channel D left alone.
    dac.write(ADDRESS, &[0x0B, 0xB8, 0x03, 0xE8, 0x08, 0x00, 0x08, 0x00])
        .unwrap();
    let mut e = emu.borrow_mut();
    let c = e.input_mut();
    assert_eq!(c.dac_codes, [3000, 1000, 2048]);
    // By hand: one code moves the Fz bridge output by 3.3 V / 4096 * 5k / (3M + 5k) = 1.3406 uV
    // (frontend.toml: 5 kOhm Thevenin node, 3 MOhm injection), times the Fz gain at the ADC.
    let g = c.front_end.channels[0].gain();
    let rest = |code: u32| {
        let mut k =
            Chain::from_params(&hardware::Params::load_default().unwrap(), c.history).unwrap();
        k.dac_codes[0] = code;
        k.clean_v(0.0)[0]
    };
    // Around the null code, away from the amplifiers' rails.
    let null = c.front_end.null_codes()[0];
    let step = (rest(null + 1) - rest(null)) / g;
    let by_hand = 3.3 / 4096.0 * 5.0e3 / (3.0e6 + 5.0e3);
    assert!((step / by_hand - 1.0).abs() < 2e-3, "{step} vs {by_hand}");
}

#[test]
fn noise_has_the_budgeted_rms() {
    let quiet = chain();
    let budget = quiet.noise_rms_v();
    // Fz: ~52 nV/rtHz at the bridge over the sinc3's 275 Hz, times 1100: ~0.95 mV.
    assert!(budget[0] > 0.75e-3 && budget[0] < 1.2e-3, "{budget:?}");
    let mut noisy = chain().with_noise(7);
    let n = 20_000;
    let mut sum2 = [0.0; 4];
    for _ in 0..n {
        let v = noisy.volts(0.0);
        let c = quiet.clean_v(0.0);
        for ch in 0..4 {
            sum2[ch] += (v[ch] - c[ch]).powi(2);
        }
    }
    for ch in 0..4 {
        let rms = (sum2[ch] / n as f64).sqrt();
        // 20 000 draws: the rms estimate's relative sd is 1/sqrt(2n) = 0.5 %.
        assert!(
            (rms / budget[ch] - 1.0).abs() < 0.025,
            "ch {ch}: {rms} vs {}",
            budget[ch]
        );
    }
}
