//! Butterworth low-pass as a cascade of second-order sections, designed on the device.
//!
//! Design: the analog prototype of order N has pole pairs with quality factors
//! Q_k = 1 / (2·cos θ_k), θ_k = (2k + 1)·π / (2N), k = 0 … N/2 − 1. Each section
//! H(s) = 1 / (s² + s/Q_k + 1) is mapped with the bilinear transform, prewarped so the −3 dB point
//! lands exactly on f_c: K = tan(π·f_c / f_s),
//!   b0 = b2 = K² / D, b1 = 2·b0, a1 = 2·(K² − 1) / D, a2 = (1 − K/Q + K²) / D,
//!   D = 1 + K/Q + K².
//! Each section runs in transposed direct form II (two state variables, 5 multiplies).
//! Stability: for 0 < f_c < f_s/2 the exact poles lie inside the unit circle; in f32 the
//! coefficients are additionally checked against the stability triangle |a2| < 1, |a1| < 1 + a2,
//! and cut-offs whose sections would sit too close to z = 1 for f32 (f_c / f_s below
//! [`MIN_CUTOFF_RATIO`]) are refused by [`super::FilterBank::build`].
//!
//! Coefficients and state are kept apart so that one set of coefficients serves all channels.

use core::f32::consts::PI;

/// Highest accepted f_c / f_s (the prewarp tan() grows without bound towards 0.5).
pub const MAX_CUTOFF_RATIO: f32 = 0.45;
/// Lowest accepted f_c / f_s. The poles sit at radius ≈ 1 − 2πf_c/f_s, and the f32 state's
/// rounding is amplified by about 1/(1 − r): measured against f64 the error is 3.5e-4 of full scale
/// at 1e-3 but 2.5e-2 at 1e-4 (see dsp::tests), so lower cut-offs are refused.
pub const MIN_CUTOFF_RATIO: f32 = 1.0e-3;
/// Most sections in a cascade (order 4).
pub const MAX_SECTIONS: usize = 2;

/// State of one section for one channel (transposed direct form II).
pub type State = [f32; 2];

/// Coefficients of one second-order section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Biquad {
    pub b: [f32; 3],
    /// a1, a2 (a0 = 1).
    pub a: [f32; 2],
}

impl Biquad {
    /// The low-pass section with quality factor `q` at prewarped frequency `k` = tan(π f_c / f_s).
    pub fn low_pass(k: f32, q: f32) -> Self {
        let k2 = k * k;
        let d = 1.0 + k / q + k2;
        let a = [2.0 * (k2 - 1.0) / d, (1.0 - k / q + k2) / d];
        // b0 = K²/D analytically, which equals (1 + a1 + a2) / 4. Taking it from the rounded f32
        // a's makes the DC gain exactly 1 in f32: at low f_c/f_s, 1 + a1 + a2 is a small
        // difference of numbers near 2, and K²/D alone would miss it by up to ~0.5 %.
        let b0 = (1.0 + a[0] + a[1]) / 4.0;
        Self {
            b: [b0, 2.0 * b0, b0],
            a,
        }
    }

    /// Whether the f32 coefficients satisfy the stability triangle.
    pub fn is_stable(&self) -> bool {
        let [a1, a2] = self.a;
        a2.abs() < 1.0 && a1.abs() < 1.0 + a2
    }

    /// The steady state for a constant input `x` (DC gain 1: output = x).
    pub fn primed(&self, x: f32) -> State {
        let [_, b1, b2] = self.b;
        let [a1, a2] = self.a;
        let s1 = (b2 - a2) * x;
        [(b1 - a1) * x + s1, s1]
    }

    /// Filter one sample of one channel. The operations are ordered as the Cortex-M4's
    /// multiply-accumulate instructions compute them (`d ± a·b`, product rounded, then the sum),
    /// so the three-channel step of [`super::FilterBank`] gives bit-identical results.
    #[inline(always)]
    pub fn step(&self, s: &mut State, x: f32) -> f32 {
        let y = s[0] + self.b[0] * x;
        s[0] = (s[1] + self.b[1] * x) - self.a[0] * y;
        s[1] = self.b[2] * x - self.a[1] * y;
        y
    }
}

/// Quality factor of section `k` of an order-`order` Butterworth low-pass (order 2 or 4).
pub fn section_q(order: u8, k: usize) -> f32 {
    let n = f32::from(order);
    let theta = (2.0 * k as f32 + 1.0) * PI / (2.0 * n);
    1.0 / (2.0 * libm::cosf(theta))
}

/// The sections of a low-pass: one (order 2) or two (order 4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Butterworth {
    sections: [Biquad; MAX_SECTIONS],
    len: usize,
}

impl Butterworth {
    /// Design for `order` ∈ {2, 4} and f_c / f_s = `ratio`; `None` if the setting is outside the
    /// accepted range or the f32 coefficients fail the stability check.
    pub fn design(order: u8, ratio: f32) -> Option<Self> {
        let in_range = (MIN_CUTOFF_RATIO..MAX_CUTOFF_RATIO).contains(&ratio); // false for NaN too
        if !(order == 2 || order == 4) || !in_range {
            return None;
        }
        let k = libm::tanf(PI * ratio);
        let len = usize::from(order / 2);
        let mut sections = [Biquad::low_pass(k, core::f32::consts::FRAC_1_SQRT_2); MAX_SECTIONS];
        for (i, section) in sections.iter_mut().enumerate().take(len) {
            *section = Biquad::low_pass(k, section_q(order, i));
        }
        sections[..len]
            .iter()
            .all(Biquad::is_stable)
            .then_some(Self { sections, len })
    }

    /// Sections in use.
    pub fn sections(&self) -> &[Biquad] {
        &self.sections[..self.len]
    }
}
