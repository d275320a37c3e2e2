//! Noise of the front end referred to the bridge (input), against the ADC's own noise.

/// Boltzmann's constant, J/K (exact since the 2019 SI).
pub const BOLTZMANN_J_PER_K: f64 = 1.380_649e-23;

/// Thermal (Johnson) noise power density of a resistor, `4 k T R`, in V²/Hz.
pub fn thermal_v2_per_hz(r_ohm: f64, temperature_k: f64) -> f64 {
    4.0 * BOLTZMANN_J_PER_K * temperature_k * r_ohm
}

/// Equivalent noise bandwidth of the ADS131M04's sinc3 decimation filter:
/// `f_DATA * integral_0^inf sinc^6(x) dx = f_DATA * 11/40`.
pub fn sinc3_enbw_hz(data_rate_hz: f64) -> f64 {
    data_rate_hz * 11.0 / 40.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_5k_resistor_at_300k_gives_9_1_nv() {
        let e = libm::sqrt(thermal_v2_per_hz(5000.0, 300.0));
        assert!((e - 9.1011e-9).abs() < 1e-12, "{e}");
    }

    #[test]
    fn sinc3_enbw_matches_a_numerical_integral() {
        // Midpoint rule over 0..200 (the sinc^6 tail beyond is below 1e-13).
        let n = 2_000_000;
        let dx = 200.0 / n as f64;
        let integral: f64 = (0..n)
            .map(|i| {
                let x = (i as f64 + 0.5) * dx;
                let s = libm::sin(core::f64::consts::PI * x) / (core::f64::consts::PI * x);
                s.powi(6) * dx
            })
            .sum();
        assert!((sinc3_enbw_hz(1.0) - integral).abs() < 1e-6, "{integral}");
    }
}
