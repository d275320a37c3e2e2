//! `tactile import`: another instrument's export to a `tactile-recording/1` recording of the
//! material alone (time, rod, load; the sensor columns not measured).

use std::path::PathBuf;
use sysexit::ResultExt as _;

use anyhow::Context;
use baseline::Readout;
use recording::import::{self, mach1, machine_csv, ImportMeta};
use recording::machine::{MachineExport, MachineExportError};

/// Convert a test machine's export (Biomomentum Mach-1 text, or a generic CSV) to a recording.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The export to read.
    pub input: PathBuf,
    /// The recording to write (not needed with --list).
    #[arg(long, short, required_unless_present = "list")]
    pub out: Option<PathBuf>,
    /// The export's format.
    #[arg(long, value_enum, default_value = "mach1")]
    pub format: Format,
    /// Mach-1: print the test blocks (index, type, rows, duration) and stop.
    #[arg(long)]
    pub list: bool,
    /// Mach-1: the test block to import, by its 1-based index in --list.
    #[arg(long, conflicts_with = "test")]
    pub block: Option<usize>,
    /// Mach-1: the first test block of this type, e.g. "Stress Relaxation".
    #[arg(long)]
    pub test: Option<String>,
    /// Indenter radius, mm [default: the fingertip radius of hardware/fingertip.toml].
    #[arg(long)]
    pub radius_mm: Option<f64>,
    #[command(flatten)]
    pub csv: CsvArgs,
}

/// The generic CSV's columns and units.
#[derive(Debug, clap::Args)]
pub struct CsvArgs {
    /// CSV: the time column, by header name or 1-based index.
    #[arg(long, default_value = "1")]
    pub time_col: String,
    /// CSV: the displacement column, by header name or 1-based index.
    #[arg(long, default_value = "2")]
    pub disp_col: String,
    /// CSV: the force column, by header name or 1-based index.
    #[arg(long, default_value = "3")]
    pub force_col: String,
    /// CSV: time unit (s, ms, min).
    #[arg(long, default_value = "s")]
    pub time_unit: String,
    /// CSV: displacement unit (mm, um, m).
    #[arg(long, default_value = "mm")]
    pub disp_unit: String,
    /// CSV: force unit (N, gf, kgf, lbf, kN).
    #[arg(long, default_value = "N")]
    pub force_unit: String,
    /// CSV: negate displacement and force (a machine that reads compression as negative).
    #[arg(long)]
    pub invert: bool,
    /// CSV: lines to skip before the column header.
    #[arg(long, default_value_t = 0)]
    pub skip_rows: usize,
}

/// The export formats `tactile import` reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Biomomentum Mach-1 text export.
    Mach1,
    /// A CSV with time, displacement and force columns.
    Csv,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let name = args.input.display().to_string();
    let text = import::read_text(&args.input).coded()?;
    let (export, what) = match args.format {
        Format::Mach1 => {
            let blocks = mach1::parse(&text, &name).coded()?;
            if args.list {
                for b in &blocks {
                    println!(
                        "{}\t{}\t{} rows\t{:.2} s\tline {}",
                        b.index,
                        b.kind,
                        b.rows(),
                        b.duration_s(),
                        b.line
                    );
                }
                return Ok(());
            }
            let b = choose(&blocks, &args, &name).coded()?;
            let what = format!("Mach-1 export {name}, block {} ({})", b.index, b.kind);
            (b.to_export(), what)
        }
        Format::Csv => {
            let export = machine_csv::parse(&text, &name, &csv_options(&args.csv)).coded()?;
            (export, format!("machine CSV {name}"))
        }
    };
    write(&args, &export, what)
}

/// The Mach-1 block asked for; with neither --block nor --test, the only block.
fn choose<'b>(
    blocks: &'b [mach1::Block],
    args: &Args,
    name: &str,
) -> Result<&'b mach1::Block, MachineExportError> {
    let found = match (&args.block, &args.test) {
        (Some(i), _) => blocks.iter().find(|b| b.index == *i),
        (None, Some(kind)) => blocks.iter().find(|b| b.kind.eq_ignore_ascii_case(kind)),
        (None, None) if blocks.len() == 1 => blocks.first(),
        (None, None) => None,
    };
    found.ok_or_else(|| {
        let list: Vec<String> = blocks
            .iter()
            .map(|b| format!("{} {}", b.index, b.kind))
            .collect();
        MachineExportError::Malformed {
            path: name.into(),
            line: 1,
            field: "(test block)".into(),
            why: format!("choose one with --block or --test: {}", list.join(", ")),
        }
    })
}

fn csv_options(a: &CsvArgs) -> machine_csv::CsvOptions {
    let col = |s: &str| s.parse().unwrap_or_else(|e| match e {});
    machine_csv::CsvOptions {
        time: col(&a.time_col),
        displacement: col(&a.disp_col),
        force: col(&a.force_col),
        time_unit: a.time_unit.clone(),
        length_unit: a.disp_unit.clone(),
        force_unit: a.force_unit.clone(),
        invert: a.invert,
        skip_rows: a.skip_rows,
    }
}

/// Write the recording with the front end of `hardware/` and the radius asked for.
fn write(args: &Args, export: &MachineExport, what: String) -> anyhow::Result<()> {
    let out = args.out.as_ref().context("--out is required")?;
    let params = hardware::Params::load_default()
        .coded()
        .context("loading hardware/")?;
    let readout = Readout::from_hardware(&params).coded()?;
    let (radius_mm, radius_note) = match args.radius_mm {
        Some(r) if r > 0.0 && r.is_finite() => (r, "indenter radius given"),
        Some(r) => anyhow::bail!("--radius-mm {r}: not a positive number"),
        None => (
            params.fingertip.radius_mm,
            "indenter radius unknown: the fingertip's radius of hardware/ written",
        ),
    };
    let meta = ImportMeta {
        fingertip_radius_mm: radius_mm,
        gain: readout.signal.gain,
        excitation_v: readout.signal.excitation_v,
        source: format!("{what}; {radius_note}; sensor not measured"),
    };
    let rec = import::to_recording(export, &meta, &args.input.display().to_string()).coded()?;
    let file = std::fs::File::create(out).with_context(|| format!("creating {}", out.display()))?;
    rec.write_to(file)
        .with_context(|| format!("writing {}", out.display()))?;
    eprintln!(
        "{}: {} rows, {:.1} s at {:.0} Hz -> {}",
        what,
        rec.channels.len(),
        export.t_s.last().copied().unwrap_or(0.0),
        rec.meta.sample_rate_hz,
        out.display()
    );
    Ok(())
}
