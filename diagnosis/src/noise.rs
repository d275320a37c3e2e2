//! The noise model behind every weight and the verdict's whiteness test. Per channel, two
//! AR(1) parts:
//! - the sample-scale part, white or coloured over a few samples (the firmware's smoother, an
//!   anti-alias filter), from second differences, which cancel any smooth signal;
//! - a slow part (an amplifier's flicker, a rig's vibration, a drifting supply), which second
//!   differences barely see: its differences are small. It is looked for in the free stretch
//!   at rest before any contact, where nothing but noise moves the channels, and kept only
//!   where it is significant there. Without such a stretch (a start in contact, a real
//!   machine's export) there is nowhere to tell it from the physics, and none is assumed.
//!
//! Mistaking slow noise for white makes every block mean look several times surer than it is,
//! and its residual fail the whiteness test though nothing is missing.

use crate::stats::{erfc, levinson_durbin};

/// Fewest samples of a free stretch to look for slow noise in: the autocovariances then have a
/// standard error of a tenth of the variance or less.
const MIN_FREE: usize = 100;
/// A correlation time is looked for up to a tenth of the free stretch: longer ones leave too
/// few independent stretches to estimate, and a linear detrend takes them for a trend.
const MAX_TAU_SHARE: f64 = 0.1;
/// Correlation times tried, log-spaced from 1.5 samples to the longest allowed.
const TAU_GRID: usize = 40;
/// Family-wise false-alarm rate of the slow part over the grid, as the verdict's own test.
const SLOW_P: f64 = 1e-3;

/// One AR(1) part: standard deviation and lag-1 correlation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ar1 {
    pub sd: f64,
    pub rho: f64,
}

/// A channel's noise: the sample-scale part and, where seen, a slow part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Noise {
    pub sample: Ar1,
    pub slow: Option<Ar1>,
    /// Samples the slow part was read from (its free stretch; 0 without one).
    pub slow_samples: usize,
    /// Where no slow part is significant, the one that fits the free stretch best: the stretch
    /// cannot tell it from none (a few seconds at 50 Hz hold too few correlation times to find
    /// a 0.1 s noise as strong as the white). Only the verdict's set of noises uses it.
    pub unresolved: Option<Ar1>,
}

impl Ar1 {
    /// Covariance of two sums of `m` consecutive samples, `lag` sums apart: for lag 0,
    /// sd^2 (m (1 + rho) / (1 - rho) - 2 rho (1 - rho^m) / (1 - rho)^2); for lag h > 0,
    /// sd^2 rho^((h - 1) m + 1) (1 - rho^m)^2 / (1 - rho)^2.
    pub fn sum_covariance(&self, m: usize, lag: usize) -> f64 {
        let (r, mf, v) = (
            self.rho.clamp(0.0, 0.999_999),
            m.max(1) as f64,
            self.sd.powi(2),
        );
        let tail = 1.0 - r.powf(mf);
        if lag == 0 {
            v * (mf * (1.0 + r) / (1.0 - r) - 2.0 * r * tail / (1.0 - r).powi(2)).max(mf)
        } else {
            v * r.powf((lag - 1) as f64 * mf + 1.0) * tail * tail / (1.0 - r).powi(2)
        }
    }
}

impl Ar1 {
    /// Variance of sum_k c_k mean_k, mean_k the mean of the samples `blocks[k]` (disjoint, in
    /// time order). For k before j the means covary by sd^2 g_k g_j rho^(a_j - b_k + 1), with
    /// g = (1 - rho^n) / ((1 - rho) n): separable, so the double sum runs in one pass, carrying
    /// E_j = sum over k < j of c_k g_k rho^(a_j - b_k + 1) from one block's start to the next.
    fn block_means_variance(&self, blocks: &[(usize, usize)], c: &[f64]) -> f64 {
        let r = self.rho.clamp(0.0, 0.999_999);
        let g = |n: f64| (1.0 - r.powf(n)) / ((1.0 - r) * n);
        let (mut variance, mut carried) = (0.0, 0.0);
        for (k, (&(a, b), &ck)) in blocks.iter().zip(c).enumerate() {
            let n = (b - a).max(1);
            let gk = g(n as f64);
            variance += ck * ck * self.sum_covariance(n, 0) / (n * n) as f64
                + 2.0 * self.sd.powi(2) * ck * gk * carried;
            if let Some(&(next, _)) = blocks.get(k + 1) {
                carried = carried * r.powf(next.saturating_sub(a) as f64)
                    + ck * gk * r.powf((next + 1).saturating_sub(b) as f64);
            }
        }
        variance
    }
}

