//! The recording as the diagnosis sees it: gaps dropped, the four compared channels, a noise
//! estimate per channel, and a block-averaged copy for fitting. The blocks follow the rod's
//! moves and still stretches ([`crate::regimes::motion`]): 20 ms blocks (50 Hz) around the
//! edges of every move, at least [`MOVE_BLOCKS`] blocks along each move (20 ms to 200 ms), and
//! 200 ms blocks (5 Hz) in still stretches away from the edges. A block is never shorter than
//! one sample (10 Hz data keeps every sample where it needs fine blocks) and never straddles the
//! edge of a move. Blocks of whole mains periods also cancel 50 Hz pickup and its harmonics.

use rayon::prelude::*;
use recording::Recording;

use crate::regimes::{self, Regime, Segment};

/// Compared channels, in contract order.
pub const CHANNELS: [&str; 4] = ["load_N", "fz_V", "mx_V", "my_V"];
/// Block length around the edges of moves, and in still stretches.
pub const FINE_BLOCK_S: f64 = 0.02;
pub const COARSE_BLOCK_S: f64 = 0.2;
/// Fine blocks this long before and after each edge of a move, and after its end: the load
/// turns at an edge (contact, reversal, the fast start of a relaxation) within the response
/// times the catalogue fits, fractions of a second to seconds.
const MARGIN_BEFORE_S: f64 = 0.5;
const MARGIN_AFTER_S: f64 = 3.0;
/// Blocks along a move at least: a block mean differs from the curve at its centre by
/// f'' T^2 / 24, a relative 1e-4 of a power-law load over a twentieth of its move.
pub const MOVE_BLOCKS: f64 = 20.0;

/// One rate's worth of the signals.
#[derive(Debug, Clone, Default)]
pub struct Series {
    pub t_s: Vec<f64>,
    pub rod_mm: Vec<f64>,
    /// load_N, fz_V, mx_V, my_V.
    pub y: [Vec<f64>; 4],
    pub temp_c: Option<Vec<f64>>,
    /// Full-rate samples behind each sample (1 at full rate).
    pub count: Vec<usize>,
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
    /// Peak-to-peak range of each recorded channel (the contract's RMSE normaliser).
    pub range: [f64; 4],
    /// White-noise standard deviation of each channel at full rate.
    pub noise_full: [f64; 4],
    /// Lag-1 correlation of that noise (0 for white; the firmware smoother or an anti-alias
    /// filter colour it), modelled as AR(1).
    pub noise_rho: [f64; 4],
    /// The regimes found at the full rate, with the load telling a start in contact, as index
    /// runs on `fit` (its blocks never straddle a segment's edge). Finer than detecting them on
    /// `fit` itself, where block means blur the encoder's quanta.
    pub segments: Vec<Segment>,
    /// [`Data::weight`] of every decimated sample, computed once: every residual of every fit
    /// asks for it, and its `powf` was a sixth of a diagnosis's time.
    weights: [Vec<f64>; 4],
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
    /// The FE-backed fingertip response for the recording's angles and radius failed.
    #[error(transparent)]
    Fingertip(#[from] super::fe_response::FeResponseError),
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
            y: [
                c.load_n.clone(),
                c.fz_v.clone(),
                c.mx_v.clone(),
                c.my_v.clone(),
            ],
            temp_c: rec
                .temp_c
                .clone()
                .filter(|t| t.iter().all(|v| v.is_finite())),
            count: vec![1; c.len()],
        };
        let span = full.t_s[full.len() - 1] - full.t_s[0];
        let rate = if span > 0.0 {
            (full.len() - 1) as f64 / span
        } else {
            rec.meta.sample_rate_hz
        };
        let (_, full_segments) =
            regimes::detect_with_load(&full.t_s, &full.rod_mm, Some(&full.y[0]));
        let (block, cut) = blocks(&full.t_s, &full_segments, rate);
        let bounds = block_bounds(&block, &cut);
        let fit = decimate(&full, &bounds);
        let segments = on_blocks(&full_segments, &bounds);
        let range = std::array::from_fn(|k| peak_to_peak(&full.y[k]));
        // The noise is estimated without a mains line: its second differences are large and
        // strongly correlated, and read as AR(1) noise they weighed a channel down tenfold and
        // could hide it as one carrying no signal. The line itself is fitted later.
        let quiet: Vec<Option<Vec<f64>>> = (0..4)
            .into_par_iter()
            .map(|k| crate::mains::without_line(&full.t_s, &full.y[k], rate))
            .collect();
        let quiet = |k: usize| quiet[k].as_deref().unwrap_or(&full.y[k]);
        let noise_rho: [f64; 4] = std::array::from_fn(|k| noise_correlation(quiet(k)));
        let noise_full: [f64; 4] = std::array::from_fn(|k| {
            // Second differences of AR(1) noise have variance sigma^2 (6 - 8 rho + 2 rho^2).
            let r = noise_rho[k];
            let white = difference_noise(quiet(k)) * (6.0 / (6.0 - 8.0 * r + 2.0 * r * r)).sqrt();
            white.max(1e-6 * range[k]).max(1e-12)
        });
        let weights = std::array::from_fn(|c| {
            fit.count
                .iter()
                .map(|&n| block_weight(n, noise_rho[c], noise_full[c]))
                .collect()
        });
        Ok(Self {
            full,
            fit,
            range,
            noise_full,
            noise_rho,
            segments,
            weights,
        })
    }

    /// Weight of decimated sample `k` of channel `c`: one over its noise level.
    pub fn weight(&self, c: usize, k: usize) -> f64 {
        self.weights[c][k]
    }
}

