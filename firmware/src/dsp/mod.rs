//! Filtering of the three bridge channels: none, the first-order smoother of the original work, or
//! a Butterworth low-pass of order 2 or 4 (one or two biquads). Coefficients are computed here, on
//! the device, from the requested setting; a setting is validated before it replaces the running
//! one, so a refused command leaves the filter untouched. Cost per sample is constant for a given
//! setting (no branches on the data). State is primed by the first sample after (re)configuration.

pub mod butterworth;
pub mod smoother;

pub use butterworth::{Biquad, Butterworth};
pub use smoother::Smoother;

/// A requested filter setting (mirrors the protocol's filter configuration).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilterSpec {
    /// Pass the samples through.
    None,
    /// First-order smoother with weight `alpha` ∈ (0, 1] on the new sample.
    Smoother { alpha: f32 },
    /// Butterworth low-pass, `order` 2 or 4, −3 dB at `cutoff_hz`.
    Butterworth { order: u8, cutoff_hz: f32 },
}

/// Why a filter setting was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum FilterError {
    /// Smoother weight outside (0, 1] or not a number.
    AlphaOutOfRange,
    /// Order other than 2 or 4.
    OrderUnsupported,
    /// Cut-off not in [1e-3·f_s, 0.45·f_s), or not a number, or unstable in f32.
    CutoffOutOfRange,
}

/// One channel's running filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Filter {
    None,
    Smoother(Smoother),
    Butterworth(Butterworth),
}

impl FilterSpec {
    /// Check the setting against the sample rate and design the filter.
    pub fn build(&self, sample_rate_hz: f32) -> Result<Filter, FilterError> {
        match *self {
            FilterSpec::None => Ok(Filter::None),
            FilterSpec::Smoother { alpha } => {
                if alpha > 0.0 && alpha <= 1.0 {
                    Ok(Filter::Smoother(Smoother::new(alpha)))
                } else {
                    Err(FilterError::AlphaOutOfRange)
                }
            }
            FilterSpec::Butterworth { order, cutoff_hz } => {
                if order != 2 && order != 4 {
                    return Err(FilterError::OrderUnsupported);
                }
                Butterworth::design(order, cutoff_hz / sample_rate_hz)
                    .map(Filter::Butterworth)
                    .ok_or(FilterError::CutoffOutOfRange)
            }
        }
    }
}

impl Filter {
    /// Filter one sample.
    #[inline]
    pub fn step(&mut self, x: f32) -> f32 {
        match self {
            Filter::None => x,
            Filter::Smoother(s) => s.step(x),
            Filter::Butterworth(b) => b.step(x),
        }
    }

    /// Forget the history (after a tare or null step the old state is meaningless).
    pub fn reset(&mut self) {
        match self {
            Filter::None => {}
            Filter::Smoother(s) => s.reset(),
            Filter::Butterworth(b) => b.reset(),
        }
    }
}

#[cfg(test)]
mod tests;
