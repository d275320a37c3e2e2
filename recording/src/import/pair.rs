//! A pair of logs made one recording: a sensor's log (its own clock, rate and units, any number
//! of channels) and a reference's log (a robot's or test machine's position and a scale's or
//! load cell's force, read as a machine CSV, [`super::machine_csv`]), each on its own clock.
//!
//! The sensor's clock is put on the reference's ([`Align`], plus an offset); the output runs
//! over the stretch both logs cover, on the sensor's own times or on a uniform grid at a rate
//! asked for. The sensor's chosen columns, each one column or a linear combination
//! ([`Combination`]) times a unit factor, fill `fz_V`, `mx_V` and `my_V` (a slot with none stays
//! empty: not measured); the reference's position and force, interpolated onto those times
//! ([`Series`]), fill `rod_mm` and `load_N`. Nothing is invented outside a log's span or inside
//! an outage of it: those values are left missing (gaps).

use super::combine::Combination;
use super::machine_csv::{self, CsvOptions, MachineLog};
use super::resample::{median_step_s, Series};
use super::table::{ColumnRef, Table, TableOptions};
use super::units::Unit;
use super::{bad, ImportMeta};
use crate::machine::MachineExportError;
use crate::{Channels, Meta, Recording};

/// How the sensor's clock is put on the reference's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Align {
    /// The two logs' times are on the same clock (both Unix time, say): sensor time + offset
    /// is reference time.
    #[default]
    Clock,
    /// The two logs started together: the sensor's first time is the reference's first time
    /// (plus the offset).
    Starts,
}

/// How to read the sensor's log.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorOptions {
    /// Lines, header and delimiter.
    pub table: TableOptions,
    /// The time column.
    pub time: ColumnRef,
    /// Its unit.
    pub time_unit: Unit,
    /// What fills `fz_V`, `mx_V` and `my_V`, in that order; `None`: not measured.
    pub slots: [Option<Combination>; 3],
    /// Output units per sensor unit, applied to every slot.
    pub scale: f64,
    /// The unit of the sensor's columns times `scale` (what the output columns then hold),
    /// recorded in the metadata: `V` for volts at the ADC, anything else for a foreign sensor.
    pub unit: String,
    /// Subtract from each slot its mean over the output's first this many seconds (a sensor at
    /// rest at the start), as the front end's offset cut does.
    pub tare_s: Option<f64>,
}

/// The whole import.
#[derive(Debug, Clone, PartialEq)]
pub struct PairOptions {
    /// The sensor's log.
    pub sensor: SensorOptions,
    /// The reference's log, read as a machine CSV.
    pub reference: CsvOptions,
    /// How the clocks relate.
    pub align: Align,
    /// Seconds added to the sensor's time (after `align`) to put it on the reference's clock.
    pub sensor_offset_s: f64,
    /// Output rate, Hz: a uniform grid, every channel interpolated; `None`: the sensor's own
    /// times.
    pub rate_hz: Option<f64>,
    /// The longest stretch without a reading interpolated across, s; `None`: per log,
    /// [`super::resample::GAP_STEPS`] of its median steps.
    pub max_gap_s: Option<f64>,
}

/// A log's text and its name in errors.
#[derive(Debug, Clone, Copy)]
pub struct Source<'a> {
    /// The file, as named in errors.
    pub path: &'a str,
    /// Its text.
    pub text: &'a str,
}

/// What the import did, for the command's report.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Seconds added to the sensor's clock to put it on the reference's.
    pub sensor_offset_s: f64,
    /// Rows written.
    pub rows: usize,
    /// Missing values per output column (`rod_mm`, `load_N`, then the chosen slots; a slot
    /// not chosen counts 0).
    pub missing: [usize; 5],
}

/// The sensor's log read: times on its own clock (s) and each slot's values.
struct SensorLog {
    t_s: Vec<f64>,
    slots: [Option<Vec<f64>>; 3],
    first_line: usize,
    time_name: String,
}

