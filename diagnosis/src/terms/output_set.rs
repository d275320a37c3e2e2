//! The sensing element takes a set: while loaded it creeps towards its load faster than it
//! creeps back, so after release an output stays raised and creeps down although the load
//! cell is back at zero (soft piezoresistive strips do this; the gel's relaxation cannot, as
//! it acts on load and outputs alike). A state x follows the channel's signal s, normalised by
//! its peak S, with tau_up while s/S is above it and with tau_down while below:
//!
//! ```text
//! dx/dt = (s/S - x) / tau_up     if s/S > x
//! dx/dt = (s/S - x) / tau_down   otherwise
//! y = model + a sign(s_peak) x,   a > 0
//! ```
//!
//! at the transducer, a function of the load (through the output's signal) and of time. The
//! times come from a grid with tau_down longer than tau_up: one that recovered as fast as it
//! formed would be a lag of the output, not a set.

use super::fitting::{best_shape_where, Columns, Context};
use super::{Description, Term, TermKind};

/// Logarithmic grids of the time constants, s: the set forms within a second to a minute
/// (1–60 s) and recovers over seconds to ten minutes (4–600 s), each step a factor of about
/// 1.5, fine enough that the shape's misfit stays below what a second term would take up.
fn tau_up_s() -> impl Iterator<Item = f64> + Clone {
    (0..=10).map(|j| 60f64.powf(f64::from(j) / 10.0))
}
fn tau_down_s() -> impl Iterator<Item = f64> + Clone {
    (0..=12).map(|j| 4.0 * 150f64.powf(f64::from(j) / 12.0))
}

/// The state x over the decimated series.
fn state(t_s: &[f64], u: &[f64], tau_up_s: f64, tau_down_s: f64) -> Vec<f64> {
    let mut x = 0.0;
    let mut prev = t_s.first().copied().unwrap_or(0.0);
    t_s.iter()
        .zip(u)
        .map(|(&t, &u)| {
            let dt = (t - prev).max(0.0);
            prev = t;
            let tau = if u > x { tau_up_s } else { tau_down_s };
            x += (u - x) * (1.0 - (-dt / tau).exp());
            x
        })
        .collect()
}

pub(crate) fn fit(ctx: &Context, c: usize, others: &Columns) -> Option<Term> {
    let s = ctx.signal(c);
    let peak = s
        .iter()
        .copied()
        .max_by(|a, b| a.abs().total_cmp(&b.abs()))?;
    if peak == 0.0 {
        return None;
    }
    // The set adds to the response in its own direction: x times the sign of the peak, with a
    // positive amplitude (one that took from it would be a relaxation, `output_relaxation`).
    let sign = peak.signum();
    let u: Vec<f64> = s.iter().map(|v| v.abs() / peak.abs()).collect();
    let shapes = tau_up_s().flat_map(|up| {
        let u = &u;
        tau_down_s()
            .filter(move |&down| down > up)
            .map(move |down| {
                let x = state(ctx.t_s(), u, up, down)
                    .iter()
                    .map(|x| sign * x)
                    .collect();
                (
                    vec![up, down, sign],
                    Columns {
                        x: vec![x],
                        fixed: None,
                    },
                )
            })
    });
    let (shape, columns, beta, _) =
        best_shape_where(ctx, c, others, shapes, |b| TermKind::OutputSet.admits(b[0]))?;
    Some(Term {
        kind: TermKind::OutputSet,
        channel: c,
        shape,
        columns,
        beta,
        n_params: 3,
        info: None,
    })
}

pub(crate) fn describe(t: &Term, unit: &str) -> Description {
    // In the channel's volts: the set's direction is the response's.
    let (up, down, a) = (t.shape[0], t.shape[1], t.shape[2] * t.beta[0]);
    Description {
        name: "sensing_element_set".into(),
        params: vec![
            ("size", a, unit.into()),
            ("tau_up_s", up, "s".into()),
            ("tau_down_s", down, "s".into()),
        ],
        depends_on: vec!["load_N", "time"],
        form: format!(
            "the output gains {a:.4} {unit} x a set that follows the load with {up:.0} s and recovers with {down:.0} s"
        ),
    }
}
