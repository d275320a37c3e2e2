//! The metadata block: `# key = value` lines ahead of the header.

use super::RecordingError;

/// Typed metadata of a recording. Keys the contract does not know are kept in `other`, in file
/// order, and written back unchanged.
#[derive(Debug, Clone, PartialEq)]
pub struct Meta {
    /// Nominal sample rate of the sensor channels, Hz.
    pub sample_rate_hz: f64,
    /// Inclination theta_p of the load axis from the fingertip axis.
    pub contact_angle_deg: f64,
    /// Azimuth phi of the tilt plane from the chip's x axis, counter-clockwise.
    pub azimuth_deg: f64,
    /// Hemisphere radius, mm.
    pub fingertip_radius_mm: f64,
    /// Voltage gain of the amplifiers ahead of the ADC, Fz channel.
    pub gain_fz: f64,
    /// Voltage gain of the amplifiers ahead of the ADC, Mx channel.
    pub gain_mx: f64,
    /// Voltage gain of the amplifiers ahead of the ADC, My channel.
    pub gain_my: f64,
    /// Bridge supply, V (`excitation_V`).
    pub excitation_v: f64,
    /// Nominal rod speed while loading, if given.
    pub rod_speed_mm_per_min: Option<f64>,
    /// What produced the file, if given.
    pub source: Option<String>,
    /// Unknown keys, kept.
    pub other: Vec<(String, String)>,
}

/// The metadata key (this project's own; the format keeps unknown keys) that records the
/// firmware smoother's alpha.
pub const SMOOTHER_KEY: &str = "firmware_smoother_alpha";

/// The metadata key (this project's own) that names the device: the chip's serial number as
/// the logger reads it from the device's info frame (eight hex digits). Recordings of one
/// session must agree on it where they name it (`docs/session-format.md`).
pub const CHIP_SERIAL_KEY: &str = "chip_serial";

/// The metadata key (this project's own) that names the instrument where no chip serial does:
/// what `tactile import --sensor-id` was told, or a test machine's own serials. Recordings of
/// one session must agree on it where they name it (`docs/session-format.md`).
pub const SENSOR_KEY: &str = "sensor";

/// The metadata key (this project's own) that says which unit the outputs `fz_V`, `mx_V`,
/// `my_V` hold where it is not volts (a foreign sensor's, e.g. `uT`).
pub const SENSOR_UNIT_KEY: &str = "sensor_unit";

/// The metadata keys [`Meta`] types as numbers, in the order the writer emits them; every one
/// but the last (`rod_speed_mm_per_min`) is required. One list for every reader and writer of
/// the format (the file's, the Python package's DataFrame attributes).
pub const NUMBER_KEYS: [&str; 9] = [
    "sample_rate_hz",
    "contact_angle_deg",
    "azimuth_deg",
    "fingertip_radius_mm",
    "gain_fz",
    "gain_mx",
    "gain_my",
    "excitation_V",
    "rod_speed_mm_per_min",
];

/// Keys whose value must be a positive finite number.
pub(super) const POSITIVE_KEYS: [&str; 6] = [
    "sample_rate_hz",
    "fingertip_radius_mm",
    "gain_fz",
    "gain_mx",
    "gain_my",
    "excitation_V",
];

/// Refuse any key given twice, naming both lines.
fn refuse_repeated_keys(pairs: &[(usize, String, String)]) -> Result<(), RecordingError> {
    for (i, (line, key, _)) in pairs.iter().enumerate() {
        if let Some((first_line, _, _)) = pairs[..i].iter().find(|(_, k, _)| k == key) {
            return Err(RecordingError::DuplicateKey {
                line: *line,
                first_line: *first_line,
                key: key.clone(),
            });
        }
    }
    Ok(())
}

