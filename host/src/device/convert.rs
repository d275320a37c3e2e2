//! Codes -> volts -> loads, from the device's own info frame (SPEC.md, "Codes to volts"):
//! `v = code · (vref_mv/1000) / (pga · 2²³)` at the ADC input, `v / amp_gain` at the bridge,
//! and `(Fz, Mx, My) = C · v` with the calibration matrix C the device reports.

use protocol::codes::volts_per_code;
use protocol::{Info, Sample};

/// The conversion of one device configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Scale {
    /// Volts at the ADC input per code, per bridge channel (Fz, Mx, My).
    pub volts_per_code: [f64; 3],
    /// Volts at the ADC input per code of the temperature channel (ADC channel 3).
    pub temp_volts_per_code: f64,
    /// Amplifier voltage gain per bridge channel.
    pub amp_gain: [f64; 3],
    /// Calibration matrix, volts at the ADC input -> (Fz N, Mx N·m, My N·m).
    pub calibration: [[f64; 3]; 3],
}

impl Scale {
    pub fn from_info(info: &Info) -> Self {
        let vref_v = f64::from(info.vref_mv) / 1000.0;
        // A PGA gain of 0 is not a valid setting; treat it as 1 rather than divide by zero.
        let per_code = |pga: u8| volts_per_code(vref_v, u32::from(pga.max(1)));
        let c = info.calibration.map(|row| row.map(f64::from));
        Self {
            volts_per_code: [
                per_code(info.pga_gain[0]),
                per_code(info.pga_gain[1]),
                per_code(info.pga_gain[2]),
            ],
            temp_volts_per_code: per_code(info.pga_gain[3]),
            amp_gain: info.amp_gain.map(f64::from),
            calibration: c,
        }
    }

    /// Volts at the ADC input (the recording's `fz_V, mx_V, my_V`).
    pub fn adc_volts(&self, s: &Sample) -> [f64; 3] {
        [0, 1, 2].map(|i| f64::from(s.ch[i]) * self.volts_per_code[i])
    }

    /// Volts at the bridge output, before the amplifier.
    pub fn bridge_volts(&self, s: &Sample) -> [f64; 3] {
        let v = self.adc_volts(s);
        [0, 1, 2].map(|i| v[i] / self.amp_gain[i])
    }

    /// (Fz in N, Mx in N·m, My in N·m).
    pub fn loads(&self, s: &Sample) -> [f64; 3] {
        let v = self.adc_volts(s);
        self.calibration
            .map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info() -> Info {
        Info {
            protocol_version: 1,
            fw_version: [0, 1, 0],
            chip_serial: 1,
            sample_rate_hz: 1000,
            batch: 10,
            pga_gain: [2, 1, 1, 1],
            vref_mv: 1200,
            amp_gain: [3000.0, 1000.0, 1000.0],
            excitation_v: 3.3,
            filter: protocol::FilterConfig::NONE,
            calibration: [[2.0, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 0.25]],
            dac_codes: [0; 4],
            tare: [0; 3],
            drift: [0; 3],
            null_state: protocol::NullState::Off,
            drift_tracking: false,
            streaming: false,
            config_epoch: 0,
        }
    }

    #[test]
    fn full_scale_code_is_vref_over_pga() {
        let s = Scale::from_info(&info());
        let fs = Sample {
            ch: [protocol::CODE_MAX + 1 - 1, protocol::CODE_MIN, 1 << 22],
        };
        let v = s.adc_volts(&fs);
        assert!((v[0] - 0.6 * (8_388_607.0 / 8_388_608.0)).abs() < 1e-12);
        assert!((v[1] + 1.2).abs() < 1e-12);
        assert!((v[2] - 0.6).abs() < 1e-12);
        let b = s.bridge_volts(&fs);
        assert!((b[1] + 1.2e-3).abs() < 1e-15);
        let l = s.loads(&fs);
        assert!((l[1] + 0.6).abs() < 1e-12 && (l[2] - 0.15).abs() < 1e-12);
    }
}