fn read_sensor(src: Source, opt: &SensorOptions) -> Result<SensorLog, MachineExportError> {
    if opt.slots.iter().all(Option::is_none) {
        return Err(MachineExportError::Usage {
            option: "--fz, --mx, --my".into(),
            why: "choose the sensor's columns for at least one output".into(),
        });
    }
    let table = Table::parse(src.text, src.path, &opt.table)?;
    let k = table.column(&opt.time)?;
    let t_s = table.times(k, opt.time_unit.factor)?;
    let mut slots: [Option<Vec<f64>>; 3] = Default::default();
    for (out, comb) in slots.iter_mut().zip(&opt.slots) {
        if let Some(c) = comb {
            *out = Some(c.evaluate(&table, opt.scale)?);
        }
    }
    Ok(SensorLog {
        t_s,
        slots,
        first_line: table.line(0),
        time_name: table.name(k),
    })
}

/// The offset (reference time − sensor time) `align` and the extra offset give.
fn offset_s(sensor: &SensorLog, reference: &MachineLog, opt: &PairOptions) -> f64 {
    let base = match opt.align {
        Align::Clock => 0.0,
        Align::Starts => reference.t_s[0] - sensor.t_s[0],
    };
    base + opt.sensor_offset_s
}

/// The output's times on the reference's clock: the sensor's (or a uniform grid at the rate
/// asked for) within the stretch both logs cover; refused when they do not overlap.
fn output_times(
    sensor_t: &[f64],
    reference_span: (f64, f64),
    sensor: &SensorLog,
    src: Source,
    rate_hz: Option<f64>,
) -> Result<Vec<f64>, MachineExportError> {
    let (s0, s1) = (sensor_t[0], sensor_t[sensor_t.len() - 1]);
    let (lo, hi) = (s0.max(reference_span.0), s1.min(reference_span.1));
    let times: Vec<f64> = match rate_hz {
        None => sensor_t
            .iter()
            .copied()
            .filter(|t| (lo..=hi).contains(t))
            .collect(),
        Some(r) => {
            let n = if hi > lo {
                ((hi - lo) * r).floor() as usize + 1
            } else {
                0
            };
            (0..n).map(|i| lo + i as f64 / r).collect()
        }
    };
    if times.len() < 2 {
        return Err(bad(
            src.path,
            sensor.first_line,
            &sensor.time_name,
            format!(
                "the sensor's times ({s0} to {s1} s on the reference's clock) and the \
                 reference's ({} to {} s) share fewer than two samples: give \
                 --sensor-offset-s, or --align starts if the logs started together",
                reference_span.0, reference_span.1
            ),
        ));
    }
    Ok(times)
}

