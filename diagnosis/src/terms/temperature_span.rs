//! A span that follows the temperature: the bridges' sensitivity changes with temperature
//! (piezoresistive coefficients fall as the chip warms), so the output per unit load does:
//!
//! ```text
//! y(t) = offset + s(t) (1 + k (T(t) - T0))
//! ```
//!
//! with s the model's signal (its output less its offset) and T0 the mean temperature over the
//! fitting stretch. At the transducer, a function of temperature and load; only where the
//! recording's temperature moves.

use super::fitting::{Columns, Context};
use super::{Description, Term, TermKind};

/// The temperature over the decimated series and its mean over the fitting stretch.
fn temperature<'c>(ctx: &'c Context) -> Option<(&'c [f64], f64)> {
    let temp = ctx.data.fit.temp_c.as_deref()?;
    let rows: Vec<f64> = (0..ctx.len())
        .filter(|&k| ctx.fit_mask[k])
        .map(|k| temp[k])
        .collect();
    let mean = rows.iter().sum::<f64>() / rows.len().max(1) as f64;
    let spread = rows.iter().fold(0.0f64, |m, t| m.max((t - mean).abs()));
    (spread > 0.0).then_some((temp, mean))
}

pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    let (temp, t0) = temperature(ctx)?;
    let s = ctx.signal(c);
    let columns = Columns {
        x: vec![temp.iter().zip(&s).map(|(t, s)| (t - t0) * s).collect()],
        fixed: None,
    };
    let (beta, _) = super::fitting::solve(ctx, c, &columns.joined(others))?;
    Some(Term {
        kind: TermKind::TemperatureSpan,
        channel: c,
        shape: vec![t0],
        columns,
        beta: beta[..1].to_vec(),
        n_params: 1,
    })
}

pub(crate) fn describe(t: &Term) -> Description {
    let (t0, k) = (t.shape[0], t.beta[0]);
    Description {
        name: "span_follows_temperature",
        params: vec![("span_per_K", k, "1/K".into()), ("t0_C", t0, "°C".into())],
        depends_on: vec!["temp_C", "load_N"],
        form: format!(
            "output = offset + signal x (1 {:+.3} % per K x (T - {t0:.2} °C))",
            100.0 * k
        ),
    }
}
