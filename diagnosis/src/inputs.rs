//! The recordings a list of inputs names, checked before any work (`docs/session-format.md`,
//! "One sensor, one list of files"): folders expanded to their `*.csv`, every file there, each
//! recording once (by content, not by name), and for a joint diagnosis one sensor in one
//! fingertip. The batch ([`crate::session`]) and the joint diagnosis ([`crate::joint`]) both
//! call these, so the command line and the Python package refuse the same lists with the same
//! line.

use std::hash::Hasher as _;
use std::io::Read;
use std::path::{Path, PathBuf};

use recording::Meta;

/// Why a list of inputs is not a list of recordings to diagnose.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum InputError {
    /// The list is empty.
    #[error("no recording given: name at least one recording file, or a folder of them")]
    Nothing,
    /// An input that cannot be opened, listed or read (missing, forbidden).
    #[error("{}: {source}", .path.display())]
    Open {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A folder given as input holds no `*.csv`.
    #[error("{}: no *.csv recording in this folder", .0.display())]
    NoRecordings(PathBuf),
    /// One recording named twice: the same file (under two names, or through a symlink), or
    /// a byte-identical copy.
    #[error(
        "{} and {} are {how}: each recording is given once",
        .first.display(),
        .second.display()
    )]
    Repeated {
        first: PathBuf,
        second: PathBuf,
        /// `the same file` or `byte-identical copies`.
        how: &'static str,
    },
    /// A recording of another sensor or fingertip than the session's first.
    #[error(
        "{file}: {key} = {value}, but {reference} has {key} = {reference_value}: the recordings \
         of one session are of one sensor in one fingertip (the protocol, rate, gains and \
         temperature may differ)"
    )]
    OtherSensor {
        file: String,
        key: &'static str,
        value: String,
        /// The first readable recording that gives `key`, against which the others are judged.
        reference: String,
        reference_value: String,
    },
}

/// An empty list or a repeated recording is a usage error; an input that is not there, a
/// missing input; another sensor's recording, bad data.
impl sysexit::ExitStatus for InputError {
    fn exit_code(&self) -> u8 {
        match self {
            Self::Nothing | Self::Repeated { .. } => sysexit::USAGE,
            Self::Open { source, .. } => sysexit::of_input(source.kind()),
            Self::NoRecordings(_) => sysexit::NO_INPUT,
            Self::OtherSensor { .. } => sysexit::DATA,
        }
    }
}

fn open_error(path: &Path) -> impl FnOnce(std::io::Error) -> InputError + '_ {
    move |source| InputError::Open {
        path: path.to_path_buf(),
        source,
    }
}

