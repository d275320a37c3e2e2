//! What the decoded stream should be: codes to ADC-input volts (SPEC), and the firmware's filters
//! redone in f64 from their textbook definitions (first-order smoother; Butterworth low-pass as
//! bilinear-transformed, prewarped second-order sections), so a slip in the firmware's DSP shows
//! as a difference from the sim's ground truth passed through this reference.

use protocol::{FilterConfig, Info};

/// Volts at the ADC input of bridge channel `ch` for `code`, with the reference and PGA gain the
/// device reports (SPEC: `code · vref / (pga · 2²³)`).
pub fn code_to_v(info: &Info, ch: usize, code: i32) -> f64 {
    let vref_v = f64::from(info.vref_mv) / 1000.0;
    protocol::codes::code_to_volts(code, vref_v, u32::from(info.pga_gain[ch]))
}

/// One second-order low-pass section in f64, transposed direct form II.
#[derive(Debug, Clone, Copy)]
struct Section {
    b: [f64; 3],
    a: [f64; 2],
    s: [f64; 2],
}

impl Section {
    /// H(s) = 1 / (s² + s/Q + 1) under the bilinear transform with K = tan(π f_c / f_s).
    fn low_pass(k: f64, q: f64) -> Self {
        let d = 1.0 + k / q + k * k;
        let b0 = k * k / d;
        Self {
            b: [b0, 2.0 * b0, b0],
            a: [2.0 * (k * k - 1.0) / d, (1.0 - k / q + k * k) / d],
            s: [0.0; 2],
        }
    }

    /// Steady state for a constant input `x` (unity DC gain).
    fn prime(&mut self, x: f64) {
        let s1 = (self.b[2] - self.a[1]) * x;
        self.s = [(self.b[1] - self.a[0]) * x + s1, s1];
    }

    fn step(&mut self, x: f64) -> f64 {
        let y = self.b[0] * x + self.s[0];
        self.s[0] = self.b[1] * x - self.a[0] * y + self.s[1];
        self.s[1] = self.b[2] * x - self.a[1] * y;
        y
    }
}

/// The smoother then the Butterworth cascade, primed by the first sample (the firmware's
/// documented behaviour after every (re)configuration).
#[derive(Debug, Clone)]
pub struct ReferenceFilter {
    alpha: f64,
    smoothed: f64,
    sections: Vec<Section>,
    primed: bool,
}

impl ReferenceFilter {
    pub fn new(config: &FilterConfig, rate_hz: f64) -> Self {
        let order = usize::from(config.butterworth_order);
        let k = (std::f64::consts::PI * f64::from(config.cutoff_hz) / rate_hz).tan();
        let sections = (0..order / 2)
            .map(|i| {
                let theta = (2.0 * i as f64 + 1.0) * std::f64::consts::PI / (2.0 * order as f64);
                Section::low_pass(k, 1.0 / (2.0 * theta.cos()))
            })
            .collect();
        Self {
            alpha: f64::from(config.smoother_alpha),
            smoothed: 0.0,
            sections,
            primed: false,
        }
    }

    pub fn step(&mut self, x: f64) -> f64 {
        if !self.primed {
            self.smoothed = x;
            self.sections.iter_mut().for_each(|s| s.prime(x));
            self.primed = true;
        }
        self.smoothed += self.alpha * (x - self.smoothed);
        self.sections
            .iter_mut()
            .fold(self.smoothed, |y, s| s.step(y))
    }

    /// Noise gain sqrt(Σ h\[n\]²): white noise of rms σ leaves the filter with rms σ times this.
    pub fn noise_gain(config: &FilterConfig, rate_hz: f64) -> f64 {
        let mut f = Self::new(config, rate_hz);
        f.step(0.0);
        let mut sum = 0.0;
        let mut x = 1.0;
        for _ in 0..(20.0 * rate_hz) as usize {
            let y = f.step(x);
            sum += y * y;
            x = 0.0;
        }
        sum.sqrt()
    }
}

/// Running error statistics of one channel.
#[derive(Debug, Clone, Copy, Default)]
pub struct ErrorStats {
    pub n: u64,
    pub sum2: f64,
    pub max_abs: f64,
}

impl ErrorStats {
    pub fn add(&mut self, e: f64) {
        self.n += 1;
        self.sum2 += e * e;
        self.max_abs = self.max_abs.max(e.abs());
    }

    pub fn rms(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            (self.sum2 / self.n as f64).sqrt()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn butterworth_reference_is_3_db_down_at_the_cutoff_and_unity_at_dc() {
        // A sine at f_c after the transient: amplitude 1/sqrt(2) (prewarped bilinear design).
        for order in [2u8, 4] {
            let cfg = FilterConfig {
                smoother_alpha: 1.0,
                butterworth_order: order,
                cutoff_hz: 50.0,
            };
            let mut f = ReferenceFilter::new(&cfg, 1000.0);
            let mut peak: f64 = 0.0;
            for n in 0..4000 {
                let y = f.step((2.0 * std::f64::consts::PI * 50.0 * n as f64 / 1000.0).sin());
                if n > 2000 {
                    peak = peak.max(y.abs());
                }
            }
            assert!(
                (peak - std::f64::consts::FRAC_1_SQRT_2).abs() < 2e-3,
                "order {order}: {peak}"
            );
            let mut f = ReferenceFilter::new(&cfg, 1000.0);
            f.step(0.0);
            let dc = (0..2000).map(|_| f.step(1.0)).last().unwrap();
            assert!((dc - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn smoother_noise_gain_is_sqrt_alpha_over_two_minus_alpha() {
        // y = a x + (1-a) y: h[n] = a (1-a)^n, sum h^2 = a^2 / (1 - (1-a)^2) = a / (2 - a).
        let cfg = FilterConfig {
            smoother_alpha: 0.1,
            butterworth_order: 0,
            cutoff_hz: 0.0,
        };
        let g = ReferenceFilter::noise_gain(&cfg, 1000.0);
        // The filter runs with the wire's f32 alpha, 0.1f32 = 0.100000001490116.
        let a = f64::from(cfg.smoother_alpha);
        assert!((g - (a / (2.0 - a)).sqrt()).abs() < 1e-9, "{g}");
    }
}
