//! Whether a user's simulation is in the recording's units: the factors the calibration fits
//! (the load scale, each output's scale: checked on the diagnosis, `crate::scale_check`) and the
//! rod's travel (checked here, as the simulation is loaded) must stay within a physically
//! plausible factor of one ([`PLAUSIBLE_FACTOR`]), or the simulation is refused, naming the
//! factor and the unit mix-up it looks like (`docs/simulation-format.md`, "Units").
//!
//! Why 10 either way: the load scale stands for the gel's modulus, an output's scale for its
//! gain and sensitivity. A lab's simulation takes the modulus from a datasheet or a Shore
//! hardness (soft silicones' published moduli spread by a factor of two to five with mix, cure
//! and strain) and its sensitivity from a model of the bridge or a calibration (tens of
//! percent, a factor of two at worst): legitimate calibration stays within 10x with room to
//! spare. A unit read as another is 1000x (mN, kN, µm, mV), about 100x (gf) or 25x (inch):
//! beyond it. A kgf (9.8x) or lbf (4.4x) read as N is not told from a modulus guess by the
//! factor alone, and is not refused. `--accept-scale` takes a factor on purpose.

use std::path::Path;

use super::SimulationError;

/// How far from one a fitted scale or the travel's ratio may be (either way).
pub const PLAUSIBLE_FACTOR: f64 = 10.0;

/// Units of each quantity with their size in the contract's unit, for the message's guess.
pub(crate) const FORCE_UNITS: [(&str, f64); 6] = [
    ("µN", 1e-6),
    ("mN", 1e-3),
    ("gf", 9.80665e-3),
    ("lbf", 4.448_221_6),
    ("kgf", 9.80665),
    ("kN", 1e3),
];
pub(crate) const LENGTH_UNITS: [(&str, f64); 5] = [
    ("nm", 1e-6),
    ("µm", 1e-3),
    ("cm", 10.0),
    ("inch", 25.4),
    ("m", 1e3),
];
pub(crate) const OUTPUT_UNITS: [(&str, f64); 4] =
    [("nV", 1e-9), ("µV", 1e-6), ("mV", 1e-3), ("kV", 1e3)];

/// The unit (of `units`, sizes in `base`) a value `ratio` times too large would be in, where
/// one is within a factor 2 (the calibration's own share of the factor aside): "mN labelled
/// N?".
pub(crate) fn guess(ratio: f64, units: &[(&str, f64)], base: &str) -> String {
    let size = 1.0 / ratio;
    units
        .iter()
        .map(|&(u, s)| (u, (s / size).ln().abs()))
        .filter(|&(_, d)| d < 2.0_f64.ln())
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map_or_else(
            || format!("a unit other than {base}?"),
            |(u, _)| format!("{u} labelled {base}?"),
        )
}

/// Whether `ratio` is beyond the plausible factor, by more than two standard errors of its
/// logarithm (`rel_sd`: the standard error over the value).
pub(crate) fn implausible(ratio: f64, rel_sd: f64) -> bool {
    ratio.is_finite()
        && ratio != 0.0
        && ratio.abs().ln().abs() - PLAUSIBLE_FACTOR.ln() > 2.0 * rel_sd
}

/// The refusal of a factor `ratio` (the simulation's over the recording's) of `what`.
pub(crate) fn refusal(path: &str, what: &str, ratio: f64, hint: String) -> SimulationError {
    SimulationError::Scale {
        path: path.into(),
        what: what.to_string(),
        ratio: ratio.abs(),
        hint,
    }
}

/// Refuse a simulation whose rod travels `simulated_mm` (its largest) where the recording's
/// largest is `recorded_mm`, beyond the plausible factor either way.
pub(crate) fn check_travel(
    path: &Path,
    simulated_mm: f64,
    recorded_mm: f64,
) -> Result<(), SimulationError> {
    let ratio = simulated_mm / recorded_mm;
    if recorded_mm > 0.0 && simulated_mm > 0.0 && implausible(ratio, 0.0) {
        let hint = guess(ratio, &LENGTH_UNITS, "mm");
        return Err(refusal(
            &path.display().to_string(),
            "rod travel (largest `rod_mm`)",
            ratio,
            hint,
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_guesses_name_the_unit_a_factor_looks_like() {
        assert_eq!(guess(1000.0, &FORCE_UNITS, "N"), "mN labelled N?");
        assert_eq!(guess(1.0 / 0.0057, &FORCE_UNITS, "N"), "gf labelled N?");
        assert_eq!(guess(1e-3, &FORCE_UNITS, "N"), "kN labelled N?");
        assert_eq!(guess(1000.0, &LENGTH_UNITS, "mm"), "µm labelled mm?");
        assert_eq!(guess(37.0, &LENGTH_UNITS, "mm"), "a unit other than mm?");
    }

    #[test]
    fn the_bound_is_ten_either_way_and_uncertainty_counts_for_the_simulation() {
        assert!(!implausible(9.9, 0.0) && !implausible(0.101, 0.0) && !implausible(-5.0, 0.0));
        assert!(implausible(10.5, 0.0) && implausible(0.095, 0.0) && implausible(-20.0, 0.0));
        // 20x with a factor-e uncertainty on it (ln 20 - ln 10 = 0.69 < 2): not shown beyond.
        assert!(!implausible(20.0, 1.0));
        assert!(!implausible(f64::NAN, 0.0) && !implausible(0.0, 0.0));
    }

    #[test]
    fn a_travel_a_thousand_times_the_recordings_is_refused_naming_the_unit() {
        let p = Path::new("sim.csv");
        check_travel(p, 6.0, 5.0).unwrap();
        check_travel(p, 40.0, 5.0).unwrap();
        let err = check_travel(p, 5000.0, 5.0).unwrap_err().to_string();
        assert!(
            err.contains("1000x") && err.contains("µm labelled mm?"),
            "{err}"
        );
        let err = check_travel(p, 0.005, 5.0).unwrap_err().to_string();
        assert!(
            err.contains("0.001x") && err.contains("m labelled mm?"),
            "{err}"
        );
    }
}
