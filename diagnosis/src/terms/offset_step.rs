//! An offset step: a connector knock, a zero jump of the amplifier, a load cell re-zeroed.
//!
//! ```text
//! y(t) = model(t) + a H(t - t0),     H the unit step
//! ```
//!
//! acting after the transduction (`electronics`), a function of time alone. t0 is searched over
//! the fitting stretch's samples; a step that the held-out stretch does not carry on is not
//! confirmed there, and the search drops it.

use super::fitting::{best_step, solve, Columns, Context};
use super::{Description, Term, TermKind};

/// The best step on channel `c`.
pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    fit_step(ctx, c, others, TermKind::OffsetStep)
}

/// The best step of `kind` on channel `c`: an offset added from t0 on, or, for a stuck
/// channel, the model replaced by a constant from t0 on. Both are a time and one amplitude.
pub(crate) fn fit_step(ctx: &Context, c: usize, others: &Columns, kind: TermKind) -> Option<Term> {
    let freezes = kind == TermKind::StuckChannel;
    let (t0, columns) = best_step(ctx, c, others, freezes)?;
    let (beta, _) = solve(ctx, c, &columns.joined(others))?;
    let (shape, beta) = (vec![t0], beta[..1].to_vec());
    Some(Term {
        kind,
        channel: c,
        shape,
        columns,
        beta,
        n_params: 2,
        info: None,
    })
}

pub(crate) fn describe(t: &Term, unit: &str) -> Description {
    let (t0, a) = (t.shape[0], t.beta[0]);
    Description {
        name: "offset_step".into(),
        params: vec![("step", a, unit.into()), ("t0_s", t0, "s".into())],
        depends_on: vec!["time"],
        form: format!("offset step of {} at t = {t0:.2} s", with_unit(a, unit)),
    }
}

/// A value with its unit, volts in mV, to three significant figures (a small step is not
/// "-0.000 N").
pub(crate) fn with_unit(v: f64, unit: &str) -> String {
    let (v, unit) = if unit == "V" {
        (1e3 * v, "mV")
    } else {
        (v, unit)
    };
    let sign = if v >= 0.0 { "+" } else { "" };
    format!("{sign}{} {unit}", figures::number::significant(v, 3))
}
