//! One simulated column as a function of one variable (time, or rod travel): monotone cubic
//! between its points (`baseline::interp`, the FE tables' interpolation: no overshoot between
//! points, so a load never turns negative or passes its neighbours), held at its end values
//! outside them.

use baseline::interp;

/// A column `y` at increasing `x`, interpolated.
pub(crate) struct Curve {
    x: Vec<f64>,
    y: Vec<f64>,
    slopes: Vec<f64>,
}

impl Curve {
    /// `x` strictly increasing, one `y` each (the callers drop repeats and gaps first).
    pub fn new(x: Vec<f64>, y: Vec<f64>) -> Self {
        debug_assert!(x.windows(2).all(|w| w[1] > w[0]), "x must increase");
        let slopes = interp::slopes(&x, &y);
        Self { x, y, slopes }
    }

    /// The value at `at`: the cubic inside the points, the end value before the first, and
    /// beyond the last along the end slope (a table of the travel a little short of the
    /// recorded peak: held flat there, a stiff load is off by its slope times the shortfall).
    pub fn at_extending(&self, at: f64) -> f64 {
        match self.x.last() {
            Some(&hi) if at > hi => {
                let n = self.x.len();
                self.y[n - 1] + self.slopes[n - 1] * (at - hi)
            }
            _ => self.at(at),
        }
    }

    /// The value at `at`: the cubic inside the points, the end value outside.
    pub fn at(&self, at: f64) -> f64 {
        match (self.x.first(), self.x.last()) {
            (Some(&lo), _) if at <= lo => self.y[0],
            (_, Some(&hi)) if at >= hi => self.y[self.y.len() - 1],
            (None, _) => 0.0,
            _ => interp::eval(&self.x, &self.y, &self.slopes, at),
        }
    }
}

/// The rows of `x` (non-decreasing, NaN where missing) and `columns` that can carry a curve:
/// every value finite, each `x` once (a repeated time keeps its first row).
pub(crate) fn usable_rows(x: &[f64], columns: &[&[f64]]) -> Vec<usize> {
    let mut keep: Vec<usize> = Vec::with_capacity(x.len());
    for i in 0..x.len() {
        if !x[i].is_finite() || columns.iter().any(|c| !c[i].is_finite()) {
            continue;
        }
        if keep.last().is_some_and(|&j| x[i] <= x[j]) {
            continue;
        }
        keep.push(i);
    }
    keep
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_its_ends_and_passes_its_points() {
        let c = Curve::new(vec![0.0, 1.0, 2.0, 3.0], vec![0.0, 1.0, 4.0, 9.0]);
        assert_eq!(c.at(-5.0), 0.0);
        assert_eq!(c.at(7.0), 9.0);
        assert!((c.at(2.0) - 4.0).abs() < 1e-12);
        let mid = c.at(1.5);
        assert!(mid > 1.0 && mid < 4.0, "{mid}");
        let beyond = c.at_extending(3.5);
        assert!(beyond > 9.0 && beyond < 9.0 + 0.5 * 7.0, "{beyond}");
        assert_eq!(c.at_extending(-1.0), 0.0);
    }

    #[test]
    fn usable_rows_drop_gaps_and_repeats() {
        let x = [0.0, 1.0, 1.0, f64::NAN, 2.0, 3.0];
        let y = [0.0, 1.0, 2.0, 3.0, f64::NAN, 5.0];
        assert_eq!(usable_rows(&x, &[&y]), [0, 1, 5]);
    }
}
