//! A session diagnosed jointly (`docs/session-format.md`): one model of the sensor and the gel
//! for every recording of a session, its effects shared or per recording as the data decide,
//! and each recording predicted from the shared physics of the others (leave-one-out).
//!
//! The steps: each recording diagnosed alone ([`crate::diagnose`]: its own effects, its
//! held-out stretch, its baseline's RMSEs) -> each calibrated alone (the session's starting
//! point) -> the session's search (`search`) -> the leave-one-out validation (`loo`) -> the
//! report (`assemble`), its JSON ([`json_text`]) and its page ([`write_report`]; `html`,
//! `tables`, `validation`).

mod assemble;
mod each;
mod headline;
mod html;
#[cfg(test)]
mod html_tests;
mod loo;
mod model;
pub mod output;
mod search;
mod seen;
mod tables;
mod transfer;
mod update;
mod validation;
mod verdict;

pub use html::{report_html, write_report};

use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;
use recording::Recording;
use sim::effects::EffectKind;

use crate::fit::{Model, Setup};
use crate::inputs::InputError;
use crate::options::Options;
use crate::outcome::{Diagnosis, PlotData};
use crate::pipeline::diagnose_kept;
use crate::prepared::Prepared;
use model::{JointFit, Layout};
use output::{Protocol, SessionReport};
use search::{Fitted, Search, OWN_ALWAYS};

/// Iterations of each recording's own calibration, the session's start.
const BASE_ITERATIONS: usize = 80;

/// Why a session could not be analysed at all.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum JointError {
    /// The inputs are not one sensor's recordings, each once ([`crate::inputs`]).
    #[error(transparent)]
    Input(#[from] InputError),
    /// No input could be read and diagnosed; each file's reason follows.
    #[error("no recording of the session could be analysed: {0}")]
    NothingUsable(String),
}

impl sysexit::ExitStatus for JointError {
    fn exit_code(&self) -> u8 {
        match self {
            Self::Input(e) => sysexit::ExitStatus::exit_code(e),
            Self::NothingUsable(_) => sysexit::DATA,
        }
    }
}

/// A session's diagnosis: the contract's report and each recording's own diagnosis (`Err`:
/// the one-line reason it could not be analysed).
pub struct SessionDiagnosis {
    pub report: SessionReport,
    pub singles: Vec<(String, Result<Diagnosis, String>)>,
    /// Per input file, in `singles`' order, its series as the session's model sees them: the
    /// recording, the baseline calibrated to it alone, and as `improved` the session's model
    /// (`None`: not analysed).
    pub plots: Vec<Option<PlotData>>,
}

/// OUT.json's text for `d`, as `tactile diagnose --joint` writes it (pretty, one final newline).
pub fn json_text(d: &SessionDiagnosis) -> serde_json::Result<String> {
    Ok(serde_json::to_string_pretty(&d.report)? + "\n")
}

/// A recording's file name.
pub fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |s| s.to_string_lossy().into_owned(),
    )
}

/// The names the recordings at `files` have in the session's output: each its file name, but
/// the path as given where another recording has the same file name (`day1/rec.csv`,
/// `day2/rec.csv`).
pub fn row_names(files: &[PathBuf]) -> Vec<String> {
    let names: Vec<String> = files.iter().map(|f| file_name(f)).collect();
    names
        .iter()
        .zip(files)
        .map(|(name, path)| {
            if names.iter().filter(|n| *n == name).count() > 1 {
                path.display().to_string()
            } else {
                name.clone()
            }
        })
        .collect()
}

/// Diagnose the recordings `inputs` name (files, and for a folder every `*.csv` in it) jointly.
/// Before any work the inputs are checked ([`crate::inputs`]): each there, each recording once
/// by content, and, once read, of one sensor in one fingertip.
pub fn diagnose_session(inputs: &[PathBuf], opt: &Options) -> Result<SessionDiagnosis, JointError> {
    let files = crate::inputs::recordings(inputs)?;
    let read: Vec<(String, Result<Recording, String>)> = files
        .iter()
        .zip(row_names(&files))
        .map(|(path, name)| (name, recording::read(path).map_err(|e| e.to_string())))
        .collect();
    // Named by their paths as given here, as every other refusal of an input is.
    let paths: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    crate::inputs::one_sensor(
        paths
            .iter()
            .zip(&read)
            .filter_map(|(path, (_, rec))| Some((path.as_str(), &rec.as_ref().ok()?.meta))),
    )?;
    diagnose_recordings(read, opt)
}

