//! Synthetic recordings: the baseline model of the compression test, optionally with catalogue
//! effects and noise, written as a recording (`docs/recording-format.md`). `tactile simulate` and the proof
//! generator (`tactile prove`) both use this.

use sim::compression::{rod_at_load, RodHistory, RodSchedule};
use sim::effects::{Effect, EffectSet, ThermalDrift, ThermalReference};

use crate::model::{evaluate, BaselineParams, Drive, Readout};
use crate::response::FingertipResponse;
use recording::{Channels, Meta, Recording};

/// Standard deviations of white measurement noise.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Noise {
    pub load_n: f64,
    /// [fz, mx, my]
    pub volts: [f64; 3],
    pub temp_c: f64,
}

/// Everything one synthetic recording needs.
pub struct SimSpec<'a> {
    pub fingertip: &'a dyn FingertipResponse,
    pub readout: Readout,
    /// The truth's baseline: modulus, and the deviations from the nominal model (exponent,
    /// sensitivities, azimuth, offsets) that a real sensor has and the diagnosis must calibrate.
    pub baseline: BaselineParams,
    pub contact_angle_deg: f64,
    pub azimuth_deg: f64,
    pub radius_mm: f64,
    pub test: RodSchedule,
    /// One compression cycle per peak load.
    pub peak_loads_n: Vec<f64>,
    pub effects: Vec<Effect>,
    pub noise: Noise,
    pub seed: u64,
    /// Temperature at power-up and its rise during warm-up (with `thermal_drift`).
    pub ambient_c: f64,
    pub warm_up_rise_c: f64,
    /// A slow sinusoidal swing of the ambient (amplitude, period), on top of any warm-up; a
    /// `thermal_drift` follows the temperature, so with a swing it is no exponential.
    pub ambient_swing: Option<(f64, f64)>,
    pub source: String,
}

/// Largest rod travel searched for the peak load.
const MAX_ROD_MM: f64 = 60.0;

/// Run the baseline (plus effects and noise) through the standard test, each cycle turning
/// where the truth's baseline alone reaches its peak load.
pub fn simulate(spec: &SimSpec) -> Recording {
    simulate_path(spec, rod_history(spec))
}

/// Run the baseline (plus effects and noise) through the standard test, each cycle turning
/// where the recorded load reaches its peak, as a test machine that stops at a load does:
/// [`rod_history_to_peaks`].
pub fn simulate_to_peaks(spec: &SimSpec) -> Recording {
    simulate_path(spec, rod_history_to_peaks(spec))
}

/// The same along any rod path (a protocol other than the standard test's cycles; `spec.test`
/// then gives only the sample rate and the speed written into the metadata).
pub fn simulate_path(spec: &SimSpec, history: RodHistory) -> Recording {
    let (drive, chain, true_temp_c) = drive_and_chain(spec, &history);
    let mut rng = Gaussian::new(spec.seed);
    let noise = spec.noise;
    let mut add_noise = |v: &mut [Vec<f64>; 3]| {
        for (b, ch) in v.iter_mut().enumerate() {
            ch.iter_mut()
                .for_each(|x| *x += noise.volts[b] * rng.normal());
        }
    };
    let out = evaluate(
        &drive,
        &spec.readout,
        &spec.baseline,
        &chain,
        spec.contact_angle_deg,
        Some(&mut add_noise),
    );
    let load_n = out
        .load_n
        .iter()
        .map(|f| f + noise.load_n * rng.normal())
        .collect();
    let temp_c = true_temp_c
        .iter()
        .map(|t| t + noise.temp_c * rng.normal())
        .collect();
    let [fz_v, mx_v, my_v] = out.volts;
    Recording {
        meta: meta(spec),
        channels: Channels {
            t_s: history.t_s,
            rod_mm: history.rod_mm,
            load_n,
            fz_v,
            mx_v,
            my_v,
        },
        temp_c: Some(temp_c),
        extra: Vec::new(),
    }
}

