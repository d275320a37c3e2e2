//! How parameters are coded for the fits ([`ParamSpec`]), and each catalogue effect's coding: bounds (each with the physical
//! reason beside it), finite-difference steps, starting values, units, and the neutral values at
//! which the effect is the identity (where every candidate starts, so that adding an effect can
//! never fit worse than the model without it).
//!
//! The bounds are plausibility ranges of the physics, not properties of one sensor, so they live
//! here beside the operators' coding rather than in `hardware/`. They are wide on purpose: a
//! bound that a real material reaches turns a finding into an artefact of the bound.

use sim::effects::EffectKind;

/// One parameter's coding: bounds, finite-difference step and starting values (internal units).
#[derive(Debug, Clone)]
pub struct ParamSpec {
    /// The catalogue's name of the parameter, for debugging output.
    #[allow(dead_code)]
    pub name: &'static str,
    pub lower: f64,
    pub upper: f64,
    pub step: f64,
    pub starts: Vec<f64>,
    /// Internal value is ln of the physical one.
    pub log: bool,
}

/// A parameter's coding; the baseline's are made in [`crate::fit`], the effects' here.
pub(crate) fn spec(
    name: &'static str,
    lower: f64,
    upper: f64,
    step: f64,
    starts: &[f64],
    log: bool,
) -> ParamSpec {
    ParamSpec {
        name,
        lower,
        upper,
        step,
        starts: starts.to_vec(),
        log,
    }
}

/// Longest relaxation time a fit may report: real elastomers relax over 1e2 to 1e5 s.
pub const MAX_RELAXATION_TAU_S: f64 = 1e5;
/// Shortest time constant a fit may report: below 50 ms (a few fine blocks of 20 ms) a decay is
/// over within the fitting series' resolution and acts as a gain, which calibration absorbs.
pub const MIN_TAU_S: f64 = 0.05;
/// AC coupling slower than 1e7 s (four months) is DC coupling over any recording this tool
/// reads (under 0.01 % sag per 1000 s); that end of the range is the effect's identity.
pub const MAX_COUPLING_TAU_S: f64 = 1e7;

/// Coding of each effect's parameters, in catalogue order. `chip_peak_v` is the largest
/// recorded output magnitude (the saturation start and upper bound), in the unit the outputs
/// hold (`sensor_unit`): every amplitude's bounds, step and start are in proportion to it, so
/// that an output multiplied by a constant changes only the values in its unit.
pub fn effect_specs(kind: EffectKind, chip_peak_v: f64) -> Vec<ParamSpec> {
    use EffectKind::*;
    let ln = f64::ln;
    // The outputs' own scale; 1 where none is recorded (no output effect is then offered).
    let u = if chip_peak_v > 0.0 && chip_peak_v.is_finite() {
        chip_peak_v
    } else {
        1.0
    };
    match kind {
        ViscoelasticRelaxation => vec![
            spec(
                "tau_s",
                ln(MIN_TAU_S),
                ln(MAX_RELAXATION_TAU_S),
                1e-4,
                &[ln(1.0), ln(5.0), ln(30.0)],
                true,
            ),
            // A solid keeps part of its instantaneous stiffness at equilibrium; fraction 1 is a
            // fluid (the load would relax to nothing under a held rod).
            spec("fraction", 0.0, 0.99, 1e-4, &[0.2], false),
        ],
        // width >= 1 would turn the unloading output's sign round: y = x (1 + w z), z = -1.
        Hysteresis => vec![spec("width", 0.0, 0.9, 1e-4, &[0.03], false)],
        HighpassCoupling => vec![spec(
            "tau_s",
            // Faster coupling would remove the signal the test is made of within a block.
            ln(MIN_TAU_S),
            ln(MAX_COUPLING_TAU_S),
            1e-4,
            &[ln(10.0), ln(100.0)],
            true,
        )],
        ThermalDrift => vec![
            // A shift beyond ten times the largest output is a rail, not a drift.
            spec(
                "amplitude_V",
                -10.0 * u,
                10.0 * u,
                1e-5 * u,
                &[1e-3 * u],
                false,
            ),
            // Warm-up of a package takes from a second (bare die) to a day (a rig in a room).
            spec("tau_s", ln(1.0), ln(1e5), 1e-4, &[ln(10.0), ln(60.0)], true),
        ],
        // Exponents beyond 1/3..3 are no longer a curvature of one load path but a different
        // contact law (the Hertzian 3/2 power sits inside with a factor two either way).
        Stiffening => vec![spec("exponent", 0.3, 3.0, 1e-4, &[1.2], false)],
        // Beyond 60 deg the moment channels have swapped roles: a wiring error, not a tilt.
        Crosstalk => vec![spec("angle_deg", -60.0, 60.0, 1e-3, &[5.0, -5.0], false)],
        AmplifierSaturation => vec![spec(
            "limit_V",
            1e-3 * u,
            // A rail above twice the largest recorded output clips nothing: the identity.
            2.0 * u,
            1e-4 * u,
            &[chip_peak_v],
            false,
        )],
        // A stream offset beyond 2 s is a wrong start time, not a lag: the standard test's
        // fastest feature (the 600 mm/min return) is over in under 2 s.
        TimeOffset => vec![spec("lag_s", -2.0, 2.0, 1e-4, &[0.05, -0.05], false)],
        MainsInterference => vec![
            spec("freq_hz", 40.0, 70.0, 1e-4, &[50.0], false),
            spec("amplitude_V", 0.0, 5.0 * u, 1e-5 * u, &[0.0], false),
        ],
        // |q| >= 1 makes the output non-monotonic in the load within full scale.
        BridgeNonlinearity => vec![spec("quadratic", -0.9, 0.9, 1e-4, &[0.05, -0.05], false)],
        // The friction band is capped at 0.9 of the demand (`contact_friction::MAX_BAND`); mu = 2
        // reaches that cap at every contact angle above 24 deg.
        ContactFriction => vec![spec("mu", 0.0, 2.0, 1e-4, &[0.1], false)],
    }
}

