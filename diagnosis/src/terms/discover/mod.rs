//! Discovery: the missing term found in the residual itself, by a method rather than a list
//! (`docs/diagnosis-format.md`, "Discovered terms"). Where the catalogue and the library leave
//! structure, a dictionary of candidate features built from what the recording holds
//! ([`dictionary`]) is searched sparsely on each channel ([`select`]: forward–backward by the
//! information criterion with the dictionary's size counted); how the channels share what is
//! found says where it arises ([`stage`]: the load and the outputs in proportion to their
//! responses, the material; the outputs but not the load, the transducer; one channel alone, or
//! unrelated to the drive, that channel's electronics); the term then passes the tests every
//! effect passes (the criterion against the model without it, and the held-out stretch), and a
//! bootstrap of the selection gives each kept feature's inclusion probability
//! ([`bootstrap`], as E-SINDy does). A library term is replaced where a discovered term
//! describes what it took up better by the criterion and no worse held out: the library's
//! terms are named points of what the dictionary can write, and a name is kept only where
//! nothing the data suggest does better.

mod bootstrap;
pub(crate) mod dictionary;
mod named;
mod passivity;
mod report;
mod select;
mod stage;

pub(crate) use report::{describe, effect};

use std::sync::Arc;

use super::fitting::Context;
use super::score::{bic, columns_on, heldout, refit, Nested};
use super::{Term, TermKind};
use crate::candidate::{heldout_needed, MIN_BIC_GAIN};
use dictionary::{Feature, Quantities, Quantity};
use sim::effects::Stage;

/// At most this many discovered effects beside the library's terms: what remains is described
/// by a few terms or not at all.
const MAX_GROUPS: usize = 2;

/// One feature of a discovered term, as the report writes it.
#[derive(Debug, Clone)]
pub(crate) struct FeatureInfo {
    pub expr: String,
    pub unit: String,
    /// The column's scale: the coefficient in the feature's unit is beta / scale.
    pub scale: f64,
    pub depends: Vec<Quantity>,
    /// Its grid value: a time constant (s), or a damped oscillation's frequency (Hz, with
    /// `true`).
    pub grid: Option<(f64, bool)>,
}

impl FeatureInfo {
    fn of(f: &Feature) -> Self {
        Self {
            expr: f.expr.clone(),
            unit: f.unit.clone(),
            scale: f.scale,
            depends: f.depends.clone(),
            grid: f.grid.map(|g| (g, f.family.starts_with("ring"))),
        }
    }
}

/// What a discovered term on one channel is.
#[derive(Debug, Clone)]
pub(crate) struct Info {
    /// The discovered effect it belongs to (its terms on several channels are one effect).
    pub group: usize,
    pub stage: Stage,
    /// The features of its columns (for an output's share of a material term: the load's).
    pub features: Vec<FeatureInfo>,
    /// An output's share of a material term: its one column is the load's term times the
    /// output's response per newton, and its amplitude how far the output follows it.
    pub propagated: bool,
    /// Each feature's inclusion probability over the bootstrap resamples.
    pub inclusion: Vec<f64>,
    /// What the stage's test said, in words.
    pub stage_note: String,
    /// The price in chi-square of choosing this part's features among those the dictionary
    /// offered ([`stage::choice_chi2`]): a description from a dictionary is weighed against
    /// the library's with it, as the selection weighed it.
    pub choice_chi2: f64,
}

/// The library's result `terms` with what discovery adds or replaces.
pub(crate) fn discover(ctx: &Context, nested: Nested, terms: Vec<Term>) -> Vec<Term> {
    let q = Quantities::of(ctx);
    // The dictionary's description from scratch against the library's: the library's terms
    // stay unless it is better by the criterion and no worse held out.
    let scratch = grow(ctx, nested, &q, Vec::new());
    let own = |t: &[Term]| t.iter().any(|t| t.kind != TermKind::Recalibration);
    let terms = if own(&scratch) && own(&terms) && better(ctx, nested, &scratch, &terms) {
        scratch
    } else {
        terms
    };
    let terms = replace_library(ctx, nested, &q, terms);
    let terms = grow(ctx, nested, &q, terms);
    // The name first: a discovered form that a named effect describes as well is that effect.
    named::name_first(ctx, nested, terms)
}

