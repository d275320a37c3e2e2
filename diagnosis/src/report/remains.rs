//! What the final residual (recording minus the chosen model) still holds, per channel: a
//! trend, a periodic component, a correlation with the load or its rate, and the regime window
//! where most of it sits. The pipeline's localisation describes the *baseline's* residual; a
//! reader of a partial explanation needs the same for what is left.

use crate::localise::{mismatches, Mismatch};
use crate::outcome::PlotData;
use crate::stats::{lag1, pearson};

/// A straight-line trend of a residual against time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trend {
    /// Slope, channel unit per second.
    pub slope: f64,
    /// Slope over its standard error, the error widened for the residual's lag-1 correlation.
    pub t_stat: f64,
    /// Slope times the recording's duration, channel unit.
    pub change: f64,
}

/// The strongest sinusoid in a residual.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    pub freq_hz: f64,
    /// Amplitude, channel unit.
    pub amplitude: f64,
    /// Share of the residual's variance the sinusoid explains.
    pub share: f64,
}

/// One channel's remaining structure. `trend`, `peak` and the correlations are reported by
/// [`Remains::findings`] only where they pass their thresholds.
#[derive(Debug, Clone)]
pub struct Remains {
    /// Index into `crate::data::CHANNELS`.
    pub channel: usize,
    /// RMS of the final residual, channel unit.
    pub rms: f64,
    /// RMS over the recorded peak-to-peak, the measure the verdict's RMSE uses.
    pub relative: f64,
    pub trend: Trend,
    pub peak: Option<Peak>,
    pub corr_load: f64,
    pub corr_rate: f64,
    /// The regime window holding the largest share of this channel's final residual.
    pub worst: Option<Mismatch>,
}

/// A trend is reported when its t statistic exceeds this and it moves the residual by at
/// least its RMS over the recording.
const TREND_T: f64 = 4.0;
/// A sinusoid is reported when it explains this share of the (detrended) residual's variance.
const PEAK_SHARE: f64 = 0.3;
/// A correlation is reported above this magnitude.
const CORR: f64 = 0.5;

/// Least-squares line through `(t, r)` with an AR(1)-aware standard error of its slope.
pub fn trend(t: &[f64], r: &[f64]) -> Trend {
    let n = t.len().min(r.len());
    let none = Trend {
        slope: 0.0,
        t_stat: 0.0,
        change: 0.0,
    };
    if n < 4 {
        return none;
    }
    let (tm, rm) = (mean(&t[..n]), mean(&r[..n]));
    let stt: f64 = t[..n].iter().map(|v| (v - tm).powi(2)).sum();
    if stt <= 0.0 {
        return none;
    }
    let slope = (0..n).map(|i| (t[i] - tm) * (r[i] - rm)).sum::<f64>() / stt;
    let e: Vec<f64> = (0..n).map(|i| r[i] - rm - slope * (t[i] - tm)).collect();
    let s2 = e.iter().map(|v| v * v).sum::<f64>() / (n - 2) as f64;
    // Correlated residuals carry fewer independent samples than they have points.
    let rho = lag1(&e).clamp(0.0, 0.99);
    let inflation = (1.0 + rho) / (1.0 - rho);
    let se = (s2 * inflation / stt).sqrt();
    Trend {
        slope,
        t_stat: if se > 0.0 { slope / se } else { 0.0 },
        change: slope * (t[n - 1] - t[0]),
    }
}

/// The sinusoid (with offset) that explains most of `r`'s variance, searched on a log grid
/// from two periods per recording up to `f_max`; works on unevenly spaced `t` (least squares
/// per frequency, as Lomb–Scargle).
pub fn spectral_peak(t: &[f64], r: &[f64], f_max: f64) -> Option<Peak> {
    let n = t.len().min(r.len());
    let duration = t.get(n.wrapping_sub(1))? - t.first()?;
    if n < 8 || duration.is_nan() || duration <= 0.0 {
        return None;
    }
    let f_min = 2.0 / duration;
    if f_max <= f_min {
        return None;
    }
    let rm = mean(&r[..n]);
    let sst: f64 = r[..n].iter().map(|v| (v - rm).powi(2)).sum();
    if sst <= 0.0 {
        return None;
    }
    const GRID: usize = 400;
    let ratio = (f_max / f_min).powf(1.0 / (GRID - 1) as f64);
    (0..GRID)
        .map(|k| f_min * ratio.powi(k as i32))
        .filter_map(|f| sinusoid_fit(&t[..n], &r[..n], f).map(|(amp, ssr)| (f, amp, ssr)))
        .map(|(freq_hz, amplitude, ssr)| Peak {
            freq_hz,
            amplitude,
            share: 1.0 - ssr / sst,
        })
        .max_by(|a, b| a.share.total_cmp(&b.share))
}