/// Read both logs and make the recording.
pub fn import(
    sensor_src: Source,
    reference_src: Source,
    opt: &PairOptions,
    meta: &ImportMeta,
) -> Result<(Recording, Summary), MachineExportError> {
    if let Some(r) = opt.rate_hz.filter(|r| !(r.is_finite() && *r > 0.0)) {
        return Err(MachineExportError::Usage {
            option: "--rate".into(),
            why: format!("{r}: not a positive rate"),
        });
    }
    let sensor = read_sensor(sensor_src, &opt.sensor)?;
    let reference = machine_csv::read_log(reference_src.text, reference_src.path, &opt.reference)?;
    let offset = offset_s(&sensor, &reference, opt);
    let sensor_t: Vec<f64> = sensor.t_s.iter().map(|t| t + offset).collect();
    let rod = Series::new(&reference.t_s, &reference.rod_mm, opt.max_gap_s);
    let load = Series::new(&reference.t_s, &reference.load_n, opt.max_gap_s);
    let span = reference_span(&rod, &load, reference_src)?;
    let times = output_times(&sensor_t, span, &sensor, sensor_src, opt.rate_hz)?;
    let mut slots: [Option<Vec<f64>>; 3] = Default::default();
    for (out, values) in slots.iter_mut().zip(&sensor.slots) {
        *out = values.as_ref().map(|v| slot_on(&sensor_t, v, &times, opt));
    }
    let tares = tare(&mut slots, &times, opt.sensor.tare_s, sensor_src)?;
    let channels = Channels {
        t_s: from_zero(&times, opt.rate_hz),
        rod_mm: times.iter().map(|&t| rod.at(t)).collect(),
        load_n: times.iter().map(|&t| load.at(t)).collect(),
        fz_v: column(&slots[0], times.len()),
        mx_v: column(&slots[1], times.len()),
        my_v: column(&slots[2], times.len()),
    };
    let rate_hz = opt
        .rate_hz
        .or_else(|| median_step_s(&times).map(|d| 1.0 / d))
        .unwrap_or(1.0);
    let missing = count_missing(&channels, &slots);
    let notes = Notes {
        offset_s: offset,
        time_zero_s: times[0],
        tares,
        max_gaps_s: [rod.max_gap_s(), load.max_gap_s()],
    };
    let rec = recording(channels, rate_hz, meta, &metadata(opt, &notes));
    let rows = rec.channels.len();
    Ok((
        rec,
        Summary {
            sensor_offset_s: offset,
            rows,
            missing,
        },
    ))
}

/// The output's `t_s`: time from its first row, rounded to the microsecond (a Unix time in s
/// carries a quarter of a microsecond of rounding, and its digits below that are noise); on a
/// uniform grid counted from its start, not subtracted from a Unix time.
fn from_zero(times: &[f64], rate_hz: Option<f64>) -> Vec<f64> {
    let micro = |t_s: f64| (t_s * 1e6).round() / 1e6;
    match rate_hz {
        Some(r) => (0..times.len()).map(|i| micro(i as f64 / r)).collect(),
        None => times.iter().map(|t| micro(t - times[0])).collect(),
    }
}

/// The span of the reference's readings (position and force both), or an error when one of
/// them has no reading at all.
fn reference_span(
    rod: &Series,
    load: &Series,
    src: Source,
) -> Result<(f64, f64), MachineExportError> {
    let span = |s: &Series, what: &str| {
        s.span_s()
            .ok_or_else(|| bad(src.path, 1, what, "no reading on any row"))
    };
    let (a, b) = (span(rod, "(position)")?, span(load, "(force)")?);
    Ok((a.0.min(b.0), a.1.max(b.1)))
}

/// One slot's values at `times`: the sensor's own where the output is on its times, else
/// interpolated.
fn slot_on(sensor_t: &[f64], values: &[f64], times: &[f64], opt: &PairOptions) -> Vec<f64> {
    if opt.rate_hz.is_none() {
        let first = sensor_t.partition_point(|t| *t < times[0]);
        return values[first..first + times.len()].to_vec();
    }
    let series = Series::new(sensor_t, values, opt.max_gap_s);
    times.iter().map(|&t| series.at(t)).collect()
}

/// Subtract from each slot its mean over the first `tare_s` of the output; the values
/// subtracted.
fn tare(
    slots: &mut [Option<Vec<f64>>; 3],
    times: &[f64],
    tare_s: Option<f64>,
    src: Source,
) -> Result<[Option<f64>; 3], MachineExportError> {
    let mut out = [None; 3];
    let Some(tare_s) = tare_s else {
        return Ok(out);
    };
    let n = times.partition_point(|t| *t <= times[0] + tare_s);
    for (k, slot) in slots.iter_mut().enumerate() {
        let Some(v) = slot else { continue };
        let rest: Vec<f64> = v[..n].iter().copied().filter(|x| x.is_finite()).collect();
        if rest.is_empty() {
            return Err(bad(
                src.path,
                1,
                crate::REQUIRED_COLUMNS[3 + k],
                format!("no reading in the first {tare_s} s to tare with"),
            ));
        }
        let mean = rest.iter().sum::<f64>() / rest.len() as f64;
        v.iter_mut().for_each(|x| *x -= mean);
        out[k] = Some(mean);
    }
    Ok(out)
}

