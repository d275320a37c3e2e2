//! The first-order recursive smoother of the original work, `y[n] = a·x[n] + (1 − a)·y[n−1]`, for
//! a single signal (the firmware's three channels run it inside [`super::FilterBank`]). The first
//! sample primes y (`y[0] = x[0]`).

/// One signal's smoother.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Smoother {
    alpha: f32,
    y: f32,
    primed: bool,
}

impl Smoother {
    /// `alpha` in (0, 1]; 1 passes the input through.
    pub fn new(alpha: f32) -> Self {
        Self {
            alpha,
            y: 0.0,
            primed: false,
        }
    }

    /// Filter one sample.
    #[inline]
    pub fn step(&mut self, x: f32) -> f32 {
        if !self.primed {
            self.y = x;
            self.primed = true;
        }
        self.y += self.alpha * (x - self.y);
        self.y
    }
}
