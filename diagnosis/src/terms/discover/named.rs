//! The name first: a discovered description and a named effect's few parameters are points of
//! one model space, and among descriptions of the same residual the simplest one within one
//! standard error of the best wins (Hastie, Tibshirani and Friedman, *Elements of Statistical
//! Learning*, §7.10, the one-standard-error rule). Here the error is the held-out chi-square
//! difference's own deviation under the noise model ([`super::heldout_diff`]), and a name
//! with its parameters is the simpler description: a discovered effect on the load cell is
//! replaced by the load cell's lag (the catalogue's `time_offset` at its electronics, the
//! library's [`super::super::load_lag`]) where the lag predicts the held-out stretch no worse
//! than one standard error beyond the discovered form and passes every test an effect passes
//! against the model without either.

use super::super::fitting::Context;
use super::super::score::{bic, heldout, refit, Nested};
use super::super::{Term, TermKind};
use super::{heldout_diff, others_on};
use crate::candidate::{heldout_needed, MIN_BIC_GAIN};

/// `terms` with each discovered effect that acts on the load cell alone replaced by the load
/// cell's lag where the one-standard-error rule prefers the name.
pub(super) fn name_first(ctx: &Context, nested: Nested, mut terms: Vec<Term>) -> Vec<Term> {
    let lag_allowed = ctx
        .forbidden
        .iter()
        .all(|k| *k != sim::effects::EffectKind::TimeOffset);
    if !lag_allowed || terms.iter().any(|t| t.kind == TermKind::LoadLag) {
        return terms;
    }
    for group in load_groups(&terms) {
        if let Some(named) = named_lag(ctx, nested, &terms, group) {
            terms = named;
            break;
        }
    }
    terms
}

/// The discovered effects whose terms are all on the load cell.
fn load_groups(terms: &[Term]) -> Vec<usize> {
    let mut groups: Vec<usize> = terms
        .iter()
        .filter_map(|t| t.info.as_ref().map(|i| i.group))
        .collect();
    groups.sort_unstable();
    groups.dedup();
    groups.retain(|&g| {
        terms
            .iter()
            .filter(|t| t.info.as_ref().is_some_and(|i| i.group == g))
            .all(|t| t.channel == 0)
    });
    groups
}

/// `terms` with discovered effect `group` replaced by the load cell's lag, where the lag is
/// within one standard error of it held out and earns its place against the model without
/// either.
fn named_lag(ctx: &Context, nested: Nested, terms: &[Term], group: usize) -> Option<Vec<Term>> {
    let mut without: Vec<Term> = terms
        .iter()
        .filter(|t| t.info.as_ref().is_none_or(|i| i.group != group))
        .cloned()
        .collect();
    refit(ctx, &mut without);
    let lag = super::super::load_lag::fit(ctx, 0, &others_on(ctx, &without, 0))?;
    // A lag is a positive delay of the reading (the load cell lags the rod).
    if lag.beta[0] <= 0.0 {
        return None;
    }
    let mut named = without.clone();
    named.push(lag);
    refit(ctx, &mut named);
    let (h_without, h_named, h_found) = (
        heldout(ctx, nested, &without),
        heldout(ctx, nested, &named),
        heldout(ctx, nested, terms),
    );
    let one_se = heldout_diff(ctx, terms, &named);
    let earns = bic(ctx, nested, &without) - bic(ctx, nested, &named) > MIN_BIC_GAIN
        && h_without - h_named > heldout_needed(heldout_diff(ctx, &without, &named), h_without);
    (earns && h_named <= h_found + one_se).then_some(named)
}
