//! The category's figures and table: each recording's answer against the lab's simulation, and
//! against our own baseline beside it.

use std::fmt::Write as _;

use super::{Scored, SimCase};
use crate::Score;

/// A primary parameter within this share of the truth is right (the category's bar).
pub const PRIMARY_WITHIN: f64 = 0.10;

/// The acceptance figures of one way of diagnosing the category.
#[derive(Debug, Clone, Copy)]
pub struct Figures {
    pub cases: usize,
    pub correct_share: f64,
    pub false_alarms: usize,
    pub no_effect_cases: usize,
    /// Effect-free recordings not answered `no_significant_mismatch`.
    pub not_quiet: usize,
    /// Share of the true effects named with their parameters whose primary parameter is within
    /// [`PRIMARY_WITHIN`] of the truth, and how many were named.
    pub primary_within: f64,
    pub primary_named: usize,
    /// True effects answered as undecided against a calibration (no parameter to compare: a
    /// rotated chip beside the moment gains' ratio in a one-direction test).
    pub undecided: usize,
}

impl Figures {
    pub fn of(scores: &[&Score]) -> Self {
        let free: Vec<&&Score> = scores.iter().filter(|s| s.effect_free()).collect();
        let primary: Vec<f64> = scores
            .iter()
            .flat_map(|s| s.primary_errors.iter().map(|(_, e)| *e))
            .collect();
        let undecided = scores
            .iter()
            .map(|s| s.truth.iter().filter(|t| s.undecided.contains(t)).count())
            .sum();
        Self {
            cases: scores.len(),
            correct_share: scores.iter().filter(|s| s.correct).count() as f64
                / scores.len().max(1) as f64,
            false_alarms: free
                .iter()
                .filter(|s| !s.found.is_empty() || !s.described().is_empty())
                .count(),
            no_effect_cases: free.len(),
            not_quiet: free.iter().filter(|s| !s.quiet).count(),
            primary_within: primary.iter().filter(|&&e| e <= PRIMARY_WITHIN).count() as f64
                / primary.len().max(1) as f64,
            primary_named: primary.len(),
            undecided,
        }
    }

    /// The category's bar: 95 % of effect sets right, no false alarm, the primary parameter of
    /// every effect named within 10 %.
    pub fn passes(&self) -> bool {
        self.correct_share >= 0.95 && self.false_alarms == 0 && self.primary_within >= 1.0
    }

    fn line(&self, what: &str) -> String {
        format!(
            "{what}: effect set right in {:.1} % of {} (need >= 95 %); false alarms {} of {} effect-free (need 0), {} of them not `no_significant_mismatch`; primary parameter within {:.0} % in {:.1} % of the {} hidden effects named (need 100 %; {} more answered undecided against a calibration, without a parameter)",
            100.0 * self.correct_share,
            self.cases,
            self.false_alarms,
            self.no_effect_cases,
            self.not_quiet,
            100.0 * PRIMARY_WITHIN,
            100.0 * self.primary_within,
            self.primary_named,
            self.undecided
        )
    }
}

/// The category as markdown: the figures both ways, then one row per recording.
pub fn table(cases: &[SimCase], scored: &[Scored]) -> (String, Figures, Figures) {
    let sim: Vec<&Score> = scored.iter().map(|s| &s.against_simulation).collect();
    let ours: Vec<&Score> = scored.iter().map(|s| &s.against_ours).collect();
    let (fs, fo) = (Figures::of(&sim), Figures::of(&ours));
    let mut out = format!(
        "- **{}. {}**\n- {} (for comparison, not a bar).\n\n",
        fs.line("Against the lab's simulation"),
        if fs.passes() { "PASS" } else { "FAIL" },
        fo.line("The same recordings against our own FE baseline")
    );
    out.push_str(
        "| case | lab's model | simulation | empty | hidden | found against the simulation | right | primary error | load scale (true) | found against our FE | right |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (c, s) in cases.iter().zip(scored) {
        let a = &s.against_simulation;
        let errs: Vec<String> = a
            .primary_errors
            .iter()
            .map(|(k, e)| format!("{k}: {:.1} %", 100.0 * e))
            .collect();
        let lacks: Vec<&str> = ["load_N", "fz_V", "mx_V", "my_V"]
            .iter()
            .zip(c.lacks)
            .filter(|(_, l)| *l)
            .map(|(n, _)| *n)
            .collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} ({:.3}) | {} | {} |",
            c.case.id,
            c.model,
            c.form.name(),
            lacks.join(" "),
            dash(&a.truth.join(" + ")),
            dash(&a.answer(" + ")),
            yes(a.correct),
            errs.join(", "),
            s.load_scale.map_or("-".into(), |v| format!("{v:.3}")),
            c.load_scale,
            dash(&s.against_ours.answer(" + ")),
            yes(s.against_ours.correct),
        );
    }
    (out, fs, fo)
}

fn dash(s: &str) -> String {
    if s.is_empty() {
        "-".into()
    } else {
        s.to_string()
    }
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "**no**"
    }
}
