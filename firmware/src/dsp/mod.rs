//! Filtering of the three bridge channels: the first-order smoother of the original work, then a
//! Butterworth low-pass of order 2 or 4 (one or two biquads); either can be off. Coefficients are computed here, on
//! the device, from the requested setting; a setting is validated before it replaces the running
//! one, so a refused command leaves the filter untouched. Cost per sample is constant for a given
//! setting (no branches on the data). State is primed by the first sample after (re)configuration.

pub mod butterworth;
pub mod smoother;

pub use butterworth::{Biquad, Butterworth};
pub use smoother::Smoother;
use protocol::FilterConfig;

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

/// One channel's filters as the protocol's `FilterConfig` describes them: the smoother (unless
/// alpha = 1), then the Butterworth low-pass (unless order 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterChain {
    smoother: Option<Smoother>,
    butterworth: Option<Butterworth>,
}

impl FilterChain {
    /// Pass-through.
    pub const NONE: Self = Self { smoother: None, butterworth: None };

    /// Validate `config` against the sample rate and design the chain.
    pub fn build(config: &FilterConfig, sample_rate_hz: f32) -> Result<Self, FilterError> {
        let alpha = config.smoother_alpha;
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(FilterError::AlphaOutOfRange);
        }
        let smoother = (alpha < 1.0).then(|| Smoother::new(alpha));
        let butterworth = match config.butterworth_order {
            0 => None,
            order @ (2 | 4) => Some(
                Butterworth::design(order, config.cutoff_hz / sample_rate_hz).ok_or(FilterError::CutoffOutOfRange)?,
            ),
            _ => return Err(FilterError::OrderUnsupported),
        };
        Ok(Self { smoother, butterworth })
    }

    /// Whether the chain leaves samples unchanged (smoother and low-pass both off).
    pub fn is_pass_through(&self) -> bool {
        self.smoother.is_none() && self.butterworth.is_none()
    }

    /// Filter one sample.
    #[inline]
    pub fn step(&mut self, mut x: f32) -> f32 {
        if let Some(s) = &mut self.smoother {
            x = s.step(x);
        }
        if let Some(b) = &mut self.butterworth {
            x = b.step(x);
        }
        x
    }

    /// Forget the history (after a tare or null step the old state is meaningless).
    pub fn reset(&mut self) {
        if let Some(s) = &mut self.smoother {
            s.reset();
        }
        if let Some(b) = &mut self.butterworth {
            b.reset();
        }
    }
}

#[cfg(test)]
mod tests;
