//! The recording as the diagnosis sees it: gaps dropped, the four compared channels, a noise
//! estimate per channel, and a block-averaged copy at about 50 Hz for fitting slow dynamics
//! (block averaging over 20 ms also cancels 50 Hz mains and its harmonics exactly).

use crate::recording::Recording;

/// Compared channels, in contract order.
pub const CHANNELS: [&str; 4] = ["load_N", "fz_V", "mx_V", "my_V"];
/// Target rate of the decimated copy.
pub const FIT_RATE_HZ: f64 = 50.0;

/// One rate's worth of the signals.
#[derive(Debug, Clone, Default)]
pub struct Series {
    pub t_s: Vec<f64>,
    pub rod_mm: Vec<f64>,
    /// load_N, fz_V, mx_V, my_V.
    pub y: [Vec<f64>; 4],
    pub temp_c: Option<Vec<f64>>,
}

impl Series {
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }
}

/// Both rates plus per-channel scales.
#[derive(Debug, Clone)]
pub struct Data {
    pub full: Series,
    pub fit: Series,
    /// Samples per block of the decimated copy.
    pub block: usize,
    /// Peak-to-peak range of each recorded channel (the contract's RMSE normaliser).
    pub range: [f64; 4],
    /// White-noise standard deviation of each channel at full rate.
    pub noise_full: [f64; 4],
    /// The same after block averaging.
    pub noise_fit: [f64; 4],
}

/// Why a recording cannot be analysed although it parsed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DataError {
    /// Fewer usable rows than a fit needs.
    #[error("only {0} rows without gaps; the diagnosis needs at least 200")]
    TooShort(usize),
    /// The rod never presses into the fingertip.
    #[error("column `rod_mm` never rises above 0: no compression in this recording")]
    NoContact,
}

impl Data {
    pub fn new(rec: &Recording) -> Result<Self, DataError> {
        let rec = rec.without_gaps();
        let c = &rec.channels;
        if c.len() < 200 {
            return Err(DataError::TooShort(c.len()));
        }
        if !c.rod_mm.iter().any(|&r| r > 0.0) {
            return Err(DataError::NoContact);
        }
        let full = Series {
            t_s: c.t_s.clone(),
            rod_mm: c.rod_mm.clone(),
            y: [c.load_n.clone(), c.fz_v.clone(), c.mx_v.clone(), c.my_v.clone()],
            temp_c: rec.temp_c.clone().filter(|t| t.iter().all(|v| v.is_finite())),
        };
        let span = full.t_s[full.len() - 1] - full.t_s[0];
        let rate = if span > 0.0 { (full.len() - 1) as f64 / span } else { rec.meta.sample_rate_hz };
        let block = ((rate / FIT_RATE_HZ).round() as usize).max(1);
        let fit = decimate(&full, block);
        let range = std::array::from_fn(|k| peak_to_peak(&full.y[k]));
        let noise_full: [f64; 4] = std::array::from_fn(|k| difference_noise(&full.y[k]).max(1e-6 * range[k]).max(1e-12));
        let noise_fit = std::array::from_fn(|k| noise_full[k] / (block as f64).sqrt());
        Ok(Self { full, fit, block, range, noise_full, noise_fit })
    }
}

fn block_mean(x: &[f64], block: usize) -> Vec<f64> {
    x.chunks(block).map(|c| c.iter().sum::<f64>() / c.len() as f64).collect()
}

/// Block means (the last, shorter block included).
pub fn decimate(s: &Series, block: usize) -> Series {
    Series {
        t_s: block_mean(&s.t_s, block),
        rod_mm: block_mean(&s.rod_mm, block),
        y: std::array::from_fn(|k| block_mean(&s.y[k], block)),
        temp_c: s.temp_c.as_ref().map(|t| block_mean(t, block)),
    }
}

pub fn peak_to_peak(x: &[f64]) -> f64 {
    let (lo, hi) = x.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| (l.min(v), h.max(v)));
    if hi >= lo { hi - lo } else { 0.0 }
}

/// White-noise level from second differences, which cancel any signal that is smooth on the
/// sample scale: var(x[k+1] - 2x[k] + x[k-1]) = 6 sigma^2. The median absolute value (scaled
/// for a normal law) keeps fast transients and clipping from inflating it.
pub fn difference_noise(x: &[f64]) -> f64 {
    if x.len() < 3 {
        return 0.0;
    }
    let mut d: Vec<f64> = x.windows(3).map(|w| (w[2] - 2.0 * w[1] + w[0]).abs()).collect();
    let mid = d.len() / 2;
    let (_, median, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
    *median / 0.674_489_75 / 6f64.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn difference_noise_recovers_sigma_under_a_slow_signal() {
        let mut g = super::super::synth::Gaussian::new(3);
        let x: Vec<f64> = (0..50_000).map(|k| (k as f64 * 1e-3).sin() * 5.0 + 0.01 * g.next()).collect();
        let s = difference_noise(&x);
        assert!((s / 0.01 - 1.0).abs() < 0.03, "{s}");
    }
}
