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
///
/// Laid out for the per-sample step: each section's five coefficients and its six state values
/// (s1 of channels 0..2, then s2 of channels 0..2) are contiguous arrays, read and written whole
/// (the FPU's multiple-register loads and stores), and the section count is a plain number, so
/// the step is straight-line code for each of the three possible cascades.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterBank {
    alpha: Option<f32>,
    smoothed: [f32; CHANNELS],
    butterworth: Option<Butterworth>,
    /// Sections in use (0, 1 or 2) and their coefficients b0, b1, b2, a1, a2.
    sections: usize,
    coef: [[f32; 5]; butterworth::MAX_SECTIONS],
    state: [[f32; 2 * CHANNELS]; butterworth::MAX_SECTIONS],
    primed: bool,
}

impl FilterBank {
    /// Pass-through.
    pub const NONE: Self = Self {
        alpha: None,
        smoothed: [0.0; CHANNELS],
        butterworth: None,
        sections: 0,
        coef: [[0.0; 5]; butterworth::MAX_SECTIONS],
        state: [[0.0; 2 * CHANNELS]; butterworth::MAX_SECTIONS],
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
        let mut bank = Self {
            alpha: (alpha < 1.0).then_some(alpha),
            butterworth,
            ..Self::NONE
        };
        if let Some(bw) = &butterworth {
            bank.sections = bw.sections().len();
            for (c, section) in bank.coef.iter_mut().zip(bw.sections()) {
                *c = [
                    section.b[0],
                    section.b[1],
                    section.b[2],
                    section.a[0],
                    section.a[1],
                ];
            }
        }
        Ok(bank)
    }

    /// Whether the bank leaves samples unchanged (smoother and low-pass both off).
    pub fn is_pass_through(&self) -> bool {
        self.alpha.is_none() && self.sections == 0
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
        match self.sections {
            0 => {}
            1 => section3(&self.coef[0], &mut self.state[0], &mut x),
            _ => {
                let [c0, c1] = &self.coef;
                let [s0, s1] = &mut self.state;
                section3(c0, s0, &mut x);
                section3(c1, s1, &mut x);
            }
        }
        x
    }

    fn prime(&mut self, x: [f32; CHANNELS]) {
        self.smoothed = x;
        if let Some(bw) = &self.butterworth {
            for (section, state) in bw.sections().iter().zip(self.state.iter_mut()) {
                for (ch, &xi) in x.iter().enumerate() {
                    let [s1, s2] = section.primed(xi);
                    state[ch] = s1;
                    state[CHANNELS + ch] = s2;
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

/// One section on the three channels, transposed direct form II exactly as [`Biquad::step`]
/// (same operations in the same order, so the same f32 results), `v` filtered in place. `c` is
/// b0, b1, b2, a1, a2; `s` holds s1 of channels 0..2, then s2 of channels 0..2.
#[cfg(not(all(target_arch = "arm", target_os = "none")))]
#[inline(always)]
fn section3(c: &[f32; 5], s: &mut [f32; 2 * CHANNELS], v: &mut [f32; CHANNELS]) {
    let [b0, b1, b2, a1, a2] = *c;
    let [p0, p1, p2, q0, q1, q2] = *s;
    let x = *v;
    let y = [p0 + b0 * x[0], p1 + b0 * x[1], p2 + b0 * x[2]];
    *s = [
        (q0 + b1 * x[0]) - a1 * y[0],
        (q1 + b1 * x[1]) - a1 * y[1],
        (q2 + b1 * x[2]) - a1 * y[2],
        b2 * x[0] - a2 * y[0],
        b2 * x[1] - a2 * y[1],
        b2 * x[2] - a2 * y[2],
    ];
    *v = y;
}

/// The same section on the Cortex-M4F: input, coefficients and state each move with one
/// multiple-register load (VLDM), state and output with one store (VSTM), and every term is one
/// multiply-accumulate: 20 instructions for the three channels, where the compiler's code took
/// about 40 (it loads and stores one register at a time). VMLA/VMLS round the product and then
/// the sum, as the portable version above does. Values pass through memory because naming FPU
/// registers as asm operands needs a target-feature name that is still unstable.
#[cfg(all(target_arch = "arm", target_os = "none"))]
#[inline(always)]
fn section3(c: &[f32; 5], s: &mut [f32; 2 * CHANNELS], v: &mut [f32; CHANNELS]) {
    // SAFETY: reads the 5 floats of `c`, reads then writes the 6 floats of `s` and the 3 of `v`
    // (both exclusively borrowed); every FPU register written is declared as clobbered.
    unsafe {
        core::arch::asm!(
            "vldmia {v}, {{s0-s2}}",
            "vldmia {c}, {{s16-s20}}",
            "vldmia {s}, {{s21-s26}}",
            // y = p + b0·x
            "vmla.f32 s21, s16, s0",
            "vmla.f32 s22, s16, s1",
            "vmla.f32 s23, s16, s2",
            // s1' = (q + b1·x) − a1·y
            "vmla.f32 s24, s17, s0",
            "vmla.f32 s25, s17, s1",
            "vmla.f32 s26, s17, s2",
            "vmls.f32 s24, s19, s21",
            "vmls.f32 s25, s19, s22",
            "vmls.f32 s26, s19, s23",
            // s2' = b2·x − a2·y
            "vmul.f32 s27, s18, s0",
            "vmul.f32 s28, s18, s1",
            "vmul.f32 s29, s18, s2",
            "vmls.f32 s27, s20, s21",
            "vmls.f32 s28, s20, s22",
            "vmls.f32 s29, s20, s23",
            "vstmia {s}, {{s24-s29}}",
            "vstmia {v}, {{s21-s23}}",
            c = in(reg) c.as_ptr(),
            s = in(reg) s.as_mut_ptr(),
            v = in(reg) v.as_mut_ptr(),
            out("s0") _, out("s1") _, out("s2") _,
            out("s16") _, out("s17") _, out("s18") _, out("s19") _, out("s20") _,
            out("s21") _, out("s22") _, out("s23") _,
            out("s24") _, out("s25") _, out("s26") _, out("s27") _, out("s28") _, out("s29") _,
            options(nostack, preserves_flags),
        );
    }
}

/// Nearest 24-bit code to a filter output, ties to even (the FPU's default rounding), clamped to
/// the code range; NaN gives 0. On the Cortex-M4F one VCVTR (convert with the current rounding
/// mode, round to nearest even unless changed) does the rounding where `as` would truncate and
/// a half-away-from-zero adjustment costs five more instructions; elsewhere libm's `rintf`, which
/// rounds the same way.
#[inline(always)]
pub fn round_to_code(y: f32) -> i32 {
    #[cfg(all(target_arch = "arm", target_os = "none"))]
    let r: i32 = {
        let bits: u32;
        // SAFETY: register-only conversion; s0 is declared clobbered.
        unsafe {
            core::arch::asm!(
                "vmov s0, {b}",
                "vcvtr.s32.f32 s0, s0",
                "vmov {b}, s0",
                b = inout(reg) y.to_bits() => bits,
                out("s0") _,
                options(pure, nomem, nostack, preserves_flags),
            );
        }
        bits as i32
    };
    #[cfg(not(all(target_arch = "arm", target_os = "none")))]
    let r: i32 = libm::rintf(y) as i32;
    r.clamp(protocol::CODE_MIN, protocol::CODE_MAX)
}

#[cfg(test)]
mod tests;
