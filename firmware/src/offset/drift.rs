//! Slow drift tracking: while a channel is unloaded (its tared value within `window` codes of
//! zero), move a correction towards it by a fraction `rate` per sample; the correction never
//! exceeds `limit` codes in magnitude. Off by default; when on, the status says so and the info
//! frame reports the correction, so it is never silent. Loaded samples (outside the window) are
//! left alone: a held load must not be tracked away.

use super::CHANNELS;

/// Settings of the tracker.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DriftSettings {
    /// |tared code| below which a channel counts as unloaded.
    pub window: i32,
    /// Fraction of the residual absorbed per unloaded sample (time constant 1/rate samples).
    pub rate: f32,
    /// Largest correction magnitude, codes.
    pub limit: i32,
}

/// Tracker state.
#[derive(Clone, Debug, PartialEq)]
pub struct DriftTracker {
    settings: DriftSettings,
    enabled: bool,
    correction: [f32; CHANNELS],
}

impl DriftTracker {
    pub fn new(settings: DriftSettings) -> Self {
        Self {
            settings,
            enabled: false,
            correction: [0.0; CHANNELS],
        }
    }

    pub fn enabled(&self) -> bool {
        self.enabled
    }

    /// Switch on or off; switching clears the correction.
    pub fn set_enabled(&mut self, enabled: bool) {
        self.enabled = enabled;
        self.correction = [0.0; CHANNELS];
    }

    /// The correction in codes, rounded.
    pub fn correction(&self) -> [i32; CHANNELS] {
        self.correction.map(|c| libm::roundf(c) as i32)
    }

    /// Whether any channel's correction sits at the limit.
    pub fn at_limit(&self) -> bool {
        let limit = self.settings.limit as f32;
        self.correction.iter().any(|c| c.abs() >= limit)
    }

    /// Apply to a tared sample: returns the corrected sample and updates the tracker.
    #[inline]
    pub fn apply(&mut self, tared: [i32; CHANNELS]) -> [i32; CHANNELS] {
        if !self.enabled {
            return tared;
        }
        let limit = self.settings.limit as f32;
        core::array::from_fn(|ch| {
            let residual = tared[ch] as f32 - self.correction[ch];
            if residual.abs() < self.settings.window as f32 {
                // max/min rather than f32::clamp: clamp's NaN/ordering panic would pull float
                // formatting (~20 KiB of flash) into the firmware.
                self.correction[ch] = (self.correction[ch] + self.settings.rate * residual)
                    .max(-limit)
                    .min(limit);
            }
            // Nearest integer (halves away from zero) with the FPU's conversion, not libm.
            let c = self.correction[ch];
            tared[ch] - (if c >= 0.0 { c + 0.5 } else { c - 0.5 }) as i32
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tracker() -> DriftTracker {
        let mut t = DriftTracker::new(DriftSettings {
            window: 1000,
            rate: 0.01,
            limit: 300,
        });
        t.set_enabled(true);
        t
    }

    #[test]
    fn tracks_a_slow_offset_while_unloaded() {
        let mut t = tracker();
        let mut out = [0; 3];
        for _ in 0..2000 {
            out = t.apply([200, -150, 0]);
        }
        assert_eq!(t.correction(), [200, -150, 0]);
        assert_eq!(out, [0, 0, 0]);
    }

    #[test]
    fn correction_is_bounded_and_load_is_not_tracked() {
        let mut t = tracker();
        for _ in 0..5000 {
            t.apply([900, 50_000, 0]);
        }
        assert_eq!(t.correction()[0], 300);
        assert!(t.at_limit());
        assert_eq!(t.correction()[1], 0, "a loaded channel stays untouched");
    }

    #[test]
    fn off_by_default() {
        let mut t = DriftTracker::new(DriftSettings {
            window: 1000,
            rate: 0.5,
            limit: 300,
        });
        assert_eq!(t.apply([100, 0, 0]), [100, 0, 0]);
        assert!(!t.enabled());
    }
}
