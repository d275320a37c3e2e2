//! One log's readings put on another's times: linear interpolation between the readings around
//! each time, nothing outside the readings' own span, and nothing inside an outage (a stretch
//! with no reading much longer than the log's usual step).

/// Linear interpolation of `y(x)` at `at` (`x` non-decreasing); `None` outside the sampled
/// range.
pub fn interpolate(x: &[f64], y: &[f64], at: f64) -> Option<f64> {
    if x.is_empty() || at < x[0] || at > x[x.len() - 1] || at.is_nan() {
        return None;
    }
    let i = x.partition_point(|v| *v <= at).clamp(1, x.len() - 1);
    let (x0, x1, y0, y1) = (x[i - 1], x[i], y[i - 1], y[i]);
    Some(if x1 > x0 {
        y0 + (y1 - y0) * (at - x0) / (x1 - x0)
    } else {
        y0
    })
}

/// The median of the positive time steps, s; `None` if there is none.
pub fn median_step_s(t_s: &[f64]) -> Option<f64> {
    let mut steps: Vec<f64> = t_s
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .collect();
    if steps.is_empty() {
        return None;
    }
    steps.sort_by(f64::total_cmp);
    Some(steps[steps.len() / 2])
}

/// A stretch without a reading longer than this many of the log's median steps is an outage
/// unless an outage length is given: up to four readings in a row may be missed or late
/// (a scale that answers every other loop, a logger's jitter) before a value is no longer
/// interpolated but left missing. Relative to the log's own step, so the same at 1 kHz and 5 Hz.
pub const GAP_STEPS: f64 = 5.0;

/// The readings of one quantity: the finite values of a column with their times.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    t_s: Vec<f64>,
    v: Vec<f64>,
    /// The longest stretch without a reading that is interpolated across, s.
    max_gap_s: f64,
}

impl Series {
    /// The readings of `v` at times `t_s` (non-decreasing), those that are `NaN` left out. A
    /// stretch without a reading longer than `max_gap_s` (by default [`GAP_STEPS`] median
    /// steps of the readings) is an outage.
    pub fn new(t_s: &[f64], v: &[f64], max_gap_s: Option<f64>) -> Self {
        let (t_s, v): (Vec<f64>, Vec<f64>) = t_s
            .iter()
            .zip(v)
            .filter(|(t, v)| t.is_finite() && v.is_finite())
            .map(|(t, v)| (*t, *v))
            .unzip();
        let max_gap_s = max_gap_s
            .or_else(|| median_step_s(&t_s).map(|d| GAP_STEPS * d))
            .unwrap_or(0.0);
        Self { t_s, v, max_gap_s }
    }

    /// Number of readings.
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// Whether there is no reading.
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// The first and last reading's times, if any.
    pub fn span_s(&self) -> Option<(f64, f64)> {
        Some((*self.t_s.first()?, *self.t_s.last()?))
    }

    /// The longest stretch without a reading interpolated across, s.
    pub fn max_gap_s(&self) -> f64 {
        self.max_gap_s
    }

    /// The value at `t`: interpolated between the readings around it; `NaN` outside the
    /// readings' span, and inside an outage where `t` is more than half the outage length from
    /// the nearer reading (so a time close to a reading on the edge of an outage keeps its
    /// value, and the middle of the outage is left missing).
    pub fn at(&self, t: f64) -> f64 {
        let Some(v) = interpolate(&self.t_s, &self.v, t) else {
            return f64::NAN;
        };
        let i = self.t_s.partition_point(|x| *x <= t);
        let before = i.checked_sub(1).map_or(f64::INFINITY, |k| t - self.t_s[k]);
        let after = self.t_s.get(i).map_or(f64::INFINITY, |x| x - t);
        if before.min(after) > 0.5 * self.max_gap_s {
            f64::NAN
        } else {
            v
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_is_linear_and_bounded() {
        let x = [0.0, 1.0, 3.0];
        let y = [0.0, 10.0, 30.0];
        assert_eq!(interpolate(&x, &y, 2.0), Some(20.0));
        assert_eq!(interpolate(&x, &y, 3.5), None);
        assert_eq!(interpolate(&[0.0, 0.0], &[1.0, 2.0], 0.0), Some(1.0));
    }

    /// Missing readings are skipped, an outage is left missing in its middle, nothing is
    /// invented outside the span.
    #[test]
    fn missing_readings_and_outages() {
        let t: Vec<f64> = (0..20).map(|i| i as f64 * 0.1).collect();
        let mut v: Vec<f64> = t.iter().map(|t| 2.0 * t).collect();
        v[3] = f64::NAN; // one missing reading: interpolated across
        for x in &mut v[8..16] {
            *x = f64::NAN; // 0.8 to 1.5 s: an outage of 0.9 s between 0.7 and 1.6
        }
        let s = Series::new(&t, &v, None);
        assert!((s.max_gap_s() - 0.5).abs() < 1e-12);
        assert!((s.at(0.3) - 0.6).abs() < 1e-12);
        assert!((s.at(0.72) - 1.44).abs() < 1e-12, "near the outage's edge");
        assert!(s.at(1.1).is_nan(), "inside the outage");
        assert!(
            s.at(-0.01).is_nan() && s.at(1.95).is_nan(),
            "beyond the span"
        );
        let wide = Series::new(&t, &v, Some(2.0));
        assert!((wide.at(1.1) - 2.2).abs() < 1e-12);
    }
}
