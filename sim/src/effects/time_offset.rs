//! Sensor stream and load reference shifted in time: y(t) = x(t - lag), linear interpolation on
//! the (possibly uneven) time base, the first value held before the start.

/// `lag_s`: positive when the sensor lags the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeOffset {
    pub lag_s: f64,
}

impl TimeOffset {
    pub fn apply(&self, t_s: &[f64], x: &mut [f64]) {
        let src = x.to_vec();
        for (y, &t) in x.iter_mut().zip(t_s) {
            *y = super::interpolate(t_s, &src, t - self.lag_s);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Catalogue signature: the residual is proportional to the derivative of the signal.
    #[test]
    fn residual_is_lag_times_derivative() {
        let t: Vec<f64> = (0..1000).map(|k| k as f64 * 1e-3).collect();
        let x: Vec<f64> = t.iter().map(|t| (3.0 * t).sin()).collect();
        let mut y = x.clone();
        TimeOffset { lag_s: 0.01 }.apply(&t, &mut y);
        let k = 500;
        let derivative = 3.0 * (3.0 * t[k]).cos();
        assert!(((x[k] - y[k]) - 0.01 * derivative).abs() < 1e-3);
    }
}
