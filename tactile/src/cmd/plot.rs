//! `tactile plot`: PNG and SVG of a recording.

use std::path::PathBuf;
use sysexit::ResultExt as _;

use crate::plot::{plot, Format};

/// Plot a recording CSV: the three bridge outputs against time (`<prefix>-time.png/.svg`) and,
/// when it has reference loads, against the load (`<prefix>-load.png/.svg`).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A recording CSV (`docs/recording-format.md`).
    pub recording: PathBuf,
    /// Output prefix (default: the recording path without its extension).
    #[arg(long, short = 'o')]
    pub out: Option<PathBuf>,
    /// Formats to write.
    #[arg(long, value_enum, default_value = "both")]
    pub format: FormatArg,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum FormatArg {
    Png,
    Svg,
    Both,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let rec = recording::read(&args.recording).coded()?;
    let prefix = args
        .out
        .unwrap_or_else(|| args.recording.with_extension(""));
    let formats: &[Format] = match args.format {
        FormatArg::Png => &[Format::Png],
        FormatArg::Svg => &[Format::Svg],
        FormatArg::Both => &[Format::Png, Format::Svg],
    };
    for p in plot(&rec, &prefix, formats)? {
        println!("{}", p.display());
    }
    Ok(())
}