/// `terms` with discovered effects added while one passes, up to [`MAX_GROUPS`] in all.
fn grow(ctx: &Context, nested: Nested, q: &Quantities, mut terms: Vec<Term>) -> Vec<Term> {
    while next_group(&terms) < MAX_GROUPS {
        match add(ctx, nested, q, &terms) {
            Some(with) => terms = with,
            None => break,
        }
    }
    terms
}

/// Whether `a` beats `b` as a description: a lower BIC by more than [`MIN_BIC_GAIN`] and a
/// lower held-out misfit by more than its own noise and half a percent of the misfit the
/// description set out to describe, as any effect must beat the model without it. A library
/// term is the smaller claim: a dictionary's terms that only match it stay out.
fn better(ctx: &Context, nested: Nested, a: &[Term], b: &[Term]) -> bool {
    let needed = heldout_needed(heldout_diff(ctx, b, a), nested.heldout_chi2);
    let priced = |t: &[Term]| bic(ctx, nested, t) + search_price(t);
    priced(a) < priced(b) - MIN_BIC_GAIN
        && heldout(ctx, nested, b) - heldout(ctx, nested, a) > needed
}

/// What the discovered terms among `terms` paid for being chosen from the dictionary: each
/// effect's [`Info::choice_chi2`] once (its terms on several channels carry the same).
pub(crate) fn search_price(terms: &[Term]) -> f64 {
    let mut groups: Vec<usize> = Vec::new();
    let mut total = 0.0;
    for info in terms.iter().filter_map(|t| t.info.as_deref()) {
        if !groups.contains(&info.group) {
            groups.push(info.group);
            total += info.choice_chi2;
        }
    }
    total
}

/// Each library term (one at a time, the best replacement first) replaced by what discovery
/// finds without it, where that is better by the criterion (by more than [`MIN_BIC_GAIN`]: the
/// library's term is the smaller claim) and no worse on the held-out stretch.
fn replace_library(
    ctx: &Context,
    nested: Nested,
    q: &Quantities,
    mut terms: Vec<Term>,
) -> Vec<Term> {
    loop {
        let best = library_groups(&terms)
            .into_iter()
            .filter_map(|group| {
                let kept: Vec<Term> = terms
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| !group.contains(i))
                    .map(|(_, t)| t.clone())
                    .collect();
                let mut kept = kept;
                refit(ctx, &mut kept);
                let with = add(ctx, nested, q, &kept)?;
                better(ctx, nested, &with, &terms).then(|| (bic(ctx, nested, &with), with))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match best {
            Some((_, with)) => terms = with,
            None => return terms,
        }
    }
}

/// The library's terms as the report groups them: one kind on several channels is one effect.
fn library_groups(terms: &[Term]) -> Vec<Vec<usize>> {
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, t) in terms.iter().enumerate() {
        if matches!(t.kind, TermKind::Recalibration | TermKind::Discovered) {
            continue;
        }
        match groups.iter_mut().find(|g| terms[g[0]].kind == t.kind) {
            Some(g) => g.push(i),
            None => groups.push(vec![i]),
        }
    }
    groups
}

/// `terms` with one more discovered effect, if one passes both tests: the way the channels
/// share it that gains most ([`stage`]), each part's features pruned by the held-out test.
fn add(ctx: &Context, nested: Nested, q: &Quantities, terms: &[Term]) -> Option<Vec<Term>> {
    let ch = channels(ctx, q, terms);
    let rows = select::Rows::fitting(ctx);
    let mut h = stage::best(ctx, &ch, &rows, stage::hypotheses(ctx, &ch, &rows))?;
    let group = next_group(terms);
    let reference = reference(ctx, terms, &h);
    let (stage, note) = stage::stage_of(ctx, &ch, &h);
    h.chosen = prune_heldout(ctx, nested, &reference, &ch, &h, (group, stage, &note));
    if h.chosen.is_empty() {
        return None;
    }
    // The stage of what the held-out test kept.
    let (stage, note) = stage::stage_of(ctx, &ch, &h);
    let new = stage::terms_of(ctx, &ch, &h, &h.chosen, (group, stage, &note));
    let mut with = joined(ctx, &reference, new);
    let gain = bic(ctx, nested, &reference) - bic(ctx, nested, &with);
    let (h_without, h_with) = (
        heldout(ctx, nested, &reference),
        heldout(ctx, nested, &with),
    );
    let needed = heldout_needed(heldout_diff(ctx, &reference, &with), nested.heldout_chi2);
    if !(gain > MIN_BIC_GAIN && h_without - h_with > needed) {
        return None;
    }
    bootstrap::inclusion(ctx, &ch, &h, &mut with, group);
    Some(with)
}

