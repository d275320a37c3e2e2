//! AC coupling of the offset cut: a first-order high-pass, y' = x' - y / tau.

use super::first_order::highpass_state;

/// `tau_s`: the coupling time constant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HighpassCoupling {
    pub tau_s: f64,
}

impl HighpassCoupling {
    pub fn apply(&self, t_s: &[f64], x: &mut [f64]) {
        let h = highpass_state(t_s, x, self.tau_s.max(1e-6));
        x.copy_from_slice(&h);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Catalogue signature: sags toward zero under a constant input, undershoots below the
    /// initial value after release, then creeps back.
    #[test]
    fn sags_then_undershoots() {
        let t: Vec<f64> = (0..=30_000).map(|k| k as f64 * 1e-3).collect();
        let mut x: Vec<f64> = t
            .iter()
            .map(|&t| if (1.0..11.0).contains(&t) { 1.0 } else { 0.0 })
            .collect();
        HighpassCoupling { tau_s: 5.0 }.apply(&t, &mut x);
        assert!(
            (x[11_000 - 1] - (-10.0f64 / 5.0).exp()).abs() < 2e-3,
            "sag {}",
            x[10_999]
        );
        assert!(x[11_010] < -0.8, "undershoot {}", x[11_010]);
        assert!((x[30_000] + (1.0 - (-2.0f64).exp()) * (-19.0f64 / 5.0).exp()).abs() < 2e-3);
    }
}
