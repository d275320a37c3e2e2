//! The rod trajectory cut into stationary stretches and monotone moves, with thresholds taken
//! from the rod's own noise and quantisation and from the size of the moves around them.
//!
//! 1. `band`: the rod's resolution. A quantised encoder flickers by one quantum between two
//!    levels and steps back by one quantum on a slow ramp, so a change must exceed two quanta;
//!    white noise (from second differences, which cancel the motion) must not leave the band
//!    over a long stationary stretch either.
//! 2. `still_stretches`: maximal runs that stay within the band.
//! 3. `accept_holds`: a still run is a hold only if it lasts a share [`HOLD_SHARE`] of the
//!    motion around it; shorter pauses (an encoder dwelling between quanta on a slow ramp, the
//!    turning point of a sinusoid, a servo pause) belong to the move.
//! 4. `merge_small_moves`: a move much smaller than its neighbours ([`SMALL_MOVE`]) is settling
//!    or creep inside a hold, not a protocol step.
//! 5. `legs`: each remaining move is split at reversals larger than [`SMALL_MOVE`] of its own
//!    extent (overshoot and back-steps stay in the leg they interrupt).

use crate::noise::difference_noise;
use crate::quantisation::{quantum, rounding};

/// A still run is a hold when it lasts at least this share of the motion between the holds
/// around it. Why a twentieth: a ramp read in N quanta dwells on each level 1/N of its
/// duration (up to 2/N within a band of two quanta), so ramps of more than 40 quanta never
/// stop (Static_data.txt's ramps are 393 quanta); a sinusoid's dwell at its turning points is
/// compared with the whole record of swings around it; the project's standard test holds 2 s
/// after ramps of a few seconds to 30 s (6 % and more).
pub const HOLD_SHARE: f64 = 0.05;
/// A move (or a reversal inside one) is a protocol step only if its extent exceeds this share
/// of its neighbours' (of its own move's). Why 5 %: a position servo overshoots by a few per
/// cent at most (0.9 % seen on a real rig) and settles back; unloading or staircase steps that a
/// tester programs are tens of per cent of the travel.
pub const SMALL_MOVE: f64 = 0.05;
/// Fewest samples a still run needs to be a hold: one sample has no level, two no trend.
const MIN_HOLD_SAMPLES: usize = 3;
/// Band in units of the rod's white noise: the range of m normal samples stays below
/// 2 sqrt(2 ln m) sigma, 11 sigma for m = 10^6 (300 s at 5 kHz would give 1.5e6 samples and
/// still 11.1), so 12 sigma keeps a noisy still rod inside one band.
const NOISE_BAND: f64 = 12.0;
/// Band in quanta: a flicker between two levels plus one back-step.
const QUANTUM_BAND: f64 = 2.0;

/// What the rod does over a piece.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    Still,
    Up,
    Down,
}

/// A piece `start..end` of the series.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Piece {
    pub motion: Motion,
    pub start: usize,
    pub end: usize,
}

/// The rod's resolution: the smallest change that is motion rather than noise or quantisation.
pub fn band(x: &[f64]) -> f64 {
    (QUANTUM_BAND * quantum(x) + NOISE_BAND * difference_noise(x)).max(rounding(x))
}

/// The rod cut into still stretches and monotone moves.
pub fn pieces(t: &[f64], x: &[f64]) -> Vec<Piece> {
    let n = x.len();
    if n == 0 {
        return Vec::new();
    }
    let h = band(x);
    let holds = accept_holds(t, &still_stretches(x, h));
    let holds = merge_small_moves(x, holds, h);
    let mut out = Vec::new();
    let mut at = 0;
    for (a, b) in holds {
        legs(x, at, a, h, &mut out);
        out.push(Piece {
            motion: Motion::Still,
            start: a,
            end: b,
        });
        at = b;
    }
    legs(x, at, n, h, &mut out);
    out
}

/// Maximal runs of at least [`MIN_HOLD_SAMPLES`] whose range stays within `h`.
fn still_stretches(x: &[f64], h: f64) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut a = 0;
    while a < x.len() {
        let (mut lo, mut hi) = (x[a], x[a]);
        let mut b = a + 1;
        while b < x.len() && hi.max(x[b]) - lo.min(x[b]) <= h {
            lo = lo.min(x[b]);
            hi = hi.max(x[b]);
            b += 1;
        }
        if b - a >= MIN_HOLD_SAMPLES {
            out.push((a, b));
        }
        a = b;
    }
    out
}

