//! A whole session at once: diagnose every recording of a test session in parallel, write each
//! one's OUT.json and report into one folder, and a summary of the session (`summary.csv`, and
//! `summary.html` with each parameter plotted across the recordings).
//!
//! One recording that cannot be analysed (missing, malformed, unusable) becomes an `error` row
//! and never stops the others. Recordings are read inside their task and dropped once
//! diagnosed, so at most a few are in memory at a time, not the whole session.

mod csv;
mod html;
mod plot;
mod table;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use rayon::prelude::*;

use crate::inputs::InputError;
use crate::options::Options;
use crate::outcome::Diagnosis;
use crate::outputs::{write_whole, OutputError};
use crate::pipeline::diagnose_owned;

/// Why a session could not run or its summary could not be written (the errors of single
/// recordings are rows, not this).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SessionError {
    /// The inputs are not a list of recordings, each once ([`crate::inputs`]).
    #[error(transparent)]
    Input(#[from] InputError),
    /// Two inputs with one file stem: both would write `DIR/<stem>.json` and its report.
    #[error("{} and {} would both be written to {stem}.json and {stem}.html in the output folder: give them different file names, or diagnose them in two runs", .first.display(), .second.display())]
    SameStem {
        stem: String,
        first: PathBuf,
        second: PathBuf,
    },
    /// An output path that cannot be used, found before any work ([`crate::outputs`]).
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The output folder could not be created.
    #[error("{}: {source}", .path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    /// An output file could not be written (the error names it: [`crate::outputs`]).
    #[error(transparent)]
    Written(std::io::Error),
}

/// One effect's primary parameter in a recording.
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    /// The catalogue name of the effect.
    pub effect: String,
    /// Its primary parameter (the first of OUT.json's `params`).
    pub name: String,
    pub value: f64,
    /// Its standard error, where the fit gave one.
    pub stderr: Option<f64>,
}

/// What the summary keeps of one diagnosis.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// OUT.json's `verdict`.
    pub verdict: String,
    /// The effects found, in OUT.json's order, each with its primary parameter.
    pub effects: Vec<Param>,
    /// The calibrated baseline's Young's modulus, Pa (NaN against a user's simulation).
    pub modulus_pa: f64,
    /// The calibrated load scale of a user's simulation, where it is the baseline.
    pub load_scale: Option<f64>,
    /// RMSE on the held-out stretch before and after the effects.
    pub heldout_rmse: (f64, f64),
}

/// One recording of the session.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The input path as given.
    pub file: String,
    /// Its file stem: the outputs are `DIR/<stem>.json` and the report.
    pub stem: String,
    /// Wall time of reading, diagnosing and writing it, s.
    pub seconds: f64,
    /// The summary, or the one-line reason it could not be analysed (naming the file).
    pub outcome: Result<Outcome, String>,
}

