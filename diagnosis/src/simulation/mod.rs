//! The user's own simulation as the baseline (`docs/simulation-format.md`): a lab's FE run, a
//! lumped model or a calibration curve of the same test takes the place of our fingertip's FE
//! tables and our chip, with the calibration freedoms of the 2026-11-27 amendment of
//! `docs/diagnosis-format.md` (a load scale, the three output scales, four offsets).
//!
//! Two forms, told apart by the file's `format` key:
//! - a **simulated test** (`tactile-recording/1`): the test in time on its own time base and
//!   rate, shifted onto the recording's by the rod's travel and interpolated at its samples
//!   (`series.rs`);
//! - a **static response** (`tactile-response/1`): rod travel -> load and outputs, driven along
//!   the recorded rod path as the FE tables are (`table.rs`).
//!
//! Either becomes one [`UnitResponse`] per full-rate sample of the recording: the load as the
//! force at a load scale of 1, the outputs read back through the signal path at the
//! simulation's own gains to the chip loads they stand for (`sim::forward::SignalPath::
//! chip_loads`), so that the catalogue's mechanical effects act on loads and its electrical ones
//! on volts, as they do on our own model. Which recording has which simulation: [`pairing`].

mod curve;
pub mod pairing;
pub(crate) mod plausible;
mod series;
mod table;

use std::path::{Path, PathBuf};

use baseline::UnitResponse;
use recording::{Meta, Recording};
use sim::forward::SignalPath;

pub use pairing::{PairingError, Simulations};

/// The channels a simulation may hold, in contract order (the recording's columns after `t_s`
/// and `rod_mm`).
fn channels() -> &'static [&'static str] {
    &recording::REQUIRED_COLUMNS[2..]
}

/// Named values that keep their order in JSON.
pub type Named<T> = Vec<(String, T)>;

/// Serialise named values as a JSON object in their order (NaN and infinities as null).
fn as_map<S: serde::Serializer, T: serde::Serialize>(
    v: &Named<T>,
    s: S,
) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeMap;
    let mut map = s.serialize_map(Some(v.len()))?;
    for (k, x) in v {
        map.serialize_entry(k, x)?;
    }
    map.end()
}

/// `baseline.simulation` in OUT.json: whose simulation the baseline was and how it was set
/// against the recording (`docs/simulation-format.md`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct SimulationReport {
    /// The simulation's file, as given.
    pub file: String,
    /// `simulated_test` (the test in time, aligned to the recording's) or `static_response`
    /// (rod travel -> load and outputs, driven along the recorded rod).
    pub form: &'static str,
    /// The simulation's own metadata, key by key as its file gives them.
    #[serde(serialize_with = "as_map")]
    pub metadata: Named<String>,
    /// How it was aligned to the recording, in words.
    pub aligned: String,
    /// The alignment's figures (a time shift and how far the rod paths stay apart, or the
    /// travel the table spans).
    #[serde(serialize_with = "as_map")]
    pub alignment: Named<f64>,
    /// The front end its outputs were given at, against the recording's, in words.
    pub outputs_at: String,
    /// The channels compared against it.
    pub channels: Vec<String>,
    /// The recording's other channels, each with why it is not compared.
    #[serde(serialize_with = "as_map")]
    pub not_compared: Named<String>,
}

/// The format keys of the two forms.
pub const RESPONSE_FORMAT: &str = "tactile-response/1";

