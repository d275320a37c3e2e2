//! The name first: a discovered description and a named effect's few parameters are points of
//! one model space, and among descriptions of the same residual the simplest one within one
//! standard error of the best wins (Hastie, Tibshirani and Friedman, *Elements of Statistical
//! Learning*, §7.10, the one-standard-error rule). Here the error is the held-out chi-square
//! difference's own deviation under the noise model ([`super::heldout_diff`]), and a name
//! with its parameters is the simpler description: a discovered effect on the load cell is
//! replaced by the load cell's lag (the catalogue's `time_offset` at its electronics, the
//! library's [`super::super::load_lag`]) or, in a test of the material alone, by the
//! material's stiffening (`stiffening` on the load, [`super::super::load_stiffening`]) where
//! the name predicts the held-out stretch no worse than one standard error beyond the
//! discovered form and passes every test an effect passes against the model without either.

use super::super::fitting::Context;
use super::super::score::{bic, heldout, refit, Nested};
use super::super::{Term, TermKind};
use super::{heldout_diff, others_on};
use crate::candidate::{heldout_needed, MIN_BIC_GAIN};

/// `terms` with each discovered effect that acts on the load cell alone replaced by the named
/// effect the one-standard-error rule prefers, if any (the better held out of those that
/// qualify).
pub(super) fn name_first(ctx: &Context, nested: Nested, mut terms: Vec<Term>) -> Vec<Term> {
    for group in load_groups(&terms) {
        let names = [TermKind::LoadLag, TermKind::LoadStiffening]
            .into_iter()
            .filter(|&kind| allowed(ctx, &terms, kind))
            .filter_map(|kind| named(ctx, nested, &terms, group, kind))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, named)) = names {
            terms = named;
        }
    }
    terms
}

/// Whether the library's `kind` may stand for a discovered effect: not already in the model,
/// and its catalogue entry's protocol preconditions met.
fn allowed(ctx: &Context, terms: &[Term], kind: TermKind) -> bool {
    let entry = kind.catalogue_kind();
    !terms.iter().any(|t| t.kind == kind) && entry.is_some_and(|e| !ctx.forbidden.contains(&e))
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

/// `terms` with discovered effect `group` replaced by the library's `kind` on the load, where
/// that is within one standard error of it held out and earns its place against the model
/// without either; with its held-out chi-square.
fn named(
    ctx: &Context,
    nested: Nested,
    terms: &[Term],
    group: usize,
    kind: TermKind,
) -> Option<(f64, Vec<Term>)> {
    let mut without: Vec<Term> = terms
        .iter()
        .filter(|t| t.info.as_ref().is_none_or(|i| i.group != group))
        .cloned()
        .collect();
    refit(ctx, &mut without);
    let others = others_on(ctx, &without, 0);
    let term = match kind {
        TermKind::LoadLag => super::super::load_lag::fit(ctx, 0, &others)?,
        _ => super::super::load_stiffening::fit(ctx, 0, &others)?,
    };
    // A lag is a positive delay of the reading (the load cell lags the rod); a stiffening adds
    // load where the load is high (`admitted_term` keeps only such).
    if kind == TermKind::LoadLag && term.beta[0] <= 0.0 {
        return None;
    }
    let mut named = without.clone();
    named.push(term);
    refit(ctx, &mut named);
    let (h_without, h_named, h_found) = (
        heldout(ctx, nested, &without),
        heldout(ctx, nested, &named),
        heldout(ctx, nested, terms),
    );
    let one_se = heldout_diff(ctx, terms, &named);
    let earns = bic(ctx, nested, &without) - bic(ctx, nested, &named) > MIN_BIC_GAIN
        && h_without - h_named > heldout_needed(heldout_diff(ctx, &without, &named), h_without);
    (earns && h_named <= h_found + one_se).then_some((h_named, named))
}
