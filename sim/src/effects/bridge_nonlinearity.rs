//! Second-order resistance change with stress: a bridge output with a quadratic term,
//! y = x + q x^2 / X, X the full scale (the signal's own peak magnitude), so q is the share of
//! full scale the quadratic term adds at full load, independent of gains.

/// `quadratic`: q.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BridgeNonlinearity {
    pub quadratic: f64,
}

impl BridgeNonlinearity {
    pub fn apply(&self, x: &mut [f64]) {
        let full_scale = super::peak_abs(x);
        if full_scale == 0.0 {
            return;
        }
        for y in x.iter_mut() {
            *y += self.quadratic * *y * *y / full_scale;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Catalogue signature: residual proportional to the square of the load, either polarity.
    #[test]
    fn residual_is_square_of_the_load() {
        let mut x = vec![-1.0, -0.5, 0.0, 0.5];
        BridgeNonlinearity { quadratic: 0.1 }.apply(&mut x);
        assert_eq!(x, vec![-0.9, -0.475, 0.0, 0.525]);
    }
}