/// The drive along `history` with the true temperature, and the effects switched on: the
/// truth's chain, shared by the recording and the search for its turns.
fn drive_and_chain(spec: &SimSpec, history: &RodHistory) -> (Drive, EffectSet, Vec<f64>) {
    let warm_up = spec.effects.iter().find_map(|e| match e {
        Effect::ThermalDrift(d) => Some(*d),
        _ => None,
    });
    // The true temperature; the offset drift follows it (for a pure warm-up this is exactly
    // the exponential law, `ThermalDrift::apply_regressed`).
    let rise_c = warm_up.map_or(0.0, |_| spec.warm_up_rise_c);
    let true_temp_c = true_temperature_c(spec, &history.t_s, warm_up, rise_c);
    let drive = Drive::new(spec.fingertip, history.t_s.clone(), &history.rod_mm)
        .with_temperature(Some(true_temp_c.clone()));
    let mut chain = EffectSet::new(spec.effects.clone());
    if rise_c != 0.0 {
        chain.thermal_reference = Some(ThermalReference {
            t0_c: spec.ambient_c,
            rise_c,
        });
    }
    (drive, chain, true_temp_c)
}

/// Largest error of a recorded peak load that [`rod_history_to_peaks`] accepts, relative to
/// the peak: far below any load cell's noise.
const PEAK_REL_TOL: f64 = 1e-6;
/// Most secant steps of [`rod_history_to_peaks`]; it needs a handful.
const PEAK_STEPS: usize = 30;

/// The rod's travel when each cycle stops where the *recorded* load reaches its peak: the
/// load the recording shows, the gel's effects on it included (a relaxation loads less than
/// the elastic law at a travel), without noise. Starting from the elastic turns, each cycle's
/// turn is found by a secant iteration on its recorded peak (one simulation of the whole
/// history a step, every cycle at once: an earlier cycle's memory moves a later one's peak a
/// little). Without an effect on the load the elastic turns are exact.
pub fn rod_history_to_peaks(spec: &SimSpec) -> RodHistory {
    let mut x: Vec<f64> = spec.peak_loads_n.iter().map(|&l| rod_at(spec, l)).collect();
    let moves_load = spec
        .effects
        .iter()
        .any(|e| e.kind().channels().contains(&"load_N"));
    if !moves_load || x.is_empty() {
        return spec.test.rod_history(&x);
    }
    let miss = |x: &[f64]| -> Vec<f64> {
        let peaks = recorded_peaks_n(spec, x);
        peaks
            .iter()
            .zip(&spec.peak_loads_n)
            .map(|(p, l)| p - l)
            .collect()
    };
    let mut f = miss(&x);
    // The second point: the elastic turn at the peak raised by the ratio it fell short.
    let mut prev: Vec<(f64, f64)> = x.iter().copied().zip(f.iter().copied()).collect();
    for (k, xk) in x.iter_mut().enumerate() {
        let (peak, got) = (spec.peak_loads_n[k], spec.peak_loads_n[k] + f[k]);
        if got > 0.0 {
            *xk = rod_at(spec, peak * peak / got);
        }
    }
    for _ in 0..PEAK_STEPS {
        f = miss(&x);
        let done = f
            .iter()
            .zip(&spec.peak_loads_n)
            .all(|(e, l)| e.abs() <= PEAK_REL_TOL * l);
        if done {
            break;
        }
        for k in 0..x.len() {
            let (x0, f0) = prev[k];
            prev[k] = (x[k], f[k]);
            if f[k] != f0 {
                x[k] = (x[k] - f[k] * (x[k] - x0) / (f[k] - f0)).clamp(0.0, MAX_ROD_MM);
            }
        }
    }
    spec.test.rod_history(&x)
}

