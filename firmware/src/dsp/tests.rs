//! The f32 filters against f64 references: the closed-form Butterworth magnitude response of a
//! bilinear-transformed design, an f64 implementation of the same difference equations, and the
//! smoother's closed-form step response.
//!
//! Stated error bound (time domain, full scale ±1, deterministic pseudo-random plus sine input,
//! 20 000 samples): |y_f32 − y_f64| ≤ 2e-5 for f_c/f_s ≥ 0.01 and ≤ 5e-4 down to f_c/f_s = 1e-3,
//! the lowest accepted cut-off;
//! magnitude response within 1e-4 (absolute) of the analytic curve for f_c/f_s ≥ 0.01 and within
//! 5e-3 at 1e-3 (f32 coefficient rounding moves the poles slightly).

use super::*;
use protocol::FilterConfig;

fn bw(order: u8, cutoff_hz: f32) -> FilterConfig {
    FilterConfig {
        smoother_alpha: 1.0,
        butterworth_order: order,
        cutoff_hz,
    }
}

fn smoother(alpha: f32) -> FilterConfig {
    FilterConfig {
        smoother_alpha: alpha,
        butterworth_order: 0,
        cutoff_hz: 0.0,
    }
}
use std::f64::consts::PI;

/// f64 reference design and filter (same equations, independent code path in f64).
struct Reference {
    sections: Vec<([f64; 3], [f64; 2], [f64; 2])>,
}

impl Reference {
    fn new(order: u8, ratio: f64) -> Self {
        let k = (PI * ratio).tan();
        let n = f64::from(order);
        let sections = (0..order / 2)
            .map(|i| {
                let q = 1.0 / (2.0 * ((2.0 * f64::from(i) + 1.0) * PI / (2.0 * n)).cos());
                let d = 1.0 + k / q + k * k;
                let b0 = k * k / d;
                (
                    [b0, 2.0 * b0, b0],
                    [2.0 * (k * k - 1.0) / d, (1.0 - k / q + k * k) / d],
                    [0.0; 2],
                )
            })
            .collect();
        Self { sections }
    }

    fn prime(&mut self, x: f64) {
        for (b, a, s) in &mut self.sections {
            s[1] = (b[2] - a[1]) * x;
            s[0] = (b[1] - a[0]) * x + s[1];
        }
    }

    fn step(&mut self, x: f64) -> f64 {
        let mut y = x;
        for (b, a, s) in &mut self.sections {
            let out = b[0] * y + s[0];
            s[0] = b[1] * y - a[0] * out + s[1];
            s[1] = b[2] * y - a[1] * out;
            y = out;
        }
        y
    }
}

/// Deterministic test input in [-1, 1]: a sine plus xorshift noise.
fn input(n: usize) -> Vec<f32> {
    let mut state = 0x2545_F491_u32;
    (0..n)
        .map(|i| {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            let noise = (state as f32 / u32::MAX as f32) - 0.5;
            0.5 * (i as f32 * 0.05).sin() + 0.4 * noise
        })
        .collect()
}

/// The bank with the same signal on all channels; every channel must give the same output.
struct Single(FilterBank);

impl Single {
    fn build(config: &FilterConfig, fs: f32) -> Result<Self, FilterError> {
        FilterBank::build(config, fs).map(Single)
    }

    fn step(&mut self, x: f32) -> f32 {
        let y = self.0.step([x, x, x]);
        assert!(y[0] == y[1] && y[1] == y[2]);
        y[0]
    }

    fn reset(&mut self) {
        self.0.reset();
    }
}

fn max_error(order: u8, ratio: f32) -> f64 {
    let mut f32_filter = Single::build(&bw(order, ratio * 1000.0), 1000.0).unwrap();
    let mut reference = Reference::new(order, f64::from(ratio));
    let x = input(20_000);
    reference.prime(f64::from(x[0]));
    x.iter()
        .map(|&xi| (f64::from(f32_filter.step(xi)) - reference.step(f64::from(xi))).abs())
        .fold(0.0, f64::max)
}

