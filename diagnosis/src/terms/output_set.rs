//! The sensing element takes a set: while loaded it creeps towards its load faster than it
//! creeps back, so after release an output stays raised and creeps down although the load
//! cell is back at zero (soft piezoresistive strips do this; the gel's relaxation cannot, as
//! it acts on load and outputs alike). A state x follows the channel's signal s, normalised by
//! its peak S, with tau_up while s/S is above it and with tau_down while below:
//!
//! ```text
//! dx/dt = (s/S - x) / tau_up     if s/S > x
//! dx/dt = (s/S - x) / tau_down   otherwise
//! y = model + a x
//! ```
//!
//! at the transducer, a function of the load (through the output's signal) and of time. The
//! times come from a grid with tau_down longer than tau_up: one that recovered as fast as it
//! formed would be a lag of the output, not a set.

use super::fitting::{best_shape, Columns, Context};
use super::{Description, Term, TermKind};

/// Grid of the time constants, s: the set forms within seconds to a minute and recovers
/// over tens of seconds to minutes.
const TAU_UP_S: [f64; 5] = [1.0, 3.0, 8.0, 20.0, 50.0];
const TAU_DOWN_S: [f64; 6] = [5.0, 12.0, 30.0, 75.0, 180.0, 450.0];

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
    let peak = s.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if peak == 0.0 {
        return None;
    }
    let u: Vec<f64> = s.iter().map(|v| v.abs() / peak).collect();
    let shapes = TAU_UP_S.iter().flat_map(|&up| {
        let u = &u;
        TAU_DOWN_S
            .iter()
            .filter(move |&&down| down > up)
            .map(move |&down| {
                let x = state(ctx.t_s(), u, up, down);
                (
                    vec![up, down],
                    Columns {
                        x: vec![x],
                        fixed: None,
                    },
                )
            })
    });
    let (shape, columns, beta, _) = best_shape(ctx, c, others, shapes)?;
    Some(Term {
        kind: TermKind::OutputSet,
        channel: c,
        shape,
        columns,
        beta,
        n_params: 3,
    })
}

pub(crate) fn describe(t: &Term, unit: &str) -> Description {
    let (up, down, a) = (t.shape[0], t.shape[1], t.beta[0]);
    Description {
        name: "sensing_element_set",
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