/// Diagnose recordings already read (each named, or the one-line reason it could not be read)
/// jointly. The readable ones must be of one sensor in one fingertip
/// ([`crate::inputs::one_sensor`]), judged against the first.
pub fn diagnose_recordings(
    inputs: Vec<(String, Result<Recording, String>)>,
    opt: &Options,
) -> Result<SessionDiagnosis, JointError> {
    if inputs.is_empty() {
        return Err(InputError::Nothing.into());
    }
    crate::inputs::one_sensor(
        inputs
            .iter()
            .filter_map(|(name, rec)| Some((name.as_str(), &rec.as_ref().ok()?.meta))),
    )?;
    let started = Instant::now();
    let files: Vec<String> = inputs.iter().map(|(f, _)| f.clone()).collect();
    let loaded: Vec<Loaded> = inputs
        .into_par_iter()
        .map(|(name, rec)| {
            let rec = rec?;
            let (d, p) = diagnose_kept(&rec, &name, opt).map_err(|e| format!("{name}: {e}"))?;
            Ok((rec, d, p))
        })
        .collect();
    let ok: Vec<usize> = (0..loaded.len()).filter(|&i| loaded[i].is_ok()).collect();
    if ok.is_empty() {
        let reasons: Vec<String> = loaded
            .iter()
            .filter_map(|l| l.as_ref().err().cloned())
            .collect();
        return Err(JointError::NothingUsable(reasons.join("; ")));
    }
    let diags: Vec<&Diagnosis> = ok
        .iter()
        .map(|&i| &loaded[i].as_ref().expect("ok").1)
        .collect();
    let recs: Vec<&Recording> = ok
        .iter()
        .map(|&i| &loaded[i].as_ref().expect("ok").0)
        .collect();
    let names: Vec<String> = ok.iter().map(|&i| files[i].clone()).collect();
    let read: Vec<&Prepared> = ok
        .iter()
        .map(|&i| &loaded[i].as_ref().expect("ok").2)
        .collect();
    let as_found = prepare_all(&read, &diags, &[]);
    let (mut report, as_is, mut plots) =
        session_report(&as_found, &diags, &recs, &names, opt, Vec::new());
    // A sign that a recording's own diagnosis found flipped (a wire) is that test's where the
    // session as read agrees: it needs that output's scale per recording, and this
    // recording's of the other sign than the rest (one sensor's sensitivity does not turn
    // over between tests). The session is then fitted again with the sign turned back. Left
    // as read, the flipped moment's scale had been predicted for each recording from the
    // others' (10 and 32 times the baseline's held-out misfit); but a rotated chip can look
    // like a flip to one recording, and there the session's shared turn fits with one scale.
    let flips = confirmed_flips(&diags, &as_is);
    if flips.iter().any(|f| !f.is_empty()) {
        let turned = prepare_all(&read, &diags, &flips);
        (report, _, plots) = session_report(&turned, &diags, &recs, &names, opt, flips);
    }
    report.recordings = merge_rows(&files, &loaded, report.recordings);
    report.summary = headline::sentence(&report);
    report.seconds = started.elapsed().as_secs_f64();
    let mut plots = plots.into_iter();
    let plots = loaded
        .iter()
        .map(|l| l.as_ref().ok().and_then(|_| plots.next()))
        .collect();
    let singles = files
        .into_iter()
        .zip(loaded)
        .map(|(f, l)| (f, l.map(|(_, d, _)| d)))
        .collect();
    Ok(SessionDiagnosis {
        report,
        singles,
        plots,
    })
}

/// Each analysed recording ready for the session (`read`: as read for its own diagnosis):
/// without what its own diagnosis found at a stage the session does not search (a sensing
/// element's relaxation, which a shared gel's would otherwise take up), and with the channels
/// in `flips` (per recording, may be empty) turned back (`Prepared::for_session`).
fn prepare_all(read: &[&Prepared], diags: &[&Diagnosis], flips: &[Vec<usize>]) -> Vec<Prepared> {
    (0..read.len())
        .map(|r| {
            let mut p = read[r].clone();
            p.for_session(
                diags[r].at_stage.as_ref(),
                flips.get(r).map_or(&[][..], Vec::as_slice),
            );
            p
        })
        .collect()
}

/// The session of `prepared` searched, validated and reported, its fitted model, and each
/// recording's series under it.
fn session_report(
    prepared: &[Prepared],
    diags: &[&Diagnosis],
    recs: &[&Recording],
    names: &[String],
    opt: &Options,
    flipped: Vec<Vec<usize>>,
) -> (SessionReport, Fitted, Vec<PlotData>) {
    let setups: Vec<Setup> = prepared.iter().map(|p| p.setup(opt)).collect();
    let members = Members {
        files: names.to_vec(),
        prepared,
        setups: setups.iter().collect(),
        diags: diags.to_vec(),
        protocols: recs
            .iter()
            .zip(prepared)
            .map(|(r, p)| protocol(r, p))
            .collect(),
        flipped,
    };
    let outcome = members.search();
    let loo = loo::leave_one_out(&members, &outcome.fitted);
    let (outcome, loo) = transfer::transferring(&members, outcome, loo);
    let (report, plots) = assemble::report(&members, &outcome, loo);
    (report, outcome.fitted, plots)
}

