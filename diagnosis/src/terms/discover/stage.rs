//! Where a discovered term arises, from how the channels share it: each way the channels could
//! share a term is a hypothesis, its features selected on the channels it names, and the
//! criterion chooses among them.
//!
//! - **The material** (between the rod and the load): one term on the load, and on each output
//!   its share r_c dL, with r_c = s_c / L the calibrated model's output signal per newton of its
//!   load. One amplitude per feature for all channels: the outputs follow the load as the model
//!   says they do.
//! - **The load alone**: the load cell's own chain (electronics) where the outputs do not follow
//!   it: their chi-square with the share added (amplitude one) is worse by more than
//!   [`MIN_BIC_GAIN`]. Where the outputs cannot tell at their noise (within it), or none is
//!   measured (a test of the material alone), a term of the drive is the material's and one of
//!   time or temperature alone the electronics'.
//! - **The outputs together, not the load**: the same features on every compared output, an
//!   amplitude each: the transducer, where a function of the drive; their electronics (a shared
//!   supply or reference) where not.
//! - **One output alone**: that channel's electronics (the transducer where it is the only output
//!   compared, since "the outputs but not the load" is then all the data can say).

use super::super::fitting::{solve, Columns, Context};
use super::super::Term;
use super::dictionary::{Feature, Quantity};
use super::select::{explained, prices, select, Block, Problem, Rows};
use super::{term, FeatureInfo, Info};
use crate::candidate::MIN_BIC_GAIN;
use sim::effects::Stage;

/// How the channels share a term.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Shape {
    Load,
    Material,
    Outputs(Vec<usize>),
    Output(usize),
}

/// What every hypothesis is built from, per channel (`None` for a channel not compared): its
/// dictionary, the target (its residual less the fixed parts of its terms) and the columns
/// refitted beside a new term.
pub(super) struct Channels {
    pub dict: [Option<Vec<Feature>>; 4],
    pub target: [Vec<f64>; 4],
    pub others: [Columns; 4],
}

/// A hypothesis: its shape, the channels it selects on, for each joint feature its index in
/// each of those channels' dictionaries, and the joint features chosen with their net gain.
#[derive(Debug, Clone)]
pub(super) struct Hypothesis {
    pub shape: Shape,
    pub channels: Vec<usize>,
    pub joint: Vec<Vec<usize>>,
    pub chosen: Vec<usize>,
    pub net: f64,
}

impl Hypothesis {
    /// Feature `j` of the hypothesis as channel number `b` of [`Self::channels`] has it.
    pub fn feature<'c>(&self, ch: &'c Channels, b: usize, j: usize) -> &'c Feature {
        let c = self.channels[b];
        &ch.dict[c]
            .as_ref()
            .expect("a compared channel has a dictionary")[self.joint[j][b]]
    }

    /// Its problems on `rows`: one stacked problem (the load alone, the material, one output) or
    /// one per output (the outputs together).
    pub fn problems(&self, ctx: &Context, ch: &Channels, rows: &Rows) -> Vec<Problem> {
        let m = self.joint.len();
        let block = |b: usize, share: Option<&[f64]>| {
            let c = self.channels[b];
            let own = if share.is_some() { 0 } else { b };
            Block {
                channel: c,
                target: &ch.target[c],
                columns: (0..m)
                    .map(|j| {
                        let f = &self.feature(ch, own, j).column;
                        Some(match share {
                            Some(s) => f.iter().zip(s).map(|(f, s)| f * s).collect(),
                            None => f.clone(),
                        })
                    })
                    .collect(),
                others: &ch.others[c],
            }
        };
        match &self.shape {
            Shape::Outputs(_) => (0..self.channels.len())
                .map(|b| Problem::new(ctx, rows, &[block(b, None)], m))
                .collect(),
            Shape::Material => {
                let shares: Vec<Vec<f64>> = self.channels[1..]
                    .iter()
                    .map(|&c| response_per_newton(ctx, c))
                    .collect();
                let mut blocks = vec![block(0, None)];
                for (b, s) in shares.iter().enumerate() {
                    blocks.push(block(b + 1, Some(s)));
                }
                vec![Problem::new(ctx, rows, &blocks, m)]
            }
            _ => vec![Problem::new(ctx, rows, &[block(0, None)], m)],
        }
    }

    /// Amplitudes per feature: one per output together, one otherwise.
    fn amplitudes(&self) -> usize {
        match &self.shape {
            Shape::Outputs(o) => o.len(),
            _ => 1,
        }
    }

    /// Select its features on `rows`.
    pub fn select(&mut self, ctx: &Context, ch: &Channels, rows: &Rows) {
        let problems = self.problems(ctx, ch, rows);
        let lead: Vec<Feature> = (0..self.joint.len())
            .map(|j| self.feature(ch, 0, j).clone())
            .collect();
        let (chosen, net) = select(&problems, &prices(&lead, rows.n(), self.amplitudes()));
        self.chosen = chosen;
        self.net = net;
    }
}

