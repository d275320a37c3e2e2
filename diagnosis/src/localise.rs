//! Where the baseline misses: per channel and regime window the residual's share, whiteness
//! (Ljung–Box), correlation with candidate drivers, and a lag estimate.

use serde::Serialize;

use super::regimes::Segment;
use crate::stats::erfc;

/// A window where the baseline misses (contract field `mismatches`).
#[derive(Debug, Clone, Serialize)]
pub struct Mismatch {
    pub channel: &'static str,
    pub t_start_s: f64,
    pub t_end_s: f64,
    pub regime: &'static str,
    /// RMS residual inside the window, in the channel's unit.
    pub rms: f64,
    /// Share of the total squared (range-normalised) residual inside the window.
    pub share: f64,
}

/// Per-channel and per-regime-window shares of `residual[c]` (decimated), worst first, keeping
/// windows that hold at least `min_share`.
pub fn mismatches(
    t_s: &[f64],
    segments: &[Segment],
    residual: &[Vec<f64>; 4],
    range: &[f64; 4],
    used: &[bool; 4],
    min_share: f64,
) -> Vec<Mismatch> {
    let norm = |c: usize, v: f64| (v / range[c].max(1e-300)).powi(2);
    let total: f64 = (0..4)
        .filter(|&c| used[c])
        .map(|c| residual[c].iter().map(|&v| norm(c, v)).sum::<f64>())
        .sum();
    if total <= 0.0 {
        return Vec::new();
    }
    let mut out = Vec::new();
    for c in (0..4).filter(|&c| used[c]) {
        for s in segments {
            let r = &residual[c][s.start..s.end];
            let share = r.iter().map(|&v| norm(c, v)).sum::<f64>() / total;
            if share >= min_share {
                let rms = (r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt();
                let t_end_s = t_s[(s.end).min(t_s.len() - 1)];
                out.push(Mismatch {
                    channel: super::data::CHANNELS[c],
                    t_start_s: t_s[s.start],
                    t_end_s,
                    regime: s.regime.name(),
                    rms,
                    share,
                });
            }
        }
    }
    out.sort_by(|a, b| b.share.total_cmp(&a.share));
    out
}

/// `e` with its isolated outliers set to its median: values beyond the level that `e.len()`
/// independent normal values, on `e`'s own robust scale (1.4826 times the median absolute
/// deviation), all stay within with probability 1 - `p` (Bonferroni), whose neighbours both
/// stay within it. At a low rate a loose connector's spike is one bin, and a portmanteau test
/// read eight of them as autocorrelation (10 Hz: an AR(15) gain of 21). Structure in time
/// spans neighbouring bins, and stays.
pub fn without_isolated_outliers(e: &[f64], p: f64) -> Vec<f64> {
    let n = e.len();
    if n < 3 {
        return e.to_vec();
    }
    let median = |v: &mut Vec<f64>| {
        let mid = v.len() / 2;
        *v.select_nth_unstable_by(mid, f64::total_cmp).1
    };
    let centre = median(&mut e.to_vec());
    let scale = 1.4826 * median(&mut e.iter().map(|v| (v - centre).abs()).collect());
    if scale <= 0.0 {
        return e.to_vec();
    }
    // Two-sided normal tail p / n, by bisection on erfc (monotone).
    let (mut lo, mut hi) = (0.0f64, 40.0f64);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if erfc(mid / std::f64::consts::SQRT_2) > p / n as f64 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let out_of = |i: usize| ((e[i] - centre) / scale).abs() > hi;
    (0..n)
        .map(|i| {
            let isolated = (i == 0 || !out_of(i - 1)) && (i + 1 == n || !out_of(i + 1));
            if out_of(i) && isolated {
                centre
            } else {
                e[i]
            }
        })
        .collect()
}

/// Lag (s) that best explains `residual` as lag x d(model)/dt with the sign of a sensor that
/// lags: recorded(t) = model(t - lag) gives residual = -lag model'(t).
pub fn lag_estimate(t_s: &[f64], model: &[f64], residual: &[f64]) -> f64 {
    let n = t_s.len();
    let (mut num, mut den) = (0.0, 0.0);
    for k in 1..n.saturating_sub(1) {
        let dt = t_s[k + 1] - t_s[k - 1];
        if dt <= 0.0 {
            continue;
        }
        let d = (model[k + 1] - model[k - 1]) / dt;
        num += -residual[k] * d;
        den += d * d;
    }
    if den > 0.0 {
        num / den
    } else {
        0.0
    }
}

/// Per-channel localisation beyond the windows.
#[derive(Debug, Clone, Serialize)]
pub struct ChannelLocalisation {
    pub channel: &'static str,
    pub ljung_box_q: f64,
    pub ljung_box_p: f64,
    pub white: bool,
    pub corr_load: f64,
    pub corr_load_squared: f64,
    pub corr_dload_dt: f64,
    pub corr_temperature: Option<f64>,
    /// Correlation with the other channels' residuals, in contract order.
    pub corr_other_residuals: Vec<(String, f64)>,
    pub lag_estimate_s: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lag_estimate_recovers_a_shift() {
        let t: Vec<f64> = (0..2000).map(|k| k as f64 * 0.01).collect();
        let model: Vec<f64> = t.iter().map(|t| (0.5 * t).sin()).collect();
        let rec: Vec<f64> = t.iter().map(|t| (0.5 * (t - 0.04)).sin()).collect();
        let r: Vec<f64> = rec.iter().zip(&model).map(|(a, b)| a - b).collect();
        assert!((lag_estimate(&t, &model, &r) - 0.04).abs() < 1e-3);
    }

    #[test]
    fn isolated_outliers_go_and_a_run_of_them_stays() {
        let mut g = baseline::synth::Gaussian::new(4);
        let mut e: Vec<f64> = (0..800).map(|_| g.normal()).collect();
        let clean = e.clone();
        for (i, size) in [(100, 30.0), (300, -20.0), (555, 45.0)] {
            e[i] += size;
        }
        // A bump over five neighbouring bins, each beyond the level: structure, kept.
        for v in &mut e[700..705] {
            *v += 8.0;
        }
        let out = without_isolated_outliers(&e, 1e-3);
        for i in [100, 300, 555] {
            assert!(out[i].abs() < 1.0, "{i}: {}", out[i]);
        }
        assert_eq!(&out[700..705], &e[700..705]);
        // White noise alone is left as it is.
        assert_eq!(without_isolated_outliers(&clean, 1e-3), clean);
    }
}