/// Per recording, the outputs (indices of `data::CHANNELS`) its own diagnosis found read with
/// their sign inverted and whose scale the session `fitted` as read per recording, of the
/// other sign than the other recordings' median.
fn confirmed_flips(diags: &[&Diagnosis], fitted: &Fitted) -> Vec<Vec<usize>> {
    let scale = |r: usize, c: usize| fitted.fit.full[r][crate::fit::SCALE_AT + c - 1];
    diags
        .iter()
        .enumerate()
        .map(|(r, d)| {
            inverted_channels(d)
                .into_iter()
                .filter(|&c| c >= 1 && fitted.layout.own_scales.contains(&(c - 1)))
                .filter(|&c| {
                    let mut others: Vec<f64> = (0..diags.len())
                        .filter(|&o| o != r)
                        .map(|o| scale(o, c))
                        .collect();
                    others.sort_by(f64::total_cmp);
                    let median = others.get(others.len() / 2).copied().unwrap_or(0.0);
                    scale(r, c) * median < 0.0
                })
                .collect()
        })
        .collect()
}

/// The channels (indices of `data::CHANNELS`) a recording's own diagnosis found read with
/// their sign inverted.
fn inverted_channels(d: &Diagnosis) -> Vec<usize> {
    d.report
        .effects
        .iter()
        .filter(|e| e.name == "inverted_sign")
        .flat_map(|e| &e.channels)
        .filter_map(|n| crate::data::CHANNELS.iter().position(|c| c == n))
        .collect()
}

/// The analysed recordings' rows in input order, with an error row for each file that could
/// not be analysed.
fn merge_rows(
    files: &[String],
    loaded: &[Loaded],
    analysed: Vec<output::RecordingRow>,
) -> Vec<output::RecordingRow> {
    let mut analysed = analysed.into_iter();
    files
        .iter()
        .zip(loaded)
        .map(|(f, l)| match l {
            Ok(_) => analysed.next().expect("one row per analysed recording"),
            Err(e) => output::RecordingRow {
                file: f.clone(),
                verdict: None,
                effects: None,
                fit: None,
                protocol: None,
                remains: None,
                error: Some(e.replace(['\r', '\n'], " ")),
            },
        })
        .collect()
}

/// A recording of the session read, diagnosed alone and ready to fit as read, or why not.
type Loaded = Result<(Recording, Diagnosis, Prepared), String>;

/// The analysed recordings of a session, in input order.
pub(crate) struct Members<'s, 'a> {
    pub files: Vec<String>,
    pub prepared: &'a [Prepared],
    pub setups: Vec<&'s Setup<'a>>,
    pub diags: Vec<&'s Diagnosis>,
    pub protocols: Vec<Protocol>,
    /// Per recording, the channels turned back from an inverted sign its own diagnosis found
    /// (empty: none, or the session that keeps them as read).
    pub flipped: Vec<Vec<usize>>,
}

/// What the session's search found.
pub(crate) struct Outcome {
    pub fitted: Fitted,
    pub tried: Vec<output::SessionCandidate>,
    /// Per shared effect, its gain over the session without it.
    pub gains: Vec<(EffectKind, search::Gain)>,
    /// The catalogue effects the session decided (searched shared, or the jig's turn): what a
    /// recording alone said of them is replaced by the session's answer.
    pub decided: Vec<EffectKind>,
}

