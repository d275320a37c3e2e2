//! The analog front end of the emulated sensor, one model per stage, usable alone or chained:
//! bridge (raw offset from arm mismatch) -> trim-DAC offset cut -> in-amp -> gain stage ->
//! anti-alias RC -> ADS131M04 codes. Circuit and part choices: `hardware/frontend.md`; the same
//! circuit as a SPICE netlist: `hardware/spice/frontend.cir`. Every number comes from
//! `hardware/*.toml` through [`FrontEnd::from_params`] (std); the models themselves are `no_std`.

pub mod adc;
pub mod amp;
pub mod antialias;
pub mod bridge;
pub mod noise;
#[cfg(feature = "std")]
mod params;
pub mod trim;

pub use adc::Ads131m04;
pub use amp::{GainStage, InAmp, Output};
pub use antialias::{AntiAlias, AntiAliasFilter};
pub use bridge::{Bridge, Thevenin};
pub use trim::Trim;

/// Bridge channels: Fz, Mx, My on ADC channels 0, 1, 2.
pub const CHANNELS: usize = 3;

/// `chip.toml`'s arm names in this module's order R1..R4: R1/R2 the negative divider (the chip's
/// right side, R1 to the supply), R3/R4 the positive one (its left side; chip output = left -
/// right = V+ - V-).
pub const CHIP_ARM_ORDER: [&str; 4] = ["upper_right", "lower_right", "upper_left", "lower_left"];

/// One bridge's signal path from its arms to its ADC input pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Channel {
    pub bridge: Bridge,
    pub trim: Trim,
    pub stage1: InAmp,
    pub stage2: GainStage,
    pub antialias: AntiAlias,
    /// Noise temperature of the bridge and resistors.
    pub temperature_k: f64,
}

impl Channel {
    /// Small-signal gain from the bridge's differential output to the ADC input.
    pub fn gain(&self) -> f64 {
        self.stage1.gain() * self.stage2.gain() * self.antialias.dc_gain()
    }

    /// The in-amp's differential input: the bridge with stress `dr_r`, the offset cut at
    /// `dac_code` and an extra imbalance `imbalance_v` in series with the positive output.
    pub fn amp_input_v(&self, dr_r: [f64; 4], imbalance_v: f64, dac_code: u32) -> f64 {
        let (pos, neg) = self.bridge.outputs(dr_r);
        self.trim.inject(pos, dac_code).v + imbalance_v - neg.v
    }

    /// Second-stage output relative to VMID (`mid_v`): what the anti-alias RC sees, DC.
    pub fn amp_output_v(&self, dr_r: [f64; 4], imbalance_v: f64, dac_code: u32, mid_v: f64) -> f64 {
        self.amplify(self.amp_input_v(dr_r, imbalance_v, dac_code), mid_v)
    }

    /// The ADC's differential input at DC for arm resistances from the chip model (its arms in
    /// [`CHIP_ARM_ORDER`], this bridge's mismatch applied on top) and a signal `signal_v` in
    /// series with the positive output (the bridge's response to a load, `crate::forward`).
    pub fn adc_input_v_for_arms(
        &self,
        arms_ohm: [f64; 4],
        signal_v: f64,
        dac_code: u32,
        mid_v: f64,
    ) -> f64 {
        let (pos, neg) = self.bridge.outputs_for_arms(arms_ohm);
        // The small offset first, then the signal: adding a 0.1 mV signal to a 1.65 V node would
        // round it to 1e-12 of itself.
        let v_in = (self.trim.inject(pos, dac_code).v - neg.v) + signal_v;
        self.antialias.dc_gain() * self.amplify(v_in, mid_v)
    }

    /// Both stages: in-amp differential input to second-stage output minus VMID.
    fn amplify(&self, v_in: f64, mid_v: f64) -> f64 {
        let o1 = self.stage1.output_v(v_in, mid_v);
        self.stage2.output_v(o1, mid_v) - mid_v
    }

    /// The ADC's differential input voltage at DC.
    pub fn adc_input_v(&self, dr_r: [f64; 4], imbalance_v: f64, dac_code: u32, mid_v: f64) -> f64 {
        self.antialias.dc_gain() * self.amp_output_v(dr_r, imbalance_v, dac_code, mid_v)
    }