/// Why a simulation cannot be the baseline of a recording. Each names the simulation's file,
/// and the field or line where there is one.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimulationError {
    /// The file could not be opened or read.
    #[error("simulation {}: {source}", .path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A simulated test that breaks the recording format (the reader's error names the line
    /// and field).
    #[error("simulation {0}")]
    Recording(#[from] recording::RecordingError),
    /// A static response table that breaks its format.
    #[error("simulation {}: line {line}: {what}", .path.display())]
    Table {
        path: PathBuf,
        line: usize,
        what: String,
    },
    /// The simulation is of another jig or fingertip than the recording.
    #[error("simulation {}: `{key}` = {simulated} but the recording's is {recorded}: a simulation of another test", .path.display())]
    Metadata {
        path: PathBuf,
        key: &'static str,
        simulated: f64,
        recorded: f64,
    },
    /// The simulated rod path is not the recorded one, at any time shift.
    #[error("simulation {}: `rod_mm` does not follow the recording's: at the best time shift ({shift_s:+.3} s) the two are {rms_mm:.3} mm apart RMS ({share_pct:.1} % of the largest recorded travel; one rod path is within {limit_pct} %) and {gap_mm:.3} mm at most: a simulation of another protocol", .path.display())]
    Protocol {
        path: PathBuf,
        shift_s: f64,
        rms_mm: f64,
        gap_mm: f64,
        share_pct: f64,
        limit_pct: f64,
    },
    /// Too few rows with a time, a rod travel and every simulated column.
    #[error("simulation {}: {rows} rows hold `t_s`, `rod_mm` and every simulated column: too few to interpolate", .path.display())]
    TooShort { path: PathBuf, rows: usize },
    /// The simulation does not span the recorded travel.
    #[error("simulation {}: `rod_mm` covers {:.3} to {:.3} mm, the recording needs {:.3} to {:.3} mm: the simulation does not cover the recorded travel", .path.display(), .covers_mm.0, .covers_mm.1, .needs_mm.0, .needs_mm.1)]
    Travel {
        path: PathBuf,
        covers_mm: (f64, f64),
        needs_mm: (f64, f64),
    },
    /// The simulated test ends (or starts) inside the recording's contact.
    #[error("simulation {}: `t_s` covers {from_s:.3} to {to_s:.3} s of the recording's time once aligned, the rod is in contact from {contact_from_s:.3} to {contact_to_s:.3} s: the simulation does not cover the recorded test", .path.display())]
    Time {
        path: PathBuf,
        from_s: f64,
        to_s: f64,
        contact_from_s: f64,
        contact_to_s: f64,
    },
    /// Neither form, or no format at all.
    #[error("simulation {}: `format` is {found}: a simulation is a recording of the test (`{}`) or a static response (`{RESPONSE_FORMAT}`), docs/simulation-format.md", .path.display(), recording::FORMAT)]
    Format { path: PathBuf, found: String },
    /// No channel that both the recording and the simulation hold.
    #[error("simulation {}: it holds {simulated}, the recording measures {recorded}: no channel in common to compare", .path.display())]
    NothingInCommon {
        path: PathBuf,
        simulated: String,
        recorded: String,
    },
    /// The simulation's outputs cannot be read back to chip loads (a zero gain or excitation).
    #[error("simulation {}: its outputs cannot be read back to the chip's loads at gains {gain:?} and excitation {excitation_v} V", .path.display())]
    SignalPath {
        path: PathBuf,
        gain: [f64; 3],
        excitation_v: f64,
    },
    /// A line that is not UTF-8 text (a binary file, UTF-16, Latin-1): bad data, not an I/O
    /// failure.
    #[error("simulation {}: line {line}: not UTF-8 text (byte 0x{byte:02x}): a binary or differently encoded file? A simulation is UTF-8 text (docs/simulation-format.md)", .path.display())]
    NotText {
        path: PathBuf,
        line: usize,
        byte: u8,
    },
    /// A fitted scale or the rod's travel beyond a physically plausible factor
    /// (10x either way, `docs/simulation-format.md`): a unit read as another, more likely than
    /// physics.
    #[error("simulation {path}: the simulation's {what} is {}x the recording's: {hint} (a calibration absorbs up to {}x either way; --accept-scale takes the factor on purpose)", factor(*.ratio), plausible::PLAUSIBLE_FACTOR)]
    Scale {
        path: String,
        what: String,
        ratio: f64,
        hint: String,
    },
    /// The options pair no simulation with this recording.
    #[error("no simulation is paired with recording {0}")]
    Unpaired(String),
}

impl sysexit::ExitStatus for SimulationError {
    fn exit_code(&self) -> u8 {
        match self {
            Self::Io { source, .. } => sysexit::of_input(source.kind()),
            Self::Recording(e) => e.exit_code(),
            Self::Unpaired(_) => sysexit::USAGE,
            _ => sysexit::DATA,
        }
    }
}

