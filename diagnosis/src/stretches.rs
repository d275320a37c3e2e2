//! The stretches of a recording: its regimes (found at the full rate with the load, carried
//! onto the decimated series) and the stretch held out of the fits.
use crate::data::Data;
use crate::regimes::{self, Segment};

/// The regimes of the test (found at the full rate with the load, carried onto the decimated
/// series) and the stretch held out of the fits.
#[derive(Clone)]
pub(crate) struct Stretches {
    pub(crate) segments: Vec<Segment>,
    /// Start and end of the held-out stretch, s.
    pub(crate) heldout: (f64, f64),
    /// The time that parts the fitted stretch from the held-out one, s.
    pub(crate) boundary_s: f64,
    /// Whether the start of the recording is held out (the end fitted) rather than its end.
    pub(crate) start_held_out: bool,
}

impl Stretches {
    pub(crate) fn detect(data: &Data) -> Self {
        let segments = data.segments.clone();
        let heldout = regimes::heldout_window(&data.fit.t_s, &segments);
        Self {
            segments,
            heldout,
            boundary_s: heldout.0,
            start_held_out: false,
        }
    }

    /// Hold out the start of the recording (up to the boundary) and fit its end instead.
    pub(crate) fn swap(&mut self, t_s: &[f64]) {
        let t0 = t_s.first().copied().unwrap_or(self.boundary_s);
        self.start_held_out = true;
        self.heldout = (t0, self.boundary_s);
    }

    /// Whether each time of `t_s` lies in the held-out stretch.
    pub(crate) fn mask(&self, t_s: &[f64]) -> Vec<bool> {
        t_s.iter()
            .map(|&t| (t >= self.boundary_s) != self.start_held_out)
            .collect()
    }
}
