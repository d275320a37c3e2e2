//! The forward–backward search over the library's terms, with the catalogue's two tests: add
//! the term with the largest BIC gain while it exceeds [`MIN_BIC_GAIN`]; then drop, one at a
//! time, any term that no longer beats the model without it by that criterion *and* on the
//! held-out stretch by more than twice its own noise and 0.5 % of the misfit left
//! ([`heldout_needed`]). A term that only fits the stretch it was fitted on is not reported.

use super::fitting::Context;
use super::score::{bic, columns_on, contribution, heldout, refit, Nested};
use super::{Term, TermKind};
use crate::candidate::{heldout_needed, MIN_BIC_GAIN};

/// At most this many terms: what remains after the catalogue is described by a few terms, or
/// it is not described (a long list of small terms would be a fit, not a finding).
const MAX_TERMS: usize = 4;

/// The terms kept, each with the comparison that kept it.
#[derive(Default)]
pub(crate) struct Found {
    pub terms: Vec<Term>,
    /// Per term: BIC gain and held-out chi-square ratio against the model without it.
    pub evidence: Vec<(f64, f64)>,
    /// The BIC of the nested model with the terms, discovered terms with their search price.
    pub bic: f64,
    /// Its chi-square on the held-out stretch.
    pub heldout_chi2: f64,
}

/// Rounds of forward and backward steps: a term the backward step drops is not offered again,
/// so the next forward step can reach the term it stood in front of (a load cell's lag that
/// fits the loading but not the held-out stretch, before the set that does).
const MAX_ROUNDS: usize = 3;

/// Search the library on the compared channels of `ctx`.
pub(crate) fn search(ctx: &Context, nested: Nested) -> Found {
    let mut terms: Vec<Term> = Vec::new();
    let mut banned: Vec<(TermKind, usize)> = Vec::new();
    for _ in 0..MAX_ROUNDS {
        let added = forward(ctx, nested, terms, &banned);
        let (kept, dropped) = backward(ctx, nested, added);
        terms = kept;
        if dropped.is_empty() {
            break;
        }
        banned.extend(dropped);
    }
    // Beside the whole catalogue model only what no catalogue effect's misfit can mimic is
    // offered (`TermKind::beside_catalogue`); a dictionary can write any smooth misfit.
    if !ctx.beside_catalogue && ctx.discover {
        terms = super::discover::discover(ctx, nested, terms);
    }
    let evidence = (0..terms.len())
        .map(|i| {
            if let Some(info) = &terms[i].info {
                return super::discover::group_evidence(ctx, nested, &terms, info.group);
            }
            let cmp = compare_without(ctx, nested, &terms, i);
            let bic_gain = if terms[i].kind == TermKind::Recalibration {
                f64::INFINITY
            } else {
                cmp.bic_gain
            };
            (bic_gain, cmp.heldout_without / cmp.heldout_with.max(1e-300))
        })
        .collect();
    Found {
        // A description from the dictionary pays for having been chosen among its features,
        // wherever it is weighed against a catalogue model.
        bic: bic(ctx, nested, &terms) + super::discover::search_price(&terms),
        heldout_chi2: heldout(ctx, nested, &terms),
        terms,
        evidence,
    }
}