impl Members<'_, '_> {
    fn search(&self) -> Outcome {
        // The moment vector's turn is each recording's own: the jig is set anew for every
        // test, within its mounting tolerance. A chip rotated on its mount is the turn all
        // recordings share beyond that tolerance (`assemble`), so it is not searched shared.
        let own: Vec<Vec<EffectKind>> = self
            .diags
            .iter()
            .zip(&self.setups)
            .map(|(d, s)| {
                let mut k = own_kinds(d);
                if s.used[2] && s.used[3] {
                    k.push(EffectKind::Crosstalk);
                }
                k
            })
            .collect();
        let base: Vec<Vec<f64>> = self
            .setups
            .par_iter()
            .map(|s| {
                Model::new(s, &[], s.initial_baseline())
                    .fit(BASE_ITERATIONS)
                    .full
            })
            .collect();
        let empty = Layout {
            shared: Vec::new(),
            own: vec![Vec::new(); self.setups.len()],
            own_scales: Vec::new(),
        };
        let start = Fitted {
            layout: empty.clone(),
            fit: JointFit::start(base),
        };
        let mut search = Search {
            setups: self.setups.clone(),
            tried: Vec::new(),
        };
        let null = search.fit_first(Layout { own, ..empty }, &start);
        let scales: Vec<usize> = (0..3)
            .filter(|&c| self.setups.iter().filter(|s| s.used[c + 1]).count() >= 2)
            .collect();
        // Effects first, with one scale per output: a scale per recording would take up part
        // of what a rotated chip does at each azimuth. The effects are searched again with the
        // scales the data chose; the backward step then drops what a per-recording scale made
        // redundant.
        let candidates = self.candidates();
        let cur = search.forward(null, &candidates);
        let one_scale = cur.layout.own_scales.clone();
        let mut cur = search.scales(cur, &scales, &start);
        // With the scales as they were, the forward step's last round would be tried again.
        if cur.layout.own_scales != one_scale {
            cur = search.forward(cur, &candidates);
        }
        let (cur, gains) = search.backward(cur);
        let fitted = search.per_recording(cur);
        Outcome {
            fitted,
            tried: search.tried,
            gains,
            decided: [candidates, vec![EffectKind::Crosstalk]].concat(),
        }
    }

    /// The catalogue effects a session may share: those some recording's protocol allows, and
    /// those only the session's variation shows (a lag or relaxation across rod speeds). A
    /// rotated chip is read from the recordings' own turns (`assemble`).
    fn candidates(&self) -> Vec<EffectKind> {
        let speeds = distinct(self.protocols.iter().map(|p| p.rod_speed_mm_per_min), 0.2);
        EffectKind::ALL
            .into_iter()
            .filter(|k| !OWN_ALWAYS.contains(k) && *k != EffectKind::Crosstalk)
            .filter(|&k| {
                let alone = self
                    .setups
                    .iter()
                    .zip(self.prepared)
                    .any(|(s, p)| p.features(s).allows(k).is_ok());
                let across = match k {
                    EffectKind::TimeOffset | EffectKind::ViscoelasticRelaxation => speeds.len() > 1,
                    _ => false,
                };
                alone || across
            })
            .collect()
    }
}

/// The catalogue effects a recording's own diagnosis found that belong to it alone (its drift,
/// its saturation): fitted per recording in every session model.
fn own_kinds(d: &Diagnosis) -> Vec<EffectKind> {
    let kinds = d
        .report
        .effects
        .iter()
        .filter(|e| e.catalogue && !e.channels.iter().any(|c| c == "load_N"))
        .filter_map(|e| EffectKind::from_name(&e.name))
        .filter(|k| *k != EffectKind::MainsInterference && OWN_ALWAYS.contains(k));
    distinct_kinds(kinds)
}

/// `kinds` each once, in their first order (a relaxation's two Prony terms are one effect).
pub(crate) fn distinct_kinds(kinds: impl IntoIterator<Item = EffectKind>) -> Vec<EffectKind> {
    kinds.into_iter().fold(Vec::new(), |mut v, k| {
        if !v.contains(&k) {
            v.push(k);
        }
        v
    })
}

/// A recording's contact angle, azimuth and rod speed (the metadata's, else the median speed
/// of the rod while it moves).
fn protocol(rec: &Recording, p: &Prepared) -> Protocol {
    let speed = rec.meta.rod_speed_mm_per_min.unwrap_or_else(|| {
        let (t, rod) = (&p.data.fit.t_s, &p.data.fit.rod_mm);
        let mut v: Vec<f64> = t
            .windows(2)
            .zip(rod.windows(2))
            .map(|(t, r)| ((r[1] - r[0]) / (t[1] - t[0]).max(1e-12)).abs() * 60.0)
            .filter(|v| *v > 1e-3)
            .collect();
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(0.0)
    });
    Protocol {
        contact_angle_deg: rec.meta.contact_angle_deg,
        azimuth_deg: rec.meta.azimuth_deg,
        rod_speed_mm_per_min: speed,
    }
}

/// The distinct values of `v`, sorted: values within `rel` of each other (relative) or 0.5 of
/// a unit are one.
pub(crate) fn distinct(v: impl Iterator<Item = f64>, rel: f64) -> Vec<f64> {
    let mut all: Vec<f64> = v.filter(|x| x.is_finite()).collect();
    all.sort_by(f64::total_cmp);
    let mut out: Vec<f64> = Vec::new();
    for x in all {
        let same = out
            .last()
            .is_some_and(|&y| (x - y).abs() <= 0.5_f64.max(rel * y.abs()));
        if !same {
            out.push(x);
        }
    }
    out
}
