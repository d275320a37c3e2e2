//! Filtering of the three bridge channels: the first-order smoother of the original work, then a
//! Butterworth low-pass of order 2 or 4 (one or two biquads); either can be off. Coefficients are
//! computed here, on the device, from the requested setting; a setting is validated before it
//! replaces the running one, so a refused command leaves the filter untouched. Cost per sample is
//! constant for a given setting (no branches on the data). State is primed by the first sample
//! after (re)configuration: the output starts at the input instead of crawling up from zero.
//!
//! The three channels share one setting, so the bank loads each coefficient once per sample and
//! applies it to all three channels.

pub mod butterworth;
pub mod smoother;

pub use butterworth::{Biquad, Butterworth};
use protocol::FilterConfig;
pub use smoother::Smoother;

/// Channels filtered together.
pub const CHANNELS: usize = 3;

/// Why a filter setting was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum FilterError {
    /// Smoother weight outside (0, 1] or not a number.
    AlphaOutOfRange,
    /// Butterworth order other than 0 (off), 2 or 4.
    OrderUnsupported,
    /// Cut-off not in [1e-3·f_s, 0.45·f_s), or not a number, or unstable in f32.
    CutoffOutOfRange,
}

/// The filters of the three bridge channels as the protocol's `FilterConfig` describes them: the
/// smoother (unless alpha = 1), then the Butterworth low-pass (unless order 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterBank {
    alpha: Option<f32>,
    smoothed: [f32; CHANNELS],
    butterworth: Option<Butterworth>,
    state: [[butterworth::State; CHANNELS]; butterworth::MAX_SECTIONS],
    primed: bool,
}

impl FilterBank {
    /// Pass-through.
    pub const NONE: Self = Self {
        alpha: None,
        smoothed: [0.0; CHANNELS],
        butterworth: None,
        state: [[[0.0; 2]; CHANNELS]; butterworth::MAX_SECTIONS],
        primed: false,
    };

    /// Validate `config` against the sample rate and design the filters.
    pub fn build(config: &FilterConfig, sample_rate_hz: f32) -> Result<Self, FilterError> {
        let alpha = config.smoother_alpha;
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(FilterError::AlphaOutOfRange);
        }
        let butterworth = match config.butterworth_order {
            0 => None,
            order @ (2 | 4) => Some(
                Butterworth::design(order, config.cutoff_hz / sample_rate_hz)
                    .ok_or(FilterError::CutoffOutOfRange)?,
            ),
            _ => return Err(FilterError::OrderUnsupported),
        };
        Ok(Self {
            alpha: (alpha < 1.0).then_some(alpha),
            butterworth,
            ..Self::NONE
        })
    }

    /// Whether the bank leaves samples unchanged (smoother and low-pass both off).
    pub fn is_pass_through(&self) -> bool {
        self.alpha.is_none() && self.butterworth.is_none()
    }

    /// Filter one sample of each channel.
    #[inline]
    pub fn step(&mut self, mut x: [f32; CHANNELS]) -> [f32; CHANNELS] {
        if !self.primed {
            self.prime(x);
        }
        if let Some(alpha) = self.alpha {
            // a·x + (1 − a)·y written as y + a·(x − y): one multiply.
            for (y, xi) in self.smoothed.iter_mut().zip(x.iter_mut()) {
                *y += alpha * (*xi - *y);
                *xi = *y;
            }
        }
        if let Some(bw) = &self.butterworth {
            for (section, states) in bw.sections().iter().zip(self.state.iter_mut()) {
                for (s, xi) in states.iter_mut().zip(x.iter_mut()) {
                    *xi = section.step(s, *xi);
                }
            }
        }
        x
    }

    fn prime(&mut self, x: [f32; CHANNELS]) {
        self.smoothed = x;
        if let Some(bw) = &self.butterworth {
            for (section, states) in bw.sections().iter().zip(self.state.iter_mut()) {
                for (s, xi) in states.iter_mut().zip(x.iter()) {
                    *s = section.primed(*xi);
                }
            }
        }
        self.primed = true;
    }

    /// Forget the history (after a tare or null step the old state is meaningless).
    pub fn reset(&mut self) {
        self.primed = false;
    }
}

#[cfg(test)]
mod tests;
