//! The lab sessions' judge. It reads a joint diagnosis only through the contract's JSON keys
//! (`tactile-session-diagnosis/1`: `shared[].name`, `shared[].recordings`, `shared[].params`,
//! `recordings[].file`, `recordings[].effects`, `recordings[].error`,
//! `validation.leave_one_out`, `undecided`), so any report that follows the contract is
//! judged alike.
//!
//! A session is right when every name acting on it is in its true place and nothing else is
//! named: each shared effect once under `shared`, over every recording (its `recordings`
//! absent or all of them); each test's own effect under that recording's `effects`; no other
//! name under `shared` or any recording; no recording in error. A friction session also needs
//! its mu within 20 %. A *false alarm* is a name concealed nowhere in the session (on a null
//! session, any name).

use serde_json::Value;
use sim::effects::Effect;

use super::design::LabKind;

/// Where a name acts: shared by the session, or one recording's own.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub enum Place {
    Shared,
    Own(String),
}

/// What a session hides and where.
#[derive(Debug, Clone, PartialEq)]
pub struct Truth {
    pub shared: Vec<Effect>,
    /// Each recording's file name and its own effects, in input order.
    pub own: Vec<(String, Vec<Effect>)>,
}

impl Truth {
    /// Every hidden effect with its place.
    fn placed(&self) -> Vec<(Place, &Effect)> {
        let shared = self.shared.iter().map(|e| (Place::Shared, e));
        let own = self
            .own
            .iter()
            .flat_map(|(f, es)| es.iter().map(move |e| (Place::Own(f.clone()), e)));
        shared.chain(own).collect()
    }

    fn files(&self) -> Vec<&str> {
        self.own.iter().map(|(f, _)| f.as_str()).collect()
    }

    /// The names hidden anywhere in the session.
    fn names(&self) -> Vec<&'static str> {
        self.placed().iter().map(|(_, e)| e.kind().name()).collect()
    }
}

/// One named effect as the report has it.
#[derive(Debug, Clone, PartialEq)]
pub struct Named {
    pub name: String,
    pub place: Place,
    /// For a shared effect, the files it acts on (`None`: all).
    pub recordings: Option<Vec<String>>,
    pub params: Value,
}

/// Every effect the report names: `shared` first, then each recording's `effects`.
pub fn named(report: &Value) -> Vec<Named> {
    let list = |v: &Value, key: &str| v.get(key).and_then(Value::as_array).cloned();
    let text = |v: &Value, key: &str| v.get(key).and_then(Value::as_str).map(str::to_string);
    let mut out = Vec::new();
    for s in list(report, "shared").unwrap_or_default() {
        out.push(Named {
            name: text(&s, "name").unwrap_or_default(),
            place: Place::Shared,
            recordings: list(&s, "recordings").map(|a| {
                a.iter()
                    .filter_map(|f| f.as_str().map(String::from))
                    .collect()
            }),
            params: s.get("params").cloned().unwrap_or(Value::Null),
        });
    }
    for r in list(report, "recordings").unwrap_or_default() {
        let file = text(&r, "file").unwrap_or_default();
        for e in list(&r, "effects").unwrap_or_default() {
            out.push(Named {
                name: text(&e, "name").unwrap_or_default(),
                place: Place::Own(file.clone()),
                recordings: None,
                params: e.get("params").cloned().unwrap_or(Value::Null),
            });
        }
    }
    out
}

/// One session's judgement.
#[derive(Debug, Clone, PartialEq)]
pub struct Judgement {
    pub right: bool,
    pub recordings_right: usize,
    pub recordings: usize,
    /// Names concealed nowhere in the session, as `name@place`.
    pub false_alarms: Vec<String>,
    /// Each hidden effect's primary parameter's relative error, where named in its place
    /// (`None`: not named there).
    pub param_errors: Vec<(String, Option<f64>)>,
    /// Mean over `validation.leave_one_out` of `rmse_after / rmse_before`.
    pub loo_ratio: Option<f64>,
    /// What the report named, for a table: `name` (shared), `name[files]` (shared over some),
    /// `file: name` (a recording's own).
    pub answer: Vec<String>,
    pub undecided: Vec<String>,
    /// Recordings reported in error, with their message.
    pub errors: Vec<String>,
    /// Keys the contract requires that the report lacks (not part of right: a figure).
    pub contract_gaps: Vec<String>,
}

impl Judgement {
    pub fn params_within(&self, share: f64) -> usize {
        let ok = |e: &Option<f64>| e.is_some_and(|e| e <= share);
        self.param_errors.iter().filter(|(_, e)| ok(e)).count()
    }
}

/// The share within which a primary parameter counts as found.
pub const PARAM_TOLERANCE: f64 = 0.2;

