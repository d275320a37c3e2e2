//! A diagnosis against a user's simulation refused where a fitted scale is beyond a physically
//! plausible factor ([`crate::simulation::plausible`], which says why 10x either way): the
//! simulation's load or outputs are then in another unit, more likely than another physics.
//! A step of its own, run on the finished diagnosis (the scales are the calibration's).

use crate::output::{ParamDetail, Report};
use crate::simulation::plausible::{guess, implausible, refusal, FORCE_UNITS, OUTPUT_UNITS};
use crate::simulation::SimulationError;

/// [`check_scales`] where `judged` (the baseline is a user's simulation and the scale is not
/// accepted on purpose); the recording's outputs are in its `sensor_unit` (volts by default).
pub(crate) fn check(
    report: &Report,
    meta: &recording::Meta,
    judged: bool,
) -> Result<(), SimulationError> {
    if !judged {
        return Ok(());
    }
    check_scales(report, meta.get(recording::SENSOR_UNIT_KEY).unwrap_or("V"))
}

/// Refuse the diagnosis `report` against a user's simulation where a fitted scale is beyond
/// the plausible factor: the load scale, and each compared output's scale where the
/// simulation's outputs are in the recording's unit (`sensor_unit`, volts by default; another
/// unit's scale is a conversion, any size). A scale the fit could not resolve is not judged.
fn check_scales(report: &Report, sensor_unit: &str) -> Result<(), SimulationError> {
    let Some(sim) = &report.baseline.simulation else {
        return Ok(());
    };
    let sim_unit = sim
        .metadata
        .iter()
        .find(|(k, _)| k == "sensor_unit")
        .map_or("V", |(_, v)| v.as_str());
    let detail = |name: &str| report.baseline.parameters.iter().find(|p| p.name == name);
    let rel_sd = |p: &ParamDetail| p.stderr.map(|s| (s / p.value).abs());
    let compared = |c: &str| sim.channels.iter().any(|x| x == c);
    if let Some(p) = detail("load_scale").filter(|_| compared("load_N")) {
        // The model's load is the simulation's times the scale: the simulation's is 1/scale
        // times the recording's.
        let ratio = 1.0 / p.value;
        if implausible(ratio, rel_sd(p).unwrap_or(0.0)) {
            let hint = guess(ratio, &FORCE_UNITS, "N");
            return Err(refusal(&sim.file, "load", ratio, hint));
        }
    }
    if !sim_unit.eq_ignore_ascii_case(sensor_unit) {
        return Ok(());
    }
    for (channel, scale) in [
        ("fz_V", "scale_fz"),
        ("mx_V", "scale_mx"),
        ("my_V", "scale_my"),
    ] {
        let Some(p) = detail(scale).filter(|_| compared(channel)) else {
            continue;
        };
        let Some(sd) = rel_sd(p) else { continue };
        let ratio = 1.0 / p.value;
        if implausible(ratio, sd) {
            let hint = format!(
                "{} or outputs before the amplifier (the gains in its metadata)?",
                guess(ratio, &OUTPUT_UNITS, sim_unit).trim_end_matches('?')
            );
            return Err(refusal(&sim.file, channel, ratio, hint));
        }
    }
    Ok(())
}