/// The still runs that are holds: longest first, each kept if it lasts [`HOLD_SHARE`] of the
/// time from the hold (or record end) before it to the hold (or end) after it; repeated until
/// nothing changes, since every kept hold shortens the motion around the others.
fn accept_holds(t: &[f64], still: &[(usize, usize)]) -> Vec<(usize, usize)> {
    let n = t.len();
    let dur = |a: usize, b: usize| t[b.min(n - 1)] - t[a.min(n - 1)];
    let mut order: Vec<usize> = (0..still.len()).collect();
    order.sort_by(|&i, &j| {
        dur(still[j].0, still[j].1 - 1).total_cmp(&dur(still[i].0, still[i].1 - 1))
    });
    let mut kept = std::collections::BTreeSet::<usize>::new();
    let mut changed = true;
    while changed {
        changed = false;
        for &i in &order {
            if kept.contains(&i) {
                continue;
            }
            let (a, b) = still[i];
            let before = kept.range(..i).next_back().map_or(0, |&j| still[j].1);
            let after = kept.range(i + 1..).next().map_or(n - 1, |&j| still[j].0);
            let around = dur(before, a) + dur(b, after);
            // The run's own duration, first to last sample.
            if dur(a, b - 1) >= HOLD_SHARE * around {
                kept.insert(i);
                changed = true;
            }
        }
    }
    kept.into_iter().map(|i| still[i]).collect()
}

/// Extent (max - min) of `x[a..b]`, 0 when empty.
fn extent(x: &[f64], a: usize, b: usize) -> f64 {
    let s = &x[a..b.max(a)];
    let hi = s.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let lo = s.iter().cloned().fold(f64::INFINITY, f64::min);
    if hi >= lo {
        hi - lo
    } else {
        0.0
    }
}

/// Join two holds when the move between them (including the holds' ends, so that a level
/// change counts) is within the band or under [`SMALL_MOVE`] of the larger neighbouring move:
/// settling, creep or encoder flicker inside one hold. Smallest moves first.
fn merge_small_moves(x: &[f64], mut holds: Vec<(usize, usize)>, h: f64) -> Vec<(usize, usize)> {
    loop {
        // Move k runs from the end of hold k-1 (or 0) to the start of hold k (or n).
        let n = x.len();
        let span = |k: usize, holds: &[(usize, usize)]| {
            let a = if k == 0 { 0 } else { holds[k - 1].0 };
            let b = if k == holds.len() { n } else { holds[k].1 };
            extent(x, a, b)
        };
        let moves: Vec<f64> = (0..=holds.len()).map(|k| span(k, &holds)).collect();
        // Only moves between two holds can be merged away.
        let candidate = (1..holds.len())
            .filter(|&k| {
                let neighbour = moves[k - 1].max(moves[k + 1]);
                moves[k] <= 2.0 * h || moves[k] < SMALL_MOVE * neighbour
            })
            .min_by(|&i, &j| moves[i].total_cmp(&moves[j]));
        let Some(k) = candidate else {
            return holds;
        };
        holds[k - 1].1 = holds[k].1;
        holds.remove(k);
    }
}

/// Monotone legs of the move `x[a..b]`, split at reversals larger than the band and than
/// [`SMALL_MOVE`] of the move's extent (a zig-zag with that threshold).
fn legs(x: &[f64], a: usize, b: usize, h: f64, out: &mut Vec<Piece>) {
    if b <= a {
        return;
    }
    // The move seen with the last sample before it and the first after it: a fast move can
    // fall between two samples of the still stretches around it.
    let (ea, eb) = (a.saturating_sub(1), (b + 1).min(x.len()));
    if extent(x, ea, eb) <= h {
        // Within the rod's resolution: no motion, whatever its length.
        out.push(Piece {
            motion: Motion::Still,
            start: a,
            end: b,
        });
        return;
    }
    let z = h.max(SMALL_MOVE * extent(x, ea, eb));
    let mut turns = vec![a];
    let mut dir = 0i8;
    let (mut hi, mut hi_i, mut lo, mut lo_i) = (x[a], a, x[a], a);
    for i in a + 1..b {
        if x[i] > hi {
            (hi, hi_i) = (x[i], i);
        }
        if x[i] < lo {
            (lo, lo_i) = (x[i], i);
        }
        if dir == 0 && hi - lo > z {
            dir = if hi_i > lo_i { 1 } else { -1 };
        } else if dir == 1 && hi - x[i] > z {
            turns.push(hi_i);
            dir = -1;
            (lo, lo_i) = lowest(x, hi_i, i);
        } else if dir == -1 && x[i] - lo > z {
            turns.push(lo_i);
            dir = 1;
            (hi, hi_i) = highest(x, lo_i, i);
        }
    }
    turns.push(b);
    // Legs alternate; the first goes the way the first confirmed swing went.
    let mut up = match dir {
        0 => x[eb - 1] >= x[ea],
        d => (d == 1) == (turns.len() % 2 == 0),
    };
    for w in turns.windows(2) {
        if w[1] > w[0] {
            out.push(Piece {
                motion: if up { Motion::Up } else { Motion::Down },
                start: w[0],
                end: w[1],
            });
        }
        up = !up;
    }
}

/// Lowest value of `x[a..=b]` and its index.
fn lowest(x: &[f64], a: usize, b: usize) -> (f64, usize) {
    (a..=b).fold(
        (f64::INFINITY, a),
        |m, i| if x[i] < m.0 { (x[i], i) } else { m },
    )
}

/// Highest value of `x[a..=b]` and its index.
fn highest(x: &[f64], a: usize, b: usize) -> (f64, usize) {
    (a..=b).fold((f64::NEG_INFINITY, a), |m, i| {
        if x[i] > m.0 {
            (x[i], i)
        } else {
            m
        }
    })
}
