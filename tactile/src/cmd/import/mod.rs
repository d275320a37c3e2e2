//! `tactile import`: another instrument's export to a `tactile-recording/1` recording of the
//! material alone (time, rod, load; the sensor columns not measured), or a pair of logs, a
//! sensor's and a reference's on their own clocks, merged into one recording (`pair.rs`).

mod pair;

use std::path::{Path, PathBuf};
use sysexit::ResultExt as _;

use anyhow::Context;
use baseline::Readout;
use recording::import::table::{Delimiter, Header, TableOptions};
use recording::import::units::{self, Unit};
use recording::import::{self, mach1, machine_csv, ImportMeta};
use recording::machine::{MachineExport, MachineExportError};

/// Convert a test machine's export (Biomomentum Mach-1 text, or a generic CSV), or a sensor's
/// log with a reference's (`--sensor`, `--reference`), to a recording.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The export to read (not with --sensor and --reference).
    #[arg(required_unless_present = "sensor", conflicts_with = "sensor")]
    pub input: Option<PathBuf>,
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
    /// Indenter (or fingertip) radius, mm: required, since the recording format requires
    /// `fingertip_radius_mm` and an import writes only what it is told or can read.
    #[arg(long)]
    pub radius_mm: Option<f64>,
    /// The instrument's identity, recorded as the metadata's `sensor` (a serial, a name): a
    /// session refuses recordings of different instruments by it. A Mach-1 export's own
    /// system and load-cell serials are recorded where this is not given.
    #[arg(long, value_name = "ID")]
    pub sensor_id: Option<String>,
    #[command(flatten)]
    pub csv: CsvArgs,
    #[command(flatten)]
    pub pair: Box<pair::PairArgs>,
}

/// The generic CSV's columns and units; with --sensor, the reference log's.
#[derive(Debug, clap::Args)]
pub struct CsvArgs {
    /// CSV or reference: the time column, by header name or 1-based index.
    #[arg(long, default_value = "1")]
    pub time_col: String,
    /// CSV or reference: the displacement (position) column, by header name or 1-based index.
    #[arg(long, visible_alias = "position-col", default_value = "2")]
    pub disp_col: String,
    /// CSV or reference: the force column, by header name or 1-based index.
    #[arg(long, default_value = "3")]
    pub force_col: String,
    /// CSV or reference: time unit (s, ms, us, ns, min; a Unix time is a count of one of them).
    #[arg(long, default_value = "s", value_parser = time_unit)]
    pub time_unit: Unit,
    /// CSV or reference: displacement unit (mm, um, m).
    #[arg(long, visible_alias = "position-unit", default_value = "mm", value_parser = length_unit)]
    pub disp_unit: Unit,
    /// CSV or reference: force unit (N, mN, kN, gf, g, kgf, kg, lbf; g and kg are a scale's
    /// grams-force and kilograms-force).
    #[arg(long, default_value = "N", value_parser = force_unit)]
    pub force_unit: Unit,
    /// CSV or reference: negate displacement and force (a machine that reads compression as
    /// negative).
    #[arg(long, conflicts_with = "press_down")]
    pub invert: bool,
    /// CSV or reference: the position decreases as the indenter presses in (a robot's z above
    /// the sample).
    #[arg(long)]
    pub press_down: bool,
    /// CSV or reference: the position reading (in its own unit) at first contact, where rod_mm
    /// is 0 [default: the first reading].
    #[arg(long, allow_negative_numbers = true, value_parser = super::common::finite)]
    pub contact_at: Option<f64>,
    /// CSV or reference: the force column's marker for no reading (e.g. -1); empty fields and
    /// nan are always missing.
    #[arg(long, allow_negative_numbers = true, value_parser = super::common::finite)]
    pub missing: Option<f64>,
    /// CSV or reference: lines to skip at the top of the file.
    #[arg(long, default_value_t = 0)]
    pub skip_rows: usize,
    /// CSV or reference: whether the first line is a header [default: auto, a header if one of
    /// its fields is not a number].
    #[arg(long, value_enum, default_value = "auto")]
    pub header: HeaderArg,
    /// CSV or reference: the delimiter (one character, `tab` or `space`) [default: detected].
    #[arg(long, value_parser = delimiter)]
    pub delimiter: Option<Delimiter>,
}

/// Whether a log's first line is a header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum HeaderArg {
    /// A header if one of its fields is not a number.
    Auto,
    /// Always a header.
    Yes,
    /// No header: columns by 1-based index only.
    No,
}

/// The export formats `tactile import` reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Biomomentum Mach-1 text export.
    Mach1,
    /// A CSV with time, displacement and force columns.
    Csv,
}

fn time_unit(s: &str) -> Result<Unit, String> {
    units::parse(&units::TIME_UNITS, s)
}

fn length_unit(s: &str) -> Result<Unit, String> {
    units::parse(&units::LENGTH_UNITS, s)
}

