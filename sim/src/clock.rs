//! A device's clock and its link's delay, as the host sees them: a crystal off by some ppm, and
//! a one-sided, jittered delay between the device sending a frame and the host reading it.
//!
//! The emulator (`hil::emu`) paces its frames by [`Crystal`] and holds each one back by a
//! [`LinkJitter`] draw; the simulated hour of `scripts/bench-hand.sh` uses the same two models on
//! a virtual clock. Both know the truth, so the host's clock estimate can be checked against it.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A device clock: `device = (1 + ppm·1e-6) · true + offset_s` (seconds).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crystal {
    /// How fast the device clock runs against true time, in parts per million.
    pub ppm: f64,
    /// Device time at true time zero.
    pub offset_s: f64,
}

impl Crystal {
    pub const PERFECT: Self = Self {
        ppm: 0.0,
        offset_s: 0.0,
    };

    /// The device's reading at true time `t_s`.
    pub fn device_s(&self, t_s: f64) -> f64 {
        (1.0 + self.ppm * 1e-6) * t_s + self.offset_s
    }

    /// The true time at which the device reads `device_s`.
    pub fn true_s(&self, device_s: f64) -> f64 {
        (device_s - self.offset_s) / (1.0 + self.ppm * 1e-6)
    }
}

/// The delay from a frame leaving the device to the host reading it. Delays are one-sided (a
/// frame is never early), made of: a fixed floor (the transfer itself), the wait for the next
/// USB poll (uniform over one USB frame), the host's scheduling (exponential), and rare long
/// stalls (another process holding the CPU, a hub): uniform up to `outlier_max_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkJitter {
    pub floor_s: f64,
    pub usb_frame_s: f64,
    pub sched_mean_s: f64,
    pub outlier_prob: f64,
    pub outlier_max_s: f64,
}

impl LinkJitter {
    /// No delay at all.
    pub const NONE: Self = Self {
        floor_s: 0.0,
        usb_frame_s: 0.0,
        sched_mean_s: 0.0,
        outlier_prob: 0.0,
        outlier_max_s: 0.0,
    };

    /// A full-speed USB CDC link on a busy host: 1 ms USB frames, 200 µs mean scheduling delay,
    /// one frame in a hundred held up to 20 ms.
    pub const USB_BUSY: Self = Self {
        floor_s: 100e-6,
        usb_frame_s: 1e-3,
        sched_mean_s: 200e-6,
        outlier_prob: 0.01,
        outlier_max_s: 20e-3,
    };

    /// One delay drawn from the model.
    pub fn draw(&self, rng: &mut ChaCha8Rng) -> f64 {
        let u: f64 = rng.random();
        let e: f64 = rng.random::<f64>();
        let mut d = self.floor_s + u * self.usb_frame_s - self.sched_mean_s * (1.0 - e).ln();
        if rng.random::<f64>() < self.outlier_prob {
            d += rng.random::<f64>() * self.outlier_max_s;
        }
        d
    }
}

/// A seeded generator for [`LinkJitter::draw`].
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crystal_round_trips() {
        let c = Crystal {
            ppm: -87.5,
            offset_s: 12.25,
        };
        let t = 3_599.123_456;
        assert!((c.true_s(c.device_s(t)) - t).abs() < 1e-12);
        // 100 ppm fast gains 0.36 s in an hour.
        let fast = Crystal {
            ppm: 100.0,
            offset_s: 0.0,
        };
        assert!((fast.device_s(3600.0) - 3600.36).abs() < 1e-9);
    }

    #[test]
    fn jitter_is_one_sided_with_its_floor() {
        let j = LinkJitter::USB_BUSY;
        let mut r = rng(7);
        let d: Vec<f64> = (0..10_000).map(|_| j.draw(&mut r)).collect();
        assert!(d.iter().all(|&x| x >= j.floor_s));
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        // floor + half a USB frame + the scheduling mean + 1 % of half the outlier span.
        let expect = 100e-6 + 500e-6 + 200e-6 + 0.01 * 10e-3;
        assert!((mean - expect).abs() < 0.1 * expect, "mean {mean}");
    }
}