/// Output `c`'s signal per newton of the load in the calibrated model, where the load is above a
/// hundredth of its largest (zero elsewhere: out of contact an output follows no load).
pub(super) fn response_per_newton(ctx: &Context, c: usize) -> Vec<f64> {
    let (s, l) = (ctx.signal(c), ctx.signal(0));
    let top = l.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    s.iter()
        .zip(&l)
        .map(|(s, l)| if l.abs() > 0.01 * top { s / l } else { 0.0 })
        .collect()
}

/// Every way the compared channels could share a term, its features selected.
pub(super) fn hypotheses(ctx: &Context, ch: &Channels, rows: &Rows) -> Vec<Hypothesis> {
    let outputs: Vec<usize> = (1..4).filter(|&c| ch.dict[c].is_some()).collect();
    let mut shapes: Vec<(Shape, Vec<usize>)> = Vec::new();
    if ch.dict[0].is_some() {
        shapes.push((Shape::Load, vec![0]));
        if !outputs.is_empty() {
            let mut all = vec![0];
            all.extend(&outputs);
            shapes.push((Shape::Material, all));
        }
    }
    if outputs.len() >= 2 {
        shapes.push((Shape::Outputs(outputs.clone()), outputs.clone()));
    }
    for &c in &outputs {
        shapes.push((Shape::Output(c), vec![c]));
    }
    use rayon::prelude::*;
    shapes
        .into_par_iter()
        .filter_map(|(shape, channels)| {
            let joint = joint_features(ch, &shape, &channels);
            let mut h = Hypothesis {
                shape,
                channels,
                joint,
                chosen: Vec::new(),
                net: 0.0,
            };
            h.select(ctx, ch, rows);
            (!h.chosen.is_empty()).then_some(h)
        })
        .collect()
}

/// The features a hypothesis selects among: the first channel's dictionary, each feature
/// matched in the others' by family and grid (the material's outputs take the load's own
/// features, times their shares).
fn joint_features(ch: &Channels, shape: &Shape, channels: &[usize]) -> Vec<Vec<usize>> {
    let dict = |c: usize| ch.dict[c].as_ref().expect("compared");
    let lead = dict(channels[0]);
    (0..lead.len())
        .filter_map(|j| {
            let f = &lead[j];
            channels
                .iter()
                .map(|&c| {
                    if c == channels[0] || *shape == Shape::Material {
                        Some(j)
                    } else {
                        dict(c)
                            .iter()
                            .position(|g| g.family == f.family && g.grid == f.grid)
                    }
                })
                .collect()
        })
        .collect()
}

/// The best way the channels share a term: the hypothesis that gains most, trimmed to the
/// outputs that carry it ([`trim`]). (Each output with a form of its own, tried beside it, took
/// more claims and no more right answers on the unnamed-physics group.)
pub(super) fn best(
    ctx: &Context,
    ch: &Channels,
    rows: &Rows,
    hs: Vec<Hypothesis>,
) -> Option<Hypothesis> {
    let mut h = hs.into_iter().max_by(|a, b| a.net.total_cmp(&b.net))?;
    trim(ctx, ch, &mut h, rows);
    Some(h)
}

