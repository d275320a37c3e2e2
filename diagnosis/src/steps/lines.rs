//! Lines in a model's residual at the full rate: the mains line (and its third harmonic) on
//! the outputs and on the load cell, and lines faster than the decimated series shows, each
//! kept where it passes both tests (the criterion on the fitting stretch, the held-out
//! stretch).
use baseline::Outputs;

use crate::candidate::{heldout_needed, MIN_BIC_GAIN};
use crate::data::Data;
use crate::fit::Setup;
use crate::mains::{self, Line};
use crate::misfit::diff;
use crate::terms;

/// The outputs' channels, where the mains line was first looked for, and the load cell's.
pub(crate) const OUTPUTS: [usize; 3] = [1, 2, 3];
pub(crate) const LOAD_CELL: [usize; 1] = [0];

pub(crate) fn line_in_residual(
    data: &Data,
    o: &Outputs,
    mask: &[bool],
    chans: &[usize],
) -> Option<Line> {
    if chans.is_empty() {
        return None;
    }
    let res: Vec<Vec<f64>> = chans
        .iter()
        .map(|&c| diff(&data.full.y[c], o.channel(c)))
        .collect();
    let refs: Vec<&[f64]> = res.iter().map(|r| r.as_slice()).collect();
    mains::find_line(&data.full.t_s, &refs, mask, data.rate_hz)
}

/// Outputs plus the fitted line on the channels `chans` it was fitted on (full rate).
pub(crate) fn add_line(data: &Data, o: &Outputs, line: Option<&Line>, chans: &[usize]) -> Outputs {
    let mut out = o.clone();
    if let Some(l) = line {
        let harmonic = l.coef[0][2] != 0.0 || l.coef[0][3] != 0.0;
        for (b, &c) in chans.iter().enumerate() {
            let values = if c == 0 {
                &mut out.load_n
            } else {
                &mut out.volts[c - 1]
            };
            for (v, &t) in values.iter_mut().zip(&data.full.t_s) {
                *v += l.at(b, t, harmonic);
            }
        }
    }
    out
}

/// The line counts if it is prominent and removing it helps on the fitting stretch and on the
/// held-out stretch, both in noise units.
pub(crate) fn mains_helps(
    data: &Data,
    o: &Outputs,
    line: &Line,
    masks: (&[bool], &[bool]),
    chans: &[usize],
) -> bool {
    line_evidence(data, o, line, masks, chans).is_some()
}

/// The line's BIC gain and held-out chi-square ratio against the model without it, where it
/// is prominent and passes both tests.
fn line_evidence(
    data: &Data,
    o: &Outputs,
    line: &Line,
    (fit, heldout): (&[bool], &[bool]),
    chans: &[usize],
) -> Option<(f64, f64)> {
    if line.prominence < mains::MIN_LINE_PROMINENCE {
        return None;
    }
    let with = add_line(data, o, Some(line), chans);
    let chi2 = |m: &Outputs, mask: &[bool]| -> f64 {
        chans
            .iter()
            .map(|&c| {
                let w = 1.0 / data.noise[c].sd();
                (0..data.full.len())
                    .filter(|&k| mask[k])
                    .map(|k| ((data.full.y[c][k] - m.channel(c)[k]) * w).powi(2))
                    .sum::<f64>()
            })
            .sum()
    };
    let (f0, f1) = (chi2(o, fit), chi2(&with, fit));
    let (h0, h1) = (chi2(o, heldout), chi2(&with, heldout));
    // The two models differ by the line itself: its norm on the held-out stretch.
    let diff = chans
        .iter()
        .map(|&c| {
            let w = 1.0 / data.noise[c].sd();
            (0..data.full.len())
                .filter(|&k| heldout[k])
                .map(|k| ((with.channel(c)[k] - o.channel(c)[k]) * w).powi(2))
                .sum::<f64>()
        })
        .sum::<f64>()
        .sqrt();
    let n = fit.iter().filter(|&&b| b).count() as f64;
    // The frequency, and per channel sine and cosine at f and 3f.
    let k = 1.0 + 4.0 * chans.len() as f64;
    let bic_gain = n * (f0 / f1).ln() - k * n.ln();
    (bic_gain > MIN_BIC_GAIN && h0 - h1 > heldout_needed(diff, h0))
        .then(|| (bic_gain, h0 / h1.max(1e-300)))
}

/// Lines faster than the decimated series shows ([`terms::line::MAX_FREQ_HZ`]), outside the
/// mains band, searched channel by channel in the residual of `o`: each with its channel and
/// evidence, where it passes both tests.
pub(crate) fn fast_lines(
    setup: &Setup,
    o: &Outputs,
    masks: (&[bool], &[bool]),
) -> Vec<terms::FastLine> {
    let data = setup.data;
    (0..4)
        .filter(|&c| setup.used[c])
        .filter_map(|c| {
            let r = diff(&data.full.y[c], o.channel(c));
            let line = mains::find_fast_line(
                &data.full.t_s,
                &[&r],
                masks.0,
                data.rate_hz,
                terms::line::MAX_FREQ_HZ,
            )?;
            let (bic_gain, ratio) = line_evidence(data, o, &line, masks, &[c])?;
            Some(terms::FastLine {
                channel: c,
                line,
                bic_gain,
                heldout_ratio: ratio,
            })
        })
        .collect()
}