#[test]
fn butterworth_f32_tracks_the_f64_reference_within_the_stated_bound() {
    for order in [2u8, 4] {
        for ratio in [0.01f32, 0.05, 0.1, 0.2, 0.3, 0.44] {
            let e = max_error(order, ratio);
            assert!(e <= 2e-5, "order {order} ratio {ratio}: {e:e}");
        }
        for ratio in [1e-3f32, 3e-3] {
            let e = max_error(order, ratio);
            assert!(e <= 5e-4, "order {order} ratio {ratio}: {e:e}");
        }
    }
}

/// |H(e^{jω})| of the f32 coefficients, evaluated in f64.
fn magnitude(sections: &[Biquad], w: f64) -> f64 {
    sections
        .iter()
        .map(|s| {
            let (c1, s1, c2, s2) = (w.cos(), w.sin(), (2.0 * w).cos(), (2.0 * w).sin());
            let b = s.b.map(f64::from);
            let a = s.a.map(f64::from);
            let num = (b[0] + b[1] * c1 + b[2] * c2, -(b[1] * s1 + b[2] * s2));
            let den = (1.0 + a[0] * c1 + a[1] * c2, -(a[0] * s1 + a[1] * s2));
            (num.0.hypot(num.1)) / (den.0.hypot(den.1))
        })
        .product()
}

#[test]
fn magnitude_response_is_the_prewarped_butterworth_curve() {
    for order in [2u8, 4] {
        for ratio in [1e-3f64, 0.01, 0.1, 0.25, 0.4] {
            let design = Butterworth::design(order, ratio as f32).unwrap();
            for frac in [0.1, 0.5, 1.0, 2.0, 4.0] {
                let f = (ratio * frac).min(0.499);
                let w = 2.0 * PI * f;
                let x = (w / 2.0).tan() / (PI * ratio).tan();
                let analytic = 1.0 / (1.0 + x.powi(2 * i32::from(order))).sqrt();
                let got = magnitude(design.sections(), w);
                let tolerance = if ratio < 0.01 { 5e-3 } else { 1e-4 };
                assert!(
                    (got - analytic).abs() < tolerance,
                    "order {order} ratio {ratio} f {f}: {got} vs {analytic}"
                );
            }
            // −3 dB at the cut-off (prewarping), within the same tolerance.
            let at_cutoff = magnitude(design.sections(), 2.0 * PI * ratio);
            let tolerance = if ratio < 0.01 { 5e-3 } else { 1e-4 };
            assert!(
                (at_cutoff - std::f64::consts::FRAC_1_SQRT_2).abs() < tolerance,
                "{order} {ratio}: {at_cutoff}"
            );
        }
    }
}

#[test]
fn every_accepted_cutoff_is_stable_and_decays() {
    let mut ratio = 1e-3f32;
    while ratio < 0.45 {
        for order in [2u8, 4] {
            let design = Butterworth::design(order, ratio).unwrap();
            assert!(design.sections().iter().all(Biquad::is_stable));
            let mut f = Single::build(&bw(order, ratio * 1000.0), 1000.0).unwrap();
            f.step(0.0);
            let mut y = f.step(1.0);
            for _ in 0..200_000 {
                y = f.step(0.0);
            }
            // An impulse dies out (slowest poles at the lowest cut-off take longest).
            assert!(y.abs() < 1e-3, "order {order} ratio {ratio}: {y}");
        }
        ratio *= 1.7;
    }
}

#[test]
fn out_of_range_settings_are_refused() {
    let fs = 1000.0;
    let bw = |order, cutoff_hz| FilterBank::build(&bw(order, cutoff_hz), fs);
    assert_eq!(bw(2, 450.0), Err(FilterError::CutoffOutOfRange));
    assert_eq!(bw(4, 0.0), Err(FilterError::CutoffOutOfRange));
    assert_eq!(bw(4, -5.0), Err(FilterError::CutoffOutOfRange));
    assert_eq!(bw(2, f32::NAN), Err(FilterError::CutoffOutOfRange));
    assert_eq!(bw(2, 0.5), Err(FilterError::CutoffOutOfRange));
    assert_eq!(bw(3, 100.0), Err(FilterError::OrderUnsupported));
    assert!(bw(2, 449.9).is_ok());
    let sm = |alpha| FilterBank::build(&smoother(alpha), fs);
    assert_eq!(sm(0.0), Err(FilterError::AlphaOutOfRange));
    assert_eq!(sm(1.01), Err(FilterError::AlphaOutOfRange));
    assert_eq!(sm(f32::NAN), Err(FilterError::AlphaOutOfRange));
    assert!(sm(1.0).is_ok());
    assert!(
        bw(0, f32::NAN).is_ok(),
        "cut-off ignored with the low-pass off"
    );
}

