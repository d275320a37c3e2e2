//! Sparse selection of features: forward–backward by the information criterion, as the
//! catalogue's effects and the library's terms are selected, with the dictionary's size counted.
//! Choosing a feature out of M is a claim the plain BIC does not price: the extended BIC (Chen
//! & Chen 2008, gamma = 1) adds 2 ln M per feature chosen, and a feature on a grid (a time
//! constant, a frequency) counts that choice as a parameter, as the library's terms count
//! theirs. A feature is kept where its chi-square gain beats its price plus the catalogue's
//! [`MIN_BIC_GAIN`].
//!
//! One selection may span several channels ([`Problem`]s): a feature's gain is the sum of its
//! gains on each, and it has one amplitude per problem. A problem may itself stack several
//! channels under one amplitude (the material's term on the load and, in proportion, on the
//! outputs). The forward step is an orthogonal matching pursuit: each feature's gain is its
//! squared projection on what is left, both made orthogonal to the columns already in.

use super::super::fitting::{Columns, Context};
use super::dictionary::Feature;
use crate::candidate::MIN_BIC_GAIN;

/// At most this many features in one term: what remains is described by a short expression,
/// or it is not described (a long sum would be a fit, not a finding).
pub(crate) const MAX_FEATURES: usize = 3;

/// The rows of the fitting stretch a selection runs on, each with a multiplicity (1, or a
/// bootstrap resample's count).
#[derive(Debug, Clone)]
pub(crate) struct Rows {
    pub index: Vec<usize>,
    pub count: Vec<f64>,
}

impl Rows {
    pub fn fitting(ctx: &Context) -> Self {
        let index: Vec<usize> = (0..ctx.len()).filter(|&k| ctx.fit_mask[k]).collect();
        let count = vec![1.0; index.len()];
        Self { index, count }
    }

    /// Rows counted: the criterion's n.
    pub fn n(&self) -> f64 {
        self.count.iter().sum()
    }
}

/// What a feature's grid value costs in chi-square: one parameter, ln n.
pub(crate) fn grid_cost(f: &Feature, n: f64) -> f64 {
    if f.grid.is_some() {
        n.max(2.0).ln()
    } else {
        0.0
    }
}

/// One block of a problem: channel `c`'s rows, its target and each feature's column there
/// (`None`: the feature does not reach this block).
pub(crate) struct Block<'a> {
    pub channel: usize,
    pub target: &'a [f64],
    pub columns: Vec<Option<Vec<f64>>>,
    /// The columns refitted beside the term on this channel.
    pub others: &'a Columns,
}

/// Vectors over the stacked rows of one or more channels, weighted by the noise and the rows'
/// counts, with the columns refitted beside the term taken out.
#[derive(Clone)]
pub(crate) struct Problem {
    target: Vec<f64>,
    features: Vec<Vec<f64>>,
    /// Each feature's norm before anything was taken out of it.
    norms: Vec<f64>,
}

impl Problem {
    /// The stacked problem of `blocks` on `rows`; `m` features.
    pub fn new(ctx: &Context, rows: &Rows, blocks: &[Block], m: usize) -> Self {
        let mut target = Vec::new();
        let mut features: Vec<Vec<f64>> = vec![Vec::new(); m];
        for block in blocks {
            let w: Vec<f64> = rows
                .index
                .iter()
                .zip(&rows.count)
                .map(|(&k, &n)| ctx.data.weight(block.channel, k) * n.sqrt())
                .collect();
            let on = |v: &[f64]| -> Vec<f64> {
                rows.index.iter().zip(&w).map(|(&k, w)| v[k] * w).collect()
            };
            let mut t = on(block.target);
            let mut cols: Vec<Vec<f64>> = block
                .columns
                .iter()
                .map(|c| c.as_ref().map_or_else(|| vec![0.0; w.len()], |c| on(c)))
                .collect();
            // The block's own others, taken out of the block alone.
            let others: Vec<Vec<f64>> = block.others.x.iter().map(|x| on(x)).collect();
            for q in orthonormal(&others) {
                deflate(&mut t, &q);
                cols.iter_mut().for_each(|v| deflate(v, &q));
            }
            target.extend(t);
            for (f, c) in features.iter_mut().zip(cols) {
                f.extend(c);
            }
        }
        let norms = features.iter().map(|f| norm(f)).collect();
        Self {
            target,
            features,
            norms,
        }
    }

    /// The chi-square feature `j` removes from what is left, or `None` where nothing of it is
    /// left (it lies in what is already in).
    fn gain(&self, j: usize) -> Option<f64> {
        let f = &self.features[j];
        let ff: f64 = f.iter().map(|x| x * x).sum();
        if ff <= 1e-12 * self.norms[j].powi(2) {
            return None;
        }
        let zf: f64 = f.iter().zip(&self.target).map(|(x, y)| x * y).sum();
        Some(zf * zf / ff)
    }

