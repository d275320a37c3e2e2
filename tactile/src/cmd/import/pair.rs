//! `tactile import --sensor S --reference R`: a sensor's log and a reference's log, each on its
//! own clock, merged into one recording (`recording::import::pair`).

use std::path::{Path, PathBuf};
use sysexit::ResultExt as _;

use anyhow::Context;
use recording::import::combine::Combination;
use recording::import::pair::{self, Align, PairOptions, SensorOptions, Source};
use recording::import::table::Delimiter;
use recording::import::units::Unit;

use super::{csv_options, delimiter, import_meta, save, table_options, time_unit, Args, HeaderArg};

/// The sensor's log and how its channels fill the outputs; the reference log is read with the
/// machine CSV's options (--time-col, --disp-col, --force-col, their units, --press-down,
/// --missing, …).
#[derive(Debug, clap::Args)]
pub struct PairArgs {
    /// The sensor's log: a time column and its channels.
    #[arg(long, requires = "reference", conflicts_with_all = ["list", "block", "test"])]
    pub sensor: Option<PathBuf>,
    /// The reference's log (position and force), read with --time-col, --disp-col,
    /// --force-col and their options.
    #[arg(long, requires = "sensor")]
    pub reference: Option<PathBuf>,
    /// Sensor: the time column, by header name or 1-based index.
    #[arg(long, default_value = "1", requires = "sensor")]
    pub sensor_time_col: String,
    /// Sensor: time unit (s, ms, us, ns, min; a Unix time is a count of one of them).
    #[arg(long, default_value = "s", value_parser = time_unit, requires = "sensor")]
    pub sensor_time_unit: Unit,
    /// Sensor: lines to skip at the top of the file.
    #[arg(long, default_value_t = 0, requires = "sensor")]
    pub sensor_skip_rows: usize,
    /// Sensor: whether the first line is a header.
    #[arg(long, value_enum, default_value = "auto", requires = "sensor")]
    pub sensor_header: HeaderArg,
    /// Sensor: the delimiter (one character, `tab` or `space`) [default: detected].
    #[arg(long, value_parser = delimiter, requires = "sensor")]
    pub sensor_delimiter: Option<Delimiter>,
    /// The sensor's columns that make fz_V: one column (name or 1-based index, the time
    /// column counted) or a linear combination, e.g. "-4+7+10-13+16" or "0.5*3 - 0.5*6".
    #[arg(long, allow_hyphen_values = true, requires = "sensor")]
    pub fz: Option<Combination>,
    /// The sensor's columns that make mx_V (as --fz); not given: not measured.
    #[arg(long, allow_hyphen_values = true, requires = "sensor")]
    pub mx: Option<Combination>,
    /// The sensor's columns that make my_V (as --fz); not given: not measured.
    #[arg(long, allow_hyphen_values = true, requires = "sensor")]
    pub my: Option<Combination>,
    /// The unit of the sensor's columns times --sensor-scale, recorded in the metadata (V for
    /// volts at the ADC; a foreign sensor's own unit, e.g. uT, otherwise).
    #[arg(long, default_value = "V", requires = "sensor")]
    pub sensor_unit: String,
    /// Output units per sensor unit, applied to every output.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true,
          value_parser = super::super::common::finite, requires = "sensor")]
    pub sensor_scale: f64,
    /// Subtract from each output its mean over the first SECONDS of the recording (a sensor
    /// at rest at the start).
    #[arg(long, value_name = "SECONDS", value_parser = super::super::common::positive_seconds,
          requires = "sensor")]
    pub tare_s: Option<f64>,
    /// How the clocks relate: `clock`, the same clock (e.g. both Unix time); `starts`, the
    /// logs started together.
    #[arg(long, value_enum, default_value = "clock", requires = "sensor")]
    pub align: AlignArg,
    /// Seconds added to the sensor's time (after --align) to put it on the reference's clock.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true,
          value_parser = super::super::common::finite, requires = "sensor")]
    pub sensor_offset_s: f64,
    /// Output rate, Hz: a uniform grid, every channel interpolated [default: the sensor's own
    /// times, its median rate].
    #[arg(long, value_name = "HZ", value_parser = positive_rate, requires = "sensor")]
    pub rate: Option<f64>,
    /// The longest stretch without a reading that is interpolated across, s [default: per log,
    /// five of its median steps].
    #[arg(long, value_parser = super::super::common::positive_seconds, requires = "sensor")]
    pub max_gap_s: Option<f64>,
}

/// How the sensor's clock relates to the reference's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum AlignArg {
    /// The same clock: sensor time + offset is reference time.
    Clock,
    /// The logs started together: the sensor's first time is the reference's first.
    Starts,
}

fn positive_rate(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("{s:?} is not a number"))?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{s}: not a positive rate"))
    }
}

fn options(args: &Args) -> PairOptions {
    let p = &args.pair;
    PairOptions {
        sensor: SensorOptions {
            table: table_options(p.sensor_header, p.sensor_delimiter, p.sensor_skip_rows),
            time: p.sensor_time_col.parse().unwrap_or_else(|e| match e {}),
            time_unit: p.sensor_time_unit,
            slots: [p.fz.clone(), p.mx.clone(), p.my.clone()],
            scale: p.sensor_scale,
            unit: p.sensor_unit.clone(),
            tare_s: p.tare_s,
        },
        reference: csv_options(&args.csv),
        align: match p.align {
            AlignArg::Clock => Align::Clock,
            AlignArg::Starts => Align::Starts,
        },
        sensor_offset_s: p.sensor_offset_s,
        rate_hz: p.rate,
        max_gap_s: p.max_gap_s,
    }
}

/// Import the pair and write the recording.
pub fn run(args: &Args) -> anyhow::Result<()> {
    let (Some(sensor), Some(reference)) = (&args.pair.sensor, &args.pair.reference) else {
        anyhow::bail!("give an export, or --sensor and --reference");
    };
    let out = args.out.as_ref().context("--out is required")?;
    let (s_name, r_name) = (name(sensor), name(reference));
    let s_text = recording::import::read_text(sensor).coded()?;
    let r_text = recording::import::read_text(reference).coded()?;
    let opt = options(args);
    let what = format!("sensor log {s_name} with reference log {r_name}");
    let note = format!(
        "fz_V, mx_V, my_V in {} (the sensor's unit x {}), gains and excitation those of \
         hardware/",
        opt.sensor.unit, opt.sensor.scale
    );
    let meta = import_meta(args, &what, &note)?;
    let (rec, summary) = pair::import(
        Source {
            path: &s_name,
            text: &s_text,
        },
        Source {
            path: &r_name,
            text: &r_text,
        },
        &opt,
        &meta,
    )
    .coded()?;
    let mut rec = rec;
    super::with_sensor(&mut rec, args.sensor_id.as_deref(), None);
    save(&rec, out, &[sensor.clone(), reference.clone()])?;
    let m = summary.missing;
    eprintln!(
        "{what}: {} rows, {:.1} s at {} Hz, sensor clock {:+} s; missing: rod_mm {}, load_N \
         {}, fz_V {}, mx_V {}, my_V {} -> {}",
        summary.rows,
        rec.channels.t_s.last().copied().unwrap_or(0.0),
        rec.meta.sample_rate_hz,
        summary.sensor_offset_s,
        m[0],
        m[1],
        m[2],
        m[3],
        m[4],
        out.display()
    );
    Ok(())
}

fn name(p: &Path) -> String {
    p.display().to_string()
}