fn force_unit(s: &str) -> Result<Unit, String> {
    units::parse(&units::FORCE_UNITS, s)
}

fn delimiter(s: &str) -> Result<Delimiter, String> {
    s.parse()
}

/// An import asked to write a recording without the radius the format requires.
#[derive(Debug, thiserror::Error)]
#[error(
    "--radius-mm is required: the recording format requires `fingertip_radius_mm` (the \
     indenter's or fingertip's radius, mm), and an import writes only what it is told or can \
     read"
)]
pub struct NoRadius;

impl sysexit::ExitStatus for NoRadius {
    fn exit_code(&self) -> u8 {
        sysexit::USAGE
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if args.radius_mm.is_none() && !args.list {
        return Err(sysexit::Coded::new(NoRadius).into());
    }
    let Some(input) = args.input.clone() else {
        return pair::run(&args);
    };
    let name = input.display().to_string();
    let text = import::read_text(&input).coded()?;
    let mut own_id = None;
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
            own_id = mach1::identity(&text);
            let what = format!("Mach-1 export {name}, block {} ({})", b.index, b.kind);
            (b.to_export(), what)
        }
        Format::Csv => {
            let export = machine_csv::parse(&text, &name, &csv_options(&args.csv)).coded()?;
            (export, format!("machine CSV {name}"))
        }
    };
    write(&args, &input, &export, (what, own_id))
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

/// The machine CSV's (or the reference log's) reading options.
fn csv_options(a: &CsvArgs) -> machine_csv::CsvOptions {
    let col = |s: &str| s.parse().unwrap_or_else(|e| match e {});
    machine_csv::CsvOptions {
        time: col(&a.time_col),
        displacement: col(&a.disp_col),
        force: col(&a.force_col),
        time_unit: a.time_unit,
        length_unit: a.disp_unit,
        force_unit: a.force_unit,
        press_down: a.invert || a.press_down,
        compression_negative: a.invert,
        contact_at: a.contact_at,
        missing: a.missing,
        table: table_options(a.header, a.delimiter, a.skip_rows),
    }
}

fn table_options(
    header: HeaderArg,
    delimiter: Option<Delimiter>,
    skip_rows: usize,
) -> TableOptions {
    TableOptions {
        delimiter,
        header: match header {
            HeaderArg::Auto => Header::Auto,
            HeaderArg::Yes => Header::Yes,
            HeaderArg::No => Header::No,
        },
        skip_rows,
    }
}

/// What every import writes into the metadata: the radius given and the front end of
/// `hardware/`; `what` opens the `source` text.
fn import_meta(args: &Args, what: &str, sensor_note: &str) -> anyhow::Result<ImportMeta> {
    let params = hardware::Params::load_default()
        .coded()
        .context("loading hardware/")?;
    let readout = Readout::from_hardware(&params).coded()?;
    let radius_mm = match args.radius_mm {
        Some(r) if r > 0.0 && r.is_finite() => r,
        Some(r) => anyhow::bail!("--radius-mm {r}: not a positive number"),
        None => return Err(sysexit::Coded::new(NoRadius).into()),
    };
    Ok(ImportMeta {
        fingertip_radius_mm: radius_mm,
        gain: readout.signal.gain,
        excitation_v: readout.signal.excitation_v,
        source: format!("{what}; {sensor_note}"),
    })
}

/// The metadata's `sensor` key (`SENSOR_KEY`): the identity given, else the file's own.
fn with_sensor(rec: &mut recording::Recording, given: Option<&str>, own: Option<String>) {
    let id = given
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(str::to_string);
    if let Some(id) = id.or(own) {
        rec.meta.other.push((recording::SENSOR_KEY.to_string(), id));
    }
}

/// Write a machine export's recording (`what` it is, and the identity its file gives).
fn write(
    args: &Args,
    input: &Path,
    export: &MachineExport,
    (what, own_id): (String, Option<String>),
) -> anyhow::Result<()> {
    let out = args.out.as_ref().context("--out is required")?;
    let meta = import_meta(args, &what, "sensor not measured")?;
    let mut rec = import::to_recording(export, &meta, &input.display().to_string()).coded()?;
    with_sensor(&mut rec, args.sensor_id.as_deref(), own_id);
    save(&rec, out, &[input.to_path_buf()])?;
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

/// Write `rec` where `out` points (`diagnosis::outputs`: `-` the standard output, a device or
/// FIFO as it is, a file whole, never one of the files read: `inputs`).
fn save(rec: &recording::Recording, out: &Path, inputs: &[PathBuf]) -> anyhow::Result<()> {
    diagnosis::outputs::check(&[out], &[], inputs).coded()?;
    let mut bytes = Vec::new();
    rec.write_to(&mut bytes).context("encoding the recording")?;
    Ok(diagnosis::outputs::write_whole(out, &bytes)?)
}