/// Where a relaxation's second Prony term starts (internal units: ln tau, then a strength of
/// zero, so still the model it extends): a decade either side of the first term's `ln_tau`.
pub fn second_prony_seeds(ln_tau: f64) -> Vec<Vec<f64>> {
    [10f64.ln(), -(10f64.ln())]
        .iter()
        .map(|d| vec![ln_tau + d, 0.0])
        .collect()
}

/// The starts of an effect added to a fitted model (internal units, one list of its parameters
/// per start), the neutral one first: the values at which the effect is the identity, so the
/// fit starts exactly at the model it extends. `seeds` are where the same effect ended in other fits (alone, or
/// a first Prony term's neighbours): a time constant starts there, at zero strength, which is
/// still neutral; without seeds the catalogue starts are added.
pub fn starts(kind: EffectKind, specs: &[ParamSpec], seeds: &[Vec<f64>]) -> Vec<Vec<f64>> {
    use EffectKind::*;
    let defaults = || -> Vec<Vec<f64>> {
        specs.iter().fold(vec![Vec::new()], |acc, s| {
            acc.into_iter()
                .flat_map(|p| s.starts.iter().map(move |&v| [p.clone(), vec![v]].concat()))
                .collect()
        })
    };
    match kind {
        // Zero strength is the identity at any time constant: the seeds' time constants (or
        // the middle catalogue start, then the catalogue starts too).
        ViscoelasticRelaxation | ThermalDrift => {
            let tau_at = usize::from(kind == ThermalDrift);
            let zero = |tau: f64| {
                let mut p = vec![0.0; 2];
                p[tau_at] = tau;
                p
            };
            if seeds.is_empty() {
                let s = &specs[tau_at].starts;
                [vec![zero(s[s.len() / 2])], defaults()].concat()
            } else {
                seeds.iter().map(|s| zero(s[tau_at])).collect()
            }
        }
        // Identity at the upper end (DC coupling, a rail above the signal), flat there: the
        // seeds or the catalogue starts as well.
        HighpassCoupling | AmplifierSaturation => {
            let others = if seeds.is_empty() {
                defaults()
            } else {
                seeds.to_vec()
            };
            [vec![vec![specs[0].upper]], others].concat()
        }
        // One parameter, a cost smooth through the identity: the neutral start suffices.
        Hysteresis | TimeOffset | BridgeNonlinearity | ContactFriction | Crosstalk => {
            vec![vec![0.0]]
        }
        Stiffening => vec![vec![1.0]],
        MainsInterference => vec![vec![specs[0].starts[0], 0.0]],
    }
}

/// Unit of an effect parameter, from its catalogue name.
pub fn unit(name: &str) -> &'static str {
    match name {
        n if n.ends_with("_s") => "s",
        n if n.ends_with("_V") => "V",
        n if n.ends_with("_hz") => "Hz",
        n if n.ends_with("_deg") => "deg",
        n if n.ends_with("_Pa") => "Pa",
        n if n.ends_with("_N") => "N",
        _ => "1",
    }
}
