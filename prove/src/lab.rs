//! The lab category of sessions (`tactile prove --sessions --category lab`): what a lab meets
//! when it presses one sensor several times in a sitting, diagnosed jointly and blind, judged
//! from the session's JSON alone ([`score`]).
//!
//! - **mixed**: two effects of the sensor or the gel shared by four tests (relaxation and a
//!   rotated chip, a lag and AC coupling, hysteresis and stiffening, ...) and one test with an
//!   effect of its own (a warm-up drift, mains pickup, a clip);
//! - **null on another model's fingertip**: nothing hidden, across azimuths, rod speeds or
//!   contact angles;
//! - **friction across speeds**: contact friction at an inclined contact, pressed at 6, 20 and
//!   60 mm/min (friction's force does not grow with the speed; a lag's does);
//! - **hysteresis or relaxation across speeds**: one of the two, at the same three speeds;
//! - **rates, gains and excitation**: each test at its own sample rate, amplifier gains and
//!   excitation (declared in its metadata), with one shared effect or none.
//!
//! Sessions alternate between our fingertip and another model's ([`crate::categories::OtherFingertip`]);
//! the null sessions are all another model's. The designs ([`design`]) are drawn from the
//! run's seed before any diagnosis runs and are never adjusted to it.

pub mod design;
pub mod generate;
pub mod score;
#[cfg(test)]
mod tests;

use std::fmt::Write as _;

use serde_json::Value;

pub use design::{Family, LabKind, Own, SessionDesign, TestDesign};
pub use generate::LabCase;
pub use score::{judge, Judgement, Place, Truth, PARAM_TOLERANCE};

/// The bar (issue 41): this share of sessions right, and no false alarm.
pub const BAR_RIGHT_SHARE: f64 = 0.9;

impl LabCase {
    /// What the session hides and where, with the file names the diagnosis is given.
    pub fn truth(&self) -> Truth {
        Truth {
            shared: self.design.shared.clone(),
            own: self
                .recordings
                .iter()
                .map(|(f, _)| f.clone())
                .zip(self.own.iter().cloned())
                .collect(),
        }
    }
}

/// One session's score: its judgement, the report it was judged on, and the time it took.
pub struct LabScore {
    pub id: usize,
    pub kind: LabKind,
    pub judgement: Judgement,
    /// The session's JSON (`None` when the session could not be diagnosed).
    pub report: Option<Value>,
    /// Why the session could not be diagnosed.
    pub failure: Option<String>,
    pub seconds: f64,
}

/// Diagnose every session jointly and blind (the truth only judges), and judge it.
pub fn run(cases: &[LabCase], opt: &diagnosis::Options) -> Vec<LabScore> {
    cases.iter().map(|c| run_one(c, opt)).collect()
}

fn run_one(c: &LabCase, opt: &diagnosis::Options) -> LabScore {
    let started = std::time::Instant::now();
    let inputs = c
        .recordings
        .iter()
        .map(|(n, r)| (n.clone(), Ok(r.clone())))
        .collect();
    let (report, failure) = match diagnosis::joint::diagnose_recordings(inputs, opt) {
        Ok(d) => match serde_json::to_value(&d.report) {
            Ok(v) => (Some(v), None),
            Err(e) => (None, Some(format!("the report does not serialise: {e}"))),
        },
        Err(e) => (None, Some(e.to_string())),
    };
    let truth = c.truth();
    let judgement = judge(
        c.design.kind,
        &truth,
        report.as_ref().unwrap_or(&Value::Null),
    );
    LabScore {
        id: c.design.id,
        kind: c.design.kind,
        judgement,
        report,
        failure,
        seconds: started.elapsed().as_secs_f64(),
    }
}

/// The bar's figures over `scores`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Totals {
    pub sessions: usize,
    pub right: usize,
    /// Sessions with at least one false alarm.
    pub false_alarm_sessions: usize,
}

impl Totals {
    pub fn of(scores: &[LabScore]) -> Self {
        Self {
            sessions: scores.len(),
            right: scores.iter().filter(|s| s.judgement.right).count(),
            false_alarm_sessions: scores
                .iter()
                .filter(|s| !s.judgement.false_alarms.is_empty())
                .count(),
        }
    }

    pub fn right_share(&self) -> f64 {
        self.right as f64 / self.sessions.max(1) as f64
    }

    pub fn passes(&self) -> bool {
        self.sessions > 0 && self.right_share() >= BAR_RIGHT_SHARE && self.false_alarm_sessions == 0
    }
}

/// Per kind and in total: sessions right, recordings right, sessions with a false alarm,
/// primary parameters within 20 %, the mean leave-one-out ratio, the time per session; then
/// the contract's missing keys and the bar.
pub fn table(scores: &[LabScore]) -> String {
    let mut out = String::from(
        "| kind | sessions right | recordings right | sessions with a false alarm | params within 20 % | leave-one-out after/before | s per session |\n|---|---|---|---|---|---|---|\n",
    );
    for kind in LabKind::ALL {
        let v: Vec<&LabScore> = scores.iter().filter(|s| s.kind == kind).collect();
        if !v.is_empty() {
            out.push_str(&row(kind.name(), &v));
        }
    }
    out.push_str(&row("**all**", &scores.iter().collect::<Vec<_>>()));
    out.push_str(&footer(scores));
    out
}