fn column(slot: &Option<Vec<f64>>, n: usize) -> Vec<f64> {
    slot.clone().unwrap_or_else(|| vec![f64::NAN; n])
}

fn count_missing(c: &Channels, slots: &[Option<Vec<f64>>; 3]) -> [usize; 5] {
    let nan = |v: &[f64]| v.iter().filter(|x| x.is_nan()).count();
    let slot = |k: usize| slots[k].as_deref().map_or(0, nan);
    [nan(&c.rod_mm), nan(&c.load_n), slot(0), slot(1), slot(2)]
}

/// What the metadata records beyond the options.
struct Notes {
    offset_s: f64,
    time_zero_s: f64,
    tares: [Option<f64>; 3],
    max_gaps_s: [f64; 2],
}

/// The extra metadata keys (readers keep and ignore them): the mapping, the units, the clocks.
fn metadata(opt: &PairOptions, notes: &Notes) -> Vec<(String, String)> {
    let s = &opt.sensor;
    let r = &opt.reference;
    let mut m = vec![
        ("sensor_unit".to_string(), s.unit.clone()),
        ("sensor_scale".into(), s.scale.to_string()),
    ];
    let names = ["fz_V", "mx_V", "my_V"];
    for ((name, comb), tare) in names.iter().zip(&s.slots).zip(notes.tares) {
        if let Some(c) = comb {
            m.push((format!("{name}_from"), c.text.clone()));
        }
        if let Some(t) = tare {
            m.push((format!("{name}_tare"), t.to_string()));
        }
    }
    m.extend([
        ("sensor_offset_s".into(), notes.offset_s.to_string()),
        ("time_zero_s".into(), notes.time_zero_s.to_string()),
        ("reference_position".into(), position_note(r)),
        ("reference_force".into(), force_note(r)),
        (
            "max_gap_s".into(),
            format!(
                "rod_mm {}, load_N {}",
                notes.max_gaps_s[0], notes.max_gaps_s[1]
            ),
        ),
    ]);
    m
}

fn position_note(r: &CsvOptions) -> String {
    let contact = r
        .contact_at
        .map_or("its first reading".to_string(), |c| c.to_string());
    let way = if r.press_down {
        "decreases"
    } else {
        "increases"
    };
    format!(
        "{} in {}, {way} as the indenter presses in, contact at {contact}",
        r.displacement, r.length_unit.name
    )
}

fn force_note(r: &CsvOptions) -> String {
    let missing = r
        .missing
        .map_or("empty".to_string(), |m| format!("{m} or empty"));
    let sign = if r.compression_negative {
        "negative"
    } else {
        "positive"
    };
    format!(
        "{} in {}, compression {sign}, no reading: {missing}",
        r.force, r.force_unit.name
    )
}

fn recording(
    channels: Channels,
    rate_hz: f64,
    meta: &ImportMeta,
    other: &[(String, String)],
) -> Recording {
    let mut rec = Recording::new(Meta {
        // Rounded to µHz, as a machine export's.
        sample_rate_hz: (rate_hz * 1e6).round() / 1e6,
        contact_angle_deg: 0.0,
        azimuth_deg: 0.0,
        fingertip_radius_mm: meta.fingertip_radius_mm,
        gain_fz: meta.gain[0],
        gain_mx: meta.gain[1],
        gain_my: meta.gain[2],
        excitation_v: meta.excitation_v,
        rod_speed_mm_per_min: None,
        source: Some(meta.source.clone()),
        other: other.to_vec(),
    });
    rec.channels = channels;
    rec
}

#[cfg(test)]
mod tests;
