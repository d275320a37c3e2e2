//! Quasi-linear viscoelasticity on the deviatoric part (Simo 1987; Puso & Weiss 1998).
//!
//! The deviatoric second Piola–Kirchhoff stress is a Prony-series convolution of the
//! instantaneous elastic one S0(F) = F^{-1} P_dev(F):
//!
//!   S(t) = g_inf S0(t) + sum_i h_i(t),   dh_i/dt + h_i / tau_i = g_i dS0/dt,
//!
//! with g_inf = 1 - sum g_i. Over a step dt the exact update for S0 varying linearly is
//! h_i^{n+1} = e^{-x} h_i^n + g_i (1 - e^{-x}) / x (S0^{n+1} - S0^n), x = dt / tau_i, so
//! S^{n+1} = beta S0(F^{n+1}) + Q with beta = g_inf + sum g_i (1 - e^{-x})/x and a history
//! stress Q fixed during the step. The first Piola stress is P = beta P_dev + F Q, and its
//! tangent beta A_dev + delta_ik Q_JL. The volumetric (nodal-pressure) part stays elastic.
//!
//! `youngs_modulus_pa` is the relaxed (long-term) modulus, so a very slow loading reproduces
//! the elastic model; the instantaneous modulus is E / g_inf.

use crate::material::{Mat3, Tensor4};

/// One Prony term: relative modulus g_i and relaxation time tau_i.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PronyTerm {
    /// Relative modulus g_i (fraction of the instantaneous modulus), in (0, 1).
    pub g: f64,
    /// Relaxation time tau_i, s.
    pub tau_s: f64,
}

/// History of one element.
#[derive(Debug, Clone, Default)]
pub struct ElementHistory {
    /// h_i per Prony term.
    pub h: Vec<Mat3>,
    /// S0 at the last converged step.
    pub s0: Mat3,
}

/// Relaxed fraction g_inf = 1 - sum g_i.
pub fn g_inf(terms: &[PronyTerm]) -> f64 {
    1.0 - terms.iter().map(|t| t.g).sum::<f64>()
}

/// (beta, Q) for a step of length `dt_s` from history `hist`.
pub fn step_coefficients(terms: &[PronyTerm], hist: &ElementHistory, dt_s: f64) -> (f64, Mat3) {
    let mut beta = g_inf(terms);
    let mut q = [[0.0; 3]; 3];
    for (k, t) in terms.iter().enumerate() {
        let x = dt_s / t.tau_s;
        let decay = (-x).exp();
        let gamma = if x < 1e-12 { 1.0 } else { (1.0 - decay) / x };
        beta += t.g * gamma;
        let h = hist.h.get(k).copied().unwrap_or_default();
        for i in 0..3 {
            for j in 0..3 {
                q[i][j] += decay * h[i][j] - t.g * gamma * hist.s0[i][j];
            }
        }
    }
    (beta, q)
}

/// Modify the instantaneous deviatoric (P, A) into the algorithmic viscoelastic ones.
pub fn apply(f: &Mat3, beta: f64, q: &Mat3, p: &mut Mat3, a: &mut Tensor4) {
    for i in 0..3 {
        for jj in 0..3 {
            p[i][jj] *= beta;
            for k in 0..3 {
                p[i][jj] += f[i][k] * q[k][jj];
            }
        }
    }
    for r in a.iter_mut() {
        for v in r.iter_mut() {
            *v *= beta;
        }
    }
    for i in 0..3 {
        for jj in 0..3 {
            for l in 0..3 {
                a[3 * i + jj][3 * i + l] += q[jj][l];
            }
        }
    }
}

/// After convergence: advance the history with the new instantaneous stress S0.
pub fn advance(terms: &[PronyTerm], hist: &mut ElementHistory, s0_new: Mat3, dt_s: f64) {
    hist.h.resize(terms.len(), [[0.0; 3]; 3]);
    for (k, t) in terms.iter().enumerate() {
        let x = dt_s / t.tau_s;
        let decay = (-x).exp();
        let gamma = if x < 1e-12 { 1.0 } else { (1.0 - decay) / x };
        for i in 0..3 {
            for j in 0..3 {
                hist.h[k][i][j] =
                    decay * hist.h[k][i][j] + t.g * gamma * (s0_new[i][j] - hist.s0[i][j]);
            }
        }
    }
    hist.s0 = s0_new;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A step strain S0 = 1 held constant relaxes as g_inf + g e^{-t/tau} (the Prony kernel).
    #[test]
    fn step_strain_relaxes_along_the_prony_kernel() {
        let terms = [PronyTerm { g: 0.4, tau_s: 2.0 }];
        let mut hist = ElementHistory::default();
        let s0 = [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]];
        advance(&terms, &mut hist, s0, 1e-9); // the jump
        let dt = 0.05;
        let mut t = 0.0;
        for _ in 0..60 {
            let (beta, q) = step_coefficients(&terms, &hist, dt);
            let s = beta * s0[0][0] + q[0][0];
            t += dt;
            let exact = 0.6 + 0.4 * (-t / 2.0f64).exp();
            assert!((s - exact).abs() < 1e-6, "t={t} s={s} exact={exact}");
            advance(&terms, &mut hist, s0, dt);
        }
    }
}
