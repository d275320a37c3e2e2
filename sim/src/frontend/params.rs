//! Building the front end from `hardware/*.toml` (the one source of every number).

use super::*;

impl FrontEnd {
    /// The front end and ADC as `params` describe them.
    pub fn from_params(params: &hardware::Params) -> Self {
        let fe = &params.frontend;
        let channels = core::array::from_fn(|i| channel(params, i));
        let adc = &params.adc;
        FrontEnd {
            channels,
            mid_dac_code: fe.mid_dac_code,
            adc: Ads131m04 {
                reference_v: adc.reference_v,
                pga_gain: adc.pga_gain,
                noise_rms_v: core::array::from_fn(|ch| adc.noise_rms_v(ch)),
                data_rate_hz: adc.data_rate_hz(),
                modulator_hz: adc.modulator_hz(),
            },
            temperature: TempSensor {
                offset_v: fe.temperature.offset_v,
                slope_v_per_c: fe.temperature.slope_v_per_c,
            },
        }
    }
}

/// Nominal arm resistances of bridge `i`: its piezoresistors in each arm plus the arm's fixed
/// resistance (the Fz bridge has two piezoresistors per arm on one side, references on the other).
fn nominal_arms_ohm(chip: &hardware::Chip, i: usize) -> [f64; 4] {
    let bridge = &chip.bridges[i];
    CHIP_ARM_ORDER.map(|arm| {
        let fixed = hardware::ARM_NAMES
            .iter()
            .position(|a| *a == arm)
            .map_or(0.0, |k| bridge.fixed_ohm[k]);
        let piezos = bridge.resistors.iter().filter(|r| r.arm == arm).count() as f64;
        fixed + piezos * chip.resistance_ohm
    })
}

fn channel(params: &hardware::Params, i: usize) -> Channel {
    let (fe, adc) = (&params.frontend, &params.adc);
    let (s1, s2) = (&fe.stage1, &fe.stage2);
    Channel {
        bridge: Bridge {
            nominal_ohm: nominal_arms_ohm(&params.chip, i),
            excitation_v: params.chip.excitation_v,
            mismatch: fe.bridge.arm_mismatch[i],
        },
        trim: Trim {
            reference_v: fe.supply_v,
            dac_bits: fe.trim.dac_bits,
            injection_ohm: fe.trim.injection_ohm[i],
        },
        stage1: InAmp {
            internal_ohm: s1.internal_ohm,
            gain_resistor_ohm: s1.gain_resistor_ohm[i],
            offset_v: s1.offset_v[i],
            gbw_hz: s1.gbw_hz,
            input_noise_v_per_rthz: s1.input_noise_v_per_rthz,
            output_noise_v_per_rthz: s1.output_noise_v_per_rthz,
            output: Output {
                supply_v: fe.supply_v,
                swing_from_rail_v: s1.swing_from_rail_v,
                knee_v: s1.knee_v,
            },
        },
        stage2: GainStage {
            feedback_ohm: s2.feedback_ohm[i],
            ground_ohm: s2.ground_ohm[i],
            open_loop_gain: libm::pow(10.0, s2.open_loop_gain_db / 20.0),
            gbw_hz: s2.gbw_hz,
            input_noise_v_per_rthz: s2.input_noise_v_per_rthz,
            output: Output {
                supply_v: fe.supply_v,
                swing_from_rail_v: s2.swing_from_rail_v,
                knee_v: s2.knee_v,
            },
        },
        antialias: AntiAlias {
            series_ohm: fe.antialias.series_ohm,
            diff_cap_f: fe.antialias.diff_cap_f,
            cm_cap_f: fe.antialias.cm_cap_f,
            load_ohm: adc.input_impedance_ohm,
        },
        temperature_k: fe.bridge.temperature_k,
    }
}