impl Meta {
    /// The value of a key the contract does not type (the last one, if repeated).
    pub fn get(&self, key: &str) -> Option<&str> {
        self.other
            .iter()
            .rev()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// The typed numbers under their keys ([`NUMBER_KEYS`] order), the rod speed where given.
    pub fn numbers(&self) -> Vec<(&'static str, f64)> {
        let values = [
            Some(self.sample_rate_hz),
            Some(self.contact_angle_deg),
            Some(self.azimuth_deg),
            Some(self.fingertip_radius_mm),
            Some(self.gain_fz),
            Some(self.gain_mx),
            Some(self.gain_my),
            Some(self.excitation_v),
            self.rod_speed_mm_per_min,
        ];
        NUMBER_KEYS
            .into_iter()
            .zip(values)
            .filter_map(|(k, v)| v.map(|v| (k, v)))
            .collect()
    }

    /// Typed metadata from `number` (a key's value, `None` where absent), `missing` (the error
    /// for an absent required key), the source and the untyped pairs.
    pub fn from_numbers<E>(
        mut number: impl FnMut(&'static str) -> Result<Option<f64>, E>,
        missing: impl Fn(&'static str) -> E,
        source: Option<String>,
        other: Vec<(String, String)>,
    ) -> Result<Self, E> {
        let mut required = |key| number(key)?.ok_or_else(|| missing(key));
        Ok(Meta {
            sample_rate_hz: required("sample_rate_hz")?,
            contact_angle_deg: required("contact_angle_deg")?,
            azimuth_deg: required("azimuth_deg")?,
            fingertip_radius_mm: required("fingertip_radius_mm")?,
            gain_fz: required("gain_fz")?,
            gain_mx: required("gain_mx")?,
            gain_my: required("gain_my")?,
            excitation_v: required("excitation_V")?,
            rod_speed_mm_per_min: number("rod_speed_mm_per_min")?,
            source,
            other,
        })
    }

    /// The `key = value` pairs to write, required keys first.
    pub fn pairs(&self) -> Vec<(String, String)> {
        let mut p = vec![("format".to_string(), super::FORMAT.to_string())];
        p.extend(
            self.numbers()
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string())),
        );
        if let Some(s) = &self.source {
            p.push(("source".into(), s.clone()));
        }
        p.extend(self.other.iter().cloned());
        p
    }

    /// Build the typed metadata from the raw pairs (with their line numbers); `header_line` is
    /// where a missing key is reported.
    pub(super) fn from_pairs(
        pairs: Vec<(usize, String, String)>,
        header_line: usize,
    ) -> Result<Self, RecordingError> {
        refuse_repeated_keys(&pairs)?;
        let find = |key: &str| pairs.iter().rev().find(|(_, k, _)| k == key);
        let (fline, _, fvalue) = find("format").ok_or(RecordingError::MissingKey {
            line: header_line,
            key: "format",
        })?;
        if fvalue != super::FORMAT {
            return Err(RecordingError::WrongFormat {
                line: *fline,
                value: fvalue.clone(),
            });
        }
        let number = |key: &'static str| -> Result<Option<f64>, RecordingError> {
            let Some((line, _, value)) = find(key) else {
                return Ok(None);
            };
            let v = parse_number(value).ok_or_else(|| RecordingError::BadMetaValue {
                line: *line,
                key: key.to_string(),
                value: value.clone(),
            })?;
            if POSITIVE_KEYS.contains(&key) && v <= 0.0 {
                return Err(RecordingError::NotPositive {
                    line: *line,
                    key,
                    value: value.clone(),
                });
            }
            Ok(Some(v))
        };
        let missing = |key| RecordingError::MissingKey {
            line: header_line,
            key,
        };
        let other = pairs
            .iter()
            .filter(|(_, k, _)| {
                k != "format" && k != "source" && !NUMBER_KEYS.contains(&k.as_str())
            })
            .map(|(_, k, v)| (k.clone(), v.clone()))
            .collect();
        let source = find("source").map(|(_, _, v)| v.clone());
        Meta::from_numbers(number, missing, source, other)
    }
}

/// A finite decimal number (metadata values and data fields alike).
pub(super) fn parse_number(s: &str) -> Option<f64> {
    let v: f64 = s.trim().parse().ok()?;
    v.is_finite().then_some(v)
}
