//! The bias a coarse quantum leaves in a mean. A channel read to a quantum q (an ADC's LSB, a
//! machine export's last digit) over a noise of deviation sigma before rounding has the mean
//! reading E[Q(x + e)] = x + b(x), and b does not average down: it is a periodic function of
//! the true value x, of period q, whose harmonic k has the amplitude
//! `A_k = q / (pi k) exp(-2 pi^2 k^2 sigma^2 / q^2)` (Widrow and Kollár, *Quantization Noise*,
//! 2008: the characteristic function of the noise at the lattice's frequencies). At sigma >= q
//! it is below 1e-9 q; at sigma = q / 3 it is 0.4 % of q, which a few hundred samples a bin
//! lift above the bins' noise. The noise model has no term for it: a value held for a second
//! keeps its own b(x), and a residual that is white otherwise fails the whiteness test.
//!
//! The verdict therefore takes out of each quantised channel's final residual its
//! least-squares fit on those harmonics at the model's values: a bias the noise is known to
//! carry, at a phase the lattice fixes, not missing physics.

use nalgebra::{DMatrix, DVector};

/// A value is on the lattice where it is within this share of a quantum of a lattice point
/// (decimal exports print 0.15 as 0.15000000000000002).
const ON_LATTICE: f64 = 1e-6;
/// Share of the values that must sit on the lattice for the channel to count as quantised.
const LATTICE_SHARE: f64 = 0.99;
/// Most harmonics taken: a noise-free sawtooth's tenth is a tenth of its first.
const MAX_HARMONICS: usize = 10;

/// Differences in `x` below this are floating-point rounding of its values, not steps.
pub fn rounding(x: &[f64]) -> f64 {
    let (lo, hi) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    1e-9 * (hi - lo).max(hi.abs()).max(lo.abs())
}

/// The quantum of a series: the smallest step between neighbouring samples beyond rounding
/// (an encoder's count, an ADC's LSB, a machine export's last digit); 0 without a step.
pub fn quantum(x: &[f64]) -> f64 {
    let floor = rounding(x);
    let q = x
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .filter(|&d| d > floor)
        .fold(f64::INFINITY, f64::min);
    if q.is_finite() {
        q
    } else {
        0.0
    }
}

/// The lattice a channel's values sit on: `origin + n quantum`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lattice {
    pub quantum: f64,
    pub origin: f64,
}

impl Lattice {
    /// The lattice of `x`, if nearly all its values sit on one whose quantum is the smallest
    /// step between neighbours ([`crate::quantisation::quantum`]); `None` for a channel of real values.
    pub fn of(x: &[f64]) -> Option<Self> {
        let quantum = quantum(x);
        let first = *x.first()?;
        if quantum <= 0.0 || !quantum.is_finite() {
            return None;
        }
        let origin = first - quantum * (first / quantum).floor();
        let lattice = Self { quantum, origin };
        let on = x
            .iter()
            .filter(|&&v| lattice.offset(v).abs() < ON_LATTICE)
            .count();
        (on as f64 >= LATTICE_SHARE * x.len() as f64).then_some(lattice)
    }

    /// Where `v` sits between lattice points, in quanta from the nearest (-0.5..0.5).
    fn offset(&self, v: f64) -> f64 {
        let u = (v - self.origin) / self.quantum;
        u - u.round()
    }

    /// The noise before rounding behind a total deviation `sd`: rounding adds q^2 / 12 to the
    /// variance of a noise at least as wide as the quantum (and no less is claimed below it).
    pub fn noise_before_rounding(&self, sd: f64) -> f64 {
        (sd * sd - self.quantum * self.quantum / 12.0)
            .max(0.0)
            .sqrt()
    }

    /// `A_k`, the amplitude of harmonic `k` of the mean rounding error under a Gaussian noise
    /// of deviation `sigma` before rounding.
    pub fn bias_amplitude(&self, k: usize, sigma: f64) -> f64 {
        let (q, kf) = (self.quantum, k as f64);
        let pi = std::f64::consts::PI;
        q / (pi * kf) * (-2.0 * (pi * kf * sigma / q).powi(2)).exp()
    }

    /// Harmonics worth taking out of `bins` bins of deviation `bin_sd`: those whose bias,
    /// projected on its own unit regressor (amplitude times sqrt(bins / 2)), would reach one
    /// bin deviation. Below that it is lost in the noise whether taken out or not.
    pub fn harmonics(&self, sigma: f64, bin_sd: f64, bins: usize) -> usize {
        (1..=MAX_HARMONICS)
            .take_while(|&k| self.bias_amplitude(k, sigma) * (bins as f64 / 2.0).sqrt() >= bin_sd)
            .count()
            .min(bins / 4)
    }
}

