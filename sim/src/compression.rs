//! The standard compression test's rod history (`docs/diagnosis-format.md`, `simulate`): the rod waits
//! at its start, moves in at 20 mm/min until the load reaches the peak, holds 2 s, returns at
//! 600 mm/min to its start and the fingertip recovers for 60 s; optionally several cycles.

/// The test protocol. Speeds in mm/min as the micro-tester is set.
#[derive(Debug, Clone, PartialEq)]
pub struct RodSchedule {
    pub sample_rate_hz: f64,
    /// Rod travel at the start, negative: the rod starts clear of the fingertip.
    pub start_rod_mm: f64,
    /// Time at the start before the rod moves.
    pub rest_s: f64,
    pub speed_mm_per_min: f64,
    pub hold_s: f64,
    pub return_speed_mm_per_min: f64,
    pub recovery_s: f64,
}

impl Default for RodSchedule {
    /// The standard test of the contract.
    fn default() -> Self {
        Self {
            sample_rate_hz: 1000.0,
            start_rod_mm: -0.5,
            rest_s: 2.0,
            speed_mm_per_min: 20.0,
            hold_s: 2.0,
            return_speed_mm_per_min: 600.0,
            recovery_s: 60.0,
        }
    }
}

/// A straight piece of the rod path.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Segment {
    t0_s: f64,
    t1_s: f64,
    rod0_mm: f64,
    rod1_mm: f64,
}

/// Sampled rod history.
#[derive(Debug, Clone, PartialEq)]
pub struct RodHistory {
    pub t_s: Vec<f64>,
    pub rod_mm: Vec<f64>,
}

impl RodHistory {
    /// A straight-line rod path through `(t_s, rod_mm)` waypoints (times non-decreasing, the
    /// first at 0), sampled at `sample_rate_hz` from 0 to the last waypoint: any protocol of
    /// ramps, holds and returns (staircases, triangles, a start in contact) is a list of them.
    pub fn from_waypoints(sample_rate_hz: f64, waypoints: &[(f64, f64)]) -> Self {
        let end_s = waypoints.last().map_or(0.0, |w| w.0);
        let n = (end_s * sample_rate_hz).floor() as usize + 1;
        let t_s: Vec<f64> = (0..n).map(|k| k as f64 / sample_rate_hz).collect();
        let mut i = 0;
        let rod_mm = t_s
            .iter()
            .map(|&t| {
                while i + 2 < waypoints.len() && t > waypoints[i + 1].0 {
                    i += 1;
                }
                let Some(&(t1, r1)) = waypoints.get(i + 1) else {
                    return waypoints.first().map_or(0.0, |w| w.1);
                };
                let (t0, r0) = waypoints[i];
                let u = if t1 > t0 {
                    ((t - t0) / (t1 - t0)).clamp(0.0, 1.0)
                } else {
                    1.0
                };
                r0 + u * (r1 - r0)
            })
            .collect();
        RodHistory { t_s, rod_mm }
    }
}

impl RodSchedule {
    /// The rod path for one cycle per entry of `turn_rod_mm` (the travel at which the load
    /// reaches each cycle's peak), sampled at `sample_rate_hz`.
    pub fn rod_history(&self, turn_rod_mm: &[f64]) -> RodHistory {
        let segments = self.segments(turn_rod_mm);
        let mut waypoints = vec![(0.0, self.start_rod_mm)];
        waypoints.extend(segments.iter().map(|s| (s.t1_s, s.rod1_mm)));
        RodHistory::from_waypoints(self.sample_rate_hz, &waypoints)
    }

    /// For each cycle of [`Self::rod_history`]`(turn_rod_mm)`, the time its loading starts and
    /// the time its hold ends, s: the stretch in which the cycle's peak load is recorded.
    pub fn loading_and_hold_s(&self, turn_rod_mm: &[f64]) -> Vec<(f64, f64)> {
        // Four segments a cycle after the first rest: loading, hold, return, recovery.
        self.segments(turn_rod_mm)[1..]
            .chunks(4)
            .map(|c| (c[0].t0_s, c[1].t1_s))
            .collect()
    }

    fn segments(&self, turn_rod_mm: &[f64]) -> Vec<Segment> {
        let mut out = Vec::new();
        let mut t = 0.0;
        let mut push = |dt: f64, a: f64, b: f64, t: &mut f64| {
            out.push(Segment {
                t0_s: *t,
                t1_s: *t + dt,
                rod0_mm: a,
                rod1_mm: b,
            });
            *t += dt;
        };
        let start = self.start_rod_mm;
        push(self.rest_s, start, start, &mut t);
        for &turn in turn_rod_mm {
            let travel = (turn - start).max(0.0);
            push(travel / self.speed_mm_per_min * 60.0, start, turn, &mut t);
            push(self.hold_s, turn, turn, &mut t);
            push(
                travel / self.return_speed_mm_per_min * 60.0,
                turn,
                start,
                &mut t,
            );
            push(self.recovery_s, start, start, &mut t);
        }
        out
    }
}

/// The rod travel at which the monotone `force_at(rod_mm)` first reaches `load_n`, by bisection
/// between 0 and `max_rod_mm`.
pub fn rod_at_load(force_at: impl Fn(f64) -> f64, load_n: f64, max_rod_mm: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, max_rod_mm);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if force_at(mid) < load_n {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_test_timeline() {
        let test = RodSchedule::default();
        let h = test.rod_history(&[10.0]);
        // 2 s rest, 10.5 mm at 20 mm/min = 31.5 s, 2 s hold, 1.05 s return, 60 s recovery.
        let end = 2.0 + 31.5 + 2.0 + 1.05 + 60.0;
        assert!((h.t_s.last().unwrap() - end).abs() < 1e-3);
        let at = |t: f64| h.rod_mm[(t * 1000.0).round() as usize];
        assert_eq!(at(1.0), -0.5);
        assert!((at(2.0 + 15.75) - 4.75).abs() < 1e-9);
        assert!((at(34.0) - 10.0).abs() < 1e-9);
        assert!((at(2.0 + 31.5 + 2.0 + 0.525) - 4.75).abs() < 1e-6);
        assert_eq!(at(40.0), -0.5);
    }

    #[test]
    fn each_cycle_loads_and_holds_where_the_history_says() {
        let test = RodSchedule::default();
        let spans = test.loading_and_hold_s(&[10.0, 4.5]);
        assert_eq!(spans.len(), 2);
        assert!((spans[0].0 - 2.0).abs() < 1e-12);
        assert!((spans[0].1 - (2.0 + 31.5 + 2.0)).abs() < 1e-9);
        // The second starts after the first's return and recovery, and loads 5 mm.
        let second = 2.0 + 31.5 + 2.0 + 1.05 + 60.0;
        assert!((spans[1].0 - second).abs() < 1e-9);
        assert!((spans[1].1 - (second + 15.0 + 2.0)).abs() < 1e-9);
    }

    #[test]
    fn bisection_finds_the_turn() {
        let r = rod_at_load(|d| 2.0 * d * d, 50.0, 100.0);
        assert!((r - 5.0).abs() < 1e-9);
    }
}