impl Noise {
    /// Variance of sum_k c_k mean_k over the means of the disjoint samples `blocks[k]`, in
    /// time order: what a smooth difference between two models' predictions is worth against
    /// slow noise, which moves neighbouring block means together.
    pub fn block_means_variance(&self, blocks: &[(usize, usize)], c: &[f64]) -> f64 {
        self.sample.block_means_variance(blocks, c)
            + self.slow.map_or(0.0, |s| s.block_means_variance(blocks, c))
    }

    /// The noise of a channel (a mains line already out): `pieces` the stretches to read the
    /// sample-scale part from, `free` its stretch at rest before contact (may be empty).
    pub fn estimate(pieces: &[&[f64]], free: &[f64]) -> Self {
        let d: Vec<f64> = pieces.iter().flat_map(|x| second_differences(x)).collect();
        let white = median_sd(&mut d.clone());
        let rho = difference_correlation(&d, white);
        // Second differences of AR(1) noise have variance sd^2 (6 - 8 rho + 2 rho^2).
        let sd = white * (6.0 / (6.0 - 8.0 * rho + 2.0 * rho * rho)).sqrt();
        let sample = Ar1 { sd, rho };
        let (slow, unresolved) = match slow_part(free, sample) {
            Some((part, true)) => (Some(part), None),
            Some((part, false)) => (None, Some(part)),
            None => (None, None),
        };
        Self {
            sample,
            slow,
            slow_samples: free.len(),
            unresolved,
        }
    }

    /// This noise and the others the free stretch cannot tell from it: the slow part's
    /// deviation and correlation time each times e^(-2 se), 1 or e^(2 se), with se = sqrt(2 tau
    /// / n) the relative standard error of either from n samples (an AR(1) coefficient's
    /// variance is (1 - phi^2) / n ~ 2 / (tau n), and tau's relative error follows; the
    /// variance's likewise). A few seconds at rest hold some twenty correlation times, so both
    /// are known to about a third; this whole set is the noise model's answer, not its middle.
    /// Where the slow part is [`Noise::unresolved`], none at all is as plausible, and comes first.
    pub fn plausible(&self) -> Vec<Noise> {
        let Some(slow) = self
            .slow
            .or(self.unresolved)
            .filter(|_| self.slow_samples > 0)
        else {
            return vec![*self];
        };
        let tau = -1.0 / slow.rho.clamp(1e-12, 0.999_999).ln();
        let se = (2.0 * tau / self.slow_samples as f64).sqrt().min(1.0);
        let factors = [(-2.0 * se).exp(), 1.0, (2.0 * se).exp()];
        let mut out = Vec::with_capacity(10);
        if self.slow.is_none() {
            out.push(*self);
        }
        for a in factors {
            for b in factors {
                out.push(Noise {
                    slow: Some(Ar1 {
                        sd: slow.sd * a,
                        rho: (-1.0 / (tau * b)).exp(),
                    }),
                    ..*self
                });
            }
        }
        out
    }

    /// The sample-scale standard deviation.
    pub fn sd(&self) -> f64 {
        self.sample.sd
    }

    /// Covariance of two sums of `m` consecutive samples, `lag` sums apart.
    pub fn sum_covariance(&self, m: usize, lag: usize) -> f64 {
        self.sample.sum_covariance(m, lag) + self.slow.map_or(0.0, |s| s.sum_covariance(m, lag))
    }

    /// Standard deviation of the mean of `n` consecutive samples.
    pub fn mean_sd(&self, n: usize) -> f64 {
        self.sum_covariance(n, 0).sqrt() / n.max(1) as f64
    }
}

