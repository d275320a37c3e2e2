//! Mains pickup, at full rate: a scan of the residual's amplitude spectrum for a narrow line
//! between 45 and 65 Hz, then a least-squares fit of the fundamental and third harmonic
//! (amplitude and phase per channel, one frequency) as `sim::effects::MainsInterference` makes.

use std::f64::consts::TAU;

use nalgebra::{DMatrix, DVector};

/// Line search band.
pub const BAND_HZ: (f64, f64) = (45.0, 65.0);
/// Scan resolution.
const SCAN_STEP_HZ: f64 = 0.05;
/// Samples used for the scan and for the refinement (the amplitude fit uses all).
const SCAN_SAMPLES: usize = 10_000;
const REFINE_SAMPLES: usize = 60_000;

/// Prominence (peak over the median of the band's spectrum) for a peak to count as a line.
pub const MIN_LINE_PROMINENCE: f64 = 30.0;

/// A fitted line: frequency and, per channel, the sine/cosine weights of the fundamental and
/// third harmonic.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    pub freq_hz: f64,
    /// Per channel [a1, b1, a3, b3]: a sin + b cos at f and at 3f.
    pub coef: Vec<[f64; 4]>,
    /// Peak over the median of the scanned amplitude spectrum.
    pub prominence: f64,
}

impl Line {
    /// Mean amplitude of the fundamental over the channels.
    pub fn amplitude(&self) -> f64 {
        self.coef.iter().map(|c| c[0].hypot(c[1])).sum::<f64>() / self.coef.len().max(1) as f64
    }

    pub fn at(&self, channel: usize, t: f64, harmonic: bool) -> f64 {
        let c = self.coef[channel];
        let w = TAU * self.freq_hz * t;
        let h = if harmonic {
            c[2] * (3.0 * w).sin() + c[3] * (3.0 * w).cos()
        } else {
            0.0
        };
        c[0] * w.sin() + c[1] * w.cos() + h
    }
}

/// Summed squared amplitude over channels at `f` (projection on sin and cos).
/// The phasor e^{i w t} is advanced by multiplying with e^{i w dt}, recomputed only when the
/// step changes (gaps, jitter) and re-anchored every 1000 samples against rounding drift. Time
/// stamps k / rate differ in their last bits from step to step; a step within 1e-9 of the last
/// is the same step (its phase error, w dt 1e-9 per sample, stays below 1e-6 rad before the
/// next anchor).
fn power(t: &[f64], residuals: &[&[f64]], f: f64, idx: &[usize]) -> f64 {
    let w = TAU * f;
    let mut sums = vec![(0.0, 0.0); residuals.len()];
    let (mut sn, mut cs) = (0.0, 1.0);
    let mut rot = (0.0, 1.0);
    let mut last_dt = f64::NAN;
    for (i, &k) in idx.iter().enumerate() {
        if i % 1000 == 0 {
            (sn, cs) = (w * t[k]).sin_cos();
        } else {
            let dt = t[k] - t[idx[i - 1]];
            if (dt - last_dt).abs() > 1e-9 * dt.abs() || last_dt.is_nan() {
                rot = (w * dt).sin_cos();
                last_dt = dt;
            }
            (sn, cs) = (sn * rot.1 + cs * rot.0, cs * rot.1 - sn * rot.0);
        }
        for (sum, r) in sums.iter_mut().zip(residuals) {
            sum.0 += r[k] * sn;
            sum.1 += r[k] * cs;
        }
    }
    sums.iter().map(|(s, c)| s * s + c * c).sum::<f64>() / (idx.len() as f64).powi(2) * 4.0
}

/// Find the strongest line in the band among the samples `mask` selects; `None` when the
/// sample rate cannot show the band.
pub fn find_line(t: &[f64], residuals: &[&[f64]], mask: &[bool], rate_hz: f64) -> Option<Line> {
    let scan = coarse_scan(t, residuals, mask, rate_hz)?;
    Some(refine(t, residuals, scan, rate_hz))
}

/// The line at the coarse scan's peak, its frequency refined and its amplitudes fitted.
fn refine(t: &[f64], residuals: &[&[f64]], scan: Scan, rate_hz: f64) -> Line {
    let (idx, freqs, imax, pmax, median) = scan;
    // Refine on a longer window, whose main lobe is narrower than the scan step: first a fine
    // scan across the coarse peak (golden section alone would land on a side lobe), then golden
    // section within one fine step.
    let window: Vec<usize> = idx.iter().copied().take(REFINE_SAMPLES).collect();
    let span = t[window[window.len() - 1]] - t[window[0]];
    let fine_step = (0.25 / span.max(1e-9)).min(SCAN_STEP_HZ);
    let n_fine = (2.0 * SCAN_STEP_HZ / fine_step).ceil() as usize;
    let p = |f: f64| power(t, residuals, f, &window);
    let f_fine = (0..=n_fine)
        .map(|i| freqs[imax] - SCAN_STEP_HZ + i as f64 * fine_step)
        .map(|f| (f, p(f)))
        .max_by(|x, y| x.1.total_cmp(&y.1))
        .map_or(freqs[imax], |(f, _)| f);
    let freq_hz = golden_max(p, f_fine - fine_step, f_fine + fine_step, 20);
    let harmonic = rate_hz > 2.2 * 3.0 * freq_hz;
    let coef = residuals
        .iter()
        .map(|r| fit_coefficients(t, r, &idx, freq_hz, harmonic))
        .collect();
    Line {
        freq_hz,
        coef,
        prominence: pmax / median,
    }
}

