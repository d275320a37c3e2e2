//! The one loader for every parameter of the sensor: `hardware/*.toml` (fingertip and gel, chip,
//! front end, ADC, board, the bounds of the diagnosis's baseline fit, the original paper's sensor),
//! read and validated here and nowhere else.
//!
//! Each file is read strictly: a missing key, a key nobody reads (usually a typo), a value of the
//! wrong type or outside its physical range is an error that names the file, the key and the
//! allowed range. All errors of a file are collected, not just the first.
//!
//! ```
//! let params = hardware::Params::load_default().unwrap();
//! assert!(params.fingertip.radius_mm > 0.0);
//! ```
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

mod adc;
mod board;
mod chip;
mod fingertip;
mod fit_bounds;
mod frontend;
mod paper_sensor;
pub mod reader;
mod sim;

use std::fmt;
use std::path::{Path, PathBuf};

pub use adc::{Adc, Crc, NOISE_TABLE_GAINS, NOISE_TABLE_OSR};
pub use board::{Board, ClockSource};
pub use chip::{Bridge as ChipBridge, Chip, Resistor as ChipResistor, ARM_NAMES, BRIDGE_NAMES};
pub use fingertip::{CompressionTest, Fingertip};
pub use fit_bounds::FitBounds;
pub use frontend::{AntiAlias, Bridge, FrontEnd, GainStage, InAmp, TempSensor, Trim, BRIDGES};
pub use paper_sensor::PaperSensor;
pub use reader::Reader;
pub use sim::Sim;

/// Every parameter of the sensor, loaded from one `hardware/` folder.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Params {
    /// The gel hemisphere, its mount, the rod and the standard compression test.
    pub fingertip: Fingertip,
    /// The silicon cross-beam chip, its piezoresistors and bridges.
    pub chip: Chip,
    /// Bridges' mismatch, trim DAC, amplifiers, anti-alias RC, temperature sensor.
    pub frontend: FrontEnd,
    /// The ADS131M04's configuration and datasheet figures.
    pub adc: Adc,
    /// The NUCLEO-F411RE pin map.
    pub board: Board,
    /// The emulated sensor's own parameters (pillar, temperature warm-up).
    pub sim: Sim,
    /// How far the diagnosis may calibrate the baseline model to a recording.
    pub fit_bounds: FitBounds,
    /// The original paper's sensor where it differs from the default model (its angle law of
    /// Fz, relaxation and AC coupling): read only by the paper's session and scorecard.
    pub paper_sensor: PaperSensor,
}

impl Params {
    /// The folder this crate was built from: the repository's `hardware/`. Overridden by the
    /// environment variable `TACTILE_HARDWARE_DIR`.
    pub fn default_dir() -> PathBuf {
        std::env::var_os("TACTILE_HARDWARE_DIR")
            .map(PathBuf::from)
            .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")))
    }

    /// Load from [`Params::default_dir`].
    pub fn load_default() -> Result<Self, LoadError> {
        Self::load(&Self::default_dir())
    }

    /// Load and validate every file in `dir`.
    pub fn load(dir: &Path) -> Result<Self, LoadError> {
        let mut errors = Vec::new();
        let fingertip = collect(Fingertip::load(&dir.join("fingertip.toml")), &mut errors);
        let chip = collect(Chip::load(&dir.join("chip.toml")), &mut errors);
        let frontend = collect(FrontEnd::load(&dir.join("frontend.toml")), &mut errors);
        let adc = collect(Adc::load(&dir.join("adc.toml")), &mut errors);
        let board = collect(Board::load(&dir.join("board.toml")), &mut errors);
        let sim = collect(Sim::load(&dir.join("sim.toml")), &mut errors);
        let fit_bounds = collect(FitBounds::load(&dir.join("fit-bounds.toml")), &mut errors);
        let paper = collect(
            PaperSensor::load(&dir.join("paper-sensor.toml")),
            &mut errors,
        );
        match (
            fingertip, chip, frontend, adc, board, sim, fit_bounds, paper,
        ) {
            (
                Some(fingertip),
                Some(chip),
                Some(frontend),
                Some(adc),
                Some(board),
                Some(sim),
                Some(fit_bounds),
                Some(paper_sensor),
            ) if errors.is_empty() => Ok(Self {
                fingertip,
                chip,
                frontend,
                adc,
                board,
                sim,
                fit_bounds,
                paper_sensor,
            }),
            _ => Err(LoadError(errors)),
        }
    }
}

fn collect<T>(result: Result<T, Vec<ParamError>>, errors: &mut Vec<ParamError>) -> Option<T> {
    result.map_err(|e| errors.extend(e)).ok()
}

/// One problem with one key of one parameter file.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamError {
    /// The file that holds (or should hold) the key.
    pub file: PathBuf,
    /// Dotted key path, e.g. `gel.youngs_modulus_pa`; empty for a whole-file problem.
    pub key: String,
    /// What is wrong with it.
    pub kind: ParamErrorKind,
}

/// What is wrong with a key.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ParamErrorKind {
    /// The file could not be read.
    Io(String),
    /// The file is not valid TOML.
    Syntax(String),
    /// A required key is absent.
    Missing,
    /// A key that no parameter uses: a typo or a leftover.
    Unknown { suggestion: Option<String> },
    /// The value has the wrong TOML type.
    WrongType { expected: &'static str },
    /// An array has the wrong number of elements.
    WrongLength { expected: usize, found: usize },
    /// The value lies outside its physical or electrical range.
    OutOfRange { value: f64, min: f64, max: f64 },
    /// A string that is not one of the allowed words.
    NotOneOf { found: String, allowed: String },
    /// A rule across several keys is broken.
    Invalid(String),
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let file = self.file.display();
        if self.key.is_empty() {
            write!(f, "{file}: ")?;
        } else {
            write!(f, "{file}: key `{}`: ", self.key)?;
        }
        match &self.kind {
            ParamErrorKind::Io(e) => write!(f, "cannot read the file: {e}"),
            ParamErrorKind::Syntax(e) => write!(f, "not valid TOML: {e}"),
            ParamErrorKind::Missing => write!(f, "missing"),
            ParamErrorKind::Unknown {
                suggestion: Some(s),
            } => {
                write!(f, "unknown key (did you mean `{s}`?)")
            }
            ParamErrorKind::Unknown { suggestion: None } => write!(f, "unknown key"),
            ParamErrorKind::WrongType { expected } => write!(f, "expected {expected}"),
            ParamErrorKind::WrongLength { expected, found } => {
                write!(f, "expected {expected} elements, found {found}")
            }
            ParamErrorKind::OutOfRange { value, min, max } => {
                write!(f, "{value} is out of range; allowed {min} ..= {max}")
            }
            ParamErrorKind::NotOneOf { found, allowed } => {
                write!(f, "`{found}` is not one of: {allowed}")
            }
            ParamErrorKind::Invalid(why) => write!(f, "{why}"),
        }
    }
}

impl std::error::Error for ParamError {}

/// Every problem found while loading a `hardware/` folder.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadError(pub Vec<ParamError>);

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let lines: Vec<String> = self.0.iter().map(ToString::to_string).collect();
        f.write_str(&lines.join("; "))
    }
}

impl std::error::Error for LoadError {}

/// A parameter file that breaks its rules is bad data.
impl sysexit::ExitStatus for LoadError {
    fn exit_code(&self) -> u8 {
        sysexit::DATA
    }
}