/// One line of [`table`] over the sessions `v`.
fn row(name: &str, v: &[&LabScore]) -> String {
    let j: Vec<&Judgement> = v.iter().map(|s| &s.judgement).collect();
    let right = j.iter().filter(|j| j.right).count();
    let recs: usize = j.iter().map(|j| j.recordings_right).sum();
    let recs_all: usize = j.iter().map(|j| j.recordings).sum();
    let alarms = j.iter().filter(|j| !j.false_alarms.is_empty()).count();
    let params: usize = j.iter().map(|j| j.param_errors.len()).sum();
    let within: usize = j.iter().map(|j| j.params_within(PARAM_TOLERANCE)).sum();
    let loo: Vec<f64> = j.iter().filter_map(|j| j.loo_ratio).collect();
    let loo = if loo.is_empty() {
        "–".to_string()
    } else {
        format!("{:.3}", loo.iter().sum::<f64>() / loo.len() as f64)
    };
    let params = if params == 0 {
        "–".to_string()
    } else {
        format!("{within}/{params}")
    };
    let secs = v.iter().map(|s| s.seconds).sum::<f64>() / v.len().max(1) as f64;
    let n = v.len();
    format!(
        "| {name} | {right}/{n} | {recs}/{recs_all} | {alarms}/{n} | {params} | {loo} | {secs:.0} |\n"
    )
}

/// The reports that lack a key the contract requires, then the bar.
fn footer(scores: &[LabScore]) -> String {
    let reports = scores.iter().filter(|s| s.report.is_some());
    let with_gaps = reports
        .clone()
        .filter(|s| !s.judgement.contract_gaps.is_empty())
        .count();
    let mut keys: Vec<&str> = reports
        .clone()
        .flat_map(|s| s.judgement.contract_gaps.iter().map(String::as_str))
        .collect();
    keys.sort_unstable();
    keys.dedup();
    let keys = if keys.is_empty() {
        String::new()
    } else {
        format!(" (`{}`)", keys.join("`, `"))
    };
    let t = Totals::of(scores);
    format!(
        "\nReports lacking a key the contract requires (not scored): {with_gaps} of {}{keys}.\n\n**{} sessions: right {:.0} % (need >= {:.0} %), sessions with a false alarm {} (need 0). {}**\n",
        reports.count(),
        t.sessions,
        100.0 * t.right_share(),
        100.0 * BAR_RIGHT_SHARE,
        t.false_alarm_sessions,
        if t.passes() { "PASS" } else { "FAIL" }
    )
}

/// One row per session: what it varies and hides, what was named, the figures.
pub fn details(scores: &[LabScore], cases: &[LabCase]) -> String {
    let mut out = String::from(
        "| id | kind | family | varies | truth | named | right | recordings | false alarms | param errors | LOO | undecided |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (s, c) in scores.iter().zip(cases) {
        let j = &s.judgement;
        let named = match &s.failure {
            Some(f) => format!("<error: {f}>"),
            None if j.answer.is_empty() => "–".into(),
            None => j.answer.join("; "),
        };
        let errs: Vec<String> = j
            .param_errors
            .iter()
            .map(|(n, e)| match e {
                Some(e) => format!("{n} {e:.2}"),
                None => format!("{n} –"),
            })
            .collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {}/{} | {} | {} | {} | {} |",
            s.id,
            s.kind.key(),
            family_word(c.design.family),
            c.design.varies,
            truth_cell(c),
            named,
            if j.right { "yes" } else { "**no**" },
            j.recordings_right,
            j.recordings,
            if j.false_alarms.is_empty() {
                "–".into()
            } else {
                j.false_alarms.join(", ")
            },
            errs.join(", "),
            j.loo_ratio.map_or("–".into(), |r| format!("{r:.3}")),
            j.undecided.join(", "),
        );
    }
    out
}

fn family_word(f: Family) -> String {
    match f {
        Family::Ours => "own".into(),
        Family::Other {
            exponent,
            linear_outputs,
        } => format!(
            "other (n {exponent:.2}{})",
            if linear_outputs { ", linear" } else { "" }
        ),
    }
}

/// The truth in a cell: shared effects with their primary parameter, then each test's own.
fn truth_cell(c: &LabCase) -> String {
    let p = |e: &sim::effects::Effect| format!("{} {:.3}", e.kind().name(), e.params()[0]);
    let mut cells: Vec<String> = c.design.shared.iter().map(p).collect();
    for ((f, _), own) in c.recordings.iter().zip(&c.own) {
        cells.extend(own.iter().map(|e| format!("{f}: {}", p(e))));
    }
    if cells.is_empty() {
        "–".into()
    } else {
        cells.join("; ")
    }
}