/// Add the term with the largest BIC gain while it exceeds [`MIN_BIC_GAIN`], up to
/// [`MAX_TERMS`], leaving out the `banned` kinds on their channels.
fn forward(
    ctx: &Context,
    nested: Nested,
    mut terms: Vec<Term>,
    banned: &[(TermKind, usize)],
) -> Vec<Term> {
    let own = |terms: &[Term]| {
        terms
            .iter()
            .filter(|t| t.kind != TermKind::Recalibration)
            .count()
    };
    while own(&terms) < MAX_TERMS {
        // Each channel's reference: the model with that channel's refit, which a term brings
        // in with it but which is not the term's doing (see `refitted`).
        let reference: [f64; 4] =
            std::array::from_fn(|c| bic(ctx, nested, &refitted(ctx, terms.clone(), c)));
        let best = candidates(ctx, &terms)
            .into_iter()
            .filter(|t| !banned.contains(&(t.kind, t.channel)))
            .map(|t| {
                let c = t.channel;
                let mut with = refitted(ctx, terms.clone(), c);
                with.push(t);
                refit(ctx, &mut with);
                (reference[c] - bic(ctx, nested, &with), with)
            })
            .filter(|(_, with)| admissible(with))
            .reduce(|best, next| if beats(next.0, best.0) { next } else { best });
        match best {
            Some((gain, with)) if gain > MIN_BIC_GAIN => terms = with,
            _ => break,
        }
    }
    terms
}

/// Whether every term keeps an amplitude its physics admits ([`TermKind::admits`]) after the
/// joint refit.
fn admissible(terms: &[Term]) -> bool {
    terms.iter().all(Term::admitted)
}

/// Whether a forward step's BIC `gain` beats the best so far. A tie (to a millionth) goes to
/// the earlier candidate: the library lists the smaller claim first, and where the fitting
/// stretch cannot tell two terms apart the smaller claim is the description to test on the
/// held-out stretch (an offset step at rest before it, which a freeze fits as well there but
/// which also says the channel stops following the load).
fn beats(gain: f64, best: f64) -> bool {
    gain - best > 1e-6 * best.abs().max(1.0)
}

/// Drop, one at a time, the term that fails either test by the most, until every term beats
/// the model without it on both: the terms kept and the (kind, channel) of those dropped. A
/// term whose removal takes another with it ([`without`]) is dropped only when no failing
/// term goes alone: the model without both says nothing about the one (a saturation dropped
/// because the recovery that had turned with it went too).
fn backward(
    ctx: &Context,
    nested: Nested,
    mut terms: Vec<Term>,
) -> (Vec<Term>, Vec<(TermKind, usize)>) {
    let mut dropped = Vec::new();
    loop {
        let failing: Vec<(usize, Comparison)> = (0..terms.len())
            .filter(|&i| terms[i].kind != TermKind::Recalibration)
            .map(|i| (i, compare_without(ctx, nested, &terms, i)))
            .filter(|(_, cmp)| !(cmp.bic_gain > MIN_BIC_GAIN && cmp.margin() > 0.0))
            .collect();
        let any_alone = failing.iter().any(|(_, cmp)| cmp.alone);
        let worst = failing
            .iter()
            .filter(|(_, cmp)| cmp.alone || !any_alone)
            .min_by(|a, b| a.1.margin().total_cmp(&b.1.margin()))
            .map(|(i, _)| *i);
        match worst {
            Some(i) => {
                dropped.push((terms[i].kind, terms[i].channel));
                terms = without(ctx, &terms, i);
            }
            None => return (terms, dropped),
        }
    }
}

/// Every library term on every compared channel it can act on, fitted with the channel's
/// terms already in the model.
fn candidates(ctx: &Context, terms: &[Term]) -> Vec<Term> {
    let jobs: Vec<(TermKind, usize)> = TermKind::ALL
        .iter()
        .flat_map(|&k| (0..4).map(move |c| (k, c)))
        .filter(|&(k, c)| ctx.used[c] && k.acts_on(c))
        .filter(|&(k, _)| !ctx.beside_catalogue || k.beside_catalogue())
        .filter(|&(k, _)| {
            k.catalogue_kind()
                .is_none_or(|e| !ctx.forbidden.contains(&e))
        })
        .collect();
    use rayon::prelude::*;
    jobs.par_iter()
        .filter_map(|&(k, c)| {
            let mut others = columns_on(terms, c, None);
            if others.x.is_empty() {
                others = TermKind::recalibration(ctx, c).columns;
            }
            k.fit(ctx, c, &others)
        })
        .collect()
}