/// Hypothesis `h` (the outputs together) on the outputs that carry its term: each keeps it
/// where its features remove more chi-square there than their price (an amplitude each, ln n,
/// and the criterion's margin); one output left is that output alone.
fn trim(ctx: &Context, ch: &Channels, h: &mut Hypothesis, rows: &Rows) {
    if !matches!(h.shape, Shape::Outputs(_)) || h.chosen.is_empty() {
        return;
    }
    let problems = h.problems(ctx, ch, rows);
    let price = h.chosen.len() as f64 * rows.n().max(2.0).ln() + MIN_BIC_GAIN;
    let keep: Vec<usize> = (0..h.channels.len())
        .filter(|&b| explained(&problems[b..=b], &h.chosen) > price)
        .collect();
    if keep.is_empty() || keep.len() == h.channels.len() {
        return;
    }
    h.channels = keep.iter().map(|&b| h.channels[b]).collect();
    h.joint = h
        .joint
        .iter()
        .map(|per| keep.iter().map(|&b| per[b]).collect())
        .collect();
    h.shape = match h.channels.as_slice() {
        [c] => Shape::Output(*c),
        cs => Shape::Outputs(cs.to_vec()),
    };
}

/// Where the term of `h` acts where the rod does not touch: the seconds of the fitting stretch
/// out of contact and the chi-square the term gains there, when the term as it is fits the
/// channels better, by more than the criterion's margin, than the same term held at zero
/// there. Neither the material nor the transducer acts without a load: such a term is the
/// electronics' (a motor's pickup moves with the rod, touching or not).
fn acts_out_of_contact(ctx: &Context, ch: &Channels, h: &Hypothesis) -> Option<(f64, f64)> {
    // The contract's travel is zero at first contact: at or below it the rod does not touch,
    // unless the load cell says it does (a test that starts under a preload has its first
    // contact before the record).
    let data = ctx.data;
    let load_clear =
        |k: usize| !ctx.used[0] || data.fit.y[0][k] - ctx.offset[0] <= 3.0 * data.noise[0].sd();
    let touching: Vec<f64> = (0..ctx.len())
        .map(|k| {
            if data.fit.rod_mm[k] <= 0.0 && load_clear(k) {
                0.0
            } else {
                1.0
            }
        })
        .collect();
    let clear: Vec<usize> = (0..ctx.len())
        .filter(|&k| ctx.fit_mask[k] && touching[k] == 0.0)
        .collect();
    if clear.is_empty() {
        return None;
    }
    let seconds: f64 = clear
        .iter()
        .map(|&k| ctx.block_span[k].1 - ctx.block_span[k].0)
        .sum();
    let material_outputs = matches!(h.shape, Shape::Material);
    let gain: f64 = (0..h.channels.len())
        .filter(|&b| !(material_outputs && b > 0))
        .map(|b| {
            let c = h.channels[b];
            let cols = columns(ch, h, b, &h.chosen);
            let others = &ch.others[c];
            let held = cols.scaled(&touching);
            match (
                solve(ctx, c, &held.joined(others)),
                solve(ctx, c, &cols.joined(others)),
            ) {
                (Some((_, in_contact)), Some((_, everywhere))) => in_contact - everywhere,
                _ => 0.0,
            }
        })
        .sum();
    (gain > MIN_BIC_GAIN).then_some((seconds, gain))
}

/// The stage of hypothesis `h` and why, in words.
pub(super) fn stage_of(ctx: &Context, ch: &Channels, h: &Hypothesis) -> (Stage, String) {
    let (stage, note) = stage_by_sharing(ctx, ch, h);
    if stage != Stage::Material {
        return (stage, note);
    }
    // Admissible physics: a material term may not give back work over a closed cycle.
    match load_loop(ctx, ch, h).filter(|l| l.gives_back_work()) {
        Some(l) => (
            Stage::Electronics,
            format!(
                "as the material's it would give back {:.3} N·mm of work over the {} closed loading cycles, which no passive material can: its loop runs the wrong way, as a reading that lags the rod does, so it is the instrument's timing or chain, not the material",
                -l.work_nmm, l.cycles
            ),
        ),
        None => (stage, note),
    }
}

