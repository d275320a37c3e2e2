//! What the protocol of a recording allows to test, and the held-out stretch chosen from it.

use serde::Serialize;

use super::{Regime, Segment};

/// Moves whose speeds differ by more than this factor make a rate change. Why 2: a speed from
/// travel over duration is good to a sample at each end, a few per cent on any move worth a
/// segment; a viscoelastic response differs visibly only when the rate changes by a good
/// factor (the loss follows the logarithm of the rate for a spread of relaxation times).
#[cfg(test)]
const RATE_RATIO: f64 = 2.0;
/// The held-out stretch leaves at least half of the record to the calibration...
const MAX_HELDOUT_SHARE: f64 = 0.5;
/// ...and holds at least a tenth of it, so that its misfit rests on enough samples.
const MIN_HELDOUT_SHARE: f64 = 0.1;
/// Share of the last hold (or ramp) held out when nothing follows: the last third. The fit
/// keeps the first two thirds, where most of a relaxation happens and every time scale shorter
/// than the hold shows its curvature; the last third tests the extrapolation of the slow decay,
/// which is what a relaxation model must get right and a static map cannot mimic.
const TAIL_SHARE: f64 = 1.0 / 3.0;

/// Which stretch was held out, and why.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum HeldoutKind {
    /// Several cycles: the last one, from its loading to the end.
    LastCycle,
    /// One cycle with an unloading: the release and the recovery after it.
    ReleaseAndRecovery,
    /// No unloading: the last third of the last hold (and anything after it).
    EndOfHold,
    /// Loading only, no hold: the last third of the last ramp. The recording cannot separate
    /// rate effects from the static response.
    EndOfRamp,
    /// No motion: the last quarter.
    EndOfRecord,
}

/// What the regimes of a recording contain (the regime tests read it; the diagnosis reads the
/// held-out stretch alone, [`heldout`], and its preconditions from [`crate::preconditions`]):
/// the preconditions of the effects a diagnosis may
/// name (no hysteresis without an unloading, no relaxation without a hold or a rate change).
#[cfg(test)]
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Protocol {
    /// Compression cycles (a loading followed later by a release; a staircase is one).
    pub cycles: usize,
    /// Loading, hold and release segments.
    pub loadings: usize,
    pub holds: usize,
    pub releases: usize,
    pub has_hold: bool,
    pub has_unloading: bool,
    /// Two moves whose speeds differ by more than a factor `RATE_RATIO` (2).
    pub has_rate_change: bool,
    /// Mean speed of each move (loading and release), in order, mm/s.
    pub rates_mm_per_s: Vec<f64>,
    /// The load shows contact from the first sample (a preload; false without a load).
    pub starts_in_contact: bool,
    /// A hold or a rate change: a rate effect (relaxation) can be told from the static
    /// response. False for a single ramp at one speed with nothing after it.
    pub separates_rate_effects: bool,
    /// The held-out window, s, and why it was chosen.
    pub heldout: (f64, f64),
    pub heldout_kind: HeldoutKind,
}

/// The protocol of `segments` found on `t_s`, `rod_mm` (and `load`, which alone can tell a
/// start in contact).
#[cfg(test)]
pub fn protocol(
    t_s: &[f64],
    rod_mm: &[f64],
    load: Option<&[f64]>,
    segments: &[Segment],
) -> Protocol {
    let count = |r: Regime| segments.iter().filter(|s| s.regime == r).count();
    let rates: Vec<f64> = segments
        .iter()
        .filter(|s| matches!(s.regime, Regime::Loading | Regime::Release))
        .filter_map(|s| speed(t_s, rod_mm, s))
        .collect();
    let fastest = rates.iter().cloned().fold(0.0, f64::max);
    let slowest = rates.iter().cloned().fold(f64::INFINITY, f64::min);
    let has_rate_change = slowest > 0.0 && fastest > RATE_RATIO * slowest;
    let has_hold = count(Regime::Hold) > 0;
    let (a, b, kind) = heldout(t_s, segments);
    Protocol {
        cycles: segments.iter().map(|s| s.cycle + 1).max().unwrap_or(0),
        loadings: count(Regime::Loading),
        holds: count(Regime::Hold),
        releases: count(Regime::Release),
        has_hold,
        has_unloading: count(Regime::Release) > 0,
        has_rate_change,
        rates_mm_per_s: rates,
        starts_in_contact: load.is_some_and(|l| super::starts_in_contact(rod_mm, l, segments)),
        separates_rate_effects: has_hold || has_rate_change,
        heldout: (a, b),
        heldout_kind: kind,
    }
}

