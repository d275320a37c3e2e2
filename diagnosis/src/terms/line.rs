//! A line at any frequency: a frame or table that vibrates, a pump, a slow wander of the zero
//! (a period of tens of seconds), pickup other than the mains:
//!
//! ```text
//! y(t) = model(t) + a sin(2 pi f t) + b cos(2 pi f t)
//! ```
//!
//! a function of time alone. f is the strongest peak of the residual's periodogram over the
//! fitting stretch (at least two periods in it, at most 10 Hz, what the decimated blocks still
//! show), where it stands out of the spectrum around it as a line does, refined on the
//! decimated series, where each block holds the line's mean over the
//! block. Where the load cell and an output share the line, it moves the rig (`material`);
//! on some channels only, it is picked up after the transduction (`electronics`).

use std::f64::consts::TAU;

use super::fitting::{best_shape, Columns, Context};
use super::offset_step::with_unit;
use super::{Description, Term, TermKind};
use sim::effects::Stage;

/// The highest frequency searched: the decimated blocks (up to 200 ms) average faster lines
/// towards nothing, and the mains band has its own search (`crate::mains`).
pub(crate) const MAX_FREQ_HZ: f64 = 10.0;
/// A line with a period beyond this is reported as a slow wander of the zero.
const WANDER_PERIOD_S: f64 = 10.0;
/// A frequency at which the rod's own periodogram stands this far above its median over the
/// octave either side is one the rod is driven at. A rod moved in ramps and holds has a smooth
/// spectrum (within a few times across two octaves); a periodic drive's line stands orders of
/// magnitude above it. A residual at a drive frequency is the material's response to the drive
/// (a loss, a lag), not a vibration that is a function of time alone, so it is not offered.
const DRIVE_PROMINENCE: f64 = 20.0;

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
    let lowest = lowest_hz(ctx);
    let (shape, columns, beta, _) = best_shape(ctx, c, others, shapes.filter(|s| s.0[0] > lowest))?;
    Some(Term {
        kind: TermKind::Line,
        channel: c,
        shape,
        columns,
        beta,
        n_params: 3,
        info: None,
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
        name: name.into(),
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

/// How the line search bins the full-rate series over the fitting stretch: from `t0`, `bins`
/// bins of `dt` (a twentieth of a second's half, or finer for the fastest line), a periodogram
/// of `size` bins, over `span` s.
struct Binning {
    t0: f64,
    dt: f64,
    bins: usize,
    size: usize,
    span: f64,
}

impl Binning {
    fn of(ctx: &Context) -> Option<Binning> {
        let full = &ctx.data.full;
        let end_s = ctx
            .t_s()
            .iter()
            .zip(ctx.heldout_mask)
            .find(|(_, &h)| h)
            .map_or(f64::INFINITY, |(t, _)| *t);
        let dt = 0.5 / MAX_FREQ_HZ.min(0.45 * ctx.data.rate_hz);
        let t0 = *full.t_s.first()?;
        let span = end_s.min(*full.t_s.last()?) - t0;
        let bins = (span / dt).floor() as usize;
        (bins >= 16).then(|| Binning {
            t0,
            dt,
            bins,
            size: (2 * bins).next_power_of_two(),
            span,
        })
    }

    /// The bin of the rod's periodic drive, if it has one (worked out once per recording).
    fn drive(&self, ctx: &Context) -> Option<usize> {
        let full = &ctx.data.full;
        let grid = (self.t0, self.dt, self.bins);
        let (at_size, cached) = *ctx
            .data
            .drive_bin
            .get_or_init(|| (self.size, drive_bin(full, grid, self.size)));
        // Another stretch than the one cached (none in a diagnosis today) is worked out anew.
        if at_size == self.size {
            cached
        } else {
            drive_bin(full, grid, self.size)
        }
    }
}

/// The frequency of the rod's periodic drive, Hz, if it has one: what the material responds
/// to, so that a term at its multiples is the response's shape, not a line.
pub(crate) fn drive_hz(ctx: &Context) -> Option<f64> {
    let b = Binning::of(ctx)?;
    b.drive(ctx).map(|d| d as f64 / (b.size as f64 * b.dt))
}

/// The strongest peak of the periodogram of channel `c`'s full-rate residual over the fitting
/// stretch, binned to a twentieth of a second's half, and the periodogram's resolution.
fn strongest_frequency(ctx: &Context, c: usize) -> Option<(f64, f64)> {
    let full = &ctx.data.full;
    let f_hi = MAX_FREQ_HZ.min(0.45 * ctx.data.rate_hz);
    let b = Binning::of(ctx)?;
    let Binning {
        t0,
        dt,
        bins,
        size,
        span,
    } = b;
    let (mut sum, mut count) = (vec![0.0; bins], vec![0usize; bins]);
    for (t, r) in full.t_s.iter().zip(&ctx.full_residual[c]) {
        let i = ((t - t0) / dt) as usize;
        if i < bins {
            sum[i] += r;
            count[i] += 1;
        }
    }
    let power = crate::stats::periodogram(&binned(&sum, &count), size);
    let drive = b.drive(ctx);
    let df = 1.0 / (size as f64 * dt);
    let f_lo = (2.0 / span).max(lowest_hz(ctx));
    let k = (1..size / 2)
        .filter(|&k| (f_lo..=f_hi).contains(&(k as f64 * df)))
        .filter(|&k| !drive.is_some_and(|d| harmonic_of(k, d)))
        .filter(|&k| {
            !ctx.beside_catalogue || !drive.is_some_and(|d| beside_harmonic(k, d, span * df))
        })
        .max_by(|&a, &b| power[a].total_cmp(&power[b]))?;
    // A line must stand out of the residual's spectrum as the mains must
    // (`mains::MIN_LINE_PROMINENCE` over the octave either side): a smooth misfit (a force law
    // the calibration does not quite hold, an effect's own) has a broad spectrum whose
    // strongest bin, fitted and tested as a line, can pass both tests where the misfit stands
    // far above the noise.
    if prominence(&power, k) <= crate::mains::MIN_LINE_PROMINENCE {
        return None;
    }
    Some((k as f64 * df, df))
}

/// The lowest frequency a line may have, searched and refined: beside the whole catalogue
/// model only a periodic line is offered, not a slow wander (`TermKind::beside_catalogue`).
fn lowest_hz(ctx: &Context) -> f64 {
    if ctx.beside_catalogue {
        1.0 / WANDER_PERIOD_S
    } else {
        0.0
    }
}

/// The periodogram's bin `k` over its median across the octave either side, leaving out the two
/// bins either side that zero padding spreads a line over.
fn prominence(power: &[f64], k: usize) -> f64 {
    let (lo, hi) = ((k / 2).max(1), (2 * k).min(power.len() / 2 - 1));
    let mut around: Vec<f64> = (lo..=hi)
        .filter(|&j| j.abs_diff(k) > 2)
        .map(|j| power[j])
        .collect();
    if around.is_empty() {
        return 0.0;
    }
    let mid = around.len() / 2;
    let (_, median, _) = around.select_nth_unstable_by(mid, f64::total_cmp);
    power[k] / median.max(1e-300)
}

/// The bin of the rod's periodic drive in a periodogram of `size` bins over `bins` bins of
/// `dt` from `t0`, if the rod has one.
fn drive_bin(
    full: &crate::data::Series,
    (t0, dt, bins): (f64, f64, usize),
    size: usize,
) -> Option<usize> {
    let (mut rod_sum, mut count) = (vec![0.0; bins], vec![0usize; bins]);
    for (t, d) in full.t_s.iter().zip(&full.rod_mm) {
        let b = ((t - t0) / dt) as usize;
        if b < bins {
            rod_sum[b] += d;
            count[b] += 1;
        }
    }
    // The rod's speed: a ramp is a plateau in it and a hold zero, so a small periodic drive
    // under a large ramp stands out where the travel's 1/f^2 leakage would hide it (and where
    // the acceleration's would be the position readout's noise).
    let travel = binned(&rod_sum, &count);
    let speed: Vec<f64> = (0..bins)
        .map(|b| {
            if b == 0 {
                0.0
            } else {
                travel[b] - travel[b - 1]
            }
        })
        .collect();
    let rod = crate::stats::periodogram(&speed, size);
    // The drive's fundamental: the peak of the lowest line that stands out (the first bin
    // found may be on its flank).
    (1..size / 2).find(|&k| driven_at(&rod, k)).map(|k0| {
        (k0..(k0 + k0 / 2 + 3).min(size / 2))
            .max_by(|&a, &b| rod[a].total_cmp(&rod[b]))
            .unwrap_or(k0)
    })
}

/// The bins' means less their mean (an empty bin is zero).
fn binned(sum: &[f64], count: &[usize]) -> Vec<f64> {
    let mean = sum.iter().sum::<f64>() / count.iter().sum::<usize>().max(1) as f64;
    sum.iter()
        .zip(count)
        .map(|(s, &n)| if n == 0 { 0.0 } else { s / n as f64 - mean })
        .collect()
}

/// Whether bin `k` is a multiple of the drive's bin `d`: a periodic drive makes the material's
/// whole response periodic (a stiffening or a loss bends the sinusoid into its harmonics), so
/// a residual at any multiple is the response. The bin of the n-th harmonic is known to n/2
/// bins from `d`'s rounding, and zero padding spreads a line over two bins either side.
fn harmonic_of(k: usize, d: usize) -> bool {
    let n = ((k as f64) / (d as f64)).round();
    n >= 1.0 && (k as f64 - n * d as f64).abs() <= 2.0 + 0.5 * n
}

/// Whether bin `k` lies in the band about a multiple of the drive's bin `d` where, beside a
/// catalogue effect, the effect's own misfit sits: a response whose amplitude changes over the
/// cycles (a material that conditions, a relaxation spectrum one Prony term does not hold)
/// puts sidebands beside each harmonic, spaced by the inverse of the record's span: 1 /
/// `span_df` bins. The band is a quarter of the drive's frequency or four sideband spacings
/// either side, whichever is wider.
fn beside_harmonic(k: usize, d: usize, span_df: f64) -> bool {
    let spacing_bins = 1.0 / span_df.max(1e-12);
    let half = (0.25 * d as f64).max(4.0 * spacing_bins);
    let n = ((k as f64) / (d as f64)).round().max(1.0);
    (k as f64 - n * d as f64).abs() <= half
}

/// Whether the rod's periodogram `rod` holds a line at bin `k` (within the two bins either
/// side that zero padding spreads a line over): [`DRIVE_PROMINENCE`] above its median over
/// the octave either side.
fn driven_at(rod: &[f64], k: usize) -> bool {
    let (lo, hi) = ((k / 2).max(1), (2 * k).min(rod.len() / 2 - 1));
    if hi <= lo + 4 {
        return false;
    }
    let peak = rod[k.saturating_sub(2).max(1)..=(k + 2).min(hi)]
        .iter()
        .fold(0.0_f64, |m, &p| m.max(p));
    // The median only where the peak could stand out: a line is `DRIVE_PROMINENCE` above at
    // least half the octave (selection, not a sort: this runs for every bin of a long test).
    let mut octave: Vec<f64> = rod[lo..=hi].to_vec();
    let mid = octave.len() / 2;
    let (_, median, _) = octave.select_nth_unstable_by(mid, f64::total_cmp);
    peak > DRIVE_PROMINENCE * *median
}