/// The loop of hypothesis `h`'s load part ([`super::passivity`]), where `h` acts on the load
/// and the recording holds closed cycles (the rod out of contact before the first and after
/// the last); `None` else.
fn load_loop(ctx: &Context, ch: &Channels, h: &Hypothesis) -> Option<super::passivity::Loop> {
    if h.channels.first() != Some(&0) || !matches!(h.shape, Shape::Load | Shape::Material) {
        return None;
    }
    let cols = columns(ch, h, 0, &h.chosen);
    let (beta, _) = solve(ctx, 0, &cols.joined(&ch.others[0]))?;
    let part = cols.contribution(&beta[..cols.x.len()]);
    super::passivity::cycle_work(&ctx.data.fit.rod_mm, &part)
}

/// The stage from how the channels share the term alone ([`stage_of`] before the passivity
/// test).
fn stage_by_sharing(ctx: &Context, ch: &Channels, h: &Hypothesis) -> (Stage, String) {
    let drive = h
        .chosen
        .iter()
        .any(|&j| h.feature(ch, 0, j).follows_drive());
    // A term with a memory (of the load, of a regime change) may go on after the rod leaves:
    // the gel creeps back, a bridge cools. Only a term of the instant must vanish there.
    let memory = h.chosen.iter().any(|&j| {
        h.feature(ch, 0, j)
            .depends
            .iter()
            .any(|q| matches!(q, Quantity::LoadHistory | Quantity::TimeSinceChange))
    });
    if let Some((seconds, gain)) = (drive && !memory)
        .then(|| acts_out_of_contact(ctx, ch, h))
        .flatten()
    {
        return (
            Stage::Electronics,
            format!(
                "it acts over the {seconds:.1} s of the fitting stretch where the rod does not touch (travel at or below first contact, the load within its noise of its offset; chi-square {gain:.0} lower with it there), which neither the material nor the transducer does: the electronics"
            ),
        );
    }
    let by_drive = if drive {
        Stage::Material
    } else {
        Stage::Electronics
    };
    let outputs: Vec<usize> = (1..4).filter(|&c| ch.dict[c].is_some()).collect();
    match &h.shape {
        Shape::Material => (
            Stage::Material,
            "the load carries it and the outputs follow in proportion to their responses".into(),
        ),
        Shape::Load if outputs.is_empty() => (
            by_drive,
            "a test of the material alone: placed by whether it follows the drive".into(),
        ),
        Shape::Load => {
            let evidence = follow_evidence(ctx, ch, h, &outputs);
            if evidence < -MIN_BIC_GAIN {
                (
                    Stage::Electronics,
                    format!(
                        "the outputs do not follow it (chi-square higher by {:.0} were they to): the load cell's own chain",
                        -evidence
                    ),
                )
            } else {
                (
                    by_drive,
                    "the outputs cannot tell, at their noise, the material from the load cell"
                        .into(),
                )
            }
        }
        Shape::Outputs(_) if drive => (
            Stage::Transducer,
            "the outputs carry it and the load does not".into(),
        ),
        Shape::Outputs(_) => (
            Stage::Electronics,
            "on the outputs, unrelated to the drive: their shared electronics".into(),
        ),
        Shape::Output(_) if outputs.len() == 1 && drive => (
            Stage::Transducer,
            "the output carries it and the load does not (no other output compared)".into(),
        ),
        Shape::Output(_) => (
            Stage::Electronics,
            "one output alone: that channel's chain".into(),
        ),
    }
}