/// The simulation of one recording, ready to be its baseline.
pub(crate) struct Loaded {
    /// The response at each full-rate sample of the recording (load scale 1).
    pub units: Vec<UnitResponse>,
    /// The recording's channels (load_N, fz_V, mx_V, my_V) the simulation does not model.
    pub lacks: [bool; 4],
    /// What OUT.json says of it (`baseline.simulation`).
    pub report: SimulationReport,
}

/// What either form gives before it is set against the recording: the simulated columns
/// (load_N, fz_V, mx_V, my_V; `None` where not simulated) at each full-rate sample, and how
/// they were aligned.
pub(crate) struct Aligned {
    pub columns: [Option<Vec<f64>>; 4],
    pub aligned: String,
    pub alignment: Named<f64>,
}

/// The full-rate samples a simulation is set against: the recording's times and rod travels
/// (gaps dropped, as the diagnosis reads them).
#[derive(Clone, Copy)]
pub(crate) struct Samples<'a> {
    pub t_s: &'a [f64],
    pub rod_mm: &'a [f64],
}

/// The simulation at `path` as the baseline of `rec`, at its full-rate samples `at`;
/// `sensitivity_per_v` is the chip's, through which its outputs are read back to loads.
/// `accept_scale`: a travel beyond the plausible factor is taken on purpose
/// ([`plausible`]).
pub(crate) fn load(
    path: &Path,
    rec: &Recording,
    at: Samples,
    sensitivity_per_v: [[f64; 3]; 3],
    accept_scale: bool,
) -> Result<Loaded, SimulationError> {
    let head = read_head(path)?;
    let largest = |v: &[f64]| {
        v.iter()
            .copied()
            .filter(|x| x.is_finite())
            .fold(0.0, f64::max)
    };
    let travel = |simulated: &[f64]| match accept_scale {
        true => Ok(()),
        false => plausible::check_travel(path, largest(simulated), largest(at.rod_mm)),
    };
    let (meta_text, own, aligned) = match head.format.as_deref() {
        Some(recording::FORMAT) => {
            let sim = recording::read(path)?;
            check_jig(path, &Angles::of_meta(&sim.meta), &rec.meta)?;
            travel(&sim.channels.rod_mm)?;
            let own = Front::of_meta(&sim.meta);
            (head.pairs.clone(), own, series::align(path, &sim, at)?)
        }
        Some(RESPONSE_FORMAT) => {
            let t = table::read(path)?;
            check_jig(path, &t.angles(), &rec.meta)?;
            travel(t.rod_mm())?;
            let own = t.front(&rec.meta);
            let aligned = t.drive(path, at)?;
            (head.pairs.clone(), own, aligned)
        }
        other => {
            return Err(SimulationError::Format {
                path: path.to_path_buf(),
                found: other.map_or("missing".into(), |f| format!("`{f}`")),
            })
        }
    };
    let lacks: [bool; 4] = std::array::from_fn(|c| aligned.columns[c].is_none());
    let not_compared = not_compared(path, &lacks, rec)?;
    let signal = SignalPath {
        sensitivity_per_v,
        gain: own.gain,
        excitation_v: own.excitation_v,
    };
    let units = units(&aligned.columns, &signal).ok_or(SimulationError::SignalPath {
        path: path.to_path_buf(),
        gain: own.gain,
        excitation_v: own.excitation_v,
    })?;
    let report = SimulationReport {
        file: path.display().to_string(),
        form: head.form_name(),
        metadata: meta_text,
        aligned: aligned.aligned,
        alignment: aligned.alignment,
        outputs_at: own.words(&rec.meta),
        channels: (0..4)
            .filter(|&c| !lacks[c] && rec.channels.measured()[c + 2])
            .map(|c| channels()[c].to_string())
            .collect(),
        not_compared,
    };
    Ok(Loaded {
        units,
        lacks,
        report,
    })
}

/// The per-sample responses: the load as the force at a load scale of 1, the outputs read back
/// to chip loads through `signal` (the simulation's own gains). `None` where the path is
/// singular.
fn units(columns: &[Option<Vec<f64>>; 4], signal: &SignalPath) -> Option<Vec<UnitResponse>> {
    let n = columns.iter().flatten().map(Vec::len).next().unwrap_or(0);
    let at = |c: usize, i: usize| columns[c].as_ref().map_or(0.0, |v| v[i]);
    (0..n)
        .map(|i| {
            let chip = signal.chip_loads([at(1, i), at(2, i), at(3, i)])?;
            Some(UnitResponse {
                force_n: at(0, i),
                chip,
            })
        })
        .collect()
}

