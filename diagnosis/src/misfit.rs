//! How far a model is from the recording: the contract's RMSE (`docs/diagnosis-format.md`) and
//! whether the residual is white (noise) on the time scales the models describe.
use baseline::Outputs;

use crate::data::Data;
use crate::fit::Setup;
use crate::{localise, noise, stats};

/// Lags of the whiteness tests (Ljung–Box for the baseline's residual, the verdict's
/// autoregression), and the Ljung–Box p-value below which a residual is structured.
pub(crate) const LB_LAGS: usize = 20;
pub(crate) const LB_P: f64 = 1e-3;

/// Whether the model `m` (its channels on the decimated series) leaves a white residual on
/// every compared channel.
///
/// Each compared channel's residual, with the noise's own colour taken out (coloured noise is
/// not a mismatch), is structured where it fails both of two tests: a portmanteau test at a
/// family-wise LB_P over the channels (Bonferroni), and the evidence an effect needs for an
/// autoregression of it (`stats::ar_evidence`). The first alone took a model's
/// approximations at a ten-thousandth of the range, spread over many lags, for a mismatch; the
/// second alone, a lag-1 correlation that whitening with a slightly wrong slow noise leaves.
/// And it must fail them under every noise the free stretch allows (`Noise::plausible`):
/// a slow part read from a few seconds is known to a third, and whitening with its middle
/// left bins correlated by +-0.25 in both directions on coloured noise alone. A channel read
/// to a quantum coarser than its noise first has its rounding bias taken out (`quantisation`):
/// a held value keeps its own bias, which no amount of averaging removes. Isolated outlying
/// bins (a spike is one bin at 10 Hz) are not structure in time and are set aside. A residual
/// whose RMS stays below [`RESOLUTION_FLOOR`] of the channel's range (a noiseless channel the
/// model reproduces: a simulation's load cell) is white: no measurement could show it.
pub(crate) fn white(setup: &Setup, m: &[Vec<f64>; 4]) -> bool {
    let data = setup.data;
    let compared = setup.used.iter().filter(|u| **u).count().max(1);
    let bin = data.fit.count.iter().copied().max().unwrap_or(1);
    (0..4).filter(|&c| setup.used[c]).all(|c| {
        let r = data.residual_without_rounding_bias(c, &m[c]);
        let rms = (r.iter().map(|v| v * v).sum::<f64>() / r.len().max(1) as f64).sqrt();
        if rms < RESOLUTION_FLOOR * data.range[c] || (data.noiseless[c] && rms < data.noise[c].sd())
        {
            return true;
        }
        let r = localise::without_isolated_outliers(&weighted(data, c, &r), LB_P);
        !data.noise[c].plausible().iter().all(|noise| {
            let e = noise::prewhitened(&r, noise, bin, LB_LAGS);
            let significant = stats::ljung_box(&e, LB_LAGS).1 <= LB_P / compared as f64;
            significant && stats::ar_evidence(&e, LB_LAGS).0 > crate::candidate::MIN_BIC_GAIN
        })
    })
}

/// One part in 2^24 of a channel's recorded range: a 24-bit converter's resolution, finer than
/// anything this chain records. A baseline whose residual stays below it (the baseline's own
/// recording from `tactile simulate` without noise) leaves nothing a measurement could show;
/// its whitened residual is then the arithmetic's error, structured but not physics.
pub(crate) const RESOLUTION_FLOOR: f64 = 1.0 / 16_777_216.0;

/// Residual re-binned to the coarse block length (fine blocks summed in groups), each bin the
/// sum over its samples divided by the noise model's deviation of such a sum: whiteness is
/// judged on the time scales the models describe, and noise coloured on the scale of a few
/// samples (smoother, anti-alias filter) does not count as structure. Normalised by the whole
/// bin's noise, not block by block: under slow noise, fine blocks' weights would make a bin in
/// a move several times as variable as one at rest, and a whiteness test over bins of unequal
/// variance rejects too often.
pub(crate) fn weighted(data: &Data, c: usize, r: &[f64]) -> Vec<f64> {
    let target = data.fit.count.iter().copied().max().unwrap_or(1);
    let mut out = Vec::new();
    let (mut sum, mut count) = (0.0, 0usize);
    for (v, &n) in r.iter().zip(&data.fit.count) {
        sum += v * n as f64;
        count += n;
        if count >= target {
            out.push(sum / data.noise[c].sum_covariance(count, 0).sqrt());
            (sum, count) = (0.0, 0);
        }
    }
    out
}

pub(crate) fn diff(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

/// Mean over the compared channels of RMS residual / recorded peak-to-peak range.
pub(crate) fn contract_rmse(data: &Data, o: &Outputs, mask: &[bool]) -> f64 {
    let used: Vec<usize> = (0..4).filter(|&c| data.compared(c)).collect();
    used.iter()
        .map(|&c| channel_rmse(data, o, c, mask))
        .sum::<f64>()
        / used.len().max(1) as f64
}

pub(crate) fn channel_rmse(data: &Data, o: &Outputs, c: usize, mask: &[bool]) -> f64 {
    let y = &data.full.y[c];
    let m = o.channel(c);
    let (mut s, mut n) = (0.0, 0usize);
    for k in 0..y.len() {
        if mask[k] {
            s += (y[k] - m[k]).powi(2);
            n += 1;
        }
    }
    (s / n.max(1) as f64).sqrt() / data.range[c].max(1e-300)
}
