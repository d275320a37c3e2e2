//! `tactile diagnose REC.csv --json OUT.json [--report DIR]` (`docs/diagnosis-format.md`).

use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Arc;

use anyhow::Context;

use diagnosis::{diagnose, report, Options};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Recording in the recording format (`docs/recording-format.md`).
    pub recording: PathBuf,
    /// Where to write the diagnosis (tactile-diagnosis/1 JSON).
    #[arg(long)]
    pub json: PathBuf,
    /// Also write an HTML report with SVG plots into this folder.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let rec = recording::read(&args.recording)?;
    let hw = hardware::Params::load_default().context("loading hardware/")?;
    let mut opt = Options::from_hardware(&hw)?;
    let bar = progress_bar(!args.quiet && std::io::stderr().is_terminal());
    let shown = bar.clone();
    opt.progress = Some(Arc::new(move |done, total| {
        shown.set_length(total as u64);
        shown.set_position(done as u64);
    }));
    let name = args.recording.display().to_string();
    let diagnosed = diagnose(&rec, &name, &opt);
    bar.finish_and_clear();
    let d = diagnosed.with_context(|| name.clone())?;
    let json = serde_json::to_string_pretty(&d.report).context("encoding the diagnosis")?;
    std::fs::write(&args.json, json + "\n")
        .with_context(|| format!("writing {}", args.json.display()))?;
    if let Some(dir) = &args.report {
        report::write(dir, &d)
            .with_context(|| format!("writing the report into {}", dir.display()))?;
    }
    Ok(())
}

/// A bar on stderr while the candidate models are fitted, or a hidden one.
fn progress_bar(show: bool) -> indicatif::ProgressBar {
    if !show {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "fitting candidate models {bar:30} {pos}/{len} {elapsed}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}
