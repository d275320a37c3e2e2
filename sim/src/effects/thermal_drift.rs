//! Warm-up drift of bridge offset: after power-up the chip warms exponentially towards its
//! operating temperature, and the offset follows the temperature linearly:
//! T(t) = T0 + dT (1 - e^{-t/tau}),  y += amplitude (1 - e^{-t/tau}).

/// `amplitude_V`: final offset shift at the output; `tau_s`: warm-up time constant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThermalDrift {
    pub amplitude_v: f64,
    pub tau_s: f64,
}

impl ThermalDrift {
    /// The warm-up fraction 1 - e^{-t/tau} at `t_s` (the shape the temperature follows too).
    pub fn warm_up(&self, t_s: f64) -> f64 {
        1.0 - (-t_s.max(0.0) / self.tau_s.max(1e-6)).exp()
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
}
