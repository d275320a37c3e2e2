//! A channel that freezes: a converter that stops updating, a wire that comes loose, an
//! amplifier stuck at a rail. From t0 on it reads a constant whatever the load:
//!
//! ```text
//! y(t) = model(t) + H(t - t0) (a - model(t))
//! ```
//!
//! after the transduction (`electronics`), a function of time alone. Fitted as the column
//! H(t - t0) with the fixed part -H(t - t0) model(t); t0 over the fitting stretch's samples.

use super::fitting::{Columns, Context};
use super::offset_step::{fit_step, with_unit};
use super::{Description, Term, TermKind};
use crate::candidate::MIN_BIC_GAIN;

/// The best freeze on channel `c`, where the recording could show one.
///
/// A freeze is told from an offset step only by what the model does after t0. Where the model
/// stays within the noise of a constant from t0 to the end of the recording (a step at rest
/// in the last recovery), no data can tell the two apart, and the step, the smaller claim, is
/// the description: the freeze is not offered. The model's course is the drive's, not the
/// measurement's, so reading it over the held-out stretch as well tests nothing in advance.
///
/// And a frozen channel reads a constant: where what it reads from t0 on holds a trend in time
/// that the criterion would keep (a load that still relaxes on a time scale the model lacks,
/// on a real Mach-1 hold), it is not frozen, and the freeze is not offered.
pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    let term = fit_step(ctx, c, others, TermKind::StuckChannel)?;
    let t0_s = term.shape[0];
    (model_moves_after(ctx, c, t0_s) > MIN_BIC_GAIN && trend_after(ctx, c, t0_s) <= MIN_BIC_GAIN)
        .then_some(term)
}

/// Chi-square (noise units) that a line in time removes from what channel `c` reads from
/// `t0_s` to the end of the recording, against its weighted mean.
fn trend_after(ctx: &Context, c: usize, t0_s: f64) -> f64 {
    let t = ctx.t_s();
    let rows: Vec<usize> = (0..ctx.len()).filter(|&k| t[k] >= t0_s).collect();
    let w2 = |k: usize| ctx.data.weight(c, k).powi(2);
    let read = |k: usize| ctx.residual[c][k] + ctx.model[c][k];
    let sw: f64 = rows.iter().map(|&k| w2(k)).sum();
    if sw <= 0.0 {
        return 0.0;
    }
    let t_mean = rows.iter().map(|&k| w2(k) * t[k]).sum::<f64>() / sw;
    let y_mean = rows.iter().map(|&k| w2(k) * read(k)).sum::<f64>() / sw;
    let stt: f64 = rows.iter().map(|&k| w2(k) * (t[k] - t_mean).powi(2)).sum();
    let sty: f64 = rows
        .iter()
        .map(|&k| w2(k) * (t[k] - t_mean) * (read(k) - y_mean))
        .sum();
    if stt <= 0.0 {
        return 0.0;
    }
    sty * sty / stt
}

/// Chi-square (noise units) of the model about its weighted mean from `t0_s` to the end of
/// the recording: how far a constant is from it there.
fn model_moves_after(ctx: &Context, c: usize, t0_s: f64) -> f64 {
    let rows: Vec<usize> = (0..ctx.len()).filter(|&k| ctx.t_s()[k] >= t0_s).collect();
    let w2 = |k: usize| ctx.data.weight(c, k).powi(2);
    let sw: f64 = rows.iter().map(|&k| w2(k)).sum();
    if sw <= 0.0 {
        return 0.0;
    }
    let m = &ctx.model[c];
    let mean = rows.iter().map(|&k| w2(k) * m[k]).sum::<f64>() / sw;
    rows.iter().map(|&k| w2(k) * (m[k] - mean).powi(2)).sum()
}

pub(crate) fn describe(t: &Term, unit: &str) -> Description {
    let (t0, a) = (t.shape[0], t.beta[0]);
    Description {
        name: "stuck_channel".into(),
        params: vec![("t0_s", t0, "s".into()), ("value", a, unit.into())],
        depends_on: vec!["time"],
        form: format!(
            "reads a constant {} from t = {t0:.2} s on, whatever the load (stuck or disconnected)",
            with_unit(a, unit)
        ),
    }
}
