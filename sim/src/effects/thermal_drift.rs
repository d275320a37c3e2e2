//! Warm-up drift of bridge offset: after power-up the chip warms exponentially towards its
//! operating temperature, and the offset follows the temperature linearly:
//! T(t) = T0 + dT (1 - e^{-t/tau}),  y += amplitude (1 - e^{-t/tau}).
//! Where the temperature is measured (`temp_C`), the same law is a regression on it,
//! y += amplitude (T(t) - T0) / dT ([`ThermalDrift::apply_regressed`]), which also follows an
//! ambient that does not warm up exponentially.

/// `amplitude_V`: final offset shift at the output; `tau_s`: warm-up time constant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThermalDrift {
    pub amplitude_v: f64,
    pub tau_s: f64,
}

/// What a drift regressed on temperature refers to: the temperature at power-up `t0_c` and the
/// warm-up rise `rise_c` (non-zero) over which the offset moves by `amplitude_v`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThermalReference {
    pub t0_c: f64,
    pub rise_c: f64,
}

impl ThermalDrift {
    /// The warm-up fraction 1 - e^{-t/tau} at `t_s` (the shape the temperature follows too).
    pub fn warm_up(&self, t_s: f64) -> f64 {
        1.0 - (-t_s.max(0.0) / self.tau_s.max(1e-6)).exp()
    }

    /// The offset regressed on a measured temperature `temp_c`: amplitude (T - T0) / dT, so
    /// `amplitude_v` keeps its meaning (the shift over the warm-up rise dT).
    pub fn apply_regressed(&self, temp_c: &[f64], reference: ThermalReference, x: &mut [f64]) {
        let per_c = self.amplitude_v / reference.rise_c;
        for (y, &t) in x.iter_mut().zip(temp_c) {
            *y += per_c * (t - reference.t0_c);
        }
    }

    pub fn apply(&self, t_s: &[f64], x: &mut [f64]) {
        for (y, &t) in x.iter_mut().zip(t_s) {
            *y += self.amplitude_v * self.warm_up(t);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Catalogue signature: slow baseline motion present at rest, unrelated to load.
    #[test]
    fn moves_the_baseline_at_rest() {
        let t: Vec<f64> = (0..=600).map(|k| k as f64 * 0.1).collect();
        let mut x = vec![0.0; t.len()];
        ThermalDrift {
            amplitude_v: 0.05,
            tau_s: 20.0,
        }
        .apply(&t, &mut x);
        assert!((x[200] - 0.05 * (1.0 - (-1.0f64).exp())).abs() < 1e-12);
        assert!(x.windows(2).all(|w| w[1] >= w[0]));
    }

    /// On an exponential warm-up the regression on temperature is the warm-up law itself; on
    /// any other temperature history the offset follows the temperature.
    #[test]
    fn regression_on_temperature() {
        let d = ThermalDrift {
            amplitude_v: 0.05,
            tau_s: 20.0,
        };
        let r = ThermalReference {
            t0_c: 25.0,
            rise_c: 4.0,
        };
        let t: Vec<f64> = (0..=600).map(|k| k as f64 * 0.1).collect();
        let warm: Vec<f64> = t.iter().map(|&s| 25.0 + 4.0 * d.warm_up(s)).collect();
        let (mut a, mut b) = (vec![0.0; t.len()], vec![0.0; t.len()]);
        d.apply(&t, &mut a);
        d.apply_regressed(&warm, r, &mut b);
        assert!(a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12));
        let mut c = vec![0.0; 2];
        d.apply_regressed(&[23.0, 27.0], r, &mut c);
        assert_eq!(c, vec![-0.025, 0.025]);
    }
}