/// Judge one session's report against its truth.
pub fn judge(kind: LabKind, truth: &Truth, report: &Value) -> Judgement {
    let named = named(report);
    let files = truth.files();
    let covers_all = |n: &Named| {
        n.recordings.as_ref().is_none_or(|r| {
            let mut r: Vec<&str> = r.iter().map(String::as_str).collect();
            r.sort_unstable();
            r.dedup();
            let mut all = files.clone();
            all.sort_unstable();
            r == all
        })
    };
    // Exactly the truth in its places: the same multiset of (place, name), every shared one
    // over all recordings.
    let mut want: Vec<(Place, String)> = truth
        .placed()
        .into_iter()
        .map(|(p, e)| (p, e.kind().name().to_string()))
        .collect();
    let mut got: Vec<(Place, String)> = named
        .iter()
        .map(|n| (n.place.clone(), n.name.clone()))
        .collect();
    want.sort();
    got.sort();
    let errors = recording_errors(report);
    let param_errors = param_errors(truth, &named);
    let params_ok = !kind.needs_parameters()
        || param_errors
            .iter()
            .all(|(_, e)| e.is_some_and(|e| e <= PARAM_TOLERANCE));
    let right = want == got
        && named
            .iter()
            .filter(|n| n.place == Place::Shared)
            .all(covers_all)
        && errors.is_empty()
        && params_ok;
    let hidden = truth.names();
    Judgement {
        right,
        recordings_right: files
            .iter()
            .filter(|f| acting_on(&truth_named(truth), f) == acting_on(&named, f))
            .filter(|f| !errors.iter().any(|e| e.starts_with(&format!("{f}: "))))
            .count(),
        recordings: files.len(),
        false_alarms: named
            .iter()
            .filter(|n| !hidden.contains(&n.name.as_str()))
            .map(|n| format!("{}@{}", n.name, place_word(&n.place)))
            .collect(),
        param_errors,
        loo_ratio: loo_ratio(report),
        answer: named.iter().map(answer_cell).collect(),
        undecided: undecided(report),
        errors,
        contract_gaps: contract_gaps(report),
    }
}

/// The session-v1 keys every report carries: `format` (its value), `verdict`, `recordings`
/// (each with `file`), `shared`, `validation.leave_one_out`, and, since the amendment of
/// 2026-11-27, `undecided` and `contradicted` always (empty lists when there is nothing).
pub fn contract_gaps(report: &Value) -> Vec<String> {
    let mut gaps = Vec::new();
    if report.get("format").and_then(Value::as_str) != Some("tactile-session-diagnosis/1") {
        gaps.push("format".to_string());
    }
    for key in [
        "verdict",
        "recordings",
        "shared",
        "undecided",
        "contradicted",
    ] {
        if report.get(key).is_none() {
            gaps.push(key.to_string());
        }
    }
    let rows = report.get("recordings").and_then(Value::as_array);
    if rows.is_some_and(|r| {
        r.iter()
            .any(|x| x.get("file").and_then(Value::as_str).is_none())
    }) {
        gaps.push("recordings[].file".into());
    }
    if report.pointer("/validation/leave_one_out").is_none() {
        gaps.push("validation.leave_one_out".into());
    }
    gaps
}

/// The truth as the report would name it (shared over all recordings).
fn truth_named(truth: &Truth) -> Vec<Named> {
    truth
        .placed()
        .into_iter()
        .map(|(place, e)| Named {
            name: e.kind().name().into(),
            place,
            recordings: None,
            params: Value::Null,
        })
        .collect()
}

/// The names acting on `file`, each with whether it is shared: sorted.
fn acting_on(named: &[Named], file: &str) -> Vec<(bool, String)> {
    let mut v: Vec<(bool, String)> = named
        .iter()
        .filter(|n| match &n.place {
            Place::Shared => n
                .recordings
                .as_ref()
                .is_none_or(|r| r.iter().any(|x| x == file)),
            Place::Own(f) => f == file,
        })
        .map(|n| (n.place == Place::Shared, n.name.clone()))
        .collect();
    v.sort();
    v
}

fn place_word(p: &Place) -> &str {
    match p {
        Place::Shared => "shared",
        Place::Own(f) => f,
    }
}

fn answer_cell(n: &Named) -> String {
    match (&n.place, &n.recordings) {
        (Place::Shared, None) => n.name.clone(),
        (Place::Shared, Some(r)) => format!("{}[{}]", n.name, r.join(",")),
        (Place::Own(f), _) => format!("{f}: {}", n.name),
    }
}

/// Each hidden effect's primary parameter against the one named in its place.
fn param_errors(truth: &Truth, named: &[Named]) -> Vec<(String, Option<f64>)> {
    truth
        .placed()
        .into_iter()
        .map(|(place, e)| {
            let kind = e.kind();
            let primary = kind.param_names()[0];
            let want = e.params()[0];
            let found = named
                .iter()
                .find(|n| n.place == place && n.name == kind.name())
                .and_then(|n| n.params.get(primary))
                .and_then(Value::as_f64);
            let err = found.map(|f| ((f - want) / want).abs());
            (kind.name().to_string(), err)
        })
        .collect()
}

fn loo_ratio(report: &Value) -> Option<f64> {
    let rows = report.get("validation")?.get("leave_one_out")?.as_array()?;
    let ratios: Vec<f64> = rows
        .iter()
        .filter_map(|r| {
            let after = r.get("rmse_after")?.as_f64()?;
            let before = r.get("rmse_before")?.as_f64()?;
            (before > 0.0).then(|| after / before)
        })
        .collect();
    (!ratios.is_empty()).then(|| ratios.iter().sum::<f64>() / ratios.len() as f64)
}

/// The names of `undecided` (each entry's `effects`, or its `name`).
fn undecided(report: &Value) -> Vec<String> {
    let Some(list) = report.get("undecided").and_then(Value::as_array) else {
        return Vec::new();
    };
    list.iter()
        .flat_map(|u| match (u.get("effects"), u.get("name")) {
            (Some(Value::Array(a)), _) => a
                .iter()
                .filter_map(|x| x.as_str().map(String::from))
                .collect(),
            (_, Some(Value::String(s))) => vec![s.clone()],
            _ => Vec::new(),
        })
        .collect()
}

fn recording_errors(report: &Value) -> Vec<String> {
    let Some(rows) = report.get("recordings").and_then(Value::as_array) else {
        return vec!["<no recordings>: the report has no `recordings`".into()];
    };
    rows.iter()
        .filter_map(|r| {
            let e = r.get("error")?.as_str()?;
            let f = r.get("file").and_then(Value::as_str).unwrap_or("?");
            Some(format!("{f}: {e}"))
        })
        .collect()
}