/// The recording's channels not compared, each with why; refused when none is left.
fn not_compared(
    path: &Path,
    lacks: &[bool; 4],
    rec: &Recording,
) -> Result<Named<String>, SimulationError> {
    let measured = rec.channels.measured();
    let mut out = Vec::new();
    let mut common = 0;
    for c in 0..4 {
        let why = match (lacks[c], measured[c + 2]) {
            (false, true) => {
                common += 1;
                continue;
            }
            (true, true) => "the simulation does not model it (its column is empty or absent)",
            (false, false) => "the recording does not measure it",
            (true, false) => "neither the recording nor the simulation holds it",
        };
        out.push((channels()[c].to_string(), why.to_string()));
    }
    if common == 0 {
        let list = |keep: &dyn Fn(usize) -> bool| {
            let names: Vec<&str> = (0..4).filter(|&c| keep(c)).map(|c| channels()[c]).collect();
            if names.is_empty() {
                "no channel".to_string()
            } else {
                names.join(", ")
            }
        };
        return Err(SimulationError::NothingInCommon {
            path: path.to_path_buf(),
            simulated: list(&|c| !lacks[c]),
            recorded: list(&|c| measured[c + 2]),
        });
    }
    Ok(out)
}

/// The jig and fingertip a simulation says it is of: contact angle, azimuth, radius (each
/// where it says).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Angles {
    pub contact_angle_deg: Option<f64>,
    pub azimuth_deg: Option<f64>,
    pub fingertip_radius_mm: Option<f64>,
}

impl Angles {
    /// What a recording's metadata says (every key is required there).
    fn of_meta(m: &Meta) -> Self {
        Self {
            contact_angle_deg: Some(m.contact_angle_deg),
            azimuth_deg: Some(m.azimuth_deg),
            fingertip_radius_mm: Some(m.fingertip_radius_mm),
        }
    }
}

/// Within this of each other two angles are one jig's (a protractor's reading), deg.
const ANGLE_TOLERANCE_DEG: f64 = 0.5;
/// Within this share of each other two radii are one fingertip's.
const RADIUS_TOLERANCE: f64 = 0.01;

/// Refuse a simulation of another jig or fingertip than the recording's.
fn check_jig(path: &Path, sim: &Angles, rec: &Meta) -> Result<(), SimulationError> {
    let wrap = |d: f64| (d + 180.0).rem_euclid(360.0) - 180.0;
    let checks = [
        (
            "contact_angle_deg",
            sim.contact_angle_deg,
            rec.contact_angle_deg,
            (sim.contact_angle_deg.unwrap_or(0.0) - rec.contact_angle_deg).abs()
                <= ANGLE_TOLERANCE_DEG,
        ),
        (
            "azimuth_deg",
            sim.azimuth_deg,
            rec.azimuth_deg,
            wrap(sim.azimuth_deg.unwrap_or(0.0) - rec.azimuth_deg).abs() <= ANGLE_TOLERANCE_DEG,
        ),
        (
            "fingertip_radius_mm",
            sim.fingertip_radius_mm,
            rec.fingertip_radius_mm,
            (sim.fingertip_radius_mm.unwrap_or(0.0) / rec.fingertip_radius_mm - 1.0).abs()
                <= RADIUS_TOLERANCE,
        ),
    ];
    for (key, simulated, recorded, same) in checks {
        if let Some(simulated) = simulated.filter(|_| !same) {
            return Err(SimulationError::Metadata {
                path: path.to_path_buf(),
                key,
                simulated,
                recorded,
            });
        }
    }
    Ok(())
}

/// The front end a simulation's outputs are given at: its gains and excitation.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Front {
    pub gain: [f64; 3],
    pub excitation_v: f64,
}

impl Front {
    fn of_meta(m: &Meta) -> Self {
        Self {
            gain: [m.gain_fz, m.gain_mx, m.gain_my],
            excitation_v: m.excitation_v,
        }
    }