/// The maximum of the unimodal `p` on (a, b) by `iterations` golden-section steps, each
/// evaluating `p` once: the inner point kept from the last step is the next step's other one.
fn golden_max(p: impl Fn(f64) -> f64, mut a: f64, mut b: f64, iterations: usize) -> f64 {
    let g = 0.618_033_988_75;
    let (mut x1, mut x2) = (b - g * (b - a), a + g * (b - a));
    let (mut p1, mut p2) = (p(x1), p(x2));
    for _ in 0..iterations {
        if p1 > p2 {
            (b, x2, p2) = (x2, x1, p1);
            x1 = b - g * (b - a);
            p1 = p(x1);
        } else {
            (a, x1, p1) = (x1, x2, p2);
            x2 = a + g * (b - a);
            p2 = p(x2);
        }
    }
    0.5 * (a + b)
}

/// The coarse scan of the band: the selected samples, the scanned frequencies, the peak's index
/// and power, and the spectrum's median; `None` when the rate cannot show the band or too few
/// samples are selected.
type Scan = (Vec<usize>, Vec<f64>, usize, f64, f64);

fn coarse_scan(t: &[f64], residuals: &[&[f64]], mask: &[bool], rate_hz: f64) -> Option<Scan> {
    if rate_hz < 2.2 * BAND_HZ.1 {
        return None;
    }
    let idx: Vec<usize> = (0..t.len()).filter(|&k| mask[k]).collect();
    if idx.len() < 1000 {
        return None;
    }
    let scan: Vec<usize> = idx.iter().copied().take(SCAN_SAMPLES).collect();
    let freqs: Vec<f64> = (0..)
        .map(|i| BAND_HZ.0 + i as f64 * SCAN_STEP_HZ)
        .take_while(|&f| f <= BAND_HZ.1)
        .collect();
    let spectrum: Vec<f64> = freqs
        .iter()
        .map(|&f| power(t, residuals, f, &scan))
        .collect();
    let (imax, &pmax) = spectrum
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))?;
    let mut sorted = spectrum.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2].max(1e-300);
    Some((idx, freqs, imax, pmax, median))
}

/// Half-width of the neighbourhood a fast line's prominence is measured against, and of the
/// gap left around the line's own bin: a residual's noise need not be white over a hundred
/// hertz, but it is within a few.
const LOCAL_HZ: (f64, f64) = (2.0, 0.2);

/// The strongest line from `lowest_hz` up to 0.45 of the rate outside the mains band (a
/// vibration, a pump, a pickup that is not the mains): the periodogram's highest bin over the
/// first [`SCAN_SAMPLES`] samples `mask` selects, refined and fitted as the mains line is, its
/// prominence against the periodogram's median within [`LOCAL_HZ`] either side.
pub fn find_fast_line(
    t: &[f64],
    residuals: &[&[f64]],
    mask: &[bool],
    rate_hz: f64,
    lowest_hz: f64,
) -> Option<Line> {
    let idx: Vec<usize> = (0..t.len()).filter(|&k| mask[k]).collect();
    let scan: Vec<usize> = idx.iter().copied().take(SCAN_SAMPLES).collect();
    if scan.len() < 1000 {
        return None;
    }
    let size = (2 * scan.len()).next_power_of_two();
    let mut power = vec![0.0; size];
    for r in residuals {
        let mean = scan.iter().map(|&k| r[k]).sum::<f64>() / scan.len() as f64;
        let x: Vec<f64> = scan.iter().map(|&k| r[k] - mean).collect();
        let p = crate::stats::periodogram(&x, size);
        power.iter_mut().zip(p).for_each(|(a, b)| *a += b);
    }
    let df = rate_hz / size as f64;
    let in_band =
        |f: f64| f >= lowest_hz && f <= 0.45 * rate_hz && !(BAND_HZ.0..=BAND_HZ.1).contains(&f);
    let k = (1..size / 2)
        .filter(|&k| in_band(k as f64 * df))
        .max_by(|&a, &b| power[a].total_cmp(&power[b]))?;
    let mut local: Vec<f64> = (1..size / 2)
        .filter(|&j| {
            let d = (j as f64 - k as f64).abs() * df;
            d <= LOCAL_HZ.0 && d > LOCAL_HZ.1
        })
        .map(|j| power[j])
        .collect();
    if local.is_empty() {
        return None;
    }
    local.sort_by(f64::total_cmp);
    let median = local[local.len() / 2].max(1e-300);
    let f = k as f64 * df;
    Some(refine(
        t,
        residuals,
        (idx, vec![f], 0, power[k], median),
        rate_hz,
    ))
}

