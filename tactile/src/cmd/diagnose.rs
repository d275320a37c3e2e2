//! `tactile diagnose REC.csv [--json OUT.json] [--report PATH]` (at least one) (`docs/diagnosis-format.md`), a
//! batch, each recording alone: `tactile diagnose A.csv B.csv ... --out-dir DIR` (or a folder of
//! recordings) through `diagnosis::session`; or jointly, one model for the session:
//! `tactile diagnose --joint A.csv B.csv ... --json OUT.json [--report OUT.html]`
//! (`docs/session-format.md`) through `diagnosis::joint`. In every mode the inputs are there
//! and the outputs can be written before any work (`diagnosis::inputs`, `diagnosis::outputs`),
//! and each output is written whole.
//! Each may take the user's own simulation as the baseline (`--simulation`,
//! `docs/simulation-format.md`).

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use sysexit::ResultExt as _;

use anyhow::Context;

use diagnosis::simulation::Simulations;
use diagnosis::{diagnose_owned, report, session, BaselineSource, Options};

use sysexit::{self as exit, ExitStatus};

/// Diagnose one recording (`--json`), several each alone in parallel (batch, `--out-dir`), or
/// several together as one session of one sensor (`--joint`).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Recordings in the recording format (`docs/recording-format.md`), or folders of them (every
    /// `*.csv` in it, sorted). One recording: --json OUT.json, --report OUT.html or both. Several: --out-dir DIR diagnoses
    /// each alone (batch), --joint --json OUT.json diagnoses them together as one session.
    #[arg(required = true, value_name = "RECORDING")]
    pub recordings: Vec<PathBuf>,
    /// The diagnosis's JSON: of one recording (tactile-diagnosis/1), or with --joint of the
    /// session (tactile-session-diagnosis/1). Missing folders are created; `-` is the standard
    /// output, and a device or FIFO is written as it is.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// The HTML page, one self-contained file: PATH itself when it ends in `.html` (or is `-`,
    /// a device or a FIFO), else PATH/report.html. Of one recording (alone or with --json), or
    /// with --joint of the session.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Batch: diagnose every recording alone, in parallel, into DIR: `<stem>.json`, its report
    /// `<stem>.html`, `summary.csv` and `summary.html` (inputs need distinct file stems).
    #[arg(long, value_name = "DIR")]
    pub out_dir: Option<PathBuf>,
    /// Diagnose the recordings jointly, as one session of one sensor in one fingertip: one
    /// model for all (tactile-session-diagnosis/1 JSON into --json, the session's page into
    /// --report; docs/session-format.md).
    #[arg(long)]
    pub joint: bool,
    /// The user's own simulation of the test as the baseline instead of ours: a recording of
    /// the simulated test or a static response table (docs/simulation-format.md). One for every
    /// recording, one per recording (repeated, in the recordings' order), or one folder
    /// holding a simulation named as each recording.
    #[arg(long, value_name = "SIM")]
    pub simulation: Vec<PathBuf>,
    /// With --simulation: take a fitted load or output scale, or a rod travel, more than 10x
    /// off the recording's on purpose (refused otherwise as a unit read as another,
    /// docs/simulation-format.md).
    #[arg(long, requires = "simulation")]
    pub accept_scale: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// What the arguments ask for, checked.
#[derive(Debug, PartialEq)]
enum Config {
    /// One recording to `--json`, `--report` or both.
    Single {
        recording: PathBuf,
        json: Option<PathBuf>,
        report: Option<PathBuf>,
    },
    /// Recordings and folders of them diagnosed jointly into one OUT.json (and page).
    Joint {
        inputs: Vec<PathBuf>,
        json: PathBuf,
        report: Option<PathBuf>,
    },
    /// Recordings and folders of them into one output folder.
    Session {
        inputs: Vec<PathBuf>,
        out_dir: PathBuf,
    },
}

/// Arguments that do not go together.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct UsageError(&'static str);

impl ExitStatus for UsageError {
    fn exit_code(&self) -> u8 {
        exit::USAGE
    }
}