/// The recordings `inputs` name, each once: [`expand`], then [`refuse_repeats`].
pub fn recordings(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, InputError> {
    let files = expand(inputs)?;
    refuse_repeats(&files)?;
    Ok(files)
}

/// The files `inputs` name: files as given, and for a folder every `*.csv` in it, sorted. Every
/// input must be there: a missing one is refused here, before any work, not met half way.
pub fn expand(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, InputError> {
    if inputs.is_empty() {
        return Err(InputError::Nothing);
    }
    let mut out = Vec::new();
    for input in inputs {
        let meta = std::fs::metadata(input).map_err(open_error(input))?;
        if meta.is_dir() {
            let before = out.len();
            out.extend(csv_files_in(input)?);
            if out.len() == before {
                return Err(InputError::NoRecordings(input.clone()));
            }
        } else {
            out.push(input.clone());
        }
    }
    Ok(out)
}

fn csv_files_in(dir: &Path) -> Result<Vec<PathBuf>, InputError> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(open_error(dir))? {
        let path = entry.map_err(open_error(dir))?.path();
        if path.extension().is_some_and(|e| e == "csv") && !path.is_dir() {
            files.push(path);
        }
    }
    files.sort();
    Ok(files)
}

/// Refuse a recording given twice: one file under two names (`a.csv ./a.csv`, a symlink: one
/// canonical path), or a byte-identical copy. Only files of one size can be copies: each is
/// hashed once, and equal hashes are compared byte for byte. The pair named is the first in
/// input order.
pub fn refuse_repeats(files: &[PathBuf]) -> Result<(), InputError> {
    let mut seen: Vec<Seen> = Vec::with_capacity(files.len());
    for (i, file) in files.iter().enumerate() {
        let canonical = std::fs::canonicalize(file).map_err(open_error(file))?;
        let bytes = std::fs::metadata(&canonical)
            .map_err(open_error(file))?
            .len();
        let mut this = Seen {
            canonical,
            bytes,
            hash: None,
        };
        for (j, earlier) in seen.iter_mut().enumerate() {
            let how = if earlier.canonical == this.canonical {
                "the same file"
            } else if earlier.bytes == this.bytes
                && earlier.hash(&files[j])? == this.hash(file)?
                && same_bytes(&earlier.canonical, &this.canonical).map_err(open_error(file))?
            {
                "byte-identical copies"
            } else {
                continue;
            };
            return Err(InputError::Repeated {
                first: files[j].clone(),
                second: files[i].clone(),
                how,
            });
        }
        seen.push(this);
    }
    Ok(())
}

/// A file already listed: where it is, its size and, once needed, its content's hash.
struct Seen {
    canonical: PathBuf,
    bytes: u64,
    hash: Option<u64>,
}

impl Seen {
    fn hash(&mut self, named: &Path) -> Result<u64, InputError> {
        if let Some(h) = self.hash {
            return Ok(h);
        }
        let mut hasher = std::hash::DefaultHasher::new();
        let mut file = std::fs::File::open(&self.canonical).map_err(open_error(named))?;
        let mut buf = vec![0u8; 1 << 16];
        loop {
            let n = file.read(&mut buf).map_err(open_error(named))?;
            if n == 0 {
                break;
            }
            hasher.write(&buf[..n]);
        }
        let h = hasher.finish();
        self.hash = Some(h);
        Ok(h)
    }
}

/// Whether two files of one size hold the same bytes.
fn same_bytes(a: &Path, b: &Path) -> std::io::Result<bool> {
    let (mut a, mut b) = (std::fs::File::open(a)?, std::fs::File::open(b)?);
    let (mut x, mut y) = (vec![0u8; 1 << 16], vec![0u8; 1 << 16]);
    loop {
        let n = fill(&mut a, &mut x)?;
        if n != fill(&mut b, &mut y)? || x[..n] != y[..n] {
            return Ok(false);
        }
        if n == 0 {
            return Ok(true);
        }
    }
}

/// Read until `buf` is full or the file ends; the bytes read.
fn fill(file: &mut std::fs::File, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match file.read(&mut buf[n..])? {
            0 => break,
            k => n += k,
        }
    }
    Ok(n)
}

/// The metadata keys that name the sensor: what may not differ between the recordings of one
/// session. The fingertip's radius (every recording gives it), and where the metadata name
/// them the device's serial (the logger writes it), the instrument's identity (`sensor`: an
/// import's `--sensor-id`, a test machine's serials) and the unit its outputs hold
/// (`sensor_unit`, a foreign sensor's import). Two recordings that lack a key are not compared
/// on it.
pub const SENSOR_KEYS: [&str; 4] = [
    "fingertip_radius_mm",
    recording::CHIP_SERIAL_KEY,
    recording::SENSOR_KEY,
    recording::SENSOR_UNIT_KEY,
];

/// Refuse a recording of another sensor: each of [`SENSOR_KEYS`] is judged against the first
/// recording (in input order) that gives it, which for the radius is the first readable one.
/// `recordings`: each readable recording's name and metadata, in input order.
pub fn one_sensor<'a>(
    recordings: impl IntoIterator<Item = (&'a str, &'a Meta)>,
) -> Result<(), InputError> {
    let mut first: [Option<(&str, String)>; SENSOR_KEYS.len()] = Default::default();
    for (name, meta) in recordings {
        for (key, first) in SENSOR_KEYS.into_iter().zip(first.iter_mut()) {
            let Some(value) = sensor_value(meta, key) else {
                continue;
            };
            match first {
                None => *first = Some((name, value)),
                Some((reference, reference_value))
                    if !reference_value.eq_ignore_ascii_case(&value) =>
                {
                    return Err(InputError::OtherSensor {
                        file: name.to_string(),
                        key,
                        value,
                        reference: reference.to_string(),
                        reference_value: reference_value.clone(),
                    });
                }
                Some(_) => {}
            }
        }
    }
    Ok(())
}

/// `key`'s value in `meta` as text (a number in its shortest form, so `20` and `20.0` agree; a
/// serial trimmed), `None` where the metadata do not give it.
fn sensor_value(meta: &Meta, key: &str) -> Option<String> {
    if key == "fingertip_radius_mm" {
        return Some(meta.fingertip_radius_mm.to_string());
    }
    meta.get(key)
        .map(str::trim)
        .filter(|v| !v.is_empty())
        .map(str::to_string)
}

#[cfg(test)]
mod tests;
