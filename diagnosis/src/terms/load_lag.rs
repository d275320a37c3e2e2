//! The load cell's stream shifted in time against the rod (a filter, a buffer, a clock): the
//! catalogue's `time_offset` at the electronics of the load cell. For a lag small against the
//! signal's time scales,
//!
//! ```text
//! y(t) = m(t - lag) ~ m(t) - lag dm/dt
//! ```
//!
//! so the column is -dm/dt and its amplitude the lag (positive: the load cell lags).

use super::fitting::{derivative, solve, Columns, Context};
use super::{Description, Term, TermKind};

pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    // A lag opens a loop: beside a loop effect of the model it is that effect's misfit.
    if ctx.loop_in_model {
        return None;
    }
    let rate: Vec<f64> = derivative(ctx.t_s(), &ctx.model[c])
        .iter()
        .map(|d| -d)
        .collect();
    let columns = Columns {
        x: vec![rate],
        fixed: None,
    };
    let (beta, _) = solve(ctx, c, &columns.joined(others))?;
    Some(Term {
        kind: TermKind::LoadLag,
        channel: c,
        shape: Vec::new(),
        columns,
        beta: beta[..1].to_vec(),
        n_params: 1,
        info: None,
    })
}

pub(crate) fn describe(t: &Term) -> Description {
    Description {
        name: "time_offset".into(),
        params: vec![("lag_s", t.beta[0], "s".into())],
        depends_on: vec!["load_rate"],
        form: format!("load cell lags the rod by {:.1} ms", 1e3 * t.beta[0]),
    }
}
