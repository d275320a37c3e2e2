//! A line at any frequency: a frame or table that vibrates, a pump, a slow wander of the zero
//! (a period of tens of seconds), pickup other than the mains:
//!
//! ```text
//! y(t) = model(t) + a sin(2 pi f t) + b cos(2 pi f t)
//! ```
//!
//! a function of time alone. f is the strongest peak of the residual's periodogram over the
//! fitting stretch (at least two periods in it, at most 10 Hz, what the decimated blocks still
//! show), refined on the decimated series, where each block holds the line's mean over the
//! block. Where the load cell and an output share the line, it moves the rig (`material`);
//! on some channels only, it is picked up after the transduction (`electronics`).

use std::f64::consts::TAU;

use super::fitting::{best_shape, Columns, Context};
use super::offset_step::with_unit;
use super::{Description, Term, TermKind};
use sim::effects::Stage;

/// The highest frequency searched: the decimated blocks (up to 200 ms) average faster lines
/// towards nothing, and the mains band has its own search (`crate::mains`).
const MAX_FREQ_HZ: f64 = 10.0;
/// A line with a period beyond this is reported as a slow wander of the zero.
const WANDER_PERIOD_S: f64 = 10.0;

/// The block means of sin and cos at `f`.
fn columns(ctx: &Context, f: f64) -> Columns {
    let w = TAU * f;
    let (sin, cos) = ctx
        .block_span
        .iter()
        .map(|&(a, b)| {
            let span = (b - a).max(1e-12);
            (
                ((w * a).cos() - (w * b).cos()) / (w * span),
                ((w * b).sin() - (w * a).sin()) / (w * span),
            )
        })
        .unzip();
    Columns {
        x: vec![sin, cos],
        fixed: None,
    }
}

/// The best line on channel `c`.
pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    let (f0, df) = strongest_frequency(ctx, c)?;
    let shapes = (-4..=4).map(|j| {
        let f = f0 + f64::from(j) * df / 4.0;
        (vec![f], columns(ctx, f))
    });
    let (shape, columns, beta, _) = best_shape(ctx, c, others, shapes.filter(|s| s.0[0] > 0.0))?;
    Some(Term {
        kind: TermKind::Line,
        channel: c,
        shape,
        columns,
        beta,
        n_params: 3,
    })
}

/// The line at the full rate's instants.
pub(crate) fn at_times(t: &Term, t_s: &[f64]) -> Vec<f64> {
    let w = TAU * t.shape[0];
    t_s.iter()
        .map(|&t_s| t.beta[0] * (w * t_s).sin() + t.beta[1] * (w * t_s).cos())
        .collect()
}

/// A line alone on its channel is pickup (`electronics`); [`merged_stage`] decides for a line
/// that several channels share.
pub(crate) fn stage(_t: &Term) -> Stage {
    Stage::Electronics
}

/// The stage of one line seen on `channels`: on the load cell and an output alike, the rig
/// itself moves (`material`); else pickup after the transduction.
pub(crate) fn merged_stage(channels: &[usize]) -> Stage {
    if channels.contains(&0) && channels.iter().any(|&c| c > 0) {
        Stage::Material
    } else {
        Stage::Electronics
    }
}

pub(crate) fn describe(t: &Term, unit: &str) -> Description {
    let f = t.shape[0];
    let amplitude = t.beta[0].hypot(t.beta[1]);
    let name = if 1.0 / f > WANDER_PERIOD_S {
        "slow_wander"
    } else {
        "periodic_line"
    };
    Description {
        name,
        params: vec![
            ("freq_hz", f, "Hz".into()),
            ("amplitude", amplitude, unit.into()),
        ],
        depends_on: vec!["time"],
        form: format!(
            "a sinusoid of {} amplitude at {f:.4} Hz (period {:.2} s)",
            with_unit(amplitude, unit).trim_start_matches('+'),
            1.0 / f
        ),
    }
}

/// The strongest peak of the periodogram of channel `c`'s full-rate residual over the fitting
/// stretch, binned to a twentieth of a second's half, and the periodogram's resolution.
fn strongest_frequency(ctx: &Context, c: usize) -> Option<(f64, f64)> {
    let full = &ctx.data.full;
    let end_s = ctx
        .t_s()
        .iter()
        .zip(ctx.heldout_mask)
        .find(|(_, &h)| h)
        .map_or(f64::INFINITY, |(t, _)| *t);
    let f_hi = MAX_FREQ_HZ.min(0.45 * ctx.data.rate_hz);
    let dt = 0.5 / f_hi;
    let t0 = *full.t_s.first()?;
    let span = end_s.min(*full.t_s.last()?) - t0;
    let bins = (span / dt).floor() as usize;
    if bins < 16 {
        return None;
    }
    let (mut sum, mut count) = (vec![0.0; bins], vec![0usize; bins]);
    for (t, r) in full.t_s.iter().zip(&ctx.full_residual[c]) {
        let b = ((t - t0) / dt) as usize;
        if b < bins {
            sum[b] += r;
            count[b] += 1;
        }
    }
    let mean = sum.iter().sum::<f64>() / count.iter().sum::<usize>().max(1) as f64;
    let x: Vec<f64> = (0..bins)
        .map(|b| match count[b] {
            0 => 0.0,
            n => sum[b] / n as f64 - mean,
        })
        .collect();
    let size = (2 * bins).next_power_of_two();
    let power = periodogram(&x, size);
    let df = 1.0 / (size as f64 * dt);
    let f_lo = 2.0 / span;
    let k = (1..size / 2)
        .filter(|&k| (f_lo..=f_hi).contains(&(k as f64 * df)))
        .max_by(|&a, &b| power[a].total_cmp(&power[b]))?;
    Some((k as f64 * df, df))
}

/// |X_k|^2 of `x` zero-padded to `size` (a power of two). An in-place radix-2 FFT of our own:
/// none of the crates the workspace keeps has one, and a periodogram needs nothing more.
fn periodogram(x: &[f64], size: usize) -> Vec<f64> {
    let mut re: Vec<f64> = x
        .iter()
        .copied()
        .chain(std::iter::repeat(0.0))
        .take(size)
        .collect();
    let mut im = vec![0.0; size];
    let bits = size.trailing_zeros();
    for i in 0..size {
        let j = i.reverse_bits() >> (usize::BITS - bits);
        if j > i {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= size {
        let (ws, wc) = (-TAU / len as f64).sin_cos();
        for start in (0..size).step_by(len) {
            let (mut ur, mut ui) = (1.0, 0.0);
            for k in 0..len / 2 {
                let (a, b) = (start + k, start + k + len / 2);
                let (tr, ti) = (re[b] * ur - im[b] * ui, re[b] * ui + im[b] * ur);
                (re[b], im[b]) = (re[a] - tr, im[a] - ti);
                (re[a], im[a]) = (re[a] + tr, im[a] + ti);
                (ur, ui) = (ur * wc - ui * ws, ur * ws + ui * wc);
            }
        }
        len *= 2;
    }
    re.iter().zip(&im).map(|(r, i)| r * r + i * i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The periodogram of a sampled sinusoid peaks at its frequency's bin.
    #[test]
    fn the_periodogram_peaks_at_the_line() {
        let x: Vec<f64> = (0..1000).map(|k| (TAU * 0.125 * k as f64).sin()).collect();
        let p = periodogram(&x, 2048);
        let k = (1..1024).max_by(|&a, &b| p[a].total_cmp(&p[b])).unwrap();
        assert_eq!(k, 256);
    }
}