/// `terms` with channel `c`'s refit ([`TermKind::recalibration`]) if it has none yet, refitted.
///
/// A term is weighed against the model with the refit that comes with it, not against the
/// model without: the refit of the catalogue's shared parameters channel by channel
/// ([`Context::catalogue`]) gains on its own where the joint fit balanced the channels, and
/// that gain is not the term's.
pub(super) fn refitted(ctx: &Context, mut terms: Vec<Term>, c: usize) -> Vec<Term> {
    if !terms.iter().any(|t| t.channel == c) {
        terms.push(TermKind::recalibration(ctx, c));
        refit(ctx, &mut terms);
    }
    terms
}

/// `terms` without number `i`, the rest refitted; the channel's refit goes with its last term.
/// A term whose sign the refit turns goes too ([`Term::admitted`]): without its partner it is no
/// longer the physics it named (a relaxation that only made up a set's shape).
pub(super) fn without(ctx: &Context, terms: &[Term], i: usize) -> Vec<Term> {
    without_turned(ctx, terms, i).0
}

/// [`without`], and whether a turned term went with number `i`.
fn without_turned(ctx: &Context, terms: &[Term], i: usize) -> (Vec<Term>, bool) {
    let mut w: Vec<Term> = terms.to_vec();
    let c = w.remove(i).channel;
    let mut turned = false;
    loop {
        let own = |t: &Term| t.channel == c && t.kind != TermKind::Recalibration;
        if !w.iter().any(own) {
            w.retain(|t| t.channel != c);
        }
        refit(ctx, &mut w);
        match w.iter().position(|t| !t.admitted()) {
            Some(j) => {
                w.remove(j);
                turned = true;
            }
            None => return (w, turned),
        }
    }
}

/// Term `i` against the model without it, as `Candidate::compare` weighs a catalogue effect.
struct Comparison {
    bic_gain: f64,
    /// Held-out chi-square without the term and with it.
    heldout_without: f64,
    heldout_with: f64,
    /// The held-out gain the term needs: twice the deviation of sum (m_l - m_s) e under the
    /// channel's noise model, and 0.5 % of the misfit left.
    needed: f64,
    /// Whether the model without it lost no other term ([`without_turned`]).
    alone: bool,
}

impl Comparison {
    /// How far the held-out gain clears what it needs (negative: it fails).
    fn margin(&self) -> f64 {
        self.heldout_without - self.heldout_with - self.needed
    }
}

fn compare_without(ctx: &Context, nested: Nested, terms: &[Term], i: usize) -> Comparison {
    // Against the model with the channel's refit kept (see `refitted`).
    let (w, turned) = without_turned(ctx, terms, i);
    let w = refitted(ctx, w, terms[i].channel);
    let bic_gain = bic(ctx, nested, &w) - bic(ctx, nested, terms);
    let (h_small, h_large) = (heldout(ctx, nested, &w), heldout(ctx, nested, terms));
    let c = terms[i].channel;
    let (with_c, without_c) = (contribution(ctx, terms, c), contribution(ctx, &w, c));
    let rows: Vec<usize> = (0..ctx.len()).filter(|&k| ctx.heldout_mask[k]).collect();
    let blocks: Vec<(usize, usize)> = rows.iter().map(|&k| ctx.data.bounds[k]).collect();
    // (m_l - m_s) in noise units, times the weight again: the coefficient of each block mean.
    let coefficients: Vec<f64> = rows
        .iter()
        .map(|&k| (with_c[k] - without_c[k]) * ctx.data.weight(c, k).powi(2))
        .collect();
    let diff = ctx.data.noise[c]
        .block_means_variance(&blocks, &coefficients)
        .max(0.0)
        .sqrt();
    Comparison {
        bic_gain,
        heldout_without: h_small,
        heldout_with: h_large,
        needed: heldout_needed(diff, h_small),
        alone: !turned,
    }
}
