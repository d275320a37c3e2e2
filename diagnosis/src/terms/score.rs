//! A set of terms scored against the chosen model: their columns on a channel (where the
//! channel is still live), their joint refit, their contribution, and the chi-square and BIC of
//! the model with them. Shared by the library's search ([`super::search`]) and the discovery
//! step ([`super::discover`]), which weigh terms by the same measure.

use super::fitting::{solve, Columns, Context};
use super::{Term, TermKind};

/// The chosen model's scores the terms are weighed against.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Nested {
    /// Weighted residuals on the fitting stretch (all compared channels).
    pub n: usize,
    /// Free parameters of the chosen model.
    pub k: usize,
    /// Its chi-square on the fitting stretch and on the held-out stretch.
    pub fit_chi2: f64,
    pub heldout_chi2: f64,
}

/// The columns of the terms on channel `c`, leaving out term number `skip`, each reaching only
/// the samples where the channel is [`live`].
pub(crate) fn columns_on(terms: &[Term], c: usize, skip: Option<usize>) -> Columns {
    let live = live(terms, c, skip);
    terms
        .iter()
        .enumerate()
        .filter(|(i, t)| t.channel == c && Some(*i) != skip)
        .fold(Columns::default(), |acc, (_, t)| {
            acc.joined(&masked(&t.columns, t, live.as_deref()))
        })
}

/// The share of each sample of channel `c` that its model and terms still reach: none from a
/// stuck channel's time on (it reads its constant whatever they give), leaving out term `skip`.
pub(crate) fn live(terms: &[Term], c: usize, skip: Option<usize>) -> Option<Vec<f64>> {
    terms
        .iter()
        .enumerate()
        .find(|(i, t)| t.channel == c && t.kind == TermKind::StuckChannel && Some(*i) != skip)
        .map(|(_, t)| t.columns.x[0].iter().map(|h| 1.0 - h).collect())
}

/// `cols` of term `t` where the channel is live (the stuck term itself is what replaces it).
fn masked(cols: &Columns, t: &Term, live: Option<&[f64]>) -> Columns {
    match live.filter(|_| t.kind != TermKind::StuckChannel) {
        Some(live) => cols.scaled(live),
        None => cols.clone(),
    }
}

/// Refit the amplitudes of each channel's terms jointly.
pub(crate) fn refit(ctx: &Context, terms: &mut [Term]) {
    for c in 0..4 {
        let cols = columns_on(terms, c, None);
        if cols.x.is_empty() {
            continue;
        }
        let Some((beta, _)) = solve(ctx, c, &cols) else {
            continue;
        };
        let mut at = 0;
        for t in terms.iter_mut().filter(|t| t.channel == c) {
            let k = t.columns.x.len();
            t.beta = beta[at..at + k].to_vec();
            at += k;
        }
    }
}

/// Channel `c`'s contribution of `terms` on the decimated series.
pub(crate) fn contribution(ctx: &Context, terms: &[Term], c: usize) -> Vec<f64> {
    let cols = columns_on(terms, c, None);
    if cols.x.is_empty() && cols.fixed.is_none() {
        return vec![0.0; ctx.len()];
    }
    let beta: Vec<f64> = terms
        .iter()
        .filter(|t| t.channel == c)
        .flat_map(|t| t.beta.iter().copied())
        .collect();
    cols.contribution(&beta)
}

/// The chi-square of the chosen model plus `terms` on `mask` (the untouched channels as the
/// nested model has them).
fn chi2(ctx: &Context, base: f64, terms: &[Term], mask: &[bool]) -> f64 {
    let mut total = base;
    for c in (0..4).filter(|&c| terms.iter().any(|t| t.channel == c)) {
        let part = contribution(ctx, terms, c);
        total += ctx.chi2(c, Some(&part), mask) - ctx.chi2(c, None, mask);
    }
    total
}

pub(crate) fn heldout(ctx: &Context, nested: Nested, terms: &[Term]) -> f64 {
    chi2(ctx, nested.heldout_chi2, terms, ctx.heldout_mask)
}

pub(crate) fn bic(ctx: &Context, nested: Nested, terms: &[Term]) -> f64 {
    let n = nested.n as f64;
    let sse = chi2(ctx, nested.fit_chi2, terms, ctx.fit_mask).max(1e-300);
    let k = nested.k + terms.iter().map(|t| t.n_params).sum::<usize>();
    n * (sse / n).ln() + k as f64 * n.ln()
}