impl Config {
    fn of(args: Args) -> Result<Self, UsageError> {
        if args.joint {
            if args.out_dir.is_some() {
                return Err(UsageError(
                    "--joint writes one session's diagnosis to --json OUT.json, not --out-dir",
                ));
            }
            let json = args
                .json
                .ok_or(UsageError("--joint needs --json OUT.json"))?;
            return Ok(Self::Joint {
                inputs: args.recordings,
                json,
                report: args.report,
            });
        }
        if let Some(out_dir) = args.out_dir {
            if args.json.is_some() || args.report.is_some() {
                return Err(UsageError(
                    "--json and --report are for one recording; with --out-dir each recording's \
                     diagnosis and report go into DIR",
                ));
            }
            return Ok(Self::Session {
                inputs: args.recordings,
                out_dir,
            });
        }
        let [recording] = <[PathBuf; 1]>::try_from(args.recordings).map_err(|_| {
            UsageError(
                "several recordings need --out-dir DIR (each diagnosed alone) or --joint \
                     --json OUT.json (diagnosed together as one session)",
            )
        })?;
        if recording.is_dir() {
            return Err(UsageError(
                "a folder of recordings needs --out-dir DIR (each diagnosed alone) or --joint \
                 --json OUT.json (diagnosed together as one session)",
            ));
        }
        if args.json.is_none() && args.report.is_none() {
            return Err(UsageError(
                "one recording needs --json OUT.json, --report OUT.html or both (or --out-dir DIR)",
            ));
        }
        Ok(Self::Single {
            recording,
            json: args.json,
            report: args.report,
        })
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let show = !args.quiet && std::io::stderr().is_terminal();
    let sims = Sims {
        files: args.simulation.clone(),
        accept_scale: args.accept_scale,
    };
    match Config::of(args).coded()? {
        Config::Single {
            recording,
            json,
            report,
        } => single(
            &recording,
            json.as_deref(),
            report.as_deref(),
            (show, &sims),
        ),
        Config::Session { inputs, out_dir } => whole_session(&inputs, &out_dir, (show, &sims)),
        Config::Joint {
            inputs,
            json,
            report,
        } => joint(&inputs, &json, report.as_deref(), (show, &sims)),
    }
}

/// The user's simulations (`--simulation`), and whether a scale beyond the plausible factor is
/// taken on purpose (`--accept-scale`).
struct Sims {
    files: Vec<PathBuf>,
    accept_scale: bool,
}

/// The baseline of `recordings`: ours, or the simulations `sims` paired with them.
fn baseline(recordings: &[PathBuf], sims: &Sims) -> anyhow::Result<BaselineSource> {
    if sims.files.is_empty() {
        return Ok(BaselineSource::Fe);
    }
    Ok(BaselineSource::Simulation(
        Simulations::pair(recordings, &sims.files)
            .coded()?
            .accepting_scale(sims.accept_scale),
    ))
}

/// The session diagnosed jointly; [`exit::DATA`] after writing when a file could not be
/// analysed (its row says why). The inputs are there and the outputs can be written before
/// any work; the library refuses a recording given twice or of another sensor.
fn joint(
    inputs: &[PathBuf],
    json: &Path,
    report_path: Option<&Path>,
    (show, sims): (bool, &Sims),
) -> anyhow::Result<()> {
    let files = diagnosis::inputs::expand(inputs).coded()?;
    let report = report_path.map(report_file);
    check_outputs(Some(json), report.as_deref(), &files)?;
    let opt = options(baseline(&files, sims)?)?;
    let bar = progress_bar(show, "diagnosing the session");
    bar.set_length(1);
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    let diagnosed = diagnosis::joint::diagnose_session(inputs, &opt);
    bar.finish_and_clear();
    let d = diagnosed.coded()?;
    let text = diagnosis::joint::json_text(&d).context("encoding the diagnosis")?;
    let html = report.as_ref().map(|_| diagnosis::joint::report_html(&d));
    write_outputs(Some((json, &text)), report.as_deref().zip(html.as_deref()))?;
    let bad: Vec<&str> = d
        .report
        .recordings
        .iter()
        .filter_map(|r| r.error.as_deref())
        .collect();
    unanalysed(&bad, d.report.recordings.len())
}

/// Refuse, before any work, a `--json` or report path that cannot be written, is one of the
/// recordings `inputs`, or is the other output ([`diagnosis::outputs::check`]).
fn check_outputs(
    json: Option<&Path>,
    report: Option<&Path>,
    inputs: &[PathBuf],
) -> anyhow::Result<()> {
    let files: Vec<&Path> = json.into_iter().chain(report).collect();
    Ok(diagnosis::outputs::check(&files, &[], inputs).coded()?)
}

/// The JSON and the page, each where asked for, written together where the user points
/// ([`diagnosis::outputs::write_all_whole`]: a device or `-` as it is, a file whole); the
/// error names the path that failed.
fn write_outputs(json: Option<(&Path, &str)>, page: Option<(&Path, &str)>) -> anyhow::Result<()> {
    let files: Vec<(&Path, &[u8])> = json
        .into_iter()
        .chain(page)
        .map(|(path, text)| (path, text.as_bytes()))
        .collect();
    Ok(diagnosis::outputs::write_all_whole(&files)?)
}

fn options(baseline: BaselineSource) -> anyhow::Result<Options> {
    let hw = hardware::Params::load_default()
        .coded()
        .context("loading hardware/")?;
    Ok(Options {
        baseline,
        ..Options::from_hardware(&hw).coded()?
    })
}

/// One recording into `json`, its page or both.
fn single(
    recording: &Path,
    json: Option<&Path>,
    report_path: Option<&Path>,
    (show, sims): (bool, &Sims),
) -> anyhow::Result<()> {
    let files =
        diagnosis::inputs::expand(std::slice::from_ref(&recording.to_path_buf())).coded()?;
    let report = report_path.map(report_file);
    check_outputs(json, report.as_deref(), &files)?;
    let baseline = baseline(&[recording.to_path_buf()], sims)?;
    let rec = recording::read(recording).coded()?;
    let mut opt = options(baseline)?;
    let bar = progress_bar(show, "fitting candidate models");
    let shown = bar.clone();
    opt.progress = Some(Arc::new(move |done, total| {
        shown.set_length(total as u64);
        shown.set_position(done as u64);
    }));
    let name = recording.display().to_string();
    let diagnosed = diagnose_owned(rec, &name, &opt);
    bar.finish_and_clear();
    let d = diagnosed.coded().with_context(|| name.clone())?;
    let text = session::json_text(&d).context("encoding the diagnosis")?;
    let html = report.as_ref().map(|_| report::html(&d));
    write_outputs(
        json.map(|j| (j, text.as_str())),
        report.as_deref().zip(html.as_deref()),
    )
}

/// The report's file: `PATH` when it names an `.html` file or is not a regular file or folder
/// (`-`, a device, a FIFO: written as it is), else `PATH/report.html` (a folder, as `--report
/// DIR` always meant).
fn report_file(path: &Path) -> PathBuf {
    let is_html = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"));
    let stream = !matches!(
        diagnosis::outputs::Sink::of(path),
        diagnosis::outputs::Sink::Whole(_)
    );
    if is_html || stream {
        path.to_path_buf()
    } else {
        path.join("report.html")
    }
}

/// Every recording into `out_dir`; one stderr line per recording that could not be analysed,
/// then [`exit::DATA`] if there was any.
fn whole_session(
    inputs: &[PathBuf],
    out_dir: &std::path::Path,
    (show, sims): (bool, &Sims),
) -> anyhow::Result<()> {
    let inputs = session::expand_inputs(inputs).coded()?;
    let opt = options(baseline(&inputs, sims)?)?;
    let bar = progress_bar(show, "diagnosing recordings");
    bar.set_length(inputs.len() as u64);
    let rows = session::run(&inputs, out_dir, &opt, &|done, _| {
        bar.set_position(done as u64)
    });
    bar.finish_and_clear();
    let rows = rows.coded()?;
    let bad: Vec<&str> = rows
        .iter()
        .filter_map(|r| r.outcome.as_ref().err().map(String::as_str))
        .collect();
    unanalysed(&bad, rows.len())
}

/// One stderr line per recording of `total` that could not be analysed, then [`exit::DATA`] if
/// there was any.
fn unanalysed(bad: &[&str], total: usize) -> anyhow::Result<()> {
    for line in bad {
        eprintln!("tactile: error: {line}");
    }
    if bad.is_empty() {
        return Ok(());
    }
    Err(exit::Reported {
        code: exit::DATA,
        what: format!("{} of {total} recordings could not be analysed", bad.len()),
    }
    .into())
}

/// A bar on stderr, or a hidden one.
fn progress_bar(show: bool, what: &str) -> indicatif::ProgressBar {
    if !show {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!(
            "{what} {{bar:30}} {{pos}}/{{len}} {{elapsed}}"
        ))
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(argv: &[&str]) -> Result<Config, UsageError> {
        #[derive(clap::Parser)]
        struct Cli {
            #[command(flatten)]
            args: Args,
        }
        let cli = <Cli as clap::Parser>::try_parse_from(
            std::iter::once("diagnose").chain(argv.iter().copied()),
        )
        .unwrap();
        Config::of(cli.args)
    }

    #[test]
    fn report_path_is_a_file_when_it_says_html_else_a_folder() {
        assert_eq!(
            report_file(Path::new("out/r.html")),
            Path::new("out/r.html")
        );
        assert_eq!(report_file(Path::new("R.HTML")), Path::new("R.HTML"));
        assert_eq!(report_file(Path::new("rep/")), Path::new("rep/report.html"));
        assert_eq!(report_file(Path::new("rep")), Path::new("rep/report.html"));
        assert_eq!(report_file(Path::new("-")), Path::new("-"));
        assert_eq!(report_file(Path::new("/dev/null")), Path::new("/dev/null"));
    }

    #[test]
    fn one_recording_keeps_its_json_and_several_need_an_out_dir() {
        assert_eq!(
            config(&["r.csv", "--json", "o.json"]).unwrap(),
            Config::Single {
                recording: "r.csv".into(),
                json: Some("o.json".into()),
                report: None
            }
        );
        assert!(config(&["r.csv"]).is_err());
        // The page alone.
        assert_eq!(
            config(&["r.csv", "--report", "r.html"]).unwrap(),
            Config::Single {
                recording: "r.csv".into(),
                json: None,
                report: Some("r.html".into())
            }
        );
        assert!(config(&["a.csv", "b.csv", "--json", "o.json"]).is_err());
        assert!(config(&["a.csv", "b.csv", "--out-dir", "d", "--json", "o.json"]).is_err());
        assert!(config(&["a.csv", "--out-dir", "d", "--report", "r"]).is_err());
        assert!(config(&[".", "--json", "o.json"]).is_err());
        assert_eq!(
            config(&["a.csv", "b.csv", "--out-dir", "d"]).unwrap(),
            Config::Session {
                inputs: vec!["a.csv".into(), "b.csv".into()],
                out_dir: "d".into()
            }
        );
    }
}
