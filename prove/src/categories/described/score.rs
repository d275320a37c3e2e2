//! Scoring the described physics through the contract's keys (the rules: [`super`]).

use std::fmt::Write as _;

use super::{Group, Truth};
use crate::categories::{Category, Labelled};
use crate::reported::ReportedEffect;
use crate::Score;

/// How one recording was answered.
#[derive(Debug, Clone, PartialEq)]
pub struct Judgement {
    /// An effect describes (or, at a new stage, names) the truth right.
    pub right: bool,
    /// Catalogue names the recording does not hide.
    pub claimed: Vec<String>,
}

/// `effect` says what `truth` says: stage, channels, and dependence or name.
fn matches(truth: &Truth, effect: &ReportedEffect) -> bool {
    let stage_right = effect
        .stage
        .as_deref()
        .is_some_and(|s| truth.stages.contains(&s));
    let has = |c: &&str| effect.channels.iter().any(|x| x == c);
    let inside = effect
        .channels
        .iter()
        .all(|c| truth.channels.contains(&c.as_str()) || truth.channels_also.contains(&c.as_str()));
    let channels_right = truth.channels.iter().all(|c| has(&c)) && inside;
    let what_right = match truth.catalogue_name {
        Some(name) => effect.is_catalogue() && effect.name == name,
        None => !effect.is_catalogue() && depends_right(truth, effect.depends_on.as_deref()),
    };
    stage_right && channels_right && what_right
}

/// `depends_on` holds one of the truth's defining quantities and nothing it does not allow.
fn depends_right(truth: &Truth, depends_on: Option<&[String]>) -> bool {
    let Some(d) = depends_on else {
        return false;
    };
    let defining =
        truth.depends_any.is_empty() || d.iter().any(|q| truth.depends_any.contains(&q.as_str()));
    defining
        && d.iter()
            .all(|q| truth.depends_allowed.contains(&q.as_str()))
}

/// Judge the effects a report gave for `truth`.
pub fn judge(truth: &Truth, effects: &[ReportedEffect]) -> Judgement {
    let right = effects.iter().any(|e| matches(truth, e));
    let claimed = effects
        .iter()
        .filter(|e| e.is_catalogue())
        .filter(|e| {
            Some(e.name.as_str()) != truth.catalogue_name && !truth.hidden.contains(&e.name)
        })
        .map(|e| e.name.clone())
        .collect();
    Judgement { right, claimed }
}

/// The acceptance figures of one group.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupSummary {
    pub recordings: usize,
    pub right_share: f64,
    /// Recordings with a catalogue name they do not hide.
    pub claimed: usize,
    pub heldout_ratio_mean: f64,
}

impl GroupSummary {
    /// The bar: 90 % right, no catalogue name claimed, held-out misfit at least halved
    /// on average.
    pub fn passes(&self) -> bool {
        self.recordings > 0
            && self.right_share >= 0.9
            && self.claimed == 0
            && self.heldout_ratio_mean <= 0.5
    }
}

/// The recordings of `group` with their truth and score.
fn of_group<'a>(
    labelled: &'a [Labelled],
    scores: &'a [Score],
    group: Group,
) -> impl Iterator<Item = (&'a Labelled, &'a Truth, &'a Score)> {
    labelled.iter().zip(scores).filter_map(move |(l, s)| {
        let t = l.truth.as_ref()?;
        (l.category == Category::Described(group)).then_some((l, t, s))
    })
}

/// The figures of `group` (a recording whose diagnosis failed counts as wrong, its held-out
/// ratio as not measured).
pub fn summary(labelled: &[Labelled], scores: &[Score], group: Group) -> GroupSummary {
    let mut n = 0;
    let mut right = 0;
    let mut claimed = 0;
    let mut ratios = Vec::new();
    for (_, t, s) in of_group(labelled, scores, group) {
        let j = judge(t, &s.effects);
        n += 1;
        right += usize::from(j.right);
        claimed += usize::from(!j.claimed.is_empty());
        let r = s.heldout_after / s.heldout_before;
        if r.is_finite() {
            ratios.push(r);
        }
    }
    GroupSummary {
        recordings: n,
        right_share: right as f64 / n.max(1) as f64,
        claimed,
        heldout_ratio_mean: if ratios.is_empty() {
            f64::NAN
        } else {
            ratios.iter().sum::<f64>() / ratios.len() as f64
        },
    }
}

/// A row per group, then every recording.
pub fn table(labelled: &[Labelled], scores: &[Score]) -> String {
    let mut out = String::from(
        "| group | recordings | described right | catalogue name claimed | held-out after/before | passes |\n|---|---|---|---|---|---|\n",
    );
    for group in [Group::OutOfCatalogue, Group::NewStage] {
        let s = summary(labelled, scores, group);
        let _ = writeln!(
            out,
            "| {} | {} | {:.0} % | {} of {} | {:.3} | {} |",
            group.name(),
            s.recordings,
            100.0 * s.right_share,
            s.claimed,
            s.recordings,
            s.heldout_ratio_mean,
            if s.passes() { "yes" } else { "no" },
        );
    }
    out.push_str(
        "\n| case | group | physics, varied | truth | answer | right | catalogue name claimed | held-out after/before |\n|---|---|---|---|---|---|---|---|\n",
    );
    for group in [Group::OutOfCatalogue, Group::NewStage] {
        for (l, t, s) in of_group(labelled, scores, group) {
            let j = judge(t, &s.effects);
            let answer: Vec<String> = s.effects.iter().map(ReportedEffect::short).collect();
            let _ = writeln!(
                out,
                "| {:02} | {} | {} | {} | {} | {} | {} | {:.3} |",
                s.id,
                group.name(),
                l.label,
                t.describe(),
                if s.found.first().is_some_and(|f| f == "<error>") {
                    "<error>".to_string()
                } else {
                    answer.join(" + ")
                },
                if j.right { "yes" } else { "**no**" },
                j.claimed.join(", "),
                s.heldout_after / s.heldout_before,
            );
        }
    }
    out
}

/// Both groups pass.
pub fn all_pass(labelled: &[Labelled], scores: &[Score]) -> bool {
    [Group::OutOfCatalogue, Group::NewStage]
        .iter()
        .all(|&g| summary(labelled, scores, g).passes())
}
