//! Scoring the group through the contract's keys (the rules: [`super`]).

use std::fmt::Write as _;

use super::{Kind, Truth};
use crate::categories::{Category, Labelled};
use crate::reported::ReportedEffect;
use crate::Score;

/// How one recording was answered.
#[derive(Debug, Clone, PartialEq)]
pub struct Judgement {
    /// A described effect says what the truth says, and the held-out misfit fell.
    pub right: bool,
    /// Catalogue names reported on a recording with physics.
    pub claimed: Vec<String>,
    /// A null recording got an effect.
    pub false_alarm: bool,
}

/// `effect` is described (`"catalogue": false`) at the truth's stage, on its channels, with its
/// dependence.
fn describes(truth: &Truth, effect: &ReportedEffect) -> bool {
    let stage_right = effect
        .stage
        .as_deref()
        .is_some_and(|s| truth.stages.contains(&s));
    let listed = |c: &str| effect.channels.iter().any(|x| x == c);
    let inside = effect
        .channels
        .iter()
        .all(|c| truth.channels.contains(&c.as_str()) || truth.channels_also.contains(&c.as_str()));
    let channels_right = truth.channels.iter().all(|c| listed(c)) && inside;
    let depends_right = effect.depends_on.as_deref().is_some_and(|d| {
        d.iter().any(|q| truth.depends_any.contains(&q.as_str()))
            && d.iter()
                .all(|q| truth.depends_allowed.contains(&q.as_str()))
    });
    !effect.is_catalogue() && stage_right && channels_right && depends_right
}

/// Judge the effects a report gave for `truth`, with its held-out misfit before and after.
pub fn judge(truth: &Truth, effects: &[ReportedEffect], before: f64, after: f64) -> Judgement {
    if truth.kind.is_none() {
        return Judgement {
            right: false,
            claimed: Vec::new(),
            false_alarm: !effects.is_empty(),
        };
    }
    let claimed = effects
        .iter()
        .filter(|e| e.is_catalogue())
        .map(|e| e.name.clone())
        .collect();
    Judgement {
        right: after < before && effects.iter().any(|e| describes(truth, e)),
        claimed,
        false_alarm: false,
    }
}

/// The figures of one kind's recordings.
#[derive(Debug, Clone, PartialEq)]
pub struct KindRow {
    pub kind: Kind,
    pub recordings: usize,
    pub right: usize,
    /// Recordings with a catalogue name.
    pub claimed: usize,
    /// Mean held-out after/before over the recordings where it was measured.
    pub heldout_ratio_mean: f64,
}

/// The group's figures.
#[derive(Debug, Clone, PartialEq)]
pub struct Totals {
    /// Recordings with physics.
    pub recordings: usize,
    pub right: usize,
    pub claimed: usize,
    pub heldout_ratio_mean: f64,
    pub nulls: usize,
    pub false_alarms: usize,
}

impl Totals {
    pub fn right_share(&self) -> f64 {
        self.right as f64 / self.recordings.max(1) as f64
    }

    /// The bar: 80 % described right, no catalogue name claimed, the held-out misfit at
    /// most 0.6 of the baseline's on average, no false alarm.
    pub fn passes(&self) -> bool {
        self.recordings > 0
            && self.right_share() >= 0.8
            && self.claimed == 0
            && self.heldout_ratio_mean <= 0.6
            && self.false_alarms == 0
    }
}

/// The group's recordings with their truth, score and judgement.
fn judged<'a>(
    labelled: &'a [Labelled],
    scores: &'a [Score],
) -> Vec<(&'a Labelled, &'a Truth, &'a Score, Judgement)> {
    labelled
        .iter()
        .zip(scores)
        .filter(|(l, _)| l.category == Category::Unnamed)
        .filter_map(|(l, s)| {
            let t = l.unnamed.as_ref()?;
            let j = judge(t, &s.effects, s.heldout_before, s.heldout_after);
            Some((l, t, s, j))
        })
        .collect()
}

/// The mean of the finite ratios (NaN where none is).
fn mean_ratio<'a>(scores: impl Iterator<Item = &'a Score>) -> f64 {
    let r: Vec<f64> = scores
        .map(|s| s.heldout_after / s.heldout_before)
        .filter(|r| r.is_finite())
        .collect();
    if r.is_empty() {
        f64::NAN
    } else {
        r.iter().sum::<f64>() / r.len() as f64
    }
}

