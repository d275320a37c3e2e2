//! Importers: other instruments' exports turned into `tactile-recording/1` recordings.
//!
//! A test machine's export alone (Mach-1 text, [`mach1`]; a generic CSV, [`machine_csv`]) is a
//! recording of the material alone (time, rod, load; the sensor columns not measured, empty on
//! every row): each parser yields a [`MachineExport`] (time in s, rod travel in mm, load in N)
//! and [`to_recording`] adds the metadata. A pair of logs, a sensor's and a reference's on their
//! own clocks ([`pair`]), is merged on time into one recording with the sensor's columns too.
//! The pieces: the one delimited-text reader ([`table`]), units ([`units`]), a sensor's columns
//! combined into an output ([`combine`]), one log put on another's times ([`resample`]).
//! Errors are [`MachineExportError`]s naming the file, the line and the field.

pub mod combine;
pub mod mach1;
pub mod machine_csv;
pub mod pair;
pub mod resample;
pub mod table;
pub mod units;

pub use resample::median_step_s;

use std::path::Path;

use crate::machine::{MachineExport, MachineExportError};
use crate::{Channels, Meta, Recording};

/// What the imported file cannot say: the indenter and the front end written into the metadata.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportMeta {
    /// Indenter (or fingertip) radius, mm, positive.
    pub fingertip_radius_mm: f64,
    /// Amplifier gains Fz, Mx, My (unused: no sensor column is measured).
    pub gain: [f64; 3],
    /// Bridge excitation, V (unused: no sensor column is measured).
    pub excitation_v: f64,
    /// Free text for the `source` key: instrument, file, block.
    pub source: String,
}

/// The recording of a material-only test: `t_s`, `rod_mm` and `load_N` from `export`, the
/// sensor columns empty on every row, `sample_rate_hz` from the median time step.
pub fn to_recording(
    export: &MachineExport,
    meta: &ImportMeta,
    path: &str,
) -> Result<Recording, MachineExportError> {
    let dt_s = median_step_s(&export.t_s).ok_or_else(|| MachineExportError::Malformed {
        path: path.into(),
        line: 1,
        field: "(time)".into(),
        why: "fewer than two distinct times: no sample rate".into(),
    })?;
    let n = export.len();
    let meta = Meta {
        // Rounded to µHz: 1 / 0.01 s is 100 Hz, not 100.0000000000199 Hz.
        sample_rate_hz: (1e6 / dt_s).round() / 1e6,
        contact_angle_deg: 0.0,
        azimuth_deg: 0.0,
        fingertip_radius_mm: meta.fingertip_radius_mm,
        gain_fz: meta.gain[0],
        gain_mx: meta.gain[1],
        gain_my: meta.gain[2],
        excitation_v: meta.excitation_v,
        rod_speed_mm_per_min: None,
        source: Some(meta.source.clone()),
        other: Vec::new(),
    };
    let mut rec = Recording::new(meta);
    rec.channels = Channels {
        t_s: export.t_s.clone(),
        rod_mm: export.rod_mm.clone(),
        load_n: export.load_n.clone(),
        fz_v: vec![f64::NAN; n],
        mx_v: vec![f64::NAN; n],
        my_v: vec![f64::NAN; n],
    };
    Ok(rec)
}

/// The text of the file at `path`, read whole (at most
/// [`crate::Limits::DEFAULT`]`.max_bytes`): UTF-8 if it is valid UTF-8, otherwise Latin-1 (the
/// instruments' exports are Latin-1).
pub fn read_text(path: &Path) -> Result<String, MachineExportError> {
    let (_, raw) = crate::machine::read_bounded(path)?;
    Ok(match String::from_utf8(raw) {
        Ok(text) => text,
        Err(e) => e.into_bytes().iter().map(|&b| char::from(b)).collect(),
    })
}

/// A malformed-input error at `line`, `field` of `path`.
pub(crate) fn bad(
    path: &str,
    line: usize,
    field: &str,
    why: impl Into<String>,
) -> MachineExportError {
    MachineExportError::Malformed {
        path: path.into(),
        line,
        field: field.into(),
        why: why.into(),
    }
}

/// A finite number, or an error naming the line and field.
pub(crate) fn number(
    path: &str,
    line: usize,
    field: &str,
    text: &str,
) -> Result<f64, MachineExportError> {
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| {
            bad(
                path,
                line,
                field,
                format!("not a number: {:?}", text.trim()),
            )
        })
}
