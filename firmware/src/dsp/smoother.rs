//! The first-order recursive smoother of the original work: y[n] = a·x[n] + (1 − a)·y[n−1].
//! The first sample after construction or reset primes y (y[0] = x[0]) so a channel that sits far
//! from zero does not crawl up from 0.

/// One channel's smoother.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Smoother {
    alpha: f32,
    y: f32,
    primed: bool,
}

impl Smoother {
    /// `alpha` in (0, 1]; 1 passes the input through. Checked by [`super::FilterChain::build`].
    pub fn new(alpha: f32) -> Self {
        Self { alpha, y: 0.0, primed: false }
    }

    /// Filter one sample.
    #[inline]
    pub fn step(&mut self, x: f32) -> f32 {
        if !self.primed {
            self.y = x;
            self.primed = true;
        }
        // a·x + (1 − a)·y written as y + a·(x − y): one multiply.
        self.y += self.alpha * (x - self.y);
        self.y
    }

    /// Forget the history; the next sample primes again.
    pub fn reset(&mut self) {
        self.primed = false;
    }
}
