//! Rate-independent hysteresis of the gel (internal friction, Mullins softening) as a scaled
//! stop operator: y = x (1 + w z), where the direction state z in [-1, 1] follows the input
//! through a stop (Prandtl) element of yield span `TRANSITION` of full scale. Loading runs
//! w above the elastic path, unloading w below it; the loop closes at zero load.

/// Share of full scale over which the direction state turns round after a reversal.
pub const TRANSITION: f64 = 0.05;

/// `width`: the loop half-width as a fraction of full scale (at full scale the loading and
/// unloading paths are `2 width` apart).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hysteresis {
    pub width: f64,
}

impl Hysteresis {
    /// Full scale is the signal's own peak magnitude, so the operator commutes with gains.
    pub fn apply(&self, x: &mut [f64]) {
        let full_scale = super::peak_abs(x);
        if full_scale == 0.0 {
            return;
        }
        let mut z = 0.0f64;
        let mut previous = x.first().copied().unwrap_or(0.0);
        for y in x.iter_mut() {
            let xi = *y;
            // Sign of the load so that "loading" means growing magnitude on either polarity.
            z = (z + (xi.abs() - previous.abs()) / (TRANSITION * full_scale)).clamp(-1.0, 1.0);
            previous = xi;
            *y = xi * (1.0 + self.width * z);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Catalogue signature: the unloading path lies below the loading path even when slow.
    #[test]
    fn unloading_path_below_loading_path() {
        let up: Vec<f64> = (0..=1000).map(|k| k as f64 / 1000.0).collect();
        let mut x: Vec<f64> = up.iter().chain(up.iter().rev()).copied().collect();
        Hysteresis { width: 0.05 }.apply(&mut x);
        let loading_half = x[500];
        let unloading_half = x[1001 + 500];
        assert!((loading_half - 0.5 * 1.05).abs() < 1e-9);
        assert!((unloading_half - 0.5 * 0.95).abs() < 1e-9);
        assert_eq!(*x.last().unwrap(), 0.0);
    }
}
