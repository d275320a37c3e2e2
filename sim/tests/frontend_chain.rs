//! The whole analog chain from the shipped `hardware/*.toml`, against a case computed by hand
//! from the datasheet equations (not from the models' own functions).

use protocol::codes::FULL_SCALE;
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
    let g2 = 1.1 / (1.0 + 1.1 / 10f64.powf(130.0 / 20.0)); // OPA333, 1 + 1k/10k, A0 130 dB
    let rc = 330.0e3 / (330.0e3 + 200.0); // ADC input impedance against 2 x 100 Ohm
    let expected = bridge * g1 * g2 * rc / 1.2 * f64::from(FULL_SCALE); // PGA 1, 1.2 V reference
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
    // By hand: +-1.2 V / 1100.1 = +-1090.8 uV, the rails at +-1.6 V * 0.9994 / 1100.1.
    assert!(((adc_hi - adc_lo) / 2.0 - 1.2 / fz.gain()).abs() < 1e-12);
    assert!((adc_hi - adc_lo) / 2.0 > 1090.0e-6 && (adc_hi - adc_lo) / 2.0 < 1092.0e-6);
}

#[test]
fn fz_noise_at_the_adc_matches_the_hand_budget() {
    // By hand, nV/rtHz at the bridge: INA333 50 and 200 / G1; the Fz bridge's two output nodes,
    // 10k || 10k || 3 MOhm and 10k || 10k, at 300 K; OPA333 55 with 10k || 1k, / G1. Over the
    // sinc3 noise bandwidth at 1 kSPS, 275 Hz, times the Fz gain.
    let fe = front_end();
    let fz = &fe.channels[0];
    let kt4 = 4.0 * 1.380_649e-23 * 300.0;
    let g1: f64 = 1.0 + 100.0e3 / 1010.0;
    let bridge = kt4 * (5.0e3 * 3.0e6 / 3.005e6 + 5.0e3);
    let opa = (55.0e-9f64.powi(2) + kt4 * 10.0e3 * 1.0e3 / 11.0e3) / g1.powi(2);
    let density = (50.0e-9f64.powi(2) + (200.0e-9 / g1).powi(2) + bridge + opa).sqrt();
    let sigma_by_hand = density * 275.0f64.sqrt() * fz.gain();
    let sigma = fz.noise_rms_v(fe.adc.data_rate_hz) * fz.gain();
    // The model's bridge resistances carry the arms' +-0.02 % mismatch; the budget does not.
    let error = (sigma / sigma_by_hand - 1.0).abs();
    assert!(error < 1.0e-6, "{sigma} vs {sigma_by_hand}");
}
