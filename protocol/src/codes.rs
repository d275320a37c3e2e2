//! ADC codes to volts and back: the ADS131M04's transfer function (datasheet SBAS890, "Ideal
//! Output Code" table), `code = round(v · pga / vref · 2²³)` clipped to the 24-bit range, and its
//! inverse `v = code · vref / (pga · 2²³)` (SPEC.md, "Codes to volts"). The firmware, the sim's
//! converter models and the host all convert through these, in f64: the same operations on every
//! platform, so the host recomputes exactly the codes the emulated ADC on a Cortex-M produces.

use crate::{Code, CODE_MAX, CODE_MIN};

/// Codes per full scale, 2²³: the input `+vref / pga` maps to this code (and clips one below
/// it), `-vref / pga` to its negative.
pub const FULL_SCALE: Code = 1 << 23;

/// Volts at the ADC input per code (one LSB) for a reference of `vref_v` and a PGA gain of
/// `pga_gain`.
pub fn volts_per_code(vref_v: f64, pga_gain: u32) -> f64 {
    vref_v / (f64::from(pga_gain) * f64::from(FULL_SCALE))
}

/// Volts at the ADC input that `code` stands for.
pub fn code_to_volts(code: Code, vref_v: f64, pga_gain: u32) -> f64 {
    f64::from(code) * volts_per_code(vref_v, pga_gain)
}

/// The ideal (noise-free) code of the differential input `v`, in volts: rounded to the nearest
/// code (halves away from zero), clipped to [`CODE_MIN`]..=[`CODE_MAX`] as the device clips.
/// A NaN input gives 0.
pub fn volts_to_code(v: f64, vref_v: f64, pga_gain: u32) -> Code {
    let code = libm::round(v / volts_per_code(vref_v, pga_gain));
    // `as` maps NaN to 0; the clamp keeps it NaN.
    code.clamp(f64::from(CODE_MIN), f64::from(CODE_MAX)) as Code
}

/// Whether `code` sits at either clip of the 24-bit range.
pub fn is_clipped(code: Code) -> bool {
    code == CODE_MAX || code == CODE_MIN
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn full_scale_edges_map_to_the_24_bit_limits() {
        // +vref/pga is one code above the largest: it clips; -vref/pga is exactly the smallest.
        assert_eq!(volts_to_code(1.2, 1.2, 1), CODE_MAX);
        assert_eq!(volts_to_code(-1.2, 1.2, 1), CODE_MIN);
        assert_eq!(volts_to_code(-0.6, 1.2, 2), CODE_MIN);
        assert_eq!(volts_to_code(2.0, 1.2, 1), CODE_MAX);
        assert_eq!(volts_to_code(-2.0, 1.2, 128), CODE_MIN);
        assert!(is_clipped(volts_to_code(5.0, 1.2, 1)) && !is_clipped(0));
        assert_eq!(code_to_volts(CODE_MIN, 1.2, 1), -1.2);
        assert_eq!(
            code_to_volts(CODE_MAX, 1.2, 1),
            1.2 * (8_388_607.0 / 8_388_608.0)
        );
        assert_eq!(code_to_volts(CODE_MIN, 1.2, 4), -0.3);
    }

    #[test]
    fn known_voltages_give_the_datasheet_codes() {
        assert_eq!(volts_to_code(0.0, 1.2, 1), 0);
        assert_eq!(volts_to_code(0.6, 1.2, 1), 1 << 22);
        assert_eq!(volts_to_code(0.3, 1.2, 2), 1 << 22);
        // One LSB = 1.2 V / 2²³ = 143.05 nV; half an LSB rounds away from zero.
        assert_eq!(volts_to_code(1.2 / 8_388_608.0, 1.2, 1), 1);
        assert_eq!(volts_to_code(-1.2 / 8_388_608.0, 1.2, 1), -1);
        assert_eq!(volts_to_code(0.5 * 1.2 / 8_388_608.0, 1.2, 1), 1);
        assert_eq!(volts_to_code(-0.5 * 1.2 / 8_388_608.0, 1.2, 1), -1);
        assert_eq!(volts_to_code(f64::NAN, 1.2, 1), 0);
    }

    #[test]
    fn codes_round_trip_through_volts_across_the_range() {
        for pga_gain in [1, 2, 8, 128] {
            for code in [CODE_MIN, CODE_MIN + 1, -12_345, -1, 0, 1, 777_777, CODE_MAX] {
                let v = code_to_volts(code, 1.2, pga_gain);
                assert_eq!(volts_to_code(v, 1.2, pga_gain), code, "pga {pga_gain}");
            }
        }
    }
}
