//! Regimes of a compression test (rest, loading, hold, release, recovery) from the rod motion
//! and contact, and the held-out stretch chosen from them.

use serde::Serialize;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Regime {
    Rest,
    Loading,
    Hold,
    Release,
    Recovery,
}

impl Regime {
    pub fn name(self) -> &'static str {
        match self {
            Regime::Rest => "rest",
            Regime::Loading => "loading",
            Regime::Hold => "hold",
            Regime::Release => "release",
            Regime::Recovery => "recovery",
        }
    }
}

/// A run of samples in one regime: `start..end` (indices) on the series it was detected on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    pub regime: Regime,
    pub start: usize,
    pub end: usize,
    /// Which compression cycle (0-based) the segment belongs to.
    pub cycle: usize,
}

/// The regime of every sample of `rod_mm` on `t_s`, and the runs.
pub fn detect(t_s: &[f64], rod_mm: &[f64]) -> (Vec<Regime>, Vec<Segment>) {
    let n = t_s.len();
    let v: Vec<f64> = (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(2), (k + 2).min(n - 1));
            if t_s[b] > t_s[a] {
                (rod_mm[b] - rod_mm[a]) / (t_s[b] - t_s[a])
            } else {
                0.0
            }
        })
        .collect();
    let threshold = 0.25 * typical_speed(&v);
    let mut regimes = Vec::with_capacity(n);
    let mut released = false;
    for k in 0..n {
        let in_contact = rod_mm[k] > 0.0;
        let r = if v[k] > threshold && in_contact {
            released = false;
            Regime::Loading
        } else if v[k] < -threshold {
            released = true;
            Regime::Release
        } else if in_contact && !released {
            Regime::Hold
        } else if released {
            Regime::Recovery
        } else {
            Regime::Rest
        };
        regimes.push(r);
    }
    let mut segments: Vec<Segment> = Vec::new();
    let mut cycle = 0;
    for (k, &r) in regimes.iter().enumerate() {
        match segments.last_mut() {
            Some(s) if s.regime == r => s.end = k + 1,
            _ => {
                if r == Regime::Loading && segments.iter().any(|s| s.regime == Regime::Loading) {
                    cycle += 1;
                }
                segments.push(Segment {
                    regime: r,
                    start: k,
                    end: k + 1,
                    cycle,
                });
            }
        }
    }
    (regimes, segments)
}

/// The loading speed: median of the clearly positive rod velocities.
fn typical_speed(v: &[f64]) -> f64 {
    let max = v.iter().cloned().fold(0.0, f64::max);
    let mut pos: Vec<f64> = v.iter().copied().filter(|&x| x > 1e-3 * max).collect();
    if pos.is_empty() {
        return f64::INFINITY;
    }
    let mid = pos.len() / 2;
    *pos.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// The stretch never fitted to, as a time window: the second compression cycle when there are
/// two or more (from its loading to the end), otherwise the release and the recovery after it.
pub fn heldout_window(t_s: &[f64], segments: &[Segment]) -> (f64, f64) {
    let end = *t_s.last().unwrap_or(&0.0);
    if let Some(s) = segments
        .iter()
        .find(|s| s.cycle == 1 && s.regime == Regime::Loading)
    {
        return (t_s[s.start], end);
    }
    if let Some(s) = segments.iter().find(|s| s.regime == Regime::Release) {
        return (t_s[s.start], end);
    }
    // No release: hold out the last quarter.
    let start = t_s[0] + 0.75 * (end - t_s[0]);
    (start, end)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_test_regimes_in_order() {
        let h = sim::compression::CompressionTest {
            sample_rate_hz: 50.0,
            ..Default::default()
        }
        .rod_history(&[10.0, 6.0]);
        let (_, segs) = detect(&h.t_s, &h.rod_mm);
        let order: Vec<(Regime, usize)> = segs
            .iter()
            .filter(|s| s.end - s.start > 3)
            .map(|s| (s.regime, s.cycle))
            .collect();
        use Regime::*;
        assert_eq!(
            &order[..5],
            &[
                (Rest, 0),
                (Loading, 0),
                (Hold, 0),
                (Release, 0),
                (Recovery, 0)
            ]
        );
        assert_eq!(order[5], (Loading, 1));
        let (a, _) = heldout_window(&h.t_s, &segs);
        assert!(a > 90.0 && a < 100.0, "{a}");
    }
}