#[test]
fn smoother_then_butterworth_is_the_cascade() {
    let config = FilterConfig {
        smoother_alpha: 0.3,
        butterworth_order: 2,
        cutoff_hz: 50.0,
    };
    let mut chain = Single::build(&config, 1000.0).unwrap();
    let mut s = Smoother::new(0.3);
    let b = Butterworth::design(2, 0.05).unwrap();
    let mut state = b.sections()[0].primed(0.0);
    let mut first = true;
    for x in input(300) {
        let smoothed = s.step(x);
        if first {
            state = b.sections()[0].primed(smoothed);
            first = false;
        }
        assert_eq!(chain.step(x), b.sections()[0].step(&mut state, smoothed));
    }
}

#[test]
fn channels_are_filtered_independently() {
    let mut bank = FilterBank::build(&bw(4, 20.0), 1000.0).unwrap();
    let mut single = Single::build(&bw(4, 20.0), 1000.0).unwrap();
    let x = input(500);
    for (i, &xi) in x.iter().enumerate() {
        let y = bank.step([xi, -2.0 * xi, 0.25]);
        let reference = single.step(xi);
        assert_eq!(y[0], reference, "sample {i}");
        assert!((y[2] - 0.25).abs() < 1e-6);
    }
}

#[test]
fn smoother_matches_its_closed_form_step_response() {
    let alpha = 0.05f32;
    let mut s = Smoother::new(alpha);
    assert_eq!(s.step(0.0), 0.0);
    for n in 1..500 {
        let y = f64::from(s.step(1.0));
        let exact = 1.0 - (1.0 - f64::from(alpha)).powi(n);
        assert!((y - exact).abs() < 1e-5, "n {n}: {y} vs {exact}");
    }
}

#[test]
fn priming_starts_at_the_first_sample() {
    let mut f = Single::build(&bw(4, 10.0), 1000.0).unwrap();
    for _ in 0..10 {
        assert!((f.step(3.0e6) - 3.0e6).abs() < 1.0);
    }
    f.reset();
    assert!((f.step(-2.0) + 2.0).abs() < 1e-5);
    let mut s = Single::build(&smoother(0.1), 1000.0).unwrap();
    assert_eq!(s.step(7.0), 7.0);
}

#[test]
fn round_to_code_is_nearest_ties_to_even_and_clamped() {
    use super::round_to_code;
    use protocol::{CODE_MAX, CODE_MIN};
    let cases = [
        (2.5, 2),
        (3.5, 4),
        (-2.5, -2),
        (-2.6, -3),
        (0.49, 0),
        (1.0e9, CODE_MAX),
        (-1.0e9, CODE_MIN),
        (f32::NAN, 0),
    ];
    for (y, code) in cases {
        assert_eq!(round_to_code(y), code, "{y}");
    }
}

#[test]
fn step_codes_is_step_then_round_for_every_cascade() {
    let configs = [
        bw(4, 20.0),
        bw(2, 20.0),
        smoother(0.3),
        FilterConfig {
            smoother_alpha: 0.5,
            butterworth_order: 4,
            cutoff_hz: 80.0,
        },
    ];
    for config in configs {
        let mut codes = FilterBank::build(&config, 1000.0).unwrap();
        let mut floats = codes;
        for (i, x) in input(400).into_iter().enumerate() {
            let c = (x * 3.0e6) as i32;
            let sample = [c, -c / 3, 8_388_607 - i as i32];
            let want = floats
                .step(sample.map(|v| v as f32))
                .map(super::round_to_code);
            assert_eq!(codes.step_codes(sample), want, "{config:?} sample {i}");
        }
    }
}
