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

/// The best freeze on channel `c`.
pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    fit_step(ctx, c, others, TermKind::StuckChannel)
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
