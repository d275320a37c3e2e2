//! `tactile._tactile`, the compiled half of the Python package `tactile` (`python/tactile/`
//! wraps it in DataFrames and dicts). Conversions only: reading, writing, simulation,
//! diagnosis and the chip's figures are the libraries' (`recording`, `diagnosis`), the same
//! calls `tactile` makes, so both give the same files, JSON and error messages.
#![cfg_attr(not(test), warn(clippy::too_many_lines))]

mod convert;
mod error;

use std::path::PathBuf;

use baseline::standard_test::{simulate_standard_test, SimulateOptions};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use convert::Columns;
use diagnosis::simulation::Simulations;
use diagnosis::BaselineSource;

/// A recording's columns and metadata, as the package builds its DataFrame from.
type Table<'py> = (Columns<'py>, Bound<'py, PyDict>);

/// `hardware/`, loaded as the command line loads it.
fn hardware() -> PyResult<hardware::Params> {
    hardware::Params::load_default().map_err(|e| error::raise(Some("loading hardware/"), &e))
}

/// The recording at `path`, its columns in the file's order.
#[pyfunction]
fn read_recording(py: Python<'_>, path: PathBuf) -> PyResult<Table<'_>> {
    let (rec, names) = recording::read_with_columns(&path).map_err(|e| error::raise(None, &e))?;
    Ok((
        convert::columns_out(py, &rec, &names)?,
        convert::attrs_out(py, &rec.meta)?,
    ))
}

/// Write the recording of `columns` and `attrs` to `path`, as the command line writes it.
#[pyfunction]
fn write_recording(columns: Columns<'_>, attrs: Bound<'_, PyDict>, path: PathBuf) -> PyResult<()> {
    let (_, bytes) = convert::file_of(&columns, &attrs)?;
    std::fs::write(&path, bytes).map_err(|e| error::file("writing", &path, &e))
}

/// `tactile simulate`'s recording for its options (the keywords are its flags).
#[pyfunction]
#[pyo3(signature = (
    contact_angle, azimuth, peak_load, rate=None, recovery_s=None, modulus_pa=None, then_peak_load=None,
    noise_v=None, noise_load_n=None, seed=None, effect=None, gain=None, smoother_alpha=None,
    ambient_swing=None, excitation_v=None, rod_speed=None
))]
#[allow(clippy::too_many_arguments)] // One keyword per flag of the command.
fn simulate(
    py: Python<'_>,
    contact_angle: f64,
    azimuth: f64,
    peak_load: f64,
    rate: Option<f64>,
    recovery_s: Option<f64>,
    modulus_pa: Option<f64>,
    then_peak_load: Option<Vec<f64>>,
    noise_v: Option<f64>,
    noise_load_n: Option<f64>,
    seed: Option<u64>,
    effect: Option<Vec<String>>,
    gain: Option<[f64; 3]>,
    smoother_alpha: Option<f64>,
    ambient_swing: Option<(f64, f64)>,
    excitation_v: Option<f64>,
    rod_speed: Option<f64>,
) -> PyResult<Table<'_>> {
    let defaults = SimulateOptions::new(contact_angle, azimuth, peak_load);
    let options = SimulateOptions {
        rate_hz: rate,
        rod_speed_mm_per_min: rod_speed,
        recovery_s,
        modulus_pa,
        then_peak_loads_n: then_peak_load.unwrap_or(defaults.then_peak_loads_n.clone()),
        noise_v: noise_v.unwrap_or(defaults.noise_v),
        noise_load_n: noise_load_n.unwrap_or(defaults.noise_load_n),
        seed: seed.unwrap_or(defaults.seed),
        effects: effect.unwrap_or(defaults.effects.clone()),
        gain,
        smoother_alpha,
        ambient_swing,
        excitation_v,
        ..defaults
    };
    let params = hardware()?;
    let rec = py
        .detach(|| simulate_standard_test(&options, &params))
        .map_err(|e| error::raise(None, &e))?;
    let names = convert::writer_order(&rec);
    Ok((
        convert::columns_out(py, &rec, &names)?,
        convert::attrs_out(py, &rec.meta)?,
    ))
}

/// The diagnosis's options from `hardware/`, with `baseline` as its baseline.
fn options(baseline: BaselineSource) -> PyResult<diagnosis::Options> {
    let hw = hardware()?;
    let options = diagnosis::Options::from_hardware(&hw).map_err(|e| error::raise(None, &e))?;
    Ok(diagnosis::Options {
        baseline,
        ..options
    })
}

