//! The documented threshold of the static-shape effects (`hardware/fit-bounds.toml`,
//! `[outputs]`): `stiffening` and `bridge_nonlinearity` are named only where they bend an output
//! beyond what the calibration's map from the load may bend it.
//!
//! Over the samples loaded to 5-100 % of the largest load (of the largest output, where the
//! baseline models no load), the calibration may move output k's
//! map anywhere between the FE's and one linear in the load: a change of ln(output / load) of up
//! to S_k = (b_max - b_min) (max ln r_k - min ln r_k) (r_k the FE's departure from linear,
//! [`Drive`]; b the map blend's bounds, 0 to 1, and 0 to 0 where the baseline is a user's
//! simulation, whose maps are its own). An effect
//! with strength s bends output k by B_k(s) = max - min of ln(y / x) over the same samples, x at
//! its FE level u = x / max|x|:
//! - stiffening, y = X sign(x) (|x| / X)^p: ln(y / x) = (p - 1) ln|u|;
//! - bridge nonlinearity, y = x + q x^2 / X: ln(y / x) = ln(1 + q u).
//!
//! The bend the data guarantees is B_k at the strength moved two standard errors towards the
//! identity; the effect is named only if it exceeds S_k on at least one output, for below that
//! the effect is one more shape among those our ignorance of the map already allows.

use sim::effects::EffectKind;

use crate::data::peak_to_peak;
use baseline::Drive;

/// The samples the span is taken over: loaded to at least this share of the largest load (the
/// range over which `fit-bounds.toml` quotes the FE's departure from linear).
const LOADED_SHARE: f64 = 0.05;

/// Each output's signed level u = x / max|x| (FE chip loads) on the loaded samples, and the
/// calibration's span S of ln(output / load) there.
pub struct Span {
    levels: Vec<[f64; 3]>,
    pub span: [f64; 3],
}

impl Span {
    pub fn of(drive: &Drive, bounds: &hardware::FitBounds) -> Self {
        let blend_range = bounds.map_blend_max - bounds.map_blend_min;
        let unit = |i: usize| drive.unit(i);
        let force_max = drive.units().map(|u| u.force_n).fold(0.0, f64::max);
        let chip_max: [f64; 3] =
            std::array::from_fn(|k| drive.units().map(|u| u.chip[k].abs()).fold(0.0, f64::max));
        // Where the baseline models no load (a user's simulation of the outputs alone), the
        // outputs' own levels say how loaded a sample is: read by the load, no sample would be,
        // and any bend would pass for the calibration's.
        let level = |i: usize| -> f64 {
            if force_max > 0.0 {
                unit(i).force_n / force_max
            } else {
                (0..3)
                    .filter(|&k| chip_max[k] > 0.0)
                    .map(|k| unit(i).chip[k].abs() / chip_max[k])
                    .fold(0.0, f64::max)
            }
        };
        let loaded: Vec<usize> = (0..drive.len())
            .filter(|&i| level(i) >= LOADED_SHARE)
            .collect();
        let span = std::array::from_fn(|k| {
            blend_range * peak_to_peak(loaded.iter().map(|&i| drive.ln_map_departure(i)[k]))
        });
        let levels = loaded
            .iter()
            .map(|&i| {
                std::array::from_fn(|k| {
                    if chip_max[k] > 0.0 {
                        unit(i).chip[k] / chip_max[k]
                    } else {
                        0.0
                    }
                })
            })
            .collect();
        Self { levels, span }
    }

    /// B_k: the bend effect `kind` of strength `s` puts on output `k`; `None` for an effect that
    /// is not a static shape.
    pub fn bend(&self, kind: EffectKind, s: f64, k: usize) -> Option<f64> {
        let ln_factor: fn(f64, f64) -> f64 = match kind {
            EffectKind::Stiffening => |s, u| (s - 1.0) * u.abs().ln(),
            EffectKind::BridgeNonlinearity => |s, u| (1.0 + s * u).max(f64::MIN_POSITIVE).ln(),
            _ => return None,
        };
        let factors = self.levels.iter().map(|u| ln_factor(s, u[k]));
        Some(peak_to_peak(factors.filter(|v| v.is_finite())))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span_on(levels: &[f64]) -> Span {
        Span {
            levels: levels.iter().map(|&u| [u, -u, u]).collect(),
            span: [0.1; 3],
        }
    }

    /// Analytical cases: a power p over levels 0.05..1 bends by |p - 1| ln 20; a quadratic by
    /// ln((1 + q) / (1 + 0.05 q)), of either sign on a negative output.
    #[test]
    fn bends_follow_the_operators() {
        let s = span_on(&[0.05, 0.3, 1.0]);
        let b = s.bend(EffectKind::Stiffening, 1.2, 0).unwrap();
        assert!((b - 0.2 * 20f64.ln()).abs() < 1e-12);
        let q = s.bend(EffectKind::BridgeNonlinearity, 0.1, 0).unwrap();
        assert!((q - (1.1f64 / 1.005).ln()).abs() < 1e-12);
        let neg = s.bend(EffectKind::BridgeNonlinearity, 0.1, 1).unwrap();
        assert!((neg - (0.995f64 / 0.9).ln()).abs() < 1e-12);
        assert_eq!(s.bend(EffectKind::Stiffening, 1.0, 2), Some(0.0));
        assert_eq!(s.bend(EffectKind::Hysteresis, 0.1, 0), None);
    }
}
