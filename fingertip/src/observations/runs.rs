//! The FE runs behind the scorecard: compressions to the peak load at several inclinations,
//! and one whole standard test (press, hold, fast return, recovery) as a time series.

use crate::{Config, CurvePoint, Error, Fingertip};

/// The standard test of the paper's rig (`hardware/fingertip.toml`, `[test]`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FeSchedule {
    /// The machine stops when its load cell reads this, N.
    pub peak_load_n: f64,
    /// Hold at the peak before "Return", s.
    pub hold_s: f64,
    /// Speed of the return, mm/s.
    pub return_speed_mm_per_s: f64,
    /// Recording after the rod is back, s.
    pub recovery_s: f64,
}

/// Return steps: the return lasts under a second; the outputs follow the rod through it.
const RETURN_STEPS: usize = 6;
/// Recovery samples, spaced geometrically from RECOVERY_FIRST_S: the tail is seconds slow.
const RECOVERY_STEPS: usize = 24;
const RECOVERY_FIRST_S: f64 = 0.05;
/// Hold steps.
const HOLD_STEPS: usize = 2;

/// A whole test as a time series of outputs, with the time the rod is back at its start.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TestSeries {
    pub points: Vec<CurvePoint>,
    /// Number of leading points that belong to the loading.
    pub loading_len: usize,
    /// Time at which the rod is back at its start, s.
    pub t_back_s: f64,
}

/// Compress `config` at each inclination of `thetas_deg` to the peak; the points at the peak.
pub fn inclination_sweep(
    config: &Config,
    thetas_deg: &[f64],
    peak_load_n: f64,
) -> Result<Vec<(f64, CurvePoint)>, Error> {
    thetas_deg
        .iter()
        .map(|&theta_deg| {
            let c = Config {
                contact_angle_deg: theta_deg,
                ..config.clone()
            };
            let curve = crate::compress(&c, peak_load_n)?;
            let peak = *curve.points.last().unwrap_or(&CurvePoint::default());
            Ok((theta_deg, peak))
        })
        .collect()
}

/// Run the standard test on `config`: press to the peak at the configured rod speed, hold,
/// return at the return speed, record the recovery.
pub fn standard_test(config: &Config, test: &FeSchedule) -> Result<TestSeries, Error> {
    let mut ft = Fingertip::new(config.clone())?;
    let loading = ft.compress_to_peak(test.peak_load_n)?;
    let mut points = loading.points;
    let loading_len = points.len();
    let last = *points.last().unwrap_or(&CurvePoint::default());
    let (t_peak, d_peak) = (last.t_s, last.rod_mm);
    let mut history = Vec::new();
    for k in 1..=HOLD_STEPS {
        history.push((t_peak + test.hold_s * k as f64 / HOLD_STEPS as f64, d_peak));
    }
    let t_return = t_peak + test.hold_s;
    let return_s = d_peak / test.return_speed_mm_per_s;
    for k in 1..=RETURN_STEPS {
        let f = k as f64 / RETURN_STEPS as f64;
        history.push((t_return + f * return_s, d_peak * (1.0 - f)));
    }
    let t_back_s = t_return + return_s;
    let ratio = (test.recovery_s / RECOVERY_FIRST_S).powf(1.0 / (RECOVERY_STEPS - 1) as f64);
    for k in 0..RECOVERY_STEPS {
        history.push((t_back_s + RECOVERY_FIRST_S * ratio.powi(k as i32), 0.0));
    }
    points.extend(ft.follow(&history)?);
    Ok(TestSeries {
        points,
        loading_len,
        t_back_s,
    })
}
