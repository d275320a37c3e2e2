//! What the generators read off a recording: its channels by name, the rod's first release,
//! speeds, a first-order lag.

use sim::compression::RodHistory;

use baseline::synth::Noise;
use recording::Recording;

/// What the channel terms read besides the recording.
pub(super) struct Ctx<'a> {
    /// The same recording without noise and without the kind's own terms (the catalogue
    /// effects it hides in).
    pub clean: &'a Recording,
    pub history: &'a RodHistory,
    pub noise: Noise,
}

impl Ctx<'_> {
    /// The white noise's deviation on `column`.
    pub fn sigma(&self, column: &str) -> f64 {
        match column {
            "load_N" => self.noise.load_n,
            "fz_V" => self.noise.volts[0],
            "mx_V" => self.noise.volts[1],
            _ => self.noise.volts[2],
        }
    }
}

pub(super) use crate::categories::{column, column_mut};

/// The rod speed at each sample, mm/min (central differences).
pub(super) fn speed_mm_per_min(t_s: &[f64], rod_mm: &[f64]) -> Vec<f64> {
    let n = rod_mm.len();
    (0..n)
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            if b == a {
                0.0
            } else {
                60.0 * (rod_mm[b] - rod_mm[a]) / (t_s[b] - t_s[a])
            }
        })
        .collect()
}

/// The index where the rod first turns back from its first peak.
pub(super) fn first_release(rod_mm: &[f64]) -> usize {
    let top = rod_mm.iter().cloned().fold(f64::MIN, f64::max);
    let start = rod_mm[0];
    (1..rod_mm.len())
        .find(|&i| rod_mm[i] < rod_mm[i - 1] - 1e-12 && rod_mm[i - 1] - start > 0.5 * (top - start))
        .unwrap_or(rod_mm.len() / 2)
}

/// First-order lag of `x` with time constant `tau_s` (exact for a held input).
pub(super) fn lag(t_s: &[f64], x: &[f64], tau_s: f64) -> Vec<f64> {
    let mut y = x.first().copied().unwrap_or(0.0);
    let mut out = Vec::with_capacity(x.len());
    for i in 0..x.len() {
        if i > 0 {
            let w = 1.0 - (-(t_s[i] - t_s[i - 1]) / tau_s).exp();
            y += w * (x[i] - y);
        }
        out.push(y);
    }
    out
}
