//! A span that follows the temperature: the bridges' sensitivity changes with temperature
//! (piezoresistive coefficients fall as the chip warms), so the output per unit load does:
//!
//! ```text
//! y(t) = offset + s(t) (1 + k (T(t) - T0))
//! ```
//!
//! with s the model's signal (its output less its offset) and T0 the mean temperature over the
//! fitting stretch: at the transducer, a function of temperature and load. An amplifier whose
//! gain follows the temperature multiplies the bridge's offset as well,
//!
//! ```text
//! y(t) = (offset + s(t)) (1 + k (T(t) - T0))
//! ```
//!
//! in the electronics; the form that fits better is kept (where the offset is small against
//! the signal the two cannot be told apart, and the transducer's is reported). Only where the
//! recording's temperature moves.

use super::fitting::{solve, Columns, Context};
use super::{Description, Term, TermKind};
use crate::candidate::MIN_BIC_GAIN;
use sim::effects::Stage;

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
    let signal = ctx.signal(c);
    let form = |whole: f64| columns_of(temp, t0, &signal, whole * ctx.offset[c]);
    let bridges = solve(ctx, c, &form(0.0).joined(others))?;
    let amplifier = solve(ctx, c, &form(1.0).joined(others))?;
    // The amplifier's form where it fits better than the bridges' by more than the criterion's
    // margin: else the two are one description, and the bridges' is the simpler.
    let whole = if bridges.1 - amplifier.1 > MIN_BIC_GAIN {
        1.0
    } else {
        0.0
    };
    let beta = if whole == 1.0 { amplifier.0 } else { bridges.0 };
    Some(Term {
        kind: TermKind::TemperatureSpan,
        channel: c,
        shape: vec![t0, whole],
        columns: form(whole),
        beta: beta[..1].to_vec(),
        n_params: 1,
        info: None,
    })
}

/// Whether the fitted span multiplies the whole output (the amplifier's gain).
pub(crate) fn stage(t: &Term) -> Stage {
    if t.shape[1] == 1.0 {
        Stage::Electronics
    } else {
        Stage::Transducer
    }
}

fn columns_of(temp: &[f64], t0: f64, signal: &[f64], offset: f64) -> Columns {
    Columns {
        x: vec![temp
            .iter()
            .zip(signal)
            .map(|(t, s)| (t - t0) * (s + offset))
            .collect()],
        fixed: None,
    }
}

pub(crate) fn describe(t: &Term) -> Description {
    let (t0, k) = (t.shape[0], t.beta[0]);
    Description {
        name: "span_follows_temperature".into(),
        params: vec![("span_per_K", k, "1/K".into()), ("t0_C", t0, "°C".into())],
        depends_on: vec!["temp_C", "load_N"],
        form: format!(
            "output = {} x (1 {:+.3} % per K x (T - {t0:.2} °C))",
            if t.shape[1] == 1.0 {
                "(offset + signal)"
            } else {
                "offset + signal"
            },
            100.0 * k
        ),
    }
}
