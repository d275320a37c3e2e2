//! Auto-null: find, per bridge channel, the trim-DAC code that brings the amplified output nearest
//! mid-scale (ADC code 0), so the high-gain amplifier is never driven into its rails by the
//! bridge's raw offset. This replaces the lab rig's hand-turned potentiometers.
//!
//! Search: measure at both ends of the DAC range first; that fixes each channel's polarity (the
//! wiring decides whether a higher code raises or lowers the output) and shows whether mid-scale
//! is reachable at all. Then bisect: each step sets the middle code, waits `settle` samples for the
//! front end to settle, averages `average` samples and keeps the half whose ends still straddle
//! mid-scale. 12 bits → 12 bisection steps, 14 measurements in all; the three channels are
//! searched in parallel. The search is a state machine fed one sample at a time by the main loop,
//! so acquisition and streaming go on while it runs (status: Searching).

use crate::mcp4728::CODE_MAX;

/// Channels searched (the three bridges).
pub const CHANNELS: usize = 3;

/// Outcome reported in the status: Off (no search since power-up), Searching, Nulled (every
/// channel straddles mid-scale), Failed (a channel cannot reach mid-scale within the DAC range,
/// its code left at the end nearest mid-scale, or the DAC could not be written).
pub use protocol::NullState;

/// What the caller must do after a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NullStep {
    /// Keep feeding samples.
    Continue,
    /// Write these codes to the DAC, then keep feeding samples.
    SetDac([u16; CHANNELS]),
    /// Search over: write these final codes; the state is now Nulled or Failed.
    Done([u16; CHANNELS]),
}

/// Timing of one measurement.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NullTiming {
    /// Samples discarded after each DAC change.
    pub settle: u16,
    /// Samples averaged per measurement (at least 1).
    pub average: u16,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    LowEnd,
    HighEnd,
    Bisect,
}

/// The search state machine.
#[derive(Clone, Debug)]
pub struct AutoNull {
    timing: NullTiming,
    state: NullState,
    phase: Phase,
    /// Code under test per channel.
    trial: [u16; CHANNELS],
    /// Bracket [lo, hi] and the mean output measured at each end.
    lo: [u16; CHANNELS],
    hi: [u16; CHANNELS],
    out_lo: [i32; CHANNELS],
    out_hi: [i32; CHANNELS],
    reachable: [bool; CHANNELS],
    /// Codes in force (last written).
    codes: [u16; CHANNELS],
    skip: u16,
    sum: [i64; CHANNELS],
    count: u16,
}

impl AutoNull {
    /// Idle, with the DAC at `initial` codes.
    pub fn new(timing: NullTiming, initial: [u16; CHANNELS]) -> Self {
        Self {
            timing: NullTiming {
                settle: timing.settle,
                average: timing.average.max(1),
            },
            state: NullState::Off,
            phase: Phase::LowEnd,
            trial: initial,
            lo: [0; CHANNELS],
            hi: [CODE_MAX; CHANNELS],
            out_lo: [0; CHANNELS],
            out_hi: [0; CHANNELS],
            reachable: [false; CHANNELS],
            codes: initial,
            skip: 0,
            sum: [0; CHANNELS],
            count: 0,
        }
    }

    pub fn state(&self) -> NullState {
        self.state
    }

    /// The codes in force.
    pub fn codes(&self) -> [u16; CHANNELS] {
        self.codes
    }

    /// The search ended in failure outside the search itself (e.g. the DAC write failed).
    pub fn fail(&mut self) {
        self.state = NullState::Failed;
    }

    /// Begin a search; returns the first codes to write.
    pub fn start(&mut self) -> [u16; CHANNELS] {
        self.state = NullState::Searching;
        self.phase = Phase::LowEnd;
        self.lo = [0; CHANNELS];
        self.hi = [CODE_MAX; CHANNELS];
        self.set_trial([0; CHANNELS])
    }

    fn set_trial(&mut self, codes: [u16; CHANNELS]) -> [u16; CHANNELS] {
        self.trial = codes;
        self.codes = codes;
        self.skip = self.timing.settle;
        self.sum = [0; CHANNELS];
        self.count = 0;
        codes
    }

    /// Feed one sample of raw codes (before tare); returns what to do next.
    pub fn on_sample(&mut self, raw: [i32; CHANNELS]) -> NullStep {
        if self.state != NullState::Searching {
            return NullStep::Continue;
        }
        if self.skip > 0 {
            self.skip -= 1;
            return NullStep::Continue;
        }
        for (sum, &x) in self.sum.iter_mut().zip(&raw) {
            *sum += i64::from(x);
        }
        self.count += 1;
        if self.count < self.timing.average {
            return NullStep::Continue;
        }
        let mean: [i32; CHANNELS] =
            core::array::from_fn(|ch| (self.sum[ch] / i64::from(self.count)) as i32);
        self.measured(mean)
    }

