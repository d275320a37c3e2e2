//! Power-law stiffening of the load path (hyperelastic, geometric): the output grows with a
//! power of the elastic response, y = X sign(x) (|x| / X)^p, X the full scale (the signal's own
//! peak magnitude, so the operator commutes with gains and p = 1 is the identity).

/// `exponent`: p.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stiffening {
    pub exponent: f64,
}

impl Stiffening {
    pub fn apply(&self, x: &mut [f64]) {
        let full_scale = super::peak_abs(x);
        if full_scale == 0.0 {
            return;
        }
        for y in x.iter_mut() {
            *y = full_scale * y.signum() * (y.abs() / full_scale).powf(self.exponent);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Catalogue signature: the residual against the linear path grows with a power of the load,
    /// the same on loading and unloading.
    #[test]
    fn grows_with_a_power_of_the_load() {
        let mut x = vec![0.0, 0.25, 0.5, 1.0, 0.5, 0.25, 0.0];
        Stiffening { exponent: 1.5 }.apply(&mut x);
        assert!((x[2] - 0.5f64.powf(1.5)).abs() < 1e-12);
        assert_eq!(x[3], 1.0);
        assert_eq!(x[1], x[5]);
    }
}
