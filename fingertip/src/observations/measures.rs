//! The quantities that test the observations, from curves and time series: a power-law
//! exponent, a recovery time, an undershoot, an S-shape. Pure functions of the samples.

/// Least-squares fit of |y| = c x^n in log-log over the samples with x above `x_from` of the
/// largest x: (n, rms of the log residual).
pub fn power_law(samples: &[(f64, f64)], x_from: f64) -> (f64, f64) {
    let xmax = samples.iter().map(|s| s.0).fold(0.0, f64::max);
    let pts: Vec<(f64, f64)> = samples
        .iter()
        .filter(|s| s.0 > x_from * xmax && s.1.abs() > 0.0)
        .map(|s| (s.0.ln(), s.1.abs().ln()))
        .collect();
    let n = pts.len() as f64;
    if n < 3.0 {
        return (f64::NAN, f64::NAN);
    }
    let (mx, my) = pts
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let slope = sxy / sxx;
    let rms = (pts
        .iter()
        .map(|p| (p.1 - my - slope * (p.0 - mx)).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    (slope, rms)
}

/// Time after `t_back_s` (the rod back at its start) from which |y - y0| stays below
/// `fraction` of `peak` (y0 the value before the test): 0 when it is already there.
pub fn recovery_time_s(
    t_s: &[f64],
    y: &[f64],
    y0: f64,
    peak: f64,
    t_back_s: f64,
    fraction: f64,
) -> f64 {
    let band = fraction * peak.abs();
    let mut last_out = None;
    for (&t, &v) in t_s.iter().zip(y) {
        if t >= t_back_s && (v - y0).abs() > band {
            last_out = Some(t);
        }
    }
    last_out.map_or(0.0, |t| t - t_back_s)
}

/// Largest excursion past the initial value, against the peak's sign, after `t_back_s`, as a
/// fraction of |peak - y0|: negative when the output crosses its initial value.
pub fn crossing_fraction(t_s: &[f64], y: &[f64], y0: f64, peak: f64, t_back_s: f64) -> f64 {
    let sign = (peak - y0).signum();
    let scale = (peak - y0).abs().max(f64::MIN_POSITIVE);
    t_s.iter()
        .zip(y)
        .filter(|(&t, _)| t >= t_back_s)
        .map(|(_, &v)| sign * (v - y0) / scale)
        .fold(0.0, f64::min)
}

/// S-shape of a trajectory (x, y), each normalised by its final value: the deviation from the
/// straight line between the ends, d = y/y_end - x/x_end. A curve that bends one way keeps the
/// sign of d; an S changes it. Returns the smaller of the two lobes, max(d) and -min(d), so
/// that a positive value is the height of the weaker lobe of an S.
pub fn s_shape_lobe(samples: &[(f64, f64)]) -> f64 {
    let Some(&(x_end, y_end)) = samples.last() else {
        return 0.0;
    };
    if x_end == 0.0 || y_end == 0.0 {
        return 0.0;
    }
    let (lo, hi) = samples
        .iter()
        .map(|&(x, y)| y / y_end - x / x_end)
        .fold((0.0f64, 0.0f64), |a, d| (a.0.min(d), a.1.max(d)));
    hi.min(-lo)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_law_recovers_an_exact_exponent() {
        let s: Vec<(f64, f64)> = (1..=20)
            .map(|k| (k as f64, 3.0 * (k as f64).powf(1.7)))
            .collect();
        let (n, rms) = power_law(&s, 0.1);
        assert!((n - 1.7).abs() < 1e-12 && rms < 1e-12);
    }

    #[test]
    fn recovery_time_of_an_exponential_tail() {
        // y = e^{-t/5} after t = 0: below 2 % of the peak 1 after 5 ln 50 = 19.56 s.
        let t: Vec<f64> = (0..=6000).map(|k| k as f64 * 0.01).collect();
        let y: Vec<f64> = t.iter().map(|&t| (-t / 5.0f64).exp()).collect();
        let tr = recovery_time_s(&t, &y, 0.0, 1.0, 0.0, 0.02);
        assert!((tr - 5.0 * 50.0f64.ln()).abs() < 0.02, "{tr}");
    }

    #[test]
    fn crossing_is_negative_only_past_the_initial_value() {
        let t = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(
            crossing_fraction(&t, &[2.0, 1.0, 0.5, 0.0], 0.0, 2.0, 1.0),
            0.0
        );
        let c = crossing_fraction(&t, &[2.0, 1.0, -0.2, 0.0], 0.0, 2.0, 1.0);
        assert!((c + 0.1).abs() < 1e-12);
    }

    #[test]
    fn s_shape_needs_both_signs_of_the_deviation() {
        let convex: Vec<(f64, f64)> = (0..=10).map(|k| (k as f64, (k as f64).powi(2))).collect();
        assert_eq!(s_shape_lobe(&convex), 0.0);
        // y = x + 0.05 sin(2 pi x) on [0, 1]: lobes of 0.05 on both sides.
        let s: Vec<(f64, f64)> = (0..=100)
            .map(|k| {
                let x = k as f64 / 100.0;
                (x, x + 0.05 * (std::f64::consts::TAU * x).sin())
            })
            .collect();
        assert!((s_shape_lobe(&s) - 0.05).abs() < 1e-3);
    }
}
