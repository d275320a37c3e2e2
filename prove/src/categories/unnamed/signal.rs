//! What the generators read off a recording and the rod's path: channels by name, speeds,
//! presses, a first-order memory, the load as a function of the travel.

use baseline::synth::SimSpec;

/// Uniform deviates `u(a, b)`.
pub(super) type Draw<'a> = &'a mut dyn FnMut(f64, f64) -> f64;

/// Drawn parameters, named.
pub(super) type Params = Vec<(&'static str, f64)>;

pub(super) use crate::categories::{column, column_mut};

/// The rod's speed at each sample, mm/min: the slope of the segment the sample ends (the path
/// is straight between corners, so this is the speed the drive was set to).
pub(super) fn speed_mm_per_min(t_s: &[f64], rod_mm: &[f64]) -> Vec<f64> {
    let n = rod_mm.len();
    (0..n)
        .map(|i| {
            let (a, b) = if i == 0 {
                (0, 1.min(n - 1))
            } else {
                (i - 1, i)
            };
            if b == a || t_s[b] <= t_s[a] {
                0.0
            } else {
                60.0 * (rod_mm[b] - rod_mm[a]) / (t_s[b] - t_s[a])
            }
        })
        .collect()
}

/// First-order memory of `x` with time constant `tau_s`, starting from `x[0]` (exact for a
/// held input).
pub(super) fn lag(t_s: &[f64], x: &[f64], tau_s: f64) -> Vec<f64> {
    let mut y = x.first().copied().unwrap_or(0.0);
    x.iter()
        .enumerate()
        .map(|(i, &xi)| {
            if i > 0 {
                y += (1.0 - (-(t_s[i] - t_s[i - 1]) / tau_s).exp()) * (xi - y);
            }
            y
        })
        .collect()
}

/// The presses of a rod path: the runs of samples where the rod is more than a tenth of its
/// range beyond its least travel.
pub(super) fn presses(rod_mm: &[f64]) -> Vec<std::ops::Range<usize>> {
    let lo = rod_mm.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = rod_mm.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let level = lo + 0.1 * (hi - lo);
    let mut out = Vec::new();
    let mut start = None;
    for (i, &r) in rod_mm.iter().enumerate() {
        match (r > level, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                out.push(s..i);
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push(s..rod_mm.len());
    }
    out
}

/// The largest magnitude of `x` over `range`.
pub(super) fn peak_abs(x: &[f64], range: std::ops::Range<usize>) -> f64 {
    x[range].iter().fold(0.0, |m: f64, v| m.max(v.abs()))
}

/// The load as a function of the travel, tabulated from a noise-free simulation of a slow ramp
/// (no effect of the catalogue is hidden in this group, so the load has no memory), to find the
/// travel at which the gel gives a wanted force.
pub(super) struct LoadTable {
    rod_mm: Vec<f64>,
    load_n: Vec<f64>,
}

impl LoadTable {
    /// From `rod_mm` (increasing) and the load at each.
    pub fn new(rod_mm: Vec<f64>, load_n: Vec<f64>) -> Self {
        // Monotone by construction of the gel; a running maximum keeps the search sound where
        // rounding makes two neighbours equal.
        let mut top = f64::NEG_INFINITY;
        let load_n = load_n
            .into_iter()
            .map(|f| {
                top = top.max(f);
                top
            })
            .collect();
        Self { rod_mm, load_n }
    }

    /// The travel at which the load is `force_n` (out of contact for a force of zero or less,
    /// where `out_of_contact_mm` is kept; the table's end beyond its largest load).
    pub fn travel(&self, force_n: f64, out_of_contact_mm: f64) -> f64 {
        let contact = self.load_n.partition_point(|&f| f <= 0.0);
        if force_n <= 0.0 || contact >= self.load_n.len() {
            let last_free = contact.saturating_sub(1).min(self.rod_mm.len() - 1);
            return out_of_contact_mm.min(self.rod_mm[last_free]);
        }
        let i = self.load_n.partition_point(|&f| f < force_n).max(1);
        if i >= self.load_n.len() {
            return self.rod_mm[self.rod_mm.len() - 1];
        }
        let (f0, f1) = (self.load_n[i - 1], self.load_n[i]);
        let w = if f1 > f0 {
            ((force_n - f0) / (f1 - f0)).clamp(0.0, 1.0)
        } else {
            1.0
        };
        self.rod_mm[i - 1] + w * (self.rod_mm[i] - self.rod_mm[i - 1])
    }
}

/// A field-by-field copy of `spec` (it holds a reference, so it is not `Clone`).
pub(super) fn copy<'a>(spec: &SimSpec<'a>) -> SimSpec<'a> {
    SimSpec {
        fingertip: spec.fingertip,
        readout: spec.readout,
        baseline: spec.baseline,
        contact_angle_deg: spec.contact_angle_deg,
        azimuth_deg: spec.azimuth_deg,
        radius_mm: spec.radius_mm,
        test: spec.test.clone(),
        peak_loads_n: spec.peak_loads_n.clone(),
        effects: spec.effects.clone(),
        noise: spec.noise,
        seed: spec.seed,
        ambient_c: spec.ambient_c,
        warm_up_rise_c: spec.warm_up_rise_c,
        ambient_swing: spec.ambient_swing,
        source: spec.source.clone(),
    }
}