/// Fit `c + a cos(wt) + b sin(wt)`: (amplitude, residual sum of squares).
fn sinusoid_fit(t: &[f64], r: &[f64], f: f64) -> Option<(f64, f64)> {
    let w = 2.0 * std::f64::consts::PI * f;
    let basis = |ti: f64| [1.0, (w * ti).cos(), (w * ti).sin()];
    let mut ata = nalgebra::Matrix3::<f64>::zeros();
    let mut atb = nalgebra::Vector3::<f64>::zeros();
    for (&ti, &ri) in t.iter().zip(r) {
        let x = nalgebra::Vector3::from(basis(ti));
        ata += x * x.transpose();
        atb += x * ri;
    }
    let c = ata.try_inverse()? * atb;
    let ssr = t
        .iter()
        .zip(r)
        .map(|(&ti, &ri)| {
            let b = basis(ti);
            (ri - c[0] * b[0] - c[1] * b[1] - c[2] * b[2]).powi(2)
        })
        .sum();
    Some((c[1].hypot(c[2]), ssr))
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

/// Rate of change by central differences on uneven `t`.
fn rate(t: &[f64], v: &[f64]) -> Vec<f64> {
    let n = t.len().min(v.len());
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            if t[b] > t[a] {
                (v[b] - v[a]) / (t[b] - t[a])
            } else {
                0.0
            }
        })
        .collect()
}

/// The final residual's structure on every compared channel, largest relative RMS first.
pub fn analyse(p: &PlotData) -> Vec<Remains> {
    let residual: [Vec<f64>; 4] = std::array::from_fn(|c| {
        let model = &p.improved[c];
        p.recorded[c]
            .iter()
            .zip(model)
            .map(|(a, b)| a - b)
            .collect()
    });
    let range: [f64; 4] = std::array::from_fn(|c| {
        let (lo, hi) = p.recorded[c]
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        (hi - lo).max(1e-300)
    });
    let windows = mismatches(&p.t_s, &p.segments, &residual, &range, &p.used, 0.0);
    let load_rate = rate(&p.t_s, &p.recorded[0]);
    // Block means are 200 ms apart at most: look for lines up to 1 Hz.
    let f_max = 1.0;
    let mut out: Vec<Remains> = (0..4)
        .filter(|&c| p.used[c] && !residual[c].is_empty())
        .map(|c| {
            let r = &residual[c];
            let tr = trend(&p.t_s, r);
            let detrended: Vec<f64> = p.t_s.iter().zip(r).map(|(t, v)| v - tr.slope * t).collect();
            let rms = (r.iter().map(|v| v * v).sum::<f64>() / r.len() as f64).sqrt();
            Remains {
                channel: c,
                rms,
                relative: rms / range[c],
                trend: tr,
                peak: spectral_peak(&p.t_s, &detrended, f_max),
                corr_load: if c == 0 {
                    0.0
                } else {
                    pearson(r, &p.recorded[0])
                },
                corr_rate: pearson(r, &load_rate),
                worst: windows
                    .iter()
                    .find(|m| m.channel == crate::data::CHANNELS[c])
                    .cloned(),
            }
        })
        .collect();
    out.sort_by(|a, b| b.relative.total_cmp(&a.relative));
    out
}

/// What stands out in one channel's residual.
#[derive(Debug, Clone, PartialEq)]
pub enum Finding {
    Drift(Trend),
    Periodic(Peak),
    FollowsLoad(f64),
    FollowsRate(f64),
}

impl Remains {
    /// The structures that pass their thresholds, strongest kind first.
    pub fn findings(&self) -> Vec<Finding> {
        let mut f = Vec::new();
        let t = self.trend;
        if t.t_stat.abs() > TREND_T && t.change.abs() >= self.rms {
            f.push(Finding::Drift(t));
        }
        if let Some(p) = self.peak.filter(|p| p.share > PEAK_SHARE) {
            f.push(Finding::Periodic(p));
        }
        if self.corr_load.abs() > CORR {
            f.push(Finding::FollowsLoad(self.corr_load));
        }
        if self.corr_rate.abs() > CORR {
            f.push(Finding::FollowsRate(self.corr_rate));
        }
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noise(n: usize) -> Vec<f64> {
        // A fixed, roughly white sequence (no rand dependency in the library).
        (0..n)
            .map(|i| ((i as f64 * 12.9898).sin() * 43_758.545).fract() - 0.5)
            .collect()
    }

    #[test]
    fn a_drift_stands_out_and_noise_does_not() {
        let t: Vec<f64> = (0..900).map(|i| 0.2 * i as f64).collect();
        let e = noise(900);
        let drifting: Vec<f64> = t.iter().zip(&e).map(|(t, e)| 0.01 * t + e).collect();
        let d = trend(&t, &drifting);
        assert!((d.slope - 0.01).abs() < 0.002, "{d:?}");
        assert!(d.t_stat > TREND_T && (d.change - 1.8).abs() < 0.4, "{d:?}");
        let flat = trend(&t, &e);
        assert!(flat.t_stat.abs() < TREND_T, "{flat:?}");
    }

    #[test]
    fn a_slow_line_is_found_on_uneven_samples() {
        // 20 ms blocks for the first 10 s, 200 ms after, as the decimation does.
        let t: Vec<f64> = (0..500)
            .map(|i| 0.02 * i as f64)
            .chain((1..900).map(|i| 10.0 + 0.2 * i as f64))
            .collect();
        let e = noise(t.len());
        let r: Vec<f64> = t
            .iter()
            .zip(&e)
            .map(|(t, e)| 2.0 * (2.0 * std::f64::consts::PI * t / 40.0).sin() + 0.3 * e)
            .collect();
        let p = spectral_peak(&t, &r, 1.0).unwrap();
        assert!((p.freq_hz - 0.025).abs() < 0.001, "{p:?}");
        assert!((p.amplitude - 2.0).abs() < 0.1 && p.share > 0.9, "{p:?}");
        let quiet = spectral_peak(&t, &e, 1.0).unwrap();
        assert!(quiet.share < PEAK_SHARE, "{quiet:?}");
    }
}
