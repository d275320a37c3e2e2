//! The recording's temperature as a regressor for `thermal_drift`: is there a usable `temp_C`,
//! and what warm-up does it show. The drift model then follows the measured temperature,
//! y += amplitude (T - T0) / dT (`sim::effects::ThermalDrift::apply_regressed`), with dT and the
//! time constant taken from the temperature itself: T(t) = T0 + dT (1 - e^{-t/tau}) fitted by
//! linear least squares in (T0, dT) on a log grid of tau.

use sim::effects::ThermalReference;

/// A temperature counts as varying when its range exceeds this many noise deviations ...
const MIN_RANGE_IN_NOISE: f64 = 10.0;
/// ... and this many kelvin (below, an offset change cannot be told from other slow motion).
const MIN_RANGE_C: f64 = 0.1;
/// Time constants tried for the warm-up, s (log grid).
const TAU_MIN_S: f64 = 1.0;
const TAU_MAX_S: f64 = 2000.0;
const TAU_STEPS: usize = 80;

/// The reference of the regression and the warm-up time constant seen in the temperature.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThermalFit {
    pub reference: ThermalReference,
    pub tau_s: f64,
    /// The 95 % profile-likelihood interval of `tau_s` on its grid: every time constant whose
    /// fit of the warm-up leaves n ln(sse) within 3.84 of the best (a chi-square of one degree),
    /// widened to the neighbouring grid values.
    pub tau_ci_s: (f64, f64),
}

/// White-noise deviation from first differences (a slow trend barely contributes).
fn noise_sd(x: &[f64]) -> f64 {
    if x.len() < 3 {
        return 0.0;
    }
    let d2: f64 = x.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum();
    (d2 / (2.0 * (x.len() - 1) as f64)).sqrt()
}

/// Fit the warm-up to `temp_c` (on `t_s`, block means) if the full-rate `temp_full` varies
/// beyond its noise; `None` when there is no usable temperature.
pub fn fit(t_s: &[f64], temp_c: &[f64], temp_full: &[f64]) -> Option<ThermalFit> {
    let (lo, hi) = temp_c
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let range = hi - lo;
    let usable = t_s.len() == temp_c.len()
        && t_s.len() >= 3
        && range.is_finite()
        && range > MIN_RANGE_C
        && range > MIN_RANGE_IN_NOISE * noise_sd(temp_full);
    if !usable {
        return None;
    }
    let t0 = t_s[0];
    let mut best: Option<(f64, f64, f64, f64)> = None; // (sse, tau, a, b)
    let grid =
        |i: usize| TAU_MIN_S * (TAU_MAX_S / TAU_MIN_S).powf(i as f64 / (TAU_STEPS - 1) as f64);
    let mut profile = vec![f64::INFINITY; TAU_STEPS];
    for (i, slot) in profile.iter_mut().enumerate() {
        let tau = grid(i);
        let g: Vec<f64> = t_s.iter().map(|&t| 1.0 - (-(t - t0) / tau).exp()).collect();
        let Some((a, b)) = line_fit(&g, temp_c) else {
            continue;
        };
        let sse: f64 = g
            .iter()
            .zip(temp_c)
            .map(|(g, y)| (y - a - b * g).powi(2))
            .sum();
        *slot = sse;
        if best.is_none_or(|(s, ..)| sse < s) {
            best = Some((sse, tau, a, b));
        }
    }
    let (sse_min, tau_s, a, b) = best?;
    let n = t_s.len() as f64;
    let inside: Vec<usize> = (0..TAU_STEPS)
        .filter(|&i| n * (profile[i] / sse_min.max(1e-300)).ln() <= 3.84)
        .collect();
    let (first, last) = (inside[0], inside[inside.len() - 1]);
    let tau_ci_s = (
        grid(first.saturating_sub(1)),
        grid((last + 1).min(TAU_STEPS - 1)),
    );
    // A temperature that does not warm up (an ambient swing) still defines the scale: its
    // net change, or its range when it comes back.
    let net = temp_c[temp_c.len() - 1] - temp_c[0];
    let rise_c = if b.abs() > 0.2 * range {
        b
    } else if net.abs() > 0.2 * range {
        net
    } else {
        range
    };
    Some(ThermalFit {
        reference: ThermalReference { t0_c: a, rise_c },
        tau_s,
        tau_ci_s,
    })
}

/// Least squares y = a + b x.
fn line_fit(x: &[f64], y: &[f64]) -> Option<(f64, f64)> {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
    if sxx <= 1e-300 {
        return None;
    }
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let b = sxy / sxx;
    Some((my - b * mx, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An exponential warm-up gives back its T0, rise and time constant (grid step 10 %).
    #[test]
    fn warm_up_is_recovered() {
        let t: Vec<f64> = (0..600).map(|k| k as f64 * 0.2).collect();
        let temp: Vec<f64> = t
            .iter()
            .map(|&s| 24.0 + 6.0 * (1.0 - (-s / 40.0).exp()))
            .collect();
        let f = fit(&t, &temp, &temp).unwrap();
        assert!((f.tau_s / 40.0 - 1.0).abs() < 0.06, "{f:?}");
        assert!((f.reference.rise_c - 6.0).abs() < 0.2, "{f:?}");
        assert!((f.reference.t0_c - 24.0).abs() < 0.1, "{f:?}");
    }

    /// A constant or noise-only temperature is no regressor.
    #[test]
    fn flat_temperature_is_not_used() {
        let t: Vec<f64> = (0..600).map(|k| k as f64 * 0.2).collect();
        let noisy: Vec<f64> = (0..600)
            .map(|k| 25.0 + 0.02 * ((k * 7919 % 13) as f64 - 6.0) / 6.0)
            .collect();
        assert_eq!(fit(&t, &vec![25.0; 600], &vec![25.0; 600]), None);
        assert_eq!(fit(&t, &noisy, &noisy), None);
    }
}
