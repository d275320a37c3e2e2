//! Digital tare: on command, average N samples at rest and subtract the mean from then on.

use super::CHANNELS;

/// Tare state of the three bridge channels.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Tare {
    /// Offset subtracted from every sample (0 until a tare completes).
    offset: [i32; CHANNELS],
    active: bool,
    /// Samples still to average; 0 when no tare is collecting.
    remaining: u16,
    total: u16,
    sum: [i64; CHANNELS],
}

impl Default for Tare {
    fn default() -> Self {
        Self::new()
    }
}

impl Tare {
    pub fn new() -> Self {
        Self {
            offset: [0; CHANNELS],
            active: false,
            remaining: 0,
            total: 0,
            sum: [0; CHANNELS],
        }
    }

    /// Start averaging `samples` (≥ 1) samples; the old offset stays in force until done.
    pub fn start(&mut self, samples: u16) {
        debug_assert!(samples > 0, "validated by the command handler");
        self.remaining = samples;
        self.total = samples;
        self.sum = [0; CHANNELS];
    }

    /// Drop the tare (offset 0).
    pub fn clear(&mut self) {
        *self = Self::new();
    }

    /// Whether a tare is collecting samples.
    pub fn collecting(&self) -> bool {
        self.remaining > 0
    }

    /// Whether an offset is being subtracted.
    pub fn active(&self) -> bool {
        self.active
    }

    pub fn offset(&self) -> [i32; CHANNELS] {
        self.offset
    }

    /// Feed one raw sample; returns true when this sample completed a tare.
    pub fn on_sample(&mut self, raw: [i32; CHANNELS]) -> bool {
        if self.remaining == 0 {
            return false;
        }
        for (sum, &x) in self.sum.iter_mut().zip(&raw) {
            *sum += i64::from(x);
        }
        self.remaining -= 1;
        if self.remaining > 0 {
            return false;
        }
        let n = i64::from(self.total);
        // Rounded mean (half away from zero).
        self.offset = core::array::from_fn(|ch| {
            let s = self.sum[ch];
            ((s + if s >= 0 { n / 2 } else { -n / 2 }) / n) as i32
        });
        self.active = true;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn averages_then_subtracts() {
        let mut tare = Tare::new();
        tare.start(4);
        assert!(!tare.on_sample([10, -10, 1]));
        assert!(!tare.on_sample([12, -12, 2]));
        assert!(!tare.on_sample([14, -14, 2]));
        assert!(!tare.active());
        assert!(tare.on_sample([16, -16, 2]));
        assert!(tare.active() && !tare.collecting());
        assert_eq!(tare.offset(), [13, -13, 2]);
        assert!(!tare.on_sample([0; 3]));
        tare.clear();
        assert_eq!(tare.offset(), [0; 3]);
    }
}
