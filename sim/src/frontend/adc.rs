//! The ADS131M04's conversion: differential input volts to a 24-bit two's-complement code,
//! `code = round(v G_PGA / V_REF * 2^23)`, clipped to `[-2^23, 2^23 - 1]` (datasheet: the output
//! clips at 7FFFFFh and 800000h), plus the datasheet's noise at the configured OSR. The transfer
//! function itself is `protocol::codes`, shared with the emulated chip and the host.

use protocol::codes;

/// The converter as configured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ads131m04 {
    pub reference_v: f64,
    /// PGA gain of channels 0..3.
    pub pga_gain: [u32; 4],
    /// Input-referred noise of channels 0..3 at the configured OSR and gain, volts rms.
    pub noise_rms_v: [f64; 4],
    pub data_rate_hz: f64,
    pub modulator_hz: f64,
}

impl Ads131m04 {
    /// Full scale `V_REF / G_PGA`: inputs beyond +-this clip.
    pub fn full_scale_v(&self, channel: usize) -> f64 {
        self.reference_v / f64::from(self.pga_gain[channel])
    }

    /// Volts of one code.
    pub fn lsb_v(&self, channel: usize) -> f64 {
        codes::volts_per_code(self.reference_v, self.pga_gain[channel])
    }

    /// The ideal (noise-free) code of a differential input `v`.
    pub fn code(&self, channel: usize, v: f64) -> i32 {
        codes::volts_to_code(v, self.reference_v, self.pga_gain[channel])
    }

    /// The code with the converter's noise: `z` is a standard normal draw from the caller's
    /// generator (kept outside so this stays a pure function).
    pub fn code_with_noise(&self, channel: usize, v: f64, z: f64) -> i32 {
        self.code(channel, v + z * self.noise_rms_v[channel])
    }

    /// Volts a code stands for.
    pub fn volts(&self, channel: usize, code: i32) -> f64 {
        codes::code_to_volts(code, self.reference_v, self.pga_gain[channel])
    }

    /// Whether `code` is at either clip.
    pub fn is_clipped(code: i32) -> bool {
        codes::is_clipped(code)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ADC: Ads131m04 = Ads131m04 {
        reference_v: 1.2,
        pga_gain: [1, 1, 2, 1],
        noise_rms_v: [3.38e-6; 4],
        data_rate_hz: 1000.0,
        modulator_hz: 4.096e6,
    };

    #[test]
    fn known_voltages_give_the_datasheet_codes() {
        assert_eq!(ADC.code(0, 0.0), 0);
        // 0.6 V at gain 1 is half of full scale: 2^22 = 0x400000.
        assert_eq!(ADC.code(0, 0.6), 0x40_0000);
        // One LSB = 1.2 V / 2^23 = 143.05 nV.
        assert_eq!(ADC.code(0, -1.2 / f64::from(codes::FULL_SCALE)), -1);
        // Gain 2 halves the full scale.
        assert_eq!(ADC.code(2, 0.3), 0x40_0000);
    }

    #[test]
    fn out_of_range_inputs_clip() {
        assert_eq!(ADC.code(0, 1.5), protocol::CODE_MAX);
        assert_eq!(ADC.code(0, -1.5), protocol::CODE_MIN);
        assert!(Ads131m04::is_clipped(ADC.code(1, 2.0)));
    }

    #[test]
    fn noise_draw_is_scaled_by_the_table_value() {
        let lsb = ADC.lsb_v(0);
        assert_eq!(
            ADC.code_with_noise(0, 0.0, 1.0),
            libm::round(3.38e-6 / lsb) as i32
        );
    }
}
