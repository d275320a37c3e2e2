//! Rod paths a user runs besides the standard test.

use baseline::synth::{rod_at, SimSpec};

/// The rod path of a recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TestShape {
    /// The standard test's two cycles at the plan's rate.
    Standard,
    /// Three ramps to a third, two thirds and all of the peak, each held 8 s, one fast return.
    Staircase,
    /// Three triangles: up and down at the same slow speed, no hold, no rest between.
    Triangles,
    /// Two cycles, the first at 6 mm/min, the second at 60 mm/min.
    SpeedDecade,
    /// One cycle held 120 s before the fast return.
    LongHold,
    /// One ramp held to the end of the recording: no release at all.
    HoldToEnd,
    /// Two cycles between a preload (15 % of the peak) and the peak: in contact from the first
    /// sample, no rest.
    StartInContact,
    /// The standard test sampled at 20, 100 and 2000 Hz.
    Rate20Hz,
    Rate100Hz,
    Rate2kHz,
}

impl TestShape {
    pub const ALL: [TestShape; 9] = [
        TestShape::Staircase,
        TestShape::Triangles,
        TestShape::SpeedDecade,
        TestShape::LongHold,
        TestShape::HoldToEnd,
        TestShape::StartInContact,
        TestShape::Rate20Hz,
        TestShape::Rate100Hz,
        TestShape::Rate2kHz,
    ];

    pub fn name(self) -> &'static str {
        match self {
            TestShape::Standard => "standard",
            TestShape::Staircase => "staircase",
            TestShape::Triangles => "triangles",
            TestShape::SpeedDecade => "speeds a decade apart",
            TestShape::LongHold => "long hold",
            TestShape::HoldToEnd => "hold to the end",
            TestShape::StartInContact => "start in contact",
            TestShape::Rate20Hz => "20 Hz",
            TestShape::Rate100Hz => "100 Hz",
            TestShape::Rate2kHz => "2 kHz",
        }
    }

    /// The protocol unloads as slowly as it loads, so a loop between the two can show.
    pub fn unloads_slowly(self) -> bool {
        self == TestShape::Triangles
    }

    /// Its own sample rate, if it sets one.
    pub fn sample_rate_hz(self) -> Option<f64> {
        match self {
            TestShape::Rate20Hz => Some(20.0),
            TestShape::Rate100Hz => Some(100.0),
            TestShape::Rate2kHz => Some(2000.0),
            _ => None,
        }
    }

    /// The rod path as `(t_s, rod_mm)` waypoints for peak loads `peaks_n`, or None for the
    /// standard test's own path.
    pub fn waypoints(self, spec: &SimSpec, peaks_n: [f64; 2]) -> Option<Vec<(f64, f64)>> {
        let slow = spec.test.speed_mm_per_min / 60.0;
        let fast = spec.test.return_speed_mm_per_min / 60.0;
        let start = spec.test.start_rod_mm;
        let peak = rod_at(spec, peaks_n[0]);
        let mut p = Path::new(start, 2.0);
        match self {
            TestShape::Staircase => {
                for share in [1.0 / 3.0, 2.0 / 3.0, 1.0] {
                    p.move_to(rod_at(spec, share * peaks_n[0]), slow);
                    p.hold(8.0);
                }
                p.move_to(start, fast);
                p.hold(40.0);
            }
            TestShape::Triangles => {
                for _ in 0..3 {
                    p.move_to(peak, slow);
                    p.move_to(start, slow);
                }
                p.hold(20.0);
            }
            TestShape::SpeedDecade => {
                for (to, speed) in [(rod_at(spec, peaks_n[1]), slow * 0.3), (peak, slow * 3.0)] {
                    p.move_to(to, speed);
                    p.hold(2.0);
                    p.move_to(start, fast);
                    p.hold(30.0);
                }
            }
            TestShape::LongHold | TestShape::HoldToEnd => {
                p.move_to(peak, slow);
                p.hold(if self == TestShape::LongHold {
                    120.0
                } else {
                    150.0
                });
                if self == TestShape::LongHold {
                    p.move_to(start, fast);
                    p.hold(40.0);
                }
            }
            TestShape::StartInContact => {
                let preload = rod_at(spec, 0.15 * peaks_n[0]);
                p = Path::new(preload, 0.0);
                for to in [peak, rod_at(spec, peaks_n[1])] {
                    p.move_to(to, slow);
                    p.hold(2.0);
                    p.move_to(preload, fast);
                    p.hold(25.0);
                }
            }
            _ => return None,
        }
        Some(p.points)
    }
}

/// Waypoints built move by move.
struct Path {
    points: Vec<(f64, f64)>,
}

impl Path {
    fn new(rod_mm: f64, rest_s: f64) -> Self {
        Path {
            points: vec![(0.0, rod_mm), (rest_s, rod_mm)],
        }
    }

    fn last(&self) -> (f64, f64) {
        self.points[self.points.len() - 1]
    }

    fn move_to(&mut self, rod_mm: f64, speed_mm_per_s: f64) {
        let (t, r) = self.last();
        self.points
            .push((t + (rod_mm - r).abs() / speed_mm_per_s, rod_mm));
    }

    fn hold(&mut self, s: f64) {
        let (t, r) = self.last();
        self.points.push((t + s, r));
    }
}