/// The slow AR(1) part in `free` beyond what `sample` explains, if significant. The stretch is
/// detrended (a drift is not noise); its autocovariances at log-spaced lags, less the sample
/// part's, are fitted by s^2 times what a unit AR(1) part's would be after the same detrending
/// ([`detrended_ar1_autocovariance`]), over a grid of correlation times. The part is kept where
/// s^2 exceeds its standard error (Bartlett: var gamma(h) ~ gamma(0)^2 / n at every lag) at a
/// family-wise `SLOW_P` over the grid. Returned with whether it is (the best fit either way).
fn slow_part(free: &[f64], sample: Ar1) -> Option<(Ar1, bool)> {
    let n = free.len();
    let max_lag = (n as f64 * MAX_TAU_SHARE) as usize;
    if n < MIN_FREE || max_lag < 2 {
        return None;
    }
    let x = detrended(free);
    let gamma0 = x.iter().map(|v| v * v).sum::<f64>() / n as f64;
    let mut lags: Vec<usize> = (0..64)
        .map(|k| (1.25f64.powi(k)).round() as usize)
        .take_while(|&h| h <= max_lag)
        .collect();
    lags.dedup();
    let excess: Vec<f64> = lags
        .iter()
        .map(|&h| autocovariance(&x, h) - sample.sd.powi(2) * sample.rho.powi(h as i32))
        .collect();
    let mut best: Option<(f64, Ar1, f64)> = None;
    for k in 0..TAU_GRID {
        let tau = 1.5 * (max_lag as f64 / 1.5).powf(k as f64 / (TAU_GRID - 1) as f64);
        let phi = (-1.0 / tau).exp();
        let basis = detrended_ar1_autocovariance(n, phi, &lags);
        let bb: f64 = basis.iter().map(|b| b * b).sum();
        let s2 = basis.iter().zip(&excess).map(|(b, g)| b * g).sum::<f64>() / bb;
        if s2 <= 0.0 {
            continue;
        }
        let sse: f64 = basis
            .iter()
            .zip(&excess)
            .map(|(b, g)| (g - s2 * b).powi(2))
            .sum();
        let z = s2 * (n as f64 * bb).sqrt() / gamma0;
        if best.as_ref().is_none_or(|b| sse < b.0) {
            best = Some((
                sse,
                Ar1 {
                    sd: s2.sqrt(),
                    rho: phi,
                },
                z,
            ));
        }
    }
    let (_, slow, z) = best?;
    Some((
        slow,
        0.5 * erfc(z / std::f64::consts::SQRT_2) < SLOW_P / TAU_GRID as f64,
    ))
}

/// The expected [`autocovariance`] at each of `lags` of `n` samples of a unit-variance AR(1)
/// series (lag-1 correlation `phi`) after [`detrended`]. The line takes a share of a slow part's
/// variance out at every lag, and the estimate divides by n: fitted by phi^h instead, a 0.1 s
/// noise over a 2 s stretch came out at 0.05 s and four fifths of its size, and its whitening
/// left a lag-1 correlation of 0.24 between bins. With x~ = (I - H) x, H = Q Q^T the projection
/// on [1, t] (Q orthonormal) and Sigma the AR(1) covariance, the sum over t of
/// E[x~_t x~_(t+h)] is that of (Sigma - H Sigma - Sigma H + H Sigma H)_(t, t+h), each term a
/// pass over Q and V = Sigma Q.
fn detrended_ar1_autocovariance(n: usize, phi: f64, lags: &[usize]) -> Vec<f64> {
    let nf = n as f64;
    let mid = (nf - 1.0) / 2.0;
    let sxx: f64 = (0..n)
        .map(|t| (t as f64 - mid).powi(2))
        .sum::<f64>()
        .max(1e-300);
    let q = [
        vec![1.0 / nf.sqrt(); n],
        (0..n)
            .map(|t| (t as f64 - mid) / sxx.sqrt())
            .collect::<Vec<f64>>(),
    ];
    let v = [ar1_times(phi, &q[0]), ar1_times(phi, &q[1])];
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let g = [
        [dot(&q[0], &v[0]), dot(&q[0], &v[1])],
        [dot(&q[1], &v[0]), dot(&q[1], &v[1])],
    ];
    lags.iter()
        .map(|&h| {
            let m = n.saturating_sub(h);
            let mut sum = m as f64 * phi.powi(h as i32);
            for t in 0..m {
                for k in 0..2 {
                    sum -= q[k][t] * v[k][t + h] + v[k][t] * q[k][t + h];
                    sum += q[k][t] * (g[k][0] * q[0][t + h] + g[k][1] * q[1][t + h]);
                }
            }
            sum / nf
        })
        .collect()
}