/// How much better the outputs fit with their shares of the load's term (amplitude one, each
/// output's refit beside it) than without, in chi-square; negative where they fit worse.
fn follow_evidence(ctx: &Context, ch: &Channels, h: &Hypothesis, outputs: &[usize]) -> f64 {
    let cols = columns(ch, h, 0, &h.chosen);
    let Some((beta, _)) = solve(ctx, 0, &cols.joined(&ch.others[0])) else {
        return 0.0;
    };
    let change = cols.contribution(&beta[..cols.x.len()]);
    outputs
        .iter()
        .map(|&c| {
            let share: Vec<f64> = response_per_newton(ctx, c)
                .iter()
                .zip(&change)
                .map(|(r, d)| r * d)
                .collect();
            let others = &ch.others[c];
            let with_share = Columns {
                x: others.x.clone(),
                fixed: Some(match &others.fixed {
                    Some(f) => f.iter().zip(&share).map(|(a, b)| a + b).collect(),
                    None => share,
                }),
            };
            match (solve(ctx, c, others), solve(ctx, c, &with_share)) {
                (Some((_, without)), Some((_, with))) => without - with,
                _ => 0.0,
            }
        })
        .sum()
}

/// The columns of joint features `chosen` on channel number `b` of the hypothesis.
fn columns(ch: &Channels, h: &Hypothesis, b: usize, chosen: &[usize]) -> Columns {
    Columns {
        x: chosen
            .iter()
            .map(|&j| h.feature(ch, b, j).column.clone())
            .collect(),
        fixed: None,
    }
}

/// Parameters the criterion counts for a term of `features` (one amplitude each) chosen out of
/// a dictionary of `m` on `n` rows: as [`prices`] prices them, in units of ln n.
fn n_params(features: &[&Feature], n: f64, m: usize) -> usize {
    let ln_n = n.max(2.0).ln();
    let choice = 2.0 * (m.max(2) as f64).ln() / ln_n;
    let grids = features.iter().filter(|f| f.grid.is_some()).count();
    (features.len() as f64 * (1.0 + choice)).ceil() as usize + grids
}

/// The terms of hypothesis `h` with features `chosen` (of its joint features), as discovered
/// effect `group` at `stage`.
pub(super) fn terms_of(
    ctx: &Context,
    ch: &Channels,
    h: &Hypothesis,
    chosen: &[usize],
    (group, stage, note): (usize, Stage, &str),
) -> Vec<Term> {
    let n = Rows::fitting(ctx).n();
    let info = |b: usize, propagated: bool| Info {
        group,
        stage,
        features: chosen
            .iter()
            .map(|&j| FeatureInfo::of(h.feature(ch, b, j)))
            .collect(),
        propagated,
        inclusion: Vec::new(),
        stage_note: note.to_string(),
        choice_chi2: choice_chi2(h),
    };
    let own = |b: usize| {
        let c = h.channels[b];
        let feats: Vec<&Feature> = chosen.iter().map(|&j| h.feature(ch, b, j)).collect();
        let m = ch.dict[c].as_ref().map_or(1, Vec::len);
        term(
            c,
            columns(ch, h, b, chosen),
            n_params(&feats, n, m),
            info(b, false),
        )
    };
    match &h.shape {
        Shape::Material => {
            let load = own(0);
            let change = match solve(ctx, 0, &load.columns.joined(&ch.others[0])) {
                Some((beta, _)) => load.columns.contribution(&beta[..chosen.len()]),
                None => vec![0.0; ctx.len()],
            };
            let mut out = vec![load];
            for &c in &h.channels[1..] {
                let share: Vec<f64> = response_per_newton(ctx, c)
                    .iter()
                    .zip(&change)
                    .map(|(r, d)| r * d)
                    .collect();
                let col = Columns {
                    x: vec![share],
                    fixed: None,
                };
                out.push(term(c, col, 1, info(0, true)));
            }
            out
        }
        Shape::Outputs(_) => (0..h.channels.len()).map(own).collect(),
        _ => vec![own(0)],
    }
}

/// The price in chi-square of having chosen `h`'s features among the joint features it was
/// offered: 2 ln M each, as the selection's extended BIC charges ([`super::select::prices`]).
pub(super) fn choice_chi2(h: &Hypothesis) -> f64 {
    h.chosen.len() as f64 * 2.0 * (h.joint.len().max(2) as f64).ln()
}
