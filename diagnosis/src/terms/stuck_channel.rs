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
pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    let term = fit_step(ctx, c, others, TermKind::StuckChannel)?;
    (model_moves_after(ctx, c, term.shape[0]) > MIN_BIC_GAIN).then_some(term)
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
        name: "stuck_channel",
        params: vec![("t0_s", t0, "s".into()), ("value", a, unit.into())],
        depends_on: vec!["time"],
        form: format!(
            "reads a constant {} from t = {t0:.2} s on, whatever the load (stuck or disconnected)",
            with_unit(a, unit)
        ),
    }
}