    /// What the outputs' level means against the recording's front end, in words.
    fn words(&self, rec: &Meta) -> String {
        let rec_gain = [rec.gain_fz, rec.gain_mx, rec.gain_my];
        let factors: [f64; 3] = std::array::from_fn(|k| {
            rec_gain[k] * rec.excitation_v / (self.gain[k] * self.excitation_v)
        });
        if factors.iter().all(|f| (f - 1.0).abs() < 1e-9) {
            return "the recording's gains and excitation".into();
        }
        format!(
            "gains {:?} and excitation {} V: read at the recording's, its outputs are x {:.4}, {:.4}, {:.4} (Fz, Mx, My)",
            self.gain, self.excitation_v, factors[0], factors[1], factors[2]
        )
    }
}

/// A factor in a few significant figures: 1000, 175, 0.0057.
fn factor(x: f64) -> String {
    if x >= 100.0 {
        return format!("{x:.0}");
    }
    let digits = (1 - x.log10().floor() as i32).max(0) as usize;
    let text = format!("{x:.digits$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// The metadata block of a simulation's file: its `# key = value` pairs in order and its
/// `format`.
struct Head {
    pairs: Vec<(String, String)>,
    format: Option<String>,
}

impl Head {
    fn form_name(&self) -> &'static str {
        if self.format.as_deref() == Some(RESPONSE_FORMAT) {
            "static_response"
        } else {
            "simulated_test"
        }
    }
}

/// Read the metadata lines ahead of the header (no further); a line that is not UTF-8 is
/// bad data, named by its number.
fn read_head(path: &Path) -> Result<Head, SimulationError> {
    use std::io::BufRead;
    let io = |source| SimulationError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut pairs = Vec::new();
    for (i, bytes) in std::io::BufReader::new(file).split(b'\n').enumerate() {
        let bytes = bytes.map_err(io)?;
        let line = utf8(path, &bytes, i + 1)?;
        let text = line.trim().trim_start_matches('\u{feff}');
        if text.is_empty() {
            continue;
        }
        let Some(comment) = text.strip_prefix('#') else {
            break;
        };
        if let Some((k, v)) = comment.split_once('=') {
            pairs.push((k.trim().to_string(), v.trim().to_string()));
        }
    }
    let format = pairs
        .iter()
        .find(|(k, _)| k == "format")
        .map(|(_, v)| v.clone());
    Ok(Head { pairs, format })
}

/// `bytes` (from line `first_line` of the simulation at `path` on) as text, or the line and
/// byte where they stop being UTF-8.
pub(crate) fn utf8<'b>(
    path: &Path,
    bytes: &'b [u8],
    first_line: usize,
) -> Result<&'b str, SimulationError> {
    std::str::from_utf8(bytes).map_err(|e| {
        let at = e.valid_up_to();
        SimulationError::NotText {
            path: path.to_path_buf(),
            line: first_line + bytes[..at].iter().filter(|&&b| b == b'\n').count(),
            byte: bytes[at],
        }
    })
}

/// The calibration's bounds with a simulation as the baseline: the issue's "same calibration
/// freedoms" are a load scale (the modulus, by the same factor as ours), the three output
/// scales and four offsets. The contact law's shape (exponent shift, curvature, warp, blend to
/// a power law) and the outputs' maps (blends, the load they are read at) are the
/// simulation's own, held at 0: bending them would fit away what the simulation left out.
/// Where the load is not compared, nothing tells a load scale from the output scales: it is
/// held at 1.
pub(crate) fn calibration_bounds(
    ours: &hardware::FitBounds,
    load_compared: bool,
) -> hardware::FitBounds {
    hardware::FitBounds {
        modulus_ln_range: if load_compared {
            ours.modulus_ln_range
        } else {
            0.0
        },
        exponent_shift_min: 0.0,
        exponent_shift_max: 0.0,
        exponent_curvature_max: 0.0,
        force_warp_max: 0.0,
        force_law_blend_max: 0.0,
        map_blend_min: 0.0,
        map_blend_max: 0.0,
        map_load_share_max: 0.0,
        map_load_level_max: 0.0,
        ..ours.clone()
    }
}