/// The baseline of `recordings`: ours, or the `simulations` paired with them as
/// `tactile diagnose --simulation` pairs them; `accept_scale` as `--accept-scale`.
fn baseline_of(
    recordings: &[PathBuf],
    simulations: &[PathBuf],
    accept_scale: bool,
) -> PyResult<BaselineSource> {
    if simulations.is_empty() {
        return Ok(BaselineSource::Fe);
    }
    let paired = Simulations::pair(recordings, simulations).map_err(|e| error::raise(None, &e))?;
    Ok(BaselineSource::Simulation(
        paired.accepting_scale(accept_scale),
    ))
}

/// `tactile diagnose`'s JSON (pretty, as the command writes it) for `rec` named `name`.
fn diagnose_json(
    py: Python<'_>,
    rec: &recording::Recording,
    name: &str,
    baseline: BaselineSource,
) -> PyResult<String> {
    let options = options(baseline)?;
    let diagnosed = py
        .detach(|| diagnosis::diagnose(rec, name, &options))
        .map_err(|e| error::raise(Some(name), &e))?;
    serde_json::to_string_pretty(&diagnosed.report)
        .map_err(|e| error::raise(Some("encoding the diagnosis"), &e))
}

/// The diagnosis of the recording at `path`, named as the command names it; against the
/// user's `simulation` where one is given.
#[pyfunction]
#[pyo3(signature = (path, simulation=None, accept_scale=false))]
fn diagnose_file(
    py: Python<'_>,
    path: PathBuf,
    simulation: Option<PathBuf>,
    accept_scale: bool,
) -> PyResult<String> {
    let baseline = baseline_of(
        std::slice::from_ref(&path),
        simulation.as_slice(),
        accept_scale,
    )?;
    let rec = recording::read(&path).map_err(|e| error::raise(None, &e))?;
    diagnose_json(py, &rec, &path.display().to_string(), baseline)
}

/// The diagnosis of the recording of `columns` and `attrs`, named `name` in the report;
/// against the user's `simulation` where one is given.
#[pyfunction]
#[pyo3(signature = (columns, attrs, name, simulation=None, accept_scale=false))]
fn diagnose_frame(
    py: Python<'_>,
    columns: Columns<'_>,
    attrs: Bound<'_, PyDict>,
    name: &str,
    simulation: Option<PathBuf>,
    accept_scale: bool,
) -> PyResult<String> {
    let baseline = baseline_of(&[PathBuf::from(name)], simulation.as_slice(), accept_scale)?;
    let (rec, _) = convert::file_of(&columns, &attrs)?;
    diagnose_json(py, &rec, name, baseline)
}

/// `tactile diagnose --joint`'s JSON (the same text, through `diagnosis::joint::json_text`) for
/// the recordings at `paths`: files, and for a folder every `*.csv` in it, checked and
/// expanded by the library as for the command; against the user's `simulations` where they are
/// given (one for all, one per recording in order, or a folder of them by the recordings' file
/// names).
#[pyfunction]
#[pyo3(signature = (paths, simulations=None, accept_scale=false))]
fn diagnose_session_json(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    simulations: Option<Vec<PathBuf>>,
    accept_scale: bool,
) -> PyResult<String> {
    let simulations = simulations.unwrap_or_default();
    let baseline = if simulations.is_empty() {
        BaselineSource::Fe
    } else {
        let inputs = diagnosis::inputs::expand(&paths).map_err(|e| error::raise(None, &e))?;
        baseline_of(&inputs, &simulations, accept_scale)?
    };
    let options = options(baseline)?;
    let text = py
        .detach(|| {
            diagnosis::joint::diagnose_session(&paths, &options)
                .map(|d| diagnosis::joint::json_text(&d))
        })
        .map_err(|e| error::raise(None, &e))?;
    text.map_err(|e| error::raise(Some("encoding the diagnosis"), &e))
}

/// `tactile chip --json`'s figures.
#[pyfunction]
fn chip_json() -> PyResult<String> {
    let report = chip::report::from_hardware(&hardware()?).map_err(|e| error::raise(None, &e))?;
    serde_json::to_string(&report).map_err(|e| error::raise(None, &e))
}

#[pymodule]
fn _tactile(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(read_recording, m)?)?;
    m.add_function(wrap_pyfunction!(write_recording, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose_file, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose_frame, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose_session_json, m)?)?;
    m.add_function(wrap_pyfunction!(chip_json, m)?)?;
    Ok(())
}