/// The recordings `inputs` name, each once ([`crate::inputs::recordings`]: files as given, for
/// a folder every `*.csv` in it, sorted; a missing input or a recording given twice is
/// refused). Refuses two inputs with the same stem, whose outputs would collide.
pub fn expand_inputs(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, SessionError> {
    let out = crate::inputs::recordings(inputs)?;
    for (i, a) in out.iter().enumerate() {
        if let Some(b) = out[..i].iter().find(|b| stem_of(b) == stem_of(a)) {
            return Err(SessionError::SameStem {
                stem: stem_of(a),
                first: b.clone(),
                second: a.clone(),
            });
        }
    }
    Ok(out)
}

/// The name the outputs of `path` take.
pub fn stem_of(path: &Path) -> String {
    path.file_stem().map_or_else(
        || path.display().to_string(),
        |s| s.to_string_lossy().into_owned(),
    )
}

/// Diagnose every recording of `inputs` in parallel into `out_dir`, then write `summary.csv`
/// and `summary.html` there; `done(finished, total)` is told as recordings finish. Rows are in
/// input order. Every output path is checked first ([`crate::outputs::check`]), and each file
/// is written whole.
///
/// The recordings share rayon's global pool with the diagnosis's own parallel candidate fits, so
/// the session saturates the cores without running pools inside pools.
pub fn run(
    inputs: &[PathBuf],
    out_dir: &Path,
    opt: &Options,
    done: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<Row>, SessionError> {
    let outputs = output_files(inputs, out_dir);
    let files: Vec<&Path> = outputs.iter().map(PathBuf::as_path).collect();
    crate::outputs::check(&files, &[out_dir], inputs)?;
    std::fs::create_dir_all(out_dir).map_err(|source| SessionError::Write {
        path: out_dir.to_path_buf(),
        source,
    })?;
    let finished = AtomicUsize::new(0);
    let rows: Vec<Row> = inputs
        .par_iter()
        .map(|path| {
            let row = one(path, out_dir, opt);
            done(finished.fetch_add(1, Ordering::Relaxed) + 1, inputs.len());
            row
        })
        .collect();
    let write = |name: &str, text: String| {
        write_whole(&out_dir.join(name), text.as_bytes()).map_err(SessionError::Written)
    };
    write("summary.csv", csv::summary(&rows))?;
    write("summary.html", html::summary(&rows))?;
    Ok(rows)
}

/// Every file a batch of `inputs` writes into `out_dir`: each recording's JSON and report, and
/// the summary's two files.
fn output_files(inputs: &[PathBuf], out_dir: &Path) -> Vec<PathBuf> {
    let each = inputs.iter().flat_map(|p| {
        let stem = stem_of(p);
        [json_path(out_dir, &stem), report_path(out_dir, &stem)]
    });
    let summary = ["summary.csv", "summary.html"].map(|n| out_dir.join(n));
    each.chain(summary).collect()
}

fn json_path(out_dir: &Path, stem: &str) -> PathBuf {
    out_dir.join(format!("{stem}.json"))
}

fn report_path(out_dir: &Path, stem: &str) -> PathBuf {
    out_dir.join(format!("{stem}.html"))
}

/// Read, diagnose and write one recording; its row either way.
fn one(path: &Path, out_dir: &Path, opt: &Options) -> Row {
    let started = Instant::now();
    let file = path.display().to_string();
    let stem = stem_of(path);
    let outcome = diagnose_file(path, &file, opt).and_then(|d| {
        write_outputs(out_dir, &stem, &d).map_err(|e| format!("{file}: {e}"))?;
        Ok(Outcome::of(&d))
    });
    Row {
        file,
        stem,
        seconds: started.elapsed().as_secs_f64(),
        // A row is one line of the summary and of stderr, whatever the error said.
        outcome: outcome.map_err(|e| e.replace(['\r', '\n'], " ")),
    }
}

/// The recording at `path` read and diagnosed; it is dropped before the outputs are written.
fn diagnose_file(path: &Path, file: &str, opt: &Options) -> Result<Diagnosis, String> {
    // The reader's errors start with the file's name already.
    let rec = recording::read(path).map_err(|e| e.to_string())?;
    diagnose_owned(rec, file, opt).map_err(|e| format!("{file}: {e}"))
}

/// `DIR/<stem>.json` and the report of one recording, written whole together.
fn write_outputs(out_dir: &Path, stem: &str, d: &Diagnosis) -> Result<(), String> {
    let text = json_text(d).map_err(|e| format!("encoding the diagnosis: {e}"))?;
    let html = crate::report::html(d);
    let (json, report) = (json_path(out_dir, stem), report_path(out_dir, stem));
    // The error names the file that failed.
    crate::outputs::write_all_whole(&[(&json, text.as_bytes()), (&report, html.as_bytes())])
        .map_err(|e| e.to_string())
}

/// OUT.json's text, exactly as `tactile diagnose REC --json OUT` writes it.
pub fn json_text(d: &Diagnosis) -> serde_json::Result<String> {
    Ok(serde_json::to_string_pretty(&d.report)? + "\n")
}

/// The report of one recording of the session: the only place that says where it goes.
pub fn write_report(out_dir: &Path, stem: &str, d: &Diagnosis) -> std::io::Result<()> {
    crate::report::write(&report_path(out_dir, stem), d)
}

impl Outcome {
    fn of(d: &Diagnosis) -> Self {
        let r = &d.report;
        let effects = r
            .effects
            .iter()
            .filter_map(|e| {
                let (name, value) = e.params.0.first()?;
                Some(Param {
                    effect: e.name.clone(),
                    name: name.clone(),
                    value: *value,
                    stderr: e.param_stderr.get(name),
                })
            })
            .collect();
        Self {
            verdict: serde_json::to_value(r.verdict)
                .ok()
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_default(),
            effects,
            modulus_pa: r
                .baseline
                .params
                .get("youngs_modulus_Pa")
                .unwrap_or(f64::NAN),
            load_scale: r.baseline.params.get("load_scale"),
            heldout_rmse: (r.fit.heldout.rmse_before, r.fit.heldout.rmse_after),
        }
    }
}

/// The inputs' and outputs' own codes; clashing names are a usage error; an output that cannot
/// be written, a failure to create.
impl sysexit::ExitStatus for SessionError {
    fn exit_code(&self) -> u8 {
        match self {
            SessionError::Input(e) => sysexit::ExitStatus::exit_code(e),
            SessionError::Output(e) => sysexit::ExitStatus::exit_code(e),
            SessionError::SameStem { .. } => sysexit::USAGE,
            SessionError::Write { .. } => sysexit::CANT_CREATE,
            SessionError::Written(e) => match e.kind() {
                std::io::ErrorKind::PermissionDenied => sysexit::NO_PERM,
                _ => sysexit::IO,
            },
        }
    }
}

#[cfg(test)]
mod tests;