/// One over the noise level of the mean of `n` samples of AR(1) noise (lag-1 correlation `r`,
/// standard deviation `sigma`).
fn block_weight(n: usize, r: f64, sigma: f64) -> f64 {
    let n = n as f64;
    // Variance of the mean of n AR(1) samples over sigma^2 / n.
    let inflation = if r > 0.0 {
        ((1.0 + r) / (1.0 - r) - 2.0 * r * (1.0 - r.powf(n)) / (n * (1.0 - r).powi(2))).max(1.0)
    } else {
        1.0
    };
    (n / inflation).sqrt() / sigma
}

/// The block length (samples) wanted at each sample, and where a block must end (the edges of
/// the segments).
fn blocks(t_s: &[f64], segments: &[Segment], rate_hz: f64) -> (Vec<usize>, Vec<bool>) {
    let n = t_s.len();
    let samples = |s: f64| ((rate_hz * s).round() as usize).max(1);
    let mut block = vec![samples(COARSE_BLOCK_S); n];
    let mut cut = vec![false; n];
    let finer = |from: f64, to: f64, len: usize, block: &mut Vec<usize>| {
        let a = t_s.partition_point(|&t| t < from);
        let b = t_s.partition_point(|&t| t <= to);
        block[a..b].iter_mut().for_each(|l| *l = (*l).min(len));
    };
    for s in segments {
        cut[s.start] = true;
        if !matches!(s.regime, Regime::Loading | Regime::Release) {
            continue;
        }
        let (t0, t1) = (t_s[s.start], t_s[s.end - 1]);
        // Whole fine blocks (whole mains periods), at most a coarse one.
        let along = ((t1 - t0) / MOVE_BLOCKS / FINE_BLOCK_S).floor().max(1.0) * FINE_BLOCK_S;
        finer(t0, t1, samples(along.min(COARSE_BLOCK_S)), &mut block);
        let fine = samples(FINE_BLOCK_S);
        finer(t0 - MARGIN_BEFORE_S, t0 + MARGIN_BEFORE_S, fine, &mut block);
        finer(t1 - MARGIN_BEFORE_S, t1 + MARGIN_AFTER_S, fine, &mut block);
    }
    (block, cut)
}

/// Blocks `start..end`, each as long as `block` asks at its first sample, ending early where
/// the wanted length changes or at a `cut`.
pub fn block_bounds(block: &[usize], cut: &[bool]) -> Vec<(usize, usize)> {
    let mut bounds = Vec::new();
    let mut k = 0;
    while k < block.len() {
        let mut end = k.saturating_add(block[k].max(1)).min(block.len());
        if let Some(j) = (k + 1..end).find(|&j| block[j] != block[k] || cut[j]) {
            end = j;
        }
        bounds.push((k, end));
        k = end;
    }
    bounds
}

/// `segments` (on the full series) as runs of the blocks `bounds`; each segment starts at a
/// block's start (a cut).
fn on_blocks(segments: &[Segment], bounds: &[(usize, usize)]) -> Vec<Segment> {
    let block_of = |k: usize| bounds.partition_point(|&(a, _)| a < k);
    segments
        .iter()
        .map(|s| Segment {
            start: block_of(s.start),
            end: block_of(s.end),
            ..*s
        })
        .filter(|s| s.end > s.start)
        .collect()
}

/// Block means over `bounds`.
pub fn decimate(s: &Series, bounds: &[(usize, usize)]) -> Series {
    let mean = |x: &[f64]| {
        bounds
            .iter()
            .map(|&(a, b)| x[a..b].iter().sum::<f64>() / (b - a) as f64)
            .collect::<Vec<f64>>()
    };
    Series {
        t_s: mean(&s.t_s),
        rod_mm: mean(&s.rod_mm),
        y: std::array::from_fn(|c| mean(&s.y[c])),
        temp_c: s.temp_c.as_ref().map(|t| mean(t)),
        count: bounds
            .iter()
            .map(|&(a, b)| s.count[a..b].iter().sum())
            .collect(),
    }
}