/// What the selection sees on each compared channel, given the terms already in the model.
fn channels(ctx: &Context, q: &Quantities, terms: &[Term]) -> stage::Channels {
    let mut ch = stage::Channels {
        dict: Default::default(),
        target: Default::default(),
        others: Default::default(),
    };
    for c in (0..4).filter(|&c| ctx.used[c]) {
        let others = others_on(ctx, terms, c);
        ch.target[c] = match &others.fixed {
            Some(f) => ctx.residual[c].iter().zip(f).map(|(r, f)| r - f).collect(),
            None => ctx.residual[c].clone(),
        };
        ch.others[c] = others;
        ch.dict[c] = Some(dictionary::features(ctx, q, c));
    }
    ch
}

/// `terms` with the refits a new term of `h` brings on its channels (the calibration along its
/// directions), refitted: what the term is weighed against.
fn reference(ctx: &Context, terms: &[Term], h: &stage::Hypothesis) -> Vec<Term> {
    let mut r = terms.to_vec();
    for &c in &h.channels {
        r = with_directions(ctx, r, c);
    }
    refit(ctx, &mut r);
    r
}

/// `reference` with the `new` terms, refitted.
fn joined(ctx: &Context, reference: &[Term], mut new: Vec<Term>) -> Vec<Term> {
    let mut with = reference.to_vec();
    with.append(&mut new);
    refit(ctx, &mut with);
    with
}

/// The chosen features of `h` without those that fail the held-out test: one at a time, the
/// one that fails by the most (the model's held-out chi-square with the term against with the
/// term less that feature, by more than twice its own noise and 0.5 % of the misfit left), until
/// every one passes. A feature that only fits the stretch it was fitted on is not part of it.
fn prune_heldout(
    ctx: &Context,
    nested: Nested,
    reference: &[Term],
    ch: &stage::Channels,
    h: &stage::Hypothesis,
    (group, stage, note): (usize, Stage, &str),
) -> Vec<usize> {
    let mut chosen = h.chosen.clone();
    // A feature's held-out gain is weighed against the misfit the description set out to
    // describe (the catalogue's model, before any term): a gain under half a percent of that
    // changes no conclusion (`heldout_needed`), however small what the others left.
    let h_reference = nested.heldout_chi2;
    let model = |set: &[usize]| {
        if set.is_empty() {
            reference.to_vec()
        } else {
            joined(
                ctx,
                reference,
                stage::terms_of(ctx, ch, h, set, (group, stage, note)),
            )
        }
    };
    while !chosen.is_empty() {
        let with = model(&chosen);
        let h_with = heldout(ctx, nested, &with);
        let worst = (0..chosen.len())
            .map(|i| {
                let mut rest = chosen.clone();
                rest.remove(i);
                let without = model(&rest);
                let h_without = heldout(ctx, nested, &without);
                let needed = heldout_needed(heldout_diff(ctx, &without, &with), h_reference);
                (i, h_without - h_with - needed)
            })
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match worst {
            Some((i, margin)) if margin <= 0.0 => {
                chosen.remove(i);
            }
            _ => break,
        }
    }
    chosen
}

/// What of the discovered terms' contributions `parts` no change of the calibration makes: each
/// channel's part less its projection on the calibration's directions ([`Context::directions`],
/// weighted on the fitting stretch), on both series. The catalogue is fitted again without this
/// (`crate::pipeline`): the rest is the calibration's to take up, and taken out with the term it
/// would pull the calibration along (a term in the load itself had shrunk an output's scale to
/// a thirtieth).
pub(crate) fn beyond_calibration(ctx: &Context, mut parts: super::AtStage) -> super::AtStage {
    let rows: Vec<usize> = (0..ctx.len()).filter(|&k| ctx.fit_mask[k]).collect();
    for c in 0..4 {
        let plain = ctx.orthonormal_of(c, &[vec![1.0; ctx.len()], ctx.signal(c)]);
        let directions = if ctx.directions[c].is_empty() {
            &plain
        } else {
            &ctx.directions[c]
        };
        for q in directions {
            let w2 = |k: usize| ctx.data.weight(c, k).powi(2);
            let a: f64 = rows
                .iter()
                .map(|&k| q[k] * parts.decimated[c][k] * w2(k))
                .sum();
            if a == 0.0 {
                continue;
            }
            parts.decimated[c]
                .iter_mut()
                .zip(q)
                .for_each(|(p, q)| *p -= a * q);
            let full_t = &ctx.data.full.t_s;
            for (p, &t) in parts.full[c].iter_mut().zip(full_t) {
                *p -= a * sim::effects::interpolate(ctx.t_s(), q, t);
            }
        }
    }
    parts
}