/// The largest recorded load of each cycle (its loading and hold) when the cycles turn at
/// `turns_mm`, without noise.
fn recorded_peaks_n(spec: &SimSpec, turns_mm: &[f64]) -> Vec<f64> {
    let history = spec.test.rod_history(turns_mm);
    let (drive, chain, _) = drive_and_chain(spec, &history);
    let out = evaluate(
        &drive,
        &spec.readout,
        &spec.baseline,
        &chain,
        spec.contact_angle_deg,
        None,
    );
    spec.test
        .loading_and_hold_s(turns_mm)
        .iter()
        .map(|&(start_s, end_s)| {
            history
                .t_s
                .iter()
                .zip(&out.load_n)
                .filter(|(t, _)| (start_s..=end_s).contains(*t))
                .map(|(_, l)| *l)
                .fold(f64::NEG_INFINITY, f64::max)
        })
        .collect()
}

/// The rod's travel: the standard test turning at each peak load of the truth's baseline.
fn rod_history(spec: &SimSpec) -> RodHistory {
    let turns: Vec<f64> = spec.peak_loads_n.iter().map(|&l| rod_at(spec, l)).collect();
    spec.test.rod_history(&turns)
}

/// The rod travel at which the truth's baseline reaches `load_n`.
pub fn rod_at(spec: &SimSpec, load_n: f64) -> f64 {
    let force_at =
        |d: f64| spec.fingertip.unit_response(d).force_n * spec.baseline.youngs_modulus_pa;
    rod_at_load(force_at, load_n, MAX_ROD_MM)
}

/// The temperature next to the chip at each time: the ambient, the warm-up `rise_c` when there
/// is a thermal drift, and the ambient's swing.
fn true_temperature_c(
    spec: &SimSpec,
    t_s: &[f64],
    warm_up: Option<ThermalDrift>,
    rise_c: f64,
) -> Vec<f64> {
    t_s.iter()
        .map(|&t| {
            let swing = spec.ambient_swing.map_or(0.0, |(a, period_s)| {
                a * (std::f64::consts::TAU * t / period_s).sin()
            });
            spec.ambient_c + warm_up.map_or(0.0, |d| rise_c * d.warm_up(t)) + swing
        })
        .collect()
}

/// The recording's metadata: the test's rate and speed, the jig's angles, the front end's
/// gains and excitation.
fn meta(spec: &SimSpec) -> Meta {
    let signal = &spec.readout.signal;
    Meta {
        sample_rate_hz: spec.test.sample_rate_hz,
        contact_angle_deg: spec.contact_angle_deg,
        azimuth_deg: spec.azimuth_deg,
        fingertip_radius_mm: spec.radius_mm,
        gain_fz: signal.gain[0],
        gain_mx: signal.gain[1],
        gain_my: signal.gain[2],
        excitation_v: signal.excitation_v,
        rod_speed_mm_per_min: Some(spec.test.speed_mm_per_min),
        source: Some(spec.source.clone()),
        other: Vec::new(),
    }
}

/// Standard normal deviates: SplitMix64 (Steele et al. 2014) with the Box–Muller transform, so
/// a seed gives the same recording on every platform without a dependency.
pub struct Gaussian {
    state: u64,
    spare: Option<f64>,
}

impl Gaussian {
    pub fn new(seed: u64) -> Self {
        Self {
            state: seed,
            spare: None,
        }
    }

    /// Uniform in (0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// A standard normal deviate.
    pub fn normal(&mut self) -> f64 {
        if let Some(s) = self.spare.take() {
            return s;
        }
        let (u, v) = (self.uniform(), self.uniform());
        let r = (-2.0 * u.ln()).sqrt();
        let (s, c) = (std::f64::consts::TAU * v).sin_cos();
        self.spare = Some(r * s);
        r * c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaussian_has_unit_variance() {
        let mut g = Gaussian::new(7);
        let x: Vec<f64> = (0..100_000).map(|_| g.normal()).collect();
        let mean = x.iter().sum::<f64>() / x.len() as f64;
        let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / x.len() as f64;
        assert!(
            mean.abs() < 0.01 && (var - 1.0).abs() < 0.02,
            "{mean} {var}"
        );
    }
}
