//! Each output's map read at another load than the fingertip model's own at that travel.
//!
//! The FE predicts how each chip output departs from proportional to the rod's load,
//! r = (output / F) / (output / F at full load), and it predicts it as a function of the travel:
//! the contact's geometry sets both the load and the outputs. Another model of the same test may
//! tie the outputs to the *load* instead (the stress under the rod), and then, with another
//! contact law, the FE's features (where the contact reaches the base, a step in r within a
//! millimetre) sit at another travel: the map blend (r raised to 1 - b) only scales them, and
//! such a recording was left with a structured misfit of one to three noise deviations on every
//! output. So the maps may be read at a load between the FE's at that travel and the calibrated
//! law's, ln F* = ln F_FE(d) + g (ln F(d) - ln F_FE(d)) + c, with g from 0 (the outputs follow
//! the travel) to 1 (they follow the load), and c the level of the load they follow where the
//! modulus moved the load alone (another law's load per pascal). Bounds and reasons:
//! `hardware/fit-bounds.toml`.

use crate::response::FingertipResponse;

/// Travels of the table, as shares of the largest travel: from 0.5 % to three times it, even in
/// ln(travel). Below, the maps are held (the warp stops at 1 %); above, a load no model reaches.
const SHARE_RANGE: (f64, f64) = (0.005, 3.0);
/// Points of the table: its steps in ln(travel) (0.027) are far below the FE's node spacing.
const POINTS: usize = 240;
/// Largest |ln r| of an output's departure, as in [`crate::model`]'s maps: beyond a decade the
/// ratio is of two numbers near zero (a moment at no inclination), not a map.
const MAX_LN_DEPARTURE: f64 = std::f64::consts::LN_10;

/// Points of the even grid in ln F the table is resampled onto, so a lookup (once per sample in
/// every evaluation of a fit) is an index, not a search.
const EVEN_POINTS: usize = 1024;

/// ln r of each output against ln F per Pa, tabulated from a fingertip model on an even grid.
#[derive(Debug, Clone, PartialEq)]
pub struct MapByLoad {
    /// ln F per Pa at the first point and the grid's step.
    ln_force_start: f64,
    step: f64,
    ln_ratio: Vec<[f64; 3]>,
}

impl MapByLoad {
    /// From `model` over travels up to `rod_max_mm` and beyond (0.5 % to three times it). Points where
    /// the force does not rise (no contact, a flat stretch) are left out, so ln F is strictly
    /// increasing and the map is a function of it.
    pub fn new(model: &dyn FingertipResponse, rod_max_mm: f64) -> Self {
        let (lo, hi) = (SHARE_RANGE.0.ln(), SHARE_RANGE.1.ln());
        let top = model.unit_response(rod_max_mm);
        let mut ln_force: Vec<f64> = Vec::with_capacity(POINTS);
        let mut ln_ratio = Vec::with_capacity(POINTS);
        for j in 0..POINTS {
            let d = rod_max_mm * (lo + (hi - lo) * j as f64 / (POINTS - 1) as f64).exp();
            let u = model.unit_response(d);
            if u.force_n.is_nan()
                || u.force_n <= 0.0
                || ln_force.last().is_some_and(|&f| u.force_n.ln() <= f)
            {
                continue;
            }
            ln_force.push(u.force_n.ln());
            ln_ratio.push(std::array::from_fn(|k| {
                let r = (u.chip[k] / u.force_n) / (top.chip[k] / top.force_n);
                if r > 0.0 && r.is_finite() {
                    r.ln().clamp(-MAX_LN_DEPARTURE, MAX_LN_DEPARTURE)
                } else {
                    0.0
                }
            }));
        }
        Self::even(&ln_force, &ln_ratio)
    }

    /// No map at all (every lookup 0): the drive of a response given per sample
    /// ([`crate::Drive::of_samples`]) has no law of the travel to read its maps at another load.
    pub fn none() -> Self {
        Self::even(&[], &[])
    }

    /// The table (`ln_force` increasing) resampled linearly onto [`EVEN_POINTS`] even in ln F.
    fn even(ln_force: &[f64], ln_ratio: &[[f64; 3]]) -> Self {
        let (Some(&first), Some(&last)) = (ln_force.first(), ln_force.last()) else {
            return Self {
                ln_force_start: 0.0,
                step: 1.0,
                ln_ratio: Vec::new(),
            };
        };
        let step = ((last - first) / (EVEN_POINTS - 1) as f64).max(f64::MIN_POSITIVE);
        let ln_ratio = (0..EVEN_POINTS)
            .map(|i| {
                let x = first + step * i as f64;
                let j = ln_force
                    .partition_point(|&f| f < x)
                    .clamp(1, ln_force.len().max(2) - 1);
                if ln_force.len() < 2 {
                    return ln_ratio[0];
                }
                let (a, b) = (ln_force[j - 1], ln_force[j]);
                let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
                std::array::from_fn(|k| {
                    ln_ratio[j - 1][k] + t * (ln_ratio[j][k] - ln_ratio[j - 1][k])
                })
            })
            .collect();
        Self {
            ln_force_start: first,
            step,
            ln_ratio,
        }
    }

    /// ln r of each output at ln F per Pa `x`: linear between the grid's points, held at its
    /// ends.
    pub fn at(&self, x: f64) -> [f64; 3] {
        let n = self.ln_ratio.len();
        if n == 0 {
            return [0.0; 3];
        }
        let u = ((x - self.ln_force_start) / self.step).clamp(0.0, (n - 1) as f64);
        let j = (u as usize).min(n.saturating_sub(2));
        let t = u - j as f64;
        let (a, b) = (self.ln_ratio[j], self.ln_ratio[(j + 1).min(n - 1)]);
        std::array::from_fn(|k| a[k] + t * (b[k] - a[k]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::response::UnitResponse;

    /// A fingertip whose force is d^2 and whose first output's ratio to it is d (a moment arm
    /// growing with the travel): r = d / d_max, so ln r = (ln F - ln F_max) / 2.
    struct Square;

    impl FingertipResponse for Square {
        fn unit_response(&self, rod_mm: f64) -> UnitResponse {
            let d = rod_mm.max(0.0);
            UnitResponse {
                force_n: d * d,
                chip: [d * d * d, 2.0 * d * d, 0.0],
            }
        }
    }

    #[test]
    fn reads_the_map_at_a_load() {
        let map = MapByLoad::new(&Square, 4.0);
        for d in [0.5f64, 1.0, 2.5, 4.0, 7.0] {
            let r = map.at((d * d).ln());
            assert!((r[0] - (d / 4.0).ln()).abs() < 1e-3, "{d}: {r:?}");
            assert!(r[1].abs() < 1e-12, "a proportional output has no departure");
            assert_eq!(r[2], 0.0, "an output that is zero has no map");
        }
        // Held at the table's ends (three times the largest travel), and a departure beyond a
        // decade is clamped there (0.5 % of the travel would be r = 0.005).
        assert!((map.at(-100.0)[0] + MAX_LN_DEPARTURE).abs() < 1e-12);
        assert!((map.at(100.0)[0] - 3.0f64.ln()).abs() < 1e-9);
    }
}