    // Indexing by channel keeps the per-channel bracket arrays side by side, as in the algorithm.
    #[allow(clippy::needless_range_loop)]
    fn measured(&mut self, mean: [i32; CHANNELS]) -> NullStep {
        match self.phase {
            Phase::LowEnd => {
                self.out_lo = mean;
                self.phase = Phase::HighEnd;
                NullStep::SetDac(self.set_trial([CODE_MAX; CHANNELS]))
            }
            Phase::HighEnd => {
                self.out_hi = mean;
                for ch in 0..CHANNELS {
                    self.reachable[ch] = straddles(self.out_lo[ch], self.out_hi[ch]);
                }
                self.phase = Phase::Bisect;
                self.next_bisection()
            }
            Phase::Bisect => {
                for ch in 0..CHANNELS {
                    if self.reachable[ch] && self.hi[ch] - self.lo[ch] > 1 {
                        if straddles(self.out_lo[ch], mean[ch]) {
                            self.hi[ch] = self.trial[ch];
                            self.out_hi[ch] = mean[ch];
                        } else {
                            self.lo[ch] = self.trial[ch];
                            self.out_lo[ch] = mean[ch];
                        }
                    }
                }
                self.next_bisection()
            }
        }
    }

    fn next_bisection(&mut self) -> NullStep {
        let searching = (0..CHANNELS).any(|ch| self.reachable[ch] && self.hi[ch] - self.lo[ch] > 1);
        if searching {
            let trial = core::array::from_fn(|ch| {
                if self.reachable[ch] {
                    self.lo[ch] + (self.hi[ch] - self.lo[ch]) / 2
                } else {
                    self.lo[ch]
                }
            });
            return NullStep::SetDac(self.set_trial(trial));
        }
        // Final: per channel, the bracket end nearest mid-scale (for an unreachable channel, the
        // range end nearest mid-scale).
        let best = core::array::from_fn(|ch| {
            if self.out_lo[ch].unsigned_abs() <= self.out_hi[ch].unsigned_abs() {
                self.lo[ch]
            } else {
                self.hi[ch]
            }
        });
        self.codes = best;
        self.state = if self.reachable.iter().all(|&r| r) {
            NullState::Nulled
        } else {
            NullState::Failed
        };
        NullStep::Done(best)
    }
}

/// Whether mid-scale (0) lies between two outputs (inclusive).
fn straddles(a: i32, b: i32) -> bool {
    (a <= 0 && b >= 0) || (a >= 0 && b <= 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A front end: output = offset + slope · (code − 2048), clipped like a 24-bit ADC.
    fn output(offset: [i32; 3], slope: [i32; 3], codes: [u16; 3]) -> [i32; 3] {
        core::array::from_fn(|ch| {
            (offset[ch] + slope[ch] * (i32::from(codes[ch]) - 2048))
                .clamp(protocol::CODE_MIN, protocol::CODE_MAX)
        })
    }

    fn run(offset: [i32; 3], slope: [i32; 3]) -> (AutoNull, usize) {
        let mut null = AutoNull::new(
            NullTiming {
                settle: 2,
                average: 4,
            },
            [2048; 3],
        );
        let mut dac = null.start();
        for n in 0..10_000 {
            // The sample after a DAC write already sees the new code.
            match null.on_sample(output(offset, slope, dac)) {
                NullStep::Continue => {}
                NullStep::SetDac(c) => dac = c,
                NullStep::Done(c) => {
                    assert_eq!(c, null.codes());
                    return (null, n);
                }
            }
        }
        panic!("search did not end");
    }

    #[test]
    fn finds_the_code_nearest_mid_scale_for_either_polarity() {
        let offset = [2_500_000, -1_000_000, 10];
        let slope = [-3000, 1500, -700];
        let (null, samples) = run(offset, slope);
        assert_eq!(null.state(), NullState::Nulled);
        let residual = output(offset, slope, null.codes());
        for ch in 0..3 {
            // Nearest code: residual within half a code step.
            assert!(
                residual[ch].abs() <= slope[ch].abs() / 2 + 1,
                "ch {ch}: {residual:?}"
            );
        }
        // 14 measurements of settle + average samples.
        assert_eq!(samples + 1, 14 * 6);
    }

    #[test]
    fn unreachable_offset_fails_and_parks_at_the_nearest_end() {
        let (null, _) = run([8_000_000, 0, 0], [-100, -100, -100]);
        assert_eq!(null.state(), NullState::Failed);
        assert_eq!(null.codes()[0], CODE_MAX);
    }

    #[test]
    fn idle_search_ignores_samples() {
        let mut null = AutoNull::new(
            NullTiming {
                settle: 0,
                average: 1,
            },
            [7; 3],
        );
        assert_eq!(null.on_sample([1, 2, 3]), NullStep::Continue);
        assert_eq!(null.state(), NullState::Off);
        assert_eq!(null.codes(), [7; 3]);
    }
}