    /// The trim code that cancels the raw offset and the in-amp's offset together (what the
    /// firmware's null search converges to), if the DAC reaches it.
    pub fn null_code(&self) -> Option<u32> {
        let (pos, _) = self.bridge.outputs([0.0; 4]);
        self.trim
            .null_code(pos, self.bridge.raw_offset_v() + self.stage1.offset_v)
    }

    /// The (lowest, highest) shift the offset cut can apply, referred to the bridge output.
    pub fn trim_range_v(&self) -> (f64, f64) {
        self.trim.range_v(self.bridge.outputs([0.0; 4]).0)
    }

    /// Offset-cut resolution referred to the bridge output.
    pub fn trim_step_v(&self) -> f64 {
        self.trim.step_v(self.bridge.outputs([0.0; 4]).0)
    }

    /// The imbalances at which the output reaches the amplifier's (low, high) limits when
    /// extrapolated linearly from the operating point at `dac_code`: where saturation starts.
    pub fn rail_limits_input_v(&self, dac_code: u32, mid_v: f64) -> (f64, f64) {
        let (lo, hi) = self.stage2.output.limits_v();
        let out0 = self.amp_output_v([0.0; 4], 0.0, dac_code, mid_v);
        let g = self.stage1.gain() * self.stage2.gain();
        ((lo - mid_v - out0) / g, (hi - mid_v - out0) / g)
    }

    /// The imbalances at which the ADC input reaches `-+full_scale_v` (linear model).
    pub fn adc_limits_input_v(&self, dac_code: u32, mid_v: f64, full_scale_v: f64) -> (f64, f64) {
        let out0 = self.adc_input_v([0.0; 4], 0.0, dac_code, mid_v);
        (
            (-full_scale_v - out0) / self.gain(),
            (full_scale_v - out0) / self.gain(),
        )
    }

    /// Noise density referred to the bridge output: bridge and trim-resistor thermal noise,
    /// in-amp, and the second stage divided by G1.
    pub fn noise_v_per_rthz(&self) -> f64 {
        let (pos, neg) = self.bridge.outputs([0.0; 4]);
        let source_ohm = self.trim.inject(pos, 0).ohm + neg.ohm;
        let bridge = noise::thermal_v2_per_hz(source_ohm, self.temperature_k);
        let stage1 = self.stage1.noise_v_per_rthz();
        let stage2 = self.stage2.noise_v_per_rthz(self.temperature_k) / self.stage1.gain();
        libm::sqrt(bridge + stage1 * stage1 + stage2 * stage2)
    }

    /// Front-end rms noise referred to the bridge output within the ADC's sinc3 bandwidth (the
    /// amplifiers are chopped: no 1/f corner to add).
    pub fn noise_rms_v(&self, data_rate_hz: f64) -> f64 {
        self.noise_v_per_rthz() * libm::sqrt(noise::sinc3_enbw_hz(data_rate_hz))
    }
}

/// The analog temperature sensor on ADC channel 3: `V = V_0 + S T`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TempSensor {
    pub offset_v: f64,
    pub slope_v_per_c: f64,
}

impl TempSensor {
    pub fn output_v(&self, temperature_c: f64) -> f64 {
        self.offset_v + self.slope_v_per_c * temperature_c
    }

    pub fn temperature_c(&self, v: f64) -> f64 {
        (v - self.offset_v) / self.slope_v_per_c
    }
}

/// The whole front end: three channels sharing VMID, the ADC and the temperature sensor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrontEnd {
    pub channels: [Channel; CHANNELS],
    /// MCP4728 channel D code that makes VMID.
    pub mid_dac_code: u32,
    pub adc: Ads131m04,
    pub temperature: TempSensor,
}

impl FrontEnd {
    /// VMID, the amplifiers' and the ADC's common reference.
    pub fn mid_v(&self) -> f64 {
        self.channels[0].trim.dac_v(self.mid_dac_code)
    }

