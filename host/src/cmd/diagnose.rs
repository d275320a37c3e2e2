//! `tactile diagnose REC.csv --json OUT.json [--report DIR]` (diagnosis-v1).

use std::io::IsTerminal;
use std::path::PathBuf;

use anyhow::Context;

use crate::diagnosis::{diagnose, report, Options};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Recording in the recording-v1 format.
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
    let rec = crate::recording::read(&args.recording)?;
    let hw = hardware::Params::load_default().context("loading hardware/")?;
    let opt = Options::from_hardware(&hw, !args.quiet && std::io::stderr().is_terminal())?;
    let name = args.recording.display().to_string();
    let d = diagnose(&rec, &name, &opt).with_context(|| name.clone())?;
    let json = serde_json::to_string_pretty(&d.report).context("encoding the diagnosis")?;
    std::fs::write(&args.json, json + "\n")
        .with_context(|| format!("writing {}", args.json.display()))?;
    if let Some(dir) = &args.report {
        report::write(dir, &d)
            .with_context(|| format!("writing the report into {}", dir.display()))?;
    }
    Ok(())
}
