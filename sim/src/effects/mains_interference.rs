//! Pickup at mains frequency with its third harmonic (the strongest one from rectifier loads):
//! y += A [sin(2 pi f t) + HARMONIC_3 sin(2 pi 3 f t)].

/// Relative amplitude of the third harmonic.
pub const HARMONIC_3: f64 = 0.3;

/// `freq_hz`: the mains frequency; `amplitude_V`: amplitude of the fundamental.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MainsInterference {
    pub freq_hz: f64,
    pub amplitude_v: f64,
}

impl MainsInterference {
    pub fn at(&self, t_s: f64) -> f64 {
        let w = std::f64::consts::TAU * self.freq_hz * t_s;
        self.amplitude_v * (w.sin() + HARMONIC_3 * (3.0 * w).sin())
    }

    pub fn apply(&self, t_s: &[f64], x: &mut [f64]) {
        for (y, &t) in x.iter_mut().zip(t_s) {
            *y += self.at(t);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Catalogue signature: a narrow spectral line at the mains frequency.
    #[test]
    fn adds_a_line_at_mains_frequency() {
        let t: Vec<f64> = (0..1000).map(|k| k as f64 * 1e-3).collect();
        let mut x = vec![0.0; t.len()];
        MainsInterference {
            freq_hz: 50.0,
            amplitude_v: 0.01,
        }
        .apply(&t, &mut x);
        // Fourier coefficient at 50 Hz over whole periods recovers the amplitude.
        let b: f64 = t
            .iter()
            .zip(&x)
            .map(|(t, x)| x * (std::f64::consts::TAU * 50.0 * t).sin())
            .sum::<f64>()
            * 2.0
            / 1000.0;
        let off: f64 = t
            .iter()
            .zip(&x)
            .map(|(t, x)| x * (std::f64::consts::TAU * 70.0 * t).sin())
            .sum::<f64>()
            * 2.0
            / 1000.0;
        assert!((b - 0.01).abs() < 1e-9 && off.abs() < 1e-9);
    }
}
