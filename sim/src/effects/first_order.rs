//! The first-order high-pass state shared by viscoelastic relaxation and AC coupling:
//! h' = x' - h / tau, integrated exactly for an input that is linear between samples, so
//! unevenly spaced (decimated, gappy) time bases give the same answer as the full-rate one.

/// h(t) for input x(t) on the time base `t_s`, starting at rest (h = 0).
pub fn highpass_state(t_s: &[f64], x: &[f64], tau_s: f64) -> Vec<f64> {
    let mut h = Vec::with_capacity(x.len());
    let mut state = 0.0;
    // The step's factors, kept while the spacing repeats (within rounding of the sample times):
    // an exponential per sample was a tenth of a diagnosis.
    let (mut last_dt, mut decay, mut gain) = (f64::NAN, 0.0, 0.0);
    for k in 0..x.len() {
        if k > 0 {
            let dt = (t_s[k] - t_s[k - 1]).max(0.0);
            let dx = x[k] - x[k - 1];
            if dt > 0.0 {
                if (dt - last_dt).abs() > 1e-12 * dt || last_dt.is_nan() {
                    decay = (-dt / tau_s).exp();
                    gain = tau_s / dt * (1.0 - decay);
                    last_dt = dt;
                }
                // Slope m = dx/dt held over the step: h += m tau (1 - e^{-dt/tau}).
                state = state * decay + dx * gain;
            } else {
                state += dx;
            }
        }
        h.push(state);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_response_decays_with_tau() {
        let t: Vec<f64> = (0..=2000).map(|k| k as f64 * 1e-3).collect();
        let x: Vec<f64> = t
            .iter()
            .map(|&t| if t >= 0.0005 { 1.0 } else { 0.0 })
            .collect();
        let h = highpass_state(&t, &x, 0.5);
        // One sample ramp then exponential decay: h(1.0 s) = e^{-(1.0-0.001)/0.5} approximately.
        let expect =
            (-(1.0 - 0.001) / 0.5f64).exp() * (0.5 / 0.001) * (1.0 - (-0.001f64 / 0.5).exp());
        assert!((h[1000] - expect).abs() < 1e-9, "{} vs {expect}", h[1000]);
    }

    #[test]
    fn ramp_settles_at_slope_times_tau_on_any_time_base() {
        let fine: Vec<f64> = (0..=10_000).map(|k| k as f64 * 1e-3).collect();
        let coarse: Vec<f64> = (0..=100).map(|k| k as f64 * 0.1).collect();
        for t in [fine, coarse] {
            let x: Vec<f64> = t.iter().map(|t| 2.0 * t).collect();
            let h = highpass_state(&t, &x, 0.3);
            assert!((h.last().unwrap() - 2.0 * 0.3).abs() < 1e-9);
        }
    }
}
