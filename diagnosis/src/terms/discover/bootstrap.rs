//! Each kept feature's inclusion probability (E-SINDy's bagging, Fasel et al. 2022): the
//! selection is run again on resamples of the fitting stretch and the share of resamples that
//! keep the feature (or its neighbour on its grid) is reported. The rows are resampled in
//! moving blocks (Künsch 1989) of n^(1/3) samples, so that what is correlated over a few
//! samples stays together; the resamples come from a fixed seed, so a diagnosis is repeatable.

use std::sync::Arc;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::super::fitting::Context;
use super::super::Term;
use super::dictionary::Feature;
use super::select::Rows;
use super::stage::{Channels, Hypothesis};

/// Resamples of the selection: enough for a share to a few hundredths.
const RESAMPLES: usize = 40;

/// Neighbours on a grid within this ratio are one choice (the grids step by 1.5 to 2.2).
const GRID_RATIO: f64 = 2.2;

/// Fill in the inclusion probabilities of the terms of discovered effect `group` in `with`:
/// hypothesis `h`'s selection run again on resamples of the fitting stretch.
pub(super) fn inclusion(
    ctx: &Context,
    ch: &Channels,
    h: &Hypothesis,
    with: &mut [Term],
    group: usize,
) {
    use rayon::prelude::*;
    let base = Rows::fitting(ctx);
    let hits: Vec<Vec<bool>> = (0..RESAMPLES)
        .into_par_iter()
        .map(|b| {
            let mut again = h.clone();
            again.select(ctx, ch, &resample(&base, (group as u64) << 32 | b as u64));
            h.chosen
                .iter()
                .map(|&j| {
                    let kept = h.feature(ch, 0, j);
                    again
                        .chosen
                        .iter()
                        .any(|&i| same(again.feature(ch, 0, i), kept))
                })
                .collect()
        })
        .collect();
    let shares: Vec<f64> = (0..h.chosen.len())
        .map(|i| hits.iter().filter(|x| x[i]).count() as f64 / RESAMPLES as f64)
        .collect();
    for t in with.iter_mut() {
        if let Some(info) = t.info.as_mut().filter(|i| i.group == group) {
            Arc::make_mut(info).inclusion = shares.clone();
        }
    }
}

/// One choice: the same family, and a grid value within a step of the kept one.
fn same(f: &Feature, k: &Feature) -> bool {
    f.family == k.family
        && match (f.grid, k.grid) {
            (Some(a), Some(b)) => (a / b).max(b / a) <= GRID_RATIO,
            (None, None) => true,
            _ => false,
        }
}

/// A moving-block resample of `rows`: blocks of n^(1/3) consecutive rows drawn with
/// replacement until n rows are drawn, each row counted as often as it was drawn.
fn resample(rows: &Rows, seed: u64) -> Rows {
    let n = rows.index.len();
    let block = ((n as f64).cbrt().ceil() as usize).clamp(1, n.max(1));
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut count = vec![0.0; n];
    let mut drawn = 0;
    while drawn < n {
        let start = rng.random_range(0..=n - block);
        for c in &mut count[start..start + block] {
            *c += 1.0;
        }
        drawn += block;
    }
    let keep: Vec<usize> = (0..n).filter(|&i| count[i] > 0.0).collect();
    Rows {
        index: keep.iter().map(|&i| rows.index[i]).collect(),
        count: keep.iter().map(|&i| count[i]).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A resample draws n rows in all, in blocks, from the rows given.
    #[test]
    fn a_resample_draws_n_rows() {
        let rows = Rows {
            index: (10..1010).collect(),
            count: vec![1.0; 1000],
        };
        let r = resample(&rows, 7);
        let n: f64 = r.count.iter().sum();
        assert!((1000.0..1010.0).contains(&n), "{n}");
        assert!(r.index.iter().all(|i| (10..1010).contains(i)));
        // Repeatable.
        assert_eq!(resample(&rows, 7).index, r.index);
    }
}