/// Sigma x for the unit AR(1) covariance Sigma_ij = phi^|i - j|: a forward and a backward pass.
fn ar1_times(phi: f64, x: &[f64]) -> Vec<f64> {
    let mut forward = vec![0.0; x.len()];
    let mut carried = 0.0;
    for (f, &v) in forward.iter_mut().zip(x) {
        carried = v + phi * carried;
        *f = carried;
    }
    let mut out = forward;
    carried = 0.0;
    for (o, &v) in out.iter_mut().zip(x).rev() {
        carried = v + phi * carried;
        *o += carried - v;
    }
    out
}

/// `x` less its least-squares line in the sample index.
fn detrended(x: &[f64]) -> Vec<f64> {
    let n = x.len() as f64;
    let mid = (n - 1.0) / 2.0;
    let mean = x.iter().sum::<f64>() / n;
    let sxx: f64 = (0..x.len()).map(|k| (k as f64 - mid).powi(2)).sum();
    let sxy: f64 = x
        .iter()
        .enumerate()
        .map(|(k, v)| (k as f64 - mid) * (v - mean))
        .sum();
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    x.iter()
        .enumerate()
        .map(|(k, v)| v - mean - slope * (k as f64 - mid))
        .collect()
}

/// Autocovariance at lag `h` of a zero-mean series (divided by its length: the estimate
/// Bartlett's standard error is for).
fn autocovariance(x: &[f64], h: usize) -> f64 {
    if h >= x.len() {
        return 0.0;
    }
    x[h..].iter().zip(x).map(|(a, b)| a * b).sum::<f64>() / x.len() as f64
}

/// `r`, sums of `m` samples of `noise` (one value per sum), with the correlation that noise
/// alone gives the sums taken out: the sums' autocovariances under the model, to lag `order`,
/// give the best linear predictor of each sum from the `order` before it (Levinson–Durbin),
/// and the prediction errors are white where `r` is that noise. A misfit the noise cannot make
/// stays structured.
pub fn prewhitened(r: &[f64], noise: &Noise, m: usize, order: usize) -> Vec<f64> {
    let c: Vec<f64> = (0..=order).map(|h| noise.sum_covariance(m, h)).collect();
    let (a, _) = levinson_durbin(&c);
    (0..r.len())
        .map(|k| {
            let past: f64 = a
                .iter()
                .enumerate()
                .take(k)
                .map(|(j, aj)| aj * r[k - 1 - j])
                .sum();
            r[k] - past
        })
        .collect()
}

/// Lag-1 correlation rho of AR(1) noise from second differences, which cancel any signal that
/// is smooth on the sample scale. For AR(1) noise (autocovariance sigma^2 rho^h) the lag-1
/// correlation of `d[k] = e[k] - 2 e[k-1] + e[k-2]` is
/// (-4 + 7 rho - 4 rho^2 + rho^3) / (6 - 8 rho + 2 rho^2), -2/3 for white noise, rising with
/// rho; inverted by bisection. Clamped to [0, 0.99]. The noise model reads it from second
/// differences it already has; the tests ask it of a series.
#[cfg(test)]
pub(crate) fn ar1_rho(x: &[f64]) -> f64 {
    let d = second_differences(x);
    let white = median_sd(&mut d.clone());
    difference_correlation(&d, white)
}

fn second_differences(x: &[f64]) -> Vec<f64> {
    x.windows(3).map(|w| w[2] - 2.0 * w[1] + w[0]).collect()
}