/// `r` less its weighted least-squares fit on the first `harmonics` harmonics of the rounding
/// bias at the model's values `model` (one per block), each block sweeping `sweep` of the
/// value while it is read: a mean over a sweep of width w attenuates harmonic k by
/// sinc(k w / q). `weight` is each block's weight (its sample count under white noise).
pub fn without_rounding_bias(
    r: &[f64],
    model: &[f64],
    sweep: &[f64],
    weight: &[f64],
    lattice: &Lattice,
    harmonics: usize,
) -> Vec<f64> {
    if harmonics == 0 || r.len() <= 2 * harmonics {
        return r.to_vec();
    }
    let q = lattice.quantum;
    let tau = std::f64::consts::TAU;
    let design = DMatrix::from_fn(r.len(), 2 * harmonics, |i, j| {
        let k = (j / 2 + 1) as f64;
        let phase = tau * k * (model[i] - lattice.origin) / q;
        let wave = if j % 2 == 0 { phase.sin() } else { phase.cos() };
        wave * sinc(k * sweep[i] / q) * weight[i].sqrt()
    });
    let target = DVector::from_iterator(r.len(), r.iter().zip(weight).map(|(v, w)| v * w.sqrt()));
    let Ok(coef) = design.clone().svd(true, true).solve(&target, 1e-12) else {
        return r.to_vec();
    };
    let fitted = &design * coef;
    r.iter()
        .zip(weight)
        .zip(fitted.iter())
        .map(|((v, w), f)| v - f / w.sqrt().max(f64::MIN_POSITIVE))
        .collect()
}

/// sin(pi z) / (pi z), the mean of a unit harmonic over a sweep of z periods.
fn sinc(z: f64) -> f64 {
    let x = std::f64::consts::PI * z;
    if x.abs() < 1e-9 {
        1.0
    } else {
        x.sin() / x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use baseline::synth::Gaussian;

    #[test]
    fn a_lattice_is_found_only_where_the_values_sit_on_one() {
        let on: Vec<f64> = (0..500).map(|i| 0.02 + 0.05 * ((i % 37) as f64)).collect();
        let l = Lattice::of(&on).expect("a lattice");
        assert!(
            (l.quantum - 0.05).abs() < 1e-12 && (l.origin - 0.02).abs() < 1e-9,
            "{l:?}"
        );
        let real: Vec<f64> = (0..500).map(|i| (i as f64 * 0.37).sin()).collect();
        assert_eq!(Lattice::of(&real), None);
        assert_eq!(Lattice::of(&[1.0; 50]), None);
    }

    #[test]
    fn the_mean_rounding_error_follows_the_characteristic_function() {
        // Monte Carlo mean of round(x + e) - x against the first harmonics' closed form.
        let l = Lattice {
            quantum: 1.0,
            origin: 0.0,
        };
        let mut g = Gaussian::new(5);
        let sigma = 0.25;
        for x in [0.1, 0.25, 0.4] {
            let n = 200_000;
            let mean = (0..n)
                .map(|_| (x + sigma * g.normal()).round() - x)
                .sum::<f64>()
                / n as f64;
            // round(u) - u = sum_k (-1)^k sin(2 pi k u) / (pi k), the sawtooth's series.
            let closed: f64 = (1..=6)
                .map(|k| {
                    let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
                    sign * l.bias_amplitude(k, sigma) * (std::f64::consts::TAU * k as f64 * x).sin()
                })
                .sum();
            assert!((mean - closed).abs() < 3e-3, "x {x}: {mean} vs {closed}");
        }
    }

    #[test]
    fn the_bias_is_taken_out_and_a_smooth_mismatch_is_left() {
        // Held values read through a coarse quantum: each hold keeps its own bias. Taking the
        // harmonics out leaves the bins near their noise; a slow sway beside it stays.
        let l = Lattice {
            quantum: 0.05,
            origin: 0.0,
        };
        let sigma = 0.015;
        let mut g = Gaussian::new(9);
        let (bins, per) = (300, 400);
        let model: Vec<f64> = (0..bins).map(|i| 1.0 + 0.0137 * (i / 10) as f64).collect();
        let sway: Vec<f64> = (0..bins).map(|i| 2e-3 * (i as f64 / 40.0).sin()).collect();
        let read = |x: f64| (x / l.quantum).round() * l.quantum;
        let mut residual = |with_sway: bool| -> Vec<f64> {
            (0..bins)
                .map(|i| {
                    let x = model[i] + if with_sway { sway[i] } else { 0.0 };
                    (0..per).map(|_| read(x + sigma * g.normal())).sum::<f64>() / per as f64
                        - model[i]
                })
                .collect()
        };
        let flat = vec![0.0; bins];
        let weight = vec![per as f64; bins];
        let bin_sd = (sigma * sigma + l.quantum.powi(2) / 12.0).sqrt() / (per as f64).sqrt();
        let h = l.harmonics(sigma, bin_sd, bins);
        assert!(h >= 1, "{h}");
        let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
        let before = residual(false);
        let after = without_rounding_bias(&before, &model, &flat, &weight, &l, h);
        assert!(rms(&before) > 2.0 * bin_sd, "{} vs {bin_sd}", rms(&before));
        assert!(rms(&after) < 1.3 * bin_sd, "{} vs {bin_sd}", rms(&after));
        let swayed = without_rounding_bias(&residual(true), &model, &flat, &weight, &l, h);
        let left: f64 = swayed.iter().zip(&sway).map(|(a, s)| a * s).sum::<f64>()
            / sway.iter().map(|s| s * s).sum::<f64>();
        assert!((left - 1.0).abs() < 0.2, "sway kept at {left}");
    }

    #[test]
    fn no_harmonic_is_taken_where_the_noise_dithers_the_quantum() {
        let l = Lattice {
            quantum: 0.01,
            origin: 0.0,
        };
        assert_eq!(l.harmonics(0.02, 1e-3, 1000), 0);
        assert!(l.harmonics(0.0, 1e-4, 1000) >= 5);
    }
}