/// `y` with a prominent line in the band (and its third harmonic) subtracted, if it holds one.
pub fn without_line(t: &[f64], y: &[f64], rate_hz: f64) -> Option<Vec<f64>> {
    let all = vec![true; t.len()];
    // The coarse scan alone tells most recordings apart, at a fraction of the refinement. A
    // NaN prominence (a column not measured) is no line either.
    let scan = coarse_scan(t, &[y], &all, rate_hz)?;
    let prominence = scan.3 / scan.4;
    if prominence.is_nan() || prominence <= MIN_LINE_PROMINENCE {
        return None;
    }
    let line = refine(t, &[y], scan, rate_hz);
    let harmonic = line.coef[0][2] != 0.0 || line.coef[0][3] != 0.0;
    Some(
        y.iter()
            .zip(t)
            .map(|(v, &t)| v - line.at(0, t, harmonic))
            .collect(),
    )
}

/// Least squares of a sin + b cos at f (and 3f) on the selected samples.
fn fit_coefficients(t: &[f64], r: &[f64], idx: &[usize], f: f64, harmonic: bool) -> [f64; 4] {
    let m = if harmonic { 4 } else { 2 };
    let mut ata = DMatrix::zeros(m, m);
    let mut atb = DVector::zeros(m);
    for &k in idx {
        let w = TAU * f * t[k];
        let basis = [w.sin(), w.cos(), (3.0 * w).sin(), (3.0 * w).cos()];
        for i in 0..m {
            atb[i] += basis[i] * r[k];
            for j in 0..m {
                ata[(i, j)] += basis[i] * basis[j];
            }
        }
    }
    let mut c = [0.0; 4];
    if let Some(x) = super::lm::solve_linear(ata, atb) {
        c[..m].copy_from_slice(x.as_slice());
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_line_off_the_scan_grid() {
        let t: Vec<f64> = (0..60_000).map(|k| k as f64 * 1e-3).collect();
        let mut g = baseline::synth::Gaussian::new(5);
        let r: Vec<f64> = t
            .iter()
            .map(|t| 0.01 * (TAU * 59.93 * t + 0.4).sin() + 0.01 * g.normal())
            .collect();
        let line = find_line(&t, &[&r], &vec![true; t.len()], 1000.0).unwrap();
        assert!((line.freq_hz - 59.93).abs() < 1e-3, "{}", line.freq_hz);
        assert!((line.amplitude() - 0.01).abs() < 5e-4);
        assert!(line.prominence > 100.0);
    }

    /// With the line taken out, the noise estimate of `Data` sees the white noise: read as
    /// AR(1) noise, the line alone had inflated it about tenfold.
    #[test]
    fn the_noise_estimate_sees_through_a_line() {
        use crate::noise::{ar1_rho as noise_correlation, difference_noise};
        let t: Vec<f64> = (0..70_000).map(|k| k as f64 * 2e-3).collect();
        let mut g = baseline::synth::Gaussian::new(9);
        let y: Vec<f64> = t
            .iter()
            .map(|t| (0.05 * t).sin() + 0.012 * (TAU * 60.0 * t).sin() + 0.003 * g.normal())
            .collect();
        assert!(
            noise_correlation(&y) > 0.5,
            "the line reads as correlated noise"
        );
        let quiet = without_line(&t, &y, 500.0).expect("a prominent line");
        assert!(noise_correlation(&quiet) < 0.05);
        let sigma = difference_noise(&quiet);
        assert!((sigma - 0.003).abs() < 2e-4, "{sigma}");
        let flat: Vec<f64> = t.iter().map(|_| 0.003 * g.normal()).collect();
        assert!(without_line(&t, &flat, 500.0).is_none());
    }

    /// A line at no mains frequency, under noise reddened at low frequencies, is found where it
    /// is and stands above its neighbourhood; the reddened noise alone holds no prominent line
    /// anywhere in the band (the prominence is against the local level, not the band's).
    #[test]
    fn a_fast_line_stands_out_of_its_own_neighbourhood() {
        let rate = 500.0;
        let t: Vec<f64> = (0..60_000).map(|k| k as f64 / rate).collect();
        let mut g = baseline::synth::Gaussian::new(11);
        let mut ar = 0.0;
        let noise: Vec<f64> = t
            .iter()
            .map(|_| {
                ar = 0.9 * ar + 0.003 * g.normal();
                ar
            })
            .collect();
        let all = vec![true; t.len()];
        let r: Vec<f64> = t
            .iter()
            .zip(&noise)
            .map(|(t, n)| 0.004 * (TAU * 17.31 * t + 1.0).sin() + n)
            .collect();
        let line = find_fast_line(&t, &[&r], &all, rate, 10.0).expect("a line");
        assert!((line.freq_hz - 17.31).abs() < 2e-3, "{}", line.freq_hz);
        assert!(line.prominence > MIN_LINE_PROMINENCE, "{}", line.prominence);
        let quiet = find_fast_line(&t, &[&noise], &all, rate, 10.0).expect("a peak");
        assert!(
            quiet.prominence < MIN_LINE_PROMINENCE,
            "{}",
            quiet.prominence
        );
    }
}
