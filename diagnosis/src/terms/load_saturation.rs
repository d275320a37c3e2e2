//! The load cell's amplifier saturating: the catalogue's `amplifier_saturation` met on the
//! load cell's channel, which reads no more than its limit L whatever the load:
//!
//! ```text
//! y(t) = min(m(t), L)
//! ```
//!
//! with m the model's load as the channel's refitted offset and scale leave it. As a column,
//! min(m, L) - m, its amplitude fitted (one where the cell clips exactly), L from a grid over
//! the model's range.

use super::fitting::{best_shape, solve, Columns, Context};
use super::{Description, Term, TermKind};

/// Limits tried, as shares of the way from the model's lowest load to its highest.
const SHARES: (f64, f64, usize) = (0.3, 0.98, 35);

pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    // The cell clips what it would read, the model as the other columns on the channel (the
    // refitted offset and scale) leave it: found in turns, each clipping the last turn's.
    let mut reads = ctx.model[c].clone();
    let mut best = None;
    let mut resolution = 0.0;
    for _ in 0..3 {
        let (shape, columns, beta, step) = best_limit(ctx, c, others, &reads)?;
        resolution = step;
        let (all, _) = solve(ctx, c, &columns.joined(others))?;
        let rest = others.contribution(&all[1..]);
        reads = ctx.model[c].iter().zip(&rest).map(|(m, r)| m + r).collect();
        best = Some((shape, columns, beta));
    }
    let (shape, columns, beta) = best?;
    // A cell that reads more above its limit is not clipping; nor is one whose recording goes
    // above the limit (beyond the limit's own resolution on its grid and three deviations of
    // its noise, in more than one sample in a hundred: a spike is not a reading): a clip is a
    // ceiling the recording shows.
    if beta[0] <= 0.0 || above_limit(ctx, c, shape[0] + resolution) > 0.01 {
        return None;
    }
    Some(Term {
        kind: TermKind::LoadSaturation,
        channel: c,
        shape,
        columns,
        beta,
        n_params: 2,
        info: None,
    })
}

/// The share of the fitting stretch's samples of channel `c` recorded above `limit` by more
/// than three deviations of their noise.
fn above_limit(ctx: &Context, c: usize, limit: f64) -> f64 {
    let y = &ctx.data.fit.y[c];
    let rows: Vec<usize> = (0..ctx.len()).filter(|&k| ctx.fit_mask[k]).collect();
    let above = rows
        .iter()
        .filter(|&&k| (y[k] - limit) * ctx.data.weight(c, k) > 3.0)
        .count();
    above as f64 / rows.len().max(1) as f64
}

/// The best limit for a cell that would read `reads`: a grid over their range, then a
/// twentieth of its step around the best (a limit a step off leaves a misfit at every peak
/// that another term would take up); with the fine grid's step, the limit's resolution.
fn best_limit(
    ctx: &Context,
    c: usize,
    others: &Columns,
    reads: &[f64],
) -> Option<(Vec<f64>, Columns, Vec<f64>, f64)> {
    let (lo, hi) = reads
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if hi.is_nan() || hi <= lo {
        return None;
    }
    let (a, b, n) = SHARES;
    let step = (hi - lo) * (b - a) / (n - 1) as f64;
    let clip = |limit: f64| {
        let x = reads.iter().map(|&v| v.min(limit) - v).collect();
        (
            vec![limit],
            Columns {
                x: vec![x],
                fixed: None,
            },
        )
    };
    let coarse = (0..n).map(|i| clip(lo + (hi - lo) * a + step * i as f64));
    let (first, _, _, _) = best_shape(ctx, c, others, coarse)?;
    let fine = (-20..=20).map(|j| clip(first[0] + step * f64::from(j) / 20.0));
    let (shape, columns, beta, _) = best_shape(ctx, c, others, fine)?;
    Some((shape, columns, beta, step / 20.0))
}

pub(crate) fn describe(t: &Term) -> Description {
    Description {
        name: "amplifier_saturation".into(),
        params: vec![("limit_N", t.shape[0], "N".into())],
        depends_on: vec!["load_N"],
        form: format!("the load cell reads no more than {:.2} N", t.shape[0]),
    }
}
