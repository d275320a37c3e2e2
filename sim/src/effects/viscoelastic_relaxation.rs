//! Quasi-linear viscoelasticity (Fung): the response is the instantaneous elastic response
//! x_e(t) convolved with a reduced relaxation function, here a one-term Prony series
//! G(t) = 1 - g + g e^{-t/tau}:  y(t) = integral G(t - s) dx_e/ds ds = (1 - g) x_e + g h(t),
//! with h the first-order high-pass of x_e (`first_order`).

use super::first_order::highpass_state;

/// `tau_s`: the Prony time constant; `fraction`: g, the relaxing share of the instantaneous
/// response (0..1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViscoelasticRelaxation {
    pub tau_s: f64,
    pub fraction: f64,
}

impl ViscoelasticRelaxation {
    pub fn apply(&self, t_s: &[f64], x: &mut [f64]) {
        let h = highpass_state(t_s, x, self.tau_s.max(1e-6));
        let g = self.fraction;
        for (y, h) in x.iter_mut().zip(h) {
            *y = (1.0 - g) * *y + g * h;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Catalogue signature: under a held step the output decays from x_e to (1 - g) x_e with
    /// time constant tau; after a fast release it undershoots and creeps back to zero.
    #[test]
    fn relaxes_under_hold_and_creeps_back_after_release() {
        let t: Vec<f64> = (0..=20_000).map(|k| k as f64 * 1e-3).collect();
        let mut x: Vec<f64> = t
            .iter()
            .map(|&t| if (1.0..10.0).contains(&t) { 1.0 } else { 0.0 })
            .collect();
        ViscoelasticRelaxation {
            tau_s: 2.0,
            fraction: 0.3,
        }
        .apply(&t, &mut x);
        assert!((x[1010] - 1.0).abs() < 0.01, "instantaneous {}", x[1010]);
        let at = |t: f64| 0.7 + 0.3 * (-(t - 1.0) / 2.0f64).exp();
        assert!((x[3000] - at(3.0)).abs() < 2e-3);
        assert!((x[9990] - at(9.99)).abs() < 2e-3);
        assert!(x[10_010] < -0.2, "undershoot after release {}", x[10_010]);
        assert!(x[20_000] < 0.0 && x[20_000] > x[12_000], "creeps back");
    }
}