/// Speed of a move, mm/s: 80 % of its travel over the time from 10 % to 90 % of it, so that a
/// still start or a settling end inside the move does not slow it down (a sinusoid's half and
/// quarter swings then differ by 10 %, not by the factor a mean over the whole leg gives).
#[cfg(test)]
fn speed(t_s: &[f64], rod_mm: &[f64], s: &Segment) -> Option<f64> {
    let last = s.end.min(t_s.len()).min(rod_mm.len()).checked_sub(1)?;
    let (x0, x1) = (rod_mm[s.start], rod_mm[last]);
    let progress = |k: usize| (rod_mm[k] - x0) / (x1 - x0);
    let at = |share: f64| (s.start..=last).find(|&k| progress(k) >= share);
    let (a, b) = (at(0.1)?, at(0.9)?);
    let dt = t_s[b] - t_s[a];
    (dt > 0.0).then(|| 0.8 * (x1 - x0).abs() / dt)
}

/// The stretch never fitted to, as a time window that runs to the end of the record (see
/// [`heldout`]).
pub fn heldout_window(t_s: &[f64], segments: &[Segment]) -> (f64, f64) {
    let (a, b, _) = heldout(t_s, segments);
    (a, b)
}

/// The held-out window and its kind: the last cycle when there are several; else the release
/// and recovery (at most the last half of the record); else the last third of the last hold;
/// else the last third of the last ramp; else the last quarter. Never less than the last tenth.
pub fn heldout(t_s: &[f64], segments: &[Segment]) -> (f64, f64, HeldoutKind) {
    let (Some(&t0), Some(&end)) = (t_s.first(), t_s.last()) else {
        return (0.0, 0.0, HeldoutKind::EndOfRecord);
    };
    let span = end - t0;
    if span.is_nan() || span <= 0.0 {
        // No duration (or time running backwards): nothing can be held out.
        return (end, end, HeldoutKind::EndOfRecord);
    }
    let at = |k: usize| t_s[k.min(t_s.len() - 1)];
    let last = |r: Regime| segments.iter().rev().find(|s| s.regime == r);
    let tail = |s: &Segment| at(s.start) + (1.0 - TAIL_SHARE) * (at(s.end) - at(s.start));
    let last_cycle = segments.iter().map(|s| s.cycle).max().unwrap_or(0);
    let first_release = segments.iter().find(|s| s.regime == Regime::Release);
    let (start, kind) = if last_cycle > 0 {
        let s = segments.iter().find(|s| s.cycle == last_cycle);
        (s.map_or(end, |s| at(s.start)), HeldoutKind::LastCycle)
    } else if let Some(s) = first_release {
        let start = at(s.start).max(t0 + (1.0 - MAX_HELDOUT_SHARE) * span);
        (start, HeldoutKind::ReleaseAndRecovery)
    } else if let Some(s) = last(Regime::Hold) {
        (tail(s), HeldoutKind::EndOfHold)
    } else if let Some(s) = last(Regime::Loading) {
        (tail(s), HeldoutKind::EndOfRamp)
    } else {
        (t0 + 0.75 * span, HeldoutKind::EndOfRecord)
    };
    (start.min(end - MIN_HELDOUT_SHARE * span), end, kind)
}