    fn take_out(&mut self, j: usize) {
        if let Some(q) = unit(&self.features[j].clone(), self.norms[j]) {
            deflate(&mut self.target, &q);
            self.features.iter_mut().for_each(|v| deflate(v, &q));
        }
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn deflate(v: &mut [f64], q: &[f64]) {
    let a: f64 = v.iter().zip(q).map(|(x, y)| x * y).sum();
    v.iter_mut().zip(q).for_each(|(x, y)| *x -= a * y);
}

/// `v` normalised, or `None` where it is (numerically) zero against `reference`.
fn unit(v: &[f64], reference: f64) -> Option<Vec<f64>> {
    let n = norm(v);
    (n > 1e-6 * reference.max(1e-300)).then(|| v.iter().map(|x| x / n).collect())
}

/// An orthonormal basis of `cols` (modified Gram–Schmidt), columns dependent on those before
/// them left out.
fn orthonormal(cols: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for v in cols {
        let mut u = v.clone();
        for q in &basis {
            deflate(&mut u, q);
        }
        if let Some(q) = unit(&u, norm(v)) {
            basis.push(q);
        }
    }
    basis
}

/// The price of each feature in chi-square: `amplitudes` parameters of ln n each, 2 ln M for
/// its choice, ln n for a grid value, and the criterion's margin.
pub(crate) fn prices(feats: &[Feature], n: f64, amplitudes: usize) -> Vec<f64> {
    let ln_n = n.max(2.0).ln();
    let choice = 2.0 * (feats.len().max(2) as f64).ln();
    feats
        .iter()
        .map(|f| amplitudes as f64 * ln_n + choice + grid_cost(f, n) + MIN_BIC_GAIN)
        .collect()
}

/// The features kept on `problems` (each feature has one amplitude per problem) at `prices`,
/// in the order chosen, and the chi-square they remove in all beyond their prices (0 when
/// none is kept).
pub(crate) fn select(problems: &[Problem], prices: &[f64]) -> (Vec<usize>, f64) {
    let mut left: Vec<Problem> = problems.to_vec();
    let m = prices.len();
    let mut chosen: Vec<usize> = Vec::new();
    while chosen.len() < MAX_FEATURES {
        let best = (0..m)
            .filter(|j| !chosen.contains(j))
            .filter_map(|j| {
                let g: Option<f64> = left.iter().map(|p| p.gain(j)).sum();
                g.map(|g| (j, g - prices[j]))
            })
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match best {
            Some((j, net)) if net > 0.0 => {
                chosen.push(j);
                left.iter_mut().for_each(|p| p.take_out(j));
            }
            _ => break,
        }
    }
    backward(problems, chosen, prices)
}

/// Drop, one at a time, the chosen feature whose partial chi-square (its gain with the others
/// already in) falls short of its price, until every one earns its place; with the net gain of
/// what is kept.
fn backward(problems: &[Problem], mut chosen: Vec<usize>, prices: &[f64]) -> (Vec<usize>, f64) {
    loop {
        if chosen.is_empty() {
            return (chosen, 0.0);
        }
        let total = explained(problems, &chosen);
        let weakest = (0..chosen.len())
            .map(|i| {
                let mut rest = chosen.clone();
                rest.remove(i);
                (i, total - explained(problems, &rest) - prices[chosen[i]])
            })
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match weakest {
            Some((i, net)) if net <= 0.0 => {
                chosen.remove(i);
            }
            _ => {
                let price: f64 = chosen.iter().map(|&j| prices[j]).sum();
                return (chosen, total - price);
            }
        }
    }
}

/// The chi-square `chosen` removes from `problems` together.
pub(crate) fn explained(problems: &[Problem], chosen: &[usize]) -> f64 {
    problems
        .iter()
        .map(|p| {
            let mut q = p.clone();
            let mut g = 0.0;
            for &j in chosen {
                g += q.gain(j).unwrap_or(0.0);
                q.take_out(j);
            }
            g
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problem(target: Vec<f64>, features: Vec<Vec<f64>>) -> Problem {
        let norms = features.iter().map(|f| norm(f)).collect();
        Problem {
            target,
            features,
            norms,
        }
    }

    /// The feature the target is made of is chosen, and one it does not hold is not.
    #[test]
    fn the_feature_in_the_target_is_chosen() {
        let n = 400;
        let x: Vec<f64> = (0..n).map(|k| (k as f64 * 0.05).sin()).collect();
        let y: Vec<f64> = (0..n).map(|k| (k as f64 * 0.013).cos()).collect();
        let noise: Vec<f64> = (0..n)
            .map(|k| ((k * 7919 % 1000) as f64 / 1000.0 - 0.5) * 0.2)
            .collect();
        let target: Vec<f64> = (0..n).map(|k| 5.0 * x[k] + noise[k]).collect();
        let p = problem(target, vec![y, x]);
        let (chosen, net) = select(&[p], &[20.0, 20.0]);
        assert_eq!(chosen, vec![1]);
        assert!(net > 0.0);
    }

    /// A feature that only helps on one of two problems still pays for both amplitudes.
    #[test]
    fn gains_add_over_problems() {
        let n = 200;
        let x: Vec<f64> = (0..n).map(|k| (k as f64 * 0.1).sin()).collect();
        let a = problem(x.iter().map(|v| 3.0 * v).collect(), vec![x.clone()]);
        let b = problem(x.iter().map(|v| 3.0 * v).collect(), vec![x.clone()]);
        let one = explained(std::slice::from_ref(&a), &[0]);
        let two = explained(&[a, b], &[0]);
        assert!((two - 2.0 * one).abs() < 1e-9 * one);
    }
}
