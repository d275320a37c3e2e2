//! The anti-alias RC in front of an ADS131M04 input pair: a series resistor R in each leg, a
//! differential capacitor C_d across the pins, a common-mode capacitor C_cm from each pin to
//! ground, and the ADC's differential input impedance R_in as the load.
//!
//! Differential half circuit: `H(s) = k / (1 + s tau)` with `k = R_in / (R_in + 2R)` and
//! `tau = (2R || R_in) (C_d + C_cm / 2)`.

/// The RC and its load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AntiAlias {
    pub series_ohm: f64,
    pub diff_cap_f: f64,
    pub cm_cap_f: f64,
    /// The ADC's differential input impedance.
    pub load_ohm: f64,
}

impl AntiAlias {
    /// DC gain `R_in / (R_in + 2R)`.
    pub fn dc_gain(&self) -> f64 {
        self.load_ohm / (self.load_ohm + 2.0 * self.series_ohm)
    }

    /// Time constant `(2R || R_in) (C_d + C_cm / 2)`.
    pub fn tau_s(&self) -> f64 {
        let r = 2.0 * self.series_ohm * self.load_ohm / (2.0 * self.series_ohm + self.load_ohm);
        r * (self.diff_cap_f + self.cm_cap_f / 2.0)
    }

    /// The -3 dB corner `1 / (2 pi tau)`.
    pub fn corner_hz(&self) -> f64 {
        1.0 / (2.0 * core::f64::consts::PI * self.tau_s())
    }

    /// `|H(f)| / |H(0)|`: the attenuation at `f`, e.g. the modulator frequency.
    pub fn relative_gain(&self, f_hz: f64) -> f64 {
        1.0 / libm::hypot(1.0, f_hz / self.corner_hz())
    }

    /// A discrete filter of this RC for samples every `dt_s` (exact for inputs held over a step).
    pub fn filter(&self, dt_s: f64) -> AntiAliasFilter {
        AntiAliasFilter {
            alpha: 1.0 - libm::exp(-dt_s / self.tau_s()),
            gain: self.dc_gain(),
            y: None,
        }
    }
}

/// The RC's state, stepped at the sample clock: `y += alpha (k x - y)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AntiAliasFilter {
    alpha: f64,
    gain: f64,
    y: Option<f64>,
}

impl AntiAliasFilter {
    /// Feed the differential amplifier output `x_v`; returns the ADC's input voltage. The first
    /// sample starts the filter settled (the board has been on for longer than tau).
    pub fn step(&mut self, x_v: f64) -> f64 {
        let target = self.gain * x_v;
        let y = match self.y {
            None => target,
            Some(y) => y + self.alpha * (target - y),
        };
        self.y = Some(y);
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RC: AntiAlias = AntiAlias {
        series_ohm: 100.0,
        diff_cap_f: 47.0e-9,
        cm_cap_f: 4.7e-9,
        load_ohm: 330.0e3,
    };

    #[test]
    fn corner_and_dc_gain_by_hand() {
        // k = 330k / 330.2k; tau = (200 || 330k)(47n + 2.35n) = 199.879 * 49.35e-9.
        assert!((RC.dc_gain() - 330.0e3 / 330.2e3).abs() < 1e-15);
        let tau = 200.0 * 330.0e3 / 330.2e3 * 49.35e-9;
        assert!((RC.tau_s() - tau).abs() < 1e-18);
        assert!(
            (RC.relative_gain(RC.corner_hz()) - core::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12
        );
    }

    #[test]
    fn discrete_filter_reaches_63_percent_after_tau() {
        let tau = RC.tau_s();
        let mut f = RC.filter(tau / 1000.0);
        f.step(0.0);
        let mut y = 0.0;
        for _ in 0..1000 {
            y = f.step(1.0);
        }
        assert!(
            (y / RC.dc_gain() - (1.0 - libm::exp(-1.0))).abs() < 1e-9,
            "{y}"
        );
    }
}
