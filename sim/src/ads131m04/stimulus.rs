//! A deterministic analog input for the emulated ADC, known to both sides of a test: the QEMU
//! firmware converts it, the host recomputes it from the conversion index and compares.
//!
//! Each channel is a triangle wave around an offset, a pure f32 function of the conversion index
//! (no transcendental functions, no state), so host and Cortex-M4F produce bit-identical volts and,
//! through `protocol::codes::volts_to_code`, bit-identical codes. The three bridge channels also carry a raw
//! offset that the trim DAC cancels: each DAC code step moves the channel by `trim_v_per_code`
//! (negative: a higher code pulls the output down), the way the front end's injection resistor
//! moves the amplified output. That lets the firmware's auto-null search run against it.

use super::AnalogInput;

/// Parameters of the stimulus (test-signal design values, not physical parameters of the sensor).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StimulusParams {
    /// Offset at the ADC input with the trim DAC at mid code (2048), volts.
    pub offset_v: [f32; 4],
    /// Peak amplitude of the triangle wave, volts.
    pub amplitude_v: [f32; 4],
    /// Period of the triangle wave in conversions.
    pub period: [u32; 4],
    /// Change of the ADC input per trim-DAC code step for the bridge channels, volts per code.
    pub trim_v_per_code: [f32; 3],
    /// Conversions at rest (bridge signals zero) before the waves start: the sensor lies unloaded
    /// while the firmware nulls and tares after power-up.
    pub rest: u64,
}

impl StimulusParams {
    /// The stimulus the QEMU board converts. Bridge offsets of 0.2–0.35 V are far from mid-scale
    /// (the auto-null must find codes about 600–1100 steps from mid); amplitudes and periods differ
    /// per channel so a channel swap shows; channel 3 (temperature) is a slow small ramp.
    pub const QEMU_BOARD: Self = Self {
        offset_v: [0.35, -0.25, 0.2, 0.05],
        amplitude_v: [0.3, 0.2, 0.1, 0.01],
        period: [400, 1000, 250, 20_000],
        trim_v_per_code: [-3.0e-4, -3.0e-4, -3.0e-4],
        rest: 2000,
    };
}

/// Mid code of the 12-bit trim DAC: no correction relative to `offset_v`.
pub const TRIM_MID_CODE: u16 = 2048;

/// The stimulus with the trim codes currently applied.
#[derive(Clone, Debug)]
pub struct Stimulus {
    pub params: StimulusParams,
    /// Trim-DAC codes of the bridge channels (channel 3 of the DAC is unused).
    pub trim_codes: [u16; 4],
}

impl Stimulus {
    /// The stimulus with the trim DAC at mid code.
    pub fn new(params: StimulusParams) -> Self {
        Self {
            params,
            trim_codes: [TRIM_MID_CODE; 4],
        }
    }

    /// Triangle wave in [-1, 1] with value -1 at index 0 and +1 at half period.
    pub fn triangle(index: u64, period: u32) -> f32 {
        let phase = (index % u64::from(period)) as f32 / period as f32;
        1.0 - 4.0
            * if phase < 0.5 {
                0.5 - phase
            } else {
                phase - 0.5
            }
    }

    /// Volts at the four ADC inputs for conversion `index`.
    #[allow(clippy::needless_range_loop)] // channel index runs over signal and output alike
    pub fn volts(&self, index: u64) -> [f32; 4] {
        let p = &self.params;
        let signal = self.signal_v(index);
        let mut v = [0.0; 4];
        for ch in 0..3 {
            v[ch] = self.bridge_v(ch, signal[ch]);
        }
        v[3] = p.offset_v[3] + signal[3];
        v
    }

    /// Volts at bridge channel `ch`'s ADC input for a signal `signal_v` (what a nulled, tared
    /// channel shows): the bench's raw offset, the signal, and the trim DAC's correction.
    pub fn bridge_v(&self, ch: usize, signal_v: f32) -> f32 {
        let steps = f32::from(self.trim_codes[ch]) - f32::from(TRIM_MID_CODE);
        self.params.offset_v[ch] + signal_v + self.params.trim_v_per_code[ch] * steps
    }

    /// The signal part alone (offsets and trim excluded), what a perfectly nulled and tared
    /// channel shows: zero for the bridges during the rest period, the triangle waves after it
    /// (counted from the end of the rest). The temperature channel's wave runs from index 0.
    pub fn signal_v(&self, index: u64) -> [f32; 4] {
        let p = &self.params;
        core::array::from_fn(|ch| {
            if ch < 3 && index < p.rest {
                0.0
            } else {
                let t = if ch < 3 { index - p.rest } else { index };
                p.amplitude_v[ch] * Self::triangle(t, p.period[ch])
            }
        })
    }
}

impl AnalogInput for Stimulus {
    fn sample_v(&mut self, index: u64) -> [f32; 4] {
        self.volts(index)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_hits_its_corners() {
        assert_eq!(Stimulus::triangle(0, 400), -1.0);
        assert_eq!(Stimulus::triangle(100, 400), 0.0);
        assert_eq!(Stimulus::triangle(200, 400), 1.0);
        assert_eq!(Stimulus::triangle(300, 400), 0.0);
        assert_eq!(Stimulus::triangle(400, 400), -1.0);
    }

    #[test]
    fn bridges_rest_then_move() {
        let s = Stimulus::new(StimulusParams::QEMU_BOARD);
        assert_eq!(&s.signal_v(1999)[..3], &[0.0; 3]);
        assert_eq!(s.volts(0)[0], 0.35);
        assert_eq!(s.signal_v(2000)[0], -0.3);
        assert_eq!(s.signal_v(2200)[0], 0.3);
    }

    #[test]
    fn trim_moves_the_bridge_channels_only() {
        let mut s = Stimulus::new(StimulusParams::QEMU_BOARD);
        let before = s.volts(2007);
        s.trim_codes = [TRIM_MID_CODE + 1000; 4];
        let after = s.volts(2007);
        for ch in 0..3 {
            assert!((after[ch] - before[ch] - (-0.3)).abs() < 1e-5, "ch {ch}");
        }
        assert_eq!(after[3], before[3]);
    }
}