    /// The trim codes that null each channel (mid code where a channel cannot be nulled).
    pub fn null_codes(&self) -> [u32; CHANNELS] {
        self.channels
            .map(|c| c.null_code().unwrap_or(c.trim.codes() / 2))
    }

    /// Noise-free ADC codes of the three bridge channels for the stress changes `dr_r` of each
    /// bridge's arms, with the trim DAC at `dac_codes`.
    pub fn codes(&self, dr_r: [[f64; 4]; CHANNELS], dac_codes: [u32; CHANNELS]) -> [i32; CHANNELS] {
        let mid = self.mid_v();
        core::array::from_fn(|i| {
            let v = self.channels[i].adc_input_v(dr_r[i], 0.0, dac_codes[i], mid);
            self.adc.code(i, v)
        })
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;

    fn front_end() -> FrontEnd {
        FrontEnd::from_params(&hardware::Params::load_default().unwrap())
    }

    #[test]
    fn nulled_channels_read_near_zero() {
        let fe = front_end();
        let codes = fe.codes([[0.0; 4]; CHANNELS], fe.null_codes());
        for (ch, code) in fe.channels.iter().zip(codes) {
            // Half a trim step through the whole gain, in codes.
            let bound = ch.trim_step_v() / 2.0 * ch.gain() / fe.adc.lsb_v(0);
            assert!(f64::from(code.abs()) <= bound + 1.0, "{code} vs {bound}");
        }
    }

    #[test]
    fn unnulled_fz_offset_needs_the_offset_cut() {
        // Raw offset 0.66 mV x 1100 = 0.73 V: over half the +-1.2 V ADC range before any load,
        // hence the offset cut.
        let fe = front_end();
        let mid = fe.mid_v();
        let v = fe.channels[0].adc_input_v([0.0; 4], 0.0, fe.mid_dac_code, mid);
        assert!(v.abs() > 0.5 * fe.adc.full_scale_v(0), "{v}");
    }

    #[test]
    fn trim_covers_the_worst_raw_offset_and_the_amplifier_offset() {
        let p = hardware::Params::load_default().unwrap();
        let t = p.frontend.bridge.arm_tolerance;
        let worst =
            Bridge::worst_raw_offset_v(p.chip.excitation_v, t) + p.frontend.stage1.offset_max_v;
        for ch in front_end().channels {
            let (lo, hi) = ch.trim_range_v();
            assert!(lo < -worst && hi > worst, "range {lo}..{hi} vs {worst}");
        }
    }

    #[test]
    fn chip_arms_give_the_same_reading_as_relative_changes() {
        let fe = front_end();
        let (mid, codes) = (fe.mid_v(), fe.null_codes());
        let mx = &fe.channels[1];
        let dr_r = [1.0e-4, -2.0e-4, 3.0e-4, -1.0e-4];
        let arms = core::array::from_fn(|i| mx.bridge.nominal_ohm[i] * (1.0 + dr_r[i]));
        let a = mx.adc_input_v_for_arms(arms, 0.0, codes[1], mid);
        let b = mx.adc_input_v(dr_r, 0.0, codes[1], mid);
        assert!((a - b).abs() < 1e-12, "{a} vs {b}");
    }

    #[test]
    fn excitation_is_the_analog_rail() {
        // The trim's zero (mid code) and its ratiometry assume the bridges run off the rail.
        let p = hardware::Params::load_default().unwrap();
        assert_eq!(p.chip.excitation_v, p.frontend.supply_v);
    }

    #[test]
    fn arms_follow_chip_toml() {
        // chip.toml: Fz = two 5 kOhm piezoresistors per arm on the left, 10 kOhm references on
        // the right; Mx, My one 5 kOhm piezoresistor per arm.
        let fe = front_end();
        assert_eq!(fe.channels[0].bridge.nominal_ohm, [10.0e3; 4]);
        assert_eq!(fe.channels[1].bridge.nominal_ohm, [5.0e3; 4]);
        assert_eq!(fe.channels[2].bridge.nominal_ohm, [5.0e3; 4]);
    }

    #[test]
    fn temperature_sensor_inverts() {
        let t = front_end().temperature;
        assert!((t.temperature_c(t.output_v(25.0)) - 25.0).abs() < 1e-12);
    }
}
