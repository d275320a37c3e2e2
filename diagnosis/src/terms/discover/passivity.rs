//! Admissible physics: a passive material cannot give back work over a closed loading cycle.
//! A term that the material would carry (on the load, the outputs following or not) adds a
//! force dF(t) to what the rod meets; over cycles that start and end with the rod out of
//! contact its work is
//!
//! ```text
//! W = ∮ dF dx   (N·mm; > 0: the material absorbs it, as any loss does)
//! ```
//!
//! A static law of the travel gives W = 0, a relaxation, a hysteresis or a friction W > 0. A
//! term with W < 0 opens its loop the wrong way, as a reading that lags the rod does (the load
//! cell's or the logger's timing): it is not the material's but the instrument's, and the stage
//! says so and why.

/// What the loop of a term's load part does over the recording's closed cycles.
pub(super) struct Loop {
    /// The work the term does on the rod over the closed cycles (N·mm): negative where the
    /// material would give work back.
    pub work_nmm: f64,
    /// The closed loading cycles it was summed over.
    pub cycles: usize,
    /// The work a loop as wide as the term's whole swing would do over those cycles, the scale
    /// against which `work_nmm` is read.
    pub scale_nmm: f64,
}

impl Loop {
    /// A loop that gives back more than the discretisation of a static law can make up: a
    /// trapezoid rule over the blocks leaves a static law's closed integral at a few tenths of
    /// a percent of its swing times the travel, far below this percent.
    pub fn gives_back_work(&self) -> bool {
        self.work_nmm < -0.01 * self.scale_nmm
    }
}

/// ∮ part dx over the closed cycles of the travel `x` (contract's travel: zero at first
/// contact), by the trapezoid rule; `None` without two stretches out of contact around a press.
pub(super) fn cycle_work(x: &[f64], part: &[f64]) -> Option<Loop> {
    let free: Vec<usize> = (0..x.len()).filter(|&k| x[k] <= 0.0).collect();
    let (&first, &last) = (free.first()?, free.last()?);
    let top = x.iter().copied().fold(0.0f64, f64::max);
    if top <= 0.0 || last <= first + 2 {
        return None;
    }
    let mut work = 0.0;
    let mut cycles = 0;
    let mut pressed = false;
    for k in first..last {
        work += 0.5 * (part[k] + part[k + 1]) * (x[k + 1] - x[k]);
        if !pressed && x[k + 1] > 0.5 * top {
            cycles += 1;
        }
        pressed = x[k + 1] > 0.5 * top || (pressed && x[k + 1] > 0.0);
    }
    if cycles == 0 {
        return None;
    }
    let swing = part[first..=last]
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    Some(Loop {
        work_nmm: work,
        cycles,
        scale_nmm: (swing.1 - swing.0) * top * cycles as f64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ten presses of a triangle wave in travel, out of contact between them.
    fn presses() -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..4000).map(|k| k as f64 * 0.01).collect();
        let x = t
            .iter()
            .map(|&t| {
                let phase = (t / 4.0).fract();
                12.0 * (1.0 - (2.0 * phase - 1.0).abs()) - 1.0
            })
            .collect();
        (t, x)
    }

    fn lagged(t: &[f64], x: &[f64], lag_s: f64) -> Vec<f64> {
        t.iter()
            .map(|&s| {
                sim::effects::interpolate(t, x, s - lag_s)
                    .max(0.0)
                    .powf(1.5)
            })
            .collect()
    }

    #[test]
    fn a_lag_gives_back_work_and_a_relaxation_or_a_static_law_does_not() {
        let (t, x) = presses();
        let load = lagged(&t, &x, 0.0);
        // A reading that lags the rod by 0.3 s, less the load itself: the part a lag adds.
        let late: Vec<f64> = lagged(&t, &x, 0.3)
            .iter()
            .zip(&load)
            .map(|(l, f)| l - f)
            .collect();
        let lag = cycle_work(&x, &late).unwrap();
        assert_eq!(lag.cycles, 10);
        assert!(
            lag.gives_back_work(),
            "{} of {}",
            lag.work_nmm,
            lag.scale_nmm
        );
        // Ahead of the rod (a force higher while loading than unloading): a loss.
        let early: Vec<f64> = late.iter().map(|v| -v).collect();
        let loss = cycle_work(&x, &early).unwrap();
        assert!(loss.work_nmm > 0.0 && !loss.gives_back_work());
        // A static law of the travel: no work over a closed cycle.
        let square: Vec<f64> = load.iter().map(|l| 0.1 * l * l).collect();
        let still = cycle_work(&x, &square).unwrap();
        assert!(!still.gives_back_work(), "{}", still.work_nmm);
        assert!(still.work_nmm.abs() < 1e-3 * still.scale_nmm);
    }

    #[test]
    fn a_ramp_has_no_closed_cycle() {
        let x: Vec<f64> = (0..500).map(|k| k as f64 * 0.02 - 1.0).collect();
        assert!(cycle_work(&x, &vec![1.0; 500]).is_none());
    }
}
