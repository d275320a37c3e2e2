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
    /// Which per-sample path applies, kept up to date by `build`, `prime` and `reset` so the
    /// step makes one decision instead of testing alpha, sections and priming each time.
    path: Path,
}

/// The per-sample paths of [`FilterBank::step_codes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Path {
    /// Smoother and low-pass off: codes pass unchanged.
    PassThrough,
    /// Primed, no smoother, two sections: the one-block cascade.
    Cascade2,
    /// Anything else (including the first sample after a change, which primes).
    General,
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
        path: Path::PassThrough,
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
        bank.update_path();
        Ok(bank)
    }

    fn update_path(&mut self) {
        self.path = if self.alpha.is_none() && self.sections == 0 {
            Path::PassThrough
        } else if self.primed && self.alpha.is_none() && self.sections == 2 {
            Path::Cascade2
        } else {
            Path::General
        };
    }

    /// Whether the bank leaves samples unchanged (smoother and low-pass both off).
    pub fn is_pass_through(&self) -> bool {
        self.path == Path::PassThrough
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

    /// Filter one sample of codes and round the result to 24-bit codes ([`round_to_code`]): the
    /// same result as `step` on the codes as f32, rounded (pass-through only clamps). The device's
    /// path. With the common setting (order 4, no smoother) on the Cortex-M4F, conversion, both
    /// sections and rounding run as one block of assembly with every value kept in FPU registers.
    #[inline]
    pub fn step_codes(&mut self, x: [i32; CHANNELS]) -> [i32; CHANNELS] {
        let clamp = |c: i32| c.clamp(protocol::CODE_MIN, protocol::CODE_MAX);
        match self.path {
            Path::Cascade2 => cascade2_codes(&self.coef, &mut self.state, x).map(clamp),
            Path::PassThrough => x.map(clamp),
            Path::General => self.step(x.map(|c| c as f32)).map(round_to_code),
        }
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
        self.update_path();
    }

    /// Forget the history (after a tare or null step the old state is meaningless).
    pub fn reset(&mut self) {
        self.primed = false;
        self.update_path();
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

/// Two sections on codes, rounded (not yet clamped): portable version, [`section3`] twice.
#[cfg(not(all(target_arch = "arm", target_os = "none")))]
#[inline(always)]
fn cascade2_codes(
    c: &[[f32; 5]; 2],
    s: &mut [[f32; 2 * CHANNELS]; 2],
    x: [i32; CHANNELS],
) -> [i32; CHANNELS] {
    let mut v = x.map(|c| c as f32);
    let [s0, s1] = s;
    section3(&c[0], s0, &mut v);
    section3(&c[1], s1, &mut v);
    v.map(|y| libm::rintf(y) as i32)
}

/// Two sections on codes, rounded (not yet clamped), on the Cortex-M4F: the codes are converted
/// in FPU registers, the ten coefficients and twelve state values arrive with one VLDM each, the
/// first section's output feeds the second without leaving the registers, and VCVTR rounds (to
/// nearest, ties to even). The same operations in the same order as [`section3`] twice and
/// [`round_to_code`], so the same results (checked on target by the self-test).
#[cfg(all(target_arch = "arm", target_os = "none"))]
#[inline(always)]
fn cascade2_codes(
    c: &[[f32; 5]; 2],
    s: &mut [[f32; 2 * CHANNELS]; 2],
    x: [i32; CHANNELS],
) -> [i32; CHANNELS] {
    let (y0, y1, y2): (i32, i32, i32);
    // SAFETY: reads the 10 floats of `c`, reads then writes the 12 floats of `s` (exclusively
    // borrowed); the state pointer and every FPU register written are declared as clobbered.
    unsafe {
        core::arch::asm!(
            "vmov s0, {x0}", "vmov s1, {x1}", "vmov s2, {x2}",
            "vcvt.f32.s32 s0, s0",
            "vcvt.f32.s32 s1, s1",
            "vcvt.f32.s32 s2, s2",
            // b0 b1 b2 a1 a2 of section 0 in s3..s7, of section 1 in s8..s12
            "vldmia {c}, {{s3-s12}}",
            // p0..p2 q0..q2 of section 0 in s13..s18, of section 1 in s19..s24
            "vldmia {s}, {{s13-s24}}",
            // section 0: y = p + b0·x (s13..s15)
            "vmla.f32 s13, s3, s0",
            "vmla.f32 s14, s3, s1",
            "vmla.f32 s15, s3, s2",
            // p' = (q + b1·x) − a1·y (s16..s18)
            "vmla.f32 s16, s4, s0",
            "vmla.f32 s17, s4, s1",
            "vmla.f32 s18, s4, s2",
            "vmls.f32 s16, s6, s13",
            "vmls.f32 s17, s6, s14",
            "vmls.f32 s18, s6, s15",
            // q' = b2·x − a2·y (s25..s27)
            "vmul.f32 s25, s5, s0",
            "vmul.f32 s26, s5, s1",
            "vmul.f32 s27, s5, s2",
            "vmls.f32 s25, s7, s13",
            "vmls.f32 s26, s7, s14",
            "vmls.f32 s27, s7, s15",
            // section 1 on y: y' = p + b0·y (s19..s21)
            "vmla.f32 s19, s8, s13",
            "vmla.f32 s20, s8, s14",
            "vmla.f32 s21, s8, s15",
            // p' = (q + b1·y) − a1·y' (s22..s24)
            "vmla.f32 s22, s9, s13",
            "vmla.f32 s23, s9, s14",
            "vmla.f32 s24, s9, s15",
            "vmls.f32 s22, s11, s19",
            "vmls.f32 s23, s11, s20",
            "vmls.f32 s24, s11, s21",
            // q' = b2·y − a2·y' (s0..s2: the input is no longer needed; s28 and up stay free
            // for the compiler, which keeps constants there)
            "vmul.f32 s0, s10, s13",
            "vmul.f32 s1, s10, s14",
            "vmul.f32 s2, s10, s15",
            "vmls.f32 s0, s12, s19",
            "vmls.f32 s1, s12, s20",
            "vmls.f32 s2, s12, s21",
            // new state, in the layout it was read in
            "vstmia {s}!, {{s16-s18}}",
            "vstmia {s}!, {{s25-s27}}",
            "vstmia {s}!, {{s22-s24}}",
            "vstmia {s}!, {{s0-s2}}",
            // round to nearest (FPSCR default) and back to core registers
            "vcvtr.s32.f32 s19, s19",
            "vcvtr.s32.f32 s20, s20",
            "vcvtr.s32.f32 s21, s21",
            "vmov {x0}, s19", "vmov {x1}, s20", "vmov {x2}, s21",
            c = in(reg) c.as_ptr(), s = inout(reg) s.as_mut_ptr() => _,
            x0 = inout(reg) x[0] => y0, x1 = inout(reg) x[1] => y1, x2 = inout(reg) x[2] => y2,
            out("s0") _, out("s1") _, out("s2") _, out("s3") _, out("s4") _, out("s5") _,
            out("s6") _, out("s7") _, out("s8") _, out("s9") _, out("s10") _, out("s11") _,
            out("s12") _, out("s13") _, out("s14") _, out("s15") _, out("s16") _, out("s17") _,
            out("s18") _, out("s19") _, out("s20") _, out("s21") _, out("s22") _, out("s23") _,
            out("s24") _, out("s25") _, out("s26") _, out("s27") _,
            options(nostack, preserves_flags),
        );
    }
    [y0, y1, y2]
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
