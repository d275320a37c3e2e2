//! Regimes of a compression test (rest, loading, hold, release, recovery) from the rod motion
//! (and, when given, the load), the cycles they form, a summary of the protocol and the
//! held-out stretch chosen from it.
//!
//! The rod is cut into still stretches and monotone moves ([`motion`]) with thresholds from
//! the rod's own noise and quantisation, so encoder back-steps, quantised slow ramps, overshoot
//! and settling do not create regimes. Moves up are loading, moves down release. A still
//! stretch is rest before any loading (hold if the load shows contact from the first sample),
//! hold after a loading, and after a release recovery once the rod is back near its lowest
//! level (hold if it is still pressed in: a staircase down). A cycle is a loading followed
//! later by a release: a staircase of ramps and holds is one cycle; a sinusoid gives one cycle
//! per period (rising leg, falling leg), split at reversals that exceed the rod's resolution and
//! a twentieth of the swing.

pub mod motion;
mod protocol;

use serde::Serialize;

use motion::{Motion, Piece};
pub use protocol::heldout_window;
#[cfg(test)]
pub use protocol::{protocol, HeldoutKind, Protocol};

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

/// The regime of every sample of `rod_mm` on `t_s`, and the runs. The rod alone cannot tell a
/// preloaded start from a free one: a still start is rest; see [`detect_with_load`].
#[cfg(test)]
pub fn detect(t_s: &[f64], rod_mm: &[f64]) -> (Vec<Regime>, Vec<Segment>) {
    detect_with_load(t_s, rod_mm, None)
}

/// As [`detect`], with the load (same length) telling whether the test starts in contact.
/// Bad input (lengths that differ, unsorted time, no finite rod value) gives one rest segment
/// over everything rather than a guess.
pub fn detect_with_load(
    t_s: &[f64],
    rod_mm: &[f64],
    load: Option<&[f64]>,
) -> (Vec<Regime>, Vec<Segment>) {
    let n = t_s.len();
    if n == 0 {
        return (Vec::new(), Vec::new());
    }
    let sane = rod_mm.len() == n
        && load.is_none_or(|l| l.len() == n)
        && t_s.windows(2).all(|w| w[1] >= w[0])
        && t_s.iter().all(|t| t.is_finite());
    let rod = sane.then(|| finite_filled(rod_mm)).flatten();
    let Some(rod) = rod else {
        let all = Segment {
            regime: Regime::Rest,
            start: 0,
            end: n,
            cycle: 0,
        };
        return (vec![Regime::Rest; n], vec![all]);
    };
    let pieces = motion::pieces(t_s, &rod);
    let mut segments = label(&rod, &pieces);
    if load.is_some_and(|l| starts_in_contact(&rod, l, &segments)) {
        // A still start under a preload is a hold, not a rest.
        if let Some(first) = segments.first_mut().filter(|s| s.regime == Regime::Rest) {
            first.regime = Regime::Hold;
        }
    }
    let mut regimes = vec![Regime::Rest; n];
    for s in &segments {
        regimes[s.start..s.end].fill(s.regime);
    }
    (regimes, segments)
}

/// `x` with each non-finite value replaced by the last finite one before it (the first finite
/// one at the start); `None` when nothing is finite.
fn finite_filled(x: &[f64]) -> Option<Vec<f64>> {
    let mut last = *x.iter().find(|v| v.is_finite())?;
    Some(
        x.iter()
            .map(|&v| {
                if v.is_finite() {
                    last = v;
                }
                last
            })
            .collect(),
    )
}

/// Mean of `x[a..b]`.
fn mean(x: &[f64], a: usize, b: usize) -> f64 {
    x[a..b].iter().sum::<f64>() / (b - a).max(1) as f64
}

/// Whether `load` shows contact from the first sample of the `segments` found on `rod`: it
/// starts clearly above zero (a preload: `NOISE_SIGMAS` noise levels and a twentieth of its
/// later rise) and it answers the first move at once (within the first twentieth of its
/// travel), which a load-cell offset with the rod still clear of the sample does not. False
/// when the lengths differ or no load value is finite.
pub fn starts_in_contact(rod: &[f64], load: &[f64], segments: &[Segment]) -> bool {
    let Some(load) = finite_filled(load).filter(|l| l.len() == rod.len() && !l.is_empty()) else {
        return false;
    };
    if segments.last().is_some_and(|s| s.end > rod.len()) {
        return false;
    }
    let is_move = |s: &&Segment| matches!(s.regime, Regime::Loading | Regime::Release);
    let sigma = crate::noise::difference_noise(&load);
    let first = segments.first().map_or(
        load.len(),
        |s| {
            if is_move(&s) {
                s.start + 1
            } else {
                s.end
            }
        },
    );
    let start = mean(&load, 0, first.clamp(1, load.len()));
    let peak = load.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    if start <= NOISE_SIGMAS * sigma || start <= motion::SMALL_MOVE * (peak - start) {
        return false;
    }
    let Some(m) = segments.iter().find(is_move) else {
        return true;
    };
    let travel = (rod[m.end - 1] - rod[m.start]).abs();
    let early = (m.start..m.end)
        .find(|&k| (rod[k] - rod[m.start]).abs() >= motion::SMALL_MOVE * travel)
        .unwrap_or(m.end - 1);
    (load[early] - load[m.start]).abs() > NOISE_SIGMAS * sigma
}

/// A load change this many noise levels from zero is not noise (one in 10^9 for a normal law).
const NOISE_SIGMAS: f64 = 6.0;

/// Regimes and cycles of the pieces (a still start is rest; see `starts_in_contact`).
fn label(rod: &[f64], pieces: &[Piece]) -> Vec<Segment> {
    let lowest = rod.iter().cloned().fold(f64::INFINITY, f64::min);
    let range = rod.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - lowest;
    let mut last_move: Option<Motion> = None;
    let (mut cycle, mut released) = (0, false);
    let mut out: Vec<Segment> = Vec::new();
    for p in pieces {
        let regime = match (p.motion, last_move) {
            (Motion::Up, _) => Regime::Loading,
            (Motion::Down, _) => Regime::Release,
            (Motion::Still, None) => Regime::Rest,
            (Motion::Still, Some(Motion::Down))
                if mean(rod, p.start, p.end) - lowest <= motion::SMALL_MOVE * range =>
            {
                Regime::Recovery
            }
            (Motion::Still, _) => Regime::Hold,
        };
        if p.motion != Motion::Still {
            last_move = Some(p.motion);
        }
        if regime == Regime::Loading && released {
            cycle += 1;
            released = false;
        }
        released |= regime == Regime::Release;
        match out.last_mut() {
            Some(s) if s.regime == regime => s.end = p.end,
            _ => out.push(Segment {
                regime,
                start: p.start,
                end: p.end,
                cycle,
            }),
        }
    }
    out
}

#[cfg(test)]
mod tests_mach1;
#[cfg(test)]
mod tests_rigs;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_test_regimes_in_order() {
        let h = sim::compression::RodSchedule {
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
