//! What a described or discovered effect adds to the model, and the standard errors of its
//! parameters.
//!
//! A term is linear in its amplitudes once its shape (a time, a frequency, a power) is chosen,
//! and its amplitudes were fitted by weighted least squares together with every other column on
//! its channel (the channel's refitted offset and scale, other terms). Their covariance is the
//! sandwich A^-1 B A^-1 of that fit: A the weighted normal matrix, B the variance of the
//! weighted score under the channel's noise model, whose sample-scale and slow AR(1) parts
//! move neighbouring block means together (`Noise::block_means_variance`). Each reported
//! parameter is a function of the amplitudes (a step, a line's amplitude, a coefficient);
//! its standard error follows by the delta method, the gradient taken by differences. A
//! parameter of the shape alone (chosen on a grid) has no gradient there and is given none:
//! the effect's `evidence` says so.

use nalgebra::DMatrix;

use super::{at_full, score, Context, Term};
use crate::output::EffectReport;

/// The effect of `terms[group]` at the full rate, per channel: what the model with it holds
/// beyond the model without it.
pub(crate) fn part(ctx: &Context, terms: &[Term], group: &[usize]) -> [Vec<f64>; 4] {
    let of: Vec<Term> = group.iter().map(|&i| terms[i].clone()).collect();
    let t = &ctx.data.full.t_s;
    std::array::from_fn(|c| {
        if of.iter().any(|x| x.channel == c) {
            at_full(ctx, &of, c, t)
        } else {
            Vec::new()
        }
    })
}

/// Sets the standard error of each of `e`'s parameters that is a function of the amplitudes of
/// `terms[lead]` (the term its parameters are read from), and says in `evidence` which were
/// chosen on a grid.
pub(crate) fn fill_stderr(ctx: &Context, terms: &[Term], lead: usize, e: &mut EffectReport) {
    let Some(cov) = amplitude_covariance(ctx, terms, lead) else {
        return;
    };
    let term = &terms[lead];
    let base = term.describe().params;
    let k = term.beta.len();
    // Gradient of every parameter against each amplitude, by central differences.
    let mut grad = vec![vec![0.0; k]; base.len()];
    for j in 0..k {
        let h = 1e-4
            * cov[(j, j)]
                .sqrt()
                .max(1e-12 * term.beta[j].abs())
                .max(1e-300);
        let at = |s: f64| {
            let mut t = term.clone();
            t.beta[j] += s * h;
            t.describe().params
        };
        let (up, down) = (at(1.0), at(-1.0));
        for (i, g) in grad.iter_mut().enumerate() {
            g[j] = (up[i].1 - down[i].1) / (2.0 * h);
        }
    }
    let mut on_grid = Vec::new();
    for (i, (name, _, _)) in base.iter().enumerate() {
        let g = &grad[i];
        let var: f64 = (0..k)
            .flat_map(|a| (0..k).map(move |b| (a, b)))
            .map(|(a, b)| g[a] * cov[(a, b)] * g[b])
            .sum();
        let p = e.parameters.iter_mut().find(|p| p.name == *name);
        match p {
            Some(p) if g.iter().any(|x| *x != 0.0) && var.is_finite() => {
                p.stderr = Some(var.max(0.0).sqrt());
                e.param_stderr.push(name, var.max(0.0).sqrt());
            }
            Some(_) => on_grid.push(*name),
            None => {}
        }
    }
    if !on_grid.is_empty() {
        e.evidence.push_str(&format!(
            " No standard error for {}: chosen on a grid, not fitted by least squares.",
            on_grid.join(", ")
        ));
    }
}

/// The covariance of `terms[lead]`'s amplitudes from the weighted least squares of every column
/// on its channel (the module's head); `None` where the normal matrix is singular.
fn amplitude_covariance(ctx: &Context, terms: &[Term], lead: usize) -> Option<DMatrix<f64>> {
    let c = terms[lead].channel;
    let cols = score::columns_on(terms, c, None);
    // Where the lead's columns sit among the channel's.
    let offset: usize = terms[..lead]
        .iter()
        .filter(|t| t.channel == c)
        .map(|t| t.columns.x.len())
        .sum();
    let k = terms[lead].beta.len();
    let n = cols.x.len();
    if k == 0 || offset + k > n {
        return None;
    }
    let rows: Vec<usize> = (0..ctx.len()).filter(|&i| ctx.fit_mask[i]).collect();
    let w2: Vec<f64> = rows
        .iter()
        .map(|&i| ctx.data.weight(c, i).powi(2))
        .collect();
    let a = DMatrix::<f64>::from_fn(n, n, |p, q| {
        rows.iter()
            .zip(&w2)
            .map(|(&i, w)| w * cols.x[p][i] * cols.x[q][i])
            .sum::<f64>()
    });
    let a_inv = a.try_inverse()?;
    // The lead's amplitudes as sums over the block means' errors: coefficient rows of A^-1 X'W^2.
    let coefficient = |j: usize| -> Vec<f64> {
        rows.iter()
            .zip(&w2)
            .map(|(&i, w)| {
                w * (0..n)
                    .map(|q| a_inv[(offset + j, q)] * cols.x[q][i])
                    .sum::<f64>()
            })
            .collect()
    };
    let blocks: Vec<(usize, usize)> = rows.iter().map(|&i| ctx.data.bounds[i]).collect();
    let noise = &ctx.data.noise[c];
    let g: Vec<Vec<f64>> = (0..k).map(coefficient).collect();
    let var = |x: &[f64]| noise.block_means_variance(&blocks, x);
    let own: Vec<f64> = g.iter().map(|x| var(x)).collect();
    Some(DMatrix::from_fn(k, k, |p, q| {
        if p == q {
            own[p]
        } else {
            let sum: Vec<f64> = g[p].iter().zip(&g[q]).map(|(a, b)| a + b).collect();
            0.5 * (var(&sum) - own[p] - own[q])
        }
    }))
}