/// One row per kind, in the catalogue of kinds' order.
pub fn rows(labelled: &[Labelled], scores: &[Score]) -> Vec<KindRow> {
    let all = judged(labelled, scores);
    Kind::ALL
        .iter()
        .map(|&kind| {
            let of: Vec<_> = all.iter().filter(|x| x.1.kind == Some(kind)).collect();
            KindRow {
                kind,
                recordings: of.len(),
                right: of.iter().filter(|x| x.3.right).count(),
                claimed: of.iter().filter(|x| !x.3.claimed.is_empty()).count(),
                heldout_ratio_mean: mean_ratio(of.iter().map(|x| x.2)),
            }
        })
        .collect()
}

/// The group's totals (a recording whose diagnosis failed counts as wrong, its held-out ratio as
/// not measured).
pub fn totals(labelled: &[Labelled], scores: &[Score]) -> Totals {
    let all = judged(labelled, scores);
    let (with, nulls): (Vec<_>, Vec<_>) = all.iter().partition(|x| x.1.kind.is_some());
    Totals {
        recordings: with.len(),
        right: with.iter().filter(|x| x.3.right).count(),
        claimed: with.iter().filter(|x| !x.3.claimed.is_empty()).count(),
        heldout_ratio_mean: mean_ratio(with.iter().map(|x| x.2)),
        nulls: nulls.len(),
        false_alarms: nulls.iter().filter(|x| x.3.false_alarm).count(),
    }
}

/// A row per kind, the totals, then every recording.
pub fn table(labelled: &[Labelled], scores: &[Score]) -> String {
    let mut out = String::from(
        "| kind | stage | recordings | described right | catalogue name claimed | held-out after/before |\n|---|---|---|---|---|---|\n",
    );
    let all = judged(labelled, scores);
    for row in rows(labelled, scores) {
        let stage = all
            .iter()
            .find(|x| x.1.kind == Some(row.kind))
            .map_or(String::new(), |x| x.1.stages.join(" or "));
        let _ = writeln!(
            out,
            "| {} | {stage} | {} | {} of {} | {} of {} | {:.3} |",
            row.kind.name(),
            row.recordings,
            row.right,
            row.recordings,
            row.claimed,
            row.recordings,
            row.heldout_ratio_mean,
        );
    }
    let t = totals(labelled, scores);
    let _ = writeln!(
        out,
        "| **all kinds** | | {} | {:.0} % (need >= 80 %) | {} (need 0) | {:.3} (need <= 0.6) |",
        t.recordings,
        100.0 * t.right_share(),
        t.claimed,
        t.heldout_ratio_mean,
    );
    let _ = writeln!(
        out,
        "\nNull recordings with an effect (false alarms): {} of {} (need 0). **{}**\n",
        t.false_alarms,
        t.nulls,
        if t.passes() { "PASS" } else { "FAIL" }
    );
    out.push_str(&details(&all));
    out
}

/// Every recording: its truth, the answer, the judgement.
fn details(all: &[(&Labelled, &Truth, &Score, Judgement)]) -> String {
    let mut out = String::from(
        "| case | varied | truth | answer | right | catalogue name claimed | held-out after/before |\n|---|---|---|---|---|---|---|\n",
    );
    for (l, t, s, j) in all {
        let answer: Vec<String> = s.effects.iter().map(ReportedEffect::short).collect();
        let right = match (t.kind, j.right, j.false_alarm) {
            (None, _, true) => "**false alarm**",
            (None, _, false) => "quiet",
            (Some(_), true, _) => "yes",
            (Some(_), false, _) => "**no**",
        };
        let _ = writeln!(
            out,
            "| {:02} | {} | {} | {} | {right} | {} | {:.3} |",
            s.id,
            l.label,
            t.describe(),
            if s.found.first().is_some_and(|f| f == "<error>") {
                "<error>".to_string()
            } else {
                answer.join(" + ")
            },
            j.claimed.join(", "),
            s.heldout_after / s.heldout_before,
        );
    }
    out
}