pub fn peak_to_peak(x: &[f64]) -> f64 {
    let (lo, hi) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    if hi >= lo {
        hi - lo
    } else {
        0.0
    }
}

/// Lag-1 correlation rho of AR(1) noise from second differences, which cancel any signal that
/// is smooth on the sample scale. For AR(1) noise (autocovariance sigma^2 rho^h) the lag-1
/// correlation of `d[k] = e[k] - 2 e[k-1] + e[k-2]` is
/// (-4 + 7 rho - 4 rho^2 + rho^3) / (6 - 8 rho + 2 rho^2), -2/3 for white noise, rising with
/// rho; inverted by bisection. Clamped to [0, 0.99].
pub fn noise_correlation(x: &[f64]) -> f64 {
    if x.len() < 5 {
        return 0.0;
    }
    let d: Vec<f64> = x.windows(3).map(|w| w[2] - 2.0 * w[1] + w[0]).collect();
    let c = super::localise::lag1(&d);
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

/// White-noise level from second differences, which cancel any signal that is smooth on the
/// sample scale: `var(x[k+1] - 2x[k] + x[k-1]) = 6 sigma^2`. The median absolute value (scaled
/// for a normal law) keeps fast transients and clipping from inflating it.
pub fn difference_noise(x: &[f64]) -> f64 {
    if x.len() < 3 {
        return 0.0;
    }
    let mut d: Vec<f64> = x
        .windows(3)
        .map(|w| (w[2] - 2.0 * w[1] + w[0]).abs())
        .collect();
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
        let x: Vec<f64> = (0..50_000)
            .map(|k| (k as f64 * 1e-3).sin() * 5.0 + 0.01 * g.normal())
            .collect();
        let s = difference_noise(&x);
        assert!((s / 0.01 - 1.0).abs() < 0.03, "{s}");
        assert!(noise_correlation(&x) < 0.02);
    }

    /// Blocks over the standard test at `rate_hz`: the bounds, the full-rate segments and the
    /// segments carried onto the blocks.
    fn blocked(rate_hz: f64) -> (Vec<(usize, usize)>, Vec<Segment>, Vec<Segment>) {
        let h = sim::compression::CompressionTest {
            sample_rate_hz: rate_hz,
            ..Default::default()
        }
        .rod_history(&[1.5, 1.0]);
        let (_, full) = regimes::detect(&h.t_s, &h.rod_mm);
        let (block, cut) = blocks(&h.t_s, &full, rate_hz);
        let bounds = block_bounds(&block, &cut);
        let carried = on_blocks(&full, &bounds);
        (bounds, full, carried)
    }

    #[test]
    fn blocks_follow_the_segments_from_10_hz_to_5_khz() {
        for rate in [10.0, 100.0, 1000.0, 5000.0] {
            let (bounds, full, carried) = blocked(rate);
            // Contiguous, never empty, covering everything.
            assert_eq!(bounds[0].0, 0);
            assert!(bounds.windows(2).all(|w| w[0].1 == w[1].0));
            assert!(bounds.iter().all(|&(a, b)| b > a));
            // Every segment survives, in order, on block edges.
            let names = |s: &[Segment]| s.iter().map(|s| (s.regime, s.cycle)).collect::<Vec<_>>();
            assert_eq!(names(&full), names(&carried), "{rate} Hz");
            for (f, c) in full.iter().zip(&carried) {
                assert_eq!(bounds[c.start].0, f.start, "{rate} Hz");
            }
            // Fine blocks (20 ms, at least a sample) in the moves, coarse (200 ms) deep in the
            // recovery, 3 s after the release.
            let len = |k: usize| bounds[k].1 - bounds[k].0;
            let fine = ((rate * FINE_BLOCK_S).round() as usize).max(1);
            let coarse = ((rate * COARSE_BLOCK_S).round() as usize).max(1);
            let release = carried
                .iter()
                .find(|s| s.regime == Regime::Release)
                .unwrap();
            assert!(
                (release.start..release.end).all(|k| len(k) <= fine),
                "{rate} Hz"
            );
            let recovery = carried
                .iter()
                .find(|s| s.regime == Regime::Recovery)
                .unwrap();
            let deep = recovery.start + (recovery.end - recovery.start) / 2;
            assert_eq!(len(deep), coarse, "{rate} Hz");
        }
    }

    #[test]
    fn ar1_correlation_is_recovered() {
        let mut g = super::super::synth::Gaussian::new(4);
        let mut e = 0.0;
        let x: Vec<f64> = (0..100_000)
            .map(|_| {
                e = 0.8 * e + g.normal();
                e
            })
            .collect();
        assert!((noise_correlation(&x) - 0.8).abs() < 0.02);
    }
}