/// The AR(1) lag-1 correlation from the second differences `d`, whose white-noise level ([`median_sd`]) is
/// `white`.
fn difference_correlation(d: &[f64], white: f64) -> f64 {
    if d.len() < 3 {
        return 0.0;
    }
    let c = trimmed_lag1(d, OUTLIER_SDS * white * 6f64.sqrt());
    let model = |r: f64| (-4.0 + 7.0 * r - 4.0 * r * r + r * r * r) / (6.0 - 8.0 * r + 2.0 * r * r);
    let (mut lo, mut hi) = (0.0, 0.99);
    if c <= model(lo) {
        return 0.0;
    }
    if c >= model(hi) {
        return hi;
    }
    for _ in 0..50 {
        let mid = 0.5 * (lo + hi);
        if model(mid) < c {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Second differences beyond this many of their robust deviations are a signal's kinks (a
/// ramp's end, a spike), not noise: one in 1.7 million normal values lies beyond it.
const OUTLIER_SDS: f64 = 5.0;

/// Lag-1 autocorrelation of `d` over the neighbouring pairs both within `limit` (all where
/// `limit` is zero). A ramp's end inside a still piece adds one large second difference; it
/// inflated the variance, pulled the correlation from -2/3 towards 0, and white noise at 10 Hz
/// read as rho = 0.7.
fn trimmed_lag1(d: &[f64], limit: f64) -> f64 {
    let inside = |v: f64| limit <= 0.0 || v.abs() <= limit;
    let kept: Vec<f64> = d.iter().copied().filter(|&v| inside(v)).collect();
    if kept.len() < 3 {
        return 0.0;
    }
    let mean = kept.iter().sum::<f64>() / kept.len() as f64;
    let c0: f64 = kept.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / kept.len() as f64;
    let pairs: Vec<f64> = d
        .windows(2)
        .filter(|w| inside(w[0]) && inside(w[1]))
        .map(|w| (w[0] - mean) * (w[1] - mean))
        .collect();
    if c0 > 0.0 && !pairs.is_empty() {
        pairs.iter().sum::<f64>() / pairs.len() as f64 / c0
    } else {
        0.0
    }
}

/// White-noise level from second differences, which cancel any signal that is smooth on the
/// sample scale: `var(x[k+1] - 2x[k] + x[k-1]) = 6 sigma^2`. The median absolute value (scaled
/// for a normal law) keeps fast transients and clipping from inflating it.
pub fn difference_noise(x: &[f64]) -> f64 {
    median_sd(&mut second_differences(x))
}

/// The deviation of normal values `d` from their median absolute value, over sqrt(6): the
/// white-noise level behind second differences. Takes `d` as scratch (made absolute, reordered).
fn median_sd(d: &mut [f64]) -> f64 {
    if d.is_empty() {
        return 0.0;
    }
    d.iter_mut().for_each(|v| *v = v.abs());
    let median = match crate::quantisation::Lattice::of(d) {
        Some(lattice) => grouped_median(d, lattice.quantum),
        None => {
            let mid = d.len() / 2;
            *d.select_nth_unstable_by(mid, f64::total_cmp).1
        }
    };
    median / 0.674_489_75 / 6f64.sqrt()
}

/// The median of non-negative values `a` that sit on multiples of `q`, each read as spread
/// evenly over its class (j q - q / 2, j q + q / 2), the lowest from 0 (the median of grouped
/// data). A plain median takes only lattice values: second differences of a load read to 0.05 N
/// over 0.02 N of noise gave 0.030 N where the deviation was 0.024 N, and the same 0.030 N up to
/// 0.030 N. Where the median is in the lowest class, nothing is read into it.
fn grouped_median(a: &mut [f64], q: f64) -> f64 {
    let class = |v: f64| (v / q).round().max(0.0);
    let mid = a.len() / 2;
    let j = class(*a.select_nth_unstable_by(mid, f64::total_cmp).1);
    if j == 0.0 {
        // Most values repeat exactly: a series smooth on the lattice (a ramp read in whole
        // steps) or a noise well below the quantum, which the values cannot resolve (the
        // callers then take the quantum's own floor).
        return 0.0;
    }
    let below = a.iter().filter(|&&v| class(v) < j).count() as f64;
    let within = a.iter().filter(|&&v| class(v) == j).count().max(1) as f64;
    let (lo, hi) = ((j - 0.5).max(0.0) * q, (j + 0.5) * q);
    lo + ((a.len() as f64 / 2.0 - below) / within).clamp(0.0, 1.0) * (hi - lo)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quantisation::quantum;

    /// The slow part read from 2000 samples at tau = 50 is known to sqrt(2 * 50 / 2000) = 0.22
    /// in ln: the plausible noises span e^(+-0.45) in its deviation and time, the middle one
    /// being the estimate; without a slow part there is only the estimate.
    #[test]
    fn plausible_noises_span_the_slow_parts_uncertainty() {
        let noise = Noise {
            sample: Ar1 { sd: 1.0, rho: 0.0 },
            slow: Some(Ar1 {
                sd: 2.0,
                rho: (-1.0f64 / 50.0).exp(),
            }),
            slow_samples: 2000,
            unresolved: None,
        };
        let all = noise.plausible();
        assert_eq!(all.len(), 9);
        let middle = all[4].slow.unwrap();
        assert!(
            (middle.sd - 2.0).abs() < 1e-12 && (middle.rho - noise.slow.unwrap().rho).abs() < 1e-12
        );
        let taus: Vec<f64> = all
            .iter()
            .map(|n| -1.0 / n.slow.unwrap().rho.ln())
            .collect();
        let (lo, hi) = taus
            .iter()
            .fold((f64::MAX, 0.0f64), |(l, h), &t| (l.min(t), h.max(t)));
        let span = 2.0 * (2.0 * 50.0 / 2000.0f64).sqrt();
        assert!((lo - 50.0 * (-span).exp()).abs() < 1e-6 && (hi - 50.0 * span.exp()).abs() < 1e-6);
        let white = Noise {
            slow: None,
            ..noise
        };
        assert_eq!(white.plausible(), vec![white]);
        // A slow part the stretch could not resolve: none, then the same span around it.
        let unresolved = Noise {
            slow: None,
            unresolved: noise.slow,
            ..noise
        };
        let all = unresolved.plausible();
        assert_eq!(all.len(), 10);
        assert_eq!(all[0], unresolved);
        assert_eq!(all[5].slow, noise.slow);
    }

    /// A load read to 0.05 N steps has that quantum, whatever its offset; a continuous one none
    /// worth the name.
    #[test]
    fn quantum_is_the_smallest_step() {
        let mut g = baseline::synth::Gaussian::new(3);
        let steps: Vec<f64> = (0..500)
            .map(|k| 12.3 + 0.05 * ((k as f64 * 0.01).sin() * 10.0 + 0.4 * g.normal()).round())
            .collect();
        assert!((quantum(&steps) - 0.05).abs() < 1e-9, "{}", quantum(&steps));
        let smooth: Vec<f64> = (0..500).map(|_| 0.02 * g.normal()).collect();
        assert!(quantum(&smooth) < 1e-3);
        assert_eq!(quantum(&[1.0; 10]), 0.0);
    }

    /// The detrended AR(1) autocovariance against the mean of many simulated detrended series,
    /// and a slow part's correlation time recovered without the detrending's bias: a 0.1 s
    /// noise at 2 kHz over 2 s (tau 200 of 4000 samples) had come out near half of it.
    #[test]
    fn detrending_is_modelled_in_the_slow_part() {
        let (n, phi, lags) = (400, 0.95, [1usize, 5, 20, 40]);
        let expected = detrended_ar1_autocovariance(n, phi, &lags);
        let mut g = Gaussian::new(8);
        let mut mean = [0.0; 4];
        let runs = 4000;
        for _ in 0..runs {
            let mut e = g.normal();
            let x: Vec<f64> = (0..n)
                .map(|_| {
                    e = phi * e + (1.0 - phi * phi).sqrt() * g.normal();
                    e
                })
                .collect();
            let d = detrended(&x);
            for (m, &h) in mean.iter_mut().zip(&lags) {
                *m += autocovariance(&d, h) / runs as f64;
            }
        }
        for ((m, e), h) in mean.iter().zip(&expected).zip(lags) {
            assert!((m - e).abs() < 0.02, "lag {h}: {m} vs {e}");
            assert!(
                *e < phi.powi(h as i32) - 0.05,
                "the detrending's bias is there"
            );
        }
        let taus: Vec<f64> = (0..20)
            .filter_map(|_| {
                let free = mixed(&mut g, 4000, 1.0, 1.0, 200.0);
                let slow = Noise::estimate(&[&free], &free).slow?;
                Some(-1.0 / slow.rho.ln())
            })
            .collect();
        let mean_tau = taus.iter().sum::<f64>() / taus.len() as f64;
        assert!(
            taus.len() >= 18 && (150.0..260.0).contains(&mean_tau),
            "{taus:?}"
        );
    }

    /// The one-pass variance of a weighted sum of block means against the double sum of the
    /// samples' AR(1) covariances, on blocks of uneven length with gaps between them.
    #[test]
    fn block_means_variance_matches_the_double_sum() {
        let noise = Noise {
            sample: Ar1 { sd: 1.5, rho: 0.3 },
            slow: Some(Ar1 { sd: 0.7, rho: 0.95 }),
            slow_samples: 0,
            unresolved: None,
        };
        let blocks = [(0, 5), (5, 17), (20, 21), (30, 42)];
        let c = [0.4, -1.0, 2.0, 0.3];
        let cov = |i: usize, j: usize| {
            let h = i.abs_diff(j) as i32;
            [noise.sample, noise.slow.unwrap()]
                .iter()
                .map(|p| p.sd * p.sd * p.rho.powi(h))
                .sum::<f64>()
        };
        let mut direct = 0.0;
        for (&(a, b), &ca) in blocks.iter().zip(&c) {
            for (&(p, q), &cp) in blocks.iter().zip(&c) {
                let (na, np) = ((b - a) as f64, (q - p) as f64);
                for i in a..b {
                    for j in p..q {
                        direct += ca * cp * cov(i, j) / (na * np);
                    }
                }
            }
        }
        let fast = noise.block_means_variance(&blocks, &c);
        assert!((fast - direct).abs() < 1e-9 * direct, "{fast} vs {direct}");
    }
    use crate::stats::ljung_box;
    use baseline::synth::Gaussian;

    /// White noise of deviation `white` plus AR(1) noise of deviation `slow` and correlation
    /// time `tau` samples.
    fn mixed(g: &mut Gaussian, n: usize, white: f64, slow: f64, tau: f64) -> Vec<f64> {
        let rho = (-1.0 / tau).exp();
        let mut s = slow * g.normal();
        (0..n)
            .map(|_| {
                s = rho * s + slow * (1.0 - rho * rho).sqrt() * g.normal();
                white * g.normal() + s
            })
            .collect()
    }

    #[test]
    fn difference_noise_recovers_sigma_under_a_slow_signal() {
        let mut g = Gaussian::new(3);
        let x: Vec<f64> = (0..50_000)
            .map(|k| (k as f64 * 1e-3).sin() * 5.0 + 0.01 * g.normal())
            .collect();
        let s = difference_noise(&x);
        assert!((s / 0.01 - 1.0).abs() < 0.03, "{s}");
        assert!(ar1_rho(&x) < 0.02);
    }

    #[test]
    fn ar1_correlation_is_recovered() {
        let mut g = Gaussian::new(4);
        let mut e = 0.0;
        let x: Vec<f64> = (0..100_000)
            .map(|_| {
                e = 0.8 * e + g.normal();
                e
            })
            .collect();
        assert!((ar1_rho(&x) - 0.8).abs() < 0.02);
    }

    /// The closed forms against the double sum of sd^2 rho^|i - j|.
    #[test]
    fn sum_covariances_follow_the_double_sum() {
        let part = Ar1 { sd: 1.3, rho: 0.7 };
        let m = 6;
        for lag in 0..4 {
            let brute: f64 = (0..m)
                .flat_map(|i| (0..m).map(move |j| (i as i32 - (j + lag * m) as i32).abs()))
                .map(|d| 1.69 * 0.7f64.powi(d))
                .sum();
            let closed = part.sum_covariance(m, lag);
            assert!(
                (closed - brute).abs() < 1e-9 * brute,
                "lag {lag}: {closed} {brute}"
            );
        }
    }

    /// A slow part as large as the white noise (correlation 50 samples) is found in 1750 free
    /// samples under a drift, near its size and time. White noise under the same drift shows one
    /// at the test's family-wise 1e-3 (found 1 in 3000 when measured), so in at most 2 of 300
    /// stretches here.
    #[test]
    fn slow_noise_is_found_in_a_free_stretch_and_only_there() {
        let mut g = Gaussian::new(11);
        let drift = |x: Vec<f64>| -> Vec<f64> {
            x.iter()
                .enumerate()
                .map(|(k, v)| v + 3e-3 * k as f64)
                .collect()
        };
        let free = drift(mixed(&mut g, 1750, 1.0, 1.0, 50.0));
        let noise = Noise::estimate(&[&free], &free);
        let slow = noise.slow.expect("a slow part");
        let tau = -1.0 / slow.rho.ln();
        assert!((slow.sd - 1.0).abs() < 0.35, "{slow:?}");
        assert!((20.0..120.0).contains(&tau), "{tau}");
        assert!((noise.sd() - 1.0).abs() < 0.1, "{noise:?}");
        let false_alarms = (0..300)
            .filter(|_| {
                let white = drift(mixed(&mut g, 1750, 1.0, 0.0, 50.0));
                Noise::estimate(&[&white], &white).slow.is_some()
            })
            .count();
        assert!(false_alarms <= 2, "{false_alarms} of 300");
        assert_eq!(
            Noise::estimate(&[&free], &free[..50]).slow,
            None,
            "too short"
        );
    }

    /// Sums of 100 samples of white-plus-slow noise are correlated themselves and fail a
    /// whiteness test; with the model's colour taken out they pass it, while a slow swing of
    /// three deviations still fails. With one sample per sum, plain AR(1) is whitened by its own
    /// coefficient.
    #[test]
    fn coloured_sums_are_white_once_the_models_colour_is_out() {
        let (m, lags) = (100, 20);
        let mut g = Gaussian::new(4);
        let x = mixed(&mut g, 2000 * m, 1.0, 1.0, 50.0);
        let sums: Vec<f64> = x.chunks(m).map(|c| c.iter().sum()).collect();
        let noise = Noise {
            sample: Ar1 { sd: 1.0, rho: 0.0 },
            slow: Some(Ar1 {
                sd: 1.0,
                rho: (-1.0f64 / 50.0).exp(),
            }),
            slow_samples: 0,
            unresolved: None,
        };
        assert!(ljung_box(&sums, lags).1 < 1e-3);
        assert!(ljung_box(&prewhitened(&sums, &noise, m, lags), lags).1 > 0.01);
        let sd = noise.sum_covariance(m, 0).sqrt();
        let swing: Vec<f64> = sums
            .iter()
            .enumerate()
            .map(|(k, v)| v + 3.0 * sd * (k as f64 * std::f64::consts::TAU / 100.0).sin())
            .collect();
        assert!(ljung_box(&prewhitened(&swing, &noise, m, lags), lags).1 < 1e-3);
        let ar1 = Noise {
            sample: Ar1 { sd: 1.0, rho: 0.5 },
            slow: None,
            slow_samples: 0,
            unresolved: None,
        };
        let e = prewhitened(&[1.0, 2.0], &ar1, 1, lags);
        assert!((e[1] - 1.5).abs() < 1e-12, "{e:?}");
    }

    #[test]
    fn a_quantised_noise_is_read_between_its_quanta() {
        // A load read to 0.05 N over 0.0192 N of noise at many levels: its deviation is
        // sqrt(0.0192^2 + 0.05^2 / 12) = 0.024 N. A plain median of the second differences takes
        // a lattice value and reads 0.030 N.
        let mut g = baseline::synth::Gaussian::new(3);
        let (q, sigma) = (0.05, 0.0192);
        let x: Vec<f64> = (0..100_000)
            .map(|i| ((0.013 * (i / 2000) as f64 + sigma * g.normal()) / q).round() * q)
            .collect();
        let sd = difference_noise(&x);
        assert!((sd - 0.024).abs() < 0.0015, "{sd}");
    }

    /// A ramp's ends inside a still piece are single large second differences; they must not
    /// read as correlated noise (white noise at 10 Hz with kinks had read as rho = 0.7).
    #[test]
    fn kinks_do_not_colour_white_noise() {
        let mut g = baseline::synth::Gaussian::new(8);
        let n = 3000;
        let mut slope = 0.0;
        let mut level = 0.0;
        let x: Vec<f64> = (0..n)
            .map(|i| {
                if i % 150 == 75 {
                    slope = if slope == 0.0 { 40.0 } else { 0.0 };
                }
                level += slope;
                level + g.normal()
            })
            .collect();
        let noise = Noise::estimate(&[&x], &[]);
        assert!(noise.sample.rho < 0.1, "{:?}", noise.sample);
        assert!((noise.sample.sd - 1.0).abs() < 0.1, "{:?}", noise.sample);
    }
}