/// Discovered effect `group` in `terms` against the model without it: the BIC gain and the
/// held-out chi-square ratio (without over with).
pub(crate) fn group_evidence(
    ctx: &Context,
    nested: Nested,
    terms: &[Term],
    group: usize,
) -> (f64, f64) {
    let mut without: Vec<Term> = terms
        .iter()
        .filter(|t| t.info.as_ref().is_none_or(|i| i.group != group))
        .cloned()
        .collect();
    refit(ctx, &mut without);
    let gain = bic(ctx, nested, &without) - bic(ctx, nested, terms);
    let ratio = heldout(ctx, nested, &without) / heldout(ctx, nested, terms).max(1e-300);
    (gain, ratio)
}

/// The next discovered effect's number.
fn next_group(terms: &[Term]) -> usize {
    terms
        .iter()
        .filter_map(|t| t.info.as_ref().map(|i| i.group + 1))
        .max()
        .unwrap_or(0)
}

/// The columns refitted beside a new term on channel `c`: the channel's terms, and the
/// chosen model's calibration along its directions ([`Context::directions`]; its offset and
/// scale where they were not worked out).
pub(crate) fn others_on(ctx: &Context, terms: &[Term], c: usize) -> super::fitting::Columns {
    columns_on(&with_directions(ctx, terms.to_vec(), c), c, None)
}

/// `terms` with channel `c`'s refit along the calibration's directions in place of its plain
/// offset and scale (not refitted).
fn with_directions(ctx: &Context, mut terms: Vec<Term>, c: usize) -> Vec<Term> {
    let along = |t: &Term| t.channel == c && t.kind == TermKind::Recalibration;
    if terms.iter().any(|t| along(t) && !t.shape.is_empty()) {
        return terms;
    }
    terms.retain(|t| !along(t));
    let x = if ctx.directions[c].is_empty() {
        vec![vec![1.0; ctx.len()], ctx.signal(c)]
    } else {
        ctx.directions[c].clone()
    };
    terms.push(Term {
        kind: TermKind::Recalibration,
        channel: c,
        // Marks the refit along the directions (the plain one has no shape).
        shape: vec![1.0],
        beta: vec![0.0; x.len()],
        columns: super::fitting::Columns { x, fixed: None },
        n_params: 0,
        info: None,
    });
    terms
}

/// The deviation, under the noise model, of the held-out chi-square difference between two
/// models that differ by `a` against `b` on some channels (as `search::compare_without` weighs
/// one term, summed over the channels).
fn heldout_diff(ctx: &Context, a: &[Term], b: &[Term]) -> f64 {
    (0..4)
        .filter(|&c| ctx.used[c])
        .map(|c| {
            let (pa, pb) = (
                super::score::contribution(ctx, a, c),
                super::score::contribution(ctx, b, c),
            );
            heldout_noise(ctx, c, &pb, &pa).powi(2)
        })
        .sum::<f64>()
        .sqrt()
}

/// The deviation under channel `c`'s noise model of the held-out chi-square difference between
/// two models of the channel that differ by `with - without` (`search::compare_without`).
pub(crate) fn heldout_noise(ctx: &Context, c: usize, with: &[f64], without: &[f64]) -> f64 {
    let rows: Vec<usize> = (0..ctx.len()).filter(|&k| ctx.heldout_mask[k]).collect();
    let blocks: Vec<(usize, usize)> = rows.iter().map(|&k| ctx.data.bounds[k]).collect();
    let coefficients: Vec<f64> = rows
        .iter()
        .map(|&k| (with[k] - without[k]) * ctx.data.weight(c, k).powi(2))
        .collect();
    ctx.data.noise[c]
        .block_means_variance(&blocks, &coefficients)
        .max(0.0)
        .sqrt()
}

/// A new discovered term on channel `c` from `cols` (the chosen features' columns).
pub(crate) fn term(
    c: usize,
    columns: super::fitting::Columns,
    n_params: usize,
    info: Info,
) -> Term {
    let k = columns.x.len();
    Term {
        kind: TermKind::Discovered,
        channel: c,
        shape: Vec::new(),
        columns,
        beta: vec![0.0; k],
        n_params,
        info: Some(Arc::new(info)),
    }
}
