//! The whole analog chain from the shipped `hardware/*.toml`, against a case computed by hand
//! from the datasheet equations (not from the models' own functions).

use sim::frontend::FrontEnd;

fn front_end() -> FrontEnd {
    FrontEnd::from_params(&hardware::Params::load_default().unwrap())
}

#[test]
fn push_pull_strain_on_mx_gives_the_hand_computed_code_step() {
    let fe = front_end();
    let codes = fe.null_codes();
    let x = 1.0e-4;
    let strained = [[0.0; 4], [x, -x, -x, x], [0.0; 4]];
    let step = fe.codes(strained, codes)[1] - fe.codes([[0.0; 4]; 3], codes)[1];

    // By hand (frontend.toml, adc.toml): each half of the bridge moves by 3.3 V * x / 2; the
    // positive half is loaded by the 1.5 MOhm trim resistor against its 2.5 kOhm source.
    let bridge = 3.3 * x / 2.0 * (1.0 + 1.5e6 / (1.5e6 + 2.5e3));
    let g1 = 1.0 + 100.0e3 / 1010.0; // INA333, RG = 1.01 kOhm
    let g2 = 10.09 / (1.0 + 10.09 / 10f64.powf(130.0 / 20.0)); // OPA333, 1 + 9.09k/1k, A0 130 dB
    let rc = 330.0e3 / (330.0e3 + 200.0); // ADC input impedance against 2 x 100 Ohm
    let expected = bridge * g1 * g2 * rc / 1.2 * f64::from(1 << 23); // PGA 1, 1.2 V reference
    let error = (f64::from(step) - expected).abs() / expected;
    assert!(
        error < 1.0e-4,
        "step {step} codes, by hand {expected:.0} ({error:e})"
    );
}

#[test]
fn full_scale_imbalance_clips_at_the_adc_before_the_amplifier_rails() {
    let fe = front_end();
    let mid = fe.mid_v();
    let codes = fe.null_codes();
    let fz = &fe.channels[0];
    let (rail_lo, rail_hi) = fz.rail_limits_input_v(codes[0], mid);
    let (adc_lo, adc_hi) = fz.adc_limits_input_v(codes[0], mid, fe.adc.full_scale_v(0));
    assert!(rail_lo < adc_lo && adc_hi < rail_hi);
    // By hand: +-1.2 V / 3008.45 = +-398.9 uV, the rails at +-1.6 V * 0.9994 / 3008.45.
    assert!(((adc_hi - adc_lo) / 2.0 - 1.2 / fz.gain()).abs() < 1e-12);
    assert!((adc_hi - adc_lo) / 2.0 > 398.0e-6 && (adc_hi - adc_lo) / 2.0 < 400.0e-6);
}

#[test]
fn noise_draws_scale_the_adc_input_by_the_front_end_noise() {
    // The sim adds the front end's noise at the bridge (z * rms) and the ADC's at its input;
    // one sigma of front-end noise on Fz is 0.843 uV * 3008 = 2.54 mV at the ADC (frontend.md).
    let fe = front_end();
    let fz = &fe.channels[0];
    let sigma = fz.noise_rms_v(fe.adc.data_rate_hz) * fz.gain();
    assert!((sigma - 2.54e-3).abs() < 0.01e-3, "{sigma}");
}
