//! `tactile diagnose REC.csv --json OUT.json [--report PATH]` (`docs/diagnosis-format.md`).

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
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
    /// Also write the HTML report, one self-contained file: PATH itself when it ends in
    /// `.html`, else PATH/report.html.
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
    if let Some(path) = &args.report {
        let file = report_file(path);
        report::write(&file, &d).with_context(|| format!("writing {}", file.display()))?;
    }
    Ok(())
}

/// The report's file: `PATH` when it names an `.html` file, else `PATH/report.html` (a folder,
/// as `--report DIR` always meant).
fn report_file(path: &Path) -> PathBuf {
    let is_html = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"));
    if is_html {
        path.to_path_buf()
    } else {
        path.join("report.html")
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_path_is_a_file_when_it_says_html_else_a_folder() {
        assert_eq!(
            report_file(Path::new("out/r.html")),
            Path::new("out/r.html")
        );
        assert_eq!(report_file(Path::new("R.HTML")), Path::new("R.HTML"));
        assert_eq!(report_file(Path::new("rep/")), Path::new("rep/report.html"));
        assert_eq!(report_file(Path::new("rep")), Path::new("rep/report.html"));
    }
}
